"""Helpers shared by the benchmark scripts: machine description, timing, option sets, output."""

from __future__ import annotations

import dataclasses
import datetime
import json
import os
import platform
import statistics
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from pounding.simulate import AnalysisOptions

HERE = Path(__file__).resolve().parent
RESULTS = HERE / "results"


def has_adaptive() -> bool:
    """Whether this version of pounding has the ``adaptive`` analysis option."""
    return "adaptive" in {f.name for f in dataclasses.fields(AnalysisOptions)}


def fixed_step(dt: float, **options: Any) -> dict[str, Any]:
    """Analysis options for one fixed step ``dt`` everywhere (no event-aware refinement)."""
    if has_adaptive():
        options["adaptive"] = False
    return {"dt": dt, **options}


def _version(module: str) -> str:
    try:
        from importlib.metadata import version

        return version(module)
    except Exception:  # noqa: BLE001 - absent optional package
        return "not installed"


def _git(*args: str) -> str:
    try:
        return subprocess.run(
            ["git", *args], cwd=HERE, capture_output=True, text=True, check=True
        ).stdout.strip()
    except Exception:  # noqa: BLE001 - not a checkout
        return ""


def machine() -> dict[str, Any]:
    """What ran the benchmark: CPU, cores, versions, commit, date."""
    cpu = ""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        cpu = platform.processor()
    dirty = _git("status", "--porcelain", "--", "pounding")
    return {
        "date": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
        "nproc": os.cpu_count(),
        "cpu": cpu,
        "python": platform.python_version(),
        "numpy": np.__version__,
        "numba": _version("numba"),
        "scipy": _version("scipy"),
        "openseespy": _version("openseespy"),
        "pounding": _version("pounding"),
        "commit": _git("rev-parse", "--short", "HEAD"),
        "pounding_sources_modified": bool(dirty),
    }


def machine_markdown(info: dict[str, Any]) -> str:
    mod = " (with uncommitted changes in pounding/)" if info["pounding_sources_modified"] else ""
    return (
        f"{info['date']}; {info['cpu']}, {info['nproc']} cores (nproc); Python {info['python']}, "
        f"numpy {info['numpy']}, numba {info['numba']}, scipy {info['scipy']}, "
        f"openseespy {info['openseespy']}; pounding {info['pounding']} at commit "
        f"{info['commit']}{mod}"
    )


def median_time(func: Callable[[], Any], repeats: int) -> tuple[float, list[float], Any]:
    """Median wall time [s] of ``func()`` over ``repeats`` calls, all times, and the last result."""
    times = []
    result = None
    for _ in range(max(1, repeats)):
        t0 = time.perf_counter()
        result = func()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), times, result


def contact_time(start: np.ndarray, end: np.ndarray, duration: float) -> float:
    """Total time [s] during which at least one gap element is closed (union of impact intervals)."""
    if start.size == 0:
        return 0.0
    end = np.where(np.isnan(end), duration, end)
    order = np.argsort(start)
    total = 0.0
    cur_s, cur_e = start[order[0]], end[order[0]]
    for s, e in zip(start[order[1:]], end[order[1:]], strict=True):
        if s > cur_e:
            total += cur_e - cur_s
            cur_s, cur_e = s, e
        else:
            cur_e = max(cur_e, e)
    return float(total + cur_e - cur_s)


def out_dirs(quick: bool) -> tuple[Path, Path]:
    """(JSON directory, PNG directory): results/ and benchmarks/, or results/quick/ for --quick."""
    if quick:
        return RESULTS / "quick", RESULTS / "quick"
    return RESULTS, HERE


def write_json(name: str, payload: dict[str, Any], directory: Path = RESULTS) -> Path:
    directory.mkdir(parents=True, exist_ok=True)
    path = directory / name
    path.write_text(json.dumps(payload, indent=1, default=_plain) + "\n")
    return path


def _plain(x: Any) -> Any:
    if isinstance(x, np.generic):
        return x.item()
    if isinstance(x, np.ndarray):
        return x.tolist()
    raise TypeError(type(x))


def fmt_time(seconds: float) -> str:
    if seconds < 1e-3:
        return f"{seconds * 1e6:.2f} µs"
    if seconds < 1.0:
        return f"{seconds * 1e3:.1f} ms"
    return f"{seconds:.2f} s"


def finish_per_step(
    script: str,
    rows: dict[str, dict[str, Any]],
    base: str,
    ratio_key: str,
    record: Any,
    dt: float,
    argv: list[str] | None,
    quick: bool,
) -> Path:
    """Each row's µs/step over the ``base`` row's as ``ratio_key``, the machine, and the JSON of a
    per-step cost benchmark (``script`` names it and the file)."""
    for label in rows:
        rows[label][ratio_key] = rows[label]["us_per_step"] / rows[base]["us_per_step"]
    info = machine()
    print(machine_markdown(info))
    payload = {"command": " ".join([f"python benchmarks/{script}.py", *(argv or sys.argv[1:])]),
               "record": record, "dt": dt, "machine": info, "rows": rows}  # fmt: skip
    path = write_json(f"{script}.json", payload, out_dirs(quick)[0])
    print(f"wrote {path}")
    return path


def write_run(
    script: str,
    argv: list[str] | None,
    info: dict[str, Any],
    record: Any,
    fields: dict[str, Any],
    name: str,
    quick: bool,
    t_start: float,
) -> Path:
    """The JSON ``name`` of a side-by-side benchmark: its command line, the machine ``info``, the
    record, ``fields`` and the wall time since ``t_start`` (``time.perf_counter``)."""
    args = sys.argv[1:] if argv is None else argv
    payload = {"command": " ".join([f"python benchmarks/{script}.py", *args]), "machine": info,
               "record": record, **fields, "wall_time": time.perf_counter() - t_start}  # fmt: skip
    path = write_json(name, payload, out_dirs(quick)[0])
    print(f"wrote {path} ({payload['wall_time']:.0f} s)")
    return path
