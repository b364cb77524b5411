"""Numba kernel of the velocity controller (method and API in `usvsim.control.velocity`).

`p` (3, N_AXIS) per-axis parameters, `s` (N_STATE,) controller state, `drag` (17,) damping coefficients.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from usvsim.control.plant import damping_force, damping_slope

# per-axis parameter columns
INERTIA, KP, LAMBDA, KI, W_REF, A_MAX, V_MAX, I_MAX, ACTIVE, AW_RATE = range(10)
N_AXIS = 10
# state layout
X_REF, A_REF, INTEG, TAU_CMD, STARTED = 0, 3, 6, 9, 12
N_STATE = 13


@njit(cache=True)
def _reference(p, s, cmd, nu, dt):
    """Critically damped second-order reference per axis with acceleration and velocity limits."""
    for k in range(3):
        if p[k, ACTIVE] == 0.0:
            s[X_REF + k], s[A_REF + k] = nu[k], 0.0
            continue
        target = min(max(cmd[k], -p[k, V_MAX]), p[k, V_MAX])
        w = p[k, W_REF]
        jerk = w * w * (target - s[X_REF + k]) - 2.0 * w * s[A_REF + k]
        a = min(max(s[A_REF + k] + dt * jerk, -p[k, A_MAX]), p[k, A_MAX])
        s[A_REF + k] = a
        s[X_REF + k] += dt * a


@njit(cache=True)
def velocity_step(p, drag, s, nu, cmd, dt, use_coriolis, tau):
    """One controller update: τ = M a_ref + C(ν_ff)ν_ff + D(ν_ff)ν_ff + Kp e + ∫Ki e (per active axis).
    ν_ff is the reference velocity (the measured one on inactive axes)."""
    if s[STARTED] == 0.0:
        for k in range(3):
            s[X_REF + k], s[A_REF + k], s[INTEG + k] = nu[k], 0.0, 0.0
        s[STARTED] = 1.0
    _reference(p, s, cmd, nu, dt)
    u, v, r = s[X_REF], s[X_REF + 1], s[X_REF + 2]
    ff, slope = np.empty(3), np.empty(3)
    damping_force(drag, u, v, r, ff)
    damping_slope(drag, u, v, r, slope)
    if use_coriolis:
        ff[0] -= p[0, INERTIA] * v * r
        ff[1] += p[1, INERTIA] * u * r
    for k in range(3):
        if p[k, ACTIVE] == 0.0:
            tau[k] = 0.0
            s[TAU_CMD + k] = 0.0
            continue
        e = s[X_REF + k] - nu[k]
        lam, m = p[k, LAMBDA], p[k, INERTIA]
        ki = p[k, KI] if p[k, KI] >= 0.0 else lam * max(slope[k], 0.25 * lam * m)
        integ = s[INTEG + k] + ki * e * dt
        s[INTEG + k] = min(max(integ, -p[k, I_MAX]), p[k, I_MAX])
        tau[k] = m * s[A_REF + k] + ff[k] + p[k, KP] * e + s[INTEG + k]
        s[TAU_CMD + k] = tau[k]


@njit(cache=True)
def back_calculate(p, s, tau_achieved, dt):
    """Anti-windup: move each integrator toward what the actuators delivered, at rate AW_RATE (1/s)."""
    for k in range(3):
        if p[k, ACTIVE] != 0.0:
            gain = min(1.0, p[k, AW_RATE] * dt)
            s[INTEG + k] += gain * (tau_achieved[k] - s[TAU_CMD + k])
