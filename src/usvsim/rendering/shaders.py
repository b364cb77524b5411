"""GLSL sources of the marine passes: sky, water (and its label pass), fog over MuJoCo's geoms.

World frame ENU, metres. Radiance in display units (see sky.py). The water surface is the ocean's tiles:
label (x0, y0) → (x0 - k·Dx, y0 - k·Dy, level + s·h) with k = s·choppiness, bilinear in each tile cell,
exactly as ocean/fft_kernels.py evaluates it for the physics.
"""

COMMON = """
#version 330
uniform vec3 u_cam;
uniform vec3 u_sun_dir, u_sun_color, u_ambient, u_haze_color, u_fog_color;
uniform float u_level;
uniform sampler2D u_sky;  // sky radiance over the upper hemisphere, indexed by (x, y) / (1 + z) (no trigonometry)
uniform vec4 u_fog;  // fog extinction at sea level (1/m), fog scale height (m), haze extinction, haze height
uniform vec2 u_at_eye;  // fog and haze density at the camera's height relative to sea level: exp(-(z - level) / H)
uniform sampler2D u_noise;  // 64 x 64 random values (fixed seed): foam texture

vec3 sky(vec3 dir) {  // through the clear-air haze, with the aureole (both in the table; also in reflections)
    return texture(u_sky, dir.xy / (1.0 + max(dir.z, 0.0)) * 0.5 + 0.5).rgb;
}

float layer_depth(vec3 dir, float dist, float sigma, float height) {
    // optical depth of an exponential layer sigma·exp(-(z - level)/height) from the camera along dir
    float dz = dir.z * dist / height;
    float path = abs(dz) > 1e-4 ? (1.0 - exp(-dz)) / dz : 1.0 - 0.5 * dz;
    return sigma * dist * path;  // times the density at the eye (u_at_eye), applied by the callers
}

vec3 fogged(vec3 color, vec3 dir, float dist) {
    float fog = u_fog.x > 0.0 ? exp(-u_at_eye.x * layer_depth(dir, dist, u_fog.x, u_fog.y)) : 1.0;
    return mix(u_fog_color, color, fog);
}


vec3 display(vec3 c) { return sqrt(max(c, 0.0)); }  // linear radiance → display (MuJoCo's space), gamma 2

float noise(vec2 p) { return texture(u_noise, p / 64.0).r; }  // smooth (bilinear) value noise, period 64
"""

FULLSCREEN_VS = """
#version 330
uniform mat4 u_inv_view_proj;
uniform vec3 u_cam;
out vec3 v_ray;  // toward the pixel, unnormalized: affine in the view at a fixed depth, so interpolated exactly
void main() {
    vec2 p = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);
    vec4 w = u_inv_view_proj * vec4(p, 0.5, 1.0);
    v_ray = w.xyz / w.w - u_cam;
    gl_Position = vec4(p, 0.0, 1.0);  // depth 0: the far plane of the reversed-Z buffer
}
"""

SKY_FS = (
    COMMON
    + """
in vec3 v_ray;
out vec4 f_color;
void main() {
    vec3 dir = normalize(v_ray);
    vec3 c = sky(dir);
    float cs = dot(dir, u_sun_dir);  // the aureole is in the table
    c += u_sun_color * 40.0 * smoothstep(0.99998, 0.999992, cs) * step(0.0, dir.z);  // the disc (0.27°)
    f_color = vec4(display(fogged(c, dir, 1e6)), 1.0);
}
"""
)

FOG_FS = (
    COMMON
    + """
uniform sampler2D u_depth;
uniform vec2 u_near_far;
uniform vec2 u_viewport;
uniform vec3 u_forward;  // the view axis (unit)
in vec3 v_ray;
out vec4 f_color;
void main() {
    float raw = texelFetch(u_depth, ivec2(gl_FragCoord.xy - u_viewport), 0).r;
    float n = u_near_far.x, f = u_near_far.y;
    float d = n / (raw + (1.0 - raw) * n / f);  // reversed Z → distance along the view axis
    vec3 dir = normalize(v_ray);
    float dist = d / max(dot(dir, u_forward), 1e-3);
    float haze = exp(-u_at_eye.y * layer_depth(dir, dist, u_fog.z, u_fog.w));
    float fog = exp(-u_at_eye.x * layer_depth(dir, dist, u_fog.x, u_fog.y));
    // blended as dst·alpha + src: the geom's colour attenuated, the in-scattered light added
    f_color = vec4(display(u_fog_color) * (1.0 - fog) + display(u_haze_color) * (1.0 - haze) * fog, haze * fog);
}
"""
)

