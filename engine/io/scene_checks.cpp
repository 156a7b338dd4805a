#include "engine/io/scene_checks.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "engine/error.h"

namespace xcut {
namespace {

bool allowed(const Scene& scene, const std::string& check) {
    return std::find(scene.allow.begin(), scene.allow.end(), check) != scene.allow.end();
}

std::string silence(const char* check) { return fmt::format(" (silence: \"allow\": [\"{}\"])", check); }

struct Box {
    Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
    void add(const Vec3& p) { lo = lo.cwiseMin(p), hi = hi.cwiseMax(p); }
    double distance(const Vec3& p) const { return (p - p.cwiseMax(lo).cwiseMin(hi)).norm(); }
};

/// Every body's box at rest, together.
Box bodies_box(const World& w) {
    Box b;
    for (int i = 0; i < w.mesh_nodes; ++i) b.add(w.nodes.rest[i]);
    return b;
}

/// The pose between two keyframes at fraction s (positions linear, orientations slerped).
Keyframe between(const Keyframe& a, const Keyframe& b, double s) {
    Keyframe k;
    k.time = a.time + s * (b.time - a.time);
    k.position = a.position + s * (b.position - a.position);
    k.orientation = a.orientation.slerp(s, b.orientation);
    return k;
}

/// How close tool i's blade or contact shape comes to the bodies' box over its trajectory [m]
/// (keyframes and 8 poses between each two), less its reach: <= 0 when it can touch them.
double closest_approach(const World& w, int i, const Box& box) {
    const ToolBodies& tb = w.tools;
    const ToolShape& shape = tb.shape[i];
    double reach = 0.0;  // the shape's bounding radius about its centre
    if (shape.kind == ToolShape::kSphere) reach = shape.radius;
    if (shape.kind == ToolShape::kCapsule) reach = shape.radius + 0.5 * shape.length;
    if (shape.kind == ToolShape::kBox) reach = shape.half_extent.norm();
    for (const Vec3& v : shape.vertices) reach = std::max(reach, (v - shape.centre).norm());
    double best = 1e300;
    const auto look = [&](const Keyframe& k) {
        if (tb.has_blade[i])
            for (int s = 0; s <= 8; ++s) {
                const Vec3 local = tb.blade_tip[i] + (s / 8.0) * (tb.blade_heel[i] - tb.blade_tip[i]);
                best = std::min(best, box.distance(k.position + k.orientation * local));
            }
        if (shape.kind != ToolShape::kNone)
            best = std::min(best, box.distance(k.position + k.orientation * shape.centre) - reach);
    };
    const auto& keys = tb.trajectory[i];
    for (size_t k = 0; k < keys.size(); ++k) {
        look(keys[k]);
        if (k + 1 < keys.size())
            for (int s = 1; s < 8; ++s) look(between(keys[k], keys[k + 1], s / 8.0));
    }
    return best;
}

void check_units(const Scene& scene, const World& w, std::vector<std::string>& out) {
    const BodyExtents rest = body_extents(w, true);
    for (size_t b = 0; b < rest.size.size(); ++b) {
        const MeshSpec& spec = b == 0 ? scene.mesh : scene.more_bodies[b - 1].mesh;
        if (spec.file.empty() || spec.placement.units_given) continue;
        const double size = rest.size[b];
        if (size >= kBodySizeMin && size <= kBodySizeMax) continue;
        out.push_back(fmt::format(
            "units: body \"{}\" ({}) measures {:.3g} m across, outside {:.0g}-{:.0g} m, and its mesh gives no \"units\": "
            "a mesh in {} needs \"units\": \"{}\" in its mesh section{}",
            w.body_names[b], spec.file, size, kBodySizeMin, kBodySizeMax, size > kBodySizeMax ? "millimetres" : "kilometres?",
            size > kBodySizeMax ? "mm" : "m", silence("units")));
    }
}

void check_materials(const World& w, std::vector<std::string>& out) {
    for (const Material& m : w.materials.list) {
        if (m.young < kTissueYoungMin || m.young > kTissueYoungMax)
            out.push_back(fmt::format("young: material \"{}\" has E = {:.3g} Pa, outside soft tissue's {:.0f} Pa-{:.0f} MPa "
                                      "(E is in Pa: 5 kPa is 5000){}",
                                      m.name, m.young, kTissueYoungMin, kTissueYoungMax / 1e6, silence("young")));
        if (m.density < kTissueDensityMin || m.density > kTissueDensityMax)
            out.push_back(fmt::format("density: material \"{}\" has {:.4g} kg/m^3, outside tissue's {:.0f}-{:.0f} kg/m^3 "
                                      "(water is 1000){}",
                                      m.name, m.density, kTissueDensityMin, kTissueDensityMax, silence("density")));
        if (m.poisson >= kLockingPoisson && !m.quadratic)
            out.push_back(fmt::format(
                "poisson: material \"{}\" has nu = {:.3g}: linear tetrahedra lock as nu nears 0.5 (volumetric "
                "locking, from about {:.2f}), so the tissue comes out too stiff, the more so the coarser the mesh: give "
                "the material \"element\": \"quadratic\" (tissue that is not cut; docs/elements.md), or use nu <= {:.2f} "
                "or a finer mesh and read displacements as a lower bound{}",
                m.name, m.poisson, kLockingPoisson, kLockingPoisson - 0.05, silence("poisson")));
    }
}

void check_tools(const Scene& scene, const World& w, std::vector<std::string>& out) {
    const Box box = bodies_box(w);
    for (int i = 0; i < w.tools.count(); ++i) {
        const bool scripted = i >= static_cast<int>(scene.devices.size()) || scene.devices[i].type == "scripted";
        if (!scripted || w.tools.trajectory[i].empty()) continue;
        if (!w.tools.has_blade[i] && w.tools.shape[i].kind == ToolShape::kNone) continue;
        const double gap = closest_approach(w, i, box);
        if (gap > 0.0)
            out.push_back(fmt::format("tool_reach: tool \"{}\" never comes within its {} of any body: over its "
                                      "trajectory it stays {:.3g} m from their bounding box{}",
                                      w.tools.name[i], w.tools.has_blade[i] ? "blade" : "contact shape", gap,
                                      silence("tool_reach")));
    }
}

void check_dt(const World& w, std::vector<std::string>& out) {
    if (w.solver.realtime || w.materials.list.empty()) return;
    double c = 0.0;  // the fastest elastic (bar) wave [m/s]
    for (const Material& m : w.materials.list) c = std::max(c, std::sqrt(m.young / m.density));
    const Box box = bodies_box(w);
    const double length = (box.hi - box.lo).maxCoeff();
    const double period = 2.0 * length / c;  // the longest such wave's period across the bodies [s]
    if (w.solver.dt > period)
        out.push_back(fmt::format(
            "dt: solver.dt {:.3g} s is longer than the slowest elastic wave's period across the body (2 L / c = "
            "2 x {:.3g} m / {:.3g} m/s = {:.3g} s): backward Euler damps every such wave within a step, so the motion "
            "comes out quasi-static (fine for a quasi-static scene){}",
            w.solver.dt, length, c, period, silence("dt")));
}

}  // namespace

BodyExtents body_extents(const World& w, bool at_rest) {
    const int bodies = static_cast<int>(w.body_names.size());
    std::vector<Box> box(bodies);
    std::vector<uint8_t> seen(w.mesh_nodes, 0);
    BodyExtents out;
    out.centre.assign(bodies, Vec3::Zero());
    out.size.assign(bodies, 0.0);
    std::vector<int> count(bodies, 0);
    const int npe = w.elements.nodes_per_element();
    for (int e = 0; e < w.mesh_elements; ++e) {
        const int b = e < static_cast<int>(w.elements.body.size()) ? w.elements.body[e] : 0;
        for (int a = 0; a < npe; ++a) {
            const int j = w.elements.nodes[e][a];
            if (seen[j]) continue;
            seen[j] = 1;
            const Vec3& x = at_rest ? w.nodes.rest[j] : w.nodes.position[j];
            box[b].add(x);
            out.centre[b] += x;
            ++count[b];
        }
    }
    for (int b = 0; b < bodies; ++b) {
        if (count[b] == 0) continue;
        out.centre[b] /= count[b];
        out.size[b] = (box[b].hi - box[b].lo).norm();
    }
    return out;
}

std::vector<std::string> plausibility_warnings(const Scene& scene, const World& world, int steps) {
    std::vector<std::string> all;
    check_units(scene, world, all);
    check_materials(world, all);
    check_tools(scene, world, all);
    if (steps > 0) check_dt(world, all);
    std::vector<std::string> out;
    for (std::string& w : all)
        if (!allowed(scene, w.substr(0, w.find(':')))) out.push_back(std::move(w));
    return out;
}

void check_output_volume(const Scene& scene, const World& w, int steps) {
    const OutputSettings& o = w.output;
    if (o.directory.empty() || !o.vtu) return;
    // A frame's arrays, uncompressed: per point 3 coordinates and 2 vectors (Float64), flags and the
    // file index; per cell its connectivity, offset, type and about 20 Float64/Int32 values; the
    // surface OBJ about 60 bytes a vertex. Compression and cut cells move this by a factor of ~2.
    const double frame = 90.0 * w.nodes.count() + 200.0 * w.elements.count() + 60.0 * w.visual.vertex_count();
    const double frames = std::floor(static_cast<double>(steps) / o.every) + 1.0;
    const double bytes = frame * frames;
    if (bytes > scene.max_output_gb * 1e9)
        throw InputError(scene.file, "output.every",
                         fmt::format("{} steps writing a frame every {} would write about {:.3g} GB, above the limit of "
                                     "{:.3g} GB (output.max_gb): raise output.every, or output.max_gb if meant",
                                     steps, o.every, bytes / 1e9, scene.max_output_gb));
}

void check_cut_fronts(const Scene& scene, const World& w) {
    for (size_t i = 0; i < scene.cuts.size(); ++i) {
        const ScriptedCut& c = scene.cuts[i];
        if (c.front_radius < 0.0) continue;
        const auto fail = [&](const std::string& why) { throw InputError(scene.file, fmt::format("cuts[{}].front", i), why); };
        if (scene.cutter == "snap") fail("crack-front enrichment is XFEM's: it needs \"cutter.type\": \"xfem\"");
        if (scene.cut_front == "progressive")
            fail("the front is enriched in the elements the cut leaves whole, which the \"progressive\" front splits: use "
                 "\"cutter.front\": \"semi\"");
        if (scene.tip_radius >= 0.0) fail("not with \"cutter.tip\": the blades' tips take the enrichment over");
        if (w.quadratic.count() > 0) fail("the branch functions enrich linear elements only (material.element \"linear\")");
        if (!c.at_rest && c.time > 0.0)
            fail("the front is placed on the body at rest: draw the polygon there (\"frame\": \"rest\") or cut at time 0");
    }
}

std::vector<std::string> end_of_run_notes(const World& w) {
    std::vector<std::string> out;
    const BodyExtents rest = body_extents(w, true), now = body_extents(w, false);
    for (size_t b = 0; b < rest.size.size(); ++b) {
        const double moved = (now.centre[b] - rest.centre[b]).norm();
        if (moved > rest.size[b])
            out.push_back(fmt::format("body \"{}\" moved {:.3g} m, more than its own size ({:.3g} m): it left the scene "
                                      "(unsupported under gravity? a mesh in mm read as m? E in kPa written as Pa?)",
                                      w.body_names[b], moved, rest.size[b]));
    }
    const bool cuts = (w.present() & kCutEvents) && w.step > 0;
    for (int i = 0; cuts && i < w.tools.count(); ++i) {
        const auto& split = w.cut_state.split_by_tool;
        if (w.tools.has_blade[i] && (i >= static_cast<int>(split.size()) || split[i] == 0))
            out.push_back(fmt::format("tool \"{}\" cut nothing: its blade crossed no element", w.tools.name[i]));
    }
    // A blade without a face pushed along its own edge through the tissue (a stab) sweeps no
    // surface: say how far. A blade with one (blade.back) cuts with its face.
    const std::vector<double>& stab = w.cut_state.stab_travel;
    for (int i = 0; i < static_cast<int>(stab.size()) && i < w.tools.count(); ++i)
        if (stab[i] > w.cut_state.mean_edge && w.cut_state.mean_edge > 0.0 &&
            (i >= static_cast<int>(w.tools.blade_back.size()) || w.tools.blade_back[i] == Vec3::Zero()))
            out.push_back(fmt::format(
                "tool \"{}\" moved {:.3g} mm along its own edge inside the tissue (a stab): a cut is the surface its "
                "edge sweeps, and an edge moving along itself sweeps none, so that travel made no incision; move the "
                "blade across its edge to cut",
                w.tools.name[i], 1e3 * stab[i]));
    // Per tool, the elements its blade crossed and left uncut, and why: one line each.
    const auto per_tool = [&](const std::vector<int>& count, auto&& line) {
        for (int i = 0; i < static_cast<int>(count.size()) && i < w.tools.count(); ++i)
            if (count[i] > 0) out.push_back(line(w.tools.name[i], count[i], count[i] == 1 ? "" : "s"));
    };
    // A 3D blade carries a front only where its edge crosses the tissue whole (straight fronts).
    per_tool(w.tips.blade_not_through, [&](const std::string& tool, int n, const char* s) {
        return fmt::format("tool \"{}\" carried no crack front in {} step{}: its edge ended inside the tissue (or "
                           "crossed it more than once), and xcut enriches a straight front through the tissue whole, not "
                           "one with an end or a corner inside it (docs/xfem.md); its cut ran there without one",
                           tool, n, s);
    });
    // A cut across an earlier wound where this world does not cut an element again.
    constexpr const char* kRecutLimits =
        "xcut cuts an element again with linear elements, the XFEM cutter and no crack tips, up to 4 cuts per "
        "element, in 2D and, with \"cutter.recut\": true, in 3D (docs/xfem.md); elsewhere they keep their cuts: an "
        "incision that meets a wound stops about an element short of it, and a closed loop does not free its piece";
    per_tool(w.cut_state.recut_ignored, [&](const std::string& tool, int n, const char* s) {
        return fmt::format("tool \"{}\" crossed {} element{} already cut along another plane and did not cut them "
                           "again: {}", tool, n, s, kRecutLimits);
    });
    if (w.cut_plan.recut_ignored > 0)
        out.push_back(fmt::format("the scripted cuts crossed {} element{} already cut along another plane and did not "
                                  "cut them again: {}", w.cut_plan.recut_ignored,
                                  w.cut_plan.recut_ignored == 1 ? "" : "s", kRecutLimits));
    // A blade whose path closed a loop (2D) while no piece was freed: a bridge still joins it. (The
    // material closes where the tissue has moved to, so a piece may come free before the path in
    // the world crosses itself: any piece since the path began counts.)
    const CutState& cs = w.cut_state;
    for (int i = 0; i < static_cast<int>(cs.loop_time.size()) && i < w.tools.count(); ++i) {
        if (cs.loop_time[i] < 0.0 || i >= static_cast<int>(cs.split_by_tool.size()) || cs.split_by_tool[i] == 0) continue;
        const int j = cs.loop_with[i];
        if (j < i && cs.loop_with[j] == i && cs.loop_time[j] >= 0.0 && cs.split_by_tool[j] > 0) continue;  // said for j
        const double since = std::min(cs.path_time[i], cs.path_time[j]);
        const bool freed = std::any_of(w.pieces.log.begin(), w.pieces.log.end(),
                                       [&](const PieceEvent& p) { return p.time >= since - 1e-12; });
        if (freed) continue;
        const std::string loop = j == i ? fmt::format("tool \"{}\"'s path crossed its own incision", w.tools.name[i])
                                        : fmt::format("the paths of tools \"{}\" and \"{}\" crossed a second time",
                                                      w.tools.name[j], w.tools.name[i]);
        out.push_back(fmt::format("{} at {:g} s (a closed loop), but no piece was freed: tissue still joins the inside "
                                  "to the outside somewhere along the loop (docs/xfem.md, Limits: a scalpel drawn round "
                                  "an ellipse)", loop, cs.loop_time[i]));
    }
    const Grasps& g = w.grasps;  // jaws that closed on nothing
    for (int i = 0; i < g.count() && i < w.tools.count(); ++i)
        if (g.radius[i] > 0.0 && g.state[i] != Grasps::kWaiting && g.held_at_close[i] == 0)
            out.push_back(fmt::format("tool \"{}\" closed its jaws at {:g} s on no skin: no surface vertex of the tissue "
                                      "lay within {:g} mm of their centre, so it held nothing (move the tool onto the "
                                      "tissue or widen \"grasp.radius\")",
                                      w.tools.name[i], g.close[i], 1e3 * g.radius[i]));
    per_tool(w.cut_state.on_skin_ignored, [](const std::string& tool, int n, const char* s) {
        return fmt::format("tool \"{}\" lay on the tissue's surface in {} element{}: its cut there stayed within {:g} "
                           "of an element's edge from the skin, a flap thinner than that, so it made none (docs/xfem.md)",
                           tool, n, s, kThinFlapFraction);
    });
    // A surface the cuts left open, pinched or with triangles without area (the MappingSystem
    // checks it after each step that cuts it where elements are cut again in 3D): drawn, exported
    // and touched with a hole.
    for (const auto& [name, s] : {std::pair{"visual", &w.visual}, std::pair{"collision", &w.collision}})
        if (s->defects_since >= 0.0)
            out.push_back(fmt::format("the {} surface is not closed and 2-manifold as drawn since t = {:g} s: {} open "
                                      "edges, {} pinched (used more than once each way), {} triangles without area "
                                      "(cutting elements again in 3D, \"cutter.recut\", still leaves such holes "
                                      "where several cuts meet in one element: docs/BENCHMARKS.md)",
                                      name, s->defects_since, s->open_edges, s->pinched_edges, s->zero_area));
    return out;
}

}  // namespace xcut
