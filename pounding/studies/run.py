"""Running a study: serially, on local worker processes or on a dask cluster, resumably."""

from __future__ import annotations

import concurrent.futures as cf
import math
import multiprocessing
import os
import signal
import time
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import xarray as xr

from pounding._version import __version__
from pounding.case import case_from_dict
from pounding.errors import PoundingInputError
from pounding.simulate import simulate
from pounding.studies.dataset import assemble, run_summary
from pounding.studies.plan import StudyPlan, plan_study
from pounding.studies.signals import _check_stop
from pounding.studies.spec import HISTORY_VARIABLES, Study, StudyError
from pounding.studies.store import _TMP_SUFFIX, _store_lock, _write_run

_MAX_POOL_RESTARTS = 3


def _result(
    task: Mapping[str, Any],
    status: str,
    error: str,
    summary: xr.Dataset | None,
    hist: xr.Dataset | None,
    elapsed: float,
) -> dict[str, Any]:
    record = {
        "key": task["key"],
        "label": task["label"],
        "status": status,
        "error": error,
        "has_histories": hist is not None,
        "elapsed": round(elapsed, 4),
        "pounding_version": __version__,
        "summary": None if summary is None else summary.to_dict(data="list"),
    }
    return {"record": record, "histories": hist}


def _execute(task: Mapping[str, Any]) -> dict[str, Any]:
    """Run one task (in a worker); never raises for a failing analysis, only records its error."""
    start = time.perf_counter()
    hist = None
    try:
        case = case_from_dict(
            task["data"],
            base_dir=None if task["base_dir"] is None else Path(task["base_dir"]),
            source="study run",
        )
        gm = task["motion"]
        if gm is not None and task["scale"] is not None:
            gm = gm.scaled(float(task["scale"]))
        ds = simulate(case, gm)
        summary = run_summary(ds)
        if task["history_dt"] is not None:
            step = max(1, round(task["history_dt"] / float(ds.attrs["output_dt"])))
            hist = ds[list(HISTORY_VARIABLES)].isel(time=slice(None, None, step))
            hist.attrs = {k: v for k, v in ds.attrs.items()}
            hist.attrs["history_dt"] = float(ds.attrs["output_dt"]) * step
            hist.attrs["run_key"] = task["key"]
        status, error = "ok", ""
    except Exception as exc:  # noqa: BLE001 - a failed run is recorded, the study goes on
        summary, hist = None, None
        status, error = "failed", f"{type(exc).__name__}: {exc}"
    return _result(task, status, error, summary, hist, time.perf_counter() - start)


# --------------------------------------------------------------------------------------------------
# Execution
# --------------------------------------------------------------------------------------------------

#: ``progress(done, total, failed)``: runs finished in this session, runs to do, failures so far.
ProgressCallback = Callable[[int, int, int], None]


def _cores() -> int:
    if hasattr(os, "sched_getaffinity"):
        return len(os.sched_getaffinity(0))
    return os.cpu_count() or 1


def _die_with_parent() -> None:
    """End this worker when the study process dies, even by SIGKILL (which no handler sees).

    Neither the parent PID nor Linux's parent-death signal works here: a forkserver worker's parent
    is the fork server, and the workers hold the fork server's liveness pipe open, so after the study
    is killed each keeps the other alive, all of them, for good. multiprocessing gives every child a
    sentinel of the process that started it; it becomes ready when that process is gone."""
    import threading
    from multiprocessing.connection import wait

    parent = multiprocessing.parent_process()
    if parent is None or parent.sentinel is None:  # pragma: no cover - not a multiprocessing child
        return

    def watch() -> None:
        wait([parent.sentinel])
        os._exit(1)

    threading.Thread(target=watch, name="pounding-parent-watch", daemon=True).start()


def _worker_init() -> None:
    # Ctrl-C reaches the whole process group; the parent decides, workers keep quiet.
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    _die_with_parent()


def _mp_context() -> multiprocessing.context.BaseContext:
    # never plain fork: numba's and the BLAS threading layers are not fork-safe
    methods = multiprocessing.get_all_start_methods()
    return multiprocessing.get_context("forkserver" if "forkserver" in methods else "spawn")


