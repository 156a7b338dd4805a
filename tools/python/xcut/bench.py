"""The Python API's benchmark: figures printed and written to CSV, never a timed test.

    PYTHONPATH=build/python python3 -m xcut.bench [--quick] [--scene scenes/skin_slab.json]

1. Steps/s stepping the scene from Python against `xcut run --no-output` (the CLI's own
   steps_per_s from --summary, the stepping loop only), alternated, median of the repeats; the
   ratio Python / CLI.
2. The overhead of reading the positions each step: the same steps with and without a read of
   Simulation.positions after each, and the read's own mean time.
3. Sweep throughput: the same 8 tasks on a LocalCluster of 1 worker and of 2; tasks/s and the ratio.

Writes results/bench_python.csv (figure,value,unit); --quick (fewer steps and repeats) writes
results/bench_python_quick.csv instead, so a quick run never overwrites the record.
"""
from __future__ import annotations

import argparse
import csv
import json
import os
import statistics
import subprocess
import tempfile
import time

from . import Simulation
from . import sweep


def cli_steps_per_s(binary: str, scene: str, steps: int, threads: int) -> float:
    with tempfile.TemporaryDirectory() as tmp:
        summary = os.path.join(tmp, "s.json")
        subprocess.run([binary, "run", scene, "--no-output", "--summary", summary, "--steps", str(steps),
                        "--threads", str(threads), "-q"], check=True, capture_output=True)
        with open(summary) as f:
            return json.load(f)["figures"]["steps_per_s"]


def python_steps_per_s(scene: str, steps: int, threads: int, read_positions: bool = False) -> float:
    sim = Simulation(scene, threads=threads)
    start = time.perf_counter()
    for _ in range(steps):
        sim.step()
        if read_positions:
            sim.positions
    return steps / (time.perf_counter() - start)


def read_cost_us(scene: str, steps: int) -> float:
    """Mean time of one fresh positions read [us] (a step between reads, so each is a new copy)."""
    sim = Simulation(scene)
    total = 0.0
    for _ in range(steps):
        sim.step()
        t = time.perf_counter()
        sim.positions
        total += time.perf_counter() - t
    return 1e6 * total / steps


def sweep_tasks_per_s(binary: str, scene: str, workers: int, steps: int, directory: str) -> float:
    spec_path = os.path.join(directory, f"sweep_{workers}.json")
    with open(spec_path, "w") as f:
        json.dump({"scene": scene, "steps": steps, "threads": 1,
                   "grid": {"material.young": [8e3, 1e4, 1.2e4, 1.4e4], "cutter.front": ["semi", "progressive"]}}, f)
    spec = sweep.load_spec(spec_path)
    start = time.perf_counter()
    r = sweep.run_sweep(spec, binary, workers=workers, show_progress=False)
    if r["failed"]:
        raise RuntimeError(f"{r['failed']} sweep tasks failed: see {r['table']}")
    return len(spec["tasks"]) / (time.perf_counter() - start)


def main() -> int:
    ap = argparse.ArgumentParser(prog="python3 -m xcut.bench", description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", default="scenes/skin_slab.json")
    ap.add_argument("--quick", action="store_true", help="fewer steps and repeats; writes *_quick.csv")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--binary", help="the xcut binary (default: $XCUT_BINARY, the build tree's, or PATH)")
    ap.add_argument("--out", default="results", help="the CSV's folder")
    a = ap.parse_args()
    binary = sweep.find_binary(a.binary)
    scene = os.path.abspath(a.scene)
    steps, repeats = (50, 2) if a.quick else (200, 5)
    rows = []

    def report(figure: str, value: float, unit: str) -> None:
        rows.append((figure, f"{value:.6g}", unit))
        print(f"{figure:<44} {value:12.4g} {unit}")

    print(f"xcut Python benchmark: {scene}, {steps} steps, {a.threads} threads, {repeats} repeats")
    cli, py = [], []
    for _ in range(repeats):  # alternated, so a change in the machine's load hits both
        cli.append(cli_steps_per_s(binary, scene, steps, a.threads))
        py.append(python_steps_per_s(scene, steps, a.threads))
    report("cli_steps_per_s_median", statistics.median(cli), "1/s")
    report("python_steps_per_s_median", statistics.median(py), "1/s")
    report("python_over_cli", statistics.median(py) / statistics.median(cli), "-")
    plain, reading = [], []
    for _ in range(repeats):
        plain.append(python_steps_per_s(scene, steps, a.threads))
        reading.append(python_steps_per_s(scene, steps, a.threads, read_positions=True))
    report("steps_per_s_reading_positions_each_step", statistics.median(reading), "1/s")
    report("reading_positions_slowdown", statistics.median(plain) / statistics.median(reading) - 1.0, "-")
    report("positions_read_mean", read_cost_us(scene, steps), "us")
    with tempfile.TemporaryDirectory() as tmp:
        one = sweep_tasks_per_s(binary, scene, 1, steps, tmp)
        two = sweep_tasks_per_s(binary, scene, 2, steps, tmp)
    report("sweep_tasks_per_s_1_worker", one, "1/s")
    report("sweep_tasks_per_s_2_workers", two, "1/s")
    report("sweep_speedup_2_over_1", two / one, "-")
    os.makedirs(a.out, exist_ok=True)
    path = os.path.join(a.out, "bench_python_quick.csv" if a.quick else "bench_python.csv")
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["figure", "value", "unit"])
        w.writerows(rows)
    print(f"written: {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
