"""User mistakes found by an outside check of every command: each is one line on stderr with exit 2, found
before any work is done (so nothing is lost), and results go to stdout. In-process where the command allows."""

from __future__ import annotations

import json
import math
import sys

import pytest
from typer.testing import CliRunner

from usvsim.cli.app import app, main
from usvsim.core.errors import UsvsimError

TINY = "version: 1\nvessels: [{name: otter, model: otter}]\n"  # builds in well under a second


def invoke(*args):
    return CliRunner().invoke(app, [str(a) for a in args])


def one_line_error(result, *words):
    assert result.exit_code == 2, result.output
    lines = [ln for ln in result.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1, result.stderr
    assert "Traceback" not in result.stderr
    for word in words:
        assert word in lines[0], lines[0]


def never(*_args, **_kw):
    raise AssertionError("the work started although the output path is unusable")


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["run", "harbor", "--duration", "-1"], ["--duration", "finite number of seconds in [0, 1e7]", "-1"]),
        (["run", "harbor", "--duration", "nan"], ["--duration", "finite number of seconds", "nan"]),  # not ">= 0"
        (["task", "station_keeping", "--trials", "0"], ["--trials"]),
        (["task", "station_keeping", "--time-limit", "inf"], ["--time-limit"]),
        (["imazu", "23"], ["case", "22"]),
        (["imazu", "3", "--speed", "inf"], ["--speed"]),
        (["dataset", "buoy_field", "--frames", "0"], ["--frames"]),
        (["run", "--no-such-option"], ["--no-such-option"]),
        (["no-such-command"], ["no-such-command"]),
        (["demo", "navigate", "--max-time", "-5"], ["--max-time"]),  # was an IndexError from the metrics
        (["task", "station_keeping", "--ros2", "--domain-id", "999"], ["--domain-id", "232"]),  # DDS traceback
    ],
)
def test_usage_mistakes_are_one_line_from_the_entry_point(monkeypatch, capsys, args, words):
    """`usvsim` (the console script) prints click's usage errors as one line, not a usage block and a panel."""
    monkeypatch.setattr(sys, "argv", ["usvsim", *args])
    with pytest.raises(SystemExit) as exit_info:
        main()
    captured = capsys.readouterr()
    assert exit_info.value.code == 2
    lines = [ln for ln in captured.err.splitlines() if ln.strip()]
    assert len(lines) == 1 and captured.out == "", captured.err
    assert lines[0].startswith("usvsim: error: ")
    for word in words:
        assert word in lines[0], lines[0]


def test_entry_point_exit_codes_for_help_and_success(monkeypatch, capsys):
    monkeypatch.setattr(sys, "argv", ["usvsim", "run", "--help"])
    with pytest.raises(SystemExit) as exit_info:
        main()
    assert exit_info.value.code == 0 and "--duration" in capsys.readouterr().out
    monkeypatch.setattr(sys, "argv", ["usvsim", "imazu", "3"])
    with pytest.raises(SystemExit) as exit_info:
        main()
    assert exit_info.value.code == 0 and "name: imazu_03" in capsys.readouterr().out


def test_task_report_path_is_checked_before_the_trials(tmp_path, monkeypatch):
    import usvsim.tasks.solutions

    monkeypatch.setattr(usvsim.tasks.solutions, "run_trial", never)
    (tmp_path / "file").write_text("x")
    one_line_error(
        invoke("task", "station_keeping", "--report", tmp_path / "file" / "r.json"), "cannot create"
    )
    one_line_error(invoke("task", "station_keeping", "--report", tmp_path), "is a directory")


def test_task_report_that_cannot_be_written_at_the_end_goes_to_stdout(tmp_path, monkeypatch):
    import usvsim.tasks.solutions

    def trial(name, difficulty, seed, timing, after_step=None):
        return {"seed": seed, "score": 1.5, "num_collisions": 0, "sim_time_s": 1.0, "wall_time_s": 0.1,
                "higher_is_better": False}  # fmt: skip

    monkeypatch.setattr(usvsim.tasks.solutions, "run_trial", trial)
    report = tmp_path / "r.json"
    monkeypatch.setattr(type(report), "write_text", lambda self, text: (_ for _ in ()).throw(OSError(28, "No space left on device")))  # fmt: skip
    result = invoke("task", "station_keeping", "--report", report)
    one_line_error(result, "No space left", "stdout")
    assert '"mean_score": 1.5' in result.stdout  # nothing lost


def test_sweep_out_path_is_checked_before_the_runs(tmp_path, monkeypatch):
    import usvsim.batch

    monkeypatch.setattr(usvsim.batch, "run", never)
    spec = tmp_path / "s.yaml"
    spec.write_text("task: station_keeping\nseeds: [0]\ntime_limit_s: 1\n")
    (tmp_path / "file").write_text("x")
    one_line_error(invoke("sweep", spec, "--out", tmp_path / "file" / "s.jsonl"), "cannot create")


def test_experiment_out_that_is_a_file_is_one_line(tmp_path):
    (tmp_path / "file").write_text("x")
    one_line_error(invoke("experiment", "sphere", "--out", tmp_path / "file"), "is a file")


