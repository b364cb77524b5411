"""End to end: the stack maps a small walled basin from LiDAR and drives to a goal behind a box."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.ndimage import binary_dilation

from usvsim.autonomy.odometry import kiss_icp_available
from usvsim.autonomy.run import build_navigator, navigate
from usvsim.autonomy.truth import true_occupancy
from usvsim.config.loader import parse_scenario
from usvsim.simulation import Simulation

LIDAR = {"type": "lidar", "name": "lidar", "preset": "os1_64", "columns": 512, "rate_hz": 10, "motion_distortion": True,
         "self_returns": False, "range_max_m": 40, "mount": {"position": [0.701, 0.0, 1.031]}}  # fmt: skip
WALLS = [("north", [0, 12, 1], [40, 1, 4]), ("south", [0, -12, 1], [40, 1, 4]), ("west", [-20, 0, 1], [1, 24, 4]),
         ("east", [20, 0, 1], [1, 24, 4]), ("block", [4, 0, 1], [2, 5, 3])]  # fmt: skip


@pytest.mark.parametrize("odometry", ["kiss_icp", "sensor"])
def test_drives_around_a_block_to_the_goal(odometry):
    if odometry == "kiss_icp" and not kiss_icp_available():
        pytest.skip("KISS-ICP not installed (extra `autonomy`)")
    data = {"version": 1, "world": {"physics_rate_hz": 100},
            "vessels": [{"name": "wamv", "model": "wamv", "pose": {"position": [-8.0, 0.0, 0.0]},
                         "controller": {"type": "velocity"},
                         "sensors": [LIDAR, {"type": "odometry", "name": "odometry", "rate_hz": 20}]}],
            "objects": [{"type": "wall", "name": n, "position": p, "size": s} for n, p, s in WALLS]}  # fmt: skip
    sim = Simulation(parse_scenario(data, "test"))
    nav, tap = build_navigator(sim, "wamv", "lidar", [(12.0, 1.0)], odometry=odometry)
    trace = navigate(sim, nav, tap, "wamv", "lidar", max_time_s=60.0)
    assert nav.done and not trace.contacts
    truth = np.array(trace.truth)
    assert np.hypot(truth[-1, 1] - 12.0, truth[-1, 2] - 1.0) < 1.5  # declared within 1 m of its estimate
    occupied = nav.grid.occupied()
    real = true_occupancy(sim, nav.grid, "wamv", nav.config.slice_m)
    stray = (occupied & ~binary_dilation(real)).sum()  # more than a cell (0.25 m) from any wall
    assert occupied.sum() > 100 and stray < 0.05 * occupied.sum(), (stray, occupied.sum())  # both deskew
    sim.close()
