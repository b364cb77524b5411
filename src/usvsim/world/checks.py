"""Set-ups that build but cannot work: warnings that `usvsim validate` prints (docs/limits.md).

- a floating body heavier than the water its closed hull (or, with voxel buoyancy, its voxels) can displace (it
  sinks whatever happens);
- a floating body whose hull is entirely above or below the still water level by more than 1 m;
- a vessel whose centre of mass lies outside its hull's bounding box (a `mass.com` typo: it floats tilted or capsizes),
  or a thruster more than 1 m outside it (outboard motors stick out less: the WAM-V's by 0.45 m);
- a sea steeper than real seas get (they break): 2π Hs / (g Tp²) above DNV-RP-C205's limit (1/15 up to Tp = 8 s, 1/25
  from 15 s, linear between), or a regular component with H / λ above the breaking limit 1/7;
- a water depth that the sea does not use (FFT seas are deep-water);
- bodies that overlap at t = 0 (MuJoCo contacts deeper than 1 cm: they are pushed apart violently), traffic ships
  (kinematic bodies) named as themselves, not as the static world;
- a camera or LiDAR mounted inside its own vessel's geometry (it sees only the hull);
- a traffic route's waypoints after a stop (speed 0) that are never reached, or a loop that the stop ends;
- Fossen hydrodynamics with no damping at all (`parameters: custom` and its zero defaults);
- in a real place (`geo:` with land): a vessel, floating object or traffic ship that starts on land, and a traffic
  route leg (one that is sailed: up to the first waypoint at speed 0) that crosses land, with the point
  (`land_warnings`).

Frames: world ENU, metres; heights relative to the still water level.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np
import shapely

from usvsim.config.loader import base_dir, source_of
from usvsim.config.traffic import Route
from usvsim.geo.resolve import frame_of
from usvsim.ocean.fft import FFTWaveField
from usvsim.ocean.presets import hs_tp
from usvsim.traffic.kernels import TrackTable
from usvsim.traffic.motion import make_track
from usvsim.world.builder import kinematic_geoms

THRUSTER_REACH_M = 1.0  # how far outside the hull's bounding box a thruster may sit before a warning
CLEARANCE_M = 1.0  # how far above or below the water a whole hull may start before a warning
OVERLAP_M = 0.01  # contact penetration at t = 0 that counts as an overlap
G = 9.81  # m/s², for wavelengths from periods (deep water)


def hull_volume_m3(vertices: np.ndarray, faces: np.ndarray) -> float:
    """Enclosed volume of a closed triangle mesh (divergence theorem; outward winding)."""
    a, b, c = (vertices[faces[:, k]] for k in range(3))
    return abs(float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum()) / 6.0)


def setup_warnings(world) -> list[str]:
    """Warnings for a `World`'s initial state (bodies, hulls, water level, contacts)."""
    env = world.scenario.environment
    start = _start_data(world)
    return [*_displacement(world), *_com_outside(world), *_far_from_water(world), *_sea(env), *_tiles(env, world.ocean.waves),
            *_overlaps(world, start), *_sensors_inside(world, start), *_route_stops(world.scenario), *land_warnings(world),
            *_undamped(world.scenario)]  # fmt: skip


def _undamped(scenario) -> list[str]:
    """Vessels with Fossen hydrodynamics of `parameters: custom` and no damping coefficient at all (the defaults):
    nothing but the wind slows them (QA: a WAM-V at full thrust reached 37 m/s in 20 s, then spun out)."""
    out = []
    for v in scenario.vessels:
        h = v.hydrodynamics
        if getattr(h, "type", None) == "fossen" and h.parameters == "custom" and not any(h.linear_damping) \
                and not any(h.quadratic_damping) and not h.cross_flow_length_m:  # fmt: skip
            out.append(f"'{v.name}' has Fossen hydrodynamics with no damping (parameters: custom, every damping "
                       "coefficient 0): nothing slows it; choose parameters (otter, wamv_vrx) or give the damping")
    return out


