#pragma once
// The quadratic tetrahedra's part of the elastic term, over the component arrays: per element into
// a buffer (in parallel), then per node in its incidence order (components/quadratic_elements.h),
// so the sums are the same on any thread count. The element kernels: systems/kernels/quadratic_tet.h.
#include <Eigen/Core>
#include <vector>

#include "components/elements.h"
#include "components/linear_system.h"
#include "components/material.h"
#include "components/quadratic_elements.h"
#include "systems/kernels/quadratic_tet.h"
#include "systems/kernels/tet10_side_rule.h"

namespace xcut {

/// What the kernels read, in one place.
struct QuadraticView {
    const QuadraticElements& quadratic;
    const Elements& elements;
    const Materials& materials;
};

/// The material's Lamé parameters [Pa]: 3D, or plane stress for a 6-node triangle (`planar`).
LameParameters quadratic_lame(const Material& m, bool planar = false);

/// Forces at positions x into buffer (sized here); returns the strain energy [J] (a fixed-order sum).
double quadratic_forces(const QuadraticView& v, const Vec3* x, std::vector<Tet10Vectors>& buffer);
/// Element t's rotation at positions x (warm: the last one, a start for the polar decomposition):
/// a whole element's is the polar factor of its corner tetrahedron's (triangle's) F, as the linear
/// element's; one side of a cut element's is that of its deformation gradient's mean over the side's
/// own rule. A side's corners include phantom nodes, placed by the side's quadratic field
/// extrapolated beyond the material it holds: for a small side their F turns by 0.05-0.1 rad from
/// step to step while the material barely moves, and at nu 0.49 each turn is a large change of the
/// side's stiffness (docs/elements.md, "A nearly incompressible cut body").
Mat3 quadratic_rotation(const QuadraticView& v, const Vec3* x, int t, const Mat3& warm);
/// Element t's strain energy at positions x with rotation R [J] (its rule: whole or side).
double quadratic_element_energy(const QuadraticView& v, const Vec3* x, int t, const Mat3& R);
/// Element t's K p into buffer[t].
void quadratic_product_element(const QuadraticView& v, const Vec3* p, int t, std::vector<Tet10Vectors>& buffer);
/// Every element's K p into buffer (sized here), in parallel.
void quadratic_products(const QuadraticView& v, const Vec3* p, std::vector<Tet10Vectors>& buffer);
/// Every element's stiffness diagonal into buffer (sized here).
void quadratic_diagonals(const QuadraticView& v, std::vector<Tet10Vectors>& buffer);
/// Node i's sum of its quadratic elements' terms, in incidence order (0 for a node none touches).
Vec3 quadratic_gathered(const QuadraticElements& q, const std::vector<Tet10Vectors>& buffer, int i);

/// Per element, the rotated gradients at the quadrature points
/// r[q][j] = R grad N_j(q) [1/m], and scale (V/4) lambda, scale (V/4) mu [N m].
struct QuadraticBlocks {
    std::array<std::array<Vec3, 10>, 4> r;
    double lambda_w = 0.0, mu_w = 0.0;
    /// A constant-pressure element's (LameParameters::lambda_mean): rbar_j = sum_q w_q R grad N_j(q)
    /// and scale V lambda_mean / W (tet10_mean_gradients); 0 otherwise.
    std::array<Vec3, 10> rbar;
    double lambda_mean_w = 0.0;
};
/// The same for an element integrated by a rule of its own (one side of a cut element, a 6-node
/// triangle), per point (weights w_q V scale).
struct QuadraticSideBlocks {
    int count = 0;
    std::array<std::array<Vec3, 10>, TetSideRule::kMaxPoints> r;
    std::array<double, TetSideRule::kMaxPoints> lambda_w{}, mu_w{};
    std::array<Vec3, 10> rbar;
    double lambda_mean_w = 0.0;
};
/// Every element's block makings: whole tetrahedra in `whole`, the others in `side` (side_of[t] its
/// index, -1 for a whole tetrahedron).
struct QuadraticTerms {
    std::vector<QuadraticBlocks> whole;
    std::vector<QuadraticSideBlocks> side;
    std::vector<int> side_of;
};
/// The blocks' makings for every element at stiff_scale (sized here).
void quadratic_block_terms(const QuadraticView& v, double stiff_scale, QuadraticTerms& terms);
/// Adds node i's block row of the quadratic elements' stiffness to A (slots: LinearSystem::quadratic_slot).
void add_quadratic_row(const QuadraticElements& q, const QuadraticTerms& terms, int i, LinearSystem& A);

}  // namespace xcut
