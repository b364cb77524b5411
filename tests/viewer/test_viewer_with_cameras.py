"""`usvsim run harbor_sensors --view` (camera sensors beside the viewer window) under Xvfb: no X error, a real
frame (sky above water) in the screenshot, and exactly the requested simulated time."""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
from PIL import Image
from test_rendering import start_xvfb


def test_viewer_runs_a_scenario_with_camera_sensors(tmp_path):
    xvfb, display = start_xvfb()
    shot = tmp_path / "view.png"
    env = {k: v for k, v in os.environ.items() if k not in ("MUJOCO_GL", "PYOPENGL_PLATFORM")}
    env.update(DISPLAY=display, NO_COLOR="1")
    video = tmp_path / "view.mp4"
    cmd = [sys.executable, "-m", "usvsim.cli", "run", "harbor_sensors", "--view", "--duration", "0.3",
           "--screenshot", str(shot), "--video", str(video)]  # fmt: skip
    try:
        result = subprocess.run(cmd, capture_output=True, text=True, timeout=300, env=env)
    finally:
        xvfb.terminate()
        xvfb.wait(timeout=10)
    assert result.returncode == 0, result.stderr[-2000:]
    assert "simulated 0.30 s" in result.stdout
    image = np.asarray(Image.open(shot).convert("RGB"), dtype=float)
    sky, water = image[:60, 600:700].mean(axis=(0, 1)), image[600:, 300:500].mean(axis=(0, 1))
    assert sky[2] > 150 and sky[2] > sky[0]  # a light blue sky at the top (not black, not noise)
    assert water[2] > water[0] and water.sum() < sky.sum()  # darker blue water below
    assert image[:60, 600:700].std(axis=(0, 1)).max() < 20  # smooth, not a garbage framebuffer
    import cv2

    reader = cv2.VideoCapture(str(video))
    ok, first = reader.read()
    assert ok and first.shape == (720, 1280, 3) and int(reader.get(cv2.CAP_PROP_FRAME_COUNT)) >= 2


def test_screenshot_key_is_reported_once():
    from usvsim.viewer.driver import ManualDriver

    class Sim:  # the driver only needs vessels and the clock here
        vessels = {"boat": type("V", (), {"position": (0.0, 0.0, 0.0), "rpy": (0.0, 0.0, 0.0)})()}
        clock = type("C", (), {"dt": 0.01})()

    driver = ManualDriver(Sim())
    driver.key("p", "press")
    assert driver.take_screenshot_request() and not driver.take_screenshot_request()


def test_viewer_window_is_visible_and_cameras_work_after_it_closes():
    """Camera sensors' contexts are hidden GLFW windows whose VISIBLE 0 hint stayed set, so the viewer's own
    window was created invisible (a user with a display saw nothing); and closing the viewer called
    glfw.terminate(), which destroyed the cameras' windows: their next images had a black sky and a grey band."""
    import json
    from pathlib import Path

    xvfb, display = start_xvfb()
    env = {k: v for k, v in os.environ.items() if k not in ("MUJOCO_GL", "PYOPENGL_PLATFORM")}
    env.update(DISPLAY=display)
    script = Path(__file__).with_name("viewer_then_cameras.py")
    try:
        result = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=300, env=env)
    finally:
        xvfb.terminate()
        xvfb.wait(timeout=10)
    assert result.returncode == 0, result.stderr[-2000:]
    out = json.loads(result.stdout.strip().splitlines()[-1])
    assert out["visible"] == 1
    red, green, blue = out["sky"]
    assert blue > 150 and blue > red  # the painted light-blue sky, not black
    assert "not initialized" not in result.stderr
