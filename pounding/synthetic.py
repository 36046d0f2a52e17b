"""Synthetic ground motions: filtered white noise and spectrum-compatible records.

* Stationary Gaussian white noise filtered by the Kanai-Tajimi or Clough-Penzien filter, then
  shaped by an amplitude envelope (Jennings-Housner-Tsai or Saragoni-Hart). Reproducible from an
  integer ``seed`` (numpy ``default_rng``).
* Spectrum-compatible records: Fourier amplitudes of an enveloped random-phase signal iterated
  until the 5 %-damped pseudo-spectral acceleration matches a target within a stated tolerance
  (Gasparini and Vanmarcke 1976, SIMQKE).

PSD convention: two-sided power spectral density :math:`S(\\omega)` [m²/s³] over
:math:`-\\infty < \\omega < \\infty` [rad/s], so the variance is :math:`\\sigma^2 = \\int S\\,d\\omega`
and white noise of intensity :math:`S_0` sampled at :math:`\\Delta t` has variance
:math:`2\\pi S_0/\\Delta t`.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from pounding.errors import PoundingInputError
from pounding.ground_motion import (
    GroundMotion,
    _check_damping,
    _check_periods,
    bandpass,
    baseline_correct,
    pseudo_spectral_acceleration,
    scale_to_pga,
)

# ---------------------------------------------------------------------------------------------
# Power spectral densities and filters
# ---------------------------------------------------------------------------------------------


def kanai_tajimi_psd(
    omega: Any, *, s0: float, omega_g: float = 15.6, zeta_g: float = 0.6
) -> np.ndarray:
    """Kanai-Tajimi power spectral density of ground acceleration [m²/s³].

    .. math::
        S(\\omega) = S_0 \\frac{1 + 4\\zeta_g^2 (\\omega/\\omega_g)^2}
        {(1 - (\\omega/\\omega_g)^2)^2 + 4\\zeta_g^2(\\omega/\\omega_g)^2}

    Parameters
    ----------
    omega : array_like
        Circular frequency [rad/s].
    s0 : float
        Intensity of the bedrock white noise [m²/s³] (two-sided).
    omega_g : float
        Ground (soil) circular frequency [rad/s]; 15.6 rad/s for firm soil (Tajimi), about
        5-8 rad/s for soft soil.
    zeta_g : float
        Ground damping ratio [-]; 0.6 for firm soil, 0.2-0.4 for soft soil.

    References
    ----------
    .. [1] Kanai, K. (1957). Semi-empirical formula for the seismic characteristics of the
       ground. Bull. Earthquake Res. Inst. Univ. Tokyo 35, 309-325.
    .. [2] Tajimi, H. (1960). A statistical method of determining the maximum response of a
       building structure during an earthquake. Proc. 2nd WCEE, Tokyo, vol. 2, 781-797.
    """
    return s0 * np.abs(_kt_filter(np.asarray(omega, dtype=float), omega_g, zeta_g)) ** 2


def clough_penzien_psd(
    omega: Any,
    *,
    s0: float,
    omega_g: float = 15.6,
    zeta_g: float = 0.6,
    omega_f: float = 1.5,
    zeta_f: float = 0.6,
) -> np.ndarray:
    """Clough-Penzien PSD [m²/s³]: Kanai-Tajimi times a second-order high-pass filter.

    .. math::
        S(\\omega) = S_{KT}(\\omega)\\,
        \\frac{(\\omega/\\omega_f)^4}{(1 - (\\omega/\\omega_f)^2)^2 + 4\\zeta_f^2(\\omega/\\omega_f)^2}

    The high-pass stage removes the non-physical finite PSD of ground displacement of the
    Kanai-Tajimi model at ω → 0. Typical ω_f ≈ 0.1 ω_g, ζ_f ≈ ζ_g.

    References
    ----------
    .. [1] Clough, R.W. and Penzien, J. (1975). Dynamics of Structures. McGraw-Hill, §25.
    """
    w = np.asarray(omega, dtype=float)
    return s0 * np.abs(_kt_filter(w, omega_g, zeta_g) * _cp_filter(w, omega_f, zeta_f)) ** 2


def _kt_filter(w: np.ndarray, omega_g: float, zeta_g: float) -> np.ndarray:
    # transfer function of the soil column from bedrock to surface acceleration
    return (omega_g**2 + 2j * zeta_g * omega_g * w) / (
        omega_g**2 - w**2 + 2j * zeta_g * omega_g * w
    )


def _cp_filter(w: np.ndarray, omega_f: float, zeta_f: float) -> np.ndarray:
    return w**2 / (omega_f**2 - w**2 + 2j * zeta_f * omega_f * w)


# ---------------------------------------------------------------------------------------------
# Envelopes
# ---------------------------------------------------------------------------------------------


def jennings_envelope(t: Any, *, rise: float, strong_end: float, decay: float) -> np.ndarray:
    """Jennings-Housner-Tsai envelope: quadratic rise, constant strong phase, exponential decay.

    .. math::
        e(t) = \\begin{cases} (t/t_1)^2 & t < t_1 \\\\ 1 & t_1 \\le t \\le t_2 \\\\
        \\exp(-c\\,(t - t_2)) & t > t_2 \\end{cases}

    Parameters
    ----------
    t : array_like
        Time [s].
    rise : float
        End of the rise t_1 [s].
    strong_end : float
        End of the strong phase t_2 [s], >= t_1.
    decay : float
        Decay rate c [1/s].

    References
    ----------
    .. [1] Jennings, P.C., Housner, G.W. and Tsai, N.C. (1968). Simulated earthquake motions.
       Report, Earthquake Engineering Research Laboratory, California Institute of Technology.
    """
    t = np.asarray(t, dtype=float)
    if not (rise > 0 and strong_end >= rise and decay > 0):
        raise PoundingInputError(
            "jennings_envelope: need rise > 0, strong_end >= rise, decay > 0; got "
            f"rise={rise}, strong_end={strong_end}, decay={decay}"
        )
    return np.where(
        t < rise,
        (np.clip(t, 0, None) / rise) ** 2,
        np.where(t <= strong_end, 1.0, np.exp(-decay * (t - strong_end))),
    )


def saragoni_hart_envelope(
    t: Any, *, duration: float, epsilon: float = 0.2, eta: float = 0.05
) -> np.ndarray:
    """Saragoni-Hart envelope in the normalised form of Boore (2003), peak 1 at t = ε t_η.

    .. math::
        e(t) = a\\,(t/t_\\eta)^b \\exp(-c\\,t/t_\\eta), \\quad
        b = \\frac{-\\epsilon \\ln\\eta}{1 + \\epsilon(\\ln\\epsilon - 1)}, \\quad
        c = b/\\epsilon, \\quad a = (e/\\epsilon)^b

    so that e(ε t_η) = 1 and e(t_η) = η.

    Parameters
    ----------
    duration : float
        t_η [s], the time at which the envelope has decayed to η.
    epsilon : float
        Fraction of t_η at which the envelope peaks (0 < ε < 1).
    eta : float
        Envelope value at t_η (0 < η < 1).

    References
    ----------
    .. [1] Saragoni, G.R. and Hart, G.C. (1974). Simulation of artificial earthquakes. Earthquake
       Engineering and Structural Dynamics 2, 249-267. doi:10.1002/eqe.4290020305
    .. [2] Boore, D.M. (2003). Simulation of ground motion using the stochastic method. Pure and
       Applied Geophysics 160, 635-676, Eq. 12. doi:10.1007/PL00012553
    """
    if not (duration > 0 and 0 < epsilon < 1 and 0 < eta < 1):
        raise PoundingInputError(
            "saragoni_hart_envelope: need duration > 0, 0 < epsilon < 1, 0 < eta < 1; got "
            f"duration={duration}, epsilon={epsilon}, eta={eta}"
        )
    b = -epsilon * math.log(eta) / (1.0 + epsilon * (math.log(epsilon) - 1.0))
    c = b / epsilon
    a = (math.e / epsilon) ** b
    x = np.clip(np.asarray(t, dtype=float), 0, None) / duration
    return a * x**b * np.exp(-c * x)


def _default_jennings(duration: float) -> dict[str, float]:
    # rise over 10 %, strong phase to 50 %, decayed to 5 % of the amplitude at the end
    return {
        "rise": 0.1 * duration,
        "strong_end": 0.5 * duration,
        "decay": math.log(20.0) / (0.5 * duration),
    }


def _default_saragoni_hart(duration: float) -> dict[str, float]:
    return {"duration": duration}


#: Envelopes by name: (function, defaults from the record duration).
ENVELOPES: dict[str, tuple[Callable[..., np.ndarray], Callable[[float], dict[str, float]]]] = {
    "jennings": (jennings_envelope, _default_jennings),
    "saragoni-hart": (saragoni_hart_envelope, _default_saragoni_hart),
}


def envelope(name: str | None, t: np.ndarray, duration: float, **params: Any) -> np.ndarray:
    """Envelope ``name`` evaluated at ``t`` [s], with defaults scaled to ``duration`` [s].

    ``None`` or ``"none"`` gives a stationary record (envelope 1).
    """
    if name is None or name == "none":
        return np.ones_like(t, dtype=float)
    try:
        func, defaults = ENVELOPES[name]
    except KeyError:
        allowed = ", ".join([*ENVELOPES, "none"])
        raise PoundingInputError(f"unknown envelope {name!r}; allowed: {allowed}") from None
    return func(t, **{**defaults(duration), **params})


# ---------------------------------------------------------------------------------------------
# Filtered white noise
# ---------------------------------------------------------------------------------------------


def _grid(duration: float, dt: float, what: str) -> int:
    if not (math.isfinite(duration) and duration > 0):
        raise PoundingInputError(f"{what}: duration must be > 0 [s], got {duration}")
    if not (math.isfinite(dt) and dt > 0 and dt < duration):
        raise PoundingInputError(f"{what}: dt must be in (0, duration) [s], got {dt}")
    return int(math.floor(duration / dt + 1e-9)) + 1


def filtered_white_noise(
    model: str = "kanai-tajimi",
    *,
    duration: float = 20.0,
    dt: float = 0.01,
    seed: int = 0,
    s0: float = 0.01,
    omega_g: float = 15.6,
    zeta_g: float = 0.6,
    omega_f: float = 1.5,
    zeta_f: float = 0.6,
    envelope_name: str | None = "jennings",
    envelope_params: dict[str, float] | None = None,
    pga: float | None = None,
    pad: float = 10.0,
) -> GroundMotion:
    """Gaussian white noise filtered by the Kanai-Tajimi or Clough-Penzien filter, enveloped.

    White noise of intensity ``s0`` is generated at step ``dt`` and filtered in the frequency
    domain by the complex transfer function of the model (so the stationary process has exactly
    the model PSD below the Nyquist frequency). ``pad`` [s] of extra noise in front is generated
    and discarded so that the circular filtering does not wrap the filter's memory around.

    Parameters
    ----------
    model : {"kanai-tajimi", "clough-penzien"}
    duration, dt : float
        Record duration and step [s].
    seed : int
        Seed of ``numpy.random.default_rng``; the same seed gives the same record.
    s0 : float
        White-noise intensity [m²/s³] (two-sided PSD); irrelevant when ``pga`` is given.
    omega_g, zeta_g, omega_f, zeta_f : float
        Filter parameters [rad/s], [-] (see :func:`clough_penzien_psd`).
    envelope_name : {"jennings", "saragoni-hart", None}
        Amplitude envelope; None for a stationary record.
    envelope_params : dict, optional
        Overrides of the envelope parameters (defaults scale with ``duration``).
    pga : float, optional
        Scale the result to this peak ground acceleration [m/s²].
    """
    what = f"{model} synthetic record"
    if model not in _FILTERS:
        allowed = ", ".join(_FILTERS)
        raise PoundingInputError(f"unknown synthetic model {model!r}; allowed: {allowed}")
    n = _grid(duration, dt, what)
    for field, value in (("s0", s0), ("omega_g", omega_g), ("omega_f", omega_f)):
        if not (math.isfinite(value) and value > 0):
            raise PoundingInputError(f"{what}: {field} must be > 0, got {value}")
    for field, value in (("zeta_g", zeta_g), ("zeta_f", zeta_f)):
        if not (math.isfinite(value) and value > 0):
            raise PoundingInputError(f"{what}: {field} must be > 0, got {value}")
    n_pad = int(round(max(pad, 0.0) / dt))
    rng = np.random.default_rng(seed)
    noise = rng.standard_normal(n + n_pad) * math.sqrt(2.0 * math.pi * s0 / dt)
    w = 2.0 * math.pi * np.fft.rfftfreq(n + n_pad, dt)
    transfer = _FILTERS[model](w, omega_g, zeta_g, omega_f, zeta_f)
    acc = np.fft.irfft(np.fft.rfft(noise) * transfer, n + n_pad)[n_pad:]
    t = dt * np.arange(n)
    acc = acc * envelope(envelope_name, t, duration, **(envelope_params or {}))
    params = {
        "model": model,
        "seed": seed,
        "duration": duration,
        "dt": dt,
        "s0": s0,
        "omega_g": omega_g,
        "zeta_g": zeta_g,
        "envelope": envelope_name,
        "envelope_params": dict(envelope_params or {}),
    }
    if model == "clough-penzien":
        params.update(omega_f=omega_f, zeta_f=zeta_f)
    gm = GroundMotion(
        acc,
        dt,
        name=f"{model} seed={seed}",
        metadata={
            "source": "synthetic",
            "generator": "pounding.synthetic.filtered_white_noise",
            "parameters": params,
            "units_read": "m/s2",
        },
    )
    if pga is not None:
        from pounding.ground_motion import scale_to_pga

        gm = scale_to_pga(gm, pga=pga)
    return gm


def _kt_transfer(w, omega_g, zeta_g, omega_f, zeta_f):
    return _kt_filter(w, omega_g, zeta_g)


def _cp_transfer(w, omega_g, zeta_g, omega_f, zeta_f):
    return _kt_filter(w, omega_g, zeta_g) * _cp_filter(w, omega_f, zeta_f)


_FILTERS = {"kanai-tajimi": _kt_transfer, "clough-penzien": _cp_transfer}


def kanai_tajimi(**params: Any) -> GroundMotion:
    """Kanai-Tajimi filtered white noise; see :func:`filtered_white_noise`."""
    return filtered_white_noise("kanai-tajimi", **params)


def clough_penzien(**params: Any) -> GroundMotion:
    """Clough-Penzien filtered white noise; see :func:`filtered_white_noise`."""
    return filtered_white_noise("clough-penzien", **params)


# ---------------------------------------------------------------------------------------------
# Spectrum-compatible records
# ---------------------------------------------------------------------------------------------


def spectrum_compatible(
    periods: Any,
    psa: Any,
    *,
    duration: float = 20.0,
    dt: float = 0.01,
    damping: float = 0.05,
    seed: int = 0,
    envelope_name: str | None = "jennings",
    envelope_params: dict[str, float] | None = None,
    tolerance: float = 0.1,
    max_iterations: int = 30,
    n_control: int = 60,
    name: str | None = None,
    process: Callable[[GroundMotion], GroundMotion] | None = None,
) -> GroundMotion:
    """A record whose pseudo-spectral acceleration matches a target spectrum.

    Gaussian white noise (from ``seed``) is multiplied by the envelope; at each iteration the
    record's Fourier transform is multiplied by the ratio target/achieved PSa,
    interpolated in log-period from ``n_control`` control periods spread geometrically over
    the target's period range (Gasparini and Vanmarcke 1976); 2 % half-cosine ramps keep the
    record's ends at zero. The iteration stops when the
    largest relative deviation over the control periods is at most ``tolerance`` or after
    ``max_iterations``; the best record found is returned either way.

    Parameters
    ----------
    periods : array_like
        Periods T [s] of the target, > 0, increasing; the control periods cover
        [max(T_min, 5 dt), T_max] (below 5 dt the record cannot be
        controlled: its Nyquist frequency is 2.5 times higher).
    psa : array_like
        Target pseudo-spectral acceleration [m/s²] at ``periods``.
    duration, dt : float
        Record duration and step [s].
    damping : float
        Damping ratio of the target spectrum [-].
    seed : int
        Seed of the random phases.
    envelope_name, envelope_params
        Amplitude envelope (see :func:`envelope`).
    tolerance : float
        Requested largest relative deviation |PSa/target - 1| over the control periods.
    max_iterations : int
    n_control : int
        Number of control periods.
    process : callable, optional
        Processing applied to the candidate at every iteration, before its spectrum is computed
        (e.g. ``lambda gm: standard_processing(gm, rescale=False)``), so the returned record is
        both processed and spectrum-compatible; its steps are kept in ``metadata["processing"]``.

    Returns
    -------
    GroundMotion
        ``metadata["achieved_tolerance"]`` is the largest relative deviation over the control
        periods (computed with :func:`pounding.ground_motion.pseudo_spectral_acceleration`),
        ``metadata["converged"]`` whether it is within ``tolerance``,
        ``metadata["control_periods"]`` the periods checked.

    References
    ----------
    .. [1] Gasparini, D.A. and Vanmarcke, E.H. (1976). Simulated earthquake motions compatible
       with prescribed response spectra (SIMQKE). MIT Dept. of Civil Engineering, Report R76-4.
    """
    what = "spectrum_compatible"
    periods = _check_periods(periods)
    psa = np.atleast_1d(np.asarray(psa, dtype=float))
    if psa.shape != periods.shape or not np.all(np.isfinite(psa)) or np.any(psa <= 0):
        raise PoundingInputError(
            f"{what}: psa must be positive and match periods in shape, got {psa}"
        )
    if np.any(np.diff(periods) <= 0):
        raise PoundingInputError(f"{what}: periods must be strictly increasing")
    damping = _check_damping(damping)
    if not (math.isfinite(tolerance) and tolerance > 0):
        raise PoundingInputError(f"{what}: tolerance must be > 0, got {tolerance}")
    n = _grid(duration, dt, what)
    t_lo = max(periods[0], 5.0 * dt)
    t_hi = periods[-1]
    if not t_lo < t_hi:
        raise PoundingInputError(f"{what}: target periods must extend above 5 dt = {5 * dt:g} s")
    control = np.geomspace(t_lo, t_hi, int(n_control))
    log_t = np.log(periods)
    target = np.exp(np.interp(np.log(control), log_t, np.log(psa)))

    rng = np.random.default_rng(seed)
    env = envelope(envelope_name, dt * np.arange(n), duration, **(envelope_params or {}))
    acc = env * rng.standard_normal(n)
    # the FFT is zero-padded to twice the length so that the correction does not wrap around
    n_fft = 2 * n
    freq = np.fft.rfftfreq(n_fft, dt)
    log_period_of_freq = np.full(freq.size, np.inf)
    log_period_of_freq[1:] = -np.log(freq[1:])
    log_control = np.log(control)
    ends = np.ones(n)
    m = max(2, n // 50)  # 2 % half-cosine ramps
    ends[:m] = 0.5 * (1.0 - np.cos(np.pi * np.arange(m) / m))
    ends[n - m :] = ends[:m][::-1]

    best = (math.inf, acc, 0)
    steps: list[str] = []
    for iteration in range(int(max_iterations) + 1):
        if process is not None:
            processed = process(GroundMotion(acc, dt))
            acc, steps = processed.acceleration, processed.metadata.get("processing", [])
        achieved = pseudo_spectral_acceleration(GroundMotion(acc, dt), control, damping=damping)
        error = float(np.max(np.abs(achieved / target - 1.0)))
        if error < best[0]:
            best = (error, acc, iteration)
        if error <= tolerance or iteration == max_iterations:
            break
        ratio = np.interp(log_period_of_freq, log_control, target / achieved)
        # the correction spreads energy over the whole record: keep its ends at zero
        acc = ends * np.fft.irfft(np.fft.rfft(acc, n_fft) * ratio, n_fft)[:n]
    error, acc, used = best
    meta = {
        "source": "synthetic",
        "generator": "pounding.synthetic.spectrum_compatible",
        "parameters": {
            "seed": seed,
            "duration": duration,
            "dt": dt,
            "damping": damping,
            "envelope": envelope_name,
            "envelope_params": dict(envelope_params or {}),
            "tolerance": tolerance,
            "max_iterations": int(max_iterations),
        },
        "achieved_tolerance": error,
        "converged": bool(error <= tolerance),
        "iterations": int(used),
        "control_periods": control.tolist(),
        "units_read": "m/s2",
    }
    if steps:
        meta["processing"] = list(steps)
    return GroundMotion(acc, dt, name=name or f"spectrum-compatible seed={seed}", metadata=meta)


# ---------------------------------------------------------------------------------------------
# Standard processing
# ---------------------------------------------------------------------------------------------

#: Band-pass corners [Hz] and baseline degree of :func:`standard_processing`.
STANDARD_BAND = (0.1, 25.0)
STANDARD_BASELINE_ORDER = 3


def standard_processing(gm: GroundMotion, *, rescale: bool = True) -> GroundMotion:
    """Process a synthetic record like a recorded one (and like the records shipped in the repository).

    0.1-25 Hz zero-phase Butterworth band-pass, then a cubic baseline correction fitted on
    displacement, then (``rescale``) the PGA scaled back to its value before processing (Boore and
    Bommer 2005). Filtered white noise keeps power near ω = 0: unprocessed, its ground velocity and
    displacement drift without bound (metres of displacement for a 0.3 g record). The low-pass corner
    is left out when 25 Hz is not below 0.8 times the Nyquist frequency 1/(2 dt). Each step is
    appended to ``metadata["processing"]``.

    References
    ----------
    .. [1] Boore, D.M. and Bommer, J.J. (2005). Processing of strong-motion accelerograms: needs,
       options and consequences. Soil Dyn. Earthq. Eng. 25, 93-115. doi:10.1016/j.soildyn.2004.10.007
    """
    low, high = STANDARD_BAND
    if high >= 0.8 * 0.5 / gm.dt:
        high = None
    out = baseline_correct(bandpass(gm, low=low, high=high), order=STANDARD_BASELINE_ORDER)
    return scale_to_pga(out, pga=gm.pga) if rescale else out


#: Synthetic generators by name (used by the ``synthetic:`` record references).
SYNTHETIC_MODELS: dict[str, Callable[..., GroundMotion]] = {
    "kanai-tajimi": kanai_tajimi,
    "clough-penzien": clough_penzien,
}
