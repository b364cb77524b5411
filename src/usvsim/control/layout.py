"""A vessel's thrusters as seen by control allocation: geometry about the CoM, limits, configuration matrix.

Frames and units: body FLU (x forward, y left, z up), metres; the generalized force is the planar
τ = (X [N], Y [N], N [N m]) about the centre of mass, N positive counter-clockwise seen from above
(REP 103). A thruster at (x, y) relative to the CoM pushing with thrust T along heading θ gives
X = T cos θ, Y = T sin θ, N = x T sin θ - y T cos θ; θ = mount yaw + azimuth angle.

Extended-thrust (Cartesian) decomposition (Sørdalen 1997; physics.md §5.2): a fixed thruster (a tunnel
thruster is a fixed one with mount yaw 90°) is one column (cos θ, sin θ, x sin θ - y cos θ); an azimuth
thruster is two virtual fixed forces along body x and y: columns (1, 0, -y) and (0, 1, x).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from usvsim.config.vessel import Thruster
from usvsim.hydro.thrusters import MAP_CODES

# Columns of ThrusterLayout.params (one row per thruster), the packed form the numba kernels read.
X, Y, MOUNT, IS_AZ, A_MIN, A_MAX, A_RATE, A_TAU, T_FWD, T_REV, T_RATE, MAP, WEIGHT = range(13)
N_PARAMS = 13


@dataclass(frozen=True)
class ThrusterLayout:
    """Thrusters of one vessel relative to its CoM. `params` rows: x_m, y_m, mount_yaw_rad, is_azimuth,
    angle_min_rad, angle_max_rad, angle_rate_rad_s, angle_time_constant_s, max_forward_n, max_reverse_n,
    thrust_rate_n_s (inf = none), map code, allocation weight (1 = default)."""

    names: tuple[str, ...]
    params: np.ndarray
    columns: np.ndarray  # first column of each thruster in the extended matrix
    extended: np.ndarray  # (3, m) configuration matrix of the extended thrust vector

    @classmethod
    def from_thrusters(
        cls, thrusters: Sequence[Thruster], com_flu_m=(0.0, 0.0, 0.0), weights=None
    ) -> ThrusterLayout:
        """Layout of thruster configs (positions in base_link FLU) about the CoM `com_flu_m`."""
        rows = [_row(t, com_flu_m) for t in thrusters]
        params = np.array(rows, dtype=float).reshape(len(rows), N_PARAMS)
        if weights is not None:
            params[:, WEIGHT] = np.asarray(weights, dtype=float)
        columns = np.cumsum([0] + [2 if p[IS_AZ] else 1 for p in params])
        return cls(
            tuple(t.name for t in thrusters), params, columns[:-1].astype(np.int64), extended_matrix(params)
        )

    @property
    def n(self) -> int:
        return len(self.names)

    @property
    def azimuth(self) -> np.ndarray:
        return self.params[:, IS_AZ] > 0

    def tau_from_thrusts(self, thrust_n, angle_rad) -> np.ndarray:
        """τ (X, Y, N) of signed thrusts (N) at azimuth angles (rad; ignored for fixed thrusters)."""
        return thrust_matrix(self.params, np.asarray(angle_rad, dtype=float)) @ np.asarray(
            thrust_n, dtype=float
        )

    def capacity(self) -> np.ndarray:
        """Rough per-axis capacity (X [N], Y [N], N [N m]): each thruster at full forward thrust along the axis'
        best direction it can take (an upper bound, used for reference-model limits and scaling)."""
        p = self.params
        out = np.zeros(3)
        for row in p:
            x, y, f = row[X], row[Y], row[T_FWD]
            if row[IS_AZ]:
                out += f * np.array([1.0, 1.0, math.hypot(x, y)])
            else:
                c, s = math.cos(row[MOUNT]), math.sin(row[MOUNT])
                out += f * np.abs([c, s, x * s - y * c])
        return out

    def is_fully_actuated(self) -> bool:
        """True if the extended matrix has rank 3 (sway is controllable independently)."""
        return (
            self.n > 0
            and np.linalg.matrix_rank(self.extended, tol=1e-9 * max(1.0, np.abs(self.extended).max())) == 3
        )


def _row(t: Thruster, com) -> list[float]:
    az = t.azimuth
    return [
        t.position[0] - com[0], t.position[1] - com[1], math.radians(t.mount_yaw_deg), 1.0 if az else 0.0,
        math.radians(az.min_deg) if az else 0.0, math.radians(az.max_deg) if az else 0.0,
        math.radians(az.max_rate_deg_s) if az else 0.0, az.time_constant_s if az else 0.0,
        t.thrust.max_forward_n, t.thrust.max_reverse_n, t.max_rate_n_s or math.inf, MAP_CODES[t.thrust.type], 1.0,
    ]  # fmt: skip


def extended_matrix(params: np.ndarray) -> np.ndarray:
    """(3, m) configuration matrix of the extended thrust vector (fixed: 1 column, azimuth: 2)."""
    cols = []
    for row in params:
        x, y = row[X], row[Y]
        if row[IS_AZ]:
            cols += [(1.0, 0.0, -y), (0.0, 1.0, x)]
        else:
            c, s = math.cos(row[MOUNT]), math.sin(row[MOUNT])
            cols.append((c, s, x * s - y * c))
    return np.array(cols, dtype=float).reshape(-1, 3).T


def thrust_matrix(params: np.ndarray, angle_rad: np.ndarray) -> np.ndarray:
    """(3, n) matrix mapping signed thrusts to τ at the given azimuth angles (fixed thrusters: angle 0)."""
    theta = params[:, MOUNT] + np.where(params[:, IS_AZ] > 0, angle_rad, 0.0)
    c, s = np.cos(theta), np.sin(theta)
    return np.vstack([c, s, params[:, X] * s - params[:, Y] * c])


def weighted_pseudo_inverse(extended: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """P = W⁻¹ Bᵀ (B W⁻¹ Bᵀ)⁻¹ (m, 3): the minimizer of fᵀ W f subject to B f = τ is f = P τ.
    For a rank-deficient B (e.g. no sway authority) the Moore–Penrose inverse of B W^-1/2 is used."""
    w_inv_sqrt = 1.0 / np.sqrt(np.asarray(weights, dtype=float))
    return w_inv_sqrt[:, None] * np.linalg.pinv(extended * w_inv_sqrt[None, :], rcond=1e-10)


def extended_weights(params: np.ndarray) -> np.ndarray:
    """Per-column weights of the extended vector: a thruster's weight over its max forward thrust squared
    (so that thrusters are used in proportion to their size)."""
    out = []
    for row in params:
        w = max(row[WEIGHT], 1e-9) / row[T_FWD] ** 2
        out += [w, w] if row[IS_AZ] else [w]
    return np.array(out)
