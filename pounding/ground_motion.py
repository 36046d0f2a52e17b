"""Ground motions: the :class:`GroundMotion` type and analytic excitations.

A ground motion is a uniformly sampled ground acceleration [m/s²] with its time step [s], a name and
free-form metadata (source, units as read, processing chain). Between samples the acceleration is
taken as linear, which is what the integrators and the response-spectrum recurrence assume.

Record files are read in :mod:`pounding.records`; this module holds no I/O.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from pounding.errors import PoundingInputError
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
            raise PoundingInputError(
                f"ground motion {self.name!r}: acceleration must be 1-D, got {acc.ndim}-D"
            )
        if acc.size < 2:
            raise PoundingInputError(
                f"ground motion {self.name!r}: acceleration needs >= 2 samples"
            )
        bad = np.flatnonzero(~np.isfinite(acc))
        if bad.size:
            raise PoundingInputError(
                f"ground motion {self.name!r}: acceleration sample {bad[0]} is {acc[bad[0]]}; "
                "all samples must be finite"
            )
        dt = float(self.dt)
        if not (math.isfinite(dt) and dt > 0.0):
            raise PoundingInputError(
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

    @functools.cached_property
    def time(self) -> np.ndarray:
        """Sample times [s] (read-only)."""
        # built once: `at` is called per time step by solve_ivp right-hand sides
        time = self.dt * np.arange(self.npts)
        time.setflags(write=False)
        return time

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
            raise PoundingInputError(f"scale factor must be finite, got {factor}")
        return self.with_step(f"scaled by {factor:g}", self.acceleration * factor)


def _grid(duration: float, dt: float, what: str) -> np.ndarray:
    if not (duration > 0 and math.isfinite(duration)):
        raise PoundingInputError(f"{what}: duration must be > 0 [s], got {duration}")
    if not (dt > 0 and math.isfinite(dt)):
        raise PoundingInputError(f"{what}: dt must be > 0 [s], got {dt}")
    n = int(math.floor(duration / dt + 1e-9)) + 1
    return dt * np.arange(n)


def _positive(value: float, field: str, what: str) -> float:
    value = float(value)
    if not (value > 0 and math.isfinite(value)):
        raise PoundingInputError(f"{what}: {field} must be a positive number, got {value}")
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
        raise PoundingInputError(
            f"unknown ground motion type {kind!r}; allowed: {allowed}"
        ) from None
    return factory(**params)


# ---------------------------------------------------------------------------------------------
# Integration of the piecewise-linear acceleration
# ---------------------------------------------------------------------------------------------


def ground_velocity(gm: GroundMotion) -> np.ndarray:
    """Ground velocity [m/s] at the samples, starting from rest.

    Exact for acceleration linear between samples (trapezoidal rule):

    .. math:: v_{i+1} = v_i + \\tfrac{\\Delta t}{2} (a_i + a_{i+1})
    """
    a = gm.acceleration
    return np.concatenate(([0.0], np.cumsum(0.5 * gm.dt * (a[:-1] + a[1:]))))


def ground_displacement(gm: GroundMotion) -> np.ndarray:
    """Ground displacement [m] at the samples, starting from rest.

    Exact for acceleration linear between samples:

    .. math:: u_{i+1} = u_i + v_i \\Delta t + \\tfrac{\\Delta t^2}{6} (2 a_i + a_{i+1})
    """
    a, dt = gm.acceleration, gm.dt
    v = ground_velocity(gm)
    du = v[:-1] * dt + dt * dt / 6.0 * (2.0 * a[:-1] + a[1:])
    return np.concatenate(([0.0], np.cumsum(du)))


# ---------------------------------------------------------------------------------------------
# Processing: each step returns a new record and appends itself to metadata["processing"]
# ---------------------------------------------------------------------------------------------


def _check_range(value: float, field: str, low: float, high: float, what: str) -> float:
    value = float(value)
    if not (math.isfinite(value) and low <= value <= high):
        raise PoundingInputError(f"{what}: {field} must be in [{low:g}, {high:g}], got {value}")
    return value


def remove_mean(gm: GroundMotion) -> GroundMotion:
    """Subtract the mean acceleration (the simplest baseline correction)."""
    mean = float(np.mean(gm.acceleration))
    return gm.with_step(f"removed mean {mean:.6g} m/s2", gm.acceleration - mean)


def baseline_correct(gm: GroundMotion, *, order: int = 2) -> GroundMotion:
    """Polynomial baseline correction fitted on displacement.

    A polynomial :math:`p(t)` of degree ``order`` is fitted by least squares to the ground
    displacement obtained by integrating the record twice; its second derivative is the
    acceleration baseline that is removed:

    .. math:: \\tilde a(t) = a(t) - p''(t)

    Parameters
    ----------
    gm : GroundMotion
    order : int
        Degree of the displacement polynomial, 2 to 10 (2 removes a constant acceleration
        offset, 3 a linear acceleration drift).

    References
    ----------
    .. [1] Boore, D.M. and Bommer, J.J. (2005). Processing of strong-motion accelerograms:
       needs, options and consequences. Soil Dynamics and Earthquake Engineering 25, 93-115.
       doi:10.1016/j.soildyn.2004.10.007
    """
    if isinstance(order, bool) or not isinstance(order, (int, np.integer)) or not 2 <= order <= 10:
        raise PoundingInputError(
            f"baseline_correct: order must be an integer in 2..10, got {order!r}"
        )
    # The record starts at rest, so the displacement baseline has no constant or linear term:
    # fit d(t) ≈ Σ_{j=2..order} c_j t^j. (A full polynomial would leave p'(0) t in the corrected
    # displacement, because integrating p'' from rest gives back p − p(0) − p'(0) t only.)
    t = gm.time
    scale = max(gm.duration, gm.dt)
    x = t / scale
    powers = np.arange(2, int(order) + 1)
    coef, *_ = np.linalg.lstsq(x[:, None] ** powers, ground_displacement(gm), rcond=None)
    baseline = (x[:, None] ** (powers - 2) * (powers * (powers - 1) * coef)).sum(axis=1) / scale**2
    return gm.with_step(
        f"baseline correction: degree-{order} polynomial fitted on displacement",
        gm.acceleration - baseline,
    )


def bandpass(
    gm: GroundMotion,
    *,
    low: float | None = 0.1,
    high: float | None = 25.0,
    order: int = 4,
) -> GroundMotion:
    """Zero-phase Butterworth filter (forward and backward, so the amplitude response is squared).

    Parameters
    ----------
    low : float or None
        High-pass corner frequency [Hz]; None for a low-pass filter only.
    high : float or None
        Low-pass corner frequency [Hz], below the Nyquist frequency 1/(2 dt); None for a
        high-pass filter only.
    order : int
        Order of the Butterworth design (1 to 10), applied twice.
    """
    from scipy import signal

    what = "bandpass"
    nyquist = 0.5 / gm.dt
    if low is None and high is None:
        raise PoundingInputError(f"{what}: give at least one of low, high [Hz]")
    if not isinstance(order, (int, np.integer)) or not 1 <= order <= 10:
        raise PoundingInputError(f"{what}: order must be an integer in 1..10, got {order!r}")
    if low is not None:
        low = _check_range(low, "low", 0.0, nyquist, what)
        if low == 0.0:
            raise PoundingInputError(f"{what}: low must be > 0 Hz, got 0")
    if high is not None:
        high = _check_range(high, "high", 0.0, nyquist, what)
        if high >= nyquist or high == 0.0:
            raise PoundingInputError(
                f"{what}: high must be in (0, {nyquist:g}) Hz (below Nyquist), got {high:g}"
            )
    if low is not None and high is not None and not low < high:
        raise PoundingInputError(f"{what}: low ({low:g} Hz) must be below high ({high:g} Hz)")
    if low is None:
        sos = signal.butter(order, high, btype="lowpass", fs=1.0 / gm.dt, output="sos")
    elif high is None:
        sos = signal.butter(order, low, btype="highpass", fs=1.0 / gm.dt, output="sos")
    else:
        sos = signal.butter(order, [low, high], btype="bandpass", fs=1.0 / gm.dt, output="sos")
    acc = signal.sosfiltfilt(sos, gm.acceleration)
    return gm.with_step(f"zero-phase Butterworth order {order}, low={low} Hz, high={high} Hz", acc)


def taper(gm: GroundMotion, *, fraction: float = 0.05, side: str = "both") -> GroundMotion:
    """Half-cosine (Tukey) taper over ``fraction`` of the record length at ``side``.

    ``side`` is ``"start"``, ``"end"`` or ``"both"``.
    """
    what = "taper"
    fraction = _check_range(fraction, "fraction", 0.0, 0.5, what)
    if side not in ("start", "end", "both"):
        raise PoundingInputError(f"{what}: side must be 'start', 'end' or 'both', got {side!r}")
    n = gm.npts
    m = int(round(fraction * (n - 1)))
    w = np.ones(n)
    if m > 0:
        ramp = 0.5 * (1.0 - np.cos(np.pi * np.arange(m) / m))
        if side in ("start", "both"):
            w[:m] = ramp
        if side in ("end", "both"):
            w[n - m :] = ramp[::-1]
    return gm.with_step(f"cosine taper {fraction:g} at {side}", gm.acceleration * w)


def zero_pad(gm: GroundMotion, *, before: float = 0.0, after: float = 0.0) -> GroundMotion:
    """Add zeros for ``before`` [s] in front of and ``after`` [s] behind the record."""
    what = "zero_pad"
    before = _check_range(before, "before", 0.0, math.inf, what)
    after = _check_range(after, "after", 0.0, math.inf, what)
    nb = int(round(before / gm.dt))
    na = int(round(after / gm.dt))
    acc = np.concatenate((np.zeros(nb), gm.acceleration, np.zeros(na)))
    return gm.with_step(f"zero padding {nb * gm.dt:g} s before, {na * gm.dt:g} s after", acc)


def free_vibration_tail(gm: GroundMotion, *, duration: float) -> GroundMotion:
    """Append ``duration`` [s] of zero ground acceleration so a simulation records free vibration.

    If the last sample is not zero, the first added interval ramps it linearly to zero.
    """
    duration = _check_range(duration, "duration", 0.0, math.inf, "free_vibration_tail")
    n = int(math.ceil(duration / gm.dt - 1e-9))
    acc = np.concatenate((gm.acceleration, np.zeros(n)))
    return gm.with_step(f"free-vibration tail of {n * gm.dt:g} s", acc)


def resample(gm: GroundMotion, *, dt: float) -> GroundMotion:
    """Resample to a new time step ``dt`` [s].

    Refining (``dt`` smaller) interpolates linearly, which reproduces the piecewise-linear record
    exactly. Coarsening first applies a zero-phase 8th-order Butterworth low-pass at 0.8 times the
    new Nyquist frequency (anti-aliasing), then interpolates.
    """
    from scipy import signal

    dt = _positive(dt, "dt", "resample")
    acc = gm.acceleration
    note = "linear interpolation"
    if dt > gm.dt * (1 + 1e-12):
        corner = 0.8 * 0.5 / dt
        sos = signal.butter(8, corner, btype="lowpass", fs=1.0 / gm.dt, output="sos")
        acc = signal.sosfiltfilt(sos, acc)
        note = f"anti-alias low-pass {corner:.4g} Hz, linear interpolation"
    n = int(math.floor(gm.duration / dt + 1e-9)) + 1
    if n < 2:
        raise PoundingInputError(f"resample: dt = {dt:g} s leaves fewer than 2 samples")
    t_new = dt * np.arange(n)
    return gm.with_step(
        f"resampled from dt={gm.dt:g} s to dt={dt:g} s ({note})",
        np.interp(t_new, gm.time, acc),
        dt=dt,
    )


def trim_significant(
    gm: GroundMotion,
    *,
    start: float = 0.05,
    end: float = 0.95,
    before: float = 0.0,
    after: float = 0.0,
) -> GroundMotion:
    """Keep the part of the record between the ``start`` and ``end`` fractions of Arias intensity.

    ``before`` and ``after`` [s] keep that much more of the record on either side. The kept part
    is shifted to start at t = 0; ``metadata["start_time"]`` accumulates the removed lead [s].
    """
    what = "trim_significant"
    start = _check_range(start, "start", 0.0, 1.0, what)
    end = _check_range(end, "end", 0.0, 1.0, what)
    if not start < end:
        raise PoundingInputError(f"{what}: start ({start}) must be below end ({end})")
    before = _check_range(before, "before", 0.0, math.inf, what)
    after = _check_range(after, "after", 0.0, math.inf, what)
    t1, t2 = significant_window(gm, start=start, end=end)
    i1 = max(int(math.floor((t1 - before) / gm.dt + 1e-9)), 0)
    i2 = min(int(math.ceil((t2 + after) / gm.dt - 1e-9)), gm.npts - 1)
    if i2 - i1 < 1:
        i2 = min(i1 + 1, gm.npts - 1)
        i1 = i2 - 1
    out = gm.with_step(
        f"trimmed to {start:g}-{end:g} Arias window {t1:.4g}-{t2:.4g} s "
        f"(+{before:g} s before, +{after:g} s after)",
        gm.acceleration[i1 : i2 + 1].copy(),
    )
    out.metadata["start_time"] = float(gm.metadata.get("start_time", 0.0)) + i1 * gm.dt
    return out


def scale_to_pga(gm: GroundMotion, *, pga: float) -> GroundMotion:
    """Scale the record so that its peak ground acceleration is ``pga`` [m/s²]."""
    pga = _positive(pga, "pga", "scale_to_pga")
    factor = pga / gm.pga
    return gm.with_step(f"scaled by {factor:.6g} to PGA {pga:.6g} m/s2", gm.acceleration * factor)


def scale_to_sa(
    gm: GroundMotion, *, sa: float, period: float, damping: float = 0.05
) -> GroundMotion:
    """Scale the record so that its pseudo-spectral acceleration at ``period`` is ``sa``.

    Parameters
    ----------
    sa : float
        Target pseudo-spectral acceleration PSa(T) = ω² Sd(T) [m/s²].
    period : float
        Oscillator period T [s].
    damping : float
        Damping ratio ζ [-], 0 <= ζ < 1.
    """
    what = "scale_to_sa"
    sa = _positive(sa, "sa", what)
    period = _positive(period, "period", what)
    current = float(pseudo_spectral_acceleration(gm, [period], damping=damping)[0])
    factor = sa / current
    return gm.with_step(
        f"scaled by {factor:.6g} to PSa({period:g} s, {damping:g}) = {sa:.6g} m/s2",
        gm.acceleration * factor,
    )


#: Processing steps by name (used by case files: ``processing = [{step = "bandpass", ...}]``).
PROCESSING_STEPS = {
    "remove_mean": remove_mean,
    "baseline": baseline_correct,
    "bandpass": bandpass,
    "taper": taper,
    "zero_pad": zero_pad,
    "tail": free_vibration_tail,
    "resample": resample,
    "trim": trim_significant,
    "scale_pga": scale_to_pga,
    "scale_sa": scale_to_sa,
}


def process(gm: GroundMotion, step: str, **params: Any) -> GroundMotion:
    """Apply the processing step named ``step`` (a key of :data:`PROCESSING_STEPS`)."""
    try:
        func = PROCESSING_STEPS[step]
    except KeyError:
        allowed = ", ".join(PROCESSING_STEPS)
        raise PoundingInputError(f"unknown processing step {step!r}; allowed: {allowed}") from None
    return func(gm, **params)


# ---------------------------------------------------------------------------------------------
# Intensity measures
# ---------------------------------------------------------------------------------------------


def husid(gm: GroundMotion) -> np.ndarray:
    """Cumulative Arias intensity [m/s] at the samples (Husid plot, not normalised).

    Exact integral of the squared piecewise-linear acceleration:
    :math:`\\int_{t_i}^{t_{i+1}} a^2\\,dt = \\tfrac{\\Delta t}{3}(a_i^2 + a_i a_{i+1} + a_{i+1}^2)`.
    """
    a = gm.acceleration
    seg = gm.dt / 3.0 * (a[:-1] ** 2 + a[:-1] * a[1:] + a[1:] ** 2)
    return np.pi / (2.0 * G) * np.concatenate(([0.0], np.cumsum(seg)))


def arias_intensity(gm: GroundMotion) -> float:
    """Arias intensity [m/s].

    .. math:: I_a = \\frac{\\pi}{2 g} \\int_0^{t_d} a_g(t)^2 \\, dt

    References
    ----------
    .. [1] Arias, A. (1970). A measure of earthquake intensity. In R.J. Hansen (ed.), Seismic
       Design for Nuclear Power Plants, MIT Press, 438-483.
    """
    return float(husid(gm)[-1])


def significant_window(
    gm: GroundMotion, *, start: float = 0.05, end: float = 0.95
) -> tuple[float, float]:
    """Times [s] at which the cumulative Arias intensity reaches ``start`` and ``end`` of its total."""
    h = husid(gm)
    if h[-1] <= 0.0:
        raise PoundingInputError(
            f"ground motion {gm.name!r}: zero Arias intensity, no significant window"
        )
    h = h / h[-1]
    # h is non-decreasing; interpolate on its strictly increasing part
    keep = np.concatenate(([True], np.diff(h) > 0))
    t1, t2 = np.interp([start, end], h[keep], gm.time[keep])
    return float(t1), float(t2)


def significant_duration(gm: GroundMotion, *, start: float = 0.05, end: float = 0.95) -> float:
    """Significant duration [s] between ``start`` and ``end`` fractions of Arias intensity.

    D5-95 by default; D5-75 with ``end=0.75``.

    References
    ----------
    .. [1] Trifunac, M.D. and Brady, A.G. (1975). A study on the duration of strong earthquake
       ground motion. Bulletin of the Seismological Society of America 65(3), 581-626.
    """
    t1, t2 = significant_window(gm, start=start, end=end)
    return t2 - t1


def cumulative_absolute_velocity(gm: GroundMotion) -> float:
    """Cumulative absolute velocity CAV = ∫|a_g| dt [m/s], exact for the piecewise-linear record.

    References
    ----------
    .. [1] EPRI (1988). A criterion for determining exceedance of the operating basis earthquake.
       Report NP-5930, Electric Power Research Institute, Palo Alto.
    """
    a0, a1 = gm.acceleration[:-1], gm.acceleration[1:]
    same = a0 * a1 >= 0.0
    denom = np.where(same, 1.0, np.abs(a0) + np.abs(a1))
    area = np.where(same, 0.5 * (np.abs(a0) + np.abs(a1)), 0.5 * (a0**2 + a1**2) / denom)
    return float(gm.dt * np.sum(area))


def _fourier_amplitude(gm: GroundMotion) -> tuple[np.ndarray, np.ndarray]:
    amp = np.abs(np.fft.rfft(gm.acceleration)) * gm.dt
    freq = np.fft.rfftfreq(gm.npts, gm.dt)
    return freq, amp


def predominant_period(gm: GroundMotion) -> float:
    """Period [s] of the largest Fourier amplitude of the acceleration (Kramer 1996, §3.3.2).

    References
    ----------
    .. [1] Kramer, S.L. (1996). Geotechnical Earthquake Engineering. Prentice Hall, §3.3.2.
    """
    freq, amp = _fourier_amplitude(gm)
    k = 1 + int(np.argmax(amp[1:]))
    return float(1.0 / freq[k])


def mean_period(gm: GroundMotion, *, fmin: float = 0.25, fmax: float = 20.0) -> float:
    """Mean period T_m [s] of the Fourier amplitude spectrum C(f) between ``fmin`` and ``fmax`` [Hz].

    .. math:: T_m = \\frac{\\sum_i C_i^2 / f_i}{\\sum_i C_i^2}

    References
    ----------
    .. [1] Rathje, E.M., Abrahamson, N.A. and Bray, J.D. (1998). Simplified frequency content
       estimates of earthquake ground motions. J. Geotech. Geoenviron. Eng. 124(2), 150-159.
       doi:10.1061/(ASCE)1090-0241(1998)124:2(150)
    """
    freq, amp = _fourier_amplitude(gm)
    band = (freq >= fmin) & (freq <= fmax)
    if not np.any(band) or np.sum(amp[band] ** 2) == 0.0:
        return float("nan")
    c2 = amp[band] ** 2
    return float(np.sum(c2 / freq[band]) / np.sum(c2))


#: Intensity measures: name -> (function, units, long name). SI units.
INTENSITY_MEASURES: dict[str, tuple[Any, str, str]] = {
    "pga": (lambda gm: gm.pga, "m s-2", "peak ground acceleration"),
    "pga_time": (
        lambda gm: float(gm.time[np.argmax(np.abs(gm.acceleration))]),
        "s",
        "time of peak ground acceleration",
    ),
    "pgv": (lambda gm: float(np.max(np.abs(ground_velocity(gm)))), "m s-1", "peak ground velocity"),
    "pgd": (
        lambda gm: float(np.max(np.abs(ground_displacement(gm)))),
        "m",
        "peak ground displacement",
    ),
    "arias_intensity": (arias_intensity, "m s-1", "Arias intensity"),
    "d5_95": (significant_duration, "s", "significant duration D5-95"),
    "d5_75": (
        lambda gm: significant_duration(gm, start=0.05, end=0.75),
        "s",
        "significant duration D5-75",
    ),
    "cav": (cumulative_absolute_velocity, "m s-1", "cumulative absolute velocity"),
    "predominant_period": (predominant_period, "s", "predominant period (Fourier)"),
    "mean_period": (mean_period, "s", "mean period Tm (Rathje 1998)"),
}


def intensity_measures(gm: GroundMotion) -> dict[str, float]:
    """All intensity measures of :data:`INTENSITY_MEASURES` in SI units (NaN where undefined)."""
    out: dict[str, float] = {}
    for name, (func, _, _) in INTENSITY_MEASURES.items():
        try:
            out[name] = float(func(gm))
        except ValueError:
            out[name] = float("nan")
    return out


# ---------------------------------------------------------------------------------------------
# Elastic SDOF response to the piecewise-linear record (Nigam-Jennings)
# ---------------------------------------------------------------------------------------------


def nigam_jennings_coefficients(omega, damping, h):
    """Exact recurrence coefficients of a damped SDOF under piecewise-linear ground acceleration.

    For :math:`\\ddot x + 2\\zeta\\omega\\dot x + \\omega^2 x = -a_g(t)` with :math:`a_g` linear
    over a step :math:`h`:

    .. math::
        x_{i+1} = A x_i + B \\dot x_i + C a_i + D a_{i+1}, \\qquad
        \\dot x_{i+1} = A' x_i + B' \\dot x_i + C' a_i + D' a_{i+1}

    (Chopra 2012, Table 5.2.1, with :math:`p = -a_g` and :math:`k = \\omega^2` per unit mass.)
    Written with numpy ufuncs so that it works on arrays and compiles with numba on scalars.

    Parameters
    ----------
    omega : float or ndarray
        Natural circular frequency ω [rad/s], > 0.
    damping : float
        Damping ratio ζ [-], 0 <= ζ < 1.
    h : float
        Step [s].

    Returns
    -------
    tuple of 8
        A, B [s], C [s²], D [s²], A' [1/s], B', C' [s], D' [s].

    References
    ----------
    .. [1] Nigam, N.C. and Jennings, P.C. (1969). Calculation of response spectra from
       strong-motion earthquake records. Bull. Seismol. Soc. Am. 59(2), 909-922.
    .. [2] Chopra, A.K. (2012). Dynamics of Structures, 4th ed., Prentice Hall, §5.2.
    """
    z = damping
    sq = np.sqrt(1.0 - z * z)
    wd = omega * sq
    e = np.exp(-z * omega * h)
    s = np.sin(wd * h)
    c = np.cos(wd * h)
    k = omega * omega
    wh = omega * h
    A = e * (z / sq * s + c)
    B = e * s / wd
    C = (2 * z / wh + e * (((1 - 2 * z * z) / (wd * h) - z / sq) * s - (1 + 2 * z / wh) * c)) / k
    D = (1 - 2 * z / wh + e * ((2 * z * z - 1) / (wd * h) * s + 2 * z / wh * c)) / k
    Ap = -e * omega / sq * s
    Bp = e * (c - z / sq * s)
    Cp = (-1 / h + e * ((omega / sq + z / (h * sq)) * s + c / h)) / k
    Dp = (1 - e * (z / sq * s + c)) / (k * h)
    # p = -a_g: the forcing coefficients change sign
    return A, B, -C, -D, Ap, Bp, -Cp, -Dp


#: Fewest sub-steps per record step. The relative velocity and the absolute acceleration of a
#: long-period oscillator follow the ground velocity, whose peaks are as sharp as the record's
#: samples; four sub-steps bring their sampling error below 0.05 %.
MIN_SUBSTEPS = 4


def substeps(period, dt, steps_per_period):
    """Sub-steps per record step: the SDOF step is at most T/steps_per_period and dt/4."""
    m = np.ceil(steps_per_period * dt / period - 1e-9)
    return np.maximum(MIN_SUBSTEPS, m).astype(np.int64)


def _check_damping(damping: float) -> float:
    damping = float(damping)
    if not (math.isfinite(damping) and 0.0 <= damping < 1.0):
        raise PoundingInputError(f"damping ratio must be in [0, 1), got {damping}")
    return damping


#: Oscillator periods [s] a spectrum is computed at: a period of 1e300 s divided by zero in the
#: oscillator's step, one of 1e9 s would sub-step its free vibration for hours and one of 1e-7 s
#: a 0.02 s record (T/100 sub-steps); 1e-5 s stands in for T = 0 (Sa = PGA).
PERIOD_RANGE = (1e-5, 100.0)


def _check_periods(periods: Any) -> np.ndarray:
    p = np.atleast_1d(np.asarray(periods, dtype=float))
    low, high = PERIOD_RANGE
    if p.ndim != 1 or p.size == 0 or not np.all((p >= low) & (p <= high)):
        raise PoundingInputError(
            f"periods must be a non-empty 1-D array of values from {low:g} to {high:g} [s], got {p}"
        )
    return p


def pseudo_spectral_acceleration(
    gm: GroundMotion,
    periods: Any,
    *,
    damping: float = 0.05,
    steps_per_period: int = 100,
) -> np.ndarray:
    """Pseudo-spectral acceleration PSa = ω² max|x| [m/s²] by the Nigam-Jennings recurrence.

    Pure numpy/scipy path (the recurrence is run as a second-order IIR filter with
    :func:`scipy.signal.lfilter`), used by layer-2 code (scaling, synthetic records). The public,
    compiled and complete spectra are :func:`pounding.spectra.response_spectrum`; the two are
    checked against each other in the tests. The step is refined to at most T/steps_per_period
    and dt/4 (linear interpolation of the record, exact for the piecewise-linear model) and one
    period of free vibration after the record is included (the record is taken to end with a
    jump to zero acceleration).
    """
    from scipy import signal

    damping = _check_damping(damping)
    periods = _check_periods(periods)
    out = np.empty(periods.size)
    t = gm.time
    for j, period in enumerate(periods):
        m = int(substeps(period, gm.dt, steps_per_period))
        h = gm.dt / m
        n_tail = int(math.ceil(period / h)) + 1
        fine_t = h * np.arange((gm.npts - 1) * m + 1)
        u = np.concatenate((np.interp(fine_t, t, gm.acceleration), np.zeros(n_tail)))
        omega = 2.0 * np.pi / period
        A, B, C, D, Ap, Bp, Cp, Dp = nigam_jennings_coefficients(omega, damping, h)
        # the step from the last sample to the tail is a jump to zero, not a ramp
        u0, u1 = u[:-1].copy(), u[1:]
        u0[fine_t.size - 1] = 0.0
        f = C * u0 + D * u1
        g = Cp * u0 + Dp * u1
        rhs = f.copy()
        rhs[1:] += -Bp * f[:-1] + B * g[:-1]
        x = signal.lfilter([1.0], [1.0, -(A + Bp), A * Bp - B * Ap], rhs)
        out[j] = omega * omega * np.max(np.abs(x))
    return out
