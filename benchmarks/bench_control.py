"""Control cost per call: velocity controller + thrust allocation, usvsim vs baselines in the same run.

    python benchmarks/bench_control.py [--calls 5000] [--no-metrics]

Timed (best of 5 runs of `--calls` calls, states and commands cycling through 64 random samples):
- usvsim constrained:   VesselController.compute (reference model, PI + feed-forward, back-calculation,
                        box-constrained allocation with the angle servo, inverse thrust maps);
- usvsim unconstrained: the same with the pseudo-inverse allocator;
- baseline lsq_linear:  the same controller, then scipy.optimize.lsq_linear (BVLS) on the same bounded
                        least-squares problem at the same angles (what a straightforward implementation calls);
- baseline pinv:        the same controller, then numpy.linalg.pinv of the extended matrix every call and
                        uniform scaling into the limits (the Navier stack's allocate_thrust.py, seed §2.4).
- usvsim apply:         `apply()` on a live simulation vessel handle (reads its state, commands its thrusters).
Also records the closed-loop step-response metrics of the acceptance tests (unless --no-metrics).
Writes benchmarks/results/control.json.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import time
from pathlib import Path

import numpy as np
from scipy.optimize import lsq_linear

from usvsim.control import VesselController, VesselState
from usvsim.control.layout import thrust_matrix
from usvsim.control.plant import reference_at_com
from usvsim.control.step_response import ClosedLoop, step_metrics

RESULTS = Path(__file__).parent / "results" / "control.json"
DT = 0.05


def samples(ctrl: VesselController, n: int = 64) -> list[tuple[VesselState, np.ndarray]]:
    rng = np.random.default_rng(0)
    p = ctrl.layout.params
    out = []
    for _ in range(n):
        nu = rng.uniform([-0.5, -0.3, -0.2], [2.0, 0.3, 0.2])
        state = VesselState(
            np.zeros(3), 0.0, nu, rng.uniform(p[:, 4], p[:, 5]), rng.uniform(-p[:, 9], p[:, 8]) * 0.5
        )
        out.append((state, rng.uniform([0.0, -0.5, -0.3], [2.5, 0.5, 0.3])))
    return out


def baseline_lsq(ctrl: VesselController):
    """Controller + scipy BVLS on min ||Q^½(Bt - τ)||² + Σ w t²/T² at the constrained allocator's angles."""
    p, q = (
        ctrl.layout.params,
        ctrl.allocator.tau_weights if hasattr(ctrl.allocator, "tau_weights") else np.ones(3),
    )
    reg = np.diag(np.sqrt(p[:, 12]) / p[:, 8])

    def call(state, cmd):
        tau = ctrl.velocity.update(state.nu_com, reference_at_com(cmd, ctrl.plant.com_flu_m), DT)
        B = np.sqrt(q)[:, None] * thrust_matrix(p, state.thruster_angle_rad)
        t = lsq_linear(np.vstack([B, reg]), np.concatenate([np.sqrt(q) * tau, np.zeros(len(p))]),
                       bounds=(-p[:, 9], p[:, 8]), method="bvls").x  # fmt: skip
        ctrl.velocity.report_achieved(thrust_matrix(p, state.thruster_angle_rad) @ t, DT)

    return call


def baseline_pinv(ctrl: VesselController):
    p, ext = ctrl.layout.params, ctrl.layout.extended

    def call(state, cmd):
        tau = ctrl.velocity.update(state.nu_com, reference_at_com(cmd, ctrl.plant.com_flu_m), DT)
        f = np.linalg.pinv(ext) @ tau
        f = f * min(1.0, p[:, 8].min() / max(np.abs(f).max(), 1e-12))
        ctrl.velocity.report_achieved(ext @ f, DT)

    return call


def time_calls(call, data, calls: int) -> float:
    """Best of 5: microseconds per call."""
    best = np.inf
    for _ in range(5):
        start = time.perf_counter()
        for i in range(calls):
            call(*data[i % len(data)])
        best = min(best, (time.perf_counter() - start) / calls)
    return best * 1e6


def bench_vessel(model: str, calls: int) -> dict:
    loop = ClosedLoop(model)
    runs = {}
    for kind in ("constrained", "unconstrained"):
        ctrl = VesselController.for_model(loop.vessel.model, allocator=kind)
        data = samples(ctrl)
        runs[f"usvsim {kind}"] = time_calls(lambda s, c, ctrl=ctrl: ctrl.compute(s, c, DT), data, calls)
    ctrl = VesselController.for_model(loop.vessel.model)
    runs["baseline lsq_linear"] = time_calls(baseline_lsq(ctrl), samples(ctrl), max(calls // 10, 50))
    runs["baseline pinv"] = time_calls(baseline_pinv(ctrl), samples(ctrl), calls)
    runs["usvsim apply (sim handle I/O)"] = time_calls(lambda c: loop.controller.apply(loop.vessel, c, DT),
                                                       [((1.0, 0.0, 0.1),)], calls)  # fmt: skip
    us = {k: round(v, 2) for k, v in runs.items()}
    ratios = {
        "lsq_linear / usvsim constrained": round(runs["baseline lsq_linear"] / runs["usvsim constrained"], 1),
        "pinv / usvsim unconstrained": round(runs["baseline pinv"] / runs["usvsim unconstrained"], 2),
    }
    return {"us_per_call": us, "ratios": ratios, "thrusters": loop.controller.layout.n}


def metrics(model: str) -> dict:
    out = {}
    for name, ref, col, final in (
        ("surge 0->1.5 m/s", (1.5, 0, 0), 1, 1.5),
        ("yaw rate 0->0.2 rad/s", (0, 0, 0.2), 3, 0.2),
    ):
        log = ClosedLoop(model).run(ref, 25.0)
        over, settle = step_metrics(log[:, 0] - log[0, 0] + 0.01, log[:, col], 0.0, final)
        out[name] = {"overshoot_pct": round(over, 3), "settling_2pct_s": round(settle, 2)}
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--calls", type=int, default=5000)
    parser.add_argument("--no-metrics", action="store_true")
    args = parser.parse_args()
    report = {
        "machine": f"{platform.machine()}, {os.cpu_count()} cores",
        "controller_period_s": DT,
        "vessels": {},
    }
    for model in ("wamv", "otter"):
        entry = bench_vessel(model, args.calls)
        if not args.no_metrics:
            entry["step_response"] = metrics(model)
        report["vessels"][model] = entry
        print(model, json.dumps(entry, indent=2))
    RESULTS.parent.mkdir(parents=True, exist_ok=True)
    RESULTS.write_text(json.dumps(report, indent=2) + "\n")


if __name__ == "__main__":
    main()
