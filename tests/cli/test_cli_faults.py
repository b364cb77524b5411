"""User mistakes with outputs and durations, in-process (no subprocess start-up): one line, exit 2."""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

from usvsim.cli.app import app


def invoke(*args):
    return CliRunner().invoke(app, list(args))


def one_line_error(result, *words):
    assert result.exit_code == 2, result.output
    lines = [ln for ln in result.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and result.stdout == "", result.stderr
    for word in words:
        assert word in lines[0]


@pytest.mark.parametrize(("target", "words"), [("missing/run.mcap", ["does not exist"]), (".", ["is a directory"]),
                                               ("taken.mcap", ["exists", "--force"]), ("run.txt", ["ending in .mcap"]),
                                               ("run", ["ending in .mcap"])])  # fmt: skip
def test_bad_recording_targets_are_one_line(tmp_path, monkeypatch, target, words):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "taken.mcap").write_bytes(b"precious")
    one_line_error(invoke("run", "--duration", "0.1", "--record", target), *words)
    assert (tmp_path / "taken.mcap").read_bytes() == b"precious"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["taken.mcap"]  # nothing written


def test_nonfinite_duration_is_one_line():
    one_line_error(invoke("run", "--duration", "inf"), "--duration")


def test_low_physics_rate_runs_exactly_the_duration_and_force_overwrites(tmp_path):
    scenario = tmp_path / "slow.yaml"
    scenario.write_text("version: 1\nworld: {physics_rate_hz: 20}\noutputs: {recording: {clock_rate_hz: 20, "
                        "ground_truth_rate_hz: 20}}\nvessels: [{name: otter, model: otter}]\n")  # fmt: skip
    out = tmp_path / "run.mcap"
    out.write_bytes(b"old")
    result = invoke("run", str(scenario), "--duration", "1.3", "--record", str(out), "--force")
    assert result.exit_code == 0, result.output
    assert "simulated 1.30 s" in result.stdout and out.stat().st_size > 1000


EMPTY_CDR = b"\x00\x01\x00\x00\x00"  # std_msgs/msg/Empty as `ros2 topic pub --once /reset std_msgs/msg/Empty` sends it


class ResetAfterOneSecond:
    """A bridge whose peer asks for /reset once the clock has passed 1 s: the command goes through the simulation's
    command inbox exactly as one from the DDS, ROS-TCP or Foxglove bridge does."""

    def __init__(self, sim):
        self.sim, self.stats = sim, {"resets_sent": 0}
        self._unsubscribe = sim.subscribe(self._on_message)

    def _on_message(self, envelope):
        if envelope.topic == "/clock" and envelope.stamp_ns >= 1_000_000_000 and not self.stats["resets_sent"]:
            assert self.sim.commands.post_cdr("/reset", EMPTY_CDR)
            self.stats["resets_sent"] += 1

    def close(self):
        self._unsubscribe()


@pytest.mark.parametrize(("given", "seeds"), [([], [3, 4]), (["--reset-seed", "same", "--ros2"], [3, 3])])
def test_a_reset_mid_run_does_not_lengthen_the_run(tmp_path, monkeypatch, given, seeds):
    """`usvsim run --duration 3` with a /reset at t = 1 s ran 1 + 3 s: the duration counted from the new episode.
    It is the run's total simulated time: 1 s of the first episode and 2 s of the second. The reset runs the next
    seed (it replayed the run's seed: the same sea every episode) unless --reset-seed same asks for it."""
    import json

    from readers import read_with_mcap_ros2

    import usvsim.cli.bridges

    monkeypatch.setattr(usvsim.cli.bridges, "open_bridges", lambda sim, options: [ResetAfterOneSecond(sim)])
    scenario = tmp_path / "tiny.yaml"
    scenario.write_text("version: 1\nworld: {physics_rate_hz: 100}\noutputs: {recording: {clock_rate_hz: 100}}\n"
                        "vessels: [{name: otter, model: otter}]\n")  # fmt: skip
    out = tmp_path / "run.mcap"
    result = invoke("run", str(scenario), "--duration", "3", "--record", str(out), "--seed", "3", *given)
    assert result.exit_code == 0, result.output
    assert "simulated 3.00 s over 2 episodes" in result.stdout and "resets_sent 1" in result.stdout
    messages = read_with_mcap_ros2(out)
    assert [json.loads(m.data)["seed"] for t, _, m in messages if t == "/usvsim/episode"] == seeds
    clocks = [m.clock.sec + m.clock.nanosec / 1e9 for t, _, m in messages if t == "/clock"]
    restart = clocks.index(0.0, 1)
    assert clocks[restart - 1] == 1.0 and clocks[-1] == 2.0  # 100 + 200 steps
    assert len(clocks) == 101 + 201


