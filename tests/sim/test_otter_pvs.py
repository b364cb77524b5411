"""The Otter with Fossen's model in the full simulation (MuJoCo + mesh hydrostatics + Fossen forces) against
PVS's equations (issue [seas] item 4).

Reference numbers: made by Fossen's PythonVehicleSimulator (PVS) itself, commit c717e073, unmodified: its otter()
with a constant command, its own mainLoop.simulate (forward Euler, h = 0.02 s), 120 s from rest, mean of the last
10 s, with the payload-weight double count switched off at run time (vehicle.mp = 0 after construction; physics.md
§3.2 quirk 2); velocities at Fossen's CO, FLU. Recorded here as constants; `pvs_reference_runs.py` beside this file
says exactly how (2026-11-28). usvsim's own re-implementation (`usvsim.experiments.otter.simulate`,
payload_quirk=False) gives the same numbers to every digit shown.
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


# n rad/s on both propellers -> PVS's steady surge u (m/s at CO); straight (v = r = 0 exactly in PVS)
PVS_STRAIGHT = {51.965432: 0.771600, 60.0: 1.028645}

MODELS = ["otter", "otter_pvs"]  # the default hull with Fossen's model; the hull made to Fossen's hydrostatics
# physics.md §3.1 (PVS's formulas): metacentric heights (m), both pontoons' waterplane area (m²), draft (m)
PVS_GM_T, PVS_GM_L, PVS_WATERPLANE, DRAFT = 1.23250, 3.11126, 0.75, 0.195
# Roll released from 5° at rest (no thrust) in PVS's equations, payload double count off, integrated with RK4 at
# h = 0.002 s by an independent re-implementation of PVS's otter.py (not usvsim's code): the first damped period
# between downward zero crossings (s) and the first positive peak after the release (deg).
PVS_ROLL_PERIOD_S, PVS_ROLL_FIRST_PEAK_DEG = 0.97498, 1.1949


def _otter(n_left: float, n_right: float, model: str = "otter") -> Simulation:
    vessel = {"name": "o", "model": model}
    if model == "otter":
        vessel["hydrodynamics"] = {"type": "fossen", "parameters": "otter"}  # otter_pvs has it by default
    sim = Simulation(parse_scenario({"version": 1, "vessels": [vessel]}, "t"))
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


def _steady(sim, settle_s: float) -> np.ndarray:
    """(u, v, r) at CO, FLU, averaged over 10 s (a sample a second) after `settle_s` s, as PVS's last 10 s."""
    sim.run(settle_s)
    samples = []
    for _ in range(10):
        sim.run(1.0)
        samples.append(_at_co(sim))
    return np.mean(samples, axis=0)


def test_centre_of_mass_sits_at_fossens_r_g_from_the_reference_point():
    r_g_flu = np.asarray(otter.COM) - np.asarray(OTTER_CO_BASE_LINK)
    np.testing.assert_allclose(r_g_flu, (0.153125, 0.0, 0.246875), atol=1e-8)


@pytest.mark.parametrize("model", MODELS)
def test_equal_commands_run_straight_where_pvs_does(model):
    """n = 60 rad/s on both: a 1e-3 rad/s yaw kick dies out (PVS's equations: to 3e-8 in 60 s)."""
    sim = _otter(60.0, 60.0, model)
    sim.run(30.0)
    o = sim.vessels["o"]
    sim.world.teleport(0, (o.position, o.quat), np.r_[o.velocity_body, 0.0, 0.0, 1e-3])
    sim.run(60.0)
    assert abs(o.angular_velocity_body[2]) < 1e-7  # 4e-8 (1.2e-5 with the default hull before it was symmetric)
    sim.close()


@pytest.mark.parametrize("model", [*MODELS, "wamv"])
def test_catamaran_hulls_are_exactly_symmetric(model):
    """trimesh: the buoyancy centre on the centreline at any draft (a translated starboard pontoon put it 1e-5 m
    off and turned the Otter at 70 rad/s on equal commands, where PVS's unstable equations need a kick)."""
    trimesh = pytest.importorskip("trimesh")
    from usvsim.vessels.library import LIBRARY

    hull = LIBRARY[model][0]().hull
    mesh = trimesh.Trimesh(hull.vertices, hull.faces, process=False)
    for draft in (0.1, 0.2, 0.3):
        centre = mesh.slice_plane(plane_origin=[0, 0, draft], plane_normal=[0, 0, -1], cap=True).center_mass
        assert abs(centre[1]) < 1e-12


@pytest.mark.parametrize("model", MODELS)
@pytest.mark.parametrize("command", list(PVS_TURNS))
def test_steady_turn_against_pvs_equations(command, model):
    """Surge, sway, yaw rate and turning diameter within 3 % (the issue's target; measured within 1.2 %)."""
    u_ref, v_ref, r_ref, d_ref = PVS_TURNS[command]
    sim = _otter(*command, model=model)
    u, v, r = _steady(sim, 70.0)
    assert u == pytest.approx(u_ref, rel=0.03)
    assert v == pytest.approx(v_ref, rel=0.03)
    assert r == pytest.approx(r_ref, rel=0.03)
    assert 2 * np.hypot(u, v) / abs(r) == pytest.approx(d_ref, rel=0.03)
    sim.close()


