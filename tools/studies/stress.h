#pragma once
// `xcut stress` (docs/verification.md problems 7, 8, 9): numerical stability under slivers, many random
// cuts and large steps / large deformation. Seeded and reproducible; every invariant that breaks is
// counted, and the command exits non-zero if any did.
//  7  slivers: a clamped block cut through at delta * h from a node layer (delta = 1e-1 ... 1e-9)
//     and exactly through a face, an edge and a node, 50 steps under gravity;
//  8  many cuts: random scalpel trajectories (three random waypoints, random depth and tilt) over a
//     slab with visual and collision surfaces, `count` of them within the time budget; with
//     `blades` > 1, several scalpels per trajectory (crossing in one step, stabs, faces);
//  9  large steps: dt = 1e-4 ... 0.1 s on a slab twisted 180 degrees and released, and on a block cut
//     through and compressed to 50 % and released; once with the paper's once-linearized implicit
//     Euler ("9 large steps"), once with Newton iterations to convergence ("9 large steps, Newton").
// Invariants: no NaN or infinity; CG within kStressCgBound iterations; kinetic + elastic energy
// never above the work put in (gravity's, or the initial elastic energy) by more than 1 % (the
// once-linearized rows of problem 9: by more than the watchdog's solver.energy_factor, as that
// scheme is not dissipative at large rotations); every surface vertex bound to a live element with
// barycentric coordinates in [-1e-9, 1 + 1e-9]; every surface edge shared by exactly two
// triangles, consistently oriented; no surface triangle without area; with closed loops (2D), the
// pieces of an element or more are the regions the blades' paths enclose. Measured and printed, not yet
// held (docs/BENCHMARKS.md): bridges, elements a blade crossed through that its cut left joined
// (tools/studies/bridges.h), and the strips closed loops free (pieces smaller than an element).
#include <map>
#include <random>
#include <string>

#include "engine/io/scene.h"

namespace xcut {

constexpr int kStressCgBound = 400;        ///< CG iterations per solve (the mean over a step's Newton solves)
constexpr int kStressNewtonIterations = 50; ///< problem 9 runs again with Newton to 1e-9 (at most this many)
constexpr double kStressEnergyBound = 1.01; ///< (kinetic + elastic) / work put in, for a dissipative scheme
constexpr int kRandomCutSteps = 25;
constexpr int kStressRecordCount = 10000;  ///< trajectories of the committed record (docs/BENCHMARKS.md)  ///< steps of a problem-8 run (dt 0.02 s: the blade's 0.4 s and 0.1 s after)

/// Problem 8's scene for the next trajectory of `rng`: a 40 x 40 x 4 mm slab held at its x borders,
/// visual (1 subdivision) and collision surfaces, a scalpel through three random waypoints at a
/// random depth (1-6 mm below the top) and tilt (±0.4 rad about its path); `front` is its
/// cutter.front ("semi" or "progressive").
Scene random_cut_scene(std::mt19937_64& rng, const std::string& front = "semi");
/// The same slab cut by 2 to `blades` scalpels at once, each drawn through three random waypoints
/// or stabbed straight down along its edge, half of them with a face 4 mm wide (blade.back): the
/// second blade crosses the first's path at the same instant (in one step) half the time, and a
/// quarter of the drawn blades keep to a grid plane (a cut through mesh nodes and edges).
Scene random_blades_scene(std::mt19937_64& rng, const std::string& front, int blades);

/// Problem 8 in 2D with crack tips: a 40 x 40 mm skin patch (2 mm cells, 2 mm thick) held at its
/// x borders under gravity along -y, a scalpel point through three random waypoints (some outside
/// the patch: it enters and leaves), its tip enriched within a random radius (0: the tip's element,
/// 2 or 4 mm); a quarter of the blades stop 0.1 mm past their second waypoint and stand.
Scene random_tip_scene(std::mt19937_64& rng);
/// Problem 8 in 3D with crack fronts: random_cut_scene's slab and scalpel (some deeper than the
/// slab's 4 mm: their edges cross it whole and carry a front), cutter.tip within a random radius
/// (0: the front's elements, 2 or 4 mm).
Scene random_front_scene(std::mt19937_64& rng);

struct StressOptions {
    int count = 200;          ///< random trajectories of problem 8
    double budget_s = 120.0;  ///< wall-time budget for problem 8 [s]; it stops early when spent
    unsigned seed = 1;
    std::string csv = "results/bench_stress.csv";
    bool csv_given = false;   ///< false: a run short of kStressRecordCount writes <csv>_quick.csv instead
    std::string front = "semi";  ///< problem 8's cutter.front
    int blades = 1;           ///< problem 8's scalpels per trajectory: 1, or 2 to this many (random_blades_scene)
    bool tip = false;         ///< problem 8 on the 2D patch with crack tips (random_tip_scene)
    /// problem 8 in 3D with crack fronts at the blades: random_cut_scene (one scalpel, the semi
    /// front) with cutter.tip at a random radius (0, 2 or 4 mm); a blade deeper than the slab
    /// carries a front, a shallower one none (random_front_scene)
    bool fronts = false;
    /// problem 8 as closed loops: a scalpel round a random ellipse in a 2D skin patch, a cross-cut
    /// through its lens in two of three (tools/studies/stress_loops.h); the pieces checked
    bool loops = false;
    /// problem 8's tissue: "linear" or "quadratic" tetrahedra (docs/elements.md; 3D, not with `tip`)
    std::string element = "linear";
    /// > 1: problem 8's steps iterated by Newton to 1e-9, at most this many times (1: the paper's
    /// once-linearized step), to tell the scheme's energy gain at large rotations from a defect
    int newton = 1;
    /// problem 8 with "cutter.recut" on: an element already cut is cut again (3D: docs/xfem.md)
    bool recut = false;
    /// >= 0: run only problem 8's trajectory of this index (the index-th of `seed`, as the full run
    /// numbers them; the ones before it are drawn, not run), to reproduce one case. Never the record.
    int only = -1;
    bool progress = true;
};

struct StressSummary {
    int cases = 0, nan = 0, cg_over = 0, energy_over = 0, lost_vertices = 0;
    int open_edges = 0, pinched_edges = 0;       ///< surface edges with a gap / closed but not 2-manifold
    int zero_area = 0;                           ///< surface triangles with no area (zero_area_triangles)
    int runs_with_open = 0, runs_with_pinched = 0;  ///< cases with at least one such edge
    /// Elements blades crossed through, those of them left bridged (not yet in violations()), the
    /// cases with a bridge, and the elements the check left out (tools/studies/bridges.h).
    int crossed = 0, bridged = 0, runs_bridged = 0, left_out = 0;
    /// Loop trajectories whose pieces of an element or more do not match the regions their paths
    /// enclose (stress_loops.h), and the pieces smaller than an element they freed (strips; measured)
    int pieces_mismatch = 0, strips = 0;
    int max_cg = 0;
    double max_energy_ratio = 0.0;  ///< max over steps of (kinetic + elastic) / work put in
    int violations() const {
        return nan + cg_over + energy_over + lost_vertices + open_edges + pinched_edges + zero_area + pieces_mismatch;
    }
};

/// Runs the three problems; prints a summary table; writes one CSV row per case. Returns the
/// summary per problem ("7 slivers", "8 many cuts", "9 large steps") and over all ("all").
std::map<std::string, StressSummary> run_stress(const StressOptions& options);
int stress_command(const StressOptions& options);

}  // namespace xcut
