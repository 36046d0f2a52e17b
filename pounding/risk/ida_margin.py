"""The FEMA P695 collapse margin of every variant of an incremental dynamic analysis.

Each record's collapse intensity is the lowest level at which it collapsed (a hunt-and-fill IDA
brackets it to its tolerance; listed levels give it to their spacing), and Ŝ_CT is their median,
records that never collapsed ranking above all others.

With ``scaling = "set"`` the levels are those of FEMA P695 (Sec. 6.2): the records normalised by
their PGV (NM_i = median PGV / PGV_i) and scaled together so that the set's median Sa(T) is the
level; the median of the collapse levels is then the level at which half the records collapse,
P695's Ŝ_CT exactly (with the set's median spectrum from the records analysed rather than FEMA's
tabulated one). With the default ``scaling = "record"`` each record is scaled to Sa(T) on its own:
the record-to-record dispersion of Sa(T) is removed, and the numbers are comparable, not identical.
"""

from __future__ import annotations

import json
from typing import Any

import numpy as np

from pounding.errors import PoundingInputError
from pounding.fragility import COLLAPSE, study_fragility
from pounding.risk.collapse_margin import (
    _ductility,
    _period,
    _sdc,
    acceptable_acmr,
    collapse_margin,
    mce_spectral_acceleration,
    spectral_shape_factor,
    total_uncertainty,
)

_FIELDS = {
    "median_collapse_sa": ("g", "median collapse intensity Ŝ_CT"),
    "cmr": ("1", "collapse margin ratio Ŝ_CT/S_MT"),
    "acmr": ("1", "adjusted collapse margin ratio SSF × CMR"),
    "p_collapse_mce": ("1", "probability of collapse at the MCE, Φ(−ln ACMR/β_TOT)"),
    "n_censored": ("1", "records without a collapse (censored)"),
}


def ida_collapse_margin(
    ds: Any,
    ductility: float,
    sdc: str = "Dmax",
    design: str = "B",
    test: str = "B",
    model: str = "B",
    building: str | None = None,
) -> Any:
    """Collapse margin (:func:`~pounding.risk.collapse_margin.collapse_margin`) of every variant of
    an IDA Dataset whose intensity measure is Sa(T) [g]: ``median_collapse_sa``, ``cmr``, ``acmr``,
    ``p_collapse_mce``, ``passes`` (ACMR ≥ ACMR20 %), ``n_censored`` and, when the IDA has the
    no-contact law, ``cmr_ratio`` (CMR with contact / without). The period T is the IDA's own;
    attributes give S_MT, SSF, β_TOT, ACMR10 %/20 % and the assumptions."""
    import xarray as xr

    im = json.loads(ds.attrs.get("intensity_measure", "{}") or "{}")
    if im.get("measure") != "sa":
        raise PoundingInputError(
            f"collapse margin: the IDA's intensity measure is {im.get('measure') or 'none'}; "
            "allowed: sa (FEMA P695 scales to Sa(T) at the fundamental period)"
        )
    period = float(im["period"])
    # the design values hold for every variant (and are checked before the fits)
    t, mu = _period(period), _ductility(ductility)
    beta = total_uncertainty(mu, design, test, model)
    design_values = {
        "period": t,
        "sdc": _sdc(sdc),
        "s_mt": mce_spectral_acceleration(t, _sdc(sdc)),
        "ssf": spectral_shape_factor(t, mu, _sdc(sdc)),
        "beta_total": beta,
        "acmr10": acceptable_acmr(beta, 0.10),
        "acmr20": acceptable_acmr(beta, 0.20),
    }
    fr = study_fragility(ds, COLLAPSE, building=building, method="ida")
    cap = fr["capacity"].sel(limit_state=COLLAPSE, drop=True)
    dims = [d for d in cap.dims if d != "record"]
    shape = tuple(cap.sizes[d] for d in dims)
    out = {name: np.full(shape, np.nan) for name in _FIELDS}
    passes = np.zeros(shape, dtype=bool)
    notes = np.full(shape, "", dtype=object)
    # every cell, the no-contact law at each gap too: the ratios with contact divide by it
    for index in np.ndindex(*shape):
        values = cap.isel(dict(zip(dims, index, strict=True))).values
        sa = np.where(np.isfinite(values), values, np.inf)
        try:
            cm = collapse_margin(sa, period, ductility, sdc, design, test, model)
        except PoundingInputError as exc:
            notes[index] = str(exc)
            continue
        for name in _FIELDS:
            out[name][index] = getattr(cm, name)
        passes[index] = cm.passes
    coords = {d: cap[d] for d in dims}
    res = xr.Dataset(
        {
            name: (dims, values, {"units": units, "long_name": long_name})
            for name, values, (units, long_name) in ((n, out[n], _FIELDS[n]) for n in _FIELDS)
        },
        coords=coords,
    )
    res["passes"] = (dims, passes, {"long_name": "ACMR ≥ ACMR20 % (FEMA P695 Sec. 7.5)"})
    res["note"] = (dims, notes.astype(str), {"long_name": "why no margin (empty: computed)"})
    if "law" in dims and "none" in [str(v) for v in cap["law"].values]:
        ratio = res["cmr"] / res["cmr"].sel(law="none")
        res["cmr_ratio"] = ratio.assign_attrs(
            units="1", long_name="CMR with contact / without (below 1: pounding lowers the margin)"
        )
    scaling = str(ds.attrs.get("scaling", "record"))
    how = (
        "the PGV-normalised set scaled together (FEMA P695 Sec. 6.2; its median spectrum from these "
        "records, not FEMA's table), Ŝ_CT the set intensity at which half the records collapsed"
        if scaling == "set"
        else "records scaled one by one, not as a PGV-normalised set; Ŝ_CT the median of the "
        "records' collapse Sa(T)"
    )
    res.attrs.update(
        **design_values,
        ductility=float(ductility),
        ratings=f"design {design}, test {test}, model {model}",
        building=building or "any",
        scaling=scaling,
        method=(
            f"FEMA P695: {how} (records without a collapse rank above all others), "
            "CMR = Ŝ_CT/S_MT, ACMR = SSF·CMR (Appendix B), β_TOT (Eq. 7-5), ACMR20 % (Table 7-3)"
        ),
    )
    return res
