"""The radar beam as rays: which directions are cast for a run of spokes, and what each ray stands for.

Azimuth: every spoke is sampled by `oversampling` rays across its width, and the sector is cast with the
spokes half a beam width beyond either end, so the horizontal two-way beam pattern
G(Δθ) = exp(-8 ln2 (Δθ / θ_h)²) (half power one-way at ±θ_h/2) can be applied as a weight matrix.

Elevation: a target on the water at range r spans elevations from -atan(h / r) upwards (h = antenna height),
a band that shrinks with range; the vertical beam (tens of degrees) is far wider. So rays are not spread
evenly: `n_down` rays point at the water at ranges log-spaced over the display (ray k meets the water at r_k
unless something stands in the way, which also tells where sea clutter is shadowed), and the rest go up to
~11° for tall structures. Rays are levelled with the horizon (a pitching hull must not tip the sparse
near-horizon rays into the sea); each stands for the solid angle Δaz · Δel · cos(el) around it, weighted by
the vertical two-way pattern about the antenna's tilted plane.
"""

from __future__ import annotations

import math

import numpy as np

LN2_8 = 8.0 * math.log(2.0)


def two_way_gain(offset_rad: np.ndarray, beamwidth_rad: float) -> np.ndarray:
    return np.exp(-LN2_8 * (offset_rad / beamwidth_rad) ** 2)


def elevations(height_m: float, range_min_m: float, range_max_m: float, n: int, up_to_rad: float = 0.2):
    """Levelled ray elevations (n,) rad, the range (n,) m at which each meets the water (inf above the horizon),
    and the elevation interval (n,) rad each stands for."""
    h = max(height_m, 0.1)
    n_up = max(1, n // 4)
    water = np.geomspace(max(range_min_m, 2.0 * h, 1.0), 1.25 * range_max_m, n - n_up)
    el = np.concatenate([-np.arctan(h / water), np.linspace(up_to_rad / n_up, up_to_rad, n_up)])
    edges = np.concatenate([[el[0] - 0.5 * (el[1] - el[0])], 0.5 * (el[1:] + el[:-1]), [el[-1]]])
    return el, np.concatenate([water, np.full(n_up, np.inf)]), np.diff(edges)


class SpokeRays:
    """Ray azimuths for spokes k0 .. k0 + count - 1 (sensor frame, CCW from the bow) and the horizontal weights."""

    def __init__(self, spokes: int, hbw_rad: float, oversampling: int):
        self.spokes, self.oversampling = spokes, oversampling
        self.step = 2.0 * math.pi / spokes
        self.margin = int(math.ceil(hbw_rad / self.step))  # spokes cast beyond each end of a sector
        self.hbw = hbw_rad

    def azimuths(self, k0: int, count: int) -> np.ndarray:
        """Fine ray azimuths (rad) covering spokes k0 - margin .. k0 + count - 1 + margin."""
        m = self.oversampling
        first = (k0 - self.margin) * m
        j = np.arange(first, first + (count + 2 * self.margin) * m)
        return (j + 0.5) * self.step / m - 0.5 * self.step

    def weights(self, count: int) -> np.ndarray:
        """(count, fine rays) horizontal gain of each fine ray for each output spoke."""
        fine = self.azimuths(0, count)
        centres = np.arange(count) * self.step
        return two_way_gain(fine[None, :] - centres[:, None], self.hbw)
