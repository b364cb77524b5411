"""`usvsim dataset`: a labelled image data set (YOLO, COCO, masks) from a scenario's cameras."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer
from rich.console import Console
from rich.markup import escape
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeRemainingColumn

from usvsim.core.errors import UsvsimError


def dataset_command(
    scenario: Annotated[str, typer.Argument(help="built-in scenario name or YAML file (needs a camera)")],
    frames: Annotated[int, typer.Option(help="frames per camera", min=1)] = 100,
    out: Annotated[str, typer.Option(help="output folder")] = "dataset",
    format: Annotated[
        str, typer.Option("--format", help="comma-separated: yolo, coco, masks")
    ] = "yolo,coco,masks",
    seed: Annotated[int, typer.Option(help="random seed: the same seed writes the same bytes", min=0)] = 0,
    randomize: Annotated[
        str | None, typer.Option(help="randomization YAML file or preset (clear_calm, foggy_wavy)")
    ] = None,
    resolution: Annotated[str | None, typer.Option(help="WIDTHxHEIGHT for every camera")] = None,
    splits: Annotated[str, typer.Option(help="train,val,test fractions")] = "0.8,0.1,0.1",
    min_visible_pixels: Annotated[int, typer.Option(
        help="leave out objects with fewer visible pixels (in fog: pixels that keep at least 2 % of their contrast, "
        "docs/datasets.md)")] = 20,
    min_visible_fraction: Annotated[
        float, typer.Option(help="leave out objects with a smaller visible_fraction (visible pixels / pixels of the "
                                 "object drawn alone, 0-1)")
    ] = 0.0,
    renderer: Annotated[
        str | None, typer.Option(help="shader (the marine look: sky, waves, fog) or mujoco; default: the scenario's")
    ] = None,
    coco_segmentation: Annotated[
        str, typer.Option(help="COCO segmentation: rle (uncompressed), compressed_rle or polygon (Detectron2's "
                               "default, Ultralytics' converter); all exact")
    ] = "rle",
    yolo_labels: Annotated[
        str, typer.Option(help="YOLO label lines: box (class cx cy w h) or segment (class and the object's polygon, "
                               "Ultralytics' segmentation format)")
    ] = "box",
    force: Annotated[
        bool, typer.Option("--force", help="replace the data set already in --out (its files only)")
    ] = False,
) -> None:
    """Render a scenario's cameras with domain randomization and write images, labels and masks. Ctrl-C or
    SIGTERM stops it between two frames: the frames begun are written and the annotations, data.yaml and
    dataset.json describe exactly those (exit status 130 or 143)."""
    from usvsim.cli.outputs import prepare_folder
    from usvsim.cli.stopping import StopSignals, exit_status, signal_name
    from usvsim.config.loader import load_scenario
    from usvsim.datasets.generate import DatasetGenerator, DatasetSpec, clear_previous
    from usvsim.datasets.randomization import load_randomization

    console = Console(stderr=True)
    stop = StopSignals()
    size, fractions, error = None, (0.8, 0.1, 0.1), None
    try:  # one message named both options, whichever was wrong
        wh = [int(v) for v in resolution.lower().split("x")] if resolution else None
        if wh is not None and len(wh) != 2:
            raise ValueError
        size = (wh[0], wh[1]) if wh else None
    except ValueError:
        error = f"--resolution {resolution!r}: give WIDTHxHEIGHT in pixels, e.g. 640x480"
    try:
        values = [float(v) for v in splits.split(",")]
        if len(values) != 3:
            raise ValueError
        fractions = (values[0], values[1], values[2])
    except ValueError:
        error = error or f"--splits {splits!r}: give three fractions train,val,test summing to 1, e.g. 0.8,0.1,0.1"
    if not out.strip():  # an empty --out (an unset shell variable) wrote the set into the current folder
        error = error or "--out is empty: give the output folder (--out . for the current one)"
    if error:
        console.print(f"[bold red]usvsim: error:[/] {escape(error)}", highlight=False, soft_wrap=True)
        raise typer.Exit(2)
    folder = Path(out)
    try:
        spec = DatasetSpec(scenario, frames, folder, tuple(f.strip() for f in format.split(",")), seed, randomize,
                           size, fractions, min_visible_pixels, min_visible_fraction, renderer=renderer,
                           coco_segmentation=coco_segmentation, yolo_labels=yolo_labels)  # fmt: skip
        load_scenario(scenario), load_randomization(randomize)  # bad input fails before the folder is made
        columns = (TextColumn("dataset"), BarColumn(), MofNCompleteColumn(), TimeRemainingColumn())
        written = [0]

        def progress(n: int) -> None:
            written[0] = n
            bar.update(task, completed=n)

        # SIGTERM used to end the process mid-frame: files cut short, no annotations, data.yaml or dataset.json
        with stop:
            gen = DatasetGenerator(spec)  # the scenario's cameras, the look keys and the drawn environment are
            try:  # checked here, before the folder is made (an empty --out folder was left behind)
                prepare_folder(folder)
                clear_previous(folder, force)
                with Progress(*columns, console=console, transient=True, disable=not console.is_terminal) as bar:
                    task = bar.add_task("frames", total=frames)  # the bar is gone when done: an error stays one line
                    gen.run(progress=progress, stop=lambda: signal_name(stop.signum) if stop.signum else None)
            finally:
                gen.close()
    except UsvsimError as exc:
        console.print(f"[bold red]usvsim: error:[/] {escape(str(exc))}", highlight=False, soft_wrap=True)
        raise typer.Exit(2) from None
    if stop.signum:
        typer.echo(f"stopped ({signal_name(stop.signum)}): wrote {written[0]} of {frames} frames to {out}; its "
                   "annotations, data.yaml and dataset.json cover those frames (dataset.json: stopped, frames_requested)")  # fmt: skip
        raise typer.Exit(exit_status(stop.signum))
    typer.echo(f"wrote {frames} frame{'s' if frames != 1 else ''} to {out}")  # the result on stdout, progress on stderr
    if randomize is None:  # after the run: an error stays one line
        console.print(f"usvsim: note: no --randomize: nothing was drawn; every frame is the scenario as written, "
                      f"{spec.settle_s:g} s after a reset (only a wavy sea's phases differ); give --randomize "
                      "clear_calm, foggy_wavy or a file", highlight=False, soft_wrap=True)  # fmt: skip

