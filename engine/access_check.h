#pragma once
// A check that a system touches only what it declares (Jolt's debug access guards, after the
// fact): every checked component of the world is hashed before and after each system, and one that
// changed without being among the system's declared writes is an error naming both. Off by
// default (it hashes the whole world twice per system); the scheduler runs it when asked
// (Scheduler::set_access_check), as the tests do.
#include <cstdint>
#include <string>
#include <vector>

#include "engine/world.h"

namespace xcut {

/// The component kinds whose contents are hashed (the others are settings no system writes).
inline constexpr uint32_t kCheckedComponents[] = {kNodes, kElements, kForces, kMetrics, kCutPlan, kCutEvents,
                                                  kXfem,  kTools,    kVisual, kCollision, kLinear, kContacts,
                                                  kCutState, kSnap, kPieces, kGrasps};

/// One hash per kCheckedComponents entry, of the world as it is.
std::vector<uint64_t> component_hashes(const World& world);

/// Throws std::logic_error naming `system` and the component when one changed between `before`
/// and `after` that `writes` does not declare.
void check_declared_writes(const std::string& system, uint32_t writes, const std::vector<uint64_t>& before,
                           const std::vector<uint64_t>& after);

}  // namespace xcut
