"""python3 -m xcut.sweep on a dask LocalCluster: 8 cases equal the same 8 run one by one; a failed
task is a row and the rest go on; a rerun skips what the table holds; bad specs name the field."""
import csv
import json
import os
import subprocess
import sys

import pytest

from xcut import sweep

VARYING = {"wall_s", "steps_per_s", "run_s"}


def write_spec(tmp_path, skin_scene_path, **extra):
    spec = {"scene": skin_scene_path, "steps": 30, "threads": 1,
            "grid": {"material.young": [8000.0, 12000.0], "solver.dt": [0.01, 0.008],
                     "cutter.front": ["semi", "progressive"]},
            "table": str(tmp_path / "table.csv")}
    spec.update(extra)
    path = tmp_path / "spec.json"
    path.write_text(json.dumps(spec))
    return str(path)


def test_a_cluster_sweep_equals_the_cases_run_one_by_one(tmp_path, skin_scene_path, binary):
    spec_path = write_spec(tmp_path, skin_scene_path)
    p = subprocess.run([sys.executable, "-m", "xcut.sweep", spec_path, "--workers", "2", "--binary", binary],
                       capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr
    assert "8 tasks run (0 failed)" in p.stdout
    with open(tmp_path / "table.csv") as f:
        rows = {r["task"]: r for r in csv.DictReader(f)}
    assert len(rows) == 8
    spec = sweep.load_spec(spec_path)
    for params in spec["tasks"]:  # one by one, no dask
        alone = sweep.run_task(binary, spec, params)
        row = rows[sweep.task_key(params)]
        assert row["status"] == "ok" and alone["status"] == "ok"
        for k in sweep.FIGURES:
            if k not in VARYING:
                assert row[k] == str(alone[k]), k
    splits = {rows[k]["elements_split"] for k in rows}
    assert len(splits) > 1 or "0" not in splits  # the grid changed something that matters
    # A rerun skips all 8.
    p = subprocess.run([sys.executable, "-m", "xcut.sweep", spec_path, "--binary", binary, "--quiet"],
                       capture_output=True, text=True, timeout=600)
    assert p.returncode == 0 and "0 tasks run (0 failed), 8 already in" in p.stdout


def test_a_failed_task_is_a_row_and_the_rest_go_on(tmp_path, skin_scene_path, binary):
    spec_path = write_spec(tmp_path, skin_scene_path, steps=5,
                           grid={"material.poisson": [0.3, 0.7, 0.35]})
    spec = sweep.load_spec(spec_path)
    r = sweep.run_sweep(spec, binary, workers=2, show_progress=False)
    assert r == {"ran": 3, "skipped": 0, "failed": 1, "table": spec["table"]}
    with open(spec["table"]) as f:
        rows = list(csv.DictReader(f))
    bad = [row for row in rows if row["param:material.poisson"] == "0.7"][0]
    assert bad["status"] == "input_error" and "material.poisson" in bad["message"] and bad["exit_code"] == "2"
    assert sorted(row["status"] for row in rows) == ["input_error", "ok", "ok"]


def test_other_commands_get_their_parameters_as_options(tmp_path, binary):
    mesh = os.path.join(os.environ["XCUT_SOURCE_DIR"], "scenes", "meshes", "abdominal_wall.msh")
    spec = {"command": "mesh", "grid": {"--units": ["m", "parsec"]}, "args": [mesh], "table": str(tmp_path / "mesh.csv")}
    path = tmp_path / "mesh.json"
    path.write_text(json.dumps(spec))
    r = sweep.run_sweep(sweep.load_spec(str(path)), binary, workers=1, show_progress=False)
    assert r["ran"] == 2 and r["failed"] == 1
    with open(tmp_path / "mesh.csv") as f:
        rows = {json.loads(row["param:--units"]): row for row in csv.DictReader(f)}
    assert rows["m"]["status"] == "ok" and rows["m"]["exit_code"] == "0"
    assert rows["parsec"]["status"] != "ok" and rows["parsec"]["exit_code"] != "0"
    assert "parsec" in rows["parsec"]["message"]  # the line the command printed


@pytest.mark.parametrize("spec, field", [
    ({"grid": {"a": [1]}}, "scene"),
    ({"scene": "x.json"}, "scene"),
    ({"scene": "SKIN", "grid": {"material.young": []}}, "grid.material.young"),
    ({"scene": "SKIN", "steps": -1}, "steps"),
    ({"scene": "SKIN", "colour": 1}, "colour"),
    ({"scene": "SKIN", "cases": [1]}, "cases"),
])
def test_bad_specs_name_the_field(tmp_path, skin_scene_path, spec, field):
    if spec.get("scene") == "SKIN":
        spec["scene"] = skin_scene_path
    path = tmp_path / "s.json"
    path.write_text(json.dumps(spec))
    with pytest.raises(sweep.SpecError, match=f": {field}: "):
        sweep.load_spec(str(path))
    p = subprocess.run([sys.executable, "-m", "xcut.sweep", str(path)], capture_output=True, text=True)
    assert p.returncode == 2 and p.stderr.startswith("error: ")