@pytest.mark.parametrize("model", MODELS)
@pytest.mark.parametrize("n", list(PVS_STRAIGHT))
def test_steady_straight_surge_against_pvs(n, model):
    """Equal commands where PVS's equations are directionally stable (n < ~65 rad/s): straight, at PVS's surge
    within 3 % (the issue's target; measured -0.3 and -0.4 %)."""
    sim = _otter(n, n, model)
    u, v, r = _steady(sim, 60.0)
    assert u == pytest.approx(PVS_STRAIGHT[n], rel=0.03)
    assert abs(v) < 1e-6 and abs(r) < 1e-6
    sim.close()


def test_otter_pvs_hull_has_fossens_waterplane_and_metacentric_heights():
    """trimesh (not usvsim's hydrostatics) cuts the otter_pvs hull at Fossen's draft: his displacement (80 kg in
    1025 kg/m³), waterplane area, GM_T and GM_L (the default otter hull: 0.693 m², 1.100 m, 1.674 m)."""
    trimesh = pytest.importorskip("trimesh")
    from usvsim.vessels.library import LIBRARY

    model = LIBRARY["otter_pvs"][0]()
    hull = trimesh.Trimesh(model.hull.vertices, model.hull.faces, process=False)
    assert hull.is_watertight
    wet = hull.slice_plane(plane_origin=[0, 0, DRAFT], plane_normal=[0, 0, -1], cap=True)
    volume, kb = wet.volume, wet.center_mass[2]
    assert volume == pytest.approx(80.0 / 1025.0, rel=1e-9)
    np.testing.assert_allclose(wet.center_mass[:2], model.com[:2], atol=1e-9)  # floats level
    section, _ = hull.section(plane_origin=[0, 0, DRAFT], plane_normal=[0, 0, 1]).to_2D(to_2D=np.eye(4))
    area = sx = ixx = iyy = 0.0
    for polygon in section.polygons_full:  # area, first and second moments of each waterline polygon (shoelace)
        x, y = np.asarray(polygon.exterior.coords).T
        c = x[:-1] * y[1:] - x[1:] * y[:-1]
        sign = np.sign(c.sum())
        area += sign * c.sum() / 2
        sx += sign * ((x[:-1] + x[1:]) * c).sum() / 6
        ixx += sign * ((y[:-1] ** 2 + y[:-1] * y[1:] + y[1:] ** 2) * c).sum() / 12  # about the centreline
        iyy += sign * ((x[:-1] ** 2 + x[:-1] * x[1:] + x[1:] ** 2) * c).sum() / 12
    iyy -= sx**2 / area  # about the centre of flotation
    kg = model.com[2]
    assert area == pytest.approx(PVS_WATERPLANE, rel=1e-9)
    assert kb + ixx / volume - kg == pytest.approx(PVS_GM_T, rel=1e-5)
    assert kb + iyy / volume - kg == pytest.approx(PVS_GM_L, rel=1e-5)


def test_otter_pvs_floats_level_at_the_draft_and_rolls_as_pvs():
    """The full simulation: level at Fossen's draft; released from 5° of roll (about CO, at rest), the first roll
    period and peak within 1 % and 3 % of PVS's equations' (the default hull's period is 5 % longer: GM_T 1.10 m)."""
    from scipy.spatial.transform import Rotation

    sim = _otter(0.0, 0.0, "otter_pvs")
    sim.run(10.0)
    o = sim.vessels["o"]
    assert o.position[2] == pytest.approx(-DRAFT, abs=1e-6)  # base_link is the keel
    np.testing.assert_allclose(o.rpy[:2], 0.0, atol=1e-6)
    level = Rotation.from_quat(np.roll(o.quat, -1))
    co = o.position + level.apply(OTTER_CO_BASE_LINK)
    heel = Rotation.from_euler("x", 5.0, degrees=True)
    sim.world.teleport(0, (co + heel.apply(o.position - co), np.roll((heel * level).as_quat(), 1)), np.zeros(6))
    dt, roll = sim.world.clock.dt, []
    for _ in range(300):
        sim.step()
        roll.append(o.rpy[0])
    roll = np.array(roll)
    down = np.flatnonzero((roll[:-1] > 0) & (roll[1:] <= 0))
    crossings = (down + roll[down] / (roll[down] - roll[down + 1])) * dt
    peak = roll[down[0] : down[1]].max()  # the first positive peak after the release
    assert crossings[1] - crossings[0] == pytest.approx(PVS_ROLL_PERIOD_S, rel=0.01)
    assert np.degrees(peak) == pytest.approx(PVS_ROLL_FIRST_PEAK_DEG, rel=0.03)
    sim.close()
