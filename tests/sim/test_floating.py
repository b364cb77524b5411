"""Floating at rest: equilibrium drafts against Archimedes, and no drift in calm water.

The reference for the draft is independent of the simulator's kernels: the settled hull mesh is cut by
the water plane with trimesh (a capped, closed solid), and the vertical offset that makes
rho g V = m g is found by bisection.
"""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from usvsim.core.transforms import matrix_from_quat
from usvsim.simulation import Simulation


def archimedes_offset(body, rho: float) -> float:
    """Vertical shift (m) of the settled hull that would make rho V = m exactly (0 = perfect)."""
    hull = body.model.hull
    world = hull.vertices @ matrix_from_quat(body.quat).T + body.position
    mesh = trimesh.Trimesh(world, hull.faces, process=False)

    def volume(water_z: float) -> float:
        cut = trimesh.intersections.slice_mesh_plane(mesh, [0, 0, -1], [0, 0, water_z], cap=True)
        return cut.volume

    lo, hi = -0.05, 0.05  # water level that would float the settled hull exactly
    for _ in range(40):
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if volume(mid) * rho < body.model.mass_kg else (lo, mid)
    return (lo + hi) / 2


@pytest.fixture(scope="module")
def settled():
    """Every library vessel (and a custom box) dropped from 0.3 m above its waterline, 60 s later."""
    from usvsim.config.loader import parse_scenario

    vessels = [
        {"name": "wamv", "model": "wamv", "pose": {"position": [0.0, 0.0, 0.3]}},
        {"name": "otter", "model": "otter", "pose": {"position": [30.0, 0.0, 0.3]}},
    ]
    sim = Simulation(parse_scenario({"version": 1, "vessels": vessels}, "test"))
    sim.run(60.0)
    return sim


@pytest.mark.parametrize("name", ["wamv", "otter"])
def test_settles_at_archimedes_draft(settled, name):
    body = settled.vessels[name]
    assert abs(archimedes_offset(body, settled.rho)) < 1e-3
    # and the simulator's own hydrostatics agree with its weight
    assert body.displaced_volume * settled.rho == pytest.approx(body.model.mass_kg, rel=1e-6)


def test_otter_floats_at_fossen_draft(settled):
    """Fossen's Otter: 80 kg at T = 0.195 m; our keel-level base_link sits at -T."""
    otter = settled.vessels["otter"]
    assert otter.position[2] == pytest.approx(-0.195, abs=1e-3)
    assert abs(otter.rpy[1]) < 1e-3


def test_no_drift_in_calm_water(settled):
    start = {n: (v.position, v.rpy[2]) for n, v in settled.vessels.items()}
    settled.run(600.0)
    for name, v in settled.vessels.items():
        p0, yaw0 = start[name]
        assert np.linalg.norm(v.position[:2] - p0[:2]) < 0.01, name
        assert abs(np.degrees(v.rpy[2] - yaw0)) < 0.1, name


def test_custom_box_floats_at_analytic_draft(scenario_of, box_stl, tmp_path):
    """A 2 x 1 m box of 500 kg: T = m / (rho L B) = 0.2439 m."""
    vessel = {"name": "box", "model": "custom", "hull_mesh": box_stl.name, "mass": {"mass_kg": 500.0,
              "com": [0.0, 0.0, 0.2]}, "pose": {"position": [0.0, 0.0, 0.3]}}  # fmt: skip
    sim = Simulation(scenario_of({"vessels": [vessel]}, tmp_path))
    sim.run(30.0)
    assert sim.vessels["box"].position[2] == pytest.approx(-500.0 / (1025.0 * 2.0), abs=1e-3)


