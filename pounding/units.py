"""Physical constants and unit factors.

Everything inside :mod:`pounding` is SI (m, s, kg, N). Conversion happens only at the edges
(record readers, case files, CLI flags that name their unit) through the factors defined here.
"""

from __future__ import annotations

from pounding.errors import PoundingInputError

G = 9.80665
"""Standard gravity [m/s²] (CGPM 1901)."""

#: Factors that convert an acceleration given in the key's unit to m/s².
ACCELERATION_UNITS: dict[str, float] = {
    "g": G,
    "m/s2": 1.0,
    "m/s^2": 1.0,
    "m/s**2": 1.0,
    "cm/s2": 0.01,
    "cm/s^2": 0.01,
    "gal": 0.01,
    "mm/s2": 0.001,
    "mm/s^2": 0.001,
}

#: Factors that convert a length given in the key's unit to m.
LENGTH_UNITS: dict[str, float] = {"m": 1.0, "cm": 0.01, "mm": 0.001, "in": 0.0254, "ft": 0.3048}

#: Factors that convert a velocity given in the key's unit to m/s.
VELOCITY_UNITS: dict[str, float] = {
    "m/s": 1.0,
    "cm/s": 0.01,
    "mm/s": 0.001,
    "in/s": 0.0254,
}


def _factor(table: dict[str, float], unit: str, quantity: str) -> float:
    key = unit.strip().lower().replace(" ", "")
    try:
        return table[key]
    except KeyError:
        allowed = ", ".join(sorted(table))
        raise PoundingInputError(f"unknown {quantity} unit {unit!r}; allowed: {allowed}") from None


def acceleration_factor(unit: str) -> float:
    """Factor [m/s² per unit] for an acceleration unit name (``g``, ``m/s2``, ``cm/s2``, ``gal``...)."""
    return _factor(ACCELERATION_UNITS, unit, "acceleration")


def length_factor(unit: str) -> float:
    """Factor [m per unit] for a length unit name (``m``, ``cm``, ``mm``, ``in``, ``ft``)."""
    return _factor(LENGTH_UNITS, unit, "length")


def velocity_factor(unit: str) -> float:
    """Factor [m/s per unit] for a velocity unit name (``m/s``, ``cm/s``, ``mm/s``, ``in/s``)."""
    return _factor(VELOCITY_UNITS, unit, "velocity")
