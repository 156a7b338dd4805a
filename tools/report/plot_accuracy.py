#!/usr/bin/env python3
"""Plots of `xcut bench --suite accuracy` (docs/BENCHMARKS.md) from its CSV: one PNG per
docs/verification.md problem, relative error against CPU time (cut + static solve), log-log, every
cutter of that problem on one plot, each point labelled with its resolution, and the reference's own
error estimate as a grey band (errors inside it are not resolved). Comment lines ("# ...", the
suite's verdicts) give the band and are otherwise skipped. tools/report/benchmarks_report.py calls
plot() for the document.

Usage: python3 tools/report/plot_accuracy.py CSV OUTDIR   (writes OUTDIR/accuracy_problem<k>.png)
"""
import csv
import re
import os
import sys

STYLE = {"xfem": ("tab:blue", "o-"), "xfem_tip": ("tab:green", "D-"), "snap": ("tab:red", "s--"),
         "xfem-quadratic": ("tab:purple", "v-"), "uncut": ("tab:gray", "^-")}
TITLES = {
    "3": "Problem 3: cantilever under its own weight (no cut)",
    "5": "Problem 5: partial cut, pulled apart",
    "6": "Problem 6: edge-cracked plate, CMOD",
}
BAND = re.compile(r"problem (\d+) reference: (.*?) at levels .*its own error estimate ([0-9.eE+-]+) %")


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(l for l in f if l.strip() and not l.startswith("#")))


def bands(path):
    """{problem: (solver, error estimate in %)} from the suite's reference lines."""
    out = {}
    with open(path) as f:
        for line in f:
            m = BAND.search(line) if line.startswith("#") else None
            if m:
                out[m.group(1)] = (m.group(2), float(m.group(3)))
    return out


def plot(plt, rows, outdir, band=None):
    """One PNG per problem into outdir; returns [(problem, file name)]."""
    written = []
    for problem in sorted({str(r["problem"]) for r in rows}):
        fig, ax = plt.subplots(figsize=(6.4, 4.6))
        for cutter in ("xfem", "xfem_tip", "snap", "xfem-quadratic", "uncut"):
            sel = sorted((r for r in rows if str(r["problem"]) == problem and r["cutter"] == cutter),
                         key=lambda r: int(r["resolution"]))
            if not sel:
                continue
            t = [float(r.get("cpu_time_s") or r["run_time_s"]) for r in sel]  # records before CPU time: wall
            e = [100.0 * float(r["error"]) for r in sel]
            colour, style = STYLE[cutter]
            ax.loglog(t, e, style, color=colour, label=cutter)
            for r, x, y in zip(sel, t, e):
                ax.annotate(str(r["resolution"]), (x, y), textcoords="offset points", xytext=(4, 4), fontsize=7,
                            color=colour)
        if problem == "6":
            ax.axhline(1.0, color="k", lw=0.8, ls=":", label="1 % target")
        if band and problem in band:
            solver, estimate = band[problem]
            ax.axhspan(estimate / 10, estimate, color="0.6", alpha=0.35,  # up to the reference's own error
                       label=f"reference ({solver}): its error {estimate:.2g} %")
        ax.set_xlabel("CPU time: cut + static solve [s] (labels: resolution)")
        ax.set_ylabel("relative error [%]")
        ax.set_title(TITLES.get(problem, "Problem " + problem), fontsize=10)
        ax.grid(alpha=0.3, which="both")
        ax.legend()
        fig.tight_layout()
        name = "accuracy_problem{}.png".format(problem)
        fig.savefig(os.path.join(outdir, name), dpi=110)
        plt.close(fig)
        written.append((problem, name))
    return written


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as pyplot

    plot(pyplot, read(sys.argv[1]), sys.argv[2], bands(sys.argv[1]))
