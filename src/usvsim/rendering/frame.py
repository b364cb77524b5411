"""One frame of the marine look for a simulation: daylight from `sim.look`, ocean textures, MuJoCo's lights.

Used by the camera sensors and the viewer alike: `prepare` before drawing (the GL context current), then
`apply_lights` on the MjvScene after `mjv_updateScene` and before `mjr_render`, then `MarinePass.draw`.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import NamedTuple

import mujoco
import numpy as np

from usvsim.core.overlap import Overlap
from usvsim.rendering.mips import mip_levels
from usvsim.rendering.sky import Daylight, daylight
from usvsim.rendering.surface import SurfaceData, surface_data


class SeaTextures(NamedTuple):
    data: SurfaceData
    levels: (
        tuple[list[np.ndarray], list[np.ndarray]] | None
    )  # mip levels of data.geo and data.slope (None: uploaded)


WATER_GROUP = 2  # MuJoCo's own water (height field, still-water plane): hidden when the shader draws water


def prepare(marine, sim, center_xy) -> Daylight:
    """Upload the ocean at `sim.time` and set the light of `sim.look`; returns the frame's daylight."""
    light = prepare_light(marine, sim, center_xy)
    prepare_sea(marine, sim, center_xy)
    return light


def prepare_light(marine, sim, center_xy) -> Daylight:
    """The daylight of `sim.look`, the geoms' materials and the navigation lights: what MuJoCo's geom pass needs
    (`center_xy`: where the frame is centred, for the sun's shadow map)."""
    origin = sim.scenario.world.origin
    light = daylight(sim.look, origin.latitude_deg, origin.longitude_deg)
    marine.daylight = light
    marine.center_xy = (float(center_xy[0]), float(center_xy[1]))
    marine.lamps = lamps(marine.sea_cache, sim, light)
    marine.materials = None
    if sim.look.materials:
        from usvsim.rendering.materials import Materials

        if marine.sea_cache.get("materials_model") is not sim.model:
            marine.sea_cache["materials_model"] = sim.model
            marine.sea_cache["materials"] = Materials(sim.model, list(sim.vessels), list(sim.bodies))
        marine.materials = marine.sea_cache["materials"]
    return light


def start_sea(marine, sim, center_xy, overlap: Overlap | None = None) -> Callable[[], SeaTextures]:
    """After `prepare_light`: the ocean's texture data at `sim.time` with their mip levels (`sea_textures`), made on
    `overlap`'s worker thread (mostly without the GIL: numba and numpy) while the caller goes on with MuJoCo's pass,
    or here without `overlap`; returns the call that waits for them. Until they are taken, the caller must leave
    `sim.ocean` alone (its snapshot rings are the worker's)."""
    detail, whitecap = sea_extras(marine.sea_cache, sim.ocean, sim.look)  # its cache is this thread's
    marine.mip_ratio = (
        marine.sea_cache["mip_ratio"] if detail is not None or whitecap != float("inf") else None
    )
    args = (marine.texture_key, sim.ocean, sim.time, tuple(center_xy[:2]), detail, whitecap)
    if overlap is None:
        textures = sea_textures(*args)
        return lambda: textures
    return overlap.submit(sea_textures, *args)


def sea_textures(uploaded_key, ocean, t: float, center_xy, detail, whitecap: float) -> SeaTextures:
    """The ocean's textures at time `t` (`surface_data`) and their mip levels (none when the data's key is
    `uploaded_key`, what the textures already hold). No GL."""
    data = surface_data(ocean, t, center_xy, detail, whitecap)
    levels = None if data.key == uploaded_key else (mip_levels(data.geo), mip_levels(data.slope))
    return SeaTextures(data, levels)


