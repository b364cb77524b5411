"""Scenario keys of a vessel: model, pose, mass properties, physics models, thrusters.

Frames: positions of parts (thrusters, centre of mass) are in the vessel body frame `base_link`
(FLU: x forward, y left, z up; metres). Initial poses are in the world frame (ENU, metres).
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field, model_validator

from usvsim.config.base import (
    AngleDeg,
    GeoPose,
    Inertia3,
    KeyedValueError,
    MassKg,
    NonNegativeFloat,
    PoseDeg,
    PositiveFloat,
    Scale,
    Section,
    TupleOf,
    Vec3,
)
from usvsim.config.control import Controller
from usvsim.config.hydro_models import FossenHydrodynamics, KernerHydrodynamics, VoxelBuoyancy, WindLoad
from usvsim.config.sensors import Sensors


class Pose(PoseDeg, GeoPose):
    """A world pose: position (m, ENU) and roll/pitch/yaw in degrees (REP 103, yaw CCW from east)."""

    position: Vec3 = Field(default=(0.0, 0.0, 0.0), description="[x east, y north, z up] of base_link in the world "
                           "frame (ENU), m; z 0 puts the keel at the still water, from where the hull settles to its draft")
    yaw_deg: AngleDeg = Field(default=0.0, description="heading of +x, counter-clockwise from east (90 = north)")


class MassProperties(Section):
    """Rigid-body mass properties. Omitted values come from the library model, or for model `custom` (which needs
    `mass_kg`) from the hull mesh as a uniform solid of that mass."""

    mass_kg: MassKg | None = None
    com: Vec3 | None = Field(default=None, description="centre of mass in base_link (FLU), m")
    inertia: Inertia3 | None = Field(default=None, description="principal moments about the CoM along FLU axes, kg m^2; "
                                     "a rigid body's satisfy A + B >= C for every order")

    @model_validator(mode="after")
    def _rigid_body_inertia(self):
        # any mass distribution has I_xx + I_yy >= I_zz (and the other two orders): MuJoCo refuses the rest with a
        # traceback at the build ("inertia must satisfy A + B >= C"); equal sums are a flat body and allowed
        if self.inertia is not None:
            a = self.inertia
            for i, j, k in ((0, 1, 2), (1, 2, 0), (2, 0, 1)):
                if a[i] + a[j] < a[k]:
                    axes = "xyz"
                    raise KeyedValueError("inertia", f"no rigid body has these principal moments: I_{axes[i]} + "
                                          f"I_{axes[j]} = {a[i] + a[j]:g} is below I_{axes[k]} = {a[k]:g} kg m² "
                                          f"(got {list(a)}); each moment must be at most the sum of the other two")
        return self


class StateSpaceDrag(Section):
    """The seed's state-space drag (thesis §4.2.7), damping constants >= 0, body frame FLU at the CoM.

    Force = -(X_u u + X_uu |u|u + X_uuu u^3, Y_v v + Y_vv |v|v + Y_vvv v^3 + Y_r r, Z_w w + Z_ww |w|w,
    K_p p + K_pp |p|p, M_q q + M_qq |q|q, N_r r + N_rr |r|r + N_rrr r^3 + N_v v), on the velocity
    relative to the water. Units: linear N s/m (N m s for rotations), quadratic N s^2/m^2, cubic N s^3/m^3.
    """

    type: Literal["state_space"] = "state_space"
    X_u: NonNegativeFloat = 0.0
    X_uu: NonNegativeFloat = 0.0
    X_uuu: NonNegativeFloat = 0.0
    Y_v: NonNegativeFloat = 0.0
    Y_vv: NonNegativeFloat = 0.0
    Y_vvv: NonNegativeFloat = 0.0
    Y_r: float = 0.0
    Z_w: NonNegativeFloat = 0.0
    Z_ww: NonNegativeFloat = 0.0
    K_p: NonNegativeFloat = 0.0
    K_pp: NonNegativeFloat = 0.0
    M_q: NonNegativeFloat = 0.0
    M_qq: NonNegativeFloat = 0.0
    N_r: NonNegativeFloat = 0.0
    N_rr: NonNegativeFloat = 0.0
    N_rrr: NonNegativeFloat = 0.0
    N_v: float = 0.0


class TriangleBuoyancy(Section):
    """Hydrostatics by exact pressure integration over the clipped physics mesh.

    `wave_pressure`: the pressure under waves. `froude_krylov` (default): linear-wave pressure, each component's
    dynamic part decaying with depth as e^{kz} (cosh at finite depth) with Wheeler stretching, so short waves
    excite a hull less, as in reality (ocean/pressure.py). `hydrostatic`: the column under the local surface,
    ρ g (η - z) (every wave acts as an infinitely long one). Same in calm water. Vessels with
    `water_sampling.mode: patch` always use `hydrostatic` (naming `froude_krylov` with it is an error).
    """

    type: Literal["triangles"] = "triangles"
    wave_pressure: Literal["froude_krylov", "hydrostatic"] = "froude_krylov"


Buoyancy = Annotated[TriangleBuoyancy | VoxelBuoyancy, Field(discriminator="type")]
Hydrodynamics = Annotated[StateSpaceDrag | KernerHydrodynamics | FossenHydrodynamics, Field(discriminator="type")]


class ThrustMap(Section):
    """Normalized command u in [-1, 1] → thrust (N). Forward and reverse have their own maximum.

    `linear`: T = u·max (per direction); `quadratic`: T = u|u|·max (fixed-pitch propeller, T ∝ n|n|);
    `glf`: VRX's generalized logistic fits of measured thruster data (max values scale the curves).
    """

    type: Literal["linear", "quadratic", "glf"] = "linear"
    max_forward_n: PositiveFloat = 250.0
    max_reverse_n: PositiveFloat = 100.0


class Azimuth(Section):
    """A steerable thruster: angle limits, first-order servo and its rate limit (REP 103: + is CCW from above)."""

    min_deg: AngleDeg = Field(default=-90.0, description="clockwise limit (at most 0)")
    max_deg: AngleDeg = Field(default=90.0, description="counter-clockwise limit (at least 0)")
    time_constant_s: PositiveFloat = 0.3
    max_rate_deg_s: PositiveFloat = 90.0

    @model_validator(mode="after")
    def _ordered(self):
        if not self.min_deg <= 0.0 <= self.max_deg:
            raise ValueError("azimuth limits must satisfy min_deg <= 0 <= max_deg")
        return self


class Thruster(Section):
    """One thruster: force point and mounting heading in base_link, thrust map, dynamics, optional azimuth."""

    name: str = Field(pattern=r"^[A-Za-z][A-Za-z0-9_]*$")
    position: Vec3 = Field(description="force application point in base_link (FLU), m")
    mount_yaw_deg: AngleDeg = Field(default=0.0, description="thrust direction at zero azimuth, CCW from +x (90 = tunnel)")
    thrust: ThrustMap = ThrustMap()
    time_constant_s: PositiveFloat = Field(default=0.2, description="first-order lag of the thrust to the command")
    max_rate_n_s: PositiveFloat | None = Field(default=None, description="thrust slew limit; null: none")
    azimuth: Azimuth | None = Field(default=None, description="null: a fixed thruster")
    propeller_diameter_m: PositiveFloat | None = Field(
        default=0.2,
        description="propeller disc (vertical, centred at `position`), m: the thrust scales with its area under the "
        "local water surface (none in the air); null: full thrust wherever the point is",
    )


class WaterSampling(Section):
    """How the hull's water heights are found each step: `direct` queries the ocean at every hull vertex
    (exact); `patch` samples an n x n grid over the hull footprint plus a margin and interpolates on its
    triangles (the seed's method, done right: current, bounds-checked)."""

    mode: Literal["direct", "patch"] = "direct"
    resolution: Annotated[int, Field(ge=2, le=256, description="n of the n x n patch grid")] = 10
    margin_m: NonNegativeFloat = Field(default=1.0, description="patch beyond the hull footprint on each side")


class Vessel(Section):
    """A vessel: a library model (`wamv`, `otter`, `otter_pvs`) or `custom` with a hull mesh file."""

    name: str = Field(pattern=r"^[A-Za-z][A-Za-z0-9_]*$")
    model: str = Field(description="wamv, otter, otter_pvs (library vessels) or custom (hull_mesh)")
    hull_mesh: str | None = Field(default=None, description="physics hull mesh file for model 'custom' (OBJ, STL, PLY, "
                                  "glTF, DAE; closed; base_link frame FLU, m), relative to the scenario file")
    visual_mesh: str | None = Field(default=None, description="mesh drawn instead of the hull (model 'custom'), same "
                                    "frame, relative to the scenario file")
    mesh_scale: Scale = Field(default=1.0, description="scale of the hull and visual mesh files (model 'custom' only)")
    pose: Pose = Pose()
    mass: MassProperties = MassProperties()
    buoyancy: Buoyancy = TriangleBuoyancy()
    water_sampling: WaterSampling = WaterSampling()
    hydrodynamics: Hydrodynamics | None = Field(default=None, description="null: the library model's; model custom: "
                                                "an estimated linear drag (surge time constant 5 s, sway and yaw 1 s, "
                                                "heave, roll, pitch 30 % of critical; vessels/custom.py)")
    thrusters: TupleOf[Thruster] | None = Field(default=None, description="null: the library model's; [] none")
    wind_load: WindLoad | None = Field(default=None, description="wind force on the hull above water (library default)")
    sensors: Sensors = Field(default=(), description="LiDAR, cameras, IMU, GNSS, odometry, ground truth")
    controller: Controller | None = Field(default=None, description="velocity control / station keeping (cmd_vel)")
    command_timeout_s: NonNegativeFloat = Field(default=1.0, description="watchdog: zero thrust after this silence; 0 = off")

    @model_validator(mode="after")
    def _custom_needs_mesh(self):
        if self.model == "custom" and self.hull_mesh is None:
            raise ValueError("model 'custom' needs 'hull_mesh' (a closed mesh file: OBJ, STL, PLY, glTF, DAE)")
        if self.model != "custom" and self.hull_mesh is not None:
            raise KeyedValueError("hull_mesh", f"'hull_mesh' is only for model 'custom' (model is '{self.model}')")
        if self.model != "custom" and self.mesh_scale != 1.0:  # a library hull is built to its size (was ignored)
            raise KeyedValueError("mesh_scale", f"'mesh_scale' is only for model 'custom' (model is '{self.model}')")
        if (self.water_sampling.mode == "patch" and isinstance(self.buoyancy, TriangleBuoyancy)
                and "wave_pressure" in self.buoyancy.model_fields_set and self.buoyancy.wave_pressure == "froude_krylov"):
            # it was taken and ignored: a patch interpolates surface heights only, so patch vessels use `hydrostatic`
            raise KeyedValueError("buoyancy.wave_pressure", "froude_krylov needs water_sampling.mode: direct (a patch "
                                  "interpolates surface heights only, and patch vessels use hydrostatic); set "
                                  "wave_pressure: hydrostatic, or mode: direct")  # fmt: skip
        for kind, names in (("thruster", [t.name for t in self.thrusters or ()]), ("sensor", [s.name for s in self.sensors])):
            repeat = next((i for i, name in enumerate(names) if name in names[:i]), None)
            if repeat is not None:
                raise KeyedValueError(f"{kind}s[{repeat}].name", f"{names[repeat]!r} is already the name of "
                                      f"{kind}s[{names.index(names[repeat])}]; {kind} names must be unique")
        return self
