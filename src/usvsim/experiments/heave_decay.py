"""`usvsim experiment heave-decay`: heave natural period of a floating box against √(m/(ρ g A_wp)).

A wall-sided box (L = 2, B = 1, D = 1 m, m = 820 kg, draft 0.4 m in ρ = 1025) is released 5 cm above
its equilibrium and oscillates in heave under MuJoCo with the triangle hydrostatics and a light
linear heave damping (ζ ≈ 3 %). The damped period T_d comes from the zero up-crossings, the damping
ratio from the logarithmic decrement, and T_n = T_d √(1 - ζ²) is compared with
T = 2π √(m / (ρ g A_wp)), A_wp = L B (no added mass in the simulation, so none in the formula).
"""

from __future__ import annotations

import json
import tempfile
from pathlib import Path

import numpy as np

from usvsim.config.loader import parse_scenario
from usvsim.experiments._scenario_tools import write_box
from usvsim.simulation import Simulation

RHO, G = 1025.0, 9.81
L, B, D, MASS, DRAFT = 2.0, 1.0, 1.0, 820.0, 0.4
Z_W = 250.0  # N s/m, ζ = Z_w / (2 √(k m)) ≈ 0.031


def simulate(seconds: float = 8.0, offset_m: float = 0.05):
    with tempfile.TemporaryDirectory() as tmp:
        write_box(Path(tmp), L, B, D)
        vessel = {"name": "box", "model": "custom", "hull_mesh": "box.stl",
                  "pose": {"position": [0.0, 0.0, -DRAFT + offset_m]},
                  "mass": {"mass_kg": MASS, "com": [0.0, 0.0, 0.2]},
                  "hydrodynamics": {"type": "state_space", "Z_w": Z_W, "K_p": 200.0, "M_q": 400.0}}  # fmt: skip
        data = {"version": 1, "name": "heave", "world": {"physics_rate_hz": 100.0, "water_density_kgpm3": RHO,
                "gravity_mps2": G}, "vessels": [vessel]}  # fmt: skip
        sim = Simulation(parse_scenario(data, "heave_decay", Path(tmp)))
    n = int(round(seconds * 100))
    t, z = np.zeros(n + 1), np.zeros(n + 1)
    z[0] = sim.state.pos[0, 2]
    for i in range(1, n + 1):
        sim.step()
        t[i], z[i] = sim.time, sim.state.pos[0, 2]
    return t, z + DRAFT  # heave about the analytic equilibrium


def analyse(t: np.ndarray, x: np.ndarray) -> dict:
    """Damped period from up-crossings (linear interpolation), ζ from successive peaks, T_n."""
    s = np.signbit(x)
    idx = np.nonzero(s[:-1] & ~s[1:])[0]
    cross = t[idx] - x[idx] * (t[idx + 1] - t[idx]) / (x[idx + 1] - x[idx])
    t_d = float(np.mean(np.diff(cross)))
    peaks = [x[a:b].max() for a, b in zip(idx[:-1], idx[1:])]
    delta = float(np.mean(np.log(np.array(peaks[:-1]) / np.array(peaks[1:]))))
    zeta = delta / np.sqrt(4 * np.pi**2 + delta**2)
    return {"damped_period_s": t_d, "zeta": float(zeta), "natural_period_s": float(t_d * np.sqrt(1 - zeta**2))}


def run(out_dir: Path) -> dict:
    t, x = simulate()
    res = analyse(t, x)
    formula = 2 * np.pi * np.sqrt(MASS / (RHO * G * L * B))
    rel = abs(res["natural_period_s"] - formula) / formula
    summary = {**res, "formula_period_s": float(formula), "rel_err": float(rel)}
    result = {"passed": bool(rel <= 0.05), "summary": summary}
    (Path(out_dir) / "heave_decay.json").write_text(json.dumps(result, indent=2))
    _plot(Path(out_dir) / "heave_decay.png", t, x, summary)
    return result


def _plot(path: Path, t, x, summary) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 3.5))
    ax.plot(t, x * 1000, label="simulated heave")
    w, z = 2 * np.pi / summary["formula_period_s"], summary["zeta"]
    wd = w * np.sqrt(1 - z**2)
    ax.plot(t, 50 * np.exp(-z * w * t) * np.cos(wd * t), "k--", lw=0.8, label="analytic (T from formula, ζ fitted)")
    ax.set(xlabel="t [s]", ylabel="heave [mm]", title=f"Heave decay: T_n = {summary['natural_period_s']:.4f} s, "
           f"formula {summary['formula_period_s']:.4f} s")  # fmt: skip
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
