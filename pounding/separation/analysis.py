"""The separation check: options, the case, every estimate per record and interface, the Dataset."""

from __future__ import annotations

import dataclasses
import datetime
import json
import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from pounding._version import __version__
from pounding.case import Case, CaseError, load_case
from pounding.errors import PoundingInputError
from pounding.ground_motion import GroundMotion
from pounding.records import resolve
from pounding.separation.pairs import (
    FacingPair,
    _as_grounds,
    _system_and_options,
    _time_history,
    _unique_names,
    facing_pairs,
)
from pounding.separation.probability import (
    empirical_pounding_probability,
    fit_lognormal,
    gap_for_probability,
    lognormal_pounding_probability,
)
from pounding.separation.rules import (
    _positive,
    abs_gap,
    asce7_inelastic_displacement,
    asce7_separation,
    combine_modes,
    cqc_correlation,
    ddc_gap,
    design_spectral_displacements,
    ec8_design_displacement,
    ec8_separation,
    modal_contributions,
    record_spectral_displacements,
    srss_gap,
)
from pounding.separation.variables import ESTIMATES, STATISTICS, _apply_attrs, _pair_coords
from pounding.spectra import (
    EC8_GROUND_TYPES,
)
from pounding.system import LEFT_SIGN, RIGHT_SIGN, WALL
from pounding.units import G

# ---------------------------------------------------------------------------------------------
# Options ([separation] table of a case file)
# ---------------------------------------------------------------------------------------------

#: Sources of the spectral estimates: the record's own spectrum or a code design spectrum.
SPECTRUM_SOURCES = ("record", "asce7", "ec8")


