"""pyright (basic mode, the `[tool.pyright]` settings of pyproject.toml) finds no error in `src/`.

MuJoCo's bindings ship no type information: `typings/mujoco/__init__.pyi` (pyright's default stub path) declares
the names usvsim uses. pyright comes with the `dev` extra; it runs on Node.js, which the `pyright[nodejs]` extra
brings as a wheel (else a `node` on PATH). The check reads files only and takes about a minute on two cores.
Where pyright cannot start the test skips, except in CI (`CI` set), where it fails.
"""

from __future__ import annotations

import importlib.util
import json
import os
import subprocess
import sys
from pathlib import Path
from typing import NoReturn

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _cannot_run(why: str) -> NoReturn:
    """Skip where pyright cannot start; in CI (CI=true, which installs the dev extra) that is a failure."""
    if os.environ.get("CI"):
        pytest.fail(f"pyright must run in CI: {why}")
    pytest.skip(why)


def _pyright_json() -> dict:
    if importlib.util.find_spec("pyright") is None:
        _cannot_run("pyright is not installed (pip install -e '.[dev]')")
    # --pythonpath: resolve third-party imports in the environment running the tests
    cmd = [sys.executable, "-m", "pyright", "--outputjson", "--pythonpath", sys.executable, "src"]
    proc = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, timeout=900)
    try:
        return json.loads(proc.stdout)
    except json.JSONDecodeError:
        # pyright's own start-up failed (no Node.js and no way to fetch one): not a type error to report
        _cannot_run(f"pyright did not run (exit {proc.returncode}): {(proc.stderr or proc.stdout)[-400:]}")


def test_pyright_basic_finds_no_error_in_src():
    report = _pyright_json()
    summary = report["summary"]
    assert summary["filesAnalyzed"] > 100, summary  # it looked at the package, not at an empty selection
    errors = [d for d in report["generalDiagnostics"] if d["severity"] == "error"]
    lines = [
        f"{Path(d['file']).relative_to(ROOT)}:{d['range']['start']['line'] + 1}: {d['message']} ({d.get('rule', '')})"
        for d in errors
    ]
    assert not errors, f"{len(errors)} pyright error(s) in src/:\n" + "\n".join(lines)


def test_the_package_is_marked_typed():
    assert (ROOT / "src" / "usvsim" / "py.typed").is_file()
    pyproject = (ROOT / "pyproject.toml").read_text()
    assert '"py.typed"' in pyproject  # shipped in the wheel (package-data)
