"""Rendering: offscreen frames (EGL) and the real window under Xvfb driving a lap of the harbour."""

from __future__ import annotations

import json
import os
import random
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

HERE = Path(__file__).resolve().parent
SCRIPT = HERE / "render_scripts.py"


def run_script(kind: str, out: Path, env: dict, timeout: float = 300) -> dict:
    proc = subprocess.run([sys.executable, str(SCRIPT), kind, str(out)], env=env, capture_output=True, text=True,
                          timeout=timeout)  # fmt: skip
    assert proc.returncode == 0, proc.stderr[-3000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])


def load(path) -> np.ndarray:
    from PIL import Image

    return np.asarray(Image.open(path).convert("RGB")).astype(int)


def test_offscreen_frame_has_waves_hud_points_and_inset(tmp_path):
    env = dict(os.environ, MUJOCO_GL="egl")
    env.pop("PYOPENGL_PLATFORM", None)
    result = run_script("offscreen", tmp_path / "frame.png", env)
    frame, plain = load(result["frame"]), load(result["plain"])
    assert frame.shape == (720, 1280, 3)
    # the inset (top-right, 28 % of the width) shows the synthetic image: red left half, green right half
    x0, y0 = 1280 - 10 - int(1280 * 0.28), 10
    red, green = frame[y0 + 20, x0 + 40], frame[y0 + 20, 1280 - 10 - 40]
    assert red[0] > 200 and red[1] < 60 and green[1] > 200 and green[0] < 60
    # the water below the horizon is not one flat colour: waves are drawn
    water = plain[450:700, 100:1180]
    assert water.std(axis=(0, 1)).max() > 6.0
    assert water[..., 2].mean() > water[..., 0].mean()  # and it is blue
    # the HUD darkens the top-left panel and writes light text into it
    panel = frame[10:300, 10:400]
    assert (panel.sum(axis=2) > 600).mean() > 0.01
    assert not np.array_equal(frame[10:300, 10:400], plain[10:300, 10:400])
    # the point ring (coloured cubes) adds pixels the plain frame lacks
    assert (np.abs(frame - plain).sum(axis=2) > 60)[300:700].sum() > 200


def test_geoms_out_of_view_are_culled_without_changing_a_pixel(tmp_path):
    env = dict(os.environ, MUJOCO_GL="egl")
    env.pop("PYOPENGL_PLATFORM", None)
    stats = run_script("culled", tmp_path / "unused.png", env)
    for renderer in ("shader", "mujoco"):
        assert stats[renderer]["same"], stats  # the same bytes with and without culling
        assert stats[renderer]["culled"] > 100, stats  # most of the 252 mooring-line segments lie out of view


def test_the_mono_water_is_drawn_from_the_eye_the_geoms_are(tmp_path):
    env = dict(os.environ, MUJOCO_GL="egl")
    env.pop("PYOPENGL_PLATFORM", None)
    stats = run_script("eye_distance", tmp_path / "unused.png", env)
    assert stats["ipds"][0] > 0.0 and stats["same"], stats


def test_sea_textures_made_on_the_worker_thread_give_the_same_bytes(tmp_path):
    stats = run_script("sea_overlap", tmp_path / "unused.png", dict(os.environ, MUJOCO_GL="egl"))
    assert stats["frames"] == 6 and stats["shape"] == [180, 320, 3]
    assert stats["differing"] == 0


def test_water_over_geoms_drawn_by_the_quads_that_reach_them_gives_the_same_bytes(tmp_path):
    """The water's program for pixels with a geom behind runs over the quads whose displaced corners' box meets a
    geom's box only (MarinePass._over_geoms_runs); the viewer's picture is the one drawn with every quad, and every
    pixel where MuJoCo drew a geom lies in the image of the boxes (cull.drawn_boxes)."""
    env = dict(os.environ, MUJOCO_GL="egl")
    env.pop("PYOPENGL_PLATFORM", None)
    stats = run_script("over_geoms", tmp_path / "unused.png", env)
    for view in stats:
        assert view["same"], stats
        assert view["boxes"] > 0 and 0 < view["over_geoms"] < view["quads"], stats
        assert view["geom_pixels_outside"] == 0, stats  # every pixel MuJoCo drew lies in its geoms' boxes


def start_xvfb():
    if shutil.which("Xvfb") is None:
        pytest.skip("Xvfb is not installed (apt-get install xvfb)")
    for _ in range(5):
        display = f":{random.randint(100, 999)}"
        proc = subprocess.Popen(["Xvfb", display, "-screen", "0", "1280x800x24", "-nolisten", "tcp"],
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)  # fmt: skip
        time.sleep(1.0)
        if proc.poll() is None:
            return proc, display
    pytest.skip("could not start Xvfb")


def test_window_drives_a_lap_of_the_harbor_under_xvfb(tmp_path):
    xvfb, display = start_xvfb()
    try:
        env = {k: v for k, v in os.environ.items() if k not in ("MUJOCO_GL", "PYOPENGL_PLATFORM")}
        env["DISPLAY"] = display
        result = run_script("lap", tmp_path / "window.png", env)
    finally:
        xvfb.terminate()
        xvfb.wait(timeout=10)
    assert result["sim_time"] >= 33.9
    track, start = np.array(result["track"]), np.array(result["start"])
    path = np.linalg.norm(np.diff(track, axis=0), axis=1).sum()
    travelled = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(track, axis=0), axis=1))])
    closest = np.linalg.norm(track[travelled > 40.0] - start, axis=1).min()
    assert path >= 60.0 and closest < 3.0, (path, closest)
    shot = load(tmp_path / "window.png")
    assert shot.shape == (720, 1280, 3)
    assert shot.std() > 10  # a real picture, not a blank buffer
    assert result["frames"] > 20


def test_window_with_the_shader_look_under_xvfb(tmp_path):
    xvfb, display = start_xvfb()
    try:
        env = {k: v for k, v in os.environ.items() if k not in ("MUJOCO_GL", "PYOPENGL_PLATFORM")}
        env["DISPLAY"] = display
        result = run_script("shader_window", tmp_path / "shader.png", env)
    finally:
        xvfb.terminate()
        xvfb.wait(timeout=10)
    shot = load(tmp_path / "shader.png")
    assert shot.shape == (720, 1280, 3) and shot.std() > 10
    assert shot[5:60, 500:800, 2].mean() > shot[5:60, 500:800, 0].mean()  # sky at the top, bluish
    assert result["frames"] >= 1
