"""Clustered still-water hydrostatics (hydro/flat.py) against the per-face kernel and an independent reference.

Frames and units: world ENU (z up), metres, newtons; body frame FLU. `compute_flat` must equal `compute` with
eta = level at every vertex (the same integrals, summed per cluster) to 1e-9 of each output's largest value,
for every body, every per-face row and every cluster state change (dry ↔ wet ↔ crossing).
"""

from __future__ import annotations

import numpy as np
import trimesh

from usvsim.hydro.flat import DRY, MIXED, WET, use_flat
from usvsim.hydro.hydrostatics import HullSet, HydrostaticsResult
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
        for name in HydrostaticsResult.FIELDS:
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


def _fleet():
    """Repeated hulls as in a fleet: three WAM-Vs (one with its centre of mass moved: a kind of its own), two
    Otters and a sphere, in an order that interleaves them."""
    meshes, coms = _hulls()
    order = [0, 1, 0, 2, 0, 1]
    fleet_coms = coms[order].copy()
    fleet_coms[4] += [0.1, 0.0, -0.05]  # the same mesh with another centre of mass: other coefficients
    return [meshes[i] for i in order], fleet_coms


def test_bodies_of_one_hull_share_tables_and_keep_their_own_states():
    """One table per (mesh, centre of mass); every body's results still equal the per-face kernel's, and each
    body's clusters change state on their own (identical hulls in different poses)."""
    meshes, coms = _fleet()
    exact, flat = HullSet(meshes), HullSet(meshes)
    use_flat(flat, coms)
    fc = flat._flat
    assert fc.kind_of.tolist() == [0, 1, 0, 2, 3, 1]
    single = HullSet(meshes[:1])
    use_flat(single, coms[:1])
    wamv_clusters = len(single._flat.coef)
    assert int(fc.kind_clusters[1] - fc.kind_clusters[0]) == wamv_clusters
    assert len(fc.state) == sum(int(fc.kind_clusters[k + 1] - fc.kind_clusters[k]) for k in fc.kind_of.astype(int))
    rng = np.random.default_rng(11)
    for trial in range(150):
        pos, rot, com = _pose(rng, coms, 0.03 if trial % 3 else 0.6)
        level = rng.normal(0.0, 0.3)
        world = exact.world_vertices(pos, rot)
        a = exact.compute(world, np.full(len(world), level), com, RHO, G)
        b = flat.compute_flat(rot, com, level, RHO, G)
        for name in HydrostaticsResult.FIELDS:
            x, y = getattr(a, name), getattr(b, name)
            if name == "cob":
                x, y = x[a.volume > 1e-6], y[a.volume > 1e-6]
            if x.size:
                assert np.abs(x - y).max() <= 1e-9 * max(float(np.abs(x).max()), 1e-3), (trial, name)
        # body 2 (a WAM-V sharing body 0's table) gives the bits of a hull set holding it alone
        single_res = single.compute_flat(rot[2:3], com[2:3], level, RHO, G)
        assert np.array_equal(single_res.force[0], b.force[2]) and np.array_equal(single_res.cob[0], b.cob[2])
        lo, hi = int(flat.face_offsets[2]), int(flat.face_offsets[3])
        assert np.array_equal(single_res.face_submerged_area, b.face_submerged_area[lo:hi])


def test_the_split_over_two_threads_gives_the_same_bits():
    """Half the bodies on the overlap worker (large fleets): every output bit for bit that of one thread."""
    from usvsim.core.overlap import Overlap

    meshes, coms = _fleet()
    one, two = HullSet(meshes), HullSet(meshes)
    use_flat(one, coms)
    use_flat(two, coms)
    overlap = Overlap()
    rng = np.random.default_rng(5)
    try:
        for trial in range(40):
            pos, rot, com = _pose(rng, coms, 0.03 if trial % 2 else 0.6)
            a = one.compute_flat(rot, com, 0.0, RHO, G)
            b = two.compute_flat(rot, com, 0.0, RHO, G, overlap)
            for name in HydrostaticsResult.FIELDS:
                assert np.array_equal(getattr(a, name), getattr(b, name)), (trial, name)
    finally:
        overlap.close()
