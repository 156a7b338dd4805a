#include "tools/studies/stress_loops.h"

#include <algorithm>
#include <cmath>

#include "engine/fragment_geometry.h"
#include "engine/world.h"
#include "systems/xfem_queries.h"
#include "systems/cut/material_anchor.h"
#include "systems/cut/pieces_system.h"
#include "systems/cut/recut.h"
#include "tools/studies/parted_regions.h"

namespace xcut {
namespace {

constexpr double kPatch = kLoopPatch;
constexpr double kCell = 0.002;   ///< its cells [m]
constexpr double kMargin = 0.005; ///< the ellipse's bounding box from the held borders [m]
constexpr double kPast = 0.003;   ///< the cross-cut's reach past the rim [m]
static_assert(kLoopJoin == kJoinFraction * kCell * 1.4142135623730951, "kLoopJoin: the cutter's join on the cells' diagonal");

/// An ellipse in the patch's plane: centre, angle of its major axis, semi-axes [m].
struct Ellipse {
    Vec3 centre;
    double angle, a, b;
    /// The world point of (x, y) in the unit-circle frame (x a along the major axis, y b across).
    Vec3 at(double x, double y) const {
        const double c = std::cos(angle), s = std::sin(angle), u = a * x, v = b * y;
        return centre + Vec3(c * u - s * v, s * u + c * v, 0.0);
    }
};

/// A scalpel point (2D: its edge along z through the sheet) moving through `keys`.
void add_scalpel(Scene& s, const std::string& name, std::vector<Keyframe> keys) {
    ToolBodies& tb = s.tools;
    tb.name.push_back(name);
    tb.has_blade.push_back(1);
    tb.blade_tip.push_back(Vec3::Zero());
    tb.blade_heel.push_back(Vec3(0, 0, 0.001));
    tb.blade_back.push_back(Vec3::Zero());
    tb.position.push_back(keys.front().position);
    tb.orientation.push_back(keys.front().orientation);
    tb.trajectory.push_back(std::move(keys));
}

Keyframe key(double time, const Vec3& position) {
    Keyframe k;
    k.time = time, k.position = position;
    return k;
}

/// The regions the chord at signed distance d along unit normal n (unit-circle frame) divides the
/// ellipse into: each segment's area (closed form: a b (acos d - d sqrt(1 - d^2)) beyond the line)
/// and its boundary, the arc (summed over 720 pieces) and the chord.
void chord_regions(const Ellipse& el, const Vec3& n, double d, double chord, LoopRegions& r) {
    const double beyond = el.a * el.b * (std::acos(d) - d * std::sqrt(1.0 - d * d));
    r.area = {beyond, M_PI * el.a * el.b - beyond};
    r.perimeter = {chord, chord};
    const int parts = 720;
    for (int k = 0; k < parts; ++k) {
        const double t0 = 2.0 * M_PI * k / parts, t1 = 2.0 * M_PI * (k + 1) / parts, tm = 0.5 * (t0 + t1);
        const double length = (el.at(std::cos(t1), std::sin(t1)) - el.at(std::cos(t0), std::sin(t0))).norm();
        r.perimeter[n.x() * std::cos(tm) + n.y() * std::sin(tm) > d ? 0 : 1] += length;
    }
}

/// The ellipse's perimeter [m] (Ramanujan's second approximation, relative error below 1e-9 here).
double ellipse_perimeter(double a, double b) {
    const double h = (a - b) * (a - b) / ((a + b) * (a + b));
    return M_PI * (a + b) * (1.0 + 3.0 * h / (10.0 + std::sqrt(4.0 - 3.0 * h)));
}

}  // namespace

Scene random_loop_scene(std::mt19937_64& rng, LoopRegions* regions) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    Scene s;
    s.name = "stress loops";
    s.mesh.generator = "plate";
    s.mesh.grid.size = Vec3(kPatch, kPatch, 0.0);
    s.mesh.grid.cells = Eigen::Vector3i(20, 20, 1);
    s.material.thickness = 0.002;
    s.solver.cg_tolerance = 1e-8;
    s.solver.cg_max_iterations = 800;  // past the stress bound, so that a miss is seen
    s.solver.dt = kLoopStep;
    s.solver.damping_mass = 1.0;
    s.solver.damping_stiffness = 0.01;
    s.output.directory.clear();
    s.visual_subdivisions = 1;
    const double far = 1.0, edge = 1e-9, pull = kLoopPull;
    s.constraints.boxes.push_back({Vec3(-far, -far, -far), Vec3(edge, far, far), 7, Vec3(-pull, 0, 0)});
    s.constraints.boxes.push_back({Vec3(kPatch - edge, -far, -far), Vec3(far, far, far), 7, Vec3(pull, 0, 0)});
    s.constraints.boxes.push_back({Vec3(-far, -far, -far), Vec3(far, edge, far), 7, Vec3(0, -pull, 0)});
    s.constraints.boxes.push_back({Vec3(-far, kPatch - edge, -far), Vec3(far, far, far), 7, Vec3(0, pull, 0)});

