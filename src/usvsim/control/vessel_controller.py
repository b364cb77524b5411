"""One vessel's control chain: state → (station keeping) → velocity controller → allocation → thrusters.

References (velocity for base_link, body FLU, like ROS `cmd_vel`; or a `Pose2D` target for station
keeping; or a force τ about the CoM like `cmd_force`) go through `compute*` (pure with respect to the
simulation: state in, commands out) or `apply*` (reads a usvsim `Vessel` handle, commands its thrusters).
`ControlLoop` runs a controller at a fixed rate inside `Simulation.run(on_step=...)`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from usvsim.control.allocation import ALLOCATORS, Allocation
from usvsim.control.layout import ThrusterLayout
from usvsim.control.plant import PlantModel, com_velocity, reference_at_com
from usvsim.control.station_keeping import Pose2D, StationKeeping
from usvsim.control.velocity import VelocityController, actuator_time_constant
from usvsim.core.clock import steps_per_period
from usvsim.core.errors import InputError, UsvsimError


@dataclass(frozen=True)
class VesselState:
    """What the controller needs: base_link position (world ENU, m), yaw (rad, REP 103), planar velocity
    (u, v, r) at the CoM (body FLU), and optionally each thruster's current azimuth angle and thrust."""

    position_enu_m: np.ndarray
    yaw_rad: float
    nu_com: np.ndarray
    thruster_angle_rad: np.ndarray | None = None
    thruster_thrust_n: np.ndarray | None = None


def read_state(vessel, thruster_names) -> VesselState:
    """VesselState of a usvsim `Vessel` handle (velocities converted from base_link to the CoM)."""
    nu = com_velocity(vessel.velocity_body, vessel.angular_velocity_body, vessel.model.com)
    handles = [vessel.thrusters[n] for n in thruster_names]
    w, x, y, z = vessel.quat
    yaw = math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))  # REP 103 yaw of R = Rz Ry Rx
    return VesselState(vessel.position, yaw, nu,
                       np.array([h.angle_rad for h in handles]), np.array([h.thrust_n for h in handles]))  # fmt: skip


class VesselController:
    """Velocity controller + thrust allocator (+ station keeping) for one vessel model."""

    def __init__(self, plant: PlantModel, layout: ThrusterLayout, velocity: VelocityController, allocator,
                 station_keeping: StationKeeping | None = None):  # fmt: skip
        self.plant, self.layout, self.velocity, self.allocator = plant, layout, velocity, allocator
        self.station_keeping = station_keeping or StationKeeping(fully_actuated=layout.is_fully_actuated())
        self.last: Allocation | None = None

    @classmethod
    def for_model(cls, model, allocator: str = "constrained", tuning=None, station_keeping=None,
                  coriolis_feedforward: bool = True) -> VesselController:  # fmt: skip
        """Gains and allocation derived from a `BodyModel` (mass, inertia, drag, thrusters)."""
        plant = PlantModel.from_body_model(model)
        layout = ThrusterLayout.from_thrusters(model.thrusters, plant.com_flu_m)
        tau_act = actuator_time_constant(model.thrusters)
        velocity = VelocityController.design(plant, layout, tau_act, tuning, coriolis_feedforward)
        if allocator not in ALLOCATORS:  # was a bare KeyError: 'qp'
            raise InputError(f"allocator {allocator!r}: choose {' or '.join(map(repr, ALLOCATORS))}")
        return cls(plant, layout, velocity, ALLOCATORS[allocator](layout), station_keeping)

    def reset(self) -> None:
        self.velocity.reset()
        self.allocator.reset()
        self.last = None

    # -- pure: state in, allocation out -------------------------------------------------------
    def compute_force(self, state: VesselState, tau, dt: float) -> Allocation:
        """Allocate a force τ (X [N], Y [N], N [N m]) about the CoM (the `cmd_force` path)."""
        self.last = last = self.allocator.allocate(tau, state.thruster_angle_rad, state.thruster_thrust_n, dt)
        return last

    def compute(self, state: VesselState, nu_cmd_base, dt: float) -> Allocation:
        """Track a velocity command (u [m/s], v [m/s], r [rad/s]) for base_link (the `cmd_vel` path)."""
        tau = self.velocity.update(state.nu_com, reference_at_com(nu_cmd_base, self.plant.com_flu_m), dt)
        allocation = self.compute_force(state, tau, dt)
        self.velocity.report_achieved(allocation.tau_achieved, dt)
        return allocation

    def compute_hold(self, state: VesselState, target: Pose2D, dt: float) -> Allocation:
        """Station keeping: hold base_link at `target` (world ENU position, yaw)."""
        nu_cmd = self.station_keeping.velocity_reference(state.position_enu_m, state.yaw_rad, target)
        return self.compute(state, nu_cmd, dt)

    # -- with a usvsim Vessel handle ----------------------------------------------------------
    def apply(self, vessel, reference, dt: float) -> Allocation:
        """Read the vessel, compute, command its thrusters. `reference`: (u, v, r) velocity or a Pose2D."""
        state = read_state(vessel, self.layout.names)
        if isinstance(reference, Pose2D):
            allocation = self.compute_hold(state, reference, dt)
        else:
            allocation = self.compute(state, reference, dt)
        send(vessel, allocation)
        return allocation

    def apply_force(self, vessel, tau, dt: float) -> Allocation:
        allocation = self.compute_force(read_state(vessel, self.layout.names), tau, dt)
        send(vessel, allocation)
        return allocation


