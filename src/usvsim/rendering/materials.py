"""Materials of the geoms in the shader look: a small physically based set, shaded per pixel.

Each visual geom gets one class, once per model, from what it is: on a vessel, dark grey parts are rubber
(inflatable pontoons, fenders), light grey or white parts metal (frames, superstructure), the rest painted hull;
floating bodies that are not vessels are buoy plastic; static geoms by their paint (the object library's `wood`,
`concrete`, `grey`) are wood, concrete and metal; anything else is paint. A class is a metallic level and a
roughness (`CLASSES`); the base colour is the geom's own.

MuJoCo still draws the geoms (its display lists, poses, textures, shadow map, its depth and ids), but with a
GLSL program of the compatibility profile bound during its colour pass (`GeomShading.begin`/`end`), which
replaces the fixed-function lighting: Lambert diffuse plus a GGX specular lobe (Smith-Schlick masking, Schlick
Fresnel) under the sun, and the sky as a hemisphere (diffuse) and a rough reflection (specular), lit in linear
light (MuJoCo's colours are display values; gamma 2, as for the water). The program reads each geom's class, texture mode and
mark from the material values MuJoCo passes per geom (`shininess` and `specular`, written into the scene's geoms
per frame; the model and MuJoCo's plain look are untouched). Procedural marks, made in the shader from the geom's
own frame (no image assets): two-digit hull numbers on both sides of each vessel's hulls, near the bow, and a
white band round each buoy. With the sun's shadows on, MuJoCo draws the sun in a second, additive pass with its
shadow map; the program tells that pass by MuJoCo's fog colour (set to transparent black only there) and adds
the sun's terms through the same shadow-map lookup MuJoCo makes. The vertex transform is `ftransform()`, the
fixed-function one, so the depth image is unchanged; ids are drawn in a pass without the program.
"""

from __future__ import annotations

import mujoco
import numpy as np

CLASSES = {  # name: (code, metallic, roughness)
    "paint": (1, 0.0, 0.35),
    "metal": (2, 1.0, 0.4),
    "rubber": (3, 0.0, 0.75),
    "plastic": (4, 0.0, 0.3),
    "wood": (5, 0.0, 0.8),
    "concrete": (6, 0.0, 0.9),
}
MAX_MARKS = 24  # geoms with a hull number or a buoy band
TEX_NONE, TEX_GEN, TEX_COORD = 0, 1, 2  # MuJoCo's 2D texture: none, object-linear texgen, the mesh's coordinates


def _close(rgba, ref) -> bool:
    return bool(np.max(np.abs(np.asarray(rgba[:3]) - np.asarray(ref[:3]))) < 0.02)


def geom_classes(model: mujoco.MjModel, vessels, bodies) -> dict[int, str]:
    """Geom id → class name for the visual geoms (group 1) of `model`."""
    from usvsim.config.objects import COLORS

    vessel_ids = {model.body(n).id for n in vessels}
    floating_ids = {model.body(n).id for n in bodies}
    out = {}
    for g in np.flatnonzero(model.geom_group == 1):
        rgba, body = model.geom_rgba[g], int(model.geom_bodyid[g])
        grey = float(np.ptp(rgba[:3])) < 0.06
        if body in vessel_ids:
            cls = (
                "rubber"
                if grey and rgba[:3].max() < 0.3
                else "metal"
                if grey and rgba[:3].min() > 0.5
                else "paint"
            )
        elif body in floating_ids:
            cls = "plastic"
        elif _close(rgba, COLORS["wood"]):
            cls = "wood"
        elif _close(rgba, COLORS["concrete"]):
            cls = "concrete"
        elif _close(rgba, COLORS["grey"]):
            cls = "metal"
        else:
            cls = "paint"
        out[int(g)] = cls
    return out


def _geom_rotation(model: mujoco.MjModel, g: int) -> np.ndarray:
    mat = np.zeros(9)
    mujoco.mju_quat2Mat(mat, model.geom_quat[g])
    return mat.reshape(3, 3)  # geom frame → body frame