def _route_stops(scenario) -> list[str]:
    """Traffic routes with waypoints after a stop (a waypoint of speed 0, where the ship stays for good) that are
    never reached: the next one of a route stopped at its start gives its heading; any others are lost."""
    out = []
    for k, ship in enumerate(scenario.traffic.ships):
        if not isinstance(ship.motion, Route):
            continue
        points = ship.motion.waypoints
        stop = next((i for i, w in enumerate(points[:-1]) if w.speed_mps <= 0.0), None)
        if stop is None and ship.motion.loop and points[-1].speed_mps <= 0.0:
            stop = len(points) - 1
        if stop is None:
            continue
        lost = list(range(stop + 2 if stop == 0 else stop + 1, len(points)))
        what = [f"waypoint{'s' if len(lost) > 1 else ''} {', '.join(map(str, lost))} never reached"] if lost else []
        what += ["no loop"] if ship.motion.loop else []
        if what:
            x, y = points[stop].position
            out.append(f"traffic.ships[{k}] '{ship.name}': waypoint {stop} ({x:g}, {y:g}) has speed_mps 0, where the "
                       f"ship stops for good: {' and '.join(what)}")  # fmt: skip
    return out


def land_warnings(world) -> list[str]:
    """A real place's land under a floating body's or a traffic ship's start, or across a route leg a traffic ship
    sails (world ENU points, with their latitude and longitude). Empty without land."""
    place = getattr(world, "place", None)
    polygons = list(place.land_polygons) if place is not None else []
    if not polygons:
        return []
    land = shapely.union_all(polygons)
    origin = world.scenario.world.origin
    frame = frame_of(world.scenario) if origin is not None else None  # the scenario's own, made once

    def where(x: float, y: float) -> str:
        text = f"({x:.1f}, {y:.1f}) m"
        if frame is not None:
            lat, lon, _ = frame.to_geodetic(x, y)[0]
            text += f" (lat {lat:.6f}, lon {lon:.6f})"
        return text

    out = []
    for body in world.bodies.values():
        x, y = world.state.pos[body.index, :2]
        if shapely.contains_xy(land, x, y):
            out.append(f"'{body.name}' starts on land at {where(x, y)}")
    ships = world.scenario.traffic.ships
    kinematic = [k for k, s in enumerate(ships) if s.vessel is None]  # physics ships are bodies (above)
    if kinematic:
        source, base = source_of(world.scenario), base_dir(world.scenario)
        tracks = [make_track(ships[k].motion, origin, base, source, f"traffic.ships[{k}].motion") for k in kinematic]
        pos, vel, yaw = np.zeros((len(tracks), 2)), np.zeros((len(tracks), 2)), np.zeros(len(tracks))
        TrackTable.of(tracks).evaluate(0.0, pos, vel, yaw)
        for k, (x, y) in zip(kinematic, pos):
            if shapely.contains_xy(land, x, y):
                out.append(f"traffic.ships[{k}] '{ships[k].name}' starts on land at {where(x, y)}")
    for k, ship in enumerate(ships):
        if not isinstance(ship.motion, Route):
            continue
        points = [w.position for w in ship.motion.waypoints]
        speeds = [w.speed_mps for w in ship.motion.waypoints]
        legs = list(range(len(points) - 1)) + ([len(points) - 1] if ship.motion.loop else [])
        for i in legs:
            if speeds[i] <= 0.0:
                break  # it stops there for good
            j = (i + 1) % len(points)
            line = shapely.LineString([points[i], points[j]])
            if line.length == 0.0 or not line.intersects(land):
                continue
            entry = min(line.project(shapely.Point(p)) for p in shapely.get_coordinates(line.intersection(land)))
            x, y = line.interpolate(entry).coords[0]
            (ax, ay), (bx, by) = points[i], points[j]
            out.append(f"traffic.ships[{k}] '{ship.name}': its route leg from waypoint {i} ({ax:g}, {ay:g}) to {j} "
                       f"({bx:g}, {by:g}) crosses land at {where(x, y)}")  # fmt: skip
    return out