@dataclasses.dataclass(frozen=True)
class SeparationOptions:
    """Options of a separation analysis (the ``[separation]`` table of a case file).

    Attributes
    ----------
    records : tuple of str
        Record references (:func:`pounding.records.resolve`); default the case's ground motion.
    spectrum : {"record", "asce7", "ec8"}
        Spectrum of the spectral and code estimates: each record's own, or a design spectrum.
    s_ds, s_d1 : float
        ASCE 7 design spectral accelerations [g] (``spectrum = "asce7"``).
    t_l : float
        ASCE 7 long-period transition period [s].
    a_g : float
        EC8 design ground acceleration on type A ground [g] (``spectrum = "ec8"``).
    ground_type, spectrum_type
        EC8 ground type A-E and spectrum type 1 or 2.
    c_d, i_e, r : float
        ASCE 7 deflection amplification factor C_d, importance factor I_e (default 1.0) and response
        modification coefficient R [-]; the ASCE 7 estimates need C_d and R.
    q, q_d : float
        EC8 behaviour factor q and displacement behaviour factor q_d (default q) [-]; the EC8
        estimates need q.
    target_probability : float
        Probability of pounding for which the gap is reported (default 0.1).
    gaps : tuple of float, optional
        Gaps [m] of the probability curve; default 121 points from 0 to 1.5 × the largest g*.
    """

    records: tuple[str, ...] = ()
    spectrum: str = "record"
    s_ds: float | None = None
    s_d1: float | None = None
    t_l: float = 8.0
    a_g: float | None = None
    ground_type: str = "C"
    spectrum_type: int = 1
    c_d: float | None = None
    i_e: float = 1.0
    r: float | None = None
    q: float | None = None
    q_d: float | None = None
    target_probability: float = 0.1
    gaps: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        w = "separation"
        records = (self.records,) if isinstance(self.records, str) else tuple(self.records)
        if not all(isinstance(r, str) and r.strip() for r in records):
            raise PoundingInputError(
                f"{w}.records = {self.records!r}; allowed: record references (strings)"
            )
        object.__setattr__(self, "records", records)
        if self.spectrum not in SPECTRUM_SOURCES:
            raise PoundingInputError(
                f"{w}.spectrum = {self.spectrum!r}; allowed: {', '.join(SPECTRUM_SOURCES)}"
            )
        for name in ("s_ds", "s_d1", "t_l", "a_g", "c_d", "i_e", "r", "q", "q_d"):
            value = getattr(self, name)
            if value is not None:
                object.__setattr__(self, name, _positive(value, f"{w}.{name}"))
        if self.spectrum == "asce7" and (self.s_ds is None or self.s_d1 is None):
            raise PoundingInputError(f"{w}: spectrum = 'asce7' needs s_ds and s_d1 [g]")
        if self.spectrum == "ec8" and self.a_g is None:
            raise PoundingInputError(f"{w}: spectrum = 'ec8' needs a_g [g]")
        if self.spectrum_type not in EC8_GROUND_TYPES:
            raise PoundingInputError(f"{w}.spectrum_type = {self.spectrum_type!r}; allowed: 1, 2")
        ground = str(self.ground_type).strip().upper()
        if ground not in EC8_GROUND_TYPES[self.spectrum_type]:
            raise PoundingInputError(
                f"{w}.ground_type = {self.ground_type!r}; allowed: "
                f"{', '.join(EC8_GROUND_TYPES[self.spectrum_type])}"
            )
        object.__setattr__(self, "ground_type", ground)
        if (self.c_d is None) != (self.r is None):
            raise PoundingInputError(
                f"{w}: the ASCE 7 estimates need both c_d (C_d) and r (R); got c_d = {self.c_d}, "
                f"r = {self.r}"
            )
        if self.q_d is not None and self.q is None:
            raise PoundingInputError(f"{w}: q_d = {self.q_d} needs the behaviour factor q as well")
        p = float(self.target_probability)
        if not (0.0 < p < 1.0):
            raise PoundingInputError(f"{w}.target_probability = {p}; allowed: 0 < P < 1")
        object.__setattr__(self, "target_probability", p)
        if self.gaps is not None:
            gaps = np.asarray(self.gaps, float).ravel()
            if gaps.size == 0 or np.any(~np.isfinite(gaps)) or np.any(gaps < 0):
                raise PoundingInputError(f"{w}.gaps = {self.gaps!r}; allowed: numbers >= 0 [m]")
            object.__setattr__(self, "gaps", tuple(np.unique(gaps).tolist()))

    @classmethod
    def from_mapping(cls, options: Mapping[str, Any]) -> SeparationOptions:
        """Build from a mapping (a ``[separation]`` table), naming unknown keys and the allowed ones."""
        allowed = [f.name for f in dataclasses.fields(cls)]
        unknown = sorted(set(options) - set(allowed))
        if unknown:
            raise PoundingInputError(
                f"unknown separation option(s) {', '.join(unknown)}; allowed: {', '.join(allowed)}"
            )
        return cls(**dict(options))

    def spectrum_parameters(self) -> dict[str, Any]:
        """Keyword arguments of :func:`pounding.spectra.design_spectrum` in SI (a_g converted from g)."""
        if self.spectrum == "asce7":
            return {"s_ds": self.s_ds, "s_d1": self.s_d1, "t_l": self.t_l}
        if self.spectrum == "ec8":
            return {
                "a_g": self.a_g * G,
                "ground_type": self.ground_type,
                "spectrum_type": self.spectrum_type,
            }
        return {}

    def spectrum_description(self) -> str:
        """The spectrum of the spectral and code estimates, with its clause and parameters."""
        if self.spectrum == "asce7":
            return (
                f"ASCE/SEI 7-16 §11.4.6 design spectrum, S_DS = {self.s_ds:g} g, "
                f"S_D1 = {self.s_d1:g} g, T_L = {self.t_l:g} s (5 % damping)"
            )
        if self.spectrum == "ec8":
            return (
                f"EN 1998-1:2004 §3.2.2.2 elastic spectrum type {self.spectrum_type}, ground type "
                f"{self.ground_type}, a_g = {self.a_g:g} g (eta from each mode's damping, Eq. 3.6)"
            )
        return "each record's own elastic response spectrum at the modal periods and damping"

    def to_attrs(self) -> dict[str, Any]:
        """The options as NetCDF-safe attributes (None left out, sequences as JSON)."""
        out: dict[str, Any] = {}
        for f in dataclasses.fields(self):
            value = getattr(self, f.name)
            if value is None:
                continue
            out[f.name] = json.dumps(list(value)) if isinstance(value, tuple) else value
        return out


def load_separation_case(path: str | Path) -> tuple[Case, SeparationOptions]:
    """Read a case file and the options of its optional ``[separation]`` table."""
    case = load_case(path)
    table = case.data.get("separation", {})
    if not isinstance(table, Mapping):
        raise CaseError(f"{path}: [separation] must be a table")
    try:
        options = SeparationOptions.from_mapping(table)
    except (ValueError, TypeError) as exc:
        raise CaseError(f"{path}: {exc}") from None
    return case, options


