"""The `usvsim` command line: run, validate, scenarios, experiment."""

from __future__ import annotations

import inspect
import os
import signal
import sys
import time
from contextlib import ExitStack
from dataclasses import dataclass
from pathlib import Path
from typing import Annotated, Any

import typer
from rich.console import Console
from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn
from rich.table import Table

from usvsim.cli.dataset import dataset_command
from usvsim.cli.errors import console, fail
from usvsim.cli.geo_map import map_command
from usvsim.cli.info import info
from usvsim.cli.navigate import demo_app
from usvsim.cli.recover import recover
from usvsim.cli.schema import schema_command
from usvsim.cli.stopping import exit_status, signal_name
from usvsim.cli.sweep import sweep as sweep_command
from usvsim.cli.task import task as task_command
from usvsim.cli.traffic import imazu
from usvsim.cli.traffic import print_report as print_traffic_report
from usvsim.core.errors import UsvsimError
from usvsim.io.topic_filter import TopicFilter

app = typer.Typer(
    add_completion=False, no_args_is_help=True, help="usvsim: unmanned surface vehicle simulator."
)
app.command()(imazu)  # usvsim imazu (cli/traffic.py)

EXPERIMENTS = {  # name: (module, what it checks, run time on the shared 2-core machine at load 2-7)
    "sphere": ("usvsim.experiments.sphere", "sphere lowered through flat water: volume vs the analytic cap", "10 s"),
    "voxel-sphere": ("usvsim.experiments.voxel_sphere", "voxel buoyancy of the sphere, with and without cutting", "5 s"),
    "box-righting": ("usvsim.experiments.box_righting", "heeled box: righting moment vs the wall-sided formula", "5 s"),
    "drafts": ("usvsim.experiments.drafts", "library vessels' equilibrium drafts vs Archimedes", "30 s"),
    "heave-decay": ("usvsim.experiments.heave_decay",
                    "heave and roll natural periods of a box, with and without added mass, vs closed forms", "10 s"),
    "otter": ("usvsim.experiments.otter", "Fossen's Otter: his equations vs PythonVehicleSimulator's runs, and "
              "usvsim's otter_pvs vs his equations", "30 s"),
    "kerner-vectors": ("usvsim.experiments.kerner_vectors", "single-triangle Kerner forces vs test vectors", "15 s"),
    "waves": ("usvsim.experiments.waves", "wave statistics, dispersion and height queries", "1.5 min"),
    "detection-robustness": ("usvsim.experiments.detection_robustness", "YOLO trained on clear synthetic buoys, "
                             "evaluated on clear and foggy sets (needs Ultralytics: docs/datasets.md)", "30 min"),
    "endurance": ("usvsim.experiments.endurance",
                  "one hour in sea state 6 with each of four models: afloat, upright, bounded", "15 min"),
}  # fmt: skip
EXPERIMENT_HELP = "\n".join(f"{name}: {text} (about {took})" for name, (_, text, took) in EXPERIMENTS.items())


