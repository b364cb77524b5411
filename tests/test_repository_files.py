"""The checkout holds only files with portable names: a stray file named after a line of code (left by a shell
redirect gone wrong, e.g. `ater_depth_m: Annotated[...] | None`) cannot be checked out on Windows or macOS
case-insensitive volumes and breaks `pip install` from an sdist."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
NOT_PORTABLE = set('<>:"|?*\\')


@pytest.mark.skipif(shutil.which("git") is None or not (ROOT / ".git").exists(), reason="not a git checkout")
def test_tracked_file_names_are_portable():
    names = subprocess.run(["git", "-C", str(ROOT), "ls-files", "-z"], capture_output=True, check=True).stdout
    paths = [p for p in names.decode().split("\0") if p]
    assert len(paths) > 100  # the listing worked
    bad = [p for p in paths if NOT_PORTABLE & set(p) or p != p.strip() or any(ord(c) < 32 for c in p)]
    assert bad == []
