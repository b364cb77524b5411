"""CPA/TCPA against closed forms and brute-force minimization; COLREG encounter classes for textbook geometries."""

import math

import numpy as np
import pytest

from usvsim.traffic import awareness as aw


def test_crossing_at_right_angles_closed_form():
    # own ship north at 5 m/s from the origin; target 1000 m east heading west at 5 m/s, 100 m north of the own
    # ship's track: relative motion (-5, -5) from (1000, 100): TCPA = 1100/10 = 110 s, CPA = 900/sqrt(2)
    cpa, tcpa = aw.cpa_tcpa(np.array([[1000.0, 100.0]]), np.array([[-5.0, -5.0]]))
    assert tcpa[0] == pytest.approx(110.0)
    assert cpa[0] == pytest.approx(900.0 / math.sqrt(2.0))


def test_cpa_matches_brute_force_minimum():
    rng = np.random.default_rng(3)
    rel_pos, rel_vel = rng.uniform(-2000, 2000, (200, 2)), rng.uniform(-10, 10, (200, 2))
    cpa, tcpa = aw.cpa_tcpa(rel_pos, rel_vel)
    t = np.linspace(-2000, 2000, 400001)
    for k in range(0, 200, 20):
        d = np.linalg.norm(rel_pos[k] + rel_vel[k] * t[:, None], axis=1)
        assert cpa[k] == pytest.approx(d.min(), abs=1e-3)
        assert tcpa[k] == pytest.approx(t[d.argmin()], abs=0.02)


def test_no_relative_motion():
    cpa, tcpa = aw.cpa_tcpa(np.array([[30.0, 40.0]]), np.zeros((1, 2)))
    assert cpa[0] == 50.0 and tcpa[0] == 0.0


def classify(target_pos, target_course_deg, target_speed, own_speed=5.0):
    own_vel = np.array([0.0, own_speed])  # own ship heading north (ENU yaw 90°)
    c = math.radians(target_course_deg)
    tv = target_speed * np.array([[math.sin(c), math.cos(c)]])
    rel = np.array([target_pos], float)
    _, tcpa = aw.cpa_tcpa(rel, tv - own_vel)
    return aw.ENCOUNTER_NAMES[aw.encounters(rel, own_vel, math.pi / 2, tv, [math.pi / 2 - c], tcpa)[0]]


@pytest.mark.parametrize(
    "pos, course, speed, expected",
    [
        ((0, 1000), 180, 5, "head_on"),
        ((20, 1000), 182, 5, "head_on"),
        ((1000, 1000), 270, 5, "crossing_give_way"),  # target on the starboard bow crossing to port
        ((-1000, 1000), 90, 5, "crossing_stand_on"),  # target on the port bow
        ((0, 500), 0, 2, "overtaking"),  # slower target ahead on the same course
        ((0, -500), 0, 8, "overtaken"),  # faster target astern
        ((0, -500), 180, 5, "none"),  # opening astern
    ],
)
def test_encounter_classes(pos, course, speed, expected):
    assert classify(pos, course, speed) == expected


def test_min_distance_over_a_period():
    d, when = aw.min_distance_over(np.array([[100.0, 10.0], [100.0, 10.0]]), np.array([[-10.0, 0.0], [10.0, 0.0]]), 5.0)
    np.testing.assert_allclose(d, [math.hypot(50, 10), math.hypot(100, 10)])
    np.testing.assert_allclose(when, [5.0, 0.0])


def _reference(own, pos, vel, yaw):
    """The definitions of awareness.py's docstring in plain numpy, target by target."""
    rel, w = pos - own[:2], vel - own[2:4]
    w2 = (w * w).sum(1)
    tcpa = np.where(w2 > 1e-12, -(rel * w).sum(1) / np.maximum(w2, 1e-12), 0.0)
    cpa = np.linalg.norm(rel + w * tcpa[:, None], axis=1)
    bearing = np.arctan2(rel[:, 0], rel[:, 1]) % (2 * np.pi)
    own_heading, tgt_heading = np.pi / 2 - own[4], np.pi / 2 - yaw
    rel_bearing = aw.wrap_pi(bearing - own_heading)
    own_from_tgt = aw.wrap_pi(np.arctan2(-rel[:, 0], -rel[:, 1]) % (2 * np.pi) - tgt_heading)
    reciprocal = np.abs(aw.wrap_pi(tgt_heading - own_heading - np.pi)) <= aw.HEAD_ON_RAD
    faster = np.hypot(own[2], own[3]) > np.linalg.norm(vel, axis=1)
    enc = np.where(rel_bearing > 0, aw.CROSSING_GIVE_WAY, aw.CROSSING_STAND_ON)
    enc = np.where(np.abs(rel_bearing) > aw.ABAFT_BEAM_RAD, aw.OVERTAKEN, enc)
    enc = np.where((np.abs(own_from_tgt) > aw.ABAFT_BEAM_RAD) & faster & (np.abs(rel_bearing) <= aw.ABAFT_BEAM_RAD),
                   aw.OVERTAKING, enc)  # fmt: skip
    enc = np.where((np.abs(rel_bearing) <= aw.HEAD_ON_RAD) & reciprocal, aw.HEAD_ON, enc)
    return rel, w, cpa, tcpa, bearing, rel_bearing, np.where(tcpa > 0, enc, aw.NONE)


def test_situation_kernel_matches_the_definitions():
    """The one-call kernel the simulation uses (awareness.situation) against the definitions, 2000 random targets
    (all encounter classes occur), and its run-report update against a brute-force search back in time."""
    rng = np.random.default_rng(11)
    n = 2000
    own = np.array([10.0, -20.0, 1.5, 4.0, 1.2])
    pos, vel, yaw = rng.uniform(-1500, 1500, (n, 2)), rng.uniform(-8, 8, (n, 2)), rng.uniform(-np.pi, np.pi, n)
    yaw[::7] = own[4] + np.pi + rng.uniform(-0.1, 0.1, len(yaw[::7]))  # some reciprocal courses
    targets = np.arange(n, dtype=np.int64)
    out, min_dist, t_min, min_cpa = np.zeros((n, 10)), np.full(n, np.inf), np.zeros(n), np.full(n, np.inf)
    aw.situation(own, pos, vel, yaw, targets, out, 30.0, 100.0, min_dist, t_min, min_cpa)
    rel, w, cpa, tcpa, bearing, rel_bearing, enc = _reference(own, pos, vel, yaw)
    np.testing.assert_allclose(out[:, aw.X : aw.Y + 1], rel)
    np.testing.assert_allclose(out[:, aw.VX : aw.VY + 1], w)
    np.testing.assert_allclose(out[:, aw.RANGE], np.linalg.norm(rel, axis=1))
    np.testing.assert_allclose(out[:, [aw.CPA, aw.TCPA, aw.BEARING, aw.REL_BEARING]],
                               np.c_[cpa, tcpa, bearing, rel_bearing], atol=1e-9)  # fmt: skip
    np.testing.assert_array_equal(out[:, aw.ENCOUNTER], enc)
    assert set(enc) == set(range(6))
    np.testing.assert_allclose(min_cpa, np.where(tcpa > 0, cpa, np.inf))
    back = np.linspace(0.0, 30.0, 30001)  # brute force: the least distance over the last 30 s
    for k in range(0, n, 97):
        d = np.linalg.norm(rel[k] - w[k] * back[:, None], axis=1)
        assert min_dist[k] == pytest.approx(d.min(), abs=1e-3)
        assert t_min[k] == pytest.approx(100.0 - back[d.argmin()], abs=2e-3)
