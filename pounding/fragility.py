r"""Lognormal fragility functions fitted to collapse (or limit-state) data [1]_.

P(LS | IM = x) = Φ(ln(x/θ)/β), θ the median capacity (in the units of the intensity given) and β
the dispersion (the standard deviation of ln capacity).

Fits:

* **IDA** (a capacity x_i per record, the lowest intensity at which it reached the limit state):
  ln θ = mean(ln x_i), β = std(ln x_i, ddof = 1) (the method of moments). When n − m records never
  reached it up to x_max (right-censored, a truncated IDA), θ and β maximise

  .. math:: \sum_{\mathrm{reached}} \ln\frac{\phi(\ln(x_i/θ)/β)}{β x_i}
            + (n - m)\ln[1 - Φ(\ln(x_\max/θ)/β)].

* **Stripes** (multiple-stripe analysis: z_j of n_j records reach it at intensity x_j): θ and β
  maximise the binomial likelihood [1]_

  .. math:: \sum_j \ln\binom{n_j}{z_j} + z_j \ln p_j + (n_j - z_j)\ln(1 - p_j),
            \qquad p_j = Φ(\ln(x_j/θ)/β).

  The maximisation is over (ln θ, ln β) (Nelder-Mead from the moments of the stripes, then a
  Newton polish), so θ, β > 0.

* **Bootstrap** confidence intervals: records resampled with replacement (IDA), or the stripes'
  counts redrawn from Bin(n_j, p̂_j) (parametric), refitted ``n_boot`` times; percentile intervals
  of θ and β and a pointwise band of the fragility curve.

References
----------
.. [1] Baker, J.W. (2015). Efficient analytical fragility function fitting using dynamic structural
   analysis. Earthquake Spectra 31(1), 579-599. doi:10.1193/021113EQS025M
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from pounding.errors import PoundingInputError


def _phi(x: np.ndarray) -> np.ndarray:
    """Standard normal CDF Φ."""
    from scipy.special import ndtr

    return ndtr(x)


@dataclass(frozen=True)
class Fragility:
    """A fitted lognormal fragility function.

    Attributes
    ----------
    median : float
        θ, the intensity at 50 % probability (units of the data).
    beta : float
        β, the lognormal dispersion.
    method : str
        A name of :data:`METHODS`.
    n : int
        Records (IDA) or analyses (stripes) the fit rests on.
    median_ci, beta_ci : (float, float) or None
        Bootstrap percentile interval (level ``ci_level``), once :func:`bootstrap` ran.
    """

    median: float
    beta: float
    method: str
    n: int
    median_ci: tuple[float, float] | None = None
    beta_ci: tuple[float, float] | None = None
    ci_level: float | None = None
    samples: np.ndarray | None = field(default=None, repr=False, compare=False)

    def probability(self, im: float | np.ndarray) -> np.ndarray:
        """P(limit state | IM = im) = Φ(ln(im/θ)/β)."""
        x = np.asarray(im, dtype=float)
        with np.errstate(divide="ignore"):
            return _phi(np.log(x / self.median) / self.beta)

    def band(self, im: float | np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Pointwise bootstrap band (lower, upper) of the probability at ``im``."""
        if self.samples is None or self.ci_level is None:
            raise PoundingInputError("fragility band: run bootstrap() on the fit first")
        x = np.atleast_1d(np.asarray(im, dtype=float))
        with np.errstate(divide="ignore"):
            p = _phi(np.log(x[None, :] / self.samples[:, :1]) / self.samples[:, 1:])
        tail = 50.0 * (1.0 - self.ci_level)
        return np.percentile(p, tail, axis=0), np.percentile(p, 100.0 - tail, axis=0)


def _values(x: Sequence[float] | np.ndarray, field: str) -> np.ndarray:
    a = np.asarray(x, dtype=float).ravel()
    if a.size == 0:
        raise PoundingInputError(f"{field}: no values; allowed: intensities > 0")
    bad = np.flatnonzero(~(a > 0.0) | np.isnan(a))
    if bad.size:
        raise PoundingInputError(
            f"{field}[{int(bad[0])}] = {float(a[bad[0]])!r}; allowed: intensities > 0 (inf: not reached)"
        )
    return a


