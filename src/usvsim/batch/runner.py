"""Run many task trials: `expand(spec)` → runs, `run(runs, backend=...)` → one metrics dict per run, in order.

Backends: `process` (local processes, the default) and `ray` (a local Ray instance, or a cluster at
`address`; extra `ray`). Every worker runs numba with one thread, so results are bit-identical whatever
the backend and the number of workers (the run's `wall_time_s` aside).

A run that fails (a divergence, a bad value, a bug) does not end the sweep: its place holds
`{"run": spec, "error": "DivergenceError: ..."}` and the other runs go on (`failed(results)` lists them).
"""

from __future__ import annotations

import itertools
import multiprocessing
import os
import signal
from collections.abc import Callable, Sequence
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from dataclasses import asdict, dataclass

from usvsim.batch.spec import SweepSpec
from usvsim.core.errors import UsvsimError


@dataclass(frozen=True)
class RunSpec:
    task: str
    difficulty: int = 0
    seed: int = 0
    time_limit_s: float = 60.0
    sea_state: int | None = None
    mass_kg: float | None = None
    hold: tuple[tuple[str, float], ...] = ()


def expand(spec: SweepSpec | dict) -> list[RunSpec]:
    """The product of tasks × difficulties × grid values × seeds (seeds vary fastest)."""
    spec = spec if isinstance(spec, SweepSpec) else SweepSpec.model_validate(spec)
    as_list = lambda v: v if isinstance(v, list) else [v]  # noqa: E731
    g = spec.grid
    hold_keys = sorted(g.hold)
    holds = [tuple(zip(hold_keys, values)) for values in itertools.product(*(g.hold[k] for k in hold_keys))]
    axes = (as_list(spec.task), as_list(spec.difficulty), g.sea_state, g.mass_kg, holds, spec.seed_list())
    return [RunSpec(task, d, seed, spec.time_limit_s, sea, mass, hold)
            for task, d, sea, mass, hold, seed in itertools.product(*axes)]  # fmt: skip


def run_one(spec: RunSpec, after_step: Callable[[], None] | None = None) -> dict:
    """One run in this process (numba with one thread): the reference solution's trial report + the run.
    `after_step()` runs after every physics step (an exception from it ends the run)."""
    from usvsim.tasks.solutions import run_trial
    from usvsim.tasks.timing import TaskTiming, limit_numba_threads

    limit_numba_threads(1)
    report = run_trial(spec.task, spec.difficulty, spec.seed, TaskTiming(running_s=spec.time_limit_s),
                       spec.sea_state, spec.mass_kg, dict(spec.hold), after_step=after_step)  # fmt: skip
    return {"run": asdict(spec), **report}


def run_or_error(spec: RunSpec, after_step: Callable[[], None] | None = None) -> dict:
    """`run_one`, or `{"run": spec, "error": "Type: message"}` for a run that raised: one failed run (a divergence
    in one grid corner) ended the whole sweep and lost every other run's result. A stop (KeyboardInterrupt, the
    CLI's Stopped) is not a failure: it propagates."""
    try:
        return run_one(spec, after_step)
    except Exception as exc:
        return {"run": asdict(spec), "error": f"{type(exc).__name__}: {exc}"}


def failed(results: Sequence[dict | None]) -> list[dict]:
    """The results of runs that failed (they hold "error" instead of a score)."""
    return [r for r in results if r is not None and "error" in r]


def run(runs: Sequence[RunSpec], backend: str = "process", workers: int | None = None, address: str | None = None,
        progress: Callable[[int, int], None] | None = None, stop: Callable[[], None] | None = None,
        finished: list[dict | None] | None = None) -> list[dict]:  # fmt: skip
    """Metrics of every run, in the order of `runs` (a failed run: its "error", see `run_or_error`); `workers` ≥ 1,
    default the CPU count. `progress(done, total)` is called as runs finish. `stop()`
    is called between runs (and, in this process, between steps; a few times a second while waiting on workers):
    an exception from it ends the sweep, the workers stopped, and propagates; `finished`, if given (a list of
    len(runs)), holds each run's result as it comes in, so the caller keeps what was done."""
    if workers is None:
        workers = os.cpu_count() or 1
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:  # 0 silently meant every CPU
        raise UsvsimError(f"workers must be a whole number >= 1 (default: the CPU count), not {workers!r}")
    out: list[dict | None] = [None] * len(runs) if finished is None else finished
    if backend == "process":
        return _process(runs, workers, progress, stop or _never, out)
    if backend == "ray":
        return _ray(runs, workers, address, progress, stop or _never, out)
    raise UsvsimError(f"unknown backend {backend!r}; choose process or ray")


