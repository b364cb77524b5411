"""The World: the one owner of simulation state. Clock, random streams, MuJoCo model and data, body
kinematics, the ocean (waves, wind, current), hull sets, marine models and thrusters live here.

Sensors, controllers, ground truth and the vessel/thruster handles take a `World` (a narrow view, as
dm_control's tasks take `Physics`), never the loop (`usvsim.simulation.Simulation`, which orders the step,
applies commands and feeds subscribers). One physics step of the world (`step_physics`): ocean advanced →
hull vertices → water heights (direct or patch) → hydrostatics (one batched kernel) → relative velocities
→ each body's buoyancy and hydrodynamics models + wind (hydro/models.py) → thruster dynamics → wrenches
into MuJoCo (`xfrc_applied`, world frame, about each CoM) → `mj_step` (divergence check) → clock tick →
body kinematics.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import mujoco
import numpy as np

from usvsim.config.loader import base_dir, source_of
from usvsim.config.objects import Buoy
from usvsim.config.scenario import Scenario
from usvsim.config.vessel import TriangleBuoyancy, VoxelBuoyancy
from usvsim.core.clock import Clock, period_ns
from usvsim.core.errors import (
    DivergenceError,
    InputError,
    Names,
    ScenarioError,
    UnknownNameError,
    UsvsimError,
)
from usvsim.core.overlap import Overlap
from usvsim.core.rng import RngStreams
from usvsim.core.transforms import cross3, matrix_from_quat, quat_from_rpy
from usvsim.geo.parts import GeoParts, geo_parts, set_clip_planes
from usvsim.geo.resolve import load_place, resolve_geo, with_local_depth
from usvsim.hydro.flat import use_flat
from usvsim.hydro.fused import fused_hydrostatics
from usvsim.hydro.hydrostatics import NO_HEAD, HullSet, HydrostaticsResult
from usvsim.hydro.models import MarineModels
from usvsim.hydro.thrusters import ThrusterBank
from usvsim.hydro.voxelize import check_grid
from usvsim.hydro.wrenches import assemble, body_kinematics, relative_velocity_body
from usvsim.ocean import build_ocean
from usvsim.ocean.patch import WaterPatch
from usvsim.ocean.pressure import hull_water, surface_and_dynamic_head
from usvsim.vessel import Body, Thruster, Vessel
from usvsim.vessels import buoy
from usvsim.vessels.library import vessel_model
from usvsim.world.builder import FloatingBody, KinematicBody, build_model, geom_owners
from usvsim.world.divergence import DivergenceGuard
from usvsim.world.obstacles import static_parts
from usvsim.world.poses import PoseLike, pose_arrays, twist_array
from usvsim.world.state import BodyState

FLAT_MAX_FACES = 30_000  # still water: clustered hydrostatics (hydro/flat.py) while the distinct hulls (one cluster
# table per mesh, shared by the bodies using it) have at most this many faces. A/B in one process, calm WAM-V fleets,
# clustered vs per-face kernel, wall / CPU µs per step (load 0.3; both split over two cores from 8,000 faces here,
# the clusters now from FLAT_SPLIT_MIN_FACES):
# 1 WAM-V 16.2 vs 17.7, 10: 109 / 131 vs 126 / 152, 40: 246 / 356 vs 298 / 430, 100: 520 / 829 vs 654 / 1,005,
# 200: 1,024 / 1,665 vs 1,533 / 2,391 (with a table per body, 11.5 MB at 100 WAM-Vs, the clusters lost from ~40 on)
OVERLAP_MIN_FACES = 8000  # below this the thread hand-off costs more than overlapping the two kernels saves
SPLIT_MIN_FACES = 8000  # per-face hydrostatics of this many faces or more: half the bodies on the second core
FLAT_SPLIT_MIN_FACES = 30_000  # the same for the clustered kernel (cheaper per face). Calm WAM-V fleets, split vs one
# thread, wall / CPU µs per step (load 0.4): 10: 111 / 133 vs 80 / 80, 20: 158 / 208 vs 156 / 156, 40: 249 / 360 vs
# 304 / 304, 100: 525 / 829 vs 755 / 756
BAD_QPOS, BAD_QVEL, BAD_QACC = (int(mujoco.mjtWarning.mjWARN_BADQPOS), int(mujoco.mjtWarning.mjWARN_BADQVEL),
                                int(mujoco.mjtWarning.mjWARN_BADQACC))  # fmt: skip


class World:
    """The state of one scenario: physics, ocean, bodies, thrusters, clock. `seed` drives every random stream.
    `kinematic` bodies (e.g. traffic ships) are world-body geoms (`builder.kinematic_geoms`); whoever moves them
    writes their `model.geom_pos`/`geom_quat` (and puts them back at their t = 0 poses on a reset)."""

    def __init__(self, scenario: Scenario, seed: int = 0, kinematic: tuple[KinematicBody, ...] = ()):
        scenario = resolve_geo(scenario)
        self.place = load_place(scenario)  # a real place (geo/), or None
        scenario = with_local_depth(scenario, self.place)
        self.rng = RngStreams(seed)  # checks the seed (int() truncated 2.9 to 2, and took True and '3')
        self.scenario, self.seed = scenario, self.rng.seed
        world = scenario.world
        self.rho, self.g, self.rho_air = (
            world.water_density_kgpm3,
            world.gravity_mps2,
            world.air_density_kgpm3,
        )
        self.clock = Clock(period_ns(world.physics_rate_hz))
        self.look = scenario.rendering  # the current look (config/rendering.py); cameras read it every frame
        self.wakes: Any = None  # the vessels' recent tracks (rendering/wakes.WakeTracks), set by the Simulation
        self.traffic: Any = None  # the Simulation's traffic (other ships' tracks for the renderer), set by it
        try:
            self.ocean = build_ocean(scenario.environment, self.rng.get("ocean"), dt_s=self.clock.dt)
        except ValueError as exc:  # tile sizes the FFT cascade cannot use (ocean/fft.py)
            raise ScenarioError(source_of(scenario), "environment.sea", str(exc)) from None
        floating = self._floating_bodies()
        if not floating:
            raise ScenarioError(source_of(scenario), "vessels", "nothing floats: add a vessel or a buoy")
        static = static_parts(scenario.objects, base_dir(scenario), source_of(scenario))
        geo = geo_parts(self.place) if self.place else GeoParts([], [])
        self.model = build_model(floating, static, self.clock.dt, self.g, geo.visual, geo.collision, kinematic)
        self._geom_owners: list[str] | None = None
        if self.place and self.place.settings is not None:
            set_clip_planes(self.model, self.place.settings.extent_m)
        self.data = mujoco.MjData(self.model)
        self._overlap = Overlap()
        self._init_physics(floating)
        self._init_handles(floating)
        self._guard = DivergenceGuard(world.divergence, list(self.bodies), self.clock.dt)
        self.unwatched = False  # True inside `Simulation.run` for steps nobody looks at between (traffic/fleet.py)
        self.teleports = 0  # bodies put somewhere by `teleport` (traffic/fleet.py: far ships may have come near)
        self.body_teleports = np.zeros(len(self.qpos_adr), np.int64)  # per body (the IMU: a jump is no motion)
        self.odom_origin: dict[str, tuple[np.ndarray, np.ndarray]] = {}  # each vessel's pose at the episode start
        self._mark_odom_origin()

    # -- construction -------------------------------------------------------------------------
    def _floating_bodies(self) -> list[FloatingBody]:
        out, source = [], source_of(self.scenario)
        for i, v in enumerate(self.scenario.vessels):
            model = vessel_model(v, i, base_dir(self.scenario), source)
            quat = quat_from_rpy(
                *(math.radians(a) for a in (v.pose.roll_deg, v.pose.pitch_deg, v.pose.yaw_deg))
            )
            out.append(FloatingBody(v.name, model, v.pose.position, tuple(quat)))
        for obj in self.scenario.objects:
            if isinstance(obj, Buoy):
                x, y, _ = obj.position
                m = obj.mooring
                anchor = (x, y, -m.water_depth_m) if m else None
                length = m.scope * m.water_depth_m if m else 0.0
                out.append(FloatingBody(obj.name, buoy.build(obj), obj.position, (1.0, 0.0, 0.0, 0.0),
                                        anchor, length, obj.radius_m))  # fmt: skip
        return out

    def _init_physics(self, floating: list[FloatingBody]) -> None:
        m, n = self.model, len(floating)
        self._body_ids = np.arange(1, n + 1)
        joints = m.body_jntadr[self._body_ids]
        self.qpos_adr, self.qvel_adr = m.jnt_qposadr[joints].copy(), m.jnt_dofadr[joints].copy()
        self.hulls = HullSet([(fb.model.hull.vertices, fb.model.hull.faces) for fb in floating])
        self._com_body = np.array([fb.model.com for fb in floating], dtype=float).reshape(n, 3)
        if self.hulls.mesh_face_offsets[-1] <= FLAT_MAX_FACES:  # the distinct hulls' faces
            use_flat(self.hulls, self._com_body)  # clustered still-water hydrostatics (hydro/flat.py)
        big = len(self.hulls.faces) >= FLAT_SPLIT_MIN_FACES and self.hulls.n_bodies > 1
        self._flat_overlap = self._overlap if big else None  # clustered hydrostatics: half the bodies on the second core
        self._body_wrenches = np.zeros((2, n, 6))  # body-frame: marine (damping + wind), thrust
        self._xfrc = self.data.xfrc_applied[1 : n + 1]  # floating bodies are bodies 1..n (world frame, CoM)
        self._air = np.zeros((n, 3))
        self._air_from = None  # the ocean whose constant wind _air holds
        self._water_vel, self._water_from = np.zeros((n, 3)), None  # water velocity at each CoM (and whose steady one)
        self._warnings = self.data.warning.number  # a live view of MuJoCo's warning counters
        self.state = BodyState(n)
        entries, timeouts = [], np.zeros(n)
        for i, v in enumerate(self.scenario.vessels):
            timeouts[i] = v.command_timeout_s
            entries += [(i, f"{v.name}/{t.name}", t) for t in floating[i].model.thrusters]
        self.thrusters = ThrusterBank(entries, n, timeouts)
        self._patches = self._water_patches()
        self._still_eta = None  # (ocean, heights) of still water, see _water_heights
        self._direct_vertices = ~np.isin(self.hulls.vert_body, list(self._patches))
        vessels = self.scenario.vessels
        buoyancy = [v.buoyancy for v in vessels] + [TriangleBuoyancy()] * (n - len(vessels))
        self._head = np.zeros(len(self.hulls.vertices_body))
        self._eta = np.zeros(len(self.hulls.vertices_body))  # surface heights of the one-call FFT path
        for i, b in enumerate(buoyancy[: len(vessels)]):
            if isinstance(b, VoxelBuoyancy):  # too fine a grid: a MemoryError (or the OOM killer) otherwise
                try:
                    check_grid(floating[i].model.hull.vertices, b.voxel_size_m)
                except ValueError as exc:
                    raise ScenarioError(source_of(self.scenario), f"vessels[{i}].buoyancy.voxel_size_m", str(exc)) from None
        hydro = [v.hydrodynamics or fb.model.drag for v, fb in zip(vessels, floating)]
        hydro += [fb.model.drag for fb in floating[len(vessels) :]]
        self.marine = MarineModels([fb.model for fb in floating], buoyancy, hydro, self.hulls, self.model,
                                   self.qvel_adr, self.rho, self.g, self.rho_air)  # fmt: skip
        self._scenario_models = (list(buoyancy), list(hydro))
        self._wave_pressure_masks()
        self._update_kinematics()
        self.settle_hydrostatics()

    def _init_handles(self, floating: list[FloatingBody]) -> None:
        self.vessels: dict[str, Vessel] = Names("vessel")
        self.bodies: dict[str, Body] = Names("body")
        for i, fb in enumerate(floating):
            if i < len(self.scenario.vessels):
                handles = {n.split("/", 1)[1]: Thruster(self, k, n) for k, n in enumerate(self.thrusters.names)
                           if self.thrusters.body[k] == i}  # fmt: skip
                self.bodies[fb.name] = self.vessels[fb.name] = Vessel(self, i, fb.name, fb.model, handles)
            else:
                self.bodies[fb.name] = Body(self, i, fb.name, fb.model)

    # -- time ---------------------------------------------------------------------------------
    @property
    def time(self) -> float:
        """Simulation time in seconds (float); `clock_ns` is exact."""
        return self.clock.seconds

    @property
    def clock_ns(self) -> int:
        return self.clock.now_ns

    def step_physics(self) -> None:
        """Advance the physics one step: marine and thrust wrenches, `mj_step`, clock tick, kinematics."""
        self._apply_marine_wrenches()
        mujoco.mj_step(self.model, self.data)
        w = self._warnings  # MuJoCo resets the state on NaN/inf and only counts a warning
        if w[BAD_QPOS] or w[BAD_QVEL] or w[BAD_QACC]:
            self._raise_divergence()
        self.clock.tick()
        self._guard.kinematics_and_check(self.data.qpos, self.data.qvel, self.qpos_adr, self.qvel_adr,
                                         self._com_body, self.state, self.clock.seconds)  # fmt: skip

    def reset(self, seed: int | None = None, poses: Mapping[str, PoseLike] | None = None) -> None:
        """Back to t = 0 exactly as a fresh `World(scenario, seed)` (seed None: keep this world's seed):
        random streams, ocean with its wind and current processes, MuJoCo data, thrusters, marine models
        (the scenario's, histories cleared). `poses` (body name → pose, see `world.poses.pose_arrays`)
        places bodies at rest. No recompilation: the MuJoCo model is kept."""
        if poses is not None and not isinstance(poses, Mapping):  # a name read as its letters: "no body named ['a', ..."
            raise InputError(f"reset: poses maps body names to poses, e.g. {{'wamv': (x, y, z, roll, pitch, yaw)}}, "
                             f"not {type(poses).__name__}")  # fmt: skip
        unknown = sorted(set(poses or ()) - set(self.bodies))
        if unknown:
            raise UnknownNameError(f"no body named {unknown}; bodies: {sorted(self.bodies)}")
        placed = {self.bodies[name].index: pose_arrays(pose) for name, pose in (poses or {}).items()}  # checked first
        self._check_moorings(placed)
        seed = self.seed if seed is None else seed
        self.rng.reseed(seed)  # checks the seed before anything changes
        self.seed = self.rng.seed
        self.ocean = build_ocean(self.scenario.environment, self.rng.get("ocean"), dt_s=self.clock.dt)
        self._patches = self._water_patches()
        mujoco.mj_resetData(self.model, self.data)
        self.clock.reset()
        self.look = self.scenario.rendering
        self.thrusters.reset()
        self._restore_scenario_models()
        self.marine.reset()
        self._guard.reset()
        for index, (pos, quat) in placed.items():
            self._place(index, pos, quat, np.zeros(6))
        self._update_kinematics()
        self.settle_hydrostatics()
        self._mark_odom_origin()

    def teleport(self, index: int, pose: PoseLike, twist=0) -> None:
        """Put body `index` at `pose` with body-frame `twist` (FLU: u, v, w m/s, p, q, r rad/s) now; the
        marine models' histories restart (as after a model switch)."""
        pos, quat = pose_arrays(pose)
        nu = twist_array(twist)  # both checked before anything changes (a bad twist counted a teleport)
        self._check_moorings({index: (pos, quat)})
        self.teleports += 1
        self.body_teleports[index] += 1
        self._place(index, pos, quat, nu)
        self.marine.reset()
        self._guard.reset()
        self._update_kinematics()
        self.settle_hydrostatics()

    def _place(self, index: int, pos: np.ndarray, quat: np.ndarray, nu: np.ndarray, data=None) -> None:
        """base_link at `pos` with orientation `quat` and body-frame twist `nu` (of base_link's origin), in `data`
        (default: the simulation's)."""
        data = self.data if data is None else data
        a, d = self.qpos_adr[index], self.qvel_adr[index]
        rot = matrix_from_quat(quat)
        com = rot @ self._com_body[index]  # the free joint's origin is the CoM (world/builder.py)
        data.qpos[a : a + 3], data.qpos[a + 3 : a + 7] = pos + com, quat
        data.qvel[d : d + 3] = rot @ nu[:3] + cross3(rot @ nu[3:], com)  # world-frame CoM velocity
        data.qvel[d + 3 : d + 6] = nu[3:]  # and body-frame angular velocity

    def _check_moorings(self, placed: dict[int, tuple[np.ndarray, np.ndarray]]) -> None:
        """An InputError if a pose puts a moored body beyond its line's reach from the anchor (MuJoCo's tendon limit
        then tears it back: the first step diverged, the error blaming the time step)."""
        names = list(self.bodies)
        lines = {i: mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_TENDON, f"{names[i]}_mooring") for i in placed}
        lines = {i: t for i, t in lines.items() if t >= 0}
        if not lines:
            return
        data = mujoco.MjData(self.model)
        data.qpos[:] = self.data.qpos
        for i in lines:
            self._place(i, *placed[i], np.zeros(6), data)
        mujoco.mj_fwdPosition(self.model, data)
        for i, t in lines.items():
            length, reach = float(data.ten_length[t]), float(self.model.tendon_range[t, 1])
            if length > reach + 1e-6:
                raise InputError(f"'{names[i]}' would be {length:.3g} m from its anchor, beyond its mooring line "
                                 f"({reach:.3g} m): place it within the line's reach")  # fmt: skip

    def set_buoyancy(self, index: int, model) -> None:
        """Switch body `index` to another buoyancy model (a TriangleBuoyancy or VoxelBuoyancy section) now: its
        wave pressure too. A patch-sampled vessel refuses an explicit `froude_krylov` (as a scenario file does:
        a patch holds surface heights only); a model that cannot be built leaves the current one (the error
        raised)."""
        if (index in self._patches and "wave_pressure" in getattr(model, "model_fields_set", ())
                and getattr(model, "wave_pressure", "") == "froude_krylov"):  # fmt: skip
            raise InputError(f"buoyancy: {self.scenario.vessels[index].name}'s water is sampled on a patch (surface "
                             "heights only): froude_krylov needs water_sampling.mode: direct; use wave_pressure: "
                             "hydrostatic")  # fmt: skip
        self.marine.set_buoyancy(index, model)
        self._wave_pressure_masks()
        self.settle_hydrostatics()  # displaced_volume reads the new model at once

    def _wave_pressure_masks(self) -> None:
        """Which hull vertices take Froude–Krylov pressure heads (ocean/pressure.py): those of bodies whose active
        buoyancy model asks for them and whose water is sampled directly (patch vessels are hydrostatic)."""
        fk = [i for i, b in enumerate(self.marine.buoyancy) if getattr(b, "wave_pressure", "") == "froude_krylov"]
        self._fk_vertices = np.isin(self.hulls.vert_body, fk) & self._direct_vertices
        self._fk_all, self._fk_any = bool(self._fk_vertices.all()), bool(self._fk_vertices.any())

    def _restore_scenario_models(self) -> None:
        buoyancy, hydro = self._scenario_models
        for i, (b, h) in enumerate(zip(buoyancy, hydro)):
            if self.marine.buoyancy[i] is not b:
                self.marine.set_buoyancy(i, b)
            if self.marine.hydrodynamics[i] is not h:
                self.marine.set_hydrodynamics(i, h)
        self._wave_pressure_masks()

    def _water_patches(self) -> dict[int, WaterPatch]:
        return {i: WaterPatch(self.ocean, v.water_sampling.resolution, v.water_sampling.margin_m)
                for i, v in enumerate(self.scenario.vessels) if v.water_sampling.mode == "patch"}  # fmt: skip

    def _mark_odom_origin(self) -> None:
        self.odom_origin.update({name: (v.position, v.quat) for name, v in self.vessels.items()})

    def close(self) -> None:
        self._overlap.close()

    # -- physics ------------------------------------------------------------------------------
    def _update_kinematics(self) -> None:
        s = self.state
        body_kinematics(self.data.qpos, self.data.qvel, self.qpos_adr, self.qvel_adr, self._com_body,
                        s.pos, s.rot, s.com_world, s.vcom_world, s.omega_body)  # fmt: skip

    def settle_hydrostatics(self) -> None:
        """Hydrostatics and each buoyancy model's displaced volume at the current state, outside a step (after a
        build, reset, teleport or buoyancy switch)."""
        s, t = self.state, self.clock.seconds
        verts = self.hulls.world_vertices(s.pos, s.rot)
        eta, head = self._water(verts, t)
        self.hydrostatics = self.hulls.compute(verts, eta, s.com_world, self.rho, self.g, head)
        self.marine.settle_volumes(s, self.hydrostatics, self.ocean, t)

    def _water(self, verts: np.ndarray, t: float) -> tuple[np.ndarray, np.ndarray]:
        """Water height z (m) above every hull vertex, and the pressure heads p/(rho g) (m) for the kernel:
        Froude–Krylov (ocean/pressure.py) at the vertices of bodies that use it, the column eta - z at the others;
        NO_HEAD (all hydrostatic) in calm water or when no body uses it."""
        fk = self._fk_vertices
        if self.ocean.waves is None or not self._fk_any:
            return self._water_heights(verts, t), NO_HEAD
        level, head = self.ocean.level_m, self._head
        if self._fk_all:  # the common case: every vertex (no masks, no copies)
            if len(self._eta) != len(verts):
                self._eta = np.empty(len(verts))
            if hull_water(self.ocean.waves, verts, level, t, self._eta, head):  # an FFT sea: one compiled call
                return self._eta, head
            eta, zeta = surface_and_dynamic_head(self.ocean.waves, verts[:, 0], verts[:, 1], verts[:, 2] - level, t)
            eta += level
            np.subtract(zeta + level, verts[:, 2], out=head)
            return eta, head
        eta = self._water_heights(verts, t, self._direct_vertices & ~fk)
        x, y, z = verts[fk, 0], verts[fk, 1], verts[fk, 2]
        eta_fk, zeta = surface_and_dynamic_head(self.ocean.waves, x, y, z - level, t)
        eta[fk] = eta_fk + level
        np.subtract(eta, verts[:, 2], out=head)
        head[fk] = zeta + level - z
        return eta, head

    def _water_heights(self, verts: np.ndarray, t: float, direct: np.ndarray | None = None) -> np.ndarray:
        """Water surface z (m) above every hull vertex: queried directly, or from each patch vessel's grid.
        `direct`: the vertices to query directly (default: all but the patch vessels'; the rest of the rows
        are left for the caller). Still water: one read-only array of the level, made once per ocean (every
        consumer only reads it)."""
        if self.ocean.waves is None and direct is None and not self._patches:
            if self._still_eta is None or self._still_eta[0] is not self.ocean:
                eta = self.ocean.elevation(verts[:, 0], verts[:, 1], t)
                eta.flags.writeable = False
                self._still_eta = (self.ocean, eta)
            return self._still_eta[1]
        if direct is None and not self._patches:
            return self.ocean.elevation(verts[:, 0], verts[:, 1], t)
        eta = np.empty(len(verts))
        direct = self._direct_vertices if direct is None else direct
        eta[direct] = self.ocean.elevation(verts[direct, 0], verts[direct, 1], t)
        for i, patch in self._patches.items():
            a, b = self.hulls.vert_offsets[i], self.hulls.vert_offsets[i + 1]
            patch.update(verts[a:b, :2], t)
            eta[a:b] = patch.water_height(verts[a:b, 0], verts[a:b, 1])
        return eta

    def _apply_marine_wrenches(self) -> None:
        s, t, ocean = self.state, self.clock.seconds, self.ocean
        ocean.advance(t)
        still = ocean.waves is None and not self._patches
        flat = still and self.hulls.has_flat  # clustered hydrostatics from the poses (hydro/flat.py)
        simple = self.marine.simple
        if flat and simple:  # no world vertices needed
            hydrostatics = self.hulls.compute_flat(s.rot, s.com_world, ocean.level_m, self.rho, self.g,
                                                   self._flat_overlap)  # fmt: skip
        elif (fused := self._fused_hull_pass(t)) is not None:  # a wavy fleet: a body at a time (hydro/fused.py)
            hydrostatics, verts, eta = fused, self.hulls.world_buffer, self._eta
        else:
            verts = self.hulls.world_vertices(s.pos, s.rot)
            eta, head = self._water(verts, t)
            if flat:
                hydrostatics = self.hulls.compute_flat(s.rot, s.com_world, ocean.level_m, self.rho, self.g,
                                                       self._flat_overlap)  # fmt: skip
            elif self.marine.has_kerner and len(self.hulls.faces) >= OVERLAP_MIN_FACES:  # both kernels, two cores
                hydrostatics = self._overlap.submit(self.hulls.compute, verts, eta, s.com_world, self.rho, self.g,
                                                    head)  # fmt: skip
            elif len(self.hulls.faces) >= SPLIT_MIN_FACES and self.hulls.n_bodies > 1:  # bodies over two cores
                hydrostatics = self.hulls.compute_split(self._overlap, verts, eta, s.com_world, self.rho, self.g, head)
            else:
                hydrostatics = self.hulls.compute(verts, eta, s.com_world, self.rho, self.g, head)
        self.thrusters.immerse(s.pos, s.rot, ocean, t)
        if simple:  # the rest of the step in one compiled call (marine.tail)
            assert isinstance(hydrostatics, HydrostaticsResult)  # simple models have no Kerner: no overlapped call
            steady = ocean.steady_velocity_rows(len(s.com_world))
            if steady is None:
                ocean.velocity_into(s.com_world, t, self._water_vel)
            elif self._water_from is not ocean:
                self._water_vel[:], self._water_from = steady, ocean
            if self._air_from is not ocean or not ocean.wind_constant:
                self._air[:], self._air_from = ocean.wind_velocity(t), ocean
            self.marine.tail(s, hydrostatics, self._water_vel, self._air, self.thrusters, self._com_body, self._xfrc,
                             self.clock.now_ns, self.clock.dt)  # fmt: skip
            self.hydrostatics = hydrostatics
            return
        water = ocean.velocity(s.com_world[:, 0], s.com_world[:, 1], s.com_world[:, 2], t)
        relative_velocity_body(s.rot, s.vcom_world, s.omega_body, water, s.nu)
        self._air[:] = ocean.wind_velocity(t)  # one wind for every body, no allocation per step
        self.hydrostatics = self.marine.compute(s, hydrostatics, verts, eta, ocean, t, self.clock.dt, water,
                                                self._air)  # fmt: skip
        self._body_wrenches[0] = self.marine.body_wrench
        self._body_wrenches[1] = self.thrusters.step(self.clock.now_ns, self.clock.dt, self._com_body)
        assemble(s.rot, self._body_wrenches, self.marine.world_force, self.marine.world_torque, self._xfrc)

    def _fused_hull_pass(self, t: float) -> HydrostaticsResult | None:
        """What the step's world vertices, `_water` and split hydrostatics below make, bit for bit, in one pass a body
        at a time over the two cores (hydro/fused.py: the water query split too), for hull sets that split (8,000+
        faces) when every vertex is Froude–Krylov under an FFT sea (no Kerner); else None. Smaller sets keep the
        three passes (1-3 % faster on one core: 1 to 30 WAM-Vs, sea state 4). With simple models (marine.tail) the
        world vertices and heights are not written out (nothing reads them)."""
        waves, s = self.ocean.waves, self.state
        if waves is None or not self._fk_all or self.marine.has_kerner:
            return None
        if len(self.hulls.faces) < SPLIT_MIN_FACES or self.hulls.n_bodies < 2:
            return None
        keep = not self.marine.simple  # simple models (marine.tail) read no vertices or heights afterwards
        # and no model here reads the per-face rows (only Kerner does): made when read (HydrostaticsResult)
        return fused_hydrostatics(self.hulls, waves, self.ocean.level_m, t, s.pos, s.rot, s.com_world, self.rho,
                                  self.g, self._eta, self._head, self._overlap, keep, rows=False)  # fmt: skip

    def _raise_divergence(self) -> None:
        """Name the body whose degree of freedom MuJoCo found non-finite (its warning's info field)."""
        for kind in (BAD_QPOS, BAD_QVEL, BAD_QACC):
            warning = self.data.warning[kind]
            if warning.number > 0:
                dof = min(max(warning.lastinfo, 0), self.model.nv - 1)
                body = max(int(self.model.dof_bodyid[dof]) - 1, 0)
                raise DivergenceError(list(self.bodies)[body], self.time, f"({mujoco.mjtWarning(kind).name})")

    # -- state access -------------------------------------------------------------------------
    def body_quat(self, i: int) -> np.ndarray:
        a = self.qpos_adr[i]
        q = self.data.qpos[a + 3 : a + 7]
        return q / np.linalg.norm(q)

    def origin_velocity(self, i: int) -> np.ndarray:
        """World-frame velocity of body i's frame (base_link) origin (m/s)."""
        s = self.state
        omega_world = s.rot[i] @ s.omega_body[i]
        return s.vcom_world[i] - cross3(omega_world, s.com_world[i] - s.pos[i])

    def point_velocity(self, i, point: np.ndarray) -> np.ndarray:
        """World-frame velocity (m/s) of `point` (ENU m) moving with body i: v_com + ω × (point - com). `i` an index
        and `point` (3,), or indices (n,) and points (n, 3)."""
        s = self.state
        omega_world = (s.rot[i] @ s.omega_body[i][..., None])[..., 0]
        return s.vcom_world[i] + cross3(omega_world, point - s.com_world[i])

    def depth_at(self, x_m, y_m) -> np.ndarray:
        """Water depth (m, positive down from still water) at ENU points: the place's seabed (geo/; minus the
        land height on land), else the environment's `water_depth_m` (inf: deep water). UsvsimError for a
        position that is not a finite number (NaN read the default depth)."""
        for name, v in (("x_m", x_m), ("y_m", y_m)):
            values = np.asarray(v, float)
            if not np.all(np.isfinite(values)):
                bad = values[~np.isfinite(values)] if values.ndim else values
                raise UsvsimError(f"depth_at: {name} must be finite numbers (m), got {np.ravel(bad)[0]!r}")
        if self.place is not None:
            return self.place.depth_at(x_m, y_m)
        return np.full(np.shape(np.atleast_1d(x_m)), self.scenario.environment.water_depth_m or math.inf)

    def contacts(self) -> list[tuple[str, str, float]]:
        """Active contacts as (body name, other body name or 'world', penetration depth m >= 0)."""
        if self._geom_owners is None:
            self._geom_owners = geom_owners(self.model)  # body names, kinematic bodies' for their geoms
        names = self._geom_owners
        return [(names[c.geom[0]], names[c.geom[1]], max(0.0, -float(c.dist))) for c in self.data.contact[: self.data.ncon]]
