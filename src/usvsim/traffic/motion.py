"""Where a traffic ship is at time t: routes, constant course and speed, replayed AIS tracks.

A `Track` is a table of segments; `kernels.evaluate` gives every ship's position (world ENU, m), velocity
(ENU, m/s) and heading (ENU yaw, rad, counter-clockwise from east) at simulation time t in one call.
Tracks are pure functions of time: nothing to reset, and a reset simulation replays them exactly.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from datetime import UTC, datetime
from pathlib import Path
from typing import NoReturn

import numpy as np
import pymap3d

from usvsim.config import traffic as cfg
from usvsim.config.base import MAX_COORDINATE_M
from usvsim.core.errors import ScenarioError
from usvsim.traffic.ais import grid_bearing_deg

KNOT_MPS = 1852.0 / 3600.0
AIS_NO_HEADING = 511
AIS_NO_COURSE = 360.0  # ITU-R M.1371: COG 3600 (360.0°) = not available


def yaw_from_course(course_rad: float) -> float:
    """ENU yaw (CCW from east) of a nautical course (clockwise from north), both radians."""
    return 0.5 * math.pi - course_rad


def course_from_velocity(vx: float, vy: float) -> float:
    """Nautical course (rad, [0, 2π), clockwise from north) of an ENU velocity."""
    return math.atan2(vx, vy) % (2.0 * math.pi)


@dataclass(frozen=True)
class Track:
    """A ship's motion as segments, each valid on [t0, t1): `linear` ones move at v0 from p0 (exactly, also
    for t1 = inf), the others are cubic Hermite curves from (p0, v0) to (p1, v1). Before the first segment the
    ship rests at its start; after the last it rests at its end (or, with `period_s` > 0, starts over)."""

    t0: np.ndarray  # (S,) s
    t1: np.ndarray
    p0: np.ndarray  # (S, 2) world ENU, m
    p1: np.ndarray
    v0: np.ndarray  # (S, 2) m/s
    v1: np.ndarray
    yaw0: np.ndarray  # (S,) ENU yaw at t0 and t1, rad
    yaw1: np.ndarray
    linear: np.ndarray  # (S,) bool
    period_s: float = 0.0


def constant_track(start_enu, course_rad: float, speed_mps: float) -> Track:
    v = speed_mps * np.array([[math.sin(course_rad), math.cos(course_rad)]])
    p = np.asarray(start_enu, float).reshape(1, 2)
    yaw = np.array([yaw_from_course(course_rad)])
    return Track(np.zeros(1), np.full(1, np.inf), p, p, v, v, yaw, yaw, np.ones(1, bool))


def route_track(points, speeds, loop: bool = False) -> Track:
    """Legs between waypoints, each at its start waypoint's speed; the heading turns at a waypoint. A waypoint at
    speed 0 is where the ship stops for good: it stays there, heading as it arrived (the previous leg's
    direction), or, stopped at the route's start, along the leg that starts there; the waypoints after it are
    never reached and a loop does not go round. Legs of zero length are left out (there is nothing to sail); a ship
    never jumps."""
    pts = np.asarray(points, float)
    if loop:
        pts = np.vstack([pts, pts[:1]])
    legs, speed = np.diff(pts, axis=0), np.asarray(speeds, float)[: len(pts) - 1]
    length = np.linalg.norm(legs, axis=1)
    stops = np.flatnonzero(speed <= 0)
    sailed = int(stops[0]) if len(stops) else len(legs)  # the legs before the first stop
    keep = np.arange(len(legs)) < sailed
    keep &= length > 1e-9
    if not keep.any():  # stopped at the start: heading along the route's first leg (north if all points coincide)
        moving = np.flatnonzero(length > 1e-9)
        course = course_from_velocity(*legs[moving[0]]) if len(moving) else 0.0
        return constant_track(pts[0], course, 0.0)
    legs, length, speed, start = legs[keep], length[keep], speed[keep], pts[:-1][keep]
    dirs = legs / length[:, None]
    t1 = np.cumsum(length / speed)
    t0 = np.concatenate([[0.0], t1[:-1]])
    yaw = np.arctan2(dirs[:, 1], dirs[:, 0])
    v = dirs * speed[:, None]
    period = float(t1[-1]) if loop and not len(stops) else 0.0
    return Track(t0, t1, start, start + legs, v, v, yaw, yaw, np.ones(len(t0), bool), period)


def hermite_track(t_s, pos_enu, vel_enu, yaw_rad) -> Track:
    """Samples joined by cubic Hermite curves: exact at the samples, velocity-consistent in between."""
    t, p, v, yaw = (np.asarray(a, float) for a in (t_s, pos_enu, vel_enu, yaw_rad))
    yaw_next = yaw[:-1] + (yaw[1:] - yaw[:-1] + math.pi) % (2 * math.pi) - math.pi  # the short way round
    return Track(t[:-1], t[1:], p[:-1], p[1:], v[:-1], v[1:], yaw[:-1], yaw_next, np.zeros(len(t) - 1, bool))


COLUMNS = ("time", "lat", "lon", "sog", "cog", "heading")


def _stamp(text: str) -> float:
    """An ISO 8601 time in seconds (a time without a zone is UTC, as AIS's)."""
    when = datetime.fromisoformat(text.replace("Z", "+00:00"))
    return (when if when.tzinfo else when.replace(tzinfo=UTC)).timestamp()


def _fail(where: tuple[str, str], message: str) -> NoReturn:
    raise ScenarioError(where[0], where[1], message)


def _column(name: str, values: list[str], rows: list[int], where: tuple[str, str], path: Path) -> np.ndarray:
    """One CSV column as floats (`time`: seconds, or ISO 8601 times made seconds from the first)."""
    iso = name == "time" and bool(values) and not _is_number(values[0])
    out = np.empty(len(values))
    for k, text in enumerate(values):
        try:
            out[k] = _stamp(text) if iso else float(text)
        except ValueError:
            what = "an ISO 8601 time like the first row's" if iso else "a number"
            _fail(where, f"{path}: row {rows[k]}: {name} {text[:40]!r} is not {what}")
    return out - out[0] if iso else out


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _first(mask: np.ndarray, rows: list[int]) -> int:
    """The CSV row number (the header is row 1) of the first True in `mask`."""
    return rows[int(np.argmax(mask))]


def _read_rows(path: Path, where: tuple[str, str]) -> tuple[list[list[str]], list[int], dict[str, int]]:
    """The data rows (blank lines skipped), their row numbers and the columns' indices."""
    try:
        with open(path, newline="", encoding="utf-8-sig") as f:  # a BOM (spreadsheet export) is not part of the header
            reader = csv.reader(f)
            header = [h.strip() for h in next(reader, [])]
            rows, numbers = [], []
            for row in reader:
                if row:
                    rows.append(row)
                    numbers.append(reader.line_num)
    except FileNotFoundError:
        _fail(where, f"AIS CSV not found: {path}")
    except UnicodeDecodeError:
        _fail(where, f"{path}: not a UTF-8 text (CSV) file")
    except csv.Error as exc:
        _fail(where, f"{path}: not a CSV file ({exc})")
    except OSError as exc:
        _fail(where, f"{path}: cannot read it: {exc.strerror or exc}")
    if any(c not in header for c in COLUMNS):
        _fail(where, f"{path}: needs a header row {','.join(COLUMNS)}")
    for row, number in zip(rows, numbers):
        if len(row) != len(header):
            _fail(where, f"{path}: row {number} has {len(row)} fields, the header {len(header)}")
    return rows, numbers, {c: header.index(c) for c in COLUMNS}


def read_ais_csv(path: Path, origin, source: str = "", key: str = "") -> Track:
    """An AIS track CSV (see `config.traffic.AisReplay`) as a Hermite track in the world frame of `origin`
    (a `GeodeticOrigin`)."""
    where = (source, key)
    data, lines, index = _read_rows(path, where)
    t, lat, lon, sog, cog, hdg = (_column(c, [r[index[c]].strip() for r in data], lines, where, path) for c in COLUMNS)
    for name, values in (("time", t), ("lat", lat), ("lon", lon), ("sog", sog), ("cog", cog), ("heading", hdg)):
        if not np.all(np.isfinite(values)):  # float() reads 'nan' and 'inf'
            raise ScenarioError(source, key, f"{path}: {name} must be finite numbers (row {_first(~np.isfinite(values), lines)})")
    for name, values, lo, hi in (("lat", lat, -90, 90), ("lon", lon, -180, 180), ("sog", sog, 0, 102.2), ("cog", cog, 0, 360)):
        if np.any((values < lo) | (values > hi)):  # sog: AIS's largest, 102.2 kn
            raise ScenarioError(source, key, f"{path}: {name} must be in [{lo}, {hi}] (row {_first((values < lo) | (values > hi), lines)})")
    bad_heading = (hdg != AIS_NO_HEADING) & ((hdg < 0) | (hdg >= 360))
    if np.any(bad_heading):
        raise ScenarioError(source, key, f"{path}: heading must be in [0, 360) or 511 (row {_first(bad_heading, lines)})")
    if len(t) < 2:
        raise ScenarioError(source, key, f"{path}: needs at least two rows with increasing time")
    if np.any(np.diff(t) <= 0):
        raise ScenarioError(source, key, f"{path}: time must increase from row to row (row {_first(np.diff(t) <= 0, lines[1:])})")
    alt = origin.altitude_m  # 2D positions sit at the origin's height, as geo data and latlon placements do
    e, n, _ = pymap3d.geodetic2enu(lat, lon, alt, origin.latitude_deg, origin.longitude_deg, alt)
    far = np.maximum(np.abs(e), np.abs(n)) > MAX_COORDINATE_M
    if np.any(far):
        raise ScenarioError(source, key, f"{path}: row {_first(far, lines)} is more than {MAX_COORDINATE_M / 1000:.0f} km "
                            "from the world origin (world.origin)")  # fmt: skip
    _refuse_jumps(e, n, t, lines, path, where)
    # true course and heading → bearings from the world's y axis (north at the origin only: ais.grid_bearing_deg)
    lat0, lon0 = origin.latitude_deg, origin.longitude_deg
    course = np.radians(grid_bearing_deg(lat, lon, np.where(cog == AIS_NO_COURSE, 0.0, cog), lat0, lon0))
    if np.any(cog == AIS_NO_COURSE):  # not available (it was taken as north): the track's own direction there
        course = np.where(cog == AIS_NO_COURSE, np.arctan2(np.gradient(e, t), np.gradient(n, t)), course)
    vel = (sog * KNOT_MPS)[:, None] * np.stack([np.sin(course), np.cos(course)], axis=1)
    heading = np.where(hdg == AIS_NO_HEADING, np.degrees(course),
                       grid_bearing_deg(lat, lon, np.where(hdg == AIS_NO_HEADING, 0.0, hdg), lat0, lon0))  # fmt: skip
    yaw = 0.5 * np.pi - np.radians(heading)
    return hermite_track(t, np.stack([e, n], axis=1), vel, yaw)


def _refuse_jumps(e: np.ndarray, n: np.ndarray, t: np.ndarray, lines: list[int], path: Path, where) -> None:
    """A row further from the one before than a ship sails in the time between (faster than cfg.MAX_SHIP_SPEED_MPS,
    the limit of every other ship speed) is an error naming it: the replayed ship flew there (found by QA: a
    0.1° latitude glitch 1 s later was replayed at 11 km/s), as a position glitch in a real AIS log would."""
    dt = np.diff(t)
    step = np.hypot(np.diff(e), np.diff(n))
    fast = step > cfg.MAX_SHIP_SPEED_MPS * dt
    if np.any(fast):
        i = int(np.argmax(fast))
        _fail(where, f"{path}: row {lines[i + 1]} is {step[i]:.0f} m from row {lines[i]} only {dt[i]:g} s before "
                     f"({step[i] / dt[i]:.0f} m/s; ships sail at most {cfg.MAX_SHIP_SPEED_MPS} m/s): a position jump; "
                     "fix or remove the row")  # fmt: skip


def make_track(motion, origin, base: Path, source: str = "", key: str = ""):
    """The track of a ship's `motion` config."""
    if isinstance(motion, cfg.Constant):
        return constant_track(motion.position, math.radians(motion.course_deg), motion.speed_mps)
    if isinstance(motion, cfg.Route):
        return route_track([w.position for w in motion.waypoints], [w.speed_mps for w in motion.waypoints], motion.loop)
    return read_ais_csv(base / motion.path, origin, source, f"{key}.path")
