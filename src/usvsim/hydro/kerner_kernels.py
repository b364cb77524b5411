"""Kerner's hydrodynamic forces per submerged (sub)triangle, all bodies in one numba call.

Reference: physics.md §1.2 (cutting), §1.5 (viscous), §1.6 (pressure/suction), §1.7 (slamming),
§1.8 (air). Frames and units: world ENU (z up), SI. Every velocity is taken at the centroid of the
(sub)triangle it acts on: v = v_com + ω × (c - x_com) minus the water velocity there (waves plus
current, interpolated linearly from the per-vertex values the caller sampled) — or minus the wind
for the dry part. Forces act at those centroids; torques are about each body's centre of mass.

The water is planar over each hull triangle (cut points are linear interpolations of the vertex
heights, exactly as in `hydrostatics.py`, whose `_cut` helper is reused). A cut face gives one or
two submerged pieces, described by barycentric centroids in the parent triangle, so position and
water velocity (both affine over the face) come out of the same weights. The dry part of a face is
handled as one piece (its centroid = the parent's minus the submerged part's, area weighted).

Performance layout (the arithmetic of each term is that of the formulas above; only the order of
work changes):
- per face, the rigid-motion invariants are precomputed once (`face_geometry`: area, 0.5/area for
  the unit normal from the world cross product, 1/area, the dry centroid weight);
- per body, a pass over its vertex heights classifies it: entirely above water (air drag only),
  entirely below (no cutting), or crossing; per face, three paths: whole and wet (the common
  case, straight-line code), whole and dry (air only), cut (general pieces);
- divisions by per-body constants (v_R, Γ_max, S, dt) are multiplications by their reciprocals,
  and the slamming of a whole wet face reuses the drag's speed and cos θ; these change results
  by a few ulps per term (tests hold them to 1e-12 relative against the reference formulas);
- |cos θ|^f is taken for all pieces at once by a vectorized np.power between two kernel calls
  (fast paths f = 1, 2, 1/2 stay inline); the pressure sums follow in face order;
- bodies are independent: `kerner_wrenches_parallel` spreads them over threads (prange over
  bodies, each body's sums written by one thread), bit-identical to the serial entry point.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from usvsim.hydro.hydrostatics import _cut

# Columns of the per-body coefficient table (see kerner.py for units and defaults)
RHO, NU, FORM_K, CPD1, CPD2, FP, CSD1, CSD2, FS, VREF = 0, 1, 2, 3, 4, 5, 6, 7, 8, 9
SLAM_P, SLAM_GMAX, SLAM_SCALE, RHO_AIR, C_AIR = 10, 11, 12, 13, 14
VISC_SCALE, PRES_SCALE, AIR_SCALE, RN_MIN, LENGTH, MASS, AREA = 15, 16, 17, 18, 19, 20, 21
N_COEF = 22
# Rows of the per-body output table out[b, k, 0:6] = (force, torque)
VISCOUS, PRESSURE, SLAMMING, AIR = 0, 1, 2, 3
# Columns of the per-face geometry table (rigid-motion invariant, see face_geometry)
G_AREA, G_HALF_INV_AREA, G_INV_AREA, G_THIRD = 0, 1, 2, 3
N_GEOM = 4

_ZERO3 = (0.0, 0.0, 0.0)
_ZERO6 = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
_THIRD = 1.0 / 3.0


def face_geometry(face_area: np.ndarray) -> np.ndarray:
    """Per-face table (Nf, N_GEOM): area m², 0.5/area (unit normal = cross product × this) 1/m²,
    1/area 1/m², and (area/3)/area, the centroid weight of a whole dry face; zeros for area 0."""
    a = np.asarray(face_area, dtype=np.float64)
    pos = a > 0.0
    safe = np.where(pos, a, 1.0)
    geom = np.zeros((len(a), N_GEOM))
    geom[:, G_AREA] = a
    geom[:, G_HALF_INV_AREA] = np.where(pos, 0.5 / safe, 0.0)
    geom[:, G_INV_AREA] = np.where(pos, 1.0 / safe, 0.0)
    geom[:, G_THIRD] = np.where(pos, (safe / 3.0) / safe, 0.0)
    return np.ascontiguousarray(geom)


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


@njit(cache=True, inline="always")
def _fast_power(f):
    """True for the exponents _pow evaluates without pow (their pressure pieces skip the batch)."""
    return f == 1.0 or f == 2.0 or f == 0.5


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
def _slam_scalar(a, vx, vy, vz, c, sp0, sp1, sp2, inv_adt, sk):
    """Slamming (§1.7) multiplier s (force = s v) of a piece of area a moving at v with cos θ = c >= 0,
    given the previous A'v' = sp: Γ = |A v - A'v'| / (A_total dt) (inv_adt = 1/(A_total dt));
    sk = (p, 1/Γmax, 2 m / S)."""
    dx, dy, dz = a * vx - sp0, a * vy - sp1, a * vz - sp2
    ratio = min(math.sqrt(dx * dx + dy * dy + dz * dz) * inv_adt * sk[1], 1.0)
    return -_pow(ratio, sk[0]) * c * (sk[2] * a)


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
def _record_pressure(prec, pexp, slot, pr, n, r):
    """Store one pressure piece: k, |cos θ|^f (or |cos θ| with pexp = f when f needs pow), n, r."""
    k, c, f = pr
    fast = _fast_power(f)
    prec[slot, 0], prec[slot, 1] = k, _pow(c, f) if fast else c
    prec[slot, 2], prec[slot, 3], prec[slot, 4] = n[0], n[1], n[2]
    prec[slot, 5], prec[slot, 6], prec[slot, 7] = r[0], r[1], r[2]
    pexp[slot] = 0.0 if fast else f


@njit(cache=True, inline="always")
def _body_constants(b, coef, vcom, omega, water_vel_com, wind, dt):
    """Per-body inputs of the face loop: velocities, drag/slamming constants, scales."""
    k = coef[b]
    vc, om, wd = (vcom[b, 0], vcom[b, 1], vcom[b, 2]), (omega[b, 0], omega[b, 1], omega[b, 2]), (wind[b, 0], wind[b, 1], wind[b, 2])
    dx, dy, dz = vc[0] - water_vel_com[b, 0], vc[1] - water_vel_com[b, 1], vc[2] - water_vel_com[b, 2]
    c_f = friction_coefficient(math.sqrt(dx * dx + dy * dy + dz * dz), k[LENGTH], k[NU], k[RN_MIN])
    k_visc = 0.5 * k[RHO] * c_f * (1.0 + k[FORM_K]) * k[VISC_SCALE]
    pc = (k[CPD1], k[CPD2], k[FP], k[CSD1], k[CSD2], k[FS], 1.0 / k[VREF])
    sk = (k[SLAM_P], 1.0 / k[SLAM_GMAX], 2.0 * k[MASS] / k[AREA])
    # (pressure scale, air scale, rho_air C_air, slamming scale, 1/dt)
    scales = (k[PRES_SCALE], k[AIR_SCALE], k[RHO_AIR] * k[C_AIR], k[SLAM_SCALE], 1.0 / dt)
    return vc, om, wd, k_visc, pc, sk, scales


@njit(cache=True, inline="always")
def _height_bounds(vertices, eta, v0, v1):
    """min, max of the height above water z - eta over vertices v0:v1 (m)."""
    lo, hi = math.inf, -math.inf
    for i in range(v0, v1):
        h = vertices[i, 2] - eta[i]
        lo = min(lo, h)
        hi = max(hi, h)
    return lo, hi


# (fastmath "contract", i.e. FMAs, measured ~5 % faster but breaks the exact mirror symmetry
# the moving-sphere test checks, so the face loop stays IEEE-exact, like the previous kernel.)
@njit(cache=True)
def _body_wrenches(b, vertices, faces, geom, face_offsets, vert_offsets, eta, water_vel, com, vcom, omega,
                   water_vel_com, wind, coef, dt, slam_ready, swept_prev, swept, out, prec, pexp, n_pieces):  # fmt: skip
    """Kerner forces on body b (arguments as in kerner_wrenches): writes out[b] (pressure: see
    pressure_wrenches), the swept rows and the body's pressure pieces from slot 2 face_offsets[b]."""
    vc, om, wd, k_visc, pc, sk, scales = _body_constants(b, coef, vcom, omega, water_vel_com, wind, dt)
    slam_on = slam_ready and scales[3] != 0.0
    air_on = scales[1] != 0.0
    cx, cy, cz = com[b, 0], com[b, 1], com[b, 2]
    lo, hi = _height_bounds(vertices, eta, vert_offsets[b], vert_offsets[b + 1])
    all_dry, all_wet = lo > 0.0, hi <= 0.0
    visc = slam = air = _ZERO6
    slot = 2 * face_offsets[b]  # each face gives at most two pressure pieces
    for f in range(face_offsets[b], face_offsets[b + 1]):
        i0, i1, i2 = faces[f, 0], faces[f, 1], faces[f, 2]
        area = geom[f, G_AREA]
        h0, h1, h2 = vertices[i0, 2] - eta[i0], vertices[i1, 2] - eta[i1], vertices[i2, 2] - eta[i2]
        n_below = 3 if all_wet else (0 if all_dry else (h0 <= 0.0) + (h1 <= 0.0) + (h2 <= 0.0))
        dry = n_below == 0 or (n_below == 1 and min(h0, h1, h2) == 0.0)  # or touching at one vertex
        if dry and not air_on:
            swept[f, 0] = swept[f, 1] = swept[f, 2] = 0.0
            continue
        # positions relative to the CoM (m), world axes
        r0 = (vertices[i0, 0] - cx, vertices[i0, 1] - cy, vertices[i0, 2] - cz)
        r1 = (vertices[i1, 0] - cx, vertices[i1, 1] - cy, vertices[i1, 2] - cz)
        r2 = (vertices[i2, 0] - cx, vertices[i2, 1] - cy, vertices[i2, 2] - cz)
        n = _normal(r0, r1, r2, geom[f, G_HALF_INV_AREA])
        if dry:  # whole face in the air
            swept[f, 0] = swept[f, 1] = swept[f, 2] = 0.0
            if area > 0.0:
                r = _mean3(geom[f, G_THIRD], r0, r1, r2)
                air = _add(air, r, _air(r, area, vc, om, wd, n, scales[2]), scales[1])
            continue
        u0 = (water_vel[i0, 0], water_vel[i0, 1], water_vel[i0, 2])
        u1 = (water_vel[i1, 0], water_vel[i1, 1], water_vel[i1, 2])
        u2 = (water_vel[i2, 0], water_vel[i2, 1], water_vel[i2, 2])
        if n_below == 3:  # whole face under water: one piece, the face itself
            r, w = _mean3(_THIRD, r0, r1, r2), _mean3(_THIRD, u0, u1, u2)
            v = _rigid(r, vc, om)
            vx, vy, vz = v[0] - w[0], v[1] - w[1], v[2] - w[2]
            fv, pr, cos = _drag(vx, vy, vz, n, area, k_visc, pc)
            visc = _add(visc, r, fv, 1.0)
            _record_pressure(prec, pexp, slot, pr, n, r)
            slot += 1
            if slam_on and cos >= 0.0 and area > 0.0:
                inv_adt = geom[f, G_INV_AREA] * scales[4]
                s = _slam_scalar(area, vx, vy, vz, cos, swept_prev[f, 0], swept_prev[f, 1], swept_prev[f, 2], inv_adt, sk)
                slam = _acc(slam, r, (s * vx, s * vy, s * vz), scales[3])
            swept[f, 0], swept[f, 1], swept[f, 2] = area * vx, area * vy, area * vz
            continue
        # cut face: one or two submerged pieces, the rest in the air
        count, p1, p2 = _pieces(r0, r1, r2, h0, h1, h2, n_below)
        fvis, a_sub, sr, sv, sl = _ZERO6, 0.0, _ZERO3, _ZERO3, _ZERO3
        for j in range(count):
            piece = p1 if j == 0 else p2
            a = piece[3] * area
            r, w = _lerp3(piece, r0, r1, r2), _lerp3(piece, u0, u1, u2)
            v = _rigid(r, vc, om)
            vx, vy, vz = v[0] - w[0], v[1] - w[1], v[2] - w[2]
            fv, pr, _ = _drag(vx, vy, vz, n, a, k_visc, pc)
            fvis = _acc(fvis, r, fv, 1.0)
            _record_pressure(prec, pexp, slot, pr, n, r)
            slot += 1
            a_sub += a
            sr = (sr[0] + a * r[0], sr[1] + a * r[1], sr[2] + a * r[2])
            sv = (sv[0] + a * vx, sv[1] + a * vy, sv[2] + a * vz)
            sl = (sl[0] + a * piece[0], sl[1] + a * piece[1], sl[2] + a * piece[2])
        visc = (visc[0] + fvis[0], visc[1] + fvis[1], visc[2] + fvis[2], visc[3] + fvis[3], visc[4] + fvis[4],
                visc[5] + fvis[5])  # fmt: skip
        a_dry = area - a_sub
        if air_on and a_dry > 1e-9 * area:  # the dry remainder, one piece at its centroid
            third = area / 3.0
            l_dry = ((third - sl[0]) / a_dry, (third - sl[1]) / a_dry, (third - sl[2]) / a_dry)
            r = _lerp3(l_dry, r0, r1, r2)
            air = _add(air, r, _air(r, a_dry, vc, om, wd, n, scales[2]), scales[1])
        if slam_on and a_sub > 0.0:  # on the area-weighted mean velocity of the submerged part
            inv = 1.0 / a_sub
            fs = slamming_force(a_sub, sv[0] * inv, sv[1] * inv, sv[2] * inv,
                                (swept_prev[f, 0], swept_prev[f, 1], swept_prev[f, 2]), area, dt,
                                n[0], n[1], n[2], coef[b, MASS], coef[b, AREA], sk[0], coef[b, SLAM_GMAX])  # fmt: skip
            slam = _acc(slam, (sr[0] * inv, sr[1] * inv, sr[2] * inv), fs, scales[3])
        swept[f, 0], swept[f, 1], swept[f, 2] = sv[0], sv[1], sv[2]
    n_pieces[b] = slot - 2 * face_offsets[b]
    for j in range(6):
        out[b, VISCOUS, j] = visc[j]
        out[b, SLAMMING, j] = slam[j]
        out[b, AIR, j] = air[j]