# ---------------------------------------------------------------------------------------------
# The comparison
# ---------------------------------------------------------------------------------------------


#: Estimates of the required gap: name -> (label, basis: formula, clause, edition).
def _case_gaps(case: Any, interfaces: Sequence[str]) -> np.ndarray:
    """The case's gap at each interface (its smallest when floors differ); NaN where the case has
    no contact there."""
    gaps = dict.fromkeys(interfaces, math.inf)
    for c in getattr(case, "contacts", ()):
        name = f"{c.left}|{c.right}"
        if name in gaps:
            gaps[name] = min(gaps[name], float(c.gap))
    return np.array([g if math.isfinite(g) else np.nan for g in gaps.values()])


def _grounds_from_options(case: Case, refs: Sequence[str]) -> list[GroundMotion]:
    if not refs:
        return [case.ground_motion]
    base = case.path.parent if case.path is not None else None
    # the case's [ground_motion] scale applies to the suite too (a design level set once)
    scale = (case.data.get("ground_motion") or {}).get("scale")
    out: list[GroundMotion] = []
    for ref in refs:
        found = resolve(ref, base_dir=base)
        out.extend(found if scale is None else [gm.scaled(float(scale)) for gm in found])
    return out


def _pad(rows: Sequence[np.ndarray], width: int) -> np.ndarray:
    out = np.full((len(rows), width), np.nan)
    for i, r in enumerate(rows):
        out[i, : r.size] = r
    return out


def separation_analysis(
    case: Case,
    records: Sequence[GroundMotion] | Sequence[str] | None = None,
    options: SeparationOptions | Mapping[str, Any] | None = None,
    **analysis: Any,
) -> xr.Dataset:
    """Every estimate of the required gap of a case, side by side, as one Dataset.

    Parameters
    ----------
    case : Case
        Buildings (left to right), contacts (only to name facing pairs and set the integration step),
        analysis options and ground motion (:func:`load_separation_case`, :func:`pounding.load_case`).
    records : sequence of GroundMotion or of record references, optional
        The record suite; default ``options.records``, else the case's ground motion.
    options : SeparationOptions or mapping, optional
        Default: the case's ``[separation]`` table (``case.data["separation"]``), else the defaults.
    **analysis
        Overrides of the case's ``[analysis]`` options for the time histories (``method``, ``dt``).

    Returns
    -------
    xarray.Dataset
        Dims ``record``, ``pair``, ``interface``, ``estimate``, ``statistic``, ``gap``,
        ``building``, ``floor``, ``mode``. Key variables: ``exact_gap`` (record, pair),
        ``required_gap`` (record, interface, estimate), ``required_gap_statistic`` (interface,
        estimate, statistic), ``pounding_probability`` and ``pounding_probability_lognormal``
        (interface, gap), ``gap_for_target_probability`` (interface). CF ``units``/``long_name`` on
        every variable; parameters and provenance in ``attrs``. :func:`separation_table` and
        :func:`separation_summary` read it.
    """
    if not isinstance(case, Case):
        raise TypeError(
            "separation_analysis takes a Case (pounding.separation.load_separation_case)"
        )
    options, grounds = _options_and_grounds(case, records, options)
    system, opts = _system_and_options(case, analysis)
    pairs = facing_pairs(system)
    if not pairs:
        raise PoundingInputError(
            "the case has no facing points: give at least two buildings with a floor at a common "
            "elevation, or contacts with explicit floors or walls"
        )
    pk = _peaks(system, grounds, opts, pairs, options)
    estimates = _estimate_names(options)
    per_pair = np.full((pk.n_rec, len(pairs), len(estimates)), np.nan)
    rho_pair = np.full(len(pairs), np.nan)
    for p, pair in enumerate(pairs):
        cols, rho_pair[p] = _pair_estimates(pk, p, pair, options)
        for e, name in enumerate(estimates):
            per_pair[:, p, e] = cols[name]
    interfaces = list(dict.fromkeys(p.interface for p in pairs))
    members = [np.array([p.interface == f for p in pairs]) for f in interfaces]
    required = np.stack([per_pair[:, m, :].max(axis=1) for m in members], axis=1)
    stats = np.stack(
        [
            np.median(required, axis=0),
            np.percentile(required, 84.0, axis=0),
            required.max(axis=0),
        ],
        axis=-1,
    )  # (interface, estimate, statistic)
    # probability of pounding versus gap, per interface
    gstar = required[:, :, estimates.index("time_history")]  # (record, interface)
    gap_grid, probability = _probability(gstar, options)
    width = pk.width
    data = {
        "natural_period": (("building", "mode"), _pad([m.periods for m in pk.modals], width)),
        "modal_damping_ratio": (
            ("building", "mode"),
            _pad([m.damping_ratios for m in pk.modals], width),
        ),
        "spectral_displacement": (("record", "building", "mode"), pk.sd),
        "peak_displacement_time_history": (("record", "building", "floor"), pk.peak_th),
        "peak_displacement_srss": (("record", "building", "floor"), pk.peak_srss),
        "peak_displacement_cqc": (("record", "building", "floor"), pk.peak_cqc),
        "exact_gap": (("record", "pair"), pk.exact),
        "pair_correlation": (("pair",), rho_pair),
        "required_gap_pair": (("record", "pair", "estimate"), per_pair),
        "required_gap": (("record", "interface", "estimate"), required),
        "required_gap_statistic": (("interface", "estimate", "statistic"), stats),
        **probability,
        "case_gap": (("interface",), _case_gaps(case, interfaces)),
    }
    modes = np.arange(1, width + 1)
    coords = {
        "record": _unique_names(grounds),
        **_pair_coords(pairs),
        "interface": interfaces,
        "estimate": estimates,
        "estimate_label": ("estimate", [ESTIMATES[e][0] for e in estimates]),
        "estimate_basis": ("estimate", [ESTIMATES[e][1] for e in estimates]),
        "statistic": list(STATISTICS),
        "gap": gap_grid,
        "building": [b.name for b in system.buildings],
        "floor": modes,
        "mode": modes,
    }
    ds = xr.Dataset(data, coords=coords)
    _apply_attrs(ds)
    ds.attrs.update(_separation_attrs(case, options, pk))
    return ds


