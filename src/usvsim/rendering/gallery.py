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
        {"sun": {"utc": "2025-06-21T02:50:00Z"}, "sky": {"turbidity": 6.0}, "haze": {"visibility_m": 5000.0}},
        "viewer",
    ),
    "fog": (3, {"fog": {"visibility_m": 250.0}, "sun": {"elevation_deg": 25.0}}, "viewer"),
    "dusk": (2, {"sun": {"azimuth_deg": 300.0, "elevation_deg": -3.0}}, "viewer"),
    "onboard_sea_state_4": (4, {"sun": {"azimuth_deg": 100.0, "elevation_deg": 20.0}}, "camera"),
}


def scenario_dict(sea_state: int, look: dict, width: int = 640, height: int = 480) -> dict:
    """The built-in harbour with a sea state, a `rendering:` look and one camera `wamv/camera`."""
    raw = yaml.safe_load((files("usvsim.scenarios") / "harbor_sensors.yaml").read_text())
    raw["environment"] = {"sea": {"type": "sea_state", "code": sea_state}}
    raw["vessels"][0]["sensors"] = [{**CAMERA, "width": width, "height": height}]
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
    sim = load(scenario_dict(sea_state, look, width, height))
    try:
        sim.run(settle_s)
        if view == "camera":
            from usvsim.sensors.camera.sensor import Camera

            camera = sim.sensors["wamv/camera"]
            assert isinstance(camera, Camera)
            return save_png(camera.render(sim.world)["rgb"], Path(out_dir) / f"{name}.png")
        viewer = OffscreenViewer(sim, width, height)
        viewer.view.show_hud = False
        try:
            return save_png(viewer.render(), Path(out_dir) / f"{name}.png")
        finally:
            viewer.close()
    finally:
        sim.close()


def render_gallery(out_dir: Path, width: int = 960, height: int = 540, names=None) -> list[Path]:
    return [render_look(name, out_dir, width, height) for name in (names or LOOKS)]