def prepare_sea(marine, sim, center_xy, textures: Callable[[], SeaTextures] | None = None) -> None:
    """After `prepare_light`: upload the ocean at `sim.time` (`textures`: what `start_sea` returned, else made
    here), set the light's uniforms and the wakes. Nothing in it needs MuJoCo's pass, so the viewer runs it while
    llvmpipe draws the geoms."""
    light = marine.daylight
    sea = (textures or start_sea(marine, sim, center_xy))()
    marine.upload(sea.data, sea.levels)
    marine.set_light(light, sim.look, sim.ocean.level_m)
    marine.set_rain(sim.look.rain.rate_mm_h, sim.seed)
    marine.restore()  # setting uniforms binds programs: MuJoCo's fixed-function pipeline needs none bound
    tracks = getattr(sim, "wakes", None)
    marine.wake = tracks.ribbons(sim.time, sim.look.water.wake_s) if tracks is not None else None


def lamps(cache: dict, sim, light: Daylight):
    """(NavigationLights of the model, body positions, rotations, time, intensity) when the look lights them."""
    from usvsim.rendering.lights import NavigationLights, lights_on

    elevation = float(np.degrees(np.arcsin(np.clip(light.sun_dir[2], -1.0, 1.0))))
    if not lights_on(sim.look, elevation):
        return None
    from usvsim.rendering.lights import kinematic_ships, ship_boxes

    ships = kinematic_ships(sim)
    kinematic = [] if ships is None else ships[0]
    if cache.get("lamps_model") is not sim.model:
        vessels = list(sim.vessels)
        buoys = [name for name in sim.bodies if name not in sim.vessels]
        boxes = ship_boxes(sim.model, ships) if ships is not None else []
        cache["lamps_model"], cache["lamps"] = sim.model, NavigationLights(sim.model, vessels, buoys, boxes)
    n = sim.model.nbody + len(kinematic)
    pos, rot = np.zeros((n, 3)), np.tile(np.eye(3), (n, 1, 1))
    for body in sim.bodies.values():  # the current state (MuJoCo's xpos lags a step)
        mj = sim.model.body(body.name).id
        pos[mj], rot[mj] = body.position, _rotation(body.quat)
    if ships is not None:  # traffic ships: world-body geoms placed by the traffic
        for j, (xy, yaw) in enumerate(zip(ships[1], ships[3])):
            pos[sim.model.nbody + j, :2] = xy
            rot[sim.model.nbody + j, :2, :2] = ((np.cos(yaw), -np.sin(yaw)), (np.sin(yaw), np.cos(yaw)))
    return cache["lamps"], pos, rot, sim.time, sim.look.lights.intensity


def _rotation(quat) -> np.ndarray:
    mat = np.zeros(9)
    mujoco.mju_quat2Mat(mat, np.asarray(quat, dtype=np.float64))
    return mat.reshape(3, 3)


def sea_extras(cache: dict, ocean, look):
    """(the FFT field's `DetailBand` or None, the whitecap slope) of `ocean`, made once per wave field."""
    from usvsim.rendering.detail import (
        DetailBand,
        fft_waves,
        mip_slope_ratio,
        resolved_statistics,
        whitecap_threshold,
    )

    waves = fft_waves(ocean)
    if waves is None:
        cache.pop("waves", None)
        return None, float("inf")  # a patch measures its own whitecap slope (surface.py)
    if cache.get("waves") is not waves:
        cache.update(waves=waves, whitecap=whitecap_threshold(*resolved_statistics(waves)), detail=None,
                     mip_ratio=tuple(float(r) for r in mip_slope_ratio(waves)))  # fmt: skip
    if look.water.short_waves > 0 and cache["detail"] is None:
        cache["detail"] = DetailBand(waves)
    return (cache["detail"] if look.water.short_waves > 0 else None), cache["whitecap"]


