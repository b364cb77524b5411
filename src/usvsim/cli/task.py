"""`usvsim task NAME`: run a VRX task with the built-in reference solution, or live over ROS 2 (`--ros2`, with
`--external` for a team's own stack driving the boat); print scores, write a JSON report."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer
from rich.console import Console
from rich.table import Table

from usvsim.cli.errors import console, fail
from usvsim.core.errors import UsvsimError


def task(
    name: Annotated[str, typer.Argument(help="station_keeping, wayfinding, perception, follow_path, wildlife, gymkhana")],
    difficulty: Annotated[int, typer.Option(help="0 calm, 1 moderate, 2 rough (VRX 2023 practice levels)")] = 0,
    seed: Annotated[int, typer.Option(help="seed of the first trial (trial k uses seed + k)", min=0)] = 0,
    trials: Annotated[int, typer.Option(help="number of trials", min=1)] = 1,
    time_limit: Annotated[float, typer.Option(help="running time limit, s (VRX: 300)", min=1.0, max=1e6)] = 300.0,
    report: Annotated[Path, typer.Option(help="JSON report path")] = Path("out/task_report.json"),
    ros2: Annotated[bool, typer.Option("--ros2", help="publish the task's VRX topics and every sensor over DDS")] = False,
    external: Annotated[bool, typer.Option("--external", help="with --ros2: no built-in solution, the boat obeys "
                                           "ROS 2 commands (VRX thruster topics); paced to the wall clock")] = False,
    domain_id: Annotated[int | None, typer.Option(help="ROS domain id (default $ROS_DOMAIN_ID or 0)", min=0,
                                                  max=232)] = None,  # as `usvsim run`: Cyclone's ports end there
    ros2_interface: Annotated[str, typer.Option(help="DDS network interface (lo: this machine only)")] = "lo",
    landmark_type: Annotated[str, typer.Option(help="/vrx/perception/landmark type: pose (geometry_msgs/"
                                               "PoseStamped, VRX on Gazebo Sim) or geopose (geographic_msgs/GeoPoseStamped)")] = "pose",
    ready_s: Annotated[float, typer.Option(help="seconds before the task starts running (VRX: 20)", min=0.0, max=1e6)] = 0.0,
    record: Annotated[Path | None, typer.Option(help="MCAP recording of the (last) trial, task topics included")] = None,
    force: Annotated[bool, typer.Option("--force", help="overwrite an existing --record file")] = False,
    record_epoch: Annotated[str, typer.Option(help="the recording's log times are this epoch + simulation time, as "
                                              "`usvsim run --record-epoch`: now (the wall clock), seconds since "
                                              "1970 (0: log time = simulation time) or an ISO 8601 date such as "
                                              "2026-01-01T00:00:00Z (byte-identical files)")] = "now",
) -> None:
    """Run a task with the reference solution (our station-keeping controller) or live over ROS 2; prints the
    score per trial. Ctrl-C or SIGTERM stops it between two steps: the --record file is closed complete and the
    report holds the finished trials (exit status 130 or 143)."""
    from usvsim.cli.outputs import check_output, prepare_file
    from usvsim.cli.stopping import Stopped, StopSignals
    from usvsim.io.mcap_recorder import parse_epoch
    from usvsim.tasks import TASKS, TaskTiming
    from usvsim.tasks.solutions import run_trial

    stopped: tuple[int, int] | None = None  # (signal, trial) of a Ctrl-C or SIGTERM
    results: list[dict] = []
    records: list[Path | None] = [record] * trials
    try:
        if name not in TASKS:
            raise UsvsimError(f"unknown task {name!r}; choose one of: {', '.join(TASKS)}")
        if external and not ros2:
            raise UsvsimError("--external needs --ros2 (the boat's commands come over ROS 2)")
        if landmark_type not in ("pose", "geopose"):
            raise UsvsimError(f"--landmark-type must be pose or geopose, got {landmark_type!r}")
        epoch_ns = parse_epoch(record_epoch)  # `usvsim run` had --record-epoch, `usvsim task` did not (qa25)
        if record is None and record_epoch != "now":
            raise UsvsimError("--record-epoch applies to a recording: add --record FILE.mcap")
        prepare_file(report)  # a bad --report path fails now, not after the trials
        records = trial_recordings(record, trials)  # one file per trial: each trial overwrote the one before
        for path in records:
            if path is not None:
                check_output(path, force)  # never overwritten without --force, as `usvsim run --record`
        timing = TaskTiming(ready_s=ready_s, running_s=time_limit)
        with StopSignals() as stop:  # SIGTERM used to end the process with the recording unfinished, no report
            for k in range(trials):
                with console.status(f"{name} difficulty {difficulty}, trial {k + 1}/{trials} (seed {seed + k})"):
                    try:
                        if ros2 or record is not None:
                            results.append(_live(name, difficulty, seed + k, timing, ros2, external, domain_id,
                                                 ros2_interface, landmark_type, records[k], stop.check, epoch_ns))  # fmt: skip
                            if records[k] is not None:
                                results[-1]["recording"] = str(records[k])
                        else:
                            results.append(run_trial(name, difficulty, seed + k, timing, after_step=stop.check))
                    except Stopped as exc:
                        stopped = (exc.signum, k)
                        break
    except UsvsimError as exc:
        fail(exc)
    if stopped is not None:
        _report_stopped(name, difficulty, trials, seed, results, stopped, report, records[stopped[1]])
    _print_table(results)
    scores = [r["score"] for r in results]
    summary = {"task": name, "difficulty": difficulty, "trials": results, "mean_score": sum(scores) / len(scores),
               "higher_is_better": results[0]["higher_is_better"]}  # fmt: skip
    text = json.dumps(summary, indent=2, default=float)
    try:
        report.write_text(text)
    except OSError as exc:
        typer.echo(text)  # nothing lost: the report goes to stdout instead
        fail(f"cannot write {report}: {exc.strerror or exc}; the report was printed to stdout instead")
    typer.echo(f"{name}: mean score {summary['mean_score']:.4g} over {trials} trial(s); wrote {report}")


def trial_recordings(record: Path | None, trials: int) -> list[Path | None]:
    """The --record file of each trial: RECORD itself for one trial, RECORD's stem + _trialK for several."""
    if record is None or trials == 1:
        return [record] * trials
    return [record.with_name(f"{record.stem}_trial{k}{record.suffix}") for k in range(trials)]


