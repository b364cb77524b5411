"""Scripts the rendering tests run in a fresh interpreter (the GL platform is chosen when MuJoCo loads).

python render_scripts.py offscreen OUT.png     # MUJOCO_GL=egl: waves, HUD, points and inset
python render_scripts.py lap OUT.png           # DISPLAY=...: the windowed viewer drives the harbour lap
"""

from __future__ import annotations

import json
import sys

import numpy as np


def synthetic_inset() -> np.ndarray:
    image = np.zeros((120, 160, 3), dtype=np.uint8)
    image[:, :80] = (255, 0, 0)
    image[:, 80:] = (0, 255, 0)
    return image


def offscreen(out: str) -> None:
    from usvsim.simulation import Simulation
    from usvsim.viewer.demo import harbor_with_waves
    from usvsim.viewer.offscreen import OffscreenViewer

    sim = Simulation(harbor_with_waves())
    for _ in range(300):
        sim.vessels["wamv"].command(0.8, 0.0)
        sim.step()
    boat = sim.vessels["wamv"].position
    ring = np.linspace(0, 2 * np.pi, 400, endpoint=False)
    points = np.stack(
        [boat[0] + 6 * np.cos(ring), boat[1] + 6 * np.sin(ring), np.full_like(ring, 1.0)], axis=1
    )
    viewer = OffscreenViewer(sim, 1280, 720)
    viewer.view.points, viewer.view.inset = points, synthetic_inset()
    viewer.save(out)
    viewer.view.points = viewer.view.inset = None
    viewer.view.show_hud = False
    plain = out.replace(".png", "_plain.png")
    viewer.save(plain)
    viewer.close()
    print(json.dumps({"frame": out, "plain": plain}))


def lap(out: str) -> None:
    from usvsim.simulation import Simulation
    from usvsim.viewer.app import run_viewer
    from usvsim.viewer.demo import HARBOR_LAP, HARBOR_LAP_SECONDS

    sim = Simulation.from_scenario("harbor")
    sim.look = sim.look.updated({"renderer": "mujoco"})  # the lap tests driving: the cheap look keeps it short
    boat = sim.vessels["wamv"]
    start, track = boat.position[:2].copy(), []
    stats = run_viewer(sim, script=HARBOR_LAP, max_seconds=HARBOR_LAP_SECONDS, screenshot=out, time_scale=4.0,
                       points=lambda s: track.append(s.vessels["wamv"].position.copy()) or np.array(track))  # fmt: skip
    stats.update(start=start.tolist(), track=[p[:2].tolist() for p in track], sim_time=sim.time)
    print(json.dumps(stats))


def shader_window(out: str) -> None:
    """A few frames of the shader look in a real window: moderngl attached to a GLX context."""
    from usvsim.simulation import Simulation
    from usvsim.viewer.app import run_viewer

    sim = Simulation.from_scenario("harbor")
    sim.look = sim.look.updated({"renderer": "shader"})
    stats = run_viewer(sim, max_seconds=0.2, screenshot=out, gamepad=False)
    print(json.dumps(stats))


def culled(out: str) -> None:
    """The benchmark's viewer frame (harbour, sea state 4) in both looks with and without frustum culling."""
    import mujoco

    from usvsim.rendering.gallery import load, scenario_dict
    from usvsim.viewer.offscreen import OffscreenViewer

    stats = {}
    for renderer in ("shader", "mujoco"):
        sim = load(scenario_dict(4, {"renderer": renderer, "fog": {"visibility_m": 2000.0}}, 64, 48))
        sim.run(3.0)  # as the benchmark: the mooring lines are drawn in 252 segments by then
        viewer = OffscreenViewer(sim, 640, 360)
        frame = viewer.render()
        scene = viewer.renderer.scene
        count = sum(int(g.type) == int(mujoco.mjtGeom.mjGEOM_NONE) for g in scene.geoms[: scene.ngeom])
        viewer.renderer.cull = lambda width, height: 0
        full = viewer.render()
        stats[renderer] = {"culled": count, "geoms": scene.ngeom, "same": bool(np.array_equal(frame, full))}
        viewer.close()
        sim.close()
    print(json.dumps(stats))


def eye_distance(out: str) -> None:
    """The shader look's viewer frame with MuJoCo's stereo eye distance (`vis.global.ipd`) at its default and at 0:
    a mono picture is drawn from the eyes' mean, so both must be the same bytes (the water was drawn from the
    left eye once, 3.4 cm beside the geoms)."""
    from usvsim.rendering.gallery import load, scenario_dict
    from usvsim.viewer.offscreen import OffscreenViewer

    sim = load(scenario_dict(4, {"renderer": "shader", "fog": {"visibility_m": 2000.0}}, 64, 48))
    sim.run(1.0)
    viewer = OffscreenViewer(sim, 320, 180)
    frames = {}
    for ipd in (float(sim.model.vis.global_.ipd), 0.0):
        sim.model.vis.global_.ipd = ipd
        frames[ipd] = viewer.render()
    viewer.close()
    sim.close()
    (a, b) = frames.values()
    print(json.dumps({"ipds": list(frames), "same": bool(np.array_equal(a, b)), "differing": int((a != b).any(2).sum())}))


