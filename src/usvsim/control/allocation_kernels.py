"""Numba kernels of thrust allocation (see `usvsim.control.allocation` for the method and the API).

Packed arguments: `params` (n, 13) thruster rows (`usvsim.control.layout` columns), `P` (m, 3) the weighted
pseudo-inverse of the extended matrix, `cols` (n,) first extended column of each thruster. Output rows
`out` (n, 4): signed thrust [N], angle command [rad], effective angle [rad], normalized command u.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from usvsim.control.boxqp import box_qp
from usvsim.control.layout import (
    A_MAX,
    A_MIN,
    A_RATE,
    A_TAU,
    IS_AZ,
    MAP,
    MOUNT,
    T_FWD,
    T_RATE,
    T_REV,
    WEIGHT,
    X,
    Y,
)
from usvsim.control.thrust_inverse import command_for_thrust

THRUST, ANGLE_CMD, ANGLE_EFF, U = 0, 1, 2, 3


@njit(cache=True)
def wrap_pi(a):
    """Angle wrapped to [-π, π)."""
    return (a + math.pi) % (2.0 * math.pi) - math.pi


@njit(cache=True)
def _pick_angle(heading, mag, row, now, constrained, reverse_bias):
    """(angle, signed thrust) for a desired force of magnitude `mag` along body heading `heading`:
    forward at angle a1 or reverse at a1 + π, whichever the azimuth limits allow; the constrained
    allocator picks the feasible one closest to the current angle (reverse costs `reverse_bias` rad)."""
    a1 = wrap_pi(heading - row[MOUNT])
    a2 = wrap_pi(a1 + math.pi)
    ok1 = row[A_MIN] <= a1 <= row[A_MAX]
    ok2 = row[A_MIN] <= a2 <= row[A_MAX]
    if ok1 and ok2 and constrained:
        if abs(a2 - now) + reverse_bias < abs(a1 - now):
            return a2, -mag
        return a1, mag
    if ok1:
        return a1, mag
    if ok2:
        return a2, -mag
    return min(max(a1, row[A_MIN]), row[A_MAX]), mag


@njit(cache=True)
def desired(tau, params, P, cols, angle_now, constrained, reverse_bias, out):
    """Extended-thrust solution f = P τ turned into (signed thrust, angle) per thruster (rows of out)."""
    for i in range(params.shape[0]):
        c, row = cols[i], params[i]
        fx = P[c, 0] * tau[0] + P[c, 1] * tau[1] + P[c, 2] * tau[2]
        if row[IS_AZ] > 0.0:
            fy = P[c + 1, 0] * tau[0] + P[c + 1, 1] * tau[1] + P[c + 1, 2] * tau[2]
            mag = math.hypot(fx, fy)
            if mag <= 1e-9 * row[T_FWD]:
                out[i, ANGLE_CMD], out[i, THRUST] = angle_now[i], 0.0
            else:
                a, t = _pick_angle(math.atan2(fy, fx), mag, row, angle_now[i], constrained, reverse_bias)
                out[i, ANGLE_CMD], out[i, THRUST] = a, t
        else:
            out[i, ANGLE_CMD], out[i, THRUST] = 0.0, fx


@njit(cache=True)
def _column(row, angle, col):
    theta = row[MOUNT] + (angle if row[IS_AZ] > 0.0 else 0.0)
    c, s = math.cos(theta), math.sin(theta)
    col[0], col[1], col[2] = c, s, row[X] * s - row[Y] * c


@njit(cache=True)
def _servo(now, cmd, dt, tau, rate):
    """Azimuth angle after dt of the thruster's servo (first-order lag with a rate limit)."""
    step = (cmd - now) * (1.0 - math.exp(-dt / tau)) if tau > 0.0 else cmd - now
    limit = rate * dt
    return now + min(max(step, -limit), limit)


@njit(cache=True)
def _bounds(row, thrust_now, dt):
    lo, hi = -row[T_REV], row[T_FWD]
    if math.isfinite(row[T_RATE]) and dt > 0.0:
        lo, hi = max(lo, thrust_now - row[T_RATE] * dt), min(hi, thrust_now + row[T_RATE] * dt)
        if lo > hi:
            lo = hi = min(max(thrust_now, -row[T_REV]), row[T_FWD])
    return lo, hi


@njit(cache=True)
def finish(params, out, tau_out):
    """Normalized commands from the thrusts and τ at the effective angles."""
    tau_out[:] = 0.0
    col = np.empty(3)
    for i in range(params.shape[0]):
        row = params[i]
        out[i, U] = command_for_thrust(out[i, THRUST], int(row[MAP]), row[T_FWD], row[T_REV])
        t = min(max(out[i, THRUST], -row[T_REV]), row[T_FWD])
        _column(row, out[i, ANGLE_EFF], col)
        for k in range(3):
            tau_out[k] += col[k] * t


@njit(cache=True)
def allocate_unconstrained(tau, params, P, cols, angle_now, out, tau_out):
    """The seed's method: weighted pseudo-inverse, then angle and magnitude; no limits but the angle
    range. τ achieved (tau_out) is evaluated with thrusts clipped to the map's range."""
    desired(tau, params, P, cols, angle_now, False, 0.0, out)
    for i in range(params.shape[0]):
        out[i, ANGLE_EFF] = out[i, ANGLE_CMD]
    finish(params, out, tau_out)


@njit(cache=True)
def allocate_constrained(tau, params, P, cols, q, angle_now, thrust_now, dt, reverse_bias, out, tau_out):
    """Angles from the pseudo-inverse (limited to the azimuth range, reached through the servo's lag and
    rate limit over dt), then thrusts by box-constrained least squares at those effective angles:
    min (Bt - τ)ᵀ diag(q) (Bt - τ) + Σ w_i t_i² / T_max,i²  s.t.  thrust (and thrust-rate) bounds."""
    n = params.shape[0]
    desired(tau, params, P, cols, angle_now, True, reverse_bias, out)
    B = np.empty((3, n))
    lo, hi, z = np.empty(n), np.empty(n), np.empty(n)
    for i in range(n):
        row = params[i]
        if row[IS_AZ] > 0.0:
            out[i, ANGLE_EFF] = _servo(angle_now[i], out[i, ANGLE_CMD], dt, row[A_TAU], row[A_RATE])
        else:
            out[i, ANGLE_EFF] = 0.0
        _column(row, out[i, ANGLE_EFF], B[:, i])
        lo[i], hi[i] = _bounds(row, thrust_now[i], dt)
        z[i] = out[i, THRUST]
    H, g = np.empty((n, n)), np.empty(n)
    for i in range(n):
        g[i] = q[0] * B[0, i] * tau[0] + q[1] * B[1, i] * tau[1] + q[2] * B[2, i] * tau[2]
        for j in range(n):
            H[i, j] = q[0] * B[0, i] * B[0, j] + q[1] * B[1, i] * B[1, j] + q[2] * B[2, i] * B[2, j]
        H[i, i] += params[i, WEIGHT] / (params[i, T_FWD] * params[i, T_FWD])
    box_qp(H, g, lo, hi, z)
    for i in range(n):
        out[i, THRUST] = z[i]
    finish(params, out, tau_out)
