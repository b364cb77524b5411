"""Rings of raindrops on the water (drawn by the water shader when rain is on; shaders.WATER_FS, `#ifdef RAIN`).

A drop that hits the sea leaves a ring of capillary-gravity waves that spreads at a few tens of cm/s and dies out
in a fraction of a second; only the larger drops leave rings a camera sees. The shader places the rings on a grid
of cells (RING_CELL = 0.2 m): each cell holds at most one ring at a time, once per cycle of RING_PERIOD = 0.4 s,
with a chance per cycle, its phase and the drop's place drawn by an integer hash of the cell, the cycle and the
simulation's seed (same seed and time, same bytes). The chance follows the rain rate: the flux of drops larger
than 2 mm (Marshall–Palmer drop sizes N(D) = 8000 e^(-ΛD) per m³ per mm, Λ = 4.1 R^-0.21 per mm, R in mm/h;
fall speed v = 3.78 D^0.67 m/s, Atlas & Ulbrich 1977) over the most the cells can hold (1 / (0.2² · 0.4) =
62.5 per m² per s): 2.5 mm/h: 18 per m² per s (chance 0.29), 5 mm/h: 53 (0.84), 10 mm/h: 136 (1: saturated). The rings change the
normals only (RGB): the surface that depth and labels hold, and the physics, never see them. They fade out where a
pixel grows from one to three ring widths (5-14 m away from a VGA camera), as the eye loses them too.
"""

from __future__ import annotations

import numpy as np

RING_CELL_M = 0.2  # as shaders.WATER_FS's RING_CELL and RING_PERIOD
RING_PERIOD_S = 0.4
RING_STRENGTH = 2.0  # the rings' steepest slope is 0.86 times this (height exp(-x²/w²), w = 1.2 cm); set by eye
MIN_RING_DROP_MM = 2.0


def ringing_drop_flux(rate_mm_h: float, min_diameter_mm: float = MIN_RING_DROP_MM) -> float:
    """Drops larger than `min_diameter_mm` hitting a square metre of sea per second (Marshall–Palmer sizes,
    Atlas–Ulbrich fall speeds)."""
    if rate_mm_h <= 0:
        return 0.0
    lam = 4.1 * rate_mm_h**-0.21
    d = np.linspace(min_diameter_mm, min_diameter_mm + 40.0 / lam, 2001)
    f = 8000.0 * np.exp(-lam * d) * 3.78 * d**0.67
    return float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(d)))


def ring_chance(rate_mm_h: float) -> float:
    """The chance that a ring cell holds a drop in one cycle (the shader's u_rain.x)."""
    return min(ringing_drop_flux(rate_mm_h) * RING_CELL_M**2 * RING_PERIOD_S, 1.0)
