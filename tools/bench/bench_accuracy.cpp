#include <cstdlib>
#include "tools/bench/bench_accuracy.h"

#include <algorithm>
#include <map>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <fmt/os.h>
#include <stdexcept>

#include "tools/studies/accuracy_problems.h"
#include "tools/studies/crack_reference.h"
#include "engine/io/output.h"
#include "tools/studies/plot_script.h"
#include "engine/parallel.h"

namespace xcut {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

const char* kCutters[2] = {"xfem", "snap"};

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// The row of one run: figures of the world after its solve.
AccuracyRow row_of(int problem, const char* cutter, int level, double h, const World& w, int split, double run_s,
                   const StaticResult& r) {
    if (!r.converged)
        throw std::runtime_error(fmt::format("problem {} ({}, level {}): no static equilibrium (residual {:.3g})", problem,
                                             cutter, level, r.residual));
    AccuracyRow row;
    row.problem = problem;
    row.cutter = cutter;
    row.resolution = level;
    row.element_size = h;
    row.dofs = w.elements.dim * w.nodes.count();
    row.split = split;
    row.run_s = run_s;
    row.newton = r.newton_iterations;
    row.cg = r.cg_iterations;
    return row;
}

AccuracyRow cantilever_run(int n) {
    const CantileverSpec spec;
    World w = cantilever_world(spec, n);
    const auto t0 = Clock::now();
    const StaticResult r = solve_equilibrium(w);
    AccuracyRow row = row_of(3, "uncut", n, spec.height / n, w, 0, seconds_since(t0), r);
    row.value = cantilever_tip_deflection(w, spec);
    row.reference = cantilever_reference(spec);
    row.error = std::abs(row.value / row.reference - 1.0);
    return row;
}

AccuracyRow block_run(int n, const char* cutter, const ReferenceField& ref) {
    const CutBlockSpec spec;
    World w = cut_block_world(spec, n);
    w.snap.enabled = std::string(cutter) == "snap";
    const auto t0 = Clock::now();
    const int split = cut_with_polygon(w, cut_block_polygon(spec));
    pull_block_ends(w, spec);
    const StaticResult r = solve_equilibrium(w);
    AccuracyRow row = row_of(5, cutter, n, spec.size.x() / n, w, split, seconds_since(t0), r);
    const std::vector<Probe> probes = locate_points(w, cut_block_samples(spec));
    double diff = 0.0, norm = 0.0, own = 0.0;
    for (size_t k = 0; k < probes.size(); ++k) {
        const Vec3 u = probe_displacement(w, probes[k]);
        diff += (u - ref.displacement[k]).squaredNorm();
        norm += ref.displacement[k].squaredNorm();
        own += u.squaredNorm();
    }
    row.value = std::sqrt(own / probes.size());
    row.reference = std::sqrt(norm / probes.size());
    row.error = std::sqrt(diff / norm);
    return row;
}

AccuracyRow plate_run(int n, const char* cutter) {
    const EdgeCrackSpec spec;
    World w = edge_crack_world(spec, n);
    w.snap.enabled = std::string(cutter) == "snap";
    const auto t0 = Clock::now();
    const int split = cut_with_polygon(w, edge_crack_segment(spec));
    const Eigen::VectorXd load = edge_crack_load(w, spec);
    const StaticResult r = solve_equilibrium(w, load);
    AccuracyRow row = row_of(6, cutter, n, spec.width / n, w, split, seconds_since(t0), r);
    row.value = edge_crack_cmod(w, spec);
    row.reference = edge_crack_reference_cmod(spec);
    row.error = std::abs(row.value / row.reference - 1.0);
    return row;
}

/// The user's cache directory (XDG Base Directory: $XDG_CACHE_HOME, else ~/.cache), never beside
/// the binary: an installed xcut may sit in a directory its user cannot write.
std::string default_cache_dir() {
    const char* xdg = std::getenv("XDG_CACHE_HOME");
    if (xdg && *xdg && fs::path(xdg).is_absolute()) return (fs::path(xdg) / "xcut" / "accuracy").string();
    const char* home = std::getenv("HOME");
    if (home && *home) return (fs::path(home) / ".cache" / "xcut" / "accuracy").string();
    return (fs::current_path() / ".xcut_cache" / "accuracy").string();
}

void check_options(const AccuracyBenchOptions& o) {
    if (o.threads < 1) throw std::invalid_argument(fmt::format("--threads: {} must be at least 1", o.threads));
    for (int p : o.problems)
        if (p != 3 && p != 5 && p != 6) throw std::invalid_argument(fmt::format("--problems: {} is not 3, 5 or 6", p));
    auto positive = [](const std::vector<int>& v, const char* what) {
        if (v.empty()) throw std::invalid_argument(fmt::format("{}: no resolution given", what));
        for (int n : v)
            if (n < 1) throw std::invalid_argument(fmt::format("{}: resolution {} must be at least 1", what, n));
    };
    positive(o.cantilever_levels, "cantilever levels");
    positive(o.block_levels, "block levels");
    positive(o.plate_levels, "plate levels");
    const CutBlockSpec block;
    for (int n : o.block_levels) cut_block_cells(block, n);  // throws on a level whose grid misses the crack front
    for (int n : o.plate_levels) edge_crack_cells(EdgeCrackSpec{}, n);
    if (o.block_reference <= *std::max_element(o.block_levels.begin(), o.block_levels.end()))
        throw std::invalid_argument("the conforming reference must be finer than every block level");
}

bool wants(const AccuracyBenchOptions& o, int problem) {
    return std::find(o.problems.begin(), o.problems.end(), problem) != o.problems.end();
}

}  // namespace

