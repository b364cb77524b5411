"""The documentation pictures: the harbour in several looks, from the viewer and from the onboard camera.

`render_gallery(out_dir)` writes docs/gallery/*.png (examples/gallery.py runs it); `scenario_dict` is the
harbour with one VGA camera on the WAM-V, a sea state and a look, also used by benchmarks/bench_rendering.py.
"""

from __future__ import annotations

import tempfile
from importlib.resources import files
from pathlib import Path

import yaml

CAMERA = {"type": "camera", "name": "camera", "horizontal_fov_deg": 80.0, "rate_hz": 10, "near_m": 0.05,
          "far_m": 400.0, "streams": ["rgb", "depth", "segmentation"], "mount": {"position": [0.3, 0.0, 1.3]}}  # fmt: skip
LOOKS = {  # name: (sea state, look, view: "viewer" or "camera")
    "calm_noon": (1, {"sun": {"azimuth_deg": 160.0, "elevation_deg": 55.0}, "shadows": True}, "viewer"),
    "sea_state_5": (5, {"sun": {"azimuth_deg": 120.0, "elevation_deg": 30.0}}, "viewer"),
    "dawn_haze": (
        2,
        {"sun": {"azimuth_deg": 78.0, "elevation_deg": 5.0, "intensity": 2.5}, "sky": {"turbidity": 6.0},
         "haze": {"visibility_m": 5000.0}},  # intensity: as a camera would expose for dawn
        "viewer",
    ),
    "fog": (3, {"fog": {"visibility_m": 250.0}, "sun": {"elevation_deg": 25.0}}, "viewer"),
    "dusk": (2, {"sun": {"azimuth_deg": 300.0, "elevation_deg": -3.0}}, "viewer"),
    "onboard_sea_state_4": (4, {"sun": {"azimuth_deg": 100.0, "elevation_deg": 20.0}}, "camera"),
    "wake": (2, {"sun": {"azimuth_deg": 230.0, "elevation_deg": 30.0}, "shadows": True}, "viewer"),
    "rain_onboard": (
        4,
        {"sun": {"azimuth_deg": 270.0, "elevation_deg": 35.0, "intensity": 0.6}, "sky": {"turbidity": 8.0},
         "fog": {"visibility_m": 1500.0}, "rain": {"rate_mm_h": 8.0}, "camera": {"droplets": 0.5}},
        "camera",
    ),  # fmt: skip
    "shallow_clear": (0, {"sun": {"azimuth_deg": 110.0, "elevation_deg": 55.0}, "water": {"clarity_m": 6.0}}, "shore"),
    "rain_rings": (
        1,
        {"sun": {"azimuth_deg": 250.0, "elevation_deg": 30.0, "intensity": 0.8}, "sky": {"turbidity": 6.0},
         "fog": {"visibility_m": 2000.0}, "rain": {"rate_mm_h": 5.0}},
        "camera",
    ),  # fmt: skip
    "motion_blur": (3, {"sun": {"azimuth_deg": 200.0, "elevation_deg": 25.0}, "camera": {"motion_blur_ms": 60.0}}, "camera"),
}
SHORE = {  # "shore" views: harbor_geo's origin moved onto its western shore (m east), kept extent (m), viewer pose
    "shallow_clear": (-1150.0, 400.0, ((-20.0, -2.0, 0.0), 40.0, 190.0, -45.0)),
}
UNDER_WAY = {  # looks drawn with the WAM-V under way: thrust, seconds, start pose (open water west of the buoys)
    "wake": (1.0, 12.0, {"position": [8.0, -30.0, 0.0], "yaw_deg": 180.0}),
    "motion_blur": (1.0, 8.0, {"position": [-5.0, -45.0, 0.0], "yaw_deg": 90.0}),  # north, toward the buoys
}


def scenario_dict(sea_state: int, look: dict, width: int = 640, height: int = 480) -> dict:
    """The built-in harbour with a sea state, a `rendering:` look and one camera `wamv/camera`."""
    raw = yaml.safe_load((files("usvsim.scenarios") / "harbor_sensors.yaml").read_text())
    raw["environment"] = {"sea": {"type": "sea_state", "code": sea_state}}
    raw["vessels"][0]["sensors"] = [{**CAMERA, "width": width, "height": height}]
    raw["rendering"] = {"renderer": "shader", **look}
    return raw


def shore_dict(name: str, look: dict) -> dict:
    """harbor_geo with its origin `SHORE[name][0]` m east of the scenario's (its water shoals from ~4 m to the
    shore ~40 m west of it), a smaller kept extent (finer seabed cells: 6 m instead of 47) and a calm sea."""
    import math

    east_m, extent_m, _ = SHORE[name]
    src = files("usvsim.scenarios") / "harbor_geo.yaml"
    raw = yaml.safe_load(src.read_text())
    origin = raw["world"]["origin"]
    origin["longitude_deg"] += math.degrees(east_m / (6378137.0 * math.cos(math.radians(origin["latitude_deg"]))))
    geo = raw["geo"]
    geo["extent_m"], geo["marks"] = extent_m, []  # the fairway's marks lie farther out
    for part in [geo["land"], geo["bathymetry"], *geo["structures"]]:
        part["file"] = str(Path(str(src)).parent / part["file"])
    raw["environment"] = {"sea": {"type": "jonswap", "hs_m": 0.15, "tp_s": 3.0, "direction_deg": 200}}
    raw["vessels"][0]["pose"] = {"position": [-5.0, -6.0, 0.0], "heading_deg": 20.0}
    raw["rendering"] = {"renderer": "shader", **look}
    return raw