def test_imazu_rejects_unknown_models_and_bad_out(tmp_path):
    one_line_error(invoke("imazu", "5", "--model", "nosuch"), "nosuch", "wamv")
    one_line_error(invoke("imazu", "5", "--out", tmp_path), "is a directory")
    (tmp_path / "file").write_text("x")
    one_line_error(invoke("imazu", "5", "--out", tmp_path / "file" / "i.yaml"), "cannot create")
    result = invoke("imazu", "5", "--model", "otter", "--out", tmp_path / "i.yaml")
    assert result.exit_code == 0 and "model: otter" in (tmp_path / "i.yaml").read_text()


def test_imazu_refuses_options_that_make_a_scenario_that_cannot_run(tmp_path):
    """--speed 50 --encounter 1e6 wrote a file whose ships start 50,000 km out, which `usvsim run` then refused."""
    out = tmp_path / "far.yaml"
    one_line_error(invoke("imazu", "5", "--speed", "50", "--encounter", "1e6", "--out", out), "--speed", "--encounter")
    assert not out.exists()
    result = invoke("imazu", "5", "--speed", "5", "--encounter", "600", "--out", out)
    assert result.exit_code == 0 and out.exists()


@pytest.mark.parametrize("option", ["--speed", "--encounter"])
def test_imazu_nan_is_one_clear_line(option):
    """`usvsim imazu 1 --speed nan` said "Input should be less than or equal to 50" (NaN is no number at all)."""
    one_line_error(invoke("imazu", "1", option, "nan"), option, "finite number", "got nan")


def test_imazu_warns_of_a_speed_above_the_vessels_top_speed(tmp_path):
    """An Otter asked for 5 m/s (its velocity controller tops out at 3.09 m/s surge, thrusters at full ahead
    against its damping) was written without a word and then sailed slower than the encounter assumed."""
    result = invoke("imazu", "1", "--model", "otter", "--speed", "5", "--out", tmp_path / "fast.yaml")
    assert result.exit_code == 0 and (tmp_path / "fast.yaml").exists()
    lines = [ln for ln in result.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and "warning" in lines[0] and "otter's top speed, 3.09 m/s" in lines[0], result.stderr
    within = invoke("imazu", "1", "--model", "otter", "--speed", "3", "--out", tmp_path / "ok.yaml")
    assert within.exit_code == 0 and "warning" not in within.stderr


def test_map_prints_the_file_it_writes_and_rejects_unknown_formats(tmp_path):
    scenario = tmp_path / "tiny.yaml"
    scenario.write_text(TINY)
    one_line_error(invoke("map", scenario, "--out", tmp_path / "m.txt"), "unknown image format", ".txt")
    result = invoke("map", scenario, "--out", tmp_path / "plan")  # matplotlib adds .png
    assert result.exit_code == 0, result.output
    assert (
        result.stdout.strip() == str(tmp_path / "plan.png") and (tmp_path / "plan.png").stat().st_size > 1000
    )


def test_recover_refuses_a_file_that_is_not_mcap_and_writes_nothing(tmp_path):
    junk, empty = tmp_path / "junk.mcap", tmp_path / "empty.mcap"
    junk.write_text("this is not a recording\n")
    empty.write_bytes(b"")
    one_line_error(invoke("recover", junk), "not an MCAP recording")
    one_line_error(invoke("recover", empty), "is empty")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["empty.mcap", "junk.mcap"]


def test_recover_refuses_an_output_hard_linked_to_its_input(tmp_path):
    """--force over a hard link to the input truncated the input itself (QA: a whole recording lost)."""
    from usvsim.io.mcap_recover import MCAP_MAGIC

    source, link = tmp_path / "run.mcap", tmp_path / "link.mcap"
    source.write_bytes(MCAP_MAGIC + bytes(range(256)) * 40)  # (the refusal comes before any reading)
    before = source.read_bytes()
    link.hardlink_to(source)
    one_line_error(invoke("recover", source, "--out", link, "--force"), "choose an output other than")
    assert source.read_bytes() == before


def test_recover_still_takes_a_file_cut_inside_its_magic(tmp_path):
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(b"\x89MCA")  # kill -9 after 4 bytes
    result = invoke("recover", cut)
    assert result.exit_code == 0 and "recovered 0 messages" in result.stdout


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["--resolution", "0x0"], ["--resolution", "8-4096"]),
        (["--resolution", "-64x48"], ["--resolution"]),
        (["--splits", "nan,0,0"], ["splits"]),
        (["--min-visible-fraction", "nan"], ["--min-visible-fraction"]),
    ],
)
def test_dataset_bad_numbers_are_one_line(tmp_path, args, words):
    one_line_error(invoke("dataset", "buoy_field", "--frames", "1", "--out", tmp_path / "ds", *args), *words)
    assert not (tmp_path / "ds").exists()


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["no_such_scenario"], ["no_such_scenario", "built-in"]),
        (["buoy_field", "--randomize", "no_such_preset"], ["no_such_preset"]),
    ],
)
def test_dataset_bad_scenario_or_randomization_makes_no_folder(tmp_path, args, words):
    one_line_error(invoke("dataset", *args, "--frames", "1", "--out", tmp_path / "ds"), *words)
    assert not (tmp_path / "ds").exists()


def test_dataset_spec_rejects_nan_splits(tmp_path):
    from usvsim.datasets.generate import DatasetSpec

    with pytest.raises(UsvsimError, match="splits"):
        DatasetSpec("buoy_field", 1, tmp_path, splits=(float("nan"), 0.0, 0.0))


