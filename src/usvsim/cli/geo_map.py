"""`usvsim map`: a plan view of a scenario or a task (coast, depth contours, structures, objects, traffic
routes, task goals, vessels) as PNG."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer


def map_command(
    scenario: Annotated[str, typer.Argument(help="built-in scenario name, YAML file, or with --task a task name")],
    out: Annotated[Path, typer.Option(help="PNG file to write")] = Path("map.png"),
    task: Annotated[bool, typer.Option("--task", help="SCENARIO names a task (usvsim task): draw its goals")] = False,
    difficulty: Annotated[int, typer.Option(help="task difficulty 0-2 (with --task)", min=0, max=2)] = 0,
    seed: Annotated[int, typer.Option(help="task layout seed (with --task)", min=0)] = 0,
) -> None:
    """Draw a plan view (land, depth contours, structures, objects, traffic routes, task goals) to a PNG."""
    from matplotlib.backend_bases import FigureCanvasBase

    from usvsim.cli.errors import fail as _fail
    from usvsim.cli.outputs import prepare_file
    from usvsim.core.errors import UsvsimError
    from usvsim.geo.plan import draw_plan
    from usvsim.simulation import Simulation

    if not out.suffix:  # matplotlib would add ".png" itself; say so in the path printed
        out = out.with_name(out.name + ".png")
    formats = FigureCanvasBase.get_supported_filetypes()
    if out.suffix[1:].lower() not in formats:
        _fail(f"--out {out}: unknown image format {out.suffix!r}; use .png (or {', '.join(sorted(formats))})")
    try:
        prepare_file(out)
        marks = []
        if task:
            sim, marks = _task_simulation(scenario, difficulty, seed)
        else:
            sim = Simulation.from_scenario(scenario)
        draw_plan(sim, out, marks=marks)
    except UsvsimError as exc:
        _fail(exc)
    except OSError as exc:
        _fail(f"cannot write {out}: {exc.strerror}")
    typer.echo(str(out))


def _task_simulation(name: str, difficulty: int, seed: int):
    """The task's scenario as a simulation and its plan marks (`Task.plan_marks`)."""
    from usvsim.core.errors import UsvsimError
    from usvsim.simulation import Simulation
    from usvsim.tasks import TASKS

    if name not in TASKS:
        raise UsvsimError(f"no task '{name}' (tasks: {', '.join(TASKS)})")
    task = TASKS[name](difficulty, seed)
    return Simulation(task.scenario(), seed=seed), task.plan_marks()