def send(vessel, allocation: Allocation) -> None:
    """Command each thruster of `vessel` (normalized thrust, azimuth angle), stamped for the watchdog: a
    controller is a periodic source, and when it stops the thrusters stop after `command_timeout_s`."""
    for i, name in enumerate(allocation.names):
        vessel.thrusters[name].command(float(allocation.u[i]), float(allocation.angle_rad[i]), hold=False)


class ControlLoop:
    """Runs a VesselController every `rate_hz` period inside `sim.run(seconds, on_step=loop)`.
    The rate's period must be a whole number of physics steps (ValueError otherwise). Set `reference`
    to a velocity (u, v, r) for base_link or a Pose2D; `force` (τ about the CoM) overrides both."""

    def __init__(
        self,
        sim,
        vessel_name: str,
        controller: VesselController,
        rate_hz: float = 20.0,
        reference=(0.0, 0.0, 0.0),
    ):
        self.vessel = sim.vessels[vessel_name]
        self.controller = controller
        self.every = steps_per_period(rate_hz, sim.clock.step_ns)
        self.dt = self.every * sim.clock.step_ns / 1e9
        self.reference = reference
        self.force = None
        self._next = sim.clock.steps

    @property
    def reference(self):
        """The velocity (u m/s, v m/s, r rad/s; base_link, FLU) or the Pose2D the controller tracks."""
        return self._reference

    @reference.setter
    def reference(self, value) -> None:
        # checked here: a NaN was taken and poisoned the controller's state for good (the boat never moved
        # again, whatever the later references), and (1.0,) failed at the next step, far from the mistake
        numbers = (value.x_m, value.y_m, value.yaw_rad) if isinstance(value, Pose2D) else value
        if not _three_finite(numbers):
            raise UsvsimError(f"reference must be 3 finite numbers (u m/s, v m/s, r rad/s) or a Pose2D, not {value!r}")
        self._reference = value

    @property
    def force(self):
        """A force τ (X N, Y N, N N m) about the CoM, body FLU, that overrides the reference; None: the reference."""
        return self._force

    @force.setter
    def force(self, value) -> None:
        # checked as the reference is: a NaN left the thrusters at 0 without a word, (1.0,) was broadcast to
        # (1, 1, 1), and a string failed inside the next sim.run
        if value is not None and not _three_finite(value):
            raise UsvsimError(f"force must be 3 finite numbers (X N, Y N, N N m) or None, not {value!r}")
        self._force = value

    def reset(self) -> None:
        """Controller state cleared, next update at the next step (after a simulation reset)."""
        self.controller.reset()
        self._next = 0

    def __call__(self, sim) -> None:
        if sim.clock.steps < self._next:
            return
        self._next = sim.clock.steps + self.every
        if self.force is not None:
            self.controller.apply_force(self.vessel, self.force, self.dt)
        else:
            self.controller.apply(self.vessel, self.reference, self.dt)


def _three_finite(numbers) -> bool:
    """Whether `numbers` is 3 finite numbers (a NaN, a wrong length or a string is not)."""
    try:
        return len(numbers) == 3 and all(math.isfinite(float(v)) for v in numbers)
    except (TypeError, ValueError):
        return False