AccuracyBenchOptions AccuracyBenchOptions::tiny() {
    AccuracyBenchOptions o;
    o.cantilever_levels = {1, 2, 3};
    o.block_levels = {4, 8, 12};
    o.block_reference = 24;
    o.plate_levels = {16, 32, 64};
    o.plots = false;
    o.progress = false;
    return o;
}

std::vector<AccuracyRow> run_accuracy_bench(const AccuracyBenchOptions& o) {
    check_options(o);
    set_thread_count(o.threads);
    std::vector<AccuracyRow> rows;
    const int total = (wants(o, 3) ? o.cantilever_levels.size() : 0) + (wants(o, 5) ? 2 * o.block_levels.size() + 1 : 0) +
                      (wants(o, 6) ? 2 * o.plate_levels.size() : 0);
    ProgressBar bar("accuracy", o.progress ? total : 0);
    int done = 0;
    if (wants(o, 3))
        for (int n : o.cantilever_levels) rows.push_back(cantilever_run(n)), bar.update(++done);
    if (wants(o, 5)) {
        const ReferenceField ref = cut_block_reference(CutBlockSpec{}, o.block_reference,
                                                       o.cache_dir.empty() ? default_cache_dir() : o.cache_dir);
        bar.update(++done);
        if (o.progress)
            fmt::print(stderr, "\nproblem 5 reference: {} DOFs, {} ({})\n", ref.dofs,
                       ref.from_cache ? "from the cache" : fmt::format("solved in {:.1f} s", ref.solve_s), ref.path);
        for (int n : o.block_levels)
            for (const char* c : kCutters) rows.push_back(block_run(n, c, ref)), bar.update(++done);
    }
    if (wants(o, 6))
        for (int n : o.plate_levels)
            for (const char* c : kCutters) rows.push_back(plate_run(n, c)), bar.update(++done);
    bar.finish();
    return rows;
}

void write_accuracy_csv(const std::string& path, const std::vector<AccuracyRow>& rows,
                        const std::vector<std::string>& summary) {
    const fs::path p(path);
    if (p.has_parent_path()) fs::create_directories(p.parent_path());
    auto csv = fmt::output_file(path);
    csv.print("problem,cutter,resolution,element_size_m,dofs,split,run_time_s,newton,cg_iterations,value_m,reference_m,error\n");
    for (const AccuracyRow& r : rows)
        csv.print("{},{},{},{:.6g},{},{},{:.6g},{},{},{:.10g},{:.10g},{:.6g}\n", r.problem, r.cutter, r.resolution,
                  r.element_size, r.dofs, r.split, r.run_s, r.newton, r.cg, r.value, r.reference, r.error);
    for (const std::string& line : summary) csv.print("# {}\n", line);
}

std::vector<FrontComparison> compare_fronts(const std::vector<AccuracyRow>& rows, int problem) {
    std::map<std::string, std::vector<const AccuracyRow*>> front;
    for (const AccuracyRow& r : rows)
        if (r.problem == problem && (r.cutter == "xfem" || r.cutter == "snap")) front[r.cutter].push_back(&r);
    for (auto& [cutter, runs] : front)
        std::sort(runs.begin(), runs.end(), [](auto* a, auto* b) { return a->run_s < b->run_s; });
    std::vector<FrontComparison> out;
    for (const AccuracyRow& x : rows) {
        if (x.problem != problem || (x.cutter != "xfem" && x.cutter != "snap")) continue;
        FrontComparison c;
        c.run = &x;
        const auto& other = front[x.cutter == "xfem" ? "snap" : "xfem"];
        for (size_t k = 1; k < other.size(); ++k) {
            const AccuracyRow &a = *other[k - 1], &b = *other[k];
            if (x.run_s < a.run_s || x.run_s > b.run_s || !(b.run_s > a.run_s)) continue;
            const double t = std::log(x.run_s / a.run_s) / std::log(b.run_s / a.run_s);
            c.other_error = std::exp((1.0 - t) * std::log(a.error) + t * std::log(b.error));
            c.ratio = x.error / c.other_error;
            break;
        }
        out.push_back(c);
    }
    return out;
}