def test_dataset_out_under_a_file_is_one_line_and_the_result_line_is_on_stdout(tmp_path):
    (tmp_path / "file").write_text("x")
    one_line_error(
        invoke("dataset", "buoy_field", "--frames", "1", "--out", tmp_path / "file" / "ds"), "cannot create"
    )
    out = tmp_path / "ds"
    result = invoke(
        "dataset", "buoy_field", "--frames", "1", "--resolution", "64x48", "--format", "coco", "--out", out
    )
    assert result.exit_code == 0, result.output
    assert result.stdout.strip() == f"wrote 1 frame to {out}"
    coco = json.loads(next((out / "annotations").glob("*.json")).read_text())
    assert "images" in coco


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["--goals", "nan,0"], ["--goals"]),  # was accepted and drove nowhere
        # was accepted: no path was ever planned to it, the boat stayed put until --max-time, metrics all FAIL
        (["--goals", "10,0;1e9,5"], ["goal 1e+09,5 is outside the map", "objects + 10 m"]),
    ],
)
def test_navigate_bad_numbers_are_one_line(tmp_path, args, words):
    one_line_error(invoke("demo", "navigate", "--out", tmp_path / "nav", *args), *words)
    assert not (tmp_path / "nav").exists()


@pytest.mark.parametrize(
    ("scenario", "words"),
    [
        ("no_such_scenario", ["no_such_scenario", "built-in"]),
        ("harbor", ["harbor", "no default goals"]),  # a scenario the demo has no goals for
    ],
)
def test_navigate_bad_scenario_makes_no_folder(tmp_path, scenario, words):
    one_line_error(invoke("demo", "navigate", scenario, "--out", tmp_path / "nav"), *words)
    assert not (tmp_path / "nav").exists()
    with_goals = invoke("demo", "navigate", "harbor", "--goals", "10,0", "--out", tmp_path / "nav")
    one_line_error(with_goals, "controller", "lidar")  # harbor's vessels cannot navigate
    assert not (tmp_path / "nav").exists()


def test_navigate_out_under_a_file_is_one_line(tmp_path):
    (tmp_path / "file").write_text("x")
    one_line_error(invoke("demo", "navigate", "--out", tmp_path / "file" / "nav"), "cannot create")


@pytest.mark.parametrize(
    "args",
    [
        ["run", "harbor", "--duration", "0.1", "--seed", "-1"],
        ["task", "station_keeping", "--seed", "-1"],
        ["dataset", "buoy_field", "--seed", "-1"],
        ["map", "wayfinding", "--task", "--seed", "-1"],
        ["demo", "navigate", "--seed", "-1"],
    ],
)
def test_negative_seeds_are_one_line_from_the_entry_point(monkeypatch, capsys, args):
    """numpy's SeedSequence refuses them with a ValueError; was a traceback from every command."""
    monkeypatch.setattr(sys, "argv", ["usvsim", *args])
    with pytest.raises(SystemExit) as exit_info:
        main()
    lines = [ln for ln in capsys.readouterr().err.splitlines() if ln.strip()]
    assert exit_info.value.code == 2 and len(lines) == 1 and "--seed" in lines[0], lines


def test_a_negative_seed_in_python_is_a_usvsim_error_and_changes_nothing():
    from usvsim.simulation import Simulation

    with pytest.raises(UsvsimError, match="non-negative"):
        Simulation.from_scenario("harbor", seed=-1)
    sim = Simulation.from_scenario("harbor", seed=5)
    with pytest.raises(UsvsimError, match="non-negative"):
        sim.reset(seed=-3)
    assert sim.world.seed == 5
    sim.reset()  # the seed kept is still usable
    assert sim.world.seed == 5
    sim.close()


def test_the_traffic_report_of_a_run_is_on_stdout(tmp_path):
    """Results on stdout, progress on stderr: the CPA table was printed to stderr."""
    scenario = tmp_path / "imazu.yaml"
    assert invoke("imazu", "2", "--out", scenario).exit_code == 0
    result = invoke("run", scenario, "--duration", "1")
    assert result.exit_code == 0, result.output
    assert "min CPA (m)" in result.stdout and "target_1" in result.stdout
    assert "CPA" not in result.stderr


