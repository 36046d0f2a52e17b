"""Reliability campaign (issue 16): malformed and fuzzed inputs through the CLI, as a user meets them.

Each input is a case file (or a record) given to ``pounding run CASE -o OUT.nc`` in a fresh process,
where OUT.nc already holds a good result. Every outcome falls in one class:

- ``clean error``: exit 2, one line on stderr, no traceback, the previous OUT.nc untouched;
- ``clean error, key not named``: as above, but the line does not name the perturbed key;
- ``ran``: exit 0, the result reads back, finite peaks, energy balance error < 1 %;
- ``silent wrong``: exit 0 although the scripted input must be refused, or a result with NaN or an
  energy balance error >= 1 %;
- ``traceback``: a Python traceback, or an exit status other than 0 and 2;
- ``lost data``: a failed run that changed or removed the previous OUT.nc, or left a temporary file;
- ``hang``: no exit within the time limit.

Usage::

    python benchmarks/reliability_campaign.py            # 40 scripted + 600 fuzzed inputs, ~10 min
    python benchmarks/reliability_campaign.py --fuzz 50  # quicker

The fuzzed inputs are the two-SDOF example perturbed one key at a time with a wrong type, an
out-of-range or an extreme value (seeded: the same inputs each time). Results are printed and, with
``--out``, written as JSON (one row per input).
"""

from __future__ import annotations

import argparse
import collections
import concurrent.futures as cf
import copy
import hashlib
import json
import math
import os
import random
import shutil
import subprocess
import sys
import tempfile
import time
import tomllib
from pathlib import Path

import numpy as np
import xarray as xr

ROOT = Path(__file__).resolve().parents[1]
BASE = tomllib.loads((ROOT / "examples" / "two_sdof.toml").read_text())
BASE["ground_motion"]["duration"] = 1.5  # s: keeps ~640 runs within minutes
TIMEOUT = 60.0  # s per input: a hang
_DELETE = "<deleted>"

# (label, path, value, key the error must name); each must be refused
SCRIPTED = [
    ("contact = 5", ("contact",), 5, "contact"),
    ("contact = ''", ("contact",), "", "contact"),
    ("left = ['A']", ("contact", 0, "left"), ["A"], "left"),
    ("floors = true", ("contact", 0, "floors"), True, "floors"),
    ("floors = []", ("contact", 0, "floors"), [], "floors"),
    ("e = {}", ("contact", 0, "e"), {}, "contact[0].e"),
    ("e = 1e-6", ("contact", 0, "e"), 1e-6, "contact[0].e"),
    ("law = 'nope'", ("contact", 0, "law"), "nope", "law"),
    ("units = 1", ("ground_motion", "units"), 1, "units"),
    ("amplitude = true", ("ground_motion", "amplitude"), True, "amplitude"),
    ("record dt = 1e-300", ("ground_motion", "dt"), 1e-300, "dt"),
    ("max_halvings = inf", ("analysis", "max_halvings"), math.inf, "max_halvings"),
    ("max_iter = 1e20", ("analysis", "max_iter"), 1e20, "max_iter"),
    ("adaptive = 'false'", ("analysis", "adaptive"), "false", "adaptive"),
    ("dt = true", ("analysis", "dt"), True, "dt"),
    ("dt = 100", ("analysis", "dt"), 100.0, "dt"),
    ("dt = 1e-9", ("analysis", "dt"), 1e-9, "dt"),
    ("steps_per_contact = 2**63-1", ("analysis", "steps_per_contact"), 2**63 - 1, "steps_per"),
    ("duration = 1e9", ("analysis", "duration"), 1e9, "duration"),
    ("n_floors = -inf", ("building", 0, "n_floors"), -math.inf, "n_floors"),
    ("n_floors = 2.7", ("building", 0, "n_floors"), 2.7, "n_floors"),
    ("n_floors = 100000", ("building", 0, "n_floors"), 100_000, "n_floors"),
    ("mass = -1", ("building", 0, "mass"), -1.0, "mass"),
    ("period = nan", ("building", 0, "period"), math.nan, "period"),
    ("heights on a uniform building", ("building", 0, "heights"), [3.0], "heights"),
    ("name with NUL", ("building", 0, "name"), "A\x00B", "name"),
    ("damping ratio = '5%'", ("building", 0, "damping"), {"ratio": "5%"}, "ratio"),
    ("title = 3", ("title",), 3, "title"),
    ("drift_limit = -1", ("output",), {"drift_limit": -1}, "drift_limit"),
    ("missing building", ("building",), _DELETE, "building"),
    ("missing contact gap", ("contact", 0, "gap"), _DELETE, "gap"),
]
# inputs that are not a perturbed key: (label, kind)
SPECIAL = [
    ("case file not UTF-8", "latin1"),
    ("case file not TOML", "garbage"),
    ("record is a named pipe", "fifo"),
    ("record is /dev/zero", "devzero"),
    ("record with a NaN sample", "nan_record"),
    ("record file empty", "empty_record"),
    ("-o x.csv", "csv_output"),
    ("report of a case file, not a result", "report_case"),
    ("building name '$\\undefinedmacro$' (report)", "mathtext"),
    ("building name with an escape code", "escape"),
]

