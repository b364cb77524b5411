"""Direct sum of wave components (Airy or Gerstner): exact, unbounded queries (physics.md §4.3–§4.6).

The height at a world point p inverts the horizontal displacement with Newton's method on
X(x0) = p, X(x0) = x0 - Σ Q A d sin θ, J = I - Σ Q A k cos θ d dᵀ, starting at x0 = p; it stops when the
horizontal residual |p - X(x0)| < `tol` (default 1e-9 m) or after `max_iter` (default 30) iterations. Where the
Jacobian is nearly singular (Σ Q A k ≥ 1 lets the surface fold) the step falls back to the fixed-point step.
"""

from __future__ import annotations

import math
from typing import Literal, overload

import numpy as np
from numba import njit, prange

from usvsim.ocean.components import WaveComponents
from usvsim.ocean.dispatch import pick, serial_and_parallel
from usvsim.ocean.field import Labels, LabelsIterations, WaveField, as_points


@njit(cache=True, inline="always")
def _evaluate(x0, y0, t, amp, kx, ky, om, ph, qx, qy, s):
    """Displaced position, height, Jacobian (j00, j01, j11) and height gradient at label (x0, y0)."""
    X = x0
    Y = y0
    z = 0.0
    j00 = 1.0
    j01 = 0.0
    j11 = 1.0
    zx = 0.0
    zy = 0.0
    for i in range(amp.shape[0]):
        th = kx[i] * x0 + ky[i] * y0 - om[i] * t + ph[i]
        sn = math.sin(th)
        cs = math.cos(th)
        X -= s * qx[i] * sn
        Y -= s * qy[i] * sn
        z += s * amp[i] * cs
        j00 -= s * qx[i] * kx[i] * cs
        j01 -= s * qx[i] * ky[i] * cs
        j11 -= s * qy[i] * ky[i] * cs
        zx -= s * amp[i] * kx[i] * sn
        zy -= s * amp[i] * ky[i] * sn
    return X, Y, z, j00, j01, j11, zx, zy


def _invert_impl(px, py, t, amp, kx, ky, om, ph, qx, qy, s, tol, max_iter, x0_out, y0_out, z_out, it_out):
    """Newton inversion per point; writes labels, height and iteration count."""
    for p in prange(px.shape[0]):
        x0 = px[p]
        y0 = py[p]
        it = 0
        while True:
            X, Y, z, j00, j01, j11, zx, zy = _evaluate(x0, y0, t, amp, kx, ky, om, ph, qx, qy, s)
            rx = px[p] - X
            ry = py[p] - Y
            if rx * rx + ry * ry <= tol * tol or it >= max_iter:
                break
            det = j00 * j11 - j01 * j01
            if det > 1e-3:
                x0 += (j11 * rx - j01 * ry) / det
                y0 += (j00 * ry - j01 * rx) / det
            else:
                x0 += rx
                y0 += ry
            it += 1
        x0_out[p] = x0
        y0_out[p] = y0
        z_out[p] = z
        it_out[p] = it


def _heights_impl(px, py, t, amp, kx, ky, om, ph, s, z_out):
    """Heights at world points of a sea without horizontal displacement (every Q = 0): the label is the point,
    and z is summed exactly as `_evaluate` sums it (bit for bit what the Newton inversion returns at once)."""
    for p in prange(px.shape[0]):
        z = 0.0
        for i in range(amp.shape[0]):
            th = kx[i] * px[p] + ky[i] * py[p] - om[i] * t + ph[i]
            z += s * amp[i] * math.cos(th)
        z_out[p] = z


def _displaced_impl(x0, y0, t, amp, kx, ky, om, ph, qx, qy, s, out, normals):
    """Displaced surface points and unit normals at labels (x0, y0)."""
    for p in prange(x0.shape[0]):
        X, Y, z, j00, j01, j11, zx, zy = _evaluate(x0[p], y0[p], t, amp, kx, ky, om, ph, qx, qy, s)
        out[p, 0] = X
        out[p, 1] = Y
        out[p, 2] = z
        # tangents Tx = (j00, j01, zx), Ty = (j01, j11, zy); n = Tx × Ty
        nx = j01 * zy - zx * j11
        ny = zx * j01 - j00 * zy
        nz = j00 * j11 - j01 * j01
        norm = math.sqrt(nx * nx + ny * ny + nz * nz)
        normals[p, 0] = nx / norm
        normals[p, 1] = ny / norm
        normals[p, 2] = nz / norm


@njit(cache=True, inline="always")
def _profiles(k, z, depth):
    """Airy depth factors (horizontal, vertical) at depth z ≤ 0 (deep water when depth is inf)."""
    if depth == math.inf or k * depth > 20.0:
        e = math.exp(k * z)
        return e, e
    sh = math.sinh(k * depth)
    return math.cosh(k * (z + depth)) / sh, math.sinh(k * (z + depth)) / sh


def _kinematics_impl(x0, y0, zeff, t, amp, kx, ky, om, ph, s, depth, vel, acc):
    """Orbital velocity and acceleration (ENU) of linear waves, phases at labels, depth factors at zeff."""
    for p in prange(x0.shape[0]):
        u = v = w = au = av = aw = 0.0
        for i in range(amp.shape[0]):
            k = math.hypot(kx[i], ky[i])
            th = kx[i] * x0[p] + ky[i] * y0[p] - om[i] * t + ph[i]
            fh, fv = _profiles(k, zeff[p], depth)
            cs = math.cos(th)
            sn = math.sin(th)
            a1 = s * amp[i] * om[i]
            a2 = a1 * om[i]
            u += a1 * fh * cs * kx[i] / k
            v += a1 * fh * cs * ky[i] / k
            w += a1 * fv * sn
            au += a2 * fh * sn * kx[i] / k
            av += a2 * fh * sn * ky[i] / k
            aw -= a2 * fv * cs
        vel[p, 0] = u
        vel[p, 1] = v
        vel[p, 2] = w
        acc[p, 0] = au
        acc[p, 1] = av
        acc[p, 2] = aw


