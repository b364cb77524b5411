"""Buoyancy and hydrodynamics models chosen per vessel, and switched at run time without artifacts."""

from __future__ import annotations

import numpy as np
import pytest

from usvsim.simulation import Simulation

SEA = {"sea": {"type": "jonswap", "hs_m": 1.0, "tp_s": 5.0, "realization": {"resolution": 64}}}
MODELS = {
    "state_space": {"type": "state_space", "X_u": 100.0, "Y_v": 100.0, "Z_w": 500.0, "K_p": 300.0, "M_q": 900.0,
                    "N_r": 800.0},
    "kerner": {"type": "kerner"},
    "fossen": {"type": "fossen", "parameters": "wamv_vrx"},
}  # fmt: skip


def scenario(scenario_of, hydro=None, buoyancy=None, model="wamv"):
    vessel = {"name": "boat", "model": model, "pose": {"position": [0.0, 0.0, 0.0], "yaw_deg": 30.0}}
    if hydro:
        vessel["hydrodynamics"] = hydro
    if buoyancy:
        vessel["buoyancy"] = buoyancy
    return scenario_of({"environment": SEA, "vessels": [vessel]})


@pytest.mark.parametrize("name", list(MODELS))
def test_each_model_rides_waves_afloat_and_upright(scenario_of, name):
    sim = Simulation(scenario(scenario_of, MODELS[name]))
    boat = sim.vessels["boat"]
    for _ in range(3000):
        boat.command(0.6, 0.2)
        sim.step()
        assert abs(boat.rpy[0]) < 0.6 and abs(boat.rpy[1]) < 0.6
    assert np.isfinite(sim.data.qvel).all() and boat.displaced_volume > 0.5 * boat.model.mass_kg / sim.rho
    assert np.linalg.norm(boat.velocity_body[:2]) > 0.3  # it moves under thrust with every model


def test_otter_with_fossen_and_voxels(scenario_of):
    sim = Simulation(scenario(scenario_of, {"type": "fossen", "parameters": "otter"}, {"type": "voxels"}, "otter"))
    sim.run(20.0)
    otter = sim.vessels["boat"]
    assert np.isfinite(sim.data.qpos).all() and abs(otter.rpy[0]) < 0.5
    assert sim.model.dof_armature[1] > 0  # Fossen's added mass integrated implicitly (sway ~ 82 kg)


def _restart_with(sc, source: Simulation) -> Simulation:
    """A fresh simulation of `sc` placed in `source`'s state and time, its models without history."""
    sim = Simulation(sc)
    sim.data.qpos[:], sim.data.qvel[:] = source.data.qpos, source.data.qvel
    sim.clock.steps, sim.clock.now_ns = source.clock.steps, source.clock.now_ns
    sim.thrusters.thrust[:], sim.thrusters.angle[:] = source.thrusters.thrust, source.thrusters.angle
    sim.world._update_kinematics()
    return sim


@pytest.mark.parametrize("first, second", [("state_space", "kerner"), ("kerner", "fossen"),
                                           ("fossen", "state_space")])  # fmt: skip
def test_switching_gives_exactly_the_new_models_force(scenario_of, first, second):
    """After a switch the applied wrench is the new model's own wrench at that state (the genuine
    difference between the models), with no transient from the switch itself, and no NaN."""
    sim = Simulation(scenario(scenario_of, MODELS[first]))
    sim.run(8.0)
    before = sim.world._xfrc.copy()
    sim.vessels["boat"].set_hydrodynamics(MODELS[second])
    reference = _restart_with(scenario(scenario_of, MODELS[second]), sim)
    reference.world._apply_marine_wrenches()
    sim.world._apply_marine_wrenches()
    np.testing.assert_allclose(sim.world._xfrc, reference.world._xfrc, rtol=1e-9, atol=1e-9)
    assert np.isfinite(sim.world._xfrc).all() and not np.allclose(before, sim.world._xfrc)
    sim.run(10.0)
    assert np.isfinite(sim.data.qvel).all()


def test_switching_buoyancy_keeps_the_weight_balance(scenario_of):
    sim = Simulation(scenario(scenario_of, buoyancy={"type": "triangles"}, model="otter"))
    sim.run(5.0)
    sim.vessels["boat"].set_buoyancy({"type": "voxels", "voxel_size_m": 0.04})
    sim.run(20.0)
    assert sim.vessels["boat"].buoyancy.type == "voxels" and np.isfinite(sim.data.qpos).all()


@pytest.mark.parametrize("first, second", [("froude_krylov", "hydrostatic"), ("hydrostatic", "froude_krylov")])
def test_switching_wave_pressure_runs_exactly_the_new_model(scenario_of, first, second):
    """A run-time switch of `wave_pressure` moves the boat as a simulation started with it (it was ignored: the
    pressure heads kept the scenario's model), and a reset restores the scenario's."""
    sims = [Simulation(scenario(scenario_of, buoyancy={"type": "triangles", "wave_pressure": w}))
            for w in (first, second, first)]  # fmt: skip
    sims[0].vessels["boat"].set_buoyancy({"type": "triangles", "wave_pressure": second})
    for sim in sims:
        sim.run(2.0)
    np.testing.assert_array_equal(sims[0].data.qpos, sims[1].data.qpos)
    assert not np.allclose(sims[0].data.qpos, sims[2].data.qpos, rtol=0, atol=1e-6)  # the models differ here
    sims[0].reset()
    sims[2].reset()
    sims[0].run(2.0)
    sims[2].run(2.0)
    np.testing.assert_array_equal(sims[0].data.qpos, sims[2].data.qpos)