@njit(cache=True)
def kerner_wrenches(vertices, faces, geom, face_offsets, vert_offsets, eta, water_vel, com, vcom, omega,
                    water_vel_com, wind, coef, dt, slam_ready, swept_prev, swept, out, prec, pexp, n_pieces,
                    base, expo, first):  # fmt: skip
    """Kerner viscous, slamming and air forces of every body, and its pressure/suction pieces.

    Inputs (world ENU, SI; arrays float64 C-order): vertices (Nv,3) m; faces (Nf,3) uint32 outward
    CCW; geom (Nf, N_GEOM) per-face table from `face_geometry`; face_offsets (nb+1,) uint64;
    vert_offsets (nb+1,) int: body b owns vertices vert_offsets[b]:vert_offsets[b+1] (its faces
    index only those); eta (Nv,) water height at each vertex m; water_vel (Nv,3) water velocity
    (orbital + current) at each vertex m/s; com (nb,3) m; vcom (nb,3) CoM velocity m/s; omega (nb,3)
    angular velocity rad/s (world axes); water_vel_com (nb,3) water velocity at the CoM (for the
    Reynolds number) m/s; wind (nb,3) wind velocity m/s; coef (nb, N_COEF) per-body coefficients;
    dt s (slamming); slam_ready: False on the first step (no previous swept volume); swept_prev
    (Nf,3) A'v' from the previous step m³/s.
    Outputs, overwritten: swept (Nf,3) A·v of this step; out (nb,4,6) per body and force kind
    (VISCOUS, SLAMMING, AIR; PRESSURE comes from pressure_wrenches): force N and torque N·m about
    the CoM, world axes; the pressure pieces of body b in rows 2 face_offsets[b] + (0..n_pieces[b])
    of prec (2Nf, 8): (k, |cos θ|^f or |cos θ|, n, r) and pexp (2Nf,): f where |cos θ|^f is still to
    be taken, else 0; those are gathered into base, expo (2Nf,) by `pow_inputs`, whose count is
    returned.

    |cos θ|^f is left to one vectorized np.power(base[:q], expo[:q]) over all pieces (a pow call
    per piece inside the face loop costs about 4x more); `pressure_wrenches` then forms the
    pressure sums in face order.
    """
    for b in range(face_offsets.shape[0] - 1):
        _body_wrenches(b, vertices, faces, geom, face_offsets, vert_offsets, eta, water_vel, com, vcom, omega,
                       water_vel_com, wind, coef, dt, slam_ready, swept_prev, swept, out, prec, pexp,
                       n_pieces)  # fmt: skip
    return pow_inputs(face_offsets, n_pieces, prec, pexp, base, expo, first)


