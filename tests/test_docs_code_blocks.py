"""Every Python block of the docs runs as written: a page's blocks in order, as one script, in a fresh
process (as a reader would paste them). Pages whose blocks another test runs are named here."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
RUN_ELSEWHERE = {"README.md": "tests/test_docs_and_examples.py", "geo.md": "tests/geo/test_geo_docs.py",
                 "rendering.md": "tests/rendering/test_look_config.py",
                 "tasks.md": "tests/tasks/test_docs_tasks.py"}  # fmt: skip
PAGES = [p for p in sorted((ROOT / "docs").glob("*.md")) if p.name not in RUN_ELSEWHERE and "```python" in p.read_text()]


def python_blocks(page: Path) -> list[str]:
    return re.findall(r"```python\n(.*?)```", page.read_text(), flags=re.DOTALL)


def test_pages_run_elsewhere_are_run_there():
    for page, test in RUN_ELSEWHERE.items():
        assert page in (ROOT / test).read_text(), f"{test} should run the blocks of {page}"


@pytest.mark.parametrize("page", PAGES, ids=[p.name for p in PAGES])
def test_python_blocks_run(page, tmp_path):
    script = tmp_path / f"{page.stem}.py"
    script.write_text("\n".join(python_blocks(page)))
    env = dict(os.environ, MUJOCO_GL=os.environ.get("MUJOCO_GL", "egl"))
    result = subprocess.run([sys.executable, str(script)], cwd=tmp_path, env=env, capture_output=True, text=True,
                            timeout=600)  # fmt: skip
    assert result.returncode == 0, result.stderr[-3000:]