TILES = """
uniform sampler2DArray u_geo;
uniform float u_tile[5];
uniform int u_bands;
uniform int u_detail;  // 1: the last layer is the unresolved short waves (slopes only, per pixel)
uniform vec4 u_surface;  // height scale s, displacement scale k, still-water level, texel count N
uniform vec4 u_patch;    // patch mode: centre x, y, half size (0: periodic tiles), unused
vec2 tile_uv_m(vec2 label, float tile_m) {  // texel centres on the tile vertices
    if (u_patch.z > 0.0) return (label - u_patch.xy) / (2.0 * u_patch.z) + 0.5;
    return label / tile_m + 0.5 / u_surface.w;
}
vec2 tile_uv(vec2 label, int b) { return tile_uv_m(label, u_tile[b]); }
"""

WATER_VS = (  # run once per frame with transform feedback: the displaced grid, shared by the colour and label passes
    COMMON
    + """
uniform mat4 u_inv_view_proj;
uniform vec2 u_cell;     // view width of one grid cell at unit distance (m/m), far distance of the grid (m)
uniform sampler2DArray u_slope;
"""
    + TILES
    + """
in vec2 in_ndc;          // where the vertex lies in the view (normalized device coordinates)
out vec3 v_world;
out vec2 v_label;
out float v_spacing;
out vec4 v_atm;          // fog and haze along the view ray: colour · v_atm.x + v_atm.yzw (smooth: per vertex)
out vec2 v_slope;        // ∂h/∂x, ∂h/∂y of the bands (unscaled)
out vec3 v_jac;          // ∂Dx/∂x, ∂Dy/∂y, ∂Dx/∂y (∂Dx/∂y, small, is left out)
void main() {
    vec4 p = u_inv_view_proj * vec4(in_ndc, 0.5, 1.0);
    vec3 dir = normalize(p.xyz / p.w - u_cam);
    float h = max(u_cam.z - u_surface.z, 0.05);
    float horiz = max(length(dir.xy), 1e-6);
    float reach = dir.z < -1e-6 ? min(h / -dir.z * horiz, u_cell.y) : u_cell.y;
    vec2 label = u_cam.xy + dir.xy / horiz * reach;
    float along = reach / horiz;  // distance along the ray
    float spacing = along * u_cell.x / max(-dir.z, 0.02);
    vec3 disp = vec3(0.0);
    v_slope = vec2(0.0);
    v_jac = vec3(0.0);
    int bands = u_bands - u_detail;
    for (int b = 0; b < bands; b++) {  // sampled per vertex, filtered to the grid's cell (grid.py)
        float lod = log2(max(spacing * u_surface.w / u_tile[b], 1.0));
        vec3 uvw = vec3(tile_uv(label, b), b);
        vec4 g = textureLod(u_geo, uvw, lod);
        disp += vec3(g.y, g.z, g.x);
        if (b < bands - 1 || bands == 1) {  // the shortest band's slopes: per pixel (WATER_FS)
            vec4 s = textureLod(u_slope, uvw, lod);
            v_slope += s.xy;
            v_jac += vec3(s.zw, 0.0);
        }
    }
    if (u_patch.z > 0.0) {
        vec2 r = abs(label - u_patch.xy) / u_patch.z;
        disp *= 1.0 - smoothstep(0.8, 1.0, max(r.x, r.y));
    }
    v_world = vec3(label - u_surface.y * disp.xy, u_surface.z + u_surface.x * disp.z);
    v_label = label;
    v_spacing = spacing;
    vec3 to_eye = u_cam - v_world;
    float dist = length(to_eye);
    vec3 view = -to_eye / max(dist, 1e-6);
    float haze = exp(-u_at_eye.y * layer_depth(view, dist, u_fog.z, u_fog.w));
    float fog = u_fog.x > 0.0 ? exp(-u_at_eye.x * layer_depth(view, dist, u_fog.x, u_fog.y)) : 1.0;
    v_atm = vec4(haze * fog, u_haze_color * (1.0 - haze) * fog + u_fog_color * (1.0 - fog));
}
"""
)

