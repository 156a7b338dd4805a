#!/usr/bin/env python3
"""Regenerates the tables and plots of docs/BENCHMARKS.md from the CSVs in results/.

Every `xcut bench --suite S` writes results/bench_S.csv (the perf suite also results/bench_perf_*.csv).
For each suite this script replaces the text between `<!-- generated: S -->` and `<!-- end -->` in
the document and writes its plots (PNG) into docs/benchmarks/; the hand-written text around the
markers is kept. A suite whose CSV is missing is skipped with a note and its section left as it
is; a CSV of a suite the document has no markers for gets a new section at the end.

Usage: python3 tools/report/benchmarks_report.py [--results results] [--doc docs/BENCHMARKS.md]
                                          [--plots docs/benchmarks] [--no-plots]
"""
import argparse
import csv
import math
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # tools/report/ -> the project


def import_pyplot():
    """matplotlib.pyplot, or None. Debian's python3-matplotlib belongs to /usr/bin/python3: a python3
    earlier on PATH (a virtual environment) may lack it, so the script re-runs itself there."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        return plt
    except ImportError:
        system = "/usr/bin/python3"
        if os.path.exists(system) and os.path.realpath(sys.executable) != os.path.realpath(system):
            os.execv(system, [system] + sys.argv)
        return None


# ---------------------------------------------------------------- reading and formatting


def read_csv(path):
    """(rows as dicts with numbers converted, comment lines without their '#')."""
    with open(path, newline="") as f:
        lines = f.read().splitlines()
    comments = [l[1:].strip() for l in lines if l.startswith("#")]
    rows = list(csv.DictReader(l for l in lines if l and not l.startswith("#")))
    for r in rows:
        for k, v in r.items():
            try:
                r[k] = int(v)
            except (TypeError, ValueError):
                try:
                    r[k] = float(v)
                except (TypeError, ValueError):
                    pass
    return rows, comments


def num(v, digits=3):
    """A figure for a table: integers with thin grouping, others to about `digits` significant digits."""
    if isinstance(v, int):
        return f"{v:,}".replace(",", " ")
    if not isinstance(v, float):
        return str(v)
    if not math.isfinite(v):
        return str(v)
    if v == 0:
        return "0"
    decimals = max(0, digits - 1 - int(math.floor(math.log10(abs(v)))))
    return f"{v:.{decimals}f}"


def table(header, rows, align=None):
    align = align or ["---:"] * len(header)
    out = ["| " + " | ".join(header) + " |", "|" + "|".join(align) + "|"]
    out += ["| " + " | ".join(num(c) if not isinstance(c, str) else c for c in r) + " |" for r in rows]
    return "\n".join(out)


def generic_table(rows):
    keys = list(rows[0].keys())
    return table(keys, [[r[k] for k in keys] for r in rows],
                 ["---" if isinstance(rows[0][k], str) else "---:" for k in keys])


def nearest(rows, tets, **where):
    """The row whose tets is closest to `tets` among those matching `where`."""
    pool = [r for r in rows if all(r.get(k) == v for k, v in where.items())]
    return min(pool, key=lambda r: abs(math.log(r["tets"] / tets))) if pool else None


def verdict(value, target, higher_is_better=True):
    ok = value >= target if higher_is_better else value <= target
    if ok:
        return "**met**"
    ratio = target / value if higher_is_better else value / target
    return f"**missed** ({ratio:.1f}x short)" if higher_is_better else f"**missed** ({ratio:.1f}x over)"


# ---------------------------------------------------------------- the perf suite


def perf_targets(steps, kernel, cut):
    lines = []
    r50, r2 = nearest(steps, 50000, threads=2), nearest(steps, 2000, threads=2)
    if r50:
        lines.append(["≥ 60 steps/s at 50k tets, 2 threads", f"{num(r50['steps_per_s'])} at {num(r50['tets'])}",
                      verdict(r50["steps_per_s"], 60)])
    if r2:
        lines.append(["≥ 1000 steps/s at 2k tets, 2 threads", f"{num(r2['steps_per_s'])} at {num(r2['tets'])}",
                      verdict(r2["steps_per_s"], 1000)])
    if r50:
        best = max((r for r in steps if r["threads"] == 2), key=lambda r: r["speedup"])
        lines.append(["≥ 1.8× from 1 to 2 threads", f"{num(r50['speedup'])}× at {num(r50['tets'])} "
                      f"(best {num(best['speedup'])}× at {num(best['tets'])})", verdict(r50["speedup"], 1.8)])
    worst = max(steps, key=lambda r: r["bytes_per_tet_components"])
    lines.append(["≤ 400 bytes per tet (component arrays)", f"{num(worst['bytes_per_tet_components'])} at most "
                  f"(at {num(worst['tets'])})", verdict(worst["bytes_per_tet_components"], 400, higher_is_better=False)])
    if cut:
        c50 = nearest(cut, 50000)
        lines.append(["≤ 1 ms p99 cut update at 50k tets", f"{num(c50['update_p99_ms'])} ms at {num(c50['tets'])}",
                      verdict(c50["update_p99_ms"], 1.0, higher_is_better=False)])
    kernel = [k for k in kernel if k["kernel"] == "force"]
    if kernel:
        k50 = nearest(kernel, 50000, threads=2) or kernel[-1]
        lines.append(["force kernel ≥ 50 % of its roofline bound",
                      f"{100 * k50['fraction_of_bound']:.0f} % at {num(k50['tets'])}, 2 threads ({k50['bound']}-bound)",
                      verdict(k50["fraction_of_bound"], 0.5)])
    return table(["target", "measured", ""], lines, ["---", "---", "---"])


def perf_section(d, plt, plots):
    steps, _ = read_csv(os.path.join(d, "bench_perf.csv"))
    part = {}
    for name in ("systems", "roofline", "kernel", "cut", "skip"):
        p = os.path.join(d, f"bench_perf_{name}.csv")
        part[name] = read_csv(p)[0] if os.path.exists(p) else []
    loads = [r["load_average"] for r in steps if "load_average" in r]
    noise = []
    # The load average counts this suite's own threads: more than one beyond them is other work.
    if any(r["load_average"] > r["threads"] + 1 for r in steps if "load_average" in r):
        noise = [f"**Noisy:** the machine's load average was {num(min(loads))}–{num(max(loads))} during these runs "
                 "(this suite's own threads count 1–2 on 2 cores): other work shared the cores.", ""]
    out = noise + ["### Targets", "", perf_targets(steps, part["kernel"], part["cut"]), "",
           "### Steps per second against mesh size", "",
           table(["tets", "nodes", "threads", "steps/s", "ms/step", "CG it./step", "force ms", "solver ms",
                  "B/tet (components)", "B/tet (peak RSS)", "speed-up"],
                 [[r["tets"], r["nodes"], r["threads"], r["steps_per_s"], r["ms_per_step"], r["cg_iter_per_step"],
                   r["force_ms"], r["solver_ms"], r["bytes_per_tet_components"], r["bytes_per_tet_rss"],
                   r["speedup"]] for r in steps]), ""]
    if part["systems"]:
        names = list(dict.fromkeys(r["system"] for r in part["systems"]))
        keyed = {}
        for r in part["systems"]:
            keyed.setdefault((r["tets"], r["threads"]), {})[r["system"]] = r
        rows = [[t, th] + [f"{num(v[n]['ms_per_step'])} ({100 * v[n]['share_of_step']:.0f} %)" if n in v else "–"
                           for n in names] for (t, th), v in keyed.items()]
        out += ["### Time per system (ms per step, share of the step)", "",
                table(["tets", "threads"] + [n.replace("System", "") for n in names], rows), ""]
    if part["roofline"]:
        isa = part["roofline"][0]["vector_isa"]
        out += ["### Roofline of this machine, measured by `xcut bench`", "",
                f"Triad over 3 × {num(part['roofline'][0]['triad_mib'] / 3)} MiB; multiply-add chains as this build "
                f"compiles them ({isa}), and the same chains with AVX2 + FMA for reference.", "",
                table(["threads", "triad GB/s", "peak GFLOP/s (as built)", "peak GFLOP/s (AVX2 + FMA)"],
                      [[r["threads"], r["triad_gbs"], r["peak_gflops"], r["fma_gflops"]] for r in part["roofline"]]),
                ""]
    if part["kernel"]:
        out += ["### Kernels against the roofline", "",
                "`force`: the ForceSystem, per step; `cg_product`: the CG's matrix-free product K p, per iteration.", "",
                table(["kernel", "tets", "threads (used)", "ms", "Newton it.", "flop/tet", "B/tet", "flop/B", "GFLOP/s", "GB/s",
                       "bound GFLOP/s", "bound by", "achieved"],
                      [[r["kernel"], r["tets"], f"{r['threads']} ({r['kernel_threads']})", r["ms"],
                        r["newton_iterations"] or "–", r["flops_per_element"],
                        r["bytes_per_element"], r["intensity"], r["achieved_gflops"], r["achieved_gbs"],
                        r["bound_gflops"], r["bound"], f"{100 * r['fraction_of_bound']:.1f} %"]
                       for r in part["kernel"]], ["---"] + ["---:"] * 12), ""]
    if part["cut"]:
        out += ["### Cut update against mesh size (neighbourhood search)", "",
                table(["tets", "quads", "splits", "quad p50 ms", "quad p99 ms", "update p50 ms", "update p99 ms"],
                      [[r["tets"], r["quads"], r["splits"], r["quad_p50_ms"], r["quad_p99_ms"], r["update_p50_ms"],
                        r["update_p99_ms"]] for r in part["cut"]]), ""]
    if part["skip"]:
        out += skip_table(part["skip"])
    if plt and plots:
        out += perf_plots(plt, plots, steps, part)
    else:
        out += existing_plots(plots, PERF_PLOTS)
    return "\n".join(out).rstrip()


PERF_PLOTS = {"perf_steps.png": "steps per second against mesh size",
              "perf_systems.png": "share of the step per system",
              "perf_roofline.png": "kernels on the roofline"}


def existing_plots(plots, captions):
    """Links to plots made earlier, when this run makes none (no matplotlib, or --no-plots)."""
    rel = os.path.relpath(plots, os.path.dirname(ARGS.doc))
    found = [f"![{c}]({rel}/{n})\n" for n, c in captions.items() if os.path.exists(os.path.join(plots, n))]
    return ["### Plots", ""] + found if found else []


def skip_table(rows):
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    systems = list(dict.fromkeys(r["system"] for r in rows))
    cell = {(r["scene"], r["system"]): r for r in rows}

    def show(r):
        return f"{num(r['ms_per_step'])} ({r['calls']} calls)" if r["scheduled"] else \
            f"skipped: {r['calls']} calls, {num(r['ms_per_step'])} ms"

    body = [[s] + [show(cell[(sc, s)]) for sc in scenes] for s in systems]
    body.append(["whole step"] + [num(next(r["step_ms"] for r in rows if r["scene"] == sc)) for sc in scenes])
    return ["### Skip what the scene doesn't need (ms per step)", "",
            table(["system"] + [f"{sc} tools and surfaces" for sc in scenes], body, ["---"] + ["---:"] * len(scenes)),
            ""]


def perf_plots(plt, plots, steps, part):
    os.makedirs(plots, exist_ok=True)
    rel = os.path.relpath(plots, os.path.dirname(ARGS.doc))
    images = []
    fig, ax = plt.subplots(figsize=(6, 4))
    for th in sorted({r["threads"] for r in steps}):
        rs = [r for r in steps if r["threads"] == th]
        ax.loglog([r["tets"] for r in rs], [r["steps_per_s"] for r in rs], "o-", label=f"{th} thread(s)")
    ax.plot([50000], [60], "k*", markersize=10, label="targets")
    ax.plot([2000], [1000], "k*", markersize=10)
    ax.set_xlabel("tetrahedra")
    ax.set_ylabel("steps/s")
    ax.grid(alpha=0.3, which="both")
    ax.legend()
    images.append(save(fig, plots, "perf_steps.png", rel, PERF_PLOTS["perf_steps.png"]))
    if part["systems"]:
        rows = [r for r in part["systems"] if r["threads"] == max(x["threads"] for x in part["systems"])]
        sizes = sorted({r["tets"] for r in rows})
        names = list(dict.fromkeys(r["system"] for r in rows))
        fig, ax = plt.subplots(figsize=(6, 4))
        bottom = [0.0] * len(sizes)
        for n in names:
            share = [next((100 * r["share_of_step"] for r in rows if r["tets"] == t and r["system"] == n), 0.0)
                     for t in sizes]
            ax.bar([num(t) for t in sizes], share, bottom=bottom, label=n)
            bottom = [b + s for b, s in zip(bottom, share)]
        ax.set_xlabel("tetrahedra")
        ax.set_ylabel("% of the step")
        ax.legend(fontsize=7)
        images.append(save(fig, plots, "perf_systems.png", rel, PERF_PLOTS["perf_systems.png"]))
    if part["roofline"] and part["kernel"]:
        fig, ax = plt.subplots(figsize=(6, 4))
        ai = [10 ** (x / 20) for x in range(-40, 41)]
        for p in part["roofline"]:
            ax.loglog(ai, [min(p["peak_gflops"], a * p["triad_gbs"]) for a in ai], label=f"roofline, {p['threads']} thr.")
        for k in part["kernel"]:
            ax.plot(k["intensity"], k["achieved_gflops"], "o" if k["kernel_threads"] == 1 else "s",
                    color="k" if k["kernel"] == "force" else "tab:red", alpha=0.5)
        ax.set_xlabel("arithmetic intensity [flop/byte]")
        ax.set_ylabel("GFLOP/s")
        ax.set_title("black: ForceSystem, red: CG product K p (circles 1 thread, squares 2)", fontsize=9)
        ax.grid(alpha=0.3, which="both")
        ax.legend()
        images.append(save(fig, plots, "perf_roofline.png", rel, PERF_PLOTS["perf_roofline.png"]))
    return ["### Plots", ""] + images


def save(fig, plots, name, rel, caption):
    fig.tight_layout()
    fig.savefig(os.path.join(plots, name), dpi=110)
    return f"![{caption}]({rel}/{name})\n"


# ---------------------------------------------------------------- other suites


def cut_section(d, plt, plots):
    rows, _ = read_csv(os.path.join(d, "bench_cut.csv"))
    return table(["search", "tets", "quads", "splits", "cut again", "quad p50 ms", "quad p99 ms", "update p50 ms",
                  "update p99 ms", "delay p50 s", "delay p99 s", "update max ms", "its cutter ms", "its enrichment ms"],
                 [[r["search"], r["tets"], r["quads"], r["splits"], r.get("cut_again", "–"), r["quad_p50_ms"],
                   r["quad_p99_ms"], r["update_p50_ms"], r["update_p99_ms"], r["delay_p50_s"], r["delay_p99_s"],
                   r.get("update_max_ms", "–"), r.get("worst_cutter_ms", "–"), r.get("worst_enrichment_ms", "–")]
                  for r in rows],
                 ["---"] + ["---:"] * 13)


def accuracy_section(d, plt, plots):
    """docs/verification.md problems 3, 5, 6: one table per problem (the cutters side by side per resolution), the
    suite's verdicts (its CSV's comment lines) and one error-against-run-time plot per problem."""
    rows, comments = read_csv(os.path.join(d, "bench_accuracy.csv"))
    names = {3: "Problem 3 — cantilever under its own weight (no cut: one series)",
             5: "Problem 5 — partial cut, pulled apart",
             6: "Problem 6 — edge-cracked plate, CMOD"}
    out = []
    for problem in sorted({r["problem"] for r in rows}):
        sel = [r for r in rows if r["problem"] == problem]
        cutters = list(dict.fromkeys(r["cutter"] for r in sel))
        header = ["level", "h mm"]
        for c in cutters:
            header += [f"{c} DOFs", f"{c} run s", f"{c} CPU s", f"{c} error %"]
        body = []
        for level in sorted({r["resolution"] for r in sel}):
            at = {r["cutter"]: r for r in sel if r["resolution"] == level}
            line = [level, 1e3 * next(iter(at.values()))["element_size_m"]]
            for c in cutters:
                r = at.get(c)
                line += [r["dofs"], r["run_time_s"], r.get("cpu_time_s", "–"), 100 * r["error"]] if r else ["–"] * 4
            body.append(line)
        out += [f"### {names.get(problem, f'Problem {problem}')}", "", table(header, body), ""]
    out += [f"- {c}" for c in comments] + [""]
    if plt and plots:
        sys.path.insert(0, os.path.join(ROOT, "tools"))
        import plot_accuracy

        os.makedirs(plots, exist_ok=True)
        rel = os.path.relpath(plots, os.path.dirname(ARGS.doc))
        out += ["### Error against CPU time", ""]
        out += [f"![problem {p}: error against CPU time]({rel}/{name})\n" for p, name in plot_accuracy.plot(
            plt, rows, plots, plot_accuracy.bands(os.path.join(d, "bench_accuracy.csv")))]
    elif plots:  # no new plots (--no-plots, no matplotlib): the ones already drawn stay linked
        rel = os.path.relpath(plots, os.path.dirname(ARGS.doc))
        drawn = [(p, f"accuracy_problem{p}.png") for p in sorted({r["problem"] for r in rows})]
        drawn = [(p, name) for p, name in drawn if os.path.exists(os.path.join(plots, name))]
        if drawn:
            out += ["### Error against CPU time", ""]
            out += [f"![problem {p}: error against CPU time]({rel}/{name})\n" for p, name in drawn]
    return "\n".join(out).rstrip()


def stress_section(d, plt, plots, csv="bench_stress.csv"):
    """docs/verification.md problems 7-9 (`xcut stress`): one line per problem from the per-case CSV, the figures
    the command's own summary prints (bounds as in tools/studies/stress.h: CG 400 per solve, energy per case).
    `xcut stress --front progressive` writes bench_stress_progressive.csv, rendered the same way."""
    rows, _ = read_csv(os.path.join(d, csv))
    body = []
    for problem in dict.fromkeys(r["problem"] for r in rows):
        sel = [r for r in rows if r["problem"] == problem]
        runs = lambda key: sum(1 for r in sel if r[key] > 0)
        bounds = sorted({float(r.get("energy_bound", 1.01)) for r in sel})
        body.append([problem, len(sel), sum(1 for r in sel if r["nan"] > 0), max(r["max_cg"] for r in sel),
                     sum(1 for r in sel if r["max_cg"] > 400), max(float(r["energy_ratio"]) for r in sel),
                     " / ".join(f"{b:g}" for b in bounds),
                     sum(1 for r in sel if r["energy_ratio"] > float(r.get("energy_bound", 1.01))),
                     sum(r["lost_vertices"] for r in sel),
                     f"{sum(r['open_edges'] for r in sel)} ({runs('open_edges')})",
                     f"{sum(r['pinched_edges'] for r in sel)} ({runs('pinched_edges')})",
                     sum(r.get("zero_area_triangles", 0) for r in sel)])
    return table(["problem", "cases", "NaN", "max CG", "CG > 400", "max E / work", "E / work bound", "over bound",
                  "lost vertices", "open edges (runs)", "pinched edges (runs)", "zero-area triangles"],
                 body, ["---"] + ["---:"] * 11)


def solver_section(d, plt, plots):
    """`xcut bench --suite solver`: each linear method per case, its speed-up against jacobi measured in the
    same run, and the loaded rows (another process busy on one core, 1 and 2 threads)."""
    rows, _ = read_csv(os.path.join(d, "bench_solver.csv"))
    body = []
    for r in rows:
        failed = str(r["failure"])
        step = re.search(r"step (\d+)", failed)
        spread = (f"{num(r['slowest_steps_per_s'])}-{num(r['fastest_steps_per_s'])}"
                  if r.get("repeats", 1) not in (1, "", None) else "")
        body.append([r["case"], r["method"], r["threads"], r["tets"], num(r["steps_per_s"]), spread, num(r["cg_per_step"]),
                     f"{float(r['max_residual']):.1e}", r["refactored_steps"], r["substepped_steps"],
                     num(r["factor_bytes_per_tet"]), num(r["rss_bytes_per_tet"]),
                     f"{float(r['speedup_vs_jacobi']):.2f}x" if float(r["speedup_vs_jacobi"]) > 0 else "-",
                     num(r.get("load_setup_ms", 0)),
                     f"stopped at step {step.group(1)}" if failed and step else ("stopped" if failed else "")])
    return table(["case", "method", "threads", "tets", "steps/s (median)", "range of 3", "CG / step", "max residual",
                  "renewed", "substepped", "L bytes / tet", "RSS bytes / tet", "vs jacobi", "setup at load ms", "run"],
                 body, ["---", "---", "---:", "---:", "---:", "---:", "---:", "---:", "---:", "---:", "---:", "---:",
                        "---:", "---:", "---"])


def generic_section(name):
    def render(d, plt, plots):
        rows, comments = read_csv(os.path.join(d, f"bench_{name}.csv"))
        out = [generic_table(rows)] if rows else ["(no rows)"]
        out += ["", *[f"- {c}" for c in comments]] if comments else []
        return "\n".join(out)

    return render


SUITES = {"perf": perf_section, "cut": cut_section, "accuracy": accuracy_section, "stress": stress_section,
          "stress_progressive": lambda d, plt, plots: stress_section(d, plt, plots, "bench_stress_progressive.csv"),
          "stress_blades": lambda d, plt, plots: stress_section(d, plt, plots, "bench_stress_blades.csv"),
          "stress_tip": lambda d, plt, plots: stress_section(d, plt, plots, "bench_stress_tip.csv"),
          "stress_fronts": lambda d, plt, plots: stress_section(d, plt, plots, "bench_stress_fronts.csv"),
          "solver": solver_section}


def render_suite(name, d, plt, plots):
    return (SUITES.get(name) or generic_section(name))(d, plt, plots)


# ---------------------------------------------------------------- the document


def splice(doc, name, body, source):
    begin, end = f"<!-- generated: {name} -->", "<!-- end -->"
    block = f"{begin}\n_Generated by `python3 tools/report/benchmarks_report.py` from {source}; edits between these " \
            f"markers are overwritten._\n\n{body}\n{end}"
    pattern = re.compile(re.escape(begin) + r".*?" + re.escape(end), re.S)
    if pattern.search(doc):
        return pattern.sub(lambda _: block, doc, count=1)
    return doc.rstrip() + f"\n\n## `xcut bench --suite {name}`\n\n{block}\n"


def suites_in(d):
    found = set()
    for f in os.listdir(d) if os.path.isdir(d) else []:
        m = re.fullmatch(r"bench_([a-z0-9_]+)\.csv", f)
        if m:
            found.add(m.group(1))
    return found


def main():
    doc = open(ARGS.doc).read()
    plt = None if ARGS.no_plots else import_pyplot()
    if plt is None and not ARGS.no_plots:
        print("note: no matplotlib: tables only, plots left as they are")
    marked = re.findall(r"<!-- generated: ([a-z0-9_]+) -->", doc)
    present = suites_in(ARGS.results)
    # A suite is a marked section, or a CSV bench_<name>.csv whose name has no "_" (bench_perf_cut.csv,
    # bench_solver_quick.csv are a suite's other tables and quick runs, not suites of their own).
    for name in list(dict.fromkeys(marked + sorted(n for n in present if "_" not in n))):
        if name not in present:
            print(f"skipped {name}: no {ARGS.results}/bench_{name}.csv (run `xcut bench --suite {name}`); "
                  "its section is left as it is")
            continue
        body = render_suite(name, ARGS.results, plt, ARGS.plots)
        source = f"`{os.path.relpath(ARGS.results, ROOT)}/bench_{name}*.csv`"
        doc = splice(doc, name, body, source)
        print(f"regenerated {name}")
    with open(ARGS.doc, "w") as f:
        f.write(doc)


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--results", default=os.path.join(ROOT, "results"))
    p.add_argument("--doc", default=os.path.join(ROOT, "docs", "BENCHMARKS.md"))
    p.add_argument("--plots", default=os.path.join(ROOT, "docs", "benchmarks"))
    p.add_argument("--no-plots", action="store_true")
    return p.parse_args()


if __name__ == "__main__":
    ARGS = parse_args()
    main()
