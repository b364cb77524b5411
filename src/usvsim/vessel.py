"""User-facing handles: a floating body's state and a vessel's thrusters (views of the `World`)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Protocol, get_args

import numpy as np
from pydantic import TypeAdapter, ValidationError

from usvsim.config.loader import first_error_text
from usvsim.config.schema import did_you_mean
from usvsim.config.vessel import Buoyancy, Hydrodynamics
from usvsim.core.errors import InputError, Names
from usvsim.core.transforms import rpy_from_quat
from usvsim.hydro.thrusters import HOLD_NS

if TYPE_CHECKING:
    from usvsim.hydro.hydrostatics import HullSet, HydrostaticsResult
    from usvsim.hydro.models import MarineModels
    from usvsim.hydro.thrusters import ThrusterBank
    from usvsim.vessels.model import BodyModel
    from usvsim.world.state import BodyState


class World(Protocol):
    """What the handles read: a view of `usvsim.world.world.World`, which satisfies it (and owns them)."""

    state: BodyState
    thrusters: ThrusterBank
    hydrostatics: HydrostaticsResult
    hulls: HullSet
    marine: MarineModels

    @property
    def clock_ns(self) -> int: ...

    def body_quat(self, i: int) -> np.ndarray: ...

    def origin_velocity(self, i: int) -> np.ndarray: ...

    def teleport(self, index: int, pose, twist) -> None: ...

    def set_buoyancy(self, index: int, model) -> None: ...


class Thruster:
    """One thruster of a vessel. Commands: normalized thrust u in [-1, 1], azimuth angle in rad (REP 103)."""

    def __init__(self, world: World, index: int, name: str):
        self._world, self._i, self.name = world, index, name

    def command(self, thrust: float, angle_rad: float | None = None, hold: bool = True) -> bool:
        """Set the command; returns False (and counts it) if rejected: not a real number (a string, None), NaN/inf
        or |thrust| > 1. A command from Python holds until changed; `hold=False` (what network sources use) lets
        the vessel's `command_timeout_s` watchdog zero it when no new command comes."""
        stamp_ns = HOLD_NS if hold else self._world.clock_ns
        return self._world.thrusters.command(self._i, thrust, angle_rad, stamp_ns)

    def command_angle(self, angle_rad: float) -> bool:
        """Set only the azimuth command (rad, REP 103); False (counted) if not a finite real number."""
        return self._world.thrusters.command_angle(self._i, angle_rad)

    @property
    def thrust_n(self) -> float:
        """Current thrust (N) after the thruster's dynamics."""
        return float(self._world.thrusters.thrust[self._i])

    @property
    def angle_rad(self) -> float:
        """Current azimuth angle (rad, CCW from the mounting heading)."""
        return float(self._world.thrusters.angle[self._i])

    @property
    def immersion(self) -> float:
        """Wet fraction of the propeller disc in the last step (0 in the air, 1 under water): the hull feels
        `thrust_n` times this."""
        return float(self._world.thrusters.wet[self._i])


