"""Batch runs on dask.distributed: a grid of scene variants, or of any xcut command, as independent
tasks; one CSV table of results (docs/python.md#sweep).

    python3 -m xcut.sweep SPEC.json [--workers 2] [--scheduler tcp://HOST:8786] [--table out.csv]

SPEC (JSON; relative paths start at the spec's folder):
    {"scene": "../scenes/skin_slab.json",           # command "run" (the default)
     "steps": 50, "threads": 1,
     "set": {"output.every": 10},                    # every task's --set
     "grid": {"material.young": [5e3, 1e4], "solver.dt": [0.01, 0.005]},
     "cases": [{"cutter.type": "snap"}, {}],         # optional: each case times the grid
     "table": "sweep_skin.csv",                      # default: SPEC.csv beside the spec
     "timeout_s": 600}                               # optional: a task running longer is stopped
    {"command": "stress", "args": ["--count", "4"], "grid": {"--seed": [1, 2, 3]}}

Each task is one run of the xcut binary in a process of its own (a task that crashes or fails is a
row with its status; the rest go on). A "run" task runs `xcut run SCENE --no-output --summary F`
with its parameters as --set, and its row holds the summary's figures; any other command gets
its parameters as options and its row the exit status and the last line it printed. Rows are
appended as tasks finish; a rerun skips every task already in the table.
"""
from __future__ import annotations

import argparse
import csv
import itertools
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from typing import Any, Dict, List, Optional, Sequence

FIGURES = ["time_s", "wall_s", "steps", "steps_per_s", "free_dofs", "last_cg_iterations", "max_displacement_m",
           "kinetic_J", "elastic_J", "elements_split", "enriched_nodes", "front_held_nodes", "max_opening_m",
           "snap_elements_split", "snap_nodes_snapped", "refactored_steps", "substepped_steps"]
FIXED = ["task", "command", "status", "exit_code", "run_s", "message"]
# Exit codes of the xcut binary (tools/xcut.cpp).
STATUS = {0: "ok", 1: "error", 2: "input_error", 3: "numerical_error"}


class SpecError(ValueError):
    """A sweep spec that cannot run: names the file and the field."""

    def __init__(self, path: str, field: str, message: str) -> None:
        super().__init__(f"{path}: {field}: {message}")


def find_binary(given: Optional[str] = None) -> str:
    """The xcut binary: `given`, $XCUT_BINARY, the build tree's (<build>/python/xcut -> <build>/xcut),
    the installed one (<prefix>/lib/pythonX.Y/dist-packages/xcut -> <prefix>/bin/xcut), or PATH."""
    here = os.path.dirname(os.path.abspath(__file__))
    for c in (given, os.environ.get("XCUT_BINARY"), os.path.join(here, "..", "..", "xcut"),
              os.path.join(here, "..", "..", "..", "..", "bin", "xcut"), shutil.which("xcut")):
        if c and os.path.isfile(c) and os.access(c, os.X_OK):
            return os.path.abspath(c)
    raise FileNotFoundError("the xcut binary: not found (give --binary, set XCUT_BINARY or put xcut on PATH)")


def _check_list(path: str, field: str, value: Any) -> list:
    if not isinstance(value, list) or not value:
        raise SpecError(path, field, "expected a non-empty list of values")
    return value