def _stop_workers(pool: cf.ProcessPoolExecutor, grace: float = 2.0) -> None:
    procs = list(getattr(pool, "_processes", {}).values())
    for proc in procs:
        if proc.is_alive():
            proc.terminate()
    pool.shutdown(wait=False, cancel_futures=True)
    # a worker stuck in compiled code may not honour SIGTERM at once: never wait for it long
    deadline = time.monotonic() + grace
    for proc in procs:
        proc.join(max(0.0, deadline - time.monotonic()))
        if proc.is_alive():
            proc.kill()


def _run_processes(
    tasks: list[dict],
    jobs: int,
    on_done: Callable[[dict], None],
    keep: dict[str, Any] | None = None,
) -> None:
    """Run the tasks on worker processes; ``keep`` holds a pool to reuse from call to call (the
    rounds of a hunt-and-fill IDA: starting workers costs seconds), shut down by the caller."""
    pending = list(tasks)
    restarts = 0
    while pending:
        pool = keep.get("pool") if keep is not None else None
        if pool is None:
            workers = jobs if keep is not None else min(jobs, len(pending))
            pool = cf.ProcessPoolExecutor(
                max_workers=workers, mp_context=_mp_context(), initializer=_worker_init
            )
            if keep is not None:
                keep["pool"] = pool
        finished: set[str] = set()
        try:
            futures = {pool.submit(_execute, t): t["key"] for t in pending}
            for fut in cf.as_completed(futures):
                try:
                    result = fut.result()
                except cf.process.BrokenProcessPool:
                    continue
                on_done(result)
                finished.add(result["record"]["key"])
            _check_stop()
        except BaseException:
            _stop_workers(pool)
            if keep is not None:
                keep.pop("pool", None)
            raise
        pending = [t for t in pending if t["key"] not in finished]
        if keep is None or pending:  # a broken pool is not kept
            pool.shutdown(wait=True)
            if keep is not None:
                keep.pop("pool", None)
        if pending:
            # a SIGTERM sent to the whole process group also kills the workers: that is a stop,
            # not a crash to recover from by starting a new pool
            _check_stop()
            restarts += 1
            if restarts > _MAX_POOL_RESTARTS:
                raise RuntimeError(
                    f"worker processes died {restarts} times; the {len(pending)} unfinished runs "
                    "are not stored (finished runs are); rerun with jobs=1 to find the culprit"
                )


def _run_dask(tasks: list[dict], scheduler: Any, on_done: Callable[[dict], None]) -> None:
    try:
        from distributed import Client, as_completed
    except ImportError:  # pragma: no cover - depends on the optional extra
        raise StudyError(
            "scheduler given but dask.distributed is not installed: pip install 'pounding[distributed]'"
        ) from None
    own = not isinstance(scheduler, Client)
    client = Client(scheduler) if own else scheduler
    futures = []
    try:
        futures = [
            client.submit(_execute, t, key=f"pounding-run-{t['key']}", pure=False) for t in tasks
        ]
        for fut in as_completed(futures):
            try:
                result = fut.result()
            except Exception as exc:  # noqa: BLE001 - e.g. KilledWorker: the run crashed its worker
                key = fut.key.removeprefix("pounding-run-")
                task = next(t for t in tasks if t["key"] == key)
                err = f"{type(exc).__name__}: {exc}"
                result = _result(task, "failed", err, None, None, 0.0)
            on_done(result)
    except BaseException:
        client.cancel(futures)
        raise
    finally:
        if own:
            client.close()


