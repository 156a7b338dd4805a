#pragma once
// ForceSystem: corotational linear FEM forces (paper App. B, eq. 10), matrix-free.
// Per step it updates each element's rotation (polar decomposition of F, frozen for the rest of the
// step), the elastic and gravity forces, the strain energy and diag(K) for the preconditioner.
// It also provides the stiffness action K p that the implicit solver calls in every CG iteration.
#include <Eigen/Core>

#include "engine/scheduler.h"
#include "engine/world.h"
#include "systems/kernels/corotational_kernel.h"
#include "systems/step_term.h"

namespace xcut {

/// Lame parameters of a material for the mesh's dimension (2D: plane stress) [Pa].
LameParameters lame_of(const Material& material, int dim);
/// R of every element from the current positions (warm-started from the previous R).
void update_rotations(World& world);
/// world.forces.{force, elastic_energy} from positions, rotations and gravity, and
/// stiffness_diagonal when stiffness_diagonal_used.
void compute_forces(World& world);
/// world.forces.stiffness_diagonal: diag(K) of the elements at the current rotations.
void compute_stiffness_diagonal(World& world);
/// Strain energy [J] at the current positions, each element's rotation extracted from them (the
/// stored rotations, forces and energy are those of the step's start and are left untouched).
double elastic_energy_now(const World& world);
/// The same, keeping the 3D rotations it took (ForceState::checked_rotation) for the next
/// update_rotations at the same positions: the step's energy check.
double elastic_energy_checked(World& world);
/// out = K_el p (K_el = -df/dx of the elements with rotations frozen, positive semi-definite), 3
/// entries per node.
void elastic_stiffness_product(World& world, const Eigen::VectorXd& p, Eigen::VectorXd& out);
/// The elastic term of the implicit step (systems/step_term.h): linearize = update_rotations,
/// force = compute_forces, its product (inside a team: the element pass and the gather are
/// worksharing loops, a barrier after each; the same sums in the same order as
/// elastic_stiffness_product), and its block rows of the assembled A.
std::shared_ptr<StepTerm> elastic_step_term();
/// Sums per-element nodal terms into per-node entries in a fixed order (node -> element incidence).
void gather_element_terms(const World& world, Eigen::VectorXd& out);

SystemDesc force_system();

}  // namespace xcut
