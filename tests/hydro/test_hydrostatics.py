"""Hull hydrostatics kernel against closed-form answers and independent references.

References: trimesh's own plane clipping and mass properties (clipped polyhedron volume and
centroid), Archimedes, the wall-sided righting-moment formula, and brute-force quadrature.
"""

from __future__ import annotations

import numpy as np
import pytest
import trimesh
from trimesh.intersections import slice_faces_plane
from trimesh.triangles import mass_properties

from usvsim.hydro.hydrostatics import HullSet, HydrostaticsResult

RHO, G, R = 1000.0, 9.81, 0.5


def rot_x(phi: float) -> np.ndarray:
    c, s = np.cos(phi), np.sin(phi)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def random_rotation(rng: np.random.Generator) -> np.ndarray:
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


def solve(meshes, pos, rot, com, eta_fn=lambda v: np.zeros(len(v)), rho=RHO):
    """One HullSet.compute for bodies at poses (pos (nb,3), rot (nb,3,3)); returns (hulls, result)."""
    hulls = HullSet(meshes)
    world = hulls.world_vertices(np.asarray(pos, float), np.asarray(rot, float))
    result = hulls.compute(world, eta_fn(world), np.asarray(com, float), rho, G)
    return hulls, result


def clipped_reference(vertices, faces, plane_point, plane_normal_up):
    """Volume and centroid of the part of a closed mesh below a plane (trimesh, independent).

    The mesh is rotated so the plane is z = 0 through the origin: the missing cap then adds
    nothing to the divergence-theorem integrals, so the open clipped surface gives exact values.
    """
    n = np.asarray(plane_normal_up, float) / np.linalg.norm(plane_normal_up)
    q = trimesh.geometry.align_vectors(n, [0.0, 0.0, 1.0])[:3, :3]
    local = (np.asarray(vertices) - plane_point) @ q.T
    v, f = slice_faces_plane(local, np.asarray(faces), np.array([0.0, 0.0, -1.0]), np.zeros(3))[:2]
    if len(f) == 0:
        return 0.0, np.asarray(plane_point, float), 0.0
    props = mass_properties(v[f], skip_inertia=True)
    area = trimesh.triangles.area(v[f]).sum()
    return props.volume, props.center_mass @ q + plane_point, area


def icosphere(subdivisions: int) -> trimesh.Trimesh:
    return trimesh.creation.icosphere(subdivisions=subdivisions, radius=R)


# ---------------------------------------------------------------------------------------------
# sphere in flat water


@pytest.mark.parametrize("subdivisions", [1, 2, 3, 4])
def test_sphere_matches_clipped_polyhedron(subdivisions):
    mesh = icosphere(subdivisions)
    for z_c in np.linspace(-0.6, 0.6, 29):
        _, res = solve([(mesh.vertices, mesh.faces)], [[0, 0, z_c]], [np.eye(3)], [[0, 0, z_c]])
        v_ref, c_ref, wet_ref = clipped_reference(mesh.vertices + [0, 0, z_c], mesh.faces, 0, [0, 0, 1])
        if v_ref == 0.0:
            assert res.volume[0] == 0.0 and np.all(res.force == 0.0)
            continue
        assert res.volume[0] == pytest.approx(v_ref, rel=1e-9)
        assert res.force[0, 2] == pytest.approx(RHO * G * v_ref, rel=1e-9)
        assert np.abs(res.force[0, :2]).max() <= 1e-9 * res.force[0, 2]
        np.testing.assert_allclose(res.cob[0], c_ref, atol=1e-10)
        assert res.wetted_area[0] == pytest.approx(wet_ref, rel=1e-9)
        assert res.face_submerged_area.sum() == pytest.approx(wet_ref, rel=1e-9)
        # closed hull, planar water: the resultant acts through the centre of buoyancy
        np.testing.assert_allclose(
            res.torque[0], np.cross(res.cob[0] - [0, 0, z_c], res.force[0]), atol=1e-9 * res.force[0, 2]
        )


@pytest.mark.parametrize("z_c", [0.3, 0.05, -0.2])
def test_sphere_waterplane_area_is_volume_derivative(z_c):
    """A_wp = -dV/dz_c of the clipped polyhedron (central difference of the trimesh reference)."""
    mesh = icosphere(3)
    _, res = solve([(mesh.vertices, mesh.faces)], [[0, 0, z_c]], [np.eye(3)], [[0, 0, z_c]])
    dz = 1e-6
    v_lo = clipped_reference(mesh.vertices + [0, 0, z_c - dz], mesh.faces, 0, [0, 0, 1])[0]
    v_hi = clipped_reference(mesh.vertices + [0, 0, z_c + dz], mesh.faces, 0, [0, 0, 1])[0]
    assert res.waterplane_area[0] == pytest.approx((v_lo - v_hi) / (2 * dz), rel=1e-6)


