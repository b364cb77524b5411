"""Run many task trials: `expand(spec)` → runs, `run(runs, backend=...)` → one metrics dict per run, in order.

Backends: `process` (local processes, the default) and `ray` (a local Ray instance, or a cluster at
`address`; extra `ray`). Every worker runs numba with one thread, so results are bit-identical whatever
the backend and the number of workers (the run's `wall_time_s` aside).
"""

from __future__ import annotations

import itertools
import multiprocessing
import os
from collections.abc import Callable, Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
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


def run_one(spec: RunSpec) -> dict:
    """One run in this process (numba with one thread): the reference solution's trial report + the run."""
    from usvsim.tasks.solutions import run_trial
    from usvsim.tasks.timing import TaskTiming, limit_numba_threads

    limit_numba_threads(1)
    report = run_trial(spec.task, spec.difficulty, spec.seed, TaskTiming(running_s=spec.time_limit_s),
                       spec.sea_state, spec.mass_kg, dict(spec.hold))  # fmt: skip
    return {"run": asdict(spec), **report}


def run(runs: Sequence[RunSpec], backend: str = "process", workers: int | None = None, address: str | None = None,
        progress: Callable[[int, int], None] | None = None) -> list[dict]:  # fmt: skip
    """Metrics of every run, in the order of `runs`. `progress(done, total)` is called as runs finish."""
    workers = workers or os.cpu_count() or 1
    if backend == "process":
        return _process(runs, workers, progress)
    if backend == "ray":
        return _ray(runs, workers, address, progress)
    raise UsvsimError(f"unknown backend {backend!r}; choose process or ray")


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
    """Forked from this (warm) process where the platform can fork; else fresh workers warm up once each."""
    if "fork" in multiprocessing.get_all_start_methods():
        return ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("fork"))
    return ProcessPoolExecutor(max_workers=workers, initializer=warm_up)


def _filled(out: list[dict | None]) -> list[dict]:
    """The runs' results in run order, once every slot has been filled."""
    results = [r for r in out if r is not None]
    assert len(results) == len(out), "a run's result is missing"
    return results


def _process(runs, workers, progress) -> list[dict]:
    out: list[dict | None] = [None] * len(runs)
    warm_up()
    if workers == 1:
        for i, r in enumerate(runs):
            out[i] = run_one(r)
            if progress:
                progress(i + 1, len(runs))
        return _filled(out)
    with _pool(workers) as pool:
        futures = {pool.submit(run_one, r): i for i, r in enumerate(runs)}
        for done, f in enumerate(as_completed(futures), 1):
            out[futures[f]] = f.result()
            if progress:
                progress(done, len(runs))
    return _filled(out)


def _ray(runs, workers, address, progress) -> list[dict]:
    try:
        import ray
    except ImportError:
        raise UsvsimError("the ray backend needs Ray: pip install 'usvsim[ray]'") from None
    started = not ray.is_initialized()
    if started:
        local = {} if address else {"num_cpus": workers, "_node_ip_address": "127.0.0.1"}  # loopback only
        ray.init(address=address, include_dashboard=False, log_to_driver=False, configure_logging=False, **local)
    try:
        remote = ray.remote(num_cpus=1)(run_one)
        refs = [remote.remote(r) for r in runs]
        index = {ref: i for i, ref in enumerate(refs)}
        out: list[dict | None] = [None] * len(runs)
        pending, done = list(refs), 0
        while pending:
            ready, pending = ray.wait(pending, num_returns=1)
            out[index[ready[0]]] = ray.get(ready[0])
            done += 1
            if progress:
                progress(done, len(runs))
        return _filled(out)
    finally:
        if started:
            ray.shutdown()
