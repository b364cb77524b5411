"""A marker buoy floats where a sphere of its radius and mass floats (independent closed form: the
spherical cap), although its hull for the hydrostatics is an 80-face polyhedron."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from usvsim import Simulation
from usvsim.config.loader import parse_scenario


def sphere_centre_height(radius_m: float, mass_kg: float, rho: float = 1025.0) -> float:
    """Height (m) of a floating sphere's centre above still water: the cap of depth t below the surface holds
    V = pi t^2 (3 r - t) / 3 = m / rho."""
    volume = mass_kg / rho
    t = brentq(lambda d: math.pi * d * d * (3.0 * radius_m - d) / 3.0 - volume, 0.0, 2.0 * radius_m)
    return radius_m - t


@pytest.mark.parametrize(("radius_m", "mass_kg"), [(0.3, 20.0), (0.5, 150.0), (0.25, 40.0)])
def test_a_buoy_floats_at_the_height_of_its_sphere(radius_m, mass_kg):
    buoy = {"type": "buoy", "name": "b", "position": [0.0, 0.0, 0.0], "radius_m": radius_m, "mass_kg": mass_kg,
            "mooring": None}  # fmt: skip
    sim = Simulation(parse_scenario({"version": 1, "objects": [buoy]}, "buoy"))
    sim.run(30.0)
    world = sim.world
    body = world.bodies["b"].index
    centre_z = world.state.pos[body][2]  # the body frame's origin is the sphere's centre (ENU, m)
    assert abs(world.state.vcom_world[body][2]) < 1e-4  # settled
    assert centre_z == pytest.approx(sphere_centre_height(radius_m, mass_kg), abs=1e-3)
    assert world.hydrostatics.volume[body] * 1025.0 == pytest.approx(mass_kg, rel=1e-4)


def test_the_buoy_hull_is_trimeshs_icosphere():
    """The buoy's own icosphere (made without importing trimesh) against trimesh.creation.icosphere(1): the same 42
    vertices, closed with consistent outward winding, the same volume."""
    trimesh = pytest.importorskip("trimesh")
    from usvsim.vessels.buoy import icosphere

    vertices, faces = icosphere()
    ref = trimesh.creation.icosphere(subdivisions=1, radius=1.0)
    mine = trimesh.Trimesh(vertices, faces, process=False)
    assert len(faces) == 80 and mine.is_watertight and mine.is_winding_consistent and mine.volume > 0
    assert mine.volume == pytest.approx(ref.volume, rel=1e-14)
    ours = np.array(sorted(map(tuple, vertices.round(12))))
    theirs = np.array(sorted(map(tuple, np.asarray(ref.vertices).round(12))))
    np.testing.assert_allclose(ours, theirs, atol=1e-12)
