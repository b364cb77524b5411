"""Exact hydrostatics of triangle hulls cut by a water surface (Kerner's surfacic method, done right).

Frames and units: world ENU (z up), metres, newtons, kilograms per cubic metre. The water height
``eta`` is given per hull vertex (the surface height above that vertex's (x, y)); the surface is
treated as planar over each triangle, so the height above water h = z - eta and the depth
d = -h are linear over every (sub)triangle and the cut points are linear interpolations
(reference/physics.md §1.2).

Per submerged (sub)triangle the pressure p = rho g d is integrated exactly: force and moment
integrands are at most quadratic, so the 3-point edge-midpoint rule is exact (§1.3). The displaced
volume and centre of buoyancy come from signed vertical prisms with exact centroids (§2.2); for
a closed hull under planar water they equal the clipped polyhedron's volume and centroid.

All floating bodies are processed in one kernel call; faces of body b are the contiguous range
``face_offsets[b]:face_offsets[b + 1]``.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np
from numba import njit


@njit(cache=True)
def transform_vertices(verts_body, vert_body, pos, rot, out):
    """out[v] = rot[b] @ verts_body[v] + pos[b] with b = vert_body[v] (rot is body → world, m)."""
    b_loaded = -1
    r00 = r01 = r02 = r10 = r11 = r12 = r20 = r21 = r22 = px = py = pz = 0.0
    for v in range(verts_body.shape[0]):
        b = vert_body[v]
        if b != b_loaded:  # vertices come grouped by body
            r00, r01, r02 = rot[b, 0, 0], rot[b, 0, 1], rot[b, 0, 2]
            r10, r11, r12 = rot[b, 1, 0], rot[b, 1, 1], rot[b, 1, 2]
            r20, r21, r22 = rot[b, 2, 0], rot[b, 2, 1], rot[b, 2, 2]
            px, py, pz = pos[b, 0], pos[b, 1], pos[b, 2]
            b_loaded = b
        x, y, z = verts_body[v, 0], verts_body[v, 1], verts_body[v, 2]
        out[v, 0] = r00 * x + r01 * y + r02 * z + px
        out[v, 1] = r10 * x + r11 * y + r12 * z + py
        out[v, 2] = r20 * x + r21 * y + r22 * z + pz


@njit(cache=True)
def _depth_moments(p0, p1, p2, d0, d1, d2):
    """Depth integrals over a triangle per unit area, times 12, by the edge-midpoint rule.

    p_k: vertices (m, any origin), d_k: depths at them (m); depth is linear, so the rule is exact
    for every integrand here (at most quadratic). Returns 12 × (w, qx, qy, qz, e) with
    w = ∫d dA / A, q = ∫p d dA / A, e = ∫d² dA / (2A). (The factor 12 keeps divisions out.)
    """
    a = d0 + d1  # twice the depth at each edge midpoint
    b = d1 + d2
    c = d2 + d0
    qx = (p0[0] + p1[0]) * a + (p1[0] + p2[0]) * b + (p2[0] + p0[0]) * c
    qy = (p0[1] + p1[1]) * a + (p1[1] + p2[1]) * b + (p2[1] + p0[1]) * c
    qz = (p0[2] + p1[2]) * a + (p1[2] + p2[2]) * b + (p2[2] + p0[2]) * c
    return 2.0 * (a + b + c), qx, qy, qz, 0.5 * (a * a + b * b + c * c)


@njit(cache=True)
def _cut(p, q, hp, hq):
    """Zero crossing of the height (hp at p, hq at q, opposite signs) on edge p→q.

    Returns (point, t, u): t = fraction of the way from p, u = 1 - t (without cancellation).
    """
    inv = 1.0 / (hp - hq)
    t = hp * inv
    u = -hq * inv
    return (u * p[0] + t * q[0], u * p[1] + t * q[1], u * p[2] + t * q[2]), t, u


@njit(cache=True)
def _one_above(ra, rb, rc, ha, hb, hc, db, dc):
    """Apex a above water, b and c below: the quad (b, c, I_c, I_b) as two sub-triangles; db, dc: the
    pressure heads at b and c (-hb, -hc for hydrostatics; 0 at the cut points).

    Returns (12 × (w, qx, qy, qz, e) per parent area, submerged area fraction) and the
    waterline (I_c, I_b). Fractions of the parent area: (b, c, I_c) u_c, (b, I_c, I_b) s_c u_b.
    """
    ib, _, ub = _cut(ra, rb, ha, hb)
    ic, sc, uc = _cut(ra, rc, ha, hc)
    w1, qx1, qy1, qz1, e1 = _depth_moments(rb, rc, ic, db, dc, 0.0)
    w2, qx2, qy2, qz2, e2 = _depth_moments(rb, ic, ib, db, 0.0, 0.0)
    f1 = uc
    f2 = sc * ub
    w, e = f1 * w1 + f2 * w2, f1 * e1 + f2 * e2
    qx, qy, qz = f1 * qx1 + f2 * qx2, f1 * qy1 + f2 * qy2, f1 * qz1 + f2 * qz2
    return (w, qx, qy, qz, e, f1 + f2), ic, ib


@njit(cache=True)
def _two_above(ra, rb, rc, ha, hb, hc, da):
    """Apex a below water, b and c above: the sub-triangle (a, J_b, J_c); da: the pressure head at a.

    Returns (12 × (w, qx, qy, qz, e) per parent area, submerged area fraction t_b t_c) and the
    waterline (J_b, J_c).
    """
    jb, tb, _ = _cut(ra, rb, ha, hb)
    jc, tc, _ = _cut(ra, rc, ha, hc)
    w, qx, qy, qz, e = _depth_moments(ra, jb, jc, da, 0.0, 0.0)
    f = tb * tc
    return (f * w, f * qx, f * qy, f * qz, f * e, f), jb, jc


@njit(cache=True)
def _cut_face(r0, r1, r2, h0, h1, h2, d0, d1, d2, n_below):
    """Submerged part of a face crossed by the surface (n_below = 1 or 2 vertices with h <= 0); d_k: the
    pressure head at each vertex (-h_k for hydrostatics).

    The odd vertex out becomes apex a; (a, b, c) keeps the face's cyclic order. The waterline
    segment is oriented along the boundary of the submerged surface (counter-clockwise about
    the outward normal).
    """
    apex_below = n_below == 1
    if (h0 <= 0.0) == apex_below:
        ra, rb, rc, ha, hb, hc, da, db, dc = r0, r1, r2, h0, h1, h2, d0, d1, d2
    elif (h1 <= 0.0) == apex_below:
        ra, rb, rc, ha, hb, hc, da, db, dc = r1, r2, r0, h1, h2, h0, d1, d2, d0
    else:
        ra, rb, rc, ha, hb, hc, da, db, dc = r2, r0, r1, h2, h0, h1, d2, d0, d1
    if apex_below:
        return _two_above(ra, rb, rc, ha, hb, hc, da)
    return _one_above(ra, rb, rc, ha, hb, hc, db, dc)


@njit(cache=True)
def _combine_one_above(m1, m2, f1, f2):
    """`_one_above`'s weighted sum of its two sub-triangles' moments (the same expressions)."""
    w1, qx1, qy1, qz1, e1 = m1
    w2, qx2, qy2, qz2, e2 = m2
    w, e = f1 * w1 + f2 * w2, f1 * e1 + f2 * e2
    qx, qy, qz = f1 * qx1 + f2 * qx2, f1 * qy1 + f2 * qy2, f1 * qz1 + f2 * qz2
    return (w, qx, qy, qz, e, f1 + f2)


@njit(cache=True)
def _cut_face_and_heads(r0, r1, r2, h0, h1, h2, p0, p1, p2, n_below):
    """`_cut_face` twice in one: with the hydrostatic depths -h_k and with the pressure heads p_k (Froude–Krylov),
    the cut points computed once. Returns (terms with -h, segment p, q, terms with p_k); each set bit for bit
    what `_cut_face` returns for it."""
    apex_below = n_below == 1
    if (h0 <= 0.0) == apex_below:
        ra, rb, rc, ha, hb, hc, pa, pb, pc = r0, r1, r2, h0, h1, h2, p0, p1, p2
    elif (h1 <= 0.0) == apex_below:
        ra, rb, rc, ha, hb, hc, pa, pb, pc = r1, r2, r0, h1, h2, h0, p1, p2, p0
    else:
        ra, rb, rc, ha, hb, hc, pa, pb, pc = r2, r0, r1, h2, h0, h1, p2, p0, p1
    if apex_below:  # `_two_above`
        jb, tb, _ = _cut(ra, rb, ha, hb)
        jc, tc, _ = _cut(ra, rc, ha, hc)
        f = tb * tc
        w, qx, qy, qz, e = _depth_moments(ra, jb, jc, -ha, 0.0, 0.0)
        wp, qxp, qyp, qzp, ep = _depth_moments(ra, jb, jc, pa, 0.0, 0.0)
        return (f * w, f * qx, f * qy, f * qz, f * e, f), jb, jc, (f * wp, f * qxp, f * qyp, f * qzp, f * ep, f)
    ib, _, ub = _cut(ra, rb, ha, hb)  # `_one_above`
    ic, sc, uc = _cut(ra, rc, ha, hc)
    f1, f2 = uc, sc * ub
    geo = _combine_one_above(_depth_moments(rb, rc, ic, -hb, -hc, 0.0), _depth_moments(rb, ic, ib, -hb, 0.0, 0.0),
                             f1, f2)  # fmt: skip
    heads = _combine_one_above(_depth_moments(rb, rc, ic, pb, pc, 0.0), _depth_moments(rb, ic, ib, pb, 0.0, 0.0),
                               f1, f2)  # fmt: skip
    return geo, ic, ib, heads


@njit(cache=True)
def _store_segment(seg, seg_count, f, p, q, cx, cy, cz):
    """Write the waterline segment (p, q) (CoM-relative, m) of face f in world coordinates."""
    seg[f, 0, 0], seg[f, 0, 1], seg[f, 0, 2] = p[0] + cx, p[1] + cy, p[2] + cz
    seg[f, 1, 0], seg[f, 1, 1], seg[f, 1, 2] = q[0] + cx, q[1] + cy, q[2] + cz
    seg_count[f] = 1


@njit(cache=True)
def _clear_segment(seg, seg_count, f):
    """Mark face f as having no waterline segment (its row zeroed)."""
    for i in range(2):
        for k in range(3):
            seg[f, i, k] = 0.0
    seg_count[f] = 0


@njit(cache=True)
def _store_body(b, sums, c, rho_g, force, torque, volume, cob, wetted_area, waterplane_area):
    """Scale body b's sums (each 24 × its integral, see _depth_moments) into the outputs."""
    fx, fy, fz, tx, ty, tz, vol, mx, my, mz, wet, awp = sums
    cx, cy, cz = c
    k = -rho_g / 24.0
    force[b, 0], force[b, 1], force[b, 2] = k * fx, k * fy, k * fz
    torque[b, 0], torque[b, 1], torque[b, 2] = k * tx, k * ty, k * tz
    volume[b] = vol / 24.0
    inv = 1.0 / vol if vol != 0.0 else 0.0
    cob[b, 0], cob[b, 1], cob[b, 2] = cx + mx * inv, cy + my * inv, cz + mz * inv
    wetted_area[b] = wet
    waterplane_area[b] = 0.5 * awp


