"""benchmarks/bench_harbor.py's bare-MuJoCo baseline must not step the simulation's own data: bare stepping (no
buoyancy) sinks the hull, and the usvsim case timed after it then ran from that state (since the divergence guard,
it stopped with DivergenceError)."""

import importlib.util
from pathlib import Path

import numpy as np

from usvsim import Simulation

BENCH = Path(__file__).resolve().parents[2] / "benchmarks" / "bench_harbor.py"


def load_bench():
    spec = importlib.util.spec_from_file_location("bench_harbor", BENCH)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_bare_baseline_leaves_the_simulation_state_alone():
    sim = Simulation.from_scenario("harbor")
    sim.run(0.2)
    qpos, qvel, time_s = sim.data.qpos.copy(), sim.data.qvel.copy(), sim.data.time
    cases = load_bench().make_cases(sim, 100)
    cases["mujoco_only"]()
    np.testing.assert_array_equal(sim.data.qpos, qpos)
    np.testing.assert_array_equal(sim.data.qvel, qvel)
    assert sim.data.time == time_s
    cases["usvsim"]()  # the simulation then steps on from where it was
    assert sim.data.time > time_s
    sim.close()
