"""Foxglove connection limit under 200 connection attempts: process memory (RSS) and the simulation's step rate.

`harbor_sensors` with the Foxglove bridge (default limit: 16 connections, 16 MiB unsent per client). Phase 1
(undisturbed): the bridge on, no client; phase 2 (loaded): a client process makes 200 connection attempts;
every admitted connection subscribes to every channel; odd ones read everything, even ones never read (they
are dropped at the buffer bound). The step rate of phase 2 is reported as a ratio to phase 1 of the same run
(medians of `--rounds` chunks of `--seconds` simulated seconds), the RSS as the maximum sampled after each chunk
(the simulation's process; the proxy process's RSS is added when it is found). The client process runs on the
same 2 cores at normal priority: it reads ~100 MB/s in Python, so the ratio includes that contention.

    python benchmarks/bench_foxglove_clients.py [--seconds 1] [--rounds 5] [--attempts 200]
Writes benchmarks/results/foxglove_clients.json (`--max-clients M`: foxglove_clients_M.json).
Acceptance (issue 19): RSS < 1 GB, ratio >= 0.5.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import threading
import time
from pathlib import Path

RESULTS = Path(__file__).parent / "results" / "foxglove_clients.json"


def client_main(url: str, attempts: int) -> None:
    """Make `attempts` connections; admitted ones subscribe to everything; read (odd) or stall (even)."""
    from websockets.exceptions import InvalidStatus
    from websockets.sync.client import connect

    counts = {"admitted": 0, "refused_503": 0, "other_errors": 0, "messages": 0, "bytes": 0}
    stop, lock = threading.Event(), threading.Lock()
    threading.Thread(target=lambda: (sys.stdin.read(), stop.set()), daemon=True).start()

    def serve(ws, read: bool) -> None:
        subscribed = set()
        while not stop.is_set():
            try:
                frame = ws.recv(timeout=0.1)
            except TimeoutError:
                continue
            except Exception:  # dropped by the proxy, or closed
                return
            if isinstance(frame, str):
                new = [c["id"] for c in json.loads(frame).get("channels", []) if c["id"] not in subscribed]
                subscribed.update(new)
                if new:
                    ws.send(
                        json.dumps(
                            {"op": "subscribe", "subscriptions": [{"id": c, "channelId": c} for c in new]}
                        )
                    )
                if not read and subscribed:
                    stop.wait()  # subscribed to everything, never reads again
                    return
            else:
                with lock:
                    counts["messages"] += 1
                    counts["bytes"] += len(frame)

    for k in range(attempts):
        try:
            ws = connect(url, subprotocols=["foxglove.sdk.v1"], max_size=None, open_timeout=10, legacy=True)
        except InvalidStatus as exc:
            counts["refused_503" if exc.response.status_code == 503 else "other_errors"] += 1
            continue
        except Exception:
            counts["other_errors"] += 1
            continue
        counts["admitted"] += 1
        threading.Thread(target=serve, args=(ws, k % 2 == 1), daemon=True).start()
    print(json.dumps({"attempts_done": True}), flush=True)
    stop.wait()
    print(json.dumps(counts), flush=True)


def rss_mb(pid: int | str = "self") -> float:
    try:
        return int(Path(f"/proc/{pid}/statm").read_text().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2**20
    except OSError:
        return 0.0


def timed(sim, seconds: float) -> float:
    start = time.perf_counter()
    sim.run(seconds)
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=1.0, help="simulated seconds per chunk")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--attempts", type=int, default=200)
    parser.add_argument("--max-clients", type=int, default=16)
    parser.add_argument("--client", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.client:
        return client_main(args.client, args.attempts)
    from usvsim.bridges.foxglove import FoxgloveBridge
    from usvsim.simulation import Simulation

    sim = Simulation.from_scenario("harbor_sensors")
    bridge = FoxgloveBridge(sim, port=0, max_clients=args.max_clients)
    sim.run(0.5)  # warm: numba, render context; every topic advertised
    load = [os.getloadavg()[0]]
    base = [timed(sim, args.seconds) for _ in range(args.rounds)]
    rss_base = rss_mb() + rss_mb(bridge._proxy._child.pid)
    cmd = [sys.executable, __file__, "--client", bridge.url, "--attempts", str(args.attempts)]
    client = subprocess.Popen(cmd, stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
    loaded, rss = [], [rss_base]
    done = threading.Event()
    threading.Thread(target=lambda: (client.stdout.readline(), done.set()), daemon=True).start()
    while (
        not done.is_set() or len(loaded) < args.rounds
    ):  # chunks while the attempts go on, then `rounds` more
        loaded.append(timed(sim, args.seconds))
        rss.append(rss_mb() + rss_mb(bridge._proxy._child.pid))
    out_text, _ = client.communicate("", timeout=60)
    load.append(os.getloadavg()[0])
    stats = dict(bridge.stats)
    bridge.close()
    sim.close()
    summary = {
        "undisturbed_wall_s_per_chunk": round(statistics.median(base), 3),
        "loaded_wall_s_per_chunk": round(statistics.median(loaded), 3),
        "step_rate_ratio": round(statistics.median(base) / statistics.median(loaded), 3),
        "rss_mb_undisturbed": round(rss_base), "rss_mb_max_loaded": round(max(rss)),
        "client": json.loads(out_text.strip().splitlines()[-1]),
        "bridge": {k: v for k, v in stats.items() if k.startswith("connections")},
        "loadavg_1min_start_end": load, "max_clients": args.max_clients, "chunks_loaded": len(loaded), "seconds_per_chunk": args.seconds,
    }  # fmt: skip
    path = RESULTS if args.max_clients == 16 else RESULTS.with_stem(f"{RESULTS.stem}_{args.max_clients}")
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(summary, indent=2) + "\n")
    print(json.dumps(summary, indent=2))


if __name__ == "__main__":
    main()