def test_reset_seed_is_checked_and_needs_something_that_can_reset():
    one_line_error(invoke("run", "--reset-seed", "random"), "--reset-seed", "next or same")
    one_line_error(invoke("run", "--reset-seed", "same"), "--reset-seed", "--view")  # no /reset can come


def test_run_help_says_the_duration_is_the_total():
    result = invoke("run", "--help")
    assert "in all" in result.stdout and "/reset" in result.stdout


@pytest.mark.parametrize(("target", "words"), [("missing/run.mcap", ["does not exist"]),
                                               ("taken.mcap", ["exists", "--force"])])  # fmt: skip
def test_a_bad_recording_path_in_the_scenario_names_its_key(tmp_path, monkeypatch, target, words):
    """outputs.recording.path said only "directory missing does not exist": not that the scenario asked for it."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "taken.mcap").write_bytes(b"precious")
    scenario = tmp_path / "rec.yaml"
    scenario.write_text(f"version: 1\noutputs: {{recording: {{path: {target}}}}}\nvessels: [{{name: a, model: otter}}]\n")
    one_line_error(invoke("run", str(scenario), "--duration", "0.1"), "rec.yaml: outputs.recording.path: ", *words)
    assert (tmp_path / "taken.mcap").read_bytes() == b"precious"


def test_the_scenario_recording_path_is_written_and_record_overrides_it(tmp_path, monkeypatch):
    """`outputs.recording.path` was checked and then never written: `usvsim run` recorded nothing (QA)."""
    from mcap.reader import make_reader

    monkeypatch.chdir(tmp_path)
    scenario = tmp_path / "rec.yaml"
    scenario.write_text("version: 1\noutputs: {recording: {path: from_scenario.mcap}}\nvessels: [{name: a, model: otter}]\n")
    result = invoke("run", str(scenario), "--duration", "0.1")
    assert result.exit_code == 0, result.output
    with (tmp_path / "from_scenario.mcap").open("rb") as f:
        topics = {channel.topic for channel in make_reader(f).get_summary().channels.values()}
    assert {"/clock", "/a/ground_truth/odometry"} <= topics
    result = invoke("run", str(scenario), "--duration", "0.1", "--record", "given.mcap")
    assert result.exit_code == 0 and (tmp_path / "given.mcap").is_file()  # --record wins, the scenario's file stays
    assert (tmp_path / "from_scenario.mcap").stat().st_size > 0


def test_a_viewer_that_cannot_open_leaves_no_recording_behind(tmp_path, monkeypatch):
    """Without a display, `run --view --record x.mcap` failed and left an empty x.mcap: the next try said 'exists;
    pass --force'."""
    for name in ("DISPLAY", "WAYLAND_DISPLAY"):
        monkeypatch.delenv(name, raising=False)
    monkeypatch.setenv("MUJOCO_GL", "egl")  # run --view sets glfw: restored after the test
    out, scenario = tmp_path / "x.mcap", tmp_path / "tiny.yaml"
    scenario.write_text("version: 1\nvessels: [{name: a, model: otter}]\n")
    one_line_error(invoke("run", str(scenario), "--view", "--duration", "0.1", "--record", str(out)), "viewer", "display")
    assert not out.exists()


