"""Linear-wave (Froude–Krylov) pressure under the waves, for the hull pressure integral.

Airy theory: the pressure at depth in a wave component of amplitude a, wavenumber k and phase θ is
p = -ρ g z + ρ g a cos θ · F(k, z), F = e^{kz} in deep water, cosh(k(z + h))/cosh(kh) at depth h. Short waves
barely reach a hull's bottom, long waves act like a hydrostatic column under the local surface (F → 1).
Above z = 0 linear theory says nothing; Wheeler stretching maps the wetted column [-h, η] onto [-h, 0]:
z' = (z - η) h/(h + η) (deep: z' = z - η), so the pressure is exactly 0 at the moving surface.

Returned as heads (m, p / (ρ g)): the *dynamic head* ζ(x, y, z) = Σ a cos θ F(k, z') (the wave part; = η at the
surface and in the long-wave limit), and the hull kernel's pressure head ζ - z. Frames: world ENU, z up,
heights relative to the still-water level.

Direct seas sum their components exactly (phases at the surface label above the point, as the kinematics).
FFT seas decay each band's height by exp(κ_b z') with κ_b the band's variance-weighted mean wavenumber (an
approximation within a band, as for the FFT kinematics).
"""

from __future__ import annotations

import math
import weakref
from typing import TypeGuard

import numpy as np
from numba import njit, prange

from usvsim.ocean.direct import DirectWaveField
from usvsim.ocean.dispatch import pick, serial_and_parallel
from usvsim.ocean.fft import FFTWaveField
from usvsim.ocean.fft_kernels import (
    _bilinear,
    _blend4_real,
    _cell,
    band_height,
    heights_cached,
)
from usvsim.ocean.field import WaveField, as_points
from usvsim.ocean.spectra import G


def _direct_head_impl(x0, y0, zrel, eta, t, amp, kx, ky, om, ph, s, depth, out):
    """ζ = s Σ a cos θ F(k, z') at labels (x0, y0) of points at zrel under the surface eta (Wheeler z');
    ζ = η at points above it (their head η - z < 0 is never integrated)."""
    deep = math.isinf(depth)
    for p in prange(x0.shape[0]):
        if zrel[p] >= eta[p]:
            out[p] = eta[p]
            continue
        zp = zrel[p] - eta[p] if deep else max((zrel[p] - eta[p]) * depth / (depth + eta[p]), -depth)
        acc = 0.0
        for i in range(amp.shape[0]):
            k = math.hypot(kx[i], ky[i])
            th = kx[i] * x0[p] + ky[i] * y0[p] - om[i] * t + ph[i]
            if deep or k * depth > 20.0:
                f = math.exp(k * zp)
            else:
                f = math.cosh(k * (zp + depth)) / math.cosh(k * depth)
            acc += amp[i] * math.cos(th) * f
        out[p] = s * acc


def _fft_head_impl(x0, y0, zrel, eta, geo, wts, inv_cells, decay_k, out):
    """ζ = Σ_b exp(κ_b z') η_b(label), z' = zrel - eta (deep water): each band's bilinear height, attenuated;
    ζ = η at points above the surface."""
    mask = geo.shape[3] - 1
    for p in prange(x0.shape[0]):
        zp = zrel[p] - eta[p]
        if zp >= 0.0:
            out[p] = eta[p]
            continue
        acc = 0.0
        for b in range(geo.shape[0]):
            ix0, ix1, fx = _cell(x0[p], inv_cells[b], mask)
            iy0, iy1, fy = _cell(y0[p], inv_cells[b], mask)
            a00, a10, a01, a11 = _blend4_real(geo, wts, b, 0, iy0, iy1, ix0, ix1)
            h, _, _ = _bilinear(a00, a10, a01, a11, fx, fy, inv_cells[b])
            acc += math.exp(decay_k[b] * zp) * h
        out[p] = acc


