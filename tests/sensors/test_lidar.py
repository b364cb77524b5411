"""LiDAR: message conformance (REP 117, Nav2/slam_toolbox rules), geometry against a known box, water."""

from __future__ import annotations

import math

import numpy as np
import pytest
from sensor_rig import Collector, make_sim, sensor_configs

from usvsim.config.loader import parse_scenario
from usvsim.config.sensors import Lidar as LidarConfig
from usvsim.sensors import SensorSuite
from usvsim.sensors.lidar import patterns
from usvsim.sensors.messages import FLOAT32, UINT16, points_from_cloud
from usvsim.simulation import Simulation

BOX = {"type": "box", "name": "crate", "position": [9.0, 1.0, 0.5], "size": [2.0, 4.0, 3.0], "yaw_deg": 30.0}
MOUNT = {"position": [0.7, 0.0, 1.2]}


def _suite(*sensors, objects=(BOX,)):
    sim = make_sim(objects=objects)
    suite = SensorSuite(sim.world, {"wamv": sensor_configs(*sensors)})
    sim.step()
    return sim, suite


def _world_points(sim, sensor, msg):
    pts = points_from_cloud(msg).reshape(-1)
    xyz = np.stack([pts["x"], pts["y"], pts["z"]], axis=1).astype(float)
    pos, rot = sensor.pose_world(sim)
    return xyz @ rot.T + pos, pts


def _box_distance(points_world):
    """Unsigned distance (m) of world points to the surface of BOX."""
    c, half, yaw = np.array(BOX["position"]), np.array(BOX["size"]) / 2, math.radians(BOX["yaw_deg"])
    rot = np.array([[math.cos(yaw), -math.sin(yaw), 0], [math.sin(yaw), math.cos(yaw), 0], [0, 0, 1]])
    local = np.abs((points_world - c) @ rot)
    outside = np.linalg.norm(np.maximum(local - half, 0.0), axis=1)
    return np.where((local <= half).all(axis=1), (half - local).min(axis=1), outside)


@pytest.mark.parametrize("stddev", [0.0, 0.01])
def test_points_on_a_known_box_lie_on_its_faces(stddev):
    sim, suite = _suite({"type": "lidar", "name": "lidar", "preset": "vlp16", "range_stddev_m": stddev, "mount": MOUNT})
    lidar = suite["wamv/lidar"]
    msg = lidar.sample(sim, sim.clock_ns)[0].msg
    world, pts = _world_points(sim, lidar, msg)
    near = np.linalg.norm(world[:, :2] - np.array(BOX["position"][:2]), axis=1) < 4.0
    assert near.sum() > 100
    d = _box_distance(world[near])
    assert d.max() < 1e-3 + 4.5 * stddev  # float32 coordinates; 4.5 sigma over a few hundred points
    assert world[:, 2].min() > -1e-3 or stddev > 0  # nothing from below the water surface
    assert pts["intensity"][near].min() > 0 and pts["intensity"].max() <= 1.0


def test_pointcloud2_layout_float32_ring_time_and_organized():
    sim, suite = _suite({"type": "lidar", "name": "a", "preset": "os1_64", "columns": 512, "mount": MOUNT},
                        {"type": "lidar", "name": "b", "preset": "os1_64", "columns": 512, "organized": True,
                         "mount": MOUNT})  # fmt: skip
    flat = suite["wamv/a"].sample(sim, 10)[0].msg
    org = suite["wamv/b"].sample(sim, 10)[0].msg
    fields = {f.name: (f.offset, f.datatype, f.count) for f in flat.fields}
    assert fields == {"x": (0, FLOAT32, 1), "y": (4, FLOAT32, 1), "z": (8, FLOAT32, 1), "intensity": (12, FLOAT32, 1),
                      "ring": (16, UINT16, 1), "time": (20, FLOAT32, 1)}  # fmt: skip
    assert flat.height == 1 and flat.is_dense and flat.row_step == flat.point_step * flat.width
    assert (org.height, org.width) == (64, 512) and not org.is_dense
    grid = points_from_cloud(org)
    assert np.isnan(grid["x"]).any() and np.all(grid["ring"] == np.arange(64)[:, None])
    assert np.isfinite(grid["x"]).sum() == flat.width
    assert not flat.is_bigendian and len(flat.data) == flat.width * flat.point_step