def apply_lights(
    scene: mujoco.MjvScene, light: Daylight, materials=None, center_xy=None, far: float = 0.0
) -> None:
    """Sun and sky light on MuJoCo's geoms: directional lights follow the sun, the headlight gives sky fill.
    MuJoCo's colours are display values, so the levels are display levels (noon: ambient 0.35, sun 0.6).
    With `materials` (rendering/materials.Materials) the geoms are shaded by `begin_geoms`' program instead;
    the lights still tell MuJoCo where the sun's shadow map looks from: its orthographic view (±shadowclip across,
    the drawing camera's near..far deep) from the light's position along the sun. With `center_xy` (ENU m) and the
    camera's `far` (m) the light sits `min(far / 2, 1000)` m up the sun from the still-water point there, so the map
    covers the geoms around the camera's vessel within far/2 of that point along the sun (at 1000 m up the sun
    from the origin, as without them, a camera's 400 m depth range held no geom: no shadows)."""
    sky_level = float(light.ambient @ (0.3, 0.6, 0.1))
    tint = 0.75 + 0.25 * light.ambient / max(sky_level, 1e-6)
    ambient = np.clip(min(1.1 * sky_level, 0.4) * tint, 0.0, 1.0)
    sun = np.clip(0.62 * light.sun_color, 0.0, 1.0)
    for i in range(scene.nlight):
        lamp = scene.lights[i]
        if lamp.headlight:
            lamp.ambient[:], lamp.diffuse[:], lamp.specular[:] = ambient, 0.0, 0.0
        else:
            lamp.dir[:] = -light.sun_dir
            if center_xy is not None and far > 0:
                lamp.pos[:] = (center_xy[0], center_xy[1], 0.0) + light.sun_dir * min(0.5 * far, 1000.0)
            else:
                lamp.pos[:] = light.sun_dir * 1000.0
            lamp.diffuse[:], lamp.ambient[:], lamp.specular[:] = (
                sun,
                0.0,
                (0.8 if materials is not None else 0.3) * sun,
            )


def begin_geoms(marine, scene: mujoco.MjvScene, shadows: bool) -> bool:
    """Bind the materials' program (rendering/materials.py) for MuJoCo's colour pass when the look has
    materials; call `end_geoms` after `mjr_render`. `shadows`: MuJoCo draws the sun's shadow map this pass."""
    if marine is None or marine.materials is None or marine.daylight is None:
        return False
    if marine.geom_shading is None:
        from usvsim.rendering.materials import GeomShading

        marine.geom_shading = GeomShading(marine.ctx)
    shadows = shadows and any(
        scene.lights[i].castshadow and not scene.lights[i].headlight for i in range(scene.nlight)
    )
    marine.geom_shading.begin(scene, marine.materials, marine.daylight, shadows, marine.noise_texture)
    return True


def end_geoms(marine) -> None:
    marine.geom_shading.end()


def sun_shadow_map(marine, scene: mujoco.MjvScene, ctx: mujoco.MjrContext) -> None:
    """After MuJoCo's colour pass: tell the water about the sun's shadow map MuJoCo drew in it (its texture and
    its world → map transform, `MarinePass.take_shadow_map`), or that there is none this frame."""
    if marine is None:
        return
    drawn = bool(scene.flags[mujoco.mjtRndFlag.mjRND_SHADOW]) and ctx.shadowFBO and any(
        scene.lights[i].castshadow and not scene.lights[i].headlight for i in range(scene.nlight))  # fmt: skip
    marine.take_shadow_map(int(ctx.shadowTex) if drawn else None)


def water_label(model: mujoco.MjModel) -> int:
    """The label (geom id + 1) of water pixels: the drawn surface geom, else the still-water plane, else 0."""
    for name in ("water_surface", "still_water"):
        geom = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, name)
        if geom >= 0:
            return geom + 1
    return 0


def id_color(index: int) -> tuple[float, float, float]:
    """MuJoCo's segmentation colour of scene index `index` - 1 (24-bit little-endian in R, G, B)."""
    return (index & 255) / 255.0, ((index >> 8) & 255) / 255.0, ((index >> 16) & 255) / 255.0
