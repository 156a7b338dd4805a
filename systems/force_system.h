#pragma once
// ForceSystem: corotational linear FEM forces (paper App. B, eq. 10), matrix-free.
// Per step it updates each element's rotation (polar decomposition of F, frozen for the rest of the
// step), the elastic and gravity forces, the strain energy and diag(K) for the preconditioner.
// It also provides the stiffness action K p that the implicit solver calls in every CG iteration.
#include <Eigen/Core>

#include "engine/scheduler.h"
#include "engine/world.h"
#include "systems/kernels/corotational_kernel.h"

namespace xcut {

/// Lame parameters of a material for the mesh's dimension (2D: plane stress) [Pa].
LameParameters lame_of(const Material& material, int dim);
/// R of every element from the current positions (warm-started from the previous R).
void update_rotations(World& world);
/// world.forces.{force, elastic_energy} from positions, rotations and gravity, and
/// stiffness_diagonal when stiffness_diagonal_used.
void compute_forces(World& world);
/// Whether the step uses world.forces.stiffness_diagonal: the matrix-free jacobi method's
/// preconditioner (or no method chosen yet); the assembled methods take theirs from the matrix.
/// The contact stiffness is added to it on the same condition (systems/collision_system.h).
bool stiffness_diagonal_used(const World& world);
/// world.forces.stiffness_diagonal: diag(K) of the elements at the current rotations.
void compute_stiffness_diagonal(World& world);
/// Strain energy [J] at the current positions, each element's rotation extracted from them (the
/// stored rotations, forces and energy are those of the step's start and are left untouched).
double elastic_energy_now(const World& world);
/// out = K p (K = -df/dx with rotations frozen, positive semi-definite), 3 entries per node.
void stiffness_product(World& world, const Eigen::VectorXd& p, Eigen::VectorXd& out);
/// stiffness_product for the threads of an OpenMP team, each calling it (systems/kernels/team_cg.h):
/// the element pass and the gather are worksharing loops (a barrier after each), the contacts one
/// thread's. Same sums in the same order: the same bits as stiffness_product. Before the team,
/// prepare_stiffness_product sizes the element buffers; `out` is sized by the caller.
void stiffness_product_in_team(World& world, const Eigen::VectorXd& p, Eigen::VectorXd& out);
void prepare_stiffness_product(World& world);
/// Sums per-element nodal terms into per-node entries in a fixed order (node -> element incidence).
void gather_element_terms(const World& world, Eigen::VectorXd& out);

SystemDesc force_system();

}  // namespace xcut
