#include "systems/kernels/front_enrichment.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>

namespace xcut {

FrontValues front_functions(const FrontFrame& front, const Vec3d& X, int side) {
    const Vec3d d = front.direction, n = front.normal(), rel = X - front.point;
    static const TipFrame plane{Vec2::Zero(), Vec2::UnitX()};  // the front's plane: x1 along d, x2 along n
    const BranchValues b = branch_functions(plane, Vec2(rel.dot(d), rel.dot(n)), side);
    FrontValues out;
    out.f = b.f;
    for (int l = 0; l < 4; ++l) out.grad[l] = b.grad[l].x() * d + b.grad[l].y() * n;
    return out;
}

double front_distance(const FrontFrame& front, const Vec3d& X) {
    const Vec3d rel = X - front.point;
    return (rel - rel.dot(front.tangent) * front.tangent).norm();
}

namespace {

double tet_size(const std::array<Vec3d, 4>& X) {
    double h = 0.0;
    for (int a = 0; a < 4; ++a)
        for (int b = a + 1; b < 4; ++b) h = std::max(h, (X[a] - X[b]).norm());
    return h;
}

/// The part of convex polygon `p` where a x + b y + c >= 0 (Sutherland & Hodgman, CACM 17, 1974).
std::vector<Vec2> clip_polygon(const std::vector<Vec2>& p, double a, double b, double c) {
    std::vector<Vec2> out;
    const int n = static_cast<int>(p.size());
    for (int i = 0; i < n; ++i) {
        const Vec2 &u = p[i], &v = p[(i + 1) % n];
        const double lu = a * u.x() + b * u.y() + c, lv = a * v.x() + b * v.y() + c;
        if (lu >= 0.0) out.push_back(u);
        if ((lu > 0.0 && lv < 0.0) || (lu < 0.0 && lv > 0.0)) out.push_back(u + lu / (lu - lv) * (v - u));
    }
    return out.size() >= 3 ? out : std::vector<Vec2>{};
}

/// The section of a tetrahedron (corners in the front's coordinates: x1, x2 and the height x3) at
/// height s: where its edges cross the plane, counter-clockwise; empty if fewer than three.
std::vector<Vec2> section(const std::array<Vec3d, 4>& L, double s) {
    std::vector<Vec2> p;
    for (int a = 0; a < 4; ++a)
        for (int b = a + 1; b < 4; ++b) {
            const double ha = L[a].z() - s, hb = L[b].z() - s;
            if ((ha < 0.0 && hb > 0.0) || (ha > 0.0 && hb < 0.0)) p.push_back(L[a].head<2>() + ha / (ha - hb) * (L[b] - L[a]).head<2>());
        }
    if (p.size() < 3) return {};
    Vec2 centre = Vec2::Zero();
    for (const Vec2& q : p) centre += q / static_cast<double>(p.size());
    std::sort(p.begin(), p.end(), [&](const Vec2& u, const Vec2& v) {
        return std::atan2(u.y() - centre.y(), u.x() - centre.x()) < std::atan2(v.y() - centre.y(), v.x() - centre.x());
    });
    return p;
}

/// Gauss-Legendre points and weights on [0, 1].
struct GaussRule {
    std::vector<double> x, w;
};

/// Gauss points per direction of a section's Duffy triangles at least, where the front's point lies
/// outside the section: its fan's triangles are signed, and a rule's error in their cancellation
/// can make the branch functions' stiffness indefinite (2 x 2 points did, on the stress suite's
/// fronts: a pivot -0.04 of the largest; 3 x 3 held over 10,000 trajectories).
constexpr int kSignedFanOrder = 3;

/// Adds the rule of convex polygon `p` (counter-clockwise, in the front's plane: the front's point at
/// the origin) as the signed fan of triangles from the origin over its edges, each by Duffy's collapse
/// onto the origin, its weights negated where its edge faces the origin (the origin outside `p`):
/// the rule is exact in r at the front's point wherever that lies, inside, on or beside the polygon.
/// Rule `positive` where every weight is (the origin inside or on `p`), `signed_rule` where not.
void signed_fan(const std::vector<Vec2>& p, const GaussRule& positive, const GaussRule& signed_rule, double min_area,
                std::vector<QuadraturePoint>& out) {
    const int n = static_cast<int>(p.size());
    bool outside = false;
    for (int i = 0; i < n; ++i) outside |= cross2(p[i], p[(i + 1) % n]) < -min_area;
    const GaussRule& r = outside ? signed_rule : positive;
    for (int i = 0; i < n; ++i) {
        const Vec2 &b = p[i], &c = p[(i + 1) % n];
        const size_t first = out.size();
        add_duffy(Vec2::Zero(), b, c, r.x, r.w, min_area, out);
        if (cross2(b, c) < 0.0)
            for (size_t k = first; k < out.size(); ++k) out[k].weight = -out[k].weight;
    }
}

/// The slabs' ends of the part {x : a_m . x + c_m >= 0} (the front's coordinates): the heights of its
/// corners (where three of its planes meet inside all the others) and of where the front (x1 = x2 =
/// 0) enters and leaves it, [lo, hi] (lo >= hi: it misses it). Between two, each section is one
/// convex polygon whose corners move linearly and the front's point stays inside, on or outside it:
/// the section's integral is smooth in the height. Sorted.
std::vector<double> slab_ends(const std::vector<Vec3d>& a, const std::vector<double>& c, double h, double& lo, double& hi) {
    const int planes = static_cast<int>(a.size());
    std::vector<double> ends;
    for (int i = 0; i < planes; ++i)
        for (int j = i + 1; j < planes; ++j)
            for (int k = j + 1; k < planes; ++k) {
                Mat3d A;
                A << a[i].transpose(), a[j].transpose(), a[k].transpose();
                if (std::abs(A.determinant()) <= 1e-12 * a[i].norm() * a[j].norm() * a[k].norm()) continue;
                const Vec3d v = A.partialPivLu().solve(-Vec3d(c[i], c[j], c[k]));
                bool inside = true;
                for (int m = 0; m < planes && inside; ++m) inside = a[m].dot(v) + c[m] >= -1e-12 * h * a[m].norm();
                if (inside) ends.push_back(v.z());
            }
    lo = -std::numeric_limits<double>::infinity(), hi = std::numeric_limits<double>::infinity();
    for (int m = 0; m < planes; ++m) {
        if (a[m].z() > 0.0) lo = std::max(lo, -c[m] / a[m].z());
        else if (a[m].z() < 0.0) hi = std::min(hi, -c[m] / a[m].z());
        else if (c[m] < 0.0) hi = lo;  // the line lies outside this plane
    }
    if (hi > lo) ends.push_back(lo), ends.push_back(hi);
    std::sort(ends.begin(), ends.end());
    return ends;
}

/// The conical product rule of tetrahedron X (Stroud, Approximate Calculation of Multiple Integrals,
/// 1971, §2.7): the unit cube's n x n x n Gauss-Legendre points mapped by X0 + u (X1 - X0) + u v (X2 -
/// X1) + u v w (X3 - X2), Jacobian 6 V u² v; every point on the crack's side `side`.
FrontRule conical_rule(const std::array<Vec3d, 4>& X, int n, int side) {
    thread_local std::vector<double> gx, gw;
    if (static_cast<int>(gx.size()) != n) gauss_legendre_unit(n, gx, gw);
    const double six_volume = std::abs((X[1] - X[0]).dot((X[2] - X[0]).cross(X[3] - X[0])));
    FrontRule out;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            for (int k = 0; k < n; ++k) {
                const double u = gx[i], v = gx[j], w = gx[k];
                out.points.push_back({X[0] + u * (X[1] - X[0]) + u * v * (X[2] - X[1]) + u * v * w * (X[3] - X[2]),
                                      gw[i] * gw[j] * gw[k] * six_volume * u * u * v});
                out.side.push_back(side);
            }
    return out;
}

/// A part this far from the front's line, against its tetrahedron's size, holds no singularity: the
/// conical rule takes its tetrahedra (within 9.1e-5 of the slab rule on 1/r at this distance) [-].
constexpr double kSmoothDistance = 0.1;

/// Distance from the front's line to tetrahedron L (front coordinates: the line is x1 = x2 = 0):
/// from the origin to the hull of its corners' (x1, x2), 0 inside it [m].
double line_distance(const std::array<Vec3d, 4>& L) {
    const auto cross = [](const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); };
    for (int skip = 0; skip < 4; ++skip) {  // inside a triangle of three corners: inside the hull
        std::array<Vec2, 3> t;
        for (int k = 0, j = 0; k < 4; ++k)
            if (k != skip) t[j++] = L[k].head<2>();
        const double c0 = cross(t[1] - t[0], -t[0]), c1 = cross(t[2] - t[1], -t[1]), c2 = cross(t[0] - t[2], -t[2]);
        if ((c0 >= 0.0 && c1 >= 0.0 && c2 >= 0.0) || (c0 <= 0.0 && c1 <= 0.0 && c2 <= 0.0)) return 0.0;
    }
    double d = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 4; ++a)
        for (int b = a + 1; b < 4; ++b) {  // the hull's edges are among the corners' pairs
            const Vec2 p = L[a].head<2>(), q = L[b].head<2>(), e = q - p;
            const double t = e.squaredNorm() > 0.0 ? std::clamp(-p.dot(e) / e.squaredNorm(), 0.0, 1.0) : 0.0;
            d = std::min(d, (p + t * e).norm());
        }
    return d;
}

