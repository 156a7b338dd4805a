// xcut bench --suite perf|cut|mapping|collision|accuracy|solver|mesh_io|cutstep|cutforce|locking: benchmarks that print figures and write
// CSV (never pass/fail); docs/BENCHMARKS.md is generated from their CSVs by tools/report/.
#include <algorithm>
#include <map>

#include "tools/bench/bench.h"
#include "tools/bench/bench_accuracy.h"
#include "tools/bench/bench_collision.h"
#include "tools/bench/bench_cut.h"
#include "tools/bench/bench_cutforce.h"
#include "tools/bench/bench_cutstep.h"
#include "tools/bench/bench_locking.h"
#include "tools/bench/bench_mapping.h"
#include "tools/bench/bench_mesh_io.h"
#include "tools/bench/bench_solver.h"
#include "tools/xcut_commands.h"

namespace xcut {
namespace {

struct BenchOptions {
    std::string suite = "perf";
    PerfBenchOptions perf;
    CutBenchOptions cut;
    AccuracyBenchOptions accuracy;
    bool accuracy_tiny = false, accuracy_no_plots = false;
    std::vector<std::string> cases;  ///< solver: only these cases
};

void add_bench_options(CLI::App& cmd, BenchOptions& o) {
    cmd.add_option("--suite", o.suite,
                   "perf: steps/s, CG, bytes per tet; cut: cut update per quad, crossing delay; mapping: surface "
                   "update and re-binding; collision: contact time per step, haptic rate; accuracy: error against "
                   "run time, XFEM and snapping (docs/verification.md problems 3, 5, 6); solver: every linear method against "
                   "jacobi, and 1 vs 2 threads under load; mesh_io: reading a 200k-tet mesh in each binary format; cutstep: "
                   "step times through a continuous cut, the steps that split against the median; cutforce: the blade's cutting "
                   "resistance against its speed and depth; locking: the clamped beam at nu 0-0.49, linear against quadratic tetrahedra")
        ->check(CLI::IsMember({"perf", "cut", "mapping", "collision", "accuracy", "solver", "mesh_io", "cutstep", "cutforce",
                               "locking"}));
    cmd.add_option("--sizes", o.perf.sizes, "Target tetrahedron counts")->delimiter(',');
    cmd.add_option("--threads", o.perf.threads, "Thread counts (perf)")->delimiter(',');
    cmd.add_option("--steps", o.perf.steps, "Timed steps per run (perf)")->check(CLI::PositiveNumber);
    cmd.add_option("--scene", o.perf.scene, "Scene whose mesh.grid is resized (perf)");
    cmd.add_option("--csv", o.perf.csv, "CSV to write (default results/bench_<suite>.csv)");
    cmd.add_option("--speed", o.cut.speed, "Blade speed [m/s] (cut)")->check(CLI::PositiveNumber);
    cmd.add_option("--problems", o.accuracy.problems, "docs/verification.md problems (accuracy): 3, 5, 6")
        ->delimiter(',');
    cmd.add_option("--cases", o.cases, "Only these cases (solver, cutstep; a partial run writes its quick CSV): solver: "
                   "skin_slab, hand_dorsum, block_2k, block_53k, block_200k, thin_membrane; cutstep: skin_2mm, skin_1mm, "
                   "skin_0.7mm, block_20k, block_53k, block_200k")->delimiter(',');
    cmd.add_flag("--tiny", o.accuracy_tiny,
                 "The small configuration (accuracy, solver, mesh_io, cutstep, cutforce, locking): writes its own CSV");
    cmd.add_option("--cache-dir", o.accuracy.cache_dir,
                   "Where the CalculiX references are cached (accuracy, locking; default $XDG_CACHE_HOME/xcut/accuracy, ~/.cache/xcut/accuracy)");
    cmd.add_flag("--no-plots", o.accuracy_no_plots, "CSV only (accuracy)");
}

/// "results/bench_x.csv" -> "results/bench_x_quick.csv": where a quick or partial run (--tiny,
/// --sizes, --steps, --problems, --threads) writes, so it never overwrites the committed record.
std::string quick_csv(const std::string& record) {
    const size_t dot = record.rfind(".csv");
    return (dot == std::string::npos ? record : record.substr(0, dot)) + "_quick.csv";
}

/// The CSV a run writes: --csv if given; the record's own name for a full run; else its quick file.
std::string csv_for(const CLI::App& cmd, const std::string& given, const std::string& record, bool partial) {
    if (cmd.count("--csv")) return given;
    if (!partial) return record;
    const std::string quick = quick_csv(record);
    fmt::print("a quick or partial run: it writes {}, not the record {}\n", quick, record);
    return quick;
}

/// A suite's options with --csv applied when given (each suite has its own default CSV).
template <class Options>
Options& with_csv(const CLI::App& cmd, const std::string& csv, Options& options) {
    if (cmd.count("--csv")) options.csv = csv;
    return options;
}

/// A suite whose only options are --tiny and --csv.
template <class Options>
int run_tiny_or_full(const CLI::App& cmd, const BenchOptions& o, int (*run)(const Options&)) {
    Options options;
    options.tiny = o.accuracy_tiny;
    return run(with_csv(cmd, o.perf.csv, options));
}

/// The options each suite reads besides --suite and --csv. One given to a suite that does not read
/// it is refused, not ignored: a run that silently ignored --sizes once wrote its full record.
const std::map<std::string, std::vector<const char*>> kSuiteOptions = {
    {"perf", {"--sizes", "--threads", "--steps", "--scene"}},
    {"cut", {"--sizes", "--speed"}},
    {"mapping", {"--threads", "--steps"}},
    {"collision", {"--steps"}},
    {"accuracy", {"--problems", "--threads", "--tiny", "--cache-dir", "--no-plots"}},
    {"solver", {"--cases", "--tiny"}},
    {"mesh_io", {"--tiny"}},
    {"cutstep", {"--cases", "--tiny"}},
    {"cutforce", {"--tiny"}},
    {"locking", {"--tiny", "--cache-dir"}},
};
/// Options that change what a suite measures: with any of them given, the run is partial and
/// writes its quick CSV, never the committed record.
constexpr const char* kPartialOptions[] = {"--sizes", "--threads", "--steps", "--scene", "--speed",
                                           "--problems", "--tiny", "--cases"};

/// Throws CLI::ValidationError when an option the suite does not read was given; whether the run
/// is partial otherwise.
bool check_suite_options(const CLI::App& cmd, const std::string& suite) {
    const std::vector<const char*>& reads = kSuiteOptions.at(suite);
    bool partial = false;
    for (const char* opt : kPartialOptions) {
        if (cmd.count(opt) == 0) continue;
        if (std::find_if(reads.begin(), reads.end(), [&](const char* r) { return std::string(r) == opt; }) == reads.end())
            throw CLI::ValidationError(opt, fmt::format("the {} suite does not read it (it reads: {})", suite,
                                                        fmt::join(reads, ", ")));
        partial = true;
    }
    return partial;
}

int run_bench(const CLI::App& cmd, const BenchOptions& o) {
    const PerfBenchOptions& perf = o.perf;
    const bool partial = check_suite_options(cmd, o.suite);
    if (o.suite == "mapping") {
        MappingBenchOptions m;
        if (cmd.count("--threads")) m.threads = perf.threads;
        if (cmd.count("--steps")) m.repeats = perf.steps;
        m.csv = csv_for(cmd, perf.csv, m.csv, partial);
        return mapping_bench_command(m);
    }
    if (o.suite == "collision") {
        CollisionBenchOptions c;
        if (cmd.count("--steps")) c.steps = perf.steps;
        c.csv = csv_for(cmd, perf.csv, c.csv, partial);
        return collision_bench_command(c);
    }
    if (o.suite == "accuracy") {
        AccuracyBenchOptions a = o.accuracy_tiny ? AccuracyBenchOptions::tiny() : AccuracyBenchOptions{};
        a.problems = o.accuracy.problems;
        a.cache_dir = o.accuracy.cache_dir;
        a.plots = !o.accuracy_no_plots;
        a.progress = true;
        if (cmd.count("--threads")) a.threads = perf.threads.front();
        a.csv = csv_for(cmd, perf.csv, a.csv, partial);
        return accuracy_bench_command(a);
    }
    if (o.suite == "solver") {
        SolverBenchOptions solver;
        solver.tiny = o.accuracy_tiny;
        if (solver.tiny) solver.repeats = 1;
        solver.cases = o.cases;
        solver.csv = csv_for(cmd, perf.csv, "results/bench_solver.csv", partial);
        return solver_bench_command(solver);
    }
    if (o.suite == "cutstep") {
        CutStepBenchOptions c;
        c.tiny = o.accuracy_tiny, c.cases = o.cases;
        c.csv = csv_for(cmd, perf.csv, c.csv, partial);
        return cutstep_bench_command(c);
    }
    if (o.suite == "mesh_io") return run_tiny_or_full<MeshIoBenchOptions>(cmd, o, mesh_io_bench_command);
    if (o.suite == "cutforce") {
        CutForceBenchOptions c;
        c.tiny = o.accuracy_tiny;
        c.csv = csv_for(cmd, perf.csv, c.csv, partial);
        return cutforce_bench_command(c);
    }
    if (o.suite == "locking") {
        LockingBenchOptions l;
        l.tiny = o.accuracy_tiny, l.cache_dir = o.accuracy.cache_dir;
        l.csv = csv_for(cmd, perf.csv, l.csv, partial);
        return locking_bench_command(l);
    }
    if (o.suite == "cut") {
        CutBenchOptions cut = o.cut;
        cut.sizes = perf.sizes;
        cut.csv = csv_for(cmd, perf.csv, "results/bench_cut.csv", partial);
        return cut_bench_command(cut);
    }
    PerfBenchOptions full = perf;
    full.csv = csv_for(cmd, perf.csv, PerfBenchOptions{}.csv, partial);
    return perf_bench_command(full);
}

}  // namespace

Command add_bench_command(CLI::App& app) {
    auto o = std::make_shared<BenchOptions>();
    CLI::App* cmd = app.add_subcommand("bench", "Benchmarks: print figures and write CSV (never pass/fail)");
    add_bench_options(*cmd, *o);
    return {cmd, [o, cmd] { return run_bench(*cmd, *o); }};
}

}  // namespace xcut