# What a face's per-face rows hold, for the pass a body at a time (hydro/fused.py), kept between its calls: FACE_DRY
# no submerged area and a zero segment row, FACE_WET the whole face submerged and a zero row, FACE_CUT a count of 1;
# FACE_UNKNOWN: to be written. A dry or submerged face whose rows already say so is not written again (at 200 WAM-Vs
# every face's area row, 1.8 MB, was rewritten every step; now those of the ~15 % of faces the waterline cuts, and of
# faces that change). Every other writer of the rows (compute, compute_split, compute_flat) leaves the states to be
# reset (HullSet.face_state).
FACE_UNKNOWN, FACE_DRY, FACE_WET, FACE_CUT = 0, 1, 2, 3


@njit(cache=True, inline="always")
def _add_face(sums, r0, r1, r2, wp, qxp, qyp, qzp, w, qx, qy, qz, e, frac):
    """`sums` (fx, fy, fz, tx, ty, tz, vol, mx, my, mz, awp) plus one face's submerged part: pressure force and
    moment from its depth moments (`wp`, `qxp`..: with Froude–Krylov heads, else the hydrostatic `w`, `qx`..),
    displaced volume and its moments (`w`, `qx`.., `e`), waterplane area (`frac` of the face under water). C = 2 A n,
    twice the parent's area vector; sub-triangles share its normal."""
    fx, fy, fz, tx, ty, tz, vol, mx, my, mz, awp = sums
    ux, uy, uz = r1[0] - r0[0], r1[1] - r0[1], r1[2] - r0[2]
    vx, vy, vz = r2[0] - r0[0], r2[1] - r0[1], r2[2] - r0[2]
    sx = uy * vz - uz * vy
    sy = uz * vx - ux * vz
    sz = ux * vy - uy * vx
    fx += wp * sx
    fy += wp * sy
    fz += wp * sz
    tx += qyp * sz - qzp * sy
    ty += qzp * sx - qxp * sz
    tz += qxp * sy - qyp * sx
    vol -= w * sz
    mx -= qx * sz
    my -= qy * sz
    mz -= (qz + e) * sz
    awp -= frac * sz
    return fx, fy, fz, tx, ty, tz, vol, mx, my, mz, awp


