"""Foxglove bridge cost: wall time of the `harbor_sensors` simulation (2D + 3D LiDAR, 512x512 RGB-D camera, IMU,
odometry, GNSS, two vessels, nine buoys) with the bridge on vs off, in the same run.

Modes, interleaved round by round (the machine is shared: ratios, medians of the rounds):
- off: no bridge (baseline);
- serialize: no bridge, a subscriber that reads every message's CDR (what any consumer, e.g. the recorder, pays);
- idle: bridge on, no client;
- client: a client in another process (like the Foxglove app) subscribed to every channel, reading all of it;
- stalled: three clients subscribed to every channel that never read a byte (plus the reading client).

    python benchmarks/bench_foxglove.py [--seconds 2] [--rounds 3]
Reported per mode: median wall time and its ratio to `off`, and the simulation process's CPU time (all its
threads, the SDK's server threads included) and its ratio: on shared cores the CPU ratio is the steadier one.
Writes benchmarks/results/foxglove.json.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

RESULTS = Path(__file__).parent / "results" / "foxglove.json"
MODES = ("off", "serialize", "idle", "client", "stalled")


def client_main(url: str) -> None:
    """Subscribe to every channel and read until stdin closes; print what arrived as JSON."""
    import threading

    from websockets.sync.client import connect

    ws = connect(url, subprotocols=["foxglove.sdk.v1"], max_size=None, legacy=True)
    stop, counts = threading.Event(), {"messages": 0, "bytes": 0}
    threading.Thread(target=lambda: (sys.stdin.read(), stop.set()), daemon=True).start()
    subscribed = set()
    while not stop.is_set():
        try:
            frame = ws.recv(timeout=0.1)
        except TimeoutError:
            continue
        if isinstance(frame, str):
            msg = json.loads(frame)
            new = (
                [c["id"] for c in msg.get("channels", []) if c["id"] not in subscribed]
                if msg["op"] == "advertise"
                else []
            )
            if new:
                subscribed.update(new)
                subs = [{"id": cid, "channelId": cid} for cid in new]
                ws.send(json.dumps({"op": "subscribe", "subscriptions": subs}))
        elif frame[0] == 0x01:
            counts["messages"] += 1
            counts["bytes"] += len(frame) - 13
    ws.close()
    print(json.dumps(counts | {"channels": len(subscribed)}))


def start_client(url: str) -> subprocess.Popen:
    cmd = [sys.executable, __file__, "--client", url]
    return subprocess.Popen(cmd, stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)


def stalled_clients(bridge, n: int = 3) -> list:
    sys.path.insert(0, str(Path(__file__).parents[1] / "tests" / "bridges"))
    from foxglove_client import FoxgloveClient, raw_connect, send_frame

    probe = FoxgloveClient(bridge.url)
    probe.pump(0.3)
    subs = [{"id": cid, "channelId": cid} for cid in probe.channels]
    probe.close()
    socks = [raw_connect(bridge.port) for _ in range(n)]
    for sock in socks:
        send_frame(sock, json.dumps({"op": "subscribe", "subscriptions": subs}).encode())
    return socks


def run_mode(sim, mode: str, seconds: float) -> dict:
    from usvsim.bridges.foxglove import FoxgloveBridge

    if mode in ("off", "serialize"):
        unsubscribe = sim.subscribe(lambda env: env.cdr) if mode == "serialize" else None
        start, cpu = time.perf_counter(), time.process_time()
        sim.run(seconds)
        out = {"wall_s": time.perf_counter() - start, "cpu_s": time.process_time() - cpu}
        if unsubscribe is not None:
            unsubscribe()
        return out
    bridge, client, socks = FoxgloveBridge(sim, port=0), None, []
    try:
        sim.run(0.2)  # every topic advertised before the timed part
        if mode in ("client", "stalled"):
            client = start_client(bridge.url)
            time.sleep(1.0)  # the client process starts and subscribes
        if mode == "stalled":
            socks = stalled_clients(bridge)
        start, cpu = time.perf_counter(), time.process_time()
        children = resource.getrusage(resource.RUSAGE_CHILDREN)
        sim.run(seconds)
        out = {
            "wall_s": time.perf_counter() - start,
            "cpu_s": time.process_time() - cpu,
            "bridge": dict(bridge.stats),
        }
    finally:
        for sock in socks:
            sock.close()
        if client is not None:
            out_text, _ = client.communicate("", timeout=30)
            after = resource.getrusage(resource.RUSAGE_CHILDREN)
            out["client"] = json.loads(out_text) | {
                "cpu_s": after.ru_utime + after.ru_stime - children.ru_utime - children.ru_stime
            }
        bridge.close()
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=2.0, help="simulated seconds per timed run")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--client", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.client:
        return client_main(args.client)
    from usvsim.simulation import Simulation

    sim = Simulation.from_scenario("harbor_sensors")
    sim.run(0.5)  # warm: numba, render context
    runs = {m: [] for m in MODES}
    for r in range(args.rounds):
        for mode in MODES:
            runs[mode].append(run_mode(sim, mode, args.seconds))
            print(f"round {r} {mode:8s} {runs[mode][-1]['wall_s']:.3f} s", flush=True)
    sim.close()
    report = summarize(runs, args)
    RESULTS.parent.mkdir(parents=True, exist_ok=True)
    RESULTS.write_text(json.dumps(report, indent=2) + "\n")
    print(json.dumps(report["summary"], indent=2))


def summarize(runs: dict, args) -> dict:
    median = {m: statistics.median(r["wall_s"] for r in runs[m]) for m in MODES}
    cpu = {m: statistics.median(r["cpu_s"] for r in runs[m]) for m in MODES}  # all threads of the sim process
    summary = {
        m: {"median_wall_s": round(median[m], 3), "ratio_vs_off": round(median[m] / median["off"], 3),
            "realtime_factor": round(args.seconds / median[m], 2),
            "sim_process_cpu_s": round(cpu[m], 3), "cpu_ratio_vs_off": round(cpu[m] / cpu["off"], 3)}
        for m in MODES
    }  # fmt: skip
    for m in ("client", "stalled"):
        last = runs[m][-1]
        summary[m]["delivered_mb_per_sim_s"] = round(last["client"]["bytes"] / 1e6 / args.seconds, 2)
        summary[m]["client_process_cpu_s"] = round(
            statistics.median(r["client"]["cpu_s"] for r in runs[m]), 3
        )
        summary[m]["bridge_stats_last_round"] = last["bridge"]
    return {
        "machine": f"{platform.machine()}, {os.cpu_count()} cores (shared: noisy, compare ratios)",
        "scenario": "harbor_sensors",
        "simulated_seconds_per_run": args.seconds,
        "rounds": args.rounds,
        "summary": summary,
        "walls_s": {m: [round(r["wall_s"], 3) for r in runs[m]] for m in MODES},
    }


if __name__ == "__main__":
    main()
