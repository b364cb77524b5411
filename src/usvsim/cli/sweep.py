"""`usvsim sweep SPEC.yaml`: task runs over seeds and parameter grids, locally or on Ray; writes JSON lines."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

from usvsim.cli.errors import console, fail
from usvsim.core.errors import UsvsimError


def sweep(
    spec: Annotated[Path, typer.Argument(help="sweep YAML (see usvsim.batch.spec)")],
    out: Annotated[Path, typer.Option(help="results, one JSON object per run")] = Path("out/sweep.jsonl"),
    backend: Annotated[str | None, typer.Option(help="process or ray (default: the file's)")] = None,
    workers: Annotated[int | None, typer.Option(help="parallel workers (default: the file's, else CPUs)", min=1)] = None,
) -> None:
    """Run a sweep: tasks × difficulties × grid × seeds with the reference solution; prints mean scores."""
    import yaml
    from pydantic import ValidationError

    from usvsim.batch import expand, failed, run
    from usvsim.batch.spec import SweepSpec
    from usvsim.cli.outputs import prepare_file
    from usvsim.cli.stopping import Stopped, StopSignals, exit_status, signal_name
    from usvsim.config import safe_yaml

    try:
        if not spec.is_file():  # was "[Errno 2] No such file or directory: 'nosuch.yaml'"
            raise UsvsimError(f"{spec}: {'a directory, not' if spec.is_dir() else 'no such'} sweep file (a YAML "
                              "file with task, seeds, difficulty, grid; docs/tasks.md)")  # fmt: skip
        try:
            data = yaml.load(spec.read_text(), Loader=safe_yaml.Loader)
            if not isinstance(data, dict):  # pydantic said "Input should be a valid dictionary or instance of SweepSpec"
                raise UsvsimError(f"{spec}: {'is empty' if data is None else 'is not a mapping'}: a sweep file is a YAML "
                                  "mapping (task, seeds, difficulty, grid; docs/tasks.md)")  # fmt: skip
            config = SweepSpec.model_validate(data)
        except (OSError, yaml.YAMLError, ValidationError) as exc:
            raise UsvsimError(f"{spec}: {_first_error(exc)}") from None
        runs = expand(config)
        prepare_file(out)  # a bad --out path fails now, not after every run
        columns = (TextColumn("sweep"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn())
        finished: list[dict | None] = [None] * len(runs)
        signum, broken = 0, None
        # Ctrl-C or SIGTERM: the runs still going are ended and not written (a run is scored whole), the finished
        # ones are (they were lost, and forked workers went on running after the sweep's process had gone)
        with StopSignals() as stop, Progress(*columns, console=console, transient=True) as bar:
            job = bar.add_task("runs", total=len(runs))
            try:
                run(runs, backend or config.backend, workers or config.workers, config.address,
                    progress=lambda done, total: bar.update(job, completed=done), stop=stop.check,
                    finished=finished)  # fmt: skip
            except Stopped as exc:
                signum = exc.signum
            except UsvsimError:  # the sweep could not start (backend, workers, Ray missing)
                raise
            except Exception as exc:  # the sweep broke (a worker killed): keep what was finished
                broken = exc
        results = [r for r in finished if r is not None]
    except UsvsimError as exc:
        fail(exc)
    lines = "".join(json.dumps(r, default=float) + "\n" for r in results)
    try:
        out.write_text(lines)
    except OSError as exc:
        typer.echo(lines, nl=False)  # nothing lost: the results go to stdout instead
        fail(f"cannot write {out}: {exc.strerror or exc}; the results were printed to stdout instead")
    errors = failed(results)
    groups = mean_scores([r for r in results if "error" not in r])
    _print_table(groups)
    if broken is not None:
        fail(f"the sweep stopped: {type(broken).__name__}: {broken}; wrote the {len(results)} of {len(runs)} runs "
             f"finished to {out}")  # fmt: skip
    mean = "no score" if not groups else (f"mean score {groups[0]['mean_score']:.4g}" if len(groups) == 1
                                          else f"mean scores of {len(groups)} configurations above")  # fmt: skip
    if signum:
        typer.echo(f"stopped ({signal_name(signum)}): {len(results)} of {len(runs)} runs finished, {mean}; wrote "
                   f"them to {out} (the runs under way are not scored)")  # fmt: skip
        raise typer.Exit(exit_status(signum))
    if errors:
        for r in errors[:5]:
            typer.echo(f"failed: {_describe(r['run'])}: {r['error']}", err=True)
        more = f" ({len(errors) - 5} more in {out})" if len(errors) > 5 else ""
        typer.echo(f"{len(errors)} of {len(results)} runs failed{more}; the others: {mean}; wrote {out}")
        raise typer.Exit(1)
    typer.echo(f"{len(results)} runs, {mean}; wrote {out}")


def _describe(run: dict) -> str:
    """A run in one line: task, level, the grid values set, seed."""
    grid = [f"{k}={run[k]:g}" for k in ("sea_state", "mass_kg") if run.get(k) is not None]
    grid += [f"{k}={v:g}" for k, v in run.get("hold") or ()]
    return " ".join([f"{run['task']} level {run['difficulty']}", *grid, f"seed {run['seed']}"])


def mean_scores(results: list[dict]) -> list[dict]:
    """The mean score per configuration (the run without its seed), in run order: one mean over every run
    mixed tasks (metres with gate points) and levels into one meaningless number."""
    groups: dict[str, dict] = {}
    for r in results:
        config = {k: v for k, v in r["run"].items() if k != "seed"}
        key = json.dumps(config, sort_keys=True, default=float)
        g = groups.setdefault(key, {**config, "higher_is_better": r["higher_is_better"], "scores": [],
                                    "collisions": 0})  # fmt: skip
        g["scores"].append(r["score"])
        g["collisions"] += r["num_collisions"]
    return [g | {"runs": len(g["scores"]), "mean_score": sum(g["scores"]) / len(g["scores"])} for g in groups.values()]


def _print_table(groups: list[dict]) -> None:
    """One row per configuration; the sea state, mass and hold columns only where the sweep varies them."""
    from rich.console import Console
    from rich.table import Table

    if not groups:
        return
    optional = {"sea_state": "sea state", "mass_kg": "mass kg", "hold": "hold"}
    shown = [k for k in optional if any(g[k] not in (None, [], ()) for g in groups)]
    table = Table(box=None)
    for title in ("task", "level", *(optional[k] for k in shown), "runs", "mean score", "better", "collisions"):
        table.add_column(title, overflow="fold", no_wrap=title == "task")
    for g in groups:
        cells = {"sea_state": _or_dash(g["sea_state"]), "mass_kg": _or_dash(g["mass_kg"]),
                 "hold": ", ".join(f"{k}={v:g}" for k, v in g["hold"]) or "-"}  # fmt: skip
        table.add_row(g["task"], str(g["difficulty"]), *(cells[k] for k in shown), str(g["runs"]),
                      f"{g['mean_score']:.4g}", "higher" if g["higher_is_better"] else "lower", str(g["collisions"]))  # fmt: skip
    Console().print(table)


def _or_dash(value) -> str:
    return "-" if value is None else f"{value:g}"


def _first_error(exc: Exception) -> str:
    from pydantic import ValidationError

    if isinstance(exc, ValidationError):
        errors = exc.errors()  # a union (seeds: list or {start, count}) fails in every branch: the first error
        # said the list branch's "Input should be a valid list" for a {start, count} with a bad count
        e = next((x for x in errors if not x["type"].endswith("_type")), errors[0])
        where = ".".join(str(p) for p in e["loc"] if not (isinstance(p, str) and (p[:1].isupper() or "[" in p)))
        message = e["msg"].removeprefix("Value error, ")
        if e["type"] == "extra_forbidden":
            from difflib import get_close_matches

            from usvsim.batch.spec import Grid, SweepSpec

            fields = Grid.model_fields if e["loc"][:1] == ("grid",) else SweepSpec.model_fields
            close = get_close_matches(str(e["loc"][-1]), list(fields), n=1)
            message = "unknown key" + (f" (did you mean {close[0]!r}?)" if close else f"; keys: {', '.join(fields)}")
        return f"{where}: {message}" if where else message
    import yaml

    if isinstance(exc, yaml.YAMLError):  # str() is several lines with the excerpt; one line as for scenarios
        mark = getattr(exc, "problem_mark", None)
        problem = str(getattr(exc, "problem", None) or "syntax error")[:120]
        return f"line {mark.line + 1}: not valid YAML: {problem}" if mark else f"not valid YAML: {problem}"
    return str(exc)
