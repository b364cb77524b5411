"""The 22 Imazu encounter situations (H. Imazu, 1987; the benchmark set of ship collision-avoidance research)
as scenarios for a chosen own ship and speed.

Geometry source: NTNU's colav-simulator (github.com/NTNU-TTO/SFI-AutoShip-COLAV-simulator,
`scenarios/imazu_cases/imazu01.yaml` .. `imazu22.yaml`), where the own ship heads north at 10 m/s. The table
below holds, per case and target, the target's start relative to the own ship (east, north in metres), its
course (degrees clockwise from north) and its speed (m/s) from those files. Cases 1-4 have one target, 5-13
two... 22 three (see the table). For an own ship at `speed_mps` reaching the encounter after about
`encounter_s`, speeds are scaled by k = speed_mps / 10 and distances by k · encounter_s / REFERENCE_S,
which keeps every bearing, course, speed ratio and the order of events (CPA and TCPA scale alike).
"""

from __future__ import annotations

import math

import numpy as np
import yaml

REFERENCE_SPEED_MPS = 10.0
REFERENCE_S = 700.0  # about when the reference crossing (case 2) would collide
IMAZU: dict[int, tuple[tuple[float, float, float, float], ...]] = {
    1: ((0, 13060, 180, 10),),
    2: ((7000, 7060, 270, 10),),
    3: ((0, 2060, 0, 5),),
    4: ((-5500, 2560, 40, 10),),
    5: ((7000, 7060, 270, 10), (0, 14120, 180, 10)),
    6: ((5000, 2560, 320, 10), (2700, 860, 342, 10)),
    7: ((5000, 2560, 320, 9), (0, 2060, 0, 5)),
    8: ((-7000, 7060, 90, 10), (0, 14120, 180, 10)),
    9: ((7000, 7060, 270, 10), (2950, 810, 345, 10)),
    10: ((7000, 7060, 270, 10), (-2750, 710, 45, 10)),
    11: ((-7000, 7060, 90, 10), (2950, 810, 345, 10)),
    12: ((5000, 2560, 320, 9), (-2750, 710, 45, 10), (0, 14120, 180, 10)),
    13: ((-5500, 2560, 40, 10), (-2750, 710, 45, 10), (0, 14120, 180, 10)),
    14: ((5000, 2200, 320, 10), (2700, 500, 342, 10), (6400, 5700, 270, 10)),
    15: ((5000, 2200, 320, 10), (0, 1700, 0, 5), (6400, 5700, 270, 10)),
    16: ((-7000, 7060, 90, 10), (-2750, 710, 45, 10), (7000, 7060, 270, 10)),
    17: ((5000, 2200, 320, 10), (0, 1700, 0, 5), (-2750, 350, 45, 10)),
    18: ((5000, 2200, 320, 10), (2700, 500, 342, 10), (4500, 10200, 225, 10)),
    19: ((-2450, 350, 45, 10), (2700, 500, 342, 10), (4500, 10200, 225, 10)),
    20: ((2700, 500, 342, 10), (0, 1700, 0, 5), (6400, 5700, 270, 10)),
    21: ((-2450, 350, 45, 10), (2700, 500, 342, 10), (6400, 5700, 270, 10)),
    22: ((5000, 2200, 320, 10), (0, 1700, 0, 5), (6400, 5700, 270, 10)),
}
OWN_MMSI, FIRST_TARGET_MMSI = 257999000, 257999001


def imazu_scenario(case: int, model: str = "wamv", speed_mps: float = 2.0, encounter_s: float = 300.0,
                   target_length_m: float = 25.0, avoid: bool = False) -> dict:  # fmt: skip
    """Scenario dict of Imazu case `case` (1-22): own ship `model` heading north from the origin at `speed_mps`
    (full physics, LOS pilot + velocity controller; with `avoid`, COLREG collision avoidance with its defaults:
    usvsim.traffic.colav), targets kinematic at constant course and speed."""
    if case not in IMAZU:
        raise ValueError(f"Imazu cases are 1-22, got {case}")
    k = speed_mps / REFERENCE_SPEED_MPS
    scale = k * encounter_s / REFERENCE_S
    length, beam = _dimensions(model)
    own = {"name": "own_ship", "mmsi": OWN_MMSI, "vessel": "own", "ship_type": "other", "length_m": length,
           "beam_m": beam, "ais": {"enabled": False},
           "motion": {"type": "constant", "position": [0.0, 0.0], "course_deg": 0.0, "speed_mps": speed_mps}}  # fmt: skip
    if avoid:
        own["avoidance"] = {"type": "velocity_obstacle"}
    ships = [own]
    for j, (east, north, course, speed) in enumerate(IMAZU[case]):
        ships.append({"name": f"target_{j + 1}", "mmsi": FIRST_TARGET_MMSI + j, "ship_type": "cargo",
                      "length_m": target_length_m, "beam_m": round(target_length_m / 4.0, 2),
                      "motion": {"type": "constant", "position": [round(east * scale, 2), round(north * scale, 2)],
                                 "course_deg": float(course), "speed_mps": round(speed * k, 4)}})  # fmt: skip
    return {
        "version": 1,
        "name": f"imazu_{case:02d}",
        "description": f"Imazu encounter {case} ({len(IMAZU[case])} target{'s' if len(IMAZU[case]) > 1 else ''}): "
        f"{model} north at {speed_mps:g} m/s, encounter after about {encounter_s:g} s",
        "vessels": [{"name": "own", "model": model, "pose": {"position": [0.0, 0.0, 0.0], "yaw_deg": 90.0},
                     "controller": {"type": "velocity"}, "command_timeout_s": 0.0}],  # fmt: skip
        "traffic": {"ships": ships, "awareness": {"own_ship": "own", "rate_hz": 1.0}},
    }


def _dimensions(model: str) -> tuple[float, float]:
    """Length and beam (m, to the cm) of a library vessel's hull: the own ship's entry (it was 5 x 2.5 m for all)."""
    from usvsim.vessels.library import LIBRARY

    size = np.ptp(LIBRARY[model][0]().hull.vertices, axis=0)
    return round(float(size[0]), 2), round(float(size[1]), 2)


def imazu_yaml(case: int, **kw) -> str:
    head = ("# Generated by usvsim.traffic.imazu (geometry: colav-simulator's imazu_cases, see that module);\n"
            "# other own ships and speeds: `usvsim imazu CASE --model otter --speed 1.5 --out my.yaml`.\n")  # fmt: skip
    return head + yaml.safe_dump(imazu_scenario(case, **kw), sort_keys=False, default_flow_style=None, width=120)


def encounter_time_s(case: int, speed_mps: float = 2.0, encounter_s: float = 300.0) -> list[float]:
    """Closed-form TCPA (s from the start) of each target against the own ship on its nominal straight track."""
    out = []
    for east, north, course, speed in IMAZU[case]:
        s, k = speed_mps / REFERENCE_SPEED_MPS * encounter_s / REFERENCE_S, speed_mps / REFERENCE_SPEED_MPS
        c = math.radians(course)
        rel_vel = (k * speed * math.sin(c), k * speed * math.cos(c) - speed_mps)
        w2 = rel_vel[0] ** 2 + rel_vel[1] ** 2
        out.append(-(east * s * rel_vel[0] + north * s * rel_vel[1]) / w2 if w2 > 0 else 0.0)
    return out