def fit_ida(
    capacities: Sequence[float] | np.ndarray,
    censored_above: float | Sequence[float] | np.ndarray | None = None,
) -> Fragility:
    """Fit to one capacity per record (the IM at which it reached the limit state); ``inf`` for a
    record that had not reached it at ``censored_above``, the largest intensity analysed (then the
    truncated-IDA likelihood is maximised). ``censored_above`` may also be one level per record
    (each record's highest run, as in a hunt-and-fill IDA)."""
    x = _values(capacities, "capacities")
    reached = np.isfinite(x)
    m = int(reached.sum())
    if m < 2:
        raise PoundingInputError(
            f"fit_ida: {m} of {x.size} records reached the limit state; allowed: at least 2"
        )
    if m == x.size:
        ln = np.log(x)
        if np.ptp(ln) == 0.0:
            raise PoundingInputError(
                f"fit_ida: every record reached the limit state at {x[0]:.4g}; the dispersion is "
                "undetermined (analyse finer levels)"
            )
        return Fragility(float(np.exp(ln.mean())), float(ln.std(ddof=1)), "moments", x.size)
    top = None if censored_above is None else np.asarray(censored_above, dtype=float)
    if top is not None and top.ndim and top.size != x.size:
        raise PoundingInputError(
            f"fit_ida: censored_above has {top.size} values for {x.size} capacities; allowed: "
            "one level, or one per record"
        )
    limit = None if top is None else np.broadcast_to(top, x.shape)[~reached]
    if limit is None or not np.all(np.isfinite(limit) & (limit > 0.0)):
        raise PoundingInputError(
            f"fit_ida: {x.size - m} record(s) did not reach the limit state; give censored_above "
            "(the largest intensity analysed, > 0)"
        )
    if top is not None and not top.ndim and np.any(x[reached] > top):
        raise PoundingInputError("fit_ida: a capacity exceeds censored_above")
    ln_x = np.log(x[reached])
    ln_max = np.log(limit)

    def nll(q: np.ndarray) -> float:
        from scipy.special import log_ndtr

        mu, beta = q[0], math.exp(q[1])
        r = (ln_x - mu) / beta
        ll = np.sum(-0.5 * r * r - math.log(beta) - ln_x) + np.sum(log_ndtr(-(ln_max - mu) / beta))
        return -float(ll)

    mu, beta = _maximise(nll, ln_x.mean(), ln_x.std(ddof=1) if m > 1 else 0.5)
    return Fragility(math.exp(mu), beta, "truncated_mle", x.size)


