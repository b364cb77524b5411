"""Labelled data set throughput: 640x480 frames written per second, against the camera-only rate in the same run.

Scene: the built-in `buoy_field` (WAM-V, VGA camera, 10 buoys, a vessel, a dock), randomized with the
`foggy_wavy` look (fog, blur, noise: the most image post-processing) but one episode, frames one physics step
apart, so that the figure measures rendering, labelling and writing rather than the physics that settles a
new episode (reported separately as `episode_s`; the clock starts after the first frame, which holds the
episode, and stops when the last file is written). Labelled frame: RGB + depth + segmentation rendered, look
applied, instance and semantic masks, visible/amodal boxes, COCO RLE, YOLO labels, 3 PNGs and a metadata
JSON written (look, masks, COCO and files on 2 worker threads). Baseline: the same camera rendering RGB only
(one pass), same states. Also measured: labelled frames without the amodal-mask passes (`amodal_masks=False`:
visible_fraction from the boxes' areas).

    python benchmarks/bench_datasets.py [--frames 40] [--repeats 3]
Writes benchmarks/results/datasets.json: medians of `--repeats` runs (each a labelled run then a camera-only
run, so `ratio` compares like loads), with the 1-minute load average, and the CPU time per frame of all the
process's threads (on a loaded machine the frame rates swing; CPU time per frame much less).
"""

from __future__ import annotations

import argparse
import json
import os
import tempfile
import time
from pathlib import Path

os.environ.setdefault("MUJOCO_GL", "egl")

import yaml

from usvsim.datasets.generate import DatasetGenerator, DatasetSpec
from usvsim.datasets.randomization import load_randomization

RESULTS = Path(__file__).parent / "results"


def _spec(out: Path, frames: int, amodal: bool = True) -> DatasetSpec:
    rnd = load_randomization("foggy_wavy").model_dump(mode="json", exclude_defaults=True)
    rnd.update(per="episode", frames_per_episode=frames)
    path = out / "randomize.yaml"
    path.write_text(yaml.safe_dump(rnd))
    return DatasetSpec("buoy_field", frames, out / "set", seed=1, randomize=str(path), frame_interval_s=0.01,
                       amodal_masks=amodal)  # fmt: skip


def labelled(frames: int, amodal: bool) -> tuple[float, float]:
    """(frames/s, CPU ms per frame) of a labelled run, clocked from the end of the first frame."""
    with tempfile.TemporaryDirectory() as tmp:
        gen = DatasetGenerator(_spec(Path(tmp), frames, amodal))
        try:
            marks: list[tuple[float, float]] = []
            gen.run(lambda done: marks.append((time.perf_counter(), time.process_time())))
            wall, cpu = time.perf_counter() - marks[0][0], time.process_time() - marks[0][1]
        finally:
            gen.close()
    return (frames - 1) / wall, 1e3 * cpu / (frames - 1)


def run_once(frames: int) -> dict:
    with tempfile.TemporaryDirectory() as tmp:
        gen = DatasetGenerator(_spec(Path(tmp), frames))
        try:
            marks: list[tuple[float, float]] = []
            gen.run(lambda done: marks.append((time.perf_counter(), time.process_time())))
            labelled_s = time.perf_counter() - marks[0][0]  # frames 2..N, until every file is written
            labelled_cpu = time.process_time() - marks[0][1]  # all threads of this process (GL ones too)
            t0 = time.perf_counter()
            gen._episode()
            episode_s = time.perf_counter() - t0
            _, cam = gen.cameras[0]
            t0, c0 = time.perf_counter(), time.process_time()
            for _ in range(frames):
                gen.sim.run(0.01)
                cam.render(gen.sim, streams=("rgb",))
            camera_s, camera_cpu = time.perf_counter() - t0, time.process_time() - c0
        finally:
            gen.close()
    box_fps, box_cpu = labelled(frames, amodal=False)
    return {"labelled_fps": (frames - 1) / labelled_s, "camera_only_fps": frames / camera_s,
            "ratio": (frames - 1) / labelled_s / (frames / camera_s), "episode_s": episode_s,
            "labelled_cpu_ms_per_frame": 1e3 * labelled_cpu / (frames - 1),
            "camera_only_cpu_ms_per_frame": 1e3 * camera_cpu / frames,
            "labelled_no_amodal_fps": box_fps, "labelled_no_amodal_cpu_ms_per_frame": box_cpu}  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--frames", type=int, default=40)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    run_once(4)  # warm-up: numba caches, GL
    runs = [run_once(args.frames) for _ in range(args.repeats)]
    median = {k: sorted(r[k] for r in runs)[len(runs) // 2] for k in runs[0]}
    out = {"frames": args.frames, "repeats": args.repeats, "resolution": [640, 480], "median": median,
           "labelled_over_camera_only": median["labelled_fps"] / median["camera_only_fps"], "runs": runs,
           "load_average_1min": os.getloadavg()[0], "cpus": os.cpu_count()}  # fmt: skip
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "datasets.json").write_text(json.dumps(out, indent=2) + "\n")
    print(
        json.dumps(
            {k: out[k] for k in ("median", "labelled_over_camera_only", "load_average_1min")}, indent=2
        )
    )


if __name__ == "__main__":
    main()
