"""Helpers shared by the simulation-based hydro experiments: a box hull file and level drafts."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import trimesh

from usvsim.hydro.hydrostatics import HullSet


def write_box(directory: Path, length: float, beam: float, depth: float, name: str = "box.stl") -> Path:
    """A closed box mesh (keel at z = 0, centred in x and y) written as STL; returns its path."""
    box = trimesh.creation.box((length, beam, depth))
    box.apply_translation((0.0, 0.0, depth / 2))
    path = Path(directory) / name
    box.export(path)
    return path


def level_draft(vertices: np.ndarray, faces: np.ndarray, mass_kg: float, rho: float) -> float:
    """Draft T (m, keel z = 0 of the mesh frame) at which the level hull displaces mass/rho (bisection)."""
    hulls = HullSet([(vertices, faces)])
    target = mass_kg / rho
    lo, hi = 0.0, float(np.ptp(np.asarray(vertices)[:, 2]))
    z_keel = float(np.min(np.asarray(vertices)[:, 2]))
    for _ in range(60):
        t = 0.5 * (lo + hi)
        pos = np.array([[0.0, 0.0, -(z_keel + t)]])
        world = hulls.world_vertices(pos, np.eye(3)[None])
        vol = hulls.compute(world, np.zeros(len(world)), pos, rho, 9.81).volume[0]
        lo, hi = (t, hi) if vol < target else (lo, t)
    return 0.5 * (lo + hi)
