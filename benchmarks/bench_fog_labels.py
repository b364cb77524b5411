"""Cost of labelling only what the fog leaves visible (datasets/fog_sight.py), per 640x480 frame.

Scene: the built-in `buoy_field` (WAM-V, VGA camera, 10 buoys, a vessel, a dock), one frame rendered (RGB,
depth, segmentation) and then labelled many times: Labeller.objects_in (without the amodal passes, which
are the same with and without fog) and Labeller.masks. Baseline: no fog (label_stats). Fog: 60 m visibility
(foggy_wavy's range is 40-90 m), under MuJoCo's look (uniform fog) and under the shader's (height falloff and
rain: the same kernel with more arithmetic per pixel): FogSight.frame, the fog-aware pass over the object
pixels, and the masks with the fog-hidden pixels cleared (fog leaves fewer objects to box). `pass_*`: the
pixel pass alone, label_stats against the fog-aware kernel; `pass_full_*`: the same over a segmentation whose
every pixel is an object's (the worst case: transmittance computed for all 307 200 pixels). The variants alternate within each round, so each
median compares like loads (the machine is shared).

    python benchmarks/bench_fog_labels.py [--rounds 300]
Writes benchmarks/results/fog_labels.json: median wall and thread-CPU µs per frame of each variant, the ratio
to the baseline, labels found, and the 1-minute load average before and after.
"""

from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

os.environ.setdefault("MUJOCO_GL", "egl")

import numpy as np

from usvsim.datasets.generate import DatasetGenerator, DatasetSpec, jittered_pose
from usvsim.sensors.base import OPTICAL_ROT
from usvsim.sensors.camera.boxes2d import label_stats

RESULTS = Path(__file__).parent / "results"
VISIBILITY_M = 60.0


def load1() -> float:
    return float(Path("/proc/loadavg").read_text().split()[0])


def measure(rounds: int) -> dict:
    gen = DatasetGenerator(DatasetSpec("buoy_field", 1, Path("unused"), seed=1, min_visible_pixels=20))
    try:
        look, scene = gen._episode()
        (_, cam), lab, sight, sim = gen.cameras[0], gen.labellers[0], gen.fogs[0], gen.sim
        pos, rot = jittered_pose(cam, sim, scene)
        images, _ = gen.render(0, pos, rot, look)
        seg, depth, rot_optical = images["segmentation"], images["depth"], rot @ OPTICAL_ROT
        level = sim.world.ocean.level_m
        looks = {"fog_mujoco": look.updated({"fog": {"visibility_m": VISIBILITY_M}}),
                 "fog_shader": look.updated({"renderer": "shader", "fog": {"visibility_m": VISIBILITY_M},
                                             "rain": {"rate_mm_h": 5.0}})}  # fmt: skip

        def baseline():
            labels = lab.objects_in(sim, seg, pos, rot_optical, 20, 0.0)
            lab.masks(seg, labels)
            return labels

        def fogged(name):
            def run():
                fog = sight.frame(looks[name], depth, pos, rot_optical, level)
                labels = lab.objects_in(sim, seg, pos, rot_optical, 20, 0.0, fog=fog)
                lab.masks(seg, labels, fog.hidden)
                return labels

            return run

        def pass_only(name, pixels=seg):
            fog = sight.frame(looks[name], depth, pos, rot_optical, level)
            return lambda: fog.stats(pixels, lab.owner, len(lab.objects))

        full = np.full_like(seg, lab.objects[0].geoms[0] + 1)  # the worst case: every pixel an object's

        found = {name: [(x.name, x.visible_pixels, round(x.fog_transmittance, 4)) for x in f()]
                 for name, f in (("baseline", baseline), ("fog_mujoco", fogged("fog_mujoco")),
                                 ("fog_shader", fogged("fog_shader")))}  # fmt: skip  (the first calls compile)
        variants = {"baseline": baseline, "fog_mujoco": fogged("fog_mujoco"), "fog_shader": fogged("fog_shader"),
                    "pass_baseline": lambda: label_stats(seg, lab.owner, len(lab.objects)),
                    "pass_fog_mujoco": pass_only("fog_mujoco"), "pass_fog_shader": pass_only("fog_shader"),
                    "pass_full_baseline": lambda: label_stats(full, lab.owner, len(lab.objects)),
                    "pass_full_fog_mujoco": pass_only("fog_mujoco", full),
                    "pass_full_fog_shader": pass_only("fog_shader", full)}  # fmt: skip
        for f in variants.values():
            f()
        times: dict[str, list[tuple[float, float]]] = {name: [] for name in variants}
        before = load1()
        for _ in range(rounds):
            for name, f in variants.items():
                w, c = time.perf_counter(), time.thread_time()
                f()
                times[name].append((time.perf_counter() - w, time.thread_time() - c))
        after = load1()
    finally:
        gen.close()
    med = {name: np.median(np.array(t), axis=0) * 1e6 for name, t in times.items()}
    out = {"frame": "640x480 buoy_field", "rounds": rounds, "visibility_m": VISIBILITY_M,
           "load_1min_before": before, "load_1min_after": after,
           "object_pixels": int((lab.owner[seg] > 0).sum()), "labels": found}  # fmt: skip
    for name, (wall, cpu) in med.items():
        base = med["pass_full_baseline" if "full" in name else "pass_baseline" if "pass" in name else "baseline"]
        out[name] = {"median_wall_us": round(float(wall), 1), "median_cpu_us": round(float(cpu), 1),
                     "wall_ratio_to_baseline": round(float(wall / base[0]), 3),
                     "cpu_ratio_to_baseline": round(float(cpu / base[1]), 3)}  # fmt: skip
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=300)
    args = parser.parse_args()
    result = measure(args.rounds)
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "fog_labels.json").write_text(json.dumps(result, indent=2) + "\n")
    print(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
