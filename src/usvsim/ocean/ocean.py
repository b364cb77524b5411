"""The ocean of a simulation: one wave field, current and wind; the single source of truth for physics,
rendering and sensors. Implements `WaterSurface` (world ENU metres, seconds).
"""

from __future__ import annotations

import numpy as np

from usvsim.ocean.current import Current
from usvsim.ocean.field import WaveField, as_points
from usvsim.ocean.wind import Wind


class Ocean:
    """Waves (or still water when `waves` is None) at mean level `level_m`, plus current and wind.

    The stochastic parts (gusts, current variations) are Gauss–Markov processes stepped on a fixed dt; `advance(t)`
    moves them forward to t (never back). Queries at time t advance them too, so their state is a function of t
    alone as long as time does not run backwards. Processes with zero standard deviation are constant (they draw
    no random numbers): they are not stepped, and the constant wind and current vectors are computed once.
    """

    def __init__(
        self,
        waves: WaveField | None = None,
        wind: Wind | None = None,
        current: Current | None = None,
        level_m: float = 0.0,
    ):
        self.waves = waves
        self.wind = wind if wind is not None else Wind()
        self.current = current if current is not None else Current()
        self.level_m = float(level_m)
        self._steady = self.wind.constant and self.current.constant  # nothing to step: skip `advance`
        self._wind_const = self.wind.velocity() if self.wind.constant else None
        self._current_const = self.current.surface_velocity() if self.current.constant else None
        self._current_rows = np.zeros((0, 3))  # the constant current, one row per queried point (reused)
        self._steady_rows: np.ndarray | None = None  # see steady_velocity_rows

    def advance(self, t: float) -> None:
        """Bring wind gusts and current to time t (s) and prepare the wave tiles for t."""
        if not self._steady:
            self.wind.advance(t)
            self.current.advance(t)
        update = getattr(self.waves, "update", None)
        if update is not None:
            update(t)

    def elevation(self, x, y, t: float) -> np.ndarray:
        """Surface height z (m, ENU) at world points (x, y) and time t, horizontal displacement inverted."""
        if self.waves is None:
            return np.full(np.shape(x), self.level_m)
        return self.waves.elevation(x, y, t) + self.level_m

    def normal(self, x, y, t: float) -> np.ndarray:
        """Unit surface normal (n, 3), ENU, at world points (x, y)."""
        if self.waves is None:
            return np.tile([0.0, 0.0, 1.0], (np.size(x), 1))
        return self.waves.normal(x, y, t)

    def kinematics(self, x, y, z, t: float, acceleration: bool = True) -> tuple[np.ndarray, np.ndarray]:
        """Water velocity (orbital + current) and acceleration (orbital), (n, 3) each, ENU, at world points.
        Without `acceleration` the second array has no rows (and costs nothing)."""
        self.advance(t)
        px, py, pz = as_points(x, y, z)
        zrel = pz - self.level_m
        if self.waves is None:
            vel, acc = np.zeros((len(px), 3)), np.zeros((len(px) if acceleration else 0, 3))
        elif acceleration:
            vel, acc = self.waves.kinematics(px, py, zrel, t)
        else:
            vel, acc = self.waves.velocity(px, py, zrel, t), np.zeros((0, 3))
        return vel + self._current_at(zrel, t), acc

    def velocity(self, x, y, z, t: float) -> np.ndarray:
        """Water particle velocity (n, 3), m/s ENU: wave orbital velocity plus current."""
        if self.waves is None:  # fast path (every physics step in calm scenarios): current only
            return self._current_at(np.asarray(z, dtype=float) - self.level_m, t)
        return self.kinematics(x, y, z, t, acceleration=False)[0]

    def _current_at(self, zrel: np.ndarray, t: float) -> np.ndarray:
        """The current (n, 3), m/s ENU, at heights `zrel` (m above the mean level): a constant uniform current
        is copied from rows made once."""
        if self._current_const is None or self.current.profile != "uniform":
            self.current.advance(t)
            return self.current.velocity(zrel)
        if len(self._current_rows) != np.size(zrel):
            self._current_rows = np.tile(self._current_const, (np.size(zrel), 1))
        return self._current_rows.copy()

    def velocity_into(self, points: np.ndarray, t: float, out: np.ndarray) -> None:
        """`velocity` at points (n, 3) m ENU, written into out (n, 3): one compiled call for an FFT sea without
        displacement under a constant uniform current (the same values bit for bit), the array path otherwise."""
        fast = getattr(self.waves, "velocity_at_points", None)
        if fast is not None and self._current_const is not None and self.current.profile == "uniform":
            self.advance(t)
            if fast(points, self.level_m, t, self._current_const, out):
                return
        out[:] = self.velocity(points[:, 0], points[:, 1], points[:, 2], t)

    def steady_velocity_rows(self, n: int) -> np.ndarray | None:
        """Still water with a constant uniform current: its velocity (n, 3), m/s ENU, as one read-only array
        made once (the same array every call); None otherwise (use `velocity`)."""
        if self.waves is not None or self._current_const is None or self.current.profile != "uniform":
            return None
        rows = self._steady_rows
        if rows is None or len(rows) != n:
            rows = self._steady_rows = np.tile(self._current_const, (n, 1))
            rows.flags.writeable = False
        return rows

    @property
    def wind_constant(self) -> bool:
        """Whether `wind_velocity` is the same at every time (no gusts)."""
        return self._wind_const is not None

    def acceleration(self, x, y, z, t: float) -> np.ndarray:
        """Water particle acceleration (n, 3), m/s² ENU (the current's slow variation is neglected)."""
        return self.kinematics(x, y, z, t)[1]

    def wind_velocity(self, t: float) -> np.ndarray:
        """Wind velocity (3,), m/s ENU, at time t (mean + gust, toward the wind direction)."""
        if self._wind_const is not None:
            return self._wind_const.copy()
        self.advance(t)
        return self.wind.velocity()

    def height_grid(self, center_xy, size_m: float, n: int, t: float) -> np.ndarray:
        """Heights (n, n) [iy, ix] on a world grid of side `size_m` centred on `center_xy` (rendering, patches)."""
        if self.waves is None:
            return np.full((n, n), self.level_m)
        return self.waves.height_grid(center_xy, size_m, n, t) + self.level_m

    def render_grid(self, center_xy, size_m: float, n: int, t: float) -> np.ndarray:
        """Vertices (n, n, 3) of the displaced surface over a label grid: the mesh a renderer draws."""
        if self.waves is None:
            axis = np.linspace(-0.5 * size_m, 0.5 * size_m, n)
            gx, gy = np.meshgrid(center_xy[0] + axis, center_xy[1] + axis)
            return np.stack([gx, gy, np.full_like(gx, self.level_m)], axis=-1)
        grid = self.waves.render_grid(center_xy, size_m, n, t)
        grid[..., 2] += self.level_m
        return grid
