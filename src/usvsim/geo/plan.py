"""A plan view of a scenario (world ENU, metres, north up): land, depth contours, structures, obstacles,
buoys, traffic routes, task goals and vessels at their start poses. Used by `usvsim map` and the docs."""

from __future__ import annotations

import math

import numpy as np
import shapely

from usvsim.config.objects import COLORS, Buoy
from usvsim.world.obstacles import static_parts

LAND, WATER, STRUCTURE = "#8a9a6b", "#d8e8f0", "#9a9a96"


DEFAULT_CONTOURS_M = (1, 2, 5, 10, 20, 50, 100, 200)


def draw_plan(sim, path, size_in: float = 9.0, dpi: int = 110, marks=(), contours_m=None, graticule: bool = True,
              tracks=()) -> list[str]:  # fmt: skip
    """Write the plan view of a built simulation (its scenario and place) to a PNG file; `marks` are a task's
    targets (`Task.plan_marks`: x, y m ENU, heading rad or None, label), drawn as labelled markers (a triangle
    pointing along the heading where there is one). `contours_m`: depth contour levels (m; None: the default
    levels within the place's depths); `graticule`: parallels and meridians labelled in degrees and minutes;
    `tracks`: recorded tracks (geo/track.py) drawn as lines. Returns notes for the user (levels no water reaches)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from usvsim.geo.graticule import draw_graticule
    from usvsim.geo.resolve import frame_of

    fig, ax = plt.subplots(figsize=(size_in, size_in), dpi=dpi)
    ax.set_facecolor(WATER)
    place, scenario, notes = sim.place, sim.scenario, []
    if place is not None:
        notes += _draw_place(ax, place, contours_m)
    _draw_objects(ax, scenario, sim)
    _draw_traffic(ax, scenario)
    _draw_marks(ax, marks)
    _draw_tracks(ax, tracks)
    if place is None:
        ax.margins(0.12)
    ax.autoscale_view()
    ax.set_aspect("equal")
    if graticule:
        ax.apply_aspect()  # the view as drawn, before the graticule is fitted to it
        draw_graticule(ax, frame_of(scenario))
    span = max(np.ptp(ax.get_xlim()), np.ptp(ax.get_ylim()))
    for name, boat in sim.vessels.items():
        x, y, _ = boat.position
        yaw, arrow = boat.rpy[2], 0.04 * span
        ax.annotate("", (x + arrow * math.cos(yaw), y + arrow * math.sin(yaw)), (x, y), zorder=6,
                    arrowprops={"arrowstyle": "-|>", "color": "#d62728", "lw": 2})  # fmt: skip
        ax.plot([x], [y], "o", color="#d62728", ms=4)
        ax.text(x, y, f"  {name}", color="#d62728", fontsize=8, va="bottom")
    o = scenario.world.origin
    ax.set_title(f"{scenario.name}: origin {latlon_text(o.latitude_deg, o.longitude_deg)} (x east, y north, m)",
                 fontsize=9)  # fmt: skip
    ax.set_xlabel("x (m, east)")
    ax.set_ylabel("y (m, north)")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return notes


def latlon_text(lat_deg: float, lon_deg: float) -> str:
    """'16.80000° S, 179.99500° W': hemispheres by letter (the title said '-16.80000° N' south of the equator)."""
    return f"{abs(lat_deg):.5f}° {'S' if lat_deg < 0 else 'N'}, {abs(lon_deg):.5f}° {'W' if lon_deg < 0 else 'E'}"


def _draw_place(ax, place, contours_m=None) -> list[str]:
    t = place.terrain
    e = place.settings.extent_m
    step = max(1, len(t.xs) // 400)
    z = t.z[::step, ::step]
    depth = np.where(z < 0, -z, np.nan)
    low, high = (np.nanmin(depth), np.nanmax(depth)) if np.isfinite(depth).any() else (0.0, 0.0)
    levels = [d for d in (DEFAULT_CONTOURS_M if contours_m is None else contours_m) if low < d < high]
    if levels:
        cs = ax.contour(t.xs[::step], t.ys[::step], depth, levels=levels, colors="#4a7fa0", linewidths=0.6)
        ax.clabel(cs, fmt="%g m", fontsize=7)
    missed = [d for d in contours_m or () if d not in levels]
    notes = [f"--contours: no contour at {', '.join(f'{d:g}' for d in missed)} m: the place's water is {low:.3g} to "
             f"{high:.3g} m deep"] if missed else []  # fmt: skip
    for polygon in place.land_polygons:
        ax.fill(*np.asarray(polygon.exterior.coords).T, color=LAND, lw=0, zorder=2)
        for hole in polygon.interiors:
            ax.fill(*np.asarray(hole.coords).T, color=WATER, lw=0, zorder=2)
        ax.plot(*np.asarray(polygon.exterior.coords).T, color="#3d4a2a", lw=0.8, zorder=3)
    for _, mesh, _, color in place.structures:  # the top faces filled, their outline dark (a quay is a few pixels)
        tris = mesh.vertices[mesh.faces]
        top = tris[np.all(tris[:, :, 2] == tris[:, :, 2].max(), axis=1)]
        for tri in top:
            ax.fill(tri[:, 0], tri[:, 1], color=COLORS[color][:3], lw=0, zorder=4)
        outline = shapely.union_all([shapely.Polygon(tri[:, :2]) for tri in top]).buffer(0)
        for part in getattr(outline, "geoms", [outline]):
            if not part.is_empty:
                ax.plot(*np.asarray(part.exterior.coords).T, color="#202020", lw=1.2, zorder=5)
    ax.set_xlim(-e, e)
    ax.set_ylim(-e, e)
    return notes


def _draw_objects(ax, scenario, sim) -> None:
    from usvsim.config.loader import base_dir, source_of

    for obj in scenario.objects:
        if isinstance(obj, Buoy):
            ax.plot([obj.position[0]], [obj.position[1]], "o", color=COLORS[obj.color][:3], ms=5, mec="k", mew=0.5,
                    zorder=5)
            continue
        for part in static_parts([obj], base_dir(scenario), source_of(scenario)):
            if part.kind == "box":
                _box(ax, part)
            else:
                ax.plot([part.pos[0]], [part.pos[1]], "s", color=STRUCTURE, ms=3)


TRAFFIC = "#7b3fa0"
CONSTANT_COURSE_S = 300.0  # a constant-course ship is drawn over its first five minutes


def _draw_traffic(ax, scenario) -> None:
    """Traffic ships' routes (waypoints) and constant courses, labelled with the ship's name."""
    traffic = getattr(scenario, "traffic", None)
    for ship in traffic.ships if traffic is not None else ():
        motion = ship.motion
        if motion.type == "route":
            xy = np.array([w.position for w in motion.waypoints])
        elif motion.type == "constant":
            course = math.radians(90.0 - motion.course_deg)  # compass → ENU angle
            run = motion.speed_mps * CONSTANT_COURSE_S
            start = np.asarray(motion.position)
            xy = np.array([start, start + run * np.array([math.cos(course), math.sin(course)])])
        else:
            continue  # AIS replays are drawn by their own tools
        ax.plot(xy[:, 0], xy[:, 1], "--", color=TRAFFIC, lw=1.2, zorder=5)
        ax.plot(xy[:1, 0], xy[:1, 1], "s", color=TRAFFIC, ms=4, zorder=5)
        ax.text(xy[0, 0], xy[0, 1], f"  {ship.name}", color=TRAFFIC, fontsize=7, va="top", zorder=5)


GOAL = "#e07b00"
TRACK = "#c2185b"


def _draw_tracks(ax, tracks) -> None:
    """Recorded tracks (geo/track.py): a line per vessel and episode, a dot where it starts."""
    for track in tracks:
        xy = np.asarray(track.xy)
        ax.plot(xy[:, 0], xy[:, 1], "-", color=TRACK, lw=1.4, zorder=6, gid="track")
        ax.plot(xy[:1, 0], xy[:1, 1], "o", color=TRACK, ms=3, zorder=6)


def _draw_marks(ax, marks) -> None:
    for x, y, yaw, label in marks:
        if yaw is None:
            ax.plot([x], [y], "o", mfc="none", mec=GOAL, mew=1.5, ms=12, zorder=6)
        else:
            ax.plot([x], [y], marker=(3, 0, math.degrees(yaw) - 90.0), color=GOAL, ms=11, zorder=6)
        ax.text(x, y, f"  {label}", color=GOAL, fontsize=8, zorder=6)


def _box(ax, part) -> None:
    w, x, y, z = part.quat
    yaw = math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    hx, hy = part.size[0], part.size[1]
    corners = np.array([[-hx, -hy], [hx, -hy], [hx, hy], [-hx, hy]])
    c, s = math.cos(yaw), math.sin(yaw)
    xy = corners @ np.array([[c, s], [-s, c]]) + np.asarray(part.pos[:2])
    ax.fill(xy[:, 0], xy[:, 1], color=part.rgba[:3], ec="k", lw=0.4)
