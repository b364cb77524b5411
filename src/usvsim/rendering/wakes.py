"""Wakes: foam trails behind moving vessels, from each hull's past track.

`WakeTracks` keeps every vessel's and kinematic traffic ship's track (stern position, heading, speed over
ground) every `SAMPLE_S` of simulated time, the last `KEEP_S` seconds; the simulation records it each step (a
clock check; a sample every 25 steps), so a picture shows the same wake however often frames were drawn before it (same seed, same bytes).

`WakePass` draws the tracks, once per frame, into a small top-down foam texture around them (512², square,
at most `MAX_REGION_M` across) that the water shader reads by the surface point's label: a turbulent
centre wake as wide as the beam that spreads and fades (e-folding `TURBULENT_S`), and the two arms of the
Kelvin wedge at ±19.47° from the track (half-width grows by speed·age·tan 19.47°), fading faster
(`KELVIN_S`), both scaled by the speed the hull had there (nothing below 0.3 m/s, full from 2 m/s). It is
foam, not displacement: the surface that depth and labels hold is the ocean's.
"""

from __future__ import annotations

import math

import numpy as np

from usvsim.core.transforms import cross3

SAMPLE_S, KEEP_S = 0.25, 60.0
TURBULENT_S, KELVIN_S = 20.0, 6.0
KELVIN_TAN = math.tan(math.radians(19.47))
MAX_REGION_M, TEXELS = 2000.0, 512
CLEAR = 0.25 / 255.0  # a foam value below this is stored as 0 in the 8-bit texture (rounded: 0.5 / 255), with margin
CELLS = 32  # `WakePass.occupied`: the region in CELLS x CELLS cells


class WakeTracks:
    """Past stern positions of a simulation's vessels (world ENU, m), sampled on simulated time."""

    def __init__(self, world):
        from usvsim.rendering.lights import _visual_box, kinematic_ships, ship_boxes

        self.every = max(int(round(SAMPLE_S / world.clock.dt)), 1)
        self.keep = int(KEEP_S / SAMPLE_S)
        self.vessels = []  # (body, stern x in the body frame, half beam)
        for vessel in world.vessels.values():
            body = world.model.body(vessel.name).id
            lo, hi = _visual_box(world.model, body)
            if lo is not None and hi is not None:
                self.vessels.append((vessel, float(lo[0]), 0.5 * float(hi[1] - lo[1])))
        ships = kinematic_ships(world)  # the traffic's kinematic ships: (stern x, half beam) in their frames
        boxes = ship_boxes(world.model, ships) if ships is not None else []
        self.ships = [(float(lo[0]), 0.5 * float(hi[1] - lo[1])) if lo is not None and hi is not None else (0.0, 1.0)
                      for lo, hi in boxes]  # fmt: skip
        self.half_beams = [v[2] for v in self.vessels] + [s[1] for s in self.ships]
        self._index = np.array([v.index for v, _, _ in self.vessels], dtype=np.intp)
        self._stern = np.array([st for _, st, _ in self.vessels], dtype=float)
        self.reset()

    def reset(self) -> None:
        self.samples: list[np.ndarray] = []  # per sample (vessels, 5): stern x, y, heading, speed, time
        self.cuts: list[list[float]] = [[] for _ in self.half_beams]  # per track: times (s) where it restarts
        self._teleports: np.ndarray | None = None  # the vessels' `teleport` counts at the last sample

    def record(self, world) -> None:
        """Called after every physics step; samples every `every` steps."""
        if not self.half_beams or world.clock.steps % self.every:
            return
        t = world.clock.seconds
        row = np.zeros((len(self.half_beams), 5))
        n, st = len(self.vessels), world.state
        if n:  # all vessels at once: stern point, heading, speed of the body frame's origin over ground
            i = self._index
            rot, origin = st.rot[i], st.pos[i]
            fwd = rot[:, :, 0]
            omega = np.einsum("nij,nj->ni", rot, st.omega_body[i])
            vel = st.vcom_world[i] - cross3(omega, st.com_world[i] - origin)  # World.origin_velocity
            row[:n, 0:2] = origin[:, :2] + self._stern[:, None] * fwd[:, :2]
            row[:n, 2] = np.arctan2(fwd[:, 1], fwd[:, 0])
            row[:n, 3] = np.hypot(vel[:, 0], vel[:, 1])
            row[:n, 4] = t
            counts = world.body_teleports[i]  # a teleported hull did not sail from where it was: cut its track
            if self._teleports is not None:
                for v in np.flatnonzero(counts != self._teleports):
                    self.cuts[v].append(t)
            self._teleports = counts.copy()
        if self.ships:
            from usvsim.rendering.lights import kinematic_ships

            ships = kinematic_ships(world)
            if ships is not None:
                _, pos, vel, yaw = ships
                m = len(self.ships)
                stern = np.array([st for st, _ in self.ships])
                row[n:, 0] = pos[:m, 0] + stern * np.cos(yaw[:m])
                row[n:, 1] = pos[:m, 1] + stern * np.sin(yaw[:m])
                row[n:, 2] = yaw[:m]
                row[n:, 3] = np.hypot(vel[:m, 0], vel[:m, 1])
                row[n:, 4] = t
        self.samples.append(row)
        if len(self.samples) > self.keep:
            del self.samples[0]
            oldest = self.samples[0][0, 4]
            for cuts in self.cuts:  # a cut at or before the oldest sample splits nothing
                while cuts and cuts[0] <= oldest:
                    del cuts[0]

    def ribbons(self, now_s: float, length_s: float) -> np.ndarray:
        """Triangles of the tracks' ribbons for `WakePass`, (n, 6) float32 per vertex: x, y (m), across the
        ribbon (-1..1), age (s), speed there (m/s), the ribbon's half width (m); the last `length_s` seconds."""
        if len(self.samples) < 2 or length_s <= 0:
            return np.zeros((0, 6), np.float32)
        track = np.stack(self.samples[::-1])  # newest first: (samples, vessels, 5)
        age = now_s - track[:, 0, 4]
        track = track[age <= length_s]
        age = age[age <= length_s]
        tris = []
        for v, half_beam in enumerate(self.half_beams):  # a vessel's track is cut where it was teleported
            piece = np.searchsorted(np.array(self.cuts[v]), track[:, v, 4], side="right") if self.cuts[v] else None
            for k in [None] if piece is None else np.unique(piece):
                mine = slice(None) if k is None else piece == k
                tris += self._ribbon(track[mine, v], age[mine], half_beam)
        return np.concatenate(tris).astype(np.float32) if tris else np.zeros((0, 6), np.float32)

    @staticmethod
    def _ribbon(track: np.ndarray, age: np.ndarray, half_beam: float) -> list[np.ndarray]:
        """The triangles of one stretch of a track (samples, 5), newest first; [] when it leaves no foam."""
        pts, speed = track[:, :2], track[:, 3]
        if len(pts) < 2 or speed.max() < 0.3:
            return []
        d = np.gradient(pts, axis=0)
        norm = np.linalg.norm(d, axis=1, keepdims=True)
        heading = track[:, 2]
        d = np.where(
            norm > 1e-6, d / np.maximum(norm, 1e-9), np.stack([-np.cos(heading), -np.sin(heading)], 1)
        )
        side = np.stack([-d[:, 1], d[:, 0]], axis=1)
        half = half_beam + speed * age * KELVIN_TAN + 1.0
        left, right = pts + side * half[:, None], pts - side * half[:, None]
        edge = np.stack([np.c_[left, np.ones(len(pts))], np.c_[right, -np.ones(len(pts))]])  # (2, n, 3)
        attrs = np.c_[age, speed, half]  # per sample
        a = np.arange(len(pts) - 1)
        # per segment two triangles: left a, right a, left b; left b, right a, right b
        sides, samples = np.array([0, 1, 0, 0, 1, 1]), np.stack([a, a, a + 1, a + 1, a, a + 1], axis=1)
        corners = edge[sides[None, :], samples]  # (segments, 6, 3)
        return [np.concatenate([corners, attrs[samples]], axis=2).reshape(-1, 6)]


