"""Serial and parallel builds of one per-point kernel, chosen by batch size.

A physics step queries a few thousand points; handing them to numba's thread pool costs more than it
saves, and on a loaded 2-core machine it is ruinous (measured: 26 ms instead of 0.74 ms per wavy
step). Large batches (rendering grids, benchmarks) do gain from threads. So every per-point kernel is
written once with `prange` and compiled twice: serial (cached; `prange` runs as `range`) and
parallel (compiled on first use), and `pick(kernels, n)` chooses by the number of points.
"""

from __future__ import annotations

from numba import njit

PARALLEL_MIN_POINTS = 65_536


def serial_and_parallel(fn):
    """(serial, parallel) compiled versions of a numba-compatible function that uses `prange`."""
    return njit(cache=True)(fn), njit(parallel=True, cache=True)(fn)


def pick(kernels, n_points: int):
    """The serial kernel for small batches, the parallel one from PARALLEL_MIN_POINTS points up."""
    return kernels[1] if n_points >= PARALLEL_MIN_POINTS else kernels[0]
