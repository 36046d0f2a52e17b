"""Case files: a TOML description of buildings, contacts, a ground motion and analysis options.

Units are SI unless a key says otherwise (``units`` of a ground motion). Every error names the file, the
key and the allowed values, and is raised before anything is integrated. See README.md for the format.
"""

from __future__ import annotations

import copy
import dataclasses
import tomllib
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from pounding import records
from pounding.contact.calibrate import CALIBRATIONS
from pounding.errors import PoundingInputError
from pounding.ground_motion import ANALYTIC_MOTIONS, GroundMotion, analytic
from pounding.simulate import ANALYSIS_KEYS, OUTPUT_KEYS, AnalysisOptions
from pounding.soil import SoilFoundation
from pounding.stories import STORY_MODELS, Stories
from pounding.structure import IsolationBase, ModalDamping, RayleighDamping, ShearBuilding
from pounding.system import Contact, Link, PoundingSystem, assemble
from pounding.units import acceleration_factor
from pounding.validation import Key, check_table, reference

#: Most floors a building may have (a model larger than this is a typing error, not a building).
MAX_FLOORS = 500
#: Shortest story height [m] of a case file: a shake-table model's; 1e-300 m overflowed the
#: stiffness of a column struck between floors.
MIN_STORY_HEIGHT = 0.01

