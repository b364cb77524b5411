"""What viewers outside usvsim draw (the Foxglove live scene, RViz and recorded markers): the scene's static
obstacles read back from the MuJoCo model as `Part`s, and a body's drawable parts.

Static obstacles are the world body's visual geoms (group 1: docks, piers, berths, walls, mesh obstacles,
anchors) less the kinematic traffic ships' (they move); boxes, cylinders, spheres and meshes, poses in the world
frame (ENU, m). Height fields (land from geodata) are left out: they are not drawn outside the viewer.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import mujoco
import numpy as np

from usvsim.vessels.parts import Mesh, Part
from usvsim.world.builder import kinematic_geoms

if TYPE_CHECKING:
    from usvsim.vessels.model import BodyModel

VISUAL_GROUP = 1  # world/builder.py: visual geoms (group 1) never collide
_KINDS = {int(mujoco.mjtGeom.mjGEOM_BOX): "box", int(mujoco.mjtGeom.mjGEOM_CYLINDER): "cylinder",
          int(mujoco.mjtGeom.mjGEOM_SPHERE): "sphere", int(mujoco.mjtGeom.mjGEOM_MESH): "mesh"}  # fmt: skip
HULL_RGBA = (0.8, 0.8, 0.8, 1.0)


def static_parts(model: mujoco.MjModel) -> list[Part]:
    """The world body's visual geoms (static obstacles) as parts in the world frame."""
    moving = kinematic_geoms(model)[1]  # traffic ships: world-body geoms that move, not obstacles
    static = (model.geom_bodyid == 0) & (model.geom_group == VISUAL_GROUP)
    static[moving] = False
    return [part for _, part in _geom_parts(model, np.flatnonzero(static))]


def kinematic_parts(model: mujoco.MjModel) -> list[tuple[int, str, Part]]:
    """The kinematic traffic ships' visual geoms: (geom id, ship name, part at the geom's current world pose);
    the traffic kernel moves them by writing `model.geom_pos` / `geom_quat` (traffic/kernels.py)."""
    names, geoms, owner = kinematic_geoms(model)
    ship = dict(zip(geoms.tolist(), (names[k] for k in owner), strict=True))
    drawn = [g for g in geoms.tolist() if model.geom_group[g] == VISUAL_GROUP]
    return [(g, ship[g], part) for g, part in _geom_parts(model, drawn)]


def _geom_parts(model: mujoco.MjModel, geoms) -> list[tuple[int, Part]]:
    parts = []
    for g in geoms:
        kind = _KINDS.get(int(model.geom_type[g]))
        if kind is None:
            continue
        mesh = None
        if kind == "mesh":
            m = int(model.geom_dataid[g])
            va, vn = model.mesh_vertadr[m], model.mesh_vertnum[m]
            fa, fn = model.mesh_faceadr[m], model.mesh_facenum[m]
            mesh = Mesh(model.mesh_vert[va : va + vn], model.mesh_face[fa : fa + fn])
        name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, g) or ""
        size, pos, quat, rgba = (tuple(float(x) for x in a[g]) for a in
                                 (model.geom_size, model.geom_pos, model.geom_quat, model.geom_rgba))  # fmt: skip
        parts.append((int(g), Part(kind, size, pos, quat, mesh, rgba, name)))  # type: ignore[arg-type]
    return parts


def drawn_parts(model: BodyModel) -> list[Part]:
    """A body's visual parts (body frame), or its physics hull when it has none to draw."""
    visuals = [p for p in model.visuals if p.kind in ("box", "cylinder", "sphere") or p.mesh is not None]
    return visuals or [Part("mesh", (), mesh=model.hull, rgba=HULL_RGBA)]