    Ellipse el{Vec3::Zero(), M_PI * u(rng), 0.006 + 0.007 * u(rng), 0.0};
    el.b = 0.004 + (std::min(0.009, el.a) - 0.004) * u(rng);
    const double c = std::cos(el.angle), sn = std::sin(el.angle);
    const double ex = std::hypot(el.a * c, el.b * sn), ey = std::hypot(el.a * sn, el.b * c);
    el.centre = Vec3(ex + kMargin + (kPatch - 2.0 * (ex + kMargin)) * u(rng),
                     ey + kMargin + (kPatch - 2.0 * (ey + kMargin)) * u(rng), 0.0);
    const double start = 2.0 * M_PI * u(rng), way = u(rng) < 0.5 ? 1.0 : -1.0;
    const int cross = static_cast<int>(3.0 * u(rng));  // 0: none, 1: after the loop, 2: before it
    const double psi = M_PI * u(rng), d = u(rng) - 0.5;

    const double loop_from = cross == 2 ? 0.8 : 0.2;
    std::vector<Keyframe> loop{key(0.0, el.at(std::cos(start), std::sin(start)))};
    for (int k = 0; k <= 60; ++k) {
        const double th = start + way * (2.0 * M_PI + 0.4) * k / 60;
        loop.push_back(key(loop_from + 2.0 * k / 60, el.at(std::cos(th), std::sin(th))));
    }
    add_scalpel(s, "loop", std::move(loop));

    LoopRegions r{{M_PI * el.a * el.b}, {ellipse_perimeter(el.a, el.b)}};
    if (cross > 0) {
        const Vec3 m(std::cos(psi), std::sin(psi), 0.0), n(-std::sin(psi), std::cos(psi), 0.0);
        const double half = std::sqrt(1.0 - d * d);
        const Vec3 p = el.at(d * n.x() - half * m.x(), d * n.y() - half * m.y());
        const Vec3 q = el.at(d * n.x() + half * m.x(), d * n.y() + half * m.y());
        const Vec3 along = (q - p).normalized();
        const double from = cross == 1 ? 2.4 : 0.0;
        std::vector<Keyframe> keys{key(0.0, p - kPast * along)};
        if (from > 0.0) keys.push_back(key(from, p - kPast * along));
        keys.push_back(key(from + 0.6, q + kPast * along));
        add_scalpel(s, "cross", std::move(keys));
        chord_regions(el, n, d, (q - p).norm(), r);
    }
    // At rest: the paths are drawn on the patch stretched by its borders (x = S X - pull).
    for (double& a : r.area) a /= kLoopStretch * kLoopStretch;
    for (double& p : r.perimeter) p /= kLoopStretch;
    if (regions) *regions = r;
    return s;
}

