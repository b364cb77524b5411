"""Each VRX scorer against a hand computation on a scripted trajectory (no simulation)."""

import math

import pytest

from usvsim.tasks.gates import Gate, GateCourseScorer, Side
from usvsim.tasks.perception import PerceptionObject, PerceptionScorer
from usvsim.tasks.pose_error import StationKeepingScorer, WayfindingScorer, heading_error, pose_error
from usvsim.tasks.timing import CollisionCounter, TaskTiming
from usvsim.tasks.wildlife import WildlifeScorer


def test_pose_error_is_d_plus_075_pow_d_times_heading_error():
    # 3-4-5 triangle: d = 5 m; heading error 0.5 rad → 5 + 0.75^5 · 0.5 = 5.11865234375
    assert pose_error((3.0, 4.0, 0.5), 0.0, 0.0, 0.0) == pytest.approx(5.0 + 0.2373046875 * 0.5, abs=1e-12)
    assert pose_error((3.0, 4.0, 0.5), 0.0, 0.0, 0.0, heading=False) == 5.0
    # heading error wraps: goal 3 rad, yaw -3 rad → 2π - 6 rad
    assert heading_error(3.0, -3.0) == pytest.approx(2 * math.pi - 6.0)


def test_station_keeping_mean_of_samples():
    s = StationKeepingScorer((0.0, 0.0, 0.0))
    held = [(1.0, 0.0, 0.2), (0.0, 2.0, -0.4), (0.0, 0.0, 1.0)]  # offsets and heading errors
    for x, y, yaw in held:
        s.update(x, y, yaw)
    expected = [1.0 + 0.75 * 0.2, 2.0 + 0.75**2 * 0.4, 1.0]
    assert s.score == pytest.approx(sum(expected) / 3, abs=1e-12)
    assert s.samples == 3


def test_wayfinding_mean_of_minimum_errors():
    w = WayfindingScorer([(0.0, 0.0, 0.0), (10.0, 0.0, math.pi / 2)])
    for x in (0.5, 0.0, 4.0, 9.0, 12.0):  # drives along x with yaw 0
        w.update(x, 0.0, 0.0)
    min0 = 0.0  # at x = 0, yaw 0
    min1 = min(abs(10 - x) + 0.75 ** abs(10 - x) * math.pi / 2 for x in (0.5, 0.0, 4.0, 9.0, 12.0))
    assert w.min_errors == pytest.approx([min0, min1])
    assert w.score == pytest.approx((min0 + min1) / 2)


def test_gate_geometry_red_to_starboard():
    g = Gate(left=(0.0, -10.0), right=(0.0, 10.0))  # red at y=-10: crossing direction +x
    assert g.direction == pytest.approx((1.0, 0.0))
    assert g.side(-1.0, 0.0) is Side.BEFORE and g.side(1.0, 9.9) is Side.AFTER and g.side(1.0, 10.5) is Side.OUTSIDE


def _course():
    return [Gate(left=(x, -10.0), right=(x, 10.0)) for x in (10.0, 40.0, 70.0)]


def test_navigation_all_gates_in_order():
    s = GateCourseScorer(_course())
    for x in range(0, 80):
        s.update(float(x), 0.0)
    # 3 gates × 10 + consecutive bonus for gates 2 and 3 + completion bonus
    assert s.score == 3 * 10 + 2 + 1 and s.finished


def test_navigation_collision_penalty_and_skipped_gate():
    s = GateCourseScorer(_course())
    for x in range(0, 30):
        s.update(float(x), 0.0)
    s.collide()  # 10 - 3
    for x in range(30, 80):  # gate 2 passed outside its width, gate 3 through
        s.update(float(x), 15.0 if x < 50 else 0.0)
    assert s.score == 10 - 3 + 10 + 1  # gate 3 is not consecutive to gate 1: only the completion bonus
    assert s.gates_crossed == 2 and s.finished


def test_navigation_backwards_invalidates_and_score_floor_zero():
    s = GateCourseScorer(_course())
    s.collide(2)
    assert s.score == 0.0
    for x in (5.0, 15.0, 35.0, 45.0, 35.0):  # gate 1 crossed, gate 2 crossed... then back through it
        s.update(x, 0.0)
    assert s.score == 10 + 10 + 1 and s.states[1] is Side.CROSSED


def _circle(cx, cy, r, clockwise, n=60, turns=1.2):
    """Points on a circle, 360/n = 6 degrees apart, starting at angle 0."""
    sign = -1.0 if clockwise else 1.0
    return [(cx + r * math.cos(sign * 2 * math.pi * k / n), cy + r * math.sin(sign * 2 * math.pi * k / n))
            for k in range(int(n * turns) + 1)]


