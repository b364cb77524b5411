"""User-facing handles: a floating body's state and a vessel's thrusters (read from the simulation)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from pydantic import TypeAdapter

from usvsim.config.vessel import Buoyancy, Hydrodynamics
from usvsim.core.transforms import rpy_from_quat

if TYPE_CHECKING:
    from usvsim.simulation import Simulation
    from usvsim.vessels.model import BodyModel


class Thruster:
    """One thruster of a vessel. Commands: normalized thrust u in [-1, 1], azimuth angle in rad (REP 103)."""

    def __init__(self, sim: Simulation, index: int, name: str):
        self._sim, self._i, self.name = sim, index, name

    def command(self, thrust: float, angle_rad: float | None = None) -> bool:
        """Set the command; returns False (and counts it) if rejected: NaN/inf or |thrust| > 1."""
        return self._sim.thrusters.command(self._i, float(thrust), angle_rad, self._sim.clock_ns)

    def command_angle(self, angle_rad: float) -> bool:
        """Set only the azimuth command (rad, REP 103); False (counted) if not finite."""
        return self._sim.thrusters.command_angle(self._i, float(angle_rad))

    @property
    def thrust_n(self) -> float:
        """Current thrust (N) after the thruster's dynamics."""
        return float(self._sim.thrusters.thrust[self._i])

    @property
    def angle_rad(self) -> float:
        """Current azimuth angle (rad, CCW from the mounting heading)."""
        return float(self._sim.thrusters.angle[self._i])


class Body:
    """A floating body (vessel or buoy): pose of its frame in the world, twist, hydrostatic outputs."""

    def __init__(self, sim: Simulation, index: int, name: str, model: BodyModel):
        self._sim, self.index, self.name, self.model = sim, index, name, model

    @property
    def position(self) -> np.ndarray:
        """Origin of the body frame (base_link) in the world, ENU m."""
        return self._sim.state.pos[self.index].copy()

    @property
    def quat(self) -> np.ndarray:
        """Orientation (w, x, y, z), body FLU → world ENU."""
        return self._sim.body_quat(self.index)

    @property
    def rpy(self) -> np.ndarray:
        """Roll, pitch, yaw (rad), REP 103."""
        return rpy_from_quat(self.quat)

    @property
    def velocity_body(self) -> np.ndarray:
        """Linear velocity of the body-frame origin, in the body frame FLU (m/s)."""
        s = self._sim.state
        return s.rot[self.index].T @ self._sim.origin_velocity(self.index)

    @property
    def angular_velocity_body(self) -> np.ndarray:
        """Angular velocity in the body frame FLU (rad/s)."""
        return self._sim.state.omega_body[self.index].copy()

    @property
    def displaced_volume(self) -> float:
        """Displaced water volume at the last step (m^3)."""
        return float(self._sim.hydrostatics.volume[self.index])

    def waterline(self) -> np.ndarray:
        """Waterline segments (k, 2, 3), world ENU m, from the last step."""
        return self._sim.hulls.waterline(self.index)

    @property
    def hydrodynamics(self):
        """The active hydrodynamics model (a config section: state_space, kerner or fossen)."""
        return self._sim.marine.hydrodynamics[self.index]

    def set_hydrodynamics(self, model) -> None:
        """Switch the hydrodynamics model now; `model` is a section or a dict like {"type": "kerner"}."""
        self._sim.marine.set_hydrodynamics(self.index, _validated(model, Hydrodynamics))

    @property
    def buoyancy(self):
        """The active buoyancy model (a config section: triangles or voxels)."""
        return self._sim.marine.buoyancy[self.index]

    def set_buoyancy(self, model) -> None:
        """Switch the buoyancy model now; `model` is a section or a dict like {"type": "voxels"}."""
        self._sim.marine.set_buoyancy(self.index, _validated(model, Buoyancy))


def _validated(model, annotation):
    """A model section from a section or a plain dict (strictly validated, like a scenario file)."""
    if isinstance(model, dict):
        return TypeAdapter(annotation).validate_python(model)
    return model


class Vessel(Body):
    """A vessel: a floating body with named thrusters."""

    def __init__(self, sim: Simulation, index: int, name: str, model: BodyModel, thrusters: dict[str, Thruster]):
        super().__init__(sim, index, name, model)
        self.thrusters = thrusters

    def command(self, thrust: float, angle_rad: float | None = None) -> bool:
        """The same command to every thruster; True if all accepted."""
        accepted = [t.command(thrust, angle_rad) for t in self.thrusters.values()]  # every thruster, no short cut
        return all(accepted)
