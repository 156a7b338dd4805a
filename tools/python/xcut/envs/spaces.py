"""The Gymnasium pieces the environments need, with or without gymnasium installed: Box is
gymnasium.spaces.Box when gymnasium imports, else a small stand-in with the same attributes
(shape, dtype, low, high) and methods (sample, contains, seed); EnvBase is gymnasium.Env or object.
"""
from __future__ import annotations

from typing import Optional, Tuple

import numpy as np

try:  # pragma: no cover - depends on what is installed
    import gymnasium as _gym

    HAVE_GYMNASIUM = True
except ImportError:
    _gym = None
    HAVE_GYMNASIUM = False


class _Box:
    """A box in R^n: low <= x <= high componentwise, float64."""

    def __init__(self, low: float, high: float, shape: Tuple[int, ...], dtype=np.float64) -> None:
        self.shape = tuple(shape)
        self.dtype = np.dtype(dtype)
        self.low = np.full(self.shape, low, dtype=self.dtype)
        self.high = np.full(self.shape, high, dtype=self.dtype)
        self._rng = np.random.default_rng()

    def seed(self, seed: Optional[int] = None) -> list:
        self._rng = np.random.default_rng(seed)
        return [seed]

    def sample(self) -> np.ndarray:
        lo = np.where(np.isfinite(self.low), self.low, -1.0)
        hi = np.where(np.isfinite(self.high), self.high, 1.0)
        return self._rng.uniform(lo, hi).astype(self.dtype)

    def contains(self, x) -> bool:
        x = np.asarray(x)
        return x.shape == self.shape and bool(np.all(x >= self.low) and np.all(x <= self.high))

    def __contains__(self, x) -> bool:
        return self.contains(x)

    def __repr__(self) -> str:
        return f"Box({self.low.min()}, {self.high.max()}, {self.shape}, {self.dtype})"


if HAVE_GYMNASIUM:  # pragma: no cover
    def Box(low, high, shape, dtype=np.float64):
        return _gym.spaces.Box(low=low, high=high, shape=shape, dtype=dtype)

    EnvBase = _gym.Env
else:
    Box = _Box
    EnvBase = object
