"""Geoms wholly outside the view are not drawn: the same pixels, less work for a software rasterizer.

MuJoCo's `mjr_render` sends every geom of the scene through the GL pipeline, and on llvmpipe the vertex work
(transform, lighting or the materials' program, clipping, triangle setup) runs on the calling thread, one geom
after another. The harbour's 252 mooring-line segments (capsules of 28 x 16 facets) cost more of it than the
rest of the scene, and from most views nearly all of them lie behind or beside the camera. `FrustumCull` marks the
scene's primitive geoms (sphere, ellipsoid, capsule, cylinder, box) whose bounding sphere lies wholly outside a
slightly widened view frustum as `mjGEOM_NONE`, which `mjr_render` skips; meshes, planes, height fields and
lines are always drawn. A geom outside the frustum covers no pixel, so colour, depth and ids are unchanged
(tests/rendering/test_cull.py). Not while MuJoCo draws reflections (in a mirror a geom behind the camera can still
show). While it draws the shadows of directional lights, a geom out of view can still cast a shadow into it: its
shadow falls along the light's direction d from it, so it is culled only if the whole ray X + s d (s >= 0) from its
bounding sphere stays outside the view, i.e. outside a frustum plane that the ray cannot cross back (its normal
toward the inside has n · d <= 0), for every light that casts shadows. Any other light that casts shadows (a spot):
nothing is culled.
"""

from __future__ import annotations

import ctypes

import mujoco
import numpy as np

from usvsim.core.transforms import cross3

WIDEN = 1.05  # the frustum's half angles are widened by 5 % ...
MARGIN_M = 0.05  # ... and a bounding sphere must clear a plane by this much plus 2 % of its radius
_G = mujoco.mjtGeom
_ROUND = (int(_G.mjGEOM_SPHERE), int(_G.mjGEOM_ELLIPSOID))
_CAPSULE, _CYLINDER, _BOX, _NONE = (int(t) for t in (_G.mjGEOM_CAPSULE, _G.mjGEOM_CYLINDER, _G.mjGEOM_BOX, _G.mjGEOM_NONE))
_MESH, _HFIELD = int(_G.mjGEOM_MESH), int(_G.mjGEOM_HFIELD)