@pytest.mark.parametrize("model", ["wamv", "otter", "otter_pvs"])
def test_no_hydrodynamic_damping_on_a_hull_in_the_air(scenario_of, model):
    """Released 20 m above calm water with a 2 m/s current: free fall (the integrator's: z = 20 - g dt² n(n+1)/2)
    and no drift until the keel meets the water. The state-space drag (otter, wamv) and Fossen's damping
    (otter_pvs) acted in full on a hull in the air: the Otter fell at 1.3 m/s and drifted with the current.
    Fossen's added mass (otter_pvs, in MuJoCo's armature) fades with the damping: it fell at m / (m + A_33) g =
    0.59 g."""
    sc = scenario_of({"environment": {"current": {"speed_mps": 2.0, "direction_deg": 0.0}},
                      "vessels": [{"name": "b", "model": model, "pose": {"position": [0.0, 0.0, 20.0]}}]})  # fmt: skip
    sim = Simulation(sc)
    n = 120
    sim.run(n * sim.world.clock.dt)
    boat, dt = sim.vessels["b"], sim.world.clock.dt
    assert not sim.model.dof_armature.any()  # no added mass in the air
    fall = 9.81 * dt * dt * n * (n + 1) / 2
    assert boat.position[2] == pytest.approx(20.0 - fall, abs=1e-6)
    assert abs(boat.position[0]) < 1e-9 and abs(boat.position[1]) < 1e-9
    sim.close()


def test_fossen_added_mass_returns_with_the_water(scenario_of):
    """otter_pvs dropped from 1 m: no armature (added mass) in the air, all of Fossen's heave added mass afloat
    again, and a reset starts with it."""
    sc = scenario_of({"vessels": [{"name": "b", "model": "otter_pvs", "pose": {"position": [0.0, 0.0, 1.0]}}]})
    sim = Simulation(sc)
    heave = sim.world.qvel_adr[0] + 2
    full = float(sim.model.dof_armature[heave])
    assert full > 0.0
    sim.step()
    assert sim.model.dof_armature[heave] == 0.0
    sim.run(8.0)
    assert sim.model.dof_armature[heave] == full  # afloat: at least half the displacement under water
    sim.run(0.3)
    sim.reset()
    assert sim.model.dof_armature[heave] == full


def test_fossen_added_mass_acts_on_a_body_mujoco_treats_as_simple(scenario_of, box_stl, tmp_path):
    """A custom box with diagonal inertia along FLU is a 'simple' body for MuJoCo, whose mass matrix is the constant
    dof_M0 made at compile time: the armature written afterwards was ignored (a box with A_33 = 410 kg heaved at
    1.27 s, not 2π√((m + A_33)/(ρ g A_wp)) = 1.55 s). Released from rest 5 cm above its equilibrium, its first step
    is v = dt F / (m + A_33) with F = -ρ g L B 0.05 (semi-implicit Euler; no damping at rest); after a switch to
    state-space drag, dt F / m."""
    mass, a33, rho, g = 820.0, 410.0, 1025.0, 9.81
    vessel = {"name": "box", "model": "custom", "hull_mesh": box_stl.name, "pose": {"position": [0.0, 0.0, -0.35]},
              "mass": {"mass_kg": mass, "com": [0.0, 0.0, 0.2], "inertia": [136.0, 300.0, 330.0]},
              "hydrodynamics": {"type": "fossen", "added_mass": [0.0, 0.0, a33, 40.0, 0.0, 0.0]}}  # fmt: skip
    sim = Simulation(scenario_of({"vessels": [vessel]}, tmp_path))
    assert sim.model.body_simple[1]  # the case under test
    box, dt = sim.vessels["box"], sim.world.clock.dt
    force = -rho * g * 2.0 * 1.0 * 0.05  # N, the box is 2 m x 1 m at the waterline
    sim.step()
    assert box.velocity_body[2] == pytest.approx(dt * force / (mass + a33), rel=1e-9)
    sim.reset()
    box.set_hydrodynamics({"type": "state_space"})
    sim.step()
    assert box.velocity_body[2] == pytest.approx(dt * force / mass, rel=1e-9)  # no added mass any more
    sim.close()
