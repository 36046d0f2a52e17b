"""The ``[study]`` table: axes, law parameters, records, and the case of each combination."""

from __future__ import annotations

import copy
import dataclasses
import functools
import hashlib
import json
import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from pounding import records
from pounding._version import __version__
from pounding.case import Case, CaseError, case_from_dict, read_case_file
from pounding.contact.laws import get_contact_law
from pounding.errors import PoundingInputError
from pounding.ground_motion import GroundMotion
from pounding.intensity import MEASURES, IntensityMeasure
from pounding.studies.hunt import HuntOptions, is_limit_state
from pounding.units import G

#: Axes with a meaning of their own; any other axis is a dotted path into the case.
NAMED_AXES = ("law", "gap", "e", "k", "record", "scale", "im_level")
#: Largest record scale factor and intensity level [g] of a study (a record at 100 g collapses any
#: building; 1e300 g was accepted).
MAX_SCALE, MAX_IM_LEVEL = 1000.0, 100.0
#: Keys of ``[study]`` that are options, not axes.
STUDY_OPTIONS = (
    "law_params",
    "keep_histories",
    "history_dt",
    "im",
    "limit_states",
    "hunt",
    "scaling",
)
#: How records reach a target intensity: one by one, or as a PGV-normalised set (FEMA P695).
SCALINGS = ("record", "set")
#: Keys of an ``im`` table beside ``measure``.
IM_KEYS = ("building", "period", "period_low", "period_high", "n_periods", "damping")
#: The ``law`` value that removes every contact (the no-contact baseline).
NO_CONTACT = "none"
#: Keys a ``[study.law_params.LAW]`` table may set.
LAW_PARAM_KEYS = (
    "k",
    "e",
    "n",
    "a",
    "delta_m",
    "calibration",
    "thickness",
    "k_rubber",
    "e_rubber",
    "crush",
    "k_filler",
    "c_filler",
)
#: The rubber layer of law "bumper" (dropped for the other laws).
_BUMPER_KEYS = ("thickness", "k_rubber", "e_rubber", "crush")
#: The filler of law "filler" (dropped for the other laws).
_FILLER_KEYS = ("k_filler", "c_filler", "crush")
# A stand-in [ground_motion] used while the record comes from the `record` axis (never integrated).
_PLACEHOLDER_MOTION = {"type": "sine_pulse", "duration": 0.01, "dt": 0.005}


#: Time-history variables kept per run with ``keep_histories = true``.
HISTORY_VARIABLES = ("displacement", "contact_force", "penetration", "energy")
# Kept histories are for plots: single precision, compressed (about 0.2 MB per 2000 steps).
_HISTORY_ENCODING = {"dtype": "float32", "zlib": True, "complevel": 4, "shuffle": True}


class StudyError(CaseError):
    """A ``[study]`` table is malformed or one of its combinations is invalid."""


# --------------------------------------------------------------------------------------------------
# The study definition
# --------------------------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class Record:
    """One value of the ``record`` axis: a ground motion, or the error that prevented reading it."""

    name: str
    reference: str
    motion: GroundMotion | None
    error: str = ""