def run_study(
    study: Study | StudyPlan,
    store: str | Path | None = None,
    *,
    jobs: int | None = None,
    scheduler: Any = None,
    progress: ProgressCallback | None = None,
    retry_failed: bool = False,
) -> xr.Dataset:
    """Run the runs of a study the store does not hold yet, then assemble the study Dataset.

    Parameters
    ----------
    study : Study or StudyPlan
        From :func:`load_study` (then ``store`` is required) or :func:`plan_study`.
    store : path, optional
        Directory of the per-run files (see :func:`default_store`).
    jobs : int, optional
        Local worker processes; default all cores; 1 runs serially in this process.
    scheduler : str or distributed.Client, optional
        Address of a ``dask.distributed`` scheduler (or a client): run there instead.
    progress : callable, optional
        Called as ``progress(done, total, failed)`` before the first and after every run.
    retry_failed : bool
        Run again the runs stored as failed.

    Returns
    -------
    xarray.Dataset
        See :func:`assemble`. A KeyboardInterrupt stops the workers and propagates; finished runs
        are stored and a rerun resumes. Inside :func:`stop_on_signals`, SIGINT and SIGTERM raise
        :class:`StudyInterrupted` the same way, checked after every run.

    Notes
    -----
    Local workers are started with the ``forkserver`` (or ``spawn``) method, never ``fork``, which is
    unsafe with numba's and BLAS's threads; a script that calls this with ``jobs > 1`` must do so
    under ``if __name__ == "__main__":``.
    """
    if isinstance(study, StudyPlan):
        plan = study
    else:
        if store is None:
            raise PoundingInputError("run_study(study, store): a store directory is required")
        plan = plan_study(study, store, retry_failed=retry_failed)
    todo = [plan.tasks[k] for k in plan.todo]
    done = failed = 0
    if progress:
        progress(0, len(todo), 0)

    def on_done(result: dict) -> None:
        nonlocal done, failed
        _write_run(plan.store, result)
        done += 1
        failed += result["record"]["status"] != "ok"
        if progress:
            progress(done, len(todo), failed)
        _check_stop()  # stored first: a stop request never loses a finished run

    if todo:
        plan.store.mkdir(parents=True, exist_ok=True)
        with _store_lock(plan.store):
            _clear_stale(plan.store)
            _execute_all(todo, jobs, scheduler, on_done)
    _check_stop()
    return assemble(plan)


def _clear_stale(store: Path) -> None:
    for stale in store.glob(f".*{_TMP_SUFFIX}"):  # left by a killed run
        stale.unlink(missing_ok=True)


def _execute_all(
    todo: list[dict],
    jobs: int | None,
    scheduler: Any,
    on_done: Callable[[dict], None],
    keep: dict[str, Any] | None = None,
) -> None:
    n_jobs = max(1, int(jobs or _cores()))
    if scheduler is not None:
        _run_dask(todo, scheduler, on_done)
    elif n_jobs == 1 or len(todo) == 1:
        for task in todo:
            _check_stop()
            on_done(_execute(task))
    elif keep is not None and "pool" in keep:
        _run_processes(todo, n_jobs, on_done, keep)
    else:
        # the first run goes in this process: it compiles the kernels once and writes
        # numba's disk cache, which the workers then load instead of compiling again
        on_done(_execute(todo[0]))
        _run_processes(todo[1:], n_jobs, on_done, keep)


# --------------------------------------------------------------------------------------------------
# Hunt-and-fill IDA
# --------------------------------------------------------------------------------------------------


def _reached(record: Mapping[str, Any] | None, limit: str | float) -> bool:
    """Whether a stored run reached the hunt's limit state (a failed run counts as collapse)."""
    import numpy as np

    if record is None or record["status"] != "ok":
        return True
    summary = record["summary"]["data_vars"]
    if limit == "pounding":
        return bool(np.nansum(np.asarray(summary["impact_count"]["data"], dtype=float)) > 0)
    if np.isfinite(np.asarray(summary["collapse_time"]["data"], dtype=float)).any():
        return True
    if limit == "collapse":
        return False
    drift = np.asarray(summary["peak_drift_ratio"]["data"], dtype=float)
    return bool(np.nanmax(drift) >= float(limit))