_BUILDING_KEYS = (
    Key("name", "string", "building name (unique; used in contacts and results)", required=True),
    Key(
        "masses",
        "numbers",
        "floor masses, lowest floor first",
        unit="kg",
        low=1.0,
        high=1e12,
    ),
    Key(
        "stiffnesses",
        "numbers",
        "story stiffnesses, lowest story first",
        unit="N/m",
        low=0.0,
        high=1e15,
        open_low=True,
    ),
    Key(
        "heights",
        "numbers",
        "story heights (default 3 m each)",
        unit="m",
        low=MIN_STORY_HEIGHT,
        high=1000.0,
    ),
    Key(
        "damping",
        "any",
        "a table { ratio, modes } (Rayleigh, default 5 % at modes 1, 2) or { ratios } (modal)",
    ),
    Key("n_floors", "integer", "floors of a uniform building", low=1, high=MAX_FLOORS),
    Key(
        "period",
        "number",
        "fundamental period of a uniform building",
        unit="s",
        low=1e-3,
        high=100.0,
    ),
    Key(
        "mass",
        "number",
        "floor mass of a uniform building",
        unit="kg",
        low=1.0,
        high=1e12,
    ),
    Key(
        "height",
        "number",
        "story height of a uniform building (default 3)",
        unit="m",
        low=MIN_STORY_HEIGHT,
        high=1000.0,
    ),
    Key(
        "base", "any", "a table: isolation: { type, mass, friction, ... } (README, base isolation)"
    ),
    Key(
        "stories",
        "any",
        "a table: story model { model, yield_drift or yield_force, hardening, ... } "
        "(README, yielding stories)",
    ),
    Key("p_delta", "bool", "add the P-Δ geometric stiffness of the floors' gravity loads"),
    Key(
        "soil",
        "any",
        "a table: flexible base { shear_wave_velocity, density, poisson, radius or width and "
        "length, mass, ... } (README, soil flexibility)",
    ),
)
_SOIL_KEYS = (
    Key("shear_wave_velocity", "number", "shear-wave velocity V_s of the soil", unit="m/s",
        low=0.0, high=1e4, open_low=True, required=True),
    Key("density", "number", "soil mass density (typical 1600-2200)", unit="kg/m^3", low=0.0,
        high=1e4, open_low=True, required=True),
    Key("poisson", "number", "soil Poisson ratio", low=0.0, high=0.5, required=True),
    Key("radius", "number", "radius of a circular footing (or width and length)", unit="m",
        low=0.0, high=1e4, open_low=True),
    Key("width", "number", "footing plan across the row (with length)", unit="m", low=0.0,
        high=1e4, open_low=True),
    Key("length", "number", "footing plan along the row, the direction of shaking", unit="m",
        low=0.0, high=1e4, open_low=True),
    Key("mass", "number", "mass of the foundation slab", unit="kg", low=1.0, high=1e12,
        required=True),
    Key("inertia", "number", "rotational inertia of the foundation (default: a thin slab's)",
        unit="kg m^2", low=0.0, high=1e18, open_low=True),
    Key("dashpots", "bool", "radiation dashpots C_x, C_θ (default true)"),
)  # fmt: skip
_DAMPING_KEYS = (
    Key("ratio", "number", "Rayleigh damping ratio at both modes", low=0.0, high=1.0),
    Key("modes", "integers", "the two modes of the Rayleigh ratio", low=1, high=MAX_FLOORS),
    Key("ratios", "numbers", "modal damping ratio of each mode", low=0.0, high=1.0),
)
_CONTACT_KEYS = (
    Key("left", "string", "building on the left, or wall", required=True),
    Key("right", "string", "building on the right, or wall", required=True),
    Key("gap", "number", "clear distance at rest", unit="m", low=0.0, high=100.0, required=True),
    Key("law", "string", "contact law (pounding laws lists them; default linear)"),
    Key(
        "floors",
        "any",
        '"common", "all" (with a wall), "elevation" (slabs strike the neighbour\'s floors or '
        "columns) or a non-empty list of floors / [left, right] pairs",
    ),
    Key("k", "number", "contact stiffness", unit="N/m^n", low=0.0, high=1e15, open_low=True),
    Key(
        "e",
        "number",
        "coefficient of restitution (laws with damping)",
        low=0.01,
        high=1.0,
    ),
    Key(
        "n",
        "number",
        "exponent of the penetration (Hertz family, default 1.5)",
        low=0.0,
        high=10.0,
        open_low=True,
    ),
    Key(
        "a",
        "number",
        "bilinear yield fraction δ_y/δ_m (default 0.1)",
        low=0.0,
        high=1.0,
        open_low=True,
    ),
    Key(
        "delta_m",
        "number",
        "bilinear maximum penetration",
        unit="m",
        low=0.0,
        high=10.0,
        open_low=True,
    ),
    Key(
        "calibration",
        "string",
        "damping calibrated to e nominally or exactly",
        choices=CALIBRATIONS,
    ),
    Key(
        "thickness",
        "number",
        "bumper thickness on one face (law bumper; shortens the gap)",
        unit="m",
        low=0.0,
        high=10.0,
        open_low=True,
    ),
    Key(
        "k_rubber",
        "number",
        "Hertz stiffness of the bumper's rubber (law bumper)",
        unit="N/m^n",
        low=0.0,
        high=1e15,
        open_low=True,
    ),
    Key(
        "e_rubber",
        "number",
        "coefficient of restitution of the rubber (law bumper)",
        low=0.01,
        high=1.0,
    ),
    Key(
        "k_filler",
        "number",
        "stiffness of a viscoelastic filler filling the gap (law filler)",
        unit="N/m",
        low=0.0,
        high=1e15,
        open_low=True,
    ),
    Key(
        "c_filler",
        "number",
        "damping of the filler (law filler, default 0)",
        unit="N s/m",
        low=0.0,
        high=1e15,
    ),
    Key(
        "crush",
        "number",
        "fraction of the bumper (or filled gap) compressed when the structures meet (default 1)",
        low=0.0,
        high=1.0,
        open_low=True,
    ),
    Key(
        "column_share",
        "number",
        'share of a struck story\'s stiffness in the struck column line (floors = "elevation", '
        "default 1)",
        low=0.0,
        high=1.0,
        open_low=True,
    ),
    Key(
        "column_mass",
        "number",
        "mass of a struck column's impact node (default 2 % of the floor above)",
        unit="kg",
        low=1.0,
        high=1e12,
    ),
    Key(
        "column_capacity",
        "number",
        "shear capacity of a struck column's segments: a peak above it is flagged",
        unit="N",
        low=0.0,
        high=1e15,
        open_low=True,
    ),
    Key(
        "level_tolerance",
        "number",
        'distance within which a slab is level with a floor (floors = "elevation", default 0.1)',
        unit="m",
        low=0.0,
        high=100.0,
    ),
)
_ANALYTIC_KEYS = (
    Key("type", "string", "analytic motion", choices=tuple(ANALYTIC_MOTIONS), required=True),
    Key(
        "amplitude", "number", "peak ground acceleration, in the table's units", low=-1e4, high=1e4
    ),
    Key("units", "string", "unit of the amplitude (default g)"),
    Key("period", "number", "period of the pulse or harmonic", unit="s", low=1e-3, high=100.0),
    Key("duration", "number", "length of the motion", unit="s", low=0.0, high=1e4, open_low=True),
    Key("dt", "number", "sampling step", unit="s", low=1e-6, high=1.0),
    Key("cycles", "number", "number of cycles (harmonic)", low=0.0, high=1e4, open_low=True),
    Key("t0", "number", "start time of the pulse", unit="s", low=0.0, high=1e5),
    Key("scale", "number", "factor on the acceleration", low=0.0, high=100.0, open_low=True),
)
_RECORD_KEYS = (
    Key("file", "string", "record file (PEER AT2, COSMOS, K-NET, text), relative to the case file"),
    Key("record", "string", "record reference (pounding records list)"),
    Key("units", "string", "unit of a text file's values (g, m/s2, cm/s2, ...)"),
    Key("dt", "number", "sampling step of a one-column text file", unit="s", low=1e-6, high=1.0),
    Key("format", "string", "file format, when it cannot be recognised"),
    Key("scale", "number", "factor on the acceleration", low=0.0, high=100.0, open_low=True),
)
_LINK_KEYS = (
    Key("left", "string", "building on the left", required=True),
    Key("right", "string", "building on the right (the left one's neighbour)", required=True),
    Key("type", "string", "link law: kelvin (default), viscous or maxwell (pounding laws)"),
    Key("floors", "any", '"common" or a non-empty list of [left, right] floor pairs'),
    Key("k", "number", "spring stiffness (kelvin, maxwell)", unit="N/m", low=0.0, high=1e15),
    Key(
        "c",
        "number",
        "damping coefficient (kelvin, maxwell: N s/m; viscous: N (s/m)^alpha)",
        low=0.0,
        high=1e15,
    ),
    Key(
        "alpha",
        "number",
        "velocity exponent of a viscous damper (default 1)",
        low=0.0,
        high=2.0,
        open_low=True,
    ),  # fmt: skip
    Key(
        "v_lin",
        "number",
        "speed below which a viscous damper is linear (default 0.001)",
        unit="m/s",
        low=0.0,
        high=1.0,
        open_low=True,
    ),  # fmt: skip
)
_TOP_KEYS = (
    "title",
    "building",
    "contact",
    "link",
    "ground_motion",
    "analysis",
    "output",
    "study",
    "separation",
)
#: Every table of a case file with its keys (the reference in docs/case_file.md is generated from it).
CASE_SCHEMA = {
    "[[building]]": _BUILDING_KEYS,
    "[[building]] damping": _DAMPING_KEYS,
    "[[building]] soil": _SOIL_KEYS,
    "[[contact]]": _CONTACT_KEYS,
    "[[link]]": _LINK_KEYS,
    "[ground_motion] (analytic)": _ANALYTIC_KEYS,
    "[ground_motion] (record)": _RECORD_KEYS,
    "[analysis]": ANALYSIS_KEYS,
    "[output]": OUTPUT_KEYS,
}