def test_the_traffic_report_counts_a_cpa_only_within_the_tcpa_limit(tmp_path):
    """A ship stopped 200 m off the drifting WAM-V: the relative velocity is mm/s, the CPA ~0 m hours away; the
    report said 'min predicted CPA 0.4 m'. Now a CPA counts only with 0 <= TCPA <= tcpa_limit_s (ARPA's alarm
    window): '-' for it, its range at the end ~200 m. A ship crossing 30 m ahead of it in 20 s is counted."""
    scenario = tmp_path / "still.yaml"
    scenario.write_text(
        "version: 1\nvessels:\n  - {name: wamv, model: wamv}\ntraffic:\n  ships:\n"
        "    - name: still\n      mmsi: 257000009\n      motion:\n        type: route\n        waypoints:\n"
        "          - {position: [200, 0], speed_mps: 0}\n          - {position: [0, 0], speed_mps: 0}\n"
        "    - name: crosser\n      mmsi: 257000010\n"
        "      motion: {type: constant, position: [100, 30], course_deg: 270, speed_mps: 5}\n"
    )
    result = invoke("run", scenario, "--duration", "10")
    assert result.exit_code == 0, result.output
    rows = {line.split()[0]: line.split() for line in result.stdout.splitlines() if line.split()}
    assert rows["target"] == ["target", "min", "dist", "(m)", "at", "t", "(s)", "min", "CPA", "(m)", "at", "TCPA",
                              "(s)", "range", "(m)", "TCPA", "(s)"]  # fmt: skip
    _, min_dist, _, min_cpa, tcpa_at, range_end, tcpa_end = rows["still"]
    assert (min_cpa, tcpa_at) == ("-", "-")
    assert tcpa_end in ("steady", "opening") or float(tcpa_end) > 1200.0  # the hull settling: µm/s either way
    assert float(min_dist) == pytest.approx(200.0, abs=1.0) and float(range_end) == pytest.approx(200.0, abs=1.0)
    _, _, _, min_cpa, tcpa_at, range_end, tcpa_end = rows["crosser"]
    assert float(min_cpa) == pytest.approx(30.0, abs=1.0) and 0.0 <= float(tcpa_at) <= 1200.0
    assert float(range_end) == pytest.approx(math.hypot(50.0, 30.0), abs=1.0)  # 10 s later: 50 m east, 30 m north
    assert float(tcpa_end) == pytest.approx(10.0, abs=0.5)
    assert "0 <= TCPA <= 1200 s" in result.stdout


def test_errors_found_under_a_progress_bar_are_still_one_line(tmp_path):
    """The bar of `dataset` and `sweep` left a '0/1' line above the error."""
    one_line_error(
        invoke("dataset", "no_such_scenario", "--frames", "1", "--out", tmp_path / "ds"), "no_such_scenario"
    )
    spec = tmp_path / "s.yaml"
    spec.write_text("task: station_keeping\nseeds: [0]\ntime_limit_s: 1\n")
    one_line_error(invoke("sweep", spec, "--backend", "nosuch", "--out", tmp_path / "s.jsonl"), "backend")


@pytest.mark.parametrize(
    ("text", "words"),
    [
        (
            "task: station_keepin\n",
            ["task", "station_keepin", "station_keeping"],
        ),  # was a KeyError in a worker
        ("seeds: [-1]\n", ["seeds", "non-negative"]),  # was numpy's ValueError
        ("seeds: {start: -5, count: 2}\n", ["seeds"]),
        ("difficulty: [0, 7]\n", ["difficulty", "7"]),
        (
            "grid: {hold: {position_gain: [0.3]}}\n",
            ["grid.hold", "position_gain_1ps"],
        ),  # was a ValidationError
        ("taks: station_keeping\n", ["taks", "did you mean 'task'"]),
        ("grid: {mass: [200]}\n", ["grid.mass", "did you mean 'mass_kg'"]),
        ("time_limit_s: 1.0e9\n", ["time_limit_s"]),
        ("- 1\n", ["is not a mapping", "task, seeds"]),
        ("", ["is empty", "a sweep file is a YAML mapping"]),
        ("seeds: []\n", ["seeds", "at least one"]),  # no run: a ZeroDivisionError traceback after the sweep
        ("task: []\n", ["task", "at least one"]),
        ("difficulty: []\n", ["difficulty", "at least one"]),
        ("grid: {mass_kg: []}\n", ["grid.mass_kg: give at least one"]),  # was 0 runs, exit status 0
        ("grid: {hold: {position_gain_1ps: []}}\n", ["grid.hold.position_gain_1ps: give at least one"]),
        # was "seeds.list[int]: Input should be a valid list" (the list branch of the union)
        ("seeds: {start: 0, count: -2}\n", ["seeds.count: Input should be greater than or equal to 1"]),
        ("task: wayfinding\ntask: station_keeping\n", ["line 2", "task", "twice"]),  # ran the second one only
        ("task: [\n", ["not valid YAML"]),  # was the parser's several-line message
    ],
)
def test_sweep_spec_mistakes_are_one_line_before_any_run(tmp_path, monkeypatch, text, words):
    import usvsim.batch

    monkeypatch.setattr(usvsim.batch, "run", never)
    spec = tmp_path / "s.yaml"
    spec.write_text(text)
    result = invoke("sweep", spec, "--out", tmp_path / "s.jsonl")
    one_line_error(result, *words)
    assert ": :" not in result.stderr


@pytest.mark.parametrize("option", ["--screenshot", "--video"])
def test_viewer_outputs_without_the_viewer_are_one_line(tmp_path, option):
    """They were ignored silently: the run finished with exit 0 and no file."""
    one_line_error(invoke("run", "harbor", "--duration", "0.1", option, tmp_path / "a.png"), option, "--view")


def test_viewer_outputs_are_checked_before_the_window_opens(tmp_path):
    """An unwritable --screenshot failed only when the viewer closed, after the whole run."""
    (tmp_path / "file").write_text("x")
    result = invoke(
        "run", "harbor", "--view", "--duration", "0.1", "--screenshot", tmp_path / "file" / "a.png"
    )
    one_line_error(result, "cannot create")


def test_a_directory_given_as_scenario_says_so(tmp_path):
    one_line_error(invoke("validate", tmp_path), "a directory")