def _displacement(sim) -> list[str]:
    out = []
    voxels = sim.marine.voxel_capacity_m3(sim.state)
    for body in sim.bodies.values():
        hull = body.model.hull
        if body.index in voxels:
            capacity, what = sim.rho * voxels[body.index], "its voxels"
            hint = f" (voxel_size_m {sim.marine.buoyancy[body.index].voxel_size_m:g}: use smaller voxels)"
        else:
            capacity, what, hint = sim.rho * hull_volume_m3(hull.vertices, hull.faces), "its closed hull", ""
        if body.model.mass_kg > capacity:
            out.append(f"'{body.name}' ({body.model.mass_kg:.6g} kg) is heavier than the water {what} can "
                       f"displace ({capacity:.6g} kg): it will sink{hint}")  # fmt: skip
    return out


def _com_outside(sim) -> list[str]:
    """Vessels whose centre of mass (base_link) is outside their hull's bounding box, or with a thruster more than
    THRUSTER_REACH_M outside it: `mass.com: [50, 0, 0.3]` or a thruster at x = 50 m on a 4 m hull validated without a
    word (QA)."""
    out = []
    for i, vessel in enumerate(sim.scenario.vessels):
        body = sim.bodies.get(vessel.name)
        if body is None:
            continue
        low, high, com = body.model.hull.vertices.min(0), body.model.hull.vertices.max(0), body.model.com
        box = box_of(low, high)
        if np.any(com < low - 1e-6) or np.any(com > high + 1e-6):
            out.append(f"vessels[{i}].mass.com: '{vessel.name}' has its centre of mass at [{', '.join(f'{c:.3g}' for c in com)}] "
                       f"m (base_link, FLU), outside its hull ({box} m): it will float tilted or capsize")  # fmt: skip
        for k, thruster in enumerate(vessel.thrusters or ()):
            p = np.asarray(thruster.position)
            if np.any(p < low - THRUSTER_REACH_M) or np.any(p > high + THRUSTER_REACH_M):
                out.append(f"vessels[{i}].thrusters[{k}].position: '{vessel.name}' thruster '{thruster.name}' at "
                           f"[{', '.join(f'{c:.3g}' for c in p)}] m (base_link, FLU) is more than {THRUSTER_REACH_M:g} m "
                           f"outside its hull ({box} m): its moments will be far from the real ones")  # fmt: skip
    return out


def box_of(low, high) -> str:
    return ", ".join(f"{a} {lo:.3g}..{hi:.3g}" for a, lo, hi in zip("xyz", low, high))


def _steepness_limit(tp_s: float) -> float:
    """DNV-RP-C205: the largest significant steepness 2π Hs / (g Tp²) of real seas at peak period Tp."""
    return 1 / 15 + (1 / 25 - 1 / 15) * min(max((tp_s - 8.0) / 7.0, 0.0), 1.0)


def _tiles(env, waves) -> list[str]:
    """An FFT cascade whose tiles hold less than 90 % of the sea's Hs (tile_sizes_m far from the sea's waves)."""
    hs = hs_tp(env.sea)[0]
    if hs is None or not isinstance(waves, FFTWaveField):
        return []
    held = 4.0 * math.sqrt(waves.held_variance())
    if held >= 0.9 * hs:
        return []
    given = getattr(env.sea.realization, "tile_sizes_m", None) is not None
    fix = "leave tile_sizes_m out for tiles fitted to the sea" if given else "use more bands or a higher resolution"
    return [f"environment.sea.realization: the FFT tiles ({', '.join(f'{s:.3g}' for s in waves.sizes)} m) hold Hs "
            f"{held:.3g} m of the sea's {hs:g} m: its waves are longer than the largest tile or shorter than the "
            f"smallest tile's cells ({fix})"]  # fmt: skip