/// Appends the tetrahedra of tetrahedron X's part where (x - point) . normal >= 0: X itself, one
/// tetrahedron, or a prism's three (its lateral faces lie on X's faces and the plane: planar).
void clip_tet(const std::array<Vec3d, 4>& X, const Vec3d& point, const Vec3d& normal, std::vector<std::array<Vec3d, 4>>& out) {
    std::array<double, 4> l;
    std::vector<int> in, off;
    for (int k = 0; k < 4; ++k) l[k] = (X[k] - point).dot(normal), (l[k] >= 0.0 ? in : off).push_back(k);
    const auto at = [&](int a, int b) { return Vec3d(X[a] + l[a] / (l[a] - l[b]) * (X[b] - X[a])); };
    const auto prism = [&](const Vec3d& a, const Vec3d& b, const Vec3d& c, const Vec3d& a2, const Vec3d& b2, const Vec3d& c2) {
        out.push_back({a, b, c, a2}), out.push_back({b, c, a2, b2}), out.push_back({c, a2, b2, c2});
    };
    if (in.size() == 4) out.push_back(X);
    else if (in.size() == 1) out.push_back({X[in[0]], at(in[0], off[0]), at(in[0], off[1]), at(in[0], off[2])});
    else if (in.size() == 2) prism(X[in[0]], at(in[0], off[0]), at(in[0], off[1]), X[in[1]], at(in[1], off[0]), at(in[1], off[1]));
    else if (in.size() == 3) prism(X[in[0]], X[in[1]], X[in[2]], at(in[0], off[0]), at(in[1], off[0]), at(in[2], off[0]));
}