def run_hunt(
    study: Study,
    store: str | Path,
    *,
    jobs: int | None = None,
    scheduler: Any = None,
    progress: ProgressCallback | None = None,
    retry_failed: bool = False,
) -> xr.Dataset:
    """Trace every record of an IDA by hunt-and-fill (:mod:`pounding.studies.hunt`), resumably.

    The runs of one round (the next level of every trace not yet complete) go out together, on
    local processes or a dask cluster as in :func:`run_study`; each run is stored as it finishes.
    A rerun replays the stored runs without running them again (the levels follow from the
    results) and goes on where the study stopped. ``progress(done, total, failed)`` counts runs
    against the budget still open (``max_runs`` per unfinished trace). Returns :func:`pounding.studies.dataset.assemble_hunt`'s Dataset.
    """
    import itertools

    import numpy as np

    from pounding.studies.dataset import assemble_hunt
    from pounding.studies.hunt import next_level
    from pounding.studies.plan import _TaskBuilder
    from pounding.studies.spec import _label
    from pounding.studies.store import _read_record, _stored_ok

    options = study.hunt
    if options is None or study.im is None:
        raise StudyError(f'{study.source}: run_hunt needs an [ida] table with levels = "hunt"')
    store = Path(store)
    builder = _TaskBuilder(study)
    names = [n for n in study.axes if n != "record"]
    records = study.axes["record"]
    traces: list[dict[str, Any]] = []
    for index in itertools.product(*(range(len(study.axes[n])) for n in names)):
        combo = {n: study.axes[n][i] for n, i in zip(names, index, strict=True)}
        for r, record in enumerate(records):
            traces.append(
                {"index": (*index, r), "combo": combo, "record": record, "runs": [], "done": False}
            )
    need = builder.history_dt is not None
    errors: dict[str, str] = {}
    ran: dict[str, bool] = {}  # keys run by this call (never twice) -> limit state reached
    done = failed = 0
    keep: dict[str, Any] = {}  # one worker pool for every round
    try:
        while True:
            todo: dict[str, dict] = {}
            waiting: list[tuple[dict, float, str]] = []
            for trace in traces:
                record = trace["record"]
                while not trace["done"]:
                    level = next_level([(lv, hit) for lv, _, hit in trace["runs"]], options)
                    if record.motion is None:  # unreadable: one failed slot says why
                        trace["done"] = True
                        key = f"record-error:{record.name}"
                        errors[key] = record.error
                        trace["runs"].append((math.nan, key, True))
                        break
                    if level is None:
                        trace["done"] = True
                        break
                    scale = study.scale_factor(record, level)
                    label = _label(
                        {**trace["combo"], "record": record, "im_level": round(level, 6)}
                    )
                    key, data = builder.key(dict(trace["combo"]), record, scale, label)
                    if key in ran:
                        trace["runs"].append((level, key, ran[key]))
                        continue
                    if _stored_ok(store, key, need_histories=need, retry=retry_failed):
                        hit = _reached(_read_record(store, key), options.limit_state)
                        trace["runs"].append((level, key, hit))
                        continue
                    if key not in todo:
                        todo[key] = builder.task(key, data, record, scale, label)
                    waiting.append((trace, level, key))
                    break
            if not todo:
                break
            # the runs still possible: what is left of the budget of every unfinished trace
            total = done + sum(options.max_runs - len(t["runs"]) for t in traces if not t["done"])

            def on_done(result: dict, total: int = total) -> None:
                nonlocal done, failed
                _write_run(store, result)
                ran[result["record"]["key"]] = _reached(result["record"], options.limit_state)
                done += 1
                failed += result["record"]["status"] != "ok"
                if progress:
                    progress(done, total, failed)
                _check_stop()

            if progress:
                progress(done, total, failed)
            store.mkdir(parents=True, exist_ok=True)
            with _store_lock(store):
                _clear_stale(store)
                tasks = list(todo.values())
                _execute_all(tasks, jobs, scheduler, on_done, keep)
                for trace, level, key in waiting:
                    trace["runs"].append((level, key, ran[key]))
    finally:
        if "pool" in keep:
            keep.pop("pool").shutdown(wait=True)
    _check_stop()
    shape = (*(len(study.axes[n]) for n in names), len(records), options.max_runs)
    keys = np.full(shape, "", dtype=object)
    levels = np.full(shape, np.nan)
    hits = np.zeros(shape, dtype=bool)
    for trace in traces:
        for j, (level, key, hit) in enumerate(trace["runs"]):
            keys[(*trace["index"], j)] = key
            levels[(*trace["index"], j)] = level
            hits[(*trace["index"], j)] = hit
    return assemble_hunt(study, store, keys, levels, hits, errors)