def _report_stopped(name, difficulty, trials, seed, results, stopped, report: Path, record: Path | None):
    """After Ctrl-C or SIGTERM: the finished trials' table and report (the stopped trial has no score: VRX
    scores a whole trial), one line saying what was kept, and the shell's status for the signal."""
    from usvsim.cli.stopping import exit_status, signal_name

    signum, k = stopped
    if results:
        _print_table(results)
    scores = [r["score"] for r in results]
    summary = {"task": name, "difficulty": difficulty, "trials": results,
               "mean_score": sum(scores) / len(scores) if scores else None,
               "higher_is_better": results[0]["higher_is_better"] if results else None,
               "stopped": {"signal": signal_name(signum), "trial": k, "seed": seed + k, "trials_asked": trials}}  # fmt: skip
    text = json.dumps(summary, indent=2, default=float)
    try:
        report.write_text(text)
        kept = f"report of the {len(results)} finished trial(s) in {report}"
    except OSError as exc:
        typer.echo(text)
        kept = f"cannot write {report} ({exc.strerror or exc}): the report went to stdout"
    closed = f"; recording {record} closed complete" if record is not None else ""
    typer.echo(f"{name}: stopped ({signal_name(signum)}) in trial {k + 1}/{trials} (seed {seed + k}), which is "
               f"not scored; {kept}{closed}")  # fmt: skip
    raise typer.Exit(exit_status(signum))


def _print_table(results: list[dict]) -> None:
    table = Table("trial", "seed", "score", "collisions", "sim time s", "wall s", box=None)
    for k, r in enumerate(results):
        table.add_row(str(k), str(r["seed"]), f"{r['score']:.4g}", str(r["num_collisions"]),
                      f"{r['sim_time_s']:.1f}", f"{r['wall_time_s']:.1f}")  # fmt: skip
    Console().print(table)


def _live(name, difficulty, seed, timing, ros2, external, domain_id, interface, landmark_type, record,
          after_step=None, epoch_ns=None) -> dict:  # fmt: skip
    from usvsim.cli.bridges import BridgeOptions, open_bridges
    from usvsim.tasks.live import run_live

    options = BridgeOptions(ros2=ros2, domain_id=domain_id, ros2_interface=interface, ros_tcp=None,
                            ros_tcp_profile="", ros_tcp_vessel=None, foxglove=False, foxglove_host="", foxglove_port=0)  # fmt: skip
    return run_live(name, difficulty, seed, timing, bridges=lambda sim: open_bridges(sim, options),
                    external=external, landmark_type=landmark_type, record=record, after_step=after_step,
                    record_epoch_ns=epoch_ns)  # fmt: skip
