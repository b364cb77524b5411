"""The water-surface interface every consumer uses, and the flat sea.

All queries are vectorized over points. Positions are world ENU metres, time is simulation seconds.
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable

import numpy as np


@runtime_checkable
class WaterSurface(Protocol):
    def elevation(self, x: np.ndarray, y: np.ndarray, t: float) -> np.ndarray:
        """Surface height z (m, ENU) above the still-water level at the world points (x, y), time t."""
        ...

    def velocity(self, x: np.ndarray, y: np.ndarray, z: np.ndarray, t: float) -> np.ndarray:
        """Water particle velocity (m/s, ENU), shape (n, 3), at world points (waves plus current)."""
        ...


class FlatSea:
    """Still water at a constant level, optionally with a uniform current (ENU, m/s)."""

    def __init__(self, level: float = 0.0, current_enu: tuple[float, float, float] = (0.0, 0.0, 0.0)):
        self.level = float(level)
        self.current_enu = np.asarray(current_enu, dtype=float)

    def elevation(self, x: np.ndarray, y: np.ndarray, t: float) -> np.ndarray:
        return np.full(np.shape(x), self.level)

    def velocity(self, x: np.ndarray, y: np.ndarray, z: np.ndarray, t: float) -> np.ndarray:
        return np.broadcast_to(self.current_enu, (np.size(x), 3)).copy()