def test_sphere_waterline_is_a_closed_loop_on_the_surface():
    mesh = icosphere(2)
    hulls, res = solve([(mesh.vertices, mesh.faces)], [[0, 0, 0.17]], [np.eye(3)], [[0, 0, 0.17]])
    seg = hulls.waterline(0)
    assert len(seg) == int(res.waterline_count.sum()) > 0
    assert np.abs(seg[:, :, 2]).max() < 1e-15
    radius_wl = np.sqrt(R**2 - 0.17**2)
    assert np.linalg.norm(seg[:, :, :2], axis=2).max() <= radius_wl + 1e-12
    starts = {tuple(np.round(p, 12)) for p in seg[:, 0]}
    ends = {tuple(np.round(p, 12)) for p in seg[:, 1]}
    assert starts == ends  # every segment's end starts another one: an oriented loop
    # oriented counter-clockwise about the outward normal of the submerged cap (down): clockwise
    # seen from above, so the shoelace area is minus the waterplane area
    x0, y0, x1, y1 = seg[:, 0, 0], seg[:, 0, 1], seg[:, 1, 0], seg[:, 1, 1]
    assert -0.5 * np.sum(x0 * y1 - x1 * y0) == pytest.approx(res.waterplane_area[0], rel=1e-12)


# physics.md §1.10: vertical force [N] for z_c = +0.25, 0, -0.25, -0.6 (fully submerged)
SPHERE_FORCE_TABLE = {
    1: (642.502, 2243.248, 3843.994, 4486.496),
    2: (759.283, 2481.344, 4203.406, 4962.689),
    3: (791.545, 2546.149, 4300.753, 5092.298),
    4: (799.805, 2562.702, 4325.600, 5125.405),
}


@pytest.mark.parametrize("subdivisions", [1, 2, 3, 4])
def test_sphere_force_table(subdivisions):
    mesh = icosphere(subdivisions)
    for z_c, expected in zip((0.25, 0.0, -0.25, -0.6), SPHERE_FORCE_TABLE[subdivisions]):
        _, res = solve([(mesh.vertices, mesh.faces)], [[0, 0, z_c]], [np.eye(3)], [[0, 0, z_c]])
        assert res.force[0, 2] == pytest.approx(expected, abs=6e-4)


def test_sphere_volume_and_cob_table_1280():
    """physics.md §2.3 (1280 faces): V [m³] and c_B,z [m]."""
    mesh = icosphere(3)
    table = [(0.25, 0.080688, -0.08699), (0.0, 0.259546, -0.18696), (-0.25, 0.438405, -0.31202)]
    for z_c, volume, cob_z in table:
        _, res = solve([(mesh.vertices, mesh.faces)], [[0, 0, z_c]], [np.eye(3)], [[0, 0, z_c]])
        assert res.volume[0] == pytest.approx(volume, abs=6e-7)
        assert res.cob[0, 2] == pytest.approx(cob_z, abs=6e-6)
    _, res = solve([(mesh.vertices, mesh.faces)], [[0, 0, -0.6]], [np.eye(3)], [[0, 0, -0.6]])
    assert res.volume[0] == pytest.approx(0.519093, abs=6e-7)
    assert res.cob[0, 2] == pytest.approx(-0.6, abs=1e-12)


# ---------------------------------------------------------------------------------------------
# heeled box: righting moment


def heeled_box(phi_rad: float):
    """physics.md §1.10 box (L=2, B=1, D=1, draft 0.4, KG 0.3), 12 triangles, heeled about the
    centreline point on the waterplane (the body origin); returns the result and G in world."""
    box = trimesh.creation.box(extents=(2.0, 1.0, 1.0))
    box.apply_translation([0.0, 0.0, 0.1])  # keel at z = -0.4 (draft), deck at +0.6
    rot = rot_x(phi_rad)
    g_world = rot @ np.array([0.0, 0.0, -0.1])  # KG = 0.3 above the keel
    _, res = solve([(box.vertices, box.faces)], [[0, 0, 0]], [rot], [g_world])
    return res, g_world


