"""Output files of the CLI: never overwritten without `--force`; clear one-line errors before any work."""

from __future__ import annotations

import os
from pathlib import Path

from usvsim.core.errors import UsvsimError


def check_output(path: Path, force: bool) -> None:
    """Raise a UsvsimError unless `path` can be (re)written: parent directory exists and is writable, the
    path is not a directory, and an existing file is replaced only with `force`."""
    if path.is_dir():
        raise UsvsimError(f"{path} is a directory; give a file name ending in .mcap")
    if path.exists() and not force:
        raise UsvsimError(f"{path} exists; pass --force to overwrite it")
    parent = path.parent if str(path.parent) else Path(".")
    if not parent.is_dir():
        raise UsvsimError(f"directory {parent} does not exist; create it first")
    if (path.exists() and not os.access(path, os.W_OK)) or not os.access(parent, os.W_OK):
        raise UsvsimError(f"cannot write {path}: permission denied")
