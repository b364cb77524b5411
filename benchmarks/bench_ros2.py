"""Live ROS 2 over DDS: simulation slow-down with heavy sensor topics, and small-message latency, same run.

Sensors (the headline): the `harbor` scenario with the issue's topics produced by real sensors on the WAM-V:
a 640x480 camera, rgb8 + 32FC1 depth, at 33.3 Hz (every 3rd 10 ms step: 30 Hz has no whole-step period, so
the nearest faster rate is used), and an organized OS1-128 LiDAR at 10 Hz (all 128x2048 points, NaN where
there is no return: ~6 MB per cloud, more than the issue's 16-byte points). Run as fast as the machine
allows; slow-down = wall time with the DdsBridge and a subscriber process (Cyclone raw readers on a WaitSet)
taking every image and cloud on loopback / wall time without a bridge. Also the simulation process's CPU
time (all its threads: physics, rendering, bridge), which leaves out the subscriber's share of the cores.
Socket buffers matter (docs/ros2.md): with a 4 MiB `net.core.rmem_max` a 6 MB cloud overflows the
receiver's buffer and reliable retransmissions cost the writer ~40 % more CPU; the stored figures were
taken with `sysctl -w net.core.rmem_max=33554432 net.core.wmem_max=33554432` (recorded under "machine").

Synthetic: the `harbor` scenario's physics plus synthetic sensor envelopes emitted from an on_step hook
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
import signal
import statistics
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import yaml

from usvsim.bridges.dds import DdsBridge
from usvsim.messages import ros
from usvsim.messages.envelope import Envelope
from usvsim.messages.ros import typestore
from usvsim.simulation import Simulation

RESULTS = Path(__file__).parent / "results" / "ros2.json"
SENSORS = [  # the heavy topics from real sensors on the WAM-V
    {"type": "camera", "name": "camera", "width": 640, "height": 480, "rate_hz": 1e9 / 30e6, "streams": ["rgb", "depth"],
     "mount": {"position": [0.3, 0.0, 1.3], "pitch_deg": 5.0}},
    {"type": "lidar", "name": "lidar", "preset": "os1_128", "rate_hz": 10, "organized": True, "mount": {"position": [0.7, 0.0, 1.03]}},
]  # fmt: skip
SENSOR_TOPICS = {
    "/wamv/camera/image_raw": "sensor_msgs/msg/Image",
    "/wamv/camera/depth/image_raw": "sensor_msgs/msg/Image",
    "/wamv/lidar/points": "sensor_msgs/msg/PointCloud2",
}
HEAVY = {  # topic: (msgtype, payload bytes, rate Hz)
    "/bench/image_raw": ("sensor_msgs/msg/Image", 640 * 480 * 3, 30),
    "/bench/depth/image_raw": ("sensor_msgs/msg/Image", 640 * 480 * 4, 30),
    "/bench/points": ("sensor_msgs/msg/PointCloud2", 128 * 2048 * 16, 10),
}
LATENCY_TOPIC = "/bench/latency"
MODE = ["thread"]  # the DdsBridge mode of the sensors workload (--mode)


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
        fields = [
            field(name=n, offset=4 * i, datatype=7, count=1)
            for i, n in enumerate(("x", "y", "z", "intensity"))
        ]
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


def sysctl(name: str) -> int:
    return int(Path("/proc/sys", name).read_text())


def sensor_simulation() -> Simulation:
    from usvsim.config.loader import parse_scenario, resolve

    data = yaml.safe_load(resolve("harbor")[0])
    data["vessels"][0]["sensors"] = SENSORS
    return Simulation(parse_scenario(data, "bench_ros2"))


def run_sensors(seconds: float, bridge: bool) -> dict:
    """Unpaced: the wall time the simulation with real sensors needs, with or without the bridge."""
    sim = sensor_simulation()
    sim.run(0.5)  # warm-up: JIT, render context, first scan
    dds = DdsBridge(sim, mode=MODE[0]) if bridge else None
    sub = subscriber(seconds + 60.0, "sensors") if bridge else None
    if sub is not None:
        assert sub.stdout.readline().strip() == "ready"
        time.sleep(2.0)  # discovery
    start, cpu0 = time.perf_counter(), os.times()
    sim.run(seconds)
    wall, cpu1 = time.perf_counter() - start, os.times()
    cpu = (cpu1.user - cpu0.user) + (cpu1.system - cpu0.system)  # this process: sim, render, bridge threads
    stats, received = (dict(dds.stats) if dds else {}), {}
    if dds:
        time.sleep(0.5)
        dds.close()
        sub.terminate()
        received = json.loads(sub.communicate(timeout=60)[0] or "{}")
    sim.close()
    return {
        "bridge": bridge,
        "wall_s": wall,
        "cpu_s": cpu,
        "rtf": seconds / wall,
        "stats": stats,
        "received": received,
    }


def subscriber(duration_s: float, workload: str = "synthetic") -> subprocess.Popen:
    cmd = [sys.executable, __file__, "--subscriber", str(duration_s), "--workload", workload]
    return subprocess.Popen(cmd, stdout=subprocess.PIPE, text=True)


def subscribe(duration_s: float, workload: str) -> None:
    """Subscriber process: raw readers on every bench topic; prints counts and latencies as JSON."""
    from cyclonedds.core import InstanceState, ReadCondition, SampleState, ViewState, WaitSet
    from cyclonedds.domain import DomainParticipant
    from cyclonedds.sub import DataReader
    from cyclonedds.topic import Topic
    from cyclonedds.util import duration

    from usvsim.bridges import dds_types
    from usvsim.bridges.dds import _qos
    from usvsim.bridges.dds_config import cyclone_config
    from usvsim.bridges.dds_domain import acquire_domain
    from usvsim.messages.envelope import QosProfile

    acquire_domain(0, cyclone_config("lo"))
    p = DomainParticipant(0)
    topics = {**{k: v[0] for k, v in HEAVY.items()}, LATENCY_TOPIC: "std_msgs/msg/Header"}
    if workload == "sensors":
        topics = dict(SENSOR_TOPICS)
    readers = {k: DataReader(p, Topic(p, dds_types.dds_topic_name(k), dds_types.idl_type(t)),
                             qos=_qos(QosProfile(depth=50), t)) for k, t in topics.items()}  # fmt: skip
    counts, latencies, end = dict.fromkeys(topics, 0), [], time.monotonic() + duration_s
    signal.signal(signal.SIGTERM, lambda *_: STOP.set())
    waitset = WaitSet(p)  # block until data, as an rclpy executor does (no busy polling)
    for reader in readers.values():
        waitset.attach(ReadCondition(reader, SampleState.Any | ViewState.Any | InstanceState.Any))
    print("ready", flush=True)
    while time.monotonic() < end and not STOP.is_set():
        waitset.wait(duration(milliseconds=100))
        for topic, reader in readers.items():
            for cdr in dds_types.take_cdr(reader, 256):
                counts[topic] += 1
                if topic == LATENCY_TOPIC:
                    sec, nsec = np.frombuffer(cdr, "<i4", 2, 4)
                    latencies.append((time.time_ns() - (int(sec) * 10**9 + int(nsec) % 2**32)) / 1e6)
    print(json.dumps({"counts": counts, "latency_ms": latencies}))


STOP = threading.Event()  # set by the subscriber process on SIGTERM


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--seconds", type=float, default=5.0)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--subscriber", type=float, default=None)
    parser.add_argument("--workload", choices=("synthetic", "sensors"), default="synthetic")
    parser.add_argument("--mode", choices=("thread", "inline"), default="thread")
    args = parser.parse_args()
    MODE[0] = args.mode
    if args.subscriber is not None:
        return subscribe(args.subscriber, args.workload)
    sensor_runs = [run_sensors(args.seconds, bridge) for _ in range(args.repeats) for bridge in (False, True)]
    walls = {b: [r["wall_s"] for r in sensor_runs if r["bridge"] == b] for b in (False, True)}
    cpus = {b: [r["cpu_s"] for r in sensor_runs if r["bridge"] == b] for b in (False, True)}
    runs = [run(args.seconds, bridge) for _ in range(args.repeats) for bridge in (False, True)]
    base = [r["busy_s_per_sim_s"] for r in runs if not r["bridge"]]
    with_bridge = [r["busy_s_per_sim_s"] for r in runs if r["bridge"]]
    latencies = [x for r in runs if r["bridge"] for x in r["received"]["latency_ms"]]
    result = {
        "machine": {"cpus": os.cpu_count(), "platform": platform.platform(), "python": platform.python_version(),
                    "loadavg": os.getloadavg(), "net.core.rmem_max": sysctl("net/core/rmem_max"),
                    "net.core.wmem_max": sysctl("net/core/wmem_max")},
        "sensors": {
            "topics": SENSOR_TOPICS, "sim_seconds": args.seconds, "bridge_mode": args.mode,
            "wall_s": {"no_bridge": walls[False], "bridge": walls[True]},
            "slowdown_ratio_median": statistics.median(walls[True]) / statistics.median(walls[False]),
            "process_cpu_s": {"no_bridge": cpus[False], "bridge": cpus[True]},
            "process_cpu_ratio_median": statistics.median(cpus[True]) / statistics.median(cpus[False]),
            "runs": [{k: v for k, v in r.items() if k != "received"} | {"received": r["received"].get("counts", {})}
                     for r in sensor_runs],
        },
        "workload": {topic: {"msgtype": t, "payload_bytes": n, "rate_hz": hz} for topic, (t, n, hz) in HEAVY.items()},
        "busy_s_per_sim_s": {"no_bridge": base, "bridge": with_bridge},
        "slowdown_ratio_median": statistics.median(with_bridge) / statistics.median(base),
        "latency_ms": {"median": statistics.median(latencies), "p90": float(np.percentile(latencies, 90)),
                       "count": len(latencies)},
        "runs": [{k: v for k, v in r.items() if k != "received"} | {"received": r["received"].get("counts", {})}
                 for r in runs],
    }  # fmt: skip
    RESULTS.write_text(json.dumps(result, indent=2) + "\n")
    keys = ("busy_s_per_sim_s", "slowdown_ratio_median", "latency_ms")
    print(
        json.dumps(
            {
                "sensors_slowdown": result["sensors"]["slowdown_ratio_median"],
                "sensors_wall_s": result["sensors"]["wall_s"],
            }
            | {k: result[k] for k in keys},
            indent=2,
        )
    )


if __name__ == "__main__":
    main()
