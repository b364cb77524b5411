"""Ray casting against the world's geometry with Embree (embreex), for LiDARs (and any ray sensor).

Every MuJoCo geom of one group (visual 1 by default, so LiDAR sees what cameras see; or collision 3)
becomes triangles: boxes exactly, spheres/cylinders/capsules/ellipsoids tessellated within `TOL_M` of the
true surface, meshes as compiled. Static geoms (world body) go into one Embree scene built once; geoms of
moving bodies go into a second scene rebuilt from the bodies' current poses (`sim.state`, the post-step
pose, not MuJoCo's one-step-old `geom_xpos`) when a ray sensor first needs it at a tick. Each scene is one
Embree geometry; `prim_geom[primID]` gives the MuJoCo geom id. Water (group 2) is never in a scene.
"""

from __future__ import annotations

import math
from concurrent.futures import ThreadPoolExecutor

import mujoco
import numpy as np
import trimesh
from embreex import rtcore_scene as rtcs
from embreex.mesh_construction import TriangleMesh

from usvsim.core.transforms import matrix_from_quat

TOL_M = 0.004  # max distance of tessellated primitives from the true surface
NO_HIT = -1
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


def _scene(triangles: np.ndarray) -> rtcs.EmbreeScene | None:
    if len(triangles) == 0:
        return None
    scene = rtcs.EmbreeScene()
    TriangleMesh(scene, np.ascontiguousarray(triangles, dtype=np.float32))
    return scene


class RayWorld:
    """The triangles of one geom group, static and moving, and a multi-threaded `cast`."""

    def __init__(self, sim, group: int, threads: int = 2):
        model = sim.model
        self.sim, self.threads = sim, threads
        self.pool = ThreadPoolExecutor(threads) if threads > 1 else None
        geoms = [g for g in range(model.ngeom) if model.geom_group[g] == group]
        local = {g: geom_triangles(model, g) for g in geoms}
        local = {g: tri for g, tri in local.items() if tri is not None}
        static = [g for g in local if model.geom_bodyid[g] == 0]
        self.moving = [g for g in local if model.geom_bodyid[g] != 0]
        world_tris = [self._transform(local[g], model.geom_pos[g], matrix_from_quat(model.geom_quat[g])) for g in static]
        self.static_geom = np.repeat(np.array(static, dtype=np.int32), [len(local[g]) for g in static])
        self.static = _scene(np.concatenate(world_tris) if world_tris else np.zeros((0, 3, 3)))
        self.moving_local = [local[g] for g in self.moving]
        self.moving_geom = np.repeat(np.array(self.moving, dtype=np.int32), [len(t) for t in self.moving_local])
        self.moving_body = model.geom_bodyid[self.moving] - 1  # index into sim.state
        self.moving_pos = model.geom_pos[self.moving].copy()
        self.moving_rot = matrix_from_quat(model.geom_quat[self.moving]) if self.moving else np.zeros((0, 3, 3))
        self._dynamic, self._dynamic_step = None, -1

    @staticmethod
    def _transform(tris: np.ndarray, pos: np.ndarray, rot: np.ndarray) -> np.ndarray:
        return tris @ rot.T + pos

    def moving_triangles(self) -> np.ndarray:
        """All moving geoms' triangles in the world at the current state (n, 3, 3)."""
        s = self.sim.state
        out = [self._transform(tri, s.pos[b] + s.rot[b] @ p, s.rot[b] @ r)
               for tri, b, p, r in zip(self.moving_local, self.moving_body, self.moving_pos, self.moving_rot)]  # fmt: skip
        return np.concatenate(out) if out else np.zeros((0, 3, 3))

    def _dynamic_scene(self):
        step = self.sim.clock.steps
        if self._dynamic_step != step:
            self._dynamic, self._dynamic_step = _scene(self.moving_triangles()), step
        return self._dynamic

    def cast(self, origins: np.ndarray, dirs: np.ndarray, max_range: float):
        """Nearest hits of rays (world ENU; `dirs` unit). Returns (distance m float32, +inf on a miss; MuJoCo
        geom id, -1 on a miss; geometric normal (n, 3), world, unit where there is a hit)."""
        origins = np.ascontiguousarray(origins, np.float32)
        dirs = np.ascontiguousarray(dirs, np.float32)
        dist = geom = normal = None
        for scene, prim_geom in ((self.static, self.static_geom), (self._dynamic_scene(), self.moving_geom)):
            if scene is None:
                continue
            hit = self._run(scene, origins, dirs, max_range)
            found = hit["geomID"] != NO_HIT
            if dist is None:
                dist = np.where(found, hit["tfar"], np.float32(np.inf))
                geom = np.where(found, prim_geom[hit["primID"]], NO_HIT).astype(np.int32)
                normal = hit["Ng"]
                continue
            closer = np.flatnonzero(found & (hit["tfar"] < dist))
            dist[closer] = hit["tfar"][closer]
            geom[closer] = prim_geom[hit["primID"][closer]]
            normal[closer] = hit["Ng"][closer]
        if dist is None:
            n = len(dirs)
            return np.full(n, np.inf, np.float32), np.full(n, NO_HIT, np.int32), np.zeros((n, 3), np.float32)
        idx = np.flatnonzero(geom != NO_HIT)
        normal[idx] /= np.maximum(np.linalg.norm(normal[idx], axis=1, keepdims=True), 1e-12)
        return dist, geom, normal

    def _run(self, scene, origins, dirs, max_range):
        n = len(dirs)
        dists = np.full(n, max_range, np.float32)
        if self.pool is None or n < 4096:
            return scene.run(origins, dirs, dists=dists, output=1)
        bounds = np.linspace(0, n, self.threads + 1).astype(int)
        parts = list(self.pool.map(lambda ab: scene.run(origins[ab[0]:ab[1]], dirs[ab[0]:ab[1]], dists=dists[ab[0]:ab[1]],
                                                        output=1), zip(bounds[:-1], bounds[1:])))  # fmt: skip
        return {k: np.concatenate([p[k] for p in parts]) for k in ("tfar", "primID", "geomID", "Ng")}

    def close(self) -> None:
        if self.pool is not None:
            self.pool.shutdown(wait=False)
            self.pool = None
