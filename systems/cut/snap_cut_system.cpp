#include "systems/cut/snap_cut_system.h"

#include "systems/kernels/mesh_measures.h"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <numeric>

#include "engine/setup.h"
#include "systems/kernels/cut_geometry.h"
#include "systems/kernels/disjoint_sets.h"
#include "systems/surface/mapping_system.h"
#include "systems/kernels/snap_split_patterns.h"
#include "systems/cut/snap_quadratic.h"

namespace xcut {
namespace {

uint64_t edge_key(int a, int b) {
    return (static_cast<uint64_t>(std::min(a, b)) << 32) | static_cast<uint32_t>(std::max(a, b));
}
const int* local_edge(int dim, int k) { return dim == 3 ? kTetEdges[k] : kTriEdges[k]; }

template <class F>
void for_mesh_elements_of(const World& w, int node, F&& f) {
    for (int p = w.incidence.offset[node]; p < w.incidence.offset[node + 1]; ++p) f(w.incidence.entry[p] >> 2);
}

bool holds(const std::array<int, 4>& nodes, int npe, int node) {
    return std::find(nodes.begin(), nodes.begin() + npe, node) != nodes.begin() + npe;
}

/// Mesh elements whose pieces can hold root r: around the node, or around the edge of a point.
std::vector<int> star_of_root(const World& w, int r) {
    std::vector<int> out;
    if (r < w.mesh_nodes) {
        for_mesh_elements_of(w, r, [&](int e) { out.push_back(e); });
        return out;
    }
    const auto ab = w.snap.extra_edge[r - w.mesh_nodes];
    const int npe = w.elements.nodes_per_element();
    for_mesh_elements_of(w, ab[0], [&](int e) {
        if (holds(w.elements.nodes[e], npe, ab[1])) out.push_back(e);
    });
    return out;
}

/// Signed rest measure of a simplex (volume; 2D: area), with node `moved` at `at` if given.
double rest_measure(const World& w, const std::array<int, 4>& n, int moved = -1, const Vec3& at = Vec3::Zero()) {
    auto X = [&](int i) -> Vec3 { return n[i] == moved ? at : w.nodes.rest[n[i]]; };
    if (w.elements.dim == 3) return tet_signed_volume(X(0), X(1), X(2), X(3));
    const Vec3 a = X(1) - X(0), b = X(2) - X(0);
    return 0.5 * (a.x() * b.y() - a.y() * b.x());
}

/// The pieces of mesh element f in root ids, bisected at every point on its edges.
std::vector<std::array<int, 4>> root_pieces(const World& w, int f) {
    const Elements& el = w.elements;
    std::vector<EdgeSplit> splits;
    for (int k = 0; k < edge_count(el.dim); ++k) {
        const uint64_t key = edge_key(el.nodes[f][local_edge(el.dim, k)[0]], el.nodes[f][local_edge(el.dim, k)[1]]);
        const auto it = w.snap.edge_point.find(key);
        if (it != w.snap.edge_point.end()) splits.push_back({k, it->second, key});
    }
    return bisect_simplex(el.nodes[f], el.dim, splits);
}

}  // namespace

int add_snap_node(World& w, int from, int b, double t) {
    Nodes& n = w.nodes;
    const int p = n.count();
    auto lerp = [&](const std::vector<Vec3>& v) { return b < 0 ? Vec3(v[from]) : Vec3(v[from] + t * (v[b] - v[from])); };
    const Vec3 rest = lerp(n.rest), x = lerp(n.position), v = lerp(n.velocity);
    n.rest.push_back(rest);
    n.position.push_back(x);
    n.velocity.push_back(v);
    n.mass.push_back(0.0);
    n.fixed.push_back(b < 0 ? n.fixed[from] : static_cast<uint8_t>(n.fixed[from] & n.fixed[b]));
    Eigen::VectorXd& dv = w.forces.last_dv;  // CG's first guess follows, as for an XFEM phantom
    if (dv.size() == 3 * p) {
        dv.conservativeResize(3 * p + 3);
        dv.segment<3>(3 * p) = b < 0 ? Vec3(dv.segment<3>(3 * from))
                                     : Vec3((1.0 - t) * dv.segment<3>(3 * from) + t * dv.segment<3>(3 * b));
    }
    return p;
}

namespace {

int add_edge_point(World& w, int a, int b, double t) {
    SnapMesh& s = w.snap;
    const int p = add_snap_node(w, a, b, t);
    s.edge_point[edge_key(a, b)] = p;
    s.extra_edge.push_back({std::min(a, b), std::max(a, b)});
    s.extra_root.push_back(p);
    ++s.points;
    return p;
}

int add_copy(World& w, int root, int from) {
    const int p = add_snap_node(w, from);
    w.snap.extra_edge.push_back({-1, -1});
    w.snap.extra_root.push_back(root);
    ++w.snap.copies;
    return p;
}

/// Moves mesh node a along its edge to b by t (of the edge) onto the cut, if allowed: not held,
/// not off the boundary, and no element around it inverted in the rest shape.
bool try_snap(World& w, int a, int b, double t) {
    SnapMesh& s = w.snap;
    const int dim = w.elements.dim;
    if (w.nodes.fixed[a] & (dim == 2 ? 3 : 7)) return false;
    if (s.boundary_node[a] && !s.boundary_edges.count(edge_key(a, b))) return false;
    Nodes& n = w.nodes;
    const Vec3 target = n.rest[a] + t * (n.rest[b] - n.rest[a]);
    bool ok = true;
    for_mesh_elements_of(w, a, [&](int f) {
        for (const auto& piece : root_pieces(w, f))
            if (holds(piece, w.elements.nodes_per_element(), a) && !(rest_measure(w, piece, a, target) > 0.0)) ok = false;
    });
    if (!ok) return false;
    const double distance = t * (n.rest[b] - n.rest[a]).norm();
    n.rest[a] = target;
    n.position[a] += t * (n.position[b] - n.position[a]);
    n.velocity[a] += t * (n.velocity[b] - n.velocity[a]);
    s.snapped[a] = 1;
    ++s.snaps;
    s.snap_fraction.push_back(t);
    s.max_snap_distance = std::max(s.max_snap_distance, distance);
    return true;
}

/// Records the cut through mesh element e (node sides, snaps, edge points). Returns false if the
/// element is already split or the event's sides do not differ. New points and moved nodes are
/// appended to the lists.
bool record_split(World& w, const CutEvent& ev, std::vector<int>& moved) {
    SnapMesh& s = w.snap;
    const int e = ev.element;
    if (e < 0 || e >= w.mesh_elements || s.split[e]) return false;
    const Elements& el = w.elements;
    const int dim = el.dim, npe = el.nodes_per_element();
    const auto& c = el.nodes[e];
    auto& sign = w.enriched.sign;
    std::array<int8_t, 4> H{};
    for (int a = 0; a < npe; ++a) H[a] = sign[c[a]] != 0 ? sign[c[a]] : (ev.level[a] >= 0.0 ? 1 : -1);
    if (std::all_of(H.begin() + 1, H.begin() + npe, [&](int8_t h) { return h == H[0]; })) return false;
    for (int a = 0; a < npe; ++a) sign[c[a]] = H[a];  // the first cut decides, as for XFEM
    const double thr = s.threshold;
    for (int k = 0; k < edge_count(dim); ++k) {
        const int i = local_edge(dim, k)[0], j = local_edge(dim, k)[1];
        const int a = c[i], b = c[j];
        if (H[i] == H[j] || s.edge_point.count(edge_key(a, b)) || s.snapped[a] || s.snapped[b]) continue;
        double t = ev.edge_has_t[k] ? ev.edge_t[k] : 0.5;
        if (!ev.edge_has_t[k] && ev.level[i] != ev.level[j]) t = ev.level[i] / (ev.level[i] - ev.level[j]);
        t = std::clamp(t, 0.0, 1.0);
        if (t <= thr && try_snap(w, a, b, t)) {
            moved.push_back(a);
        } else if (t >= 1.0 - thr && try_snap(w, b, a, 1.0 - t)) {
            moved.push_back(b);
        } else {
            add_edge_point(w, a, b, t);
        }
    }
    s.split[e] = 1;
    ++s.elements_split;
    for (int a = 0; a < npe; ++a) s.level[e][a] = s.snapped[c[a]] ? 0 : H[a];
    return true;
}

/// Side of a piece of split element f: the sign of its vertices' levels (a point on an edge the
/// cut crosses is on the cut, level 0; a point on another edge takes that edge's side).
int8_t piece_side(const World& w, int f, const std::array<int, 4>& roots) {
    const SnapMesh& s = w.snap;
    const int npe = w.elements.nodes_per_element();
    const auto& c = w.elements.nodes[f];
    if (!s.split[f]) {
        // A whole element around a node snapped onto the cut lies on the side its nodes were on
        // (H, fixed when a cut first met them; a node no cut met has none): it must not join the
        // pieces across the cut. One with nodes on both sides spans the cut (the crack front): 0.
        bool above = false, below = false;
        for (int a = 0; a < npe; ++a) above |= w.enriched.sign[c[a]] > 0, below |= w.enriched.sign[c[a]] < 0;
        return static_cast<int8_t>(above == below ? 0 : (above ? 1 : -1));
    }
    auto level_of_node = [&](int node) {
        for (int a = 0; a < npe; ++a)
            if (c[a] == node) return static_cast<int>(s.level[f][a]);
        return 0;
    };
    int sum = 0;
    for (int v = 0; v < npe; ++v) {
        const int r = roots[v];
        if (r < w.mesh_nodes) {
            sum += level_of_node(r);
            continue;
        }
        const auto ab = s.extra_edge[r - w.mesh_nodes];
        const int la = level_of_node(ab[0]), lb = level_of_node(ab[1]);
        if (la * lb >= 0) sum += la + lb;  // la * lb < 0: the cut's own point, on the surface
    }
    return static_cast<int8_t>(sum > 0 ? 1 : (sum < 0 ? -1 : 0));
}

/// Replaces the pieces of mesh element f by those its points and cut give now (slots reused; the
/// spare ones get weight 0). Nodes are roots until the duplication pass resolves them.
void regenerate(World& w, int f) {
    SnapMesh& s = w.snap;
    Elements& el = w.elements;
    const auto roots = root_pieces(w, f);
    auto& list = s.pieces[f];
    while (list.size() < roots.size()) {
        list.push_back(append_element_copy(el, f, 0.0));
        s.piece_parent.push_back(f);
        s.piece_side.push_back(0);
        s.piece_roots.push_back(el.nodes[f]);
        s.piece_live.push_back(0);
    }
    for (size_t i = 0; i < list.size(); ++i) {
        const int q = list[i], slot = q - w.mesh_elements;
        const bool live = i < roots.size();
        s.piece_roots[slot] = live ? roots[i] : roots[0];
        s.piece_side[slot] = live ? piece_side(w, f, roots[i]) : 0;
        s.piece_live[slot] = live ? 1 : 0;
        el.nodes[q] = s.piece_roots[slot];
        el.weight[q] = live ? 1.0 : 0.0;
    }
    el.weight[f] = 0.0;
}

/// Splits surface root r into one copy per group of the pieces around it that touch through a
/// facet holding r without crossing the cut (pieces of opposite sides never join). A group keeps
/// the copy its pieces used before; a group that has none (or whose copy an earlier group kept)
/// takes r if free, else a new copy with the state of the copy its pieces used. Rewrites the node
/// of every piece around r; appends the rewritten pieces to `rewritten`.
void separate(World& w, int r, std::vector<int>& rewritten) {
    SnapMesh& s = w.snap;
    Elements& el = w.elements;
    const int npe = el.nodes_per_element(), facet = el.dim;  // nodes a facet shares, r included
    std::vector<int> P;
    for (int f : star_of_root(w, r))
        for (int q : s.pieces[f]) {
            const int slot = q - w.mesh_elements;
            if (s.piece_live[slot] && holds(s.piece_roots[slot], npe, r)) P.push_back(q);
        }
    const int n = static_cast<int>(P.size());
    DisjointSets sets(n);
    for (int i = 0; i < n; ++i)
        for (int j = i + 1; j < n; ++j) {
            const int si = s.piece_side[P[i] - w.mesh_elements], sj = s.piece_side[P[j] - w.mesh_elements];
            if (si * sj < 0) continue;
            const auto& ri = s.piece_roots[P[i] - w.mesh_elements];
            const auto& rj = s.piece_roots[P[j] - w.mesh_elements];
            int common = 0;
            for (int a = 0; a < npe; ++a) common += holds(rj, npe, ri[a]) ? 1 : 0;
            if (common >= facet) {
                sets.join(i, j);
            }
        }
    auto key_of = [&](int q) {
        const int slot = q - w.mesh_elements;
        return std::array<int, 3>{r, s.piece_parent[slot], s.piece_side[slot]};
    };
    std::vector<int> groups;  // representatives, in order of first piece
    for (int i = 0; i < n; ++i)
        if (sets.find(i) == i) groups.push_back(i);
    std::vector<int> chosen(groups.size(), -1), previous(groups.size(), -1);
    std::vector<int> claimed;
    for (size_t g = 0; g < groups.size(); ++g)
        for (int i = 0; i < n && chosen[g] < 0; ++i) {
            if (sets.find(i) != groups[g]) continue;
            const auto it = s.copy.find(key_of(P[i]));
            if (it == s.copy.end()) continue;
            if (previous[g] < 0) previous[g] = it->second;
            if (std::find(claimed.begin(), claimed.end(), it->second) == claimed.end())
                chosen[g] = it->second, claimed.push_back(it->second);
        }
    for (size_t g = 0; g < groups.size(); ++g) {
        if (chosen[g] >= 0) continue;
        if (std::find(claimed.begin(), claimed.end(), r) == claimed.end()) {
            chosen[g] = r;
        } else {
            chosen[g] = add_copy(w, r, previous[g] >= 0 ? previous[g] : r);
        }
        claimed.push_back(chosen[g]);
    }
    for (int i = 0; i < n; ++i) {
        const int g = static_cast<int>(std::find(groups.begin(), groups.end(), sets.find(i)) - groups.begin());
        const int q = P[i];
        s.copy[key_of(q)] = chosen[g];
        const auto& roots = s.piece_roots[q - w.mesh_elements];
        for (int a = 0; a < npe; ++a)
            if (roots[a] == r) el.nodes[q][a] = chosen[g];
        rewritten.push_back(q);
    }
}

/// Lumps masses again and rescales the nodes whose mass changed so that their sum, and so the
/// body's total mass, is what it was before the cut (snapping a boundary node along a curved
/// boundary changes the volume slightly; splitting and duplicating do not).
void relump_conserving(World& w, const std::vector<double>& before) {
    lump_masses(w);
    std::vector<double>& m = w.nodes.mass;
    double old_sum = 0.0, new_sum = 0.0;
    std::vector<int> changed;
    for (int i = 0; i < w.nodes.count(); ++i) {
        const double b = i < static_cast<int>(before.size()) ? before[i] : 0.0;
        if (m[i] == b) continue;
        changed.push_back(i);
        old_sum += b;
        new_sum += m[i];
    }
    if (new_sum > 0.0)
        for (int i : changed) m[i] *= old_sum / new_sum;
    for (int i : changed)
        if (!(m[i] > 0.0)) w.nodes.fixed[i] = 7;  // no element left: hold it (the system stays SPD)
}

/// The visual (or collision) surface rebuilt as the boundary of the live elements, bound to them.
void rebuild_surface(World& w, SurfaceMesh& surface, int subdivisions) {
    if (subdivisions < 0 || surface.vertex_count() == 0) return;
    const std::vector<int> live = live_elements(w);
    World view;
    view.nodes.position = w.nodes.position;
    view.nodes.rest = w.nodes.rest;
    view.elements.dim = w.elements.dim;
    for (int q : live) view.elements.nodes.push_back(w.elements.nodes[q]);
    view.mesh_elements = static_cast<int>(live.size());
    view.mesh_nodes = w.nodes.count();
    build_surface(view, surface, subdivisions);
    surface.node_vertex.resize(w.mesh_nodes);  // per mesh node, as for a surface built on the mesh
    const int npe = w.elements.nodes_per_element();
    auto parent_of = [&](int q) { return q < w.mesh_elements ? q : w.snap.piece_parent[q - w.mesh_elements]; };
    auto on_cut = [&](int v) {  // every node the vertex is interpolated from lies on a cut surface
        for (int a = 0; a < npe; ++a)
            if (surface.bary[v][a] > 1e-12 && !snap_surface_root(w, snap_root(w, w.elements.nodes[surface.element[v]][a])))
                return false;
        return true;
    };
    surface.bound_to.assign(w.mesh_elements, {});
    surface.base_of.assign(w.mesh_elements, {});
    for (int v = 0; v < surface.vertex_count(); ++v) {
        const int q = live[surface.element[v]];
        surface.element[v] = q;
        surface.side[v] = q < w.mesh_elements ? 0 : w.snap.piece_side[q - w.mesh_elements];
        surface.bound_to[parent_of(q)].push_back(v);
    }
    for (size_t t = 0; t < surface.triangles.size(); ++t) {
        surface.triangle_owner[t] = parent_of(live[surface.triangle_owner[t]]);
        surface.base_of[surface.triangle_owner[t]].push_back(static_cast<int>(t));
        const auto& tri = surface.triangles[t];
        surface.cut_face[t] = w.elements.dim == 3 && on_cut(tri[0]) && on_cut(tri[1]) && on_cut(tri[2]) ? 1 : 0;
    }
    surface.pieces_of = surface.base_of;
}

}  // namespace

int snap_root(const World& w, int node) {
    return node < w.mesh_nodes ? node : w.snap.extra_root[node - w.mesh_nodes];
}

bool snap_surface_root(const World& w, int root) {
    return root >= w.mesh_nodes || (!w.snap.snapped.empty() && w.snap.snapped[root]);
}

std::vector<int> live_elements(const World& w) {
    std::vector<int> live;
    for (int e = 0; e < w.elements.count(); ++e)
        if (w.elements.weight[e] > 0.0) live.push_back(e);
    return live;
}

void prepare_snap_cut(World& w) {
    SnapMesh& s = w.snap;
    if (static_cast<int>(s.split.size()) == w.mesh_elements) return;
    const Elements& el = w.elements;
    const int npe = el.nodes_per_element();
    s.split.assign(w.mesh_elements, 0);
    s.level.assign(w.mesh_elements, {});
    s.pieces.assign(w.mesh_elements, {});
    s.snapped.assign(w.mesh_nodes, 0);
    s.boundary_node.assign(w.mesh_nodes, 0);
    s.boundary_edges.clear();
    if (static_cast<int>(w.enriched.sign.size()) != w.mesh_nodes) w.enriched.sign.assign(w.mesh_nodes, 0);
    // Boundary: facets (3D faces, 2D edges) of exactly one element; sorted, so no hashing order.
    std::vector<std::array<int, 3>> facets;
    for (int e = 0; e < w.mesh_elements; ++e)
        for (int skip = 0; skip < npe; ++skip) {
            std::array<int, 3> f{-1, -1, -1};
            int k = 0;
            for (int a = 0; a < npe; ++a)
                if (a != skip) f[k++] = el.nodes[e][a];
            if (k == 3 && f[1] > f[2]) std::swap(f[1], f[2]);  // sorted by hand: k is 2 or 3
            if (f[0] > f[1]) std::swap(f[0], f[1]);
            if (k == 3 && f[1] > f[2]) std::swap(f[1], f[2]);
            facets.push_back(f);
        }
    std::sort(facets.begin(), facets.end());
    const int fn = el.dim;  // nodes per facet
    for (size_t i = 0; i < facets.size();) {
        size_t j = i + 1;
        while (j < facets.size() && facets[j] == facets[i]) ++j;
        if (j - i == 1) {
            for (int a = 0; a < fn; ++a) s.boundary_node[facets[i][a]] = 1;
            for (int a = 0; a < fn; ++a)
                for (int b = a + 1; b < fn; ++b) s.boundary_edges.insert(edge_key(facets[i][a], facets[i][b]));
        }
        i = j;
    }
}

int apply_snap_events(World& w) {
    if (w.pending_cuts.empty()) return 0;
    prepare_snap_cut(w);
    SnapMesh& s = w.snap;
    const int points_before = w.nodes.count();
    const std::vector<double> mass_before = w.nodes.mass;
    const SnapQuadraticField field = keep_quadratic_field(w);
    std::vector<int> moved, split;
    for (const CutEvent& ev : w.pending_cuts)
        if (record_split(w, ev, moved)) split.push_back(ev.element);
    w.pending_cuts.clear();
    if (split.empty()) return 0;
    place_on_quadratic_field(w, field, moved, points_before);

    // Every mesh element the cut changed: split ones, those around a new point, those around a
    // moved node.
    const int npe = w.elements.nodes_per_element();
    std::vector<int> touched = split;
    for (int p = points_before; p < w.nodes.count(); ++p) {
        const auto st = star_of_root(w, p);
        touched.insert(touched.end(), st.begin(), st.end());
    }
    for (int a : moved) for_mesh_elements_of(w, a, [&](int f) { touched.push_back(f); });
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    for (int f : touched) regenerate(w, f);

    // Duplicate the surface roots the changed pieces hold, then give every changed piece its rest
    // shape (a piece inherits its parent's rotation as the first guess of the polar decomposition).
    std::vector<int> roots, rewritten;
    for (int f : touched)
        for (int q : s.pieces[f]) {
            const int slot = q - w.mesh_elements;
            if (!s.piece_live[slot]) continue;
            rewritten.push_back(q);
            for (int a = 0; a < npe; ++a)
                if (snap_surface_root(w, s.piece_roots[slot][a])) roots.push_back(s.piece_roots[slot][a]);
        }
    std::sort(roots.begin(), roots.end());
    roots.erase(std::unique(roots.begin(), roots.end()), roots.end());
    for (int r : roots) separate(w, r, rewritten);
    std::sort(rewritten.begin(), rewritten.end());
    rewritten.erase(std::unique(rewritten.begin(), rewritten.end()), rewritten.end());
    for (int q : rewritten) {
        compute_rest_shape(w, q);
        if (w.elements.rest_volume[q] < 0.0) {  // a sliver turned over (SnapMesh::inverted_pieces)
            w.elements.rest_volume[q] = -w.elements.rest_volume[q];
            ++s.inverted_pieces;
        }
    }
    for (int f : touched)  // spare slots: a finite shape, weight 0
        for (int q : s.pieces[f])
            if (!s.piece_live[q - w.mesh_elements]) compute_rest_shape(w, q);

    build_quadratic_pieces(w, field, rewritten);
    build_virtual_incidence(w);
    relump_conserving(w, mass_before);
    rebuild_surface(w, w.visual, s.visual_subdivisions);
    rebuild_surface(w, w.collision, s.collision_subdivisions);
    return static_cast<int>(split.size());
}

SystemDesc snap_cut_system(World& world) {
    prepare_snap_cut(world);
    return {"SnapCutSystem", kNodes | kElements | kCutEvents, kNodes | kElements | kSurfaces | kCutEvents | kSnap | kForces | kXfem,
            [](World& w) {
                const int dofs_before = 3 * w.nodes.count();
                const int snaps = w.snap.snaps, points = w.snap.points, copies = w.snap.copies;
                const int split = apply_snap_events(w);
                if (split > 0 && w.verbose)
                    fmt::print("t = {:.4g} s: {} elements split ({} nodes snapped, {} edge points, {} copies); DOFs {} -> {}\n",
                               w.time, split, w.snap.snaps - snaps, w.snap.points - points, w.snap.copies - copies,
                               dofs_before, 3 * w.nodes.count());
            }};
}

}  // namespace xcut
