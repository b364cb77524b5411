"""The one simulation clock, in integer nanoseconds."""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

NS_PER_S = 1_000_000_000


def period_ns(rate_hz: float) -> int:
    """Period of `rate_hz` in integer nanoseconds; raises ValueError if it is not a whole number of ns."""
    if not rate_hz > 0:
        raise ValueError(f"rate must be positive, got {rate_hz}")
    period = NS_PER_S / rate_hz
    rounded = round(period)
    if abs(period - rounded) > 1e-3:
        raise ValueError(
            f"{rate_hz} Hz has no whole-nanosecond period ({period:.3f} ns); the clock counts integer "
            "nanoseconds, so use a rate that divides 1e9 (e.g. 50, 100, 200, 250, 500, 1000 Hz)"
        )
    return rounded


def rate_at_most(rate_hz: float, step_ns: int) -> float:
    """The highest rate not above `rate_hz` whose period is a whole number of physics steps (every step when the
    physics is slower): what an output left at its default runs at."""
    steps = max(1, math.ceil(NS_PER_S / rate_hz / step_ns - 1e-9))
    return NS_PER_S / (steps * step_ns)


def _digits(rate_hz: float) -> str:
    """A rate with the digits it needs to pass `steps_per_period` when copied (33.3333 is 1e-6 off 30 ms: refused)."""
    return f"{rate_hz:.10g}"


def steps_per_period(rate_hz: float, step_ns: int) -> int:
    """How many physics steps make one period of `rate_hz`; ValueError if it is not a whole number."""
    if not isinstance(rate_hz, numbers.Real) or not math.isfinite(rate_hz) or float(rate_hz) <= 0:
        raise ValueError(f"a rate must be a finite number of Hz > 0, not {rate_hz!r}")
    period = NS_PER_S / rate_hz
    steps = round(period / step_ns)
    if steps < 1 or abs(steps * step_ns - period) > 1e-6 * period:
        raise ValueError(
            f"{rate_hz} Hz is not a whole multiple of the physics step ({step_ns / 1e6:g} ms); "
            f"use a rate whose period is a multiple of the step, e.g. {_digits(NS_PER_S / (step_ns * max(steps, 1)))} Hz"
        )
    return steps


def _seconds(ns: int) -> str:
    """A duration of whole nanoseconds in seconds, written so that it reads back as the same float."""
    value = ns / NS_PER_S
    text = f"{value:.12g}"
    return text if float(text) == value else repr(value)


def latency_steps(latency_s: float, step_ns: int) -> int:
    """How many physics steps make `latency_s`; ValueError if it is not a whole number (nothing is rounded:
    0.015 s at a 10 ms step was published after 2 steps, 20 ms, without a word)."""
    steps = math.floor(latency_s * NS_PER_S / step_ns + 0.5)
    if abs(steps * step_ns - latency_s * NS_PER_S) > 1e-6 * step_ns:
        below = math.floor(latency_s * NS_PER_S / step_ns)
        raise ValueError(
            f"{latency_s} s is not a whole multiple of the physics step ({step_ns / 1e6:g} ms); use a latency that "
            f"is a multiple of the step, e.g. {_seconds(below * step_ns)} or {_seconds((below + 1) * step_ns)} s"
        )
    return steps


@dataclass
class Clock:
    """Simulation time as an exact integer count of nanoseconds."""

    step_ns: int
    now_ns: int = 0
    steps: int = 0

    def tick(self) -> None:
        self.steps += 1
        self.now_ns = self.steps * self.step_ns

    def reset(self) -> None:
        self.now_ns = 0
        self.steps = 0

    @property
    def seconds(self) -> float:
        return self.now_ns / NS_PER_S

    @property
    def dt(self) -> float:
        return self.step_ns / NS_PER_S