_PATHS = [
    ("title",),
    *[("building", i, k) for i in (0, 1) for k in ("name", "n_floors", "period", "mass", "height")],
    ("building", 0, "damping"),
    *[("contact", 0, k) for k in ("left", "right", "gap", "law", "k", "e", "n", "floors", "a")],
    ("contact", 0, "calibration"),
    ("contact",),
    *[("ground_motion", k) for k in ("type", "amplitude", "units", "period", "duration", "dt")],
    *[("analysis", k) for k in ("method", "dt", "output_dt", "duration", "alpha", "tol")],
    *[("analysis", k) for k in ("max_iter", "max_halvings", "locate_onset", "adaptive")],
    ("analysis", "steps_per_contact"),
    ("output", "drift_limit"),
    ("output", "floor_spectra"),
]
_ODD = [True, False, "", "x", "false", [], {}, [1], [[1, 1]], -1, 0, 1, 2.7, -2.7, 1e-300, 1e300]
_ODD += [math.inf, -math.inf, math.nan, 2**63 - 1, -(2**63), "\x00", _DELETE]


def _fuzzed(n: int, seed: int = 16) -> list[tuple[str, tuple, object, str]]:
    rng = random.Random(seed)
    out = []
    for _ in range(n):
        path = rng.choice(_PATHS)
        kind = rng.random()
        if kind < 0.5:
            value = rng.choice(_ODD)
        elif kind < 0.75:
            value = 10 ** rng.uniform(-12, 12) * rng.choice([-1, 1])
        else:
            value = rng.randint(-(2**63), 2**63 - 1) if rng.random() < 0.3 else rng.randint(-5, 50)
        out.append((f"{'.'.join(map(str, path))} = {value!r}", path, value, str(path[-1])))
    return out


def _edited(path: tuple, value: object) -> dict:
    data = copy.deepcopy(BASE)
    data.setdefault("output", {})
    node = data
    for key in path[:-1]:
        node = node[key]
    if value == _DELETE and isinstance(value, str):
        node.pop(path[-1], None)
    else:
        node[path[-1]] = value
    return data


def _value(v: object) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return (
            "nan" if math.isnan(v) else ("inf" if v > 0 else "-inf") if math.isinf(v) else repr(v)
        )
    if isinstance(v, int):
        return str(v)
    if isinstance(v, str):
        return json.dumps(v)  # JSON escapes (\u0000, \u001b) are TOML escapes too
    if isinstance(v, list):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{k} = {_value(x)}" for k, x in v.items()) + "}"
    raise TypeError(f"no TOML for {v!r}")


def _toml(data: dict) -> str:
    """The case as TOML (tables and arrays of tables; anything deeper inline)."""
    lines = [f"{k} = {_value(v)}" for k, v in data.items() if not isinstance(v, dict | list)]
    lines += [f"{k} = {_value(v)}" for k, v in data.items() if isinstance(v, list) and not v]
    for k, v in data.items():
        if isinstance(v, dict):
            lines += [f"[{k}]", *(f"{kk} = {_value(x)}" for kk, x in v.items())]
        elif isinstance(v, list) and v and all(isinstance(x, dict) for x in v):
            for x in v:
                lines += [f"[[{k}]]", *(f"{kk} = {_value(y)}" for kk, y in x.items())]
        elif isinstance(v, list) and v:
            lines.insert(0, f"{k} = {_value(v)}")
    return "\n".join(lines) + "\n"


def _digest(path: Path) -> str | None:
    return hashlib.sha256(path.read_bytes()).hexdigest() if path.exists() else None


def _run_one(item: dict, good: Path, pounding: str) -> dict:
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        case = tmp / "case.toml"
        out = tmp / "out.nc"
        shutil.copy(good, out)
        before = _digest(out)
        commands = [["run", str(case), "-o", str(out), "--no-baseline"]]
        if "special" in item:
            commands = _special(item["special"], tmp, case, out) or commands
        else:
            try:
                case.write_text(_toml(_edited(item["path"], item["value"])))
            except (TypeError, ValueError) as exc:  # not writable as TOML: not an input
                return {**_row(item), "class": "skipped", "detail": str(exc)}
        start = time.monotonic()
        for args in commands:
            try:
                proc = subprocess.run(
                    [pounding, *args], capture_output=True, text=True, timeout=TIMEOUT, cwd=tmp
                )
            except subprocess.TimeoutExpired:
                return {**_row(item), "class": "hang", "detail": f"> {TIMEOUT:.0f} s"}
            if proc.returncode != 0:
                break
            if "\x1b" in proc.stdout + proc.stderr:
                return {**_row(item), "class": "escape code printed", "detail": args[0]}
        elapsed = time.monotonic() - start
        err = proc.stderr.strip()
        keep = {"case.toml", "out.nc", "rec.at2", "report"}
        leftovers = [p.name for p in tmp.iterdir() if p.name not in keep]
        cls = _classify(item, proc.returncode, err, before, out, leftovers)
        return {
            **_row(item),
            "class": cls,
            "rc": proc.returncode,
            "detail": err[-300:],
            "s": elapsed,
        }