def schema_key(path: str) -> Key | None:
    """The case-file key that a study's dotted path varies (``building.1.soil.shear_wave_velocity``
    is ``shear_wave_velocity`` of ``[[building]] soil``), or None when the path is not a key of
    :data:`CASE_SCHEMA` (an item of a list, a story model's parameter)."""
    parts = [p for p in path.split(".") if not p.isdigit()]
    if len(parts) == 3 and parts[0] == "building" and parts[1] in ("damping", "soil"):
        tables = [f"[[building]] {parts[1]}"]
    elif len(parts) == 2 and parts[0] in ("building", "contact", "link"):
        tables = [f"[[{parts[0]}]]"]
    elif len(parts) == 2 and parts[0] in ("analysis", "output"):
        tables = [f"[{parts[0]}]"]
    elif len(parts) == 2 and parts[0] == "ground_motion":
        tables = ["[ground_motion] (record)", "[ground_motion] (analytic)"]
    else:
        return None
    for table in tables:
        for key in CASE_SCHEMA[table]:
            if key.name == parts[-1]:
                return key
    return None


class CaseError(PoundingInputError):
    """A case file is malformed; the message names the file and the key."""


@dataclasses.dataclass(frozen=True, eq=False)
class Case:
    """A loaded case: the assembled system, the ground motion and the analysis options.

    ``data`` keeps the parsed TOML (after validation) so studies can vary any value by its dotted path.
    """

    title: str
    system: PoundingSystem
    ground_motion: GroundMotion
    analysis: AnalysisOptions
    data: dict[str, Any]
    path: Path | None = None
    output: Mapping[str, Any] = dataclasses.field(default_factory=dict)

    @property
    def buildings(self) -> tuple[ShearBuilding, ...]:
        return self.system.buildings

    @property
    def contacts(self) -> tuple[Contact, ...]:
        return self.system.contacts