@app.command()
def run(
    scenario: Annotated[str, typer.Argument(help="built-in scenario name or YAML file")] = "harbor",
    duration: Annotated[
        float | None,
        typer.Option(
            help="simulated seconds in all: a /reset (ROS 2, ROS-TCP, Foxglove) or R in the viewer starts a new "
            "episode at t = 0 but does not lengthen the run (0 to 1e7; default 60, with --view until the window "
            "closes)",
            show_default=False,
        ),
    ] = None,
    realtime: Annotated[bool, typer.Option(help="pace to the wall clock")] = False,
    record: Annotated[Path | None, typer.Option(help="write an MCAP file (rosbag2 layout)")] = None,
    record_topics: Annotated[
        list[str] | None,
        typer.Option(help="record only these topics: names or patterns ('*' matches across '/'), comma-separated "
                     "or repeated, e.g. '/clock,/tf*,/wamv/imu/data'; '!' leaves one out: '!/wamv/camera/*' "
                     "(default: outputs.recording.topics, else all)"),
    ] = None,
    record_compression: Annotated[
        str | None, typer.Option(help="chunk compression of the recording: zstd, lz4 or none, all open in ros2 bag "
                                 "(default: outputs.recording.compression, zstd)"),
    ] = None,
    record_epoch: Annotated[
        str, typer.Option(help="the recording's log times are this epoch + simulation time: now (the wall clock, "
                          "so Foxglove shows the date of the run), seconds since 1970 (0: log time = simulation "
                          "time) or an ISO 8601 date such as 2026-01-01T00:00:00Z (byte-identical files); "
                          "header stamps and /clock are simulation time from 0 either way"),
    ] = "now",  # fmt: skip
    seed: Annotated[int, typer.Option(help="random seed", min=0)] = 0,
    reset_seed: Annotated[
        str, typer.Option(help="the seed of each reset asked for at run time (/reset, R in the viewer): next (seed + 1 "
                          "each time: episodes seed, seed + 1, ...) or same (the run's seed again)"),
    ] = "next",  # fmt: skip
    view: Annotated[
        bool, typer.Option(help="open the interactive viewer (W/S/A/D drive, R reset, Space pause)")
    ] = False,
    ros2: Annotated[bool, typer.Option("--ros2", help="live ROS 2 topics over DDS (extra: ros2)")] = False,
    domain_id: Annotated[
        int | None, typer.Option(help="ROS 2 domain id (default $ROS_DOMAIN_ID or 0)", min=0, max=232)
    ] = None,
    ros2_interface: Annotated[
        str,
        typer.Option(
            help="DDS network interface; 'lo' keeps traffic on this machine, 'any' lets Cyclone choose"
        ),
    ] = "lo",
    ros_tcp: Annotated[str | None, typer.Option(help="connect to a ros_tcp_endpoint at HOST:PORT")] = None,
    ros_tcp_profile: Annotated[str, typer.Option(help="topic names on ROS-TCP: usvsim or seed")] = "usvsim",
    ros_tcp_vessel: Annotated[
        str | None, typer.Option(help="vessel the seed profile renames (default: first)")
    ] = None,
    foxglove: Annotated[
        bool, typer.Option("--foxglove", help="Foxglove WebSocket live view (extra: ros2)")
    ] = False,
    foxglove_host: Annotated[str, typer.Option(help="address the Foxglove server binds")] = "127.0.0.1",
    foxglove_port: Annotated[int, typer.Option(help="Foxglove server port", min=0, max=65535)] = 8765,
    foxglove_max_clients: Annotated[
        int, typer.Option(help="Foxglove connections at once", min=1, max=1024)
    ] = 16,
    force: Annotated[bool, typer.Option("--force", help="overwrite an existing recording")] = False,
    vessel: Annotated[str | None, typer.Option(help="with --view: the vessel to follow and drive (default: the "
                                               "scenario's first)")] = None,  # fmt: skip
    screenshot: Annotated[Path | None, typer.Option(help="with --view: save the last frame as PNG")] = None,
    video: Annotated[Path | None, typer.Option(help="with --view: record the window to a video (.mp4, .avi) at 30 frames per simulated second")] = None,
) -> None:
    """Run a scenario headless or in the viewer, optionally recording it and bridging it to ROS 2 / Foxglove."""
    from usvsim.cli.bridges import BridgeOptions
    from usvsim.cli.outputs import prepare_file

    options = BridgeOptions(ros2, domain_id, ros2_interface, ros_tcp, ros_tcp_profile, ros_tcp_vessel, foxglove,
                            foxglove_host, foxglove_port, foxglove_max_clients)  # fmt: skip
    defaults = {name: p.default for name, p in inspect.signature(run).parameters.items()}
    try:  # an option away from its default without its bridge was ignored in silence
        options.check_used({name for name, value in locals().items() if name in defaults and value != defaults[name]})
    except UsvsimError as exc:
        fail(exc)
    if reset_seed not in ("next", "same"):
        fail(UsvsimError(f"--reset-seed must be next or same, got {reset_seed!r}"))
    if reset_seed != "next" and not (view or ros2 or ros_tcp or foxglove):  # else ignored in silence
        fail(UsvsimError("--reset-seed applies to resets from /reset (--ros2, --ros-tcp, --foxglove) or R (--view)"))
    if duration is not None and not 0 <= duration <= 1e7:
        fail(UsvsimError(f"--duration must be a finite number of seconds in [0, 1e7], got {duration}"))
    if (screenshot or video) and not view:
        fail(UsvsimError("--screenshot and --video record the viewer's window: add --view"))
    if vessel is not None and not view:
        fail(UsvsimError("--vessel chooses the vessel the viewer follows and drives: add --view"))
    if screenshot or video:
        from usvsim.viewer.capture import check_outputs

        try:
            check_outputs(screenshot, video)
        except UsvsimError as exc:
            fail(exc)
    for target in (screenshot, video):  # checked before the run, not when the window closes
        if target is not None:
            try:
                prepare_file(target)
            except UsvsimError as exc:
                fail(exc)
    if view:
        from usvsim.viewer.display import NO_DISPLAY, display_missing

        if display_missing():
            fail(UsvsimError(f"cannot open the viewer window: {NO_DISPLAY}"))  # at once, not after building the world
        # camera sensors then render in hidden GLFW windows beside the viewer's (an EGL context beside a GLX window
        os.environ["MUJOCO_GL"] = "glfw"  # fails with X BadAccess in glXMakeCurrent)
    from usvsim.cli.stopping import StopSignals

    # closes bridges, then the recorder, then the simulation, on every path; a stop during the set-up (kernels
    # compiling, DDS starting) is taken before the first step (it killed the process, the recording a bare header)
    with ExitStack() as stack, StopSignals() as setup:
        recording = _Recording(record, force, record_topics, record_compression, record_epoch)
        sim, recorder, bridges = _open_run(stack, scenario, seed, recording, options)
        sim.reset_seeds = reset_seed
        interrupted = 0  # the signal that stopped the run (SIGINT: Ctrl-C; SIGTERM: kill, timeout, docker stop)
        start, steps = time.perf_counter(), _StepCount()
        try:
            setup.check()
            if view:
                _run_viewer(sim, duration, screenshot, video, steps, vessel)
            else:
                _run_with_progress(sim, 60.0 if duration is None else duration, realtime, steps)
        except KeyboardInterrupt as exc:
            interrupted = getattr(exc, "signum", signal.SIGINT)
        except (UsvsimError, OSError) as exc:
            if steps.n == 0:  # no step ran (no display for --view)
                _discard_recording(stack, recorder)
            fail(exc)
        if interrupted and steps.n == 0:  # stopped during the set-up
            _discard_recording(stack, recorder)
        stack.close()
    wall = time.perf_counter() - start
    simulated = steps.n * sim.clock.dt  # over every episode of the run (sim.time restarts at a reset)
    rtf = simulated / wall if wall > 0 else float("inf")
    status = f"stopped ({signal_name(interrupted)})" if interrupted else "done"
    episodes = f" over {sim.episode + 1} episodes" if sim.episode else ""
    typer.echo(f"{status}: simulated {simulated:.2f} s{episodes} in {wall:.2f} s wall ({rtf:.1f}x real time)")
    if steps.first_s >= SLOW_FIRST_STEP_S:  # a first run's 0.1x real time read as the speed
        rest = (f"; the other steps ran at {(steps.n - 1) * sim.clock.dt / max(wall - steps.first_s, 1e-9):.1f}x "
                "real time" if steps.n > 1 else "")  # a run of one step said nothing (QA): "0.0x real time" alone
        typer.echo(f"usvsim: note: the first step took {steps.first_s:.1f} s (a first run compiles the physics "
                   f"kernels and keeps them for the next runs){rest}", err=True)  # fmt: skip
    print_traffic_report(sim, Console(soft_wrap=True))  # a result: stdout, beside "done: ..."
    if recorder and not recorder.path.exists():
        typer.echo(f"no step was taken: {recorder.path} not kept")
    elif recorder:
        typer.echo(f"recorded {recorder.message_count} messages to {recorder.path}")
        for line in recorder.topic_filter.unmatched():  # a misspelt name recorded nothing, in silence
            console.print(f"usvsim: warning: {line}", highlight=False, soft_wrap=True, markup=False)
    for bridge in bridges:
        typer.echo(f"{type(bridge).__name__}: {_stats_line(bridge.stats)}")
    if interrupted:
        raise typer.Exit(exit_status(interrupted))  # 130 for Ctrl-C, 143 for SIGTERM, as the shell reports them


