"""From responses to risk: intensity measures for scaling records, lognormal fragility fitting,
and the FEMA P695 collapse margin."""

from pounding.fragility import Fragility, bootstrap, fit_ida, fit_stripes, study_fragility
from pounding.intensity import MEASURES, IntensityMeasure
from pounding.risk.collapse_margin import (
    CollapseMargin,
    acceptable_acmr,
    collapse_margin,
    mce_spectral_acceleration,
    period_based_ductility,
    spectral_shape_factor,
    total_uncertainty,
)
from pounding.risk.ida_margin import ida_collapse_margin

__all__ = [
    "MEASURES",
    "CollapseMargin",
    "Fragility",
    "IntensityMeasure",
    "acceptable_acmr",
    "bootstrap",
    "collapse_margin",
    "fit_ida",
    "fit_stripes",
    "ida_collapse_margin",
    "mce_spectral_acceleration",
    "period_based_ductility",
    "spectral_shape_factor",
    "study_fragility",
    "total_uncertainty",
]
