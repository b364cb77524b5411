"""Clustered still-water hydrostatics (hydro/flat.py) against the per-face kernel and an independent reference.

Frames and units: world ENU (z up), metres, newtons; body frame FLU. `compute_flat` must equal `compute` with
eta = level at every vertex (the same integrals, summed per cluster) to 1e-9 of each output's largest value,
for every body, every per-face row and every cluster state change (dry ↔ wet ↔ crossing).
"""

from __future__ import annotations

import numpy as np
import trimesh

from usvsim.hydro.flat import DRY, MIXED, WET, use_flat
from usvsim.hydro.hydrostatics import HullSet
from usvsim.vessels.library import vessel_model

RHO, G = 1025.0, 9.81


def random_rotation(rng: np.random.Generator, scale: float) -> np.ndarray:
    axis = rng.normal(size=3)
    return trimesh.transformations.rotation_matrix(rng.normal(0.0, scale), axis)[:3, :3]


def _hulls():
    """Two real hulls (the WAM-V's and the Otter's) and a sphere, with off-centre centres of mass."""
    meshes, coms = [], []
    for name in ("wamv", "otter"):
        from usvsim.config.scenario import Vessel

        model = vessel_model(Vessel(name=name, model=name), 0, None, "test")
        meshes.append((model.hull.vertices, model.hull.faces))
        coms.append(model.com)
    sphere = trimesh.creation.icosphere(subdivisions=3, radius=0.6)
    meshes.append((sphere.vertices, sphere.faces))
    coms.append([0.05, -0.02, -0.1])
    return meshes, np.array(coms, float)


def _pose(rng, coms, scale):
    nb = len(coms)
    rot = np.array([random_rotation(rng, scale) for _ in range(nb)])
    pos = np.column_stack([rng.uniform(-20, 20, nb), rng.uniform(-20, 20, nb), rng.normal(0.0, 0.25, nb)])
    return pos, rot, pos + np.einsum("bij,bj->bi", rot, coms)


def test_flat_equals_the_per_face_kernel_over_random_poses_and_state_changes():
    meshes, coms = _hulls()
    exact, flat = HullSet(meshes), HullSet(meshes)
    use_flat(flat, coms)
    rng = np.random.default_rng(7)
    seen = set()
    for trial in range(300):
        pos, rot, com = _pose(rng, coms, 0.03 if trial % 3 else 0.6)  # near level, and anything
        level = rng.normal(0.0, 0.3)
        world = exact.world_vertices(pos, rot)
        a = exact.compute(world, np.full(len(world), level), com, RHO, G)
        b = flat.compute_flat(rot, com, level, RHO, G)
        seen.update(flat._flat.state.tolist())
        for name in a.__dataclass_fields__:
            x, y = getattr(a, name), getattr(b, name)
            if name == "cob":  # m / volume: compared where something is submerged
                x, y = x[a.volume > 1e-6], y[a.volume > 1e-6]
            if x.size:  # within 1e-9 of the largest value, or of an absolute floor (N, N m, m³, m, m²) near zero
                assert np.abs(x - y).max() <= 1e-9 * max(float(np.abs(x).max()), 1e-3), (trial, name)
    assert {DRY, WET, MIXED} <= seen  # every kind of cluster occurred, and rows were rewritten on changes


def test_flat_matches_trimesh_clipped_volume_and_centroid():
    """Independent reference: trimesh's plane slice of the sphere, its volume and centre of buoyancy."""
    meshes, coms = _hulls()
    hulls = HullSet(meshes)
    use_flat(hulls, coms)
    rng = np.random.default_rng(3)
    for _ in range(20):
        pos, rot, com = _pose(rng, coms, 0.5)
        pos[2, 2] = rng.uniform(-0.5, 0.5)
        com[2] = pos[2] + rot[2] @ coms[2]
        res = hulls.compute_flat(rot, com, 0.0, RHO, G)
        mesh = trimesh.Trimesh(meshes[2][0] @ rot[2].T + pos[2], meshes[2][1], process=False)
        part = mesh.slice_plane([0.0, 0.0, 0.0], [0.0, 0.0, -1.0], cap=True)
        assert abs(res.volume[2] - part.volume) <= 1e-9 * max(part.volume, 1e-9)
        np.testing.assert_allclose(res.cob[2], part.center_mass, atol=1e-9)
        np.testing.assert_allclose(res.force[2], [0.0, 0.0, RHO * G * part.volume], atol=1e-6 * RHO * G)


def test_reused_buffers_equal_a_fresh_hull_set():
    """Rows of a face without waterline are left alone when already zero (no rewrite every step): after many
    poses, both kernels' per-face outputs equal those of a fresh HullSet computing the last pose only."""
    meshes, coms = _hulls()
    used, flat_used = HullSet(meshes), HullSet(meshes)
    use_flat(flat_used, coms)
    rng = np.random.default_rng(21)
    for _ in range(50):
        pos, rot, com = _pose(rng, coms, 0.4)
        world = used.world_vertices(pos, rot)
        a = used.compute(world, np.zeros(len(world)), com, RHO, G)
        b = flat_used.compute_flat(rot, com, 0.0, RHO, G)
    fresh = HullSet(meshes)
    c = fresh.compute(fresh.world_vertices(pos, rot), np.zeros(len(world)), com, RHO, G)
    for name in ("face_submerged_area", "waterline_segments", "waterline_count"):
        assert np.array_equal(getattr(a, name), getattr(c, name)), name
        x, y = getattr(b, name), getattr(c, name)
        assert np.abs(x - y).max() <= 1e-9 * max(float(np.abs(y).max()), 1e-3), name
    assert not c.waterline_segments[c.waterline_count == 0].any()