def test_laser_scan_has_n_ranges_and_inf_for_no_return():
    sim, suite = _suite({"type": "lidar", "name": "scan", "preset": "seed_2d", "rate_hz": 5, "mount": MOUNT})
    scan = suite["wamv/scan"].sample(sim, 10)[0].msg
    n = 8000
    assert len(scan.ranges) == n == len(scan.intensities)
    assert scan.angle_max == pytest.approx(scan.angle_min + (n - 1) * scan.angle_increment, abs=1e-6)
    assert scan.angle_increment == pytest.approx(2 * math.pi / n) and scan.angle_min == pytest.approx(-math.pi)
    ranges = np.asarray(scan.ranges)
    assert np.isposinf(ranges).sum() > 0.5 * n and not np.isnan(ranges).any()
    finite = ranges[np.isfinite(ranges)]
    assert finite.min() >= scan.range_min and finite.max() <= scan.range_max
    assert scan.scan_time == pytest.approx(0.2)


def test_partial_fov_scan_edges():
    cfg = LidarConfig(type="lidar", name="s", preset="custom", output="scan", channels=1, columns=256,
                      horizontal_fov_deg=120.0, vertical_fov_deg=(0.0, 0.0))  # fmt: skip
    az, inc = patterns.azimuths(patterns.resolve(cfg))
    assert len(az) == 256 and az[0] == pytest.approx(-math.radians(60)) and az[-1] == pytest.approx(math.radians(60))


def test_presets():
    cases = {"vlp16": (16, 1800), "os1_64": (64, 2048), "os1_128": (128, 2048), "vrx": (16, 1875), "seed_3d": (16, 500)}
    for preset, (ch, cols) in cases.items():
        p = patterns.resolve(LidarConfig(type="lidar", name="l", preset=preset))
        assert (len(p.elevations_deg), p.columns) == (ch, cols)
    seed = patterns.resolve(LidarConfig(type="lidar", name="l", preset="seed_3d"))
    assert seed.elevations_deg[0] == -39.375 and seed.elevations_deg[-1] == 45.0


def test_water_gives_no_returns_by_default_and_some_with_the_option():
    down = {"position": [0.7, 0.0, 1.2], "pitch_deg": 30.0}  # pitched down: the front half looks at the sea
    lidar = {"type": "lidar", "preset": "vlp16", "columns": 360, "range_stddev_m": 0.0, "mount": down}
    sim, suite = _suite({**lidar, "name": "dry"}, {**lidar, "name": "wet", "water_returns": True}, objects=())
    dry, wet = (suite[f"wamv/{n}"] for n in ("dry", "wet"))
    world_dry, _ = _world_points(sim, dry, dry.sample(sim, 10)[0].msg)
    assert (world_dry[:, 2] > 0.05).all()  # only the boat itself, nothing at the water
    world_wet, pts = _world_points(sim, wet, wet.sample(sim, 10)[0].msg)
    water = np.abs(world_wet[:, 2]) < 1e-3
    assert water.sum() > 100
    assert 0 < pts["intensity"][water].min() and pts["intensity"][water].max() <= 0.02 + 1e-6  # ρ_water·cosθ


def test_water_returns_on_waves_lie_on_the_surface_also_at_grazing_incidence():
    """Each water return is where its beam first meets the wave surface (the same `elevation` the hydrostatics
    use): within 1 mm of it, also for near-grazing beams far out (a fixed-point iteration left those up to 1.3 m
    off in sea state 4)."""
    data = {"version": 1, "world": {"physics_rate_hz": 100}, "environment": {"sea": {"type": "sea_state", "code": 4}},
            "vessels": [{"name": "wamv", "model": "wamv", "sensors": [
                {"type": "lidar", "name": "lidar", "preset": "os1_64", "columns": 1024, "self_returns": False,
                 "range_stddev_m": 0.0, "water_returns": True, "mount": {"position": [0.7, 0.0, 1.6]}}]}]}
    sim = Simulation(parse_scenario(data, "test"), seed=0)
    sim.run(3.0)
    lidar = sim.sensors["wamv/lidar"]
    world, pts = _world_points(sim.world, lidar, lidar.sample(sim.world, sim.clock_ns)[0].msg)
    gap = world[:, 2] - sim.ocean.elevation(world[:, 0], world[:, 1], sim.time)
    far = np.linalg.norm(world[:, :2] - world[:, :2].mean(axis=0), axis=1) > 20.0
    assert len(gap) > 1000 and far.sum() > 20  # returns near the boat and near-grazing ones far out
    assert np.abs(gap).max() < 1e-3


