"""Ground-truth TF (REP 105): world → <vessel>/odom static, odom → base_link dynamic; each can be turned off."""

from __future__ import annotations

import numpy as np
import pytest

from usvsim.simulation import Simulation


def transforms(sim: Simulation, seconds: float) -> dict[str, list]:
    seen: dict[str, list] = {"/tf_static": [], "/tf": []}

    def keep(env):
        if env.topic in seen:
            seen[env.topic] += [(t.header.frame_id, t.child_frame_id, t) for t in env.msg.transforms]

    sim.subscribe(keep)
    sim.run(seconds)
    return seen


def scenario(scenario_of, **tf):
    return scenario_of({
        "vessels": [{"name": "wamv", "model": "wamv", "pose": {"position": [3.0, -2.0, 0.0], "yaw_deg": 30.0},
                     "sensors": [{"type": "imu", "name": "imu", "rate_hz": 50}]}],
        "outputs": {"tf": tf},
    })  # fmt: skip


def test_default_tree_is_world_odom_base_link_sensor(scenario_of):
    seen = transforms(Simulation(scenario(scenario_of)), 0.1)
    static = {(p, c): t for p, c, t in seen["/tf_static"]}
    assert set(static) == {("world", "wamv/odom"), ("wamv/base_link", "wamv/imu")}
    odom = static[("world", "wamv/odom")].transform
    assert (odom.translation.x, odom.translation.y) == pytest.approx((3.0, -2.0), abs=1e-9)
    assert 2 * np.degrees(np.arctan2(odom.rotation.z, odom.rotation.w)) == pytest.approx(30.0)
    assert {(p, c) for p, c, _ in seen["/tf"]} == {("wamv/odom", "wamv/base_link")}


def test_slam_and_ekf_setups_turn_off_the_transforms_they_own(scenario_of):
    seen = transforms(Simulation(scenario(scenario_of, world_to_odom=False, odom_to_base_link=False)), 0.1)
    assert {(p, c) for p, c, _ in seen["/tf_static"]} == {("wamv/base_link", "wamv/imu")}
    assert seen["/tf"] == []


def test_unknown_tf_key_is_rejected(scenario_of):
    with pytest.raises(Exception, match=r"outputs\.tf\.map_to_odom"):
        scenario(scenario_of, map_to_odom=True)
