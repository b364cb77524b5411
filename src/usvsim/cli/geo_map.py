"""`usvsim map`: a plan view of a scenario (coast, depth contours, structures, objects, vessels) as PNG."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer


def map_command(
    scenario: Annotated[str, typer.Argument(help="built-in scenario name or YAML file")],
    out: Annotated[Path, typer.Option(help="PNG file to write")] = Path("map.png"),
) -> None:
    """Draw a plan view of a scenario (land, depth contours, structures, objects, vessels) to a PNG."""
    from usvsim.cli.errors import fail as _fail
    from usvsim.core.errors import UsvsimError
    from usvsim.geo.plan import draw_plan
    from usvsim.simulation import Simulation

    try:
        sim = Simulation.from_scenario(scenario)
        draw_plan(sim, out)
    except UsvsimError as exc:
        _fail(exc)
    except OSError as exc:
        _fail(f"cannot write {out}: {exc.strerror}")
    typer.echo(str(out))
