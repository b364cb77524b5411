"""Controller config (strict pydantic sections) and building controllers and loops from it."""

from __future__ import annotations

import math
import runpy
import sys
from pathlib import Path

import pytest
from pydantic import TypeAdapter, ValidationError

from usvsim.config.control import Controller, StationKeeping, VelocityController
from usvsim.control import Pose2D
from usvsim.control.allocation import ConstrainedAllocator, PseudoInverseAllocator
from usvsim.control.factory import build_controller, check_rate, control_loop
from usvsim.core.errors import ScenarioError

ADAPTER = TypeAdapter(Controller)
EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "velocity_control.py"


def test_parses_both_types_and_rejects_unknown_keys():
    vel = ADAPTER.validate_python({"type": "velocity", "rate_hz": 50, "gains": {"yaw": {"kp": 500}}})
    assert isinstance(vel, VelocityController) and vel.gains.yaw.kp == 500.0
    sk = ADAPTER.validate_python({"type": "station_keeping", "target": {"position": [1, 2], "yaw_deg": 90}})
    assert isinstance(sk, StationKeeping) and sk.target.position == (1.0, 2.0)
    for bad in ({"type": "velocity", "gain": {}}, {"type": "pid"}, {"type": "velocity", "allocator": {"type": "lp"}},
                {"type": "velocity", "gains": {"surge": {"kp": -1}}}):  # fmt: skip
        with pytest.raises(ValidationError):
            ADAPTER.validate_python(bad)


def test_build_applies_overrides_and_allocator_choice(closed_loop):
    model = closed_loop("wamv").vessel.model
    cfg = ADAPTER.validate_python({"type": "velocity", "allocator": {"type": "unconstrained"},
                                   "gains": {"surge": {"kp": 123.0, "bandwidth_rad_s": 0.5}}})  # fmt: skip
    ctrl = build_controller(cfg, model)
    assert isinstance(ctrl.allocator, PseudoInverseAllocator)
    assert ctrl.velocity.tuning("surge").kp == 123.0 and ctrl.velocity.tuning("surge").bandwidth_rad_s == 0.5
    assert isinstance(
        build_controller(ADAPTER.validate_python({"type": "velocity"}), model).allocator, ConstrainedAllocator
    )


def test_rate_must_be_a_multiple_of_the_physics_step():
    assert check_rate(VelocityController(rate_hz=20.0), 10_000_000, "s.yaml", "vessels[0].controller") == 5
    with pytest.raises(ScenarioError, match=r"vessels\[0\]\.controller\.rate_hz"):
        check_rate(VelocityController(rate_hz=30.0), 10_000_000, "s.yaml", "vessels[0].controller")


def test_station_keeping_loop_holds_the_start_pose_by_default(closed_loop):
    sim = closed_loop("otter").sim
    loop = control_loop(sim, "boat", StationKeeping())
    assert isinstance(loop.reference, Pose2D) and loop.every == 5
    sim.run(5.0, on_step=loop)
    x, y, _ = sim.vessels["boat"].position
    assert math.hypot(x, y) < 0.05


def test_example_runs(monkeypatch, capsys):
    monkeypatch.setattr(sys, "argv", [str(EXAMPLE), "--seconds", "5", "--print-every", "2.5"])
    with pytest.raises(SystemExit) as done:
        runpy.run_path(str(EXAMPLE), run_name="__main__")
    assert done.value.code == 0
    lines = capsys.readouterr().out.strip().splitlines()
    assert len(lines) == 3 and float(lines[-1].split()[4]) > 1.0  # surging ahead after 5 s
