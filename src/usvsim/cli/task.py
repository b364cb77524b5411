"""`usvsim task NAME`: run a VRX task with the built-in reference solution; print scores, write a JSON report."""

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
    seed: Annotated[int, typer.Option(help="seed of the first trial (trial k uses seed + k)")] = 0,
    trials: Annotated[int, typer.Option(help="number of trials", min=1)] = 1,
    time_limit: Annotated[float, typer.Option(help="running time limit, s (VRX: 300)", min=1.0)] = 300.0,
    report: Annotated[Path, typer.Option(help="JSON report path")] = Path("out/task_report.json"),
) -> None:
    """Run a task with the reference solution (our station-keeping controller); prints the score per trial."""
    from usvsim.tasks import TASKS, TaskTiming
    from usvsim.tasks.solutions import run_trial

    try:
        if name not in TASKS:
            raise UsvsimError(f"unknown task {name!r}; choose one of: {', '.join(TASKS)}")
        results = []
        for k in range(trials):
            with console.status(f"{name} difficulty {difficulty}, trial {k + 1}/{trials} (seed {seed + k})"):
                results.append(run_trial(name, difficulty, seed + k, TaskTiming(running_s=time_limit)))
    except UsvsimError as exc:
        fail(exc)
    table = Table("trial", "seed", "score", "collisions", "sim time s", "wall s", box=None)
    for k, r in enumerate(results):
        table.add_row(str(k), str(r["seed"]), f"{r['score']:.4g}", str(r["num_collisions"]),
                      f"{r['sim_time_s']:.1f}", f"{r['wall_time_s']:.1f}")  # fmt: skip
    Console().print(table)
    scores = [r["score"] for r in results]
    summary = {"task": name, "difficulty": difficulty, "trials": results, "mean_score": sum(scores) / len(scores),
               "higher_is_better": results[0]["higher_is_better"]}  # fmt: skip
    report.parent.mkdir(parents=True, exist_ok=True)
    report.write_text(json.dumps(summary, indent=2, default=float))
    typer.echo(f"{name}: mean score {summary['mean_score']:.4g} over {trials} trial(s); wrote {report}")