def _checked(table: Any, keys: tuple[Key, ...], where: str) -> dict[str, Any]:
    """:func:`pounding.validation.check_table` raising :class:`CaseError` (its message as is)."""
    try:
        return check_table(table, keys, where)
    except PoundingInputError as exc:
        raise CaseError(str(exc)) from None


def _check_keys(table: Mapping[str, Any], allowed: tuple[str, ...], where: str) -> None:
    unknown = sorted(set(table) - set(allowed))
    if unknown:
        raise CaseError(
            f"{where}: unknown key(s) {', '.join(unknown)}; allowed: {', '.join(allowed)}"
        )


def _damping(spec: Any, where: str) -> RayleighDamping | ModalDamping:
    if spec is None:
        return RayleighDamping()
    if not isinstance(spec, Mapping):
        raise CaseError(f"{where}.damping must be a table, e.g. {{ ratio = 0.05, modes = [1, 2] }}")
    spec = _checked(spec, _DAMPING_KEYS, f"{where}.damping")
    if "ratios" in spec:
        if "ratio" in spec or "modes" in spec:
            raise CaseError(
                f"{where}.damping: give either ratios (modal) or ratio/modes (Rayleigh)"
            )
        return ModalDamping(ratios=tuple(spec["ratios"]))
    return RayleighDamping(ratio=spec.get("ratio", 0.05), modes=tuple(spec.get("modes", (1, 2))))


def _base(spec: Any, where: str) -> IsolationBase | None:
    """The ``base = { type = ..., mass = ..., friction = ..., ... }`` table of a building."""
    if spec is None:
        return None
    if not isinstance(spec, Mapping):
        raise CaseError(
            f'{where}.base must be a table, e.g. {{ type = "friction_pendulum", radius = 2.2, '
            f'friction = "coulomb", mu_s = 0.06, mu_d = 0.05, mass = 5e5 }}'
        )
    if "mass" not in spec:
        raise CaseError(f"{where}.base.mass [kg] (mass of the base slab) is required")
    try:
        return IsolationBase(**dict(spec))
    except (ValueError, TypeError) as exc:
        message = str(exc).removeprefix("base: ")
        raise CaseError(f"{where}.base: {message}") from None


