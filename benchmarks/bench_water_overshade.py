"""How many fragment-shader invocations llvmpipe spends per water pixel in the viewer (1280x720, sea state 4).

llvmpipe shades 4 x 4 pixel blocks per triangle, so a grid of small triangles shades the blocks along their edges
more than once ("overshading"). This counts it with GL_ARB_pipeline_statistics_query: the viewer draws one frame
of the benchmark's view, then the water's visible grid rows are drawn again (the program without wakes or geoms,
no depth or stencil test) inside a GL_FRAGMENT_SHADER_INVOCATIONS query and a GL_SAMPLES_PASSED query (the pixels
the triangles cover). llvmpipe counts 16 invocations per block it enters. For scale: a full-screen triangle and a
flat grid of the viewer's cell size.

    MUJOCO_GL=egl python benchmarks/bench_water_overshade.py
Prints JSON; writes nothing.
"""

from __future__ import annotations

import json
import os

os.environ.setdefault("MUJOCO_GL", "egl")

FRAGMENT_SHADER_INVOCATIONS, DEPTH_CLAMP = 0x82F4, 0x864F


def _count(kind: int, draw) -> int:
    from OpenGL import GL

    query = GL.glGenQueries(1)
    query = int(query[0]) if hasattr(query, "__len__") else int(query)
    GL.glBeginQuery(kind, query)
    draw()
    GL.glEndQuery(kind)
    count = int(GL.glGetQueryObjectuiv(query, GL.GL_QUERY_RESULT))
    GL.glDeleteQueries(1, [query])
    return count


def main() -> None:
    from bench_rendering import _sim
    from OpenGL import GL

    from usvsim.rendering.grid import screen_grid, view_cell_px
    from usvsim.viewer.offscreen import OffscreenViewer

    width, height = 1280, 720
    sim = _sim("shader")
    viewer = OffscreenViewer(sim, width, height)
    viewer.render()
    sim.step()
    viewer.render()
    marine = viewer.renderer.marine
    ctx, size = marine.ctx, (width, height)
    first, count = marine._rows
    columns = marine._columns[size]
    water = marine._plain_vaos[size]
    marine._framebuffer().use()
    GL.glDisable(GL.GL_STENCIL_TEST)
    GL.glDisable(GL.GL_DEPTH_TEST)
    GL.glDisable(GL.GL_SCISSOR_TEST)
    ctx.enable_direct(DEPTH_CLAMP)

    def grid():
        water.render(vertices=(count - 1) * (columns - 1) * 6, first=first * (columns - 1) * 6)

    out = {"water": {"invocations": _count(FRAGMENT_SHADER_INVOCATIONS, grid),
                     "pixels": _count(GL.GL_SAMPLES_PASSED, grid)}}  # fmt: skip
    flat = ctx.program(
        vertex_shader="#version 330\nin vec2 p;\nvoid main() { gl_Position = vec4(p, 0.0, 1.0); }",
        fragment_shader="#version 330\nout vec4 c;\nvoid main() { c = vec4(1.0); }",
    )
    full = ctx.program(
        vertex_shader="#version 330\nvoid main() { gl_Position = vec4(gl_VertexID == 1 ? 3.0 : -1.0, "
        "gl_VertexID == 2 ? 3.0 : -1.0, 0.0, 1.0); }",
        fragment_shader="#version 330\nout vec4 c;\nvoid main() { c = vec4(1.0); }",
    )
    vertices, indices, _ = screen_grid(width, height, view_cell_px(height), 0.0)
    vbo, ibo = ctx.buffer(vertices.tobytes()), ctx.buffer(indices.tobytes())
    cells = ctx.vertex_array(flat, [(vbo, "2f", "p")], index_buffer=ibo, index_element_size=4)
    screen = ctx.vertex_array(full, [])
    for name, vao, vertices_ in (("flat_grid", cells, None), ("full_screen_triangle", screen, 3)):
        draw = (lambda v=vao: v.render()) if vertices_ is None else (lambda v=vao: v.render(vertices=3))
        out[name] = {"invocations": _count(FRAGMENT_SHADER_INVOCATIONS, draw), "pixels": _count(GL.GL_SAMPLES_PASSED, draw)}
    for entry in out.values():
        entry["per_pixel"] = round(entry["invocations"] / max(entry["pixels"], 1), 3)
    out["cell_px"] = view_cell_px(height)
    for obj in (cells, screen, vbo, ibo, flat, full):
        obj.release()
    viewer.close()
    sim.close()
    print(json.dumps(out))


if __name__ == "__main__":
    main()
