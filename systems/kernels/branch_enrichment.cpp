#include "systems/kernels/branch_enrichment.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "systems/kernels/segment_distance.h"

namespace xcut {

BranchValues branch_functions(const TipFrame& tip, const Vec2& X, int side) {
    const Vec2 d = tip.direction, n(-d.y(), d.x());
    const Vec2 rel = X - tip.point;
    const double x1 = rel.dot(d), x2 = rel.dot(n), r = std::sqrt(x1 * x1 + x2 * x2);  // not hypot: no overflow at mesh scales, and 3-5x cheaper
    BranchValues out;
    if (r == 0.0) return out;
    // θ = atan2(x2, x1) in (-π, π], taken without trigonometry: cos θ and sin θ are x1 / r and
    // x2 / r, and the half angle's cosine and sine (1 ± cos θ) / 2 as (r ± x1) / 2r, each written
    // without cancellation (r + x1 = x2^2 / (r - x1) behind the tip, and the other way ahead).
    // Behind the tip a point of a cut element's side takes its lip's sign (θ = side |θ|); else the
    // sign of x2 decides, a signed zero as atan2 takes it.
    const double sign = side != 0 && x1 < 0.0 ? side : std::copysign(1.0, x2);
    const double r_plus = x1 >= 0.0 ? r + x1 : x2 * x2 / (r - x1), r_minus = x1 <= 0.0 ? r - x1 : x2 * x2 / (r + x1);
    const double sr = std::sqrt(r), c2 = std::sqrt(0.5 * r_plus / r), s2 = sign * std::sqrt(0.5 * r_minus / r);
    const double s = sign * std::abs(x2) / r, c = x1 / r;
    out.f = {sr * s2, sr * c2, sr * s2 * s, sr * c2 * s};
    // dF/dr and dF/dθ, then the local Cartesian gradient (along d, along n) by the polar chain rule.
    const std::array<double, 4> dr = {0.5 * s2 / sr, 0.5 * c2 / sr, 0.5 * s2 * s / sr, 0.5 * c2 * s / sr};
    const std::array<double, 4> dt = {0.5 * sr * c2, -0.5 * sr * s2, sr * (0.5 * c2 * s + s2 * c),
                                      sr * (-0.5 * s2 * s + c2 * c)};
    for (int l = 0; l < 4; ++l) {
        const double g1 = c * dr[l] - s / r * dt[l], g2 = s * dr[l] + c / r * dt[l];
        out.grad[l] = g1 * d + g2 * n;
    }
    return out;
}

void gauss_legendre_unit(int n, std::vector<double>& x, std::vector<double>& w) {
    x.assign(n, 0.0);
    w.assign(n, 0.0);
    for (int i = 0; i < n; ++i) {
        double z = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5)), dp = 1.0;
        for (int iteration = 0; iteration < 100; ++iteration) {
            double p0 = 1.0, p1 = 0.0;
            for (int k = 1; k <= n; ++k) {  // P_k by the three-term recurrence
                const double p2 = p1;
                p1 = p0;
                p0 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p2) / k;
            }
            dp = n * (z * p0 - p1) / (z * z - 1.0);
            const double step = p0 / dp;
            z -= step;
            if (std::abs(step) < 1e-16) break;
        }
        x[i] = 0.5 * (1.0 - z);
        w[i] = 1.0 / ((1.0 - z * z) * dp * dp);  // 2 / ((1 - z^2) P_n'^2), halved for [0, 1]
    }
}

void add_duffy(const Vec2& A, const Vec2& B, const Vec2& C, const std::vector<double>& gx,
               const std::vector<double>& gw, double min_area, std::vector<QuadraturePoint>& out) {
    const double det = std::abs(cross2(B - A, C - B));
    if (det <= min_area) return;
    if (std::atan2(det, (B - A).dot(C - A)) > 0.25 * std::numbers::pi + 1e-12) {
        const Vec2 mid = 0.5 * (B + C);
        add_duffy(A, B, mid, gx, gw, min_area, out);
        add_duffy(A, mid, C, gx, gw, min_area, out);
        return;
    }
    for (size_t i = 0; i < gx.size(); ++i)
        for (size_t j = 0; j < gx.size(); ++j) {
            const double u = gx[i], v = gx[j];
            out.push_back({A + u * (B - A) + u * v * (C - B), gw[i] * gw[j] * u * det});
        }
}

