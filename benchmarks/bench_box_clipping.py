"""Cost of a ground-truth 2D box (sensors/camera/clip.py `image_box`) against OpenCV's `projectPoints` of the
box's 8 corners (the naive box a user would compute, wrong for boxes cut by the image edge or reaching behind the
camera: the baseline, measured in the same run).

Boxes: random sizes (0.3-10 m) and orientations around the camera, kept when some part is in view, on a 640x480
pinhole camera and on a distorting one (plumb_bob, edges sampled); the two ways alternate in each round, so each
median compares like loads (the machine is shared).

    python benchmarks/bench_box_clipping.py [--rounds 15]
Writes benchmarks/results/box_clipping.json: median µs per box of each, the ratio, and the 1-minute load average
before and after.
"""

from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

import cv2
import numpy as np

from usvsim.sensors.camera.clip import camera_planes, image_box
from usvsim.sensors.camera.intrinsics import Intrinsics

RESULTS = Path(__file__).parent / "results" / "box_clipping.json"
SIGNS = np.array([[a, b, c] for a in (-1, 1) for b in (-1, 1) for c in (-1, 1)], dtype=float)


def boxes(cam: Intrinsics, n: int, seed: int) -> list[np.ndarray]:
    """n boxes (8 corners, optical frame m) of which some part is in view of `cam`."""
    rng, planes, out = np.random.default_rng(seed), camera_planes(cam, 0.05), []
    while len(out) < n:
        axis = rng.normal(size=3)
        rot = cv2.Rodrigues(axis / np.linalg.norm(axis) * rng.uniform(0, np.pi))[0]
        center, size = rng.uniform([-15, -10, -5], [15, 10, 30]), rng.uniform(0.3, 10.0, 3)
        corners = center + (SIGNS * size / 2) @ rot.T
        if image_box(corners, cam, planes) is not None:
            out.append(corners)
    return out


def per_box_us(fn, items) -> float:
    start = time.perf_counter()
    for item in items:
        fn(item)
    return (time.perf_counter() - start) / len(items) * 1e6


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=15)
    args = parser.parse_args()
    load_before = os.getloadavg()[0]
    out = {}
    for name, cam in (("pinhole", Intrinsics.from_fov(640, 480, 70.0)),
                      ("distorted", Intrinsics.from_fov(640, 480, 70.0, (-0.15, 0.03, 0.001, -0.0015, 0.002)))):  # fmt: skip
        items, planes = boxes(cam, 300, seed=1), camera_planes(cam, 0.05)
        dist = np.asarray(cam.D)

        def clipped(corners, cam=cam, planes=planes):
            return image_box(corners, cam, planes)

        def naive(corners, cam=cam, dist=dist):
            uv = cv2.projectPoints(corners, np.zeros(3), np.zeros(3), cam.K, dist)[0].reshape(-1, 2)
            return uv.min(axis=0), uv.max(axis=0)

        clipped(items[0]), naive(items[0])  # compiled / warmed up
        times = {"image_box": [], "opencv_corners": []}
        for _ in range(args.rounds):
            times["image_box"].append(per_box_us(clipped, items))
            times["opencv_corners"].append(per_box_us(naive, items))
        med = {k: round(float(np.median(v)), 2) for k, v in times.items()}
        out[name] = med | {"image_box_over_opencv_corners": round(med["image_box"] / med["opencv_corners"], 2)}
        print(name, out[name], flush=True)
    out["load_before_after"] = [round(load_before, 2), round(os.getloadavg()[0], 2)]
    RESULTS.write_text(json.dumps(out, indent=2) + "\n")
    print(json.dumps(out))


if __name__ == "__main__":
    main()
