"""Navigation lights at dusk, night and in fog: COLREG lights on vessels, flashing lights on buoys.

Each vessel shows (COLREG Rule 21, power-driven, under way): a white masthead light over 225° (dead ahead to
22.5° abaft either beam), sidelights over 112.5° each (red to port, green to starboard) and a white sternlight
over 135° aft. Placed on the vessel's visual bounding box (body frame: x forward, y to port, z up): masthead
above the top, sidelights at the beam forward of midships, the sternlight at the transom. Buoys whose paint is
red, green or yellow flash that colour (IALA flashing: Fl 2.5 s, 0.8 s on; each buoy's phase from its index).

A light is seen only from inside its arc (soft 1° edges), dimmed by the fog and haze along the line of sight,
and drawn as a point source the camera smears: a core whose size follows the lamp's size in pixels (at least a
pixel) and a glow, additive, depth-tested against geoms and water but writing no depth (depth and labels stay
exact; the label pass never draws lights). Over water each light also leaves a reflection, a vertical streak
below it drawn only on the water (stencil).
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

WHITE, RED, GREEN, YELLOW = (1.0, 0.95, 0.85), (1.0, 0.08, 0.04), (0.1, 1.0, 0.45), (1.0, 0.75, 0.1)
FLASH_PERIOD_S, FLASH_ON_S = 2.5, 0.8
LAMP_M = 0.12  # lens size of a small craft's lantern
REFERENCE_M = 120.0  # distance at which a clear-air light's glow has unit strength

VS = """
#version 330
uniform mat4 u_view_proj;
uniform vec3 u_cam;
uniform vec4 u_fog;
uniform vec2 u_at_eye;
uniform float u_focal_px;
uniform float u_level;
uniform int u_reflect;
in vec3 in_pos;
in vec3 in_color;
out vec3 v_color;
out float v_core, v_glow, v_amp;
float layer_depth(vec3 dir, float dist, float sigma, float height) {
    float dz = dir.z * dist / height;
    float path = abs(dz) > 1e-4 ? (1.0 - exp(-dz)) / dz : 1.0 - 0.5 * dz;
    return sigma * dist * path;
}
void main() {
    vec3 pos = u_reflect == 1 ? vec3(in_pos.xy, 2.0 * u_level - in_pos.z) : in_pos;
    vec3 to = pos - u_cam;
    float dist = max(length(to), 0.1);
    vec3 dir = to / dist;
    float t = exp(-u_at_eye.y * layer_depth(dir, dist, u_fog.z, u_fog.w));
    if (u_fog.x > 0.0) t *= exp(-u_at_eye.x * layer_depth(dir, dist, u_fog.x, u_fog.y));
    float strength = t * pow(REF_M / dist, 2.0);  // irradiance at the lens, 1 at the reference distance
    float seen = smoothstep(0.0005, 0.01, strength);  // fades out into the fog and the distance
    v_color = in_color * seen * (u_reflect == 1 ? 0.35 : 1.0);
    v_core = max(LAMP_R * u_focal_px / dist, 0.6);  // the lamp's radius in pixels (at least about a pixel)
    v_glow = 1.0 + 1.2 * log2(1.0 + strength);  // the lens' glow around a bright lamp (pixels)
    v_amp = 0.35 * strength / (1.0 + strength);
    gl_PointSize = min(2.0 * (3.0 * v_core + 5.0 * v_glow) + 2.0, 128.0) * (u_reflect == 1 ? 1.5 : 1.0);
    vec4 clip = u_view_proj * vec4(pos - 0.3 * dir, 1.0);  // a little toward the eye: not hidden by its own lantern
    gl_Position = clip;
}
""".replace("REF_M", repr(REFERENCE_M)).replace("LAMP_R", repr(0.5 * LAMP_M))

FS = """
#version 330
uniform int u_reflect;
in vec3 v_color;
in float v_core, v_glow, v_amp;
out vec4 f_color;
void main() {
    float size = 0.5 / max(fwidth(gl_PointCoord.x), 1e-4);  // half the sprite, pixels
    vec2 px = (gl_PointCoord - 0.5) * 2.0 * size;
    if (u_reflect == 1) px *= vec2(1.0, 0.3);  // a streak down the water
    float r = length(px);
    float core = exp(-r * r / (2.0 * v_core * v_core));
    float glow = v_amp * exp(-r / v_glow) * (1.0 - smoothstep(0.5, 1.0, length(gl_PointCoord - 0.5) * 2.0));
    vec3 c = v_color * (1.5 * core + glow);
    f_color = vec4(min(sqrt(c), vec3(1.0)), 1.0);
}
"""


def _arc_visibility(bearing: np.ndarray, start: float, end: float) -> np.ndarray:
    """1 inside the arc [start, end] of relative bearings (rad, counter-clockwise from ahead), fading over 1°
    beyond it (sidelights both show from dead ahead)."""
    mid, half = 0.5 * (start + end), 0.5 * (end - start)
    off = np.abs((bearing - mid + math.pi) % (2 * math.pi) - math.pi)
    return np.clip((half - off) / math.radians(1.0) + 1.0, 0.0, 1.0)


ARCS = {  # body-frame arc (start, end) of relative bearing, counter-clockwise from ahead (port positive)
    "masthead": (-math.radians(112.5), math.radians(112.5)),
    "port": (0.0, math.radians(112.5)),
    "starboard": (-math.radians(112.5), 0.0),
    "stern": (math.radians(112.5), math.radians(247.5)),
}


class NavigationLights:
    """The lamps of a model's vessels and buoys (body-frame positions, colours, arcs), posed per frame."""

    def __init__(self, model: mujoco.MjModel, vessels, buoys, ships=()):
        """`ships`: the traffic's kinematic ships' boxes (lo, hi) in their own frames; their lamps' bodies are
        numbered model.nbody + j (`world` takes their poses after the bodies')."""
        lamps = []  # (body, local position, colour, arc name or None, flash phase or None)
        boxes = [(mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, name), None, None) for name in vessels]
        boxes += [(model.nbody + j, lo, hi) for j, (lo, hi) in enumerate(ships)]
        for body, lo, hi in boxes:
            if lo is None:
                lo, hi = _visual_box(model, body)
            if lo is None or hi is None:
                continue
            length, beam = hi[0] - lo[0], hi[1] - lo[1]
            deck = lo[2] + 0.8 * (hi[2] - lo[2])  # high on the hull: seen over its deck from above
            fore = lo[0] + 0.6 * length
            lamps += [
                (body, (fore, 0.5 * (lo[1] + hi[1]), hi[2] + 0.1), WHITE, "masthead", None),
                (body, (fore, hi[1] + 0.02, deck), RED, "port", None),
                (body, (fore, lo[1] - 0.02, deck), GREEN, "starboard", None),
                (body, (lo[0] - 0.02, 0.5 * (lo[1] + hi[1]), deck), WHITE, "stern", None),
            ]
            del beam
        for i, name in enumerate(buoys):
            body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, name)
            lo, hi = _visual_box(model, body)
            color = _paint(model, body)
            if lo is None or hi is None or color is None:
                continue
            top = (0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), hi[2] + 0.05)
            lamps.append((body, top, color, None, (0.9 * i) % FLASH_PERIOD_S))
        self.lamps = lamps
        self.bodies = np.array([lamp[0] for lamp in lamps], dtype=np.int64)
        self.local = np.array([lamp[1] for lamp in lamps], dtype=np.float64).reshape(-1, 3)
        self.colors = np.array([lamp[2] for lamp in lamps], dtype=np.float64).reshape(-1, 3)

    def world(self, body_pos: np.ndarray, body_rot: np.ndarray, eye: np.ndarray, t: float, intensity: float):
        """(n, 6) float32: world position and colour·visibility of each lamp seen from `eye` at time t, with the
        bodies' poses `body_pos` (nbody, 3) and `body_rot` (nbody, 3, 3) by MuJoCo body id (world ENU)."""
        if not len(self.lamps):
            return np.zeros((0, 6), np.float32)
        rot = body_rot[self.bodies]
        pos = body_pos[self.bodies] + np.einsum("nij,nj->ni", rot, self.local)
        to_eye = eye[None, :] - pos
        local = np.einsum("nji,nj->ni", rot, to_eye)  # the eye in each body's frame
        bearing = np.arctan2(local[:, 1], local[:, 0])
        seen = np.ones(len(self.lamps))
        for i, (_, _, _, arc, phase) in enumerate(self.lamps):
            if arc is not None:
                seen[i] = _arc_visibility(bearing[i : i + 1], *ARCS[arc])[0]
            elif phase is not None:
                seen[i] = float((t + phase) % FLASH_PERIOD_S < FLASH_ON_S)
        out = np.concatenate([pos, self.colors * (seen * intensity)[:, None]], axis=1)
        return out[seen > 0].astype(np.float32)


