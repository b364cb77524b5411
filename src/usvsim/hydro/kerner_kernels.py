"""Kerner's hydrodynamic forces per submerged (sub)triangle, all bodies in one numba call.

Reference: physics.md §1.2 (cutting), §1.5 (viscous), §1.6 (pressure/suction), §1.7 (slamming),
§1.8 (air); slamming in a time-step independent form (an impulse over the step, see
`kerner_terms._slam_scalar`). Frames and units: world ENU (z up), SI. Every velocity is taken at the centroid of the
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
  the unit normal from the world cross product, 1/area);
- per body, a pass over its vertex heights classifies it: entirely above water, entirely below (no
  cutting), or crossing; per face, three paths: whole and wet (the common case, straight-line
  code), whole and dry (only marked: its air drag is one SIMD sum over body-frame tables, see
  `kerner_air`), cut (general pieces);
- divisions by per-body constants (v_R, v_slam, S, dt) are multiplications by their reciprocals,
  and the slamming of a whole wet face reuses the drag's speed and cos θ; these change results
  by a few ulps per term (tests hold them to 1e-12 relative against the reference formulas);
- pressure pieces go to a column table (k n, k r × n, |cos θ|, f); |cos θ|^f is taken for all of
  them at once by one vectorized np.power between two kernel calls, and the per-body sums over
  the table are SIMD reductions;
- one core: bodies run in sequence (numba's prange over bodies cost more in thread hand-offs
  than it saved on a shared 2-core machine).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from usvsim.hydro.kerner_air import dry_air_wrench
from usvsim.hydro.kerner_terms import (  # noqa: F401  (friction_coefficient, slamming_force: public API)
    _ZERO3,
    _ZERO6,
    N_PIECE_ROWS,
    P_COS,
    P_EXP,
    P_FX,
    P_FY,
    P_FZ,
    P_TX,
    P_TY,
    P_TZ,
    _acc,
    _add,
    _air,
    _drag,
    _lerp3,
    _mean3,
    _normal,
    _pieces,
    _record_pressure,
    _rigid,
    _slam_scalar,
    friction_coefficient,
    slamming_force,
)

# Columns of the per-body coefficient table (see kerner.py for units and defaults)
RHO, NU, FORM_K, CPD1, CPD2, FP, CSD1, CSD2, FS, VREF = 0, 1, 2, 3, 4, 5, 6, 7, 8, 9
SLAM_P, SLAM_SPEED, SLAM_SCALE, RHO_AIR, C_AIR = 10, 11, 12, 13, 14
VISC_SCALE, PRES_SCALE, AIR_SCALE, RN_MIN, LENGTH, MASS, AREA = 15, 16, 17, 18, 19, 20, 21
N_COEF = 22
# Rows of the per-body output table out[b, k, 0:6] = (force, torque)
VISCOUS, PRESSURE, SLAMMING, AIR = 0, 1, 2, 3
# Columns of the per-face geometry table (rigid-motion invariant, see face_geometry)
G_AREA, G_HALF_INV_AREA, G_INV_AREA = 0, 1, 2
N_GEOM = 3

_THIRD = 1.0 / 3.0



def face_geometry(face_area: np.ndarray) -> np.ndarray:
    """Per-face table (Nf, N_GEOM): area m², 0.5/area (unit normal = cross product × this) 1/m² and
    1/area 1/m²; zeros for area 0."""
    a = np.asarray(face_area, dtype=np.float64)
    pos = a > 0.0
    safe = np.where(pos, a, 1.0)
    geom = np.zeros((len(a), N_GEOM))
    geom[:, G_AREA] = a
    geom[:, G_HALF_INV_AREA] = np.where(pos, 0.5 / safe, 0.0)
    geom[:, G_INV_AREA] = np.where(pos, 1.0 / safe, 0.0)
    return np.ascontiguousarray(geom)


@njit(cache=True, inline="always")
def _cut_slam(slam, a_sub, sr, sv, a_prev, n, inv_dt, sk, scale):
    """slam + the slamming (§1.7) of a cut face's submerged part (area a_sub, area-weighted sums
    sr = Σ a r, sv = Σ a v of its pieces) at its centroid, moving at its mean velocity; a_prev: the face's
    submerged area on the previous step."""
    inv = 1.0 / a_sub
    vx, vy, vz = sv[0] * inv, sv[1] * inv, sv[2] * inv
    speed = math.sqrt(vx * vx + vy * vy + vz * vz)
    if speed <= 0.0:
        return slam
    c = (vx * n[0] + vy * n[1] + vz * n[2]) / speed
    if c < 0.0:
        return slam
    s = _slam_scalar(a_sub, vx, vy, vz, c, a_prev, inv_dt, sk)
    return _acc(slam, (sr[0] * inv, sr[1] * inv, sr[2] * inv), (s * vx, s * vy, s * vz), scale)


@njit(cache=True, inline="always")
def _body_constants(b, coef, vcom, omega, water_vel_com, wind, dt):
    """Per-body inputs of the face loop: velocities, drag/slamming constants, scales."""
    k = coef[b]
    vc, om, wd = (vcom[b, 0], vcom[b, 1], vcom[b, 2]), (omega[b, 0], omega[b, 1], omega[b, 2]), (wind[b, 0], wind[b, 1], wind[b, 2])
    dx, dy, dz = vc[0] - water_vel_com[b, 0], vc[1] - water_vel_com[b, 1], vc[2] - water_vel_com[b, 2]
    c_f = friction_coefficient(math.sqrt(dx * dx + dy * dy + dz * dz), k[LENGTH], k[NU], k[RN_MIN])
    k_visc = 0.5 * k[RHO] * c_f * (1.0 + k[FORM_K]) * k[VISC_SCALE]
    pc = (k[CPD1], k[CPD2], k[FP], k[CSD1], k[CSD2], k[FS], 1.0 / k[VREF])
    sk = (k[SLAM_P], 1.0 / k[SLAM_SPEED], 2.0 * k[MASS] / k[AREA])
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
                   water_vel_com, wind, coef, dt, slam_ready, swept_prev, swept, out, pieces, slot, dry):  # fmt: skip
    """Kerner forces on body b (arguments as in kerner_wrenches): writes out[b] (pressure: see
    pressure_wrenches), the swept rows and the body's pressure pieces from column `slot` on;
    returns the next free column."""
    vc, om, wd, k_visc, pc, sk, scales = _body_constants(b, coef, vcom, omega, water_vel_com, wind, dt)
    slam_on = slam_ready and scales[3] != 0.0
    air_on = scales[1] != 0.0
    cx, cy, cz = com[b, 0], com[b, 1], com[b, 2]
    lo, hi = _height_bounds(vertices, eta, vert_offsets[b], vert_offsets[b + 1])
    all_dry, all_wet = lo > 0.0, hi <= 0.0
    visc = slam = air = _ZERO6
    for f in range(face_offsets[b], face_offsets[b + 1]):
        i0, i1, i2 = faces[f, 0], faces[f, 1], faces[f, 2]
        area = geom[f, G_AREA]
        h0, h1, h2 = vertices[i0, 2] - eta[i0], vertices[i1, 2] - eta[i1], vertices[i2, 2] - eta[i2]
        n_below = 3 if all_wet else (0 if all_dry else (h0 <= 0.0) + (h1 <= 0.0) + (h2 <= 0.0))
        is_dry = n_below == 0 or (n_below == 1 and min(h0, h1, h2) == 0.0)  # or touching at one vertex
        dry[f] = 1.0 if is_dry else 0.0
        if is_dry:  # whole face in the air: its air drag comes from dry_air_wrench
            swept[f, 0] = 0.0
            continue
        # positions relative to the CoM (m), world axes
        r0 = (vertices[i0, 0] - cx, vertices[i0, 1] - cy, vertices[i0, 2] - cz)
        r1 = (vertices[i1, 0] - cx, vertices[i1, 1] - cy, vertices[i1, 2] - cz)
        r2 = (vertices[i2, 0] - cx, vertices[i2, 1] - cy, vertices[i2, 2] - cz)
        n = _normal(r0, r1, r2, geom[f, G_HALF_INV_AREA])
        u0 = (water_vel[i0, 0], water_vel[i0, 1], water_vel[i0, 2])
        u1 = (water_vel[i1, 0], water_vel[i1, 1], water_vel[i1, 2])
        u2 = (water_vel[i2, 0], water_vel[i2, 1], water_vel[i2, 2])
        if n_below == 3:  # whole face under water: one piece, the face itself
            r, w = _mean3(_THIRD, r0, r1, r2), _mean3(_THIRD, u0, u1, u2)
            v = _rigid(r, vc, om)
            vx, vy, vz = v[0] - w[0], v[1] - w[1], v[2] - w[2]
            fv, pr, cos = _drag(vx, vy, vz, n, area, k_visc, pc)
            visc = _add(visc, r, fv, 1.0)
            _record_pressure(pieces, slot, pr, n, r)
            slot += 1
            if slam_on and cos >= 0.0 and area > swept_prev[f, 0]:
                s = _slam_scalar(area, vx, vy, vz, cos, swept_prev[f, 0], scales[4], sk)
                slam = _acc(slam, r, (s * vx, s * vy, s * vz), scales[3])
            swept[f, 0] = area
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
            _record_pressure(pieces, slot, pr, n, r)
            slot += 1
            a_sub += a
            sr = (sr[0] + a * r[0], sr[1] + a * r[1], sr[2] + a * r[2])
            sv = (sv[0] + a * vx, sv[1] + a * vy, sv[2] + a * vz)
            sl = (sl[0] + a * piece[0], sl[1] + a * piece[1], sl[2] + a * piece[2])
        visc = (visc[0] + fvis[0], visc[1] + fvis[1], visc[2] + fvis[2], visc[3] + fvis[3], visc[4] + fvis[4],
                visc[5] + fvis[5])  # fmt: skip
        a_dry = area - a_sub
        if air_on and a_dry > 1e-9 * area:  # the dry remainder, one piece at its centroid
            third, inv_dry = area / 3.0, 1.0 / a_dry
            l_dry = ((third - sl[0]) * inv_dry, (third - sl[1]) * inv_dry, (third - sl[2]) * inv_dry)
            r = _lerp3(l_dry, r0, r1, r2)
            air = _add(air, r, _air(r, a_dry, vc, om, wd, n, scales[2]), scales[1])
        if slam_on and a_sub > swept_prev[f, 0]:  # on the area-weighted mean velocity of the submerged part
            slam = _cut_slam(slam, a_sub, sr, sv, swept_prev[f, 0], n, scales[4], sk, scales[3])
        swept[f, 0] = a_sub
    for j in range(6):
        out[b, VISCOUS, j] = visc[j]
        out[b, SLAMMING, j] = slam[j]
        out[b, AIR, j] = air[j]
    return slot


@njit(cache=True)
def _add_dry_air(b, face_offsets, vertices, com, vcom, omega, wind, coef, air, out):
    """out[b, AIR] += the air drag on body b's whole dry faces (kerner_air), times its scale."""
    rel = (vcom[b, 0] - wind[b, 0], vcom[b, 1] - wind[b, 1], vcom[b, 2] - wind[b, 2])
    w = dry_air_wrench(b, face_offsets[b], face_offsets[b + 1], air[0], air[1], vertices, air[2], air[3], com, rel,
                       omega, coef[b, RHO_AIR] * coef[b, C_AIR])  # fmt: skip
    for j in range(6):
        out[b, AIR, j] += coef[b, AIR_SCALE] * w[j]