@pytest.mark.parametrize("deg, table", [(5, -74.6452), (10, -152.0493), (20, -327.8255), (30, -561.3500)])
def test_box_righting_moment_matches_wall_sided_formula(deg, table):
    res, _ = heeled_box(np.radians(deg))
    phi, volume, draft, beam, kg = np.radians(deg), 0.8, 0.4, 1.0, 0.3
    bm = beam**2 / (12 * draft)
    gm = draft / 2 + bm - kg
    gz = np.sin(phi) * (gm + bm * np.tan(phi) ** 2 / 2)
    exact = -RHO * G * volume * gz  # exact for a wall-sided box within its wall-sided range
    assert res.torque[0, 0] == pytest.approx(exact, rel=1e-10)
    assert res.torque[0, 0] == pytest.approx(table, rel=1e-6)
    assert np.abs(res.torque[0, 1:]).max() < 1e-9
    assert res.force[0, 2] == pytest.approx(7848.0, rel=1e-12)
    assert res.volume[0] == pytest.approx(0.8, rel=1e-12)
    assert res.waterplane_area[0] == pytest.approx(2.0 / np.cos(phi), rel=1e-12)


# ---------------------------------------------------------------------------------------------
# fully submerged, tilted water, single triangles


def random_convex_mesh(seed: int = 3) -> trimesh.Trimesh:
    points = np.random.default_rng(seed).normal(size=(40, 3)) * [0.8, 0.5, 0.3]
    return trimesh.convex.convex_hull(points)


def test_fully_submerged_force_is_depth_independent_and_acts_at_centroid():
    mesh = random_convex_mesh()
    rng = np.random.default_rng(1)
    for depth in (3.0, 10.0, 250.0):
        rot = random_rotation(rng)
        pos = np.array([0.3, -0.7, -depth])
        centroid = rot @ mesh.center_mass + pos
        _, res = solve([(mesh.vertices, mesh.faces)], [pos], [rot], [centroid])
        assert res.force[0, 2] == pytest.approx(RHO * G * mesh.volume, rel=1e-11)
        assert np.abs(res.force[0, :2]).max() <= 1e-11 * res.force[0, 2] * depth
        assert np.abs(res.torque[0]).max() <= 1e-11 * res.force[0, 2] * depth
        np.testing.assert_allclose(res.cob[0], centroid, atol=1e-10 * depth)
        assert res.wetted_area[0] == pytest.approx(mesh.area, rel=1e-12)
        assert abs(res.waterplane_area[0]) < 1e-12 and res.waterline_count.sum() == 0


@pytest.mark.parametrize("slope", [(0.0, 0.0), (0.12, -0.05), (-0.3, 0.2)])
def test_tilted_planar_water(slope):
    """Planar water eta = a x + b y + e0: F = rho g V (-a, -b, 1), tau = (c_B - com) x F,
    with V and c_B those of the mesh clipped by the tilted plane (divergence theorem)."""
    a, b = slope
    e0 = 0.05
    mesh = random_convex_mesh()
    rot = random_rotation(np.random.default_rng(7))
    pos = np.array([0.4, -0.2, 0.0])
    com = np.array([0.45, -0.1, 0.02])
    _, res = solve(
        [(mesh.vertices, mesh.faces)], [pos], [rot], [com], eta_fn=lambda v: a * v[:, 0] + b * v[:, 1] + e0
    )
    world = mesh.vertices @ rot.T + pos
    v_ref, c_ref, wet_ref = clipped_reference(world, mesh.faces, [0, 0, e0], [-a, -b, 1.0])
    assert 0.05 * mesh.volume < v_ref < 0.95 * mesh.volume
    assert res.volume[0] == pytest.approx(v_ref, rel=1e-9)
    np.testing.assert_allclose(res.cob[0], c_ref, atol=1e-10)
    f_ref = RHO * G * v_ref * np.array([-a, -b, 1.0])
    np.testing.assert_allclose(res.force[0], f_ref, rtol=0, atol=1e-9 * f_ref[2])
    np.testing.assert_allclose(res.torque[0], np.cross(c_ref - com, f_ref), rtol=0, atol=1e-9 * f_ref[2])
    assert res.wetted_area[0] == pytest.approx(wet_ref, rel=1e-9)


def test_single_triangle_reference_vector():
    """physics.md §1.10: triangle at depth 1 m, n = (0, 0, -1), A = 0.5, rho = 1025."""
    verts = np.array([[0.0, 0.0, -1.0], [0.0, 1.0, -1.0], [1.0, 0.0, -1.0]])
    _, res = solve([(verts, [[0, 1, 2]])], [[0, 0, 0]], [np.eye(3)], [[0, 0, 0]], rho=1025.0)
    np.testing.assert_allclose(res.force[0], [0.0, 0.0, 5027.625], atol=1e-9)
    # centre of pressure of a uniformly loaded triangle = its centroid (1/3, 1/3)
    np.testing.assert_allclose(res.torque[0], np.cross([1 / 3, 1 / 3, -1.0], res.force[0]), atol=1e-9)