@njit(cache=True, parallel=True)
def kerner_wrenches_parallel(vertices, faces, geom, face_offsets, vert_offsets, eta, water_vel, com, vcom, omega,
                             water_vel_com, wind, coef, dt, slam_ready, swept_prev, swept, out, prec, pexp,
                             n_pieces, base, expo, first):  # fmt: skip
    """kerner_wrenches with the bodies spread over numba's threads. Each body is summed by one
    thread in face order, so the results are bit-identical to the serial call, run to run."""
    for b in prange(face_offsets.shape[0] - 1):
        _body_wrenches(b, vertices, faces, geom, face_offsets, vert_offsets, eta, water_vel, com, vcom, omega,
                       water_vel_com, wind, coef, dt, slam_ready, swept_prev, swept, out, prec, pexp,
                       n_pieces)  # fmt: skip
    return pow_inputs(face_offsets, n_pieces, prec, pexp, base, expo, first)


@njit(cache=True)
def pow_inputs(face_offsets, n_pieces, prec, pexp, base, expo, first):
    """Gather the pieces whose |cos θ|^f is still to be taken into base, expo (compact, body by
    body, face order); first (nb+1,) the start of each body's run. Returns their count."""
    q = 0
    for b in range(face_offsets.shape[0] - 1):
        first[b] = q
        for p in range(2 * face_offsets[b], 2 * face_offsets[b] + n_pieces[b]):
            if pexp[p] != 0.0:
                base[q], expo[q] = prec[p, 1], pexp[p]
                q += 1
    first[face_offsets.shape[0] - 1] = q
    return q