def test_task_record_with_several_trials_keeps_every_trial(tmp_path):
    """`usvsim task --trials 2 --record r.mcap` wrote each trial to the same file: the second replaced the
    first (the MCAP held 1 s of /clock for 2 s simulated). Now r_trial0.mcap and r_trial1.mcap, named in the
    report, and both checked before the first trial."""
    from mcap.reader import make_reader

    record, report = tmp_path / "r.mcap", tmp_path / "r.json"
    result = invoke("task", "station_keeping", "--time-limit", "1", "--trials", "2", "--record", record,
                    "--report", report)  # fmt: skip
    assert result.exit_code == 0, result.output
    trials = json.loads(report.read_text())["trials"]
    for k, trial in enumerate(trials):
        path = tmp_path / f"r_trial{k}.mcap"
        assert trial["recording"] == str(path) and trial["seed"] == k
        with path.open("rb") as f:
            clocks = sum(1 for _ in make_reader(f).iter_messages(topics=["/clock"]))
        assert clocks == 101  # 0 to 1 s at the 100 Hz clock
    assert not record.exists()
    again = invoke("task", "station_keeping", "--time-limit", "1", "--trials", "2", "--record", record,
                   "--report", report)  # fmt: skip
    one_line_error(again, "r_trial0.mcap exists", "--force")


def test_task_record_is_never_overwritten_without_force_and_is_checked_first(tmp_path, monkeypatch):
    """`usvsim task --record` replaced an existing recording silently, and an unwritable one was a traceback."""
    import usvsim.tasks.live

    monkeypatch.setattr(usvsim.tasks.live, "run_live", never)
    taken = tmp_path / "taken.mcap"
    taken.write_bytes(b"precious")
    report = tmp_path / "r.json"
    one_line_error(
        invoke("task", "station_keeping", "--record", taken, "--report", report), "exists", "--force"
    )
    assert taken.read_bytes() == b"precious"
    one_line_error(invoke("task", "station_keeping", "--record", tmp_path / "no" / "r.mcap", "--report", report),
                   "does not exist")  # fmt: skip


def test_python_dash_m_usvsim_is_the_command():
    """`python -m usvsim` said "'usvsim' is a package and cannot be directly executed"."""
    import subprocess

    result = subprocess.run(
        [sys.executable, "-m", "usvsim", "imazu", "1"], capture_output=True, text=True, timeout=120
    )
    assert result.returncode == 0 and "name: imazu_01" in result.stdout, result.stderr


@pytest.mark.parametrize(
    ("physics_hz", "latency", "nearest"),
    [(100, 0.015, ("0.01", "0.02")), (100, 0.004, ("0", "0.01")), (128, 0.01, ("0.0078125", "0.015625")),
     (1000, 1.0005, ("1", "1.001"))],
)
def test_a_latency_that_is_not_whole_steps_is_one_line_naming_the_nearest_valid_ones(tmp_path, physics_hz, latency,
                                                                                      nearest):  # fmt: skip
    """It was rounded half-to-even without a word (0.015 s at a 10 ms step published after 20 ms); now validate and
    run refuse it like a rate that is not whole steps, and each value suggested validates."""
    path = tmp_path / "lat.yaml"

    def scenario(value) -> str:
        return (f"version: 1\nworld: {{physics_rate_hz: {physics_hz}}}\noutputs: {{recording: {{clock_rate_hz: "
                f"{physics_hz / 4}, ground_truth_rate_hz: {physics_hz / 4}}}}}\nvessels: [{{name: otter, model: otter, "
                f"sensors: [{{type: imu, name: imu, rate_hz: {physics_hz / 4}}}, {{type: gnss, name: gps, rate_hz: 1, "
                f"latency_s: {value}}}]}}]\n")  # fmt: skip

    path.write_text(scenario(latency))
    step_ms = f"{1000 / physics_hz:g} ms"
    words = ["vessels[0].sensors[1].latency_s", str(latency), step_ms, f"{nearest[0]} or {nearest[1]} s"]
    one_line_error(invoke("validate", path), *words)
    one_line_error(invoke("run", path, "--duration", "0.1"), *words)
    for value in nearest:
        path.write_text(scenario(value))
        result = invoke("validate", path)
        assert result.exit_code == 0, result.output


@pytest.mark.parametrize(
    ("geo", "words"),
    [
        ("{land: {file: coast.geojson}}", ["geo.land.file", "'coast.geojson' not found", "scenario file's folder",
                                           "geospatial files there: quays.geojson"]),
        ("{bathymetry: {file: depth.tif}}", ["geo.bathymetry.file", "'depth.tif' not found"]),
        ("{structures: [{file: quays.geojson}, {file: piers.gpkg}]}", ["geo.structures[1].file", "'piers.gpkg'"]),
        ("{marks: [{file: charts/marks.geojson}]}", ["geo.marks[0].file", "charts does not exist"]),
        ("{land: {file: charts}}", ["geo.land.file", "is a directory"]),
    ],
)
def test_a_missing_geo_file_names_its_key_and_what_is_there(tmp_path, geo, words):
    """It said only `/abs/path/coast.geojson: no such file`: not which key, nor where relative paths start."""
    (tmp_path / "quays.geojson").write_text('{"type": "FeatureCollection", "features": []}')
    if "file: charts}" in geo:
        (tmp_path / "charts").mkdir()
    path = tmp_path / "place.yaml"
    path.write_text(f"version: 1\ngeo: {geo}\nvessels: [{{name: otter, model: otter}}]\n")
    one_line_error(invoke("validate", path), str(path), *words)
    one_line_error(invoke("run", path, "--duration", "0.1"), str(path), *words)