WATER_DRAW_VS = """
#version 330
uniform mat4 u_view_proj;
in vec3 in_world;
in vec2 in_label;
in float in_spacing;
in vec4 in_atm;
in vec2 in_slope;
in vec3 in_jac;
out vec2 v_label;
out vec3 v_world;
out float v_spacing;
out vec4 v_atm;
out vec2 v_slope;
out vec3 v_jac;
void main() {
    v_slope = in_slope;
    v_jac = in_jac;
    v_world = in_world;
    v_label = in_label;
    v_spacing = in_spacing;
    v_atm = in_atm;
    gl_Position = u_view_proj * vec4(in_world, 1.0);
}
"""

LABEL_VS = """
#version 330
uniform mat4 u_view_proj;
in vec3 in_world;
void main() { gl_Position = u_view_proj * vec4(in_world, 1.0); }
"""

WATER_FS = (
    COMMON
    + TILES
    + """
uniform sampler2DArray u_slope;
uniform sampler2D u_depth;
uniform vec3 u_water;
uniform vec4 u_look;     // foam, glint, render choppiness for whitecaps, time (s)
uniform vec2 u_sea;      // gain on the short-wave slopes, resolved slope above which the surface breaks
uniform float u_mip_ratio[8];  // the shortest band's rms slope per mip level over level 0's (whitecaps)
uniform vec2 u_tile_fs;  // u_tile[] of the shortest band drawn per pixel and of the short-wave layer (a uniform array
                         // indexed by a variable costs llvmpipe a load per pixel)
uniform sampler2D u_wake;  // wakes' foam, top-down (rendering/wakes.py)
uniform vec4 u_wake_region;  // its corner x, y, side (m); w = 0: no wake
uniform float u_pixel;   // view width of one pixel at unit distance
uniform float u_clarity; // distance (m) in the water over which a geom behind the surface fades by e (0: opaque)
uniform vec2 u_near_far;
uniform vec2 u_viewport;
uniform int u_pierce_taps;  // 8 (marine.PIERCE_TAPS). A constant count would be unrolled, and llvmpipe runs every
                            // statement for every pixel; a loop it leaves once no pixel of the block is in it
in vec2 v_label;
in vec3 v_world;
in float v_spacing;
in vec4 v_atm;
in vec2 v_slope;
in vec3 v_jac;
out vec4 f_color;
#ifdef SUN_SHADOW
uniform sampler2DShadow u_sun_shadow;  // MuJoCo's shadow map (reversed Z, compare GEQUAL)
uniform mat4 u_shadow_matrix;  // world → its texture coordinates (marine.MarinePass._use_shadow_map)
#endif
#ifdef RAIN
uniform vec3 u_rain;  // chance that a ring cell holds a drop per cycle (rendering/rain.py), the seed, strength
const float RING_CELL = 0.2;     // m: a cell holds at most one drop's ring at a time
const float RING_PERIOD = 0.4;   // s: a cell's cycle (its phase from the hash)
const float RING_SPEED = 0.25;   // m/s: how fast a ring spreads (capillary-gravity waves of a few cm)
const float RING_WIDTH = 0.012;  // m
const float RING_LIFE = 0.36;    // s: it reaches 0.09 m = RING_CELL / 2 - ring cells nearer than the 2 x 2 suffice
uint hash3(uvec3 v) {  // integer hash (deterministic on any machine: no float sin-hash)
    v = v * 1664525u + 1013904223u;
    v.x += v.y * v.z; v.y += v.z * v.x; v.z += v.x * v.y;
    v ^= v >> 16u;
    v.x += v.y * v.z; v.y += v.z * v.x; v.z += v.x * v.y;
    return v.x ^ v.y ^ v.z;
}
float u01(uint h) { return float(h >> 8u) * (1.0 / 16777216.0); }
vec2 rain_rings(vec2 p, float t, float footprint) {
    // slopes of the rings that drops leave where they hit: each cell of RING_CELL holds, once per cycle of
    // RING_PERIOD (its phase and the drop's place from the hash of the cell, the cycle and the seed), a drop with
    // chance u_rain.x; its ring spreads at RING_SPEED and fades over RING_LIFE. Rings narrower than a pixel fade out.
    float w = max(RING_WIDTH, footprint);
    float seen = u_rain.z * (1.0 - smoothstep(RING_WIDTH, 3.0 * RING_WIDTH, footprint)) * RING_WIDTH / w;
    vec2 base = floor(p / RING_CELL - 0.5);
    vec2 slope = vec2(0.0);
    for (int j = 0; j < 2; j++) {
        for (int i = 0; i < 2; i++) {
            vec2 cell = base + vec2(i, j);
            uvec3 key = uvec3(ivec3(ivec2(cell), int(u_rain.y)));
            float phase = u01(hash3(key));
            float cycle = t / RING_PERIOD + phase;
            float n = floor(cycle);
            uint h = hash3(key ^ uvec3(uint(int(n)) * 2654435761u, 40503u, 977u));
            float age = (cycle - n) * RING_PERIOD;
            vec2 c = (cell + vec2(u01(h * 747796405u + 1u), u01(h * 2891336453u + 7u))) * RING_CELL;
            vec2 d = p - c;
            float r = length(d);
            float x = r - RING_SPEED * age;
            float life = clamp(1.0 - age / RING_LIFE, 0.0, 1.0);
            float on = step(u01(h), u_rain.x) * life * life;
            // a ring of height exp(-x²/w²): its slope along the radius -2x/w² · exp(-x²/w²), scaled to w
            slope += on * (-2.0 * x / w) * exp(-x * x / (w * w)) * d / max(r, 1e-4);
        }
    }
    return seen * slope;
}
#endif

void main() {
    vec2 zs = v_slope;
    vec3 jac = v_jac;
    float footprint = length(u_cam - v_world) * u_pixel;
    int bands = u_bands - u_detail;
    vec2 zr = zs;  // whitecaps: where the shortest resolved waves are steepest
    float filtered = 1.0;  // their rms slope at the mip level sampled, over the unfiltered one
    float resolved = 1.0;  // whitecaps per pixel while a pixel spans few texels; beyond, too small to show
    if (bands > 1) {  // the shortest band per pixel, filtered by the footprint across the ray: distant glitter
        int b = bands - 1;
        float lod_s = log2(max(footprint * u_surface.w / u_tile_fs.x, 1.0));
        int level = min(int(lod_s + 0.5), 7);  // LINEAR_MIPMAP_NEAREST: the nearest level
        float ratio = u_mip_ratio[0];  // u_mip_ratio[level] by selects: an index that varies costs a load per pixel
        for (int i = 1; i < 8; i++) ratio = level == i ? u_mip_ratio[i] : ratio;
        filtered = max(ratio, 0.05);
        resolved = 1.0 - smoothstep(3.0, 5.0, lod_s);
        vec4 s = textureLod(u_slope, vec3(tile_uv_m(v_label, u_tile_fs.x), b), lod_s);
        zs += s.xy;
        jac += vec3(s.zw, 0.0);
        zr = s.xy;
    }
    if (u_detail == 1) {  // the short waves, where the pixel resolves them (beyond: only the glint's roughness)
        int b = u_bands - 1;
        float lod = log2(max(footprint * u_surface.w / u_tile_fs.y, 1.0));
        if (lod < log2(u_surface.w) - 1.0)
            zs += u_sea.x * textureLod(u_slope, vec3(tile_uv_m(v_label, u_tile_fs.y), b), lod).xy;
    }
    float k = u_surface.y, kf = max(u_look.z, k);
    vec3 tx = vec3(1.0 - k * jac.x, -k * jac.z, u_surface.x * zs.x);
    vec3 ty = vec3(-k * jac.z, 1.0 - k * jac.y, u_surface.x * zs.y);
#ifdef RAIN
    vec2 rings = rain_rings(v_label, u_look.w, footprint);  // on any sea, a flat one too (not scaled by the ramp)
    tx.z += rings.x;
    ty.z += rings.y;
#endif
    vec3 n = normalize(cross(tx, ty));
    float det = (1.0 - kf * jac.x) * (1.0 - kf * jac.y) - kf * kf * jac.z * jac.z;

    vec3 to_cam = u_cam - v_world;
    float dist = length(to_cam);
    vec3 v = to_cam / dist;
    if (dot(n, v) < 0.02) n = normalize(n + (0.02 - dot(n, v)) * v);
    vec3 r = reflect(-v, n);
    float cos_v = clamp(dot(n, v), 0.0, 1.0);
    float m = 1.0 - cos_v, m2 = m * m;
    float fresnel = 0.02 + 0.98 * m2 * m2 * m;  // Schlick
    vec3 reflected = sky(vec3(r.xy, abs(r.z)));
    // sun glint: a Beckmann-like lobe widened with distance (unresolved ripples)
    float rough = 0.015 + 0.06 * clamp(v_spacing / 4.0, 0.0, 1.0);
    vec3 h = normalize(v + u_sun_dir);
    float nh = max(dot(n, h), 0.0);
    float nh2 = max(nh * nh, 1e-4), nh4 = max(nh2 * nh2, 1e-8);
    float t2 = (1.0 - nh2) / nh2;
    float lobe = exp(-t2 / (rough * rough)) / (3.1416 * rough * rough * nh4);
    float wake = 0.0;  // wake foam (the top-down texture of rendering/wakes.py)
#ifdef MARKS
    if (u_wake_region.w > 0.0) {
        vec2 uv = (v_label - u_wake_region.xy) / u_wake_region.z;
        if (all(greaterThan(uv, vec2(0.0))) && all(lessThan(uv, vec2(1.0)))) wake = texture(u_wake, uv).r;
    }
#endif
    float lit = 1.0;  // in a geom's shadow: no direct sun
#ifdef SUN_SHADOW  // MuJoCo's shadow map of the sun (the geoms' meshes as drawn), at the surface point itself
    lit = 1.0 - 0.92 * (1.0 - textureProj(u_sun_shadow, u_shadow_matrix * vec4(v_world, 1.0)));
#endif
    vec3 glint = u_sun_color * u_look.y * fresnel * lobe * 0.25 * step(0.0, u_sun_dir.z) * lit;
    // body colour: sky and sun light scattered back from inside, brighter through thin crests toward the sun
    float scatter = 0.5 + 0.5 * max(dot(-v.xy, u_sun_dir.xy), 0.0) * clamp(1.0 - cos_v, 0.0, 1.0);
    vec3 body = u_water * (u_ambient * 1.2 + u_sun_color * max(u_sun_dir.z, 0.0) * scatter * 0.6 * lit);
    vec3 c = mix(body, reflected, fresnel) + glint;
    // foam: whitecaps where the choppy surface folds, broken up by noise; and along hulls at the waterline
    float grain = noise(v_label * 1.7 + u_look.w * 0.3);
    float gust = 0.7 + 0.6 * noise(v_label * 0.23 - u_look.w * 0.05);  // breaking is patchy: crests break here and there
    float steep = resolved * smoothstep(0.8, 1.0, gust * u_surface.x * length(zr) / (u_sea.y * filtered));  // the steepest faces: Monahan's share
    // a crest breaks in streaks, not as a sheet: without this breakup a gust blob (the noise's bilinear texel, ~4 m)
    // over a steep patch near the camera saturated into one flat white polygon
    steep *= smoothstep(0.35, 0.8, noise(v_label * 3.1 + vec2(0.37, 0.61)) * 0.6 + grain * 0.4);
    float whitecap = max(smoothstep(0.6, 0.1, det), steep) * (0.55 + 0.45 * grain);
#ifdef GEOM
    float raw = texelFetch(u_depth, ivec2(gl_FragCoord.xy - u_viewport), 0).r;
#else
    float raw = 0.0;  // no geom behind the water here (the stencil the fog pass marks): the same bytes, no depth reads
#endif
    float n0 = u_near_far.x, f0 = u_near_far.y;
    float behind = raw > 0.0 ? n0 / (raw + (1.0 - raw) * n0 / f0) - n0 / (gl_FragCoord.z + (1.0 - gl_FragCoord.z) * n0 / f0) : 1e9;
#ifdef GEOM
    float contact = (1.0 - smoothstep(0.0, 0.35 + 0.002 * dist, behind)) * (0.6 + 0.4 * grain);
#else
    float contact = 0.0;  // what the line above gives with nothing behind (behind = 1e9: smoothstep 1, exactly)
#endif
#ifdef GEOM
    float z_here = n0 / (gl_FragCoord.z + (1.0 - gl_FragCoord.z) * n0 / f0);
    vec2 dz = vec2(dFdx(z_here), dFdy(z_here));  // the water's depth at a neighbour: the surface's plane here
    if (contact > 0.0) {  // only where the geom pierces the surface nearby (a waterline), not over a submerged top
        float r = clamp(0.8 / max(dist * u_pixel, 1e-6), 2.0, 32.0);  // 0.8 m on screen, in pixels
        float pierce = 0.0;
        for (int i = 0; i < u_pierce_taps; i++) {  // 8; a uniform: see u_pierce_taps
            vec2 d = (i < 4 ? 1.0 : 0.5) * r * vec2(i % 2 == 0 ? 1.0 - float(i & 2) : 0.0, i % 2 == 1 ? 1.0 - float(i & 2) : 0.0);
            float rn = texelFetch(u_depth, clamp(ivec2(gl_FragCoord.xy - u_viewport + d), ivec2(0), textureSize(u_depth, 0) - 1), 0).r;
            if (rn > 0.0 && n0 / (rn + (1.0 - rn) * n0 / f0) < z_here + dot(dz, d)) pierce = 1.0;
            if (pierce > 0.0) break;  // found: the block leaves the loop once all its pixels have
        }
        contact *= pierce;
    }
#endif
#ifdef MARKS
    if (wake > 0.0)
        contact = max(contact, wake * smoothstep(0.15, 0.65, 0.5 * noise(v_label * 0.9) + 0.5 * grain));
#endif
    float foam = clamp(u_look.x * max(whitecap, contact), 0.0, 1.0);
    vec3 foam_light = vec3(0.85) * (u_ambient * 2.5 + u_sun_color * max(u_sun_dir.z, 0.0) * lit);
    foam *= 1.0 - smoothstep(1000.0, 6000.0, dist);
    c = mix(c, foam_light, foam);
    // clear shallow water: the geom behind the surface (seabed, a hull's underwater part) shows through what
    // is not reflected or foam, fading with the path in the water (blended over it: alpha = 1 - that share)
    float seen = raw > 0.0 && u_clarity > 0.0 ? (1.0 - fresnel) * (1.0 - foam) * exp(-behind / u_clarity) : 0.0;
    f_color = vec4(display(c * v_atm.x + v_atm.yzw), 1.0 - seen * v_atm.x);
}
"""
)

