"""The shape of a kinematic traffic ship: a hull prism with a pointed bow and a deckhouse aft, in the ship's
body frame (FLU: x forward, z up, origin at midship on the waterline). Its size comes from the scenario
(length, beam, height above the waterline, draft), its colour from the ship type."""

from __future__ import annotations

import numpy as np

from usvsim.config.traffic import Ship
from usvsim.vessels.parts import Mesh, Part

HULL_RGBA = {"cargo": (0.55, 0.15, 0.12, 1.0), "tanker": (0.2, 0.2, 0.22, 1.0), "passenger": (0.95, 0.95, 0.95, 1.0),
             "fishing": (0.2, 0.35, 0.6, 1.0), "tug": (0.85, 0.45, 0.1, 1.0), "pilot": (0.1, 0.1, 0.1, 1.0)}  # fmt: skip
DEFAULT_RGBA = (0.9, 0.9, 0.88, 1.0)
HOUSE_RGBA = (0.93, 0.93, 0.9, 1.0)


def hull_mesh(length: float, beam: float, height: float, draft: float) -> Mesh:
    """A closed convex prism: a rectangle aft of `length/2 - beam` and a triangular bow, from -draft to height."""
    half_l, half_b = 0.5 * length, 0.5 * beam
    shoulder = max(half_l - beam, -half_l + 1e-3)
    outline = np.array([[-half_l, -half_b], [shoulder, -half_b], [half_l, 0.0], [shoulder, half_b], [-half_l, half_b]])
    n = len(outline)
    verts = np.vstack([np.c_[outline, np.full(n, -draft)], np.c_[outline, np.full(n, height)]])
    faces = [[0, k + 1, k] for k in range(1, n - 1)]  # bottom (normals down)
    faces += [[n, n + k, n + k + 1] for k in range(1, n - 1)]  # top (up)
    for k in range(n):
        j = (k + 1) % n
        faces += [[k, j, n + j], [k, n + j, n + k]]  # sides, outline counter-clockwise seen from above
    return Mesh(verts, np.array(faces))


def ship_parts(ship: Ship) -> tuple[tuple[Part, ...], tuple[Part, ...]]:
    """(solid parts, visual parts) of a kinematic ship: the hull prism is drawn, seen by ray sensors and collides
    (MuJoCo uses its convex hull: the prism itself); the deckhouse is drawn. Two geoms a ship: MuJoCo's step
    costs per geom, which matters with hundreds of ships."""
    hull = Part("mesh", mesh=hull_mesh(ship.length_m, ship.beam_m, ship.height_m, ship.draft_m),
                rgba=HULL_RGBA.get(ship.ship_type, DEFAULT_RGBA))  # fmt: skip
    house_half = (0.125 * ship.length_m, 0.4 * ship.beam_m, 0.25 * ship.height_m)
    house = Part("box", size=house_half, pos=(-0.25 * ship.length_m, 0.0, ship.height_m + house_half[2]),
                 rgba=HOUSE_RGBA)  # fmt: skip
    return (hull,), (house,)
