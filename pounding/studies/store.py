"""The run store: one atomic file pair per run, a log, a lock, and the checks of a resume."""

from __future__ import annotations

import contextlib
import json
import os
from collections.abc import Callable, Iterator, Mapping
from pathlib import Path
from typing import Any

import xarray as xr

from pounding.studies.signals import _stop_deferred
from pounding.studies.spec import _HISTORY_ENCODING, StudyError

#: Suffix of the store's own temporary files: a cleanup removes these and nothing of the user's.
_TMP_SUFFIX = ".pounding-store.tmp"
#: The store's lock file (holds the PID of the study writing into it).
_LOCK_NAME = ".pounding-store.lock"
_HDF5_SIGNATURE = b"\x89HDF\r\n\x1a\n"


def _atomic_write(path: Path, write: Callable[[Path], None]) -> None:
    tmp = path.with_name(f".{path.name}.{os.getpid()}{_TMP_SUFFIX}")
    write(tmp)
    os.replace(tmp, path)


def _read_record(store: Path, key: str) -> dict[str, Any] | None:
    path = store / f"{key}.json"
    try:
        return json.loads(path.read_text())
    except (OSError, ValueError):
        return None  # missing or unreadable: run again


def _stored_ok(store: Path, key: str, *, need_histories: bool, retry: bool) -> bool:
    rec = _read_record(store, key)
    if rec is None or not isinstance(rec, dict):
        return False
    if rec.get("status") != "ok":
        return not retry
    if not isinstance(rec.get("summary"), dict):
        return False  # "summary": null made every resume crash
    if rec.get("has_histories") and not _history_intact(store / f"{key}.nc"):
        return False
    return not need_histories or bool(rec.get("has_histories"))


def _history_intact(path: Path) -> bool:
    """The history file exists and starts as an HDF5 file (a truncated copy breaks the report)."""
    try:
        with path.open("rb") as fh:
            return fh.read(8) == _HDF5_SIGNATURE and path.stat().st_size > 512
    except OSError:
        return False


def _damaged(store: Path, key: str) -> bool:
    """A run file exists but cannot be used (rerun, counted apart from the runs never made)."""
    return (store / f"{key}.json").exists() and (
        _read_record(store, key) is None
        or not _stored_ok(store, key, need_histories=False, retry=False)
    )


def _write_run(store: Path, result: Mapping[str, Any]) -> None:
    """Write one finished run atomically and log it (the log lists every run ever made).

    ``KEY.json`` holds the status, the error and the summary; ``KEY.nc`` the kept time histories,
    written first, so a run counts as stored only once both are complete.
    """
    with _stop_deferred():
        _write_run_files(store, result)


def _write_run_files(store: Path, result: Mapping[str, Any]) -> None:
    store.mkdir(parents=True, exist_ok=True)
    rec = result["record"]
    if result["histories"] is not None:
        _atomic_write(
            store / f"{rec['key']}.nc",
            lambda tmp: result["histories"].to_netcdf(
                tmp,
                engine="h5netcdf",
                encoding={v: _HISTORY_ENCODING for v in result["histories"].data_vars},
            ),
        )
    _atomic_write(store / f"{rec['key']}.json", lambda tmp: tmp.write_text(json.dumps(rec)))
    entry = {k: rec[k] for k in ("key", "status", "error", "elapsed")}
    with (store / "log.jsonl").open("a") as fh:
        fh.write(json.dumps(entry) + "\n")


def open_run(store: str | Path, key: str) -> xr.Dataset:
    """A stored run as a Dataset: its summary (:func:`run_summary`) and, when kept, its decimated
    time histories; attrs ``status`` and ``error``."""
    store = Path(store)
    rec = _read_record(store, key)
    if rec is None:
        raise FileNotFoundError(f"no stored run {key} in {store}")
    ds = xr.Dataset.from_dict(rec["summary"]) if rec["summary"] else xr.Dataset()
    if rec.get("has_histories") and (store / f"{key}.nc").is_file():
        with xr.open_dataset(store / f"{key}.nc", engine="h5netcdf") as hist:
            hist = hist.load()
        ds = xr.merge([hist, ds], compat="override", combine_attrs="override")
    ds.attrs.update({k: rec[k] for k in ("key", "label", "status", "error", "elapsed")})
    ds.attrs["has_histories"] = int(bool(rec.get("has_histories")))
    return ds


def run_log(store: str | Path) -> list[dict[str, Any]]:
    """Every run made into ``store`` (one entry per run, in order; reruns would appear twice)."""
    path = Path(store) / "log.jsonl"
    if not path.is_file():
        return []
    return [json.loads(line) for line in path.read_text().splitlines() if line.strip()]


@contextlib.contextmanager
def _store_lock(store: Path) -> Iterator[None]:
    """Hold the store for this process: a second study into the same store stops at once with
    the PID of the first (two writers deleted each other's temporary files and crashed)."""
    try:
        import fcntl
    except ImportError:  # pragma: no cover - not POSIX: no lock
        yield
        return
    path = store / _LOCK_NAME
    with open(path, "a+") as fh:
        try:
            fcntl.flock(fh, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            fh.seek(0)
            pid = fh.read().strip() or "?"
            raise StudyError(
                f"store {store} in use by PID {pid} (another pounding study writing into it); "
                "wait for it to finish or give another --store"
            ) from None
        fh.seek(0)
        fh.truncate()
        fh.write(str(os.getpid()))
        fh.flush()
        try:
            yield
        finally:
            fcntl.flock(fh, fcntl.LOCK_UN)
