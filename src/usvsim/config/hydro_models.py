"""Proposed scenario keys for the switchable buoyancy, hydrodynamics and wind models.

To be joined into `config/vessel.py`'s tagged unions by the lead:
    Buoyancy = Annotated[TriangleBuoyancy | VoxelBuoyancy, Field(discriminator="type")]
    Hydrodynamics = Annotated[StateSpaceDrag | KernerHydrodynamics | FossenHydrodynamics,
                              Field(discriminator="type")]
    Vessel.wind: WindLoad | None = None
Frames: body FLU at the centre of mass unless stated; world ENU. Units in the names or docstrings.
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field

from usvsim.config.base import NonNegativeFloat, PositiveFloat, Section, TupleOf, Vec3


class VoxelBuoyancy(Section):
    """Archimedes over a voxelization of the hull (cached on disk by mesh hash and voxel size).

    `cut`: partially submerged voxels count s²(s/2 - h) (thesis §4.2.5.2) instead of all-or-nothing.
    `match_mesh_volume`: scale every voxel so their total equals the mesh volume (removes the
    staircase volume error; the seed did not).
    """

    type: Literal["voxels"] = "voxels"
    voxel_size_m: PositiveFloat = 0.05
    cut: bool = True
    match_mesh_volume: bool = True


class KernerHydrodynamics(Section):
    """Kerner's per-triangle hydrodynamics (physics.md §1.5-§1.8); defaults from asv_wave_sim.

    Viscous: ITTC-57 C_F(Rn), Rn = |v_rel,CoM| L / nu (L = waterline length along x, of the previous step),
    times (1 + k).
    Pressure/suction: (C1 v/v_R + C2 (v/v_R)²) S |cos θ|^f along the normal (Pa at v_R head-on).
    Slamming: an impulse -ramp cos θ m v (2 ΔA / S) per face over each step (ΔA: area wetted during the
    step), ramp = min(normal entry speed / slamming_speed_mps, 1)^p; time-step independent; scale 0 disables. Air: C_air on dry faces.
    """

    type: Literal["kerner"] = "kerner"
    kinematic_viscosity_m2ps: PositiveFloat = Field(
        default=1.19e-6, description="sea water 15 C, 35 g/kg (ITTC), beside the sea-water density; fresh water 15 C "
        "1.14e-6; asv_wave_sim used 1.0533e-6 (C_F 2.4 % higher at Rn ~ 5e6)"
    )
    form_factor_k: NonNegativeFloat = 0.0
    reynolds_min: PositiveFloat = 1.0e3
    viscous_scale: NonNegativeFloat = 1.0
    pressure_linear_pa: NonNegativeFloat = 100.0
    pressure_quadratic_pa: NonNegativeFloat = 100.0
    pressure_falloff: PositiveFloat = 0.4
    suction_linear_pa: NonNegativeFloat = 100.0
    suction_quadratic_pa: NonNegativeFloat = 100.0
    suction_falloff: PositiveFloat = 0.4
    reference_speed_mps: PositiveFloat = 1.0
    pressure_scale: NonNegativeFloat = 1.0
    slamming_power: PositiveFloat = 2.0
    slamming_speed_mps: PositiveFloat = Field(
        default=5.0, description="normal entry speed at which a face gets its full share of the stopping impulse"
    )
    slamming_scale: NonNegativeFloat = 1.0
    air_drag_coefficient: NonNegativeFloat = 0.8
    air_scale: NonNegativeFloat = 1.0


Six = Annotated[TupleOf[NonNegativeFloat], Field(min_length=6, max_length=6)]  # surge, sway, heave, roll, pitch, yaw


class FossenHydrodynamics(Section):
    """Fossen's 6-DOF manoeuvring model: added mass, Coriolis (incl. added mass), damping, cross-flow.

    `parameters`: a library set ("otter", "wamv_vrx", "wamv_vrx_classic") or "custom" with the keys
    below. Coefficients are given as positive magnitudes in Fossen's NED/FRD convention
    (M_A = diag(added_mass), D = diag(linear) + diag(quadratic)·|ν|); they are converted to FLU once.
    `reference_point` (base_link, FLU, m): Fossen's CO where ν is taken; None = centre of mass.
    `vrx_compatible`: no added-mass Coriolis and no Munk moment (VRX assembles C_A but never adds it).
    """

    type: Literal["fossen"] = "fossen"
    parameters: Literal["otter", "wamv_vrx", "wamv_vrx_classic", "custom"] = "custom"
    added_mass: Six = Field(default=(0.0,) * 6, description="[X_u̇, Y_v̇, Z_ẇ, K_ṗ, M_q̇, N_ṙ] magnitudes: kg "
                            "(surge, sway, heave), kg m² (roll, pitch, yaw)")
    linear_damping: Six = Field(default=(0.0,) * 6, description="same order: N s/m, N m s")
    quadratic_damping: Six = Field(default=(0.0,) * 6, description="same order: N s²/m², N m s²")
    cross_flow_length_m: NonNegativeFloat = 0.0
    cross_flow_draft_m: NonNegativeFloat = 0.0
    cross_flow_beam_m: NonNegativeFloat = 0.0
    reference_point: Vec3 | None = Field(default=None, description="in base_link (FLU), m; null: the centre of mass")
    added_mass_coriolis: bool = True
    vrx_compatible: bool = False
    acceleration_filter_s: NonNegativeFloat = Field(default=0.0, description="low-pass on the lagged ν̇ (0 = none)")


class WindLoad(Section):
    """Quadratic wind load on the hull above water from the wind relative to the vessel.

    `fossen`: X = q A_F C_X(γ), Y = q A_L C_Y(γ), N = q A_L L C_N(γ), q = ½ rho_air V², with
    C_X = -c_x cos γ, C_Y = -c_y sin γ, C_N = -c_n sin 2γ in FLU (Fossen 2021 §10.1, converted).
    `vrx`: F = c ⊙ |w|w per body axis, N = -2 c_n w_x w_y (VRX usv wind form).
    """

    type: Literal["fossen", "vrx"] = "fossen"
    frontal_area_m2: NonNegativeFloat = 0.0
    lateral_area_m2: NonNegativeFloat = 0.0
    length_m: NonNegativeFloat = 0.0
    c_x: float = 0.7
    c_y: float = 0.825
    c_n: float = 0.125