def foam_bound(tris: np.ndarray) -> np.ndarray:
    """Per triangle of `tris` (n, 6 as `WakeTracks.ribbons`; n / 3 triangles): an upper bound of the foam FS draws
    anywhere in it. Its speed and age interpolate between its vertices', so FS's value is at most
    go(highest speed) · max(0.7 exp(-lowest age / TURBULENT_S), 0.4 exp(-lowest age / KELVIN_S) [speed >= 1]) (the
    across-track factors and `fresh` are at most 1). A hull slower than 0.3 m/s leaves none; a slow one's old track
    fades below `CLEAR`: such triangles leave the texture clear, and the water needs no wake code over them."""
    t = tris.reshape(-1, 3, 6).astype(np.float64)
    speed = t[..., 4].max(axis=1)
    speed = speed + 1e-5 * np.abs(speed) + 1e-6  # float32 interpolation and rounding: a little more
    age = t[..., 3].min(axis=1)
    age = age - 1e-5 * np.abs(age) - 1e-6
    x = np.clip((speed - 0.3) / (2.0 - 0.3), 0.0, 1.0)
    go = x * x * (3.0 - 2.0 * x)
    centre = 0.7 * np.exp(-age / TURBULENT_S)
    arm = 0.4 * np.exp(-age / KELVIN_S) * (speed >= 1.0)
    return go * np.maximum(centre, arm)


VS = """
#version 330
uniform vec3 u_region;  // x0, y0 of the texture's corner, side (m)
in vec2 in_xy;
in float in_across, in_age, in_speed, in_half;
out float v_across, v_age, v_speed, v_half;
void main() {
    v_across = in_across; v_age = in_age; v_speed = in_speed; v_half = in_half;
    gl_Position = vec4((in_xy - u_region.xy) / u_region.z * 2.0 - 1.0, 0.0, 1.0);
}
"""

