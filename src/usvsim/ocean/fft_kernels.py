"""Numba kernels of the FFT wave field: spectra at time t, and bilinear tile queries with Newton inversion.

Tiles are complex64 arrays [band, slot, iy, ix] with cell (iy, ix) at world (ix, iy)·L/N (periodic). Geometry
slots: 0 = h + i·Dx, 1 = Dy + i·w. Kinematics slots: 0 = u + i·v, 1 = ax + i·ay, 2 = az. The displaced surface is
X = x0 - c·D(x0), z = h(x0), with D, h bilinear in each cell, so the physics queries the very surface that a
renderer draws from the same tiles (and at tile vertices the two coincide exactly).
"""

from __future__ import annotations

import math

from numba import njit, prange

from usvsim.ocean.dispatch import serial_and_parallel


@njit(cache=True, inline="always")
def _pair(amp, omega, b, iy, ix, jy, jx, t):
    """H and G = ∂H/∂t at k and -k: E = ½ c e^{-iωt}, H(k) = E(k) + conj(E(-k)), H(-k) = conj(H(k))."""
    w = omega[b, iy, ix]
    rot = complex(math.cos(w * t), -math.sin(w * t))
    e = 0.5 * amp[b, iy, ix] * rot
    em = (0.5 * amp[b, jy, jx] * rot).conjugate()
    return e + em, -1j * w * (e - em), w


@njit(cache=True, inline="always")
def _rows(n, iy):
    """Columns of row iy that are canonical in their (k, -k) pair; rows 0 and n/2 pair with themselves."""
    return n // 2 + 1 if iy == 0 or iy == n // 2 else n


