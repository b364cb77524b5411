"""Output files of the CLI: never overwritten without `--force`; clear one-line errors before any work."""

from __future__ import annotations

import os
from pathlib import Path

from usvsim.core.errors import UsvsimError


def check_output(path: Path, force: bool) -> None:
    """Raise a UsvsimError unless `path` can be the MCAP recording asked for: a file name ending in .mcap whose parent
    directory exists and is writable, and an existing file is replaced only with `force`."""
    if path.is_dir():
        raise UsvsimError(f"{path} is a directory; give a file name ending in .mcap")
    if path.suffix.lower() != ".mcap":  # `--record run.txt` wrote an MCAP that ROS 2 and Foxglove do not open as one
        raise UsvsimError(f"{path}: a recording is an MCAP file; give a file name ending in .mcap")
    if path.exists() and not force:
        raise UsvsimError(f"{path} exists; pass --force to overwrite it")
    parent = path.parent if str(path.parent) else Path(".")
    if not parent.is_dir():
        raise UsvsimError(f"directory {parent} does not exist; create it first")
    if (path.exists() and not os.access(path, os.W_OK)) or not os.access(parent, os.W_OK):
        raise UsvsimError(f"cannot write {path}: permission denied")


def prepare_file(path: Path) -> None:
    """For a report a command writes when its work is done (an existing file is replaced): create its folder and
    check that it can be written now, so that a bad path is a one-line UsvsimError before any work, not a
    traceback after it."""
    if path.is_dir():
        raise UsvsimError(f"{path} is a directory; give a file name")
    _make_folder(path.parent if str(path.parent) else Path("."))
    if path.exists() and not os.access(path, os.W_OK):
        raise UsvsimError(f"cannot write {path}: permission denied")


def prepare_folder(path: Path) -> None:
    """Create an output folder (and its parents), or raise a one-line UsvsimError."""
    if path.exists() and not path.is_dir():
        raise UsvsimError(f"{path} is a file; give a folder")
    _make_folder(path)


def _make_folder(folder: Path) -> None:
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise UsvsimError(f"cannot create the folder {folder}: {exc.strerror or exc}") from None
    if not os.access(folder, os.W_OK):
        raise UsvsimError(f"cannot write in {folder}: permission denied")
