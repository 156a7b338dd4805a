#!/usr/bin/env python3
"""Plots of `xcut compare` (docs/compare.md) from the CSVs in DIR: XFEM (semi-progressive and
progressive front) against snapping and subdivision. Writes dofs_vs_cuts.png (paper Fig. 9 / 10), crossing_delay.png (Fig. 12),
steps.png (CG iterations and step time per step) and profile.png (wall time per system).

Usage: python3 tools/report/plot_compare.py DIR
"""
import csv
import os
import statistics
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.ticker import MaxNLocator  # noqa: E402

COLOURS = {"xfem": "tab:blue", "xfem_progressive": "tab:green", "snap": "tab:red"}


def cutters(table, suffix):
    """The cutters whose `<cutter><suffix>` column the table has, in COLOURS' order."""
    return [c for c in COLOURS if table and c + suffix in table[0]]


def rows(directory, name):
    with open(os.path.join(directory, name), newline="") as f:
        return list(csv.DictReader(f))


def column(table, key, cast=float):
    return [cast(r[key]) for r in table]


def running_mean(values, width):
    """The mean of each value's window of `width` (centred; shorter at the ends)."""
    half = width // 2
    return [statistics.fmean(values[max(0, i - half):i + half + 1]) for i in range(len(values))]


def dofs_vs_cuts(d):
    t = rows(d, "dofs_vs_cuts.csv")
    fig, ax = plt.subplots(figsize=(6, 4))
    cuts = column(t, "cuts", int)
    for c in cutters(t, "_added"):
        ax.plot(cuts, column(t, c + "_added", int), "o-", color=COLOURS[c], label=c)
    ax.set_xlabel("cuts")
    ax.xaxis.set_major_locator(MaxNLocator(integer=True))  # a count: no fractional ticks
    ax.set_ylabel("DOFs added")
    ax.set_title("Generation of DOFs: XFEM vs snapping and subdivision")
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(d, "dofs_vs_cuts.png"), dpi=120)


def crossing_delay(d):
    t = rows(d, "crossing_delay.csv")
    if not t:
        return
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    sizes = sorted({float(r["element_size_m"]) for r in t if r["cutter"] == "xfem"})
    for c in [c for c in COLOURS if any(r["cutter"] == c for r in t)]:
        for i, h in enumerate(sizes):
            sel = [r for r in t if r["cutter"] == c and abs(float(r["element_size_m"]) - h) < 1e-12]
            sel.sort(key=lambda r: float(r["speed_m_s"]))
            if not sel:
                continue
            style = ["o-", "s--", "^:"][i % 3]
            label = "{} h = {:.2f} mm".format(c, h * 1e3)
            if c != "snap" and "open_delay_mean_s" in sel[0]:  # when the wound opens (XFEM)
                axes[1].plot(column(sel, "speed_m_s"), column(sel, "open_delay_mean_s"), style, color=COLOURS[c],
                             label=label)
            axes[0].plot(column(sel, "speed_m_s"), column(sel, "delay_mean_s"), style, color=COLOURS[c], label=label)
    axes[0].set_ylabel("mean split delay, simulated [s]")
    axes[1].set_ylabel("mean opening delay (XFEM), simulated [s]")
    for ax in axes:
        ax.set_xlabel("blade speed [m/s]")
        ax.set_xscale("log")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=7)
    fig.suptitle("Crossing delay against blade speed and mesh size")
    fig.tight_layout()
    fig.savefig(os.path.join(d, "crossing_delay.png"), dpi=120)


def steps(d):
    t = rows(d, "steps.csv")
    fig, axes = plt.subplots(3, 1, figsize=(8, 8), sharex=True)
    time = column(t, "time_s")
    # Per-step CG iterations and times jump from step to step, and three cutters' raw lines on one
    # panel hid each other: each step as a faint dot, and a running mean over 15 steps as a line (a
    # mean, not a median: the counts are small integers, and three cutters' medians coincide).
    for c in cutters(t, "_dofs"):
        axes[0].plot(time, column(t, c + "_dofs", int), color=COLOURS[c], label=c)
        for ax, key in ((axes[1], "_cg_iterations"), (axes[2], "_step_ms")):
            values = column(t, c + key)
            ax.plot(time, values, ".", color=COLOURS[c], ms=2, alpha=0.25)
            ax.plot(time, running_mean(values, 15), color=COLOURS[c], lw=1.4, label=c)
    axes[0].set_ylabel("DOFs")
    axes[1].set_ylabel("CG iterations\n(dots: steps; line: mean of 15)")
    axes[1].yaxis.set_major_locator(MaxNLocator(integer=True))
    axes[2].set_ylabel("step time [ms]\n(dots: steps; line: mean of 15)")
    axes[2].set_xlabel("simulated time [s]")
    for ax in axes:
        ax.grid(alpha=0.3)
    axes[0].legend()
    fig.tight_layout()
    fig.savefig(os.path.join(d, "steps.png"), dpi=120)


def profile(d):
    t = rows(d, "profile.csv")
    fig, ax = plt.subplots(figsize=(8, 4))
    names = column(t, "system", str)
    y = range(len(names))
    shown = cutters(t, "_ms_per_step")
    width = 0.8 / max(1, len(shown))
    for k, c in enumerate(shown):
        offset = (k - (len(shown) - 1) / 2) * width
        ax.barh([i + offset for i in y], column(t, c + "_ms_per_step"), height=width, color=COLOURS[c], label=c)
    ax.set_yticks(list(y))
    ax.set_yticklabels(names)
    ax.invert_yaxis()
    ax.set_xlabel("wall time per step [ms]")
    ax.set_title("Time per system")
    ax.grid(alpha=0.3, axis="x")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(d, "profile.png"), dpi=120)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    d = sys.argv[1]
    for plot in (dofs_vs_cuts, crossing_delay, steps, profile):
        plot(d)
    print("plots: {}/{{dofs_vs_cuts,crossing_delay,steps,profile}}.png".format(d))


if __name__ == "__main__":
    main()
