"""Voxelizer (non-convex, multi-component meshes; cache) and voxel buoyancy against closed forms."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from usvsim.hydro.voxelize import voxel_centers, voxelize
from usvsim.hydro.voxels import VoxelSet
from usvsim.vessels import wamv


@pytest.fixture(autouse=True)
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("USVSIM_CACHE", str(tmp_path))
    return tmp_path


def test_box_on_aligned_grid_is_exact():
    box = trimesh.creation.box((2.0, 1.0, 1.0))
    assert len(voxel_centers(box.vertices, box.faces, 0.1)) == 2000  # faces on grid points: half-open rule


def test_torus_and_catamaran_volume_within_one_percent():
    torus = trimesh.creation.torus(1.0, 0.3, major_sections=96, minor_sections=48)
    hull = wamv.build().hull  # two separate pontoons
    for v, f, s in ((torus.vertices, torus.faces, 0.05), (hull.vertices, hull.faces, 0.05)):
        g = voxelize(v, f, s)
        volume = trimesh.Trimesh(v, f).volume
        assert g.volume == pytest.approx(volume, rel=0.01)
        assert g.mesh_volume == pytest.approx(volume, rel=1e-9)
    # centre sampling agrees with an analytic torus inside test on the same grid points
    s = 0.05
    centers = voxel_centers(torus.vertices, torus.faces, s)
    inside = (np.hypot(centers[:, 0], centers[:, 1]) - 1.0) ** 2 + centers[:, 2] ** 2 < 0.3**2 * 1.01
    assert inside.mean() > 0.995


def test_cache_round_trip(cache):
    sph = trimesh.creation.icosphere(3, radius=0.5)
    g1 = voxelize(sph.vertices, sph.faces, 0.1)
    files = list((cache / "voxels").glob("*.npz"))
    assert len(files) == 1 and files[0].stem == g1.key
    g2 = voxelize(sph.vertices, sph.faces, 0.1)
    np.testing.assert_array_equal(g1.centers, g2.centers)
    assert voxelize(sph.vertices, sph.faces, 0.05).key != g1.key


def test_box_buoyancy_cut_is_exact_and_acts_at_the_centre_of_buoyancy():
    box = trimesh.creation.box((2.1, 1.1, 1.1))  # faces on cell boundaries of the 0.1 m grid
    grid = voxelize(box.vertices, box.faces, 0.1, supersample=1)
    assert grid.volume == pytest.approx(2.1 * 1.1 * 1.1)
    vs = VoxelSet([grid], match_mesh_volume=False)
    for z in (0.37, 0.1, -0.23):  # box centre height: draft 0.55 - z
        pos, com = np.array([[0.0, 0.0, z]]), np.array([[0.3, -0.2, z]])
        c = vs.world_centers(pos, np.eye(3)[None])
        r = vs.compute(c, np.zeros(len(c)), com, 1000.0, 9.81, cut=True)
        draft = 0.55 - z
        assert r.volume[0] == pytest.approx(2.1 * 1.1 * draft, rel=1e-9)
        np.testing.assert_allclose(r.cob[0], [0.0, 0.0, -draft / 2], atol=1e-9)
        np.testing.assert_allclose(r.torque[0], np.cross(r.cob[0] - com[0], r.force[0]), atol=1e-6)


def test_sphere_cut_error_beats_the_seed():
    sph = trimesh.creation.icosphere(4, radius=0.5)
    vs = VoxelSet([voxelize(sph.vertices, sph.faces, 0.05)])
    err, prev = 0.0, None
    for h in np.linspace(0.0, 1.0, 101):
        pos = np.array([[0.0, 0.0, 0.5 - h]])
        c = vs.world_centers(pos, np.eye(3)[None])
        v = vs.compute(c, np.zeros(len(c)), pos, 1000.0, 9.81, True).volume[0]
        err = max(err, abs(v - np.pi * h * h * (1.5 - h) / 3))
        if prev is not None:
            assert abs(v - prev) <= 1.5 * np.pi * 0.25 * 0.01  # no jumps
        prev = v
    assert err <= 0.0044


def test_displaced_volume_is_the_voxel_models_before_a_step_and_after_reset_and_teleport():
    """Vessel.displaced_volume under voxel buoyancy: the voxel model's volume at the pose a build, reset or
    teleport set (it read the triangle model's there: 0.0815 against 0.0747 m³ for this Otter), as after a step."""
    from usvsim.config.loader import parse_scenario
    from usvsim.simulation import Simulation

    boat = {"name": "v", "model": "otter", "pose": {"position": [0, 0, -0.2]}, "buoyancy": {"type": "voxels", "cut": False}}
    sim = Simulation(parse_scenario({"version": 1, "vessels": [boat]}, "t"))
    world, vessel = sim.world, sim.vessels["v"]

    def voxel_volume():  # the voxel set itself at the current pose, in calm water at z = 0
        voxels = world.marine._voxels
        centers = voxels.world_centers(world.state.pos[[0]], world.state.rot[[0]])
        com = np.ascontiguousarray(world.state.com_world[[0]])
        return float(voxels.compute(centers, np.zeros(len(centers)), com, world.rho, world.g).volume[0])

    assert abs(float(world.hydrostatics.volume[0]) / voxel_volume() - 1) > 0.05  # the two models differ here
    assert vessel.displaced_volume == voxel_volume()
    sim.run(0.5)
    sim.reset()
    assert vessel.displaced_volume == voxel_volume()
    vessel.teleport({"position": [3.0, 1.0, -0.25], "roll_deg": 10.0})
    assert vessel.displaced_volume == voxel_volume()
    sim.close()


def test_displaced_volume_follows_a_buoyancy_switch_at_once():
    """After set_buoyancy it read the old model's volume until the next step (found by QA)."""
    from usvsim.config.loader import parse_scenario
    from usvsim.simulation import Simulation

    sim = Simulation(parse_scenario({"version": 1, "vessels": [{"name": "v", "model": "otter"}]}, "t"))
    vessel = sim.vessels["v"]
    sim.run(1.0)
    triangles = vessel.displaced_volume
    vessel.set_buoyancy({"type": "voxels", "cut": False})
    switched = vessel.displaced_volume
    assert abs(switched / triangles - 1) > 0.02  # the voxel model's own volume, at once
    sim.step()
    assert vessel.displaced_volume == pytest.approx(switched, rel=1e-3)
    sim.close()
