"""The hydro validation experiments run and pass (shortened where the reference allows it)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from usvsim.experiments import box_righting, drafts, heave_decay, kerner_vectors, otter, voxel_sphere


@pytest.fixture(autouse=True)
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("USVSIM_CACHE", str(tmp_path / "cache"))


def _check(result, out, name):
    assert result["passed"], result["summary"]
    saved = json.loads((out / f"{name}.json").read_text())
    assert saved["passed"]
    assert " m" in saved["units"] and ("ENU" in saved["units"] or "FLU" in saved["units"])  # units and frames stated
    assert (out / f"{name}.png").stat().st_size > 1000


def test_kerner_vectors(tmp_path):
    _check(kerner_vectors.run(tmp_path), tmp_path, "kerner_vectors")


def test_box_righting(tmp_path):
    r = box_righting.run(tmp_path)
    _check(r, tmp_path, "box_righting")
    by = {row["heel_deg"]: row for row in r["rows"]}
    assert by[30.0]["usvsim_12"] == pytest.approx(-561.3500, abs=1e-4)  # physics.md §1.10
    assert by[30.0]["centroid_rule_12"] == pytest.approx(-323.3667, abs=1e-4)


def test_otter_straight_runs_match_pvs():
    """60 s runs are converged to < 1e-5 in u (PVS t95 ≈ 3.7 s); the experiment uses 200 s like §3.4."""
    model = otter.OtterFLU(otter.otter_pvs())
    for name, n_cmd, u_ref, w_ref, th_ref, _z_ref in otter.REFERENCE:
        ss = otter.steady_state(*otter.simulate((n_cmd, n_cmd), 60.0, True, model))
        assert ss["u_ss"] == pytest.approx(u_ref, rel=2e-5), name
        assert ss["w_ss"] == pytest.approx(w_ref, abs=2e-6), name
        assert ss["theta_end"] == pytest.approx(th_ref, abs=2e-6), name
    fixed = otter.steady_state(*otter.simulate((otter.REFERENCE[3][1],) * 2, 60.0, False, model))
    assert fixed["u_ss"] == pytest.approx(6 * 0.5144, rel=1e-5)  # U_max without the payload quirk


def test_otter_experiment_judges_every_figure_at_pvs_precision_and_runs_the_simulator(tmp_path, monkeypatch):
    """u, w, θ, z within 1e-6 of PVS's 6-decimal figures (the limit was 2 % on u alone: a θ off by 1e-5 or a u off by
    1 % passed), and usvsim's own simulation of otter_pvs within 1.5 % of PVS's equations (it was not run at all)."""
    result = otter.run(tmp_path, seconds=40.0, sim_seconds=40.0)
    _check(result, tmp_path, "otter")
    assert [r["case"] for r in result["simulator"]] == list(otter.SIM_CASES)
    assert all(r["max_rel_err"] < 0.015 for r in result["simulator"])
    assert "FRD" in result["units"] and "FLU" in result["units"]
    bad = list(otter.REFERENCE)
    name, n_cmd, u_ref, w_ref, th_ref, z_ref = bad[1]
    bad[1] = (name, n_cmd, u_ref, w_ref, th_ref + 1e-5, z_ref)  # a pitch off by 1e-5 rad
    monkeypatch.setattr(otter, "REFERENCE", tuple(bad))
    monkeypatch.setattr(otter, "simulator_runs", lambda model, seconds: result["simulator"])
    assert not otter.run(tmp_path, seconds=40.0)["passed"]


def test_voxel_sphere(tmp_path):
    r = voxel_sphere.run(tmp_path, sizes=(0.1, 0.05), n_depths=201)
    _check(r, tmp_path, "voxel_sphere")
    assert r["summary"]["usvsim_cut_max_err_s0.05"] < 0.0044


def test_drafts(tmp_path):
    """Judged against trimesh's cut of the settled hull (it compared with usvsim's own hydrostatics: its level draft
    by bisection on HullSet, and the simulation's own displaced volume, within 0.5 %)."""
    result = drafts.run(tmp_path, seconds=20.0)
    _check(result, tmp_path, "drafts")
    rows = {r["vessel"]: r for r in result["rows"]}
    for name, row in rows.items():
        assert row["volume_trimesh_m3"] * drafts.RHO == pytest.approx(row["mass_kg"], rel=1e-5), name
    assert not rows["wamv"]["level"]  # trims 0.4°: its draft is reported, not judged
    for name in ("otter", "otter_pvs", "box"):
        assert rows[name]["level"] and rows[name]["draft_sim_m"] == pytest.approx(rows[name]["draft_analytic_m"], abs=1e-4)
    assert rows["box"]["draft_analytic_m"] == pytest.approx(820.0 / (1025.0 * 2.0 * 1.0), abs=1e-9)  # m / (ρ L B)


def test_heave_decay(tmp_path):
    """Heave and roll, without and with Fossen's added mass (it was ignored on this box, a 'simple' MuJoCo body:
    1.27 s instead of 1.55 s in heave): every period within 1 % of the closed form, here checked from its inputs."""
    r = heave_decay.run(tmp_path)
    _check(r, tmp_path, "heave_decay")
    rows = {(row["dof"], row["hydrodynamics"]): row for row in r["rows"]}
    assert len(rows) == 4
    k_heave = 1025.0 * 9.81 * 2.0 * 1.0  # ρ g A_wp, N/m
    k_roll = 1025.0 * 9.81 * 0.8 * (0.2 + 1.0 / (12 * 0.4) - 0.2)  # ρ g ∇ GM_T, N m/rad
    i_xx = 820.0 * (1.0 + 1.0) / 12  # kg m²
    expected = {("heave", "state_space"): 2 * np.pi * np.sqrt(820.0 / k_heave),
                ("heave", "fossen"): 2 * np.pi * np.sqrt((820.0 + 410.0) / k_heave),
                ("roll", "state_space"): 2 * np.pi * np.sqrt(i_xx / k_roll),
                ("roll", "fossen"): 2 * np.pi * np.sqrt((i_xx + 40.0) / k_roll)}  # fmt: skip
    for key, period in expected.items():
        assert rows[key]["natural_period_s"] == pytest.approx(period, rel=0.01), key


def test_endurance_short_run(tmp_path):
    """The endurance experiment's checks on a 2-minute run of every model (the CLI runs one hour)."""
    from usvsim.experiments import endurance

    heard: list[str] = []
    result = endurance.run(tmp_path, duration_s=120.0, progress=heard.append)
    assert result["passed"], result["summary"]
    assert len(heard) == 2 * len(endurance.MODELS) and heard[-1].startswith("model 4 of 4, voxels: PASS")
    assert "rad" in result["units"] and "FLU" in result["units"]
    assert (tmp_path / "endurance.json").exists() and (tmp_path / "endurance.png").exists()


def test_endurance_afloat_judges_the_mean_displacement():
    """A hull that a crest lifts nearly clear for a moment is afloat (the check was volume > 0 at every sample, which
    no sinking hull fails); one that displaces its whole hull, or nothing, on average is not."""
    from usvsim.experiments.endurance import _verdict

    t = np.arange(100.0)
    rows = np.column_stack([t, np.zeros(100), np.zeros(100), np.zeros(100), np.ones(100), np.ones(100)])
    rows[50, 4] = 0.02  # a crest lifts it almost out
    assert _verdict("x", rows, 1.0)["checks"]["afloat"]
    assert not _verdict("x", rows, 1.0 / 3.0)["checks"]["afloat"]  # three times its displacement: sinking
    assert not _verdict("x", rows, 5.0)["checks"]["afloat"]