@njit(cache=True)
def _direct_surface_and_head(px, py, zrel, t, amp, kx, ky, om, ph, s, depth, k_abs, cos_th, eta_out, zeta_out):
    """η and ζ at world points of a direct sea without displacement (labels = points) in one pass over the
    components: each cos θ once (kept in `cos_th`), η summed as `direct._heights_impl` sums it and ζ as
    `_direct_head_impl` does, so both equal the two-pass results bit for bit. Serial (one scratch row)."""
    deep = math.isinf(depth)
    for i in range(amp.shape[0]):
        k_abs[i] = math.hypot(kx[i], ky[i])
    for p in range(px.shape[0]):
        z = 0.0
        for i in range(amp.shape[0]):
            c = math.cos(kx[i] * px[p] + ky[i] * py[p] - om[i] * t + ph[i])
            cos_th[i] = c
            z += s * amp[i] * c
        eta_out[p] = z
        if zrel[p] >= z:
            zeta_out[p] = z
            continue
        zp = zrel[p] - z if deep else max((zrel[p] - z) * depth / (depth + z), -depth)
        acc = 0.0
        for i in range(amp.shape[0]):
            k = k_abs[i]
            if deep or k * depth > 20.0:
                f = math.exp(k * zp)
            else:
                f = math.cosh(k * (zp + depth)) / math.cosh(k * depth)
            acc += amp[i] * cos_th[i] * f
        zeta_out[p] = s * acc


@njit(inline="always")
def _head_from_bands(band_h, p, z, zrel_p, decay_k):
    """ζ at point p from its band heights band_h[p] (summed to η = z): the surface value above the surface,
    else each band decayed by exp(k_b (zrel - η)), summed in band order."""
    zp = zrel_p - z
    if zp >= 0.0:
        return z
    acc = 0.0
    for b in range(band_h.shape[1]):
        acc += math.exp(decay_k[b] * zp) * band_h[p, b]
    return acc


def _fft_surface_and_head_impl(px, py, zrel, geo, wts, inv_cells, decay_k, band_h, eta_out, zeta_out):
    """η and ζ at world points of an FFT sea without choppy displacement (labels = points) in one pass over the
    tiles: each band's bilinear height h_b is computed once (kept in `band_h`), η = Σ h_b as `fft_kernels._heights`
    sums it and ζ as `_fft_head_impl` sums it, so both equal the two-pass results bit for bit."""
    mask = geo.shape[3] - 1
    for p in prange(px.shape[0]):
        z = 0.0
        for b in range(geo.shape[0]):
            h = band_height(geo, wts, inv_cells[b], mask, b, px[p], py[p])
            band_h[p, b] = h
            z += h
        eta_out[p] = z
        zeta_out[p] = _head_from_bands(band_h, p, z, zrel[p], decay_k)


@njit(cache=True)
def fft_surface_and_head_cached(px, py, zrel, geo, wts, inv_cells, decay_k, band_h, eta_out, zeta_out, cache, stamp,
                                now):  # fmt: skip
    """`_fft_surface_and_head_impl` (serial) with the band heights from `fft_kernels.band_heights_cached` (each
    blended tile node once per blend state): bit for bit the same η and ζ."""
    heights_cached(px, py, geo, wts, inv_cells, eta_out, band_h, cache, stamp, now)
    for p in range(px.shape[0]):
        zeta_out[p] = _head_from_bands(band_h, p, eta_out[p], zrel[p], decay_k)


@njit(cache=True, nogil=True)  # nogil: a snapshot being made ahead (FFTWaveField.AHEAD) may take the GIL meanwhile
def fft_hull_water_cached(verts, level, geo, wts, inv_cells, decay_k, eta_out, head_out, cache, stamp, now):
    """What world.World._water computes for hull vertices (N,3) world m under an FFT sea without displacement,
    every vertex Froude-Krylov, in one call: eta_out = η + level (surface z) and head_out = ζ + level - z (the
    hull kernel's pressure head), with η, ζ of `fft_surface_and_head_cached` at (x, y, z - level); the same
    operations as the array code, bit for bit, in one pass over the vertices: each band's height as
    `fft_kernels.band_heights_cached` makes it (its node cache and last-cell corners), kept for the vertex only
    (a fleet's per-band heights, 2.7 MB at 200 WAM-Vs, are not written out and read back): `hull_water_rows` over
    every row (hydro/fused.py calls it a body's rows at a time)."""
    last, corners, hb = water_scratch(geo.shape[0])
    hull_water_rows(verts, 0, verts.shape[0], level, geo, wts, inv_cells, decay_k, eta_out, head_out, cache, stamp,
                    now, last, corners, hb)  # fmt: skip


