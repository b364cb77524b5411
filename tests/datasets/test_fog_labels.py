"""Labels only for what the fog leaves visible (datasets/fog_sight.py): a wall 3 km away in 300 m fog (its pixels
are fog colour to within exp(-39)) got a label; now an object pixel counts only where the fog's transmittance
along its ray reaches Koschmieder's 2 %, computed as the active renderer draws the fog. Checked against closed
forms: exp(-3.912 r / V) per pixel for MuJoCo's look, and for the shader's height fog (with rain) the optical
depth integrated numerically along each pixel's ray."""

from __future__ import annotations

import math

import numpy as np
import pytest
import yaml

from usvsim.datasets.fog_sight import CONTRAST_THRESHOLD
from usvsim.datasets.generate import DatasetGenerator, DatasetSpec, jittered_pose
from usvsim.sensors.base import OPTICAL_ROT

VISIBILITY_M = 300.0
NEAR_FACE = np.array([99.0, -20.0, 2.0])  # centre of the near box's face toward the camera (ENU, m)
SCENE = {
    "version": 1,
    "name": "fog_labels",
    "world": {"physics_rate_hz": 100},
    "vessels": [{"name": "wamv", "model": "wamv", "sensors": [
        {"type": "camera", "name": "camera", "width": 320, "height": 240, "horizontal_fov_deg": 70, "rate_hz": 10,
         "near_m": 0.5, "far_m": 5000, "streams": ["rgb"], "mount": {"position": [0.3, 0.0, 1.3]}}]}],
    "objects": [
        {"type": "box", "name": "near", "position": [100.0, -20.0, 2.0], "size": [2.0, 10.0, 6.0]},
        {"type": "wall", "name": "far", "position": [3000.0, 300.0, 30.0], "size": [10.0, 200.0, 80.0]},
    ],
}  # fmt: skip


def _frame(tmp_path, renderer: str, look_changes: dict):
    """Labels, images, the labeller, camera intrinsics, eye position, optical → world rotation and sea level of
    one frame of SCENE under the scenario's look with `look_changes`."""
    path = tmp_path / "fog_labels.yaml"
    path.write_text(yaml.safe_dump(SCENE))
    gen = DatasetGenerator(DatasetSpec(str(path), 1, tmp_path / "unused", min_visible_pixels=20, renderer=renderer))
    try:
        look, scene = gen._episode()
        (_, cam), sim = gen.cameras[0], gen.sim
        pos, rot = jittered_pose(cam, sim, scene)
        images, labels = gen.render(0, pos, rot, look.updated(look_changes))
        return labels, images, gen.labellers[0], cam.intrinsics, pos, rot @ OPTICAL_ROT, sim.world.ocean.level_m
    finally:
        gen.close()


def _pixels(images, lab, instance: int):
    return np.nonzero(lab.owner[images["segmentation"]] == instance)


def _check_masks(images, lab, labels, far_index: int):
    """The far wall is in no instance mask (it has no annotation) and keeps its class in the semantic mask."""
    instance, semantic = lab.masks(images["segmentation"], labels, images.get("fog_hidden"))
    far = _pixels(images, lab, far_index + 1)
    assert len(far[0]) >= 20 and not instance[far].any()
    assert (semantic[far] == lab.semantic_lut[lab.objects[far_index].geoms[0] + 1]).all()
    assert set(np.unique(instance)) - {0} == {label.instance for label in labels}


def test_an_object_beyond_the_visibility_gets_no_label_in_the_plain_look(tmp_path):
    clear, _, _, _, _, _, _ = _frame(tmp_path, "mujoco", {})
    assert {x.name for x in clear} == {"near", "far"}  # without fog both are labelled
    assert all(x.fog_transmittance == 1.0 for x in clear)
    labels, images, lab, cam, pos, _, _ = _frame(tmp_path, "mujoco", {"fog": {"visibility_m": VISIBILITY_M}})
    assert [x.name for x in labels] == ["near"]
    near = labels[0]
    # closed form at the face's distance (~101 m; its pixels span ~±2 m of range: ±3 % in transmittance)
    assert near.fog_transmittance == pytest.approx(math.exp(-3.912 * np.linalg.norm(NEAR_FACE - pos) / VISIBILITY_M),
                                                   rel=0.03)  # fmt: skip
    rows, cols = _pixels(images, lab, near.instance)  # Koschmieder per pixel from the ray length
    xy = cam.rays()[rows, cols]
    r = images["depth"][rows, cols].astype(np.float64) * np.sqrt(1.0 + (xy**2).sum(axis=1))
    assert near.fog_transmittance == pytest.approx(np.exp(-3.912 * r / VISIBILITY_M).mean(), rel=1e-9)
    assert near.visible_pixels == len(rows) and near.fog_transmittance > 10 * CONTRAST_THRESHOLD
    _check_masks(images, lab, labels, [o.name for o in lab.objects].index("far"))


def _height_fog_transmittance(r, direction, eye_z, level_m, sigma, height_m, steps=4000):
    """exp(-∫ σ exp(-(z(s) - level) / H) ds) along rays of length r (n,) and unit world directions (n, 3),
    by the trapezoidal rule."""
    s = np.linspace(0.0, 1.0, steps + 1)[None, :] * r[:, None]
    density = sigma * np.exp(-(eye_z + s * direction[:, 2:3] - level_m) / height_m)
    return np.exp(-np.trapezoid(density, s, axis=1))


def test_the_shader_look_labels_by_its_height_fog_and_rain(tmp_path):
    pytest.importorskip("moderngl")
    clear, *_ = _frame(tmp_path, "shader", {})
    assert {x.name for x in clear} == {"near", "far"}
    rain = 10.0
    labels, images, lab, cam, pos, rot_optical, level = _frame(
        tmp_path, "shader", {"fog": {"visibility_m": VISIBILITY_M, "height_falloff_m": 40.0}, "rain": {"rate_mm_h": rain}}
    )
    assert [x.name for x in labels] == ["near"]
    near = labels[0]
    rows, cols = _pixels(images, lab, near.instance)
    xy = cam.rays()[rows, cols]
    ray = np.concatenate([xy, np.ones((len(rows), 1))], axis=1)
    r = images["depth"][rows, cols].astype(np.float64) * np.linalg.norm(ray, axis=1)
    direction = (ray / np.linalg.norm(ray, axis=1, keepdims=True)) @ rot_optical.T
    sigma = 3.912 / VISIBILITY_M + 0.25e-3 * rain**0.63  # config Rain: 0.25·R^0.63 per km added to the fog
    keep = _height_fog_transmittance(r, direction, pos[2], level, sigma, 40.0)
    assert near.fog_transmittance == pytest.approx(keep.mean(), rel=1e-6)
    uniform = math.exp(-sigma * np.linalg.norm(NEAR_FACE - pos))  # the eye ~1.3 m up: density ~0.97 of sea level
    assert uniform < near.fog_transmittance < uniform ** 0.85
    _check_masks(images, lab, labels, [o.name for o in lab.objects].index("far"))
