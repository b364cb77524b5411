"""numba's on-disk cache in a directory of its own per version of the package's kernels.

numba keys a cached kernel on the contents of its own file only. A kernel that calls (and so inlines) a kernel of
another file keeps its cached machine code when that other file changes, after an update or an edit, and runs the
old code without a word: `hydro/fused.py` inlines the wave queries of `ocean/fft_kernels.py`, and after the FFT
snapshots went from four to eight per query a cached fused pass still blended four (its motion differed from the
three separate passes it must equal bit for bit). So `usvsim` points numba's cache (`NUMBA_CACHE_DIR`) at
`~/.cache/usvsim/numba/<digest>` (or under `$XDG_CACHE_HOME`), the digest a hash of every source file of the package
that uses numba: a change to any of them compiles afresh. Kernels that read a constant from a file without numba are
not covered. A `NUMBA_CACHE_DIR` of the user's own is left as it is. Directories of other versions are removed once
unused for a day, but for the `KEEP` most recently used.
"""

from __future__ import annotations

import hashlib
import os
import shutil
import sys
import time
from pathlib import Path

KEEP = 4  # directories of other source versions kept (the most recently used), e.g. for other checkouts
STALE_S = 86_400.0  # older directories than that, beyond KEEP, are removed
MARK = "USVSIM_NUMBA_CACHE_DIR"  # the NUMBA_CACHE_DIR this module chose (not the user's)


def cache_base() -> Path:
    return Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "usvsim" / "numba"


def source_digest(package_dir: Path) -> str:
    """A hash of the relative paths and contents of the package's Python files that mention numba."""
    digest = hashlib.sha256()
    for dirpath, dirs, files in os.walk(package_dir):
        dirs.sort()
        for name in sorted(files):
            if name.endswith(".py"):
                path = os.path.join(dirpath, name)
                with open(path, "rb") as f:
                    text = f.read()
                if b"numba" in text:
                    digest.update(os.path.relpath(path, package_dir).encode() + b"\0" + text + b"\0")
    return digest.hexdigest()[:16]


def isolate(package_dir: Path, base: Path | None = None) -> Path | None:
    """Point numba's cache at `base/<source_digest(package_dir)>` (before the kernels are made); None when the user
    set NUMBA_CACHE_DIR elsewhere. Safe to call again (the same directory)."""
    base = cache_base() if base is None else base
    chosen = os.environ.get("NUMBA_CACHE_DIR")
    if chosen and chosen != os.environ.get(MARK) and not Path(chosen).is_relative_to(base):
        return None  # the user's
    path = base / source_digest(package_dir)
    try:
        path.mkdir(parents=True, exist_ok=True)
        os.utime(path)  # in use: the most recent
        _prune(base, path)
    except OSError:  # not writable: numba falls back to the __pycache__ folders next to the sources
        return None
    os.environ["NUMBA_CACHE_DIR"] = os.environ[MARK] = str(path)  # read when numba is imported, and by children
    numba = sys.modules.get("numba")
    if numba is not None:  # already imported: its config is read when each kernel is decorated
        numba.config.CACHE_DIR = str(path)
    return path


def _prune(base: Path, keep: Path) -> None:
    others = sorted((p for p in base.iterdir() if p.is_dir() and p != keep), key=lambda p: p.stat().st_mtime,
                    reverse=True)  # fmt: skip
    now = time.time()
    for old in others[KEEP:]:
        if now - old.stat().st_mtime > STALE_S:
            shutil.rmtree(old, ignore_errors=True)
