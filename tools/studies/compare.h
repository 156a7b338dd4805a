#pragma once
// `xcut compare SCENE`: the XFEM cutter, on the paper's semi-progressive front and on the progressive
// one (cutter.front), against the snapping-and-subdivision baseline on the same scene, tools and
// decisions, in one run (paper §4, Fig. 9, 10, 12). Writes into out/<scene>/compare/ (docs/compare.md):
//  - dofs_vs_cuts.csv: DOFs after each of N incisions (the scene's incision repeated N times,
//    offset sideways), both cutters (Fig. 9 in 2D, Fig. 10 in 3D);
//  - steps.csv: per step DOFs, CG iterations and step time of both runs; profile.csv: wall time
//    per system of both runs side by side; quality.csv: element quality after the N cuts;
//  - crossing_delay.csv: crossing delay (split and opening) against blade speed and mesh size
//    (Fig. 12), every cutter;
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

/// One point of the crossing-delay sweep: one cutter alone (tool, CutSystem, the cutter's split and
/// surface update; no dynamics) along the scene's incision. Split delay: from an element's first
/// crossed edge to its split. Opening delay (XFEM only; NaN for snapping): from that crossing to the
/// step its virtual elements first use a phantom vertex, i.e. the wound can open there.
struct DelayRow {
    std::string cutter;  ///< "xfem" (semi-progressive front), "xfem_progressive" or "snap"
    double mesh_scale = 1, speed_factor = 1, element_size = 0, speed = 0, dt = 0;  ///< [-], [-], [m], [m/s], [s]
    int elements = 0, splits = 0, opened = 0;
    double mean_s = 0, p99_s = 0, max_s = 0, wall_mean_ms = 0, wall_p99_ms = 0;
    double open_mean_s = 0, open_p99_s = 0, open_max_s = 0;
};

/// Blade speeds of the sweep besides the scene's own [m/s]: 10 to 200 mm/s.
inline constexpr double kDelaySweepSpeeds[] = {0.01, 0.025, 0.05, 0.1, 0.2};

/// The crossing-delay sweep (Fig. 12): the scene's incision at its own speed and at
/// kDelaySweepSpeeds, on its mesh and (generated meshes) 1.5x coarser and 1.33x finer, for each cutter.
std::vector<DelayRow> crossing_delay_sweep(const Scene& scene, bool progress);

/// Runs the comparison, prints the table, writes the CSVs (and plots); returns 0.
int compare_command(const CompareOptions& options);

}  // namespace xcut