def _options_and_grounds(
    case: Case, records: Any, options: Any
) -> tuple[SeparationOptions, list[GroundMotion]]:
    """The separation options (given, or the case's [separation] table) and the record suite."""
    if options is None:
        options = SeparationOptions.from_mapping(case.data.get("separation", {}))
    elif not isinstance(options, SeparationOptions):
        options = SeparationOptions.from_mapping(options)
    if records is None:
        return options, _grounds_from_options(case, options.records)
    records = list(records)
    if all(isinstance(r, str) for r in records):
        return options, _grounds_from_options(case, records)
    return options, _as_grounds(case, records)


@dataclasses.dataclass(frozen=True, eq=False)
class _Peaks:
    """Peak floor displacements of every building by every estimate, per record: spectral
    displacements ``sd`` and modal contributions ``contrib`` (per building: record, floor, mode),
    the time histories ``th`` with their exact gaps ``exact`` (record, pair), and the SRSS, CQC and
    time-history peaks (record, building, floor)."""

    system: Any
    index: dict[str, int]
    modals: list[Any]
    width: int
    n_rec: int
    sd: np.ndarray
    contrib: list[np.ndarray]
    th: list[Any]
    exact: np.ndarray
    peak_srss: np.ndarray
    peak_cqc: np.ndarray
    peak_th: np.ndarray

    def at(self, name: str, floor: int, peaks: np.ndarray) -> np.ndarray:
        """One end of a facing pair: the peaks of building ``name`` at ``floor`` per record (0 for
        a wall). An isolated building's base slab (floor 0) has its time-history peak; fixed-base
        modal spectra (and the code rules built on them) say nothing about a sliding slab."""
        if name == WALL:
            return np.zeros(self.n_rec)
        if floor == 0:
            if peaks is self.peak_th:
                dof = int(self.system.base_dof[self.index[name]])
                return np.array([t.peak_displacement[dof] for t in self.th])
            return np.full(self.n_rec, np.nan)
        return peaks[:, self.index[name], floor - 1]