/// The conical rule over the part of X in `keep`, split by the crack's plane (each side's points
/// carry it), for a part away from the front (line_distance): smooth on each side.
FrontRule split_conical_rule(const std::array<Vec3d, 4>& X, const HalfSpace& keep, const FrontFrame& front, double h,
                             int conical_order) {
    std::vector<std::array<Vec3d, 4>> kept, sided;
    if (keep.normal.squaredNorm() > 0.0) clip_tet(X, keep.point, keep.normal, kept);
    else kept.push_back(X);
    FrontRule out;
    for (int side : {1, -1}) {
        sided.clear();
        for (const auto& T : kept) clip_tet(T, front.point, side * front.normal(), sided);
        for (const auto& T : sided) {
            if (std::abs((T[1] - T[0]).dot((T[2] - T[0]).cross(T[3] - T[0]))) <= 1e-12 * h * h * h) continue;
            const FrontRule r = conical_rule(T, conical_order, side);
            out.points.insert(out.points.end(), r.points.begin(), r.points.end());
            out.side.insert(out.side.end(), r.side.begin(), r.side.end());
        }
    }
    return out;
}

}  // namespace

bool front_in_tet(const std::array<Vec3d, 4>& X, const FrontFrame& front, double& from, double& to) {
    // A line farther from the corners' centroid than the farthest corner (and a margin far beyond
    // the 1e-9 of the tetrahedron below) misses it: most of a mesh, at a few flops each.
    const Vec3d c = 0.25 * (X[0] + X[1] + X[2] + X[3]), v = c - front.point;
    double reach = 0.0;
    for (const Vec3d& x : X) reach = std::max(reach, (x - c).squaredNorm());
    if ((v - v.dot(front.tangent) * front.tangent).squaredNorm() > reach * (1.0 + 1e-6)) return false;
    Mat3d D;
    D << X[1] - X[0], X[2] - X[0], X[3] - X[0];
    const Mat3d Dinv = D.inverse();
    const Vec3d alpha = Dinv * (front.point - X[0]), beta = Dinv * front.tangent;
    // Barycentric coordinates along the line: λ_i(s) = α_i + s β_i (λ_0 = 1 - Σ), each >= -1e-9.
    const std::array<double, 4> a = {1.0 - alpha.sum(), alpha.x(), alpha.y(), alpha.z()};
    const std::array<double, 4> b = {-beta.sum(), beta.x(), beta.y(), beta.z()};
    double lo = -std::numeric_limits<double>::infinity(), hi = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 4; ++i) {
        const double level = a[i] + 1e-9;
        if (b[i] == 0.0) {
            if (level < 0.0) return false;
            continue;
        }
        const double s = -level / b[i];
        if (b[i] > 0.0) lo = std::max(lo, s);
        else hi = std::min(hi, s);
    }
    from = lo, to = hi;
    return hi - lo > 1e-9 * tet_size(X);
}

