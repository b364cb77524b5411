"""`usvsim experiment drafts`: equilibrium draft of the library vessels and a custom box.

Each vessel is released level slightly above its waterline in calm water and simulated (MuJoCo +
triangle hydrostatics + the vessel's default drag) until it settles. The simulated draft at the keel
origin and the displaced volume are compared with the analytic level draft where ρ g V(T) = m g
(found by bisection on the same hull mesh) and with m/ρ. A vessel whose centre of mass is not above
its centre of buoyancy trims; its mean draft still matches and its displaced volume must equal m/ρ.
"""

from __future__ import annotations

import json
import tempfile
from pathlib import Path

import numpy as np

from usvsim.config.loader import parse_scenario
from usvsim.experiments._scenario_tools import level_draft, write_box
from usvsim.simulation import Simulation

RHO = 1025.0
BOX = {"length": 2.0, "beam": 1.0, "depth": 1.0, "mass_kg": 820.0, "com": [0.0, 0.0, 0.2]}


def _scenario(vessel: dict, base_dir: Path | None):
    data = {"version": 1, "name": "drafts", "world": {"physics_rate_hz": 100.0, "water_density_kgpm3": RHO},
            "vessels": [vessel]}  # fmt: skip
    return parse_scenario(data, "drafts", base_dir)


def settle(vessel: dict, base_dir: Path | None, seconds: float) -> dict:
    sim = Simulation(_scenario(vessel, base_dir))
    steps = int(seconds * 100)
    z, pitch = [], []
    for i in range(steps):
        sim.step()
        if i >= steps - 100:
            z.append(sim.state.pos[0, 2])
            pitch.append(np.arcsin(-sim.state.rot[0, 2, 0]))
    hull = sim.vessels[vessel["name"]].model.hull
    mass = float(sim.model.body_mass[1])
    return {"draft_sim_m": -float(np.mean(z)) - float(hull.vertices[:, 2].min()),
            "pitch_deg": float(np.degrees(np.mean(pitch))), "volume_sim_m3": float(sim.hydrostatics.volume[0]),
            "mass_kg": mass, "hull": hull}  # fmt: skip


def run(out_dir: Path, seconds: float = 30.0) -> dict:
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        write_box(Path(tmp), BOX["length"], BOX["beam"], BOX["depth"])
        cases = {
            "wamv": ({"name": "wamv", "model": "wamv", "pose": {"position": [0.0, 0.0, -0.05]}}, None),
            "otter": ({"name": "otter", "model": "otter", "pose": {"position": [0.0, 0.0, -0.15]}}, None),
            "otter_pvs": ({"name": "otter_pvs", "model": "otter_pvs", "pose": {"position": [0.0, 0.0, -0.15]}}, None),
            "box": ({"name": "box", "model": "custom", "hull_mesh": "box.stl", "pose": {"position": [0.0, 0.0, -0.35]},
                     "mass": {"mass_kg": BOX["mass_kg"], "com": BOX["com"]}}, Path(tmp)),
        }  # fmt: skip
        for name, (vessel, base) in cases.items():
            r = settle(vessel, base, seconds)
            hull = r.pop("hull")
            analytic = level_draft(hull.vertices, hull.faces, r["mass_kg"], RHO)
            rows.append({"vessel": name, **r, "draft_analytic_m": analytic, "volume_analytic_m3": r["mass_kg"] / RHO,
                         "draft_rel_err": abs(r["draft_sim_m"] - analytic) / analytic,
                         "volume_rel_err": abs(r["volume_sim_m3"] * RHO / r["mass_kg"] - 1.0)})  # fmt: skip
    passed = all(r["volume_rel_err"] < 5e-3 and (r["draft_rel_err"] < 0.03 or abs(r["pitch_deg"]) > 0.5) for r in rows)
    result = {"passed": bool(passed), "summary": {r["vessel"]: {k: r[k] for k in ("draft_sim_m", "draft_analytic_m",
              "pitch_deg", "volume_rel_err")} for r in rows}, "rows": rows}  # fmt: skip
    (Path(out_dir) / "drafts.json").write_text(json.dumps(result, indent=2))
    _plot(Path(out_dir) / "drafts.png", rows)
    return result


def _plot(path: Path, rows) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 3.5))
    x = np.arange(len(rows))
    ax.bar(x - 0.2, [r["draft_analytic_m"] for r in rows], 0.4, label="analytic (ρgV = mg, level)")
    ax.bar(x + 0.2, [r["draft_sim_m"] for r in rows], 0.4, label="simulated (MuJoCo, settled)")
    ax.set_xticks(x, [r["vessel"] for r in rows])
    ax.set(ylabel="draft at the keel origin [m]", title="Equilibrium drafts")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
