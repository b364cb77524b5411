"""Recorder throughput: usvsim `McapRecorder` vs the pure-Python `mcap_ros2.writer.Writer`, same run.

Both start from in-memory messages and write the same data to an MCAP file with the same chunk
compression; timed (best of 3): serialization + writing + closing. usvsim serializes each message once with the
rosbags typestore (`Envelope.cdr`) and writes those bytes; the baseline encodes from Python objects
(images given as `bytes`, its fast path).

    python benchmarks/bench_recorder.py [--steps 5000] [--images 100]
Two workloads, reported separately: "state" (/clock, /tf, odometry: per-message overhead) and
"images" (640x480 rgb8: bytes throughput).
Writes benchmarks/results/recorder.json.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import tempfile
import time
from pathlib import Path

import numpy as np
from mcap.writer import CompressionType
from mcap_ros2.writer import Writer as McapRos2Writer

from usvsim.io.mcap_recorder import McapRecorder
from usvsim.messages import ros
from usvsim.messages.envelope import Envelope

STEP_NS = 10_000_000
RESULTS = Path(__file__).parent / "results" / "recorder.json"


def state_messages(steps: int) -> list[tuple[str, int, object]]:
    """(topic, stamp_ns, message) for /clock, /tf and odometry at every step."""
    rng = np.random.default_rng(0)
    out: list[tuple[str, int, object]] = []
    for k in range(1, steps + 1):
        t = k * STEP_NS
        pos, q = rng.normal(size=3), np.array([1.0, 0.0, 0.0, 0.0])
        out.append(("/clock", t, ros.clock_msg(t)))
        tf = ros.transform_stamped(t, "wamv/odom", "wamv/base_link", pos, q)
        out.append(("/tf", t, ros.tf_message([tf])))
        odom = ros.odometry_msg(
            t, "wamv/odom", "wamv/base_link", pos, q, rng.normal(size=3), rng.normal(size=3)
        )
        out.append(("/wamv/ground_truth/odometry", t, odom))
    return out


def image_messages(count: int) -> list[tuple[str, int, object]]:
    """640x480 rgb8 camera frames at 10 Hz: a gradient with noise (compresses little, like real video)."""
    rng = np.random.default_rng(1)
    gradient = np.linspace(0, 200, 640, dtype=np.float32)[None, :, None] * np.ones((480, 1, 3), np.float32)
    out = []
    for k in range(1, count + 1):
        pixels = (gradient + rng.normal(0, 8, gradient.shape)).clip(0, 255).astype(np.uint8)
        out.append(
            (
                "/wamv/camera/image_raw",
                k * 10 * STEP_NS,
                ros.image_msg(k * 10 * STEP_NS, "wamv/camera_optical", pixels),
            )
        )
    return out


def to_python(msg: object) -> object:
    """rosbags dataclass -> plain dicts/lists/bytes, the input `mcap_ros2.writer` expects."""
    if isinstance(msg, np.ndarray):
        return msg.tobytes() if msg.dtype == np.uint8 else msg.tolist()
    if isinstance(msg, list):
        return [to_python(m) for m in msg]
    if hasattr(msg, "__dataclass_fields__"):
        return {name: to_python(getattr(msg, name)) for name in msg.__dataclass_fields__}
    return msg


def run_usvsim(path: Path, messages, compression: str) -> float:
    start = time.perf_counter()
    recorder = McapRecorder(path, compression=compression)
    try:
        for topic, stamp, msg in messages:
            recorder.write(Envelope(topic, stamp, msg))
    finally:
        recorder.close()
    return time.perf_counter() - start


def run_baseline(path: Path, messages, compression: str) -> float:
    plain = [(topic, stamp, msg.__msgtype__, to_python(msg)) for topic, stamp, msg in messages]
    start = time.perf_counter()
    with path.open("wb") as f:
        writer = McapRos2Writer(f, compression=getattr(CompressionType, compression.upper()))
        schemas = {}
        for topic, stamp, msgtype, msg in plain:
            if msgtype not in schemas:
                schemas[msgtype] = writer.register_msgdef(msgtype, ros.message_definition(msgtype))
            writer.write_message(topic, schemas[msgtype], msg, log_time=stamp, publish_time=stamp)
        writer.finish()
    return time.perf_counter() - start


def measure(name: str, seconds: float, messages, payload: int, path: Path) -> dict:
    return {
        "writer": name,
        "seconds": round(seconds, 4),
        "messages_per_s": round(len(messages) / seconds),
        "payload_mb_per_s": round(payload / seconds / 1e6, 1),
        "file_mb": round(path.stat().st_size / 1e6, 2),
    }


def best_of(run, path: Path, messages, compression: str, repeats: int = 3) -> float:
    """Fastest of `repeats` runs (file writes to disk are noisy)."""
    return min(run(path, messages, compression) for _ in range(repeats))


def bench_workload(name: str, messages, tmp: Path) -> dict:
    payload = sum(len(Envelope(t, s, m).cdr) for t, s, m in messages)  # also warms the serializers
    runs = []
    for compression in ("zstd", "lz4", "none"):
        path = tmp / f"{name}_usvsim_{compression}.mcap"
        runs.append(
            measure(
                f"usvsim/{compression}",
                best_of(run_usvsim, path, messages, compression),
                messages,
                payload,
                path,
            )
        )
    path = tmp / f"{name}_baseline.mcap"
    runs.append(
        measure("mcap_ros2/zstd", best_of(run_baseline, path, messages, "zstd"), messages, payload, path)
    )
    speedup = runs[-1]["seconds"] / runs[0]["seconds"]
    print(f"{name}: {len(messages)} messages, {payload / 1e6:.2f} MB CDR payload")
    for r in runs:
        print(
            f"  {r['writer']:16s} {r['seconds']:7.3f} s  {r['messages_per_s']:>8d} msg/s  "
            f"{r['payload_mb_per_s']:7.1f} MB/s  file {r['file_mb']} MB"
        )
    print(f"  speedup usvsim vs mcap_ros2 (zstd both): {speedup:.2f}x")
    return {
        "messages": len(messages),
        "payload_mb": round(payload / 1e6, 2),
        "runs": runs,
        "speedup_vs_mcap_ros2_zstd": round(speedup, 2),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=5000, help="steps of /clock + /tf + odometry")
    parser.add_argument("--images", type=int, default=100, help="640x480 rgb8 images")
    args = parser.parse_args()
    report = {"machine": f"{platform.machine()}, {os.cpu_count()} cores", "workloads": {}}
    with tempfile.TemporaryDirectory() as tmp:
        report["workloads"]["state"] = bench_workload("state", state_messages(args.steps), Path(tmp))
        report["workloads"]["images"] = bench_workload("images", image_messages(args.images), Path(tmp))
    RESULTS.parent.mkdir(parents=True, exist_ok=True)
    RESULTS.write_text(json.dumps(report, indent=2) + "\n")


if __name__ == "__main__":
    main()