def test_dropout_and_noise_statistics():
    sim, suite = _suite({"type": "lidar", "name": "a", "preset": "vlp16", "mount": MOUNT},
                        {"type": "lidar", "name": "b", "preset": "vlp16", "dropout": 0.3, "mount": MOUNT})  # fmt: skip
    full = suite["wamv/a"].sample(sim, 10)[0].msg.width
    dropped = suite["wamv/b"].sample(sim, 10)[0].msg.width
    assert dropped / full == pytest.approx(0.7, abs=0.05)


def test_rate_and_motion_distortion_timing():
    sim = make_sim(objects=(BOX,))
    cfgs = sensor_configs({"type": "lidar", "name": "l", "preset": "vlp16", "columns": 360, "rate_hz": 10,
                           "motion_distortion": True, "mount": MOUNT})  # fmt: skip
    suite = SensorSuite(sim.world, {"wamv": cfgs})
    col = Collector(sim, suite).run(2.0)
    got = col.by_topic["/wamv/l/points"]
    assert len(got) == 20
    now, env = got[-1]
    assert env.stamp_ns == now - round(0.1 * 359 / 360 * 1e9)  # header = first column's firing time
    t = points_from_cloud(env.msg)["time"]
    assert t.min() >= 0.0 and t.max() == pytest.approx(0.1 * 359 / 360, abs=1e-6)


def test_distortion_moves_points_of_a_turning_boat():
    """A yawing boat: with distortion the early columns were cast from an earlier heading."""
    sim = make_sim(objects=(BOX,))
    base = {"type": "lidar", "name": "a", "preset": "vlp16", "columns": 720, "organized": True, "range_stddev_m": 0.0,
            "mount": MOUNT}  # fmt: skip
    suite = SensorSuite(sim.world, {"wamv": sensor_configs(base, {**base, "name": "b", "motion_distortion": True})})

    def turn(sim):
        for t in sim.vessels["wamv"].thrusters.values():
            t.command(0.9 if "right" in t.name else -0.9)

    sim.run(4.0, on_step=turn)
    assert abs(sim.vessels["wamv"].angular_velocity_body[2]) > 0.05
    a = points_from_cloud(suite["wamv/a"].sample(sim, 10)[0].msg)
    b = points_from_cloud(suite["wamv/b"].sample(sim, 10)[0].msg)
    both = np.isfinite(a["x"]) & np.isfinite(b["x"])
    assert both.sum() > 50
    assert not np.allclose(a["x"][both], b["x"][both], atol=1e-3)


def _world_posed_scene(sim, group=1):
    """Reference: every geom's triangles posed in the world from MuJoCo's own kinematics (float64), one scene."""
    import mujoco
    from embreex import rtcore_scene as rtcs
    from embreex.mesh_construction import TriangleMesh

    from usvsim.sensors.lidar.scene import geom_triangles

    m, d = sim.model, mujoco.MjData(sim.model)
    d.qpos[:] = sim.data.qpos
    mujoco.mj_kinematics(m, d)
    tris, ids = [], []
    for g in np.flatnonzero(m.geom_group == group):
        local = geom_triangles(m, g)
        if local is not None and len(local):
            tris.append(local @ d.geom_xmat[g].reshape(3, 3).T + d.geom_xpos[g])
            ids.append(np.full(len(local), g, np.int32))
    scene = rtcs.EmbreeScene()
    TriangleMesh(scene, np.concatenate(tris).astype(np.float32))
    return scene, np.concatenate(ids)