def load_spec(path: str) -> Dict[str, Any]:
    """Reads and checks a spec; returns it with "tasks": the parameter dicts, in order."""
    try:
        with open(path) as f:
            spec = json.load(f)
    except OSError as e:
        raise SpecError(path, "file", f"cannot read it: {e.strerror}") from None
    except json.JSONDecodeError as e:
        raise SpecError(path, "JSON", f"not valid JSON (line {e.lineno}): {e.msg}") from None
    if not isinstance(spec, dict):
        raise SpecError(path, "JSON", "expected an object")
    known = {"command", "scene", "steps", "threads", "set", "grid", "cases", "args", "table", "timeout_s"}
    for k in spec:
        if k not in known:
            raise SpecError(path, k, f"not a field of a sweep spec (known: {', '.join(sorted(known))})")
    base = os.path.dirname(os.path.abspath(path))
    command = spec.get("command", "run")
    if not isinstance(command, str) or not command:
        raise SpecError(path, "command", "expected an xcut command name (run, stress, bench, ...)")
    if command == "run":
        if not isinstance(spec.get("scene"), str):
            raise SpecError(path, "scene", "a \"run\" sweep needs the scene file's path")
        spec["scene"] = os.path.normpath(os.path.join(base, spec["scene"]))
        if not os.path.isfile(spec["scene"]):
            raise SpecError(path, "scene", f"{spec['scene']} does not exist")
    grid = spec.get("grid", {})
    if not isinstance(grid, dict):
        raise SpecError(path, "grid", "expected an object {parameter: [values]}")
    keys = list(grid)
    values = [_check_list(path, f"grid.{k}", grid[k]) for k in keys]
    cases = spec.get("cases", [{}])
    if not isinstance(cases, list) or not all(isinstance(c, dict) for c in cases) or not cases:
        raise SpecError(path, "cases", "expected a non-empty list of objects {parameter: value}")
    tasks = []
    for case in cases:
        for combo in itertools.product(*values):
            params = dict(case)
            params.update(zip(keys, combo))
            tasks.append(params)
    if len(tasks) > 1_000_000:
        raise SpecError(path, "grid", f"{len(tasks)} tasks: above the limit of 1,000,000")
    for field in ("steps", "threads"):
        if field in spec and (not isinstance(spec[field], int) or spec[field] < (0 if field == "steps" else 1)):
            raise SpecError(path, field, "expected a whole number" + (" >= 1" if field == "threads" else " >= 0"))
    if "timeout_s" in spec and (not isinstance(spec["timeout_s"], (int, float)) or not spec["timeout_s"] > 0):
        raise SpecError(path, "timeout_s", "expected a number of seconds > 0")
    for field in ("set", "args"):
        v = spec.get(field, {} if field == "set" else [])
        if field == "set" and not isinstance(v, dict):
            raise SpecError(path, "set", "expected an object {field.path: value}")
        if field == "args" and not (isinstance(v, list) and all(isinstance(a, str) for a in v)):
            raise SpecError(path, "args", "expected a list of strings")
    stem = os.path.splitext(os.path.basename(path))[0]
    spec["table"] = os.path.normpath(os.path.join(base, spec.get("table", stem + ".csv")))
    spec["tasks"] = tasks
    return spec


def task_key(params: Dict[str, Any]) -> str:
    """A task's name in the table: its parameters as canonical JSON."""
    return json.dumps(params, sort_keys=True, separators=(",", ":"))


def task_args(spec: Dict[str, Any], params: Dict[str, Any], summary: str) -> List[str]:
    """The xcut command line of one task (after the binary)."""
    if spec.get("command", "run") == "run":
        args = ["run", spec["scene"], "--no-output", "--summary", summary, "-q"]
        if "steps" in spec:
            args += ["--steps", str(spec["steps"])]
        args += ["--threads", str(spec.get("threads", 1))]
        for k, v in list(spec.get("set", {}).items()) + list(params.items()):
            args += ["--set", f"{k}={json.dumps(v)}"]
        return args
    args = [spec["command"]] + list(spec.get("args", []))
    for k, v in params.items():
        args += [k] if v is True else [k, v if isinstance(v, str) else json.dumps(v)]
    return args


def run_task(binary: str, spec: Dict[str, Any], params: Dict[str, Any]) -> Dict[str, Any]:
    """Runs one task in a process of its own; returns its table row (never raises for the task's
    own failure: that is the row's status)."""
    row: Dict[str, Any] = {"task": task_key(params), "command": spec.get("command", "run")}
    with tempfile.TemporaryDirectory(prefix="xcut-sweep-") as tmp:
        summary = os.path.join(tmp, "summary.json")
        start = time.perf_counter()
        try:
            p = subprocess.run([binary] + task_args(spec, params, summary), capture_output=True, text=True,
                               cwd=tmp, timeout=spec.get("timeout_s"))
            code, out, err = p.returncode, p.stdout, p.stderr
        except OSError as e:
            code, out, err = -1, "", f"cannot start {binary}: {e.strerror}"
        except subprocess.TimeoutExpired:
            code, out, err = -9, "", f"error: stopped after the spec's timeout_s of {spec['timeout_s']} s"
        row["run_s"] = round(time.perf_counter() - start, 4)
        row["exit_code"] = code
        row["status"] = STATUS.get(code, f"crashed (signal {-code})" if code < 0 else f"exit {code}")
        # A failure's message: its "error:" line, else the first line it wrote to stderr (a usage
        # error), else the last line of its output; a success's: the last line of its output.
        err_lines = [l for l in err.splitlines() if l.strip()]
        out_lines = [l for l in out.splitlines() if l.strip()]
        errors = [l for l in err_lines if l.startswith("error:")]
        if code != 0:
            message = errors[-1] if errors else err_lines[0] if err_lines else out_lines[-1] if out_lines else ""
        else:
            message = out_lines[-1] if out_lines and spec.get("command", "run") != "run" else ""
        row["message"] = message[:500]
        if os.path.isfile(summary):
            with open(summary) as f:
                s = json.load(f)
            row["status"] = s.get("status", row["status"])
            row["message"] = s.get("message", "") or row["message"]
            row.update({k: v for k, v in s.get("figures", {}).items() if k in FIGURES})
    row.update({f"param:{k}": json.dumps(v) for k, v in params.items()})
    return row


