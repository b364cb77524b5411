"""Wind loads on the above-water hull from the wind relative to the vessel (body frame FLU, CoM).

Two lumped forms (per-triangle air drag is the AIR part of `kerner.py`, physics.md §1.8):
- FOSSEN (Fossen 2021 §10.1, with his simple coefficient shapes): with the boat's velocity
  relative to the air u_r = R^T (v_com - v_wind) (FLU), V_r² = u_r² + v_r² (horizontal),
  γ = atan2(v_r, u_r) (the angle Fossen writes -atan2(v_rw, u_rw) in FRD), q = ½ rho_air V_r²:
      X = -q A_F c_x cos γ,   Y = -q A_L c_y sin γ,   N = -q A_L L c_n sin 2γ
  (FLU; in FRD Y and N change sign, which is Fossen's C_Y = c_y sin γ, C_N = c_n sin 2γ).
  Quadratic in speed, with air density — unlike the seed (linear in V, no density).
  Typical c_x 0.50-0.90, c_y 0.70-0.95, c_n 0.05-0.20 (Fossen's table for ships).
- VRX (usv wind plugin form): apparent wind w = R^T (v_wind - v_com) (FLU),
      X = c_x |w_x| w_x,   Y = c_y |w_y| w_y,   N = -2 c_n w_x w_y   (coefficients in kg/m, kg).
Both act at the CoM; no vertical force, no roll/pitch moment.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

FOSSEN, VRX = 0, 1
# coefficient columns: A_F m², A_L m², L m, c_x, c_y, c_n


@njit(cache=True)
def wind_wrenches(kind, coef, rho_air, rot, vcom_world, wind_world, out):
    """out (nb,6): wind force N and moment N·m, body frame FLU, about the CoM, per body.

    kind (nb,) int (FOSSEN/VRX); coef (nb,6); rot (nb,3,3) body → world; vcom_world, wind_world
    (nb,3) m/s (ENU)."""
    for b in range(rot.shape[0]):
        dx = vcom_world[b, 0] - wind_world[b, 0]
        dy = vcom_world[b, 1] - wind_world[b, 1]
        dz = vcom_world[b, 2] - wind_world[b, 2]
        u = rot[b, 0, 0] * dx + rot[b, 1, 0] * dy + rot[b, 2, 0] * dz  # boat relative to the air, FLU
        v = rot[b, 0, 1] * dx + rot[b, 1, 1] * dy + rot[b, 2, 1] * dz
        for j in range(6):
            out[b, j] = 0.0
        a_f, a_l, length, cx, cy, cn = coef[b, 0], coef[b, 1], coef[b, 2], coef[b, 3], coef[b, 4], coef[b, 5]
        if kind[b] == FOSSEN:
            q = 0.5 * rho_air * (u * u + v * v)
            gamma = math.atan2(v, u)
            out[b, 0] = -q * a_f * cx * math.cos(gamma)
            out[b, 1] = -q * a_l * cy * math.sin(gamma)
            out[b, 5] = -q * a_l * length * cn * math.sin(2.0 * gamma)
        else:
            wx, wy = -u, -v  # apparent wind
            out[b, 0] = cx * abs(wx) * wx
            out[b, 1] = cy * abs(wy) * wy
            out[b, 5] = -2.0 * cn * wx * wy


def coefficient_row(cfg) -> tuple[int, np.ndarray]:
    """(kind, coef row) of a `config.hydro_models.WindLoad` section."""
    kind = FOSSEN if cfg.type == "fossen" else VRX
    return kind, np.array([cfg.frontal_area_m2, cfg.lateral_area_m2, cfg.length_m, cfg.c_x, cfg.c_y, cfg.c_n])