def test_wildlife_circles_and_avoid_bonus():
    w = WildlifeScorer([("croc", "avoid"), ("platypus", "circumnavigate_clockwise"),
                        ("turtle", "circumnavigate_counterclockwise")])
    animals = [(100.0, 100.0), (0.0, 0.0), (50.0, 0.0)]
    t = 0.0
    for path in (_circle(0, 0, 6, clockwise=True), _circle(50, 0, 6, clockwise=False)):
        for x, y in path:
            t += 1.0
            w.update(t, x, y, animals)
    assert [a.state for a in w.animals][1:] == ["CIRCUMNAVIGATED", "CIRCUMNAVIGATED"]
    # By hand: the first point only engages; the gate at 0 deg then starts BEFORE/AFTER, so the eight
    # counted crossings are the gates at 45..315 and 360 deg, the last on the point at 366 deg (index 61).
    # The turtle's path starts at t = len(platypus path) + 1; score = that time - 30 s x (2 circled + 1 avoided).
    t_done = len(_circle(0, 0, 6, True)) + 1 + 61
    assert w.finished and w.score == pytest.approx(t_done - 3 * 30.0)


def test_wildlife_wrong_direction_never_counts():
    w = WildlifeScorer([("platypus", "circumnavigate_clockwise")])
    for k, (x, y) in enumerate(_circle(0, 0, 6, clockwise=False, turns=2.0)):
        w.update(float(k), x, y, [(0.0, 0.0)])
    assert w.animals[0].state == "ENGAGED" and w.animals[0].gates_crossed == 0 and not w.finished


def test_perception_errors_capped_and_unmatched():
    p = PerceptionScorer([PerceptionObject("red", 1.0, 10.0, 0.0), PerceptionObject("green", 10.0, 0.0, 10.0)])
    p.update(0.5)
    p.report("red", 10.0, 0.5)  # not active yet: balance 0, dropped at the next update
    p.update(0.6)
    p.update(2.0)
    p.report("green", 10.0, 0.3)  # wrong class: burns the one attempt
    p.report("red", 10.0, 0.3)  # balance 0: ignored
    p.update(3.0)
    p.update(6.5)  # red despawned with error 10
    p.update(11.0)
    p.report("green", 1.0, 10.0)  # 1.0 m
    p.update(12.0)
    p.update(15.5)
    assert p.finished and p.score == pytest.approx((10.0 + 1.0) / 2)
    q = PerceptionScorer([PerceptionObject("red", 0.0, 0.0, 0.0)])
    q.update(1.0)
    q.report("red", 30.0, 0.0)  # right class, far off: capped at 2 m
    q.update(2.0)
    q.update(6.0)
    assert q.score == 2.0


def test_perception_score_before_every_object_has_gone():
    """A time limit under the last window (30 s) gave the score NaN: 'mean score nan' and NaN in the JSON
    report. Objects not yet shown count 10 m, one being shown its error so far."""
    p = PerceptionScorer([PerceptionObject("red", 1.0, 10.0, 0.0), PerceptionObject("green", 10.0, 0.0, 10.0)])
    assert p.score == 10.0
    p.update(2.0)
    p.report("red", 10.0, 0.5)
    p.update(2.1)
    assert not p.finished and p.score == pytest.approx((0.5 + 10.0) / 2)


def test_perception_trial_shorter_than_its_objects_has_a_score():
    import json

    from usvsim.tasks import TaskTiming
    from usvsim.tasks.solutions import run_trial

    report = run_trial("perception", timing=TaskTiming(running_s=3.0))  # the first object shows at 5 s
    assert report["score"] == 10.0
    json.dumps(report, allow_nan=False)


def test_timing_and_collision_buffer():
    timing = TaskTiming(10.0, 10.0, 300.0)
    assert [timing.state(t) for t in (0.0, 10.0, 20.0, 320.0)] == ["initial", "ready", "running", "finished"]
    c = CollisionCounter(3.0)
    counted = [c.update(t, True) for t in (1.0, 2.0, 4.0, 4.5, 9.0)]
    assert counted == [1, 0, 0, 1, 1]  # strictly more than 3 s after the last counted one


def test_wildlife_time_out_subtracts_the_bonus_of_the_goals_met_as_vrx():
    """VRX's OnFinished at the time limit: timeout score = score - time bonus, used when positive. Before, a
    trial that timed out kept the full elapsed time (90 s with the platypus circled and the crocodile never
    approached, where VRX scores 90 - 60 = 30)."""
    w = WildlifeScorer([("croc", "avoid"), ("platypus", "circumnavigate_clockwise"),
                        ("turtle", "circumnavigate_counterclockwise")], time_limit_s=90.0)  # fmt: skip
    animals = [(100.0, 100.0), (0.0, 0.0), (50.0, 0.0)]
    for k, (x, y) in enumerate(_circle(0, 0, 6, clockwise=True)):
        w.update(float(k), x, y, animals)
    w.update(90.0, 20.0, 0.0, animals)
    assert w.score == 90.0 and not w.finished
    w.time_out()
    assert w.finished and w.score == 90.0 - 2 * 30.0
    w.update(91.0, 50.0, 6.0, animals)  # nothing changes after the end
    assert w.score == 30.0
    short = WildlifeScorer([("croc", "avoid"), ("platypus", "circumnavigate_clockwise")], time_limit_s=20.0)
    short.update(20.0, 0.0, 50.0, [(0.0, 0.0), (100.0, 0.0)])
    short.time_out()  # 20 - 30 is not positive: VRX keeps the score
    assert short.finished and short.score == 20.0