@njit(cache=True, inline="always")
def _body_pressure(b, face_offsets, n_pieces, prec, pexp, powed, first, coef, out, force, torque):
    """Pressure/suction wrench of body b: Σ (scale k |cos θ|^f n, r × ...) over its pieces in order."""
    scale = coef[b, PRES_SCALE]
    pres = _ZERO6
    q = first[b]
    for p in range(2 * face_offsets[b], 2 * face_offsets[b] + n_pieces[b]):
        fall = prec[p, 1]
        if pexp[p] != 0.0:
            fall = powed[q]
            q += 1
        m = prec[p, 0] * fall
        pres = _add(pres, (prec[p, 5], prec[p, 6], prec[p, 7]), (m * prec[p, 2], m * prec[p, 3], m * prec[p, 4]), scale)
    for j in range(6):
        out[b, PRESSURE, j] = pres[j]
    for j in range(3):  # totals over the kinds, in kind order
        force[b, j] = out[b, 0, j] + out[b, 1, j] + out[b, 2, j] + out[b, 3, j]
        torque[b, j] = out[b, 0, j + 3] + out[b, 1, j + 3] + out[b, 2, j + 3] + out[b, 3, j + 3]


@njit(cache=True)
def pressure_wrenches(face_offsets, n_pieces, prec, pexp, powed, first, coef, out, force, torque):
    """out[:, PRESSURE] from the pieces of kerner_wrenches (powed: |cos θ|^f of its pow inputs), then
    the totals force (nb,3) N and torque (nb,3) N·m over the four kinds."""
    for b in range(face_offsets.shape[0] - 1):
        _body_pressure(b, face_offsets, n_pieces, prec, pexp, powed, first, coef, out, force, torque)


@njit(cache=True, parallel=True)
def pressure_wrenches_parallel(face_offsets, n_pieces, prec, pexp, powed, first, coef, out, force, torque):
    """pressure_wrenches over numba's threads, one body per thread (bit-identical to the serial)."""
    for b in prange(face_offsets.shape[0] - 1):
        _body_pressure(b, face_offsets, n_pieces, prec, pexp, powed, first, coef, out, force, torque)
