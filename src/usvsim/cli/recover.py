"""`usvsim recover FILE`: rewrite the readable part of a recording cut short into a complete MCAP."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from usvsim.cli.errors import fail
from usvsim.core.errors import UsvsimError


def recover(
    file: Annotated[Path, typer.Argument(help="an MCAP recording cut short (kill -9, disk full)")],
    out: Annotated[Path | None, typer.Option(help="output file (default: FILE with .recovered.mcap)")] = None,
    force: Annotated[bool, typer.Option("--force", help="overwrite the output file")] = False,
) -> None:
    """Recover a recording: every complete chunk (flushed at least every 0.5 s simulated) into a new file."""
    from usvsim.cli.outputs import check_output
    from usvsim.io.mcap_recover import recover as recover_file

    target = out or file.with_suffix(".recovered.mcap")
    try:
        if not file.is_file():
            raise UsvsimError(f"{file} is a directory, not a recording (an .mcap file)" if file.is_dir()
                              else f"no such recording: {file}")  # a directory said 'no such recording'
        check_output(target, force)
        result = recover_file(file, target)
    except (UsvsimError, OSError) as exc:
        fail(exc)
    state = "was complete" if result.complete else "was cut short"
    typer.echo(f"{file} {state}: recovered {result.messages} messages up to t = {result.end_ns / 1e9:.3f} s "
               f"into {result.path}")  # fmt: skip
