"""Vessel control: velocity controller, thrust allocation, station keeping, manual driving.

    from usvsim.control import VesselController, ControlLoop
    sim = Simulation.from_scenario("harbor")
    ctrl = VesselController.for_model(sim.vessels["wamv"].model)          # gains from the vessel
    loop = ControlLoop(sim, "wamv", ctrl, rate_hz=20, reference=(1.5, 0.0, 0.2))   # u, v, r for base_link
    sim.run(30.0, on_step=loop)

Frames: body FLU; τ = (X [N], Y [N], N [N m]) about the CoM; yaw rate and azimuth angles CCW (REP 103).
"""

from usvsim.control.allocation import Allocation, ConstrainedAllocator, PseudoInverseAllocator
from usvsim.control.layout import ThrusterLayout
from usvsim.control.manual import DriveAxes, axes_to_velocity, gamepad_axes, keyboard_axes, manual_commands
from usvsim.control.plant import PlantModel
from usvsim.control.station_keeping import HeadingHold, Pose2D, StationKeeping, wrap_angle
from usvsim.control.thrust_inverse import command_for_thrust
from usvsim.control.velocity import AxisTuning, VelocityController
from usvsim.control.vessel_controller import ControlLoop, VesselController, VesselState, read_state

__all__ = [
    "Allocation", "AxisTuning", "ConstrainedAllocator", "ControlLoop", "DriveAxes", "HeadingHold", "PlantModel",
    "Pose2D", "PseudoInverseAllocator", "StationKeeping", "ThrusterLayout", "VelocityController",
    "VesselController", "VesselState", "axes_to_velocity", "command_for_thrust", "gamepad_axes",
    "keyboard_axes", "manual_commands", "read_state", "wrap_angle",
]  # fmt: skip
