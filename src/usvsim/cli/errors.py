"""How every CLI command reports a usvsim error: one line on stderr, exit status 2. Command modules import
`fail` from here (not from `cli.app`, which imports them: that would be an import cycle)."""

from __future__ import annotations

from typing import NoReturn

import typer
from rich.console import Console
from rich.markup import escape

console = Console(stderr=True)


def fail(exc: Exception | str) -> NoReturn:
    console.print(f"[bold red]usvsim: error:[/] {escape(str(exc))}", highlight=False, soft_wrap=True)
    raise typer.Exit(2)
