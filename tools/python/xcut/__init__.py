"""xcut from Python: real-time cutting of soft tissue with the corotational XFEM.

    import xcut
    sim = xcut.Simulation("scenes/skin_slab.json", {"solver.dt": 0.005})
    sim.step(10)
    x = sim.positions            # (N, 3) numpy array [m]
    sim.set_tool_pose("scalpel", [0.031, 0.01, 0.0])

A scene is a file path or a dict with the scene file's schema (docs/scene-format.md); bad input
raises xcut.InputError with the message `xcut run` prints. Units are SI throughout. Every array a
Simulation returns is a read-only copy owned by numpy, made at most once per step (see
docs/python.md for why no array is a view of the engine's memory).
"""
from __future__ import annotations

import json
import os
import time as _time
import warnings as _warnings
from typing import Any, Dict, Iterable, Mapping, Optional, Sequence, Tuple, Union

# OpenMP reads its wait policy once, when its library loads (with the engine's, or numpy's BLAS):
# threads spinning while they wait take a core from the work beside them (a renderer, other
# workers, a test beside this one). The xcut program sets the same for itself; a policy the user
# chose is kept.
os.environ.setdefault("OMP_WAIT_POLICY", "passive")

import numpy as np  # noqa: E402  (after the wait policy)

from . import _xcut  # noqa: E402
from ._xcut import InputError, NumericalError

__all__ = ["Simulation", "InputError", "NumericalError", "XcutWarning", "set_threads", "threads", "overrides_list"]

SceneLike = Union[str, "os.PathLike[str]", Mapping[str, Any]]
Overrides = Union[None, Mapping[str, Any], Sequence[str]]


class XcutWarning(UserWarning):
    """A scene that is valid but likely not meant (the CLI's `warning:` lines)."""


def set_threads(n: int) -> None:
    """Threads the engine uses, process-wide (results are bit-identical for any count)."""
    if int(n) < 1:
        raise ValueError("threads must be >= 1")
    _xcut.set_threads(int(n))


def threads() -> int:
    """Threads the engine uses."""
    return _xcut.threads()


def overrides_list(overrides: Overrides) -> list:
    """`--set` items from a dict {"field.path": value} (values as JSON) or a list of "path=json"."""
    if overrides is None:
        return []
    if isinstance(overrides, Mapping):
        return [f"{k}={json.dumps(v)}" for k, v in overrides.items()]
    if isinstance(overrides, str):
        raise TypeError("overrides: give a dict or a list of 'field.path=value' strings, not one string")
    return [str(o) for o in overrides]


