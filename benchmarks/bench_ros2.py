"""Live ROS 2 over DDS: simulation slow-down with heavy sensor topics, and small-message latency, same run.

Throughput: the `harbor` scenario's physics plus synthetic sensor envelopes emitted from an on_step hook
at their rates in simulation time (independent of camera/LiDAR speed): VGA rgb8 (0.92 MB) at 30 Hz,
VGA 32FC1 depth (1.23 MB) at 30 Hz, a 128x2048 point cloud (16 B/point, 4.2 MB) at 10 Hz. The simulation
is paced to real time (as a user runs it with sensors); the measure is the simulation thread's busy time
per simulated second, without a bridge vs with the DdsBridge and a subscriber process (cyclonedds raw
readers, loopback) taking every message. Runs alternate (no bridge, bridge) `--repeats` times.
Latency: a std_msgs/Header on /bench/latency at 100 Hz stamped with the wall clock at emission;
the subscriber process records receive time - stamp.

    python benchmarks/bench_ros2.py [--seconds 5] [--repeats 3]
Writes benchmarks/results/ros2.json. Everything stays on loopback (the bridge's default configuration).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from usvsim.bridges.dds import DdsBridge
from usvsim.messages import ros
from usvsim.messages.envelope import Envelope
from usvsim.messages.ros import typestore
from usvsim.simulation import Simulation

RESULTS = Path(__file__).parent / "results" / "ros2.json"
HEAVY = {  # topic: (msgtype, payload bytes, rate Hz)
    "/bench/image_raw": ("sensor_msgs/msg/Image", 640 * 480 * 3, 30),
    "/bench/depth/image_raw": ("sensor_msgs/msg/Image", 640 * 480 * 4, 30),
    "/bench/points": ("sensor_msgs/msg/PointCloud2", 128 * 2048 * 16, 10),
}
LATENCY_TOPIC = "/bench/latency"


def heavy_cdr(msgtype: str, size: int) -> bytes:
    """One message of `size` payload bytes, serialized (the sensors' fast path builds CDR the same way)."""
    data = np.random.default_rng(0).integers(0, 255, size, dtype=np.uint8)
    h = ros.header(0, "bench")
    if msgtype.endswith("Image"):
        bpp = 3 if size == 640 * 480 * 3 else 4
        msg = ros.msg_class(msgtype)(header=h, height=480, width=640, encoding="rgb8" if bpp == 3 else "32FC1",
                                     is_bigendian=0, step=640 * bpp, data=data)  # fmt: skip
    else:
        field = ros.msg_class("sensor_msgs/msg/PointField")
        fields = [field(name=n, offset=4 * i, datatype=7, count=1) for i, n in enumerate(("x", "y", "z", "intensity"))]
        msg = ros.msg_class(msgtype)(header=h, height=128, width=2048, fields=fields, is_bigendian=False,
                                     point_step=16, row_step=16 * 2048, data=data, is_dense=True)  # fmt: skip
    return bytes(typestore().serialize_cdr(msg, msgtype))


class Hook:
    """on_step: emits the heavy envelopes at their rates (sim time) and a wall-stamped latency probe."""

    def __init__(self, sim: Simulation):
        self.cdr = {topic: heavy_cdr(t, n) for topic, (t, n, _) in HEAVY.items()}
        self.every = {topic: round(1e9 / hz / sim.clock.step_ns) for topic, (_, _, hz) in HEAVY.items()}
        self.busy_s = 0.0

    def __call__(self, sim: Simulation) -> None:
        t = time.perf_counter()
        out = [Envelope(topic, sim.clock_ns, msgtype=HEAVY[topic][0], cdr=self.cdr[topic])
               for topic, k in self.every.items() if sim.clock.steps % k == 0]  # fmt: skip
        out.append(Envelope(LATENCY_TOPIC, 0, ros.header(time.time_ns(), "bench")))
        sim._emit(out)  # the same fan-out as sensor output
        self.busy_s += time.perf_counter() - t


def run(seconds: float, bridge: bool) -> dict:
    sim = Simulation.from_scenario("harbor")
    hook, dds = Hook(sim), (DdsBridge(sim) if bridge else None)
    sub = subscriber(seconds + 5.0) if bridge else None
    if sub is not None:
        assert sub.stdout.readline().strip() == "ready"
        time.sleep(2.0)  # discovery
    steps = round(seconds * 1e9 / sim.clock.step_ns)
    busy, start = 0.0, time.perf_counter()
    for _ in range(steps):
        t = time.perf_counter()
        sim.step()
        hook(sim)
        busy += time.perf_counter() - t
        ahead = (sim.clock.steps / steps) * seconds - (time.perf_counter() - start)
        if ahead > 0:
            time.sleep(ahead)
    wall = time.perf_counter() - start
    stats = dict(dds.stats) if dds else {}
    received = {}
    if dds:
        time.sleep(0.5)
        dds.close()
        received = json.loads(sub.communicate(timeout=60)[0])
    sim.close()
    return {"bridge": bridge, "busy_s_per_sim_s": busy / seconds, "wall_s": wall, "rtf": seconds / wall,
            "stats": stats, "received": received}  # fmt: skip


def subscriber(duration_s: float) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, __file__, "--subscriber", str(duration_s)], stdout=subprocess.PIPE, text=True)


