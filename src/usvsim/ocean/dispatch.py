"""Serial and parallel builds of one per-point kernel; the serial one answers every query by default.

Every per-point kernel is written once with `prange` and compiled twice on demand: serial (`prange` runs as
`range`) and parallel, both cached on disk. The parallel build is compiled from a renamed copy of the
function: numba's cache is keyed by the function's qualified name and signature, not by the `parallel` flag,
so two builds of one function shared one cache entry and whichever compiled first answered for both (which
is why the "parallel" kernel used to be exactly as fast as the serial one at every size).

Measured with both builds real (benchmarks/bench_seas.py, `query_kernel_crossover_us`; 2 cores shared with
other jobs, load 5-6): numba's thread pool is never reliably faster here and is ruinous when the other
core is busy (1,000 points: 20 ms instead of 0.06 ms; 112,000 hull faces: 16 ms instead of 1 ms; 256,000
points: 1.3x slower); the issue's fresh 2-core machine saw 1.4-1.9x slower at 112,800 points. So there is
no size threshold: `pick` returns the serial kernel unless `PARALLEL_MIN_POINTS` is set (a quiet machine
with cores to spare may set it after measuring with the benchmark).
"""

from __future__ import annotations

import types

from numba import njit

PARALLEL_MIN_POINTS: int | None = None  # no batch size is reliably faster with threads on a shared 2-core box


def _renamed(fn, suffix: str):
    """A copy of function `fn` whose (qualified) name ends with `suffix`: its own numba cache entry."""
    copy = types.FunctionType(
        fn.__code__, fn.__globals__, fn.__name__ + suffix, fn.__defaults__, fn.__closure__
    )
    copy.__qualname__ = fn.__qualname__ + suffix
    copy.__doc__, copy.__module__ = fn.__doc__, fn.__module__
    return copy


def serial_and_parallel(fn):
    """(serial, parallel) compiled versions of a numba-compatible function that uses `prange`."""
    return njit(cache=True)(fn), njit(parallel=True, cache=True)(_renamed(fn, "_parallel"))


def pick(kernels, n_points: int):
    """The serial kernel, or the parallel one from PARALLEL_MIN_POINTS points up when that is set."""
    return kernels[1] if PARALLEL_MIN_POINTS is not None and n_points >= PARALLEL_MIN_POINTS else kernels[0]