def brute_force_pressure(tri: np.ndarray, eta_fn, n_sub: int):
    """Force and moment about the origin of p = rho g max(eta - z, 0) on one triangle, by the
    centroid rule on n_sub² congruent sub-triangles (second-order accurate)."""
    i, j = np.meshgrid(np.arange(n_sub), np.arange(n_sub), indexing="ij")
    keep = i + j < n_sub
    up = np.stack([i[keep] + 1 / 3, j[keep] + 1 / 3], axis=1) / n_sub
    keep = i + j < n_sub - 1
    down = np.stack([i[keep] + 2 / 3, j[keep] + 2 / 3], axis=1) / n_sub
    uv = np.concatenate([up, down])
    pts = tri[0] + uv[:, :1] * (tri[1] - tri[0]) + uv[:, 1:] * (tri[2] - tri[0])
    area_vec = 0.5 * np.cross(tri[1] - tri[0], tri[2] - tri[0])
    p = RHO * G * np.maximum(eta_fn(pts) - pts[:, 2], 0.0) / n_sub**2
    forces = -p[:, None] * area_vec
    return forces.sum(axis=0), np.cross(pts, forces).sum(axis=0), (p > 0).mean() * np.linalg.norm(area_vec)


@pytest.mark.parametrize("n_above", [1, 2])
@pytest.mark.parametrize("seed", range(3))
def test_cut_triangle_against_brute_force_quadrature(n_above, seed):
    """Random triangles with 1 or 2 vertices above tilted planar water, any vertex order."""
    rng = np.random.default_rng(seed)
    a, b = rng.uniform(-0.3, 0.3, size=2)

    def eta_fn(v):
        return a * v[:, 0] + b * v[:, 1]

    tri = rng.uniform(-1, 1, size=(3, 3))
    signs = rng.permutation([1.0] * n_above + [-1.0] * (3 - n_above))
    tri[:, 2] = eta_fn(tri) + signs * rng.uniform(0.1, 1.0, size=3)
    _, res = solve([(tri, [[0, 1, 2]])], [[0, 0, 0]], [np.eye(3)], [[0, 0, 0]], eta_fn=eta_fn)
    coarse = brute_force_pressure(tri, eta_fn, 300)
    force, moment, area = brute_force_pressure(tri, eta_fn, 600)
    force, moment = (4 * force - coarse[0]) / 3, (4 * moment - coarse[1]) / 3  # Richardson, 2nd order
    scale = np.abs(force).max()
    np.testing.assert_allclose(res.force[0], force, atol=1e-5 * scale)
    np.testing.assert_allclose(res.torque[0], moment, atol=1e-5 * scale)
    assert res.wetted_area[0] == pytest.approx(area, rel=2e-2)  # sample counting, first order
    assert res.waterline_count[0] == 1
    assert np.abs(res.waterline_segments[0, :, 2] - eta_fn(res.waterline_segments[0])).max() < 1e-14


# ---------------------------------------------------------------------------------------------
# batching, determinism, transforms, degenerate input


def test_batched_bodies_equal_separate_calls_and_repeat_bit_identically():
    sphere, box = icosphere(2), trimesh.creation.box(extents=(2.0, 1.0, 1.0))
    rng = np.random.default_rng(5)
    rots = [random_rotation(rng), rot_x(0.3)]
    pos = [[5.0, 1.0, 0.1], [-3.0, 2.0, 0.05]]
    com = [[5.0, 1.1, 0.0], [-3.0, 2.0, -0.1]]
    meshes = [(sphere.vertices, sphere.faces), (box.vertices, box.faces)]

    def wavy(v):
        return 0.2 * np.sin(0.7 * v[:, 0]) * np.cos(0.4 * v[:, 1])

    hulls, res = solve(meshes, pos, rots, com, eta_fn=wavy)
    first = {k: getattr(res, k).copy() for k in HydrostaticsResult.FIELDS}
    for k in range(2):
        single_hulls, single = solve([meshes[k]], [pos[k]], [rots[k]], [com[k]], eta_fn=wavy)
        faces = slice(int(hulls.face_offsets[k]), int(hulls.face_offsets[k + 1]))
        for name in ("force", "torque", "volume", "cob", "wetted_area", "waterplane_area"):
            np.testing.assert_array_equal(getattr(res, name)[k], getattr(single, name)[0])
        np.testing.assert_array_equal(res.face_submerged_area[faces], single.face_submerged_area)
        np.testing.assert_array_equal(hulls.waterline(k), single_hulls.waterline(0))
    world = hulls.world_vertices(np.asarray(pos), np.asarray(rots))
    again = hulls.compute(world, wavy(world), np.asarray(com), RHO, G)
    for name, value in first.items():
        np.testing.assert_array_equal(getattr(again, name), value)


