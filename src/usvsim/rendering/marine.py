"""The marine passes drawn after MuJoCo's geoms into the same framebuffer: fog on geoms, sky, water.

MuJoCo draws the geoms with reversed Z (clip depth 0..1, depth 1 at the near plane, cleared to 0,
GL_GEQUAL). The water uses the same projection, so depth testing against the geoms is exact and the depth
image that MuJoCo reads back holds the water too. Water beyond the far plane is depth-clamped onto it
(drawn far to near) and reads back as "nothing within range". Order per frame: displace the grid once
(transform feedback; the label pass reuses it) → copy the geoms' depth → fog over geoms → water (foam where a
hull lies just behind the surface; it marks the stencil) → sky where neither was drawn. The label pass draws
the same displaced grid in one flat id colour.
"""

from __future__ import annotations

import ctypes
from collections.abc import Callable
from typing import TYPE_CHECKING, cast

import numpy as np

from usvsim.rendering import shaders
from usvsim.rendering.detail import foam_noise
from usvsim.rendering.gl import attach_current
from usvsim.rendering.grid import CELL_PX, FAR_M, screen_grid
from usvsim.rendering.mips import mip_levels
from usvsim.rendering.sky import Daylight, hazy_sky_table
from usvsim.rendering.surface import SurfaceData

if TYPE_CHECKING:
    import moderngl

GL_DEPTH_CLAMP, GL_GEQUAL = 0x864F, 0x0206
TEXTURE_UNITS = {"u_geo": 5, "u_slope": 6, "u_depth": 7, "u_sky": 8, "u_noise": 9, "u_wake": 10,
                 "u_sun_shadow": 11}  # above MuJoCo's
FOAM_CHOPPINESS = 2.0  # whitecaps where a surface this choppy would fold (the physics may use less)
HAZE_HEIGHT_M = 500.0
SKY_TEXELS = 256  # the sky table with the horizon haze baked in: the haze band above the horizon spans texels
FEEDBACK = ("v_world", "v_label", "v_spacing", "v_atm", "v_slope", "v_jac")  # per vertex: 3+2+1+4+2+3 floats
FEEDBACK_BYTES = 60
POINTS = 0x0000
FOG_SCISSOR = True
PIERCE_TAPS = 8  # depth samples around a waterline pixel (WATER_FS: does the geom pierce the surface nearby?)
WATER_BIT, GEOM_BIT = 1, 2  # stencil: the water is the nearest surface drawn here; a geom was drawn here (fog pass)


