"""Endurance: a vessel for one simulated hour in sea state 6 (Hs 5 m, Tp 12.4 s) with each model in turn.

Each run checks that nothing goes non-finite, the hull stays afloat (its mean displaced volume within 10 % of m/ρ,
what a floating hull's buoyancy balances on average: a sinking hull displaces more, one thrown clear of the water
less; a wave may lift it almost out for a moment, so the least volume alone says nothing) and upright (|roll|,
|pitch| < 60 degrees), and that the energy does not run away: the mean kinetic energy of the last 10 minutes is at
most 3 times that of the first 10 minutes after the ramp (a bounded, statistically stationary response; shorter
runs use thirds of the record). The Fossen run uses the Otter, whose parameter set has added mass (integrated
through MuJoCo's armature). Samples start when the 20 s ramp ends (the boat is launched with its keel on still
water). The boat idles (no thrust): the hull drifts freely, as a survey boat waiting on station would.
"""

from __future__ import annotations

import json
import math
import pathlib
import time
from collections.abc import Callable

import numpy as np

from usvsim.config.loader import parse_scenario
from usvsim.simulation import Simulation

MODELS = {  # name: (vessel model, buoyancy, hydrodynamics or None for the vessel's own state-space drag)
    "state_space": ("wamv", {"type": "triangles"}, None),
    "kerner": ("wamv", {"type": "triangles"}, {"type": "kerner"}),
    "fossen": ("otter", {"type": "triangles"}, {"type": "fossen", "parameters": "otter"}),  # with added mass
    "voxels": ("wamv", {"type": "voxels", "voxel_size_m": 0.05}, None),
}
UNITS = ("t s; roll and pitch rad in series, max_*_deg degrees (REP 103, body FLU); volumes m³; energy J: "
         "½ m |v|² of base_link's velocity (world ENU), sampled once a second after the ramp")  # fmt: skip
SEA = {"sea": {"type": "sea_state", "code": 6, "realization": {"resolution": 64}}, "ramp_time_s": 20.0}


def run_model(name: str, duration_s: float, seed: int = 0) -> dict:
    model, buoyancy, hydro = MODELS[name]
    vessel = {"name": "boat", "model": model, "buoyancy": buoyancy}
    if hydro:
        vessel["hydrodynamics"] = hydro
    sim = Simulation(parse_scenario({"version": 1, "environment": SEA, "vessels": [vessel]}, f"endurance/{name}"),
                     seed=seed)  # fmt: skip
    boat, rows = sim.vessels["boat"], []
    every = round(1.0 / sim.clock.dt)
    for k in range(round(duration_s / sim.clock.dt)):
        sim.step()
        if k % every == 0 and sim.time > SEA["ramp_time_s"]:  # judged once the sea is fully up
            v = sim.origin_velocity(0)
            energy = 0.5 * boat.model.mass_kg * float(v @ v)
            rows.append((sim.time, *boat.rpy[:2], boat.position[2], boat.displaced_volume, energy))
    return _verdict(name, np.array(rows), boat.model.mass_kg / sim.world.rho)


def _verdict(name: str, rows: np.ndarray, rest_volume_m3: float) -> dict:
    t, roll, pitch, _, volume, energy = rows.T
    window = max(1, int(min(600.0, len(energy) / 3)))
    early, late = energy[:window], energy[-window:]
    checks = {
        "finite": bool(np.isfinite(rows).all()),
        "afloat": bool(abs(volume.mean() / rest_volume_m3 - 1.0) < 0.1),
        "upright": bool(np.abs(roll).max() < math.radians(60) and np.abs(pitch).max() < math.radians(60)),
        "bounded_energy": bool(late.mean() <= 3.0 * max(early.mean(), 1e-9)),
    }
    return {
        "model": name,
        "passed": all(checks.values()),
        "checks": checks,
        "max_roll_deg": float(np.degrees(np.abs(roll).max())),
        "max_pitch_deg": float(np.degrees(np.abs(pitch).max())),
        "min_volume_m3": float(volume.min()),
        "mean_volume_over_rest": float(volume.mean() / rest_volume_m3),
        "kinetic_energy_mean_early_late_j": [float(early.mean()), float(late.mean())],
        "series": {"t": t.tolist(), "roll": roll.tolist(), "pitch": pitch.tolist(), "energy": energy.tolist()},
    }


def run(out_dir: pathlib.Path, duration_s: float = 3600.0, progress: Callable[[str], None] | None = None) -> dict:
    """Run every model for duration_s; `progress` (if given) hears one line as each model starts and ends."""
    out_dir = pathlib.Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    results = []
    for k, name in enumerate(MODELS, 1):
        start = time.monotonic()
        if progress:
            progress(f"model {k} of {len(MODELS)}, {name}: {duration_s:g} s of sea state 6 ...")
        results.append(run_model(name, duration_s))
        if progress:
            progress(f"model {k} of {len(MODELS)}, {name}: {'PASS' if results[-1]['passed'] else 'FAIL'} "
                     f"({time.monotonic() - start:.0f} s)")  # fmt: skip
    summary = {r["model"]: f"{'PASS' if r['passed'] else 'FAIL'}: max roll {r['max_roll_deg']:.1f} deg, "
               f"max pitch {r['max_pitch_deg']:.1f} deg, mean volume {r['mean_volume_over_rest']:.3f} of m/rho"
               for r in results}  # fmt: skip
    result = {"experiment": "endurance", "units": UNITS, "duration_s": duration_s, "sea": SEA, "runs": results,
              "passed": all(r["passed"] for r in results), "summary": summary}  # fmt: skip
    (out_dir / "endurance.json").write_text(json.dumps(result, indent=1))
    _plot(out_dir / "endurance.png", results)
    return result


def _plot(path: pathlib.Path, results: list[dict]) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(len(results), 1, figsize=(10, 2.2 * len(results)), sharex=True)
    for ax, r in zip(np.atleast_1d(axes), results):
        s = r["series"]
        ax.plot(s["t"], np.degrees(s["roll"]), lw=0.6, label="roll")
        ax.plot(s["t"], np.degrees(s["pitch"]), lw=0.6, label="pitch")
        ax.set_ylabel(f"{r['model']}\n[deg]")
        ax.legend(loc="upper right", fontsize=7)
    np.atleast_1d(axes)[-1].set_xlabel("t [s]")
    fig.suptitle("Sea state 6 (Hs 5 m, Tp 12.4 s), one model per run (Fossen: Otter, others: WAM-V)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
