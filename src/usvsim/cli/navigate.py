"""`usvsim demo navigate`: the reference autonomy stack mapping and driving a scenario (usvsim.autonomy)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

demo_app = typer.Typer(no_args_is_help=True, help="Demonstrations of what usvsim drives.")


@demo_app.command("navigate")
def navigate_command(
    scenario: Annotated[str, typer.Argument(help="scenario YAML file or built-in name")] = "harbor_navigate",
    goals: Annotated[
        str | None, typer.Option(help="'x,y;x,y;...' world ENU m (default: the scenario's)")
    ] = None,
    out: Annotated[
        Path, typer.Option(help="output folder: map.png/.yaml, map_truth.png, trajectory.png, metrics.json")
    ] = Path("navigate_out"),
    max_time: Annotated[
        float, typer.Option(help="simulation seconds before giving up", min=1.0, max=1e6)
    ] = 400.0,
    seed: Annotated[int, typer.Option(help="random seed", min=0)] = 0,
    odometry: Annotated[
        str, typer.Option(help="auto | kiss_icp | sensor (the odometry sensor's pose)")
    ] = "auto",
    planner: Annotated[
        str,
        typer.Option(help="astar (A*, corners filleted) | hybrid (hybrid A*: arcs of the turning radius)"),
    ] = "astar",
) -> None:
    """Map as it goes (LiDAR odometry + occupancy grid), plan, drive to each goal; write pictures and metrics."""
    from usvsim.autonomy.demo import acceptance, check_demo, parse_goals, run_demo
    from usvsim.cli.errors import fail as _fail
    from usvsim.cli.outputs import prepare_folder
    from usvsim.core.errors import UsvsimError

    try:
        if odometry not in ("auto", "kiss_icp", "sensor"):
            raise UsvsimError(f"--odometry {odometry!r}: choose auto, kiss_icp or sensor")
        if planner not in ("astar", "hybrid"):
            raise UsvsimError(f"--planner {planner!r}: choose astar or hybrid")
        parsed = check_demo(scenario, parse_goals(goals) if goals else None)  # before the folder is made
        prepare_folder(out)
        summary = run_demo(scenario, parsed, out, max_time, seed, odometry, planner)
    except UsvsimError as exc:
        _fail(exc)
    checks = acceptance(summary)
    typer.echo(json.dumps({k: v for k, v in summary.items() if k != "files"}, indent=2))
    for g in summary["goals_given_up"]:
        x, y = g["goal"]
        typer.echo(f"goal {x:g},{y:g} given up at t = {g['t_s']:g} s: {g['why']}")
    typer.echo(" ".join(f"{k}: {'PASS' if ok else 'FAIL'}" for k, ok in checks.items()))
    typer.echo(f"wrote {', '.join(summary['files'])}")
    if not all(checks.values()):  # as `usvsim experiment`: scripts see a failed check (it exited 0)
        raise typer.Exit(1)