@pytest.mark.parametrize(
    ("entry", "words"),
    [
        ("vessels: [{name: otter, model: otter, sensors: [{name: imu, rate_hz: 50}]}]",
         ["vessels[0].sensors[0].type", "missing", "'imu'", "camera, detections, gnss, ground_truth, imu, lidar"]),
        ("objects: [{name: b1, position: [5, 0, 0]}]", ["objects[0].type", "missing", "buoy", "dock", "pier"]),
        ("vessels: [{name: otter, model: otter, controller: {rate_hz: 10}}]",
         ["vessels[0].controller.type", "missing", "station_keeping, velocity"]),
    ],
)
def test_an_entry_without_its_type_says_which_types_there_are(tmp_path, entry, words):
    """It said "vessels[0].sensors[0]: Unable to extract tag using discriminator 'type'"."""
    path = tmp_path / "untyped.yaml"
    path.write_text(f"version: 1\n{entry}\n")
    one_line_error(invoke("validate", path), *words)
    one_line_error(invoke("run", path, "--duration", "0.1"), *words)
    assert "discriminator" not in invoke("validate", path).stderr


@pytest.mark.parametrize("value", ["abc", "999", "-1"])
@pytest.mark.parametrize("command", [["run", "harbor", "--duration", "0.1", "--ros2"],
                                     ["task", "station_keeping", "--ros2", "--time-limit", "1"]])  # fmt: skip
def test_a_bad_ros_domain_id_variable_is_one_line(tmp_path, monkeypatch, command, value):
    """$ROS_DOMAIN_ID=abc said "invalid literal for int() with base 10: 'abc'"; 999 was a DDS_RETCODE_ERROR
    traceback from Cyclone (its ports end at 232)."""
    pytest.importorskip("cyclonedds")
    monkeypatch.setenv("ROS_DOMAIN_ID", value)
    extra = ["--report", tmp_path / "r.json"] if command[0] == "task" else []
    one_line_error(invoke(*command, *extra), "$ROS_DOMAIN_ID", "0 to 232", repr(value), "--domain-id")


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ("vessels: {name: a, model: otter}\n", ["vessels: should be a list", "got a mapping of 'name', 'model'"]),
        ("vessels: [{name: a, model: otter, sensors: [imu]}]\n",
         ["vessels[0].sensors[0]: should be a mapping", "got the text 'imu'"]),
        ("vessels: [{name: a, model: otter, sensors: [null]}]\n", ["sensors[0]: should be a mapping", "null"]),
        ("world: 5\n", ["world: should be a mapping", "got a number 5"]),
        ("vessels: [{name: a, model: otter, pose: {position: 3}}]\n",
         ["pose.position: should be a list ([a, b], or one '- ' line", "got a number 3"]),
    ],
)
def test_a_list_or_mapping_in_the_wrong_place_is_said_in_yaml_words(tmp_path, text, words):
    """pydantic's words were shown: "Input should be a valid tuple (got <dict of 2 items>)", "a valid dictionary or
    object to extract fields from"; and the console's markup ate any [word] of a message (here "[a, b]")."""
    path = tmp_path / "shape.yaml"
    path.write_text("version: 1\n" + text)
    one_line_error(invoke("validate", path), *words)
    assert "tuple" not in invoke("validate", path).stderr


def test_brackets_in_an_error_are_printed_as_they_are(tmp_path):
    """A path or value with [letters] lost them to the console's markup: 'runs[ab].yaml' was printed 'runs.yaml'."""
    one_line_error(invoke("validate", tmp_path / "runs[ab].yaml"), "runs[ab].yaml", "no such scenario file")
    one_line_error(invoke("dataset", tmp_path / "runs[ab].yaml", "--out", tmp_path / "ds"), "runs[ab].yaml")