def mark_geoms(model: mujoco.MjModel, vessels, bodies) -> list[tuple[int, np.ndarray, np.ndarray, float]]:
    """(geom id, basis (3, 3): columns forward, up, port side in the geom's frame, centre in the geom's frame,
    kind: 0 a buoy band, n > 0 hull number n) of the geoms that carry a mark, at most `MAX_MARKS`.

    Hulls: on each vessel, the visual geoms at least half the volume of its largest and longest fore and aft;
    buoys: the round visual geoms (sphere, ellipsoid, cylinder, capsule) of floating bodies that are not vessels."""
    out = []
    vessel_ids = [model.body(n).id for n in vessels]
    buoy_ids = {model.body(n).id for n in bodies} - set(vessel_ids)
    visual = np.flatnonzero(model.geom_group == 1)
    frames = {}
    for g in visual:
        rot = _geom_rotation(model, int(g))
        basis = rot.T @ np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]]).T  # body x, z, y in the geom
        half = np.abs(basis.T) @ model.geom_aabb[g, 3:]  # half lengths along forward, up, side
        frames[int(g)] = (basis, model.geom_aabb[g, :3].copy(), half)
    for number, body in enumerate(vessel_ids, start=1):
        geoms = [int(g) for g in visual if model.geom_bodyid[g] == body]
        volume = {g: float(np.prod(frames[g][2])) for g in geoms}
        if not geoms:
            continue
        biggest = max(volume.values())
        for g in geoms:
            half = frames[g][2]
            if volume[g] >= 0.5 * biggest and half[0] >= half.max() - 1e-9:
                out.append((g, frames[g][0], frames[g][1], float(number)))
    round_types = {int(mujoco.mjtGeom.mjGEOM_SPHERE), int(mujoco.mjtGeom.mjGEOM_ELLIPSOID),
                   int(mujoco.mjtGeom.mjGEOM_CYLINDER), int(mujoco.mjtGeom.mjGEOM_CAPSULE)}  # fmt: skip
    for g in visual:
        if int(model.geom_bodyid[g]) in buoy_ids and int(model.geom_type[g]) in round_types:
            out.append((int(g), frames[int(g)][0], frames[int(g)][1], 0.0))
    return out[:MAX_MARKS]


def _texture_modes(model: mujoco.MjModel) -> np.ndarray:
    """Per geom: whether MuJoCo maps a 2D texture on it (TEX_GEN; TEX_COORD is decided per scene geom)."""
    modes = np.zeros(model.ngeom, dtype=np.int64)
    for g in range(model.ngeom):
        mat = int(model.geom_matid[g])
        if mat < 0:
            continue
        tex = int(model.mat_texid[mat, int(mujoco.mjtTextureRole.mjTEXROLE_RGB)])
        if tex >= 0 and int(model.tex_type[tex]) == int(mujoco.mjtTexture.mjTEXTURE_2D):
            modes[g] = TEX_GEN
    return modes


