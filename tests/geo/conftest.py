"""Fixtures of the geo tests: the sample place written once per module, and a geo cache of each test's own."""

from __future__ import annotations

import pytest
from place import write_place


@pytest.fixture(scope="module")
def place(tmp_path_factory):
    return write_place(tmp_path_factory.mktemp("place"))


@pytest.fixture(autouse=True)
def _own_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("USVSIM_CACHE", str(tmp_path / "cache"))
