"""xcut.Simulation against the CLI: the same positions bit for bit, the same metrics, the same
errors; a tool driven from Python cuts as the scene's trajectory does; arrays are read-only copies."""
import json
import os

import numpy as np
import pytest
import vtk
from vtk.util.numpy_support import vtk_to_numpy

import xcut
from conftest import run_cli


def read_vtu_points(path):
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    return vtk_to_numpy(r.GetOutput().GetPoints().GetData())


def test_positions_equal_the_clis_vtu_bit_for_bit(binary, skin_scene_path, tmp_path):
    steps = 40  # the blade has split elements by then
    code, _, err = run_cli(binary, "run", skin_scene_path, "--steps", str(steps), "-o", str(tmp_path), "-q",
                           "--set", f"output.every={steps}", "--threads", "2")
    assert code == 0, err
    cli = read_vtu_points(os.path.join(tmp_path, f"skin_slab_{steps:06d}.vtu"))
    sim = xcut.Simulation(skin_scene_path, threads=2)
    sim.step(steps)
    x = sim.positions
    assert sim.cut_state["elements_split"] > 0
    assert x.shape == (len(sim.rest_positions), 3)
    assert np.array_equal(cli[: len(x)], x)  # bit for bit, the mesh nodes first in the VTU
    # The same run from the scene as a dict, and with the overrides as a dict.
    with open(skin_scene_path) as f:
        scene = json.load(f)
    as_dict = xcut.Simulation(scene, {"output.every": steps}, base_directory=os.path.dirname(skin_scene_path))
    as_dict.step(steps)
    assert np.array_equal(as_dict.positions, x)


def test_metrics_are_the_csv_columns(binary, skin_scene_path, tmp_path):
    code, _, err = run_cli(binary, "run", skin_scene_path, "--steps", "25", "-o", str(tmp_path), "-q")
    assert code == 0, err
    with open(os.path.join(tmp_path, "skin_slab_metrics.csv")) as f:
        lines = f.read().splitlines()
    header, last = lines[0].split(","), lines[-1].split(",")
    sim = xcut.Simulation(skin_scene_path)
    sim.step(25)
    m = sim.metrics()
    assert list(m) == [h for h in header if not h.startswith("OutputSystem")]  # no output from Python
    for name, value in zip(header, last):
        if name.endswith("_ms") or name not in m:
            continue  # wall times differ from run to run
        digits = {"cg_residual": 1e-3, "crossing_delay_mean_s": 1e-5, "crossing_delay_max_s": 1e-5}  # as printed
        assert float(value) == pytest.approx(m[name], rel=digits.get(name, 1e-8), abs=1e-300), name
    assert m["step"] == 25 and m["elements_split"] >= 0


def scripted_position(keys, t):
    """The scene's keyframes, interpolated as the engine does (linear in position)."""
    times = [k["time"] for k in keys]
    if t <= times[0]:
        return np.array(keys[0]["position"], float)
    for a, b in zip(keys, keys[1:]):
        if t <= b["time"]:
            u = (t - a["time"]) / (b["time"] - a["time"])
            return (1 - u) * np.array(a["position"], float) + u * np.array(b["position"], float)
    return np.array(keys[-1]["position"], float)


def test_a_tool_driven_from_python_cuts_as_its_trajectory(skin_scene_path, skin_scene_dict):
    steps = 70
    scripted = xcut.Simulation(skin_scene_path)
    scripted.step(steps)
    driven = xcut.Simulation(skin_scene_path)
    keys = skin_scene_dict["tools"][0]["trajectory"]
    for _ in range(steps):
        driven.set_tool_pose("scalpel", scripted_position(keys, driven.time + driven.dt))
        driven.step()
    a, b = scripted.cut_state, driven.cut_state
    assert a["elements_split"] > 10
    assert sorted(a["cut_elements"]) == sorted(b["cut_elements"])
    assert np.array_equal(a["enriched_nodes"], b["enriched_nodes"])
    np.testing.assert_allclose(driven.positions, scripted.positions, rtol=0, atol=1e-9)
    np.testing.assert_allclose(driven.tool_pose(0)[0], scripted.tool_pose(0)[0], atol=1e-12)