def _rays_at_bodies(sim, world, rng, per_body=3000):
    """Rays from 4-10 m away aimed at random points inside each moving body's bounding sphere (world)."""
    pos, rot = world.poses()
    origins, dirs = [], []
    for b, body in enumerate(world.bodies):
        center = pos[b] + rot[b] @ body.center_body_m
        target = center + body.radius_m * rng.uniform(-1, 1, (per_body, 3))
        away = rng.normal(size=(per_body, 3)) * [1, 1, 0.3]
        start = center + away / np.linalg.norm(away, axis=1, keepdims=True) * rng.uniform(4, 10, (per_body, 1))
        origins.append(start)
        dirs.append((target - start) / np.linalg.norm(target - start, axis=1, keepdims=True))
    return np.concatenate(origins).astype(np.float32), np.concatenate(dirs).astype(np.float32)


def test_body_frame_casting_matches_world_posed_geometry():
    """Bodies are cast in their own frames against scenes built once; the result must equal casting against
    the geometry posed in the world at the current state (moving, rotated boats and buoys of the harbour)."""
    from usvsim import Simulation
    from usvsim.sensors.lidar.raycast import RayWorld

    sim = Simulation.from_scenario("harbor")
    cfg = {"type": "lidar", "name": "l", "preset": "os1_64", "columns": 1024, "range_stddev_m": 0.0}
    suite = SensorSuite(sim.world, {"wamv": sensor_configs({**cfg, "mount": {"position": [0.7, 0.0, 1.03], "roll_deg": 3}})})
    lidar = suite["wamv/l"]

    def turn(sim):
        for t in sim.vessels["wamv"].thrusters.values():
            t.command(0.8 if "right" in t.name else -0.4)

    sim.run(3.0, on_step=turn)
    _, rot = lidar.world.poses()
    assert abs(sim.vessels["wamv"].angular_velocity_body[2]) > 0.05 and abs(rot[0][0, 1]) > 0.05  # turned
    scene, prim_geom = _world_posed_scene(sim)
    lidar_o, lidar_d, _, _ = lidar._rays(sim)
    rng = np.random.default_rng(1)
    body_o, body_d = _rays_at_bodies(sim, lidar.world, rng)
    pos, _ = lidar.world.poses()
    # one origin between the Otter and the WAM-V, all directions; then the same origin jittered by 5 cm
    sphere_d = rng.normal(size=(200_000, 3)).astype(np.float32)
    sphere_d /= np.linalg.norm(sphere_d, axis=1, keepdims=True)
    sphere_d = sphere_d[np.argsort(sphere_d[:, 2])]  # chunks are bands of elevation, as in a LiDAR
    sphere_o = np.broadcast_to((0.5 * (pos[0] + pos[1]) + [0, 0, 1.5]).astype(np.float32), sphere_d.shape)
    jitter_o = sphere_o + rng.uniform(-0.05, 0.05, sphere_d.shape).astype(np.float32)
    world_cast = lambda o, d: lidar.world.cast(o, d, 120.0)  # noqa: E731
    cases = ((lidar_o, lidar_d, lidar._cast, 2),  # own-vessel hits cached in its frame; the Otter
             (body_o, body_d, world_cast, len(lidar.world.bodies)),  # every moving body hit
             (sphere_o, sphere_d, world_cast, 2), (jitter_o, sphere_d, world_cast, 2))  # fmt: skip
    for origins, dirs, cast, bodies_hit in cases:
        origins = np.ascontiguousarray(origins)
        dist, geom, cos_inc = cast(origins.copy(), dirs.copy())
        ref = scene.run(origins, dirs, dists=np.full(len(dirs), 120.0, np.float32), output=1)
        ref_geom = np.where(ref["geomID"] == -1, -1, prim_geom[ref["primID"]])
        both = (geom == ref_geom) & (geom != -1)
        assert both.sum() > 1000 and (geom == ref_geom).mean() > 0.999  # edge grazes may differ
        err_m, cos_both = np.abs(dist[both] - ref["tfar"][both]), cos_inc[both]
        # float32 round-off (the reference's world coordinates reach 25 m): ranges within 1e-5 m unless the ray
        # grazes the surface; then the hit slides along the ray, but stays within 10 µm of the surface
        assert err_m[cos_both > 0.3].max() < 1e-5 and (err_m * cos_both).max() < 1e-5
        assert len(set(sim.model.geom_bodyid[geom[both]]) - {0}) >= bodies_hit
    one_thread = RayWorld(sim, 1, threads=1)  # one chunk: no chunk-level culling; same hits
    for got, want in zip(one_thread.cast(jitter_o, sphere_d, 120.0), lidar.world.cast(jitter_o, sphere_d, 120.0)):
        np.testing.assert_array_equal(got, want)