def test_froude_krylov_on_a_patch_vessel_is_refused_at_run_time(scenario_of):
    vessel = {"name": "boat", "model": "wamv", "water_sampling": {"mode": "patch"}}
    sim = Simulation(scenario_of({"environment": SEA, "vessels": [vessel]}))
    before = sim.vessels["boat"].buoyancy
    with pytest.raises(ValueError, match="boat's water is sampled on a patch .* froude_krylov needs "
                                         "water_sampling.mode: direct"):  # fmt: skip
        sim.vessels["boat"].set_buoyancy({"type": "triangles", "wave_pressure": "froude_krylov"})
    assert sim.vessels["boat"].buoyancy is before
    sim.vessels["boat"].set_buoyancy({"type": "triangles", "wave_pressure": "hydrostatic"})  # allowed
    sim.run(0.5)


def test_bad_model_switch_is_a_clear_error(scenario_of):
    sim = Simulation(scenario(scenario_of))
    with pytest.raises(ValueError, match="unknown type 'kernel'; expected one of 'state_space', 'kerner', 'fossen'"):
        sim.vessels["boat"].set_hydrodynamics({"type": "kernel"})


def test_hydrostatics_beside_kerner_on_a_second_thread_gives_identical_motion(scenario_of, monkeypatch):
    """The overlapped path (hydrostatics on a worker thread while Kerner runs) changes timing, not results."""
    import usvsim.world.world as world_module

    def trajectory() -> np.ndarray:
        sc = scenario_of({
            "environment": SEA,
            "vessels": [{"name": "wamv", "model": "wamv", "hydrodynamics": {"type": "kerner"},
                         "pose": {"position": [0.0, 0.0, 0.2], "roll_deg": 5.0}}],
        })  # fmt: skip
        sim = Simulation(sc)
        sim.vessels["wamv"].command(0.6, 0.2)
        sim.run(1.0)
        sim.close()
        return sim.data.qpos.copy()

    serial = trajectory()
    monkeypatch.setattr(world_module, "OVERLAP_MIN_FACES", 0)
    assert np.array_equal(trajectory(), serial)


def test_voxel_cut_setting_reaches_the_kernel_and_volume_is_the_voxels(scenario_of):
    """`cut: false` counts whole voxels below the surface (a different, staircase volume); the vessel's
    displaced volume is the voxel model's, not the triangle integral."""
    volumes = {}
    for cut in (True, False):
        sim = Simulation(scenario(scenario_of, None, {"type": "voxels", "voxel_size_m": 0.1, "cut": cut}, "otter"))
        sim.run(1.0)  # dropped from z = 0 into the water
        voxels = sim.marine._voxels
        assert voxels.cut.tolist() == [cut]
        volumes[cut] = sim.vessels["boat"].displaced_volume
        assert volumes[cut] == pytest.approx(float(voxels._out[2][0]), rel=1e-12)
        assert volumes[cut] != pytest.approx(float(sim.hydrostatics.volume[0]), rel=1e-6)
    assert volumes[True] != pytest.approx(volumes[False], rel=1e-3)


def test_hydrostatics_split_over_two_cores_gives_identical_motion(scenario_of, monkeypatch):
    """A fleet's per-face hydrostatics split over two threads (HullSet.compute_split) changes timing, not results:
    every body's sums are its own loop, whichever thread runs it."""
    import usvsim.world.world as world_module

    def trajectory() -> np.ndarray:
        vessels = [{"name": f"b{i}", "model": "otter" if i % 2 else "wamv",
                    "pose": {"position": [12.0 * i, 0.0, 0.1], "roll_deg": 3.0 * i}} for i in range(5)]  # fmt: skip
        sim = Simulation(scenario_of({"environment": SEA, "vessels": vessels}))
        for i, boat in enumerate(sim.vessels.values()):
            boat.command(0.2 * i, 0.1)
        sim.run(1.0)
        sim.close()
        return sim.data.qpos.copy()

    serial = trajectory()
    monkeypatch.setattr(world_module, "SPLIT_MIN_FACES", 0)
    assert np.array_equal(trajectory(), serial)


@pytest.mark.parametrize("hydro", [None, MODELS["fossen"]])
def test_fused_hull_pass_gives_identical_motion(scenario_of, monkeypatch, hydro):
    """A wavy fleet's world vertices, FFT water and hydrostatics a body at a time over two threads (hydro/fused.py)
    move every body exactly as the three separate passes: with simple models (the world vertices and heights not
    written out) and with Fossen's (they are kept for the models, and equal too)."""
    import usvsim.world.world as world_module

    monkeypatch.setattr(world_module, "SPLIT_MIN_FACES", 0)  # a fleet of four splits

    def trajectory(fused: bool) -> np.ndarray:
        vessels = [{"name": f"b{i}", "model": "otter" if i % 2 and hydro is None else "wamv",
                    "pose": {"position": [12.0 * i, 0.0, 0.1], "roll_deg": 3.0 * i}} for i in range(4)]  # fmt: skip
        for v in vessels if hydro else ():
            v["hydrodynamics"] = hydro
        sim = Simulation(scenario_of({"environment": SEA, "vessels": vessels}))
        assert sim.world.marine.simple == (hydro is None)
        assert sim.world._fused_hull_pass(0.0) is not None  # this sea and these models take the fused pass
        if not fused:
            monkeypatch.setattr(sim.world, "_fused_hull_pass", lambda t: None)
        for i, boat in enumerate(sim.vessels.values()):
            boat.command(0.2 * i, 0.1)
        sim.run(1.0)
        sim.close()
        kept = [sim.world._eta, sim.world.hulls.world_buffer.ravel()] if hydro else []
        return np.concatenate([sim.data.qpos, sim.data.qvel, sim.hydrostatics.face_submerged_area, *kept])

    assert np.array_equal(trajectory(True), trajectory(False))
