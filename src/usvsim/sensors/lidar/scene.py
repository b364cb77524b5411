"""The world's geometry as Embree (embreex) scenes for ray sensors: one static scene and one per moving body.

Every MuJoCo geom of one group (visual 1 by default, so LiDAR sees what cameras see; or collision 3)
becomes triangles: boxes exactly, spheres/cylinders/capsules/ellipsoids tessellated within `TOL_M` of the
true surface, meshes as compiled. Static geoms (world body) go into one scene in the world frame; the geoms
of each moving body go into one scene in that body's frame. All scenes are built once: a moving body's
scene never changes, the rays are brought into its frame instead (`raycast.RayWorld`). Each scene is one
Embree geometry; `prim_geom[primID]` gives the MuJoCo geom id. Water (group 2) is never in a scene.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import mujoco
import numpy as np
import trimesh
from embreex import rtcore_scene as rtcs
from embreex.mesh_construction import TriangleMesh

from usvsim.core.transforms import matrix_from_quat
from usvsim.world.builder import base_offset, kinematic_geoms

TOL_M = 0.004  # max distance of tessellated primitives from the true surface
NO_HIT = -1
STATIC = -1  # `BodyScene.body` of the static world scene
KINEMATIC = -2  # `BodyScene.body` of a kinematic body's scene (world-body geoms that move, e.g. traffic ships)
_G = mujoco.mjtGeom


def _sphere(radius: float) -> trimesh.Trimesh:
    sub = next((s for s, f in ((1, 0.05), (2, 0.0127), (3, 0.0032)) if radius * f < TOL_M), 4)
    return trimesh.creation.icosphere(sub, radius)


def _sections(radius: float) -> int:
    return int(np.clip(math.ceil(math.pi / math.acos(max(1.0 - TOL_M / radius, -1.0))), 16, 256))


def geom_triangles(model: mujoco.MjModel, g: int) -> np.ndarray | None:
    """Triangles (n, 3, 3) of geom g in its own frame (m), or None for planes/height fields."""
    t, size = model.geom_type[g], model.geom_size[g]
    if t == _G.mjGEOM_BOX:
        mesh = trimesh.creation.box(extents=2.0 * size)
    elif t == _G.mjGEOM_SPHERE:
        mesh = _sphere(size[0])
    elif t == _G.mjGEOM_ELLIPSOID:
        mesh = _sphere(max(size)).apply_scale(size / max(size))
    elif t == _G.mjGEOM_CYLINDER:
        mesh = trimesh.creation.cylinder(size[0], 2.0 * size[1], sections=_sections(size[0]))
    elif t == _G.mjGEOM_CAPSULE:
        mesh = trimesh.creation.capsule(2.0 * size[1], size[0], count=[_sections(size[0]), _sections(size[0])])
    elif t == _G.mjGEOM_MESH:
        m = model.geom_dataid[g]
        verts = model.mesh_vert[model.mesh_vertadr[m] : model.mesh_vertadr[m] + model.mesh_vertnum[m]]
        faces = model.mesh_face[model.mesh_faceadr[m] : model.mesh_faceadr[m] + model.mesh_facenum[m]]
        return verts[faces].astype(np.float64)
    else:
        return None
    return np.asarray(mesh.triangles, dtype=np.float64)


def geom_triangles_body(model: mujoco.MjModel, g: int) -> np.ndarray | None:
    """Triangles (n, 3, 3) of geom g in its body's frame (base_link; the world frame for static geoms), m."""
    tris = geom_triangles(model, g)
    offset = base_offset(model, model.geom_bodyid[g])  # MuJoCo's frame of a floating body sits at its CoM
    return None if tris is None else tris @ matrix_from_quat(model.geom_quat[g]).T + model.geom_pos[g] + offset