# The water with the wakes' texture (u_wake) compiled in, for the triangles whose labels can fall in its
# region; WATER_FS (no MARKS) for the others. llvmpipe runs an `if` body for every pixel whatever the condition
# (its shaders are SIMD over a 4 x 4 block, with no branch on a uniform), so code left out is the only code skipped.
WATER_MARKS_FS = WATER_FS.replace("#version 330\n", "#version 330\n#define MARKS\n", 1)


def water_fs(marks: bool, rain: bool = False, sun_shadow: bool = False, geom: bool = False) -> str:
    """WATER_FS with optional parts compiled in: the wakes' texture (MARKS), the rings of raindrops (RAIN), MuJoCo's
    shadow map of the sun (SUN_SHADOW), the geoms' depth behind the surface (GEOM: hull foam at the waterline, clear
    water; for the pixels where a geom lies behind the water, the stencil bit GEOM_BIT the fog pass marks). Without
    them the programs run none of their code."""
    flags = (("MARKS", marks), ("RAIN", rain), ("SUN_SHADOW", sun_shadow), ("GEOM", geom))
    defines = "".join(f"#define {name}\n" for name, on in flags if on)
    return WATER_FS.replace("#version 330\n", "#version 330\n" + defines, 1)

LABEL_FS = """
#version 330
uniform vec3 u_id_color;
out vec4 f_color;
void main() { f_color = vec4(u_id_color, 1.0); }
"""
