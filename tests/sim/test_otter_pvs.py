"""The Otter with Fossen's model in the full simulation (MuJoCo + mesh hydrostatics + Fossen forces) against
PVS's equations (issue [seas] item 4).

Reference numbers: Fossen's PythonVehicleSimulator (PVS) Otter equations (otter.py at c717e073, physics.md §3.1–3.2)
integrated as PVS does (forward Euler, h = 0.02 s) by `usvsim.experiments.otter.simulate` (which reproduces PVS's
straight runs of physics.md §3.5), with PVS's payload-weight double count switched off (payload_quirk=False),
120 s from rest, mean of the last 10 s; velocities at Fossen's CO, FLU. Recorded here as constants.
Finding: PVS's equations themselves are directionally unstable from about n = 65 rad/s with equal commands (a
1e-3 rad/s yaw kick grows into a 0.06 rad/s turn at 75 rad/s, 0.27 rad/s at 103.9); PVS's straight runs stay
straight only because its arithmetic is exactly symmetric. So straightness is checked at 60 rad/s, where PVS
damps a kick.
"""

from __future__ import annotations

import numpy as np
import pytest

from usvsim.config.loader import parse_scenario
from usvsim.hydro.fossen_sets import OTTER_CO_BASE_LINK
from usvsim.simulation import Simulation
from usvsim.vessels import otter

N_MAX = 103.930864  # rad/s, Fossen's n_max (T_max = 119.682 N)
# (n_left, n_right) rad/s -> PVS equations' steady u, v (m/s, at CO, FLU), r (rad/s, FLU), turning diameter 2U/|r| m
PVS_TURNS = {
    (80.0, 120.0): (2.33759, -0.23076, 0.27228, 17.2540),
    (103.930864, 51.965432): (1.82746, 0.19086, -0.28624, 12.8381),
}


def _otter(n_left: float, n_right: float) -> Simulation:
    hydro = {"type": "fossen", "parameters": "otter"}
    sim = Simulation(parse_scenario({"version": 1, "vessels": [{"name": "o", "model": "otter",
                                                                "hydrodynamics": hydro}]}, "t"))  # fmt: skip
    thrusters = sim.vessels["o"].thrusters
    thrusters["left"].command(min(n_left / N_MAX, 1.0))
    thrusters["right"].command(min(n_right / N_MAX, 1.0))
    return sim


def _at_co(sim) -> np.ndarray:
    """(u, v, r) at Fossen's CO, body FLU."""
    o = sim.vessels["o"]
    w = o.angular_velocity_body
    v = o.velocity_body + np.cross(w, np.asarray(OTTER_CO_BASE_LINK))
    return np.array([v[0], v[1], w[2]])


def test_centre_of_mass_sits_at_fossens_r_g_from_the_reference_point():
    r_g_flu = np.asarray(otter.COM) - np.asarray(OTTER_CO_BASE_LINK)
    np.testing.assert_allclose(r_g_flu, (0.153125, 0.0, 0.246875), atol=1e-8)


def test_equal_commands_run_straight_where_pvs_does():
    """n = 60 rad/s on both: a 1e-3 rad/s yaw kick dies out (PVS's equations: to 3e-8 in 60 s)."""
    sim = _otter(60.0, 60.0)
    sim.run(30.0)
    o = sim.vessels["o"]
    sim.world.teleport(0, (o.position, o.quat), np.r_[o.velocity_body, 0.0, 0.0, 1e-3])
    sim.run(40.0)
    assert abs(o.angular_velocity_body[2]) < 1e-4
    sim.close()


@pytest.mark.parametrize("command", list(PVS_TURNS))
def test_steady_turn_against_pvs_equations(command):
    """Surge, sway, yaw rate and turning diameter within 3 % (the issue's target; measured within 1 %)."""
    u_ref, v_ref, r_ref, d_ref = PVS_TURNS[command]
    sim = _otter(*command)
    sim.run(70.0)
    samples = []
    for _ in range(10):
        sim.run(1.0)
        samples.append(_at_co(sim))
    u, v, r = np.mean(samples, axis=0)
    assert u == pytest.approx(u_ref, rel=0.03)
    assert v == pytest.approx(v_ref, rel=0.03)
    assert r == pytest.approx(r_ref, rel=0.03)
    assert 2 * np.hypot(u, v) / abs(r) == pytest.approx(d_ref, rel=0.03)
    sim.close()
