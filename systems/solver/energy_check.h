#pragma once
// The energy check of the once-linearized step (solver "newton": {"on_energy_gain": N}).
//
// Backward Euler converged on the corotational model does not gain energy: each step minimizes the
// incremental potential, so kinetic + stored + gravity's potential energy falls by the damping's and
// the scheme's dissipation, or rises by no more than the work the tools do on the tissue. The
// paper's once-linearized step (rotations frozen at the step's start, §4.3) only approximates it,
// and where the tissue turns fast (a freed flap or piece swinging, a large dt) it can gain: up to
// 2.4 × the work of gravity in the crack-tip stress suite (docs/BENCHMARKS.md, stability). The
// check measures the step's balance with the rotations taken afresh from the end positions, and a
// step that gained goes on with Newton iterations from where the linearized solve ended (the
// iterations then converge to backward Euler itself: the minimizer of the incremental potential,
// Gast, Schroeder, Stomakhin, Jiang & Teran, "Optimization integrator for large time steps", IEEE
// TVCG 21, 2015). The held terms (the tools' contacts and grasps) are external forces linear in the
// step, f_h0 - K_h (x - x_n): their work on the tissue over it is f_h0 . dx - dx . K_h dx / 2 exactly
// (ForceState::held_force is f_h0). A blade's cutting resistance does no work on the tissue's energy.
#include <Eigen/Core>

#include "engine/world.h"

namespace xcut {

/// Relative tolerance of the balance [-]: a step gains energy when its energy rises by more than
/// the held terms' work plus this fraction of the energy involved (the kinetic and stored energy at
/// the step's start, the held terms' work and gravity's over the step). 1e-3: far above the balance's
/// round-off and the CG tolerance's effect (1e-6 relative residual), far below the gains found
/// (7-136 % of the work put in).
inline constexpr double kEnergyGainTolerance = 1e-3;

/// Absolute floor of the balance [J]: a tissue at rest (no load, a blade splitting it) holds energies
/// of round-off, 1e-36 to 1e-33 J, whose changes are not gains. 1e-15 J is the strain energy
/// ½ E eps^2 V of a strain of 4.5e-7 in a cubic centimetre at E = 1e4 Pa, far below what a surgical
/// scene stores (1e-8 to 1e-3 J).
inline constexpr double kEnergyGainFloor = 1e-15;

/// The parts of the energy of the state x, v [J]: kinetic ½ vᵀ M v, stored (the terms' energy_now,
/// or the forces' at the step's start), gravity's potential -sum m g.x.
struct StepEnergy {
    double kinetic = 0.0, stored = 0.0, gravity = 0.0;
    double total() const { return kinetic + stored + gravity; }
};

/// The kinetic and gravity parts of the world's state with velocities v (3 per DOF node) [J].
StepEnergy motion_energy(const World& world, const Eigen::VectorXd& m3, const Eigen::VectorXd& v);

/// Whether a step from `before` to `after` gained energy: more than `work`, what the held terms did
/// on the tissue over it [J], plus kEnergyGainTolerance of the energy involved plus kEnergyGainFloor.
bool gained_energy(const StepEnergy& before, const StepEnergy& after, double work);

}  // namespace xcut
