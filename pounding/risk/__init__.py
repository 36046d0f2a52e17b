"""From responses to risk: intensity measures for scaling records, lognormal fragility fitting,
and the FEMA P695 collapse margin."""

from pounding.fragility import Fragility, bootstrap, fit_ida, fit_stripes
from pounding.intensity import MEASURES, IntensityMeasure

__all__ = [
    "MEASURES",
    "Fragility",
    "IntensityMeasure",
    "bootstrap",
    "fit_ida",
    "fit_stripes",
]
