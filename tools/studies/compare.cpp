#include "tools/studies/compare.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fmt/format.h>
#include <fmt/os.h>
#include <map>

#include "tools/bench/bench_cut.h"
#include "systems/kernels/element_bvh.h"
#include "engine/error.h"
#include "tools/studies/mesh_quality.h"
#include "engine/io/output.h"
#include "tools/studies/plot_script.h"
#include "engine/parallel.h"
#include "systems/kernels/mesh_measures.h"
#include "systems/pipeline.h"
#include "systems/cut/cut_system.h"
#include "systems/cut/enrichment_system.h"
#include "systems/surface/mapping_system.h"
#include "systems/cut/snap_cut_system.h"
#include "systems/tool_system.h"

namespace xcut {
namespace {

namespace fs = std::filesystem;

/// The cutters compared: XFEM on the paper's semi-progressive front, XFEM on the progressive front
/// (cutter.front, docs/xfem.md), and snapping and subdivision.
struct Variant {
    const char* label;  ///< CSV column prefix and table header
    const char* cutter;
    const char* front;
};
constexpr Variant kVariants[] = {{"xfem", "xfem", "semi"}, {"xfem_progressive", "xfem", "progressive"}, {"snap", "snap", "semi"}};
constexpr int kRuns = sizeof(kVariants) / sizeof(kVariants[0]);

Scene with_variant(Scene scene, const Variant& v) {
    scene.cutter = v.cutter;
    scene.cut_front = v.front;
    return scene;
}

int first_blade(const Scene& scene) {
    for (int i = 0; i < scene.tools.count(); ++i)
        if (scene.tools.has_blade[i]) return i;
    throw InputError(scene.file, "tools", "xcut compare needs a tool with a blade: the incision it repeats");
}

/// Tool b of `tb`, `n` times (each per-tool array repeated).
ToolBodies replicate_tool(const ToolBodies& tb, int b, int n) {
    ToolBodies out;
    auto rep = [&](auto& dst, const auto& src) {
        if (static_cast<int>(src.size()) > b) dst.assign(n, src[b]);
    };
    rep(out.name, tb.name), rep(out.trajectory, tb.trajectory), rep(out.position, tb.position);
    rep(out.orientation, tb.orientation), rep(out.has_blade, tb.has_blade), rep(out.blade_tip, tb.blade_tip);
    rep(out.blade_heel, tb.blade_heel), rep(out.shape, tb.shape), rep(out.contact_stiffness, tb.contact_stiffness);
    rep(out.contact_damping, tb.contact_damping), rep(out.velocity, tb.velocity);
    rep(out.reaction_force, tb.reaction_force), rep(out.reaction_torque, tb.reaction_torque);
    rep(out.cutting_force, tb.cutting_force), rep(out.cutting_torque, tb.cutting_torque), rep(out.blade_depth, tb.blade_depth);
    return out;
}

int dofs_of(const World& w) { return w.elements.dim * w.nodes.count(); }
int splits_of(const World& w) { return w.cuts.count() + w.snap.elements_split; }

double mean(const std::vector<double>& v) {
    double s = 0.0;
    for (double x : v) s += x;
    return v.empty() ? 0.0 : s / v.size();
}

/// One cutter over the repeated incisions, with the full pipeline (physics included).
struct Run {
    int dim = 3;
    int dofs0 = 0;
    std::vector<int> dofs_after, split_after;  ///< per incision
    std::vector<double> time, step_ms, cg;
    std::vector<int> dofs;
    std::vector<std::string> systems;
    std::vector<double> system_ms;             ///< summed over the run
    MeshQuality quality;
    double wall_s = 0.0;
};

Run run_incisions(const Incisions& inc, const Variant& variant, double threshold_deg, bool progress) {
    const Scene scene = with_variant(inc.scene, variant);
    auto sim = make_simulation(scene, /*with_output=*/false);
    World& w = sim->world;
    Run r;
    r.dofs0 = dofs_of(w);
    r.dim = w.elements.dim;
    r.systems = w.metrics.system_names;
    r.system_ms.assign(r.systems.size(), 0.0);
    ProgressBar bar(fmt::format("compare {}", variant.label), progress ? scene.steps : 0);
    size_t next = 0;
    for (int i = 0; i < scene.steps; ++i) {
        step_simulation(*sim);
        const StepMetrics& m = w.metrics.current;
        r.time.push_back(w.time), r.step_ms.push_back(m.step_ms), r.cg.push_back(m.cg_iterations);
        r.dofs.push_back(dofs_of(w));
        r.wall_s += m.step_ms * 1e-3;
        for (size_t k = 0; k < r.systems.size(); ++k) r.system_ms[k] += m.system_ms[k];
        for (; next < inc.end_time.size() && w.time >= inc.end_time[next] - 1e-9; ++next)
            r.dofs_after.push_back(dofs_of(w)), r.split_after.push_back(splits_of(w));
        bar.update(i + 1);
    }
    bar.finish();
    for (; next < inc.end_time.size(); ++next) r.dofs_after.push_back(dofs_of(w)), r.split_after.push_back(splits_of(w));
    r.quality = mesh_quality(w, threshold_deg);
    return r;
}

/// Mean, 99th percentile and maximum of `v` (all 0 when empty).
struct Spread {
    double mean = 0, p99 = 0, max = 0;
};
Spread spread(const std::vector<double>& v) {
    return {mean(v), percentile(v, 0.99), v.empty() ? 0.0 : *std::max_element(v.begin(), v.end())};
}

/// The blade's speed over the last stretch of its trajectory [m/s].
double last_speed(const std::vector<Keyframe>& keys) {
    const Keyframe &a = keys[keys.size() - 2], &b = keys.back();
    return (b.position - a.position).norm() / (b.time - a.time);
}

DelayRow delay_run(const Scene& base, int blade, const Variant& variant, double mesh_scale, double speed_factor) {
    Scene s = with_variant(base, variant);
    s.tools = replicate_tool(base.tools, blade, 1);
    for (Keyframe& k : s.tools.trajectory[0]) k.time /= speed_factor;
    if (!s.mesh.generator.empty()) {
        const int axes = s.mesh.generator == "plate" ? 2 : 3;
        for (int a = 0; a < axes; ++a)
            s.mesh.grid.cells[a] = std::max(1, static_cast<int>(std::lround(s.mesh.grid.cells[a] / mesh_scale)));
    }
    World w = build_world(s);
    if (s.visual_subdivisions >= 0) build_surface(w, w.visual, s.visual_subdivisions);
    ElementBvh bvh;
    prepare_cut_search(w, bvh);
    prepare_enrichment(w);
    if (w.snap.enabled) prepare_snap_cut(w);
    const auto& keys = s.tools.trajectory[0];
    const double dt = s.solver.dt;
    const int steps = static_cast<int>(std::ceil(keys.back().time / dt)) + 3;
    for (int i = 0; i <= steps; ++i) {
        w.time = i * dt;
        advance_tools(w, w.time);
        run_cut_system(w, bvh);
        if (w.snap.enabled) {
            apply_snap_events(w);
        } else {
            apply_cut_events(w);
            rebind_cut_vertices(w);
        }
    }
    DelayRow row;
    row.cutter = variant.label;
    row.dt = dt;
    row.mesh_scale = mesh_scale;
    row.speed_factor = speed_factor;
    row.element_size = w.cut_state.mean_edge;
    row.elements = w.mesh_elements;
    row.speed = last_speed(keys);
    const CutState& cs = w.cut_state;
    row.splits = static_cast<int>(cs.delay_sim.size());
    const Spread split = spread(cs.delay_sim);
    row.mean_s = split.mean, row.p99_s = split.p99, row.max_s = split.max;
    std::vector<double> wall_ms;
    for (double d : cs.delay_wall) wall_ms.push_back(d * 1e3);
    const Spread wall = spread(wall_ms);
    row.wall_mean_ms = wall.mean, row.wall_p99_ms = wall.p99;
    if (!w.snap.enabled) {
        row.opened = static_cast<int>(w.cuts.open_delay_sim.size());
        const Spread open = spread(w.cuts.open_delay_sim);
        row.open_mean_s = open.mean, row.open_p99_s = open.p99, row.open_max_s = open.max;
    } else {
        row.open_mean_s = row.open_p99_s = row.open_max_s = NAN;
    }
    return row;
}

/// "<label><suffix>" for every variant, comma-separated: a CSV header's columns.
std::string columns(const char* suffix) {
    std::string out;
    for (const Variant& v : kVariants) out += fmt::format("{}{}{}", out.empty() ? "" : ",", v.label, suffix);
    return out;
}

/// f(run) for every run, comma-separated.
template <class F>
std::string cells(const Run run[], F f) {
    std::string out;
    for (int c = 0; c < kRuns; ++c) out += (c ? "," : "") + f(run[c]);
    return out;
}

void write_csvs(const std::string& dir, const Incisions& inc, const Run run[], const std::vector<DelayRow>& delays) {
    auto dofs = fmt::output_file(dir + "/dofs_vs_cuts.csv");
    dofs.print("cuts,time_s,{},{},{}\n", columns("_dofs"), columns("_added"), columns("_split"));
    const auto int_cell = [](int v) { return std::to_string(v); };
    dofs.print("0,0,{},{},{}\n", cells(run, [&](const Run& r) { return int_cell(r.dofs0); }),
               cells(run, [](const Run&) { return std::string("0"); }), cells(run, [](const Run&) { return std::string("0"); }));
    for (size_t k = 0; k < inc.end_time.size(); ++k)
        dofs.print("{},{:.6g},{},{},{}\n", k + 1, inc.end_time[k], cells(run, [&](const Run& r) { return int_cell(r.dofs_after[k]); }),
                   cells(run, [&](const Run& r) { return int_cell(r.dofs_after[k] - r.dofs0); }),
                   cells(run, [&](const Run& r) { return int_cell(r.split_after[k]); }));
    auto steps = fmt::output_file(dir + "/steps.csv");
    steps.print("step,time_s,{},{},{}\n", columns("_dofs"), columns("_cg_iterations"), columns("_step_ms"));
    for (size_t i = 0; i < run[0].time.size(); ++i)
        steps.print("{},{:.6g},{},{},{}\n", i + 1, run[0].time[i], cells(run, [&](const Run& r) { return int_cell(r.dofs[i]); }),
                    cells(run, [&](const Run& r) { return fmt::format("{:g}", r.cg[i]); }),
                    cells(run, [&](const Run& r) { return fmt::format("{:.4f}", r.step_ms[i]); }));
    auto profile = fmt::output_file(dir + "/profile.csv");
    profile.print("system,{},{}\n", columns("_ms"), columns("_ms_per_step"));
    std::vector<std::string> names;
    for (int c = 0; c < kRuns; ++c)
        for (const auto& n : run[c].systems)
            if (std::find(names.begin(), names.end(), n) == names.end()) names.push_back(n);
    const double steps_run = std::max<size_t>(1, run[0].time.size());
    for (const auto& n : names) {
        const auto ms = [&](const Run& r) {
            const auto it = std::find(r.systems.begin(), r.systems.end(), n);
            return it != r.systems.end() ? r.system_ms[it - r.systems.begin()] : 0.0;
        };
        profile.print("{},{},{}\n", n, cells(run, [&](const Run& r) { return fmt::format("{:.3f}", ms(r)); }),
                      cells(run, [&](const Run& r) { return fmt::format("{:.5f}", ms(r) / steps_run); }));
    }
    auto quality = fmt::output_file(dir + "/quality.csv");
    quality.print("cutter,elements,min_angle_deg,min_volume_m3,min_effective_volume_m3,below_threshold\n");
    for (int c = 0; c < kRuns; ++c) {
        const MeshQuality& q = run[c].quality;
        quality.print("{},{},{:.6g},{:.6g},{:.6g},{}\n", kVariants[c].label, q.elements, q.min_angle_deg, q.min_volume,
                      q.min_effective_volume, q.below_threshold);
    }
    auto delay = fmt::output_file(dir + "/crossing_delay.csv");
    delay.print("cutter,mesh_scale,elements,element_size_m,speed_m_s,dt_s,splits,delay_mean_s,delay_p99_s,delay_max_s,delay_wall_mean_ms,"
                "delay_wall_p99_ms,opened,open_delay_mean_s,open_delay_p99_s,open_delay_max_s\n");
    for (const DelayRow& d : delays)
        delay.print("{},{},{},{:.6g},{:.6g},{:g},{},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{},{:.6g},{:.6g},{:.6g}\n", d.cutter,
                    d.mesh_scale, d.elements, d.element_size, d.speed, d.dt, d.splits, d.mean_s, d.p99_s, d.max_s, d.wall_mean_ms, d.wall_p99_ms,
                    d.opened, d.open_mean_s, d.open_p99_s, d.open_max_s);
}

}  // namespace

Incisions repeated_incisions(const Scene& scene, int cuts, double spacing) {
    const int b = first_blade(scene);
    const auto& keys = scene.tools.trajectory[b];
    const Vec3 path = keys.back().position - keys.front().position;
    const Vec3 edge = keys.front().orientation * (scene.tools.blade_heel[b] - scene.tools.blade_tip[b]);
    const Vec3 across = path.cross(edge);
    if (!(across.norm() > 0.0))
        throw InputError(scene.file, "tools", "the blade's path must not be along its edge: no sideways direction");
    const Vec3 side = across.normalized(), up = edge.normalized();
    const World body = build_world(scene);
    Incisions out;
    out.spacing = spacing;
    if (!(spacing > 0.0)) {
        double lo = 1e300, hi = -1e300;
        for (const Vec3& X : body.nodes.rest) lo = std::min(lo, X.dot(side)), hi = std::max(hi, X.dot(side));
        out.spacing = std::min(1.25 * mean_edge_length(body.elements, body.nodes.rest, body.mesh_elements), 0.9 * (hi - lo) / cuts);
    }
    // Depth of the body's top (along the blade edge) under an incision offset by o: the highest node
    // within half a spacing of the offset path, between the path's ends.
    const double c0 = keys.front().position.dot(side), a0 = keys.front().position.dot(path.normalized()),
                 a1 = keys.back().position.dot(path.normalized());
    auto top = [&](double o) {
        double t = -1e300;
        for (const Vec3& X : body.nodes.rest) {
            const double along = X.dot(path.normalized());
            if (std::abs(X.dot(side) - c0 - o) <= 0.5 * out.spacing && along >= std::min(a0, a1) && along <= std::max(a0, a1))
                t = std::max(t, X.dot(up));
        }
        return t;
    };
    const double top0 = top(0.0);
    const double slot = keys.back().time - keys.front().time;
    out.scene = scene;
    out.scene.tools = replicate_tool(scene.tools, b, cuts);
    for (int k = 0; k < cuts; ++k) {
        const double o = out.spacing * ((k + 1) / 2) * (k % 2 == 1 ? 1.0 : -1.0);
        const double t = top(o), lift = t > -1e299 && top0 > -1e299 ? t - top0 : 0.0;
        out.scene.tools.name[k] = fmt::format("{}_{}", scene.tools.name[b], k);
        for (Keyframe& key : out.scene.tools.trajectory[k]) {
            key.time += k * slot;
            key.position += o * side + lift * up;
        }
        out.scene.tools.position[k] = out.scene.tools.trajectory[k].front().position;
        out.end_time.push_back(keys.back().time + k * slot + 2.0 * scene.solver.dt);
    }
    const double tail = std::max(scene.steps * scene.solver.dt - keys.back().time, 3.0 * scene.solver.dt);
    out.scene.steps = static_cast<int>(std::ceil((keys.back().time + (cuts - 1) * slot + tail) / scene.solver.dt - 1e-9));
    return out;
}

std::vector<DelayRow> crossing_delay_sweep(const Scene& scene, bool progress) {
    const int blade = first_blade(scene);
    const double own = last_speed(scene.tools.trajectory[blade]);
    const std::vector<double> scales = scene.mesh.generator.empty() ? std::vector<double>{1.0}
                                                                    : std::vector<double>{1.5, 1.0, 0.75};
    std::vector<double> factors = {1.0};  // the scene's own speed, then 10 ... 200 mm/s
    if (own > 0.0)
        for (double v : kDelaySweepSpeeds) factors.push_back(v / own);
    std::vector<DelayRow> delays;
    ProgressBar bar("crossing delay", progress ? static_cast<int>(scales.size() * factors.size() * kRuns) : 0);
    for (double m : scales)
        for (double f : factors)
            for (const Variant& v : kVariants) {
                delays.push_back(delay_run(scene, blade, v, m, f));
                bar.update(static_cast<int>(delays.size()));
            }
    bar.finish();
    return delays;
}

namespace {

/// The crossing-delay table: per speed on the scene's mesh, each XFEM front's split and opening
/// delay in steps (max over the elements), and the target's verdict (opening within one step).
void print_delay_table(const std::vector<DelayRow>& delays) {
    fmt::print("\ncrossing delay on the scene's mesh, in steps (max over elements; mean in brackets)\n");
    fmt::print("  {:>10}  {:>22}{:>22}  {:>22}{:>22}\n", "speed mm/s", "semi: split", "semi: opening", "progressive: split",
               "progressive: opening");
    const auto steps = [](double max_s, double mean_s, double dt) {
        return std::isnan(max_s) ? std::string("-") : fmt::format("{:.1f} ({:.2f})", max_s / dt, mean_s / dt);
    };
    for (const DelayRow& semi : delays) {
        if (semi.cutter != "xfem" || semi.mesh_scale != 1.0) continue;
        const DelayRow* prog = nullptr;
        for (const DelayRow& d : delays)
            if (d.cutter == "xfem_progressive" && d.mesh_scale == 1.0 && d.speed_factor == semi.speed_factor) prog = &d;
        if (!prog) continue;
        fmt::print("  {:>10.3g}  {:>22}{:>22}  {:>22}{:>22}\n", semi.speed * 1e3, steps(semi.max_s, semi.mean_s, semi.dt),
                   steps(semi.open_max_s, semi.open_mean_s, semi.dt), steps(prog->max_s, prog->mean_s, prog->dt),
                   steps(prog->open_max_s, prog->open_mean_s, prog->dt));
    }
    // The verdict over every mesh and speed; the worst element and the 99th percentile named.
    int met = 0, rows = 0;
    double worst = 0.0, worst_p99 = 0.0;
    for (const DelayRow& d : delays) {
        if (d.cutter != "xfem_progressive") continue;
        ++rows;
        met += d.open_max_s <= d.dt * (1.0 + 1e-9);
        worst = std::max(worst, d.open_max_s / d.dt);
        worst_p99 = std::max(worst_p99, d.open_p99_s / d.dt);
    }
    fmt::print("  target: the wound opens within one step of the blade entering an element (progressive): met at {} of {} "
               "(mesh, speed); worst element {:.0f} steps, 99th percentile {:.0f}\n",
               met, rows, worst, worst_p99);
}

}  // namespace

int compare_command(const CompareOptions& o) {
    set_thread_count(o.threads);
    const Scene scene = load_scene(o.scene, o.overrides);
    const Incisions inc = repeated_incisions(scene, o.cuts, o.spacing);
    const std::string dir = o.output.empty() ? "out/" + scene.name + "/compare" : o.output;
    fs::create_directories(dir);
    fmt::print("compare {}: {} incisions {:.3g} mm apart, {} steps of {} s, {} threads; xfem (semi-progressive), xfem "
               "(progressive), snap (threshold {})\n",
               scene.name, o.cuts, inc.spacing * 1e3, inc.scene.steps, scene.solver.dt, configured_thread_count(), scene.snap_threshold);
    Run run[kRuns];
    for (int c = 0; c < kRuns; ++c) run[c] = run_incisions(inc, kVariants[c], o.quality_threshold_deg, !o.quiet);
    const std::vector<DelayRow> delays = o.delay_sweep ? crossing_delay_sweep(scene, !o.quiet) : std::vector<DelayRow>{};
    write_csvs(dir, inc, run, delays);

    // The one-screen table.
    const int n = o.cuts, snap = kRuns - 1;
    double added[kRuns];
    for (int c = 0; c < kRuns; ++c) added[c] = run[c].dofs_after.back() - run[c].dofs0;
    const auto row = [&](const std::string& label, auto cell, std::string ratio = "") {
        fmt::print("  {:<34}", label);
        for (int c = 0; c < kRuns; ++c) fmt::print("{:>18}", cell(run[c]));
        fmt::print("{:>12}\n", ratio);
    };
    const auto num = [](double v) { return fmt::format("{:.4g}", v); };
    const auto ratio = [](double a, double b) { return b != 0.0 ? fmt::format("{:.3f}", a / b) : std::string("-"); };
    fmt::print("\n{} ({}D): XFEM against snapping and subdivision, {} incisions\n  {:<34}", scene.name, run[0].dim, n, "");
    for (const Variant& v : kVariants) fmt::print("{:>18}", v.label);
    fmt::print("{:>12}\n", "xfem/snap");
    row("DOFs before cutting", [&](const Run& r) { return num(r.dofs0); });
    row(fmt::format("DOFs after {} cuts", n), [&](const Run& r) { return num(r.dofs_after.back()); },
        ratio(run[0].dofs_after.back(), run[snap].dofs_after.back()));
    row(fmt::format("DOFs added by {} cuts", n), [&](const Run& r) { return num(r.dofs_after.back() - r.dofs0); },
        ratio(added[0], added[snap]));
    row("elements split", [&](const Run& r) { return num(r.split_after.back()); });
    row(fmt::format("min {} angle [deg]", run[0].dim == 2 ? "triangle" : "dihedral"),
        [](const Run& r) { return fmt::format("{:.2f}", r.quality.min_angle_deg); });
    row(fmt::format("elements below {:g} deg", o.quality_threshold_deg), [&](const Run& r) { return num(r.quality.below_threshold); });
    row("min element volume [m^3]", [](const Run& r) { return fmt::format("{:.3e}", r.quality.min_volume); });
    row("min effective volume V*w [m^3]", [](const Run& r) { return fmt::format("{:.3e}", r.quality.min_effective_volume); });
    row("step time mean [ms]", [](const Run& r) { return fmt::format("{:.2f}", mean(r.step_ms)); },
        ratio(mean(run[0].step_ms), mean(run[snap].step_ms)));
    row("step time p99 [ms]", [](const Run& r) { return fmt::format("{:.2f}", percentile(r.step_ms, 0.99)); },
        ratio(percentile(run[0].step_ms, 0.99), percentile(run[snap].step_ms, 0.99)));
    row("CG iterations per step, mean", [](const Run& r) { return fmt::format("{:.1f}", mean(r.cg)); });
    fmt::print("  target: xfem/snap DOFs added <= 0.5 after 20 cuts\n");
    if (!delays.empty()) print_delay_table(delays);
    auto summary = fmt::output_file(dir + "/summary.csv");
    summary.print("cutter,cuts,dofs_before,dofs_after,dofs_added,elements_split,min_angle_deg,below_threshold,min_volume_m3,"
                  "min_effective_volume_m3,step_ms_mean,step_ms_p99,cg_mean,wall_s\n");
    for (int c = 0; c < kRuns; ++c)
        summary.print("{},{},{},{},{},{},{:.6g},{},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g}\n", kVariants[c].label, n, run[c].dofs0,
                      run[c].dofs_after.back(), added[c], run[c].split_after.back(), run[c].quality.min_angle_deg,
                      run[c].quality.below_threshold, run[c].quality.min_volume, run[c].quality.min_effective_volume,
                      mean(run[c].step_ms), percentile(run[c].step_ms, 0.99), mean(run[c].cg), run[c].wall_s);
    summary.close();
    fmt::print("csv: {}/{{dofs_vs_cuts,steps,profile,quality,crossing_delay,summary}}.csv\n", dir);

    if (o.plots) run_plot_script("plot_compare.py", fmt::format("'{}'", dir));
    return 0;
}

}  // namespace xcut