FrontRule front_tet_rule(const std::array<Vec3d, 4>& X, const HalfSpace& keep, const FrontFrame& front, int order,
                         int slab_order, int conical_order) {
    const Vec3d d = front.direction, n = front.normal(), t = front.tangent;
    const auto local = [&](const Vec3d& p) { return Vec3d((p - front.point).dot(d), (p - front.point).dot(n), (p - front.point).dot(t)); };
    std::array<Vec3d, 4> L;
    for (int k = 0; k < 4; ++k) L[k] = local(X[k]);
    const double h = tet_size(X);
    const bool clipped = keep.normal.squaredNorm() > 0.0;
    // A whole tetrahedron strictly on one side of the crack's plane holds neither the front nor the
    // crack: its integrands are smooth there, and the conical product rule takes them.
    const bool above = std::all_of(L.begin(), L.end(), [](const Vec3d& l) { return l.y() > 0.0; });
    const bool below = std::all_of(L.begin(), L.end(), [](const Vec3d& l) { return l.y() < 0.0; });
    if (!clipped && (above || below)) return conical_rule(X, conical_order, above ? 1 : -1);
    if (line_distance(L) >= kSmoothDistance * h) return split_conical_rule(X, keep, front, h, conical_order);
    // The part's half-spaces in the front's coordinates, a . x + c >= 0: the tetrahedron's faces
    // (each toward its opposite corner), the kept half-space, and (last) the crack's plane's side.
    std::vector<Vec3d> a;
    std::vector<double> c;
    for (int k = 0; k < 4; ++k) {
        const Vec3d &p = L[(k + 1) % 4], &q = L[(k + 2) % 4], &r = L[(k + 3) % 4];
        Vec3d normal = (q - p).cross(r - p);
        if (normal.dot(L[k] - p) < 0.0) normal = -normal;
        a.push_back(normal), c.push_back(-normal.dot(p));
    }
    const Vec3d kn(d.dot(keep.normal), n.dot(keep.normal), t.dot(keep.normal));
    const double kc = (front.point - keep.point).dot(keep.normal);
    if (clipped) a.push_back(kn), c.push_back(kc);
    a.push_back(Vec3d::Zero()), c.push_back(0.0);
    thread_local std::vector<double> sx, sw;
    thread_local GaussRule plane, signed_plane;
    if (static_cast<int>(sx.size()) != slab_order) gauss_legendre_unit(slab_order, sx, sw);
    if (static_cast<int>(plane.x.size()) != order) gauss_legendre_unit(order, plane.x, plane.w);
    if (static_cast<int>(signed_plane.x.size()) != std::max(order, kSignedFanOrder))
        gauss_legendre_unit(std::max(order, kSignedFanOrder), signed_plane.x, signed_plane.w);
    std::vector<QuadraturePoint> plane_rule;
    FrontRule out;
    for (int side : {1, -1}) {
        a.back() = Vec3d(0.0, side, 0.0);
        double lo = 0.0, hi = 0.0;
        const std::vector<double> ends = slab_ends(a, c, h, lo, hi);
        const auto crossing = [&](double e) { return hi > lo && (std::abs(e - lo) <= 1e-12 * h || std::abs(e - hi) <= 1e-12 * h); };
        for (size_t i = 0; i + 1 < ends.size(); ++i) {
            const double s0 = ends[i], s1 = ends[i + 1];
            if (s1 - s0 <= 1e-12 * h) continue;
            const bool from_front = crossing(s0), to_front = crossing(s1);
            for (int j = 0; j < slab_order; ++j) {
                // Graded toward an end where the front enters or leaves the half: there the section's
                // integral goes as δ ln δ in the distance δ to that height, which a plain Gauss rule
                // meets at N^-4. With s = s0 + (s1 - s0) p(τ), p = τ³ (1 - (1 - τ)³ toward s1; the
                // cubic smoothstep 3τ² - 2τ³ toward both), it is τ^5 ln τ (τ³ ln τ).
                const double tau = sx[j];
                double p = tau, dp = 1.0;
                if (from_front && to_front) p = tau * tau * (3.0 - 2.0 * tau), dp = 6.0 * tau * (1.0 - tau);
                else if (from_front) p = tau * tau * tau, dp = 3.0 * tau * tau;
                else if (to_front) p = 1.0 - std::pow(1.0 - tau, 3), dp = 3.0 * (1.0 - tau) * (1.0 - tau);
                const double s = s0 + p * (s1 - s0), ws = sw[j] * dp * (s1 - s0);
                std::vector<Vec2> poly = section(L, s);
                if (clipped && !poly.empty()) poly = clip_polygon(poly, kn.x(), kn.y(), kn.z() * s + kc);
                if (!poly.empty()) poly = clip_polygon(poly, 0.0, side, 0.0);
                if (poly.empty()) continue;
                plane_rule.clear();
                signed_fan(poly, plane, signed_plane, 1e-14 * h * h, plane_rule);
                for (const QuadraturePoint& q : plane_rule) {
                    out.points.push_back({front.point + q.X.x() * d + q.X.y() * n + s * t, q.weight * ws});
                    out.side.push_back(side);
                }
            }
        }
    }
    return out;
}