def fit_stripes(
    levels: Sequence[float] | np.ndarray,
    analyses: Sequence[int] | np.ndarray,
    reached: Sequence[int] | np.ndarray,
) -> Fragility:
    """Fit to stripes: at intensity ``levels[j]``, ``reached[j]`` of ``analyses[j]`` records
    reached the limit state (binomial maximum likelihood)."""
    x = _values(levels, "levels")
    n = np.asarray(analyses, dtype=float).ravel()
    z = np.asarray(reached, dtype=float).ravel()
    if not (x.size == n.size == z.size):
        raise PoundingInputError(
            f"fit_stripes: {x.size} levels, {n.size} analysis counts, {z.size} reached counts; "
            "allowed: one of each per stripe"
        )
    if np.any(~np.isfinite(x)) or np.any(n < 1) or np.any(z < 0) or np.any(z > n):
        raise PoundingInputError(
            "fit_stripes: allowed: finite levels > 0, analyses ≥ 1, 0 ≤ reached ≤ analyses"
        )
    if not (z.sum() > 0 and (n - z).sum() > 0):
        raise PoundingInputError(
            "fit_stripes: every analysis reached the limit state, or none did; the median is "
            "outside the stripes (allowed: some of each)"
        )
    order = np.argsort(x)
    w_sorted = (z / n)[order]
    inner = (w_sorted > 0.0) & (w_sorted < 1.0)
    outer = w_sorted[~inner]
    if inner.sum() <= 1 and np.all(np.diff(outer) >= 0.0):
        at = int(np.argmax(w_sorted > 0.0))
        if not inner.any() or np.all(w_sorted[at + 1 :] == 1.0):
            # no stripe, or one, between "none reached" and "all reached": the likelihood grows
            # as β → 0 (a step at the median), so there is no dispersion to estimate
            raise PoundingInputError(
                "fit_stripes: the records go from none to all reaching the limit state between "
                f"{x[order][max(at - 1, 0)]:g} and {x[order][min(at + 1, x.size - 1)]:g} "
                "(at most one stripe in between): the dispersion cannot be estimated (β → 0); "
                "add levels there"
            )
    ln_x = np.log(x)
    from scipy.special import log_ndtr

    def nll(q: np.ndarray) -> tuple[float, np.ndarray]:
        # −log-likelihood and its gradient in (ln θ, ln β): dr/d ln θ = −1/β, dr/d ln β = −r
        beta = math.exp(q[1])
        r = (ln_x - q[0]) / beta
        lp, lq = log_ndtr(r), log_ndtr(-r)
        log_phi = -0.5 * r * r - 0.5 * math.log(2.0 * math.pi)
        with np.errstate(over="ignore", invalid="ignore"):
            g = z * np.exp(log_phi - lp) - (n - z) * np.exp(log_phi - lq)
        return -float(np.sum(z * lp + (n - z) * lq)), np.array([np.sum(g) / beta, np.sum(g * r)])

    # start: a probit line through the stripes strictly between 0 and 1
    w = z / n
    inner = (w > 0.0) & (w < 1.0)
    if inner.sum() >= 2 and np.ptp(ln_x[inner]) > 0:
        from scipy.special import ndtri

        slope, icpt = np.polyfit(ln_x[inner], ndtri(w[inner]), 1)
        if slope > 0.05:  # β below 20
            mu0, beta0 = -icpt / slope, 1.0 / slope
        else:
            mu0, beta0 = float(ln_x[inner].mean()), 0.5
    else:
        mu0 = float(np.interp(0.5, np.maximum.accumulate(w), ln_x)) if w[-1] >= 0.5 else ln_x.mean()
        beta0 = max(0.3, float(np.std(ln_x)))
    solved = _newton_stripes(ln_x, n, z, float(mu0), float(beta0), nll)
    mu, beta = solved if solved is not None else _maximise(nll, float(mu0), float(beta0))
    return Fragility(math.exp(mu), beta, "stripes_mle", int(n.sum()))


def _newton_stripes(ln_x, n, z, mu0: float, beta0: float, nll) -> tuple[float, float] | None:
    """Newton's method on the stripes' −log-likelihood in q = (ln θ, ln β) with its exact Hessian
    and a backtracking line search; None if it does not converge (the caller then optimises
    generally). With λ1 = φ/Φ(r), λ2 = φ/Φ(−r): ℓ' = z λ1 − (n − z) λ2,
    ℓ'' = −z λ1 (r + λ1) − (n − z) λ2 (λ2 − r), r = (ln x − ln θ)/β."""
    from scipy.special import log_ndtr

    q = np.array([mu0, math.log(min(max(beta0, 1e-2), 5.0))])
    f, g = nll(q)
    for _ in range(60):
        if q[1] <= -7.0:  # β below 1e-3: the stripes all but separate, there is no dispersion
            raise PoundingInputError(
                "fit_stripes: the dispersion runs to 0 (β < 0.001): the records reach the limit "
                "state almost all at one level; add levels around it"
            )
        if q[1] >= 3.0:  # β above 20: leave it to the bounded search
            return None
        beta = math.exp(q[1])
        r = (ln_x - q[0]) / beta
        log_phi = -0.5 * r * r - 0.5 * math.log(2.0 * math.pi)
        with np.errstate(over="ignore"):
            l1 = np.exp(log_phi - log_ndtr(r))
            l2 = np.exp(log_phi - log_ndtr(-r))
        if not (np.all(np.isfinite(l1)) and np.all(np.isfinite(l2))):
            return None
        d1 = z * l1 - (n - z) * l2
        d2 = -z * l1 * (r + l1) - (n - z) * l2 * (l2 - r)
        h = -np.array(
            [
                [np.sum(d2) / beta**2, np.sum(d2 * r + d1) / beta],
                [np.sum(d2 * r + d1) / beta, np.sum(d2 * r * r + d1 * r)],
            ]
        )
        try:
            step = np.linalg.solve(h, g)
        except np.linalg.LinAlgError:
            return None
        if not np.all(np.isfinite(step)) or float(step @ g) <= 0.0:
            step = g  # not a descent direction: steepest descent
        t = 1.0
        while t > 1e-8:
            trial = q - t * step
            f_new, g_new = nll(trial)
            if np.isfinite(f_new) and f_new <= f:
                break
            t *= 0.5
        else:
            return None
        q, f, g = trial, f_new, g_new
        if np.max(np.abs(t * step)) < 1e-12 or np.max(np.abs(g)) < 1e-10 * max(1.0, float(n.sum())):
            return float(q[0]), float(math.exp(q[1]))
    return None