def test_bad_input_raises_with_the_clis_message(binary, skin_scene_path, tmp_path):
    with open(skin_scene_path) as f:
        scene = json.load(f)
    scene["material"]["poisson"] = 0.7
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(scene))
    code, _, err = run_cli(binary, "run", str(bad), "--no-output")
    assert code == 2
    with pytest.raises(xcut.InputError) as e:
        xcut.Simulation(str(bad))
    assert err.strip() == f"error: {e.value}"
    assert e.value.file == str(bad) and e.value.field == "material.poisson"
    with pytest.raises(xcut.InputError) as e:  # a dict: the same field named
        xcut.Simulation(scene, base_directory=os.path.dirname(skin_scene_path))
    assert e.value.field == "material.poisson" and "<scene dict>" in str(e.value)
    with pytest.raises(xcut.InputError, match="solver.dt"):
        xcut.Simulation(skin_scene_path, ["solver.dt=-1"])
    with pytest.raises(xcut.InputError, match="no such scene file"):
        xcut.Simulation(str(tmp_path / "missing.json"))
    sim = xcut.Simulation(skin_scene_path)
    with pytest.raises(xcut.InputError, match="scalpel"):
        sim.set_tool_pose("forceps", [0, 0, 0])
    with pytest.raises(xcut.InputError, match="finite"):
        sim.set_tool_pose("scalpel", [np.nan, 0, 0])
    with pytest.raises(IndexError):
        sim.tool_pose(3)
    with pytest.raises(TypeError):
        xcut.Simulation(42)


def test_arrays_are_read_only_copies_made_once_a_step(skin_scene_path):
    sim = xcut.Simulation(skin_scene_path)
    x0 = sim.positions
    assert sim.positions is x0  # the same copy within a step
    assert not x0.flags.writeable
    with pytest.raises(ValueError):
        x0[0, 0] = 1.0
    sim.step(2)
    assert sim.positions is not x0 and not np.array_equal(sim.positions, x0)
    assert sim.elements.shape[1] == 4 and sim.elements.max() < len(sim.positions)
    assert sim.von_mises.shape == (len(sim.elements),) and np.all(np.isfinite(sim.von_mises))
    s = sim.visual_surface
    assert s["triangles"].shape[1] == 3 and s["triangles"].max() < len(s["vertices"])
    assert s["cut_face"].shape == (len(s["triangles"]),)
    assert sim.collision_surface["vertices"].shape[1] == 3


def step_two_at_once(scene, overrides, steps):
    """Two simulations stepped in two threads; how many times this thread ran meanwhile."""
    import threading
    import time

    sims = [xcut.Simulation(scene, overrides) for _ in range(2)]
    threads = [threading.Thread(target=s.step, args=(steps,)) for s in sims]
    for t in threads:
        t.start()
    ticks = 0
    while any(t.is_alive() for t in threads):  # this thread runs while they step: the GIL is free
        ticks += 1
        time.sleep(0.001)
    for t in threads:
        t.join()
    return sims, ticks


@pytest.mark.parametrize("linear", ["amg", "block_jacobi", "cholesky"])
def test_two_simulations_step_concurrently_in_two_threads(skin_scene_path, linear):
    overrides = {"solver.linear": linear}
    serial = xcut.Simulation(skin_scene_path, overrides)
    serial.step(60)
    sims, ticks = step_two_at_once(skin_scene_path, overrides, 60)
    assert ticks >= 5, "the main thread did not run while the simulations stepped: step() holds the GIL"
    for s in sims:
        assert s.cut_state["elements_split"] == serial.cut_state["elements_split"] > 0
        if linear == "cholesky":
            # CHOLMOD's BLAS sums in an order that may depend on where each thread's malloc put its
            # arrays: the same solution to ~1e-14 m, not always the same bits (docs/python.md).
            np.testing.assert_allclose(s.positions, serial.positions, rtol=0, atol=1e-12)
        else:
            assert np.array_equal(s.positions, serial.positions)  # concurrency changes no bit


