"""Shared test fixtures: small scenarios built in memory, and mesh files written to tmp dirs."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from usvsim.config.loader import parse_scenario


@pytest.fixture
def scenario_of():
    """Build a validated scenario from a dict, with `version: 1` filled in."""

    def make(data: dict, base_dir=None):
        return parse_scenario({"version": 1, **data}, "test", base_dir)

    return make


@pytest.fixture
def box_stl(tmp_path):
    """A closed 2 x 1 x 1 m box hull (base at z = 0) as an STL file."""
    box = trimesh.creation.box(extents=(2.0, 1.0, 1.0))
    box.apply_translation((0.0, 0.0, 0.5))
    path = tmp_path / "box.stl"
    box.export(path)
    return path


@pytest.fixture
def open_stl(tmp_path):
    """A box with one face removed: not watertight."""
    box = trimesh.creation.box(extents=(2.0, 1.0, 1.0))
    mesh = trimesh.Trimesh(box.vertices, np.asarray(box.faces)[:-1], process=False)
    path = tmp_path / "open.stl"
    mesh.export(path)
    return path
