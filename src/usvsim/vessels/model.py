"""What a vessel (or any floating body) is to the simulator: hull, parts, mass properties, physics, thrusters."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from usvsim.config.hydro_models import FossenHydrodynamics, KernerHydrodynamics, WindLoad
from usvsim.config.vessel import StateSpaceDrag, Thruster
from usvsim.vessels.parts import Mesh, Part


@dataclass(frozen=True)
class BodyModel:
    """A floating body in its own frame (FLU, metres): `hull` is the closed physics mesh for hydrostatics,
    `collision` convex parts or primitives, `visuals` what is drawn. Inertia (kg m^2) is the full tensor
    about the centre of mass `com`, in body axes."""

    hull: Mesh
    collision: tuple[Part, ...]
    visuals: tuple[Part, ...]
    mass_kg: float
    com: np.ndarray
    inertia: np.ndarray
    drag: StateSpaceDrag | KernerHydrodynamics | FossenHydrodynamics  # the hydrodynamics model (library default)
    thrusters: tuple[Thruster, ...] = ()
    wind_load: WindLoad | None = None


def composite_inertia(
    parts: list[tuple[float, tuple[float, float, float], np.ndarray | None]],
) -> tuple[float, np.ndarray, np.ndarray]:
    """Mass, CoM and inertia about the CoM of rigid parts (mass, position, own inertia about its CoM or None)."""
    mass = sum(m for m, _, _ in parts)
    moment = np.zeros(3)
    for m, p, _ in parts:
        moment += m * np.asarray(p, dtype=float)
    com = moment / mass
    inertia = np.zeros((3, 3))
    for m, p, own in parts:
        r = np.asarray(p, dtype=float) - com
        inertia += m * (r @ r * np.eye(3) - np.outer(r, r))
        if own is not None:
            inertia += np.asarray(own, dtype=float)
    return mass, com, inertia
