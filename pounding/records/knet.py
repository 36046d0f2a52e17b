"""K-NET / KiK-net ASCII records: reader."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from pounding.ground_motion import GroundMotion, remove_mean
from pounding.records.common import _NUMBER, RecordFormatError, _check_dt, _finite, _numbers
from pounding.units import acceleration_factor

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