def read_table(path: str) -> List[Dict[str, str]]:
    if not os.path.isfile(path):
        return []
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def table_columns(spec: Dict[str, Any]) -> List[str]:
    params = []
    for t in spec["tasks"]:
        for k in t:
            if f"param:{k}" not in params:
                params.append(f"param:{k}")
    return FIXED + params + (FIGURES if spec.get("command", "run") == "run" else [])


class Table:
    """The results CSV, appended to a row at a time (an interrupted sweep keeps what it finished)."""

    def __init__(self, path: str, columns: List[str]) -> None:
        self.path, self.columns = path, columns
        self.rows = read_table(path)
        if self.rows and list(self.rows[0].keys()) != columns:
            raise SpecError(path, "table", "holds other columns than this spec's: give another table (--table)")
        os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
        if not self.rows:
            with open(path, "w", newline="") as f:
                csv.DictWriter(f, columns).writeheader()

    def done(self) -> set:
        return {r["task"] for r in self.rows}

    def append(self, row: Dict[str, Any]) -> None:
        with open(self.path, "a", newline="") as f:
            csv.DictWriter(f, self.columns, extrasaction="ignore").writerow(row)
        self.rows.append({k: str(row.get(k, "")) for k in self.columns})


def progress(done: int, total: int, failed: int, start: float) -> None:
    width = 30
    filled = width * done // max(total, 1)
    sys.stderr.write(f"\rsweep [{'#' * filled:<{width}}] {done}/{total} done, {failed} failed, "
                     f"{time.perf_counter() - start:.0f} s ")
    sys.stderr.flush()


def make_client(scheduler: Optional[str], workers: int):
    """A dask client: on the scheduler given, else on a LocalCluster of `workers` workers (threads
    of this process: each task's work is a process of its own)."""
    from distributed import Client, LocalCluster

    if scheduler:
        return Client(scheduler), None
    cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=False, dashboard_address=None)
    return Client(cluster), cluster


def run_sweep(spec: Dict[str, Any], binary: str, scheduler: Optional[str] = None, workers: int = 2,
              show_progress: bool = True) -> Dict[str, Any]:
    """Runs the spec's tasks not yet in its table; returns {"ran", "skipped", "failed", "table"}."""
    from distributed import as_completed

    table = Table(spec["table"], table_columns(spec))
    done = table.done()
    todo = [p for p in spec["tasks"] if task_key(p) not in done]
    result = {"ran": 0, "skipped": len(spec["tasks"]) - len(todo), "failed": 0, "table": spec["table"]}
    if not todo:
        return result
    client, cluster = make_client(scheduler, workers)
    try:
        start = time.perf_counter()
        futures = [client.submit(run_task, binary, spec, p, pure=False) for p in todo]
        for future in as_completed(futures):
            try:
                row = future.result()
            except Exception as e:  # the worker itself failed (not the task's run): a row says so
                row = {"task": "?", "status": "worker_error", "message": str(e)[:500]}
            table.append(row)
            result["ran"] += 1
            result["failed"] += row.get("status") != "ok"
            if show_progress:
                progress(result["ran"], len(todo), result["failed"], start)
        if show_progress:
            sys.stderr.write("\n")
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    return result


def main(argv: Optional[Sequence[str]] = None) -> int:
    ap = argparse.ArgumentParser(prog="python3 -m xcut.sweep", description=__doc__.split("\n\n")[0])
    ap.add_argument("spec", help="the sweep spec (JSON)")
    ap.add_argument("--scheduler", help="a running dask scheduler, tcp://HOST:8786 (default: a LocalCluster here)")
    ap.add_argument("--workers", type=int, default=2, help="LocalCluster workers (default 2)")
    ap.add_argument("--table", help="the results CSV (default: the spec's \"table\", or SPEC.csv beside it)")
    ap.add_argument("--binary", help="the xcut binary (default: $XCUT_BINARY, the build tree's, or PATH)")
    ap.add_argument("--quiet", action="store_true", help="no progress bar")
    a = ap.parse_args(argv)
    try:
        if a.workers < 1:
            raise SpecError(a.spec, "--workers", "must be >= 1")
        spec = load_spec(a.spec)
        if a.table:
            spec["table"] = os.path.abspath(a.table)
        r = run_sweep(spec, find_binary(a.binary), a.scheduler, a.workers, not a.quiet)
    except (SpecError, FileNotFoundError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    print(f"sweep: {r['ran']} tasks run ({r['failed']} failed), {r['skipped']} already in {r['table']}")
    return 1 if r["failed"] else 0


if __name__ == "__main__":
    sys.exit(main())