@dataclasses.dataclass(frozen=True, eq=False)
class Study:
    """A validated study: the base case, the axes in order, and the options.

    ``axes`` maps each axis name to its values; the ``record`` axis (always present: the case's own
    ground motion when the study does not sweep records) holds :class:`Record` objects.
    """

    case: Case
    axes: dict[str, tuple[Any, ...]]
    law_params: dict[str, dict[str, Any]]
    keep_histories: bool = False
    history_dt: float = 0.02
    base_dir: Path | None = None
    source: str = "case"
    # True when the ground motion is defined per run by the case (ground_motion.* axes)
    motion_from_case: bool = False
    #: the intensity measure of the ``im_level`` axis (records scaled to each level)
    im: IntensityMeasure | None = None
    #: limit states for the fragility of an IDA: "collapse" or story drift ratios
    limit_states: tuple[str | float, ...] = ("collapse",)
    #: hunt-and-fill levels per record instead of the ``im_level`` axis (``[ida] levels = "hunt"``)
    hunt: HuntOptions | None = None
    #: "record": each record scaled to the level; "set": the records normalised by their PGV and
    #: scaled together so that the set's median intensity is the level (FEMA P695 Sec. 6.2)
    scaling: str = "record"

    def scale_factor(self, record: Record, level: float) -> float:
        """The factor that brings ``record`` to intensity ``level`` [g] of :attr:`im` (with set
        scaling: its PGV normalisation times the factor that brings the normalised set's median
        to ``level``)."""
        assert self.im is not None
        if self.scaling == "set":
            normal, median = self._set_statistics
            return normal[record.name] * level * G / median
        value = self.record_intensity(record)
        if not value > 0.0:  # the measure's own error, naming the record
            return self.im.scale_factor(record.motion, level * G)  # type: ignore[arg-type]
        return level * G / value

    def record_intensity(self, record: Record) -> float:
        """The record's :attr:`im` as read [m/s²], computed once per record (a response spectrum
        each: scaling a record to many levels must not recompute it)."""
        return self._intensities[record.name]

    @functools.cached_property
    def _intensities(self) -> dict[str, float]:
        assert self.im is not None
        im = self.im
        return {r.name: im.of(r.motion) for r in self.axes["record"] if r.motion is not None}

    def normalisation(self, record: Record) -> float:
        """FEMA P695's NM_i = median(PGV)/PGV_i of a record (1 when records are scaled one by
        one)."""
        return self._set_statistics[0][record.name] if self.scaling == "set" else 1.0

    @functools.cached_property
    def _set_statistics(self) -> tuple[dict[str, float], float]:
        """({record: NM_i}, the median intensity [m/s²] of the normalised set)."""
        assert self.im is not None
        from pounding.ground_motion import ground_velocity

        recs = [r for r in self.axes["record"] if r.motion is not None]
        pgv = {r.name: float(np.max(np.abs(ground_velocity(r.motion)))) for r in recs}
        median_pgv = float(np.median(list(pgv.values())))
        normal = {name: median_pgv / v for name, v in pgv.items()}
        median = float(np.median([normal[r.name] * self.record_intensity(r) for r in recs]))
        return normal, median

    @property
    def warnings(self) -> list[str]:
        """What the user should know before the runs: an IDA whose collapse limit state no
        building can reach (elastic stories without P-Δ)."""
        if self.im is None or "collapse" not in self.limit_states:
            return []
        if any(b.can_collapse for b in self.case.system.buildings):
            return []
        return [
            "no building can collapse (elastic stories without P-Δ): the collapse limit state is "
            "never reached; its fragility will have no fit (give yielding stories or p_delta = "
            "true, or drift limit states such as limit_states = [0.02])"
        ]

    @property
    def level_label(self) -> str:
        """What a level [g] is: ``target Sa(0.52 s, 5 %)``, or the set's median of it."""
        assert self.im is not None
        measure = self.im.label.removesuffix(" [g]")
        if self.scaling == "set":
            return f"target median {measure} of the PGV-normalised set"
        return f"target {measure}"

    @property
    def title(self) -> str:
        return self.case.title

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(len(v) for v in self.axes.values())

    @property
    def size(self) -> int:
        return math.prod(self.shape)


def _flatten(table: Mapping[str, Any], prefix: str = "") -> list[tuple[str, Any]]:
    """Bare dotted TOML keys arrive as nested tables: turn them back into (dotted path, list)."""
    out = []
    for key, value in table.items():
        path = f"{prefix}{key}"
        if isinstance(value, Mapping):
            out.extend(_flatten(value, f"{path}."))
        else:
            out.append((path, value))
    return out


def _axis_values(name: str, value: Any, where: str) -> tuple[Any, ...]:
    if not isinstance(value, list) or not value:
        raise StudyError(f"{where}: study.{name} = {value!r}; allowed: a non-empty list of values")
    keys = [json.dumps(v, sort_keys=True, default=str) for v in value]
    dupes = sorted({k for k in keys if keys.count(k) > 1})
    if dupes:
        raise StudyError(f"{where}: study.{name} repeats {', '.join(dupes)}; values must differ")
    return tuple(value)


