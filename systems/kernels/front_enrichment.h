#pragma once
// Crack-front (branch) enrichment in 3D, pure kernels (rest configuration, SI units: m).
//
// Along a straight crack front the near-front field is, to leading order, the plane field of the
// tip in the plane normal to the front (modes I and II; mode III's sqrt(r) sin(θ/2) is the first
// function again): the four functions of systems/kernels/branch_enrichment.h in the front's polar
// coordinates (r, θ) of that plane, constant along the front (Moës, Gravouil & Belytschko, IJNME 53,
// 2002, §3; Sukumar, Moës, Moran & Belytschko, IJNME 48, 2000, for planar 3D cracks).
//
// Integrals over a tetrahedron (or one side of a cut one) of the gradients of the shifted enriched
// shape functions φ_{k,l} = N_k (F_l - F_l(X_k)) are singular as 1/r along the front and
// discontinuous across the crack behind it. They are taken in slabs along the front: the tetrahedron
// is sliced at the heights (along the front) of its corners, of its cut's points and of where the
// front enters and leaves it, so that within a slab each section is one convex polygon whose shape
// changes smoothly; a Gauss-Legendre rule runs over the slab's heights and, at each, the 2D tip rule
// (Duffy's collapse onto the front's point, branch_enrichment.h) over the section's two halves
// either side of the crack's plane. The rule is exact in the front's direction for the polynomial
// part and carries the 2D rule's treatment of the singular one.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <vector>

#include "systems/kernels/branch_enrichment.h"

namespace xcut {

using Vec3d = Eigen::Vector3d;
using Mat3d = Eigen::Matrix3d;

/// A straight crack front: a point on it, the crack's direction there (unit, ahead of the front,
/// in the crack's plane, normal to the front) and the front's unit tangent. The crack's normal is
/// tangent x direction; side +1 is the normal's. In 2D (tangent = z) this is TipFrame.
struct FrontFrame {
    Vec3d point = Vec3d::Zero();      ///< [m]
    Vec3d direction = Vec3d::UnitX(); ///< [-]
    Vec3d tangent = Vec3d::UnitZ();   ///< [-]
    Vec3d normal() const { return tangent.cross(direction); }
};

/// The four functions and their gradients at X [sqrt(m), 1/sqrt(m)]; `side` as branch_functions.
struct FrontValues {
    std::array<double, 4> f{};
    std::array<Vec3d, 4> grad{};
};
FrontValues front_functions(const FrontFrame& front, const Vec3d& X, int side);

/// A quadrature point and its weight (a volume [m^3]).
struct VolumePoint {
    Vec3d X;
    double weight;
};

/// A half-space {X : (X - point) . normal >= 0}; a zero normal is the whole space.
struct HalfSpace {
    Vec3d point = Vec3d::Zero();
    Vec3d normal = Vec3d::Zero();
};

/// Points per direction of the conical product rule: 4³ = 64 (within 9.1e-5 of the slab rule on
/// 1/r with the front a tenth of the tetrahedron's size away: tests/systems/test_crack_front.cpp).
inline constexpr int kConicalOrder = 4;

/// The rule over the part of tetrahedron X in half-space `keep`, for integrands singular as 1/r
/// along the front and discontinuous across the crack's plane: slabs along the front, `slab_order`
/// Gauss-Legendre heights a slab, and at each the 2D tip rule of order `order` over the section's
/// halves either side of the crack's plane (of order 3 at least where the front's point lies
/// outside the half: its fan's triangles are signed). Each point carries the side (+1, -1) of the crack's
/// plane it lies on, for the functions' lip behind the front. A whole tetrahedron strictly on one
/// side of the crack's plane (its integrands smooth) takes the conical product rule instead
/// (Stroud 1971: `conical_order`³ points), and so does a part a tenth of its tetrahedron's size or
/// more from the front's line, on each tetrahedron of its split by the kept half-space and the
/// crack's plane.
struct FrontRule {
    std::vector<VolumePoint> points;
    std::vector<int> side;
};
FrontRule front_tet_rule(const std::array<Vec3d, 4>& X, const HalfSpace& keep, const FrontFrame& front, int order,
                         int slab_order, int conical_order = kConicalOrder);

/// Integrals over a rule of the gradients of φ_{k,l} for the tetrahedron's enriched corners `slots`
/// (local nodes k), functions ordered (slot, l): G_a = Σ w ∇φ_a [m^2.5] and M_ab = Σ w ∇φ_a ∇φ_b^T
/// [m^2], row-major by (a, b). `node_side`: per corner, the lip its node lies on (0 if none), so its
/// shift F_l(X_k) is that of every element around it. `side`: the part's lip (+1, -1) when it lies on
/// one side of the crack, 0 to take each point's own (FrontRule::side).
struct FrontIntegrals {
    std::vector<Vec3d> G;
    std::vector<Mat3d> M;
};
FrontIntegrals front_integrals(const std::array<Vec3d, 4>& X, const std::vector<int>& slots,
                               const std::array<int, 4>& node_side, const FrontFrame& front, int side,
                               const FrontRule& rule);

/// The part of the front's line inside tetrahedron X, as heights along the tangent from the
/// front's point [m]: false when the line misses it or only touches it (a part shorter than 1e-9
/// of the tetrahedron's size).
bool front_in_tet(const std::array<Vec3d, 4>& X, const FrontFrame& front, double& from, double& to);

/// Distance from X to the front's line [m].
double front_distance(const FrontFrame& front, const Vec3d& X);

}  // namespace xcut