@njit(cache=True, nogil=True)  # nogil: runs while the hydrostatics kernel works on the other core
def kerner_wrenches(vertices, faces, geom, face_offsets, vert_offsets, eta, water_vel, com, vcom, omega,
                    water_vel_com, wind, coef, dt, slam_ready, swept_prev, swept, out, pieces, first, air):  # fmt: skip
    """Kerner viscous, slamming and air forces of every body, and its pressure/suction pieces.

    Inputs (world ENU, SI; arrays float64 C-order): vertices (Nv,3) m; faces (Nf,3) uint32 outward
    CCW; geom (Nf, N_GEOM) per-face table from `face_geometry`; face_offsets (nb+1,) uint64;
    vert_offsets (nb+1,) int: body b owns vertices vert_offsets[b]:vert_offsets[b+1] (its faces
    index only those); eta (Nv,) water height at each vertex m; water_vel (Nv,3) water velocity
    (orbital + current) at each vertex m/s; com (nb,3) m; vcom (nb,3) CoM velocity m/s; omega (nb,3)
    angular velocity rad/s (world axes); water_vel_com (nb,3) water velocity at the CoM (for the
    Reynolds number) m/s; wind (nb,3) wind velocity m/s; coef (nb, N_COEF) per-body coefficients;
    dt s (slamming); slam_ready: False on the first step (no previous areas); swept_prev (Nf,3): column
    0 is each face's submerged area on the previous step m² (the other columns are unused).
    Outputs, overwritten: swept (Nf,3) column 0: submerged area of each face now; out (nb,4,6) per body and force kind
    (VISCOUS, SLAMMING, AIR; PRESSURE comes from pressure_wrenches): force N and torque N·m about
    the CoM, world axes; pieces (N_PIECE_ROWS, 2Nf): the pressure/suction pieces of all bodies,
    body b in columns first[b]:first[b+1] (first (nb+1,) int64). Returns their count q.
    air: (dry (Nf,) scratch: 1.0 on whole dry faces, the rest of kerner_air's tables: dry-face table,
    anchors, frames) for the air drag on whole dry faces.

    |cos θ|^f is then one vectorized np.power(pieces[P_COS, :q], pieces[P_EXP, :q]) over all pieces
    (a pow call per piece inside the face loop costs about 4x more); `pressure_wrenches` sums them.
    """
    slot = 0
    for b in range(face_offsets.shape[0] - 1):
        first[b] = slot
        slot = _body_wrenches(b, vertices, faces, geom, face_offsets, vert_offsets, eta, water_vel, com, vcom,
                              omega, water_vel_com, wind, coef, dt, slam_ready, swept_prev, swept, out, pieces,
                              slot, air[0])  # fmt: skip
        if coef[b, AIR_SCALE] != 0.0:
            _add_dry_air(b, face_offsets, vertices, com, vcom, omega, wind, coef, air, out)
    first[face_offsets.shape[0] - 1] = slot
    return slot


