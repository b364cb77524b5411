"""`usvsim map`: a plan view of a scenario or a task (coast, depth contours, structures, objects, traffic
routes, task goals, vessels, a latitude/longitude graticule, recorded tracks) as PNG; a recorded run's tracks
as GeoJSON or CSV with latitudes and longitudes."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated

import typer


def map_command(
    scenario: Annotated[str, typer.Argument(help="built-in scenario name, YAML file, or with --task a task name")],
    out: Annotated[Path, typer.Option(help="PNG file to write")] = Path("map.png"),
    task: Annotated[bool, typer.Option("--task", help="SCENARIO names a task (usvsim task): draw its goals")] = False,
    difficulty: Annotated[int, typer.Option(help="task difficulty 0-2 (with --task)", min=0, max=2)] = 0,
    seed: Annotated[int, typer.Option(help="task layout seed (with --task)", min=0)] = 0,
    contours: Annotated[str | None, typer.Option(
        help="depth contour levels in metres, comma-separated (e.g. 2,5,10,20); default 1,2,5,10,20,50,100,200 "
             "within the place's depths")] = None,  # fmt: skip
    graticule: Annotated[bool, typer.Option(
        help="draw parallels and meridians labelled in degrees and minutes")] = True,  # fmt: skip
    track: Annotated[Path | None, typer.Option(
        help="a recording of this scenario (usvsim run --record): draw each vessel's track")] = None,  # fmt: skip
    track_out: Annotated[Path | None, typer.Option(
        help="write --track's tracks with latitude/longitude: .geojson (a LineString per vessel and episode) or "
             ".csv (a row per pose)")] = None,  # fmt: skip
) -> None:
    """Draw a plan view (land, depth contours, structures, objects, traffic routes, task goals, a lat/lon
    graticule, recorded tracks) to a PNG; write a recording's tracks as GeoJSON or CSV."""
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
    levels = _levels(contours) if contours is not None else None
    _check_track_out(track, track_out)
    try:
        prepare_file(out)
        if track_out is not None:
            prepare_file(track_out)
        marks = []
        if task:
            sim, marks = _task_simulation(scenario, difficulty, seed)
        else:
            sim = Simulation.from_scenario(scenario)
        if levels is not None and sim.place is None:
            raise UsvsimError(f"--contours: {scenario} has no geo: section, so no depths to contour (docs/geo.md)")
        tracks, notes = _tracks(sim, track, track_out)
        notes += draw_plan(sim, out, marks=marks, contours_m=levels, graticule=graticule, tracks=tracks)
    except UsvsimError as exc:
        _fail(exc)
    except OSError as exc:
        _fail(f"cannot write {exc.filename or out}: {exc.strerror}")
    for note in notes:
        typer.echo(f"usvsim: note: {note}", err=True)
    typer.echo(str(out))
    if track_out is not None:
        typer.echo(str(track_out))


def _levels(text: str) -> list[float]:
    from usvsim.cli.errors import fail

    try:
        levels = [float(v) for v in text.split(",")]
    except ValueError:
        fail(f"--contours {text!r}: give depths in metres, comma-separated, e.g. 2,5,10,20")
    bad = [v for v in levels if not (math.isfinite(v) and v > 0)]
    if bad:
        fail(f"--contours {text!r}: {bad[0]:g} is no depth; levels are depths in metres > 0")
    return sorted(set(levels))


def _check_track_out(track: Path | None, track_out: Path | None) -> None:
    from usvsim.cli.errors import fail
    from usvsim.geo.track import TRACK_SUFFIXES

    if track_out is not None and track is None:
        fail("--track-out needs --track RECORDING (the run whose tracks to write)")
    if track_out is not None and track_out.suffix.lower() not in TRACK_SUFFIXES:
        fail(f"--track-out {track_out}: unknown format {track_out.suffix!r}; use .geojson or .csv")


def _tracks(sim, track: Path | None, track_out: Path | None):
    """The recording's tracks and notes; the --track-out file written."""
    if track is None:
        return [], []
    from usvsim.geo.resolve import frame_of
    from usvsim.geo.track import read_tracks, tracks_text

    tracks, notes = read_tracks(track, sim.world.odom_origin)
    if track_out is not None:
        track_out.write_text(tracks_text(tracks, frame_of(sim.scenario), track_out.suffix.lower()))
    return tracks, notes


def _task_simulation(name: str, difficulty: int, seed: int):
    """The task's scenario as a simulation and its plan marks (`Task.plan_marks`)."""
    from usvsim.core.errors import UsvsimError
    from usvsim.simulation import Simulation
    from usvsim.tasks import TASKS

    if name not in TASKS:
        raise UsvsimError(f"no task '{name}' (tasks: {', '.join(TASKS)})")
    task = TASKS[name](difficulty, seed)
    return Simulation(task.scenario(), seed=seed), task.plan_marks()
