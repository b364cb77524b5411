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
