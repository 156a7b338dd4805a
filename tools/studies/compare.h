#pragma once
// `xcut compare SCENE`: the XFEM cutter against the snapping-and-subdivision baseline on the same
// scene, tools and decisions, in one run (paper §4, Fig. 9, 10, 12). Writes into
// out/<scene>/compare/ (docs/compare.md):
//  - dofs_vs_cuts.csv: DOFs after each of N incisions (the scene's incision repeated N times,
//    offset sideways), both cutters (Fig. 9 in 2D, Fig. 10 in 3D);
//  - steps.csv: per step DOFs, CG iterations and step time of both runs; profile.csv: wall time
//    per system of both runs side by side; quality.csv: element quality after the N cuts;
//  - crossing_delay.csv: crossing delay against blade speed and mesh size (Fig. 12), both cutters;
//  - summary.csv and a one-screen table; PNG plots by tools/report/plot_compare.py when Python and
//    matplotlib are there (the CSVs are complete without them).
#include <string>
#include <vector>

#include "engine/io/scene.h"

namespace xcut {

struct CompareOptions {
    std::string scene;
    std::vector<std::string> overrides;   ///< --set field=value, as for `xcut run`
    int cuts = 20;                        ///< incisions
    double spacing = 0.0;                 ///< sideways distance between incisions [m]; 0: automatic
    int threads = 2;
    std::string output;                   ///< default: out/<scene name>/compare
    double quality_threshold_deg = 10.0;  ///< an element below this smallest angle counts as poor [deg]
    bool delay_sweep = true;              ///< the Fig. 12 sweep (blade speeds x mesh sizes)
    bool plots = true;
    bool quiet = false;
};

/// The incisions of a comparison: the scene's first bladed tool's trajectory repeated `cuts` times,
/// one after another in time. Incision k is offset sideways (across the blade's path and edge) by
/// s, -s, 2s, -2s, ... and along the blade edge so that it meets the body at the same depth as the
/// first (on a curved body the blade follows the surface). Automatic spacing s: the smaller of
/// 1.25 mean edge lengths and 0.9 x the body's width across / cuts.
struct Incisions {
    Scene scene;                   ///< with one tool per incision and the duration to run them all
    double spacing = 0.0;          ///< s [m]
    std::vector<double> end_time;  ///< per incision: when its last sweep has been applied [s]
};
Incisions repeated_incisions(const Scene& scene, int cuts, double spacing);

/// Runs the comparison, prints the table, writes the CSVs (and plots); returns 0.
int compare_command(const CompareOptions& options);

}  // namespace xcut