def _maximise(nll, mu0: float, beta0: float) -> tuple[float, float]:
    """Minimise nll over (ln θ, ln β). ``nll`` returns the value, or (value, gradient): then BFGS
    with the gradient from the start, Nelder–Mead (then BFGS) where that fails."""
    from scipy.optimize import minimize

    start = np.array([mu0, math.log(min(max(beta0, 1e-2), 5.0))])
    jac = isinstance(nll(start), tuple)
    # β between 1e-3 and 20: a dispersion outside it is no fit (the data separate, or say nothing)
    bounds = [(None, None), (math.log(1e-3), math.log(20.0))]
    with np.errstate(all="ignore"):
        best = minimize(nll, start, method="L-BFGS-B", jac=jac, bounds=bounds,
                        options=dict(gtol=1e-10, ftol=1e-15, maxiter=200))  # fmt: skip
        if not best.success:
            value = (lambda q: nll(q)[0]) if jac else nll
            first = minimize(value, start, method="Nelder-Mead",
                             options=dict(xatol=1e-10, fatol=1e-12, maxiter=1000))  # fmt: skip
            if first.fun < (nll(best.x)[0] if jac else nll(best.x)):
                best = first
    q = best.x
    if not math.log(1e-3) + 1e-9 < q[1] < math.log(20.0) - 1e-9:
        raise PoundingInputError(
            f"fragility fit: the dispersion runs to its bound (β = {math.exp(q[1]):.3g}): the "
            "data do not determine it"
        )
    if not np.all(np.isfinite(q)):
        raise PoundingInputError("fragility fit did not converge")
    return float(q[0]), float(math.exp(q[1]))


def bootstrap(
    fit: Fragility,
    capacities: Sequence[float] | np.ndarray | None = None,
    *,
    censored_above: float | Sequence[float] | np.ndarray | None = None,
    stripes: tuple[Sequence[float], Sequence[int], Sequence[int]] | None = None,
    n_boot: int = 1000,
    level: float = 0.9,
    seed: int = 0,
) -> Fragility:
    """The fit with bootstrap percentile intervals of θ and β (``level``, default 90 %): records
    resampled with replacement (``capacities``, as given to :func:`fit_ida`), or each stripe's
    count redrawn from Bin(n_j, p̂_j) (``stripes`` = (levels, analyses, reached))."""
    if not (isinstance(n_boot, int) and n_boot >= 10):
        raise PoundingInputError(f"n_boot = {n_boot!r}; allowed: an integer ≥ 10")
    if not 0.0 < level < 1.0:
        raise PoundingInputError(f"level = {level!r}; allowed: 0 < level < 1")
    if (capacities is None) == (stripes is None):
        raise PoundingInputError("bootstrap: give capacities (IDA) or stripes, one of them")
    rng = np.random.default_rng(seed)
    out = np.empty((n_boot, 2))
    k = tries = 0
    budget = 2 * n_boot  # resamples that cannot be fitted (all or none reached) are drawn again
    if capacities is not None:
        x = _values(capacities, "capacities")
        top = None if censored_above is None else np.asarray(censored_above, dtype=float)
        while k < n_boot and tries < budget:
            tries += 1
            pick = rng.integers(0, x.size, x.size)
            try:
                f = fit_ida(x[pick], top[pick] if top is not None and top.ndim else top)
            except PoundingInputError:  # fewer than two reached in this resample
                continue
            out[k] = f.median, f.beta
            k += 1
    else:
        levels, analyses, _ = (np.asarray(s, dtype=float) for s in stripes)  # type: ignore[union-attr]
        p = fit.probability(levels)
        n = analyses.astype(int)
        while k < n_boot and tries < budget:
            tries += 1
            z = rng.binomial(n, p)
            try:
                f = fit_stripes(levels, n, z)
            except PoundingInputError:  # all or none reached in this draw
                continue
            out[k] = f.median, f.beta
            k += 1
    if k < n_boot:
        raise PoundingInputError(
            f"bootstrap: only {k} of {tries} resamples could be fitted (in the others the "
            "records step from none to all reaching the limit state): too few records or levels "
            "for an interval"
        )
    tail = 50.0 * (1.0 - level)
    lo, hi = np.percentile(out, [tail, 100.0 - tail], axis=0)
    return replace(
        fit,
        median_ci=(float(lo[0]), float(hi[0])),
        beta_ci=(float(lo[1]), float(hi[1])),
        ci_level=level,
        samples=out,
    )


