"""Run one GIL-free (numba `nogil=True`) kernel call on the second core while the caller works on.

    wait = overlap.submit(kernel_wrapper, *args)   # starts now on the worker thread
    ...                                            # other work in this thread (another nogil kernel)
    result = wait()                                # blocks until the worker is done; re-raises its error

One worker thread that sleeps on a lock between calls (no spinning, unlike numba's parallel backends,
whose spinning workers were measured 30x slower when the machine is loaded). A hand-off costs tens of
microseconds, so use it only for calls of a millisecond or more.
"""

from __future__ import annotations

from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from typing import Any


class Overlap:
    def __init__(self) -> None:
        self._pool: ThreadPoolExecutor | None = None

    def submit(self, fn: Callable[..., Any], *args: Any) -> Callable[[], Any]:
        if self._pool is None:
            self._pool = ThreadPoolExecutor(max_workers=1, thread_name_prefix="usvsim-overlap")
        return self._pool.submit(fn, *args).result

    def close(self) -> None:
        if self._pool is not None:
            self._pool.shutdown(wait=True)
            self._pool = None
