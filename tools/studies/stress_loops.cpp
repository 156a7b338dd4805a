#include "tools/studies/stress_loops.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "engine/fragment_geometry.h"
#include "engine/world.h"
#include "systems/cut/pieces_system.h"

namespace xcut {
namespace {

constexpr double kPatch = kLoopPatch;
constexpr double kCell = 0.002;   ///< its cells [m]
constexpr double kMargin = 0.005; ///< the ellipse's bounding box from the held borders [m]
constexpr double kPast = 0.003;   ///< the cross-cut's reach past the rim [m]

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

/// Rest point X in the unit-circle frame of the ellipse at rest.
Eigen::Vector2d unit_of(const LoopRegions& r, const Vec3& X) {
    const double c = std::cos(r.angle), s = std::sin(r.angle);
    const Eigen::Vector2d d = (X - r.centre).head<2>();
    return Eigen::Vector2d((c * d.x() + s * d.y()) / r.a, (-s * d.x() + c * d.y()) / r.b);
}

/// The point of the ellipse at rest at angle th of its unit-circle frame.
Vec3 ellipse_at(const LoopRegions& r, double th) { return Ellipse{r.centre, r.angle, r.a, r.b}.at(std::cos(th), std::sin(th)); }

/// Where segment p -> q crosses the ellipse, p and q on either side of it (bisection to 1e-15 of it).
Vec3 rim_crossing(const LoopRegions& r, const Vec3& p, const Vec3& q) {
    const bool p_in = unit_of(r, p).norm() < 1.0;
    double lo = 0.0, hi = 1.0;
    for (int k = 0; k < 50; ++k) {
        const double mid = 0.5 * (lo + hi);
        ((unit_of(r, p + mid * (q - p)).norm() < 1.0) == p_in ? lo : hi) = mid;
    }
    return p + 0.5 * (lo + hi) * (q - p);
}

double polyline_length(const std::vector<Vec3>& p) {
    double l = 0.0;
    for (size_t k = 1; k < p.size(); ++k) l += (p[k] - p[k - 1]).norm();
    return l;
}

}  // namespace

void track_cross_cut(const World& w, const LoopRegions& r, std::vector<Vec3>& path) {
    if (!r.cross_after_loop || w.tools.count() < 2 || w.time > w.tools.trajectory[1].back().time + 1e-9) return;
    // x = A X + t over the lens's nodes, least squares (X from the ellipse's centre).
    Eigen::Matrix3d hh = Eigen::Matrix3d::Zero();
    Eigen::Matrix<double, 3, 2> hx = Eigen::Matrix<double, 3, 2>::Zero();
    int n = 0;
    for (int i = 0; i < w.mesh_nodes; ++i) {
        if (unit_of(r, w.nodes.rest[i]).norm() > 0.7) continue;
        const Eigen::Vector3d h((w.nodes.rest[i] - r.centre).x(), (w.nodes.rest[i] - r.centre).y(), 1.0);
        hh += h * h.transpose();
        hx += h * w.nodes.position[i].head<2>().transpose();
        ++n;
    }
    if (n < 3) return;
    const Eigen::Matrix<double, 3, 2> m = hh.ldlt().solve(hx);
    const Eigen::Matrix2d A = m.topRows<2>().transpose();
    const Eigen::Vector2d X = A.inverse() * (w.tools.position[1].head<2>() - m.row(2).transpose());
    path.push_back(r.centre + Vec3(X.x(), X.y(), 0.0));
}

bool path_regions(const LoopRegions& r, const std::vector<Vec3>& path, LoopRegions& out) {
    const int count = static_cast<int>(path.size());
    int first = -1, last = -1;  // the segments that enter first and leave last
    for (int k = 0; k + 1 < count; ++k) {
        const bool in = unit_of(r, path[k]).norm() < 1.0, next = unit_of(r, path[k + 1]).norm() < 1.0;
        if (!in && next && first < 0) first = k;
        if (in && !next && first >= 0) last = k;
    }
    if (first < 0 || last < 0) return false;
    std::vector<Vec3> chord{rim_crossing(r, path[first], path[first + 1])};
    chord.insert(chord.end(), path.begin() + first + 1, path.begin() + last + 1);
    chord.push_back(rim_crossing(r, path[last], path[last + 1]));
    const Eigen::Vector2d in = unit_of(r, chord.front()), out_at = unit_of(r, chord.back());
    const double from = std::atan2(out_at.y(), out_at.x()), to = std::atan2(in.y(), in.x());
    const double span = std::fmod(to - from + 4.0 * M_PI, 2.0 * M_PI);  // from the exit round to the entry, counter-clockwise
    out.area.clear(), out.perimeter.clear();
    for (const double way : {1.0, -1.0}) {
        const double turn = way > 0.0 ? span : 2.0 * M_PI - span;
        const int pieces = std::max(2, static_cast<int>(std::ceil(720.0 * turn / (2.0 * M_PI))));
        std::vector<Vec3> region = chord, arc{chord.back()};
        for (int k = 1; k < pieces; ++k) arc.push_back(ellipse_at(r, from + way * turn * k / pieces));
        arc.push_back(chord.front());
        region.insert(region.end(), arc.begin() + 1, arc.end() - 1);
        out.area.push_back(polygon_area(region));
        out.perimeter.push_back(polyline_length(chord) + polyline_length(arc));
    }
    return true;
}

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
    r.cross_after_loop = cross == 1;
    r.centre = (el.centre + Vec3(kLoopPull, kLoopPull, 0.0)) / kLoopStretch;
    r.angle = el.angle, r.a = el.a / kLoopStretch, r.b = el.b / kLoopStretch;
    if (regions) *regions = r;
    return s;
}

LoopTally loop_pieces(World& w, const LoopRegions& drawn, const std::vector<Vec3>& path) {
    LoopRegions regions = drawn;
    if (drawn.cross_after_loop) path_regions(drawn, path, regions);
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
    t.expected = 1 + static_cast<int>(regions.area.size());
    if (t.pieces != t.expected) return t.mismatch = 1, t;
    // The patch's area less the regions', its error the regions' (along the cuts round them).
    std::vector<std::pair<double, double>> want{{kPatch * kPatch, 0.0}};
    for (size_t k = 0; k < regions.area.size(); ++k) {
        want.front().first -= regions.area[k];
        want.front().second += regions.perimeter[k];
        want.push_back({regions.area[k], regions.perimeter[k]});
    }
    std::sort(want.begin() + 1, want.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
    for (size_t k = 0; k < want.size(); ++k) t.offset = std::max(t.offset, std::abs(big[k] - want[k].first) / want[k].second);
    t.mismatch = t.offset > kLoopAreaTolerance;
    return t;
}

}  // namespace xcut