def _never() -> None:
    return None


def warm_up() -> None:
    """Import the simulation and load its compiled kernels (numba's on-disk cache) in this process, with a
    0.1 s trial: about 2 s of CPU per process (imports ~1.3 s, kernels and a model ~0.9 s). The process
    backend does it once, before it forks its workers, so every worker starts warm instead of paying it
    again (CPU that workers sharing the cores with other work would otherwise spend in parallel)."""
    from usvsim.tasks.solutions import run_trial
    from usvsim.tasks.timing import TaskTiming, limit_numba_threads

    limit_numba_threads(1)
    run_trial("station_keeping", timing=TaskTiming(running_s=0.1))


def _pool(workers: int) -> ProcessPoolExecutor:
    """Forked from this (warm) process where the platform can fork; else fresh workers warm up once each. Workers
    leave Ctrl-C to this process (a terminal sends it to all of them), which stops them itself."""
    if "fork" in multiprocessing.get_all_start_methods():
        return ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("fork"),
                                   initializer=_ignore_interrupt)  # fmt: skip
    return ProcessPoolExecutor(max_workers=workers, initializer=_warm_worker)


def _ignore_interrupt() -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)  # a fork copies the parent's stop handler: terminate() must end it


def _warm_worker() -> None:
    _ignore_interrupt()
    warm_up()


def _filled(out: list[dict | None]) -> list[dict]:
    """The runs' results in run order, once every slot has been filled."""
    results = [r for r in out if r is not None]
    assert len(results) == len(out), "a run's result is missing"
    return results


def _process(runs, workers, progress, stop, out) -> list[dict]:
    warm_up()
    if workers == 1:
        for i, r in enumerate(runs):
            stop()
            out[i] = run_or_error(r, after_step=stop)
            if progress:
                progress(i + 1, len(runs))
        return _filled(out)
    pool = _pool(workers)
    try:
        futures = {pool.submit(run_or_error, r): i for i, r in enumerate(runs)}
        pending, done = set(futures), 0
        while pending:
            stop()
            ready, pending = wait(pending, timeout=0.2, return_when=FIRST_COMPLETED)
            for f in ready:
                out[futures[f]] = f.result()
                done += 1
                if progress:
                    progress(done, len(runs))
    except BaseException:  # a stop (or an error): no more runs, the running ones ended now
        for process in list(getattr(pool, "_processes", {}).values()):
            process.terminate()
        pool.shutdown(wait=True, cancel_futures=True)
        raise
    pool.shutdown(wait=True)
    return _filled(out)


def _check_reachable(address: str, timeout_s: float = 5.0) -> None:
    """UsvsimError unless a TCP connection to a Ray `address` ("host:port" or "ray://host:port") opens: an
    unreachable one held `usvsim sweep` for minutes in Ray's own retries, printing only Ray's warnings."""
    import socket

    host, _, port = address.removeprefix("ray://").rpartition(":")
    if address in ("auto", "local") or not host or not port.isdigit():
        return  # Ray's own keywords and forms: left to Ray
    try:
        socket.create_connection((host.strip("[]"), int(port)), timeout=timeout_s).close()
    except OSError as exc:
        raise UsvsimError(f"cannot reach the Ray cluster at {address}: {exc.strerror or exc}") from None


def _ray(runs, workers, address, progress, stop, out) -> list[dict]:
    try:
        import ray
    except ImportError:
        raise UsvsimError("the ray backend needs Ray: pip install 'usvsim[ray]'") from None
    started = not ray.is_initialized()
    if started and address:
        _check_reachable(address)
    if started:
        local = {} if address else {"num_cpus": workers, "_node_ip_address": "127.0.0.1"}  # loopback only
        ray.init(address=address, include_dashboard=False, log_to_driver=False, configure_logging=False, **local)
    pending: list = []
    try:
        remote = ray.remote(num_cpus=1)(run_or_error)
        refs = [remote.remote(r) for r in runs]
        index = {ref: i for i, ref in enumerate(refs)}
        pending, done = list(refs), 0
        while pending:
            stop()
            ready, pending = ray.wait(pending, num_returns=1, timeout=0.2)
            for ref in ready:
                out[index[ref]] = ray.get(ref)
                done += 1
                if progress:
                    progress(done, len(runs))
        return _filled(out)
    except BaseException:
        for ref in pending:  # no more runs
            ray.cancel(ref, force=True)
        raise
    finally:
        if started:
            ray.shutdown()
