"""The simulation side of test_dds_ros2.py; runs inside a loopback-only network namespace.

1. harbor_sensors + DdsBridge; /tf_static goes out before any subscriber exists (late joiner).
2. The rclpy peer (`accept`: Kilted's Fast DDS with 4 MiB socket buffers for the images and clouds, type
   propagation at its default, see docs/ros2.md) subscribes to everything and drives the boats; the sim steps
   paced to the wall clock until the peer is done.
3. Two `noisy` peers are started and killed (SIGKILL) in turn while they send garbage; the step times
   of this phase are compared with phase 2.
4. A `match` peer with Kilted's default settings only (no profile at all) takes a few messages of every topic.
Every phase is bounded in wall time (at most ~520 s in all on a machine at load ~15; ~20 s when idle); a
peer still running at its bound is killed and reported as `{"timed_out": true}`. Prints one JSON object.
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from usvsim.bridges.dds import DdsBridge
from usvsim.simulation import Simulation

HERE = Path(__file__).parent
FASTDDS_PROFILE = """<?xml version="1.0" encoding="UTF-8" ?>
<dds xmlns="http://www.eprosima.com"><profiles>
  <transport_descriptors><transport_descriptor><transport_id>udp</transport_id><type>UDPv4</type>
    <sendBufferSize>4194304</sendBufferSize><receiveBufferSize>4194304</receiveBufferSize>
  </transport_descriptor></transport_descriptors>
  <participant profile_name="usvsim_test" is_default_profile="true"><rtps>
    <userTransports><transport_id>udp</transport_id></userTransports>
    <useBuiltinTransports>false</useBuiltinTransports>
  </rtps></participant>
</profiles></dds>
"""


def peer(mode: str, *args: str, buffers: bool = True) -> subprocess.Popen:
    """An rclpy peer; `buffers`: Fast DDS with 4 MiB socket buffers, else Kilted's default settings."""
    env = dict(os.environ, RMW_IMPLEMENTATION="rmw_fastrtps_cpp", PYTHONPATH=str(HERE), ROS_DOMAIN_ID="0")
    env.pop("FASTDDS_DEFAULT_PROFILES_FILE", None)
    if buffers:
        profile = Path(os.environ.get("TMPDIR", "/tmp")) / f"usvsim_fastdds_{os.getpid()}.xml"
        profile.write_text(FASTDDS_PROFILE)
        env["FASTDDS_DEFAULT_PROFILES_FILE"] = str(profile)
    cmd = [sys.executable, str(HERE / "dds_rclpy_peer.py"), mode, *args]
    report = tempfile.TemporaryFile("w+")  # not a pipe: a report larger than the pipe would block the peer
    proc = subprocess.Popen(cmd, env=env, stdout=report, stderr=subprocess.DEVNULL, text=True)
    proc.report = report  # type: ignore[attr-defined]
    return proc


def step_while(sim: Simulation, alive, wall_limit_s: float) -> list[float]:
    """Step paced to the wall clock while `alive()`; returns the wall time of every step."""
    durations, start_wall, start_ns = [], time.perf_counter(), sim.clock_ns
    while alive() and time.perf_counter() - start_wall < wall_limit_s:
        t = time.perf_counter()
        sim.step()
        durations.append(time.perf_counter() - t)
        ahead = (sim.clock_ns - start_ns) / 1e9 - (time.perf_counter() - start_wall)
        if ahead > 0:
            time.sleep(ahead)
    return durations


def collect(proc: subprocess.Popen) -> dict:
    """A peer's JSON report; a peer still running past its wall bound is killed and reported as timed out."""
    if proc.poll() is None:
        proc.kill()
        proc.wait()
        return {"timed_out": True}
    proc.report.seek(0)  # type: ignore[attr-defined]
    return json.loads(proc.report.read() or "{}")  # type: ignore[attr-defined]


def main(seconds: float) -> dict:
    sim = Simulation.from_scenario("harbor_sensors")
    bridge = DdsBridge(sim)
    try:
        for _ in range(10):
            sim.step()  # /tf_static is written now, long before the peer exists
        start = {name: v.position.copy() for name, v in sim.vessels.items()}
        accept = peer("accept", str(seconds))
        steps = step_while(sim, lambda: accept.poll() is None, 250.0)  # the peer's own bounds: 240 s
        result = collect(accept)
        moved = {name: float(abs(v.position - start[name])[:2].max()) for name, v in sim.vessels.items()}
        noisy_steps = []
        for _ in range(2):
            noisy, refused = peer("noisy"), bridge.stats["commands_refused"]
            rejected = sim.commands.stats["rejected"]

            def waiting(r=refused, j=rejected) -> bool:  # until garbage and out-of-range commands both arrived
                return bridge.stats["commands_refused"] == r or sim.commands.stats["rejected"] == j

            # bounded, but long enough for rclpy to start on a machine at load ~10
            noisy_steps += step_while(sim, waiting, 60.0)
            noisy_steps += step_while(sim, lambda: True, 0.5)  # killed mid-stream, while sending
            noisy.kill()
            noisy.wait()
        after = step_while(sim, lambda: True, 1.0)
        defaults = peer("match", "3", buffers=False)
        step_while(sim, lambda: defaults.poll() is None, 140.0)  # the peer's own bound: 120 s
        defaults_result = collect(defaults)
    finally:
        bridge.close()
        sim.close()
    return {"peer": result, "defaults_peer": defaults_result, "moved_m": moved, "bridge": bridge.stats,
            "commands": dict(sim.commands.stats),
            "step_s": {"accept_median": statistics.median(steps), "noisy_median": statistics.median(noisy_steps),
                       "accept_max": max(steps), "noisy_max": max(noisy_steps), "after_steps": len(after),
                       "after_sim_s": len(after) * sim.clock.dt}}  # fmt: skip


if __name__ == "__main__":
    print("RESULT " + json.dumps(main(float(sys.argv[1]) if len(sys.argv) > 1 else 3.0)), flush=True)