def test_a_look_range_past_a_keys_bounds_is_refused_before_any_frame(tmp_path):
    """uniform: [-50, 100] on fog.visibility_m (> 0) passed the check of one draw and failed with a traceback
    at the first frame that drew a negative value, leaving frames without annotations or dataset.json."""
    rnd = tmp_path / "rnd.yaml"
    rnd.write_text("version: 1\nlook: {fog.visibility_m: {uniform: [-50, 100]}}\n")
    result = invoke("dataset", "buoy_field", "--frames", "1", "--randomize", rnd, "--out", tmp_path / "ds")
    one_line_error(result, f"randomization {rnd}", "look.fog.visibility_m", "greater than 0, got -50")
    assert not list((tmp_path / "ds").glob("*"))  # no frame written


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ("environment: [\n", ["line 2", "not valid YAML"]),  # was "while parsing a flow node"
        ("- 1\n", ["a randomization file is a mapping of version, per"]),  # was ": : Input should be a valid dict"
        ("perr: frame\n", ["perr: unknown key", "did you mean 'per'"]),
        ("scene: {buoy_offset: {normal: [0, 2]}}\n", ["scene: unknown key 'buoy_offset'", "'buoy_offset_m'"]),
        ("environment: {sea.hs_m: {uniform: [1]}}\n",  # was "environment.sea.hs_m.bool: Input should be a valid boolean"
         ["environment.sea.hs_m: {'uniform': [1]} is not {uniform: [low, high]}"]),
        ("look: {sun.azimuth_dg: 30}\n", ["look.sun.azimuth_dg: unknown key", "rendering"]),  # was a tuple repr
        ("environment: {sea.hs_m: 1.0}\n",  # the scenario has no sea: it blamed the scenario file for sea.type
         ["randomization", "environment", "the drawn values make the scenario's environment.sea.type invalid"]),
        # these three were a traceback ('ValueError: high - low < 0', 'scale < 0') or silently all one value
        ("look: {sun.elevation_deg: {uniform: [60, 5]}}\n", ["look.sun.elevation_deg: uniform: low 60 is above high 5"]),
        ("scene: {buoy_offset_m: {normal: [0, -1]}}\n", ["scene.buoy_offset_m: normal: the stddev -1 is negative"]),
        ("look: {sun.elevation_deg: {normal: [10, 5], clip: [20, 0]}}\n",
         ["look.sun.elevation_deg: clip: low 20 is above high 0"]),
    ],
)
def test_randomization_file_mistakes_are_one_line_in_its_words(tmp_path, text, words):
    scenario, rnd = tmp_path / "cam.yaml", tmp_path / "rnd.yaml"
    scenario.write_text("version: 1\nvessels: [{name: a, model: otter, sensors: [{type: camera, name: c, width: 64, "
                        "height: 48}]}]\n")  # fmt: skip
    rnd.write_text(text)
    result = invoke("dataset", scenario, "--frames", "1", "--randomize", rnd, "--out", tmp_path / "ds")
    one_line_error(result, f"randomization {rnd}", *words)
    assert "[key]" not in result.stderr and "Input should" not in result.stderr


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ("objects: [{type: mesh, name: rock, mesh: {file: rock.stl}}]\n",  # was "objects[0].mesh.file: Field required"
         ["objects[0].file: missing"]),
        ("vessels: [{name: a}]\n", ["vessels[0].model: missing"]),
        ("objects: [{type: mesh, name: rock, file: rock.stl, mesh: 1}]\n", ["objects[0].mesh: unknown key"]),
    ],
)
def test_a_missing_key_is_named_where_it_belongs(tmp_path, text, words):
    path = tmp_path / "missing.yaml"
    path.write_text("version: 1\n" + text)
    one_line_error(invoke("validate", path), *words)
    assert "Field required" not in invoke("validate", path).stderr


def test_a_dataset_is_not_written_over_another_without_force(tmp_path):
    """Written over, the first set's frames beyond the second's count stayed beside annotations that no longer
    listed them (4 frames then 2: 4 images on disk, 2 in the COCO files), and nothing said so."""
    out = tmp_path / "ds"
    args = ["dataset", "buoy_field", "--resolution", "64x48", "--out", out]
    assert invoke(*args, "--frames", "4").exit_code == 0
    (out / "notes.txt").write_text("mine")
    one_line_error(invoke(*args, "--frames", "2", "--seed", "3"), str(out), "already holds a data set", "--force")
    assert len(list((out / "images").rglob("*.png"))) == 4  # untouched
    result = invoke(*args, "--frames", "2", "--seed", "3", "--force")
    assert result.exit_code == 0, result.output
    images = sorted(p.name for p in (out / "images").rglob("*.png"))
    coco = [img for f in (out / "annotations").glob("*.json") for img in json.loads(f.read_text())["images"]]
    assert len(images) == 2 and sorted(img["file_name"].split("/")[1] for img in coco) == images
    assert (out / "notes.txt").read_text() == "mine"  # --force removes the data set's files only


def test_a_missing_sweep_file_and_a_mesh_that_is_a_folder_say_so(tmp_path):
    one_line_error(invoke("sweep", tmp_path / "nosuch.yaml"), "nosuch.yaml: no such sweep file")  # was [Errno 2]
    one_line_error(invoke("sweep", tmp_path), "a directory, not sweep file")
    one_line_error(invoke("recover", tmp_path), "is a directory, not a recording")  # was "no such recording"
    one_line_error(invoke("recover", tmp_path / "gone.mcap"), "no such recording", "gone.mcap")
    path = tmp_path / "hull.yaml"
    path.write_text("version: 1\nvessels: [{name: a, model: custom, hull_mesh: ., mass: {mass_kg: 9.0}}]\n")
    one_line_error(invoke("validate", path), "vessels[0].hull_mesh", "is a directory; give a mesh file")


def test_a_dataset_from_a_scenario_whose_step_10_hz_does_not_divide(tmp_path):
    """The cameras were rendered at a forced 10 Hz: with 128 Hz physics (7.8125 ms steps) a ValueError traceback
    although the scenario (an 8 Hz camera) validates."""
    scenario = tmp_path / "fast.yaml"
    scenario.write_text("version: 1\nworld: {physics_rate_hz: 128}\noutputs: {recording: {clock_rate_hz: 128, "
                        "ground_truth_rate_hz: 64}}\nvessels: [{name: a, model: otter, sensors: [{type: camera, "
                        "name: c, width: 64, height: 48, rate_hz: 8}]}]\n")  # fmt: skip
    assert invoke("validate", scenario).exit_code == 0
    result = invoke("dataset", scenario, "--frames", "2", "--out", tmp_path / "ds")
    assert result.exit_code == 0, result.output
    assert len(list((tmp_path / "ds" / "images").rglob("*.png"))) == 2


