"""`usvsim experiment kerner-vectors`: the single-triangle test vectors of physics.md §1.10.

Triangle (0,0,-1), (0,1,-1), (1,0,-1) (outward normal -z, A = 0.5 m²) under flat water, rho = 1025,
g = 9.81, nu = 1.0533e-6, L = 2 m, point velocity (2, 0, -0.5) m/s. Every figure is produced by the
batched kernels (HullSet for the hydrostatic force, KernerForces for the rest). Slamming is the kernel's
time-step independent impulse form (kerner_terms._slam_scalar), not §1.10's per-step formula (that one is
`kerner_terms.slamming_force`, checked against §1.10 in tests/hydro): a cut triangle of 0.08 m² with 0.05 m²
submerged (water tilted across it), 0.03 m² on the previous step, v = (0, 0, -2) m/s, m = 80 kg, S = 6 m²,
dt = 0.02 s: F_z = min(2 / v_slam, 1)^p · 2 m · 2 · 0.02 / (S · 0.02) = 53.333 · ramp N.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from usvsim.config.hydro_models import KernerHydrodynamics
from usvsim.hydro import kerner_kernels as kk
from usvsim.hydro.hydrostatics import HullSet
from usvsim.hydro.kerner import KernerForces

TRI = np.array([(0.0, 0.0, -1.0), (0.0, 1.0, -1.0), (1.0, 0.0, -1.0)])
FACE = np.array([[0, 1, 2]])
V_POINT = np.array([[2.0, 0.0, -0.5]])
REFERENCE = {
    "hydrostatic_fz": 5027.625, "reynolds": 3.914465e6, "c_f": 0.0035557, "viscous_fx": -3.87243,
    "pressure_100_100_0.4": 179.0674, "pressure_10_10_0.5": 15.5415, "pressure_5_100_1.0": 52.7888,
    "slam_p2_v1": 160.0 / 3.0, "slam_p2_v4": 40.0 / 3.0, "slam_p0.5_v4": 160.0 / 3.0 * 0.5**0.5,
}  # fmt: skip


UNITS = ("forces N, world ENU (z up): hydrostatic_fz, pressure_* and slam_* are z components, viscous_fx the x "
         "component; reynolds and c_f dimensionless. References: physics.md §1.10; for slam_* the impulse formula "
         "in this module's docstring (the triangle, flat water at z = 0, velocities in m/s)")  # fmt: skip


def _kerner(hulls, cfg, mass=80.0, length=2.0):
    return KernerForces(hulls, [cfg], [mass], [length], rho_water=1025.0)


def _drag(c1, c2, f):
    hulls = HullSet([(TRI, FACE)])
    cfg = KernerHydrodynamics(kinematic_viscosity_m2ps=1.0533e-6, pressure_linear_pa=c1, pressure_quadratic_pa=c2, pressure_falloff=f,
                              suction_falloff=f, slamming_scale=0.0, air_scale=0.0)  # fmt: skip
    z3 = np.zeros((1, 3))
    res = _kerner(hulls, cfg).compute(TRI, np.zeros(3), np.zeros((3, 3)), np.array([[0.3, 0.3, -1.0]]), V_POINT,
                                      z3, z3, z3, 0.02)  # fmt: skip
    return res.parts[0]


def _slam(power, speed):
    """Horizontal 0.08 m² triangle, 0.05 m² below the (tilted) water (0.03 m² a step before), v = (0,0,-2)."""
    side = np.sqrt(0.16)
    tri = np.array([(0.0, 0.0, -1.0), (0.0, side, -1.0), (side, 0.0, -1.0)])
    t = np.sqrt(0.05 / 0.08)  # two vertices above: submerged fraction t_b t_c = t²
    h_above = 1.0 / t - 1.0  # height above water of b and c for a cut at fraction t from a (h_a = -1)
    eta = np.array([0.0, -1.0 - h_above, -1.0 - h_above])
    hulls = HullSet([(tri, FACE)])
    cfg = KernerHydrodynamics(viscous_scale=0.0, pressure_scale=0.0, air_scale=0.0, slamming_power=power,
                              slamming_speed_mps=speed)  # fmt: skip
    k = _kerner(hulls, cfg)
    k.coef[0, kk.AREA] = 6.0  # S, the total hull area of the reference case
    k.set_previous_areas(np.array([0.03]))
    z3 = np.zeros((1, 3))
    res = k.compute(tri, eta, np.zeros((3, 3)), np.array([[0.1, 0.1, -1.0]]), np.array([[0.0, 0.0, -2.0]]),
                    z3, z3, z3, 0.02)  # fmt: skip
    return res.parts[0, kk.SLAMMING, 2]


def compute() -> dict:
    hulls = HullSet([(TRI, FACE)])
    hs = hulls.compute(TRI.copy(), np.zeros(3), np.array([[0.3, 0.3, -1.0]]), 1025.0, 9.81)
    speed = float(np.linalg.norm(V_POINT))
    base = _drag(100, 100, 0.4)
    return {
        "hydrostatic_fz": float(hs.force[0, 2]), "reynolds": speed * 2.0 / 1.0533e-6,
        "c_f": float(kk.friction_coefficient(speed, 2.0, 1.0533e-6, 1e3)), "viscous_fx": float(base[kk.VISCOUS, 0]),
        "pressure_100_100_0.4": float(base[kk.PRESSURE, 2]),
        "pressure_10_10_0.5": float(_drag(10, 10, 0.5)[kk.PRESSURE, 2]),
        "pressure_5_100_1.0": float(_drag(5, 100, 1.0)[kk.PRESSURE, 2]),
        "slam_p2_v1": float(_slam(2.0, 1.0)), "slam_p2_v4": float(_slam(2.0, 4.0)),
        "slam_p0.5_v4": float(_slam(0.5, 4.0)),
    }  # fmt: skip


def run(out_dir: Path) -> dict:
    got = compute()
    # physics.md prints 5-7 significant digits: agreement to its rounding (< 5e-5 relative) is a
    # match; tests/hydro/test_kerner.py checks the same kernels against full-precision formulas at 1e-9
    rel = {k: abs(got[k] - v) / abs(v) for k, v in REFERENCE.items()}
    passed = all(r <= 5e-5 for r in rel.values())
    result = {"experiment": "kerner-vectors", "units": UNITS, "passed": bool(passed),
              "summary": {"max_rel_err": max(rel.values())},
              "values": got, "reference": REFERENCE, "rel_err": rel}  # fmt: skip
    (Path(out_dir) / "kerner_vectors.json").write_text(json.dumps(result, indent=2))
    _plot(Path(out_dir) / "kerner_vectors.png", got)
    return result


def _plot(path: Path, got: dict) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    keys = list(REFERENCE)
    fig, ax = plt.subplots(figsize=(8, 3.5))
    ax.bar(range(len(keys)), [got[k] / REFERENCE[k] for k in keys])
    ax.axhline(1.0, color="k", lw=0.5)
    ax.set_xticks(range(len(keys)), keys, rotation=40, ha="right", fontsize=7)
    ax.set(ylabel="usvsim / reference", ylim=(0.99, 1.01),
           title="Kerner single-triangle test vectors (physics.md §1.10; slamming: impulse formula)")  # fmt: skip
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
