#pragma once
// `xcut view --timing-csv FILE`: how evenly the window and the physics update through a session, a
// mouse cut above all (the step that splits elements must not freeze the picture or the force a
// haptic loop gets). Every frame's start and every physics step's publication are kept; at the end
// their intervals are summed up against their medians, and one row is appended to FILE.
// tools/bench/viewer_cut.sh drives a real mouse cut (xdotool on a virtual display) for the record.
#include <string>
#include <vector>

#include "tools/viewer/physics_thread.h"

namespace xcut::viewer {

struct TimingLog {
    std::vector<double> frame_start;  ///< wall time each frame began [s]
    std::vector<StepTiming> steps;    ///< the physics' steps, in order
};

/// Intervals [ms]: their median, 99th percentile and largest, and how many exceed twice the median.
struct IntervalFigures {
    int count = 0;
    double p50 = 0.0, p99 = 0.0, max = 0.0;
    int over_twice = 0;
};

struct TimingFigures {
    double from = 0.0, to = 0.0;  ///< the wall-time window the figures cover [s]
    IntervalFigures frames;   ///< between frame starts
    IntervalFigures updates;  ///< between physics publications (what the window and a haptic loop get)
    int split_steps = 0;      ///< steps that split elements
    double split_update_max = 0.0;  ///< the largest interval ending at a step that split [ms]
    double step_p50 = 0.0;          ///< median step's own time [ms]
    double split_step_max = 0.0;    ///< the slowest step that split [ms]
};

/// The figures of the intervals that end within [from, to] (wall seconds); intervals across a pause
/// (longer than `pause_s`) are left out.
TimingFigures timing_figures(const TimingLog& log, double from, double to, double pause_s = 0.25);

/// The cut: from `margin` [s] before the first step that split elements to `margin` after the last
/// one; false if no step split.
bool cut_window(const TimingLog& log, double margin, double& from, double& to);

/// Prints the figures of the whole session and, if elements were split, of the cut (with half a
/// second either side), and appends one row per part to `csv` (a header if the file is new).
void report_timing(const TimingLog& log, const std::string& scene, int threads, const std::string& csv);

}  // namespace xcut::viewer