class Materials:
    """Per-geom class codes and marks of a model, written into a scene's geoms for `GeomShading`."""

    def __init__(self, model: mujoco.MjModel, vessels, bodies):
        self.classes = geom_classes(model, vessels, bodies)
        self.code = np.full(model.ngeom, -1, dtype=np.int64)
        for g, cls in self.classes.items():
            self.code[g] = CLASSES[cls][0]
        self.texture = _texture_modes(model)
        self.marks = mark_geoms(model, vessels, bodies)
        self.mark_of = np.zeros(model.ngeom, dtype=np.int64)  # 1-based index into `marks`, 0: none
        for i, (g, *_) in enumerate(self.marks):
            self.mark_of[g] = i + 1
        # geom frame → mark frame (rows: forward, up, side), and the mark frame's origin in the geom frame
        self._basis_t = np.array([m[1].T for m in self.marks]).reshape(-1, 3, 3)
        self._centre = np.array([m[2] for m in self.marks]).reshape(-1, 3)
        self._info = np.array([[*(np.abs(m[1].T) @ model.geom_aabb[m[0], 3:]), m[3]] for m in self.marks])
        self._info = self._info.reshape(-1, 4)

    def apply(self, scene: mujoco.MjvScene) -> np.ndarray:
        """Write class/texture codes (shininess) and mark indices (specular) into the scene's geoms; returns
        (MAX_MARKS, 4, 4) world → mark-frame matrices (metres) of the marked geoms found in the scene."""
        geom_type, culled = mujoco.mjtObj.mjOBJ_GEOM, mujoco.mjtGeom.mjGEOM_NONE  # (culled: not drawn, rendering/cull.py)
        world_to_mark = np.zeros((MAX_MARKS, 4, 4), dtype=np.float32)
        for geom in scene.geoms[: scene.ngeom]:
            if geom.type == culled or geom.objtype != geom_type:
                continue
            g = geom.objid
            if not 0 <= g < len(self.code) or self.code[g] < 0:
                continue
            texture = self.texture[g]
            if texture and geom.texcoord:
                texture = TEX_COORD
            geom.shininess = (self.code[g] + 8 * texture + 0.5) / 128.0  # MuJoCo passes 128 × shininess
            mark = int(self.mark_of[g])
            geom.specular = mark / 64.0
            if mark:
                rot = np.asarray(geom.mat, dtype=np.float64).reshape(3, 3)  # geom frame → world
                m = np.eye(4)
                m[:3, :3] = self._basis_t[mark - 1] @ rot.T
                m[:3, 3] = -m[:3, :3] @ np.asarray(geom.pos, dtype=np.float64) - self._basis_t[mark - 1] @ self._centre[mark - 1]
                world_to_mark[mark - 1] = m
        return world_to_mark


GEOM_VS = """
#version 330 compatibility
out vec3 v_eye;
out vec3 v_normal;
out vec4 v_color;
out vec2 v_uv;
out vec4 v_shadow;
flat out vec3 v_material;  // shininess code, mark, emission level
uniform mat4 u_mark[24];   // world → mark frame (m): forward, up, port
uniform vec4 u_mark_info[24];  // half lengths (forward, up, side), kind (0 band, n hull number)
flat out mat4 v_mark;      // this geom's u_mark[mark] and u_mark_info[mark]: picked per vertex, as an index that
flat out vec4 v_mark_info; // varies per pixel costs llvmpipe a load per pixel and value
void main() {
    vec4 eye = gl_ModelViewMatrix * gl_Vertex;
    v_eye = eye.xyz;
    v_normal = gl_NormalMatrix * gl_Normal;
    v_color = gl_Color;
    float code = floor(gl_FrontMaterial.shininess);
    float tex = floor(code / 8.0);
    v_uv = tex == 2.0 ? gl_MultiTexCoord0.st
         : vec2(dot(gl_ObjectPlaneS[0], gl_Vertex), dot(gl_ObjectPlaneT[0], gl_Vertex));
    v_shadow = gl_TextureMatrix[1] * vec4(dot(gl_EyePlaneS[1], eye), dot(gl_EyePlaneT[1], eye),
                                          dot(gl_EyePlaneR[1], eye), dot(gl_EyePlaneQ[1], eye));
    v_material = vec3(code, floor(gl_FrontMaterial.specular.r * 64.0 + 0.5), 0.0);
    int mark = int(v_material.y) - 1;
    bool marked = mark >= 0 && mark < 24;
    v_mark = marked ? u_mark[mark] : mat4(0.0);
    v_mark_info = marked ? u_mark_info[mark] : vec4(0.0);
    gl_Position = ftransform();
}
"""