FS = (
    """
#version 330
in float v_across, v_age, v_speed, v_half;
out vec4 f_color;
void main() {
    float x = abs(v_across) * v_half;  // metres from the track
    float go = smoothstep(0.3, 2.0, v_speed);
    float width = max(v_half - v_speed * v_age * TAN - 1.0, 0.3) * (0.6 + 0.03 * v_age);  // the turbulent wake spreads
    float centre = exp(-x * x / (width * width)) * exp(-v_age / TURB);
    float arm = exp(-pow((v_half - 1.0 - x) / (0.3 + 0.03 * v_age), 2.0)) * exp(-v_age / KELVIN) * step(1.0, v_speed);
    float fresh = smoothstep(0.0, 0.6, v_age + 0.1);  // no foam ahead of the stern
    f_color = vec4(go * fresh * max(0.7 * centre, 0.4 * arm), 0.0, 0.0, 1.0);
}
""".replace("TAN", repr(KELVIN_TAN))
    .replace("TURB", repr(TURBULENT_S))
    .replace("KELVIN", repr(KELVIN_S))
)


class WakePass:
    """The foam texture of the wakes (R, 0..1) and where it lies (x0, y0, side in m), on the marine context."""

    def __init__(self, ctx):
        self.ctx = ctx
        self.prog = ctx.program(vertex_shader=VS, fragment_shader=FS)
        self.texture = ctx.texture((TEXELS, TEXELS), 4, dtype="f1")  # R: wake foam (GBA unused; RGBA: fetched faster)
        self.texture.repeat_x = self.texture.repeat_y = False
        self.fbo = ctx.framebuffer(color_attachments=[self.texture])
        self.buffer = ctx.buffer(reserve=6 * 4 * 1024)
        self.vao = ctx.vertex_array(self.prog, [(self.buffer, "2f 1f 1f 1f 1f", "in_xy", "in_across", "in_age",
                                                 "in_speed", "in_half")])  # fmt: skip
        self.region = (0.0, 0.0, 1.0)
        self.occupied = np.zeros((CELLS, CELLS), bool)  # [row y, column x] cells of the region where it may not be zero

    def draw(self, tris: np.ndarray) -> bool:
        """Render the ribbons (R); False (and nothing drawn) when there are none."""
        if not len(tris):
            return False
        xy = tris[:, :2]
        lo, hi = xy.min(axis=0), xy.max(axis=0)
        side = float(min(max(hi[0] - lo[0], hi[1] - lo[1], 32.0) + 4.0, MAX_REGION_M))
        centre = 0.5 * (lo + hi)
        self.region = (float(centre[0] - 0.5 * side), float(centre[1] - 0.5 * side), side)
        pad = 2.0 * side / TEXELS  # the texels the triangles touch, and their bilinear neighbours
        shown = tris.reshape(-1, 3, 6)[foam_bound(tris) >= CLEAR, :, :2]  # triangles that can leave a texel above 0
        self.occupied = np.zeros((CELLS, CELLS), bool)
        if len(shown):  # each one's box and the texels around it, in cells
            corner, cell = np.array(self.region[:2]), side / CELLS
            first = np.clip(np.floor((shown.min(axis=1) - pad - corner) / cell), 0, CELLS - 1).astype(int)
            last = np.clip(np.floor((shown.max(axis=1) + pad - corner) / cell), 0, CELLS - 1).astype(int)
            for (x0, y0), (x1, y1) in zip(first, last):
                self.occupied[y0 : y1 + 1, x0 : x1 + 1] = True
        data = np.ascontiguousarray(tris, np.float32).tobytes()
        if len(data) > self.buffer.size:
            self.buffer.orphan(len(data))
        if len(data):
            self.buffer.write(data)
        self.prog["u_region"].value = self.region
        from OpenGL import GL

        ctx = self.ctx
        bound = int(GL.glGetIntegerv(GL.GL_DRAW_FRAMEBUFFER_BINDING))
        viewport = [int(v) for v in GL.glGetIntegerv(GL.GL_VIEWPORT)]
        self.fbo.use()
        self.fbo.clear(0.0, 0.0, 0.0, 0.0)
        ctx.disable(ctx.DEPTH_TEST)
        ctx.enable(ctx.BLEND)
        ctx.blend_equation = 0x8008  # GL_MAX: overlapping segments do not add up
        ctx.blend_func = ctx.ONE, ctx.ONE
        self.vao.render(vertices=len(tris))
        ctx.blend_equation = 0x8006  # GL_FUNC_ADD
        ctx.disable(ctx.BLEND)
        GL.glBindFramebuffer(GL.GL_FRAMEBUFFER, bound)
        GL.glViewport(*viewport)
        return True

    def release(self) -> None:
        for obj in (self.vao, self.buffer, self.fbo, self.texture, self.prog):
            obj.release()