def geom_pixels_outside_boxes(viewer, boxes) -> int:
    """How many pixels of the frame just drawn hold a geom (the stencil's GEOM_BIT, marked where MuJoCo wrote depth)
    outside the image boxes of `boxes` (cull.drawn_boxes)."""
    import mujoco
    from OpenGL import GL

    from usvsim.rendering.marine import GEOM_BIT, camera_matrices

    width, height = viewer.viewport.width, viewer.viewport.height
    scene = viewer.renderer.scene
    view_proj, _, _, _ = camera_matrices(mujoco.mjv_averageCamera(scene.camera[0], scene.camera[1]), width, height)
    stencil = np.empty((height, width), np.uint8)
    GL.glBindFramebuffer(GL.GL_READ_FRAMEBUFFER, viewer.renderer.marine._framebuffer().glo)
    GL.glPixelStorei(GL.GL_PACK_ALIGNMENT, 1)
    GL.glReadPixels(0, 0, width, height, GL.GL_STENCIL_INDEX, GL.GL_UNSIGNED_BYTE, stencil)
    clip = boxes @ view_proj[:, :3].T + view_proj[:, 3]
    x = (clip[..., 0] / clip[..., 3] + 1.0) * 0.5 * width
    y = (clip[..., 1] / clip[..., 3] + 1.0) * 0.5 * height
    inside = np.zeros((height, width), bool)
    for x0, x1, y0, y1 in zip(x.min(axis=1), x.max(axis=1), y.min(axis=1), y.max(axis=1)):
        inside[max(int(np.floor(y0)), 0) : max(int(np.ceil(y1)) + 1, 0), max(int(np.floor(x0)), 0) : max(int(np.ceil(x1)) + 1, 0)] = True
    return int(((stencil & GEOM_BIT) > 0)[~inside].sum())


def over_geoms(out: str) -> None:
    """The shader viewer's frames (harbour, sea state 4, the benchmark's view and one from low over the buoys) with
    the water over geoms drawn by the quads that can reach a geom's pixel only (cull.drawn_boxes) and by every
    quad: the same bytes, and fewer quads."""
    from usvsim.rendering import cull
    from usvsim.rendering.gallery import load, scenario_dict
    from usvsim.viewer.camera import CameraPose
    from usvsim.viewer.offscreen import OffscreenViewer

    sim = load(scenario_dict(4, {"renderer": "shader", "fog": {"visibility_m": 2000.0}}, 64, 48))
    sim.run(3.0)
    viewer = OffscreenViewer(sim, 640, 360)
    stats = []
    for pose in (None, CameraPose(np.array([-6.0, -2.0, 0.0]), 25.0, 200.0, -25.0)):
        if pose is not None:
            viewer.view.camera_pose = lambda dt=0.0, pose=pose: pose
        boxes = cull.drawn_boxes
        selected = viewer.render()
        marine = viewer.renderer.marine
        first, count = marine._rows
        columns = marine._columns[(640, 360)]
        runs = marine._over_geoms  # None: every quad
        drawn = -1 if runs is None else int(np.diff(np.clip(runs, first * (columns - 1), (first + count - 1) * (columns - 1)), axis=1).sum())
        frame_boxes = cull.drawn_boxes(viewer.renderer.scene, sim.model)  # the frame's, as the viewer gave them
        n = len(frame_boxes) if frame_boxes is not None else -1
        outside = geom_pixels_outside_boxes(viewer, frame_boxes) if n > 0 else -1
        cull.drawn_boxes = lambda scene, model: None
        every = viewer.render()
        cull.drawn_boxes = boxes
        stats.append({"same": bool(np.array_equal(selected, every)), "quads": (count - 1) * (columns - 1),
                      "over_geoms": drawn, "boxes": n, "geom_pixels_outside": outside})
    viewer.close()
    sim.close()
    print(json.dumps(stats))


def sea_overlap(out: str) -> None:
    """The shader viewer's frames with the ocean's textures made on the worker thread (the default) and on the
    drawing thread (two viewers of one simulation, each with its own textures), the simulation stepping between
    frames (new tiles every frame) and standing still (no upload): the same bytes."""
    from usvsim.rendering.gallery import load, scenario_dict
    from usvsim.viewer.offscreen import OffscreenViewer

    sim = load(scenario_dict(4, {"renderer": "shader"}, 64, 48))
    sim.run(1.0)
    worker, serial = OffscreenViewer(sim, 320, 180), OffscreenViewer(sim, 320, 180)
    serial.renderer.overlap = None
    differing, frames = 0, 0
    for k in range(6):
        if k % 3:
            sim.run(0.05)
        a, b = worker.render(), serial.render()
        differing += int((a != b).any(2).sum())
        frames += 1
    worker.close()
    serial.close()
    sim.close()
    print(json.dumps({"frames": frames, "differing": differing, "shape": list(a.shape)}))


if __name__ == "__main__":
    kinds = {"offscreen": offscreen, "lap": lap, "shader_window": shader_window, "culled": culled,
             "eye_distance": eye_distance, "over_geoms": over_geoms, "sea_overlap": sea_overlap}
    kinds[sys.argv[1]](sys.argv[2])
