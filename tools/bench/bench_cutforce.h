#pragma once
// `xcut bench --suite cutforce`: the blade's cutting resistance (systems/cut/cutting_force.h) against
// blade speed and depth. A scalpel is drawn straight across a liver-like block (60 x 40 x 30 mm,
// 3 mm cells, E 5 kPa, toughness 200 J/m^2: porcine liver cut by a blade, 187-225 J/m^2) at several
// speeds with its edge at several depths; the full pipeline runs (gravity, XFEM splits). Per run,
// over the steady part of the cut (the blade in the tissue, from 25 % to 75 % of its path): the mean
// force against the advance, its spread, the largest change from one step to the next (what a
// haptic device renders), the edge's mean depth, and the force per depth against the toughness.
// Across speeds at one depth: the spread of the mean force (measured cutting forces do not depend
// on speed: Greenish et al. 2002). A benchmark: prints figures and writes results/bench_cutforce.csv
// (--tiny: results/bench_cutforce_quick.csv).
#include <string>
#include <vector>

namespace xcut {

struct CutForceBenchOptions {
    bool tiny = false;  ///< one depth, two speeds
    std::string csv = "results/bench_cutforce.csv";
};

struct CutForceBenchRow {
    double speed = 0, depth = 0;       ///< blade speed [m/s], edge depth below the top [m]
    int steps = 0, steady_steps = 0;
    double mean_force = 0, std_force = 0, max_jump = 0;  ///< [N]
    double mean_depth = 0;             ///< the edge's length in the tissue [m]
    double force_per_depth = 0;        ///< mean force / mean depth [N/m]: J_c in steady cutting
    int elements_split = 0;
    double ms_per_step = 0;
};

std::vector<CutForceBenchRow> run_cutforce_bench(const CutForceBenchOptions& options);
int cutforce_bench_command(const CutForceBenchOptions& options);

}  // namespace xcut