def test_a_stop_during_the_set_up_is_taken_before_the_first_step(tmp_path, monkeypatch):
    """SIGTERM while the run was still setting up (kernels compiling, DDS starting) killed the process and left a
    recording with only its header (`usvsim recover` needed); then the run stopped before its first step but left a
    recording of no step, so the next try needed --force. Now it stops before its first step, exit 143, and keeps
    no file (nothing was simulated)."""
    import signal

    import usvsim.cli.app as cli_app

    real_open = cli_app._open_run

    def open_then_terminated(*args):
        opened = real_open(*args)
        signal.raise_signal(signal.SIGTERM)  # arrives during the set-up, once the recording is open
        return opened

    monkeypatch.setattr(cli_app, "_open_run", open_then_terminated)
    out = tmp_path / "x.mcap"
    result = invoke("run", "harbor", "--duration", "5", "--record", str(out))
    assert result.exit_code == 143, result.output
    assert "stopped (SIGTERM): simulated 0.00 s" in result.stdout
    assert f"no step was taken: {out} not kept" in result.stdout and "recorded" not in result.stdout
    assert not out.exists()


def test_a_run_whose_bridge_cannot_start_leaves_no_recording_behind(tmp_path):
    """`usvsim run --record x.mcap --foxglove` with the port taken failed in one line but left an empty x.mcap:
    the next try said 'x.mcap exists; pass --force'."""
    import socket

    out, scenario = tmp_path / "x.mcap", tmp_path / "tiny.yaml"
    scenario.write_text("version: 1\nvessels: [{name: a, model: otter}]\n")
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        result = invoke("run", str(scenario), "--duration", "0.1", "--record", str(out), "--foxglove",
                        "--foxglove-port", str(taken.getsockname()[1]))  # fmt: skip
    one_line_error(result, "cannot start the Foxglove server")
    assert not out.exists()


def test_a_slow_first_step_is_told_apart_from_the_speed(tmp_path, monkeypatch):
    """A first run compiles the kernels in its first steps: "simulated 1.00 s in 7.43 s wall (0.1x real time)" read
    as the simulator's speed. A first step of 2 s or more gets a note with the speed of the other steps."""
    import time

    from usvsim.simulation import Simulation

    original, calls = Simulation.step, []

    def slow_first(self):
        if not calls:
            time.sleep(2.2)  # (a lower bound: holds on a loaded machine)
        calls.append(1)
        original(self)

    monkeypatch.setattr(Simulation, "step", slow_first)
    scenario = tmp_path / "tiny.yaml"
    scenario.write_text("version: 1\nvessels: [{name: otter, model: otter}]\n")
    result = invoke("run", str(scenario), "--duration", "0.5")
    assert result.exit_code == 0, result.output
    assert "done: simulated 0.50 s" in result.stdout
    notes = [ln for ln in result.stderr.splitlines() if "note:" in ln]
    assert len(notes) == 1 and "the first step took" in notes[0] and "the other steps ran at" in notes[0], notes
    calls.clear()  # a run of a single step (0.01 s at 100 Hz) said nothing beside its "0.0x real time"
    result = invoke("run", str(scenario), "--duration", "0.01")
    assert result.exit_code == 0, result.output
    notes = [ln for ln in result.stderr.splitlines() if "note:" in ln]
    assert len(notes) == 1 and "the first step took" in notes[0] and "other steps" not in notes[0], notes


@pytest.mark.parametrize(("path", "words"), [("out.txt", ["ending in .mcap"]), ("missing/run.mcap", ["does not exist"])])
def test_validate_checks_the_scenarios_recording_path(tmp_path, monkeypatch, path, words):
    """`usvsim validate` said OK to a recording path that `usvsim run` then refused."""
    monkeypatch.chdir(tmp_path)
    scenario = tmp_path / "s.yaml"
    vessels = "vessels: [{name: a, model: otter}]\n"
    scenario.write_text(f"version: 1\n{vessels}outputs: {{recording: {{path: {path}}}}}\n")
    one_line_error(invoke("validate", str(scenario)), "outputs.recording.path", *words)
    (tmp_path / "taken.mcap").write_bytes(b"x")
    scenario.write_text(f"version: 1\n{vessels}outputs: {{recording: {{path: taken.mcap}}}}\n")  # --force's business
    assert invoke("validate", str(scenario)).exit_code == 0
