"""The generated corpus of broken and extreme scenarios (scenario_corpus.py): no traceback, no hang, no
non-finite value accepted, warnings for set-ups that cannot work, and valid ones run."""

from __future__ import annotations

import math
import signal

import pytest
from scenario_corpus import write_corpus
from typer.testing import CliRunner

from usvsim.cli.app import app
from usvsim.core.errors import DivergenceError, UsvsimError
from usvsim.simulation import Simulation
from usvsim.world.checks import setup_warnings

HANG_GUARD_S = 120  # far above the ~0.1 s a file takes: only a hang trips it, never a busy machine


@pytest.fixture(scope="module")
def corpus(tmp_path_factory):
    return write_corpus(tmp_path_factory.mktemp("corpus"))


def _floats(value):
    if isinstance(value, float):
        yield value
    elif isinstance(value, dict):
        for item in value.values():
            yield from _floats(item)
    elif isinstance(value, list | tuple):
        for item in value:
            yield from _floats(item)


def _outcome(path) -> tuple[str, str]:
    def hang(_signum, _frame):
        raise TimeoutError(f"{path.name} took more than {HANG_GUARD_S} s")

    previous = signal.signal(signal.SIGALRM, hang)
    signal.alarm(HANG_GUARD_S)
    try:
        sim = Simulation.from_scenario(path)
    except UsvsimError as exc:
        return "error", str(exc)
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)
    try:
        assert all(math.isfinite(x) for x in _floats(sim.scenario.model_dump())), f"{path.name}: non-finite accepted"
        warnings = setup_warnings(sim.world)
        try:
            sim.run(0.2)  # a valid scenario also runs
        except DivergenceError as exc:  # bodies placed inside each other (which it warns of) may blow apart
            assert warnings, f"{path.name}: diverged without a warning: {exc}"
    finally:
        sim.close()
    return ("warn" if warnings else "ok"), "; ".join(warnings)


def test_corpus_no_traceback_no_hang_no_nonfinite(corpus):
    assert len(corpus) >= 100
    wrong = []
    for path, expected in corpus:
        got, message = _outcome(path)
        assert "\n" not in message and len(message) < 1000, f"{path.name}: error is not one short line"
        if got != expected:
            wrong.append(f"{path.name}: expected {expected}, got {got} ({message})")
    assert not wrong, "\n".join(wrong)


@pytest.mark.parametrize("name", ["alias_bomb_9", "binary", "deep_list", "latin1", "empty"])
def test_cli_validate_prints_one_line_and_exits_2(corpus, name):
    path = next(p for p, _ in corpus if p.stem == name)
    result = CliRunner().invoke(app, ["validate", str(path)])
    assert result.exit_code == 2, result.stderr
    assert len(result.stderr.strip().splitlines()) == 1 and result.stdout == ""
    assert len(result.stderr) < 600


def test_cli_validate_warns_for_a_hull_that_cannot_float(corpus):
    path = next(p for p, _ in corpus if p.stem == "heavier_than_displacement")
    result = CliRunner().invoke(app, ["validate", str(path)])
    assert result.exit_code == 0 and result.stdout.startswith("OK")
    assert "warning:" in result.stderr and "sink" in result.stderr
    coarse = next(p for p, _ in corpus if p.stem == "voxels_too_coarse")  # validated OK and sank to -27 m, silent
    result = CliRunner().invoke(app, ["validate", str(coarse)])
    assert "its voxels can displace (0 kg): it will sink (voxel_size_m 10: use smaller voxels)" in result.stderr
    strict = CliRunner().invoke(app, ["validate", "--strict", str(path)])
    assert strict.exit_code == 1 and strict.stdout.startswith("NOT OK (--strict)") and "sink" in strict.stderr
    clean = CliRunner().invoke(app, ["validate", "--strict", "harbor"])
    assert clean.exit_code == 0 and clean.stdout.startswith("OK")


def test_cli_run_says_what_validate_warns_about(corpus):
    """`usvsim run` prints validate's warnings before the run (it ran silently: QA)."""
    path = next(p for p, _ in corpus if p.stem == "heavier_than_displacement")
    result = CliRunner().invoke(app, ["run", str(path), "--duration", "0.01"])
    assert result.exit_code == 0 and "warning:" in result.stderr and "sink" in result.stderr
    clean = CliRunner().invoke(app, ["run", "harbor", "--duration", "0.01"])
    assert clean.exit_code == 0 and "warning" not in clean.stderr
