"""Marker buoys: ballasted spheres that float (VRX marker-buoy damping)."""

from __future__ import annotations

import numpy as np

from usvsim.config.objects import COLORS, Buoy
from usvsim.config.vessel import StateSpaceDrag
from usvsim.vessels.model import BodyModel
from usvsim.vessels.parts import Mesh, Part


def build(cfg: Buoy) -> BodyModel:
    """A sphere of radius r (frame origin at its centre), CoM 0.3 r below the centre (ballast).

    Its hull for the hydrostatics is an 80-face icosphere scaled to the sphere's volume (a factor 1.046 on the
    radius): with its vertices on the sphere it would hold 87 % of the volume and float 18 mm low (r 0.3 m, 20
    kg); volume-matched, the floating height of the centre is the sphere's to 0.1 mm (tests/hydro/test_buoy.py).
    Collision and visual stay the exact sphere."""
    import trimesh  # here: importing trimesh takes ~0.5 s, and a scene without buoys never needs it

    r, m = cfg.radius_m, cfg.mass_kg
    ico = trimesh.creation.icosphere(subdivisions=1, radius=1.0)
    scale = r * (4.0 / 3.0 * np.pi / ico.volume) ** (1.0 / 3.0)
    hull = Mesh(np.asarray(ico.vertices) * scale, np.asarray(ico.faces))
    inertia = np.eye(3) * 0.4 * m * r * r
    rgba = COLORS[cfg.color]
    drag = StateSpaceDrag(X_u=25.0, Y_v=25.0, Z_w=0.3 * 2 * np.sqrt(1025 * 9.81 * np.pi * r * r * m),
                          K_p=2.0, M_q=2.0, N_r=2.0)  # fmt: skip
    return BodyModel(
        hull=hull,
        collision=(Part("sphere", size=(r,)),),
        visuals=(Part("sphere", size=(r,), rgba=rgba),),
        mass_kg=m, com=np.array([0.0, 0.0, -0.3 * r]), inertia=inertia, drag=drag,
    )  # fmt: skip