# --------------------------------------------------------------------------------------------------
# Fragility of a study with an im_level axis (incremental dynamic / multiple-stripe analysis)
# --------------------------------------------------------------------------------------------------

#: The limit state that is the analysis' own collapse (story drift past ``collapse_drift``, a
#: Newton failure past it, or a story whose deterioration capacity is spent and then collapses).
COLLAPSE = "collapse"


def variants(ds, dims: Sequence[str]) -> list[dict[str, int]]:
    """Index selections over the variant axes ``dims`` of a study or fragility Dataset; the
    no-contact law (``law = "none"``) once, at index 0 of the other axes, since without contact
    they (gap, e, k) change nothing."""
    out = []
    for index in np.ndindex(*(ds.sizes[d] for d in dims)):
        at = dict(zip(dims, index, strict=True))
        if no_contact(ds, at) and any(i for d, i in at.items() if d != "law"):
            continue
        out.append(at)
    return out


def no_contact(ds, at: dict[str, int]) -> bool:
    """Whether the selection ``at`` is the no-contact law."""
    return "law" in at and str(ds["law"].values[at["law"]]) == "none"


#: The "limit state" of the buildings touching at all: at least one impact in the run.
POUNDING = "pounding"


def _limit_label(limit: str | float) -> str:
    if limit in (COLLAPSE, POUNDING):
        return str(limit)
    return f"drift {100 * float(limit):g} %"


def _exceeded(ds, limit: str | float, building: str | None):
    """Per run (True/False; NaN for a failed run): the limit state reached by ``building`` (any
    building when None). A collapsed run exceeds every drift limit."""
    import xarray as xr

    if limit == POUNDING:
        if "impact_count" not in ds or "contact" not in ds["impact_count"].dims:
            raise PoundingInputError("fragility(limit_state='pounding'): the study has no contacts")
        ok = ds["run_status"] == "ok" if "run_status" in ds else True
        return (ds["impact_count"].sum("contact") > 0).astype(float).where(ok)
    if limit == COLLAPSE:
        hit = np.isfinite(ds["collapse_time"]) if "collapse_time" in ds else None
        if hit is None:
            raise PoundingInputError(
                "fragility(limit_state='collapse'): the study has no collapse_time (no building "
                "with yielding stories or P-Δ)"
            )
    else:
        if isinstance(limit, bool) or not isinstance(limit, int | float) or not 0 < limit < 10:
            raise PoundingInputError(
                f"limit_state = {limit!r}; allowed: 'collapse' or a story drift ratio, e.g. 0.015"
            )
        hit = ds["peak_drift_ratio"].max("story") >= float(limit)
        if "collapse_time" in ds:
            hit = hit | np.isfinite(ds["collapse_time"])
    if building is not None:
        names = [str(b) for b in ds["building"].values]
        if building not in names:
            raise PoundingInputError(f"building = {building!r}; allowed: {', '.join(names)}")
        hit = hit.sel(building=building)
    else:
        hit = hit.any("building")
    ok = ds["run_status"] == "ok" if "run_status" in ds else xr.ones_like(hit, bool)
    return hit.astype(float).where(ok)


def _drift(ds, building: str | None):
    """Peak story drift ratio per run of ``building`` (the largest of all when None); a collapsed
    run counts at least the collapse drift (the IDA curve's flatline)."""
    import json

    drift = ds["peak_drift_ratio"].max("story")
    if "collapse_time" in ds:
        limit = float(json.loads(ds.attrs.get("analysis", "{}")).get("collapse_drift") or 0.1)
        drift = drift.where(~np.isfinite(ds["collapse_time"]), np.fmax(drift, limit))
    return drift.sel(building=building) if building else drift.max("building")