def test_files_on_demand(skin_scene_path, tmp_path):
    sim = xcut.Simulation(skin_scene_path)
    sim.step(3)
    sim.write_vtu(tmp_path / "a.vtu")
    sim.write_surface_obj(tmp_path / "a.obj")
    assert np.array_equal(read_vtu_points(str(tmp_path / "a.vtu"))[: len(sim.positions)], sim.positions)
    assert (tmp_path / "a.obj").read_text().startswith(("#", "v ", "o ", "g "))
    out = xcut.Simulation(skin_scene_path, {"output.every": 2}, output=tmp_path / "series")
    out.step(4)
    assert (tmp_path / "series" / "skin_slab_metrics.csv").is_file()
    assert (tmp_path / "series" / "skin_slab_000004.vtu").is_file()
    f = out.figures()
    assert f["steps"] == 4 and f["time_s"] == pytest.approx(0.04)


def test_a_cut_through_a_bar_frees_a_piece_python_sees():
    cut = [[0.035, -1, -1], [0.035, 1, -1], [0.035, 1, 1], [0.035, -1, 1]]
    scene = {"mesh": {"generator": "box", "origin": [0, 0, 0], "size": [0.1, 0.01, 0.01], "element_size": 0.01},
             "material": {"young": 1e5, "poisson": 0.3, "density": 1000},
             "constraints": {"fixed_boxes": [{"min": [-1, -1, -1], "max": [1e-6, 1, 1]}]},
             "cuts": [{"time": 0.01, "polygon": cut}], "solver": {"dt": 0.005}, "steps": 4}
    sim = xcut.Simulation(scene)
    sim.step(1)
    assert sim.cut_state["pieces"] == 1
    sim.step(3)
    state = sim.cut_state
    assert state["pieces"] == 2
    # The clamped 35 mm first, then the freed 65 mm: exact volume fractions (no gravity: cut at rest).
    assert np.allclose(state["piece_volume_m3"], [0.35e-5, 0.65e-5], rtol=1e-9, atol=0)
    assert list(state["piece_anchored"]) == [1, 0]
    assert sim.figures()["pieces"] == 2
    assert np.allclose(sim.figures()["freed_volumes_m3"], [0.65e-5], rtol=1e-9, atol=0)
    assert sim.metrics()["pieces"] == 2


def test_notes_say_what_the_runs_end_would(skin_scene_dict, skin_scene_path):
    """A scalpel carried 20 mm above the skin cuts nothing: xcut run warns so at its end, and
    Simulation.notes says it after the steps, not at load (before any step there is nothing to say)."""
    scene = json.loads(json.dumps(skin_scene_dict))
    for key in scene["tools"][0]["trajectory"]:
        key["position"][2] += 0.02
    sim = xcut.Simulation(scene, base_directory=os.path.dirname(skin_scene_path))
    assert sim.notes == []
    sim.step(130)
    assert sim.cut_state["elements_split"] == 0
    assert any('tool "scalpel" cut nothing' in n for n in sim.notes), sim.notes
    # The default scene's scalpel does cut: nothing to say about it.
    cuts = xcut.Simulation(skin_scene_path)
    cuts.step(130)
    assert cuts.cut_state["elements_split"] > 0
    assert not any("cut nothing" in n for n in cuts.notes), cuts.notes


@pytest.mark.parametrize("chosen, spin", [(None, "0"), ("active", "30000000000")])
def test_openmp_threads_wait_passively_unless_the_user_chose(chosen, spin):
    """OpenMP (libgomp) prints what it read at load with OMP_DISPLAY_ENV=verbose: importing xcut
    makes its threads sleep at once when they wait (spin count 0; the default spins 300,000 times
    first), and keeps a policy the user set (active: spin for good)."""
    import subprocess
    import sys
    env = {k: v for k, v in os.environ.items() if k != "OMP_WAIT_POLICY"}
    env["OMP_DISPLAY_ENV"] = "verbose"
    if chosen is not None:
        env["OMP_WAIT_POLICY"] = chosen
    r = subprocess.run([sys.executable, "-c", "import xcut"], env=env, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert f"GOMP_SPINCOUNT = '{spin}'" in r.stderr, r.stderr
