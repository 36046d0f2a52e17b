r"""Intensity measures (IM) of a ground motion, for scaling records to target intensities.

A record is scaled by multiplying its whole accelerogram by SF = IM_target / IM(record), which is
exact for the measures here, all linear in the amplitude [1]_:

``pga``
    Peak ground acceleration [m/s²].
``sa``
    Pseudo-spectral acceleration Sa(T) = ω² S_d(T, ζ) [m/s²] of a linear oscillator of period T
    (typically a building's T1) and damping ratio ζ (default 5 %).
``sa_avg``
    Average spectral acceleration, the geometric mean (Π_j Sa(T_j))^(1/N) over N periods T_j
    [m/s²] [2]_, geometrically spaced between ``period_low`` and ``period_high`` (Eads et al.
    recommend 0.2 T1 to 3 T1, N = 10).

The spectral ordinates come from :func:`pounding.integrators.sdof.spectral_peaks` (the exact
piecewise-linear recurrence of Nigam & Jennings, as :func:`pounding.spectra.response_spectrum`).

References
----------
.. [1] Vamvatsikos, D., Cornell, C.A. (2002). Incremental dynamic analysis. Earthquake Eng. Struct.
   Dyn. 31(3), 491-514. doi:10.1002/eqe.141
.. [2] Eads, L., Miranda, E., Lignos, D.G. (2015). Average spectral acceleration as an intensity
   measure for collapse risk assessment. Earthquake Eng. Struct. Dyn. 44(12), 2057-2073.
   doi:10.1002/eqe.2575
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pounding.errors import PoundingInputError
from pounding.ground_motion import PERIOD_RANGE, GroundMotion
from pounding.integrators.sdof import spectral_peaks

#: Intensity measures by name, with what they are.
MEASURES = {
    "pga": "peak ground acceleration",
    "sa": "pseudo-spectral acceleration at one period",
    "sa_avg": "geometric mean of pseudo-spectral accelerations over a period range",
}
#: Number of periods of ``sa_avg`` by default (Eads et al. 2015).
SA_AVG_PERIODS = 10


def _period(value: object, field: str) -> float:
    low, high = PERIOD_RANGE
    if isinstance(value, bool) or not isinstance(value, int | float) or not low <= value <= high:
        raise PoundingInputError(
            f"{field} = {value!r}; allowed: a number >= {low:g} and <= {high:g} [s]"
        )
    return float(value)


@dataclass(frozen=True)
class IntensityMeasure:
    """An intensity measure: ``measure`` (a name of :data:`MEASURES`) and its periods.

    Parameters
    ----------
    measure : {"pga", "sa", "sa_avg"}
    period : float, optional
        T [s] of ``sa``.
    period_low, period_high : float, optional
        The range [s] of ``sa_avg``.
    n_periods : int
        N of ``sa_avg`` (default 10).
    damping : float
        Damping ratio ζ of the spectral ordinates (default 0.05).
    """

    measure: str
    period: float | None = None
    period_low: float | None = None
    period_high: float | None = None
    n_periods: int = SA_AVG_PERIODS
    damping: float = 0.05

    def __post_init__(self) -> None:
        if self.measure not in MEASURES:
            raise PoundingInputError(
                f"intensity measure = {self.measure!r}; allowed: {', '.join(MEASURES)}"
            )
        if not (isinstance(self.damping, int | float) and 0.0 <= self.damping < 1.0):
            raise PoundingInputError(f"damping = {self.damping!r}; allowed: 0 <= ζ < 1")
        if self.measure == "sa":
            _period(self.period, "period")
        if self.measure == "sa_avg":
            low = _period(self.period_low, "period_low")
            high = _period(self.period_high, "period_high")
            if high <= low:
                raise PoundingInputError(
                    f"period_high = {high:g} s must exceed period_low = {low:g} s"
                )
            if isinstance(self.n_periods, bool) or not (
                isinstance(self.n_periods, int) and self.n_periods >= 2
            ):
                raise PoundingInputError(f"n_periods = {self.n_periods!r}; allowed: an integer ≥ 2")

    @classmethod
    def for_periods(
        cls, measure: str, fundamental: list[float] | tuple[float, ...], **options: float
    ) -> IntensityMeasure:
        """``sa`` at the longest of the buildings' fundamental periods T1 (unless ``period`` is
        given), ``sa_avg`` from 0.2 min T1 to 3 max T1 (Eads et al. 2015; unless given), ``pga``."""
        if measure == "sa" and "period" not in options:
            options["period"] = max(fundamental)
        if measure == "sa_avg":
            options.setdefault("period_low", 0.2 * min(fundamental))
            options.setdefault("period_high", 3.0 * max(fundamental))
        return cls(measure, **options)

    @property
    def periods(self) -> np.ndarray:
        """The oscillator periods [s] it reads (none for ``pga``)."""
        if self.measure == "sa":
            return np.array([float(self.period)])
        if self.measure == "sa_avg":
            return np.geomspace(float(self.period_low), float(self.period_high), self.n_periods)
        return np.zeros(0)

    @property
    def label(self) -> str:
        """A short label with units of g, e.g. ``Sa(0.52 s, 5 %) [g]``."""
        z = f"{100 * self.damping:g} %"
        if self.measure == "sa":
            return f"Sa({self.period:.3g} s, {z}) [g]"
        if self.measure == "sa_avg":
            return f"Sa_avg({self.period_low:.3g}-{self.period_high:.3g} s, {z}) [g]"
        return "PGA [g]"

    def of(self, gm: GroundMotion) -> float:
        """The measure of a record [m/s²]."""
        if self.measure == "pga":
            return float(np.max(np.abs(gm.acceleration)))
        periods = self.periods
        peaks = spectral_peaks(gm.acceleration, gm.dt, periods, float(self.damping))
        psa = (2.0 * np.pi / periods) ** 2 * peaks[:, 0]
        return float(np.exp(np.mean(np.log(psa))))

    def scale_factor(self, gm: GroundMotion, target: float) -> float:
        """SF that brings the record to ``target`` [m/s²]."""
        value = self.of(gm)
        if not value > 0.0:
            raise PoundingInputError(
                f"record {gm.name!r} has {self.label} = 0: it cannot be scaled"
            )
        return target / value

    def to_dict(self) -> dict[str, object]:
        out: dict[str, object] = {"measure": self.measure, "damping": self.damping}
        if self.measure == "sa":
            out["period"] = self.period
        if self.measure == "sa_avg":
            out.update(
                period_low=self.period_low, period_high=self.period_high, n_periods=self.n_periods
            )
        return out