@njit(cache=True, nogil=True)
def water_scratch(bands):
    """(last, corners, hb): the per-band state `hull_water_rows` carries from one vertex (and one call) to the next:
    no cell yet, zero corners, one vertex's band heights."""
    return np.full((bands, 2), -1, np.int64), np.zeros((bands, 4)), np.empty((1, bands))


@njit(cache=True, nogil=True)
def hull_water_rows(verts, v0, v1, level, geo, wts, inv_cells, decay_k, eta_out, head_out, cache, stamp, now, last,
                    corners, hb):  # fmt: skip
    """The loop of `fft_hull_water_cached` for vertex rows v0:v1 (rows outside untouched), `last` and `corners`
    carried between calls (`water_scratch`). The values do not depend on which rows came before: a
    row range at a time (one body's vertices, hydro/fused.py) gives the bits of one pass over all rows."""
    mask = geo.shape[3] - 1
    nb = geo.shape[0]
    for p in range(v0, v1):
        x, y = verts[p, 0], verts[p, 1]
        z = 0.0
        for b in range(nb):
            ix0, ix1, fx = _cell(x, inv_cells[b], mask)
            iy0, iy1, fy = _cell(y, inv_cells[b], mask)
            if ix0 != last[b, 0] or iy0 != last[b, 1]:
                for iy, ix in ((iy0, ix0), (iy0, ix1), (iy1, ix0), (iy1, ix1)):
                    if stamp[b, iy, ix] != now:
                        c = 0.0
                        for r in range(wts.shape[1]):  # (written out: as an inlined helper ~1.4 us slower)
                            w = wts[b, r]
                            if w != 0.0:
                                c += w * geo[b, r, 0, iy, ix].real
                        cache[b, iy, ix] = c
                        stamp[b, iy, ix] = now
                corners[b, 0], corners[b, 1] = cache[b, iy0, ix0], cache[b, iy0, ix1]
                corners[b, 2], corners[b, 3] = cache[b, iy1, ix0], cache[b, iy1, ix1]
                last[b, 0], last[b, 1] = ix0, iy0
            a00, a10, a01, a11 = corners[b, 0], corners[b, 1], corners[b, 2], corners[b, 3]
            h = a00 * (1 - fx) * (1 - fy) + a10 * fx * (1 - fy) + a01 * (1 - fx) * fy + a11 * fx * fy
            hb[0, b] = h
            z += h  # η summed in band order, as `fft_kernels.heights_cached` sums it
        zeta = _head_from_bands(hb, 0, z, verts[p, 2] - level, decay_k)
        eta_out[p] = z + level
        head_out[p] = (zeta + level) - verts[p, 2]


def serial_fft(waves: WaveField | None, n: int) -> TypeGuard[FFTWaveField]:
    """Whether `waves` is an FFT sea without displacement whose queries of n points the serial kernels answer
    (what `hull_water` does in one call; the fused hull pass, hydro/fused.py, needs it)."""
    return (isinstance(waves, FFTWaveField) and waves.choppiness == 0.0
            and pick(FFT_SURFACE_AND_HEAD, n) is FFT_SURFACE_AND_HEAD[0])  # fmt: skip