def _peaks(system: Any, grounds: list[GroundMotion], opts: Any, pairs: list[FacingPair],
           options: SeparationOptions) -> _Peaks:  # fmt: skip
    """Spectra first (cheap, and a bad design-spectrum parameter fails before any integration),
    then the time histories and the modal combinations."""
    blds = system.buildings
    modals = [b.modal() for b in blds]
    width = max(b.n_floors for b in blds)
    n_rec = len(grounds)
    params = options.spectrum_parameters()
    sd = np.full((n_rec, len(blds), width), np.nan)
    for k, gm in enumerate(grounds):
        for i, b in enumerate(blds):
            sd[k, i, : b.n_floors] = (
                record_spectral_displacements(b, gm)
                if options.spectrum == "record"
                else design_spectral_displacements(b, options.spectrum, **params)
            )
    contrib = [
        np.stack([modal_contributions(b, sd[k, i, : b.n_floors]) for k in range(n_rec)])
        for i, b in enumerate(blds)
    ]
    th = [_time_history(system, gm, opts, pairs) for gm in grounds]
    peak_srss = np.full((n_rec, len(blds), width), np.nan)
    peak_cqc = np.full_like(peak_srss, np.nan)
    peak_th = np.full_like(peak_srss, np.nan)
    for i, (b, m) in enumerate(zip(blds, modals, strict=True)):
        peak_srss[:, i, : b.n_floors] = combine_modes(
            contrib[i], m.periods, m.damping_ratios, "srss"
        )
        peak_cqc[:, i, : b.n_floors] = combine_modes(contrib[i], m.periods, m.damping_ratios, "cqc")
        off = int(system.dof_offset[i])
        for k in range(n_rec):
            peak_th[k, i, : b.n_floors] = th[k].peak_displacement[off : off + b.n_floors]
    return _Peaks(system, {b.name: i for i, b in enumerate(blds)}, modals, width, n_rec, sd,
                  contrib, th, np.array([t.exact_gap for t in th]), peak_srss, peak_cqc,
                  peak_th)  # fmt: skip


def _estimate_names(options: SeparationOptions) -> list[str]:
    """The estimates computed: always the time-history and spectral ones; the ASCE 7 and EC8 rules
    when their factors (c_d, q) are given."""
    estimates = [
        "time_history",
        "abs_time_history",
        "srss_time_history",
        "ddc_time_history",
        "abs_spectral",
        "srss_spectral",
        "ddc_spectral",
        "cqc_relative_spectral",
    ]
    if options.c_d is not None:
        estimates += ["asce7_same_property", "asce7_property_line"]
    if options.q is not None:
        estimates += ["ec8_same_property", "ec8_property_line"]
    return estimates


def _pair_estimates(
    pk: _Peaks, p: int, pair: FacingPair, options: SeparationOptions
) -> tuple[dict[str, np.ndarray], float]:
    """Every estimate of the gap a facing pair needs, per record, and the CQC correlation of the two
    buildings' first modes (NaN against a wall)."""
    cols: dict[str, np.ndarray] = {"time_history": pk.exact[:, p]}
    both = pair.left != WALL and pair.right != WALL
    rho = math.nan
    ta = tb = za = zb = math.nan
    if both:
        ma, mb = pk.modals[pk.index[pair.left]], pk.modals[pk.index[pair.right]]
        ta, tb = ma.periods[0], mb.periods[0]
        za, zb = ma.damping_ratios[0], mb.damping_ratios[0]
        rho = float(cqc_correlation(ta, tb, za, zb))
    for source, peaks in (("time_history", pk.peak_th), ("spectral", pk.peak_cqc)):
        ua = pk.at(pair.left, pair.left_floor, peaks)
        ub = pk.at(pair.right, pair.right_floor, peaks)
        cols[f"abs_{source}"] = abs_gap(ua, ub)
        cols[f"srss_{source}"] = srss_gap(ua, ub)
        cols[f"ddc_{source}"] = (
            ddc_gap(ua, ub, period_a=ta, period_b=tb, damping_a=za, damping_b=zb)
            if both
            else abs_gap(ua, ub)
        )
    # u_left - u_right over the modes of both buildings (a wall contributes nothing)
    terms, periods, damps = [], [], []
    for name, floor, sign in (
        (pair.left, pair.left_floor, LEFT_SIGN),
        (pair.right, pair.right_floor, RIGHT_SIGN),
    ):
        if name != WALL:
            i = pk.index[name]
            terms.append(sign * pk.contrib[i][:, floor - 1, :])
            periods.append(pk.modals[i].periods)
            damps.append(pk.modals[i].damping_ratios)
    cols["cqc_relative_spectral"] = combine_modes(
        np.concatenate(terms, axis=1), np.concatenate(periods), np.concatenate(damps), "cqc"
    )
    if pair.left_floor == 0 or pair.right_floor == 0:
        # fixed-base modes do not describe a sliding base slab
        cols["cqc_relative_spectral"] = np.full(pk.n_rec, np.nan)
    cols.update(_code_estimates(pk, pair, options))
    return cols, rho


