"""Re-renders a data set's frame from its metadata file (`meta/<stem>.json`) and the run's `dataset.json`.

The world is rebuilt from the scenario with the run's drawn environment, reset with the episode's seed (its
ocean), and put in the recorded state: MuJoCo qpos and clock steps (time), kinematic traffic ships placed
for that time. The camera renders from the recorded pose under the recorded look, labels come from the
segmentation as when the set was written, and the look's image noise is drawn from the same per-frame
generator: the image, masks and labels equal the written ones bit for bit (tests/datasets/test_rerender.py).
"""

from __future__ import annotations

import json
from pathlib import Path

import mujoco
import numpy as np

from usvsim.config.rendering import Rendering
from usvsim.datasets.generate import DatasetGenerator, DatasetSpec
from usvsim.datasets.labels import ObjectLabel


def rerender(root: Path, stem: str) -> dict:
    """{'rgb', 'instance', 'semantic', 'labels'} of frame `stem` of the data set in `root`."""
    root = Path(root)
    run = json.loads((root / "dataset.json").read_text())
    meta = json.loads((root / "meta" / f"{stem}.json").read_text())
    spec = DatasetSpec(run["scenario"], 1, root, tuple(run["formats"]), run["seed"], None,
                       tuple(run["resolution"]) if run["resolution"] else None, min_visible_pixels=run["min_visible_pixels"],
                       min_visible_fraction=run["min_visible_fraction"], horizontal_fov_deg=run["horizontal_fov_deg"],
                       amodal_masks=run["amodal_masks"], renderer=run.get("renderer"))  # fmt: skip
    gen = DatasetGenerator(spec, environment=run["environment"])
    try:
        names = [f"{vessel}/{cam.cfg.name}" for vessel, cam in gen.cameras]
        k = names.index(meta["camera"])
        sim = gen.sim
        sim.reset(seed=meta["seed"])
        sim.data.qpos[:] = meta["qpos"]
        clock = sim.world.clock
        clock.steps = meta["clock_steps"]
        clock.now_ns = clock.steps * clock.step_ns
        mujoco.mj_forward(sim.model, sim.data)
        sim.world._update_kinematics()  # as generate.apply_scene
        sim.traffic.fleet.place_now(sim.world)  # traffic ships where the clock puts them
        look = Rendering.model_validate(meta["look"])
        pos, rot = np.array(meta["camera_position_m"]), np.array(meta["camera_rotation_flu_to_world"])
        images, labels = gen.render(k, pos, rot, look)
        rng = np.random.default_rng([run["seed"], meta["frame"], k])
        rgb = gen.looks[k].after(look, images["rgb"], images["depth"], rng)
        instance, semantic = gen.labellers[k].masks(images["segmentation"], labels, images.get("fog_hidden"))
    finally:
        gen.close()
    return {"rgb": rgb, "instance": instance, "semantic": semantic, "labels": labels}


def labels_of(meta: dict) -> list[ObjectLabel]:
    """The labels recorded in a metadata file, as ObjectLabel."""
    return [ObjectLabel(**{**o, "visible_box": tuple(o["visible_box"]), "amodal_box": tuple(o["amodal_box"])})
            for o in meta["objects"]]  # fmt: skip