@dataclass(frozen=True)
class BodyScene:
    """The geoms of one body as one Embree scene in the body frame, with a bounding sphere for culling."""

    scene: rtcs.EmbreeScene
    prim_geom: np.ndarray  # (triangles,) int32: MuJoCo geom id of each triangle
    body: int  # index into `sim.state` arrays; STATIC for the world scene (frame = world); KINEMATIC: see anchor
    center_body_m: np.ndarray  # (3,) bounding sphere centre, body frame
    radius_m: float
    part_centers_m: np.ndarray  # (geoms, 3) bounding sphere centre of each geom, body frame
    part_radii_m: np.ndarray  # (geoms,)
    box_lo_m: np.ndarray  # (3,) corners of the bounding box, body frame, 1 mm margin
    box_hi_m: np.ndarray
    anchor: int = -1  # KINEMATIC scenes: the geom whose frame (model.geom_pos/quat, moved in place) is the scene's


def bounding_sphere(verts: np.ndarray) -> tuple[np.ndarray, float]:
    """A sphere (centre, radius m) around points (n, 3): centred on their box, 1 mm margin for float32."""
    center = 0.5 * (verts.min(axis=0) + verts.max(axis=0))
    return center, float(np.linalg.norm(verts - center, axis=1).max()) + 1e-3


def _body_scene(geoms: list[int], tris: list[np.ndarray], body: int) -> BodyScene:
    all_tris = np.concatenate(tris)
    center, radius = bounding_sphere(all_tris.reshape(-1, 3))
    parts = [bounding_sphere(t.reshape(-1, 3)) for t in tris]
    scene = rtcs.EmbreeScene()  # pyright: ignore[reportAttributeAccessIssue] (Cython module: pyright reads its .pxd)
    TriangleMesh(scene, np.ascontiguousarray(all_tris, dtype=np.float32))
    prim_geom = np.repeat(np.array(geoms, np.int32), [len(t) for t in tris])
    verts = all_tris.reshape(-1, 3)
    return BodyScene(scene, prim_geom, body, center, radius, np.array([c for c, _ in parts]),
                     np.array([r for _, r in parts]), verts.min(axis=0) - 1e-3, verts.max(axis=0) + 1e-3)  # fmt: skip


def body_scenes(model: mujoco.MjModel, group: int) -> tuple[BodyScene | None, list[BodyScene]]:
    """The static scene (None without static triangles) and one scene per moving body with triangles."""
    by_body: dict[int, tuple[list[int], list[np.ndarray]]] = {}
    for g in range(model.ngeom):
        if model.geom_group[g] != group or (tris := geom_triangles_body(model, g)) is None or len(tris) == 0:
            continue
        geoms, tri_list = by_body.setdefault(int(model.geom_bodyid[g]), ([], []))
        geoms.append(g)
        tri_list.append(tris)
    moving = _kinematic_scenes(model, by_body.get(0, ([], [])))
    static = _body_scene(*by_body.pop(0), STATIC) if by_body.get(0, ([],))[0] else None
    return static, [_body_scene(*by_body[b], b - 1) for b in sorted(by_body) if b] + moving


def _kinematic_scenes(model: mujoco.MjModel, world: tuple[list[int], list[np.ndarray]]) -> list[BodyScene]:
    """Take the kinematic bodies' geoms out of the world body's lists: one scene each, in the frame of its first
    geom (triangles as built, in the world frame, moved into that frame)."""
    names, kin, owner = kinematic_geoms(model)
    geoms, tris = world
    by_owner: dict[int, tuple[list[int], list[np.ndarray]]] = {}
    for g, t in zip(list(geoms), list(tris)):
        found = np.flatnonzero(kin == g)
        if len(found):
            k = geoms.index(g)
            geoms.pop(k)
            tris.pop(k)
            parts = by_owner.setdefault(int(owner[found[0]]), ([], []))
            parts[0].append(g)
            parts[1].append(t)
    out = []
    for gs, ts in by_owner.values():
        anchor = gs[0]
        rot, pos = matrix_from_quat(model.geom_quat[anchor]), model.geom_pos[anchor]
        scene = _body_scene(gs, [(t - pos) @ rot for t in ts], KINEMATIC)
        out.append(dataclasses.replace(scene, anchor=anchor))
    return out
