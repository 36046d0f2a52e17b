"""The separation Dataset's vocabulary: the estimates, the statistics, units and long names of every
variable, and the coordinates of the facing pairs."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
import xarray as xr

from pounding._schema import ATTRS

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


def _apply_attrs(ds: xr.Dataset) -> None:
    # the package's one vocabulary of units and long names (pounding._schema.ATTRS)
    for name in ds.variables:
        if name in ATTRS:
            ds[name].attrs.update(ATTRS[name])


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