def _check_number(
    name: str, values: Sequence[Any], where: str, low: float, what: str, high: float = math.inf
) -> None:
    for v in values:
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not (math.isfinite(v)):
            raise StudyError(f"{where}: study.{name} value {v!r}; allowed: {what}")
        if v < low or v > high or (low == 0.0 and name != "gap" and v == 0.0):
            raise StudyError(f"{where}: study.{name} value {v!r}; allowed: {what}")


def _history_dt(value: Any, source: str) -> float:
    """``study.history_dt`` [s], finite and positive (NaN reached the decimation of every run)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not 0 < value < math.inf:
        raise StudyError(
            f"{source}: study.history_dt = {value!r}; allowed: a finite number > 0 [s]"
        )
    return float(value)


def _law_name(value: Any, where: str) -> str:
    if value == NO_CONTACT:
        return NO_CONTACT
    try:
        return get_contact_law(str(value)).name
    except ValueError as exc:
        raise StudyError(f"{where}: study.law: {exc} (or {NO_CONTACT!r} for no contact)") from None


def _parse_law_params(spec: Any, where: str) -> dict[str, dict[str, Any]]:
    if not isinstance(spec, Mapping):
        raise StudyError(
            f"{where}: study.law_params must hold one table per law, e.g. [study.law_params.linear]"
        )
    out: dict[str, dict[str, Any]] = {}
    for law, params in spec.items():
        name = _law_name(law, where)
        if name == NO_CONTACT or not isinstance(params, Mapping):
            raise StudyError(
                f"{where}: study.law_params.{law} must be a table of contact parameters"
            )
        unknown = sorted(set(params) - set(LAW_PARAM_KEYS))
        if unknown:
            raise StudyError(
                f"{where}: study.law_params.{law}: unknown key(s) {', '.join(unknown)}; "
                f"allowed: {', '.join(LAW_PARAM_KEYS)}"
            )
        out[name] = dict(params)
    return out


def _records(refs: Sequence[Any], base: Case, base_dir: Path | None, where: str) -> list[Record]:
    """Resolve the ``record`` axis; a reference that cannot be read becomes a failed record."""
    out: list[Record] = []
    for ref in refs:
        if isinstance(ref, Mapping):  # an inline [ground_motion]-style table
            data = {**base.data, "contact": [], "ground_motion": dict(ref)}
            try:
                gm = case_from_dict(
                    data, base_dir=base_dir, source=f"{where}: study.record"
                ).ground_motion
            except CaseError as exc:
                raise StudyError(str(exc)) from None
            out.append(Record(gm.name, json.dumps(dict(ref), sort_keys=True), gm))
            continue
        if not isinstance(ref, str):
            raise StudyError(
                f"{where}: study.record value {ref!r}; allowed: a record reference or a "
                "[ground_motion]-style table"
            )
        try:
            found = records.resolve(ref, base_dir=base_dir)
        except records.SuiteUnavailableError as exc:
            raise StudyError(f"{where}: study.record: {exc}") from None
        except (ValueError, OSError) as exc:
            out.append(Record(ref, ref, None, f"record {ref!r}: {exc}"))
            continue
        for gm in found:
            out.append(Record(gm.name, str(gm.metadata.get("reference", ref)), gm))
    names: list[str] = []
    unique = []
    for rec in out:
        name, k = rec.name, 2
        while name in names:
            name, k = f"{rec.name} ({k})", k + 1
        names.append(name)
        unique.append(dataclasses.replace(rec, name=name))
    return unique


def study_from_dict(
    data: Mapping[str, Any], *, base_dir: str | Path | None = None, source: str = "case"
) -> Study:
    """Build a :class:`Study` from a parsed case mapping that has a ``[study]`` table."""
    data = copy.deepcopy(dict(data))
    base_dir = None if base_dir is None else Path(base_dir)
    if "ida" in data:
        if "study" in data:
            raise StudyError(f"{source}: give [ida] or [study], not both")
        data["study"] = _ida_as_study(data.pop("ida"), source)
    spec = data.pop("study", None)
    if not isinstance(spec, Mapping) or not spec:
        raise StudyError(f"{source}: no [study] or [ida] table (see the README for their axes)")
    law_params = _parse_law_params(spec.get("law_params", {}), source)
    keep = spec.get("keep_histories", False)
    if not isinstance(keep, bool):
        raise StudyError(f"{source}: study.keep_histories = {keep!r}; allowed: true or false")
    history_dt = _history_dt(spec.get("history_dt", 0.02), source)

    axes: dict[str, tuple[Any, ...]] = {}
    entries = [(k, v) for k, v in spec.items() if k not in STUDY_OPTIONS]
    for key, value in entries:
        pairs = [(key, value)] if key in NAMED_AXES else _flatten({key: value})
        for name, values in pairs:
            axes[name] = _axis_values(name, values, source)
    if not axes:
        raise StudyError(
            f"{source}: [study] has no axes; give at least one of {', '.join(NAMED_AXES)} "
            "or a dotted path such as contact.0.k"
        )
    if law_params and "law" not in axes:
        raise StudyError(
            f"{source}: study.law_params apply when the law axis sets a law; add study.law "
            "(or set the parameters in the [[contact]] tables)"
        )
    if "law" in axes:
        axes["law"] = tuple(_law_name(v, source) for v in axes["law"])
        _axis_values("law", list(axes["law"]), source)  # aliases may collide
        families = {get_contact_law(v).has_exponent for v in axes["law"] if v != NO_CONTACT}
        if "k" in axes and len(families) > 1:
            raise StudyError(
                f"{source}: study.k sets one k for laws whose k has different units (N/m for "
                "the linear family, N/m^n for the Hertz family); sweep k with laws of one family "
                "(or drop study.k and give each law its k in [study.law_params.LAW])"
            )
    unused = sorted(set(law_params) - set(axes.get("law", ())))
    if unused:
        raise StudyError(
            f"{source}: study.law_params.{unused[0]}: law {unused[0]!r} is not on the law axis"
        )
    _check_number("gap", axes.get("gap", ()), source, 0.0, "a number >= 0 [m]")
    _check_number("e", axes.get("e", ()), source, 0.0, "0 < e <= 1")
    if any(v > 1 for v in axes.get("e", ())):
        raise StudyError(f"{source}: study.e values {axes['e']}; allowed: 0 < e <= 1")
    _check_number("k", axes.get("k", ()), source, 0.0, "a number > 0 [N/m^n]")
    # a record scaled by 1e300 or to 1e300 g is a typing error, not a stripe of an IDA
    _check_number(
        "scale", axes.get("scale", ()), source, -MAX_SCALE, f"|scale| <= {MAX_SCALE:g}", MAX_SCALE
    )
    _check_number(
        "im_level", axes.get("im_level", ()), source, 0.0,
        f"a number > 0 and <= {MAX_IM_LEVEL:g} [g]", MAX_IM_LEVEL,
    )  # fmt: skip
    hunt = None
    if "hunt" in spec:
        try:
            hunt = HuntOptions.from_table(spec["hunt"])
        except PoundingInputError as exc:
            raise StudyError(f"{source}: {exc}") from None
        if "im_level" in axes or "scale" in axes:
            raise StudyError(
                f'{source}: ida.levels = "hunt" chooses each record\'s levels; it cannot be '
                "combined with study.im_level or study.scale"
            )
    scaling = spec.get("scaling", "record")
    if scaling not in SCALINGS:
        raise StudyError(f"{source}: scaling = {scaling!r}; allowed: {', '.join(SCALINGS)}")
    if scaling == "set" and "im" not in spec:
        raise StudyError(f'{source}: scaling = "set" scales records to an intensity: give im')
    if ("im_level" in axes or hunt is not None) != ("im" in spec):
        raise StudyError(
            f"{source}: study.im_level (target intensities [g]) and study.im (the intensity "
            f"measure: {', '.join(MEASURES)}) go together"
        )
    if "im_level" in axes and "scale" in axes:
        raise StudyError(
            f"{source}: study.im_level scales each record to the levels; it cannot be combined "
            "with study.scale (a fixed factor)"
        )
    paths = [a for a in axes if a not in NAMED_AXES]
    for path in paths:
        head = path.split(".")[0]
        if head not in ("building", "contact", "ground_motion", "analysis"):
            raise StudyError(
                f"{source}: study axis {path!r}: unknown; allowed: {', '.join(NAMED_AXES)} or a "
                "dotted path into building, contact, ground_motion or analysis (e.g. contact.0.k)"
            )
    motion_from_case = any(p.startswith("ground_motion.") for p in paths)
    if motion_from_case and ("record" in axes or "scale" in axes or "im_level" in axes):
        raise StudyError(
            f"{source}: study axes ground_motion.* cannot be combined with record, scale or "
            "im_level (sweep one or the other)"
        )
    if "record" in axes and "ground_motion" not in data:
        data["ground_motion"] = dict(_PLACEHOLDER_MOTION)
    try:
        base = case_from_dict(data, base_dir=base_dir, source=source)
    except CaseError as exc:
        raise StudyError(str(exc)) from None
    if not data.get("contact") and any(a in axes for a in ("gap", "e", "k")):
        raise StudyError(f"{source}: study axes gap, e and k need at least one [[contact]]")
    for path in paths:
        _set_path(copy.deepcopy(data), path, axes[path][0], source)
    if "record" in axes:
        recs = _records(axes["record"], base, base_dir, source)
    else:
        gm = base.ground_motion
        recs = [Record(gm.name, str(gm.metadata.get("reference", gm.name)), gm)]
    study = Study(
        case=base,
        axes={**axes, "record": tuple(recs)},
        law_params=law_params,
        keep_histories=keep,
        history_dt=float(history_dt),
        base_dir=base_dir,
        source=source,
        motion_from_case=motion_from_case,
        im=_intensity_measure(spec["im"], base, source) if "im" in spec else None,
        limit_states=_limit_states(spec.get("limit_states", ["collapse"]), source),
        hunt=hunt,
        scaling=scaling,
    )
    if hunt is not None and hunt.limit_state == "collapse":
        if not any(b.can_collapse for b in base.system.buildings):
            raise StudyError(
                f"{source}: ida.hunt traces collapse, but no building can collapse (elastic "
                "stories without P-Δ); allowed: yielding stories or p_delta = true, or "
                "ida.hunt.limit_state = a story drift ratio (e.g. 0.05)"
            )
    if scaling == "set":
        usable = [r for r in study.axes["record"] if r.motion is not None]
        if len(usable) < 2:
            raise StudyError(
                f'{source}: scaling = "set" normalises a set of records; {len(usable)} readable '
                "record(s) given, allowed: 2 or more"
            )
        flat = [r.name for r in usable if not np.max(np.abs(r.motion.acceleration)) > 0]
        if flat:
            raise StudyError(f"{source}: record {flat[0]!r} is all zeros: it cannot be scaled")
    return study


#: Keys of an ``[ida]`` table beside the study's axes and options.
IDA_KEYS = ("im", "levels", "records", "hunt")


def _limit_states(value: Any, source: str) -> tuple[str | float, ...]:
    """``limit_states = ["collapse", 0.005, 0.015]``: collapse or story drift ratios."""
    values = value if isinstance(value, list) else [value]
    for v in values:
        if not is_limit_state(v):
            raise StudyError(
                f'{source}: limit_states value {v!r}; allowed: "collapse", "pounding" or a story drift '
                "ratio > 0 (e.g. 0.015 for 1.5 %)"
            )
    if not values:
        raise StudyError(f'{source}: limit_states is empty; allowed: a list such as ["collapse"]')
    return tuple(values)


def _ida_as_study(ida: Any, source: str) -> dict[str, Any]:
    """``[ida]`` (im, levels [g], records, the variants as study axes) as a ``[study]`` table with
    the ``im_level`` and ``record`` axes."""
    if not isinstance(ida, Mapping):
        raise StudyError(f"{source}: [ida] must be a table (im, levels, records, variants)")
    for key in ("levels", "records"):
        if key not in ida:
            raise StudyError(
                f"{source}: ida.{key} is missing; [ida] needs im (default sa), levels (target "
                "intensities [g]) and records (a suite or a list of references)"
            )
    spec = {k: v for k, v in ida.items() if k not in IDA_KEYS}
    spec["im"] = ida.get("im", "sa")
    if ida["levels"] == "hunt":
        spec["hunt"] = ida.get("hunt", {})
    elif "hunt" in ida:
        raise StudyError(
            f'{source}: ida.hunt sets the hunt-and-fill schedule; give it with levels = "hunt" '
            "(or a list of levels [g] without ida.hunt)"
        )
    else:
        spec["im_level"] = ida["levels"]
    records = ida["records"]
    spec["record"] = [records] if isinstance(records, str) else records
    return spec


def _intensity_measure(value: Any, case: Case, source: str) -> IntensityMeasure:
    """``im = "sa"`` or ``im = { measure = "sa", building = "A" }``: Sa at the named building's T1
    (default: the longest T1 of the case's buildings); ``sa_avg`` from 0.2 to 3 times the
    buildings' T1 unless ``period_low``/``period_high`` are given."""
    table = {"measure": value} if isinstance(value, str) else value
    if not isinstance(table, Mapping) or "measure" not in table:
        raise StudyError(
            f"{source}: study.im = {value!r}; allowed: {', '.join(MEASURES)}, or a table "
            '{ measure = "sa", building = "A" } (keys: ' + ", ".join(IM_KEYS) + ")"
        )
    options = {k: v for k, v in table.items() if k != "measure"}
    unknown = sorted(set(options) - set(IM_KEYS))
    if unknown:
        raise StudyError(f"{source}: study.im.{unknown[0]}: unknown; allowed: {', '.join(IM_KEYS)}")
    buildings = case.system.buildings
    names = [b.name for b in buildings]
    name = options.pop("building", None)
    if name is not None and name not in names:
        raise StudyError(f"{source}: study.im.building = {name!r}; allowed: {', '.join(names)}")
    periods = [float(b.modal().periods[0]) for b in buildings if name is None or b.name == name]
    try:
        return IntensityMeasure.for_periods(str(table["measure"]), periods, **options)
    except PoundingInputError as exc:
        raise StudyError(f"{source}: study.im: {exc}") from None


def load_study(path: str | Path) -> Study:
    """Read a case file with a ``[study]`` table (its ``[ground_motion]`` may be omitted when the
    study sweeps ``record``)."""
    path = Path(path)
    return study_from_dict(read_case_file(path), base_dir=path.parent, source=str(path))


# --------------------------------------------------------------------------------------------------
# Combinations -> runs
# --------------------------------------------------------------------------------------------------


def _set_path(data: dict[str, Any], path: str, value: Any, where: str) -> None:
    """Set ``data[a][b]...`` by a dotted path; list items by their 0-based index."""
    parts = path.split(".")
    node: Any = data
    for depth, part in enumerate(parts):
        last = depth == len(parts) - 1
        here = ".".join(parts[: depth + 1])
        if isinstance(node, list):
            if not part.isdigit() or int(part) >= len(node):
                raise StudyError(
                    f"{where}: study axis {path!r}: {here!r} is not an item of a list of "
                    f"{len(node)} (indices start at 0)"
                )
            key: Any = int(part)
        elif isinstance(node, dict):
            if not last and part not in node:
                raise StudyError(
                    f"{where}: study axis {path!r}: the case has no {here!r}; "
                    f"keys there: {', '.join(map(str, node)) or 'none'}"
                )
            key = part
        else:
            raise StudyError(f"{where}: study axis {path!r}: {here!r} is not a table or a list")
        if last:
            node[key] = copy.deepcopy(value)
        else:
            node = node[key]


def _exponent(contact: Mapping[str, Any], law: Any) -> float:
    return 1.0 if not law.has_exponent else float(contact.get("n") or law.default_n)


def _apply_law(
    contact: dict[str, Any], law_name: str, params: Mapping[str, Any], k_swept: bool, where: str
) -> dict[str, Any]:
    old = get_contact_law(contact.get("law", "linear"))
    new = get_contact_law(law_name)
    c = {**contact, "law": new.name, **params}
    if not new.has_exponent:
        c.pop("n", None)
    elif not old.has_exponent and "n" not in params:
        c.pop("n", None)
    if "k" not in params and not k_swept and _exponent(contact, old) != _exponent(c, new):
        raise StudyError(
            f"{where}: study.law = {new.name!r}: its k is in N/m^{_exponent(c, new):g} but the "
            f"contact's k is for {old.name!r} (N/m^{_exponent(contact, old):g}); set "
            f"[study.law_params.{new.name}] k = ..."
        )
    return c


def _normalise_contact(c: dict[str, Any]) -> dict[str, Any]:
    """Drop the parameters the contact's law ignores, so such combinations share one run."""
    law = get_contact_law(c.get("law", "linear"))
    out = dict(c)
    if not law.has_damping:
        out.pop("e", None)
        out.pop("calibration", None)
    if not law.is_bilinear:
        out.pop("a", None)
        out.pop("delta_m", None)
    if not law.has_exponent:
        out.pop("n", None)
    keep = {*(_BUMPER_KEYS if law.is_bumper else ()), *(_FILLER_KEYS if law.is_filler else ())}
    for key in {*_BUMPER_KEYS, *_FILLER_KEYS} - keep:
        out.pop(key, None)
    return out


def _combination_data(study: Study, combo: Mapping[str, Any]) -> dict[str, Any]:
    """The case data of one combination (the record and scale are not part of it)."""
    data = copy.deepcopy(study.case.data)
    data.pop("study", None)
    where = study.source
    law = combo.get("law")
    contacts = [dict(c) for c in data.get("contact", [])]
    if law == NO_CONTACT:
        contacts = []
    else:
        if law is not None:
            contacts = [
                _apply_law(c, law, study.law_params.get(law, {}), "k" in combo, where)
                for c in contacts
            ]
        for key in ("gap", "e", "k"):
            if key in combo:
                for c in contacts:
                    c[key] = combo[key]
    data["contact"] = contacts
    for path, value in combo.items():
        if path in NAMED_AXES:
            continue
        if path.startswith("contact.") and law == NO_CONTACT:
            continue
        _set_path(data, path, value, where)
    data["contact"] = [_normalise_contact(c) for c in data["contact"]]
    if not data["contact"]:
        data.pop("contact")
    if not study.motion_from_case:
        data["ground_motion"] = dict(_PLACEHOLDER_MOTION)
    return data


def _fingerprint(gm: GroundMotion | None) -> str:
    if gm is None:
        return "case"
    h = hashlib.sha256(np.ascontiguousarray(gm.acceleration, dtype=float).tobytes())
    h.update(repr((gm.dt, gm.name)).encode())
    return h.hexdigest()


def run_key(data: Mapping[str, Any], record: Record, scale: float | None) -> str:
    """Hash of everything that defines a run: case data, record samples, scale, package version."""
    text = json.dumps(
        {
            "case": data,
            "record": _fingerprint(record.motion) if record.motion is not None else record.error,
            "scale": scale,
            "version": __version__,
        },
        sort_keys=True,
        default=str,
    )
    return hashlib.sha256(text.encode()).hexdigest()[:20]


def _label(combo: Mapping[str, Any]) -> str:
    parts = []
    for name, value in combo.items():
        value = value.name if isinstance(value, Record) else value
        parts.append(f"{name}={value!r}" if isinstance(value, str) else f"{name}={value}")
    return ", ".join(parts)
