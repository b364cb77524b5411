"""The pictures of docs/traffic.md: the radar picture beside the camera view of the same moment, and an Imazu
encounter with each target's closest point of approach.

    MUJOCO_GL=egl python examples/traffic_figures.py [OUT_DIR] [--quick]
"""

from __future__ import annotations

import math
import os
import sys
from pathlib import Path

os.environ.setdefault("MUJOCO_GL", "egl")

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import yaml

from usvsim import Simulation
from usvsim.config.loader import parse_scenario, resolve
from usvsim.traffic.imazu import imazu_scenario

RADAR = {"type": "radar", "name": "radar", "rpm": 24, "range_max_m": 600.0, "mount": {"position": [0.0, 0.0, 2.5]},
         "sea_clutter": {"sea_state": 2}, "image": "polar"}  # fmt: skip
CAMERA = {"type": "camera", "name": "camera", "width": 960, "height": 540, "horizontal_fov_deg": 90.0, "rate_hz": 10,
          "far_m": 1000.0, "mount": {"position": [0.3, 0.0, 1.6]}}  # fmt: skip
SHIPS = [  # world ENU; the WAM-V is at the origin heading east
    {"name": "ferry", "mmsi": 257000101, "ship_type": "passenger", "length_m": 40, "beam_m": 10, "height_m": 5,
     "motion": {"type": "constant", "position": [260.0, -120.0], "course_deg": 350.0, "speed_mps": 5.0}},
    {"name": "tug", "mmsi": 257000102, "ship_type": "tug", "length_m": 15, "beam_m": 5,
     "motion": {"type": "constant", "position": [120.0, 60.0], "course_deg": 200.0, "speed_mps": 2.0}},
    {"name": "cargo", "mmsi": 257000103, "ship_type": "cargo", "length_m": 90, "beam_m": 15, "height_m": 8,
     "motion": {"type": "constant", "position": [480.0, 200.0], "course_deg": 270.0, "speed_mps": 4.0}},
]  # fmt: skip


def radar_and_camera(out: Path, turns: int) -> None:
    data = yaml.safe_load(resolve("harbor")[0])
    data["vessels"][0]["sensors"] = [RADAR, CAMERA]
    data["traffic"] = {"ships": SHIPS}
    sim = Simulation(parse_scenario(data, "figure"))
    sim.run(turns * 2.5 + 0.1)  # 24 rpm: 2.5 s a turn
    radar = sim.sensors["wamv/radar"]
    image = sim.sensors["wamv/camera"].released[0].msg
    rgb = np.asarray(image.data).reshape(image.height, image.width, 3)
    tracks = radar.revolution.tracker.confirmed() if radar.revolution.tracker else []
    fig = plt.figure(figsize=(15, 5.2))
    ax = fig.add_axes([0.01, 0.04, 0.6, 0.9])
    ax.imshow(rgb)
    ax.set_title("camera (forward, 90° field of view)")
    ax.axis("off")
    polar = fig.add_axes([0.63, 0.06, 0.34, 0.86], projection="polar")
    echoes = radar.revolution.echoes  # spokes x bins, spoke k at -k·2π/N (clockwise)
    angles = -np.arange(radar.n + 1) * 2 * np.pi / radar.n
    ranges = np.arange(radar.bins + 1) * radar.bin_m
    polar.pcolormesh(angles, ranges, echoes.T, cmap="inferno", vmin=0.0, vmax=0.6, shading="flat")
    polar.set_theta_zero_location("N")  # head-up: the bow up
    polar.set_theta_direction(1)  # sensor angles counter-clockwise (port to the left)
    polar.set_ylim(0, radar.cfg.range_max_m)
    polar.set_yticks([150, 300, 450, 600])
    polar.tick_params(colors="0.4", labelsize=7)
    pos, rot = radar.pose_world(sim)
    heading = math.atan2(rot[1, 0], rot[0, 0])
    for t in tracks:
        rel = t.pos - pos[:2]
        if np.hypot(*rel) < 60.0:  # the harbour's own docks and buoys (tracked too, at 0 m/s)
            continue
        a = math.atan2(rel[1], rel[0]) - heading
        polar.plot([a], [np.hypot(*rel)], "o", mfc="none", mec="cyan", ms=12)
        polar.annotate(f"{t.id}: {np.hypot(*t.vel):.1f} m/s", (a, np.hypot(*rel)), color="cyan", fontsize=8,
                       xytext=(8, 8), textcoords="offset points")  # fmt: skip
    polar.set_title("X-band radar, 24 rpm, 1024 spokes x 512 bins, 600 m; ARPA tracks (cyan)", fontsize=9)
    fig.savefig(out / "traffic_radar.png", dpi=90)
    plt.close(fig)
    sim.close()


def encounter(out: Path, case: int, encounter_s: float) -> None:
    sim = Simulation(parse_scenario(imazu_scenario(case, speed_mps=2.0, encounter_s=encounter_s), "imazu"))
    own, fleet = sim.vessels["own"], sim.traffic.fleet
    tracks: dict[str, list] = {"own": []} | {n: [] for n in fleet.names[1:]}

    def record(s):
        if s.clock.steps % 100 == 0:
            tracks["own"].append(own.position[:2].copy())
            for k, name in enumerate(fleet.names[1:], start=1):
                tracks[name].append(fleet.pos_enu[k].copy())

    sim.run(2.0 * encounter_s, on_step=record)
    report = sim.traffic.report()
    fig, ax = plt.subplots(figsize=(7, 7))
    path = np.array(tracks["own"])
    ax.plot(path[:, 0], path[:, 1], "k-", lw=2, label="own ship (WAM-V, full physics, LOS pilot)")
    for name, r in report.items():
        p = np.array(tracks[name])
        line = ax.plot(p[:, 0], p[:, 1], "-", lw=1.5, label=f"{name}: min distance {r['min_distance_m']:.0f} m "
                       f"at {r['t_min_distance_s']:.0f} s")[0]  # fmt: skip
        ax.plot(*p[0], "o", color=line.get_color())
        i = min(max(int(round(r["t_min_distance_s"])) - 1, 0), len(p) - 1)  # one sample a second from t = 1 s
        ax.plot([path[i, 0], p[i, 0]], [path[i, 1], p[i, 1]], ":", color=line.get_color(), lw=2)
        ax.plot(*p[i], "x", color=line.get_color(), ms=10)
    ax.plot(*path[0], "ko")
    ax.set_aspect("equal")
    ax.set_xlabel("east (m)")
    ax.set_ylabel("north (m)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="lower right")
    ax.set_title(f"Imazu case {case}: tracks, closest approach (dotted) without collision avoidance")
    fig.savefig(out / "traffic_encounter.png", dpi=90)
    plt.close(fig)
    sim.close()


if __name__ == "__main__":
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    quick = "--quick" in sys.argv
    out = Path(args[0] if args else "docs")
    out.mkdir(parents=True, exist_ok=True)
    radar_and_camera(out, turns=1 if quick else 4)
    encounter(out, case=14, encounter_s=30.0 if quick else 150.0)
    print(f"wrote {out / 'traffic_radar.png'} and {out / 'traffic_encounter.png'}")
