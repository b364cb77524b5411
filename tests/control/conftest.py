"""Closed-loop helpers for the control tests (see usvsim.control.step_response)."""

from __future__ import annotations

import pytest

from usvsim.control.step_response import ClosedLoop, one_vessel, step_metrics

__all__ = ["ClosedLoop", "one_vessel", "step_metrics"]


@pytest.fixture
def closed_loop():
    return ClosedLoop