@njit(cache=True, parallel=True)
def naive_elevation_kernel(px, py, t, amp, kx, ky, om, ph, s, out):
    """η(p) = Σ A cos(k·p - ωt + φ) with no displacement inversion (VRX's ComputeDepthSimply): the baseline."""
    for p in prange(px.shape[0]):
        z = 0.0
        for i in range(amp.shape[0]):
            z += amp[i] * math.cos(kx[i] * px[p] + ky[i] * py[p] - om[i] * t + ph[i])
        out[p] = s * z


INVERT = serial_and_parallel(_invert_impl)
HEIGHTS = serial_and_parallel(_heights_impl)
DISPLACED = serial_and_parallel(_displaced_impl)
KINEMATICS = serial_and_parallel(_kinematics_impl)


class DirectWaveField(WaveField):
    """A sea given by explicit components, queried exactly anywhere (no tiles, no repetition).

    `depth` (m, inf = deep) sets the Airy depth profiles of the kinematics; the components' ω must already obey
    the dispersion relation at that depth (see `components.from_arrays`).
    """

    def __init__(
        self,
        components: WaveComponents,
        depth: float = math.inf,
        ramp_time_s: float = 0.0,
        tol: float = 1e-9,
        max_iter: int = 30,
    ):
        super().__init__(ramp_time_s)
        self.components = components
        self.depth = float(depth)
        self.tol = float(tol)
        self.max_iter = int(max_iter)
        c = components
        k = np.where(c.k > 0, c.k, 1.0)
        qa = c.steepness * c.amplitude
        self._args = (c.amplitude, c.kx, c.ky, c.omega, c.phase, qa * c.kx / k, qa * c.ky / k)
        self._flat_labels = not np.any(qa)  # no displacement: labels are the points, no inversion needed

    @overload
    def surface_labels(self, x, y, t: float, return_iterations: Literal[False] = False) -> Labels: ...
    @overload
    def surface_labels(self, x, y, t: float, return_iterations: Literal[True]) -> LabelsIterations: ...
    def surface_labels(self, x, y, t: float, return_iterations: bool = False) -> Labels | LabelsIterations:
        """Labels (x0, y0) displaced onto the world points, the height z there and optionally iterations used."""
        px, py = as_points(x, y)
        x0, y0, z = np.empty_like(px), np.empty_like(px), np.empty_like(px)
        iters = np.empty(px.shape, dtype=np.int64)
        if self._flat_labels:  # exactly what the inversion returns here, without the Jacobian's sines
            pick(HEIGHTS, len(px))(px, py, float(t), *self._args[:5], self.ramp(t), z)
            x0[:], y0[:], iters[:] = px, py, 0
            return (x0, y0, z, iters) if return_iterations else (x0, y0, z)
        pick(INVERT, len(px))(px, py, float(t), *self._args, self.ramp(t), self.tol, self.max_iter, x0, y0, z, iters)
        return (x0, y0, z, iters) if return_iterations else (x0, y0, z)

    def naive_elevation(self, x, y, t: float) -> np.ndarray:
        """η at the world point without inverting the displacement (wrong on a choppy sea; for comparison)."""
        px, py = as_points(x, y)
        out = np.empty_like(px)
        naive_elevation_kernel(px, py, float(t), *self._args[:5], self.ramp(t), out)
        return out

    def displaced_surface(self, x0, y0, t: float) -> np.ndarray:
        return self._displaced(x0, y0, t)[0]

    def normal(self, x, y, t: float) -> np.ndarray:
        """Unit surface normal (n, 3), ENU, at world points (x, y)."""
        x0, y0, _ = self.surface_labels(x, y, t)
        return self._displaced(x0, y0, t)[1]

    def _displaced(self, x0, y0, t):
        x0, y0 = as_points(x0, y0)
        out, normals = np.empty((len(x0), 3)), np.empty((len(x0), 3))
        pick(DISPLACED, len(x0))(x0, y0, float(t), *self._args, self.ramp(t), out, normals)
        return out, normals

    def kinematics(self, x, y, z, t: float) -> tuple[np.ndarray, np.ndarray]:
        """Orbital velocity and acceleration (n, 3), ENU, of linear (Airy) waves at world points.

        Phases are those of the surface label above the point; depth factors use Wheeler stretching,
        z' = (z - η) h/(h + η) clamped to [-h, 0] (deep water: z' = min(z - η, 0)), so the surface moves with the
        full surface velocity and points above the surface get the surface value.
        """
        px, py, pz = as_points(x, y, z)
        x0, y0, eta = self.surface_labels(px, py, t)
        if math.isinf(self.depth):
            zeff = np.minimum(pz - eta, 0.0)
        else:
            zeff = np.clip((pz - eta) * self.depth / (self.depth + eta), -self.depth, 0.0)
        vel, acc = np.empty((len(px), 3)), np.empty((len(px), 3))
        pick(KINEMATICS, len(x0))(x0, y0, zeff, float(t), *self._args[:5], self.ramp(t), self.depth, vel, acc)
        return vel, acc

    def velocity(self, x, y, z, t: float) -> np.ndarray:
        return self.kinematics(x, y, z, t)[0]

    def acceleration(self, x, y, z, t: float) -> np.ndarray:
        return self.kinematics(x, y, z, t)[1]