GEOM_FS = """
#version 330 compatibility
uniform sampler2D u_texture;       // MuJoCo's 2D texture of the geom (unit 0)
uniform sampler2DShadow u_shadow_map;  // MuJoCo's shadow map (unit 1)
uniform sampler2D u_noise;         // the marine pass' noise (its unit)
uniform mat4 u_eye_to_world;
uniform vec3 u_sun_dir;    // toward the sun, world
uniform vec3 u_sun;        // sun irradiance on a face toward it (linear, display-referred)
uniform vec3 u_sky;        // sky irradiance on an upward face (linear)
uniform vec3 u_ground;     // light from below (the sea) on a downward face (linear)
uniform int u_shadows;     // MuJoCo draws the sun in a second pass with its shadow map
flat in mat4 v_mark;       // world → mark frame (m): forward, up, port (GEOM_VS: u_mark)
flat in vec4 v_mark_info;  // half lengths (forward, up, side), kind (0 band, n hull number)
in vec3 v_eye;
in vec3 v_normal;
in vec4 v_color;
in vec2 v_uv;
in vec4 v_shadow;
flat in vec3 v_material;
out vec4 f_color;

const float PI = 3.14159265;
const vec2 CLASS[7] = vec2[7](vec2(0.0, 0.6), vec2(0.0, 0.35), vec2(1.0, 0.4), vec2(0.0, 0.75), vec2(0.0, 0.3),
                              vec2(0.0, 0.8), vec2(0.0, 0.9));  // metallic, roughness (materials.CLASSES)

float vnoise(vec3 p) {  // smooth value noise from the marine pass' 64² noise texture (bilinear): two planes
    return 0.5 * (texture(u_noise, (p.xy + 0.37 * p.z) / 64.0).r + texture(u_noise, (p.yz + vec2(17.0, 5.0)) / 64.0).r);
}

float box(vec2 p, vec2 lo, vec2 hi) { return step(lo.x, p.x) * step(p.x, hi.x) * step(lo.y, p.y) * step(p.y, hi.y); }

float digit(vec2 p, int d) {  // seven segments in the unit cell [0, 0.6] x [0, 1]; 1 on a segment
    const int SEG[10] = int[10](0x3F, 0x06, 0x5B, 0x4F, 0x66, 0x6D, 0x7D, 0x07, 0x7F, 0x6F);  // a..g bits
    int s = SEG[d];
    float t = 0.11, w = 0.6;
    float on = 0.0;
    on = max(on, float((s >> 0) & 1) * box(p, vec2(0.0, 1.0 - t), vec2(w, 1.0)));          // a: top
    on = max(on, float((s >> 1) & 1) * box(p, vec2(w - t, 0.5), vec2(w, 1.0)));            // b: top right
    on = max(on, float((s >> 2) & 1) * box(p, vec2(w - t, 0.0), vec2(w, 0.5)));            // c: bottom right
    on = max(on, float((s >> 3) & 1) * box(p, vec2(0.0, 0.0), vec2(w, t)));                // d: bottom
    on = max(on, float((s >> 4) & 1) * box(p, vec2(0.0, 0.0), vec2(t, 0.5)));              // e: bottom left
    on = max(on, float((s >> 5) & 1) * box(p, vec2(0.0, 0.5), vec2(t, 1.0)));              // f: top left
    on = max(on, float((s >> 6) & 1) * box(p, vec2(0.0, 0.5 - 0.5 * t), vec2(w, 0.5 + 0.5 * t)));  // g: middle
    return on;
}

vec3 to_linear(vec3 c) { return c * c; }  // display → linear: gamma 2, as the water's display()
float pow5(float x) { float x2 = x * x; return x2 * x2 * x; }

void main() {
    int code = int(v_material.x);
    int cls = code % 8;
    int tex = code / 8;
    bool shadow_pass = gl_Fog.color.a == 0.0;  // MuJoCo's second, additive pass for the sun (black fog)
    vec3 base = v_color.rgb;
    if (tex > 0) base *= texture(u_texture, v_uv).rgb;
    vec3 world = (u_eye_to_world * vec4(v_eye, 1.0)).xyz;
    vec3 n = normalize(mat3(u_eye_to_world) * v_normal);
    vec3 v = normalize(mat3(u_eye_to_world) * -v_eye);
    if (!gl_FrontFacing) n = -n;
    vec2 mr = CLASS[clamp(cls, 0, 6)];
    float metal = mr.x, rough = mr.y;
    // one noise lookup per pixel (llvmpipe runs every branch): wood grain along the planks, concrete speckle,
    // brushed metal's roughness
    vec3 scale = cls == 5 ? vec3(0.7, 0.7, 9.0) : vec3(cls == 6 ? 7.0 : 11.0);
    float nz = vnoise(world * scale);
    if (cls == 5) base *= 0.8 + 0.4 * nz;
    else if (cls == 6) { base *= 0.86 + 0.26 * nz; rough = 0.8 + 0.15 * nz; }
    else if (cls == 2) rough += 0.12 * (nz - 0.5);
    int mark = int(v_material.y) - 1;
    if (mark >= 0 && mark < 24) {
        vec3 p = (v_mark * vec4(world, 1.0)).xyz;  // forward, up, port (m)
        vec4 info = v_mark_info;
        vec3 nl = mat3(v_mark) * n;
        float light = dot(base, vec3(0.3, 0.6, 0.1));
        if (info.w > 0.0) {  // hull number on both sides, near the bow, reading from bow to stern as seen
            float h = min(1.1 * info.y, 0.3 * info.x);
            float side = sign(p.z);
            vec2 q = vec2(-side * (p.x - 0.45 * info.x), p.y - 0.05 * info.y) / h + vec2(0.65, 0.5);
            int number = int(info.w);
            float on = digit(q, (number / 10) % 10) + digit(q - vec2(0.8, 0.0), number % 10);
            on *= step(0.4, abs(nl.z));  // on the sides only
            base = mix(base, light < 0.35 ? vec3(0.92) : vec3(0.06), clamp(on, 0.0, 1.0));
        } else {  // buoy: a white retro-reflective band above the waterline, a dark band at it
            float z = p.y / max(info.y, 1e-3);
            base = mix(base, vec3(0.9), step(0.25, z) * step(z, 0.5));
            base = mix(base, base * 0.35, step(-0.12, z) * step(z, 0.05));
        }
    }
    vec3 albedo = to_linear(base);
    rough = clamp(rough, 0.05, 1.0);
    float a = rough * rough, a2 = a * a;
    vec3 f0 = mix(vec3(0.04), albedo, metal);
    float nv = max(dot(n, v), 1e-3);
    // the sky: a hemisphere (diffuse) and its rough reflection (specular), and the geom's own emission
    float up = 0.5 + 0.5 * n.z;
    vec3 irradiance = mix(u_ground, u_sky, up);
    vec3 r = reflect(-v, n);
    vec3 env = mix(u_ground, u_sky, smoothstep(-0.2, 0.2, r.z)) * mix(1.6, 1.0, rough);
    vec3 fe = f0 + (max(vec3(1.0 - rough), f0) - f0) * pow5(1.0 - nv);  // Schlick, roughness-aware
    vec3 ambient = (1.0 - fe) * (1.0 - metal) * albedo * irradiance + fe * env * (1.0 - 0.7 * rough);
    if (!shadow_pass) ambient += to_linear(gl_FrontMaterial.emission.rgb);
    // the sun: Lambert diffuse and a GGX lobe with Smith-Schlick masking and Schlick's Fresnel
    vec3 l = u_sun_dir;
    float nl = max(dot(n, l), 0.0);
    vec3 h = normalize(l + v);
    float nh = max(dot(n, h), 0.0), vh = max(dot(v, h), 0.0);
    float dd = nh * nh * (a2 - 1.0) + 1.0;
    float d = a2 / (PI * dd * dd);
    float k = (rough + 1.0) * (rough + 1.0) / 8.0;
    float g = nv / (nv * (1.0 - k) + k) * nl / (nl * (1.0 - k) + k);
    vec3 f = f0 + (1.0 - f0) * pow5(1.0 - vh);
    vec3 spec = d * g * f / max(4.0 * nv * nl, 1e-4);
    vec3 sun = ((1.0 - f) * (1.0 - metal) * albedo + PI * spec) * u_sun * nl;
    vec3 display_ambient = sqrt(ambient);
    if (shadow_pass) {  // MuJoCo adds this pass (blend ONE, ONE) onto the first: add what the sun adds on display
        float lit = textureProj(u_shadow_map, v_shadow);
        f_color = vec4(sqrt(ambient + sun * lit) - display_ambient, 1.0);  // alpha 1: MuJoCo alpha-tests this pass
    } else {
        f_color = vec4(u_shadows == 1 ? display_ambient : sqrt(ambient + sun), v_color.a);
    }
}
"""