def _sea(env) -> list[str]:
    sea, out = env.sea, []
    hs, tp = hs_tp(sea)
    if hs is not None and tp is not None:
        steep = 2 * math.pi * hs / (G * tp * tp)
        if steep > _steepness_limit(tp):
            out.append(f"environment.sea: Hs {hs:g} m at Tp {tp:g} s is a steepness 2π Hs/(g Tp²) of {steep:.3g}, beyond "
                       f"the {_steepness_limit(tp):.3g} real seas reach (DNV-RP-C205): waves this steep break")  # fmt: skip
    for i, c in enumerate(getattr(sea, "components", ())):
        length = c.wavelength_m if c.wavelength_m is not None else G * c.period_s**2 / (2 * math.pi)
        if 2 * c.amplitude_m / length > 1 / 7:
            out.append(f"environment.sea.components[{i}]: a wave {2 * c.amplitude_m:g} m high and {length:.3g} m long "
                       f"(H/λ {2 * c.amplitude_m / length:.2f}) is beyond the breaking limit 1/7")  # fmt: skip
    realization = getattr(sea, "realization", None)
    if env.water_depth_m is not None and getattr(realization, "method", None) == "fft":
        out.append(f"environment.water_depth_m {env.water_depth_m:g} m: FFT seas are deep-water; only "
                   "realization: {method: direct} uses the depth")  # fmt: skip
    return out


def _far_from_water(sim) -> list[str]:
    s, level = sim.state, sim.scenario.environment.water_level_m
    verts = sim.hulls.world_vertices(s.pos, s.rot)
    out = []
    for i, name in enumerate(sim.bodies):
        z = verts[sim.hulls.vert_offsets[i] : sim.hulls.vert_offsets[i + 1], 2] - level
        if z.min() > CLEARANCE_M:
            out.append(f"'{name}' starts {z.min():.3g} m above the water (its lowest hull point): it will fall")
        elif z.max() < -CLEARANCE_M:
            out.append(f"'{name}' starts {-z.max():.3g} m below the water (its highest hull point): it will shoot up")
    return out


def _start_data(sim) -> mujoco.MjData:
    """A copy of the world's MuJoCo data at its start pose, forwarded (contacts, geom poses) for the checks."""
    data = mujoco.MjData(sim.model)
    data.qpos[:] = sim.data.qpos
    mujoco.mj_forward(sim.model, data)
    return data


def _overlaps(sim, data: mujoco.MjData) -> list[str]:
    labels = _geom_labels(sim.model)
    pairs = set()
    for contact in data.contact[: data.ncon]:
        if contact.dist < -OVERLAP_M:
            pairs.add(tuple(sorted(labels[g] for g in contact.geom)))
    return [f"{a[1]} and {b[1]} overlap at the start: they will be pushed apart" for a, b in sorted(pairs)]


def _sensors_inside(sim, data: mujoco.MjData) -> list[str]:
    """Cameras and LiDARs mounted inside their own vessel's geometry: the rays along ±x, ±y, ±z (world) from the mount
    all hit that vessel (MuJoCo's ray cast over every geom group); such a sensor sees only the inside of its hull."""
    model = sim.model
    out, s, geom = [], sim.state, np.zeros(1, dtype=np.int32)
    for cfg in sim.scenario.vessels:
        i = sim.vessels[cfg.name].index
        root = model.body_rootid[sim._body_ids[i]]
        for sensor in cfg.sensors:
            if sensor.type not in ("camera", "lidar"):
                continue
            point = s.pos[i] + s.rot[i] @ np.asarray(sensor.mount.position, dtype=float)
            far = 0.0
            for direction in np.vstack([np.eye(3), -np.eye(3)]):
                dist = mujoco.mj_ray(model, data, point, direction, None, 1, -1, geom)
                if dist < 0 or model.body_rootid[model.geom_bodyid[geom[0]]] != root:
                    break
                far = max(far, dist)
            else:
                out.append(f"'{cfg.name}' {sensor.type} '{sensor.name}' is mounted inside the vessel's own geometry (every "
                           f"ray from its mount hits the vessel within {far:.2g} m): it sees only the hull; move its mount")  # fmt: skip
    return out


def _geom_labels(model: mujoco.MjModel) -> list[tuple[int, str]]:
    """Per geom, what it belongs to as (sort key, words): the static world (its geoms that stay put), a floating
    body, or a kinematic body (e.g. a traffic ship: world-body geoms that move along a track, see
    `world.builder.KinematicBody`)."""
    out = [(0, "the static world") if b == 0 else (1 + b, f"'{model.body(b).name}'") for b in model.geom_bodyid]
    names, geoms, owner = kinematic_geoms(model)
    for g, k in zip(geoms, owner):
        out[g] = (1 + model.nbody + k, f"the moving '{names[k]}'")
    return out
