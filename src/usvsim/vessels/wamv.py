"""WAM-V 16: twin inflatable pontoons, four azimuth outboards (the seed's layout), VRX mass and inertia.

Body frame `base_link`: FLU, origin on the centreline at mid-length, at the pontoons' keel line.
Sources: VRX wamv_description (masses, inertia, pontoon spacing ±1.03 m, hull radius 0.213 m,
length 4.9 m); the seed's Demo WAM-V (thruster force points, 250 N); VRX SimpleHydrodynamics (drag).
"""

from __future__ import annotations

import numpy as np

from usvsim.config.hydro_models import WindLoad
from usvsim.config.vessel import Azimuth, StateSpaceDrag, Thruster, ThrustMap
from usvsim.vessels.hulls import loft
from usvsim.vessels.model import BodyModel, composite_inertia
from usvsim.vessels.parts import Mesh, Part, merge

HULL_LENGTH_M = 4.9
HULL_RADIUS_M = 0.213
PONTOON_Y_M = 1.03
PONTOON_RGBA = (0.2, 0.2, 0.22, 1.0)
FRAME_RGBA = (0.75, 0.75, 0.78, 1.0)


def pontoon(y_center: float, n_around: int = 14) -> Mesh:
    """One pontoon: a round tube with an upswept, narrowing bow and a slightly rounded stern."""
    half = HULL_LENGTH_M / 2
    x = np.concatenate([[-half, -half + 0.05, -half + 0.15], np.linspace(-2.05, 1.1, 8), np.linspace(1.35, half, 9)])
    r0 = HULL_RADIUS_M
    bow = np.clip((x - 1.1) / (half - 1.1), 0, 1)
    stern = np.clip((-2.2 - x) / (half - 2.2), 0, 1)
    z_bottom = 0.36 * bow**2 + 0.06 * stern**2
    z_top = 2 * r0 + 0.12 * bow**2
    half_width = r0 * (1 - 0.55 * bow**2) * (1 - 0.25 * stern**2)
    return loft(x, z_bottom, z_top, half_width, y_center=y_center, n_around=n_around)


def _mass_properties():
    """VRX WAM-V links combined: base 180 kg (I 120/393/446), engines 2x15, propellers 2x0.5,
    batteries 2x23.5, CPU case 20 kg, at their VRX positions (keel-level origin)."""
    base = np.diag([120.0, 393.0, 446.0])
    engine = np.diag([0.889245, 0.911125, 0.078125])
    parts: list[tuple[float, tuple[float, float, float], np.ndarray | None]] = [(180.0, (0.0, 0.0, 0.0), base)]
    for s in (1, -1):
        parts += [
            (15.0, (-2.373776, s * 1.027135, 0.318237), engine),
            (0.5, (-2.651932, s * 1.027135, -0.191134), np.diag([0.008545, 0.008545, 0.0144])),
            (23.5, (0.0, s * 1.0, 0.45), None),
        ]
    parts.append((20.0, (-0.15, 0.0, 1.53), None))
    return composite_inertia(parts)


def thrusters() -> tuple[Thruster, ...]:
    """The seed's four azimuth outboards (force points in FLU relative to the keel), 250 N forward
    and VRX's measured 100 N reverse (generalized logistic maps), ±90 degrees azimuth; 0.25 m propellers (an
    electric outboard's, estimated: neither the seed nor VRX gives one)."""
    azimuth = Azimuth(min_deg=-90.0, max_deg=90.0, time_constant_s=0.3, max_rate_deg_s=90.0)
    thrust = ThrustMap(type="glf", max_forward_n=250.0, max_reverse_n=100.0)
    points = {
        "rear_left": (-2.570, 1.027, -0.228),
        "rear_right": (-2.570, -1.027, -0.228),
        "front_left": (1.230, 1.027, -0.428),
        "front_right": (1.230, -1.027, -0.428),
    }
    return tuple(
        Thruster(name=n, position=p, thrust=thrust, time_constant_s=0.2, azimuth=azimuth, propeller_diameter_m=0.25)
        for n, p in points.items()
    )


def drag() -> StateSpaceDrag:
    """VRX (gz) WAM-V SimpleHydrodynamics damping, linear and quadratic (kg/s, kg/m and rotational kin)."""
    return StateSpaceDrag(
        X_u=100.0, X_uu=150.0, Y_v=100.0, Y_vv=100.0, Z_w=500.0,
        K_p=300.0, K_pp=600.0, M_q=900.0, M_qq=900.0, N_r=800.0, N_rr=800.0,
    )  # fmt: skip


def wind_load() -> WindLoad:
    """Fossen-form wind load: above-water pontoons, deck and electronics box seen from ahead and abeam."""
    return WindLoad(type="fossen", frontal_area_m2=1.5, lateral_area_m2=2.2, length_m=HULL_LENGTH_M)


def _parts(left: Mesh, right: Mesh):
    deck_z = 2 * HULL_RADIUS_M + 0.55
    collision = [
        Part("mesh", mesh=left, name="pontoon_left"),
        Part("mesh", mesh=right, name="pontoon_right"),
        Part("box", size=(1.0, 1.1, 0.05), pos=(-0.2, 0.0, deck_z), name="deck"),
    ]
    visuals = [
        Part("mesh", mesh=left, rgba=PONTOON_RGBA, name="pontoon_left"),
        Part("mesh", mesh=right, rgba=PONTOON_RGBA, name="pontoon_right"),
        Part("box", size=(1.0, 1.1, 0.05), pos=(-0.2, 0.0, deck_z), rgba=FRAME_RGBA, name="deck"),
        Part("box", size=(0.35, 0.3, 0.25), pos=(-0.15, 0.0, deck_z + 0.3), rgba=(0.9, 0.9, 0.9, 1), name="cabin"),
    ]
    for x in (-1.4, 1.0):
        for s in (1, -1):
            visuals.append(
                Part("box", size=(0.04, 0.04, 0.3), pos=(x, s * PONTOON_Y_M, deck_z - 0.27), rgba=FRAME_RGBA)
            )
    for t in thrusters():
        x, y, z = t.position
        visuals.append(Part("box", size=(0.12, 0.08, 0.35), pos=(x + 0.1, y, z + 0.35), rgba=(0.1, 0.1, 0.1, 1)))
    return tuple(collision), tuple(visuals)


def build() -> BodyModel:
    left = pontoon(PONTOON_Y_M)
    right = left.mirrored_y()
    mass, com, inertia = _mass_properties()
    collision, visuals = _parts(left, right)
    return BodyModel(
        hull=merge([left, right]), collision=collision, visuals=visuals,
        mass_kg=mass, com=com, inertia=inertia, drag=drag(), thrusters=thrusters(), wind_load=wind_load(),
    )  # fmt: skip