def _crossing(levels: np.ndarray, drift: np.ndarray, hit: np.ndarray, limit: float) -> float:
    """The intensity at which a record's IDA curve (its runs sorted by level, from the origin,
    linear in between) first reaches the drift ``limit``; a failed run (NaN drift) is a crossing
    at its level."""
    order = np.argsort(levels)
    lv, d, h = levels[order], drift[order], hit[order]
    keep = np.isfinite(lv) & np.isfinite(h)
    lv, d, h = lv[keep], d[keep], h[keep]
    j = int(np.argmax(h == 1.0))
    if not np.isfinite(d[j]) or d[j] <= limit:  # failed run, or reached at exactly its level
        return float(lv[j])
    l0, d0 = (float(lv[j - 1]), float(d[j - 1])) if j else (0.0, 0.0)
    return l0 + (limit - d0) / (float(d[j]) - d0) * (float(lv[j]) - l0)


#: The fragility Dataset's ``method`` attribute: how each method fits.
_METHOD_NOTES = {
    "stripes": "binomial maximum likelihood over the stripes (Baker 2015)",
    "ida": "IDA capacities, truncated-IDA likelihood beyond the highest level (Baker 2015)",
}


def _study_axes(ds, method: str | None) -> tuple[bool, str, str]:
    """(hunt, step, method): whether ``ds`` is a hunt-and-fill IDA, its run axis, the fit method."""
    hunt = "ida_run" in ds.dims
    step = "ida_run" if hunt else "im_level"
    if step not in ds.dims or "record" not in ds.dims:
        raise PoundingInputError(
            "fragility() needs a study Dataset with im_level and record axes (study.im, "
            "study.im_level: records scaled to target intensities) or a hunt-and-fill IDA"
        )
    if method is None:
        method = "ida" if hunt else "stripes"
    if method not in ("stripes", "ida"):
        raise PoundingInputError(f"method = {method!r}; allowed: stripes, ida")
    if hunt and method == "stripes":
        raise PoundingInputError(
            "method = 'stripes': a hunt-and-fill IDA has no common levels to count collapses "
            "at; allowed: ida"
        )
    return hunt, step, method


def _record_capacities(
    runs: np.ndarray,
    lv: np.ndarray,
    limit: str | float,
    drift: np.ndarray | None,
    top_level: float,
) -> tuple[np.ndarray, float | np.ndarray]:
    """(capacity, top): each record's capacity (inf: never reached) and its censoring level."""
    # the capacity is the lowest level reaching the limit state; a hunt-and-fill IDA (``drift``
    # given) interpolates a drift limit on the record's IDA curve, and censors each record at
    # the highest level it ran
    cap = np.full(runs.shape[1], np.inf)
    for r in range(runs.shape[1]):
        reached = runs[:, r] == 1.0
        if reached.any():
            cap[r] = float(np.min(lv[reached, r]))
        if drift is not None and limit not in (COLLAPSE, POUNDING) and reached.any():
            cap[r] = _crossing(lv[:, r], drift[:, r], runs[:, r], float(limit))
    if drift is None:
        return cap, top_level
    return cap, np.max(np.where(np.isfinite(runs), lv, -np.inf), axis=0)


def _fit_cell(
    stripes: tuple[np.ndarray, np.ndarray, np.ndarray] | None,
    cap: np.ndarray | None,
    top: float | np.ndarray,
    n_boot: int,
    level: float,
) -> tuple[Fragility | None, str]:
    """(fit, note): the stripes' (or else the capacities') fit, None if it failed, and why."""
    try:
        fit = fit_stripes(*stripes) if stripes is not None else fit_ida(cap, censored_above=top)
    except PoundingInputError as exc:
        return None, str(exc)
    if n_boot:
        try:  # a failed bootstrap keeps the fit, without intervals
            if stripes is not None:
                fit = bootstrap(fit, stripes=stripes, n_boot=n_boot, level=level)
            else:
                fit = bootstrap(fit, cap, censored_above=top, n_boot=n_boot, level=level)
        except PoundingInputError as exc:
            return fit, str(exc)
    return fit, ""