def kinematic_ships(world):
    """(names, positions (n, 2), velocities (n, 2), yaws (n,)) of the traffic's kinematic ships at the world's
    time (ENU, m, m/s, rad; their tracks evaluated, nothing in the traffic changed), or None without any."""
    traffic = getattr(world, "traffic", None)
    fleet = getattr(traffic, "fleet", None)
    if fleet is None or not len(fleet.kinematic):
        return None
    n = len(fleet.kinematic)
    pos, vel, yaw = np.zeros((n, 2)), np.zeros((n, 2)), np.zeros(n)
    fleet.table.evaluate(world.clock.now_ns / 1e9, pos, vel, yaw)
    return [fleet.names[k] for k in fleet.kinematic], pos, vel, yaw


def ship_boxes(model: mujoco.MjModel, ships) -> list:
    """Per kinematic ship of `ships` (`kinematic_ships`, where the geoms are now): its geoms' bounds (lo, hi) in
    its own frame (x forward, z up from the waterline)."""
    from usvsim.world.builder import kinematic_geoms

    names, geoms, owner = kinematic_geoms(model)
    out = []
    for name, p, yaw in zip(ships[0], ships[1], ships[3]):
        j = names.index(name) if name in names else -1
        pts = []
        c, s = math.cos(yaw), math.sin(yaw)
        for g in geoms[owner == j]:
            mat = np.zeros(9)
            mujoco.mju_quat2Mat(mat, model.geom_quat[g])
            world = (model.geom_aabb[g, :3] + _SIGNS * model.geom_aabb[g, 3:]) @ mat.reshape(3, 3).T + model.geom_pos[g]
            d = world[:, :2] - p
            pts.append(np.c_[c * d[:, 0] + s * d[:, 1], -s * d[:, 0] + c * d[:, 1], world[:, 2]])
        if pts:
            allp = np.concatenate(pts)
            out.append((allp.min(axis=0), allp.max(axis=0)))
        else:
            out.append((None, None))
    return out


