"""Controllers from scenario config (`usvsim.config.control`): what the simulation loop builds per vessel."""

from __future__ import annotations

import math

from usvsim.config import control as cfg
from usvsim.control.allocation import ConstrainedAllocator, PseudoInverseAllocator
from usvsim.control.layout import ThrusterLayout
from usvsim.control.plant import PlantModel
from usvsim.control.station_keeping import HeadingHold, Pose2D, StationKeeping
from usvsim.control.velocity import AxisTuning, VelocityController, actuator_time_constant
from usvsim.control.vessel_controller import ControlLoop, VesselController
from usvsim.core.clock import steps_per_period
from usvsim.core.errors import ScenarioError


def tuning_from_config(gains: cfg.VelocityGains) -> tuple[AxisTuning, AxisTuning, AxisTuning]:
    surge, sway, yaw = (AxisTuning(**getattr(gains, axis).model_dump()) for axis in ("surge", "sway", "yaw"))
    return surge, sway, yaw


def build_controller(config: cfg.VelocityController, model) -> VesselController:
    """A VesselController for a `BodyModel` (e.g. `sim.vessels[name].model`) from its controller config."""
    plant = PlantModel.from_body_model(model)
    layout = ThrusterLayout.from_thrusters(model.thrusters, plant.com_flu_m)
    velocity = VelocityController.design(plant, layout, actuator_time_constant(model.thrusters),
                                         tuning_from_config(config.gains), config.coriolis_feedforward)  # fmt: skip
    if config.allocator.type == "constrained":
        allocator = ConstrainedAllocator(layout, yaw_priority=config.allocator.yaw_priority)
    else:
        allocator = PseudoInverseAllocator(layout)
    hold = None
    if isinstance(config, cfg.StationKeeping):
        h = config.hold
        hold = StationKeeping(h.position_gain_1ps, HeadingHold(h.heading_gain_1ps, h.max_yaw_rate_rad_s),
                              h.max_speed_mps, layout.is_fully_actuated(), h.arrive_radius_m)  # fmt: skip
    return VesselController(plant, layout, velocity, allocator, hold)


def check_rate(config: cfg.VelocityController, step_ns: int, source: str, key: str) -> int:
    """Physics steps per control period; ScenarioError at `key`.rate_hz if it is not a whole number."""
    try:
        return steps_per_period(config.rate_hz, step_ns)
    except ValueError as exc:
        raise ScenarioError(source, f"{key}.rate_hz", str(exc)) from None


def control_loop(world, vessel_name: str, config: cfg.VelocityController) -> ControlLoop:
    """A ControlLoop for one scenario vessel, its reference the `initial_reference`; ScenarioError for a vessel
    without thrusters (its controller would command nothing)."""
    vessel = world.vessels[vessel_name]
    if not vessel.model.thrusters:
        from usvsim.config.loader import source_of

        index = [v.name for v in world.scenario.vessels].index(vessel_name)
        raise ScenarioError(source_of(world.scenario), f"vessels[{index}].controller",
                            f"vessel '{vessel_name}' has no thrusters to control (give it 'thrusters', or drop "
                            "the controller)")  # fmt: skip
    loop = ControlLoop(world, vessel_name, build_controller(config, vessel.model), config.rate_hz)
    loop.reference = initial_reference(world, vessel_name, config)
    return loop


def initial_reference(world, vessel_name: str, config: cfg.VelocityController):
    """Velocity controllers start at rest (reference 0); station keeping holds its `target`, or the vessel's
    pose now (at construction, or at the start of an episode)."""
    if not isinstance(config, cfg.StationKeeping):
        return (0.0, 0.0, 0.0)
    t = config.target
    if t is None:
        vessel = world.vessels[vessel_name]
        x, y, _ = vessel.position
        return Pose2D(float(x), float(y), float(vessel.rpy[2]))
    return Pose2D(t.position[0], t.position[1], math.radians(t.yaw_deg))
