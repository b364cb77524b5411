"""Kerner force terms on one (sub)triangle: scalar numba helpers for `kerner_kernels`' face loop.

Reference: physics.md §1.2 (cutting), §1.5 (viscous), §1.6 (pressure/suction), §1.7 (slamming),
§1.8 (air). Frames and units: world ENU (z up), SI; positions r are relative to the body's CoM,
velocities v relative to the water (or to the wind for dry parts). Vectors are 3-tuples, wrench
accumulators 6-tuples (force N, torque N·m about the CoM).
"""

from __future__ import annotations

import math

from numba import njit

from usvsim.hydro.hydrostatics import _cut

# Rows of the pressure-piece table (see _record_pressure): k n, k r × n, |cos θ|, falloff power f
P_FX, P_FY, P_FZ, P_TX, P_TY, P_TZ, P_COS, P_EXP = 0, 1, 2, 3, 4, 5, 6, 7
N_PIECE_ROWS = 8

_ZERO3 = (0.0, 0.0, 0.0)
_ZERO6 = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


@njit(cache=True)
def friction_coefficient(speed, length, nu, rn_min):
    """ITTC-1957 line C_F = 0.075 / (log10 Rn - 2)^2, Rn = speed·length/nu clamped to >= rn_min."""
    rn = max(speed * length / nu, rn_min)
    lg = math.log10(rn) - 2.0
    return 0.075 / (lg * lg)


@njit(cache=True, inline="always")
def _pow(c, f):
    """c**f for c >= 0 with the common powers (1, 2, 1/2) done without pow (exact as c**f)."""
    if f == 1.0:
        return c
    if f == 2.0:
        return c * c
    if f == 0.5:
        return math.sqrt(c)
    return c**f


@njit(cache=True)
def slamming_force(a_sub, vx, vy, vz, swept_prev, a_total, dt, nx, ny, nz, mass, hull_area, power, gamma_max):
    """Slamming (§1.7) on one face: -clamp(Γ/Γmax, 0, 1)^p cos θ · m v (2 A / S) when cos θ >= 0.

    a_sub, (vx, vy, vz): submerged area and its centroid velocity now; swept_prev: A'v' (3,) of
    the previous step; Γ = |A v - A'v'| / (A_total dt).
    """
    speed = math.sqrt(vx * vx + vy * vy + vz * vz)
    if a_sub <= 0.0 or speed <= 0.0:
        return 0.0, 0.0, 0.0
    c = (vx * nx + vy * ny + vz * nz) / speed
    if c < 0.0:
        return 0.0, 0.0, 0.0
    dx = a_sub * vx - swept_prev[0]  # swept_prev: (3,) tuple or array
    dy = a_sub * vy - swept_prev[1]
    dz = a_sub * vz - swept_prev[2]
    gamma = math.sqrt(dx * dx + dy * dy + dz * dz) / (a_total * dt)
    ratio = min(gamma / gamma_max, 1.0)
    s = -_pow(ratio, power) * c * mass * 2.0 * a_sub / hull_area
    return s * vx, s * vy, s * vz


@njit(cache=True, inline="always")
def _slam_scalar(a, vx, vy, vz, c, a_prev, inv_dt, sk):
    """Slamming multiplier s (force = s v) of a piece of area a moving at v with cos θ = c >= 0 whose face had
    a_prev submerged on the previous step. Time-step independent form of §1.7: the impulse over the step is
    -ramp · cos θ · m v (2 ΔA / S) with ΔA = max(a - a_prev, 0) the area wetted during the step (a flat face
    slapping the water at once gets its whole share of the stopping momentum m v 2A/S in one step, whatever
    the step), ramp = min(v cos θ / v_slam, 1)^p on the normal entry speed; force = impulse / dt.
    sk = (p, 1/v_slam, 2 m / S)."""
    da = a - a_prev
    if da <= 0.0:
        return 0.0
    speed = math.sqrt(vx * vx + vy * vy + vz * vz)
    ratio = min(c * speed * sk[1], 1.0)
    return -_pow(ratio, sk[0]) * c * sk[2] * da * inv_dt