class Body:
    """A floating body (vessel or buoy): pose of its frame in the world, twist, hydrostatic outputs."""

    def __init__(self, world: World, index: int, name: str, model: BodyModel):
        self._world, self.index, self.name, self.model = world, index, name, model

    @property
    def position(self) -> np.ndarray:
        """Origin of the body frame (base_link) in the world, ENU m."""
        return self._world.state.pos[self.index].copy()

    @property
    def quat(self) -> np.ndarray:
        """Orientation (w, x, y, z), body FLU → world ENU."""
        return self._world.body_quat(self.index)

    @property
    def rpy(self) -> np.ndarray:
        """Roll, pitch, yaw (rad), REP 103."""
        return rpy_from_quat(self.quat)

    @property
    def velocity_body(self) -> np.ndarray:
        """Linear velocity of the body-frame origin, in the body frame FLU (m/s)."""
        s = self._world.state
        return s.rot[self.index].T @ self._world.origin_velocity(self.index)

    @property
    def angular_velocity_body(self) -> np.ndarray:
        """Angular velocity in the body frame FLU (rad/s)."""
        return self._world.state.omega_body[self.index].copy()

    @property
    def displaced_volume(self) -> float:
        """Displaced water volume (m^3) of the body's buoyancy model (triangles or voxels) at the last step, or
        at the state a build, reset, teleport or buoyancy switch left."""
        volume = self._world.marine.displaced_volume_m3
        return float((self._world.hydrostatics.volume if volume is None else volume)[self.index])

    def waterline(self) -> np.ndarray:
        """Waterline segments (k, 2, 3), world ENU m, from the last step."""
        return self._world.hulls.waterline(self.index)

    def teleport(self, pose, twist=0) -> None:
        """Move the body now: `pose` as in `usvsim.world.poses.pose_arrays` (a scenario pose dict, 6 numbers
        x, y, z m + roll, pitch, yaw rad, or 7 with a (w, x, y, z) quaternion); `twist` 0 or 6 numbers
        (u, v, w m/s, p, q, r rad/s) in base_link (FLU)."""
        self._world.teleport(self.index, pose, twist)

    @property
    def hydrodynamics(self):
        """The active hydrodynamics model (a config section: state_space, kerner or fossen)."""
        return self._world.marine.hydrodynamics[self.index]

    def set_hydrodynamics(self, model) -> None:
        """Switch the hydrodynamics model now; `model` is a section or a dict like {"type": "kerner"}."""
        self._world.marine.set_hydrodynamics(self.index, _validated(model, Hydrodynamics, "hydrodynamics"))

    @property
    def buoyancy(self):
        """The active buoyancy model (a config section: triangles or voxels)."""
        return self._world.marine.buoyancy[self.index]

    def set_buoyancy(self, model) -> None:
        """Switch the buoyancy model now; `model` is a section or a dict like {"type": "voxels"}. A model that cannot
        be built for this hull (voxels too fine) raises InputError and leaves the current one."""
        section = _validated(model, Buoyancy, "buoyancy")
        try:
            self._world.set_buoyancy(self.index, section)
        except InputError:
            raise
        except ValueError as exc:  # voxelize.check_grid: a bare ValueError, and the model was switched half
            raise InputError(f"buoyancy {model!r}: {exc}") from None


def _validated(model, annotation, what: str):
    """A model section from a section or a plain dict (strictly validated, like a scenario file); anything else,
    or a dict with a mistake, raises ValueError with one line (nothing is switched)."""
    members = get_args(get_args(annotation)[0])  # Annotated[A | B | ..., Field(discriminator="type")]
    if isinstance(model, members):
        return model
    kinds = ", ".join(repr(get_args(m.model_fields["type"].annotation)[0]) for m in members)
    if not isinstance(model, dict):
        raise InputError(f"{what} {model!r}: give a dict like {{'type': ...}} (type one of {kinds}) or a section")
    try:
        return TypeAdapter(annotation).validate_python(model)
    except ValidationError as exc:
        first = exc.errors()[0]
        if first["type"] == "extra_forbidden":  # the key's own section's keys (not a scenario's)
            member = next((m for m in members if model.get("type") in get_args(m.model_fields["type"].annotation)),
                          None)  # fmt: skip
            key = str(first["loc"][-1])
            text = f"{key}: unknown key" + did_you_mean(key, list(member.model_fields) if member else [])
        else:
            text = first_error_text(exc, model, list(model))
        raise InputError(f"{what} {model!r}: {text}") from None


class Vessel(Body):
    """A vessel: a floating body with named thrusters."""

    def __init__(self, world: World, index: int, name: str, model: BodyModel, thrusters: dict[str, Thruster]):
        super().__init__(world, index, name, model)
        self.thrusters = Names("thruster", thrusters)
        self.sensors: dict[str, Any] = Names("sensor")  # short name → Sensor, filled in by the Simulation

    def command(self, thrust: float, angle_rad: float | None = None, hold: bool = True) -> bool:
        """The same command to every thruster (holds until changed, see `Thruster.command`); True if all
        accepted."""
        accepted = [t.command(thrust, angle_rad, hold) for t in self.thrusters.values()]  # every one, no short cut
        return all(accepted)