@njit(cache=True, inline="always")  # inlined into the caller: one loop in its body (see hull_hydrostatics)
def _body_faces(vertices, faces, face_area, f_lo, f_hi, v_off, out_off, eta, head, fk, cx, cy, cz,
                face_area_sub, seg, seg_count, face_state, rows):  # fmt: skip
    """`hull_hydrostatics`' loop over one body's faces, the same operations, for hydro/fused.py: faces rows
    f_lo:f_hi (their vertex indices + v_off index vertices, eta and head), the per-face outputs of face f in row
    f + out_off (unsigned offsets); a dry or submerged face whose rows already say so (face_state, FACE_*) is not
    written again. `rows` False: no per-face row or state is touched (the body sums alone). Returns the body's 12
    sums (see _store_body)."""
    fx = fy = fz = tx = ty = tz = vol = mx = my = mz = wet = awp = 0.0
    for f in range(f_lo, f_hi):
        i0, i1, i2 = faces[f, 0] + v_off, faces[f, 1] + v_off, faces[f, 2] + v_off
        o = f + out_off  # the face's row in the outputs
        h0 = vertices[i0, 2] - eta[i0]
        h1 = vertices[i1, 2] - eta[i1]
        h2 = vertices[i2, 2] - eta[i2]
        n_below = (h0 <= 0.0) + (h1 <= 0.0) + (h2 <= 0.0)
        if n_below == 0 or (n_below == 1 and min(h0, h1, h2) == 0.0):  # dry, or touching at one vertex
            if rows and face_state[o] != FACE_DRY:  # rows already dry are left alone
                face_area_sub[o] = 0.0
                if seg_count[o] != 0:  # a row with count 0 is already zero: most dry faces write nothing there
                    for i in range(6):  # (written out: a helper with this branch is not inlined, ~4x slower)
                        seg[o, i // 3, i % 3] = 0.0
                    seg_count[o] = 0
                face_state[o] = FACE_DRY
            continue
        r0 = (vertices[i0, 0] - cx, vertices[i0, 1] - cy, vertices[i0, 2] - cz)
        r1 = (vertices[i1, 0] - cx, vertices[i1, 1] - cy, vertices[i1, 2] - cz)
        r2 = (vertices[i2, 0] - cx, vertices[i2, 1] - cy, vertices[i2, 2] - cz)
        if n_below == 3:
            w, qx, qy, qz, e = _depth_moments(r0, r1, r2, -h0, -h1, -h2)
            frac = 1.0
            if rows and face_state[o] != FACE_WET:  # as for dry faces above (the area, frac * face_area, below)
                if seg_count[o] != 0:
                    for i in range(6):
                        seg[o, i // 3, i % 3] = 0.0
                    seg_count[o] = 0
            if fk:
                wp, qxp, qyp, qzp, _ = _depth_moments(r0, r1, r2, head[i0], head[i1], head[i2])
        else:
            if fk:
                terms, p, q, hterms = _cut_face_and_heads(r0, r1, r2, h0, h1, h2, head[i0], head[i1], head[i2],
                                                          n_below)  # fmt: skip
                wp, qxp, qyp, qzp = hterms[0], hterms[1], hterms[2], hterms[3]
            else:
                terms, p, q = _cut_face(r0, r1, r2, h0, h1, h2, -h0, -h1, -h2, n_below)
            w, qx, qy, qz, e, frac = terms
            if rows:
                seg[o, 0, 0], seg[o, 0, 1], seg[o, 0, 2] = p[0] + cx, p[1] + cy, p[2] + cz  # as _store_segment
                seg[o, 1, 0], seg[o, 1, 1], seg[o, 1, 2] = q[0] + cx, q[1] + cy, q[2] + cz
                if face_state[o] != FACE_CUT:  # (a face cut last time holds its count 1)
                    seg_count[o] = 1
                    face_state[o] = FACE_CUT
        if not fk:
            wp, qxp, qyp, qzp = w, qx, qy, qz
        running = (fx, fy, fz, tx, ty, tz, vol, mx, my, mz, awp)
        fx, fy, fz, tx, ty, tz, vol, mx, my, mz, awp = _add_face(
            running, r0, r1, r2, wp, qxp, qyp, qzp, w, qx, qy, qz, e, frac
        )
        a_sub = frac * face_area[f]
        if rows and face_state[o] != FACE_WET:  # (a wet face's row holds 1.0 * face_area already)
            face_area_sub[o] = a_sub
            if n_below == 3:
                face_state[o] = FACE_WET
        wet += a_sub
    return fx, fy, fz, tx, ty, tz, vol, mx, my, mz, wet, awp


@njit(cache=True, nogil=True)  # nogil: the simulation may run it beside the Kerner kernel (core/overlap.py)
def hull_hydrostatics(vertices, faces, face_area, face_offsets, eta, head, com, rho, g,
                      force, torque, volume, cob, wetted_area, waterplane_area,
                      face_area_sub, seg, seg_count):  # fmt: skip
    """Hydrostatic wrench, displaced volume and waterline of every body, in one call.

    Inputs (world ENU, SI): vertices (Nv,3) m; faces (Nf,3) uint32 global vertex indices, outward
    counter-clockwise winding; face_area (Nf,) m² (rigid-motion invariant, precomputed);
    face_offsets (nb+1,) uint64 (unsigned indices spare numba's negative-index handling);
    eta (Nv,) water height at each vertex's (x, y) m; head (Nv,) pressure head p/(rho g) at each vertex m
    (Froude–Krylov, ocean/pressure.py; used for the force and moment only) or an empty array for the
    hydrostatic column eta - z; com (nb,3) centres of mass m; rho kg/m³; g m/s².
    Outputs, overwritten: force (nb,3) N; torque (nb,3) N·m about the CoM; volume (nb,) m³;
    cob (nb,3) m (= com when nothing is submerged); wetted_area (nb,) m²; waterplane_area (nb,)
    m², horizontal projection of the area inside the waterline (= -Σ submerged projected area,
    exact for closed hulls); face_area_sub (Nf,) m²; seg (Nf,2,3) m oriented waterline segment
    of each face and seg_count (Nf,) its count (0 or 1; rows with count 0 are zero).
    The face loop is kept in one body on purpose: splitting it costs numba ~1.5x in speed. hydro/fused.py's pass runs
    the same loop with offsets and face states (`_body_faces`, inlined there; here it measured 2-3 % slower).
    Volume, centre of buoyancy and areas are geometric (the depth below the local surface) in both cases.
    """
    fk = head.shape[0] > 0
    for b in range(face_offsets.shape[0] - 1):
        cx, cy, cz = com[b, 0], com[b, 1], com[b, 2]
        fx = fy = fz = tx = ty = tz = vol = mx = my = mz = wet = awp = 0.0
        for f in range(face_offsets[b], face_offsets[b + 1]):
            i0, i1, i2 = faces[f, 0], faces[f, 1], faces[f, 2]
            h0 = vertices[i0, 2] - eta[i0]
            h1 = vertices[i1, 2] - eta[i1]
            h2 = vertices[i2, 2] - eta[i2]
            n_below = (h0 <= 0.0) + (h1 <= 0.0) + (h2 <= 0.0)
            if n_below == 0 or (n_below == 1 and min(h0, h1, h2) == 0.0):  # dry, or touching at one vertex
                face_area_sub[f] = 0.0
                if seg_count[f] != 0:  # a row with count 0 is already zero: most dry faces write nothing there
                    for i in range(6):  # (written out: a helper with this branch is not inlined, ~4x slower)
                        seg[f, i // 3, i % 3] = 0.0
                    seg_count[f] = 0
                continue
            r0 = (vertices[i0, 0] - cx, vertices[i0, 1] - cy, vertices[i0, 2] - cz)
            r1 = (vertices[i1, 0] - cx, vertices[i1, 1] - cy, vertices[i1, 2] - cz)
            r2 = (vertices[i2, 0] - cx, vertices[i2, 1] - cy, vertices[i2, 2] - cz)
            if n_below == 3:
                w, qx, qy, qz, e = _depth_moments(r0, r1, r2, -h0, -h1, -h2)
                frac = 1.0
                if seg_count[f] != 0:  # as for dry faces above
                    for i in range(6):
                        seg[f, i // 3, i % 3] = 0.0
                    seg_count[f] = 0
                if fk:
                    wp, qxp, qyp, qzp, _ = _depth_moments(r0, r1, r2, head[i0], head[i1], head[i2])
            else:
                if fk:
                    terms, p, q, hterms = _cut_face_and_heads(r0, r1, r2, h0, h1, h2, head[i0], head[i1], head[i2],
                                                              n_below)  # fmt: skip
                    wp, qxp, qyp, qzp = hterms[0], hterms[1], hterms[2], hterms[3]
                else:
                    terms, p, q = _cut_face(r0, r1, r2, h0, h1, h2, -h0, -h1, -h2, n_below)
                w, qx, qy, qz, e, frac = terms
                _store_segment(seg, seg_count, f, p, q, cx, cy, cz)
            if not fk:
                wp, qxp, qyp, qzp = w, qx, qy, qz
            running = (fx, fy, fz, tx, ty, tz, vol, mx, my, mz, awp)
            fx, fy, fz, tx, ty, tz, vol, mx, my, mz, awp = _add_face(
                running, r0, r1, r2, wp, qxp, qyp, qzp, w, qx, qy, qz, e, frac
            )
            a_sub = frac * face_area[f]
            face_area_sub[f] = a_sub
            wet += a_sub
        sums = (fx, fy, fz, tx, ty, tz, vol, mx, my, mz, wet, awp)
        _store_body(b, sums, (cx, cy, cz), rho * g, force, torque, volume, cob, wetted_area, waterplane_area)


NO_HEAD = np.zeros(0)  # hull_hydrostatics' "no pressure heads": the hydrostatic column under the local surface


class HydrostaticsResult:
    """Views of a HullSet's output buffers (world ENU, SI); overwritten by its next compute().

    The per-face rows (face_submerged_area, waterline_segments, waterline_count) may be made when first read: a wavy
    fleet's step reads none of them (hydro/fused.py), and writing them cost it more than the rest of the pass as the
    fleet outgrew the caches. Read them through this object (a kept array of the rows is current only when read
    through it after the compute that made it)."""

    __slots__ = ("force", "torque", "volume", "cob", "wetted_area", "waterplane_area", "_rows", "_settle")
    FIELDS = ("force", "torque", "volume", "cob", "wetted_area", "waterplane_area", "face_submerged_area",
              "waterline_segments", "waterline_count")  # fmt: skip

    force: np.ndarray  # (nb,3) N, hydrostatic force on each body
    torque: np.ndarray  # (nb,3) N·m, about each body's centre of mass
    volume: np.ndarray  # (nb,) m³, displaced volume
    cob: np.ndarray  # (nb,3) m, centre of buoyancy
    wetted_area: np.ndarray  # (nb,) m²
    waterplane_area: np.ndarray  # (nb,) m², horizontal projection of the waterplane

    def __init__(self, force: np.ndarray, torque: np.ndarray, volume: np.ndarray, cob: np.ndarray,
                 wetted_area: np.ndarray, waterplane_area: np.ndarray, face_submerged_area: np.ndarray,
                 waterline_segments: np.ndarray, waterline_count: np.ndarray,
                 settle: Callable[[], None] = lambda: None):  # fmt: skip
        self.force, self.torque, self.volume, self.cob = force, torque, volume, cob
        self.wetted_area, self.waterplane_area = wetted_area, waterplane_area
        self._rows = (face_submerged_area, waterline_segments, waterline_count)
        self._settle = settle  # makes the per-face rows if a compute left them for later

    @property
    def face_submerged_area(self) -> np.ndarray:
        """(Nf,) m², submerged area of each hull face."""
        self._settle()
        return self._rows[0]

    @property
    def waterline_segments(self) -> np.ndarray:
        """(Nf,2,3) m, oriented waterline segment of each face (world ENU)."""
        self._settle()
        return self._rows[1]

    @property
    def waterline_count(self) -> np.ndarray:
        """(Nf,) int8, 1 where the face row of waterline_segments is set."""
        self._settle()
        return self._rows[2]


class HullSet:
    """The hull meshes of all floating bodies, packed for the batched kernels.

    meshes: one (vertices_body (n,3) m in the body frame, faces (m,3) outward CCW) per body.
    """

    def __init__(self, meshes: Sequence[tuple[np.ndarray, np.ndarray]]):
        verts = [np.asarray(v, dtype=np.float64).reshape(-1, 3) for v, _ in meshes]
        faces = [np.asarray(f).reshape(-1, 3) for _, f in meshes]
        for v, f in zip(verts, faces):
            if f.size and (f.min() < 0 or f.max() >= len(v)):
                raise ValueError("hull face index out of range of its vertices")
        n_v = np.array([len(v) for v in verts])
        n_f = np.array([len(f) for f in faces])
        self.n_bodies = len(verts)
        self.vert_offsets = np.concatenate([[0], np.cumsum(n_v)]).astype(np.int32)
        self.face_offsets = np.concatenate([[0], np.cumsum(n_f)]).astype(np.uint64)
        self.vertices_body = np.ascontiguousarray(np.concatenate(verts))
        self.faces = np.ascontiguousarray(
            np.concatenate([f + o for f, o in zip(faces, self.vert_offsets)]).astype(np.uint32)
        )
        self.vert_body = np.repeat(np.arange(self.n_bodies, dtype=np.int32), n_v)
        self.face_body = np.repeat(np.arange(self.n_bodies, dtype=np.int32), n_f)
        tri = self.vertices_body[self.faces.astype(np.intp)]
        self.face_area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
        self._share_meshes(verts, faces)
        nb, nf = self.n_bodies, len(self.faces)
        self._world = np.zeros_like(self.vertices_body)
        # force, torque, volume, cob, areas (two), then the per-face buffers
        self._out = (np.zeros((nb, 3)), np.zeros((nb, 3)), np.zeros(nb), np.zeros((nb, 3)), np.zeros(nb), np.zeros(nb),
                     np.zeros(nf), np.zeros((nf, 2, 3)), np.zeros(nf, dtype=np.int8))  # fmt: skip
        self._result = HydrostaticsResult(*self._out, settle=self.settle_rows)
        self._rows_later: Callable[[], object] | None = None  # makes the per-face rows the last pass left (rows_later)
        self._face_state = np.zeros(nf, dtype=np.int8)  # the fused pass's record of the per-face rows (FACE_*)
        self._rows_untracked = False  # True when another writer wrote the per-face rows last (face_state unknown)
        self._flat = None  # FlatClusters (hydro/flat.py), made by `use_flat`

    def _share_meshes(self, verts: list[np.ndarray], faces: list[np.ndarray]) -> None:
        """One copy of each distinct hull (vertices and faces byte for byte, face areas bit for bit), for the pass a
        body at a time (hydro/fused.py): a fleet of one model reads one mesh, which stays in the core's caches.
        mesh_of (nb,) int64: body → mesh; mesh_vertices (body frame, m), mesh_faces (uint32, indices into the mesh's
        own vertices) and mesh_face_area (m², the same bits as `face_area` of the bodies using it), with
        mesh_vert_offsets / mesh_face_offsets (n_meshes + 1,) int64 as the bodies' offsets."""
        firsts: dict[tuple, list[int]] = {}  # (shape, dtype, bytes) of vertices and faces → meshes (first bodies)
        mesh_of, bodies = [], []
        fo = self.face_offsets.astype(np.int64)
        for b, (v, f) in enumerate(zip(verts, faces)):
            key = (v.shape, f.shape, f.dtype.str, v.tobytes(), f.tobytes())
            same = [m for m in firsts.get(key, ())
                    if np.array_equal(self.face_area[fo[b] : fo[b + 1]], self.face_area[fo[bodies[m]] : fo[bodies[m] + 1]])]  # fmt: skip
            if same:
                mesh_of.append(same[0])
                continue
            firsts.setdefault(key, []).append(len(bodies))
            mesh_of.append(len(bodies))
            bodies.append(b)
        self.mesh_of = np.array(mesh_of, dtype=np.int64)
        self.mesh_vert_offsets = np.concatenate([[0], np.cumsum([len(verts[b]) for b in bodies])]).astype(np.int64)
        self.mesh_face_offsets = np.concatenate([[0], np.cumsum([len(faces[b]) for b in bodies])]).astype(np.int64)
        self.mesh_vertices = np.ascontiguousarray(np.concatenate([verts[b] for b in bodies]).reshape(-1, 3))
        self.mesh_faces = np.ascontiguousarray(np.concatenate([faces[b] for b in bodies]).reshape(-1, 3).astype(np.uint32))
        self.mesh_face_area = np.ascontiguousarray(np.concatenate([self.face_area[fo[b] : fo[b + 1]] for b in bodies]))

    def use_flat(self, clusters) -> None:
        """Attach `hydro.flat.FlatClusters` made for this set (`flat.use_flat` does both): `compute_flat` uses them."""
        self._flat = clusters

    @property
    def has_flat(self) -> bool:
        """Whether `use_flat` prepared `compute_flat`."""
        return self._flat is not None

    def compute_flat(self, rot: np.ndarray, com_world: np.ndarray, level: float, rho: float, g: float,
                     overlap=None) -> HydrostaticsResult:  # fmt: skip
        """Hydrostatics of all bodies under flat water at height `level` (m): `compute` with eta = level at every
        vertex and no pressure heads, from rotations (nb,3,3) body → world and CoMs (nb,3) m (no world vertices
        needed). Equal to `compute` up to rounding (hydro/flat.py); needs `use_flat` first. `overlap`
        (core/overlap.py): half the bodies on its worker thread (the same result)."""
        if self._flat is None:
            raise RuntimeError("compute_flat() needs use_flat() first (usvsim.hydro.flat.use_flat)")
        self._flat.compute(self, rot, com_world, level, rho, g, self._out, overlap)
        self._rows_untracked, self._rows_later = True, None
        return self._result

    @property
    def world_buffer(self) -> np.ndarray:
        """The buffer `world_vertices` fills (Nv,3) m ENU, as its last call (or hydro/fused.py) left it."""
        return self._world

    def world_vertices(self, pos: np.ndarray, rot: np.ndarray) -> np.ndarray:
        """Hull vertices in world ENU (m), (Nv,3), from body positions (nb,3) m and rotations
        (nb,3,3) body → world. Returns an internal buffer, overwritten by the next call."""
        transform_vertices(self.vertices_body, self.vert_body, pos, rot, self._world)
        return self._world

    def compute(self, world_vertices: np.ndarray, eta: np.ndarray, com_world: np.ndarray, rho: float, g: float,
                head: np.ndarray = NO_HEAD) -> HydrostaticsResult:  # fmt: skip
        """Hydrostatics of all bodies. world_vertices (Nv,3) m ENU, eta (Nv,) m water height at
        each vertex's (x, y), com_world (nb,3) m, rho kg/m³, g m/s², head (Nv,) m pressure head at each
        vertex (Froude–Krylov) or empty: eta - z (arrays float64, C-order)."""
        hull_hydrostatics(
            world_vertices, self.faces, self.face_area, self.face_offsets, eta, head, com_world, rho, g, *self._out
        )
        self.rows_written()
        return self._result

    def face_state(self) -> np.ndarray:
        """The face states (Nf,) int8 (FACE_*) for a tracking writer of every per-face row (hydro/fused.py); reset to
        FACE_UNKNOWN first if another writer wrote the rows last."""
        if self._rows_untracked:
            self._face_state[:] = FACE_UNKNOWN
            self._rows_untracked = False
        return self._face_state

    def rows_written(self, tracked: bool = False) -> None:
        """After a per-face kernel call (`compute`, `compute_split`, hydro/fused.py: `tracked`): compute_flat's
        clusters must rewrite every row of theirs next time, and the face states are unknown unless tracked. The rows
        are those of this call: none is left for later."""
        if self._flat is not None:
            self._flat.invalidate()
        if not tracked:
            self._rows_untracked = True
        self._rows_later = None

    def rows_later(self, make: Callable[[], object]) -> None:
        """The last call wrote the body outputs but left the per-face rows as they were (their face states too):
        `make()` writes them (and the body outputs again, the same bits) when the result's rows are first read."""
        self._rows_later = make

    def settle_rows(self) -> None:
        """Make the per-face rows if the last call left them for later (`rows_later`)."""
        make, self._rows_later = self._rows_later, None
        if make is not None:
            make()
            self._rows_later = None

    def split_body(self) -> int:
        """Where two threads split the bodies (compute_split, hydro/fused.py, hydro/flat.py): the first body at or past
        half the faces, bodies [0, cut) on the worker, [cut, nb) here (1 <= cut <= nb - 1; needs 2 bodies or more)."""
        cut = int(np.searchsorted(self.face_offsets, self.face_offsets[-1] // 2))
        return min(max(cut, 1), self.n_bodies - 1)

    def compute_split(self, overlap, world_vertices: np.ndarray, eta: np.ndarray, com_world: np.ndarray, rho: float,
                      g: float, head: np.ndarray = NO_HEAD) -> HydrostaticsResult:  # fmt: skip
        """`compute` on two cores: the bodies split where the faces halve, the first part on `overlap`'s worker
        thread (core/overlap.py), the rest here. Each body's sums are the same loop over its own faces, so the
        result is bit-identical to `compute`."""
        nb, cut = self.n_bodies, self.split_body()
        force, torque, volume, cob, wet, awp, sub, seg, count = self._out
        parts = [(self.face_offsets[a : b + 1], com_world[a:b], force[a:b], torque[a:b], volume[a:b], cob[a:b],
                  wet[a:b], awp[a:b]) for a, b in ((0, cut), (cut, nb))]  # fmt: skip

        def run(offsets, com, f, t, v, c, w, a):
            hull_hydrostatics(world_vertices, self.faces, self.face_area, offsets, eta, head, com, rho, g,
                              f, t, v, c, w, a, sub, seg, count)  # fmt: skip

        wait = overlap.submit(run, *parts[0])
        try:
            run(*parts[1])
        finally:
            wait()
        self.rows_written()
        return self._result

    def waterline(self, body_index: int) -> np.ndarray:
        """Waterline segments (k,2,3) m ENU of one body from the last compute() (a copy)."""
        f0, f1 = int(self.face_offsets[body_index]), int(self.face_offsets[body_index + 1])
        return self._result.waterline_segments[f0:f1][self._result.waterline_count[f0:f1] == 1]