class GeomShading:
    """The materials program on a moderngl context that shares MuJoCo's GL context (marine.ctx)."""

    def __init__(self, ctx):
        self.ctx = ctx
        self.program = ctx.program(vertex_shader=GEOM_VS, fragment_shader=GEOM_FS)
        from usvsim.rendering.marine import TEXTURE_UNITS

        for name, unit in (("u_texture", 0), ("u_shadow_map", 1), ("u_noise", TEXTURE_UNITS["u_noise"])):
            if name in self.program:
                self.program[name].value = unit  # pyright: ignore[reportAttributeAccessIssue]

    def begin(self, scene: mujoco.MjvScene, materials: Materials, light, shadows: bool, noise=None) -> None:
        """Write the codes into `scene` and bind the program for MuJoCo's colour pass (`end` after it).
        `noise`: the marine pass' noise texture, bound on its unit."""
        from OpenGL import GL

        from usvsim.rendering.marine import TEXTURE_UNITS

        if noise is not None:
            noise.use(TEXTURE_UNITS["u_noise"])
            GL.glActiveTexture(GL.GL_TEXTURE0)  # MuJoCo binds its textures on the active unit

        from usvsim.rendering.marine import camera_matrices

        marks = materials.apply(scene)
        cam = mujoco.mjv_averageCamera(scene.camera[0], scene.camera[1])  # mono: the eyes' mean, as mjr_render
        _, eye, _, _ = camera_matrices(cam, 4, 3)
        fwd = np.array(cam.forward, dtype=np.float64)
        fwd /= np.linalg.norm(fwd)
        right = np.cross(fwd, np.array(cam.up, dtype=np.float64))
        right /= np.linalg.norm(right)
        up = np.cross(right, fwd)
        eye_to_world = np.eye(4)
        eye_to_world[:3, 0], eye_to_world[:3, 1], eye_to_world[:3, 2], eye_to_world[:3, 3] = right, up, -fwd, eye
        sun, sky = levels(light)
        ground = sky * 0.25  # the sea below reflects little
        values = {
            "u_eye_to_world": eye_to_world.T.astype("f4").tobytes(),
            "u_sun_dir": tuple(float(x) for x in light.sun_dir),
            "u_sun": tuple(float(x) for x in sun),
            "u_sky": tuple(float(x) for x in sky),
            "u_ground": tuple(float(x) for x in ground),
            "u_shadows": int(shadows),
            "u_mark": np.ascontiguousarray(marks.transpose(0, 2, 1)).astype("f4").tobytes(),
            "u_mark_info": _info_bytes(materials),
        }
        prog = self.program
        for name, value in values.items():
            if name not in prog:
                continue
            if isinstance(value, bytes):
                prog[name].write(value)  # pyright: ignore[reportAttributeAccessIssue]
            else:
                prog[name].value = value  # pyright: ignore[reportAttributeAccessIssue]
        GL.glUseProgram(prog.glo)

    @staticmethod
    def end() -> None:
        from OpenGL import GL

        GL.glUseProgram(0)

    def release(self) -> None:
        self.program.release()


def _info_bytes(materials: Materials) -> bytes:
    info = np.zeros((MAX_MARKS, 4), dtype=np.float32)
    info[: len(materials._info)] = materials._info
    return info.tobytes()


def levels(light) -> tuple[np.ndarray, np.ndarray]:
    """(sun, sky) irradiance levels in linear light, matched to the fixed-function look of `frame.apply_lights`
    (display levels: sky fill up to 0.4, sun 0.62 × its colour): a face the sun lights fully and an unlit upward
    face come out as bright as they were there; between them the sum is linear in cos θ (as light is)."""
    sky_level = float(light.ambient @ (0.3, 0.6, 0.1))
    tint = 0.75 + 0.25 * light.ambient / max(sky_level, 1e-6)
    ambient = np.clip(min(1.1 * sky_level, 0.4) * tint, 0.0, 1.0)
    sun = np.clip(0.62 * light.sun_color, 0.0, 1.0) * (1.0 if light.sun_dir[2] > -0.05 else 0.0)
    sky = ambient**2
    return np.maximum((ambient + sun) ** 2 - sky, 0.0), sky
