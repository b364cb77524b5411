"""Vessels' tracks from a recording (`usvsim run --record`), in world ENU and as latitude/longitude files.

A track is the ground-truth odometry `/<vessel>/ground_truth/odometry` (base_link in `<vessel>/odom`) carried
into the world frame by the episode's static `world → <vessel>/odom` (`/tf_static`; where the recording has none,
the scenario's start pose, as the simulation sets it). Each episode (`/usvsim/episode`, a reset) starts a new
track. Latitude and longitude are those of the world frame's point (as GNSS fixes and AIS reports give them,
docs/geo.md); the heading is true (compass, clockwise from true north at the point).
"""

from __future__ import annotations

import csv
import io
import json
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from usvsim.core.errors import UsvsimError
from usvsim.core.transforms import matrix_from_quat, quat_multiply
from usvsim.geo.frame import GeoFrame
from usvsim.messages.envelope import EPISODE_TOPIC

TRACK_SUFFIXES = (".geojson", ".csv")


@dataclass
class Track:
    """One vessel's path over one episode: times (s, simulation), positions (n, 2) and yaws (rad) in world ENU."""

    vessel: str
    episode: int
    time_s: list[float] = field(default_factory=list)
    xy: list[tuple[float, float]] = field(default_factory=list)
    yaw_rad: list[float] = field(default_factory=list)


def read_tracks(path: Path, start_poses: dict[str, tuple[np.ndarray, np.ndarray]]) -> tuple[list[Track], list[str]]:
    """Tracks of the vessels named in `start_poses` (vessel → (position, quat wxyz) of its odom frame in the world,
    used where the recording has no /tf_static for it); and notes for the user (which vessels fell back)."""
    from mcap.reader import make_reader

    from usvsim.messages.ros import typestore

    if not path.is_file():
        raise UsvsimError(f"--track {path}: no such recording" + (" (a directory)" if path.is_dir() else ""))
    odometry = {f"/{v}/ground_truth/odometry": v for v in start_poses}
    origins: dict[str, tuple[np.ndarray, np.ndarray]] = {}
    tracks: dict[tuple[str, int], Track] = {}
    fell_back, moved, episode, store = set(), {}, 0, typestore()
    try:
        with path.open("rb") as f:
            for schema, channel, message in make_reader(f).iter_messages(topics=[EPISODE_TOPIC, "/tf_static", *odometry]):
                msg = store.deserialize_cdr(message.data, schema.name if schema else "")  # usvsim writes every schema
                if channel.topic == EPISODE_TOPIC:
                    episode, origins = json.loads(msg.data)["episode"], {}
                elif channel.topic == "/tf_static":
                    found = _odom_origins(msg, start_poses)
                    moved |= {v: p[0] for v, p in found.items() if not _same_pose(p, start_poses[v])}
                    origins |= found
                else:
                    vessel = odometry[channel.topic]
                    if vessel not in origins:
                        origins[vessel] = start_poses[vessel]
                        fell_back.add(vessel)
                    _append(tracks, vessel, episode, origins[vessel], msg)
    except UsvsimError:
        raise
    except Exception as exc:  # mcap's errors for a file that is no MCAP or is cut short
        raise UsvsimError(f"--track {path}: cannot read it as an MCAP recording ({str(exc).splitlines()[0][:160]}); "
                          "a recording cut short is repaired by usvsim recover") from None  # fmt: skip
    if not tracks:
        raise UsvsimError(f"--track {path}: holds no {', '.join(odometry)} (a recording of another scenario, or one "
                          "whose topics filter left the ground-truth odometry out)")  # fmt: skip
    notes = [f"--track: {path} has no /tf_static world → {v}/odom; {v}'s track starts at the scenario's start pose"
             for v in sorted(fell_back)]  # fmt: skip
    notes += [f"--track: {v} starts elsewhere in {path} (at {p[0]:.1f}, {p[1]:.1f} m) than in the scenario (at "
              f"{start_poses[v][0][0]:.1f}, {start_poses[v][0][1]:.1f} m, or turned by more than 5°): a recording of "
              "another scenario or task seed?" for v, p in sorted(moved.items())]  # fmt: skip
    return list(tracks.values()), notes