namespace {

/// Each run of `problem` against the other cutter at equal run time, and who wins where.
void front_lines(const std::vector<AccuracyRow>& rows, int problem, std::vector<std::string>& out) {
    std::map<std::string, std::vector<int>> wins;
    for (const FrontComparison& c : compare_fronts(rows, problem)) {
        const AccuracyRow& r = *c.run;
        const std::string other = r.cutter == "xfem" ? "snap" : "xfem";
        if (c.ratio == 0.0) {
            out.push_back(fmt::format("problem {} {} level {} ({:.3g} s, error {:.3g} %): outside {}'s run-time range",
                                      problem, r.cutter, r.resolution, r.run_s, 100 * r.error, other));
            continue;
        }
        const std::string& winner = c.ratio <= 1.0 ? r.cutter : other;
        if (c.ratio <= 1.0) wins[r.cutter].push_back(r.resolution);
        out.push_back(fmt::format("problem {} {} level {} ({:.3g} s, error {:.3g} %): {} at equal run time {:.3g} % -> "
                                  "{:.2f} x: {} more accurate", problem, r.cutter, r.resolution, r.run_s, 100 * r.error,
                                  other, 100 * c.other_error, c.ratio, winner));
    }
    auto list = [&wins](const char* c) { return wins[c].empty() ? std::string("none") : fmt::format("{}", fmt::join(wins[c], ", ")); };
    out.push_back(fmt::format("problem {}: at equal run time XFEM is the more accurate at its levels {}; snapping at its "
                              "levels {}", problem, list("xfem"), list("snap")));
}

}  // namespace

std::vector<std::string> accuracy_summary(const std::vector<AccuracyRow>& rows) {
    std::vector<std::string> out;
    const auto finest = [&](int problem, const char* cutter) -> const AccuracyRow* {
        const AccuracyRow* best = nullptr;
        for (const AccuracyRow& r : rows)
            if (r.problem == problem && r.cutter == cutter && (!best || r.resolution > best->resolution)) best = &r;
        return best;
    };
    if (const AccuracyRow* f = finest(3, "uncut")) {
        // Richardson extrapolation of the two finest levels with the order of linear elements, p = 2.
        const AccuracyRow* g = nullptr;
        for (const AccuracyRow& r : rows)
            if (r.problem == 3 && r.resolution < f->resolution && (!g || r.resolution > g->resolution)) g = &r;
        if (g) {
            const double ratio = double(f->resolution) / g->resolution;
            const double extrapolated = f->value + (f->value - g->value) / (ratio * ratio - 1.0);
            out.push_back(fmt::format("problem 3: finest {:+.2f} % from beam theory; Richardson (p = 2) of the two finest {:+.2f} %",
                                      100 * (f->value / f->reference - 1), 100 * (extrapolated / f->reference - 1)));
        }
    }
    for (int problem : {5, 6})
        if (finest(problem, "xfem") && finest(problem, "snap")) front_lines(rows, problem, out);
    for (const char* c : kCutters)
        if (const AccuracyRow* f = finest(6, c))
            out.push_back(fmt::format("problem 6 ({}): finest CMOD {:.4e} m against Tada-Paris-Irwin {:.4e} m: {:+.2f} % "
                                      "(tolerance 5 %) -> {}", c, f->value, f->reference, 100 * (f->value / f->reference - 1),
                                      f->error <= 0.05 ? "within" : "OUTSIDE"));
    return out;
}

int accuracy_bench_command(const AccuracyBenchOptions& o) {
    const auto rows = run_accuracy_bench(o);
    fmt::print("accuracy benchmark: static solves (Newton 1e-6, CG 1e-10), {} threads; run time = cut + solve\n",
               thread_count());
    fmt::print("{:>3} {:>6} {:>5} {:>9} {:>8} {:>6} {:>9} {:>7} {:>8} {:>12} {:>12} {:>9}\n", "pb", "cutter", "level",
               "h [mm]", "DOFs", "split", "run [s]", "Newton", "CG", "value [m]", "ref [m]", "error");
    for (const AccuracyRow& r : rows)
        fmt::print("{:>3} {:>6} {:>5} {:>9.3f} {:>8} {:>6} {:>9.4f} {:>7} {:>8} {:>12.5e} {:>12.5e} {:>8.3f}%\n", r.problem,
                   r.cutter, r.resolution, r.element_size * 1e3, r.dofs, r.split, r.run_s, r.newton, r.cg, r.value,
                   r.reference, 100.0 * r.error);
    const std::vector<std::string> summary = accuracy_summary(rows);
    for (const std::string& line : summary) fmt::print("{}\n", line);
    write_accuracy_csv(o.csv, rows, summary);
    fmt::print("csv: {}\n", o.csv);
    if (o.plots) {
        const fs::path csv(o.csv);
        run_plot_script("plot_accuracy.py", fmt::format("'{}' '{}'", o.csv, (csv.has_parent_path() ? csv.parent_path() : fs::path(".")).string()));
    }
    return 0;
}

}  // namespace xcut