# A pure reduction over contiguous rows: with reassociation LLVM vectorizes it (results differ
# from face-order summation by rounding only, ~1e-16 relative).
@njit(cache=True, fastmath={"reassoc", "nsz"})
def _pressure_sums(pieces, powed, q0, q1):
    """Σ |cos θ|^f (k n, k r × n) over pieces q0:q1 (powed: |cos θ|^f per piece)."""
    fx = fy = fz = tx = ty = tz = 0.0
    for q in range(q0, q1):
        p = powed[q]
        fx += p * pieces[P_FX, q]
        fy += p * pieces[P_FY, q]
        fz += p * pieces[P_FZ, q]
        tx += p * pieces[P_TX, q]
        ty += p * pieces[P_TY, q]
        tz += p * pieces[P_TZ, q]
    return fx, fy, fz, tx, ty, tz


@njit(cache=True)
def pressure_wrenches(first, pieces, powed, coef, out, force, torque):
    """out[:, PRESSURE] from the pieces of kerner_wrenches (powed: their |cos θ|^f), then the totals
    force (nb,3) N and torque (nb,3) N·m over the four kinds (in kind order)."""
    for b in range(first.shape[0] - 1):
        sums = _pressure_sums(pieces, powed, first[b], first[b + 1])
        scale = coef[b, PRES_SCALE]
        for j in range(6):
            out[b, PRESSURE, j] = scale * sums[j]
        for j in range(3):
            force[b, j] = out[b, 0, j] + out[b, 1, j] + out[b, 2, j] + out[b, 3, j]
            torque[b, j] = out[b, 0, j + 3] + out[b, 1, j + 3] + out[b, 2, j + 3] + out[b, 3, j + 3]
