"""The separation Dataset's vocabulary: the estimates, the statistics, units and long names of every
variable, and the coordinates of the facing pairs."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
import xarray as xr

ESTIMATES: dict[str, tuple[str, str]] = {
    "time_history": (
        "exact, time history without contact",
        "max over t of u_left - u_right at every integration step",
    ),
    "abs_time_history": ("ABS of time-history peaks", "|u_A| + |u_B|"),
    "srss_time_history": ("SRSS of time-history peaks", "sqrt(u_A^2 + u_B^2)"),
    "ddc_time_history": (
        "DDC of time-history peaks",
        "sqrt(u_A^2 + u_B^2 - 2 rho u_A u_B), rho: CQC of T1, zeta1 (Jeng et al. 1992; Penzien 1997)",
    ),
    "abs_spectral": ("ABS of spectral peaks (CQC over modes)", "|u_A| + |u_B|"),
    "srss_spectral": ("SRSS of spectral peaks (CQC over modes)", "sqrt(u_A^2 + u_B^2)"),
    "ddc_spectral": (
        "DDC of spectral peaks (CQC over modes)",
        "sqrt(u_A^2 + u_B^2 - 2 rho u_A u_B), rho: CQC of T1, zeta1 (Jeng et al. 1992; Penzien 1997)",
    ),
    "cqc_relative_spectral": (
        "CQC of u_A - u_B over the modes of both buildings",
        "sqrt(sum_ij rho_ij c_i c_j) (Der Kiureghian 1981)",
    ),
    "asce7_same_property": (
        "ASCE 7-16, same property",
        "ASCE/SEI 7-16 §12.12.3 Eq. 12.12-2: sqrt(dM1^2 + dM2^2), dM = Cd dmax/Ie (Eq. 12.12-1), "
        "dmax = Ie u_el/R",
    ),
    "asce7_property_line": (
        "ASCE 7-16, setbacks from a property line",
        "ASCE/SEI 7-16 §12.12.3: dM1 + dM2, dM = Cd dmax/Ie (Eq. 12.12-1), dmax = Ie u_el/R",
    ),
    "ec8_same_property": (
        "EC8, same property",
        "EN 1998-1:2004 §4.4.2.7(2)b: sqrt(ds1^2 + ds2^2), ds = qd de (Eq. 4.23), de = u_el/q; "
        "x0.7 where floor levels coincide (§4.4.2.7(3))",
    ),
    "ec8_property_line": (
        "EC8, distances to a property line",
        "EN 1998-1:2004 §4.4.2.7(2)a: ds1 + ds2, ds = qd de (Eq. 4.23), de = u_el/q; "
        "x0.7 where floor levels coincide (§4.4.2.7(3))",
    ),
}

#: Statistics over the records.
STATISTICS = ("median", "p84", "max")

_ATTRS: dict[str, dict[str, str]] = {
    "record": {"long_name": "ground-motion record"},
    "pair": {"long_name": "facing pair"},
    "pair_label": {"long_name": "facing pair (building:floor-building:floor)"},
    "pair_left": {"long_name": "left end of the facing pair (building or wall)"},
    "pair_right": {"long_name": "right end of the facing pair (building or wall)"},
    "pair_left_floor": {"units": "1", "long_name": "floor of the left end (0 = wall)"},
    "pair_right_floor": {"units": "1", "long_name": "floor of the right end (0 = wall)"},
    "pair_left_elevation": {"units": "m", "long_name": "elevation of the left end"},
    "pair_right_elevation": {"units": "m", "long_name": "elevation of the right end"},
    "pair_interface": {"long_name": "interface (neighbours or building and wall) of the pair"},
    "pair_same_level": {"units": "1", "long_name": "floors of the pair at the same elevation"},
    "interface": {"long_name": "interface between neighbours (or a building and a wall)"},
    "building": {"long_name": "building"},
    "floor": {"long_name": "floor number (1 = lowest)"},
    "mode": {"long_name": "mode number"},
    "estimate": {"long_name": "estimate of the required gap"},
    "estimate_label": {"long_name": "estimate of the required gap, description"},
    "estimate_basis": {"long_name": "formula, clause and edition of the estimate"},
    "statistic": {"long_name": "statistic over the records (median, 84th percentile, maximum)"},
    "gap": {"units": "m", "long_name": "clear gap at rest"},
    "natural_period": {"units": "s", "long_name": "natural period"},
    "modal_damping_ratio": {"units": "1", "long_name": "modal damping ratio"},
    "spectral_displacement": {"units": "m", "long_name": "spectral displacement Sd(T_n, zeta_n)"},
    "peak_displacement_time_history": {
        "units": "m",
        "long_name": "peak floor displacement, time history without contact",
    },
    "peak_displacement_srss": {
        "units": "m",
        "long_name": "peak floor displacement, spectral, SRSS over modes",
    },
    "peak_displacement_cqc": {
        "units": "m",
        "long_name": "peak floor displacement, spectral, CQC over modes",
    },
    "exact_gap": {
        "units": "m",
        "long_name": "minimum gap avoiding contact (max over time of u_left - u_right)",
    },
    "pair_correlation": {
        "units": "1",
        "long_name": "CQC correlation of the fundamental modes of the pair's buildings (DDC)",
    },
    "required_gap_pair": {"units": "m", "long_name": "required gap of each facing pair"},
    "required_gap": {
        "units": "m",
        "long_name": "required gap (largest over the interface's pairs)",
    },
    "required_gap_statistic": {
        "units": "m",
        "long_name": "required gap, statistic over the records",
    },
    "pounding_probability": {
        "units": "1",
        "long_name": "fraction of records with contact (empirical probability of pounding)",
    },
    "pounding_probability_lognormal": {
        "units": "1",
        "long_name": "probability of pounding, lognormal fit of the exact gaps",
    },
    "lognormal_median": {"units": "m", "long_name": "median of the lognormal fit of the exact gap"},
    "lognormal_beta": {"units": "1", "long_name": "logarithmic standard deviation of the fit"},
    "lognormal_fraction": {
        "units": "1",
        "long_name": "fraction of records whose exact gap is positive",
    },
    "gap_for_target_probability": {
        "units": "m",
        "long_name": "gap with the target probability of pounding (lognormal fit)",
    },
    "case_gap": {"units": "m", "long_name": "gap of the case's contacts (smallest per interface)"},
}


def _apply_attrs(ds: xr.Dataset) -> None:
    for name in ds.variables:
        if name in _ATTRS:
            ds[name].attrs.update(_ATTRS[name])


def _pair_coords(pairs: Sequence[Any]) -> dict[str, Any]:
    # pairs: pounding.separation.pairs.FacingPair (the layer above)
    return {
        "pair": np.arange(len(pairs)),
        "pair_label": ("pair", [p.label for p in pairs]),
        "pair_left": ("pair", [p.left for p in pairs]),
        "pair_right": ("pair", [p.right for p in pairs]),
        "pair_left_floor": ("pair", np.array([p.left_floor for p in pairs], dtype=np.int64)),
        "pair_right_floor": ("pair", np.array([p.right_floor for p in pairs], dtype=np.int64)),
        "pair_left_elevation": ("pair", np.array([p.left_elevation for p in pairs])),
        "pair_right_elevation": ("pair", np.array([p.right_elevation for p in pairs])),
        "pair_interface": ("pair", [p.interface for p in pairs]),
        "pair_same_level": ("pair", np.array([p.same_level for p in pairs], dtype=np.int8)),
    }