def _discard_recording(stack: ExitStack, recorder) -> None:
    """Close everything and delete the recording of a run that took no step (it failed or was stopped during its
    set-up): the file of no step left behind made the next try need --force."""
    stack.close()
    if recorder is not None:
        recorder.path.unlink(missing_ok=True)


@dataclass
class _Recording:
    """The recording options of `usvsim run`."""

    path: Path | None
    force: bool
    topics: list[str] | None
    compression: str | None
    epoch: str = "now"


def _open_run(stack: ExitStack, scenario: str, seed: int, recording: _Recording, options):
    """Simulation, recorder (or None) and bridges, each registered on `stack` to be closed; one-line errors."""
    from usvsim.cli.bridges import close_all, open_bridges
    from usvsim.cli.outputs import check_output
    from usvsim.config.loader import source_of
    from usvsim.core.errors import ScenarioError
    from usvsim.io.mcap_recorder import COMPRESSIONS, McapRecorder, parse_epoch
    from usvsim.simulation import Simulation

    recorder, record, force = None, recording.path, recording.force
    try:
        topics = [t.strip() for text in recording.topics for t in text.split(",") if t.strip()] \
            if recording.topics is not None else None  # fmt: skip
        wanted = TopicFilter(topics, "--record-topics")
        if recording.compression not in (None, *COMPRESSIONS):  # before the (slow) build
            raise UsvsimError(f"--record-compression must be zstd, lz4 or none, got {recording.compression!r}")
        epoch_ns = parse_epoch(recording.epoch)
        if record:
            check_output(record, force)  # before the (slow) build
        sim = Simulation.from_scenario(scenario, seed=seed)
        stack.callback(sim.close)
        _print_setup_warnings(sim)  # what `usvsim validate` warns about, said before the run too
        configured = sim.scenario.outputs.recording.path
        path = record or (Path(configured) if configured else None)
        if path and not record:  # the scenario's path: the error names the key (it named only a directory)
            try:
                check_output(path, force)
            except UsvsimError as exc:
                raise ScenarioError(source_of(sim.scenario), "outputs.recording.path", str(exc)) from None
        elif path:
            check_output(path, force)
        if not path and (topics is not None or recording.compression is not None or recording.epoch != "now"):
            raise UsvsimError("--record-topics, --record-compression and --record-epoch apply to a recording: add "
                              "--record FILE.mcap")  # fmt: skip
        if path:  # the scenario's path too: it was checked and then not written (QA)
            configured_recording = sim.scenario.outputs.recording
            if topics is None and configured_recording.topics is not None:
                wanted = TopicFilter(configured_recording.topics, "outputs.recording.topics")
            compression: Any = recording.compression or configured_recording.compression  # checked above
            recorder = McapRecorder(path, compression=compression, topics=wanted, epoch_ns=epoch_ns)
            stack.callback(recorder.close)
            sim.subscribe(recorder.write)
        bridges = open_bridges(sim, options)
        stack.callback(close_all, bridges)
        for bridge in bridges:
            if hasattr(bridge, "url"):  # where to point Foxglove (with --foxglove-port 0, the port chosen)
                console.print(f"usvsim: Foxglove: open {bridge.url}", highlight=False, markup=False)
    except (UsvsimError, OSError) as exc:
        # a bridge that cannot start (port taken) left an empty recording behind
        _discard_recording(stack, recorder)
        fail(exc)
    return sim, recorder, bridges


