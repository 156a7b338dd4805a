"""IncisionEnv: follow a target incision line on a skin patch with a scalpel (Gymnasium-style).

The tissue is a 40 x 30 x 2 mm patch of skin (E = 10 kPa, nu = 0.3, 1000 kg/m^3, as the default
scene), its borders held, sagging under gravity; a scalpel stands with its edge vertical through
the thickness at the start of a target line 20 mm long along x, whose height y and slant are drawn
by reset(seed). Each step (10 ms of simulated time) the action moves the scalpel; XFEM cuts what
its edge sweeps.

action (3,), float64: the scalpel's velocity [m/s], each component in [-max_speed, max_speed]
    (0.05 m/s). z moves the blade's depth; the tool's z stays within [-1, 4] mm.
observation (12,), float64:
    0-2  the scalpel's position minus the line's start [m]
    3-6  its orientation (w, x, y, z)
    7    progress: the position's projection on the line, as a fraction of its length [-]
    8    lateral: signed distance from the line in the skin's plane [m]
    9    depth: the tool's z [m] (0: the edge spans the skin; above 4 mm it cuts nothing)
    10   elements split so far [-]
    11   the wound's largest opening |a_j| [m]
reward per step: 100 x the progress made along the line (1 in all for the whole line) minus
    |lateral| / length (leaving the line costs) minus 0.01 (time). Reaching the end
    (progress >= 1) ends the episode with +1 if the blade is within 1 mm of the end, less for each
    mm it tore past it; straying more than 5 mm from the line, or past 2 mm beyond its end, ends
    it with -1; a numerical failure ends it with -1 (info["error"] says why).
truncated after max_steps (default 150) steps.

Without gymnasium installed, the class stands alone with the same API and spaces of its own
(xcut.envs.spaces.Box); with gymnasium it subclasses gymnasium.Env and is registered as
"xcut/Incision-v0".
"""
from __future__ import annotations

import math
from typing import Any, Dict, Optional, Tuple

import numpy as np

from .. import NumericalError, Simulation
from .spaces import Box, EnvBase

LENGTH = 0.020       # the target line's length [m]
SIZE = (0.040, 0.030, 0.002)
DEPTH_RANGE = (-0.001, 0.004)  # the tool's z [m]


def skin_scene(element_size: float = 0.002) -> Dict[str, Any]:
    """The environment's scene as a dict (the scene file schema): the patch and a scalpel that
    holds still until the environment drives it."""
    return {
        "name": "incision_env",
        "mesh": {"generator": "box", "origin": [0, 0, 0], "size": list(SIZE), "element_size": element_size},
        "visual": {"subdivisions": 0},
        "material": {"young": 1e4, "poisson": 0.3, "density": 1000.0},
        "gravity": [0, 0, -9.81],
        "constraints": {"fixed_boxes": [
            {"min": [-1e-6, -1, -1], "max": [1e-6, 1, 1]},
            {"min": [SIZE[0] - 1e-6, -1, -1], "max": [SIZE[0] + 1e-6, 1, 1]},
            {"min": [-1, -1e-6, -1], "max": [1, 1e-6, 1]},
            {"min": [-1, SIZE[1] - 1e-6, -1], "max": [1, SIZE[1] + 1e-6, 1]}]},
        "tools": [{"name": "scalpel", "blade": {"tip": [0, 0, -0.003], "heel": [0, 0, 0.004]},
                   "trajectory": [{"time": 0.0, "position": [0.01, 0.015, 0.0]}]}],
        "solver": {"dt": 0.01, "cg_tolerance": 1e-6, "cg_max_iterations": 400,
                   "damping": {"mass": 1.0, "stiffness": 0.01}},
        "steps": 1000,
    }


class IncisionEnv(EnvBase):
    metadata = {"render_modes": []}

    def __init__(self, max_steps: int = 150, max_speed: float = 0.05, element_size: float = 0.002,
                 threads: Optional[int] = None) -> None:
        if max_steps < 1 or not max_speed > 0 or not element_size > 0:
            raise ValueError("max_steps >= 1, max_speed > 0 and element_size > 0")
        self.max_steps, self.max_speed, self.element_size, self.threads = max_steps, max_speed, element_size, threads
        self.action_space = Box(-max_speed, max_speed, (3,))
        self.observation_space = Box(-np.inf, np.inf, (12,))
        self.sim: Optional[Simulation] = None
        self._rng = np.random.default_rng()
        self._steps = 0

    # --- the target line ------------------------------------------------------------------------
    def _draw_line(self) -> None:
        y = self._rng.uniform(0.010, 0.020)
        angle = self._rng.uniform(-0.25, 0.25)  # [rad]
        self.start = np.array([0.010, y, 0.0])
        self.direction = np.array([math.cos(angle), math.sin(angle), 0.0])
        self.normal = np.array([-self.direction[1], self.direction[0], 0.0])

    def _progress_lateral(self, p: np.ndarray) -> Tuple[float, float]:
        d = p - self.start
        return float(d @ self.direction) / LENGTH, float(d @ self.normal)

    def _observe(self) -> np.ndarray:
        p, q = self.sim.tool_pose("scalpel")
        s, lat = self._progress_lateral(p)
        cut = self.sim.cut_state
        opening = float(cut["opening_m"].max()) if len(cut["opening_m"]) else 0.0
        return np.concatenate([p - self.start, q, [s, lat, p[2], cut["elements_split"], opening]])

    # --- the Gymnasium API ----------------------------------------------------------------------
    def reset(self, *, seed: Optional[int] = None, options: Optional[Dict[str, Any]] = None):
        if seed is not None:
            self._rng = np.random.default_rng(seed)
            self.action_space.seed(seed)
        self._draw_line()
        scene = skin_scene(self.element_size)
        scene["tools"][0]["trajectory"][0]["position"] = self.start.tolist()
        self.sim = Simulation(scene, threads=self.threads)
        self._steps = 0
        self._progress = 0.0
        return self._observe(), {"line_start": self.start.copy(), "line_direction": self.direction.copy()}

    def step(self, action):
        if self.sim is None:
            raise RuntimeError("call reset() before step()")
        a = np.clip(np.asarray(action, dtype=float).reshape(3), -self.max_speed, self.max_speed)
        p, q = self.sim.tool_pose("scalpel")
        target = p + a * self.sim.dt
        target[2] = min(max(target[2], DEPTH_RANGE[0]), DEPTH_RANGE[1])
        self.sim.set_tool_pose("scalpel", target, q)
        info: Dict[str, Any] = {}
        try:
            self.sim.step()
        except NumericalError as e:
            info["error"] = str(e)
            self.sim = None
            return np.zeros(12), -1.0, True, False, info
        self._steps += 1
        obs = self._observe()
        s, lat = obs[7], obs[8]
        reward = 100.0 * (min(s, 1.0) - min(self._progress, 1.0)) - abs(lat) / LENGTH - 0.01
        self._progress = max(self._progress, s)
        terminated = False
        past_mm = (s - 1.0) * LENGTH * 1e3
        if abs(lat) > 0.005 or past_mm > 2.0:
            reward, terminated = reward - 1.0, True
        elif s >= 1.0:
            reward, terminated = reward + 1.0 - max(past_mm - 1.0, 0.0), True
        truncated = not terminated and self._steps >= self.max_steps
        info.update({"progress": s, "lateral_m": lat, "elements_split": int(obs[10]), "time_s": self.sim.time})
        return obs, float(reward), terminated, truncated, info

    def close(self) -> None:
        self.sim = None
