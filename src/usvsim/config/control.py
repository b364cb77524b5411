"""Scenario keys of a vessel's optional controller (`vessels[i].controller`), so velocity commands work.

```yaml
controller:
  type: velocity            # or station_keeping (holds `target`, default: the start pose)
  rate_hz: 20               # period must be a whole number of physics steps
  allocator: {type: constrained, yaw_priority: 10}   # or unconstrained (the seed's pseudo-inverse)
  gains:                    # every value optional: derived from mass, inertia, drag and thrusters
    surge: {bandwidth_rad_s: 1.0, reference_bandwidth_rad_s: 1.0}
    yaw: {kp: 500.0, ki: 800.0}
```
Units: surge/sway gains in N per m/s (kp) and N per m (ki); yaw in N m per rad/s and N m per rad.
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field

from usvsim.config.base import AngleDeg, NonNegativeFloat, PositiveFloat, Section, Vec2


class AxisGains(Section):
    """One axis of the velocity controller; omitted values are derived from the vessel (λ-tuning)."""

    bandwidth_rad_s: PositiveFloat | None = Field(default=None, description="closed-loop error bandwidth λ")
    kp: NonNegativeFloat | None = None
    ki: NonNegativeFloat | None = Field(
        default=None, description="fixed integral gain; default λ·d(ν_ref), scheduled"
    )
    reference_bandwidth_rad_s: PositiveFloat | None = None
    max_acceleration: PositiveFloat | None = Field(default=None, description="m/s² (yaw: rad/s²)")
    max_velocity: PositiveFloat | None = Field(default=None, description="m/s (yaw: rad/s)")


class VelocityGains(Section):
    """Per-axis gains of the velocity controller (FLU: surge along x, sway along y, yaw about z)."""

    surge: AxisGains = AxisGains()
    sway: AxisGains = AxisGains()
    yaw: AxisGains = AxisGains()


class Allocator(Section):
    """`constrained`: respects thrust, angle and rate limits (box-constrained least squares);
    `unconstrained`: the seed's weighted pseudo-inverse (commands clipped to ±1)."""

    type: Literal["constrained", "unconstrained"] = "constrained"
    yaw_priority: PositiveFloat = 10.0


class Hold(Section):
    """Station-keeping outer loop (proportional; the velocity loop's integrators remove offsets)."""

    position_gain_1ps: PositiveFloat = 0.25
    heading_gain_1ps: PositiveFloat = 0.25
    max_speed_mps: PositiveFloat = 1.0
    max_yaw_rate_rad_s: PositiveFloat = 0.3
    arrive_radius_m: PositiveFloat = Field(default=2.0, description="underactuated vessels: drive-to vs hold switch")


class Target(Section):
    """A station-keeping target: world ENU position (m) and yaw (deg, CCW from east)."""

    position: Vec2 = Field(description="[x east, y north] in the world frame (ENU), m")
    yaw_deg: AngleDeg = Field(default=0.0, description="heading of the vessel's +x, counter-clockwise from east")


class VelocityController(Section):
    """Velocity control (`cmd_vel`: surge, sway if fully actuated, yaw rate) with thrust allocation."""

    type: Literal["velocity"] = "velocity"
    rate_hz: PositiveFloat = 20.0
    gains: VelocityGains = VelocityGains()
    allocator: Allocator = Allocator()
    coriolis_feedforward: bool = True


class StationKeeping(VelocityController):
    """Hold a position and heading (`target`, default: the vessel's start pose) over the velocity controller."""

    type: Literal["station_keeping"] = "station_keeping"  # type: ignore[assignment]
    hold: Hold = Hold()
    target: Target | None = None


Controller = Annotated[VelocityController | StationKeeping, Field(discriminator="type")]