def hull_water(waves: WaveField, verts: np.ndarray, level: float, t: float, eta: np.ndarray, head: np.ndarray) -> bool:
    """Fill eta (surface z, m) and head (ζ + level - z, m) at hull vertices `verts` (N,3) in one compiled call when
    `waves` is an FFT sea without displacement answered by the serial kernels; False (nothing done) otherwise."""
    if not (isinstance(waves, FFTWaveField) and waves.choppiness == 0.0):
        return False
    n = len(verts)
    if pick(FFT_SURFACE_AND_HEAD, n) is not FFT_SURFACE_AND_HEAD[0]:
        return False
    wts = waves.update(t)
    fft_hull_water_cached(verts, float(level), waves.geometry.tiles, wts, waves.inv_cells,
                          height_decay_wavenumbers(waves), eta, head, *waves.node_cache())  # fmt: skip
    return True


DIRECT_HEAD = serial_and_parallel(_direct_head_impl)
FFT_SURFACE_AND_HEAD = serial_and_parallel(_fft_surface_and_head_impl)
FFT_HEAD = serial_and_parallel(_fft_head_impl)
_HEIGHT_DECAY: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def height_decay_wavenumbers(waves: FFTWaveField) -> np.ndarray:
    """Per band, the mean k (rad/m) weighted by height variance |c|²: the band's pressure decay rate."""
    kept = waves.__dict__.get("_height_decay_k")  # (read every wavy step: an attribute, not a weak-dict lookup)
    if kept is not None:
        return kept
    if waves not in _HEIGHT_DECAY:
        weight = np.abs(waves._amp) ** 2
        k = waves._omega**2 / G
        total = weight.sum(axis=(1, 2))
        safe = np.where(total > 0, total, 1.0)
        _HEIGHT_DECAY[waves] = np.ascontiguousarray(np.where(total > 0, (weight * k).sum(axis=(1, 2)) / safe, 0.0))
    waves.__dict__["_height_decay_k"] = _HEIGHT_DECAY[waves]
    return _HEIGHT_DECAY[waves]


def surface_and_dynamic_head(waves: WaveField, x, y, z, t: float) -> tuple[np.ndarray, np.ndarray]:
    """(η, ζ) at world points (x, y, z), heights relative to still water (m); one displacement inversion for
    both (what `elevation` costs, plus the depth sums at the points under the surface). Fields without a
    depth model (none today) give ζ = η, the hydrostatic column under the local surface."""
    px, py, pz = as_points(x, y, z)
    n = len(px)
    zeta = np.empty(n)
    if isinstance(waves, DirectWaveField) and waves._flat_labels:  # labels = points
        eta, scratch = np.empty(n), np.empty((2, len(waves._args[0])))
        _direct_surface_and_head(px, py, pz, float(t), *waves._args[:5], waves.ramp(t), waves.depth, scratch[0],
                                 scratch[1], eta, zeta)  # fmt: skip
    elif isinstance(waves, DirectWaveField):
        x0, y0, eta = waves.surface_labels(px, py, t)  # the inversion (skipped without displacement)
        pick(DIRECT_HEAD, n)(x0, y0, pz, eta, float(t), *waves._args[:5], waves.ramp(t), waves.depth, zeta)
    elif isinstance(waves, FFTWaveField) and waves.choppiness == 0.0:  # deep water, labels = points
        eta, band_h = np.empty(n), np.empty((n, len(waves.inv_cells)))
        args = (px, py, pz, waves.geometry.tiles, waves.update(t), waves.inv_cells, height_decay_wavenumbers(waves),
                band_h, eta, zeta)  # fmt: skip
        kernel = pick(FFT_SURFACE_AND_HEAD, n)
        if kernel is FFT_SURFACE_AND_HEAD[0]:  # serial: blended tile nodes once per blend state
            fft_surface_and_head_cached(*args, *waves.node_cache())
        else:
            kernel(*args)
    elif isinstance(waves, FFTWaveField):  # deep water
        x0, y0, eta = waves.surface_labels(px, py, t)
        pick(FFT_HEAD, n)(x0, y0, pz, eta, waves.geometry.tiles, waves.update(t), waves.inv_cells,
                          height_decay_wavenumbers(waves), zeta)  # fmt: skip
    else:
        eta = np.array(waves.elevation(px, py, t), dtype=float).ravel()
        zeta[:] = eta
    return eta, zeta
