"""Exact inverses of the thruster maps of `usvsim.hydro.thrusters.thrust_map`: thrust (N) → command u.

Closed forms per map: linear u = T/max, quadratic u = sign(T) sqrt(|T|/max), and the generalized
logistic (GLF) solved for u analytically. Thrusts beyond the map's range give u = ±1.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from usvsim.hydro.thrusters import GLF_FORWARD, GLF_REVERSE, MAP_CODES, _glf

__all__ = ["MAP_CODES", "command_for_thrust", "command_for_thrust_array"]


@njit(cache=True)
def _glf_inverse(y, a, k, b, nu, c, m):
    """u with _glf(u) = y (the GLF is strictly monotone between its asymptotes a and k)."""
    ratio = (k - a) / (y - a)
    if ratio <= 0.0:
        return math.inf if k > a else -math.inf
    e = ratio**nu - c
    if e <= 0.0:
        return math.inf if b > 0 else -math.inf
    return m - math.log(e) / b


@njit(cache=True)
def command_for_thrust(thrust_n, kind, max_fwd, max_rev):
    """Normalized command u in [-1, 1] whose steady thrust is `thrust_n` (N); saturates at ±1."""
    if thrust_n == 0.0:
        return 0.0
    fwd = thrust_n > 0.0
    scale = max_fwd if fwd else max_rev
    x = abs(thrust_n) / scale
    if x >= 1.0:
        return 1.0 if fwd else -1.0
    if kind == 0:
        u = x
    elif kind == 1:
        u = math.sqrt(x)
    else:
        a, k, b, nu, c, m = GLF_FORWARD if fwd else GLF_REVERSE
        f0 = _glf(0.0, a, k, b, nu, c, m)
        f1 = _glf(1.0 if fwd else -1.0, a, k, b, nu, c, m)
        y = f0 + (thrust_n / scale) * abs(f1 - f0)
        u = abs(_glf_inverse(y, a, k, b, nu, c, m))
    u = min(u, 1.0)
    return u if fwd else -u


@njit(cache=True)
def command_for_thrust_array(thrust_n, kind, max_fwd, max_rev, out):
    for i in range(thrust_n.shape[0]):
        out[i] = command_for_thrust(thrust_n[i], int(kind[i]), max_fwd[i], max_rev[i])
    return out


def commands(thrust_n, kinds, max_fwd, max_rev) -> np.ndarray:
    """Vectorized `command_for_thrust` over arrays (kinds as `MAP_CODES` integers)."""
    t = np.asarray(thrust_n, dtype=float)
    out = np.empty_like(t)
    return command_for_thrust_array(t, np.asarray(kinds, dtype=np.int64), np.asarray(max_fwd, float),
                                    np.asarray(max_rev, float), out)  # fmt: skip