def load(raw: dict, seed: int = 0):
    from usvsim.config.loader import load_scenario
    from usvsim.simulation import Simulation

    path = Path(tempfile.mkdtemp()) / "gallery.yaml"
    path.write_text(yaml.safe_dump(raw))
    return Simulation(load_scenario(path), seed=seed)


def render_look(name: str, out_dir: Path, width: int = 960, height: int = 540, settle_s: float = 6.0) -> Path:
    """One picture of `LOOKS[name]` after `settle_s` simulated seconds, written to `out_dir/name.png`."""
    from usvsim.viewer.offscreen import OffscreenViewer, save_png

    sea_state, look, view = LOOKS[name]
    raw = shore_dict(name, look) if view == "shore" else scenario_dict(sea_state, look, width, height)
    if name in UNDER_WAY:
        raw["vessels"][0]["pose"] = UNDER_WAY[name][2]
    sim = load(raw)
    try:
        if name in UNDER_WAY:
            thrust, seconds, _ = UNDER_WAY[name]
            sim.vessels["wamv"].command(thrust, 0.0)
            settle_s = seconds
        sim.run(settle_s)
        if view == "camera":
            from usvsim.sensors.camera.sensor import Camera

            camera = sim.sensors["wamv/camera"]
            assert isinstance(camera, Camera)
            return save_png(camera.render(sim.world)["rgb"], Path(out_dir) / f"{name}.png")
        viewer = OffscreenViewer(sim, width, height)
        viewer.view.show_hud = False
        if view == "shore":
            import numpy as np

            from usvsim.viewer.camera import CameraPose

            lookat, distance, azimuth, elevation = SHORE[name][2]
            pose = CameraPose(np.array(lookat), distance, azimuth, elevation)
            viewer.view.camera_pose = lambda dt=0.0, pose=pose: pose
        try:
            return save_png(viewer.render(), Path(out_dir) / f"{name}.png")
        finally:
            viewer.close()
    finally:
        sim.close()


def render_gallery(out_dir: Path, width: int = 960, height: int = 540, names=None) -> list[Path]:
    return [render_look(name, out_dir, width, height) for name in (names or LOOKS)]


HUD_S = 2.0  # simulated seconds the README's viewer runs as the interactive viewer would before its screenshot


def run_in_real_time(viewer, until_s: float) -> None:
    """Draw frames as the interactive viewer does (each frame steps the simulation by the wall time the last one
    took, at most 0.25 s) until `until_s`, so that the HUD's frame rate and real-time factor are measured ones."""
    import time

    sim = viewer.sim
    dt = sim.clock.dt
    last = time.perf_counter()
    viewer.render()
    while sim.time < until_s - 1e-9:
        now = time.perf_counter()
        wall_dt, t0 = now - last, sim.time
        last = now
        steps = max(1, min(round(min(wall_dt, 0.25) / dt), round((until_s - sim.time) / dt)))
        for _ in range(steps):
            sim.step()
        viewer.view.rates.update(wall_dt, sim.time - t0)
        viewer.render(wall_dt)


README_LOOK = {"sun": {"azimuth_deg": 290.0, "elevation_deg": 24.0}, "shadows": True}


def render_readme(out_dir: Path, width: int = 1280, height: int = 720) -> list[Path]:
    """docs/harbor.png (the harbour from the south-east, the WAM-V under way with its wake, sea state 2) and
    docs/viewer.png (the viewer's follow camera and HUD, sea state 4, under way)."""
    import numpy as np

    from usvsim.viewer.camera import CameraPose
    from usvsim.viewer.offscreen import OffscreenViewer, save_png

    out = []
    for name, sea_state, seconds in (("harbor", 2, 10.0), ("viewer", 4, 8.0)):
        raw = scenario_dict(sea_state, README_LOOK, 640, 480)
        raw["vessels"][0]["pose"] = UNDER_WAY["wake"][2]
        sim = load(raw)
        try:
            sim.vessels["wamv"].command(0.8, 0.0)
            sim.run(seconds - (HUD_S if name == "viewer" else 0.0))
            viewer = OffscreenViewer(sim, width, height)
            try:
                if name == "harbor":
                    viewer.view.show_hud = False
                    pose = CameraPose(np.array([-8.0, -17.0, 0.0]), 58.0, 128.0, -17.0)
                    viewer.view.camera_pose = lambda dt=0.0, pose=pose: pose
                else:
                    run_in_real_time(viewer, sim.time + HUD_S)
                out.append(save_png(viewer.render(), Path(out_dir) / f"{name}.png"))
            finally:
                viewer.close()
        finally:
            sim.close()
    return out
