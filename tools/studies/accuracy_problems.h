#pragma once
// The verification problems with a reference solution (docs/verification.md problems 3, 5, 6), as worlds that a
// test or `xcut bench --suite accuracy` solves to static equilibrium. SI units: m, Pa, N, kg.
//  3. Cantilever under its own weight against beam theory (no cut).
//  5. A block with a partial planar cut, pulled apart, against a conforming fine-mesh reference
//     (tools/studies/crack_reference.h); error = relative L2 norm of the displacement at sample points.
//  6. Single edge notched tension plate (2D, plane stress): crack-mouth opening against Tada, Paris
//     & Irwin's handbook formula.
// Cut worlds are cut by a scripted planar cut (systems/cut/scripted_cut_system.h) with either cutter:
// XFEM (CutElements + virtual elements) or snapping and subdivision (world.snap.enabled).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "engine/world.h"
#include "systems/solver/solver_system.h"

namespace xcut {

// ---- Static equilibrium, with the tolerances every problem of the suite uses -----------------------

/// Newton on |f| <= 1e-6 |f0| (at most 30 iterations; the force residual's rounding floor reaches
/// ~1e-7 of the load on the finest cantilever), each linear solve by Jacobi-CG to 1e-10 relative
/// residual (at most 50000 iterations): far below the discretization errors measured (> 1e-3).
StaticResult solve_equilibrium(World& world, const Eigen::VectorXd& load = Eigen::VectorXd());

// ---- Problem 3: cantilever under its own weight ----------------------------------------------------

/// Beam L x b x h clamped at x = 0, gravity -z. nu = 0: beam theory has no Poisson coupling (a
/// clamped root with nu > 0 is stiffer than the theory's); L / h = 20 keeps the shear term at 0.2 %.
struct CantileverSpec {
    double length = 0.2, width = 0.01, height = 0.01;  ///< L, b, h [m]
    double young = 2e8;                                 ///< E [Pa]: tip deflection ~0.2 % of L
    double density = 1000.0;                            ///< rho [kg/m^3]
    double gravity = 9.81;                              ///< g [m/s^2]
    double poisson = 0.0;                               ///< nu [-] (the closed form below is for 0)
    bool quadratic = false;                             ///< 10-node tetrahedra (components/quadratic_elements.h)
    bool mean_dilatation = false;                       ///< with a constant pressure each ("quadratic-p0")
};
/// Euler-Bernoulli with Timoshenko's shear term (Timoshenko & Gere, Mechanics of Materials):
///   delta = q L^4 / (8 E I) + q L^2 / (2 kappa G A),  q = rho g b h,  I = b h^3 / 12,  kappa = 5/6.
double cantilever_reference(const CantileverSpec& spec);
/// The beam on 20n x n x n cells (6 tetrahedra each), clamped, under gravity; not yet solved.
World cantilever_world(const CantileverSpec& spec, int n);
/// Mean downward displacement of the nodes at x = L [m].
double cantilever_tip_deflection(const World& world, const CantileverSpec& spec);

// ---- Probing the displacement at fixed points ------------------------------------------------------

/// A rest point and where it lives: the force element carrying it (for a cut XFEM element, the
/// virtual element of its side, bound as surface vertices are: systems/surface/mapping_system.h; for the
/// snapping cutter, the live piece holding it) and its barycentric coordinates there.
struct Probe {
    Vec3 rest = Vec3::Zero();
    int element = -1;
    Eigen::Vector4d bary = Eigen::Vector4d::Zero();
};
/// Locates each rest point in the current topology (call after cutting); the element whose
/// barycentric coordinates are least negative wins (a point on a shared face is in either).
std::vector<Probe> locate_points(const World& world, const std::vector<Vec3>& rest_points);
/// Displacement x(X) - X of a probe at the current positions [m].
Vec3 probe_displacement(const World& world, const Probe& probe);
/// The same with the tips' (2D) or fronts' (3D) functions added where the world has any
/// (crack_enrichment_at), amplitudes b from crack_tip_amplitudes or step_tip_amplitudes [m].
Vec3 probe_displacement(const World& world, const Probe& probe, const Eigen::VectorXd& amplitudes);

/// Splits the elements the planar polygon (2D: segment) crosses completely, with the world's cutter
/// (XFEM unless world.snap.enabled); returns the mesh elements split. `progressive` (XFEM only):
/// the elements it enters too, as a progressive front's tip elements (a blade stopped there).
int cut_with_polygon(World& world, const std::vector<Vec3>& polygon, bool progressive = false);

// ---- Problem 5: partial cut, block pulled apart ----------------------------------------------------

/// Block L x B x H on [0, L] x [0, B] x [0, H], cut by the plane x = cut_x from its top z = H down to
/// depth d, through its whole width; both end faces held, displaced by `pull` outward along x.
struct CutBlockSpec {
    Vec3 size = Vec3(0.04, 0.005, 0.02);  ///< L, B, H [m]
    double cut_x = 0.0203;                 ///< cut plane [m]: off the coarse meshes' grid planes
    double depth = 0.01;                   ///< d [m]: the crack front z = H - d is a grid plane
    double pull = 2e-5;                    ///< end displacement [m] (strain 1e-3: small deformation)
    double young = 1e4, poisson = 0.3, density = 1000.0;  ///< skin (docs/scene-format.md, material) [Pa, -, kg/m^3]
    bool quadratic = false;  ///< the mesh's element (not a parameter of the reference): 10-node tetrahedra
    /// the front may lie inside a cell (the blade-stop sweep; not a parameter of the reference):
    /// else a depth off the mesh's grid planes is refused
    bool front_in_cell = false;
    bool mean_dilatation = false;  ///< with a constant pressure each ("quadratic-p0"; not a reference parameter)
    /// The CalculiX reference's grid crowds toward the crack front as (i / k)^g (1: uniform;
    /// tools/reference/calculix_reference.py says why the accuracy suite takes 2 and the locking
    /// suite 1) [-].
    double reference_grading = 2.0;
};
/// Cells of the coarse mesh with `n` cells along L: (n, n B / L, n H / L) rounded, at least one;
/// n must make n H / L an even integer so the crack front lies on a grid plane.
Eigen::Vector3i cut_block_cells(const CutBlockSpec& spec, int n);
/// The uncut block on that mesh (a regular Kuhn grid: the cut plane crosses its elements at
/// arbitrary positions), with material, no gravity.
World cut_block_world(const CutBlockSpec& spec, int n);
/// The cut polygon: the plane x = cut_x for z in [H - d, H + margin], y beyond both faces.
std::vector<Vec3> cut_block_polygon(const CutBlockSpec& spec);
/// Holds both end faces (all axes) displaced by -pull (x = 0) and +pull (x = L).
void pull_block_ends(World& world, const CutBlockSpec& spec);
/// The sample points: a lattice of 8 x 2 x 8 cell centres over the block, and 4 pairs on the crack
/// lips (x = cut_x -/+ 1e-6 L, y = B / 2, through the cut depth).
std::vector<Vec3> cut_block_samples(const CutBlockSpec& spec);
/// The samples' displacements at the static equilibrium of `world` (the block, cut) with its ends
/// pulled, the fronts' functions added where it has any (crack_tip_amplitudes, crack_enrichment_at:
/// as the suite's xfem_tip row takes them) [m]. Throws std::runtime_error if the solve fails.
std::vector<Vec3> pulled_block_displacements(World& world, const CutBlockSpec& spec);

// ---- Problem 6: single edge notched tension (2D, plane stress) -------------------------------------

/// Plate W x H in the xy plane, edge crack of length a along y = H / 2 from x = 0, remote stress
/// sigma on the edges y = 0 and y = H.
struct EdgeCrackSpec {
    double width = 0.04;    ///< W [m]
    double height = 0.12;   ///< H [m]: 3 W (>= 2 W)
    double crack = 0.02;    ///< a [m]: a / W = 0.5
    /// sigma [Pa]: strain 1e-6. The corotational model is geometrically nonlinear: the eccentric
    /// crack rotates the plate's halves and the dead-load traction straightens them (tension
    /// stiffening), which at strain 1e-3 lowered the CMOD by 5 % (H = 3 W) to 9 % (H = 6 W). The
    /// handbook is linear elasticity: at 1e-6 the effect is below 1e-4 and H = 3 W and 6 W agree
    /// to 0.03 %.
    double stress = 0.01;
    double young = 1e4, poisson = 0.3, density = 1000.0, thickness = 1e-3;  ///< [Pa, -, kg/m^3, m]
};
/// CMOD = (4 sigma a / E) V1(a / W),  V1(x) = [1.46 + 3.42 (1 - cos(pi x / 2))] / cos^2(pi x / 2):
/// Tada, Paris & Irwin, The Stress Analysis of Cracks Handbook (3rd ed., 2000), single edge notched
/// tension, plane stress (E' = E) [m].
double edge_crack_reference_cmod(const EdgeCrackSpec& spec);
/// Cells (n across W, rows along H made odd so the crack y = H / 2 runs through the middle of a
/// row). n must be even: the crack tip x = a = W / 2 is then a grid line, where the cutter's
/// "completely crossed" rule ends the crack exactly.
Eigen::Vector3i edge_crack_cells(const EdgeCrackSpec& spec, int n);
/// The plate of 3-node triangles, or of 6-node triangles (`quadratic`, docs/elements.md).
World edge_crack_world(const EdgeCrackSpec& spec, int n, bool quadratic = false);
/// The crack segment, from outside the plate's left edge to the tip.
std::vector<Vec3> edge_crack_segment(const EdgeCrackSpec& spec);
/// Holds the plate against rigid motion only (the right edge node just below the crack: x and y;
/// the bottom-right corner: x) and returns the load: sigma t over the top and bottom edges, as the
/// edges' shape functions weigh it (a 6-node triangle's mid-edge nodes included; 3 entries per DOF
/// node [N]). Self-equilibrated, so the holds carry no reaction.
Eigen::VectorXd edge_crack_load(World& world, const EdgeCrackSpec& spec);
/// Opening of the crack mouth: u_y(0, H/2 + e) - u_y(0, H/2 - e), e = 1e-6 W [m], with the tip's
/// functions where its zone reaches the mouth (step_tip_amplitudes, crack_enrichment_at).
double edge_crack_cmod(World& world, const EdgeCrackSpec& spec);


}  // namespace xcut
