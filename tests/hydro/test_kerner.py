"""Kerner forces against physics.md §1.10 and closed-form per-triangle formulas (computed here in NumPy)."""

from __future__ import annotations

import numpy as np
import pytest

from usvsim.config.hydro_models import KernerHydrodynamics
from usvsim.hydro import kerner_kernels as kk
from usvsim.hydro.hydrostatics import HullSet
from usvsim.hydro.kerner import KernerForces

TRI = np.array([(0.0, 0.0, -1.0), (0.0, 1.0, -1.0), (1.0, 0.0, -1.0)])
FACE = np.array([[0, 1, 2]])
Z3 = np.zeros((1, 3))


def one_triangle(cfg, v, omega=(0, 0, 0), com=(0.3, 0.3, -1.0), water=None, wind=(0, 0, 0), verts=TRI, eta=None):
    hulls = HullSet([(verts, FACE)])
    k = KernerForces(hulls, [cfg], [80.0], [2.0], rho_water=1025.0)
    water = np.zeros((3, 3)) if water is None else np.asarray(water, float)
    eta = np.zeros(3) if eta is None else eta
    res = k.compute(verts.copy(), eta, water, np.array([com], float), np.array([v], float), np.array([omega], float),
                    water[:1] * 0 + water.mean(axis=0), np.array([wind], float), 0.02)
    return res.parts[0].copy()


def reference_forces(v, n, area, c1, c2, f, rho=1025.0, nu=1.0533e-6, length=2.0):
    """Independent NumPy implementation of physics.md §1.5/§1.6 for one face."""
    speed = np.linalg.norm(v)
    c_f = 0.075 / (np.log10(speed * length / nu) - 2) ** 2
    vt = v - (v @ n) * n
    visc = 0.5 * rho * c_f * area * speed**2 * (-vt / np.linalg.norm(vt))
    cos = v @ n / speed
    pres = -(c1 * speed + c2 * speed**2) * area * cos**f * n if cos > 0 else (c1 * speed + c2 * speed**2) * area * (-cos) ** f * n
    return visc, pres