/// The rest point of the material nearest to p (current), where no material holds p: over each
/// whole triangle and each fragment of a cut one (its rest polygon carried by its node copies), the
/// nearest point of its current shape, pulled back through that shape. False if none is within
/// `reach` [m].
bool nearest_material(const World& w, const Vec3& p, double reach, Vec3& rest) {
    double best = reach;
    const auto consider = [&](const std::array<Vec3, 3>& X, int carrier, const std::vector<Vec3>& polygon) {
        const auto& n = w.elements.nodes[carrier];
        const std::array<Vec3, 3> x{w.nodes.position[n[0]], w.nodes.position[n[1]], w.nodes.position[n[2]]};
        const auto map = [](const std::array<Vec3, 3>& from, const std::array<Vec3, 3>& to, const Vec3& q) {
            const Vec3 b = triangle_barycentric(from, q);
            return Vec3(b.x() * to[0] + b.y() * to[1] + b.z() * to[2]);
        };
        for (size_t k = 0; k < polygon.size(); ++k) {
            const Vec3 q = nearest_on(map(X, x, polygon[k]), map(X, x, polygon[(k + 1) % polygon.size()]), p);
            const double d = (q - p).head<2>().norm();
            if (d < best) best = d, rest = map(x, X, q);
        }
    };
    for (int e = 0; e < w.mesh_elements; ++e) {
        const std::array<Vec3, 3> X = corners(w, e);
        const int c = w.cuts.cut_of_element.empty() ? -1 : w.cuts.cut_of_element[e];
        if (c < 0) {
            consider(X, e, {X.begin(), X.end()});
            continue;
        }
        CutLine first;
        const std::span<const CutLine> lines = lines_in(w, c, first);
        for (const int v : fragments_of(w, c))
            consider(X, w.virtual_elements.element[v],
                     fragment_polygon(X, lines.data(), static_cast<int>(lines.size()), w.virtual_elements.mask[v]));
    }
    return best < reach;
}

void track_blades(const World& w, std::vector<std::vector<Vec3>>& paths) {
    paths.resize(w.tools.count());
    for (int i = 0; i < w.tools.count(); ++i) {
        if (!w.tools.has_blade[i]) continue;
        const Vec3& p = w.tools.position[i];
        bool held = false;
        for (int e = 0; e < w.mesh_elements && !held; ++e) {
            const MaterialPoint m = material_in(w, e, p);
            if (m.element < 0) continue;
            paths[i].push_back(material_rest(w, m));
            held = true;
        }
        Vec3 rest;
        if (!held && nearest_material(w, p, kLoopWoundReach, rest)) paths[i].push_back(rest);
    }
}

LoopTally loop_pieces(World& w, const std::vector<std::vector<Vec3>>& paths) {
    count_pieces(w);
    const double thickness = w.materials.list.front().thickness;
    double element = 0.0;  // the mean element's area [m^2]
    for (int e = 0; e < w.mesh_elements; ++e) element += w.elements.rest_volume[e] / thickness / w.mesh_elements;
    std::vector<double> big;
    LoopTally t;
    for (size_t k = 0; k < w.pieces.volume.size(); ++k) {
        if (w.pieces.sliver[k]) continue;
        const double area = w.pieces.volume[k] / thickness;
        if (area >= element) big.push_back(area);
        else ++t.strips;
    }
    std::sort(big.rbegin(), big.rend());
    t.pieces = static_cast<int>(big.size());

    // The regions the paths part, the loop closed across its gap where its end passes within
    // kLoopJoin of its start without crossing it (the cutter joins the passes there).
    std::vector<std::vector<Vec3>> cuts = paths;
    Vec3 from = Vec3::Zero(), to = Vec3::Zero();
    if (!cuts.empty() && cuts[0].size() > 2) t.gap = closest_return(cuts[0], from, to);
    if (t.gap > 0.0 && t.gap <= kLoopJoin) cuts.push_back({from, to});
    const PartedRegions parted = parted_regions(cuts, Vec3::Zero(), Vec3(kPatch, kPatch, 0.0), kLoopRaster);
    std::vector<std::pair<double, double>> want;  // area, boundary: the regions of an element or more
    for (size_t k = 0; k < parted.area.size(); ++k)
        if (parted.area[k] >= element) want.push_back({parted.area[k], std::max(parted.boundary[k], kLoopRaster)});
    std::sort(want.rbegin(), want.rend());
    t.expected = static_cast<int>(want.size());
    if (t.pieces != t.expected) return t.mismatch = 1, t;
    for (size_t k = 0; k < want.size(); ++k) t.offset = std::max(t.offset, std::abs(big[k] - want[k].first) / want[k].second);
    t.mismatch = t.offset > kLoopAreaTolerance;
    return t;
}

}  // namespace xcut