@njit(cache=True, inline="always")
def _acc(acc, r, f, scale):
    """acc (6-tuple) + (scale f, r × scale f)."""
    fx, fy, fz = scale * f[0], scale * f[1], scale * f[2]
    return (acc[0] + fx, acc[1] + fy, acc[2] + fz, acc[3] + r[1] * fz - r[2] * fy,
            acc[4] + r[2] * fx - r[0] * fz, acc[5] + r[0] * fy - r[1] * fx)  # fmt: skip


@njit(cache=True, inline="always")
def _add(acc, r, f, scale):
    """acc (6-tuple) + (scale f, r × scale f), the face's moment formed before it is added."""
    fx, fy, fz = scale * f[0], scale * f[1], scale * f[2]
    return (acc[0] + fx, acc[1] + fy, acc[2] + fz, acc[3] + (r[1] * fz - r[2] * fy),
            acc[4] + (r[2] * fx - r[0] * fz), acc[5] + (r[0] * fy - r[1] * fx))  # fmt: skip


@njit(cache=True, inline="always")
def _lerp3(l, p0, p1, p2):
    """Barycentric combination l[0] p0 + l[1] p1 + l[2] p2 of three 3-tuples."""
    return (l[0] * p0[0] + l[1] * p1[0] + l[2] * p2[0], l[0] * p0[1] + l[1] * p1[1] + l[2] * p2[1],
            l[0] * p0[2] + l[1] * p1[2] + l[2] * p2[2])  # fmt: skip


@njit(cache=True, inline="always")
def _mean3(w, p0, p1, p2):
    """w p0 + w p1 + w p2 (one weight: a whole face's centroid with w = 1/3)."""
    return (w * p0[0] + w * p1[0] + w * p2[0], w * p0[1] + w * p1[1] + w * p2[1], w * p0[2] + w * p1[2] + w * p2[2])


@njit(cache=True, inline="always")
def _rigid(r, vc, om):
    """Velocity vc + om × r of the point r (relative to the CoM)."""
    return vc[0] + om[1] * r[2] - om[2] * r[1], vc[1] + om[2] * r[0] - om[0] * r[2], vc[2] + om[0] * r[1] - om[1] * r[0]


@njit(cache=True, inline="always")
def _in_face_order(apex, la, lb, lc):
    """Barycentric weights given for (apex, next, next-next) back in the face's own vertex order."""
    if apex == 0:
        return la, lb, lc
    if apex == 1:
        return lc, la, lb
    return lb, lc, la


@njit(cache=True, inline="always")
def _pieces(r0, r1, r2, h0, h1, h2, n_below):
    """Submerged pieces of a cut face (n_below = 1 or 2, not touching at one vertex only): count
    (1-2) and two (λ0, λ1, λ2, area fraction) in face order."""
    z = (0.0, 0.0, 0.0, 0.0)
    apex_below = n_below == 1
    if (h0 <= 0.0) == apex_below:
        apex, ra, rb, rc, ha, hb, hc = 0, r0, r1, r2, h0, h1, h2
    elif (h1 <= 0.0) == apex_below:
        apex, ra, rb, rc, ha, hb, hc = 1, r1, r2, r0, h1, h2, h0
    else:
        apex, ra, rb, rc, ha, hb, hc = 2, r2, r0, r1, h2, h0, h1
    _, tb, ub = _cut(ra, rb, ha, hb)  # I_b = u_b a + t_b b
    _, tc, uc = _cut(ra, rc, ha, hc)
    if apex_below:  # (a, J_b, J_c)
        return 1, (*_in_face_order(apex, (1.0 + ub + uc) / 3.0, tb / 3.0, tc / 3.0), tb * tc), z
    p1 = (*_in_face_order(apex, uc / 3.0, 1.0 / 3.0, (1.0 + tc) / 3.0), uc)  # (b, c, I_c)
    p2 = (*_in_face_order(apex, (uc + ub) / 3.0, (1.0 + tb) / 3.0, tc / 3.0), tc * ub)  # (b, I_c, I_b)
    return 2, p1, p2