@pytest.mark.parametrize("c1,c2,f,expected", [(100, 100, 0.4, 179.0674), (10, 10, 0.5, 15.5415), (5, 100, 1.0, 52.7888)])
def test_single_triangle_vectors(c1, c2, f, expected):
    cfg = KernerHydrodynamics(kinematic_viscosity_m2ps=1.0533e-6, pressure_linear_pa=c1, pressure_quadratic_pa=c2, pressure_falloff=f, suction_falloff=f,
                              slamming_scale=0.0, air_scale=0.0)
    parts = one_triangle(cfg, (2.0, 0.0, -0.5))
    visc, pres = reference_forces(np.array([2.0, 0.0, -0.5]), np.array([0.0, 0.0, -1.0]), 0.5, c1, c2, f)
    np.testing.assert_allclose(parts[kk.VISCOUS, :3], visc, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(parts[kk.PRESSURE, :3], pres, rtol=1e-12, atol=1e-12)
    assert parts[kk.VISCOUS, 0] == pytest.approx(-3.87243, abs=5e-6)  # physics.md, printed digits
    assert parts[kk.PRESSURE, 2] == pytest.approx(expected, abs=5e-5)
    # torque about the CoM = (centroid - com) x F
    r = TRI.mean(axis=0) - np.array([0.3, 0.3, -1.0])
    np.testing.assert_allclose(parts[kk.PRESSURE, 3:], np.cross(r, parts[kk.PRESSURE, :3]), atol=1e-12)


def test_reynolds_and_friction_line():
    assert kk.friction_coefficient(2.0615528, 2.0, 1.0533e-6, 1e3) == pytest.approx(0.0035557, abs=5e-8)
    assert kk.friction_coefficient(1.0, 5.0, 1.0533e-6, 1e3) == pytest.approx(0.00343, abs=5e-6)  # §1.5 table
    assert kk.friction_coefficient(0.0, 5.0, 1.0533e-6, 1e3) == pytest.approx(0.075)  # Rn clamped to 1e3


def test_suction_side_pulls_along_the_normal():
    cfg = KernerHydrodynamics(suction_linear_pa=7.0, suction_quadratic_pa=3.0, suction_falloff=0.5,
                              reference_speed_mps=2.0, slamming_scale=0.0, air_scale=0.0)
    v = np.array([1.0, 0.0, 1.5])  # face (normal -z) moving away from the water behind it
    parts = one_triangle(cfg, v)
    s, cos = np.linalg.norm(v) / 2.0, -1.5 / np.linalg.norm(v)
    expected = (7.0 * s + 3.0 * s * s) * 0.5 * abs(cos) ** 0.5 * np.array([0.0, 0.0, -1.0])
    np.testing.assert_allclose(parts[kk.PRESSURE, :3], expected, rtol=1e-12)


def test_velocity_is_relative_to_the_water_at_each_point():
    cfg = KernerHydrodynamics(air_scale=0.0)
    water = np.tile([2.0, 0.0, -0.5], (3, 1))  # water moves with the face: no relative flow
    parts = one_triangle(cfg, (2.0, 0.0, -0.5), water=water)
    assert np.abs(parts).max() == 0.0
    # rotation: the point velocity ω × r at the centroid, not the CoM velocity
    com = np.array([0.3, 0.3, 0.0])
    omega = np.array([0.0, 1.0, 0.0])
    r = TRI.mean(axis=0) - com
    parts = one_triangle(KernerHydrodynamics(slamming_scale=0.0, air_scale=0.0), (0.0, 0.0, 0.0), omega, com)
    _, pres = reference_forces(np.cross(omega, r), np.array([0.0, 0.0, -1.0]), 0.5, 100, 100, 0.4)
    np.testing.assert_allclose(parts[kk.PRESSURE, :3], pres, rtol=1e-12)


def test_slamming_vectors_and_first_step():
    args = (0.05, 0.0, 0.0, -2.0, np.array([0.0, 0.0, -0.045]), 0.08, 0.02, 0.0, 0.0, -1.0, 80.0, 6.0)
    assert kk.slamming_force(*args, 2.0, 1000.0)[2] == pytest.approx(0.0031510, abs=5e-8)
    assert kk.slamming_force(*args, 0.5, 1000.0)[2] == pytest.approx(0.49441, abs=5e-6)
    assert kk.slamming_force(*args, 2.0, 10.0)[2] == pytest.approx(2.6667, abs=5e-5)
    assert kk.slamming_force(*args, 2.0, 10.0)[2] == pytest.approx(80 * 2 * 2 * 0.05 / 6, rel=1e-14)
    # the first compute() has no previous step: no slamming
    cfg = KernerHydrodynamics(viscous_scale=0.0, pressure_scale=0.0, air_scale=0.0, slamming_speed_mps=0.01)
    assert np.abs(one_triangle(cfg, (0.0, 0.0, -2.0))[kk.SLAMMING]).max() == 0.0


def test_slamming_through_the_kernel_on_a_cut_face():
    from usvsim.experiments.kerner_vectors import _slam

    # impulse form: ramp (v cos θ / v_slam)^p · cos θ · m v 2 ΔA / S over dt, ΔA = 0.05 - 0.03 m², dt = 0.02 s
    assert _slam(2.0, 1.0) == pytest.approx(80 * 2 * 2 * 0.02 / 6 / 0.02, rel=1e-12)
    assert _slam(2.0, 4.0) == pytest.approx(0.5**2 * 80 * 2 * 2 * 0.02 / 6 / 0.02, rel=1e-12)


def test_cut_face_splits_area_and_dry_part_feels_the_wind():
    tri = np.array([(0.0, 0.0, -0.5), (1.0, 0.0, 0.5), (0.0, 1.0, 0.5)])  # tilted, cut by z = 0
    cfg = KernerHydrodynamics(viscous_scale=0.0, pressure_scale=0.0, slamming_scale=0.0, air_drag_coefficient=0.9)
    wind = np.array([0.0, 0.0, -10.0])  # downward wind onto the up-facing dry part
    parts = one_triangle(cfg, (0.0, 0.0, 0.0), com=(0.0, 0.0, 0.0), wind=wind, verts=tri)
    n = np.cross(tri[1] - tri[0], tri[2] - tri[0])
    area = 0.5 * np.linalg.norm(n)
    dry = area * (1 - 0.25)  # submerged apex triangle: (1/2)² of the area
    v_rel = -wind
    assert n[2] > 0
    np.testing.assert_allclose(parts[kk.AIR, :3], -0.5 * 1.225 * 0.9 * dry * 10.0 * v_rel, rtol=1e-12)


def test_batch_equals_separate_bodies():
    rng = np.random.default_rng(1)
    import trimesh

    sph = trimesh.creation.icosphere(2, radius=0.5)
    meshes = [(sph.vertices, sph.faces), (sph.vertices * 1.5, sph.faces)]
    pos = np.array([[0.0, 0.0, 0.1], [3.0, 0.0, -0.2]])
    v, w = rng.normal(size=(2, 3)), rng.normal(size=(2, 3))
    cfg = [KernerHydrodynamics(), KernerHydrodynamics(pressure_falloff=0.7)]
    both = KernerForces(HullSet(meshes), cfg, [80.0, 120.0])
    hulls = both.hulls
    verts = hulls.world_vertices(pos, np.tile(np.eye(3), (2, 1, 1)))
    water = rng.normal(size=(len(verts), 3)) * 0.1
    out = both.compute(verts, np.zeros(len(verts)), water, pos, v, w, np.zeros((2, 3)), np.zeros((2, 3)), 0.01)
    for b in range(2):
        single = KernerForces(HullSet([meshes[b]]), [cfg[b]], [[80.0, 120.0][b]])
        sl = slice(hulls.vert_offsets[b], hulls.vert_offsets[b + 1])
        r = single.compute(np.ascontiguousarray(verts[sl]), np.zeros(sl.stop - sl.start), np.ascontiguousarray(water[sl]),
                           pos[b:b + 1], v[b:b + 1], w[b:b + 1], Z3, Z3, 0.01)
        np.testing.assert_allclose(r.parts[0], out.parts[b], rtol=1e-12, atol=1e-12)


def test_moving_sphere_drag_opposes_motion_and_is_symmetric():
    import trimesh

    sph = trimesh.creation.icosphere(3, radius=0.5)
    k = KernerForces(HullSet([(sph.vertices, sph.faces)]), [KernerHydrodynamics(air_scale=0.0)], [60.0])
    verts = k.hulls.world_vertices(Z3, np.eye(3)[None])
    res = k.compute(verts, np.zeros(len(verts)), np.zeros_like(verts), Z3, np.array([[1.5, 0.0, 0.0]]), Z3, Z3, Z3, 0.01)
    assert res.force[0, 0] < 0.0
    assert abs(res.force[0, 1]) < 1e-9 * abs(res.force[0, 0])
    assert abs(res.torque[0, 2]) < 1e-9 * abs(res.force[0, 0])


def test_mixed_bodies_repeat_bit_identically():
    import trimesh

    rng = np.random.default_rng(3)
    sph = trimesh.creation.icosphere(2, radius=0.5)
    nb = 5
    hulls = HullSet([(sph.vertices, sph.faces)] * nb)
    pos = np.column_stack([np.arange(nb) * 3.0, np.zeros(nb), [1.0, 0.1, -0.2, -1.0, 0.3]])  # dry, cut, wet
    verts = hulls.world_vertices(pos, np.tile(np.eye(3), (nb, 1, 1)))
    args = (verts, rng.normal(size=len(verts)) * 0.05, rng.normal(size=(len(verts), 3)) * 0.1, pos,
            rng.normal(size=(nb, 3)), rng.normal(size=(nb, 3)), np.zeros((nb, 3)), rng.normal(size=(nb, 3)), 0.01)
    cfg = [KernerHydrodynamics(pressure_falloff=0.4 + 0.1 * b) for b in range(nb)]
    runs = [KernerForces(hulls, cfg, [80.0] * nb) for _ in range(2)]
    for _ in range(2):  # second step: with slamming
        first, second = (k.compute(*args).parts.copy() for k in runs)
        assert np.array_equal(first, second)
    assert np.abs(first[0, kk.AIR]).max() > 0.0 and np.abs(first[0, :kk.AIR]).max() == 0.0  # dry body: air only


def _rotation(rng):
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


def _posed_sphere(z, seed):
    """An icosphere (320 faces) turned and moved to a random pose: (hulls, world vertices, rng)."""
    import trimesh

    rng = np.random.default_rng(seed)
    sph = trimesh.creation.icosphere(2, radius=0.5)
    hulls = HullSet([(sph.vertices * [1.0, 0.7, 0.5], sph.faces)])  # an ellipsoid: no rotational symmetry
    verts = hulls.world_vertices(np.array([[2.0, -1.0, z]]), _rotation(rng)[None]).copy()
    return hulls, verts, rng


def _face_kinematics(tri, com, v, omega, water):
    """Per-face centroid r (about the CoM), unit normal n, area, velocity minus the water's (NumPy)."""
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    area = 0.5 * np.linalg.norm(cross, axis=1)
    r = tri.mean(axis=1) - com
    return r, cross / (2 * area[:, None]), area, v + np.cross(omega, r) - water


def test_dry_hull_air_drag_matches_per_face_reference_in_any_pose():
    """Whole dry faces are summed in the body frame recovered from the hull: same as world per face."""
    hulls, verts, rng = _posed_sphere(3.0, 5)
    com, v, omega, wind = rng.normal(size=(1, 3)) * 0.1 + [2.0, -1.0, 3.0], rng.normal(size=(1, 3)), rng.normal(size=(1, 3)), rng.normal(size=(1, 3)) * 5  # fmt: skip
    k = KernerForces(hulls, [KernerHydrodynamics(air_drag_coefficient=0.9, air_scale=1.3)], [80.0])
    parts = k.compute(verts, np.zeros(len(verts)), np.zeros_like(verts), com, v, omega, Z3, wind, 0.01).parts[0]
    r, n, area, vel = _face_kinematics(verts[hulls.faces.astype(int)], com[0], v[0], omega[0], wind[0])
    into = np.einsum("ij,ij->i", vel, n) > 0
    f = -0.5 * 1.225 * 0.9 * 1.3 * (area * np.linalg.norm(vel, axis=1) * into)[:, None] * vel
    np.testing.assert_allclose(parts[kk.AIR], np.concatenate([f.sum(0), np.cross(r, f).sum(0)]), rtol=1e-12, atol=1e-12)
    assert into.any() and not into.all() and np.abs(parts[:kk.AIR]).max() == 0.0


def test_submerged_hull_drag_matches_per_face_reference_in_any_pose():
    """Whole wet faces: viscous and pressure/suction (through the piece table and one np.power)."""
    hulls, verts, rng = _posed_sphere(-3.0, 6)
    com, v, omega = np.array([[2.0, -1.0, -3.0]]) + rng.normal(size=(1, 3)) * 0.1, rng.normal(size=(1, 3)), rng.normal(size=(1, 3))  # fmt: skip
    water = rng.normal(size=verts.shape) * 0.2
    cfg = KernerHydrodynamics(kinematic_viscosity_m2ps=1.0533e-6, pressure_falloff=0.4, suction_falloff=0.7,
                              suction_linear_pa=60.0, form_factor_k=0.1)
    k = KernerForces(hulls, [cfg], [80.0], [2.0])
    parts = k.compute(verts, np.zeros(len(verts)), water, com, v, omega, Z3, Z3, 0.01).parts[0]
    faces = hulls.faces.astype(int)
    r, n, area, vel = _face_kinematics(verts[faces], com[0], v[0], omega[0], water[faces].mean(axis=1))
    speed = np.linalg.norm(vel, axis=1)
    c_f = kk.friction_coefficient(np.linalg.norm(v[0]), 2.0, 1.0533e-6, 1e3) * 1.1
    vt = vel - np.einsum("ij,ij->i", vel, n)[:, None] * n
    visc = -0.5 * 1025.0 * c_f * (area * speed**2 / np.linalg.norm(vt, axis=1))[:, None] * vt
    cos = np.einsum("ij,ij->i", vel, n) / speed
    press = np.where(cos > 0, -(100 * speed + 100 * speed**2) * np.abs(cos) ** 0.4,
                     (60 * speed + 100 * speed**2) * np.abs(cos) ** 0.7)[:, None] * area[:, None] * n  # fmt: skip
    for kind, f in ((kk.VISCOUS, visc), (kk.PRESSURE, press)):
        np.testing.assert_allclose(parts[kind], np.concatenate([f.sum(0), np.cross(r, f).sum(0)]), rtol=1e-12, atol=1e-9)
    assert (cos > 0).any() and (cos < 0).any()


def test_slamming_is_time_step_independent_and_stops_the_share_of_momentum(tmp_path):
    """A 410 kg, 2 x 1 x 0.5 m box dropped flat from 1 m (bottom at z = 1 m), Kerner slamming only.

    Closed form: the flat bottom (A = 2 m² of S = 7 m²) wets in one step whatever the rate, so the slamming
    impulse is ramp · m v (2 A / S) with v = sqrt(2 g h) = 4.429 m/s and ramp = (v / v_slam)² (v_slam = 5 m/s):
    814 N s. It must be the same at 100, 200 and 400 Hz (within 3 %), as must the deepest immersion.
    """
    import trimesh

    from usvsim.config.loader import parse_scenario
    from usvsim.simulation import Simulation

    box = trimesh.creation.box(extents=(2.0, 1.0, 0.5))
    box.apply_translation((0.0, 0.0, 0.25))
    box.export(tmp_path / "box.stl")
    v = (2 * 9.81 * 1.0) ** 0.5
    expected = (v / 5.0) ** 2 * 410.0 * v * 2 * 2.0 / 7.0
    impulses, depths = [], []
    for rate in (100.0, 200.0, 400.0):
        vessel = {"name": "b", "model": "custom", "hull_mesh": "box.stl", "mass": {"mass_kg": 410.0,
                  "com": [0.0, 0.0, 0.2]}, "pose": {"position": [0.0, 0.0, 1.0]},
                  "hydrodynamics": {"type": "kerner", "viscous_scale": 0.0, "pressure_scale": 0.0, "air_scale": 0.0}}  # fmt: skip
        scenario = parse_scenario({"version": 1, "world": {"physics_rate_hz": rate}, "vessels": [vessel]}, "t", tmp_path)
        sim = Simulation(scenario)
        impulse, lowest = 0.0, np.inf
        for _ in range(int(rate)):
            sim.step()
            impulse += sim.world.marine._kerner._parts[0, kk.SLAMMING, 2] / rate
            lowest = min(lowest, sim.vessels["b"].position[2])
        impulses.append(impulse)
        depths.append(lowest)
        sim.close()
    assert impulses == pytest.approx([expected] * 3, rel=0.03)
    assert max(impulses) / min(impulses) < 1.03
    assert max(depths) - min(depths) < 0.01  # m; the deepest point is about 0.62 m below the surface


def test_reynolds_length_is_the_actual_waterline_length():
    """The friction's Reynolds length is the waterline's extent along the hull's x axis (not the overall
    length): checked against trimesh's section of the settled WAM-V hull by the still-water plane."""
    import trimesh

    from usvsim.config.loader import parse_scenario
    from usvsim.core.transforms import matrix_from_quat
    from usvsim.simulation import Simulation

    vessel = {"name": "w", "model": "wamv", "hydrodynamics": {"type": "kerner"}}
    sim = Simulation(parse_scenario({"version": 1, "vessels": [vessel]}, "t"))
    sim.run(5.0)
    body = sim.vessels["w"]
    rot = matrix_from_quat(body.quat)
    hull = trimesh.Trimesh(body.model.hull.vertices @ rot.T + body.position, body.model.hull.faces, process=False)
    section = trimesh.intersections.mesh_plane(hull, [0.0, 0.0, 1.0], [0.0, 0.0, 0.0]).reshape(-1, 3)
    waterline = np.ptp(section @ rot[:, 0])
    length = sim.world.marine._kerner.coef[0, kk.LENGTH]
    assert length == pytest.approx(waterline, abs=2e-3)  # m (the hull moves slightly in the lagged step)
    assert length < 0.95 * np.ptp(body.model.hull.vertices[:, 0])  # the overall length is not the waterline's
    sim.close()