def _interval_variables(
    dims: tuple[str, ...],
    level: float,
    band: tuple[np.ndarray, np.ndarray],
    median_ci: tuple[np.ndarray, np.ndarray],
    beta_ci: tuple[np.ndarray, np.ndarray],
) -> dict[str, tuple]:
    """The bootstrap intervals' Dataset variables (curve band, median and β), by name."""
    out: dict[str, tuple] = {}
    for name, values, side in (("low", band[0], "lower"), ("high", band[1], "upper")):
        out[f"probability_{name}"] = (
            (*dims, "im"),
            values,
            {"units": "1", "long_name": f"probability, pointwise {level:.0%} band, {side}"},
        )
    for name, symbol, units, ci in (
        ("median", "median", "g", median_ci),
        ("beta", "β", "1", beta_ci),
    ):
        for end, values in (("low", ci[0]), ("high", ci[1])):
            out[f"fragility_{name}_{end}"] = (
                dims,
                values,
                {"units": units, "long_name": f"{symbol}, {level:.0%} {end}"},
            )
    return out


def _pounding_variables(ds, out, others: Sequence[str], hunt: bool) -> dict:
    """The pounding DataArrays the study allows (probability per level, median ratio), by name."""
    found = {}
    if not hunt and "impact_count" in ds and "contact" in ds["impact_count"].dims:
        ok = ds["run_status"] == "ok"
        pounds = (ds["impact_count"].sum("contact") > 0).astype(float).where(ok)
        found["pounding_probability"] = (
            pounds.mean("record")
            .transpose(*others, "im_level")
            .assign_attrs(units="1", long_name="fraction of the records with at least one impact")
        )
    if "law" in others and "none" in [str(v) for v in ds["law"].values]:
        ratio = out["fragility_median"] / out["fragility_median"].sel(law="none")
        found["pounding_median_ratio"] = ratio.assign_attrs(
            units="1",
            long_name="median capacity with contact / without (below 1: pounding lowers it)",
        )
    return found


def _reached(
    ds, limit: str | float, building: str | None, hunt: bool, order: Sequence[str]
) -> np.ndarray:
    """Per run, 1.0 if it reached ``limit``, else 0.0 (NaN: failed), as an array on ``order``."""
    hit = _exceeded(ds, limit, building)
    if hunt:  # the hunt counted a failed run as reaching its limit state (V&C): so here
        hit = hit.where(ds["run_status"] != "failed", 1.0)
    return hit.transpose(*order).values


