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
    (all encounter classes occur), and its run-report update against a brute-force search back in time (straight
    relative motion between two samples 30 s apart)."""
    rng = np.random.default_rng(11)
    n = 2000
    own = np.array([10.0, -20.0, 1.5, 4.0, 1.2])
    pos, vel, yaw = rng.uniform(-1500, 1500, (n, 2)), rng.uniform(-8, 8, (n, 2)), rng.uniform(-np.pi, np.pi, n)
    yaw[::7] = own[4] + np.pi + rng.uniform(-0.1, 0.1, len(yaw[::7]))  # some reciprocal courses
    targets = np.arange(n, dtype=np.int64)
    out, min_dist, t_min, min_cpa = np.zeros((n, 10)), np.full(n, np.inf), np.zeros(n), np.full(n, np.inf)
    tcpa_at = np.full(n, np.nan)
    rel, w, cpa, tcpa, bearing, rel_bearing, enc = _reference(own, pos, vel, yaw)
    prev = rel - w * 30.0  # the relative positions of a sample 30 s ago, straight motion
    aw.situation(own, pos, vel, yaw, targets, out, 30.0, 100.0, prev, min_dist, t_min, min_cpa, tcpa_at, 300.0)
    np.testing.assert_array_equal(prev, out[:, aw.X : aw.Y + 1])  # the next chord starts here
    np.testing.assert_allclose(out[:, aw.X : aw.Y + 1], rel)
    np.testing.assert_allclose(out[:, aw.VX : aw.VY + 1], w)
    np.testing.assert_allclose(out[:, aw.RANGE], np.linalg.norm(rel, axis=1))
    np.testing.assert_allclose(out[:, [aw.CPA, aw.TCPA, aw.BEARING, aw.REL_BEARING]],
                               np.c_[cpa, tcpa, bearing, rel_bearing], atol=1e-9)  # fmt: skip
    np.testing.assert_array_equal(out[:, aw.ENCOUNTER], enc)
    assert set(enc) == set(range(6))
    counted = (tcpa >= 0) & (tcpa <= 300.0)  # ARPA's window: only these predictions count in the run report
    assert 0 < counted.sum() < n
    np.testing.assert_allclose(min_cpa, np.where(counted, cpa, np.inf))
    np.testing.assert_allclose(tcpa_at, np.where(counted, tcpa, np.nan))
    back = np.linspace(0.0, 30.0, 30001)  # brute force: the least distance over the last 30 s
    for k in range(0, n, 97):
        d = np.linalg.norm(rel[k] - w[k] * back[:, None], axis=1)
        assert min_dist[k] == pytest.approx(d.min(), abs=1e-3)
        assert t_min[k] == pytest.approx(100.0 - back[d.argmin()], abs=2e-3)


def _independent(p_own, v_own, p_tgt, v_tgt):
    """Two constant-velocity ships, closed form in plain Python: r = p_t - p_o, v = v_t - v_o,
    t* = -r·v/|v|², CPA = |r + v t*|; with v = 0 the range never changes: t* = 0, CPA = |r|."""
    rx, ry = p_tgt[0] - p_own[0], p_tgt[1] - p_own[1]
    vx, vy = v_tgt[0] - v_own[0], v_tgt[1] - v_own[1]
    v2 = vx * vx + vy * vy
    t = -(rx * vx + ry * vy) / v2 if v2 > 0 else 0.0
    return math.hypot(rx + vx * t, ry + vy * t), t


@pytest.mark.parametrize(
    "p_own, v_own, p_tgt, v_tgt, cpa, tcpa",
    [
        ((0, 0), (0, 5), (0, 1000), (0, -5), 0.0, 100.0),  # head-on on one line: collision at t = 100 s
        ((0, 0), (0, 5), (30, 1000), (0, -5), 30.0, 100.0),  # head-on, 30 m apart abeam at the pass
        ((0, 0), (0, 5), (50, -100), (0, -5), 50.0, -10.0),  # diverging: passed 50 m apart 10 s ago
        ((0, 0), (3, 4), (300, 400), (3, 4), 500.0, 0.0),  # same velocity: no relative motion, CPA = range
        ((0, 0), (0, 0), (200, 0), (0, 0), 200.0, 0.0),  # both stopped
        ((0, 0), (0, 0), (200, 0), (-0.01, 0.0), 0.0, 20000.0),  # a target 200 m off creeping in at 1 cm/s
    ],
)
def test_cpa_tcpa_against_the_closed_form_of_two_straight_tracks(p_own, v_own, p_tgt, v_tgt, cpa, tcpa):
    """The kernel (`situation`, what the simulation publishes and reports) and `cpa_tcpa` against the textbook
    values and an independent closed form, degenerate cases included."""
    ref_cpa, ref_tcpa = _independent(p_own, v_own, p_tgt, v_tgt)
    assert (ref_cpa, ref_tcpa) == (pytest.approx(cpa, abs=1e-9), pytest.approx(tcpa, abs=1e-9))
    c, t = aw.cpa_tcpa(np.subtract([p_tgt], p_own), np.subtract([v_tgt], v_own))
    assert (c[0], t[0]) == (pytest.approx(cpa, abs=1e-9), pytest.approx(tcpa, abs=1e-9))
    own = np.array([*p_own, *v_own, 0.3])
    out = np.zeros((1, 10))
    aw.situation(own, np.array([p_tgt], float), np.array([v_tgt], float), np.zeros(1), np.zeros(1, np.int64), out,
                 -1.0, 0.0, np.zeros((1, 2)), np.zeros(1), np.zeros(1), np.zeros(1), np.zeros(1), 1200.0)  # fmt: skip
    assert out[0, aw.CPA] == pytest.approx(cpa, abs=1e-9) and out[0, aw.TCPA] == pytest.approx(tcpa, abs=1e-9)
    assert out[0, aw.RANGE] == pytest.approx(math.dist(p_own, p_tgt))


@pytest.mark.parametrize(
    "v_tgt, counted",
    [
        ((0.0, 0.0), False),  # no relative motion: TCPA 0, CPA = the range: nothing approaches
        ((0.0, 0.5e-6), False),  # below STEADY_MPS: no relative motion either
        ((0.0, 1.0), True),  # passing abeam now: TCPA 0, CPA = the range (200 m)
        ((-0.01, 0.0), False),  # closing at 1 cm/s: CPA 0 m but TCPA 20000 s, beyond the 1200 s limit
        ((-1.0, 0.0), True),  # closing at 1 m/s: CPA 0 m at TCPA 200 s
        ((1.0, 0.0), False),  # opening: the closest point is past
    ],
)
def test_the_run_report_counts_a_cpa_only_within_the_tcpa_limit(v_tgt, counted):
    """ARPA's rule: a CPA is a warning only with 0 <= TCPA <= the limit; the run report's min_cpa follows it."""
    own, out = np.zeros(5), np.zeros((1, 10))
    min_cpa, tcpa_at = np.full(1, np.inf), np.full(1, np.nan)
    aw.situation(own, np.array([[200.0, 0.0]]), np.array([v_tgt]), np.zeros(1), np.zeros(1, np.int64), out, 1.0,
                 1.0, np.array([[200.0, 0.0]]) - v_tgt, np.full(1, np.inf), np.zeros(1), min_cpa, tcpa_at, 1200.0)  # fmt: skip
    if counted:
        assert min_cpa[0] == pytest.approx(out[0, aw.CPA]) and tcpa_at[0] == pytest.approx(out[0, aw.TCPA])
        assert 0.0 <= tcpa_at[0] <= 1200.0
    else:
        assert min_cpa[0] == np.inf and np.isnan(tcpa_at[0])


def test_the_least_distance_is_on_the_sampled_track_not_extrapolated_from_the_last_velocity():
    """The own ship steams east at 5 m/s, turns north at t = 10.5 s (between two 1 s samples) and goes on; a ship
    lies still at (55, -30). On the true track the least distance is 30.10 m at 10.5 s; at the samples, 30.41 m
    (hypot(5, 30)) at 10 s, the least on the straight lines between them. The report looked back along the
    relative velocity of the sample at 11 s (north) and said 27.61 m at 10 s: a distance that never happened."""
    target = np.array([[55.0, -30.0]])

    def own_at(t):
        if t <= 10.5:
            return np.array([5.0 * t, 0.0, 5.0, 0.0, 0.0])
        return np.array([52.5, 5.0 * (t - 10.5), 0.0, 5.0, math.pi / 2])

    out, prev = np.zeros((1, 10)), target - own_at(0.0)[:2]
    min_dist, t_min, min_cpa, tcpa_at = np.array([np.hypot(*prev[0])]), np.zeros(1), np.full(1, np.inf), np.full(1, np.nan)
    for t in range(1, 21):
        aw.situation(own_at(t), target, np.zeros((1, 2)), np.zeros(1), np.zeros(1, np.int64), out, 1.0, float(t),
                     prev, min_dist, t_min, min_cpa, tcpa_at, 1200.0)  # fmt: skip
    sampled = min(math.dist(target[0], own_at(t)[:2]) for t in range(21))
    assert min_dist[0] == pytest.approx(sampled, abs=1e-12) and sampled == pytest.approx(math.hypot(5.0, 30.0))
    assert t_min[0] == pytest.approx(10.0, abs=1e-12)
    true_track = min(math.dist(target[0], own_at(t)[:2]) for t in np.linspace(0.0, 20.0, 200001))
    assert true_track == pytest.approx(math.hypot(2.5, 30.0), abs=1e-6) and min_dist[0] >= true_track


def test_the_least_distance_between_two_samples_of_straight_motion_is_exact():
    """A ship passing 30 m abeam at 5 m/s between two samples 1 s apart (at 19.5 s): 30 m at 19.5 s exactly."""
    out, min_dist, t_min, min_cpa, tcpa_at = np.zeros((1, 10)), np.full(1, np.inf), np.zeros(1), np.full(1, np.inf), np.full(1, np.nan)
    prev = np.array([[2.5, 30.0]])  # at 19 s
    aw.situation(np.zeros(5), np.array([[-2.5, 30.0]]), np.array([[-5.0, 0.0]]), np.zeros(1), np.zeros(1, np.int64), out,
                 1.0, 20.0, prev, min_dist, t_min, min_cpa, tcpa_at, 1200.0)  # fmt: skip
    assert (min_dist[0], t_min[0]) == (pytest.approx(30.0, abs=1e-12), pytest.approx(19.5, abs=1e-12))
