"""The drawn water surface: a MuJoCo height field sampled from the simulation's one `Ocean`.

At build time `add_water_surface` puts a visual-only height field geom (group 2, contype/conaffinity 0,
mass 0: physics never sees it) just below the still-water plane. A renderer that wants waves calls
`update_water_visual(sim, context, center_xy)` before drawing: it samples `sim.ocean.height_grid` (the same
`Ocean.elevation` the hydrostatics query every step) on the field's grid around `center_xy`, writes the
normalized heights into `model.hfield_data` (float32; vertical scale in `hfield_size[2]`, the minimum in the
geom's z), uploads them to the GL context, and lowers the still-water plane below the field so that the plane
remains only the far-field horizon. For a flat sea the field is flat at the mean level.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

WATER_SURFACE = "water_surface"
STILL_WATER = "still_water"
WATER_GROUP = 2
SURFACE_SIZE_M = 120.0
SURFACE_POINTS = 61  # 2 m spacing over 120 m (upload cost grows as n^2: 20 ms at 121 on llvmpipe)
SURFACE_RGBA = (1.0, 1.0, 1.0, 1.0)  # the colour comes from the texture
TROUGH_RGB, MEAN_RGB, CREST_RGB = (
    np.array([0.02, 0.13, 0.24]),
    np.array([0.06, 0.27, 0.40]),
    np.array([0.42, 0.60, 0.66]),
)
SLOPE_SHADING = (
    2.5  # brightness change per unit slope toward the (virtual, low) sun: makes the waves readable
)
PLANE_GAP_M = 0.05  # the still-water plane sits this far below the field's lowest point
_MIN_SPAN_M = 1e-4


def add_water_surface(spec: mujoco.MjSpec, size_m: float = SURFACE_SIZE_M, n: int = SURFACE_POINTS) -> None:
    """Add the height field asset and its visual geom to a spec (call once, after the still-water plane)."""
    half = 0.5 * size_m  # vertical size 5 m: only the compiled bounding box; each update sets the real span
    field = spec.add_hfield(name=WATER_SURFACE, size=[half, half, 5.0, 0.05], nrow=n, ncol=n)
    field.userdata = [0.0] * (n * n)
    spec.add_texture(name=WATER_SURFACE, type=mujoco.mjtTexture.mjTEXTURE_2D, builtin=mujoco.mjtBuiltin.mjBUILTIN_FLAT,
                     width=n, height=n, rgb1=list(MEAN_RGB))  # fmt: skip
    material = spec.add_material(
        name=WATER_SURFACE, texrepeat=[1, 1], texuniform=False, specular=0.6, shininess=0.7
    )
    material.textures[mujoco.mjtTextureRole.mjTEXROLE_RGB] = WATER_SURFACE
    geom = spec.worldbody.add_geom(name=WATER_SURFACE, type=mujoco.mjtGeom.mjGEOM_HFIELD, hfieldname=WATER_SURFACE,
                                   material=WATER_SURFACE)  # fmt: skip
    geom.pos = [0.0, 0.0, -2.0 * PLANE_GAP_M]  # hidden under the plane until a renderer updates it
    geom.rgba, geom.group, geom.contype, geom.conaffinity = list(SURFACE_RGBA), WATER_GROUP, 0, 0
    geom.mass = 0.0


@dataclass(frozen=True)
class WaterSurfaceIds:
    hfield: int
    geom: int
    plane: int  # -1 if the model has no still-water plane
    texture: int  # -1 if the field has no texture

    @classmethod
    def of(cls, model: mujoco.MjModel) -> WaterSurfaceIds | None:
        hfield = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_HFIELD, WATER_SURFACE)
        geom = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, WATER_SURFACE)
        if hfield < 0 or geom < 0:
            return None
        return cls(hfield, geom, mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, STILL_WATER),
                   mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_TEXTURE, WATER_SURFACE))  # fmt: skip


def grid_axis(model: mujoco.MjModel, ids: WaterSurfaceIds) -> tuple[float, int]:
    """(side length m, points per side) of the water surface field."""
    return 2.0 * float(model.hfield_size[ids.hfield, 0]), int(model.hfield_ncol[ids.hfield])


def snapped_center(center_xy, size_m: float, n: int) -> tuple[float, float]:
    """Centre rounded to the grid spacing, so vertices stay put in the world as the field follows a boat."""
    step = size_m / (n - 1)
    return float(np.round(center_xy[0] / step) * step), float(np.round(center_xy[1] / step) * step)


def still_water_to_view(scene: mujoco.MjvScene, model: mujoco.MjModel, eye_xy, reach_m: float) -> None:
    """After `mjv_updateScene`: the scene's still-water plane centred under the eye (world ENU x, y in m), `reach_m`
    out in every direction, opaque and in the flat field's colour. It is then water to the view's far plane wherever
    the vessel is, and it writes depth: a fixed 1 km square around the origin, translucent (no depth), left the
    plain look's cameras with NaN depth beyond the 120 m field and the sky painted over it (the horizon 8 degrees
    low from 10 m up), and the viewer with no sea at all 500 m from the origin."""
    plane = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, STILL_WATER)
    if plane < 0:
        return
    for i in range(scene.ngeom):  # the plane is the world's first geom: found at once
        geom = scene.geoms[i]
        if geom.objtype == mujoco.mjtObj.mjOBJ_GEOM and geom.objid == plane:
            geom.pos[0], geom.pos[1] = float(eye_xy[0]), float(eye_xy[1])
            geom.size[0] = geom.size[1] = float(reach_m)
            geom.rgba[:3], geom.rgba[3] = MEAN_RGB, 1.0
            geom.specular = 0.0  # lit at its far corners, a specular term made it lighter than the field
            return


def update_water_visual(sim, renderer_context=None, center_xy=(0.0, 0.0)) -> np.ndarray | None:
    """Refresh the drawn surface from `sim.ocean` at `sim.time` around `center_xy` (world ENU, m).

    `renderer_context`: a `mujoco.MjrContext` (current GL context), a `mujoco.Renderer`, or None (only the
    model is updated). Returns the (n, n) heights [iy, ix] that were written, or None if the model has no field.
    """
    written = _write_model(sim, center_xy)
    if written is not None:
        _upload(sim.model, renderer_context, written[0])
    return None if written is None else written[1]


@dataclass
class WaterUpload:
    """What one GL context holds of the surface: the heights and centre it was last sent."""

    heights: np.ndarray | None = None
    center_xy: tuple[float, float] | None = None


def refresh_water_visual(sim, context: mujoco.MjrContext, center_xy, uploaded: WaterUpload) -> None:
    """`update_water_visual` that skips the GL upload (display list + texture, ~2 ms on llvmpipe) when the
    context already holds this field: a calm sea uploads once, and cameras sharing a context upload once per tick.
    The model side (heights, pose of the field and the plane) is always rewritten, so other contexts may share it."""
    written = _write_model(sim, center_xy)
    if written is None:
        return
    ids, heights, center = written
    if uploaded.center_xy == center and uploaded.heights is not None and np.array_equal(uploaded.heights, heights):
        return
    _upload(sim.model, context, ids)
    uploaded.heights, uploaded.center_xy = heights.copy(), center


def _write_model(sim, center_xy) -> tuple[WaterSurfaceIds, np.ndarray, tuple[float, float]] | None:
    model, data = sim.model, sim.data
    ids = WaterSurfaceIds.of(model)
    if ids is None:
        return None
    size_m, n = grid_axis(model, ids)
    cx, cy = snapped_center(center_xy, size_m, n)
    heights = np.asarray(sim.ocean.height_grid((cx, cy), size_m, n, sim.time), dtype=np.float64)
    low, span = float(heights.min()), max(float(np.ptp(heights)), _MIN_SPAN_M)
    model.hfield_data[model.hfield_adr[ids.hfield] : model.hfield_adr[ids.hfield] + n * n] = (
        (heights - low) / span
    ).ravel()
    model.hfield_size[ids.hfield, 2] = span
    model.geom_pos[ids.geom] = data.geom_xpos[ids.geom] = (cx, cy, low)
    if ids.plane >= 0:
        model.geom_sameframe[ids.plane] = 0  # else MuJoCo copies the world body's frame and ignores geom_pos
        model.geom_pos[ids.plane, 2] = data.geom_xpos[ids.plane, 2] = low - PLANE_GAP_M
    if ids.texture >= 0:
        _paint(model, ids.texture, heights, size_m / (n - 1), float(sim.ocean.level_m))
    return ids, heights, (cx, cy)


def _palette(levels: int = 64) -> np.ndarray:
    """Colours (levels, levels, 3) uint8 indexed by [height level, shade level]."""
    f = np.linspace(-1.0, 1.0, levels)[:, None]
    rgb = np.where(f < 0, MEAN_RGB + f * (MEAN_RGB - TROUGH_RGB), MEAN_RGB + f * (CREST_RGB - MEAN_RGB))
    shade = np.linspace(_SHADE[0], _SHADE[1], levels)
    return (np.clip(rgb[:, None, :] * shade[None, :, None], 0.0, 1.0) * 255).astype(np.uint8)


_SHADE, _LEVELS = (0.4, 1.8), 64
_PALETTE = _palette(_LEVELS)


def height_colors(heights: np.ndarray, spacing_m: float, level_m: float = 0.0) -> np.ndarray:
    """RGB (n, n, 3) uint8 of a surface: troughs dark, crests light, slopes facing a low sun brighter."""
    rel = heights - level_m
    scale = max(2.5 * float(rel.std()), 0.05)
    top = _LEVELS - 1
    level = np.clip((rel / scale + 1.0) * (0.5 * top), 0, top).astype(np.intp)
    gy, gx = np.gradient(heights, spacing_m)
    shade = (1.0 + SLOPE_SHADING * (0.8 * gx + 0.6 * gy) - _SHADE[0]) * (top / (_SHADE[1] - _SHADE[0]))
    return _PALETTE[level, np.clip(shade, 0, top).astype(np.intp)]


def _paint(
    model: mujoco.MjModel, texture_id: int, heights: np.ndarray, spacing_m: float, level_m: float
) -> None:
    n = heights.shape[0]
    if (
        model.tex_width[texture_id] != n
        or model.tex_height[texture_id] != n
        or model.tex_nchannel[texture_id] != 3
    ):
        return
    a = model.tex_adr[texture_id]
    model.tex_data[a : a + 3 * n * n] = height_colors(heights, spacing_m, level_m)[
        ::-1
    ].ravel()  # texture rows run north → south


def _surface_ids(model: mujoco.MjModel) -> WaterSurfaceIds:
    ids = WaterSurfaceIds.of(model)
    if ids is None:
        raise ValueError("the model has no water surface field")
    return ids


def drawn_heights(model: mujoco.MjModel) -> np.ndarray:
    """The surface heights (n, n) [iy, ix] the field currently draws (world z, m)."""
    ids = _surface_ids(model)
    _, n = grid_axis(model, ids)
    a = model.hfield_adr[ids.hfield]
    normalized = model.hfield_data[a : a + n * n].reshape(n, n).astype(np.float64)
    return model.geom_pos[ids.geom, 2] + normalized * model.hfield_size[ids.hfield, 2]


def grid_points(model: mujoco.MjModel) -> tuple[np.ndarray, np.ndarray]:
    """World x, y (n, n) of the field's vertices at its current position."""
    ids = _surface_ids(model)
    size_m, n = grid_axis(model, ids)
    axis = np.linspace(-0.5 * size_m, 0.5 * size_m, n)
    gx, gy = np.meshgrid(model.geom_pos[ids.geom, 0] + axis, model.geom_pos[ids.geom, 1] + axis)
    return gx, gy


def _upload(model: mujoco.MjModel, context, ids: WaterSurfaceIds) -> None:
    if context is None:
        return
    if isinstance(context, mujoco.Renderer):  # its own GL context must be current
        gl, mjr = getattr(context, "_gl_context", None), getattr(context, "_mjr_context", None)
        if gl is not None:
            gl.make_current()
        context = mjr
    if context is not None:
        mujoco.mjr_uploadHField(model, context, ids.hfield)
        if ids.texture >= 0:
            mujoco.mjr_uploadTexture(model, context, ids.texture)
