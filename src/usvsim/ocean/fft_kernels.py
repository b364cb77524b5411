"""Numba kernels of the FFT wave field: one band's spectra at one snapshot time, and tile queries.

Tiles are complex64 arrays [band, snapshot, slot, iy, ix] with cell (iy, ix) at world (ix, iy)·L/N (periodic).
Geometry slots: 0 = h + i·w (height, vertical velocity), 1 = Dx + i·Dy (choppy displacement; only read when
the choppiness is non-zero). Velocity slot: u + i·v; acceleration slots: ax + i·ay, az. Every query blends the
band's snapshots with the weights `wts[band, snapshot]` (Lagrange in time, ramp included; see
`fft_time`), then interpolates bilinearly in space. The displaced surface is X = x0 - c·D(x0), z = h(x0),
so the physics queries the very surface that a renderer draws from the same tiles.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from usvsim.ocean.dispatch import serial_and_parallel


@njit(cache=True, inline="always")
def _pair(amp, omega, iy, ix, jy, jx, t):
    """H and G = ∂H/∂t at k and -k: E = ½ c e^{-iωt}, H(k) = E(k) + conj(E(-k)), H(-k) = conj(H(k))."""
    w = omega[iy, ix]
    h, g = _pair_rot(amp, complex(math.cos(w * t), -math.sin(w * t)), w, iy, ix, jy, jx)
    return h, g, w


@njit(cache=True, inline="always")
def _pair_rot(amp, rot, w, iy, ix, jy, jx):
    """`_pair` for a given rotation rot = e^{-iωt} of the pair's ω = w."""
    e = 0.5 * amp[iy, ix] * rot
    em = (0.5 * amp[jy, jx] * rot).conjugate()
    return e + em, -1j * w * (e - em)


@njit(cache=True, inline="always")
def _rows(n, iy):
    """Columns of row iy that are canonical in their (k, -k) pair; rows 0 and n/2 pair with themselves."""
    return n // 2 + 1 if iy == 0 or iy == n // 2 else n


