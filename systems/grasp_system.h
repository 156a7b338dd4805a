#pragma once
// GraspSystem (docs/scene-format.md, Graspers): a tool's jaws close on the tissue's skin at their
// "close" time, hold it while the tool moves and let it go at their "open" time.
//  - Closing takes the skin's vertices (the collision surface's, else the visual one's) within the
//    jaws' radius of their centre that lie on the skin as built (not on a cut's faces) and on
//    material (an element side carrying at least 1e-6 of its parent: kMinHeldWeight); each is held
//    at the point of the tool frame where it was, so closing moves nothing.
//  - Holding pulls each held vertex toward that point, moving with the tool, by a linear spring:
//    f = k (g - x) on the tissue, k the grasp's stiffness [N/m], g the held point [m], x the
//    vertex's position from its binding (eq. 4, 6: the DOF nodes of the element it is bound to, with
//    its barycentric weights, so a held vertex on a freed piece pulls that piece). The vertex
//    follows the surface's re-binding through later cuts. The stiffness k w_a w_b I enters the
//    implicit Euler matrix (held at the step's start as the contacts' is, exact for a linear
//    spring), so a stiff grasp stays stable at the scene's dt. The step's Rayleigh damping beta K
//    damps the held vertex's own velocity; its force adds beta k times the held point's, so the
//    grasp damps their relative motion only (a freed piece carried at the jaws' speed feels no drag).
//    The jaws' pull (the opposite of the sum, spring and relative damping) is Grasps::force, and
//    part of the tool's reaction force and torque (ToolBodies::reaction_force, the metrics CSV).
//  - Jaws that close on nothing are not silent: the end of the run says so.
// It runs after the CollisionSystem (its forces add to the contacts').
#include <memory>

#include "engine/scheduler.h"
#include "engine/world.h"
#include "systems/step_term.h"

namespace xcut {

/// A held vertex on an element side carrying less than this fraction of its parent is not taken:
/// no material is there (as the contacts, systems/collision_system.h) [-].
inline constexpr double kMinHeldWeight = 1e-6;

/// Closes and opens the jaws due at world.time, then adds the held vertices' pull to
/// world.forces.force (and its stiffness to the diagonal when used), sets Grasps::force and adds it
/// to the tools' reaction (which starts from the cutting force when no CollisionSystem set it).
void apply_grasps(World& world);

/// The grasps' term of the implicit step: k w_a w_b I between each held vertex's element nodes.
std::shared_ptr<StepTerm> grasp_step_term();

SystemDesc grasp_system();

}  // namespace xcut