FrontIntegrals front_integrals(const std::array<Vec3d, 4>& X, const std::vector<int>& slots,
                               const std::array<int, 4>& node_side, const FrontFrame& front, int side,
                               const FrontRule& rule) {
    Mat3d D;
    D << X[1] - X[0], X[2] - X[0], X[3] - X[0];
    const Mat3d Dinv = D.inverse();
    std::array<Vec3d, 4> gradN;
    gradN[0] = -(Dinv.row(0) + Dinv.row(1) + Dinv.row(2)).transpose();
    for (int k = 1; k < 4; ++k) gradN[k] = Dinv.row(k - 1).transpose();
    const int m = 4 * static_cast<int>(slots.size()), points = static_cast<int>(rule.points.size());
    std::vector<std::array<double, 4>> shift(slots.size());
    for (size_t s = 0; s < slots.size(); ++s) shift[s] = front_functions(front, X[slots[s]], node_side[slots[s]]).f;
    // Column q: sqrt|w_q| ∇φ_a (rows 3a .. 3a + 2), so M is a symmetric rank update for the
    // positive weights less one for the negative ones (the signed fans'), made a chunk of columns at
    // a time (a few thousand points a part: a whole matrix of them is megabytes of fresh pages).
    constexpr int kChunk = 128;
    const int rows = 3 * m;
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(rows, rows);
    Eigen::VectorXd g = Eigen::VectorXd::Zero(rows);
    std::array<Eigen::MatrixXd, 2> B{Eigen::MatrixXd(rows, kChunk), Eigen::MatrixXd(rows, kChunk)};  // w > 0, w < 0
    std::array<Eigen::VectorXd, 2> root{Eigen::VectorXd(kChunk), Eigen::VectorXd(kChunk)};
    std::array<int, 2> filled{0, 0};
    const auto flush = [&](int k) {
        if (filled[k] == 0) return;
        const double sign = k == 0 ? 1.0 : -1.0;
        M.selfadjointView<Eigen::Lower>().rankUpdate(B[k].leftCols(filled[k]), sign);
        g += sign * B[k].leftCols(filled[k]) * root[k].head(filled[k]);
        filled[k] = 0;
    };
    for (int q = 0; q < points; ++q) {
        const VolumePoint& p = rule.points[q];
        const int k = p.weight < 0.0 ? 1 : 0, c = filled[k]++;
        const double r = std::sqrt(std::abs(p.weight));
        root[k][c] = r;
        const Vec3d lambda = Dinv * (p.X - X[0]);
        const std::array<double, 4> N = {1.0 - lambda.sum(), lambda.x(), lambda.y(), lambda.z()};
        const FrontValues F = front_functions(front, p.X, side != 0 ? side : rule.side[q]);
        for (size_t s = 0; s < slots.size(); ++s)
            for (int l = 0; l < 4; ++l) {
                const int corner = slots[s];
                B[k].col(c).segment<3>(3 * (4 * s + l)) = r * (gradN[corner] * (F.f[l] - shift[s][l]) + N[corner] * F.grad[l]);
            }
        if (filled[k] == kChunk) flush(k);
    }
    flush(0), flush(1);
    M.triangularView<Eigen::StrictlyUpper>() = M.transpose();
    FrontIntegrals out;
    out.G.resize(m);
    out.M.resize(static_cast<size_t>(m) * m);
    for (int a = 0; a < m; ++a) {
        out.G[a] = g.segment<3>(3 * a);
        for (int b = 0; b < m; ++b) out.M[static_cast<size_t>(a) * m + b] = M.block<3, 3>(3 * a, 3 * b);
    }
    return out;
}

}  // namespace xcut
