#pragma once
// Plausibility: what a scene can ask for that is valid but almost surely not meant (a mesh in
// millimetres read as metres, E in kPa written as Pa, a tool that never reaches the tissue), said as
// warnings at load with the number that triggered each and how to silence it ("allow": [names]);
// what a finished run should flag (a body that left the scene, a blade that cut nothing); and the
// bound on what a run may write. Tissue ranges: docs/scene-format.md#plausibility.
#include <string>
#include <vector>

#include "engine/io/scene.h"
#include "engine/world.h"

namespace xcut {

/// The checks "allow" may name, in the order they run.
inline constexpr const char* kPlausibilityChecks[] = {"units", "young", "density", "poisson", "tool_reach", "dt"};

/// Young's modulus of soft tissue, brain (~0.1 kPa) to tendon in its linear range (~100 MPa)
/// [Pa] (Fung, Biomechanics, 1993; McKee et al., Tissue Eng. B 17, 2011).
inline constexpr double kTissueYoungMin = 100.0, kTissueYoungMax = 1e8;
/// Density of soft tissue, fat (~900) to cortical bone (~1,900) with a margin [kg/m^3] (ICRP 89).
inline constexpr double kTissueDensityMin = 500.0, kTissueDensityMax = 2500.0;
/// Poisson's ratio from which linear tetrahedra lock (docs/verification.md problem 3).
inline constexpr double kLockingPoisson = 0.45;
/// A body's extent without "units" outside this range [m] is probably in other units.
inline constexpr double kBodySizeMin = 1e-3, kBodySizeMax = 2.0;

/// The warnings of a built scene (each "check: ... (silence: "allow": ["check"])"), less those
/// the scene's "allow" names.
std::vector<std::string> plausibility_warnings(const Scene& scene, const World& world, int steps);

/// Throws InputError naming output.every and output.max_gb when the run's estimated output over
/// `steps` steps exceeds scene.max_output_gb.
void check_output_volume(const Scene& scene, const World& world, int steps);

/// Throws InputError naming cuts[i].front when a cut asks for its front to be enriched in a scene
/// that cannot carry it: the snapping cutter, the progressive front, blades carrying tips
/// (cutter.tip), quadratic elements, or a polygon drawn in the current configuration after time 0
/// (the front is placed on the body at rest: "frame": "rest").
void check_cut_fronts(const Scene& scene, const World& world);

/// Each body's centre (mean of its mesh nodes) and extent (box diagonal) at rest [m].
struct BodyExtents {
    std::vector<Vec3> centre;
    std::vector<double> size;
};
BodyExtents body_extents(const World& world, bool at_rest);

/// What a finished run should flag: bodies whose centre moved more than their own size, bladed
/// tools that split nothing in a scene that cuts.
std::vector<std::string> end_of_run_notes(const World& world);

}  // namespace xcut
