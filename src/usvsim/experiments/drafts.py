"""`usvsim experiment drafts`: equilibrium draft of the library vessels and a custom box.

Each vessel is released level slightly above its waterline in calm water and simulated (MuJoCo +
triangle hydrostatics + the vessel's default drag) for 30 s until it settles. Checked against trimesh (not
usvsim's hydrostatics): the hull mesh at the settled pose, cut by the water plane, displaces m/ρ (Archimedes:
the simulation settled where its buoyancy holds its weight, and its volume is the mesh's), and a vessel that
floats level sits at the level draft where trimesh's cut volume is m/ρ (found by bisection). A vessel whose
centre of mass is not above its centre of buoyancy trims (the WAM-V, 0.4°): its draft at the keel origin is
reported, not judged.
PASS: |ρ V_trimesh / m - 1| <= 1e-5 for every vessel, and |draft - level draft| <= 0.1 mm where |pitch| < 0.05°.
"""

from __future__ import annotations

import json
import tempfile
from pathlib import Path

import numpy as np
import trimesh

from usvsim.config.loader import parse_scenario
from usvsim.core.transforms import matrix_from_quat
from usvsim.experiments._scenario_tools import write_box
from usvsim.simulation import Simulation

RHO = 1025.0
VOLUME_LIMIT, DRAFT_LIMIT_M, LEVEL_DEG = 1e-5, 1e-4, 0.05
UNITS = ("drafts m: the depth of base_link (the keel origin) below still water; pitch_deg degrees (REP 103, positive "
         "bow down); volumes m³, mass kg; world ENU, body FLU")  # fmt: skip
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
    boat = sim.vessels[vessel["name"]]
    hull = boat.model.hull
    mass = float(sim.model.body_mass[1])
    posed = trimesh.Trimesh(hull.vertices @ matrix_from_quat(boat.quat).T + boat.position, hull.faces, process=False)
    result = {"draft_sim_m": -float(np.mean(z)) - float(hull.vertices[:, 2].min()),
              "pitch_deg": float(np.degrees(np.mean(pitch))), "volume_sim_m3": float(sim.hydrostatics.volume[0]),
              "volume_trimesh_m3": _volume_below(posed, 0.0), "mass_kg": mass, "hull": hull}  # fmt: skip
    sim.close()
    return result


def _volume_below(mesh: trimesh.Trimesh, level: float) -> float:
    """trimesh's volume of the closed mesh below z = level (cut and capped)."""
    return float(mesh.slice_plane(plane_origin=[0.0, 0.0, level], plane_normal=[0.0, 0.0, -1.0], cap=True).volume)


def level_draft(vertices: np.ndarray, faces: np.ndarray, mass_kg: float, rho: float) -> float:
    """Draft T (m, above the mesh's lowest point) at which trimesh's cut volume of the level hull is mass/rho."""
    mesh = trimesh.Trimesh(vertices, faces, process=False)
    keel = float(np.min(vertices[:, 2]))
    lo, hi = 0.0, float(np.ptp(vertices[:, 2]))
    for _ in range(50):
        t = 0.5 * (lo + hi)
        lo, hi = (t, hi) if _volume_below(mesh, keel + t) < mass_kg / rho else (lo, t)
    return 0.5 * (lo + hi)


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
            level = abs(r["pitch_deg"]) < LEVEL_DEG
            rows.append({"vessel": name, **r, "draft_analytic_m": analytic, "volume_analytic_m3": r["mass_kg"] / RHO,
                         "draft_rel_err": abs(r["draft_sim_m"] - analytic) / analytic, "level": level,
                         "volume_rel_err": abs(r["volume_trimesh_m3"] * RHO / r["mass_kg"] - 1.0),
                         "draft_ok": bool(not level or abs(r["draft_sim_m"] - analytic) <= DRAFT_LIMIT_M)})  # fmt: skip
    passed = all(r["volume_rel_err"] <= VOLUME_LIMIT and r["draft_ok"] for r in rows)
    result = {"experiment": "drafts", "units": UNITS, "passed": bool(passed), "summary": {r["vessel"]: {k: r[k] for k in ("draft_sim_m", "draft_analytic_m",
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
    ax.bar(x - 0.2, [r["draft_analytic_m"] for r in rows], 0.4, label="level draft, trimesh (ρgV = mg)")
    ax.bar(x + 0.2, [r["draft_sim_m"] for r in rows], 0.4, label="simulated (MuJoCo, settled)")
    ax.set_xticks(x, [r["vessel"] + ("" if r["level"] else f" (trim {r['pitch_deg']:.2f}°)") for r in rows])
    ax.set(ylabel="draft at the keel origin [m]", title="Equilibrium drafts")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