def _code_estimates(
    pk: _Peaks, pair: FacingPair, options: SeparationOptions
) -> dict[str, np.ndarray]:
    """The ASCE 7 and EC8 separation rules on the elastic CQC peaks of the pair's two ends."""
    cols = {}
    u_el_a = pk.at(pair.left, pair.left_floor, pk.peak_cqc)
    u_el_b = pk.at(pair.right, pair.right_floor, pk.peak_cqc)
    if options.c_d is not None:
        dm_a, dm_b = (
            asce7_inelastic_displacement(
                options.i_e * u / options.r, c_d=options.c_d, i_e=options.i_e
            )
            for u in (u_el_a, u_el_b)
        )
        cols["asce7_same_property"] = asce7_separation(dm_a, dm_b, same_property=True)
        cols["asce7_property_line"] = asce7_separation(dm_a, dm_b, same_property=False)
    if options.q is not None:
        q_d = options.q_d if options.q_d is not None else options.q
        ds_a, ds_b = (ec8_design_displacement(u / options.q, q_d=q_d) for u in (u_el_a, u_el_b))
        for key, same in (("ec8_same_property", True), ("ec8_property_line", False)):
            cols[key] = ec8_separation(ds_a, ds_b, same_property=same, same_levels=pair.same_level)
    return cols


def _probability(
    gstar: np.ndarray, options: SeparationOptions
) -> tuple[np.ndarray, dict[str, tuple]]:
    """The gap grid and, per interface, the empirical and lognormal probabilities of pounding, the
    lognormal fit and the gap for the target probability, from the exact gaps (record, interface)."""
    if options.gaps is not None:
        gap_grid = np.asarray(options.gaps, float)
    else:
        top = float(gstar.max()) if gstar.size and gstar.max() > 0 else 0.01
        gap_grid = np.linspace(0.0, 1.5 * top, 121)
    n_int = gstar.shape[1]
    fits = [fit_lognormal(gstar[:, j]) for j in range(n_int)]
    return gap_grid, {
        "pounding_probability": (
            ("interface", "gap"),
            np.stack([empirical_pounding_probability(gap_grid, gstar[:, j]) for j in range(n_int)]),
        ),
        "pounding_probability_lognormal": (
            ("interface", "gap"),
            np.stack([lognormal_pounding_probability(gap_grid, f) for f in fits]),
        ),
        "lognormal_median": (("interface",), np.array([f.median for f in fits])),
        "lognormal_beta": (("interface",), np.array([f.beta for f in fits])),
        "lognormal_fraction": (("interface",), np.array([f.fraction for f in fits])),
        "gap_for_target_probability": (
            ("interface",),
            np.array([gap_for_probability(options.target_probability, f) for f in fits]),
        ),
    }


def _separation_attrs(case: Case, options: SeparationOptions, pk: _Peaks) -> dict[str, Any]:
    """Provenance and parameters of a separation Dataset."""
    return {
        "title": case.title,
        "pounding_kind": "separation",
        "pounding_version": __version__,
        "created": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
        "Conventions": "CF-1.8",
        "sign_convention": (
            "displacements relative to ground, positive to the right; "
            "penetration = u_left - u_right - gap"
        ),
        "spectrum": options.spectrum,
        "spectrum_description": options.spectrum_description(),
        "method": pk.th[0].method,
        "dt": float(pk.th[0].dt),
        "duration": float(pk.th[0].duration),
        "target_probability": options.target_probability,
        "n_records": pk.n_rec,
        **{f"option_{k}": v for k, v in options.to_attrs().items()},
    }
