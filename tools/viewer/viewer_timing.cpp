#include "tools/viewer/viewer_timing.h"

#include <algorithm>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <limits>

#include "engine/error.h"

namespace xcut::viewer {
namespace {

IntervalFigures figures_of(std::vector<double> ms) {
    IntervalFigures f;
    f.count = static_cast<int>(ms.size());
    if (ms.empty()) return f;
    std::sort(ms.begin(), ms.end());
    f.p50 = ms[ms.size() / 2];
    f.p99 = ms[static_cast<size_t>(0.99 * static_cast<double>(ms.size() - 1))];
    f.max = ms.back();
    f.over_twice = static_cast<int>(std::count_if(ms.begin(), ms.end(), [&](double x) { return x > 2.0 * f.p50; }));
    return f;
}

}  // namespace

TimingFigures timing_figures(const TimingLog& log, double from, double to, double pause_s) {
    TimingFigures f;
    f.from = from, f.to = to;
    const auto inside = [&](double t) { return t >= from && t <= to; };
    std::vector<double> frames, updates, step_ms;
    for (size_t k = 1; k < log.frame_start.size(); ++k) {
        const double dt = log.frame_start[k] - log.frame_start[k - 1];
        if (dt <= pause_s && inside(log.frame_start[k])) frames.push_back(1e3 * dt);
    }
    for (size_t k = 0; k < log.steps.size(); ++k) {
        const StepTiming& s = log.steps[k];
        if (!inside(s.wall_end)) continue;
        step_ms.push_back(s.step_ms);
        if (s.split > 0) ++f.split_steps, f.split_step_max = std::max(f.split_step_max, s.step_ms);
        if (k == 0) continue;
        const double dt = s.wall_end - log.steps[k - 1].wall_end;
        if (dt > pause_s) continue;
        updates.push_back(1e3 * dt);
        if (s.split > 0) f.split_update_max = std::max(f.split_update_max, 1e3 * dt);
    }
    f.frames = figures_of(std::move(frames));
    f.updates = figures_of(std::move(updates));
    f.step_p50 = figures_of(std::move(step_ms)).p50;
    return f;
}

bool cut_window(const TimingLog& log, double margin, double& from, double& to) {
    bool any = false;
    for (const StepTiming& s : log.steps) {
        if (s.split == 0) continue;
        if (!any) from = s.wall_end;
        to = s.wall_end, any = true;
    }
    from -= margin, to += margin;
    return any;
}

namespace {

void print_figures(const TimingFigures& f, const char* part) {
    const auto ratio = [](double x, double p50) { return p50 > 0.0 ? x / p50 : 0.0; };
    fmt::print("timing ({}, {:.2f} s): {} frames, interval median {:.1f} ms, p99 {:.1f}, max {:.1f} ms ({:.2f}x; {} over "
               "twice the median); {} physics updates, interval median {:.1f} ms, p99 {:.1f}, max {:.1f} ms ({:.2f}x; {} "
               "over twice the median); {} steps split elements: their intervals up to {:.1f} ms, their own time up to "
               "{:.1f} ms (median step {:.1f} ms)\n",
               part, f.to - f.from, f.frames.count, f.frames.p50, f.frames.p99, f.frames.max,
               ratio(f.frames.max, f.frames.p50), f.frames.over_twice, f.updates.count, f.updates.p50, f.updates.p99,
               f.updates.max, ratio(f.updates.max, f.updates.p50), f.updates.over_twice, f.split_steps,
               f.split_update_max, f.split_step_max, f.step_p50);
}

}  // namespace

void report_timing(const TimingLog& log, const std::string& scene, int threads, const std::string& csv) {
    constexpr double kCutMargin = 0.5;  // [s] either side of the steps that split
    std::vector<std::pair<std::string, TimingFigures>> parts;
    double first = std::numeric_limits<double>::infinity(), last = -first;
    for (double t : {log.frame_start.empty() ? first : log.frame_start.front(), log.steps.empty() ? first : log.steps.front().wall_end})
        first = std::min(first, t);
    for (double t : {log.frame_start.empty() ? last : log.frame_start.back(), log.steps.empty() ? last : log.steps.back().wall_end})
        last = std::max(last, t);
    if (!(last >= first)) first = last = 0.0;  // nothing kept
    parts.emplace_back("session", timing_figures(log, first, last));
    double from = 0.0, to = 0.0;
    if (cut_window(log, kCutMargin, from, to)) parts.emplace_back("cut", timing_figures(log, from, to));
    for (const auto& [part, f] : parts) print_figures(f, part.c_str());
    if (csv.empty()) return;
    const bool header = !std::filesystem::exists(csv);
    std::ofstream out(csv, std::ios::app);
    if (!out) throw InputError(csv, "--timing-csv", "cannot write the timing file");
    if (header)
        out << "scene,threads,part,seconds,frames,frame_p50_ms,frame_p99_ms,frame_max_ms,frames_over_twice,updates,"
               "update_p50_ms,update_p99_ms,update_max_ms,updates_over_twice,split_steps,split_update_max_ms,"
               "step_p50_ms,split_step_max_ms\n";
    for (const auto& [part, f] : parts)
        out << fmt::format("{},{},{},{:.3f},{},{:.3f},{:.3f},{:.3f},{},{},{:.3f},{:.3f},{:.3f},{},{},{:.3f},{:.3f},{:.3f}\n",
                           scene, threads, part, f.to - f.from, f.frames.count, f.frames.p50, f.frames.p99, f.frames.max,
                           f.frames.over_twice, f.updates.count, f.updates.p50, f.updates.p99, f.updates.max,
                           f.updates.over_twice, f.split_steps, f.split_update_max, f.step_p50, f.split_step_max);
}

}  // namespace xcut::viewer