def _print_setup_warnings(sim) -> list[str]:
    """Print (stderr) and return the warnings about set-ups that cannot work (world/checks.py)."""
    from usvsim.world.checks import setup_warnings

    warnings = setup_warnings(sim.world)
    for warning in warnings:
        console.print(f"usvsim: warning: {warning}", highlight=False, soft_wrap=True)
    return warnings


def _stats_line(stats: dict) -> str:
    return ", ".join(f"{k} {v}" for k, v in stats.items() if isinstance(v, int | float))


class _StepCount:
    """Physics steps the run has taken, across resets (the clock counts the current episode only), and the wall
    seconds from the start of the run to the end of its first step."""

    n = 0
    first_s = 0.0


SLOW_FIRST_STEP_S = 2.0  # a first step this long (s) is worth a note: numba compiling on a first run, not the speed


def _run_with_progress(sim, duration: float, realtime: bool, steps: _StepCount) -> None:
    """Run with a progress bar. Ctrl-C (SIGINT) or SIGTERM (`kill`, `timeout`, `docker stop`) stops the run
    between two steps (never inside a step, where a recorder or bridge may be half-way through writing a
    message), so the recording is closed complete; SIGTERM used to end the process with the file unfinished."""
    from usvsim.cli.stopping import StopSignals

    with StopSignals() as stop:

        started = time.perf_counter()

        def between_steps(_sim) -> None:
            steps.n += 1
            if steps.n == 1:
                steps.first_s = time.perf_counter() - started
            stop.check()

        _progress_loop(sim, duration, realtime, between_steps, steps)