class Simulation:
    """A scene, built as `xcut run` builds it, stepped from Python.

    scene: a scene file's path, or a dict with the same schema (relative file names in it start at
        `base_directory`, by default the working directory).
    overrides: like `--set`: {"material.young": 2e4} or ["material.young=2e4"].
    threads: the engine's thread count (process-wide; default: as it is, 2 at import).
    output: None writes nothing (the default); a directory writes the ParaView series, the metrics
        CSV and the surfaces there as `xcut run -o DIR` does.
    """

    def __init__(self, scene: SceneLike, overrides: Overrides = None, *, threads: Optional[int] = None,
                 output: Optional[Union[str, "os.PathLike[str]"]] = None,
                 base_directory: Optional[Union[str, "os.PathLike[str]"]] = None) -> None:
        if threads is not None:
            set_threads(threads)
        path, text = "", ""
        if isinstance(scene, Mapping):
            text = json.dumps(scene)
        elif isinstance(scene, (str, os.PathLike)):
            path = os.fspath(scene)
        else:
            raise TypeError(f"scene: give a file path or a dict, not {type(scene).__name__}")
        base = os.fspath(base_directory) if base_directory is not None else os.getcwd()
        self._sim = _xcut._Simulation(path, text, base, overrides_list(overrides),
                                      os.fspath(output) if output is not None else "")
        self._cache: Dict[str, Any] = {}
        self._cache_step = -1
        self._start = _time.perf_counter()
        for w in self._sim.warnings:
            _warnings.warn(w, XcutWarning, stacklevel=2)

    # --- stepping -------------------------------------------------------------------------------
    def step(self, n: int = 1) -> None:
        """Runs n steps (the GIL is released meanwhile). A numerical failure raises
        xcut.NumericalError and the simulation refuses to step on."""
        self._sim.step(int(n))

    @property
    def time(self) -> float:
        """Simulated time [s]."""
        return self._sim.time

    @property
    def dt(self) -> float:
        """The time step [s] (the next one, in real-time mode)."""
        return self._sim.dt

    @property
    def step_count(self) -> int:
        """Steps run so far."""
        return self._sim.step_count

    @property
    def scene_steps(self) -> int:
        """The steps the scene asks for (its `steps` or `duration`)."""
        return self._sim.scene_steps

    @property
    def name(self) -> str:
        return self._sim.name

    @property
    def dim(self) -> int:
        """3: tetrahedra; 2: triangles (plane stress)."""
        return self._sim.dim

    @property
    def warnings(self) -> list:
        """The plausibility warnings and mesh notes the scene got at load."""
        return list(self._sim.warnings)

    @property
    def notes(self) -> list:
        """What `xcut run` would warn at its end if the run ended now: a tool that cut nothing or
        stabbed, a closed loop that freed no piece, jaws closed on nothing, a surface the cuts left
        open (docs/xfem.md), ... Empty when there is nothing to say."""
        return list(self._sim.notes)

    # --- state (read-only copies, one per step) -------------------------------------------------
    def _cached(self, key: str, make):
        if self._cache_step != self._sim.step_count:
            self._cache.clear()
            self._cache_step = self._sim.step_count
        if key not in self._cache:
            self._cache[key] = make()
        return self._cache[key]

    @property
    def positions(self) -> np.ndarray:
        """Mesh node positions, (N, 3) [m]."""
        return self._cached("x", lambda: self._sim.positions(False))

    @property
    def velocities(self) -> np.ndarray:
        """Mesh node velocities, (N, 3) [m/s]."""
        return self._cached("v", lambda: self._sim.velocities(False))

    @property
    def dof_positions(self) -> np.ndarray:
        """Every DOF node: the mesh nodes, then the enriched DOFs (the phantom copies of cut
        nodes, docs/xfem.md) or the snapping cutter's new nodes, (N_dof, 3) [m]."""
        return self._cached("xd", lambda: self._sim.positions(True))

    @property
    def rest_positions(self) -> np.ndarray:
        """Mesh node rest positions, (N, 3) [m]."""
        return self._cached("X", self._sim.rest_positions)

    @property
    def elements(self) -> np.ndarray:
        """Mesh elements' nodes, (M, 4) tetrahedra or (M, 3) triangles."""
        return self._cached("e", self._sim.elements)

    @property
    def von_mises(self) -> np.ndarray:
        """Von Mises stress per mesh element, (M,) [Pa]; a cut element: its larger side's."""
        return self._cached("vm", self._sim.von_mises)

    @property
    def cut_state(self) -> Dict[str, Any]:
        """{"elements_split": int, "cut_elements": (K,) mesh elements split, "enriched_nodes": (J,)
        mesh nodes with an enriched DOF, "opening_m": (J,) |a_j| of each [m]}."""
        return self._cached("cut", self._sim.cut_state)

    @property
    def visual_surface(self) -> Dict[str, np.ndarray]:
        """{"vertices": (V, 3) [m], "triangles": (T, 3) outward, "cut_face": (T,) 1 on the wound}."""
        return self._cached("vis", lambda: self._sim.surface(False))

    @property
    def collision_surface(self) -> Dict[str, np.ndarray]:
        """The surface tools touch, as visual_surface."""
        return self._cached("col", lambda: self._sim.surface(True))

    # --- tools ----------------------------------------------------------------------------------
    @property
    def tool_names(self) -> list:
        return list(self._sim.tool_names())

    def _tool(self, tool: Union[int, str]) -> int:
        if isinstance(tool, str):
            return self._sim.tool_index(tool)
        i = int(tool)
        if not 0 <= i < len(self._sim.tool_names()):
            raise IndexError(f"tool {i}: the scene has {len(self._sim.tool_names())} tools")
        return i

    def tool_pose(self, tool: Union[int, str]) -> Tuple[np.ndarray, np.ndarray]:
        """(position (3,) [m], quaternion (4,) w, x, y, z: tool -> world) after the last step."""
        return self._sim.tool_pose(self._tool(tool))

    def set_tool_pose(self, tool: Union[int, str], position: Iterable[float],
                      quaternion: Optional[Iterable[float]] = None) -> None:
        """The tool moves to this pose over the next step, on a straight path from where it is (a
        blade cuts what it sweeps). From the first call on, the tool follows only these calls.
        quaternion: (w, x, y, z), tool -> world; None keeps the orientation."""
        i = self._tool(tool)
        p = np.asarray(position, dtype=float).reshape(3)
        q = self._sim.tool_pose(i)[1] if quaternion is None else np.asarray(quaternion, dtype=float).reshape(4)
        self._sim.set_tool_pose(i, p.tolist(), q.tolist())

    def tool_force(self, tool: Union[int, str]) -> Tuple[np.ndarray, np.ndarray]:
        """The tissue's force [N] and torque about the tool origin [N m] on the tool, last step."""
        return self._sim.tool_force(self._tool(tool))

    # --- figures and files ----------------------------------------------------------------------
    def metrics(self) -> Dict[str, Any]:
        """The last step's row of the metrics CSV, by column name."""
        return self._sim.metrics()

    def figures(self) -> Dict[str, Any]:
        """The run's figures as `xcut run --summary` writes them (wall_s: since construction)."""
        return json.loads(self._sim.figures_json(_time.perf_counter() - self._start))

    def write_vtu(self, path: Union[str, "os.PathLike[str]"]) -> None:
        """The mesh as `xcut run` writes each frame (.vtu)."""
        self._sim.write_vtu(os.fspath(path))

    def write_surface_obj(self, path: Union[str, "os.PathLike[str]"]) -> None:
        """The visual surface as OBJ (the wound's faces in group "cut")."""
        self._sim.write_surface_obj(os.fspath(path))

    def __repr__(self) -> str:
        if not hasattr(self, "_sim"):
            return "<xcut.Simulation (not built)>"
        return (f"<xcut.Simulation {self.name!r}: {len(self.positions)} nodes, {self.dim}D, "
                f"step {self.step_count}, t = {self.time:.4g} s>")
