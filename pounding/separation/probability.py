"""Probability of pounding against the gap: empirical and lognormal (maximum likelihood)."""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np
from scipy.stats import norm

from pounding.errors import PoundingInputError

# ---------------------------------------------------------------------------------------------
# Probability of pounding over a record suite
# ---------------------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class LognormalFit:
    r"""Lognormal distribution of the exact gap over a suite, with an atom at zero.

    P(g* > g) = p (1 − Φ((ln g − ln θ)/β)) for g > 0, where p is the fraction of records whose g* > 0.

    Attributes
    ----------
    median : float
        θ = exp(mean ln g*) over the records with g* > 0 [m] (NaN if none).
    beta : float
        Logarithmic standard deviation β [-] (maximum likelihood, divisor n; 0 for one record).
    fraction : float
        p, the fraction of records with g* > 0 [-].
    n : int
        Number of records.
    """

    median: float
    beta: float
    fraction: float
    n: int


def fit_lognormal(exact_gaps: Any) -> LognormalFit:
    r"""Maximum-likelihood lognormal fit of per-record exact gaps [m].

    .. math:: \ln\theta = \frac1n\sum \ln g^*_k, \qquad
              \beta^2 = \frac1n\sum (\ln g^*_k - \ln\theta)^2

    over the records with g* > 0 (the others never approach and never pound); the moments of ln g*
    are the maximum-likelihood estimates of the lognormal parameters ([5]_ uses the lognormal for the
    peak relative displacement).
    """
    g = np.asarray(exact_gaps, float).ravel()
    if g.size == 0 or np.any(~np.isfinite(g)) or np.any(g < 0):
        raise PoundingInputError(f"exact gaps = {g!r}; allowed: one or more finite values >= 0 [m]")
    pos = g[g > 0]
    if pos.size == 0:
        return LognormalFit(math.nan, math.nan, 0.0, int(g.size))
    ln = np.log(pos)
    mu = float(ln.mean())
    beta = float(np.sqrt(np.mean((ln - mu) ** 2)))
    return LognormalFit(math.exp(mu), beta, pos.size / g.size, int(g.size))


def empirical_pounding_probability(gaps: Any, exact_gaps: Any) -> np.ndarray:
    """Fraction of records that pound with gap g: #{k : g*_k > g} / n, for each gap [m].

    Exact by the property of g*: a record pounds with gap g iff g < g*.
    """
    g = np.asarray(gaps, float)
    s = np.asarray(exact_gaps, float).ravel()
    return (s[None, :] > g.ravel()[:, None]).mean(axis=1).reshape(g.shape)


def lognormal_pounding_probability(gaps: Any, fit: LognormalFit) -> np.ndarray:
    r"""P(pound | g) = p (1 − Φ((ln g − ln θ)/β)) from a :class:`LognormalFit`, for each gap [m]."""
    g = np.asarray(gaps, float)
    if fit.fraction == 0.0:
        return np.zeros_like(g)
    with np.errstate(divide="ignore"):
        if fit.beta > 0:
            surv = norm.sf((np.log(g) - math.log(fit.median)) / fit.beta)
        else:
            surv = (g < fit.median).astype(float)
    return fit.fraction * surv


def gap_for_probability(probability: float, fit: LognormalFit) -> float:
    r"""Gap [m] whose probability of pounding under the fitted distribution is ``probability``.

    .. math:: g_P = \theta \exp\big(\beta\,\Phi^{-1}(1 - P/p)\big)

    (0 when P ≥ p: at least that fraction of the records never approach).
    """
    if not (0.0 < probability < 1.0):
        raise PoundingInputError(f"target probability = {probability!r}; allowed: 0 < P < 1")
    if fit.fraction == 0.0 or probability >= fit.fraction:
        return 0.0
    return float(fit.median * math.exp(fit.beta * norm.isf(probability / fit.fraction)))
