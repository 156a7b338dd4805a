#pragma once
// CuttingForceSystem: the resistance a blade feels while it cuts, from fracture mechanics (Mahvash &
// Hayward 2004, "Haptic rendering of cutting: a fracture mechanics approach", Haptics-e 2(3)). In
// steady cutting the work the blade does goes into new cut surface: a blade whose edge is w metres
// deep in a tissue of fracture toughness J_c [J/m^2] and advances dx opens J_c w dx of it, so it
// feels F = J_c w against its advance, whatever its speed (Greenish et al. 2002 measured
// speed-independent cutting forces in rat skin, liver and tendon). The lips of the wound rub the
// blade: a friction c_f w [N/m x m] against its motion in any direction (a stab too), after the
// shaft friction per inserted length of needle-insertion models (Okamura, Simone & O'Leary 2004).
//
// Per bladed tool, each step, at the tool's new pose and the tissue's state at the step's start:
//  - the edge (tip -> heel) is clipped exactly to every element that carries material: a whole
//    mesh element, each snapping piece, and each XFEM virtual element cut by its side's plane (the
//    plane through its cut points, mapped with the element's own vertices: each side holds only
//    its material). Each interval adds its length times its material's J_c and c_f;
//  - the edge's velocity at the interval's middle [m/s] comes from its poses at the step's start
//    and end; the fracture term acts against its part across the edge (an edge sliding along
//    itself opens nothing), the friction against all of it;
//  - the fracture term counts only where the blade opens new surface: uncut elements and tip
//    elements (a progressive front's, not yet fully crossed). A cut element the blade has crossed
//    fully, or a snapping piece, is its own wound: a blade drawn back along it feels the friction,
//    and the toughness only where its edge is still in whole elements (the row at its tip that the
//    tip's own front crossed partly, which the semi front never splits). On the semi front the edge sits in the partly crossed, still whole elements ahead of the
//    wound, on the progressive one in its tip elements: steady cutting feels J_c w throughout;
//  - a velocity below kCuttingSpeedFloor is scaled down linearly (F = -J_c w v / floor), so a blade
//    held still feels nothing rather than a force that flips with the rounding of its velocity.
// 2D: the blade is a point; while it is inside an element, w is the material's thickness.
//
// The force acts on the tool only (ToolBodies::cutting_force, added into reaction_force for the
// devices, the haptic loop and the metrics); the tissue is not pushed: the energy is spent opening
// the cut, which the XFEM split represents.
#include <memory>

#include "engine/scheduler.h"
#include "engine/world.h"
#include "systems/kernels/element_bvh.h"

namespace xcut {

/// Blade speed below which the cutting force is scaled down linearly [m/s].
inline constexpr double kCuttingSpeedFloor = 1e-3;

/// Sets ToolBodies::cutting_force, cutting_torque and blade_depth for every tool (zero for tools
/// without a blade), and reaction_force / reaction_torque to them (the contacts add theirs after).
void compute_cutting_forces(World& world, ElementBvh& bvh);

/// The system over the cut search's BVH (shared with the CutSystem).
SystemDesc cutting_force_system(std::shared_ptr<ElementBvh> bvh);

}  // namespace xcut