def _soil(spec: Any, where: str) -> SoilFoundation | None:
    """The ``soil = { shear_wave_velocity = ..., density = ..., ... }`` table of a building."""
    if spec is None:
        return None
    example = (
        "{ shear_wave_velocity = 150, density = 1800, poisson = 0.35, width = 20, length = 20, "
        "mass = 8e5 }"
    )
    if not isinstance(spec, Mapping):
        raise CaseError(f"{where}.soil must be a table, e.g. {example}")
    table = _checked(spec, _SOIL_KEYS, f"{where}.soil")
    try:
        return SoilFoundation(**table)
    except PoundingInputError as exc:
        raise CaseError(f"{where}.{exc}") from None


def _stories(spec: Any, where: str) -> Stories:
    """The ``stories = { model = "bilinear", yield_drift = 0.005, hardening = 0.03 }`` table."""
    if spec is None:
        return Stories()
    if not isinstance(spec, Mapping):
        raise CaseError(
            f'{where}.stories must be a table, e.g. {{ model = "bilinear", yield_drift = 0.005, '
            "hardening = 0.03 }"
        )
    table = dict(spec)
    model = table.pop("model", None)
    if model is None:
        raise CaseError(f"{where}.stories.model is required; allowed: {', '.join(STORY_MODELS)}")
    try:
        return Stories(str(model), table)
    except PoundingInputError as exc:
        raise CaseError(f"{where}.{exc}") from None


def _building(spec: Mapping[str, Any], where: str) -> ShearBuilding:
    spec = _checked(spec, _BUILDING_KEYS, where)
    damping = _damping(spec.get("damping"), where)
    base = _base(spec.get("base"), where)
    soil = _soil(spec.get("soil"), where)
    stories = _stories(spec.get("stories"), where)
    uniform = [k for k in ("n_floors", "period", "mass") if k in spec]
    if uniform:
        missing = [k for k in ("n_floors", "period", "mass") if k not in spec]
        if missing or any(k in spec for k in ("masses", "stiffnesses", "heights")):
            raise CaseError(
                f"{where}: a uniform building takes n_floors, period [s] and mass [kg] together, "
                "and height [m] (instead of masses, stiffnesses and heights)"
            )
        return ShearBuilding.uniform(
            spec["name"],
            spec["n_floors"],
            period=spec["period"],
            mass=spec["mass"],
            height=spec.get("height", 3.0),
            damping=damping,
            base=base,
            stories=stories,
            p_delta=spec.get("p_delta", False),
            soil=soil,
        )
    for key in ("masses", "stiffnesses"):
        if key not in spec:
            raise CaseError(
                f"{where}.{key} is required (or n_floors, period and mass for a uniform building)"
            )
    if len(spec["masses"]) > MAX_FLOORS:
        raise CaseError(
            f"{where}.masses: {len(spec['masses'])} floors; allowed: at most {MAX_FLOORS}"
        )
    return ShearBuilding(
        name=str(spec["name"]),
        masses=spec["masses"],
        stiffnesses=spec["stiffnesses"],
        heights=spec.get("heights"),
        damping=damping,
        base=base,
        stories=stories,
        p_delta=spec.get("p_delta", False),
        soil=soil,
    )


def _contact(spec: Mapping[str, Any], where: str) -> Contact:
    spec = _checked(spec, _CONTACT_KEYS, where)
    floors = spec.get("floors", "common")
    if not _floors_ok(floors):
        raise CaseError(
            f'{where}.floors = {floors!r}; allowed: "common", "all" (with a wall), "elevation", a '
            "non-empty list of floor numbers (with a wall) or of [left_floor, right_floor] pairs"
        )
    return Contact(**spec)


def _each(specs: list[Mapping[str, Any]], table: str, build: Any) -> list[Any]:
    """``build(spec, "table[i]")`` of every table of an array; errors name the table and index."""
    out = []
    for i, spec in enumerate(specs):
        try:
            out.append(build(spec, f"{table}[{i}]"))
        except CaseError:
            raise
        except (ValueError, TypeError) as exc:
            raise CaseError(f"{table}[{i}]: {exc}") from None
    return out