class MarinePass:
    """Programs, the water grid and the ocean textures on one GL context (create with it current)."""

    def __init__(self, cell_px: float | Callable[[int], float] | None = None):
        """`cell_px`: the water grid's cell size in pixels, a number or a function of the image height (default
        `grid.CELL_PX`; the viewer passes `grid.view_cell_px`)."""
        from OpenGL import GL

        self._pixel_store = {
            k: int(GL.glGetIntegerv(k)) for k in (GL.GL_PACK_ALIGNMENT, GL.GL_UNPACK_ALIGNMENT)
        }
        self.ctx = ctx = attach_current()
        self.sky = _bind_samplers(
            ctx.program(vertex_shader=shaders.FULLSCREEN_VS, fragment_shader=shaders.SKY_FS)
        )
        self.fog = _bind_samplers(
            ctx.program(vertex_shader=shaders.FULLSCREEN_VS, fragment_shader=shaders.FOG_FS)
        )
        self.surface = _bind_samplers(ctx.program(vertex_shader=shaders.WATER_VS, varyings=FEEDBACK))
        self.water = _bind_samplers(  # with the wakes' texture; `plain` without: see _water
            ctx.program(vertex_shader=shaders.WATER_DRAW_VS, fragment_shader=shaders.WATER_MARKS_FS)
        )
        self.plain = _bind_samplers(
            ctx.program(vertex_shader=shaders.WATER_DRAW_VS, fragment_shader=shaders.WATER_FS)
        )
        self.full = _bind_samplers(  # marks and the geoms' depth: where a geom lies behind the water (see _water)
            ctx.program(vertex_shader=shaders.WATER_DRAW_VS, fragment_shader=shaders.water_fs(True, geom=True))
        )
        self._waters = (self.water, self.plain, self.full)  # every water program made (the rain's too, once made)
        self._water_uniforms: dict = {}  # their uniforms' last values (a program made later gets them all)
        # the water's programs with optional parts compiled in (shaders.water_fs): (rain rings, the sun's shadow map)
        # → (with marks, plain, over geoms), made on first use; (False, False) is (self.water, self.plain, self.full)
        self._variants: dict[tuple[bool, bool], tuple] = {(False, False): (self.water, self.plain, self.full)}
        self._variant_vaos: dict[tuple, tuple] = {}  # (width, height, rain, shadow) → their vertex arrays
        self._raining = False  # this frame draws the programs with the rain's rings
        self._shadow_tex: int | None = None  # MuJoCo's shadow map of the sun this frame (GL texture), or none
        self.center_xy = (0.0, 0.0)  # where the frame is centred (frame.prepare): the sun's shadow map looks there
        self._set_waters(u_pierce_taps=PIERCE_TAPS)
        self.label = ctx.program(vertex_shader=shaders.LABEL_VS, fragment_shader=shaders.LABEL_FS)
        self.fullscreen = {p: ctx.vertex_array(p, []) for p in (self.sky, self.fog)}
        self._grids: dict[
            tuple[int, int], tuple
        ] = {}  # viewport size → (water vao, label vao, cell, feedback, buffers)
        self._surface_key = None  # what the displaced grid in the feedback buffer was computed for
        self._cell_px = CELL_PX if cell_px is None else cell_px
        self._grid_rows: dict[tuple[int, int], np.ndarray] = {}  # viewport size → NDC of each row's end vertices
        self._grid_ndc: dict[tuple[int, int], np.ndarray] = {}  # viewport size → NDC of the vertices (rows, cols, 2)
        self._plain_vaos: dict[tuple[int, int], moderngl.VertexArray] = {}  # viewport size → water without marks
        self._full_vaos: dict[tuple[int, int], moderngl.VertexArray] = {}  # viewport size → water with the depth
        self._region = (0.0, 0.0, 1.0, 0.0)  # the wakes' texture region this frame (w = 0: none)
        self._occupied = np.zeros((1, 1), bool)  # cells of that region where its texels may not be clear (WakePass)
        self._marks = np.zeros((0, 2), np.int64)  # runs of quads whose labels can fall in that region
        # (n, 8, 3) corners of boxes that hold every geom MuJoCo drew this frame (cull.FrustumCull.boxes), set by the
        # caller before `draw`; None: unknown (the water over geoms is drawn with every quad)
        self.geom_boxes: np.ndarray | None = None
        self._over_geoms: np.ndarray | None = None  # runs of quads that may cover a geom's pixel (None: all)
        self._columns: dict[tuple[int, int], int] = {}  # viewport size → vertices per grid row
        self._rows = (0, 0)  # the grid's vertex rows displaced and drawn this frame (first, count)
        self._geo: moderngl.TextureArray | None = None
        self._slope: moderngl.TextureArray | None = None
        self._depth = self._periodic = None
        self._sky = ctx.texture((SKY_TEXELS, SKY_TEXELS), 4, dtype="f4")  # RGB + 1: llvmpipe fetches 16-byte texels faster
        self._sky.repeat_x = self._sky.repeat_y = False
        noise = foam_noise()  # fixed: same bytes every run
        self._noise = ctx.texture((64, 64), 1, noise.tobytes(), dtype="f4")
        self._key, self._sky_key, self._fbos = None, None, {}
        self.daylight = None
        self.sea_cache: dict = {}  # per wave field: the short-wave band and the whitecap slope (frame.py)
        self.lamps: tuple | None = None  # navigation lights of this frame (frame.lamps), drawn by `self._lights`
        self.materials = None  # the geoms' materials (rendering/materials.py), drawn by frame.begin_geoms
        self.geom_shading = None  # their program (materials.GeomShading), made on first use
        self.mip_ratio = None  # rms slope of the shortest band per mip level / level 0 (detail.mip_slope_ratio)
        self._lights = None
        self.wake = None  # the wakes' ribbons of this frame (frame.prepare), drawn by `self._wakes`
        self._wakes = None
        self._whitecap_slope, self._short_waves = 1e6, 0.0

    def _grid(self, width: int, height: int) -> tuple:
        if (width, height) not in self._grids:
            ctx = self.ctx
            size = self._cell_px(height) if callable(self._cell_px) else self._cell_px
            vertices, indices, cell = screen_grid(width, height, size)
            vbo, ibo = ctx.buffer(vertices.tobytes()), ctx.buffer(indices.tobytes())
            out = ctx.buffer(reserve=len(vertices) * FEEDBACK_BYTES)  # the displaced vertices, once per frame
            feedback = ctx.vertex_array(self.surface, [(vbo, "2f", "in_ndc")])
            water, plain, full = (ctx.vertex_array(prog, [(out, "3f 2f 1f 4f 2f 3f", *(f"in_{v[2:]}" for v in FEEDBACK))],
                                  index_buffer=ibo, index_element_size=4)
                                  for prog in (self.water, self.plain, self.full))  # fmt: skip
            self._plain_vaos[(width, height)], self._full_vaos[(width, height)] = plain, full
            label = ctx.vertex_array(self.label, [(out, f"3f {FEEDBACK_BYTES - 12}x", "in_world")],
                                     index_buffer=ibo, index_element_size=4)  # fmt: skip
            self._grids[(width, height)] = (water, label, cell, feedback, out, vbo, ibo)
            self._columns[(width, height)] = columns = int(np.count_nonzero(vertices[:, 1] == vertices[0, 1]))
            self._grid_ndc[(width, height)] = vertices.reshape(-1, columns, 2).astype(np.float64)
            self._grid_rows[(width, height)] = self._grid_ndc[(width, height)][:, [0, -1]]
        return self._grids[(width, height)]

    def _visible_rows(self, size: tuple[int, int], view_proj: np.ndarray, eye: np.ndarray) -> tuple[int, int]:
        """(first, count) vertex rows of the grid to displace and draw: the rows above the horizon, all of whose
        rays miss the sea, are skipped but one (it closes the surface onto the far circle). They lie on that
        circle, folded onto the horizon in the image: thousands of slivers that cover no pixel but cost llvmpipe
        a 4 x 4 block of fragment shading each. Rows are top first; a row's end vertices decide (the rays between
        them rise above the horizon wherever both ends do: d.z - ε|d| is concave along the row)."""
        ends = self._grid_rows[size]  # (rows, 2 ends, 2) NDC
        inv = np.linalg.inv(view_proj)
        p = ends[..., :1] * inv[:, 0] + ends[..., 1:] * inv[:, 1] + 0.5 * inv[:, 2] + inv[:, 3]
        d = p[..., :3] / p[..., 3:] - eye
        sky = (d[..., 2] > 1e-3 * np.linalg.norm(d, axis=-1)).all(axis=1)  # well above: the shader caps these rays
        leading = int(np.argmin(sky)) if not sky.all() else len(sky)
        first = max(leading - 1, 0)
        return first, len(sky) - first

    def _marks_runs(self, size: tuple[int, int], view_proj: np.ndarray, eye: np.ndarray) -> np.ndarray:
        """Runs [start, stop) of quads (their index in the grid's storage: row by row, top first) that may hold a
        pixel where the wakes' texture is not clear (the cells of WakePass.occupied), from the labels of their corners
        as WATER_VS computes them (the still-water point of the vertex's ray, capped at FAR_M): a fragment's label
        interpolates its triangle's, so it lies in their bounding box. (n, 2) int, in the stored order; empty without
        wakes, or when none shows (wakes.foam_bound: a hull too slow, or its track too old)."""
        occupied = self._occupied
        if self._region[3] <= 0.0 or not occupied.any():
            return np.zeros((0, 2), np.int64)
        label = self._labels(size, view_proj, eye)
        corners = (label[:-1, :-1], label[1:, :-1], label[:-1, 1:], label[1:, 1:])
        lo, hi = np.minimum.reduce(corners), np.maximum.reduce(corners)  # per quad (rows - 1, cols - 1, 2)
        margin = 1.0  # m: float32 on the GPU, and more than enough
        cells = occupied.shape[0]
        corner, cell = np.array(self._region[:2]), self._region[2] / cells
        first = np.floor((lo - margin - corner) / cell)  # the cells each quad's box (and margin) overlaps
        last = np.floor((hi + margin - corner) / cell)
        inside = np.all((last >= 0) & (first < cells), axis=-1)  # labels outside the region read no wake
        first, last = np.clip(first, 0, cells - 1).astype(np.intp), np.clip(last, 0, cells - 1).astype(np.intp)
        total = np.zeros((cells + 1, cells + 1), np.int64)  # occupied cells below and left of each corner
        total[1:, 1:] = occupied.cumsum(axis=0).cumsum(axis=1)
        x0, y0, x1, y1 = first[..., 0], first[..., 1], last[..., 0] + 1, last[..., 1] + 1
        hit = inside & (total[y1, x1] - total[y0, x1] - total[y1, x0] + total[y0, x0] > 0)
        return _runs(hit)

    def _labels(self, size: tuple[int, int], view_proj: np.ndarray, eye: np.ndarray) -> np.ndarray:
        """(rows, cols, 2) the grid vertices' labels as WATER_VS computes them: the still-water point of the vertex's
        ray, capped at FAR_M (m, world)."""
        ndc = self._grid_ndc[size]
        inv = np.linalg.inv(view_proj)
        p = ndc[..., :1] * inv[:, 0] + ndc[..., 1:] * inv[:, 1] + 0.5 * inv[:, 2] + inv[:, 3]
        d = p[..., :3] / p[..., 3:] - eye
        d /= np.linalg.norm(d, axis=-1, keepdims=True)
        h = max(eye[2] - self._level_m, 0.05)
        horiz = np.maximum(np.hypot(d[..., 0], d[..., 1]), 1e-6)
        reach = np.where(d[..., 2] < -1e-6, np.minimum(h / np.maximum(-d[..., 2], 1e-6) * horiz, FAR_M), FAR_M)
        return eye[:2] + d[..., :2] / horiz[..., None] * reach[..., None]

    def _geom_images(self, size: tuple[int, int], view_proj: np.ndarray, near: float):
        """(x0, y0, x1, y1) per box of `geom_boxes`: the pixel box (viewport pixels, bottom row 0) of its image, each
        (n,); None where they are unknown or a box reaches behind the eye (its image is not bounded)."""
        if self.geom_boxes is None:
            return None
        clip = self.geom_boxes @ view_proj[:, :3].T + view_proj[:, 3]
        if not (clip[..., 3] > 0.5 * near).all():
            return None
        x = (clip[..., 0] / clip[..., 3] + 1.0) * 0.5 * size[0]
        y = (clip[..., 1] / clip[..., 3] + 1.0) * 0.5 * size[1]
        return x.min(axis=1), y.min(axis=1), x.max(axis=1), y.max(axis=1)

    def _over_geoms_runs(self, size: tuple[int, int], view_proj: np.ndarray, near: float, out) -> np.ndarray | None:
        """Runs [start, stop) of quads (as `_marks_runs`) that may cover a pixel of a geom (`geom_boxes`), for the
        water program over geoms (see `_water`); None: every quad. From the displaced grid this frame (the transform
        feedback's `out`, read back) and the geoms' boxes: a triangle (or a box) wholly in front of the eye covers
        only pixels inside the box around its corners' images; quads whose box meets no geom's box (in cells of
        8 pixels, a pixel of margin) cannot reach a geom's pixel, and the stencil keeps them off all others."""
        if self.geom_boxes is None:
            return None
        width, height = size
        cell = 8
        cols, rows = -(-width // cell), -(-height // cell)

        def image(points: np.ndarray):  # window pixels of world points, and whether they lie well in front
            clip = points @ view_proj[:, :3].T + view_proj[:, 3]
            w = clip[..., 3]
            front = w > 0.5 * near
            w = np.where(front, w, 1.0)
            return (clip[..., 0] / w + 1.0) * 0.5 * width, (clip[..., 1] / w + 1.0) * 0.5 * height, front

        occupied = np.zeros((rows, cols), bool)
        boxes = self._geom_images(size, view_proj, near)
        if boxes is None:
            return None  # a geom reaches behind the eye: its image is not bounded
        if len(boxes[0]):
            x0 = np.clip(np.floor((boxes[0] - 1.0) / cell), 0, cols).astype(int)
            x1 = np.clip(np.floor((boxes[2] + 1.0) / cell), -1, cols - 1).astype(int)
            y0 = np.clip(np.floor((boxes[1] - 1.0) / cell), 0, rows).astype(int)
            y1 = np.clip(np.floor((boxes[3] + 1.0) / cell), -1, rows - 1).astype(int)
            for a, b, c, d in zip(x0, y0, x1, y1):
                if c >= a and d >= b:
                    occupied[b : d + 1, a : c + 1] = True
        first, count = self._rows
        columns = self._columns[size]
        if count < 2:
            return np.zeros((0, 2), np.int64)
        floats = FEEDBACK_BYTES // 4
        data = np.frombuffer(out.read(count * columns * FEEDBACK_BYTES, offset=first * columns * FEEDBACK_BYTES),
                             np.float32).reshape(count, columns, floats)  # fmt: skip
        x, y, front = image(data[..., :3].astype(np.float64))
        quad = lambda v, f: f.reduce((v[:-1, :-1], v[1:, :-1], v[:-1, 1:], v[1:, 1:]))  # noqa: E731
        bounded = quad(front, np.logical_and)
        total = np.zeros((rows + 1, cols + 1), np.int64)
        total[1:, 1:] = occupied.cumsum(axis=0).cumsum(axis=1)
        a = np.clip(np.floor((quad(x, np.minimum) - 1.0) / cell), 0, cols).astype(np.intp)
        b = np.clip(np.floor((quad(y, np.minimum) - 1.0) / cell), 0, rows).astype(np.intp)
        c = np.clip(np.floor((quad(x, np.maximum) + 1.0) / cell) + 1, 0, cols).astype(np.intp)
        d = np.clip(np.floor((quad(y, np.maximum) + 1.0) / cell) + 1, 0, rows).astype(np.intp)
        meets = (c > a) & (d > b) & (total[d, c] - total[b, c] - total[d, a] + total[b, a] > 0)
        return _runs(~bounded | meets) + first * (columns - 1)

    @property
    def texture_key(self):
        """The key of the surface data the textures hold (None: none yet)."""
        return self._key if self._geo is not None else None

    def upload(self, data: SurfaceData, levels: tuple[list[np.ndarray], list[np.ndarray]] | None = None) -> None:
        """Send the ocean's textures (skipped when the same data is already there); `levels`: the mip levels of
        `data.geo` and `data.slope` if made already (`mips.mip_levels`)."""
        if data.key == self._key and self._geo is not None:
            return
        bands, n = data.geo.shape[0], data.geo.shape[1]
        periodic = data.patch[2] == 0.0
        if self._geo is None or self._geo.size != (n, n, bands) or self._periodic != periodic:
            for tex in (self._geo, self._slope):
                if tex is not None:
                    tex.release()
            self._geo = self.ctx.texture_array((n, n, bands), 4, dtype="f4")
            self._slope = self.ctx.texture_array((n, n, bands), 4, dtype="f4")
            self._periodic = periodic
            for tex in (self._geo, self._slope):  # sampler changes make llvmpipe recompile: only when made
                tex.repeat_x = tex.repeat_y = periodic
                tex.filter = (0x2701, 0x2601)  # LINEAR_MIPMAP_NEAREST, LINEAR: half the fetches of trilinear
                tex.build_mipmaps()  # allocates the levels (and sets the level range) once; filled below
        assert self._geo is not None and self._slope is not None
        levels = levels or (mip_levels(data.geo), mip_levels(data.slope))  # a box filter on the CPU: no blit per level
        for tex, texture_levels in zip((self._geo, self._slope), levels):
            _write_levels(tex, texture_levels)
        self._key, self._data = data.key, data
        surface = (data.height_scale, data.displacement_scale, data.level_m, float(n))
        self._surface_key = None
        tiles = tuple(data.tiles_m) + (1.0,) * (5 - len(data.tiles_m))
        tile_fs = (tiles[max(bands - data.detail - 1, 0)], tiles[bands - 1])  # WATER_FS: the bands it reads per pixel
        tiles = {"u_tile": tiles, "u_bands": bands, "u_detail": data.detail, "u_surface": surface,
                 "u_patch": (*data.patch, 0.0)}  # fmt: skip
        _set(self.surface, **tiles)
        self._set_waters(u_tile_fs=tile_fs, **tiles)
        self._whitecap_slope = min(data.whitecap_slope, 1e6)

    def set_light(self, light: Daylight, look, level_m: float) -> None:
        """Sun, sky, fog and water uniforms for this frame."""
        from usvsim.rendering.weather import fog_extinction_per_m

        fog_sigma = fog_extinction_per_m(look)  # fog and rain (datasets/fog_sight.py labels with the same)
        brightness = float(np.clip(np.dot(light.ambient * 3.0 + light.sun_color * max(light.sun_dir[2], 0.0), (0.3, 0.6, 0.1)), 0.02, 1.2))  # fmt: skip
        common = {"u_sun_dir": tuple(light.sun_dir), "u_sun_color": tuple(light.sun_color),
                  "u_ambient": tuple(light.ambient), "u_haze_color": tuple(light.horizon),
                  "u_fog_color": tuple(np.array(look.fog.color) * brightness), "u_level": level_m,
                  "u_fog": (fog_sigma, look.fog.height_falloff_m, 3.912 / look.haze.visibility_m, HAZE_HEIGHT_M)}  # fmt: skip
        for prog in (self.sky, self.fog, self.surface):
            _set(prog, **common)
        self._set_waters(**common)
        sky_key = (
            tuple(light.sun_dir),
            tuple(light.zenith),
            tuple(light.coeffs.ravel()),
            look.haze.visibility_m,
        )
        if sky_key != self._sky_key:
            table = hazy_sky_table(light, 3.912 / look.haze.visibility_m * HAZE_HEIGHT_M, SKY_TEXELS)
            self._sky.write(np.concatenate([table, np.ones((*table.shape[:2], 1), np.float32)], axis=2).tobytes())
            self._sky_key = sky_key
        self._surface_key = None
        self._look = (look.water.foam, look.water.glint, FOAM_CHOPPINESS)
        self._level_m, self._fog_height_m = level_m, look.fog.height_falloff_m
        self._set_waters(u_water=tuple(look.water.color), u_clarity=float(look.water.clarity_m or 0.0))
        self._short_waves = look.water.short_waves

    def set_rain(self, rate_mm_h: float, seed: int) -> None:
        """Rings of raindrops on the water this frame (rendering/rain.py), drawn by programs that have them compiled
        in; rate 0: the programs without them (llvmpipe runs every branch, so only code left out costs nothing)."""
        from usvsim.rendering.rain import RING_STRENGTH, ring_chance

        self._raining = rate_mm_h > 0
        if self._raining:
            self._set_waters(u_rain=(ring_chance(rate_mm_h), float(int(seed) % 65521), RING_STRENGTH))

    def take_shadow_map(self, texture: int | None) -> None:
        """MuJoCo's shadow map of the sun drawn in this frame's colour pass (its GL texture id; None: none): the
        water shades by it (frame.sun_shadow_map calls this after `mjr_render`). Its world → map transform is the one
        MuJoCo's texture generation used, read back in `draw`."""
        self._shadow_tex = texture

    def _programs(self, rain: bool, shadow: bool) -> tuple:
        """(with marks, plain, over geoms) water programs with the rain's rings and/or the sun's shadow map."""
        if (rain, shadow) not in self._variants:
            made = tuple(_bind_samplers(self.ctx.program(vertex_shader=shaders.WATER_DRAW_VS,
                                                         fragment_shader=shaders.water_fs(marks, rain, shadow, geom)))
                         for marks, geom in ((True, False), (False, False), (True, True)))  # fmt: skip
            for prog in made:
                _set(prog, **self._water_uniforms)
            self._variants[(rain, shadow)] = made
            self._waters = (*self._waters, *made)
        return self._variants[(rain, shadow)]

    def _set_waters(self, **values) -> None:
        """Uniforms of every water program (those a program lacks are skipped), kept for programs made later."""
        self._water_uniforms.update(values)
        for prog in self._waters:
            _set(prog, **values)

    def draw(
        self, camera, rect, labels: tuple[float, float, float] | None = None, time_s: float = 0.0
    ) -> None:
        """Draw into the bound framebuffer after MuJoCo: `camera` a mujoco.MjvGLCamera (its frustum), `rect` the
        viewport. With `labels` (an RGB id colour 0..1) only the water is drawn, flat, for the label pass."""
        from OpenGL import GL

        fbo = self._framebuffer()
        view_proj, eye, near, far = camera_matrices(camera, rect.width, rect.height)
        viewport = (rect.left, rect.bottom, rect.width, rect.height)
        fbo.viewport = viewport
        water_vao, label_vao, cell, feedback, out, *_ = self._grid(rect.width, rect.height)
        inv = _mat(np.linalg.inv(view_proj))
        cell_tan = cell * 0.5 * (camera.frustum_top - camera.frustum_bottom) / near * rect.width / rect.height
        pixel_tan = (camera.frustum_top - camera.frustum_bottom) / near / rect.height  # one pixel's view width
        grid = {
            "u_cam": tuple(eye),
            "u_view_proj": _mat(view_proj),
            "u_inv_view_proj": inv,
            "u_cell": (cell_tan, FAR_M),
        }
        size = (rect.width, rect.height)
        if labels is None:  # the work that needs no pixels first: llvmpipe may still be drawing the geoms
            self._draw_wakes()
            self._marks = self._marks_runs(size, view_proj, eye)
            for prog in (self.sky, self.fog):
                _set(prog, u_cam=tuple(eye), u_inv_view_proj=inv, u_forward=_forward(camera))
            _set(self.fog, u_near_far=(near, far), u_viewport=viewport[:2])
            self._set_waters(u_near_far=(near, far), u_viewport=viewport[:2], u_look=(*self._look, time_s),
                             u_pixel=pixel_tan, u_sea=(self._short_waves, self._whitecap_slope),
                             u_mip_ratio=self.mip_ratio or (1.0,) * 8, **grid)  # fmt: skip
            self._copy_depth(fbo, viewport)  # waits for the geoms
        self.bind_textures()
        key = (grid["u_inv_view_proj"], grid["u_cell"], self._key, viewport)
        if key != self._surface_key:  # the label pass of the same view reuses the colour pass's surface
            at_eye = tuple(np.exp(-(eye[2] - self._level_m) / np.array([self._fog_height_m, HAZE_HEIGHT_M])))
            for prog in (self.sky, self.fog, self.surface):
                _set(prog, u_at_eye=at_eye)
            _set(self.surface, **grid)
            first, count = self._rows = self._visible_rows(size, view_proj, eye)
            columns = self._columns[size]
            if count > 1:  # (llvmpipe waits for the pixels drawn before a transform feedback: after the depth copy)
                feedback.transform(out, mode=POINTS, vertices=count * columns, first=first * columns,
                                   buffer_offset=first * columns * FEEDBACK_BYTES)  # fmt: skip
            self._surface_key = key
        if labels is not None:
            _set(self.label, u_id_color=labels, **grid)
            self._water(label_vao, stencil=False, blend=False, columns=self._columns[size])
        else:
            GL.glStencilMask(0xFF)
            GL.glClear(GL.GL_STENCIL_BUFFER_BIT)
            GL.glEnable(GL.GL_STENCIL_TEST)  # the fog pass marks where a geom was drawn (for the water's programs)
            GL.glStencilFunc(GL.GL_ALWAYS, GEOM_BIT, GEOM_BIT)
            GL.glStencilOp(GL.GL_KEEP, GL.GL_KEEP, GL.GL_REPLACE)
            boxes = self._geom_images(size, view_proj, near)
            if boxes is None or len(boxes[0]):  # only where a geom was drawn (depth > 0): within their boxes' images
                if boxes is not None and FOG_SCISSOR:
                    x0, y0 = (max(int(np.floor(v.min())) - 1, 0) for v in boxes[:2])
                    x1, y1 = (min(int(np.ceil(v.max())) + 2, n) for v, n in zip(boxes[2:], size))
                    GL.glEnable(GL.GL_SCISSOR_TEST)
                    GL.glScissor(rect.left + x0, rect.bottom + y0, max(x1 - x0, 0), max(y1 - y0, 0))
                self._fullscreen(self.fog, "<", blend=True)
                GL.glDisable(GL.GL_SCISSOR_TEST)
            marks, plain, full = water_vao, self._plain_vaos[size], self._full_vaos[size]
            self._over_geoms = self._over_geoms_runs(size, view_proj, near, out)
            shadow = self._shadow_tex is not None
            if shadow:
                self._use_shadow_map(camera)
            if self._raining or shadow:
                marks, plain, full = self._variant_arrays(rect.width, rect.height, self._raining, shadow)
            self._water(marks, stencil=True, blend=True, columns=self._columns[size], plain=plain, full=full)
            GL.glStencilMask(0xFF)
            GL.glStencilFunc(GL.GL_EQUAL, 0, 0xFF)  # the sky where neither geoms nor water were drawn
            GL.glStencilOp(GL.GL_KEEP, GL.GL_KEEP, GL.GL_KEEP)
            low, high = _sky_rows(view_proj, eye, rect.height)  # only rows that can see the sky: llvmpipe pays
            if high > low:  # about 1 ms per 640 x 480 for the blocks of a full-screen triangle it then rejects
                GL.glEnable(GL.GL_SCISSOR_TEST)
                GL.glScissor(rect.left, rect.bottom + low, rect.width, high - low)
                self._fullscreen(self.sky, ">=", blend=False)
                GL.glDisable(GL.GL_SCISSOR_TEST)
            GL.glDisable(GL.GL_STENCIL_TEST)
            if self.lamps is not None:
                self._draw_lamps(camera, rect, view_proj, eye)
            self.geom_boxes = None  # the caller's for this frame only
        self.restore()

    def read_water_mask(self, rect, out: np.ndarray) -> None:
        """After a colour pass: `out` (height, width) uint8, bottom row first, 1 where the water is the nearest
        surface drawn (the stencil its fragments marked when they passed the depth test against the geoms), else 0.
        The same pixels as the label pass draws in the water's id colour against the same geoms' depth, so a
        capture that drew the colour pass needs no label pass for the water (tests/rendering checks both agree)."""
        from OpenGL import GL

        GL.glBindFramebuffer(GL.GL_READ_FRAMEBUFFER, self._framebuffer().glo)
        GL.glPixelStorei(GL.GL_PACK_ALIGNMENT, 1)
        GL.glReadPixels(rect.left, rect.bottom, rect.width, rect.height, GL.GL_STENCIL_INDEX, GL.GL_UNSIGNED_BYTE, out)
        GL.glPixelStorei(GL.GL_PACK_ALIGNMENT, self._pixel_store[GL.GL_PACK_ALIGNMENT])
        np.bitwise_and(out, WATER_BIT, out=out)  # the stencil also marks the geoms (GEOM_BIT)

    def _draw_wakes(self) -> None:
        """The wakes' foam texture for the water pass (u_wake_region.w = 0: no wake this frame)."""
        from usvsim.rendering.wakes import WakePass

        region = (0.0, 0.0, 1.0, 0.0)
        wake = self.wake if self.wake is not None else np.zeros((0, 6), np.float32)
        if len(wake):
            if self._wakes is None:
                self._wakes = WakePass(self.ctx)
            if self._wakes.draw(wake):
                region = (*self._wakes.region, 1.0)
                self._occupied = self._wakes.occupied
                self._wakes.texture.use(TEXTURE_UNITS["u_wake"])
        self._set_waters(u_wake_region=region)
        self._region = region

    def _variant_arrays(self, width: int, height: int, rain: bool, shadow: bool) -> tuple:
        """The vertex arrays of `_programs(rain, shadow)` over the grid's displaced vertices, made once per size."""
        key = (width, height, rain, shadow)
        if key not in self._variant_vaos:
            _, _, _, _, out, _, ibo = self._grid(width, height)
            self._variant_vaos[key] = tuple(
                self.ctx.vertex_array(prog, [(out, "3f 2f 1f 4f 2f 3f", *(f"in_{v[2:]}" for v in FEEDBACK))],
                                      index_buffer=ibo, index_element_size=4)
                for prog in self._programs(rain, shadow))  # fmt: skip
        return self._variant_vaos[key]

    def _use_shadow_map(self, camera) -> None:
        """Bind MuJoCo's shadow map for the water and give it the map's transform: MuJoCo set it as the eye planes
        of texture unit 1's coordinate generation (each plane the row of bias · light projection · light view,
        stored in eye coordinates of the drawing camera), so world → map = planes · view."""
        from OpenGL import GL

        GL.glActiveTexture(GL.GL_TEXTURE1)
        planes = np.array([GL.glGetTexGenfv(c, GL.GL_EYE_PLANE) for c in (GL.GL_S, GL.GL_T, GL.GL_R, GL.GL_Q)],
                          dtype=np.float64).reshape(4, 4)  # fmt: skip
        GL.glActiveTexture(int(GL.GL_TEXTURE0) + TEXTURE_UNITS["u_sun_shadow"])
        GL.glBindTexture(GL.GL_TEXTURE_2D, self._shadow_tex)
        GL.glActiveTexture(GL.GL_TEXTURE0)
        self._set_waters(u_shadow_matrix=_mat(planes @ view_matrix(camera)))

    def _draw_lamps(self, camera, rect, view_proj, eye) -> None:
        from usvsim.rendering.lights import LightPass

        if self._lights is None:
            self._lights = LightPass(self.ctx)
        assert self.lamps is not None, "drawn only for a frame with lamps"
        nav, pos, rot, t, intensity = self.lamps
        focal = rect.height * camera.frustum_near / (camera.frustum_top - camera.frustum_bottom)
        at_eye = tuple(np.exp(-(eye[2] - self._level_m) / np.array([self._fog_height_m, HAZE_HEIGHT_M])))
        uniforms = {"u_cam": tuple(eye), "u_focal_px": float(focal), "u_level": self._level_m,
                    "u_at_eye": at_eye, "u_fog": cast("moderngl.Uniform", self.sky["u_fog"]).value}  # fmt: skip
        self._lights.prog["u_view_proj"].write(_mat(view_proj))
        self._lights.draw(nav.world(pos, rot, eye, t, intensity), uniforms)

    def _water(self, vao, stencil: bool, blend: bool, columns: int = 0, plain=None, full=None) -> None:
        """Draw the visible rows of the grid with `vao`; with `plain`, the quads that cannot reach the wakes'
        region with it instead (outside the region both programs compute the same bytes), in the stored order.
        `stencil`: mark WATER_BIT where the water passes the depth test. With `full` (the colour pass; the fog pass
        has marked GEOM_BIT where a geom was drawn), those pixels are drawn by `full` instead, in one call: only
        there can the water read a geom's depth behind it (hull foam, clear water), and the programs without that
        code give the same bytes elsewhere. Each pixel sees its fragments in the stored order either way."""
        from OpenGL import GL

        ctx = self.ctx
        ctx.enable(ctx.DEPTH_TEST)
        ctx.depth_func = ">="
        if stencil:
            GL.glEnable(GL.GL_STENCIL_TEST)
            GL.glStencilOp(GL.GL_KEEP, GL.GL_KEEP, GL.GL_REPLACE)
            GL.glStencilMask(WATER_BIT)
        ctx.blend_func = ctx.SRC_ALPHA, ctx.ONE_MINUS_SRC_ALPHA  # over the geoms behind the surface (clear water)
        if blend and full is None:  # with `full`, only its pixels blend: elsewhere alpha is 1 (nothing behind)
            ctx.enable(ctx.BLEND)
        ctx.enable_direct(GL_DEPTH_CLAMP)
        first, count = self._rows  # vertex rows; the quads between them, 6 indices each, are stored row by row
        if count > 1:
            start, stop = first * (columns - 1), (first + count - 1) * (columns - 1)  # quads [start, stop)
            runs = [(vao, start, stop)]
            if plain is not None:  # alternate: plain up to a run of quads that may show marks, that run, ...
                runs, at = [], start
                for lo, hi in np.clip(self._marks, start, stop):
                    runs += [(plain, at, lo), (vao, lo, hi)]
                    at = hi
                runs.append((plain, at, stop))
            if stencil:  # no geom behind (or no split: anywhere)
                GL.glStencilFunc(GL.GL_EQUAL if full is not None else GL.GL_ALWAYS, WATER_BIT, GEOM_BIT)
            for v, lo, hi in runs:
                if hi > lo:
                    v.render(vertices=(hi - lo) * 6, first=lo * 6)
            if full is not None:  # a geom behind
                GL.glStencilFunc(GL.GL_EQUAL, WATER_BIT | GEOM_BIT, GEOM_BIT)
                if blend:
                    ctx.enable(ctx.BLEND)
                over = [(start, stop)] if self._over_geoms is None else np.clip(self._over_geoms, start, stop)
                for lo, hi in over:  # only quads that can reach a geom's pixel (`_over_geoms_runs`), in stored order
                    if hi > lo:
                        full.render(vertices=(hi - lo) * 6, first=lo * 6)
        ctx.disable_direct(GL_DEPTH_CLAMP)
        ctx.disable(ctx.BLEND)

    def _fullscreen(self, prog, depth_func: str, blend: bool) -> None:
        """A triangle over the view at depth 0 (the far plane), shaded only where the depth test passes."""
        from OpenGL import GL

        ctx = self.ctx
        ctx.enable(ctx.DEPTH_TEST)
        ctx.depth_func = depth_func
        GL.glDepthMask(GL.GL_FALSE)
        if blend:
            ctx.enable(ctx.BLEND)
            ctx.blend_func = ctx.ONE, ctx.SRC_ALPHA
        else:
            ctx.disable(ctx.BLEND)
        self.fullscreen[prog].render(vertices=3)
        ctx.disable(ctx.BLEND)
        GL.glDepthMask(GL.GL_TRUE)

    def _copy_depth(self, fbo, viewport) -> None:
        """The geoms' depth into a texture for the fog and water passes. The texture has the format of MuJoCo's
        offscreen depth buffer (32-bit float depth + stencil), so llvmpipe copies it with a memcpy (a tenth of
        the time of a conversion to 24-bit depth) and the shaders read the exact depth."""
        from OpenGL import GL

        width, height = viewport[2], viewport[3]
        if self._depth is None or self._depth.size != (width, height):
            self._release_depth()
            glo = int(GL.glGenTextures(1))
            GL.glActiveTexture(int(GL.GL_TEXTURE0) + TEXTURE_UNITS["u_depth"])
            GL.glBindTexture(GL.GL_TEXTURE_2D, glo)
            _raw_tex_image_2d(GL.GL_TEXTURE_2D, 0, GL.GL_DEPTH32F_STENCIL8, width, height, 0, GL.GL_DEPTH_STENCIL,
                              GL.GL_FLOAT_32_UNSIGNED_INT_24_8_REV, None)  # fmt: skip
            for key in (GL.GL_TEXTURE_MIN_FILTER, GL.GL_TEXTURE_MAG_FILTER):  # complete without mipmaps
                GL.glTexParameteri(GL.GL_TEXTURE_2D, key, GL.GL_NEAREST)
            self._depth = self.ctx.external_texture(glo, (width, height), 1, 0, "f4")
        self._depth.use(TEXTURE_UNITS["u_depth"])  # binds it on that unit, which stays active for the copy
        GL.glBindFramebuffer(GL.GL_READ_FRAMEBUFFER, fbo.glo)
        GL.glCopyTexSubImage2D(GL.GL_TEXTURE_2D, 0, 0, 0, *viewport)

    def _release_depth(self) -> None:
        if self._depth is not None:
            from OpenGL import GL

            GL.glDeleteTextures([self._depth.glo])
            self._depth = None

    def _framebuffer(self):
        fbo = self.ctx.detect_framebuffer()
        return self._fbos.setdefault(fbo.glo, fbo)

    @property
    def noise_texture(self):
        """The 64² noise texture (fixed seed) the water's foam and the geoms' materials read."""
        return self._noise

    def restore(self) -> None:
        """Leave the state MuJoCo's fixed-function pipeline expects: no program, no vertex array."""
        from OpenGL import GL

        GL.glUseProgram(0)
        GL.glBindVertexArray(0)
        GL.glBindBuffer(GL.GL_ARRAY_BUFFER, 0)
        GL.glActiveTexture(GL.GL_TEXTURE0)
        GL.glDepthFunc(GL_GEQUAL)
        for key, value in self._pixel_store.items():  # moderngl's texture writes change the alignment
            GL.glPixelStorei(key, value)
        self.ctx.blend_func = self.ctx.SRC_ALPHA, self.ctx.ONE_MINUS_SRC_ALPHA

    def bind_textures(self) -> None:
        assert self._geo is not None and self._slope is not None, "upload() first"
        self._geo.use(TEXTURE_UNITS["u_geo"])
        self._slope.use(TEXTURE_UNITS["u_slope"])
        self._sky.use(TEXTURE_UNITS["u_sky"])
        self._noise.use(TEXTURE_UNITS["u_noise"])

    def release(self) -> None:
        for extra in (self._lights, self._wakes, self.geom_shading):
            if extra is not None:
                extra.release()
        grids = [obj for entry in self._grids.values() for obj in (entry[:2] + entry[3:])]
        grids += list(self._plain_vaos.values()) + list(self._full_vaos.values())
        grids += [v for vaos in self._variant_vaos.values() for v in vaos]
        grids += [p for key, progs in self._variants.items() if key != (False, False) for p in progs]
        self._release_depth()
        for obj in (
            self._geo,
            self._slope,
            self._sky,
            *grids,
            self.sky,
            self.fog,
            self.water,
            self.plain,
            self.full,
            self.label,
            self.surface,
        ):
            if obj is not None:
                obj.release()


def view_matrix(camera) -> np.ndarray:
    """World → eye matrix (4, 4) of a GL camera (mujoco.MjvGLCamera): x right, y up, looking along -z."""
    eye, fwd, up = (np.array(v, dtype=np.float64) for v in (camera.pos, camera.forward, camera.up))
    fwd /= np.linalg.norm(fwd)
    right_axis = np.cross(fwd, up)
    right_axis /= np.linalg.norm(right_axis)
    up_axis = np.cross(right_axis, fwd)
    view = np.eye(4)
    view[0, :3], view[1, :3], view[2, :3] = right_axis, up_axis, -fwd
    view[:3, 3] = -view[:3, :3] @ eye
    return view


def camera_matrices(camera, width: int, height: int) -> tuple[np.ndarray, np.ndarray, float, float]:
    """World → clip matrix (4, 4) of MuJoCo's reversed-Z projection for a GL camera; eye; near; far."""
    eye = np.array(camera.pos, dtype=np.float64)
    n, f = float(camera.frustum_near), float(camera.frustum_far)
    top, bottom = float(camera.frustum_top), float(camera.frustum_bottom)
    half_w = float(camera.frustum_width) or 0.5 * (top - bottom) * width / height
    left, right = camera.frustum_center - half_w, camera.frustum_center + half_w
    view = view_matrix(camera)
    proj = np.zeros((4, 4))
    proj[0, 0], proj[0, 2] = 2 * n / (right - left), (right + left) / (right - left)
    proj[1, 1], proj[1, 2] = 2 * n / (top - bottom), (top + bottom) / (top - bottom)
    proj[2, 2], proj[2, 3], proj[3, 2] = n / (f - n), n * f / (f - n), -1.0
    return proj @ view, eye, n, f


def _runs(hit: np.ndarray) -> np.ndarray:
    """(n, 2) runs [start, stop) of True in `hit` (quad rows, quads per row), as indices of quads stored row by row."""
    flat = np.concatenate([np.zeros((hit.shape[0], 1), bool), hit, np.zeros((hit.shape[0], 1), bool)], axis=1)
    edges = np.flatnonzero(np.diff(flat.ravel().astype(np.int8)))  # runs of hits, row by row (padded rows)
    starts, stops = edges[::2], edges[1::2]
    row = starts // flat.shape[1]
    shift = row * (flat.shape[1] - hit.shape[1])
    return np.stack([starts - shift, stops - shift], axis=1).astype(np.int64)


def _sky_rows(view_proj: np.ndarray, eye: np.ndarray, height: int, margin_px: int = 2) -> tuple[int, int]:
    """Window rows [low, high) of a view `height` pixels tall (bottom row 0) that hold a pixel whose ray rises
    above -1° (a band below the horizon, where no water lies beyond the grid's far circle, is kept). A row's end
    pixels decide: d.z + ε|d| is convex along a row (d affine in the pixel), so it is largest at an end."""
    inv = np.linalg.inv(view_proj)
    y = (np.arange(height) + 0.5) / height * 2.0 - 1.0
    ends = np.stack(np.broadcast_arrays(np.array([-1.0, 1.0])[None, :], y[:, None]), axis=-1)  # (height, 2, 2)
    p = ends[..., :1] * inv[:, 0] + ends[..., 1:] * inv[:, 1] + 0.5 * inv[:, 2] + inv[:, 3]
    d = p[..., :3] / p[..., 3:] - eye
    rows = np.flatnonzero((d[..., 2] > -0.0175 * np.linalg.norm(d, axis=-1)).any(axis=1))
    if len(rows) == 0:
        return 0, 0
    return max(int(rows[0]) - margin_px, 0), min(int(rows[-1]) + 1 + margin_px, height)


def _forward(camera) -> tuple[float, float, float]:
    fwd = np.array(camera.forward, dtype=np.float64)
    return tuple(fwd / np.linalg.norm(fwd))


def _write_levels(tex, levels: list[np.ndarray]) -> None:
    """Fill every mip level of a float RGBA texture array (levels allocated, each (layers, h, w, 4) float32)."""
    from OpenGL import GL
    from OpenGL.raw.GL.VERSION.GL_1_2 import glTexSubImage3D

    tex.use(TEXTURE_UNITS["u_geo"])  # binds it (the frame binds its own textures again before drawing)
    GL.glPixelStorei(GL.GL_UNPACK_ALIGNMENT, 4)
    for level, values in enumerate(levels):
        layers, height, width = values.shape[:3]
        glTexSubImage3D(GL.GL_TEXTURE_2D_ARRAY, level, 0, 0, 0, width, height, layers, GL.GL_RGBA, GL.GL_FLOAT,
                        values.ctypes.data_as(ctypes.c_void_p))  # fmt: skip


def _raw_tex_image_2d(*args) -> None:
    """glTexImage2D without PyOpenGL's array conversion (it knows no depth-stencil pixel types; no data here)."""
    from OpenGL.raw.GL.VERSION.GL_1_0 import glTexImage2D

    glTexImage2D(*args)


def _mat(m: np.ndarray) -> bytes:
    return np.ascontiguousarray(m.T, dtype=np.float32).tobytes()  # GLSL matrices are column-major


def _set(prog, **values) -> None:
    for name, value in values.items():
        if name not in prog:
            continue
        if isinstance(value, bytes):
            prog[name].write(value)
        else:
            prog[name].value = value


def _bind_samplers(prog):
    """Sampler uniforms → texture units, once per program (setting them again makes llvmpipe recompile)."""
    for name, unit in TEXTURE_UNITS.items():
        if name in prog:
            prog[name].value = unit
    return prog