def _geometry_spectra(amp, omega, khx, khy, t, out):
    """Write the geometry spectra of every band at time t into out[b, 0:2] (see module docstring).

    Each (k, -k) pair is evaluated once (one sine and cosine per pair); bins without amplitude are zeroed.
    """
    nb, n = amp.shape[0], amp.shape[1]
    for b in range(nb):
        for iy in prange(n // 2 + 1):
            jy = (n - iy) % n
            for ix in range(_rows(n, iy)):
                jx = (n - ix) % n
                if amp[b, iy, ix] == 0 and amp[b, jy, jx] == 0:
                    out[b, 0, iy, ix] = out[b, 1, iy, ix] = out[b, 0, jy, jx] = out[b, 1, jy, jx] = 0
                    continue
                h, g, _ = _pair(amp, omega, b, iy, ix, jy, jx, t)
                hx, hy = khx[b, iy, ix], khy[b, iy, ix]
                out[b, 0, iy, ix] = h * (1.0 + hx)
                out[b, 1, iy, ix] = -1j * hy * h + 1j * g
                out[b, 0, jy, jx] = h.conjugate() * (1.0 - hx)
                out[b, 1, jy, jx] = 1j * hy * h.conjugate() + 1j * g.conjugate()


def _kinematic_spectra(amp, omega, khx, khy, t, out):
    """Write the kinematics spectra of every band at time t into out[b, 0:3] (see module docstring)."""
    nb, n = amp.shape[0], amp.shape[1]
    for b in range(nb):
        for iy in prange(n // 2 + 1):
            jy = (n - iy) % n
            for ix in range(_rows(n, iy)):
                jx = (n - ix) % n
                h, g, w = _pair(amp, omega, b, iy, ix, jy, jx, t)
                rot = 1j * khx[b, iy, ix] - khy[b, iy, ix]
                rot_m = -1j * khx[b, iy, ix] + khy[b, iy, ix]
                out[b, 0, iy, ix] = g * rot
                out[b, 1, iy, ix] = -w * w * h * rot
                out[b, 2, iy, ix] = -w * w * h
                out[b, 0, jy, jx] = g.conjugate() * rot_m
                out[b, 1, jy, jx] = -w * w * h.conjugate() * rot_m
                out[b, 2, jy, jx] = -w * w * h.conjugate()


@njit(cache=True, inline="always")
def _cell(x, inv_cell, mask):
    """Cell index, next index (periodic) and fraction along one axis; N = mask + 1 is a power of two."""
    u = x * inv_cell
    fu = math.floor(u)
    i = int(fu)
    return i & mask, (i + 1) & mask, u - fu


@njit(cache=True, inline="always")
def _bilinear(f00, f10, f01, f11, fx, fy, inv_cell):
    """Value and (∂/∂x, ∂/∂y) of the bilinear interpolant on one cell."""
    val = f00 * (1 - fx) * (1 - fy) + f10 * fx * (1 - fy) + f01 * (1 - fx) * fy + f11 * fx * fy
    dfx = ((f10 - f00) * (1 - fy) + (f11 - f01) * fy) * inv_cell
    dfy = ((f01 - f00) * (1 - fx) + (f11 - f10) * fx) * inv_cell
    return val, dfx, dfy


@njit(cache=True, inline="always")
def _evaluate(geo, inv_cells, x0, y0, s, chop):
    """Displaced position, height and the Jacobian of X at label (x0, y0), summed over bands."""
    mask = geo.shape[2] - 1
    X, Y, z = x0, y0, 0.0
    jxx, jxy, jyx, jyy = 1.0, 0.0, 0.0, 1.0
    for b in range(geo.shape[0]):
        ix0, ix1, fx = _cell(x0, inv_cells[b], mask)
        iy0, iy1, fy = _cell(y0, inv_cells[b], mask)
        a00, a10, a01, a11 = (
            geo[b, 0, iy0, ix0],
            geo[b, 0, iy0, ix1],
            geo[b, 0, iy1, ix0],
            geo[b, 0, iy1, ix1],
        )
        c00, c10, c01, c11 = (
            geo[b, 1, iy0, ix0],
            geo[b, 1, iy0, ix1],
            geo[b, 1, iy1, ix0],
            geo[b, 1, iy1, ix1],
        )
        h, _, _ = _bilinear(a00.real, a10.real, a01.real, a11.real, fx, fy, inv_cells[b])
        dx, dxx, dxy = _bilinear(a00.imag, a10.imag, a01.imag, a11.imag, fx, fy, inv_cells[b])
        dy, dyx, dyy = _bilinear(c00.real, c10.real, c01.real, c11.real, fx, fy, inv_cells[b])
        z += s * h
        X -= s * chop * dx
        Y -= s * chop * dy
        jxx -= s * chop * dxx
        jxy -= s * chop * dxy
        jyx -= s * chop * dyx
        jyy -= s * chop * dyy
    return X, Y, z, jxx, jxy, jyx, jyy


def _invert(px, py, geo, inv_cells, s, chop, tol, max_iter, x0_out, y0_out, z_out, it_out):
    """Newton inversion of X(x0) = p on the interpolated tiles; fixed-point step where det J ≤ 1e-3."""
    for p in prange(px.shape[0]):
        x0 = px[p]
        y0 = py[p]
        it = 0
        while True:
            X, Y, z, jxx, jxy, jyx, jyy = _evaluate(geo, inv_cells, x0, y0, s, chop)
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


def _surface_points(x0, y0, geo, inv_cells, s, chop, out, normals):
    """Displaced points and unit normals (of the interpolated surface) at labels (x0, y0)."""
    mask = geo.shape[2] - 1
    for p in prange(x0.shape[0]):
        X, Y, z, jxx, jxy, jyx, jyy = _evaluate(geo, inv_cells, x0[p], y0[p], s, chop)
        zx = 0.0
        zy = 0.0
        for b in range(geo.shape[0]):
            ix0, ix1, fx = _cell(x0[p], inv_cells[b], mask)
            iy0, iy1, fy = _cell(y0[p], inv_cells[b], mask)
            h00, h10 = geo[b, 0, iy0, ix0].real, geo[b, 0, iy0, ix1].real
            h01, h11 = geo[b, 0, iy1, ix0].real, geo[b, 0, iy1, ix1].real
            _, hx, hy = _bilinear(h00, h10, h01, h11, fx, fy, inv_cells[b])
            zx += s * hx
            zy += s * hy
        out[p, 0], out[p, 1], out[p, 2] = X, Y, z
        # tangents Tx = (jxx, jyx, zx), Ty = (jxy, jyy, zy); n = Tx × Ty
        nx = jyx * zy - zx * jyy
        ny = zx * jxy - jxx * zy
        nz = jxx * jyy - jyx * jxy
        norm = math.sqrt(nx * nx + ny * ny + nz * nz)
        normals[p, 0], normals[p, 1], normals[p, 2] = nx / norm, ny / norm, nz / norm


@njit(cache=True, inline="always")
def _lerp(tiles, b, slot, iy0, iy1, ix0, ix1, fx, fy):
    top = tiles[b, slot, iy0, ix0] * (1 - fx) + tiles[b, slot, iy0, ix1] * fx
    bottom = tiles[b, slot, iy1, ix0] * (1 - fx) + tiles[b, slot, iy1, ix1] * fx
    return top * (1 - fy) + bottom * fy


def _sample_kinematics(x0, y0, zeff, geo, kin, inv_cells, decay_k, s, vel, acc):
    """Bilinear velocity/acceleration at labels, each band attenuated by exp(κ_b z') (deep water)."""
    mask = geo.shape[2] - 1
    for p in prange(x0.shape[0]):
        vel[p, 0] = vel[p, 1] = vel[p, 2] = acc[p, 0] = acc[p, 1] = acc[p, 2] = 0.0
        for b in range(geo.shape[0]):
            ix0, ix1, fx = _cell(x0[p], inv_cells[b], mask)
            iy0, iy1, fy = _cell(y0[p], inv_cells[b], mask)
            f = s * math.exp(decay_k[b] * zeff[p])
            uv = _lerp(kin, b, 0, iy0, iy1, ix0, ix1, fx, fy)
            axy = _lerp(kin, b, 1, iy0, iy1, ix0, ix1, fx, fy)
            az = _lerp(kin, b, 2, iy0, iy1, ix0, ix1, fx, fy)
            w = _lerp(geo, b, 1, iy0, iy1, ix0, ix1, fx, fy)
            vel[p, 0] += f * uv.real
            vel[p, 1] += f * uv.imag
            vel[p, 2] += f * w.imag
            acc[p, 0] += f * axy.real
            acc[p, 1] += f * axy.imag
            acc[p, 2] += f * az.real


# (serial, parallel) kernel pairs, chosen by batch size (points or spectrum bins) with `dispatch.pick`.
GEOMETRY_SPECTRA = serial_and_parallel(_geometry_spectra)
KINEMATIC_SPECTRA = serial_and_parallel(_kinematic_spectra)
INVERT = serial_and_parallel(_invert)
SURFACE_POINTS = serial_and_parallel(_surface_points)
SAMPLE_KINEMATICS = serial_and_parallel(_sample_kinematics)
