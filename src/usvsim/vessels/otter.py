"""Maritime Robotics Otter (Fossen's PythonVehicleSimulator parameters): twin pontoons, two fixed propellers.

Body frame `base_link`: FLU, origin on the centreline at mid-length, at the keel line.
Hull from Fossen's dimensions: L = 2.0 m, pontoon beam 0.25 m at y = ±0.395 m; the pontoon depth
(0.580 m, diamond-like sections) is chosen so that m = 80 kg (55 kg hull + 25 kg payload) floats at
Fossen's draft T = 0.195 m in sea water (block coefficient 0.40, as his Cb_pont). The centre of mass
sits over the hull's centre of buoyancy at that draft (the real boat is ballasted to float level),
0.442 m above the keel (Fossen: KG = T - z_g = 0.195 + 0.247 m).
"""

from __future__ import annotations

import numpy as np

from usvsim.config.hydro_models import WindLoad
from usvsim.config.vessel import StateSpaceDrag, Thruster, ThrustMap
from usvsim.vessels.hulls import loft
from usvsim.vessels.model import BodyModel
from usvsim.vessels.parts import Mesh, Part, merge

LENGTH_M = 2.0
PONTOON_HALF_BEAM_M = 0.125
PONTOON_Y_M = 0.395
PONTOON_DEPTH_M = 0.5801907739377171
DESIGN_DRAFT_M = 0.195
MASS_KG = 80.0
COM = (-0.20612508, 0.0, DESIGN_DRAFT_M + 0.246875)
# Fossen's Ig (about the CG, NED axes) converted to FLU: the x-z product changes sign.
INERTIA = np.array([[16.67892, 0.0, -2.51665], [0.0, 21.516699, 0.0], [-2.51665, 0.0, 15.1021]])
HULL_RGBA = (0.95, 0.45, 0.05, 1.0)


def pontoon(y_center: float) -> Mesh:
    """One pontoon: diamond-like sections, a long raked bow (last 0.7 m) and a small stern rounding."""
    depth, bow_len = PONTOON_DEPTH_M, 0.7
    x = np.concatenate([[-1.0, -0.97, -0.9], np.linspace(-0.8, 1 - bow_len, 7), np.linspace(1.15 - bow_len, 1.0, 7)])
    bow = np.clip((x - (1 - bow_len)) / bow_len, 0, 1)
    stern = np.clip((-0.85 - x) / 0.15, 0, 1)
    z_bottom = 0.8 * depth * bow**2 + 0.1 * depth * stern**2
    z_top = depth + 0.05 * bow**2
    half_width = PONTOON_HALF_BEAM_M * (1 - 0.6 * bow**2) * (1 - 0.2 * stern**2)
    return loft(x, z_bottom, z_top, half_width, y_center=y_center, n_around=12, exponent=1.5)


def thrusters() -> tuple[Thruster, ...]:
    """Two fixed propellers, Fossen's bollard pulls: 119.682 N forward, 66.708 N reverse, T ∝ n|n|; 0.1 m discs
    (a small electric pod thruster's, estimated: Fossen gives none)."""
    thrust = ThrustMap(type="quadratic", max_forward_n=119.682, max_reverse_n=66.708)
    return tuple(
        Thruster(name=n, position=(-1.05, y, 0.06), thrust=thrust, time_constant_s=0.1, propeller_diameter_m=0.1)
        for n, y in (("left", PONTOON_Y_M), ("right", -PONTOON_Y_M))
    )


def drag() -> StateSpaceDrag:
    """Fossen's Otter linear damping (X_u from U_max, Y_v and N_r from T = 1 s, Z_w/K_p/M_q from
    relative damping 0.3/0.2/0.4) and its extra quadratic yaw damping 10·N_r."""
    return StateSpaceDrag(
        X_u=77.55443, Y_v=162.5, Z_w=605.40388, K_p=62.06542, M_q=266.59700, N_r=42.65145, N_rr=426.5145
    )


def build() -> BodyModel:
    left = pontoon(PONTOON_Y_M)
    right = left.mirrored_y()
    deck_size, deck_pos = (0.55, 0.4, 0.03), (-0.1, 0.0, PONTOON_DEPTH_M - 0.03)
    collision = (Part("mesh", mesh=left), Part("mesh", mesh=right), Part("box", size=deck_size, pos=deck_pos))
    visuals = (
        Part("mesh", mesh=left, rgba=HULL_RGBA),
        Part("mesh", mesh=right, rgba=HULL_RGBA),
        Part("box", size=deck_size, pos=deck_pos, rgba=(0.15, 0.15, 0.15, 1.0)),
        Part("cylinder", size=(0.02, 0.25), pos=(0.1, 0.0, PONTOON_DEPTH_M + 0.25), rgba=(0.9, 0.9, 0.9, 1.0)),
    )
    return BodyModel(
        hull=merge([left, right]), collision=collision, visuals=visuals, mass_kg=MASS_KG,
        com=np.array(COM), inertia=INERTIA.copy(), drag=drag(), thrusters=thrusters(),
        wind_load=WindLoad(type="fossen", frontal_area_m2=0.6, lateral_area_m2=1.0, length_m=LENGTH_M),
    )  # fmt: skip
