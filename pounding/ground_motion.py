"""Ground motions: the :class:`GroundMotion` type and analytic excitations.

A ground motion is a uniformly sampled ground acceleration [m/s²] with its time step [s], a name and
free-form metadata (source, units as read, processing chain). Between samples the acceleration is
taken as linear, which is what the integrators and the response-spectrum recurrence assume.

Record files are read in :mod:`pounding.records`; this module holds no I/O.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from pounding.units import G


@dataclasses.dataclass(frozen=True, eq=False)
class GroundMotion:
    """Uniformly sampled ground acceleration.

    Parameters
    ----------
    acceleration : array_like
        Ground acceleration samples [m/s²], the first at t = 0.
    dt : float
        Sampling interval [s], > 0.
    name : str
        Label used in results and reports.
    metadata : mapping
        Free-form provenance. ``metadata["processing"]`` (a list of strings), when present, is the
        processing chain in the order applied.
    """

    acceleration: np.ndarray
    dt: float
    name: str = "ground motion"
    metadata: Mapping[str, Any] = dataclasses.field(default_factory=dict)

    def __post_init__(self) -> None:
        acc = np.array(self.acceleration, dtype=float, copy=True)
        if acc.ndim != 1:
            raise ValueError(
                f"ground motion {self.name!r}: acceleration must be 1-D, got {acc.ndim}-D"
            )
        if acc.size < 2:
            raise ValueError(f"ground motion {self.name!r}: acceleration needs >= 2 samples")
        bad = np.flatnonzero(~np.isfinite(acc))
        if bad.size:
            raise ValueError(
                f"ground motion {self.name!r}: acceleration sample {bad[0]} is {acc[bad[0]]}; "
                "all samples must be finite"
            )
        dt = float(self.dt)
        if not (math.isfinite(dt) and dt > 0.0):
            raise ValueError(
                f"ground motion {self.name!r}: dt must be a positive number [s], got {dt}"
            )
        acc.setflags(write=False)
        object.__setattr__(self, "acceleration", acc)
        object.__setattr__(self, "dt", dt)
        object.__setattr__(self, "metadata", dict(self.metadata))

    @property
    def npts(self) -> int:
        """Number of samples."""
        return int(self.acceleration.size)

    @property
    def duration(self) -> float:
        """Time of the last sample [s]."""
        return self.dt * (self.npts - 1)

    @property
    def time(self) -> np.ndarray:
        """Sample times [s]."""
        return self.dt * np.arange(self.npts)

    @property
    def pga(self) -> float:
        """Peak ground acceleration [m/s²]."""
        return float(np.max(np.abs(self.acceleration)))

    def at(self, t: float | np.ndarray) -> float | np.ndarray:
        """Acceleration [m/s²] at time(s) ``t`` [s], linear between samples, zero outside the record."""
        return np.interp(t, self.time, self.acceleration, left=0.0, right=0.0)

    def replace(self, **changes: Any) -> GroundMotion:
        """A copy with some fields changed (the record itself is immutable)."""
        return dataclasses.replace(self, **changes)

    def with_step(
        self, step: str, acceleration: np.ndarray, dt: float | None = None
    ) -> GroundMotion:
        """A copy with new samples and ``step`` appended to ``metadata["processing"]``."""
        meta = dict(self.metadata)
        meta["processing"] = [*meta.get("processing", []), step]
        return dataclasses.replace(
            self, acceleration=acceleration, dt=self.dt if dt is None else dt, metadata=meta
        )

    def starting_from_rest(self) -> GroundMotion:
        """The record with a zero sample prepended when a_g(0) != 0.

        The structure starts at rest; a non-zero first sample would be a step in the ground
        acceleration at t = 0, so one interval of linear ramp from zero is added in front.
        """
        if self.acceleration[0] == 0.0:
            return self
        return self.with_step(
            "prepended a zero sample (a_g(0) was not 0)",
            np.concatenate(([0.0], self.acceleration)),
        )

    def scaled(self, factor: float) -> GroundMotion:
        """The record multiplied by ``factor``."""
        if not math.isfinite(factor):
            raise ValueError(f"scale factor must be finite, got {factor}")
        return self.with_step(f"scaled by {factor:g}", self.acceleration * factor)


def _grid(duration: float, dt: float, what: str) -> np.ndarray:
    if not (duration > 0 and math.isfinite(duration)):
        raise ValueError(f"{what}: duration must be > 0 [s], got {duration}")
    if not (dt > 0 and math.isfinite(dt)):
        raise ValueError(f"{what}: dt must be > 0 [s], got {dt}")
    n = int(math.floor(duration / dt + 1e-9)) + 1
    return dt * np.arange(n)


def _positive(value: float, field: str, what: str) -> float:
    value = float(value)
    if not (value > 0 and math.isfinite(value)):
        raise ValueError(f"{what}: {field} must be a positive number, got {value}")
    return value


def harmonic(
    *,
    amplitude: float = 0.3 * G,
    period: float = 0.5,
    duration: float = 10.0,
    dt: float = 0.005,
    cycles: float | None = None,
) -> GroundMotion:
    """Harmonic ground acceleration a_g(t) = A sin(2π t / T) [m/s²].

    ``cycles`` limits the excitation to that many periods, followed by zeros (free vibration).
    """
    what = "harmonic ground motion"
    period = _positive(period, "period", what)
    t = _grid(duration, dt, what)
    acc = amplitude * np.sin(2.0 * np.pi * t / period)
    if cycles is not None:
        acc[t > _positive(cycles, "cycles", what) * period] = 0.0
    meta = {"type": "harmonic", "amplitude": amplitude, "period": period, "cycles": cycles}
    return GroundMotion(acc, dt, name=f"harmonic T={period:g}s", metadata=meta)


def sine_pulse(
    *,
    amplitude: float = 0.3 * G,
    period: float = 0.5,
    duration: float = 10.0,
    dt: float = 0.005,
) -> GroundMotion:
    """One full-sine acceleration pulse of period T [s] and amplitude A [m/s²], then zeros.

    a_g(t) = A sin(2π t / T) for 0 <= t <= T, 0 afterwards: a near-fault velocity pulse idealisation
    whose ground velocity returns to zero.
    """
    what = "sine_pulse ground motion"
    period = _positive(period, "period", what)
    t = _grid(duration, dt, what)
    acc = np.where(t <= period, amplitude * np.sin(2.0 * np.pi * t / period), 0.0)
    meta = {"type": "sine_pulse", "amplitude": amplitude, "period": period}
    return GroundMotion(acc, dt, name=f"sine pulse T={period:g}s", metadata=meta)


def ricker(
    *,
    amplitude: float = 0.3 * G,
    period: float = 0.5,
    t0: float | None = None,
    duration: float = 10.0,
    dt: float = 0.005,
) -> GroundMotion:
    """Ricker wavelet acceleration pulse of peak ``amplitude`` [m/s²].

    a_g(t) = A (1 − 2 π² f² τ²) exp(−π² f² τ²), τ = t − t0, f = 1/T the peak (predominant)
    frequency [Hz]. ``t0`` defaults to 1.5 T so the wavelet starts from (numerically) zero.
    """
    what = "ricker ground motion"
    period = _positive(period, "period", what)
    t0 = 1.5 * period if t0 is None else float(t0)
    t = _grid(duration, dt, what)
    arg = (np.pi * (t - t0) / period) ** 2
    acc = amplitude * (1.0 - 2.0 * arg) * np.exp(-arg)
    acc[0] = 0.0
    meta = {"type": "ricker", "amplitude": amplitude, "period": period, "t0": t0}
    return GroundMotion(acc, dt, name=f"ricker T={period:g}s", metadata=meta)


#: Analytic excitations by case-file ``type`` name.
ANALYTIC_MOTIONS = {"harmonic": harmonic, "sine_pulse": sine_pulse, "ricker": ricker}


def analytic(kind: str, **params: Any) -> GroundMotion:
    """Build an analytic ground motion by name (``harmonic``, ``sine_pulse``, ``ricker``)."""
    try:
        factory = ANALYTIC_MOTIONS[kind]
    except KeyError:
        allowed = ", ".join(ANALYTIC_MOTIONS)
        raise ValueError(f"unknown ground motion type {kind!r}; allowed: {allowed}") from None
    return factory(**params)