def test_reflectivity_of_a_body_that_is_not_there_is_an_error(scenario_of):
    """`reflectivity: {bouy_1: 0.9}` was ignored without a word (QA); a known body's value is used."""
    from usvsim.core.errors import ScenarioError
    from usvsim.simulation import Simulation
    from usvsim.world.builder import geom_owners

    def lidar(reflectivity):
        return scenario_of({"vessels": [{"name": "wamv", "model": "wamv", "sensors": [
            {"type": "lidar", "name": "lidar", "preset": "vlp16", "reflectivity": reflectivity}]}],
            "objects": [{"type": "buoy", "name": "buoy_1", "position": [10, 0, 0]}]})  # fmt: skip

    with pytest.raises(ScenarioError) as info:
        Simulation(lidar({"buoy_1": 0.5, "bouy_1": 0.9}))
    assert info.value.key_path == "vessels[0].sensors[0].reflectivity.bouy_1"
    assert "no body named 'bouy_1'" in info.value.message and "buoy_1" in info.value.message
    sim = Simulation(lidar({"buoy_1": 0.5, "world": 0.75}))
    owners = geom_owners(sim.model)
    refl = sim.sensors["wamv/lidar"].reflectivity
    assert {float(refl[g]) for g, o in enumerate(owners) if o == "buoy_1"} == {0.5}
    assert {float(refl[g]) for g, o in enumerate(owners) if o == "world"} == {0.75}
    sim.close()


def test_a_clockwise_spin_fires_the_same_beams_in_the_opposite_order():
    """`spin: clockwise` (Velodyne, Ouster): columns fire from the highest azimuth to the lowest. On a still boat the
    same beams hit the same points; a point's time is the column's firing time, so for a full sweep of N columns
    t_cw(azimuth) + t_ccw(azimuth) = (N - 1)·Δt, and time falls as the azimuth rises (LOAM's assumption)."""
    base = {"type": "lidar", "preset": "vlp16", "columns": 360, "rate_hz": 10, "range_stddev_m": 0.0,
            "organized": True, "motion_distortion": True, "mount": MOUNT}  # fmt: skip
    sim, suite = _suite({**base, "name": "ccw"}, {**base, "name": "cw", "spin": "clockwise"})
    clouds = {}
    for name in ("ccw", "cw"):
        pts = points_from_cloud(suite[f"wamv/{name}"].sample(sim, 10)[0].msg)
        pts = pts.ravel()[np.isfinite(pts["x"].ravel())]
        column = np.round((np.arctan2(pts["y"], pts["x"]) + math.pi) / (2 * math.pi / 360)).astype(int) % 360
        clouds[name] = {(r, c): (x, y, z, t) for r, c, x, y, z, t in zip(pts["ring"], column, pts["x"], pts["y"],
                                                                          pts["z"], pts["time"])}  # fmt: skip
    assert len(clouds["cw"]) == len(clouds["ccw"]) > 500 and clouds["cw"].keys() == clouds["ccw"].keys()
    for key, (x, y, z, t) in clouds["ccw"].items():
        cx, cy, cz, ct = clouds["cw"][key]
        assert (cx, cy, cz) == pytest.approx((x, y, z), abs=2e-3)  # the boat barely moves within a sweep
        assert ct + t == pytest.approx(0.1 * 359 / 360, abs=1e-6)
    cfg = LidarConfig(type="lidar", name="s", preset="seed_2d", spin="clockwise")
    az, inc = patterns.azimuths(patterns.resolve(cfg))
    assert inc == pytest.approx(-2 * math.pi / 8000) and az[0] == pytest.approx(math.pi - 2 * math.pi / 8000)