@njit(cache=True, inline="always")
def _drag(vx, vy, vz, n, a, k_visc, pc):
    """Viscous (§1.5) and pressure/suction (§1.6) force on a piece of area a, unit normal n, moving at
    v relative to the water. Viscous: k_visc |v|² a u_f, u_f = -v_t/|v_t|, k_visc = ½ rho C_F (1+k).
    Pressure (cos θ = v̂·n > 0): -(C_PD1 v/v_R + C_PD2 (v/v_R)²) a cos^f_P n; suction (cos θ <= 0):
    +(C_SD1 v/v_R + C_SD2 (v/v_R)²) a |cos θ|^f_S n; pc = (C_PD1, C_PD2, f_P, C_SD1, C_SD2, f_S, 1/v_R).
    Returns (viscous force, (k, |cos θ|, f), cos θ) with the pressure force k |cos θ|^f n, k signed;
    cos θ = -1 when v = 0 (no force, no slamming)."""
    v2 = vx * vx + vy * vy + vz * vz
    if v2 <= 0.0:
        return _ZERO3, (0.0, 0.0, 1.0), -1.0
    speed = math.sqrt(v2)
    vn = vx * n[0] + vy * n[1] + vz * n[2]
    tx, ty, tz = vx - vn * n[0], vy - vn * n[1], vz - vn * n[2]
    t2 = tx * tx + ty * ty + tz * tz
    fv = _ZERO3
    if t2 > 1e-24:
        sv = -k_visc * a * v2 / math.sqrt(t2)
        fv = (sv * tx, sv * ty, sv * tz)
    cos, s = vn / speed, speed * pc[6]
    # pressure side (cos > 0) pushes against n, suction side pulls along it; selects, not branches
    pressure = cos > 0.0
    c1 = pc[0] if pressure else pc[3]
    c2 = pc[1] if pressure else pc[4]
    fall = pc[2] if pressure else pc[5]
    m = (c1 * s + c2 * s * s) * a
    return fv, (-m if pressure else m, abs(cos), fall), cos


@njit(cache=True, inline="always")
def _air(r, a_dry, vc, om, wind, n, rho_c):
    """Air drag (§1.8) on a dry part of area a_dry centred at r: -½ rho_air C_air A |v| v if it moves
    into the air (v relative to the wind); rho_c = rho_air C_air."""
    v = _rigid(r, vc, om)
    vx, vy, vz = v[0] - wind[0], v[1] - wind[1], v[2] - wind[2]
    if vx * n[0] + vy * n[1] + vz * n[2] <= 0.0:
        return _ZERO3
    s = -0.5 * rho_c * a_dry * math.sqrt(vx * vx + vy * vy + vz * vz)
    return s * vx, s * vy, s * vz


@njit(cache=True, inline="always")
def _normal(r0, r1, r2, half_inv_area):
    """Unit outward normal (r1 - r0) × (r2 - r0) / (2 A) of a CCW face."""
    ex, ey, ez = r1[0] - r0[0], r1[1] - r0[1], r1[2] - r0[2]
    fx, fy, fz = r2[0] - r0[0], r2[1] - r0[1], r2[2] - r0[2]
    return ((ey * fz - ez * fy) * half_inv_area, (ez * fx - ex * fz) * half_inv_area,
            (ex * fy - ey * fx) * half_inv_area)  # fmt: skip


@njit(cache=True, inline="always")
def _record_pressure(pieces, slot, pr, n, r):
    """Store one pressure piece in column `slot` of pieces (N_PIECE_ROWS, ·): k n, k r × n, |cos θ|, f
    (its force is |cos θ|^f k n, taken once for all pieces by `pressure_wrenches`)."""
    k, c, f = pr
    kx, ky, kz = k * n[0], k * n[1], k * n[2]
    pieces[P_FX, slot], pieces[P_FY, slot], pieces[P_FZ, slot] = kx, ky, kz
    pieces[P_TX, slot], pieces[P_TY, slot] = r[1] * kz - r[2] * ky, r[2] * kx - r[0] * kz
    pieces[P_TZ, slot], pieces[P_COS, slot], pieces[P_EXP, slot] = r[0] * ky - r[1] * kx, c, f