def _link(spec: Mapping[str, Any], where: str) -> Link:
    spec = _checked(spec, _LINK_KEYS, where)
    floors = spec.get("floors", "common")
    if floors != "common" and not (_floors_ok(floors) and all(isinstance(f, list) for f in floors)):
        raise CaseError(
            f'{where}.floors = {floors!r}; allowed: "common" or a non-empty list of '
            "[left_floor, right_floor] pairs"
        )
    return Link(**spec)


def _floors_ok(floors: Any) -> bool:
    """``floors`` is "common", "all" or a non-empty list of floor integers or integer pairs."""
    if isinstance(floors, str):
        return floors in ("common", "all", "elevation")
    if not isinstance(floors, list) or not floors:
        return False

    def integer(x: Any) -> bool:
        return isinstance(x, int) and not isinstance(x, bool) and 0 <= x <= MAX_FLOORS

    return all(
        integer(f) or (isinstance(f, list) and len(f) == 2 and all(integer(x) for x in f))
        for f in floors
    )


def _ground_motion(spec: Mapping[str, Any], base_dir: Path | None) -> GroundMotion:
    where = "ground_motion"
    if not isinstance(spec, Mapping):
        raise CaseError(f"{where} must be a table ([ground_motion])")
    if isinstance(spec.get("units"), str):
        try:
            acceleration_factor(spec["units"])
        except ValueError as exc:  # the message names the unit and the allowed ones, not the key
            raise CaseError(f"{where}.units = {spec['units']!r}: {exc}") from None
    if "type" in spec:
        if spec["type"] not in ANALYTIC_MOTIONS:
            raise CaseError(
                f"{where}.type = {spec['type']!r}; allowed: {', '.join(ANALYTIC_MOTIONS)} "
                "(or give file = ... / record = ... instead of type)"
            )
        spec = _checked(spec, _ANALYTIC_KEYS, where)
        params = {k: v for k, v in spec.items() if k not in ("type", "units", "scale")}
        if "amplitude" in params:
            params["amplitude"] = float(params["amplitude"]) * acceleration_factor(
                spec.get("units", "g")
            )
        gm = analytic(spec["type"], **params)
    elif "file" in spec or "record" in spec:
        spec = _checked(spec, _RECORD_KEYS, where)
        if "file" in spec and "record" in spec:
            raise CaseError(f"{where}: give file or record, not both")
        if "file" in spec:
            path = Path(spec["file"])
            if not path.is_absolute() and base_dir is not None:
                path = base_dir / path
            gm = records.read_record(
                path, format=spec.get("format"), units=spec.get("units"), dt=spec.get("dt")
            )
        else:
            found = records.resolve(str(spec["record"]), base_dir=base_dir)
            if len(found) != 1:
                raise CaseError(
                    f"{where}.record = {spec['record']!r} names {len(found)} records; a single analysis "
                    "takes one (use a [study] to run a suite)"
                )
            gm = found[0]
    else:
        raise CaseError(
            f"{where}: give type = {'|'.join(ANALYTIC_MOTIONS)} (analytic), file = PATH or record = REF"
        )
    scale = spec.get("scale")
    return gm if scale is None else gm.scaled(float(scale))


