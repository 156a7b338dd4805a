#include "systems/cut/blade_front.h"

#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <vector>

#include "systems/kernels/front_enrichment.h"

namespace xcut {
namespace {

/// Where the edge's stretches in the tissue may fail to meet, and its ends lie outside the
/// tissue, against the edge's length: rounding [-].
constexpr double kEdgeTolerance = 1e-9;

/// One live tetrahedron's stretch of the edge A + s (B - A), s in [from, to], and the barycentric
/// coordinates of A and of B - A in it (current coordinates).
struct Stretch {
    int e;
    bool cut;
    double from, to;
    Eigen::Vector4d at_a, along;
};

/// The stretch of segment A -> B inside tetrahedron x, false if it misses it. Barycentric
/// coordinates are linear along the segment; each must stay >= 0.
bool clip(const std::array<Vec3, 4>& x, const Vec3& A, const Vec3& B, Stretch& s) {
    Eigen::Matrix3d D;
    D << x[1] - x[0], x[2] - x[0], x[3] - x[0];
    const Eigen::PartialPivLU<Eigen::Matrix3d> lu(D);
    if (!(std::abs(D.determinant()) > 0.0)) return false;
    const Vec3 la = lu.solve(A - x[0]), lb = lu.solve(B - x[0]);
    s.at_a << 1.0 - la.sum(), la;
    const Eigen::Vector4d at_b(1.0 - lb.sum(), lb.x(), lb.y(), lb.z());
    s.along = at_b - s.at_a;
    s.from = 0.0, s.to = 1.0;
    for (int k = 0; k < 4; ++k) {
        const double a = s.at_a[k], d = s.along[k];
        if (d == 0.0) {
            if (a < 0.0) return false;
        } else if (d > 0.0) {
            s.from = std::max(s.from, -a / d);
        } else {
            s.to = std::min(s.to, -a / d);
        }
    }
    return s.to > s.from;
}

/// A front's line through `point` along unit `tangent` (its crack's direction any normal to it).
FrontFrame line_through(const Vec3& point, const Vec3& tangent) {
    const Vec3 any = std::abs(tangent.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
    return FrontFrame{point, tangent.cross(any).normalized(), tangent};
}

std::array<Vec3, 4> rest_tet(const World& w, int e) {
    const auto& n = w.elements.nodes[e];
    return {w.nodes.rest[n[0]], w.nodes.rest[n[1]], w.nodes.rest[n[2]], w.nodes.rest[n[3]]};
}

Vec3 rest_at(const World& w, const Stretch& s, double at) {
    const auto& n = w.elements.nodes[s.e];
    Vec3 X = Vec3::Zero();
    for (int k = 0; k < 4; ++k) X += (s.at_a[k] + at * s.along[k]) * w.nodes.rest[n[k]];
    return X;
}

}  // namespace

BladeFront blade_rest_front(const World& w, int t, Vec3& point, Vec3& tangent) {
    const ToolBodies& tb = w.tools;
    const Vec3 A = tb.position[t] + tb.orientation[t] * tb.blade_tip[t];
    const Vec3 B = tb.position[t] + tb.orientation[t] * tb.blade_heel[t];
    const Vec3 lo = A.cwiseMin(B), hi = A.cwiseMax(B);
    const std::vector<int>& cut_of = w.cuts.cut_of_element;
    std::vector<Stretch> in;
    for (int e = 0; e < w.mesh_elements; ++e) {
        // The tissue: the live elements and the cut ones (by their mesh nodes: the wound's
        // elements, where an edge partly in its own wound also is).
        const bool cut = e < static_cast<int>(cut_of.size()) && cut_of[e] >= 0;
        if (w.elements.weight[e] <= 0.0 && !cut) continue;
        const auto& n = w.elements.nodes[e];
        const std::array<Vec3, 4> x{w.nodes.position[n[0]], w.nodes.position[n[1]], w.nodes.position[n[2]],
                                    w.nodes.position[n[3]]};
        Vec3 box_lo = x[0], box_hi = x[0];
        for (int k = 1; k < 4; ++k) box_lo = box_lo.cwiseMin(x[k]), box_hi = box_hi.cwiseMax(x[k]);
        if ((hi.array() < box_lo.array()).any() || (lo.array() > box_hi.array()).any()) continue;
        Stretch s{e, cut, 0.0, 0.0, {}, {}};
        if (clip(x, A, B, s)) in.push_back(s);
    }
    if (in.empty()) return BladeFront::kNone;
    // The stretches in edge order must join into one that ends short of both of the edge's ends.
    std::vector<Stretch> sorted = in;
    std::sort(sorted.begin(), sorted.end(), [](const Stretch& a, const Stretch& b) {
        return a.from < b.from || (a.from == b.from && a.e < b.e);
    });
    double reach = sorted.front().from;
    const double from = sorted.front().from;
    for (const Stretch& s : sorted) {
        if (s.from > reach + kEdgeTolerance) return BladeFront::kNotThrough;
        reach = std::max(reach, s.to);
    }
    const double to = reach;
    if (from <= kEdgeTolerance || to >= 1.0 - kEdgeTolerance) return BladeFront::kNotThrough;
    const auto holding = [&](double at, bool uncut_only) -> const Stretch* {
        const Stretch* best = nullptr;
        for (const Stretch& s : sorted)
            if (s.from <= at && at <= s.to && (!uncut_only || !s.cut) && (!best || s.e < best->e)) best = &s;
        return best;
    };
    const double middle = 0.5 * (from + to);
    const Stretch* m = holding(middle, true);
    if (!m) return BladeFront::kNone;  // in its own wound
    // The tangent from the first to the last point in uncut tissue (a cut element's mesh nodes
    // place one of its sides only).
    const Stretch *first = m, *last = m;
    for (const Stretch& s : sorted)
        if (!s.cut) first = s.from < first->from ? &s : first, last = s.to > last->to ? &s : last;
    const Vec3 d = rest_at(w, *last, last->to) - rest_at(w, *first, first->from);
    if (!(d.norm() > 0.0)) return BladeFront::kNone;
    point = rest_at(w, *m, middle);
    tangent = d.normalized();
    // The front is the whole line (enrich_crack_front): it must not run on through tissue the
    // edge is not in (a fold, a second layer), beyond a mean edge of rounding and drift.
    const double pad = std::max(w.cut_state.mean_edge, kEdgeTolerance * d.norm());
    const double first_at = std::min((rest_at(w, *first, first->from) - point).dot(tangent),
                                     (rest_at(w, *holding(from, false), from) - point).dot(tangent));
    const double last_at = std::max((rest_at(w, *last, last->to) - point).dot(tangent),
                                    (rest_at(w, *holding(to, false), to) - point).dot(tangent));
    const FrontFrame line = line_through(point, tangent);
    for (int e = 0; e < w.mesh_elements; ++e) {
        double f = 0.0, g = 0.0;
        if (w.elements.weight[e] > 0.0 && front_in_tet(rest_tet(w, e), line, f, g) && (g < first_at - pad || f > last_at + pad))
            return BladeFront::kNotThrough;
    }
    return BladeFront::kFront;
}

bool front_in_uncut_tissue(const World& w, const Vec3& point, const Vec3& tangent) {
    const FrontFrame line = line_through(point, tangent);
    for (int e = 0; e < w.mesh_elements; ++e) {
        double f = 0.0, g = 0.0;
        if (w.elements.weight[e] > 0.0 && front_in_tet(rest_tet(w, e), line, f, g)) return true;
    }
    return false;
}

}  // namespace xcut
