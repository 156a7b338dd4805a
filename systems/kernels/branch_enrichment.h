#pragma once
// Crack-tip (branch) enrichment in 2D, pure kernels (rest configuration, SI units: m).
//
// The four branch functions of Fleming et al. (IJNME 40, 1997) and Moës, Dolbow & Belytschko
// (IJNME 46, 1999),
//   F = sqrt(r) { sin(θ/2), cos(θ/2), sin(θ/2) sin θ, cos(θ/2) sin θ },
// in the tip's polar coordinates (θ = 0 straight ahead of the tip, ±π on the crack's two lips), span
// the displacement field near the tip of a crack in a linear elastic solid (Williams 1957; modes I
// and II). F_1 is discontinuous across the crack, so the tip's enrichment also opens the crack inside
// the element the tip lies in, up to the tip.
//
// Integrals over a part of an element (the element, or one side of a cut element) of the gradients
// of the enriched shape functions φ_{k,l} = N_k (F_l - F_l(X_k)) (shifted: Belytschko et al. 2001, so
// a node's value stays its displacement) are taken on a fan of triangles. A fan triangle whose apex
// is the tip is mapped from the unit square by Duffy's collapse (Duffy, SIAM J. Numer. Anal. 19,
// 1982; used for the tip by Béchet et al., IJNME 64, 2005), whose Jacobian u cancels the 1/r of a
// product of two gradients: a tensor Gauss-Legendre rule then integrates it to rounding.
#include <Eigen/Core>
#include <array>
#include <vector>

namespace xcut {

using Vec2 = Eigen::Vector2d;

/// The z component of a x b (twice the signed area of the triangle 0, a, b).
inline double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

/// A crack tip: where it is, and the crack's direction there (unit, pointing ahead of the tip). Side
/// +1 of the crack is to the left of the direction (the normal is the direction turned by +90°).
struct TipFrame {
    Vec2 point = Vec2::Zero();      ///< [m]
    Vec2 direction = Vec2::UnitX(); ///< [-]
};

/// The four functions and their gradients at X [sqrt(m), 1/sqrt(m)]. `side` (+1, -1) says which lip
/// a point behind the tip belongs to (a point of a cut element's side); 0 takes θ from atan2, for
/// points off the crack's line. At the tip itself the functions are 0 and the gradients are left 0.
struct BranchValues {
    std::array<double, 4> f{};
    std::array<Vec2, 4> grad{};
};
BranchValues branch_functions(const TipFrame& tip, const Vec2& X, int side);

/// A quadrature point and its weight (an area [m^2]).
struct QuadraturePoint {
    Vec2 X;
    double weight;
};

/// Adds the Duffy-collapsed rule of triangle (A, B, C), collapsed onto A, from the Gauss-Legendre
/// rule (gx, gw) on [0, 1] in both directions; weights are the area's share, >= 0. A triangle that
/// spans more than 45 degrees at A is halved first: the rule is exact in r, and the angular
/// integrand is then smooth enough for the Gauss rule to reach rounding. Triangles of area below
/// `min_area` add nothing.
void add_duffy(const Vec2& A, const Vec2& B, const Vec2& C, const std::vector<double>& gx, const std::vector<double>& gw,
               double min_area, std::vector<QuadraturePoint>& out);

/// A rule on a convex polygon (either orientation) for integrands singular as 1/r at the tip:
/// triangles fanned from the tip when it lies in the polygon's closure (the point where the crack
/// behind the tip leaves the polygon made a vertex, so the crack is a fan edge and no triangle spans
/// it), else from the polygon's first vertex; each triangle by Duffy's collapse of an order x order
/// Gauss-Legendre rule onto its apex.
std::vector<QuadraturePoint> tip_polygon_rule(const std::vector<Vec2>& polygon, const TipFrame& tip, int order);

/// The part of triangle `X` on side `side` of the line through `a` and `b` (side +1: to the left of
/// a -> b), counter-clockwise; empty if none.
std::vector<Vec2> clip_triangle(const std::array<Vec2, 3>& X, const Vec2& a, const Vec2& b, int side);

/// Integrals over a rule of the gradients of φ_{k,l} for the triangle's enriched corners `slots`
/// (local nodes k), functions ordered (slot, l): G_a = Σ w ∇φ_a [m^1.5] and M_ab = Σ w ∇φ_a ∇φ_b^T
/// [m], row-major by (a, b). `node_side`: per corner, the lip its node lies on (its Heaviside sign;
/// 0 if none), so its shift F_l(X_k) is that of every element around it. `side`: the rule's points' lip.
struct BranchIntegrals {
    std::vector<Vec2> G;
    std::vector<Eigen::Matrix2d> M;
};
BranchIntegrals branch_integrals(const std::array<Vec2, 3>& X, const std::vector<int>& slots,
                                 const std::array<int, 3>& node_side, const TipFrame& tip, int side,
                                 const std::vector<QuadraturePoint>& rule);

/// Where the ray p + s v (s > 0) leaves triangle X: its local edge (k: corners k and (k + 1) % 3)
/// and the point. The edge `from` (-1: none) is one p lies on, passed over. False when it leaves
/// within 1e-6 of a corner (along the edge), or nowhere.
bool ray_exit(const std::array<Vec2, 3>& X, const Vec2& p, const Vec2& v, int from, int& edge, Vec2& E);

/// Nodes and weights of the n-point Gauss-Legendre rule on [0, 1] (Newton on P_n from Chebyshev
/// guesses: Press et al., Numerical Recipes, §4.6), to rounding.
void gauss_legendre_unit(int n, std::vector<double>& x, std::vector<double>& w);

}  // namespace xcut