_SIGNS = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], dtype=np.float64)


def _visual_box(model: mujoco.MjModel, body: int):
    """Body-frame bounds (lo, hi) of the visual geoms (group 1) of `body`, or (None, None)."""
    corners = []
    signs = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], dtype=np.float64)
    for g in np.flatnonzero((model.geom_bodyid == body) & (model.geom_group == 1)):
        center, half = model.geom_aabb[g, :3], model.geom_aabb[g, 3:]
        mat = np.zeros(9)
        mujoco.mju_quat2Mat(mat, model.geom_quat[g])
        local = center[None, :] + signs * half[None, :]
        corners.append(local @ mat.reshape(3, 3).T + model.geom_pos[g])
    if not corners:
        return None, None
    pts = np.concatenate(corners)
    return pts.min(axis=0), pts.max(axis=0)


def _paint(model: mujoco.MjModel, body: int):
    """The light colour of a buoy from its paint: red, green or yellow (None: no light)."""
    geoms = np.flatnonzero((model.geom_bodyid == body) & (model.geom_group == 1))
    if not len(geoms):
        return None
    r, g, b = model.geom_rgba[geoms[0], :3]
    if r > 0.6 and g > 0.6 and b < 0.4:
        return YELLOW
    if r > 0.5 and g < 0.35:
        return RED
    if g > 0.5 and r < 0.35:
        return GREEN
    return None


def lights_on(look, sun_elevation_deg: float) -> bool:
    """Whether the look's navigation lights are lit: always, never, or (auto) from sunset to sunrise and in
    restricted visibility (COLREG Rule 20: fog under 2 km)."""
    mode = look.lights.navigation
    if mode != "auto":
        return mode == "on"
    fog = look.fog.visibility_m
    return sun_elevation_deg < 0.0 or (fog is not None and fog < 2000.0)


class LightPass:
    """The point-sprite program of the lamps and their reflections, on the marine passes' moderngl context."""

    def __init__(self, ctx):
        self.ctx = ctx
        self.prog = ctx.program(vertex_shader=VS, fragment_shader=FS)
        self.buffer = ctx.buffer(reserve=6 * 4 * 64)
        self.vao = ctx.vertex_array(self.prog, [(self.buffer, "3f 3f", "in_pos", "in_color")])

    def draw(self, lamps: np.ndarray, uniforms: dict) -> None:
        """Additive, after the water and the sky: direct lamps depth-tested, reflections on water pixels only."""
        from OpenGL import GL

        if not len(lamps):
            return
        data = np.ascontiguousarray(lamps, dtype=np.float32).tobytes()
        if len(data) > self.buffer.size:
            self.buffer.orphan(len(data))
        self.buffer.write(data)
        for name, value in uniforms.items():
            if name in self.prog:
                self.prog[name].value = value
        ctx = self.ctx
        GL.glEnable(GL.GL_PROGRAM_POINT_SIZE)
        GL.glDepthMask(GL.GL_FALSE)
        ctx.enable(ctx.BLEND)
        ctx.blend_func = ctx.ONE, ctx.ONE
        # reflections: on the water (stencil bit 1 from the water pass, marine.WATER_BIT), whatever the depth
        ctx.disable(ctx.DEPTH_TEST)
        GL.glEnable(GL.GL_STENCIL_TEST)
        GL.glStencilFunc(GL.GL_EQUAL, 1, 1)
        GL.glStencilOp(GL.GL_KEEP, GL.GL_KEEP, GL.GL_KEEP)
        self.prog["u_reflect"].value = 1
        self.vao.render(mode=0, vertices=len(lamps))
        GL.glDisable(GL.GL_STENCIL_TEST)
        ctx.enable(ctx.DEPTH_TEST)
        ctx.depth_func = ">="
        self.prog["u_reflect"].value = 0
        self.vao.render(mode=0, vertices=len(lamps))
        ctx.disable(ctx.BLEND)
        GL.glDepthMask(GL.GL_TRUE)
        GL.glDisable(GL.GL_PROGRAM_POINT_SIZE)

    def release(self) -> None:
        for obj in (self.vao, self.buffer, self.prog):
            obj.release()