def _same_pose(a, b) -> bool:
    """Within 1 m and 5° (a recording of the scenario: its odom frames are the scenario's start poses)."""
    turn = 2.0 * math.degrees(math.acos(min(1.0, abs(float(np.dot(a[1], b[1]))))))
    return bool(np.hypot(*(a[0] - b[0])[:2]) <= 1.0 and turn <= 5.0)


def _odom_origins(msg, vessels) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    out = {}
    for t in msg.transforms:
        vessel = t.child_frame_id.removesuffix("/odom")
        if t.header.frame_id == "world" and t.child_frame_id.endswith("/odom") and vessel in vessels:
            p, q = t.transform.translation, t.transform.rotation
            out[vessel] = (np.array([p.x, p.y, p.z]), np.array([q.w, q.x, q.y, q.z]))
    return out


def _append(tracks: dict, vessel: str, episode: int, origin, msg) -> None:
    pos, quat = origin
    p, q = msg.pose.pose.position, msg.pose.pose.orientation
    world = pos + matrix_from_quat(quat) @ np.array([p.x, p.y, p.z])
    w, x, y, z = quat_multiply(quat, np.array([q.w, q.x, q.y, q.z]))
    track = tracks.setdefault((vessel, episode), Track(vessel, episode))
    track.time_s.append(msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9)
    track.xy.append((float(world[0]), float(world[1])))
    track.yaw_rad.append(math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z)))


def track_rows(tracks: list[Track], frame: GeoFrame) -> list[dict]:
    """One row per recorded pose: vessel, episode, time_s, x_m, y_m (world ENU), latitude_deg, longitude_deg
    (WGS-84) and heading_deg (true, compass)."""
    from usvsim.traffic.ais import true_bearing_deg

    rows = []
    for track in tracks:
        xy = np.asarray(track.xy)
        lat, lon, _ = frame.to_geodetic(xy[:, 0], xy[:, 1]).T
        grid = 90.0 - np.degrees(track.yaw_rad)  # ENU yaw (CCW from east) → bearing from the world's y axis
        heading = np.asarray(true_bearing_deg(lat, lon, grid, *frame.origin[:2])) % 360.0
        for k, t in enumerate(track.time_s):
            rows.append({"vessel": track.vessel, "episode": track.episode, "time_s": round(t, 6),
                         "x_m": round(float(xy[k, 0]), 4) + 0.0, "y_m": round(float(xy[k, 1]), 4) + 0.0,
                         "latitude_deg": round(float(lat[k]), 9), "longitude_deg": round(float(lon[k]), 9),
                         "heading_deg": round(float(heading[k]), 3) % 360.0})  # fmt: skip (+ 0.0: no "-0.0")
    return rows


def tracks_text(tracks: list[Track], frame: GeoFrame, suffix: str) -> str:
    """The tracks as CSV (one row per pose) or GeoJSON (RFC 7946: one LineString per vessel and episode,
    [longitude, latitude] in WGS-84, with the poses' times and headings as properties)."""
    rows = track_rows(tracks, frame)
    if suffix == ".csv":
        out = io.StringIO()
        writer = csv.DictWriter(out, fieldnames=list(rows[0]), lineterminator="\n")
        writer.writeheader()
        writer.writerows(rows)
        return out.getvalue()
    features = []
    for track in tracks:
        mine = [r for r in rows if r["vessel"] == track.vessel and r["episode"] == track.episode]
        features.append({"type": "Feature", "properties": {
            "vessel": track.vessel, "episode": track.episode, "time_s": [r["time_s"] for r in mine],
            "heading_deg": [r["heading_deg"] for r in mine]},
            "geometry": {"type": "LineString" if len(mine) > 1 else "Point", "coordinates": (
                [[r["longitude_deg"], r["latitude_deg"]] for r in mine] if len(mine) > 1
                else [mine[0]["longitude_deg"], mine[0]["latitude_deg"]])}})  # fmt: skip
    return json.dumps({"type": "FeatureCollection", "features": features}) + "\n"
