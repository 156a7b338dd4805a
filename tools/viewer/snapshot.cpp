#include "tools/viewer/snapshot.h"

#include <algorithm>

#include "systems/kernels/blade_pose.h"

namespace xcut::viewer {

std::vector<std::array<int, 2>> element_edges(const Elements& elements, const std::vector<int>& which) {
    std::vector<std::array<int, 2>> edges;
    const int corners = elements.dim == 3 ? 4 : 3;
    for (int e : which)
        for (int a = 0; a < corners; ++a)
            for (int b = a + 1; b < corners; ++b) {
                const int i = elements.nodes[e][a], j = elements.nodes[e][b];
                edges.push_back({std::min(i, j), std::max(i, j)});
            }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    return edges;
}

namespace {

void add_edges(const World& w, const std::vector<std::array<int, 2>>& edges, std::vector<Vec3>& out) {
    for (const auto& e : edges) out.push_back(w.nodes.position[e[0]]), out.push_back(w.nodes.position[e[1]]);
}

/// A sphere, capsule or box as triangles, in the tool frame [m].
void shape_triangles(const ToolShape& s, std::vector<Vec3>& v, std::vector<std::array<int, 3>>& t) {
    if (s.kind == ToolShape::kMesh) {
        v = s.vertices, t = s.triangles;
        return;
    }
    if (s.kind == ToolShape::kBox) {
        for (int i = 0; i < 8; ++i)
            v.push_back(s.centre + Vec3((i & 1) ? 1 : -1, (i & 2) ? 1 : -1, (i & 4) ? 1 : -1).cwiseProduct(s.half_extent));
        t = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
             {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
        return;
    }
    if (s.kind != ToolShape::kSphere && s.kind != ToolShape::kCapsule) return;
    const int rings = 8, segments = 16;  // a UV sphere; a capsule's halves pulled apart along z
    const double half = s.kind == ToolShape::kCapsule ? 0.5 * s.length : 0.0;
    for (int r = 0; r <= rings; ++r) {
        const double th = M_PI * r / rings;
        for (int k = 0; k < segments; ++k) {
            const double ph = 2.0 * M_PI * k / segments;
            const Vec3 n(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
            v.push_back(s.centre + s.radius * n + Vec3(0, 0, r <= rings / 2 ? half : -half));
        }
    }
    for (int r = 0; r < rings; ++r)
        for (int k = 0; k < segments; ++k) {
            const int a = r * segments + k, b = r * segments + (k + 1) % segments;
            t.push_back({a, a + segments, b}), t.push_back({b, a + segments, b + segments});
        }
}

void snapshot_tools(const World& w, Snapshot& out) {
    const ToolBodies& tb = w.tools;
    out.tools.resize(tb.count());
    for (int i = 0; i < tb.count(); ++i) {
        ToolView& t = out.tools[i];
        t.name = tb.name[i];
        t.position = tb.position[i], t.orientation = tb.orientation[i];
        t.blade = tb.has_blade[i] != 0;
        if (t.blade) blade_in_world(w.tools, i, t.tip, t.heel);
        t.force = i < static_cast<int>(tb.reaction_force.size()) ? tb.reaction_force[i] : Vec3::Zero();
        t.shape_vertices.clear(), t.shape_triangles.clear();
        shape_triangles(tb.shape[i], t.shape_vertices, t.shape_triangles);
        for (Vec3& p : t.shape_vertices) p = t.position + t.orientation * p;
    }
    // The collision quad each blade is sweeping: from its anchor to where it is now.
    out.quad_lines.clear();
    const CutState& cs = w.cut_state;
    for (int i = 0; i < tb.count() && i < static_cast<int>(cs.anchored.size()); ++i) {
        if (!cs.anchored[i] || !out.tools[i].blade) continue;
        const std::array<Vec3, 4> q = {cs.anchor_tip[i], cs.anchor_heel[i], out.tools[i].heel, out.tools[i].tip};
        for (int k = 0; k < 4; ++k) out.quad_lines.push_back(q[k]), out.quad_lines.push_back(q[(k + 1) % 4]);
    }
}

}  // namespace

void take_snapshot(const World& w, const SnapshotOptions& options, Snapshot& out) {
    const StepMetrics& m = w.metrics.current;
    out.step = w.step, out.time = w.time, out.dt = m.dt, out.step_ms = m.step_ms;
    out.dim3 = w.elements.dim == 3;
    out.surface = w.visual.position;
    out.triangles = w.visual.triangles;
    out.cut_face = w.visual.cut_face;
    out.mesh_lines.clear(), out.virtual_lines.clear();
    if (options.mesh) {  // the mesh elements still whole (a cut one is drawn by its virtual elements)
        std::vector<int> whole;
        for (int e = 0; e < w.mesh_elements; ++e)
            if (e >= static_cast<int>(w.cuts.cut_of_element.size()) || w.cuts.cut_of_element[e] < 0) whole.push_back(e);
        add_edges(w, element_edges(w.elements, whole), out.mesh_lines);
    }
    if (options.virtuals) add_edges(w, element_edges(w.elements, w.virtual_elements.element), out.virtual_lines);
    out.contact_points.clear(), out.contact_normals.clear();
    for (size_t c = 0; c < w.contacts.vertex.size(); ++c) {
        const int v = w.contacts.vertex[c];
        if (v < w.collision.vertex_count()) out.contact_points.push_back(w.collision.position[v]);
        else continue;
        out.contact_normals.push_back(w.contacts.normal[c]);
    }
    snapshot_tools(w, out);
    out.systems = w.metrics.system_names;
    out.system_ms = m.system_ms;
    out.linear = w.linear.method;
    out.cg_iterations = m.cg_iterations, out.cg_residual = m.cg_residual;
    out.dofs = m.dofs;
    out.enriched_nodes = w.enriched.count();
    out.elements_split = w.cuts.count() + w.snap.elements_split;
    out.pieces = w.pieces.count, out.pieces_freed = static_cast<int>(w.pieces.log.size());
    out.kinetic = m.kinetic_energy, out.elastic = m.elastic_energy;
}

void SnapshotBuffer::publish() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::swap(back_, ready_);
    fresh_ = true;
}

bool SnapshotBuffer::acquire() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!fresh_) return false;
    std::swap(front_, ready_);
    fresh_ = false;
    return true;
}

}  // namespace xcut::viewer
