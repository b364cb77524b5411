"""`usvsim schema`: the scenario file's JSON Schema (editor completion), or its Markdown reference."""

from __future__ import annotations

from typing import Annotated

import typer


def schema_command(
    reference: Annotated[bool, typer.Option(help="print the Markdown reference (docs/scenario-reference.md)")] = False,
) -> None:
    """Print the JSON Schema of scenario files; for the YAML language server put
    `# yaml-language-server: $schema=<file>` on a scenario's first line."""
    from usvsim.config.schema import reference_markdown, schema_json

    typer.echo(reference_markdown() if reference else schema_json(), nl=False)