@njit(cache=True, nogil=True)  # nogil: FFTWaveField runs it on a worker thread (snapshots made ahead)
def geometry_and_velocity_spectra(amp, omega, khx, khy, t, choppy, out, vel, phases, bits):
    """`geometry_spectra` into `out` and, unless `vel` has no slots, `kinematic_spectra` (velocity) into `vel` in one
    pass: each (k, -k) pair's sine, cosine and H, G once for both; every velocity value is the same expression as
    in `kinematic_spectra` (bit-identical).

    With bits >= 0 and `phases` (4, N, N) complex128 (bits -1: any array, unused), the pair's rotation e^{-iωt} is not evaluated from t but
    multiplied out of tables (`PhaseTables`): phases[0] · phases[1]^(bit 0) · phases[2]^(bit 1) · phases[3]^(bit 2)
    (at most three complex products instead of a sine and a cosine; within a few 1e-16 of them)."""
    n = amp.shape[0]
    with_vel = vel.shape[0] > 0
    for iy in range(n // 2 + 1):
        jy = (n - iy) % n
        for ix in range(_rows(n, iy)):
            jx = (n - ix) % n
            if amp[iy, ix] == 0 and amp[jy, jx] == 0:
                out[0, iy, ix] = out[0, jy, jx] = 0
                if choppy:
                    out[1, iy, ix] = out[1, jy, jx] = 0
                if with_vel:
                    vel[0, iy, ix] = vel[0, jy, jx] = 0
                continue
            if bits < 0:
                h, g, _ = _pair(amp, omega, iy, ix, jy, jx, t)
            else:
                rot = phases[0, iy, ix]
                if bits & 1:
                    rot = rot * phases[1, iy, ix]
                if bits & 2:
                    rot = rot * phases[2, iy, ix]
                if bits & 4:
                    rot = rot * phases[3, iy, ix]
                h, g = _pair_rot(amp, rot, omega[iy, ix], iy, ix, jy, jx)
            out[0, iy, ix] = h + 1j * g
            out[0, jy, jx] = h.conjugate() + 1j * g.conjugate()
            if choppy:
                hx, hy = khx[iy, ix], khy[iy, ix]
                out[1, iy, ix] = h * complex(hy, -hx)
                out[1, jy, jx] = h.conjugate() * complex(-hy, hx)
            if with_vel:
                rot = 1j * khx[iy, ix] - khy[iy, ix]
                vel[0, iy, ix] = g * rot
                vel[0, jy, jx] = -g.conjugate() * rot


@njit(cache=True, nogil=True)
def geometry_and_velocity_spectra_at(pairs, amp, omega, khx, khy, t, choppy, out, vel, phases, bits):
    """`geometry_and_velocity_spectra` for the pairs listed (K, 2) (canonical (iy, ix); `fft.pair_bins`: those
    with an amplitude) only, each with the same expressions; every other bin of out and vel is left as it is,
    so arrays kept zero there get the same bytes. The long bands of a cascade have an amplitude in ~5 % of their
    bins. (The pair's body is written out again: as an inlined helper it ran 10x slower.)"""
    n = amp.shape[0]
    with_vel = vel.shape[0] > 0
    for k in range(pairs.shape[0]):
        iy, ix = pairs[k, 0], pairs[k, 1]
        jy, jx = (n - iy) % n, (n - ix) % n
        if bits < 0:
            h, g, _ = _pair(amp, omega, iy, ix, jy, jx, t)
        else:
            rot = phases[0, iy, ix]
            if bits & 1:
                rot = rot * phases[1, iy, ix]
            if bits & 2:
                rot = rot * phases[2, iy, ix]
            if bits & 4:
                rot = rot * phases[3, iy, ix]
            h, g = _pair_rot(amp, rot, omega[iy, ix], iy, ix, jy, jx)
        out[0, iy, ix] = h + 1j * g
        out[0, jy, jx] = h.conjugate() + 1j * g.conjugate()
        if choppy:
            hx, hy = khx[iy, ix], khy[iy, ix]
            out[1, iy, ix] = h * complex(hy, -hx)
            out[1, jy, jx] = h.conjugate() * complex(-hy, hx)
        if with_vel:
            rot = 1j * khx[iy, ix] - khy[iy, ix]
            vel[0, iy, ix] = g * rot
            vel[0, jy, jx] = -g.conjugate() * rot


@njit(cache=True)
def geometry_spectra(amp, omega, khx, khy, t, choppy, out):
    """One band's geometry spectra at time t into out[0] (h + i·w) and, when `choppy`, out[1] (Dx + i·Dy).

    Each (k, -k) pair is evaluated once (one sine and cosine per pair); bins without amplitude are zeroed.
    With a real field f = IFFT(F): f + i·g = IFFT(F + i·G), so two real fields cost one complex transform.
    """
    geometry_and_velocity_spectra(amp, omega, khx, khy, t, choppy, out, out[:0], np.zeros((4, 1, 1), np.complex128), -1)


@njit(cache=True)
def kinematic_spectra(amp, omega, khx, khy, t, acceleration, out):
    """One band's spectra at time t: out[0] = u + i·v, or with `acceleration` out[0] = ax + i·ay, out[1] = az."""
    n = amp.shape[0]
    for iy in range(n // 2 + 1):
        jy = (n - iy) % n
        for ix in range(_rows(n, iy)):
            jx = (n - ix) % n
            if amp[iy, ix] == 0 and amp[jy, jx] == 0:
                for s in range(out.shape[0]):
                    out[s, iy, ix] = out[s, jy, jx] = 0
                continue
            h, g, w = _pair(amp, omega, iy, ix, jy, jx, t)
            rot = 1j * khx[iy, ix] - khy[iy, ix]
            if acceleration:
                out[0, iy, ix] = -w * w * h * rot
                out[0, jy, jx] = w * w * h.conjugate() * rot
                out[1, iy, ix] = -w * w * h
                out[1, jy, jx] = -w * w * h.conjugate()
            else:
                out[0, iy, ix] = g * rot
                out[0, jy, jx] = -g.conjugate() * rot


@njit(cache=True, inline="always")
def _cell(x, inv_cell, mask):
    """Cell index, next index (periodic) and fraction along one axis; N = mask + 1 is a power of two."""
    u = x * inv_cell
    fu = math.floor(u)
    i = int(fu)
    return i & mask, (i + 1) & mask, u - fu


@njit(cache=True, inline="always")
def _blend4(tiles, wts, b, slot, iy0, iy1, ix0, ix1):
    """The four corner values of one cell, blended over the band's snapshots (zero weights skipped; four snapshots,
    a choppy sea's, in a loop of constant length: the same sums in the same order)."""
    c00 = c10 = c01 = c11 = 0j
    if wts.shape[1] == 4:
        for r in range(4):
            w = wts[b, r]
            if w != 0.0:
                c00 += w * tiles[b, r, slot, iy0, ix0]
                c10 += w * tiles[b, r, slot, iy0, ix1]
                c01 += w * tiles[b, r, slot, iy1, ix0]
                c11 += w * tiles[b, r, slot, iy1, ix1]
        return c00, c10, c01, c11
    for r in range(wts.shape[1]):
        w = wts[b, r]
        if w != 0.0:
            c00 += w * tiles[b, r, slot, iy0, ix0]
            c10 += w * tiles[b, r, slot, iy0, ix1]
            c01 += w * tiles[b, r, slot, iy1, ix0]
            c11 += w * tiles[b, r, slot, iy1, ix1]
    return c00, c10, c01, c11


@njit(cache=True, inline="always")
def _blend4_real(tiles, wts, b, slot, iy0, iy1, ix0, ix1):
    """`_blend4` of the real parts only (the height of geometry slot 0)."""
    c00 = c10 = c01 = c11 = 0.0
    if wts.shape[1] == 4:
        for r in range(4):
            w = wts[b, r]
            if w != 0.0:
                c00 += w * tiles[b, r, slot, iy0, ix0].real
                c10 += w * tiles[b, r, slot, iy0, ix1].real
                c01 += w * tiles[b, r, slot, iy1, ix0].real
                c11 += w * tiles[b, r, slot, iy1, ix1].real
        return c00, c10, c01, c11
    for r in range(wts.shape[1]):
        w = wts[b, r]
        if w != 0.0:
            c00 += w * tiles[b, r, slot, iy0, ix0].real
            c10 += w * tiles[b, r, slot, iy0, ix1].real
            c01 += w * tiles[b, r, slot, iy1, ix0].real
            c11 += w * tiles[b, r, slot, iy1, ix1].real
    return c00, c10, c01, c11


@njit(cache=True, inline="always")
def _bilinear(f00, f10, f01, f11, fx, fy, inv_cell):
    """Value and (∂/∂x, ∂/∂y) of the bilinear interpolant on one cell."""
    val = f00 * (1 - fx) * (1 - fy) + f10 * fx * (1 - fy) + f01 * (1 - fx) * fy + f11 * fx * fy
    dfx = ((f10 - f00) * (1 - fy) + (f11 - f01) * fy) * inv_cell
    dfy = ((f01 - f00) * (1 - fx) + (f11 - f10) * fx) * inv_cell
    return val, dfx, dfy


@njit(cache=True, inline="always")
def _evaluate(geo, wts, inv_cells, x0, y0, chop):
    """Displaced position, height, the Jacobian of X and the height gradient at label (x0, y0)."""
    mask = geo.shape[3] - 1
    X, Y, z, zx, zy = x0, y0, 0.0, 0.0, 0.0
    jxx, jxy, jyx, jyy = 1.0, 0.0, 0.0, 1.0
    for b in range(geo.shape[0]):
        ix0, ix1, fx = _cell(x0, inv_cells[b], mask)
        iy0, iy1, fy = _cell(y0, inv_cells[b], mask)
        a00, a10, a01, a11 = _blend4_real(geo, wts, b, 0, iy0, iy1, ix0, ix1)
        h, hx, hy = _bilinear(a00, a10, a01, a11, fx, fy, inv_cells[b])
        z += h
        zx += hx
        zy += hy
        if chop != 0.0:
            c00, c10, c01, c11 = _blend4(geo, wts, b, 1, iy0, iy1, ix0, ix1)
            dx, dxx, dxy = _bilinear(c00.real, c10.real, c01.real, c11.real, fx, fy, inv_cells[b])
            dy, dyx, dyy = _bilinear(c00.imag, c10.imag, c01.imag, c11.imag, fx, fy, inv_cells[b])
            X -= chop * dx
            Y -= chop * dy
            jxx -= chop * dxx
            jxy -= chop * dxy
            jyx -= chop * dyx
            jyy -= chop * dyy
    return X, Y, z, jxx, jxy, jyx, jyy, zx, zy


def _invert(px, py, geo, wts, inv_cells, chop, tol, max_iter, x0_out, y0_out, z_out, it_out):
    """Newton inversion of X(x0) = p on the interpolated tiles; fixed-point step where det J ≤ 1e-3."""
    for p in prange(px.shape[0]):
        x0 = px[p]
        y0 = py[p]
        it = 0
        while True:
            X, Y, z, jxx, jxy, jyx, jyy, _, _ = _evaluate(geo, wts, inv_cells, x0, y0, chop)
            rx = px[p] - X
            ry = py[p] - Y
            if rx * rx + ry * ry <= tol * tol or it >= max_iter:
                break
            det = jxx * jyy - jxy * jyx
            if det > 1e-3:
                x0 += (jyy * rx - jxy * ry) / det
                y0 += (jxx * ry - jyx * rx) / det
            else:
                x0 += rx
                y0 += ry
            it += 1
        x0_out[p] = x0
        y0_out[p] = y0
        z_out[p] = z
        it_out[p] = it


@njit(cache=True, inline="always")
def band_height(geo, wts, inv_cell, mask, b, x, y):
    """Band b's bilinear height at label (x, y): the value `_evaluate` adds for that band (same expression)."""
    ix0, ix1, fx = _cell(x, inv_cell, mask)
    iy0, iy1, fy = _cell(y, inv_cell, mask)
    a00, a10, a01, a11 = _blend4_real(geo, wts, b, 0, iy0, iy1, ix0, ix1)
    return a00 * (1 - fx) * (1 - fy) + a10 * fx * (1 - fy) + a01 * (1 - fx) * fy + a11 * fx * fy


@njit(cache=True, nogil=True)
def band_heights_cached(px, py, geo, wts, inv_cells, band_h, cache, stamp, now):
    """band_h[p, b] = `band_height` of every band at every point (labels = points), bit for bit, with each tile
    node's blend over the snapshots (the sum `_blend4_real` forms, in its order) computed once per blend state
    `now` and kept in `cache` (stamp[b, iy, ix] == now marks a current entry). A vessel's hull vertices share a
    handful of nodes of the long bands, so most of the per-point blending goes; and as neighbouring vertices
    mostly fall in the same cell (harbor, sea state 4: a new cell at 2, 9 and 16 % of the vertices in the three
    bands), each band's last four corners are kept and reused while the cell stays the same. (Written out in
    one loop: a helper called per node costs numba reference counting on every call, ~10x the work it saves.)"""
    mask = geo.shape[3] - 1
    nb = geo.shape[0]
    last = np.full((nb, 2), -1, np.int64)  # per band: the cell (ix0, iy0) whose corners are in `corners`
    corners = np.zeros((nb, 4))
    for p in range(px.shape[0]):
        for b in range(nb):
            ix0, ix1, fx = _cell(px[p], inv_cells[b], mask)
            iy0, iy1, fy = _cell(py[p], inv_cells[b], mask)
            if ix0 != last[b, 0] or iy0 != last[b, 1]:
                for iy, ix in ((iy0, ix0), (iy0, ix1), (iy1, ix0), (iy1, ix1)):
                    if stamp[b, iy, ix] != now:
                        c = 0.0
                        for r in range(wts.shape[1]):
                            w = wts[b, r]
                            if w != 0.0:
                                c += w * geo[b, r, 0, iy, ix].real
                        cache[b, iy, ix] = c
                        stamp[b, iy, ix] = now
                corners[b, 0], corners[b, 1] = cache[b, iy0, ix0], cache[b, iy0, ix1]
                corners[b, 2], corners[b, 3] = cache[b, iy1, ix0], cache[b, iy1, ix1]
                last[b, 0], last[b, 1] = ix0, iy0
            a00, a10, a01, a11 = corners[b, 0], corners[b, 1], corners[b, 2], corners[b, 3]
            band_h[p, b] = a00 * (1 - fx) * (1 - fy) + a10 * fx * (1 - fy) + a01 * (1 - fx) * fy + a11 * fx * fy


@njit(cache=True)
def heights_cached(px, py, geo, wts, inv_cells, z_out, band_h, cache, stamp, now):
    """`_heights` (serial) from `band_heights_cached`: bit for bit the same heights (z summed in band order)."""
    band_heights_cached(px, py, geo, wts, inv_cells, band_h, cache, stamp, now)
    for p in range(px.shape[0]):
        z = 0.0
        for b in range(geo.shape[0]):
            z += band_h[p, b]
        z_out[p] = z


def _heights(px, py, geo, wts, inv_cells, z_out):
    """Heights at world points of a sea without choppy displacement (labels = points): z summed exactly as
    `_evaluate` sums it, so bit for bit what `_invert` returns at its first iteration, without the gradients."""
    mask = geo.shape[3] - 1
    for p in prange(px.shape[0]):
        z = 0.0
        for b in range(geo.shape[0]):
            z += band_height(geo, wts, inv_cells[b], mask, b, px[p], py[p])
        z_out[p] = z


def _surface_points(x0, y0, geo, wts, inv_cells, chop, out, normals):
    """Displaced points and unit normals (of the interpolated surface) at labels (x0, y0)."""
    for p in prange(x0.shape[0]):
        X, Y, z, jxx, jxy, jyx, jyy, zx, zy = _evaluate(geo, wts, inv_cells, x0[p], y0[p], chop)
        out[p, 0], out[p, 1], out[p, 2] = X, Y, z
        # tangents Tx = (jxx, jyx, zx), Ty = (jxy, jyy, zy); n = Tx × Ty
        nx = jyx * zy - zx * jyy
        ny = zx * jxy - jxx * zy
        nz = jxx * jyy - jyx * jxy
        norm = math.sqrt(nx * nx + ny * ny + nz * nz)
        normals[p, 0], normals[p, 1], normals[p, 2] = nx / norm, ny / norm, nz / norm


@njit(cache=True, inline="always")
def _lerp(tiles, wts, b, slot, iy0, iy1, ix0, ix1, fx, fy):
    c00, c10, c01, c11 = _blend4(tiles, wts, b, slot, iy0, iy1, ix0, ix1)
    return (c00 * (1 - fx) + c10 * fx) * (1 - fy) + (c01 * (1 - fx) + c11 * fx) * fy


def _sample_kinematics(
    x0, y0, zeff, geo, geo_wts, vel, vel_wts, acc, acc_wts, inv_cells, decay_k, v_out, a_out
):
    """Bilinear velocity (and acceleration when a_out has rows) at labels, each band attenuated by exp(κ_b z')."""
    mask = geo.shape[3] - 1
    with_acc = a_out.shape[0] > 0
    for p in prange(x0.shape[0]):
        v_out[p, 0] = v_out[p, 1] = v_out[p, 2] = 0.0
        if with_acc:
            a_out[p, 0] = a_out[p, 1] = a_out[p, 2] = 0.0
        for b in range(geo.shape[0]):
            ix0, ix1, fx = _cell(x0[p], inv_cells[b], mask)
            iy0, iy1, fy = _cell(y0[p], inv_cells[b], mask)
            f = math.exp(decay_k[b] * zeff[p])
            uv = _lerp(vel, vel_wts, b, 0, iy0, iy1, ix0, ix1, fx, fy)
            hw = _lerp(geo, geo_wts, b, 0, iy0, iy1, ix0, ix1, fx, fy)
            v_out[p, 0] += f * uv.real
            v_out[p, 1] += f * uv.imag
            v_out[p, 2] += f * hw.imag
            if with_acc:
                axy = _lerp(acc, acc_wts, b, 0, iy0, iy1, ix0, ix1, fx, fy)
                az = _lerp(acc, acc_wts, b, 1, iy0, iy1, ix0, ix1, fx, fy)
                a_out[p, 0] += f * axy.real
                a_out[p, 1] += f * axy.imag
                a_out[p, 2] += f * az.real


# (serial, parallel) kernel pairs, chosen by the number of points with `dispatch.pick`.
INVERT = serial_and_parallel(_invert)
HEIGHTS = serial_and_parallel(_heights)
SURFACE_POINTS = serial_and_parallel(_surface_points)
SAMPLE_KINEMATICS = serial_and_parallel(_sample_kinematics)


_SAMPLE_KINEMATICS_SERIAL = SAMPLE_KINEMATICS[0]


@njit(cache=True)
def velocity_cached(px, py, pz, geo, geo_wts, vel, vel_wts, acc, acc_wts, inv_cells, decay_k, band_h, cache, stamp,
                    now, v_out):  # fmt: skip
    """`FFTWaveField.kinematics` without acceleration for a sea without displacement (labels = points), in one
    call: heights from `band_heights_cached`, z' = min(z - η, 0), then the serial `_sample_kinematics`; bit for
    bit the same velocities (m/s, ENU)."""
    n = px.shape[0]
    band_heights_cached(px, py, geo, geo_wts, inv_cells, band_h, cache, stamp, now)
    zeff = np.empty(n)
    for p in range(n):
        z = 0.0
        for b in range(geo.shape[0]):
            z += band_h[p, b]
        d = pz[p] - z
        zeff[p] = 0.0 if d > 0.0 else d  # np.minimum(d, 0.0), NaN kept
    if geo_wts.shape[1] == 8 and vel_wts.shape[1] == 8:  # the usual ring (fft_time.SNAPSHOTS): blends unrolled
        _sample_velocity(px, py, zeff, geo, geo_wts, vel, vel_wts, inv_cells, decay_k, v_out, 8)
    else:
        _SAMPLE_KINEMATICS_SERIAL(px, py, zeff, geo, geo_wts, vel, vel_wts, acc, acc_wts, inv_cells, decay_k, v_out,
                                  v_out[:0])  # fmt: skip


@njit(cache=True, inline="always")
def _lerp_k(tiles, wts, b, slot, iy0, iy1, ix0, ix1, fx, fy, k):
    """`_lerp` over k snapshots (k a constant where inlined: the loop unrolls; the same sums in the same order)."""
    c00 = c10 = c01 = c11 = 0j
    for r in range(k):
        w = wts[b, r]
        if w != 0.0:
            c00 += w * tiles[b, r, slot, iy0, ix0]
            c10 += w * tiles[b, r, slot, iy0, ix1]
            c01 += w * tiles[b, r, slot, iy1, ix0]
            c11 += w * tiles[b, r, slot, iy1, ix1]
    return (c00 * (1 - fx) + c10 * fx) * (1 - fy) + (c01 * (1 - fx) + c11 * fx) * fy


@njit(cache=True, inline="always")
def _sample_velocity(x0, y0, zeff, geo, geo_wts, vel, vel_wts, inv_cells, decay_k, v_out, k):
    """`_sample_kinematics` without acceleration (serial), each blend over k snapshots: the same expressions in
    the same order, bit for bit the same velocities."""
    mask = geo.shape[3] - 1
    for p in range(x0.shape[0]):
        v_out[p, 0] = v_out[p, 1] = v_out[p, 2] = 0.0
        for b in range(geo.shape[0]):
            ix0, ix1, fx = _cell(x0[p], inv_cells[b], mask)
            iy0, iy1, fy = _cell(y0[p], inv_cells[b], mask)
            f = math.exp(decay_k[b] * zeff[p])
            uv = _lerp_k(vel, vel_wts, b, 0, iy0, iy1, ix0, ix1, fx, fy, k)
            hw = _lerp_k(geo, geo_wts, b, 0, iy0, iy1, ix0, ix1, fx, fy, k)
            v_out[p, 0] += f * uv.real
            v_out[p, 1] += f * uv.imag
            v_out[p, 2] += f * hw.imag


@njit(cache=True)
def velocity_cached_points(points, level, geo, geo_wts, vel, vel_wts, acc, acc_wts, inv_cells, decay_k, band_h,
                           coords, cache, stamp, now, current, v_out):  # fmt: skip
    """`velocity_cached` at points (n,3) world m, z relative to `level` (z - level, as Ocean.kinematics forms it),
    plus a uniform current (3,) m/s added to each row (as Ocean adds its rows): `Ocean.velocity` for an FFT sea
    without displacement and a constant uniform current, bit for bit. coords (3, n): scratch."""
    for p in range(points.shape[0]):
        coords[0, p], coords[1, p], coords[2, p] = points[p, 0], points[p, 1], points[p, 2] - level
    velocity_cached(coords[0], coords[1], coords[2], geo, geo_wts, vel, vel_wts, acc, acc_wts, inv_cells, decay_k,
                    band_h, cache, stamp, now, v_out)  # fmt: skip
    for p in range(points.shape[0]):
        for k in range(3):
            v_out[p, k] = v_out[p, k] + current[k]
