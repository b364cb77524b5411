"""Per-body choice of buoyancy and hydrodynamics models, from the scenario and switchable at run time.

Buoyancy: `triangles` (exact pressure integral over the clipped hull, always computed: it also gives
displaced volume and waterline) or `voxels` (cut voxels, replacing the triangle force for that body).
Hydrodynamics: `state_space` (the seed's drag), `kerner` (per-triangle viscous, pressure/suction,
slamming and air forces) or `fossen` (6-DOF manoeuvring model; its diagonal added mass goes into
MuJoCo's armature so it is integrated implicitly, the rest is a lagged force). The lumped wind load
acts on every vessel that has one, except under Kerner with air drag on (which already includes it).

Outputs per step: world-frame force and torque about each CoM (buoyancy + Kerner) and a body-frame
(FLU) wrench about each CoM (state-space or Fossen damping + wind).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from usvsim.config.hydro_models import FossenHydrodynamics, KernerHydrodynamics, VoxelBuoyancy
from usvsim.config.vessel import StateSpaceDrag
from usvsim.hydro import statespace, wind
from usvsim.hydro.fossen import FossenForces, FossenParameters, added_mass_at, split_added_mass
from usvsim.hydro.fossen_sets import from_config
from usvsim.hydro.hydrostatics import HullSet, HydrostaticsResult
from usvsim.hydro.kerner import KernerForces
from usvsim.hydro.voxelize import voxelize
from usvsim.hydro.voxels import VoxelSet
from usvsim.hydro.wrenches import immersion_scale, marine_tail
from usvsim.vessels.model import BodyModel

NO_KERNER = KernerHydrodynamics(viscous_scale=0.0, pressure_scale=0.0, slamming_scale=0.0, air_scale=0.0)
NO_FOSSEN = FossenParameters(
    np.zeros((6, 6)), np.zeros((6, 6)), np.zeros(6), coriolis_added_mass=False, frame="FLU"
)


class MarineModels:
    """The buoyancy and hydrodynamics of every floating body (index = body index of the HullSet)."""

    def __init__(self, bodies: Sequence[BodyModel], buoyancy: Sequence, hydrodynamics: Sequence, hulls: HullSet,
                 mj_model, dof_adr: np.ndarray, rho: float, g: float, rho_air: float):  # fmt: skip
        self.bodies, self.hulls, self._mj, self._dof_adr = list(bodies), hulls, mj_model, np.asarray(dof_adr)
        self.rho, self.g, self.rho_air = rho, g, rho_air
        self.buoyancy, self.hydrodynamics = list(buoyancy), list(hydrodynamics)
        nb = len(self.bodies)
        self.com_body = np.array([b.com for b in self.bodies], dtype=float).reshape(nb, 3)
        self.rest_volume = np.array([b.mass_kg / rho for b in self.bodies], dtype=float)  # m³ displaced afloat
        self.world_force, self.world_torque = np.zeros((nb, 3)), np.zeros((nb, 3))
        self.body_wrench, self._scratch = np.zeros((nb, 6)), np.zeros((nb, 6))
        self.displaced_volume_m3: np.ndarray | None = None  # per body, of its active buoyancy model (last step)
        # MuJoCo's constant diagonal of M without any armature: a "simple" body (free joint, principal axes along
        # its frame) takes its mass matrix from dof_M0, made at compile time, and ignores a later dof_armature
        self._dof_m0 = np.array(mj_model.dof_M0) - np.array(mj_model.dof_armature)
        self._water_prev: np.ndarray | None = None  # water velocity at the CoMs on the last step (world, m/s)
        self._rebuild()

    # -- choosing models ----------------------------------------------------------------------
    def set_buoyancy(self, index: int, model) -> None:
        """Switch body `index` to another buoyancy model (a TriangleBuoyancy or VoxelBuoyancy section). If the
        models cannot be built with it (voxels too fine for the hull), the previous one stays and the error is
        raised."""
        self._switch(self.buoyancy, index, model)

    def set_hydrodynamics(self, index: int, model) -> None:
        """Switch body `index` to another hydrodynamics model (StateSpaceDrag, KernerHydrodynamics or
        FossenHydrodynamics section). Model states (slamming history, lagged accelerations) restart."""
        self._switch(self.hydrodynamics, index, model)

    def _switch(self, models: list, index: int, model) -> None:
        previous, models[index] = models[index], model
        try:
            self._rebuild()
        except BaseException:  # half-built (it reported voxels of 0.1 mm while it computed the triangles)
            models[index] = previous
            self._rebuild()
            raise

    def _rebuild(self) -> None:
        hydro = self.hydrodynamics
        self._state_space = statespace.coefficients([h if isinstance(h, StateSpaceDrag) else StateSpaceDrag()
                                                     for h in hydro])  # fmt: skip
        self._kerner = None
        if any(isinstance(h, KernerHydrodynamics) for h in hydro):
            configs = [h if isinstance(h, KernerHydrodynamics) else NO_KERNER for h in hydro]
            self._kerner = KernerForces(self.hulls, configs, [b.mass_kg for b in self.bodies],
                                        rho_water=self.rho, rho_air=self.rho_air)  # fmt: skip
        self._fossen = self._build_fossen()
        self._water_prev = None  # model histories restart
        self._build_wind()
        self._tail = None  # the bound arguments of `tail`, made again after every rebuild
        self._voxel_index = [i for i, b in enumerate(self.buoyancy) if isinstance(b, VoxelBuoyancy)]
        self._voxels = None
        if self._voxel_index:
            grids = [voxelize(self.bodies[i].hull.vertices, self.bodies[i].hull.faces, self.buoyancy[i].voxel_size_m)
                     for i in self._voxel_index]  # fmt: skip
            self._voxels = VoxelSet(grids, [self.buoyancy[i].match_mesh_volume for i in self._voxel_index],
                                    [self.buoyancy[i].cut for i in self._voxel_index])  # fmt: skip

    def _build_fossen(self) -> FossenForces | None:
        armature = np.zeros(len(self._dof_adr) * 6)
        if not any(isinstance(h, FossenHydrodynamics) for h in self.hydrodynamics):
            self._set_armature(armature)
            return None
        params, explicit, coriolis = [], [], []
        for i, h in enumerate(self.hydrodynamics):
            p = from_config(h).to_flu() if isinstance(h, FossenHydrodynamics) else NO_FOSSEN
            ref = self.com_body[i] if p.reference_point is None else np.asarray(p.reference_point, dtype=float)
            ma = added_mass_at(p.added_mass, ref - self.com_body[i])  # MuJoCo's armature acts at the CoM
            implicit, rest, _ = split_added_mass(np.diag(ma), self.bodies[i].mass_kg)
            armature[6 * i : 6 * i + 6] = implicit
            params.append(p)
            explicit.append(ma - np.diag(np.diag(ma)) + np.diag(rest))
            coriolis.append(ma - np.diag(np.r_[implicit[:3], 0.0, 0.0, 0.0]))
        self._set_armature(armature)
        return FossenForces(params, self.com_body, at_com=(np.array(explicit), np.array(coriolis)))

    def _water_added_mass(self, rot: np.ndarray, water_vel_com: np.ndarray, dt: float) -> None:
        """Fossen's added-mass force is -M_A ν̇_r, on the acceleration relative to the water; MuJoCo's armature
        takes its translational part on the hull's own acceleration and the explicit rest sees ν̇_r, so the
        armature's share of -M_A (-a_water) was missing: add A · a_water (world; a_water the finite difference of
        the water velocity at the CoM along its path, one step lagged; faded with the damping by immersion_scale,
        as the armature is). A hull in waves then carries the water's added-mass (diffraction) force: without it the
        Otter with Fossen's model followed the slope of a 300 m swell at 0.93 of its pitch, the Otter's sway
        added mass (half of it in the horizontal armature) holding back its surge. Nothing in still water or a
        steady current."""
        prev, self._water_prev = self._water_prev, np.array(water_vel_com, dtype=float)
        if prev is None or prev.shape != self._water_prev.shape:
            return
        acc = (self._water_prev - prev) / dt
        if not acc.any():
            return
        force = self._armature.reshape(-1, 6)[:, :3] * acc  # world frame
        self.body_wrench[:, :3] += np.einsum("bji,bj->bi", rot, force)  # into the body frame (FLU)

    def _set_armature(self, armature: np.ndarray) -> None:
        self._armature, self._armature_scale = armature.copy(), np.ones(len(self._dof_adr))
        for i in range(len(self._dof_adr)):
            self._write_armature(i, armature[6 * i : 6 * i + 6])

    def _write_armature(self, i: int, values: np.ndarray) -> None:
        """Body i's implicit added mass into MuJoCo: dof_armature, and dof_M0 as mj_setConst would make it (what a
        simple body's mass matrix is; with the armature alone its added mass was silently ignored)."""
        adr = self._dof_adr[i]
        self._mj.dof_armature[adr : adr + 6] = values
        self._mj.dof_M0[adr : adr + 6] = self._dof_m0[adr : adr + 6] + values

    def _fade_armature(self, volume: np.ndarray) -> None:
        """Fossen's added mass in MuJoCo's armature fades with the damping (`immersion_scale`'s factor: in full
        while half the displacement at rest is under water, in proportion below, none in the air): a hull in the
        air carries no water with it. Written only when a factor changes (afloat: never)."""
        scale = np.minimum(2.0 * volume / self.rest_volume, 1.0)
        for i in np.flatnonzero(scale != self._armature_scale).tolist():
            self._write_armature(i, self._armature[6 * i : 6 * i + 6] * scale[i])
            self._armature_scale[i] = scale[i]

    def _build_wind(self) -> None:
        rows = []
        for b, h in zip(self.bodies, self.hydrodynamics):
            kerner_air = isinstance(h, KernerHydrodynamics) and h.air_scale > 0
            rows.append(
                wind.coefficient_row(b.wind_load)
                if b.wind_load and not kerner_air
                else (wind.FOSSEN, np.zeros(6))
            )
        self._wind_kind = np.array([k for k, _ in rows], dtype=np.int64)
        self._wind_coef = np.array([c for _, c in rows], dtype=float).reshape(len(rows), 6)

    # -- forces ---------------------------------------------------------------------------------
    @property
    def has_kerner(self) -> bool:
        return self._kerner is not None

    @property
    def simple(self) -> bool:
        """Triangle buoyancy and state-space drag (+ wind) on every body: `tail` can do the whole step."""
        return self._kerner is None and self._fossen is None and self._voxels is None

    def tail(self, state, hydrostatics: HydrostaticsResult, water_vel_com: np.ndarray, wind_world: np.ndarray,
             thrusters, com_body: np.ndarray, xfrc: np.ndarray, now_ns: int, dt: float) -> None:
        """What `compute`, the thruster step and `wrenches.assemble` do for `simple` models, in one compiled call
        (`wrenches.marine_tail`, the same operations in the same order) with its arguments bound once: relative
        velocity into state.nu, world_force/torque, body_wrench, displaced volume, thrusters advanced, and the
        world wrench about each CoM into xfrc (nb,6). The array arguments must keep their identity between
        calls (the World's state, ocean rows and MuJoCo view do)."""
        bound = self._tail
        if bound is None or bound[0] is not state or bound[1] is not water_vel_com or bound[2] is not xfrc:
            if self.displaced_volume_m3 is None:
                self.displaced_volume_m3 = np.zeros(len(self.bodies))
            t, s = thrusters, state
            args = (s.rot, s.vcom_world, s.omega_body, water_vel_com, s.nu, hydrostatics.force, hydrostatics.torque,
                    hydrostatics.volume, self.rest_volume, self._state_space, self._wind_kind, self._wind_coef,
                    self.rho_air, wind_world, t.params, t.cmd_u, t.cmd_angle, t.last_cmd_ns, t.timeout_ns, t.thrust, t.angle, t.wet, t.body, com_body,
                    self.world_force, self.world_torque, self.displaced_volume_m3, self.body_wrench, self._scratch,
                    t.wrench_body, xfrc)  # fmt: skip
            self._tail = bound = (state, water_vel_com, xfrc, args)
        marine_tail(*bound[3], now_ns, dt)

    def compute(self, state, hydrostatics: HydrostaticsResult | Callable[[], HydrostaticsResult], verts: np.ndarray,
                eta: np.ndarray, ocean, t: float, dt: float, water_vel_com: np.ndarray,
                wind_world: np.ndarray) -> HydrostaticsResult:  # fmt: skip
        """Fill `world_force`, `world_torque` (buoyancy + Kerner) and `body_wrench` (damping + wind).
        `hydrostatics` may be a function that waits for a result computed on another thread: the Kerner forces
        (which do not need it) are computed first. Returns the hydrostatics result."""
        kerner = self._kerner_result(state, verts, eta, ocean, t, dt, water_vel_com, wind_world)
        if callable(hydrostatics):
            hydrostatics = hydrostatics()
        self.world_force[:] = hydrostatics.force
        self.world_torque[:] = hydrostatics.torque
        self.displaced_volume_m3 = hydrostatics.volume.copy()
        if self._voxels is not None:
            self._add_voxels(state, ocean, t)
        if kerner is not None and self._kerner is not None:
            self.world_force += kerner.force
            self.world_torque += kerner.torque
            self._kerner.set_waterline(hydrostatics, state.rot)  # Reynolds length for the next step
        statespace.drag_wrench(self._state_space, state.nu, self.body_wrench)
        if self._fossen is not None:
            self.body_wrench += self._fossen.compute(state.nu, dt)
            self._water_added_mass(state.rot, water_vel_com, dt)
        immersion_scale(self.displaced_volume_m3, self.rest_volume, self.body_wrench)  # none on a hull in the air
        if self._fossen is not None:
            self._fade_armature(self.displaced_volume_m3)
        wind.wind_wrenches(self._wind_kind, self._wind_coef, self.rho_air, state.rot, state.vcom_world, wind_world,
                           self._scratch)  # fmt: skip
        self.body_wrench += self._scratch
        return hydrostatics

    def settle_volumes(self, state, hydrostatics: HydrostaticsResult, ocean, t: float) -> None:
        """The displaced volumes of the active buoyancy models at the current state, outside a step (after a
        build, reset, teleport or buoyancy switch), so `Vessel.displaced_volume` reads the voxel model's there too."""
        if self.displaced_volume_m3 is None:
            self.displaced_volume_m3 = hydrostatics.volume.copy()
        else:  # in place: a bound `tail` keeps writing into this array
            self.displaced_volume_m3[:] = hydrostatics.volume
        if self._voxels is not None:
            self.displaced_volume_m3[self._voxel_index] = self._voxel_result(state, ocean, t).volume

    def voxel_capacity_m3(self, state) -> dict[int, float]:
        """Per body with voxel buoyancy (by index), the volume (m³, scaled as its buoyancy is) its voxels displace
        fully under water: what it can carry, like a closed hull's volume for triangles."""
        if self._voxels is None:
            return {}
        return {i: float(v) for i, v in zip(self._voxel_index, self._voxel_result(state).volume)}

    def _voxel_result(self, state, ocean=None, t: float = 0.0):
        """The voxel bodies' buoyancy under `ocean` at time t (None: every voxel under water)."""
        idx, voxels = self._voxel_index, self._voxels
        assert voxels is not None
        centers = voxels.world_centers(state.pos[idx], state.rot[idx])
        eta = np.full(len(centers), np.inf) if ocean is None else ocean.elevation(centers[:, 0], centers[:, 1], t)
        return voxels.compute(centers, eta, np.ascontiguousarray(state.com_world[idx]), self.rho, self.g)

    def _add_voxels(self, state, ocean, t: float) -> None:
        idx = self._voxel_index
        assert self.displaced_volume_m3 is not None, "called after the hydrostatics"
        res = self._voxel_result(state, ocean, t)
        self.world_force[idx] = res.force
        self.world_torque[idx] = res.torque
        self.displaced_volume_m3[idx] = res.volume

    def _kerner_result(self, state, verts, eta, ocean, t, dt, water_vel_com, wind_world):
        if self._kerner is None:
            return None
        water_vel = ocean.velocity(verts[:, 0], verts[:, 1], verts[:, 2], t)
        omega_world = np.einsum("bij,bj->bi", state.rot, state.omega_body)
        return self._kerner.compute(verts, eta, water_vel, state.com_world, state.vcom_world, omega_world,
                                    water_vel_com, wind_world, dt)  # fmt: skip

    def reset(self) -> None:
        """Forget model histories (after a simulation reset or a teleport)."""
        self.displaced_volume_m3 = None
        self._tail = None
        if self._kerner is not None:
            self._kerner.reset()
        self._water_prev = None
        if self._fossen is not None:
            self._fossen.reset()
            self._set_armature(self._armature)