class FrustumCull:
    """Culls one MjvScene (the scene must outlive it). Call after `mjv_updateScene`, before `mjr_render`."""

    def __init__(self, scene: mujoco.MjvScene):
        self.scene = scene
        geoms = scene.geoms
        self._size = self._pos = None
        if len(geoms) < 2:
            return
        def address(array: np.ndarray) -> int:
            return array.__array_interface__["data"][0]

        base = address(geoms[0].size)
        stride, pos_off, last = address(geoms[1].size) - base, address(geoms[0].pos) - base, len(geoms) - 1
        if (stride <= 0 or stride % 4 or pos_off % 4 or pos_off < 12 or address(geoms[last].size) != base + last * stride
                or address(geoms[last].pos) != base + last * stride + pos_off):  # fmt: skip
            return  # not one array of structs as expected: cull nothing
        n = last * stride // 4 + pos_off // 4 + 3  # floats from geom 0's size to the end of the last geom's pos
        flat = np.ctypeslib.as_array((ctypes.c_float * n).from_address(base))
        view = np.lib.stride_tricks.as_strided
        self._size = view(flat, shape=(last + 1, 3), strides=(stride, 4), writeable=False)
        self._pos = view(flat[pos_off // 4 :], shape=(last + 1, 3), strides=(stride, 4), writeable=False)

    def __call__(self, width: int, height: int) -> int:
        """Mark the geoms outside the view of `scene.camera[0]` (a `width` x `height` viewport); returns how many."""
        scene = self.scene
        flags = scene.flags
        if (self._size is None or self._pos is None or flags[mujoco.mjtRndFlag.mjRND_REFLECTION]
                or scene.stereo or scene.camera[0].orthographic):  # fmt: skip
            return 0
        rays = shadow_directions(scene) if flags[mujoco.mjtRndFlag.mjRND_SHADOW] else np.zeros((0, 3))
        if rays is None:
            return 0
        n = scene.ngeom
        geoms = scene.geoms
        types = np.fromiter((int(g.type) for g in geoms[:n]), dtype=np.int64, count=n)
        size = self._size[:n].astype(np.float64)
        radius = np.full(n, -1.0)  # < 0: never culled
        radius = np.where((types == _ROUND[0]) | (types == _ROUND[1]), size.max(axis=1), radius)
        radius = np.where(types == _CAPSULE, size[:, 2] + size[:, :2].max(axis=1), radius)
        radius = np.where(types == _CYLINDER, np.hypot(size[:, :2].max(axis=1), size[:, 2]), radius)
        radius = np.where(types == _BOX, np.linalg.norm(size, axis=1), radius)
        planes = frustum_planes(mujoco.mjv_averageCamera(scene.camera[0], scene.camera[1]), width, height)  # as mjr_render
        dist = self._pos[:n].astype(np.float64) @ planes[:, :3].T + planes[:, 3]  # (n, planes), m
        outside = dist < -(MARGIN_M + 1.02 * radius)[:, None]
        out = (radius >= 0.0) & outside.any(axis=1)
        for d in rays:  # and its shadow along d stays out of view: outside a plane the ray cannot cross back
            out &= outside[:, planes[:, :3] @ d <= 0.0].any(axis=1)
        culled = np.flatnonzero(out)
        for i in culled:
            geoms[i].type = _NONE
        return len(culled)


def drawn_boxes(scene: mujoco.MjvScene, model: mujoco.MjModel) -> np.ndarray | None:
    """(n, 8, 3) the corners (world, m) of boxes that hold every geom `scene` draws (not `mjGEOM_NONE`: after
    `FrustumCull`, not the culled ones): the primitive shapes from their sizes and frames, meshes and height fields of
    the model from `geom_aabb` (in the geom's frame), each widened by 2 % and MARGIN_M. None where a geom has no such
    box (a plane, a line, an arrow) or MuJoCo draws more than the geoms (labels, shadows, reflections, the skybox,
    skins).
    The water's program for pixels with a geom behind runs only over quads that can reach these boxes' images
    (marine.MarinePass._over_geoms_runs)."""
    flags = scene.flags
    if (flags[mujoco.mjtRndFlag.mjRND_SHADOW] or flags[mujoco.mjtRndFlag.mjRND_REFLECTION]
            or flags[mujoco.mjtRndFlag.mjRND_SKYBOX] or getattr(scene, "nskin", 0) or getattr(scene, "nflex", 0)):  # fmt: skip
        return None
    corners = []
    signs = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=np.float64)
    for g in scene.geoms[: scene.ngeom]:
        kind = int(g.type)
        if kind == _NONE:
            continue
        if g.label:  # MuJoCo writes the geom's label beside it
            return None
        size = np.array(g.size, dtype=np.float64)
        centre = np.zeros(3)
        if kind in _ROUND or kind == _BOX:
            half = size
        elif kind == _CAPSULE:
            half = np.array([size[0], size[0], size[2] + size[0]])
        elif kind == _CYLINDER:
            half = np.array([size[0], size[0], size[2]])
        elif (kind in (_MESH, _HFIELD) and int(g.objtype) == int(mujoco.mjtObj.mjOBJ_GEOM) and 0 <= g.objid < model.ngeom
                and hasattr(model, "geom_aabb")):  # fmt: skip
            centre, half = model.geom_aabb[g.objid, :3].astype(np.float64), model.geom_aabb[g.objid, 3:].astype(np.float64)
        else:
            return None
        half = 1.02 * np.abs(half) + MARGIN_M
        rot = np.array(g.mat, dtype=np.float64).reshape(3, 3)
        corners.append(np.array(g.pos, dtype=np.float64) + (centre + signs * half) @ rot.T)
    return np.array(corners) if corners else np.zeros((0, 8, 3))


def shadow_directions(scene: mujoco.MjvScene) -> np.ndarray | None:
    """(k, 3) the directions (world, unit) in which the scene's shadow-casting lights shine, all directional; None if
    one of them is not directional (its shadows spread from a point: `FrustumCull` then culls nothing)."""
    rays = []
    for i in range(scene.nlight):
        lamp = scene.lights[i]
        if not lamp.castshadow or lamp.headlight:
            continue
        if int(lamp.type) != int(mujoco.mjtLightType.mjLIGHT_DIRECTIONAL):
            return None
        d = np.array(lamp.dir, dtype=np.float64)
        rays.append(d / max(float(np.linalg.norm(d)), 1e-12))
    return np.array(rays).reshape(-1, 3)


def frustum_planes(camera, width: int, height: int) -> np.ndarray:
    """(5, 4) planes (unit normal toward the inside, offset) of a MjvGLCamera's view widened by `WIDEN`: left, right,
    bottom, top through the eye, and the plane through the eye across the view axis (the near plane, moved back)."""
    eye = np.array(camera.pos, dtype=np.float64)
    fwd = np.array(camera.forward, dtype=np.float64)
    fwd /= np.linalg.norm(fwd)
    right = cross3(fwd, np.array(camera.up, dtype=np.float64))
    right /= np.linalg.norm(right)
    up = cross3(right, fwd)
    near = float(camera.frustum_near)
    top, bottom = float(camera.frustum_top), float(camera.frustum_bottom)
    half_w = float(camera.frustum_width) or 0.5 * (top - bottom) * width / height
    center, middle = float(camera.frustum_center), 0.5 * (top + bottom)
    half_h = 0.5 * (top - bottom)
    edges = (  # a direction along each side of the frustum and the axis it turns about
        (near * fwd + (center - WIDEN * half_w) * right, up),
        (near * fwd + (center + WIDEN * half_w) * right, up),
        (near * fwd + (middle - WIDEN * half_h) * up, right),
        (near * fwd + (middle + WIDEN * half_h) * up, right),
    )
    inside = near * fwd + center * right + middle * up  # the view's centre ray
    planes = []
    for edge, axis in edges:
        normal = cross3(axis, edge)
        normal /= np.linalg.norm(normal)
        if normal @ inside < 0.0:
            normal = -normal
        planes.append((*normal, -normal @ eye))
    planes.append((*fwd, -fwd @ eye))
    return np.array(planes)