@pytest.mark.parametrize(
    ("args", "bridge"),
    [
        (["--ros-tcp-profile", "seed"], "--ros-tcp"),
        (["--ros-tcp-vessel", "nosuch"], "--ros-tcp"),
        (["--foxglove-port", "1"], "--foxglove"),
        (["--ros2-interface", "bogus0"], "--ros2"),
        (["--domain-id", "5"], "--ros2"),
    ],
)
def test_a_bridge_option_without_its_bridge_is_one_line(tmp_path, args, bridge):
    """Each was ignored in silence (exit 0) when its bridge was not on (QA)."""
    one_line_error(invoke("run", "harbor", "--duration", "0.01", *args), "applies to", bridge)


@pytest.mark.parametrize(("option", "name", "words"), [("--screenshot", "shot.txt", ".png"),
                                                       ("--video", "run.gif", ".mp4 or .avi")])  # fmt: skip
def test_viewer_output_formats_are_checked_before_the_run(tmp_path, option, name, words):
    """`--screenshot shot.txt` ran the whole session, then ended in a ValueError traceback from Pillow (the frame
    lost); `--video run.gif` opened the window and failed on its first frame. Both are one line before any work."""
    result = invoke("run", "harbor", "--view", "--duration", "0.1", option, tmp_path / name)
    one_line_error(result, words)
    assert not (tmp_path / name).exists()


def test_view_without_a_display_fails_before_building_the_world(monkeypatch, tmp_path):
    """Without DISPLAY the viewer's one-line error came after the scenario was built (~10 s) and left the
    recording to be removed again; now it comes first."""
    import sys

    import usvsim.simulation

    if not sys.platform.startswith("linux"):
        pytest.skip("DISPLAY is how Linux finds its window system")
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    monkeypatch.setattr(usvsim.simulation.Simulation, "from_scenario", never)
    one_line_error(invoke("run", "harbor", "--view", "--record", tmp_path / "r.mcap"), "no display")
    assert not (tmp_path / "r.mcap").exists()


def test_the_viewer_runs_until_closed_unless_a_duration_is_given(monkeypatch):
    """`usvsim run harbor --view` ('drive it yourself') closed the window after the headless default of 60 simulated
    seconds; now it runs until the window is closed, and --duration still stops it. Headless runs keep 60 s."""
    import usvsim.viewer
    import usvsim.viewer.display

    asked = []

    def fake_viewer(sim, max_seconds=None, **kwargs):
        asked.append(max_seconds)
        return {"steps": 0}

    monkeypatch.setenv("MUJOCO_GL", "egl")  # run --view sets glfw: restored after the test
    monkeypatch.setattr(usvsim.viewer.display, "display_missing", lambda: False)
    monkeypatch.setattr(usvsim.viewer, "run_viewer", fake_viewer)
    assert invoke("run", "harbor", "--view").exit_code == 0
    assert invoke("run", "harbor", "--view", "--duration", "5").exit_code == 0
    assert asked == [None, 5.0]
    headless = invoke("run", "harbor")
    assert headless.exit_code == 0 and "simulated 60.00 s" in headless.output


def test_the_viewer_follows_the_vessel_asked_for(monkeypatch):
    """`--vessel otter` drives and follows the Otter (the viewer always took the first vessel); without --view, or a
    vessel the scenario lacks, is one line."""
    import usvsim.viewer
    import usvsim.viewer.display

    asked = []

    def fake_viewer(sim, vessel=None, **kwargs):
        asked.append(vessel)
        return {"steps": 0}

    one_line_error(invoke("run", "harbor", "--vessel", "otter"), "--vessel", "--view")
    monkeypatch.setenv("MUJOCO_GL", "egl")
    monkeypatch.setattr(usvsim.viewer.display, "display_missing", lambda: False)
    real = usvsim.viewer.run_viewer
    monkeypatch.setattr(usvsim.viewer, "run_viewer", fake_viewer)
    assert invoke("run", "harbor", "--view", "--vessel", "otter").exit_code == 0
    assert asked == ["otter"]
    monkeypatch.setattr(usvsim.viewer, "run_viewer", real)  # the real one refuses before opening a window
    one_line_error(invoke("run", "harbor", "--view", "--vessel", "oter"), "no vessel 'oter'", "otter")


def test_task_record_epoch_as_usvsim_run(tmp_path):
    """`usvsim run` has --record-epoch, `usvsim task --record` had none: its log times were always the wall
    clock. Now the same option: epoch 0 makes log time = simulation time; a bad value or one without --record
    is one line."""
    from mcap.reader import make_reader

    record, report = tmp_path / "r.mcap", tmp_path / "r.json"
    result = invoke("task", "station_keeping", "--time-limit", "1", "--record", record, "--record-epoch", "0",
                    "--report", report)  # fmt: skip
    assert result.exit_code == 0, result.output
    with record.open("rb") as f:
        times = [m.log_time for _, _, m in make_reader(f).iter_messages(topics=["/clock"])]
    assert times[0] == 0 and times[-1] == 1_000_000_000  # simulation time from 0, not the wall clock
    one_line_error(invoke("task", "station_keeping", "--record", tmp_path / "b.mcap", "--record-epoch", "soon",
                          "--report", report), "--record-epoch")  # fmt: skip
    one_line_error(invoke("task", "station_keeping", "--record-epoch", "0", "--report", report),
                   "--record-epoch", "--record FILE.mcap")  # fmt: skip
