#pragma once
// CollisionSystem (paper §3.5): tool contact shapes against the tissue's collision surface.
//  - Broad and narrow phase by FCL: the collision surface is an FCL BVH (AABB) refitted every step
//    to the mapped vertex positions, rebuilt only when a cut changes its triangles; each shaped
//    tool is an FCL sphere, capsule, box or mesh at its current pose. FCL reports the surface
//    triangles touching the tool; their vertices are tested exactly (systems/kernels/tool_shape_depth.h).
//  - Response by penalty, one contact per vertex inside a tool: f = max(0, k d - c v_n) n on the
//    tissue, n out of the tool, d the depth, v_n the vertex's normal speed relative to the tool.
//    The force acts on the element the vertex is bound to, spread to its (real or phantom) DOF
//    nodes by the barycentric weights: on a virtual element after a cut, so a contact on one lip
//    of a wound moves that lip only. The stiffness k n n^T enters the implicit Euler matrix
//    (stiffness_product), so stiff contacts stay stable at the scene's dt; damping is explicit.
//    Vertices bound to a sliver side (weight V_s/V < 1e-6) take no contact: nothing is there.
//    Penalty was chosen over constraint projection because it yields the force to feed back
//    directly and keeps the matrix-free CG unchanged.
//  - Each tool's reaction (force and torque about its origin) is the opposite of the sum of its
//    contact forces, written to the metrics CSV.
#include <memory>

#include "engine/scheduler.h"
#include "engine/world.h"
#include "systems/step_term.h"

namespace xcut {

/// FCL state (the refitted surface BVH and the tool geometries); opaque to the rest of the engine.
struct CollisionModel;
std::shared_ptr<CollisionModel> make_collision_model();

/// Finds this step's contacts (world.contacts) from tool poses and collision-surface positions.
void detect_contacts(World& world, CollisionModel& model);
/// Adds the contact forces to world.forces.force and the contact stiffness to its diagonal; sets
/// each tool's reaction force and torque.
void apply_contact_forces(World& world);
/// out += K_contact p (K_contact = sum over contacts of k w w^T (x) n n^T).
void add_contact_stiffness_product(const World& world, const Eigen::VectorXd& p, Eigen::VectorXd& out);

/// The contacts' term of the implicit step (systems/step_term.h): held at the step's start, its
/// product and its blocks (after the mass) of the assembled A.
std::shared_ptr<StepTerm> contact_step_term();

SystemDesc collision_system(std::shared_ptr<CollisionModel> model);

}  // namespace xcut