def _row(item: dict) -> dict:
    return {"label": item["label"], "source": item["source"]}


def _classify(item, rc, err, before, out, leftovers) -> str:
    if "Traceback" in err or rc not in (0, 2):
        return "traceback"
    if rc == 2:
        if _digest(out) != before or [p for p in leftovers if p != "out.csv"]:
            return "lost data"
        if len(err.splitlines()) != 1:
            return "traceback"
        named = item.get("name")
        return "clean error" if not named or named in err else "clean error, key not named"
    if item.get("must_fail"):
        return "silent wrong"
    try:
        with xr.open_dataset(out, engine="h5netcdf") as ds:
            ok = float(ds.attrs["energy_balance_error"]) < 1e-2
            floors = np.isfinite(ds["floor_mass"].values)  # buildings of fewer floors: NaN-padded
            ok &= bool(np.isfinite(ds["displacement"].values[:, floors]).all())
    except Exception:  # noqa: BLE001 - an unreadable result after exit 0
        return "lost data"
    return "ran" if ok else "silent wrong"


def _special(kind: str, tmp: Path, case: Path, out: Path) -> list[list[str]] | None:
    data = copy.deepcopy(BASE)
    rec = tmp / "rec.at2"
    if kind == "latin1":
        case.write_bytes('title = "Bâtiment"\n'.encode("latin-1"))
    elif kind == "garbage":
        case.write_text("this is [not toml\n")
    elif kind in ("fifo", "devzero", "nan_record", "empty_record"):
        if kind == "fifo":
            os.mkfifo(rec)
        elif kind == "devzero":
            rec = Path("/dev/zero")
        elif kind == "nan_record":
            rec.write_text("0.01\n0.0 0.1 nan 0.2\n")
        else:
            rec.write_text("")
        data["ground_motion"] = {"file": str(rec), "dt": 0.01, "units": "g", "format": "text"}
        case.write_text(_toml(data))
    elif kind == "csv_output":
        case.write_text(_toml(data))
        return [["run", str(case), "-o", str(tmp / "out.csv"), "--no-baseline"]]
    elif kind == "report_case":
        case.write_text(_toml(data))
        return [["report", str(case), "-o", str(tmp / "report")]]
    elif kind in ("mathtext", "escape"):
        name = "$\\undefinedmacro$" if kind == "mathtext" else "A\x1b[2J"
        data["building"][0]["name"] = name
        data["contact"][0]["left"] = name
        case.write_text(_toml(data))
        return [
            ["run", str(case), "-o", str(out), "--no-baseline"],
            ["report", str(out), "-o", str(tmp / "report")],
        ]
    return None


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fuzz", type=int, default=600, help="fuzzed inputs (default 600)")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--out", type=Path, help="write one JSON row per input here")
    args = parser.parse_args()
    pounding = shutil.which("pounding") or str(Path(sys.executable).parent / "pounding")

    items = [
        {"label": lab, "path": p, "value": v, "name": n, "must_fail": True, "source": "scripted"}
        for lab, p, v, n in SCRIPTED
    ]
    items += [{"label": lab, "special": k, "source": "scripted"} for lab, k in SPECIAL]
    items += [
        {"label": lab, "path": p, "value": v, "name": n, "source": "fuzzed"}
        for lab, p, v, n in _fuzzed(args.fuzz)
    ]
    with tempfile.TemporaryDirectory() as tmp:
        good = Path(tmp) / "good.nc"
        case = Path(tmp) / "good.toml"
        case.write_text(_toml(BASE))
        subprocess.run(
            [pounding, "run", str(case), "-o", str(good)], check=True, capture_output=True
        )
        rows = []
        start = time.monotonic()
        with cf.ThreadPoolExecutor(args.jobs) as pool:
            for i, row in enumerate(pool.map(lambda it: _run_one(it, good, pounding), items), 1):
                rows.append(row)
                if row["class"] not in ("clean error", "ran", "skipped"):
                    print(f"  {row['class']}: {row['label']!r}: {row.get('detail', '')[-200:]}")
                if i % 50 == 0:
                    print(
                        f"  {i}/{len(items)} inputs, {time.monotonic() - start:.0f} s", flush=True
                    )
    for source in ("scripted", "fuzzed"):
        counts = collections.Counter(r["class"] for r in rows if r["source"] == source)
        tried = sum(v for k, v in counts.items() if k != "skipped")
        print(
            f"{source}: {tried} inputs: " + ", ".join(f"{k} {v}" for k, v in sorted(counts.items()))
        )
    if args.out:
        args.out.write_text("\n".join(json.dumps(r, default=str) for r in rows) + "\n")


if __name__ == "__main__":
    main()
