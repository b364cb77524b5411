"""Helpers shared by the simulation-based hydro experiments: a box hull file."""

from __future__ import annotations

from pathlib import Path

import trimesh


def write_box(directory: Path, length: float, beam: float, depth: float, name: str = "box.stl") -> Path:
    """A closed box mesh (keel at z = 0, centred in x and y) written as STL; returns its path."""
    box = trimesh.creation.box((length, beam, depth))
    box.apply_translation((0.0, 0.0, depth / 2))
    path = Path(directory) / name
    box.export(path)
    return path