def case_from_dict(
    data: Mapping[str, Any], *, base_dir: Path | None = None, source: str = "case"
) -> Case:
    """Build a :class:`Case` from a parsed case mapping (what a TOML file holds)."""
    data = copy.deepcopy(dict(data))
    try:
        if "ida" in data:
            raise CaseError(
                "[ida] makes this an incremental dynamic analysis: run it with `pounding ida FILE` "
                "(`pounding run` takes one analysis, `pounding study` a [study])"
            )
        _check_keys(data, _TOP_KEYS, "top level")
        blds = data.get("building")
        if not blds or not isinstance(blds, list) or not all(isinstance(b, Mapping) for b in blds):
            raise CaseError(
                "at least one [[building]] table is required (building = an array of tables)"
            )
        cons = data.get("contact", [])
        if not isinstance(cons, list) or not all(isinstance(c, Mapping) for c in cons):
            raise CaseError(
                f"contact = {cons!r}; allowed: [[contact]] tables (an array of tables), or none"
            )
        if "title" in data and not isinstance(data["title"], str):
            raise CaseError(f"title = {data['title']!r}; allowed: a text")
        output = _checked(data.get("output", {}), OUTPUT_KEYS, "output")
        frs = output.get("floor_spectra")
        if frs is not None and not (
            frs in ("roof", "all")
            or (
                isinstance(frs, list)
                and frs
                and all(isinstance(f, int) and not isinstance(f, bool) and f >= 1 for f in frs)
            )
        ):
            raise CaseError(
                f'output.floor_spectra = {frs!r}; allowed: "roof", "all" or a non-empty list '
                "of floor numbers >= 1"
            )
        buildings = _each(blds, "building", _building)
        contacts = _each(cons, "contact", _contact)
        lks = data.get("link", [])
        if not isinstance(lks, list) or not all(isinstance(c, Mapping) for c in lks):
            raise CaseError(
                f"link = {lks!r}; allowed: [[link]] tables (an array of tables), or none"
            )
        links = _each(lks, "link", _link)
        try:
            system = assemble(buildings, contacts, links)
        except ValueError as exc:
            raise CaseError(str(exc)) from None
        if "ground_motion" not in data:
            if "study" in data:
                raise CaseError(
                    "a [ground_motion] table is required for one analysis; this file's [study] "
                    "gives the records: run it with `pounding study FILE`"
                )
            raise CaseError("a [ground_motion] table is required")
        try:
            ground = _ground_motion(data["ground_motion"], base_dir)
        except CaseError:
            raise
        except (ValueError, TypeError) as exc:
            raise CaseError(f"ground_motion: {exc}") from None
        try:
            analysis = AnalysisOptions.from_mapping(data.get("analysis", {}))
        except (ValueError, TypeError) as exc:
            raise CaseError(
                str(exc) if str(exc).startswith("analysis") else f"analysis: {exc}"
            ) from None
    except CaseError as exc:
        raise CaseError(f"{source}: {exc}") from None
    return Case(
        title=str(data.get("title", "")),
        system=system,
        ground_motion=ground,
        analysis=analysis,
        data=data,
        path=None,
        output=output,
    )


def case_file_reference() -> str:
    """The case-file reference (docs/case_file.md): every table's keys from :data:`CASE_SCHEMA`."""
    head = (
        "# Case-file reference\n\n"
        "Generated from `pounding.case.CASE_SCHEMA` (`pounding.case.case_file_reference()`): every key "
        "a case file takes, its type, range and unit, checked before anything is built. Units are SI "
        "unless a key says otherwise. A wrong type or a value out of range is one error line naming "
        "the key, the value and what is allowed. Tables: `title` (text), `[[building]]` (one or "
        "more), `[[contact]]` (none or more), `[ground_motion]` (analytic or a record), "
        "`[analysis]`, `[output]`, and `[study]`, `[ida]` / `[separation]` (README).\n\n"
    )
    return head + reference(CASE_SCHEMA)


def read_case_file(path: str | Path) -> dict[str, Any]:
    """The parsed TOML of a case file (no validation yet); errors name the file."""
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"no case file at {path}")
    try:
        with path.open("rb") as fh:
            return tomllib.load(fh)
    except tomllib.TOMLDecodeError as exc:
        raise CaseError(f"{path}: not valid TOML: {exc}") from None
    except UnicodeDecodeError as exc:
        raise CaseError(
            f"{path}: not UTF-8 text (byte 0x{exc.object[exc.start]:02x} at position {exc.start}); "
            "allowed: a UTF-8 TOML file"
        ) from None


def load_case(path: str | Path) -> Case:
    """Read and validate a TOML case file."""
    path = Path(path)
    data = read_case_file(path)
    case = case_from_dict(data, base_dir=path.parent, source=str(path))
    return dataclasses.replace(case, path=path)