def study_fragility(
    ds,
    limit_state: str | float | Sequence[str | float] = COLLAPSE,
    *,
    building: str | None = None,
    method: str | None = None,
    n_boot: int = 0,
    level: float = 0.9,
):
    """Lognormal fragility of each limit state for every combination of a study's other axes
    (law, gap, ...), from its ``im_level`` stripes and ``record`` axis.

    ``limit_state``: ``"collapse"`` or a story drift ratio (0.015 = 1.5 %), or a list of them;
    ``building``: whose limit state (default: any building's). ``method``: ``"stripes"`` (binomial
    maximum likelihood over the levels) or ``"ida"`` (each record's capacity is the lowest level at
    which it reached the limit state; records that never did are censored at the highest level).
    Default: stripes, or ida for a hunt-and-fill IDA (``ida_run`` dimension: every record has
    levels of its own, and is censored at its highest run; a failed run reaches every limit state,
    as the hunt counted it; no ``reached_fraction`` or ``pounding_probability`` per level then).
    ``n_boot`` > 0 adds bootstrap percentile intervals (``level``). Returns a Dataset with
    ``fragility_median`` [g], ``fragility_beta``, their intervals (``_low``, ``_high``), the
    observed ``reached_fraction`` of the records per level, ``fit_note`` (why a fit is missing),
    ``pounding_probability`` (the fraction of the records that pound at each level) and, when the
    study has the no-contact law, ``pounding_median_ratio`` (median with contact / without: below 1
    pounding lowers the capacity)."""
    import xarray as xr

    hunt, step, method = _study_axes(ds, method)
    limits = [limit_state] if isinstance(limit_state, str | int | float) else list(limit_state)
    others = [d for d in ds["run_status"].dims if d not in ("record", step)]
    if hunt:
        run_levels = ds["ida_level"].transpose(*others, step, "record").values
        top_level = float(np.nanmax(run_levels))
    else:
        levels = ds["im_level"].values.astype(float)
        top_level = float(levels.max())
    labels = [_limit_label(v) for v in limits]
    shape = (len(limits), *(ds.sizes[d] for d in others))
    med, beta = np.full(shape, np.nan), np.full(shape, np.nan)
    lo, hi = np.full(shape, np.nan), np.full(shape, np.nan)
    b_lo, b_hi = np.full(shape, np.nan), np.full(shape, np.nan)
    fraction = np.full((*shape, 0 if hunt else levels.size), np.nan)
    capacities = np.full((*shape, ds.sizes["record"]), np.nan)
    grid = np.linspace(0.0, 1.15 * top_level, 116)[1:]
    curve = np.full((*shape, grid.size), np.nan)
    band_lo, band_hi = np.full_like(curve, np.nan), np.full_like(curve, np.nan)
    notes = np.full(shape, "", dtype=object)
    if hunt:
        drift = _drift(ds, building).transpose(*others, step, "record").values
    for i, limit in enumerate(limits):
        hit = _reached(ds, limit, building, hunt, (*others, step, "record"))
        for index in np.ndindex(*shape[1:]):
            runs = hit[index]  # (level or run, record)
            lv = run_levels[index] if hunt else np.broadcast_to(levels[:, None], runs.shape)
            n = np.sum(np.isfinite(runs), axis=1)
            z = np.nansum(runs, axis=1)
            if not hunt:
                with np.errstate(invalid="ignore"):
                    fraction[(i, *index)] = np.where(n > 0, z / np.maximum(n, 1), np.nan)
            cap, top = None, top_level
            if method == "ida":
                cap, top = _record_capacities(
                    runs, lv, limit, drift[index] if hunt else None, top_level
                )
                capacities[(i, *index)] = np.where(np.isfinite(cap), cap, np.nan)
            use = n > 0
            stripes = (levels[use], n[use], z[use]) if method == "stripes" else None
            fit, notes[(i, *index)] = _fit_cell(stripes, cap, top, n_boot, level)
            if fit is None:
                continue
            med[(i, *index)], beta[(i, *index)] = fit.median, fit.beta
            curve[(i, *index)] = fit.probability(grid)
            if fit.median_ci is not None:
                band_lo[(i, *index)], band_hi[(i, *index)] = fit.band(grid)
                lo[(i, *index)], hi[(i, *index)] = fit.median_ci
                b_lo[(i, *index)], b_hi[(i, *index)] = fit.beta_ci  # type: ignore[misc]
    dims = ("limit_state", *others)
    im_label = (ds["ida_level"] if hunt else ds["im_level"]).attrs.get("long_name", "intensity")
    out = xr.Dataset(
        {
            "fragility_median": (
                dims,
                med,
                {"units": "g", "long_name": "median capacity θ (fragility)"},
            ),
            "fragility_beta": (dims, beta, {"units": "1", "long_name": "lognormal dispersion β"}),
            "fit_note": (dims, notes.astype(str), {"long_name": "why no fit (empty: fitted)"}),
            "probability": (
                (*dims, "im"),
                curve,
                {"units": "1", "long_name": "fitted probability of reaching the limit state"},
            ),
        },
        coords={
            "limit_state": ("limit_state", labels, {"long_name": "limit state"}),
            **{d: ds[d] for d in others},
            "im": ("im", grid, {"units": "g", "long_name": im_label}),
        },
    )
    if method == "ida":
        out["capacity"] = (
            (*dims, "record"),
            capacities,
            {"units": "g", "long_name": "intensity at which the record reached the limit state"},
        )
        out = out.assign_coords(record=ds["record"])
    if not hunt:
        out["reached_fraction"] = (
            (*dims, "im_level"),
            fraction,
            {"units": "1", "long_name": "fraction of the records reaching the limit state"},
        )
        out = out.assign_coords(im_level=ds["im_level"])
    if n_boot:
        out.update(_interval_variables(dims, level, (band_lo, band_hi), (lo, hi), (b_lo, b_hi)))
    out.update(_pounding_variables(ds, out, others, hunt))
    out.attrs.update(
        method=_METHOD_NOTES[method],
        building=building or "any",
        intensity_measure=ds.attrs.get("intensity_measure", ""),
        im_label=im_label,
    )
    return out
