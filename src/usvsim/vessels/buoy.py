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
    r, m = cfg.radius_m, cfg.mass_kg
    vertices, faces = icosphere()
    unit = Mesh(vertices, faces)
    scale = r * (4.0 / 3.0 * np.pi / unit.volume()) ** (1.0 / 3.0)
    hull = Mesh(vertices * scale, faces)
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


_PHI = (1.0 + 5.0**0.5) / 2.0
_ICOSAHEDRON = np.array([[-1, _PHI, 0], [1, _PHI, 0], [-1, -_PHI, 0], [1, -_PHI, 0], [0, -1, _PHI], [0, 1, _PHI],
                         [0, -1, -_PHI], [0, 1, -_PHI], [_PHI, 0, -1], [_PHI, 0, 1], [-_PHI, 0, -1], [-_PHI, 0, 1]])
_ICOSAHEDRON_FACES = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
                      (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5),
                      (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]  # outward, counter-clockwise  # fmt: skip


def icosphere() -> tuple[np.ndarray, np.ndarray]:
    """The unit icosphere of one subdivision (42 vertices on the sphere, 80 outward faces): each face of the
    icosahedron split in four at its edge midpoints, pushed out to the sphere. (Made here: importing trimesh for it
    cost every run with buoys ~0.8 s.)"""
    vertices = [v / np.linalg.norm(v) for v in _ICOSAHEDRON.astype(float)]
    middle: dict[tuple[int, int], int] = {}

    def midpoint(a: int, b: int) -> int:
        key = (min(a, b), max(a, b))
        if key not in middle:
            m = vertices[a] + vertices[b]
            vertices.append(m / np.linalg.norm(m))
            middle[key] = len(vertices) - 1
        return middle[key]

    faces = []
    for a, b, c in _ICOSAHEDRON_FACES:
        ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
        faces += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
    return np.array(vertices), np.array(faces, dtype=np.int64)
