"""`usvsim experiment heave-decay`: heave and roll natural periods of a floating box against closed forms.

A wall-sided box (L = 2, B = 1, D = 1 m, m = 820 kg, KG = 0.2 m, inertia about the CoM 136.7, 341.7, 341.7 kg m²,
draft T = 0.4 m in ρ = 1025 kg/m³, g = 9.81 m/s²) is released in calm water, in the full simulation (MuJoCo, the
triangle hydrostatics, light linear damping ζ ≈ 3 %), either 5 cm above its equilibrium (heave) or heeled 3° about
its centre of mass (roll), with
- the state-space drag (no added mass), and
- Fossen's model with added mass A_33 = 410 kg and A_44 = 40 kg m² (MuJoCo's armature; illustrative values).
The damped period T_d comes from the zero up-crossings, ζ from the logarithmic decrement of successive peaks, and
T_n = T_d √(1 - ζ²) is compared with
    heave: T = 2π √((m + A_33) / (ρ g A_wp)),  A_wp = L B,
    roll:  T = 2π √((I_xx + A_44) / (ρ g ∇ GM_T)),  GM_T = KB + BM - KG = T/2 + B²/(12 T) - KG,
and ζ with the linear damping d (N s/m, N m s) over the critical damping 2 √(k (mass + added)).
Frames: heave is the keel's z (world ENU, up) above its equilibrium; roll is about the body x axis (FLU, REP 103).
PASS: every T_n within 1 % and every ζ within 5 % of the closed forms (measured: within 0.1 %).
"""

from __future__ import annotations

import json
import math
import tempfile
from pathlib import Path

import numpy as np

from usvsim.config.loader import parse_scenario
from usvsim.experiments._scenario_tools import write_box
from usvsim.simulation import Simulation

RHO, G = 1025.0, 9.81
L, B, D, MASS, DRAFT, KG = 2.0, 1.0, 1.0, 820.0, 0.4, 0.2
INERTIA = (MASS * (B**2 + D**2) / 12, MASS * (L**2 + D**2) / 12, MASS * (L**2 + B**2) / 12)  # kg m², about the CoM
Z_W, K_P, M_Q = 250.0, 30.0, 400.0  # linear heave (N s/m), roll and pitch (N m s) damping: ζ ≈ 0.03
ADDED = {"heave": 410.0, "roll": 40.0}  # A_33 kg, A_44 kg m² (Fossen's model only)
HEAVE_M, ROLL_DEG = 0.05, 3.0  # releases
HYDRO = {
    "state_space": {"type": "state_space", "Z_w": Z_W, "K_p": K_P, "M_q": M_Q},
    "fossen": {"type": "fossen", "added_mass": [0.0, 0.0, ADDED["heave"], ADDED["roll"], 0.0, 0.0],
               "linear_damping": [0.0, 0.0, Z_W, K_P, M_Q, 0.0]},
}  # fmt: skip
UNITS = ("SI: periods s, heave m (keel z, world ENU, above equilibrium), roll rad (about body x, FLU), "
         "damping ratio ζ dimensionless")  # fmt: skip


def _pose(dof: str) -> dict:
    """Heave: keel 5 cm above its equilibrium. Roll: heeled about the CoM at its equilibrium (base_link is the keel)."""
    if dof == "heave":
        return {"position": [0.0, 0.0, -DRAFT + HEAVE_M]}
    phi = math.radians(ROLL_DEG)  # base = CoM - R_x(φ) (0, 0, KG)
    return {"position": [0.0, KG * math.sin(phi), KG - DRAFT - KG * math.cos(phi)], "roll_deg": ROLL_DEG}


def simulate(dof: str = "heave", hydro: str = "state_space", seconds: float = 10.0):
    """Time (s) and heave (m) or roll (rad) of the released box."""
    with tempfile.TemporaryDirectory() as tmp:
        write_box(Path(tmp), L, B, D)
        vessel = {"name": "box", "model": "custom", "hull_mesh": "box.stl", "pose": _pose(dof),
                  "mass": {"mass_kg": MASS, "com": [0.0, 0.0, KG], "inertia": list(INERTIA)},
                  "hydrodynamics": HYDRO[hydro]}  # fmt: skip
        data = {"version": 1, "name": "heave", "world": {"physics_rate_hz": 100.0, "water_density_kgpm3": RHO,
                "gravity_mps2": G}, "vessels": [vessel]}  # fmt: skip
        sim = Simulation(parse_scenario(data, "heave_decay", Path(tmp)))
    box = sim.vessels["box"]

    def read() -> float:
        return float(box.position[2] + DRAFT) if dof == "heave" else float(box.rpy[0])

    n = int(round(seconds * 100))
    t, x = np.zeros(n + 1), np.zeros(n + 1)
    x[0] = read()
    for i in range(1, n + 1):
        sim.step()
        t[i], x[i] = sim.time, read()
    sim.close()
    return t, x


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


