#pragma once
// WatchdogSystem: runs after the SolverSystem and stops the run (NumericalError, non-zero exit) when
// the state is garbage, before any other system or an output reads it:
//  - a NaN or an infinity in any DOF position or velocity;
//  - kinetic + elastic energy above solver.energy_factor (100) times the energy put in: the state's
//    energy at the first step (prescribed displacements, initial stretch) plus the largest work
//    gravity has done plus the work the tools' contacts have done (|F . v| dt summed, a bound).
// Backward Euler dissipates energy, so a run within the bound may still be inaccurate, but a run
// beyond it is diverging (a once-linearized step at large dt and rotation gains a few times the
// work at most: docs/BENCHMARKS.md, stability).
#include "engine/scheduler.h"
#include "engine/world.h"

namespace xcut {

/// Checks the state after a step; throws NumericalError naming the step and what to change.
void check_state(World& world);

SystemDesc watchdog_system();

}  // namespace xcut