std::vector<QuadraturePoint> tip_polygon_rule(const std::vector<Vec2>& polygon, const TipFrame& tip, int order) {
    std::vector<QuadraturePoint> out;
    const int n = static_cast<int>(polygon.size());
    if (n < 3) return out;
    double h = 0.0;
    for (const Vec2& p : polygon) h = std::max(h, (p - polygon[0]).norm());
    const double eps = 1e-10 * h;
    std::vector<Vec2> loop = polygon;
    Vec2 apex = polygon[0];
    const Vec2& T = tip.point;
    bool placed = false;
    for (const Vec2& p : polygon)
        if ((p - T).norm() <= eps) apex = p, placed = true;
    for (int i = 0; i < n && !placed; ++i)
        if (segment_distance(T, polygon[i], polygon[(i + 1) % n]) <= eps) {
            loop.insert(loop.begin() + i + 1, T);
            apex = T, placed = true;
        }
    if (!placed) {
        int positive = 0, negative = 0;
        for (int i = 0; i < n; ++i) {
            const double c = cross2(polygon[(i + 1) % n] - polygon[i], T - polygon[i]);
            positive += c > 0.0, negative += c < 0.0;
        }
        if (positive == 0 || negative == 0) {  // inside: the crack behind it leaves through one edge
            apex = T;
            for (int i = 0; i < n; ++i) {
                const Vec2 a = polygon[i], ab = polygon[(i + 1) % n] - a;
                const double den = cross2(-tip.direction, ab);
                if (std::abs(den) < 1e-300) continue;
                const double s = cross2(a - T, ab) / den, t = cross2(a - T, -tip.direction) / den;
                if (s <= 0.0 || t < 0.0 || t > 1.0) continue;
                const Vec2 E = a + t * ab;
                if ((E - a).norm() > eps && (E - (a + ab)).norm() > eps) loop.insert(loop.begin() + i + 1, E);
                break;
            }
        }
    }
    // The Gauss-Legendre points, made once per thread and order (a zone is built every step a
    // blade carries its tip, a dozen rules each time).
    thread_local std::vector<double> gx, gw;
    if (static_cast<int>(gx.size()) != order) gauss_legendre_unit(order, gx, gw);
    const int m = static_cast<int>(loop.size());
    for (int i = 0; i < m; ++i) add_duffy(apex, loop[i], loop[(i + 1) % m], gx, gw, 1e-14 * h * h, out);
    return out;
}

bool ray_exit(const std::array<Vec2, 3>& X, const Vec2& p, const Vec2& v, int from, int& edge, Vec2& E) {
    double nearest = std::numeric_limits<double>::infinity(), at = -1.0;
    for (int k = 0; k < 3; ++k) {
        if (k == from) continue;
        const Vec2 a = X[k], b = X[(k + 1) % 3];
        Eigen::Matrix2d M;  // p + s v = a + u (b - a)
        M << v, a - b;
        if (std::abs(M.determinant()) <= 1e-14 * (b - a).norm()) continue;
        const Vec2 su = M.partialPivLu().solve(a - p);
        if (su.x() <= 0.0 || su.x() >= nearest || su.y() < -1e-9 || su.y() > 1.0 + 1e-9) continue;
        nearest = su.x(), at = su.y(), edge = k, E = a + su.y() * (b - a);
    }
    return at > 1e-6 && at < 1.0 - 1e-6;
}

std::vector<Vec2> clip_triangle(const std::array<Vec2, 3>& X, const Vec2& a, const Vec2& b, int side) {
    std::vector<Vec2> out;
    const auto level = [&](const Vec2& p) { return side * cross2(b - a, p - a); };
    for (int i = 0; i < 3; ++i) {
        const Vec2 &p = X[i], &q = X[(i + 1) % 3];
        const double lp = level(p), lq = level(q);
        if (lp >= 0.0) out.push_back(p);
        if ((lp > 0.0 && lq < 0.0) || (lp < 0.0 && lq > 0.0)) out.push_back(p + lp / (lp - lq) * (q - p));
    }
    return out.size() >= 3 ? out : std::vector<Vec2>{};
}

BranchIntegrals branch_integrals(const std::array<Vec2, 3>& X, const std::vector<int>& slots,
                                 const std::array<int, 3>& node_side, const TipFrame& tip, int side,
                                 const std::vector<QuadraturePoint>& rule) {
    Eigen::Matrix2d D;
    D << X[1] - X[0], X[2] - X[0];
    const Eigen::Matrix2d Dinv = D.inverse();
    const std::array<Vec2, 3> gradN = {Vec2(-Dinv.row(0).transpose() - Dinv.row(1).transpose()),
                                       Vec2(Dinv.row(0).transpose()), Vec2(Dinv.row(1).transpose())};
    const int m = 4 * static_cast<int>(slots.size()), points = static_cast<int>(rule.size());
    std::vector<std::array<double, 4>> shift(slots.size());
    for (size_t s = 0; s < slots.size(); ++s) shift[s] = branch_functions(tip, X[slots[s]], node_side[slots[s]]).f;
    // Column q: sqrt(w_q) ∇φ_a (rows 2a, 2a + 1), so M is one symmetric rank-k update (the weights
    // are areas, >= 0) and G a product with sqrt(w).
    Eigen::MatrixXd A(2 * m, points);
    Eigen::VectorXd root(points);
    for (int q = 0; q < points; ++q) {
        const QuadraturePoint& p = rule[q];
        root[q] = std::sqrt(p.weight);
        const Vec2 lambda = Dinv * (p.X - X[0]);
        const std::array<double, 3> N = {1.0 - lambda.x() - lambda.y(), lambda.x(), lambda.y()};
        const BranchValues F = branch_functions(tip, p.X, side);
        for (size_t s = 0; s < slots.size(); ++s)
            for (int l = 0; l < 4; ++l) {
                const int k = slots[s];
                A.col(q).segment<2>(2 * (4 * s + l)) = root[q] * (gradN[k] * (F.f[l] - shift[s][l]) + N[k] * F.grad[l]);
            }
    }
    const Eigen::VectorXd g = A * root;
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(2 * m, 2 * m);
    M.selfadjointView<Eigen::Lower>().rankUpdate(A);
    M.triangularView<Eigen::StrictlyUpper>() = M.transpose();
    BranchIntegrals out;
    out.G.resize(m);
    out.M.resize(static_cast<size_t>(m) * m);
    for (int a = 0; a < m; ++a) {
        out.G[a] = g.segment<2>(2 * a);
        for (int b = 0; b < m; ++b) out.M[static_cast<size_t>(a) * m + b] = M.block<2, 2>(2 * a, 2 * b);
    }
    return out;
}

}  // namespace xcut