def closed_form(dof: str, hydro: str) -> dict:
    """Natural period (s) and damping ratio of the linear oscillator the box is in calm water."""
    added = ADDED[dof] if hydro == "fossen" else 0.0
    if dof == "heave":
        inertia, stiffness, damping = MASS + added, RHO * G * L * B, Z_W
    else:
        gm = DRAFT / 2 + B**2 / (12 * DRAFT) - KG
        inertia, stiffness, damping = INERTIA[0] + added, RHO * G * (L * B * DRAFT) * gm, K_P
    return {"formula_period_s": 2 * math.pi * math.sqrt(inertia / stiffness),
            "formula_zeta": damping / (2 * math.sqrt(stiffness * inertia)), "added": added}  # fmt: skip


def run(out_dir: Path) -> dict:
    rows, traces = [], {}
    for dof in ("heave", "roll"):
        for hydro in HYDRO:
            t, x = simulate(dof, hydro)
            res, ref = analyse(t, x), closed_form(dof, hydro)
            rows.append({"dof": dof, "hydrodynamics": hydro, **res, **ref,
                         "period_rel_err": res["natural_period_s"] / ref["formula_period_s"] - 1,
                         "zeta_rel_err": res["zeta"] / ref["formula_zeta"] - 1})  # fmt: skip
            traces[(dof, hydro)] = (t, x)
    passed = all(abs(r["period_rel_err"]) <= 0.01 and abs(r["zeta_rel_err"]) <= 0.05 for r in rows)
    summary = {f"{r['dof']}, {r['hydrodynamics']} (added {r['added']:g})":
               f"T_n {r['natural_period_s']:.4f} s vs {r['formula_period_s']:.4f} s ({100 * r['period_rel_err']:+.2f} %), "
               f"zeta {r['zeta']:.4f} vs {r['formula_zeta']:.4f}" for r in rows}  # fmt: skip
    result = {"experiment": "heave-decay", "passed": bool(passed), "summary": summary, "rows": rows, "units": UNITS,
              "limits": {"period_rel_err": 0.01, "zeta_rel_err": 0.05}}  # fmt: skip
    (Path(out_dir) / "heave_decay.json").write_text(json.dumps(result, indent=2))
    _plot(Path(out_dir) / "heave_decay.png", traces, rows)
    return result


def _plot(path: Path, traces: dict, rows: list[dict]) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    for ax, dof, scale, unit in ((axes[0], "heave", 1000.0, "heave [mm]"), (axes[1], "roll", 180 / math.pi, "roll [deg]")):
        for r in (r for r in rows if r["dof"] == dof):
            t, x = traces[(dof, r["hydrodynamics"])]
            w, z = 2 * math.pi / r["formula_period_s"], r["formula_zeta"]
            line = ax.plot(t, x * scale, lw=1.2, label=f"{r['hydrodynamics']}: T_n {r['natural_period_s']:.4f} s")[0]
            wd = w * math.sqrt(1 - z * z)  # released from rest: x0 e^(-ζωt) (cos ω_d t + ζω/ω_d sin ω_d t)
            closed = x[0] * scale * np.exp(-z * w * t) * (np.cos(wd * t) + z * w / wd * np.sin(wd * t))
            ax.plot(t, closed, "--", color=line.get_color(), lw=0.8,
                    label=f"closed form (added {r['added']:g}): T {r['formula_period_s']:.4f} s")  # fmt: skip
        ax.set(ylabel=unit)
        ax.legend(fontsize=7, loc="upper right")
    axes[0].set_title("Box released in calm water: simulation vs closed forms (with and without added mass)")
    axes[1].set_xlabel("t [s]")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