def test_world_vertices_apply_pose():
    sphere, box = icosphere(1), trimesh.creation.box(extents=(2.0, 1.0, 1.0))
    rng = np.random.default_rng(9)
    rots = np.array([random_rotation(rng), random_rotation(rng)])
    pos = rng.normal(size=(2, 3))
    hulls = HullSet([(sphere.vertices, sphere.faces), (box.vertices, box.faces)])
    world = hulls.world_vertices(pos, rots)
    expected = np.concatenate([sphere.vertices @ rots[0].T + pos[0], box.vertices @ rots[1].T + pos[1]])
    np.testing.assert_allclose(world, expected, atol=1e-14)


def test_degenerate_input_gives_finite_results():
    box = trimesh.creation.box(extents=(1.0, 1.0, 1.0))
    # a zero-area face (repeated vertex) and a collinear one do not change anything
    extra = np.array([[0, 0, 1], [0, 1, 1]])
    with_degenerate = np.concatenate([box.faces, extra])
    for z in (0.5, 0.0, -0.5, 0.3):  # keel, mid-plane and deck exactly at the surface; generic
        _, plain = solve([(box.vertices, box.faces)], [[0, 0, z]], [np.eye(3)], [[0, 0, z]])
        _, res = solve([(box.vertices, with_degenerate)], [[0, 0, z]], [np.eye(3)], [[0, 0, z]])
        for name in ("force", "torque", "volume", "cob", "wetted_area", "waterplane_area"):
            values = getattr(res, name)
            assert np.all(np.isfinite(values))
            np.testing.assert_allclose(values, getattr(plain, name), atol=1e-12)
        assert res.volume[0] == pytest.approx(min(max(0.5 - z, 0.0), 1.0), abs=1e-15)
        assert res.force[0, 2] == pytest.approx(RHO * G * res.volume[0], abs=1e-9)


@pytest.mark.parametrize(
    "z, volume, n_segments, waterplane", [(0.0, 2 / 3, 4, 2.0), (-1.0, 4 / 3, 0, 0.0), (1.0, 0.0, 0, 0.0)]
)
def test_vertices_exactly_on_the_surface(z, volume, n_segments, waterplane):
    """Octahedron |x| + |y| + |z| <= 1 with its equator, top or bottom vertex exactly at z = 0."""
    verts = np.array([[1, 0, 0], [0, 1, 0], [-1, 0, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], float)
    faces = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4], [1, 0, 5], [2, 1, 5], [3, 2, 5], [0, 3, 5]]
    hulls, res = solve([(verts, faces)], [[0, 0, z]], [np.eye(3)], [[0, 0, z]])
    assert all(np.all(np.isfinite(getattr(res, k))) for k in HydrostaticsResult.FIELDS)
    assert res.volume[0] == pytest.approx(volume, abs=1e-15)
    np.testing.assert_allclose(res.force[0], [0, 0, RHO * G * volume], atol=1e-9)
    assert res.waterplane_area[0] == pytest.approx(waterplane, abs=1e-15)
    assert len(hulls.waterline(0)) == n_segments


def test_surface_through_a_vertex_of_cut_faces():
    verts = np.array([[0.0, 0.0, 0.0], [1.0, 0.1, -1.0], [0.2, 1.0, 1.0], [-1.0, -1.0, 0.5]])
    mesh = trimesh.Trimesh(verts, [[0, 1, 2], [0, 2, 3], [0, 3, 1], [1, 3, 2]])
    mesh.fix_normals()
    _, res = solve([(mesh.vertices, mesh.faces)], [[0, 0, 0]], [np.eye(3)], [[0, 0, 0]])
    v_ref, c_ref, _ = clipped_reference(mesh.vertices, mesh.faces, 0, [0, 0, 1])
    assert res.volume[0] == pytest.approx(v_ref, rel=1e-12)
    np.testing.assert_allclose(res.cob[0], c_ref, atol=1e-14)
