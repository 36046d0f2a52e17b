"""Elastic response spectra of ground motions and code design spectra.

The response of a linear SDOF oscillator of period T and damping ratio ζ to the ground
acceleration,

.. math:: \\ddot x + 2 \\zeta \\omega \\dot x + \\omega^2 x = -a_g(t), \\qquad \\omega = 2\\pi/T,

is computed by the exact recurrence for acceleration linear between samples (Nigam and Jennings
1969; coefficients in :func:`pounding.ground_motion.nigam_jennings_coefficients`), compiled and
looped over periods. Three things make it correct over the whole period range:

* short periods: when T is short relative to the record step (including T < 2 dt), each step is
  split into sub-steps of at most T/``steps_per_period`` (and at most dt/4 for all periods, as the
  velocity and absolute acceleration of long-period oscillators follow the ground velocity) with
  the acceleration interpolated linearly, which is exact for the piecewise-linear record and
  samples the peaks finely;
* long periods: the recurrence runs in the time domain, so there is no wrap-around (unlike FFT
  methods), and with ``free_vibration=True`` one period of free vibration after the record is
  included, where the peak of a long-period oscillator often occurs;
* any damping 0 <= ζ < 1.

Spectral quantities (all peaks over time of absolute values):

========  ================================================  ========
``Sd``    relative displacement max|x|                      m
``Sv``    relative velocity max|ẋ|                          m s-1
``PSv``   pseudo-velocity ω Sd                              m s-1
``PSa``   pseudo-acceleration ω² Sd                         m s-2
``Sa``    absolute acceleration max|ẍ + a_g|                m s-2
========  ================================================  ========
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Sequence
from typing import Any

import numpy as np
import xarray as xr

from pounding._version import __version__
from pounding.errors import PoundingInputError
from pounding.ground_motion import (
    PERIOD_RANGE,
    GroundMotion,
    _check_damping,
    _check_periods,
)
from pounding.integrators.sdof import modal_extremes, spectral_peaks  # noqa: F401  (re-exported)
from pounding.units import G

#: Default periods [s]: 120 log-spaced values from 0.01 s to 10 s.
DEFAULT_PERIODS = np.geomspace(0.01, 10.0, 120)


_VARIABLES = {
    "Sd": ("m", "spectral displacement (relative)"),
    "Sv": ("m s-1", "spectral velocity (relative)"),
    "PSv": ("m s-1", "pseudo-spectral velocity"),
    "PSa": ("m s-2", "pseudo-spectral acceleration"),
    "Sa": ("m s-2", "spectral acceleration (absolute)"),
}


def response_spectrum(
    gm: GroundMotion,
    periods: Any = None,
    damping: float | Sequence[float] = 0.05,
    *,
    steps_per_period: int = 100,
    free_vibration: bool = True,
) -> xr.Dataset:
    """Elastic response spectrum of a ground motion.

    Parameters
    ----------
    gm : GroundMotion
        The record (acceleration [m/s²] linear between samples).
    periods : array_like, optional
        Oscillator periods T [s], > 0. Default :data:`DEFAULT_PERIODS` (0.01-10 s).
    damping : float or sequence of float
        Damping ratio(s) ζ [-], 0 <= ζ < 1. A sequence adds a ``damping`` dimension.
    steps_per_period : int
        The integration step is refined to at most T/steps_per_period (default 100: the peak
        of a sampled sinusoid is then within 0.05 %) and to at most dt/4.
    free_vibration : bool
        Include one period of free vibration after the record ends (default True); the ground
        acceleration is zero after the last sample (a jump if that sample is not zero).

    Returns
    -------
    xarray.Dataset
        Variables ``Sd``, ``Sv``, ``PSv``, ``PSa``, ``Sa`` over ``period`` (and ``damping`` when
        a sequence is given), each with ``units`` and ``long_name``.

    References
    ----------
    .. [1] Nigam, N.C. and Jennings, P.C. (1969). Calculation of response spectra from
       strong-motion earthquake records. Bull. Seismol. Soc. Am. 59(2), 909-922.
    .. [2] Chopra, A.K. (2012). Dynamics of Structures, 4th ed., Prentice Hall, §5.2 and §6.6.
    """
    periods = _check_periods(DEFAULT_PERIODS if periods is None else periods)
    dampings = np.atleast_1d(np.asarray(damping, dtype=float))
    scalar = np.ndim(damping) == 0
    peaks = np.stack(
        [
            spectral_peaks(
                gm.acceleration,
                gm.dt,
                periods,
                float(z),
                steps_per_period=steps_per_period,
                free_vibration=free_vibration,
            )
            for z in dampings
        ]
    )  # (damping, period, 3)
    omega = 2.0 * np.pi / periods
    data = {
        "Sd": peaks[..., 0],
        "Sv": peaks[..., 1],
        "PSv": omega * peaks[..., 0],
        "PSa": omega**2 * peaks[..., 0],
        "Sa": peaks[..., 2],
    }
    coords = {
        "period": ("period", periods, {"units": "s", "long_name": "oscillator period"}),
        "damping": ("damping", dampings, {"units": "1", "long_name": "damping ratio"}),
    }
    ds = xr.Dataset(
        {
            name: (
                ("damping", "period"),
                values,
                {"units": _VARIABLES[name][0], "long_name": _VARIABLES[name][1]},
            )
            for name, values in data.items()
        },
        coords=coords,
    )
    if scalar:
        ds = ds.squeeze("damping")
    ds.attrs.update(
        record=gm.name,
        record_dt=gm.dt,
        method="Nigam-Jennings exact piecewise-linear recurrence",
        steps_per_period=int(steps_per_period),
        free_vibration=int(bool(free_vibration)),
        pounding_version=__version__,
    )
    return ds


def response_spectra(
    gms: Iterable[GroundMotion],
    periods: Any = None,
    damping: float | Sequence[float] = 0.05,
    **kwargs: Any,
) -> xr.Dataset:
    """Response spectra of several records, concatenated along a ``record`` dimension."""
    gms = list(gms)
    if not gms:
        raise PoundingInputError("response_spectra: no records given")
    names: list[str] = []
    for gm in gms:
        name = gm.name
        k = 2
        while name in names:
            name = f"{gm.name} ({k})"
            k += 1
        names.append(name)
    parts = [response_spectrum(gm, periods, damping, **kwargs) for gm in gms]
    ds = xr.concat(parts, dim="record", combine_attrs="drop_conflicts")
    ds = ds.assign_coords(record=("record", names, {"long_name": "record"}))
    ds.attrs.pop("record", None)
    ds.attrs.pop("record_dt", None)
    return ds


# ---------------------------------------------------------------------------------------------
# Design spectra
# ---------------------------------------------------------------------------------------------


def _design_array(periods: Any, values: np.ndarray, name: str, **attrs: Any) -> xr.DataArray:
    return xr.DataArray(
        values,
        dims="period",
        coords={"period": ("period", periods, {"units": "s", "long_name": "oscillator period"})},
        name="PSa",
        attrs={
            "units": "m s-2",
            "long_name": f"{name} design pseudo-spectral acceleration",
            **attrs,
        },
    )


def _design_periods(periods: Any) -> np.ndarray:
    p = np.atleast_1d(np.asarray(DEFAULT_PERIODS if periods is None else periods, dtype=float))
    if p.ndim != 1 or not np.all(np.isfinite(p)) or np.any(p < 0):
        raise PoundingInputError(f"periods must be a 1-D array of values >= 0 [s], got {p}")
    return p


def _positive_g(value: float, field: str, what: str, high: float) -> float:
    """A design-spectrum parameter in (0, high]: S_DS = 1e300 g overflowed the spectrum."""
    value = float(value)
    if not 0.0 < value <= high:
        raise PoundingInputError(
            f"{what}: {field} must be a positive number <= {high:g}, got {value}"
        )
    return value


def asce7_spectrum(
    periods: Any = None, *, s_ds: float, s_d1: float, t_l: float = 8.0
) -> xr.DataArray:
    """ASCE 7 design response spectrum (two-period shape), PSa [m/s²] over ``period``.

    .. math::
        S_a = \\begin{cases}
        S_{DS}\\,(0.4 + 0.6\\,T/T_0) & T < T_0 \\\\
        S_{DS} & T_0 \\le T \\le T_S \\\\
        S_{D1}/T & T_S < T \\le T_L \\\\
        S_{D1}\\,T_L/T^2 & T > T_L
        \\end{cases}, \\qquad T_0 = 0.2\\,S_{D1}/S_{DS},\\; T_S = S_{D1}/S_{DS}

    (ASCE 7-16 §11.4.6, Eqs. 11.4-5 to 11.4-8; times g.)

    Parameters
    ----------
    periods : array_like, optional
        Periods T [s] >= 0.
    s_ds, s_d1 : float
        Design spectral accelerations at short periods and at 1 s [g] (e.g. 1.0 and 0.6 for
        FEMA P695 SDC Dmax).
    t_l : float
        Long-period transition period T_L [s] (4 to 16 s in the ASCE 7 maps).

    References
    ----------
    .. [1] ASCE (2017). Minimum Design Loads and Associated Criteria for Buildings and Other
       Structures, ASCE/SEI 7-16, §11.4.6.
    """
    what = "asce7_spectrum"
    s_ds = _positive_g(s_ds, "s_ds [g]", what, 10.0)
    s_d1 = _positive_g(s_d1, "s_d1 [g]", what, 10.0)
    t_l = _positive_g(t_l, "t_l [s]", what, PERIOD_RANGE[1])
    t = _design_periods(periods)
    t0, ts = 0.2 * s_d1 / s_ds, s_d1 / s_ds
    safe = np.maximum(t, 1e-12)
    sa = np.select(
        [t < t0, t <= ts, t <= t_l],
        [s_ds * (0.4 + 0.6 * t / t0), np.full_like(t, s_ds), s_d1 / safe],
        s_d1 * t_l / safe**2,
    )
    return _design_array(t, sa * G, "ASCE 7", s_ds=s_ds, s_d1=s_d1, t_l=t_l, damping=0.05)


#: Eurocode 8 Tables 3.2 (Type 1) and 3.3 (Type 2): ground type -> (S, T_B, T_C, T_D).
EC8_GROUND_TYPES: dict[int, dict[str, tuple[float, float, float, float]]] = {
    1: {
        "A": (1.0, 0.15, 0.4, 2.0),
        "B": (1.2, 0.15, 0.5, 2.0),
        "C": (1.15, 0.20, 0.6, 2.0),
        "D": (1.35, 0.20, 0.8, 2.0),
        "E": (1.4, 0.15, 0.5, 2.0),
    },
    2: {
        "A": (1.0, 0.05, 0.25, 1.2),
        "B": (1.35, 0.05, 0.25, 1.2),
        "C": (1.5, 0.10, 0.25, 1.2),
        "D": (1.8, 0.10, 0.30, 1.2),
        "E": (1.6, 0.05, 0.25, 1.2),
    },
}


def eurocode8_spectrum(
    periods: Any = None,
    *,
    a_g: float,
    ground_type: str = "C",
    spectrum_type: int = 1,
    damping: float = 0.05,
) -> xr.DataArray:
    """Eurocode 8 horizontal elastic response spectrum S_e(T), PSa [m/s²] over ``period``.

    .. math::
        S_e = a_g S \\begin{cases}
        1 + \\frac{T}{T_B}(2.5\\eta - 1) & 0 \\le T \\le T_B \\\\
        2.5\\eta & T_B \\le T \\le T_C \\\\
        2.5\\eta\\,T_C/T & T_C \\le T \\le T_D \\\\
        2.5\\eta\\,T_C T_D/T^2 & T_D \\le T
        \\end{cases}, \\qquad \\eta = \\sqrt{10/(5 + \\xi)} \\ge 0.55

    (EN 1998-1:2004 Eqs. 3.2-3.6, ξ in percent; S, T_B, T_C, T_D from Tables 3.2/3.3.)

    Parameters
    ----------
    a_g : float
        Design ground acceleration on type A ground [m/s²] (γ_I a_gR).
    ground_type : {"A", "B", "C", "D", "E"}
    spectrum_type : {1, 2}
        Type 1 (large magnitude, Ms > 5.5) or Type 2.
    damping : float
        Viscous damping ratio ζ [-] (0.05 gives η = 1).

    References
    ----------
    .. [1] CEN (2004). Eurocode 8: Design of structures for earthquake resistance - Part 1,
       EN 1998-1:2004, §3.2.2.2.
    """
    what = "eurocode8_spectrum"
    a_g = _positive_g(a_g, "a_g [m/s2]", what, 10.0 * G)
    try:
        table = EC8_GROUND_TYPES[int(spectrum_type)]
    except (KeyError, ValueError, TypeError):
        raise PoundingInputError(
            f"{what}: spectrum_type must be 1 or 2, got {spectrum_type!r}"
        ) from None
    key = str(ground_type).strip().upper()
    if key not in table:
        raise PoundingInputError(
            f"{what}: ground_type must be one of A, B, C, D, E, got {ground_type!r}"
        )
    s, tb, tc, td = table[key]
    damping = _check_damping(damping)
    eta = max(math.sqrt(10.0 / (5.0 + 100.0 * damping)), 0.55)  # Eq. 3.6
    t = _design_periods(periods)
    safe = np.maximum(t, 1e-12)
    se = (
        a_g
        * s
        * np.select(
            [t <= tb, t <= tc, t <= td],
            [1.0 + t / tb * (2.5 * eta - 1.0), np.full_like(t, 2.5 * eta), 2.5 * eta * tc / safe],
            2.5 * eta * tc * td / safe**2,
        )
    )
    return _design_array(
        t,
        se,
        f"Eurocode 8 Type {int(spectrum_type)} ground {key}",
        a_g=a_g,
        ground_type=key,
        spectrum_type=int(spectrum_type),
        damping=damping,
    )


#: Design spectra by name.
DESIGN_SPECTRA: dict[str, Callable[..., xr.DataArray]] = {
    "asce7": asce7_spectrum,
    "ec8": eurocode8_spectrum,
}


def design_spectrum(code: str, periods: Any = None, **params: Any) -> xr.DataArray:
    """Design spectrum by code name (``asce7``, ``ec8``)."""
    try:
        func = DESIGN_SPECTRA[code]
    except KeyError:
        allowed = ", ".join(DESIGN_SPECTRA)
        raise PoundingInputError(f"unknown design spectrum {code!r}; allowed: {allowed}") from None
    return func(periods, **params)
