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
"""

from __future__ import annotations

import math

from numba import njit

from usvsim.hydro.hydrostatics import _cut

# Columns of the per-body coefficient table (see kerner.py for units and defaults)
RHO, NU, FORM_K, CPD1, CPD2, FP, CSD1, CSD2, FS, VREF = 0, 1, 2, 3, 4, 5, 6, 7, 8, 9
SLAM_P, SLAM_GMAX, SLAM_SCALE, RHO_AIR, C_AIR = 10, 11, 12, 13, 14
VISC_SCALE, PRES_SCALE, AIR_SCALE, RN_MIN, LENGTH, MASS, AREA = 15, 16, 17, 18, 19, 20, 21
N_COEF = 22
# Rows of the per-body output table out[b, k, 0:6] = (force, torque)
VISCOUS, PRESSURE, SLAMMING, AIR = 0, 1, 2, 3


@njit(cache=True)
def friction_coefficient(speed, length, nu, rn_min):
    """ITTC-1957 line C_F = 0.075 / (log10 Rn - 2)^2, Rn = speed·length/nu clamped to >= rn_min."""
    rn = max(speed * length / nu, rn_min)
    lg = math.log10(rn) - 2.0
    return 0.075 / (lg * lg)


@njit(cache=True, inline="always")
def _pow(c, f):
    """c**f for c >= 0 with the common powers (1, 2, 1/2) done without pow."""
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
def _acc(acc, r, f, scale):
    """acc (6-tuple) + (scale f, r × scale f)."""
    fx, fy, fz = scale * f[0], scale * f[1], scale * f[2]
    return (acc[0] + fx, acc[1] + fy, acc[2] + fz, acc[3] + r[1] * fz - r[2] * fy,
            acc[4] + r[2] * fx - r[0] * fz, acc[5] + r[0] * fy - r[1] * fx)  # fmt: skip


@njit(cache=True, inline="always")
def _lerp3(l, p0, p1, p2):
    """Barycentric combination l[0] p0 + l[1] p1 + l[2] p2 of three 3-tuples."""
    return (l[0] * p0[0] + l[1] * p1[0] + l[2] * p2[0], l[0] * p0[1] + l[1] * p1[1] + l[2] * p2[1],
            l[0] * p0[2] + l[1] * p1[2] + l[2] * p2[2])  # fmt: skip


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
    """Submerged pieces of a face: count (0-2) and two (λ0, λ1, λ2, area fraction) in face order."""
    z = (0.0, 0.0, 0.0, 0.0)
    if n_below == 0 or (n_below == 1 and min(h0, h1, h2) == 0.0):  # dry, or touching at one vertex
        return 0, z, z
    if n_below == 3:
        t = 1.0 / 3.0
        return 1, (t, t, t, 1.0), z
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
def _air(l_dry, a_dry, r0, r1, r2, vc, om, wind, n, rho_c):
    """Air drag (§1.8) on the dry part: -½ rho_air C_air A |v| v if it moves into the air. Returns (r, f)."""
    r = _lerp3(l_dry, r0, r1, r2)
    v = _rigid(r, vc, om)
    vx, vy, vz = v[0] - wind[0], v[1] - wind[1], v[2] - wind[2]
    if vx * n[0] + vy * n[1] + vz * n[2] <= 0.0:
        return r, (0.0, 0.0, 0.0)
    s = -0.5 * rho_c * a_dry * math.sqrt(vx * vx + vy * vy + vz * vz)
    return r, (s * vx, s * vy, s * vz)


@njit(cache=True, inline="always")
def _wet(piece, area, r0, r1, r2, u0, u1, u2, vc, om, n, k_visc, pc):
    """One submerged piece: (area, r, v relative to the water, viscous force, pressure force)."""
    a = piece[3] * area
    r = _lerp3(piece, r0, r1, r2)
    w = _lerp3(piece, u0, u1, u2)
    v = _rigid(r, vc, om)
    vx, vy, vz = v[0] - w[0], v[1] - w[1], v[2] - w[2]
    return a, r, (vx, vy, vz), *_drag(vx, vy, vz, n, a, k_visc, pc)


@njit(cache=True, inline="always")
def _drag(vx, vy, vz, n, a, k_visc, pc):
    """Viscous (§1.5) and pressure/suction (§1.6) force on a piece of area a, unit normal n, moving at
    v relative to the water. Viscous: k_visc |v|² a u_f, u_f = -v_t/|v_t|, k_visc = ½ rho C_F (1+k).
    Pressure (cos θ = v̂·n > 0): -(C_PD1 v/v_R + C_PD2 (v/v_R)²) a cos^f_P n; suction (cos θ <= 0):
    +(C_SD1 v/v_R + C_SD2 (v/v_R)²) a |cos θ|^f_S n; pc = (C_PD1, C_PD2, f_P, C_SD1, C_SD2, f_S, v_R)."""
    v2 = vx * vx + vy * vy + vz * vz
    if v2 <= 0.0:
        return (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)
    speed = math.sqrt(v2)
    vn = vx * n[0] + vy * n[1] + vz * n[2]
    tx, ty, tz = vx - vn * n[0], vy - vn * n[1], vz - vn * n[2]
    t2 = tx * tx + ty * ty + tz * tz
    fv = (0.0, 0.0, 0.0)
    if t2 > 1e-24:
        sv = -k_visc * a * v2 / math.sqrt(t2)
        fv = (sv * tx, sv * ty, sv * tz)
    cos, s = vn / speed, speed / pc[6]
    if cos > 0.0:
        m = -(pc[0] * s + pc[1] * s * s) * a * _pow(cos, pc[2])
    else:
        m = (pc[3] * s + pc[4] * s * s) * a * _pow(-cos, pc[5])
    return fv, (m * n[0], m * n[1], m * n[2])


@njit(cache=True, inline="always")
def _face(r0, r1, r2, h0, h1, h2, u0, u1, u2, area, vc, om, wind, k_visc, pc, scales):
    """Kerner forces on one face (positions r_k relative to the CoM, water velocities u_k).

    scales = (pressure scale, air scale, rho_air C_air). Returns (viscous, pressure, air)
    force/torque 6-tuples, the submerged area, Σ a r, Σ a v and the unit normal.
    """
    ex, ey, ez = r1[0] - r0[0], r1[1] - r0[1], r1[2] - r0[2]
    fx, fy, fz = r2[0] - r0[0], r2[1] - r0[1], r2[2] - r0[2]
    inv = 0.5 / area if area > 0.0 else 0.0
    n = ((ey * fz - ez * fy) * inv, (ez * fx - ex * fz) * inv, (ex * fy - ey * fx) * inv)
    n_below = (h0 <= 0.0) + (h1 <= 0.0) + (h2 <= 0.0)
    count, p1, p2 = _pieces(r0, r1, r2, h0, h1, h2, n_below)
    zero6 = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    visc, pres, a_sub, sr, sv, sl = zero6, zero6, 0.0, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)
    for j in range(count):
        piece = p1 if j == 0 else p2
        a, r, v, fv, fp = _wet(piece, area, r0, r1, r2, u0, u1, u2, vc, om, n, k_visc, pc)
        visc, pres = _acc(visc, r, fv, 1.0), _acc(pres, r, fp, scales[0])
        a_sub += a
        sr = (sr[0] + a * r[0], sr[1] + a * r[1], sr[2] + a * r[2])
        sv = (sv[0] + a * v[0], sv[1] + a * v[1], sv[2] + a * v[2])
        sl = (sl[0] + a * piece[0], sl[1] + a * piece[1], sl[2] + a * piece[2])
    air, a_dry = zero6, area - a_sub
    if a_dry > 1e-9 * area and scales[1] != 0.0:
        third = area / 3.0
        l_dry = ((third - sl[0]) / a_dry, (third - sl[1]) / a_dry, (third - sl[2]) / a_dry)
        r, f = _air(l_dry, a_dry, r0, r1, r2, vc, om, wind, n, scales[2])
        air = _acc(air, r, f, scales[1])
    return visc, pres, air, a_sub, sr, sv, n


@njit(cache=True, inline="always")
def _sum6(a, b):
    return a[0] + b[0], a[1] + b[1], a[2] + b[2], a[3] + b[3], a[4] + b[4], a[5] + b[5]


@njit(cache=True)
def _store(out, b, row, acc):
    for j in range(6):
        out[b, row, j] = acc[j]


@njit(cache=True)
def kerner_wrenches(vertices, faces, face_area, face_offsets, eta, water_vel, com, vcom, omega,
                    water_vel_com, wind, coef, dt, slam_ready, swept_prev, swept, out):
    """Kerner viscous, pressure/suction, slamming and air forces of every body, in one call.

    Inputs (world ENU, SI; arrays float64 C-order): vertices (Nv,3) m; faces (Nf,3) uint32 outward
    CCW; face_area (Nf,) m²; face_offsets (nb+1,) uint64; eta (Nv,) water height at each vertex m;
    water_vel (Nv,3) water velocity (orbital + current) at each vertex m/s; com (nb,3) m; vcom
    (nb,3) CoM velocity m/s; omega (nb,3) angular velocity rad/s (world axes); water_vel_com (nb,3)
    water velocity at the CoM (for the Reynolds number) m/s; wind (nb,3) wind velocity m/s; coef
    (nb, N_COEF) per-body coefficients; dt s (slamming); slam_ready: False on the first step (no
    previous swept volume); swept_prev (Nf,3) A'v' from the previous step m³/s.
    Outputs, overwritten: swept (Nf,3) A·v of this step; out (nb,4,6) per body and force kind
    (VISCOUS, PRESSURE, SLAMMING, AIR): force N and torque N·m about the CoM, world axes.
    """
    for b in range(face_offsets.shape[0] - 1):
        k = coef[b]
        cx, cy, cz = com[b, 0], com[b, 1], com[b, 2]
        vc, om, wd = (vcom[b, 0], vcom[b, 1], vcom[b, 2]), (omega[b, 0], omega[b, 1], omega[b, 2]), (wind[b, 0], wind[b, 1], wind[b, 2])
        dx, dy, dz = vc[0] - water_vel_com[b, 0], vc[1] - water_vel_com[b, 1], vc[2] - water_vel_com[b, 2]
        c_f = friction_coefficient(math.sqrt(dx * dx + dy * dy + dz * dz), k[LENGTH], k[NU], k[RN_MIN])
        k_visc = 0.5 * k[RHO] * c_f * (1.0 + k[FORM_K]) * k[VISC_SCALE]
        pc = (k[CPD1], k[CPD2], k[FP], k[CSD1], k[CSD2], k[FS], k[VREF])
        slam_on = slam_ready and k[SLAM_SCALE] != 0.0
        scales = (k[PRES_SCALE], k[AIR_SCALE], k[RHO_AIR] * k[C_AIR])
        visc = pres = slam = air = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
        for f in range(face_offsets[b], face_offsets[b + 1]):
            i0, i1, i2 = faces[f, 0], faces[f, 1], faces[f, 2]
            r0 = (vertices[i0, 0] - cx, vertices[i0, 1] - cy, vertices[i0, 2] - cz)
            r1 = (vertices[i1, 0] - cx, vertices[i1, 1] - cy, vertices[i1, 2] - cz)
            r2 = (vertices[i2, 0] - cx, vertices[i2, 1] - cy, vertices[i2, 2] - cz)
            u0 = (water_vel[i0, 0], water_vel[i0, 1], water_vel[i0, 2])
            u1 = (water_vel[i1, 0], water_vel[i1, 1], water_vel[i1, 2])
            u2 = (water_vel[i2, 0], water_vel[i2, 1], water_vel[i2, 2])
            h0, h1, h2 = vertices[i0, 2] - eta[i0], vertices[i1, 2] - eta[i1], vertices[i2, 2] - eta[i2]
            fv, fp, fa, a_sub, sr, sv, n = _face(r0, r1, r2, h0, h1, h2, u0, u1, u2, face_area[f], vc, om, wd,
                                                 k_visc, pc, scales)  # fmt: skip
            visc, pres, air = _sum6(visc, fv), _sum6(pres, fp), _sum6(air, fa)
            if slam_on and a_sub > 0.0:
                inv = 1.0 / a_sub
                fs = slamming_force(a_sub, sv[0] * inv, sv[1] * inv, sv[2] * inv,
                                    (swept_prev[f, 0], swept_prev[f, 1], swept_prev[f, 2]), face_area[f], dt,
                                    n[0], n[1], n[2], k[MASS], k[AREA], k[SLAM_P], k[SLAM_GMAX])  # fmt: skip
                slam = _acc(slam, (sr[0] * inv, sr[1] * inv, sr[2] * inv), fs, k[SLAM_SCALE])
            swept[f, 0], swept[f, 1], swept[f, 2] = sv[0], sv[1], sv[2]
        _store(out, b, VISCOUS, visc)
        _store(out, b, PRESSURE, pres)
        _store(out, b, SLAMMING, slam)
        _store(out, b, AIR, air)
