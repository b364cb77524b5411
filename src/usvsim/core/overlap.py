"""Run one GIL-free (numba `nogil=True`) kernel call on the second core while the caller works on.

    wait = overlap.submit(kernel_wrapper, *args)   # starts now on the worker thread
    ...                                            # other work in this thread (another nogil kernel)
    result = wait()                                # blocks until the worker is done; re-raises its error

One worker thread that sleeps on a lock between calls (no spinning, unlike numba's parallel backends,
whose spinning workers were measured 30x slower when the machine is loaded). A hand-off costs tens of
microseconds, so use it only for calls of a millisecond or more.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor
from typing import Any


class Overlap:
    def __init__(self) -> None:
        self._pool: ThreadPoolExecutor | None = None
        self._pid = 0  # the process that started the worker: a forked child (batch/runner.py) starts its own

    def submit(self, fn: Callable[..., Any], *args: Any) -> Callable[[], Any]:
        return self.start(fn, *args).result

    def start(self, fn: Callable[..., Any], *args: Any) -> Future:
        """`submit`, returning the Future (`done()` tells whether waiting would block)."""
        if self._pool is None or self._pid != os.getpid():  # a fork copies the pool but not its thread
            self._pool = ThreadPoolExecutor(max_workers=1, thread_name_prefix="usvsim-overlap")
            self._pid = os.getpid()
        return self._pool.submit(fn, *args)

    def close(self) -> None:
        if self._pool is not None:
            if self._pid == os.getpid():  # (a forked child's copy has no thread to join)
                self._pool.shutdown(wait=True)
            self._pool = None