def _progress_loop(sim, duration: float, realtime: bool, on_step, steps: _StepCount) -> None:
    """Steps until `duration` of simulated time in all: a /reset mid-run restarts the clock, not the count."""
    start = time.perf_counter()
    columns = (
        TextColumn("[bold]{task.description}"),
        BarColumn(),
        TextColumn("t = {task.completed:.1f} / {task.total:.1f} s"),
        TextColumn("{task.fields[rtf]}"),
        TimeElapsedColumn(),
    )
    dt = sim.clock.dt
    total = round(duration / dt)  # whole physics steps: the run ends exactly at `duration` (to the step)
    chunk = max(1, round(0.5 / dt))
    behind_warned = False
    with Progress(*columns, console=console, transient=False, disable=not console.is_terminal) as progress:
        task = progress.add_task(sim.scenario.name, total=duration, rtf="")
        while steps.n < total:
            sim.run(min(chunk, total - steps.n) * dt, realtime=realtime, on_step=on_step)
            wall, done = time.perf_counter() - start, steps.n * dt
            progress.update(task, completed=done, rtf=f"{done / wall:.1f}x RT" if wall > 0 else "")
            if realtime and not behind_warned and wall > 2.0 and done < 0.9 * wall:
                behind_warned = True
                console.print(f"usvsim: warning: --realtime is falling behind: {done:.1f} s simulated in "
                              f"{wall:.1f} s wall ({done / wall:.2f}x real time)", highlight=False, soft_wrap=True)  # fmt: skip


def _run_viewer(sim, duration: float | None, screenshot: Path | None, video: Path | None,
                steps: _StepCount, vessel: str | None = None) -> None:  # fmt: skip
    import warnings

    from usvsim.cli.stopping import Stopped, StopSignals
    from usvsim.viewer import run_viewer

    try:
        # Ctrl-C or SIGTERM ends the viewer between two frames, as Esc does (a KeyboardInterrupt landed anywhere,
        # a physics step or a recorder's write included, and the steps taken were not counted; SIGTERM killed it)
        with warnings.catch_warnings(), StopSignals() as stop:
            warnings.simplefilter("ignore")  # GLFW repeats its own error as a warning
            stats = run_viewer(sim, vessel=vessel, max_seconds=duration, screenshot=screenshot, video=video,
                               stop=lambda: bool(stop.signum))  # fmt: skip
        steps.n = stats["steps"]
    except RuntimeError as exc:  # no display, no OpenGL
        raise UsvsimError(f"cannot open the viewer window: {exc}") from None
    if stop.signum:
        raise Stopped(stop.signum)


@app.command()
def validate(
    file: Annotated[str, typer.Argument(help="scenario YAML file or built-in name")],
    strict: Annotated[bool, typer.Option(help="exit with status 1 when there are warnings (for CI)")] = False,
) -> None:
    """Check a scenario: schema, files, meshes, rates; builds the world without running it and warns about
    set-ups that cannot work (a hull too heavy to float, bodies overlapping, hulls far from the water,
    vessels or traffic on land)."""
    from usvsim.simulation import Simulation

    try:
        sim = Simulation.from_scenario(file)
        _check_recording_path(sim.scenario)  # `usvsim run` refused it after validate said OK
    except UsvsimError as exc:
        fail(exc)
    warnings = _print_setup_warnings(sim)
    sim.close()
    sc = sim.scenario
    summary = f"{file}: scenario '{sc.name}', {len(sc.vessels)} vessel(s), {len(sc.objects)} object(s)"
    if strict and warnings:
        typer.echo(f"NOT OK (--strict): {summary}, {len(warnings)} warning(s)")
        raise typer.Exit(1)
    typer.echo(f"OK: {summary}")


