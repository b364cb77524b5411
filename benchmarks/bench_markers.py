"""Cost of the scene markers (scene_markers.py), same-run ratios.

1. `/usvsim/markers/bodies` per update (harbor: nine buoys): the CDR made by patching stamps and poses into the array
   serialized once (`MovingMarkers`), against the baseline of building the marker objects and serializing them with
   rosbags (what a plain publisher does). Medians of interleaved rounds, process CPU µs per update.
2. A recorded harbor run (MCAP to a temporary file, all topics): process CPU µs per physics step with
   `outputs.markers` at its defaults against markers off, interleaved rounds in one process.
Each figure is printed with the median 1-minute load average of its rounds.

    python benchmarks/bench_markers.py [--rounds 7] [--steps 1000]
Writes benchmarks/results/markers.json.
"""

from __future__ import annotations

import argparse
import json
import os
import tempfile
import time
from pathlib import Path

import numpy as np
import yaml

from usvsim import Simulation
from usvsim.config.loader import parse_scenario, resolve
from usvsim.messages.markers import marker_array, part_marker
from usvsim.messages.ros import typestore
from usvsim.world.shapes import drawn_parts

RESULTS = Path(__file__).parent / "results" / "markers.json"


def harbor(markers: bool) -> Simulation:
    data = yaml.safe_load(resolve("harbor")[0])
    if not markers:
        data.setdefault("outputs", {})["markers"] = {"scene": False, "bodies_rate_hz": 0}
    return Simulation(parse_scenario(data, "harbor"))


def built_update(sim: Simulation) -> bytes:
    """The baseline: the bodies' markers as message objects, serialized by rosbags."""
    markers = []
    for body in sim.markers.bodies:
        markers += [part_marker(p, sim.clock_ns, "world", f"body/{body.name}", k, base_pos=body.position,
                                base_quat=body.quat) for k, p in enumerate(drawn_parts(body.model))]  # fmt: skip
    return bytes(typestore().serialize_cdr(marker_array(markers), "visualization_msgs/msg/MarkerArray"))


def per_update_us(fn, n: int) -> float:
    t = time.process_time()
    for _ in range(n):
        fn()
    return (time.process_time() - t) / n * 1e6


def recorded_step_us(sim: Simulation, steps: int) -> float:
    with tempfile.TemporaryDirectory() as tmp, sim.record(Path(tmp) / "run.mcap"):
        t = time.process_time()
        for _ in range(steps):
            sim.step()
        return (time.process_time() - t) / steps * 1e6


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=7)
    parser.add_argument("--steps", type=int, default=1000, help="physics steps per recorded round")
    args = parser.parse_args()
    sim = harbor(True)
    sim.run(0.5)
    moving, baseline, loads = [], [], []
    for _ in range(args.rounds):
        moving.append(per_update_us(lambda: sim.markers.due(0, sim.clock_ns)[0].cdr, 200))
        baseline.append(per_update_us(lambda: built_update(sim), 50))
        loads.append(os.getloadavg()[0])
    on, off, rec_loads = [], [], []
    sims = {True: harbor(True), False: harbor(False)}
    for _ in range(args.rounds):
        for flag, out in ((True, on), (False, off)):
            out.append(recorded_step_us(sims[flag], args.steps))
        rec_loads.append(os.getloadavg()[0])
    med = lambda xs: round(float(np.median(xs)), 1)  # noqa: E731
    result = {
        "bodies_update_us": {"patched": med(moving), "built_and_serialized": med(baseline),
                             "ratio": round(med(moving) / med(baseline), 4), "load": round(float(np.median(loads)), 2)},
        "recorded_harbor_step_cpu_us": {"markers": med(on), "no_markers": med(off), "ratio": round(med(on) / med(off), 3),
                                        "load": round(float(np.median(rec_loads)), 2)},
    }  # fmt: skip
    print(json.dumps(result, indent=2))
    RESULTS.parent.mkdir(exist_ok=True)
    RESULTS.write_text(json.dumps(result, indent=2) + "\n")


if __name__ == "__main__":
    main()
