"""The seed's state-space drag (thesis §4.2.7) with sway-yaw coupling, all bodies in one kernel.

Velocities are relative to the water, in the body frame FLU at the centre of mass: (u, v, w) m/s and
(p, q, r) rad/s. The returned wrench (N, N m) is in the same frame, about the CoM.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from usvsim.config.vessel import StateSpaceDrag

FIELDS = (
    "X_u", "X_uu", "X_uuu", "Y_v", "Y_vv", "Y_vvv", "Y_r", "Z_w", "Z_ww",
    "K_p", "K_pp", "M_q", "M_qq", "N_r", "N_rr", "N_rrr", "N_v",
)  # fmt: skip


def coefficients(models: list[StateSpaceDrag]) -> np.ndarray:
    """(nb, 17) coefficient table in FIELDS order."""
    return np.array([[getattr(m, f) for f in FIELDS] for m in models], dtype=float).reshape(len(models), 17)


@njit(cache=True)
def drag_wrench(c, nu, out):
    """out[i] = -D(nu[i]) nu[i]: the damping wrench of body i for its relative velocity nu[i] (6,)."""
    for i in range(nu.shape[0]):
        u, v, w, p, q, r = nu[i, 0], nu[i, 1], nu[i, 2], nu[i, 3], nu[i, 4], nu[i, 5]
        k = c[i]
        out[i, 0] = -(k[0] * u + k[1] * abs(u) * u + k[2] * u * u * u)
        out[i, 1] = -(k[3] * v + k[4] * abs(v) * v + k[5] * v * v * v + k[6] * r)
        out[i, 2] = -(k[7] * w + k[8] * abs(w) * w)
        out[i, 3] = -(k[9] * p + k[10] * abs(p) * p)
        out[i, 4] = -(k[11] * q + k[12] * abs(q) * q)
        out[i, 5] = -(k[13] * r + k[14] * abs(r) * r + k[15] * r * r * r + k[16] * v)
