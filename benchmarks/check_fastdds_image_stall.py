"""How often a Fast DDS subscriber stalls on the bridge's camera images (docs/ros2.md, known issues).

The `harbor_sensors` scenario runs with the DdsBridge, paced to the wall clock, while short-lived rclpy
subscribers (Fast DDS 3.2 from the Kilted wheels, default settings unless --profile) subscribe to both camera
images for 3 s each, `--concurrent` at a time, replaced as they end. A subscriber that has not ended 25 s after
its start is stalled (it spins inside `DataReader::take`); it is killed and counted.

    python benchmarks/check_fastdds_image_stall.py [--seconds 150] [--reliability reliable|best_effort]
        [--concurrent 3] [--profile FASTDDS_PROFILE.xml]

Needs the ROS 2 test extras and a loopback-only network namespace (run as root; it makes one itself, as
tests/bridges/test_dds_ros2.py does). Prints one JSON line: subscribers started and stalled. Not a timing.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve()
sys.path.insert(0, str(HERE.parents[1] / "tests"))
from loopback_ns import isolated, unusable  # noqa: E402

TOPICS = ("/wamv/camera/image_raw", "/wamv/camera/depth/image_raw")
LIFE_S, STALLED_AFTER_S = 3.0, 25.0
SUBSCRIBER = """
import json, sys, time, rclpy
from rclpy.node import Node
from rclpy.qos import QoSProfile, qos_profile_sensor_data
from sensor_msgs.msg import Image
life, reliability, topics = float(sys.argv[1]), sys.argv[2], sys.argv[3:]
rclpy.init()
node = Node("stall_check")
counts = {t: 0 for t in topics}
qos = QoSProfile(depth=50) if reliability == "reliable" else qos_profile_sensor_data
for t in topics:
    node.create_subscription(Image, t, lambda m, t=t: counts.__setitem__(t, counts[t] + 1), qos)
end = time.monotonic() + life
while time.monotonic() < end:
    rclpy.spin_once(node, timeout_sec=0.05)
print(json.dumps(counts), flush=True)
"""


def inside(args: argparse.Namespace) -> dict:
    from usvsim.bridges.dds import DdsBridge
    from usvsim.simulation import Simulation

    env = dict(os.environ, RMW_IMPLEMENTATION="rmw_fastrtps_cpp", ROS_DOMAIN_ID="0")
    env.pop("FASTDDS_DEFAULT_PROFILES_FILE", None)
    if args.profile:
        env["FASTDDS_DEFAULT_PROFILES_FILE"] = str(Path(args.profile).resolve())
    cmd = [sys.executable, "-c", SUBSCRIBER, str(LIFE_S), args.reliability, *TOPICS]

    def start() -> tuple[subprocess.Popen, float]:
        proc = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
        return proc, time.monotonic()

    sim = Simulation.from_scenario("harbor_sensors")
    bridge = DdsBridge(sim)
    live = [start() for _ in range(args.concurrent)]
    started, stalled, received = len(live), 0, []
    t0, sim0 = time.perf_counter(), sim.clock_ns
    try:
        while time.perf_counter() - t0 < args.seconds:
            sim.step()
            for k, (proc, since) in enumerate(live):
                if proc.poll() is not None:
                    received.append(json.loads(proc.stdout.read() or "{}"))  # type: ignore[union-attr]
                elif time.monotonic() - since > STALLED_AFTER_S:
                    stalled += 1
                    proc.kill()
                    proc.wait()
                else:
                    continue
                live[k] = start()
                started += 1
            ahead = (sim.clock_ns - sim0) / 1e9 - (time.perf_counter() - t0)
            if ahead > 0:
                time.sleep(ahead)
    finally:
        for proc, _ in live:
            proc.kill()
        bridge.close()
        sim.close()
    ended = len(received)
    mean = {t: sum(r.get(t, 0) for r in received) / max(ended, 1) for t in TOPICS}
    return {"reliability": args.reliability, "profile": bool(args.profile), "started": started,
            "stalled": stalled, "ended": ended, "mean_images_per_subscriber": mean}  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=150.0)
    parser.add_argument("--reliability", choices=("reliable", "best_effort"), default="reliable")
    parser.add_argument("--concurrent", type=int, default=3)
    parser.add_argument("--profile", help="a Fast DDS XML profile for the subscribers (default: none)")
    parser.add_argument("--inside", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.inside:
        print(json.dumps(inside(args)), flush=True)
        return
    reason = unusable()
    if reason:
        sys.exit(f"check_fastdds_image_stall: {reason}")
    done = subprocess.run(isolated(sys.executable, str(HERE), "--inside", *sys.argv[1:]), capture_output=True,
                          text=True)  # fmt: skip
    lines = [ln for ln in done.stdout.splitlines() if ln.startswith("{")]
    if done.returncode or not lines:
        sys.exit(f"check_fastdds_image_stall: the run failed: {done.stderr.strip()[-500:]}")
    print(lines[-1])


if __name__ == "__main__":
    main()
