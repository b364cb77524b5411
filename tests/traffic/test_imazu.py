"""Imazu encounters: the built-in files are the generator's output, the geometry classifies as the paper's
situations, and a case runs with the own ship under full physics."""

import math
from importlib import resources

import numpy as np
import pytest

from usvsim.config.loader import load_scenario
from usvsim.simulation import Simulation
from usvsim.traffic import awareness as aw
from usvsim.traffic.imazu import IMAZU, encounter_time_s, imazu_scenario, imazu_yaml


@pytest.mark.parametrize("case", range(1, 23))
def test_builtin_files_are_generated(case):
    text = (resources.files("usvsim.scenarios") / f"imazu_{case:02d}.yaml").read_text()
    assert text == imazu_yaml(case)


def nominal(case, speed=2.0):
    sc = imazu_scenario(case, speed_mps=speed)
    targets = sc["traffic"]["ships"][1:]
    pos = np.array([t["motion"]["position"] for t in targets])
    c = np.radians([t["motion"]["course_deg"] for t in targets])
    vel = np.array([t["motion"]["speed_mps"] for t in targets])[:, None] * np.stack([np.sin(c), np.cos(c)], 1)
    own_vel = np.array([0.0, speed])
    cpa, tcpa = aw.cpa_tcpa(pos, vel - own_vel)
    return aw.encounters(pos, own_vel, math.pi / 2, vel, math.pi / 2 - c, tcpa), cpa, tcpa


def test_single_target_cases_are_the_textbook_encounters():
    names = [aw.ENCOUNTER_NAMES[nominal(case)[0][0]] for case in (1, 2, 3, 4)]
    assert names == ["head_on", "crossing_give_way", "overtaking", "crossing_stand_on"]


@pytest.mark.parametrize("case", [1, 2, 5, 14, 22])
def test_targets_close_in_about_the_encounter_time(case):
    _, cpa, tcpa = nominal(case)
    np.testing.assert_allclose(tcpa, encounter_time_s(case), rtol=1e-4)  # positions rounded to 1 cm
    assert len(tcpa) == len(IMAZU[case]) and np.all((tcpa > 100) & (tcpa < 450))
    assert np.all(cpa < 0.15 * 2.0 * 300)  # close-quarters situations


def test_an_imazu_case_runs_with_the_own_ship_on_course():
    sim = Simulation(load_scenario("imazu_02"))
    sim.run(40.0)
    own = sim.vessels["own"]
    assert abs(own.position[0]) < 3.0 and own.position[1] > 40.0  # heading north under its LOS pilot
    situation = sim.traffic.situation.compute(sim)
    assert aw.ENCOUNTER_NAMES[situation["encounter"][0]] == "crossing_give_way"
    sim.close()


@pytest.mark.parametrize("case", range(1, 23))
def test_every_case_runs_and_its_cpa_tcpa_are_the_closed_form(case):
    """Each of the 22 scenarios runs; the targets are on their straight lines and the situation's CPA and TCPA
    are the closed form of the true relative state (r, w: TCPA = -r·w/|w|², CPA = |r + w TCPA|)."""
    sim = Simulation(load_scenario(f"imazu_{case:02d}"))
    sim.run(2.0)
    targets = imazu_scenario(case)["traffic"]["ships"][1:]
    s = sim.traffic.situation.compute(sim.world)
    own = sim.vessels["own"]
    own_pos, own_vel = own.position[:2], sim.world.origin_velocity(own.index)[:2]
    for j, t in enumerate(targets):
        c = math.radians(t["motion"]["course_deg"])
        vel = t["motion"]["speed_mps"] * np.array([math.sin(c), math.cos(c)])
        pos = np.array(t["motion"]["position"]) + vel * sim.time
        r, w = pos - own_pos, vel - own_vel
        tcpa = -(r @ w) / (w @ w)
        assert s["tcpa"][j] == pytest.approx(tcpa, rel=1e-9)
        assert s["cpa"][j] == pytest.approx(np.linalg.norm(r + w * tcpa), rel=1e-9, abs=1e-9)
    assert len(s["tcpa"]) == len(IMAZU[case])
    sim.close()


def test_usvsim_scenarios_lists_all_22():
    from typer.testing import CliRunner

    from usvsim.cli.app import app

    result = CliRunner().invoke(app, ["scenarios"])
    assert result.exit_code == 0
    listed = {word for line in result.output.splitlines() for word in line.split() if word.startswith("imazu_")}
    assert {f"imazu_{k:02d}" for k in range(1, 23)} <= listed


def test_the_documented_encounter_times_and_the_repeated_case():
    """docs/traffic.md: on straight tracks the closest approaches of the 22 cases fall between 134 and 498 s (own
    ship 2 m/s, encounter 300 s), and case 22 repeats case 15 (as in colav-simulator's files and TUD-RL's set). Each
    TCPA is checked by hand for case 1: 1119.43 m closing at 4 m/s."""
    times = [t for case in IMAZU for t in encounter_time_s(case)]
    assert round(min(times)) == 134 and round(max(times)) == 498
    assert encounter_time_s(1)[0] == pytest.approx(13060 * 0.2 * 300 / 700 / 4.0)
    assert IMAZU[22] == IMAZU[15] and len({IMAZU[c] for c in IMAZU}) == 21