def _check_recording_path(scenario) -> None:
    """A ScenarioError for an `outputs.recording.path` that `usvsim run` cannot write (an existing file is fine here:
    whether to replace it is --force's business at run time)."""
    from usvsim.cli.outputs import check_output
    from usvsim.config.loader import source_of
    from usvsim.core.errors import ScenarioError

    if scenario.outputs.recording.path:
        try:
            check_output(Path(scenario.outputs.recording.path), force=True)
        except UsvsimError as exc:
            raise ScenarioError(source_of(scenario), "outputs.recording.path", str(exc)) from None


app.command()(recover)
app.command()(info)


@app.command()
def scenarios() -> None:
    """List the built-in scenarios."""
    from usvsim.config.loader import builtin_scenarios

    table = Table("name", "description", box=None)
    for name, text in builtin_scenarios().items():
        table.add_row(name, text)
    Console().print(table)


@app.command(epilog=EXPERIMENT_HELP)
def experiment(
    name: Annotated[str, typer.Argument(help=f"one of: {', '.join(EXPERIMENTS)}")],
    out: Annotated[Path, typer.Option(help="output directory")] = Path("out/experiments"),
) -> None:
    """Run a validation experiment; writes NAME.json and NAME.png under --out (dashes in NAME become underscores),
    prints its summary and PASS or FAIL (exit status 1 on FAIL)."""
    import importlib
    import json

    if name not in EXPERIMENTS:
        fail(UsvsimError(f"unknown experiment {name!r}; choose one of: {', '.join(EXPERIMENTS)}"))
    from usvsim.cli.outputs import prepare_folder

    try:
        prepare_folder(out)
    except UsvsimError as exc:
        fail(exc)
    module = importlib.import_module(EXPERIMENTS[name][0])
    kwargs = {}
    if "progress" in inspect.signature(module.run).parameters:  # long ones say where they are, on stderr (after
        # their own checks of the environment, whose failure stays one line)
        kwargs["progress"] = lambda text: console.print(f"usvsim: {name}: {text}", highlight=False, markup=False)
    try:
        result = module.run(out, **kwargs)
    except UsvsimError as exc:
        fail(exc)
    passed = result.get("passed")
    typer.echo(json.dumps(result.get("summary", {}), indent=2, default=str))
    stem = out / name.replace("-", "_")
    typer.echo(f"{name}: {'PASS' if passed else 'FAIL'}; wrote {stem}.json and {stem}.png")
    if passed is False:
        raise typer.Exit(1)


app.command("map")(map_command)
app.command("task")(task_command)
app.command("dataset")(dataset_command)
app.add_typer(demo_app, name="demo")
app.command("sweep")(sweep_command)
app.command("schema")(schema_command)


def main() -> None:
    # typer >= 0.2x vendors click (typer._click): find its ClickException through a public class
    click_exception: type[Exception] = next(c for c in typer.BadParameter.__mro__ if c.__name__ == "ClickException")
    try:
        code = app(standalone_mode=False)
    except click_exception as exc:  # a usage mistake (bad option value, unknown option...): one line
        if type(exc).__name__ != "NoArgsIsHelpError":  # that one has printed the help already
            ctx = getattr(exc, "ctx", None)
            hint = f" (see {ctx.command_path} --help)" if ctx is not None else ""
            message = " ".join(exc.format_message().split())  # pyright: ignore[reportAttributeAccessIssue]
            console.print(f"usvsim: error: {message}{hint}", highlight=False, soft_wrap=True, markup=False)
        sys.exit(getattr(exc, "exit_code", 2))
    except typer.Abort:
        console.print("usvsim: aborted", highlight=False)
        sys.exit(1)
    except BrokenPipeError:  # `usvsim ... | head`: the reader went away; quietly, as click does
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        sys.exit(1)
    except UsvsimError as exc:  # errors raised outside a command's own handling
        console.print(f"usvsim: error: {exc}", highlight=False, soft_wrap=True, markup=False)
        sys.exit(2)
    sys.exit(code if isinstance(code, int) else 0)
