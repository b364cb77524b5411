"""Parallels and meridians over a plan view in world ENU metres, labelled in degrees and minutes (chart style).

Each line is a constant latitude (or longitude) sampled densely and converted with the scenario's exact frame
(geo/frame.py), so it stays true away from the origin: meridians lean by the convergence of the meridians
(Δλ·sin φ, 0.3° 20 km east at 59° N) and parallels bend (a parallel is no straight line in a tangent plane).
Spacing is a chart's round step (0.01′ ... 10°), chosen per axis for a few lines across the view.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from usvsim.geo.frame import GeoFrame

STEPS_MIN = (0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0, 15.0, 30.0, 60.0, 120.0, 300.0, 600.0)  # arc minutes
MAX_LINES = 6  # per direction, at most about this many lines across the view
SAMPLES = 101  # points per line


@dataclass(frozen=True)
class GraticuleLine:
    """One parallel ("lat") or meridian ("lon") at `value_deg`: its points (n, 2) in ENU metres and its label."""

    kind: str
    value_deg: float
    xy: np.ndarray
    label: str


def graticule(frame: GeoFrame, xlim: tuple[float, float], ylim: tuple[float, float]) -> list[GraticuleLine]:
    """The parallels and meridians crossing the ENU rectangle xlim × ylim (metres)."""
    (x0, x1), (y0, y1) = sorted(xlim), sorted(ylim)
    edge = np.linspace(0.0, 1.0, 41)
    bx = np.concatenate([x0 + (x1 - x0) * edge, np.full(41, x1), x1 - (x1 - x0) * edge, np.full(41, x0)])
    by = np.concatenate([np.full(41, y0), y0 + (y1 - y0) * edge, np.full(41, y1), y1 - (y1 - y0) * edge])
    lat, lon = frame.to_geodetic(bx, by)[:, :2].T
    lon0 = frame.origin[1]
    lon = lon0 + (lon - lon0 + 180.0) % 360.0 - 180.0  # continuous across the antimeridian
    pad_lat, pad_lon = 0.02 * np.ptp(lat), 0.02 * np.ptp(lon)  # lines run a little past the view (clipped there)
    lat_range, lon_range = (lat.min() - pad_lat, lat.max() + pad_lat), (lon.min() - pad_lon, lon.max() + pad_lon)
    lines = []
    for kind, (lo, hi) in (("lat", (lat.min(), lat.max())), ("lon", (lon.min(), lon.max()))):
        step = _step_min(hi - lo)
        first, last = math.ceil(lo * 60.0 / step - 1e-9), math.floor(hi * 60.0 / step + 1e-9)
        across = np.linspace(*(lon_range if kind == "lat" else lat_range), SAMPLES)
        for k in range(first, last + 1):
            value = k * step / 60.0
            la, lo_ = (np.full(SAMPLES, value), across) if kind == "lat" else (across, np.full(SAMPLES, value))
            xy = frame.to_enu(la, (lo_ + 180.0) % 360.0 - 180.0)[:, :2]
            lines.append(GraticuleLine(kind, value, xy, dm_label(value, kind, step)))
    return lines


def _step_min(span_deg: float) -> float:
    span_min = span_deg * 60.0
    return next((s for s in STEPS_MIN if span_min / s <= MAX_LINES), STEPS_MIN[-1])


def dm_label(value_deg: float, kind: str, step_min: float = 1.0) -> str:
    """'59°25′N', '10°30.5′E', '16°48.25′S': degrees and minutes with as many decimals as the step needs
    (longitudes past 180° named west: 190° is '170°0′W')."""
    if kind == "lon":
        value_deg = 180.0 if (value_deg - 180.0) % 360.0 == 0.0 else (value_deg + 180.0) % 360.0 - 180.0
    decimals = next((d for d in range(3) if abs(step_min * 10**d - round(step_min * 10**d)) < 1e-9), 2)
    minutes_total = round(abs(value_deg) * 60.0, decimals)
    degrees = int(minutes_total // 60)
    minutes = minutes_total - 60 * degrees
    hemisphere = ("S" if value_deg < 0 else "N") if kind == "lat" else ("W" if value_deg < 0 else "E")
    if minutes_total == 0 or (kind == "lon" and minutes_total == 180 * 60):
        hemisphere = ""  # the equator, the prime meridian and the antimeridian have none
    return f"{degrees}°{minutes:.{decimals}f}′{hemisphere}"


def draw_graticule(ax, frame: GeoFrame) -> list[GraticuleLine]:
    """Draws the graticule over the axes' current view (call after the limits are set); returns its lines.
    Parallels are labelled at the left edge, meridians at the bottom edge."""
    xlim, ylim = ax.get_xlim(), ax.get_ylim()
    lines = graticule(frame, xlim, ylim)
    style = {"color": "#404040", "fontsize": 7, "zorder": 7, "clip_on": True,
             "bbox": {"boxstyle": "square,pad=0.1", "fc": "white", "ec": "none", "alpha": 0.7}}  # fmt: skip
    for line in lines:
        x, y = line.xy.T
        ax.plot(x, y, color="#505050", lw=0.5, alpha=0.7, zorder=6.5, gid=f"graticule_{line.kind}")
        if line.kind == "lat" and x.min() <= xlim[0] <= x.max():
            order = np.argsort(x)
            ax.text(xlim[0], float(np.interp(xlim[0], x[order], y[order])), f" {line.label}", ha="left",
                    va="bottom", **style)  # fmt: skip
        elif line.kind == "lon" and y.min() <= ylim[0] <= y.max():
            order = np.argsort(y)
            ax.text(float(np.interp(ylim[0], y[order], x[order])), ylim[0], f" {line.label}", rotation=90,
                    ha="right", va="bottom", **style)  # fmt: skip
    ax.set_xlim(xlim)
    ax.set_ylim(ylim)
    return lines
