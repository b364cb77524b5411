"""numba's cache per version of the package's kernels (usvsim/core/numba_cache.py)."""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import numba

from usvsim.core import numba_cache

CALLEE = "import numba\n\n\n@numba.njit(cache=True)\ndef f():\n    return {}\n"
CALLER = "import numba\nfrom a import f\n\n\n@numba.njit(cache=True)\ndef g():\n    return f() + 10\n"
RUN = """
import sys
sys.path.insert(0, {pkg!r})
if {isolate}:
    from pathlib import Path
    from usvsim.core.numba_cache import isolate
    isolate(Path({pkg!r}), Path({base!r}))
from b import g
print(g())
"""


def run(pkg: Path, base: Path, isolate: bool) -> int:
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    code = RUN.format(pkg=str(pkg), base=str(base), isolate=isolate)
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    return int(out.stdout.split()[-1])


def kernels(tmp_path: Path, name: str) -> Path:
    pkg = tmp_path / name
    pkg.mkdir()
    (pkg / "a.py").write_text(CALLEE.format(1))
    (pkg / "b.py").write_text(CALLER)
    return pkg


def test_a_cached_kernel_calling_a_changed_kernel_of_another_file_is_compiled_afresh(tmp_path):
    base = tmp_path / "cache"
    for isolate in (False, True):  # numba's own cache (in __pycache__), then the package's
        pkg = kernels(tmp_path, f"isolate_{isolate}")
        assert run(pkg, base, isolate) == 11  # compiled and cached
        (pkg / "a.py").write_text(CALLEE.format(2) + "# edited\n")
        # numba alone loads g's cached code, which holds the old f: 11. With the digest: a new directory, 12.
        assert run(pkg, base, isolate) == (12 if isolate else 11)
    assert len(list(base.iterdir())) == 2  # one directory per version of the kernels


def test_a_cache_directory_the_user_chose_is_kept(tmp_path, monkeypatch):
    monkeypatch.setattr(numba.config, "CACHE_DIR", numba.config.CACHE_DIR)  # restored afterwards, as the variables
    monkeypatch.setenv(numba_cache.MARK, os.environ.get(numba_cache.MARK, ""))
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path / "mine"))
    assert numba_cache.isolate(Path(numba_cache.__file__).parents[1], tmp_path / "usvsim") is None
    assert os.environ["NUMBA_CACHE_DIR"] == str(tmp_path / "mine")


def test_the_package_points_numba_at_its_digest_and_old_directories_go(tmp_path, monkeypatch):
    monkeypatch.setattr(numba.config, "CACHE_DIR", numba.config.CACHE_DIR)
    monkeypatch.delenv(numba_cache.MARK, raising=False)
    monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    base, now = tmp_path / "numba", time.time()
    ages = [60.0, 3600.0, 2 * 86400.0, 3 * 86400.0, 4 * 86400.0, 5 * 86400.0, 6 * 86400.0]  # s since last use
    for i, age in enumerate(ages):
        old = base / f"old{i}"
        old.mkdir(parents=True)
        os.utime(old, (now - age, now - age))
    package = Path(numba_cache.__file__).parents[1]
    path = numba_cache.isolate(package, base)
    assert path == base / numba_cache.source_digest(package)
    assert os.environ["NUMBA_CACHE_DIR"] == numba.config.CACHE_DIR == str(path)
    kept = sorted(p.name for p in base.iterdir() if p != path)
    assert kept == [f"old{i}" for i in range(numba_cache.KEEP)]  # the most recent; older than a day beyond: gone
    assert numba_cache.isolate(package, base) == path  # again: the same


def test_the_digest_follows_the_kernels_files_only(tmp_path):
    pkg = kernels(tmp_path, "pkg")
    (pkg / "plain.py").write_text("X = 1\n")
    first = numba_cache.source_digest(pkg)
    (pkg / "plain.py").write_text("X = 2\n")  # no numba in it: the same kernels
    assert numba_cache.source_digest(pkg) == first
    (pkg / "a.py").write_text(CALLEE.format(3))
    assert numba_cache.source_digest(pkg) != first