def subscribe(duration_s: float) -> None:
    """Subscriber process: raw readers on every bench topic; prints counts and latencies as JSON."""
    from cyclonedds.domain import DomainParticipant
    from cyclonedds.sub import DataReader
    from cyclonedds.topic import Topic

    from usvsim.bridges import dds_types
    from usvsim.bridges.dds import _qos
    from usvsim.bridges.dds_config import cyclone_config
    from usvsim.bridges.dds_domain import acquire_domain
    from usvsim.messages.envelope import QosProfile

    acquire_domain(0, cyclone_config("lo"))
    p = DomainParticipant(0)
    topics = {**{k: v[0] for k, v in HEAVY.items()}, LATENCY_TOPIC: "std_msgs/msg/Header"}
    readers = {k: DataReader(p, Topic(p, dds_types.dds_topic_name(k), dds_types.idl_type(t)),
                             qos=_qos(QosProfile(depth=50), t)) for k, t in topics.items()}  # fmt: skip
    counts, latencies, end = dict.fromkeys(topics, 0), [], time.monotonic() + duration_s
    print("ready", flush=True)
    while time.monotonic() < end:
        for topic, reader in readers.items():
            for cdr in dds_types.take_cdr(reader, 256):
                counts[topic] += 1
                if topic == LATENCY_TOPIC:
                    sec, nsec = np.frombuffer(cdr, "<i4", 2, 4)
                    latencies.append((time.time_ns() - (int(sec) * 10**9 + int(nsec) % 2**32)) / 1e6)
        time.sleep(0.0005)
    print(json.dumps({"counts": counts, "latency_ms": latencies}))


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--seconds", type=float, default=5.0)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--subscriber", type=float, default=None)
    args = parser.parse_args()
    if args.subscriber is not None:
        return subscribe(args.subscriber)
    runs = [run(args.seconds, bridge) for _ in range(args.repeats) for bridge in (False, True)]
    base = [r["busy_s_per_sim_s"] for r in runs if not r["bridge"]]
    with_bridge = [r["busy_s_per_sim_s"] for r in runs if r["bridge"]]
    latencies = [x for r in runs if r["bridge"] for x in r["received"]["latency_ms"]]
    result = {
        "machine": {"cpus": os.cpu_count(), "platform": platform.platform(), "python": platform.python_version(),
                    "loadavg": os.getloadavg()},
        "workload": {topic: {"msgtype": t, "payload_bytes": n, "rate_hz": hz} for topic, (t, n, hz) in HEAVY.items()},
        "busy_s_per_sim_s": {"no_bridge": base, "bridge": with_bridge},
        "slowdown_ratio_median": statistics.median(with_bridge) / statistics.median(base),
        "latency_ms": {"median": statistics.median(latencies), "p90": float(np.percentile(latencies, 90)),
                       "count": len(latencies)},
        "runs": [{k: v for k, v in r.items() if k != "received"} | {"received": r["received"].get("counts", {})}
                 for r in runs],
    }  # fmt: skip
    RESULTS.write_text(json.dumps(result, indent=2) + "\n")
    print(json.dumps({k: result[k] for k in ("busy_s_per_sim_s", "slowdown_ratio_median", "latency_ms")}, indent=2))


if __name__ == "__main__":
    main()
