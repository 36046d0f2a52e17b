"""COSMOS V2 single-channel records: reader."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from pounding.ground_motion import GroundMotion
from pounding.records.common import (
    RecordFormatError,
    _check_dt,
    _finite,
    _numbers,
    _unit_from_label,
)
from pounding.units import acceleration_factor

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
