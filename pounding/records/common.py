"""What every record reader shares: the error classes, number parsing, checks, unit conversion."""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any

import numpy as np

from pounding.errors import PoundingInputError
from pounding.units import acceleration_factor, length_factor, velocity_factor

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


#: Bounds of a record's time step [s]: accelerographs sample at 20 Hz to a few kHz; a DT outside
#: is a corrupt header (DT = 1e-320 passed a positivity check and differentiated to inf).
RECORD_DT_RANGE = (1e-6, 1.0)


def _check_dt(dt: float, path: Path, line: int | None, given: float | None) -> float:
    low, high = RECORD_DT_RANGE
    if not (math.isfinite(dt) and low <= dt <= high):
        raise RecordFormatError(path, line, f"a time step DT of {low:g} to {high:g} s", dt)
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
