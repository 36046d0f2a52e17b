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
from pounding.errors import PoundingInputError
from pounding.ground_motion import ANALYTIC_MOTIONS, GroundMotion, analytic
from pounding.simulate import AnalysisOptions
from pounding.structure import IsolationBase, ModalDamping, RayleighDamping, ShearBuilding
from pounding.system import Contact, PoundingSystem, assemble
from pounding.units import acceleration_factor

_BUILDING_KEYS = (
    "name",
    "masses",
    "stiffnesses",
    "heights",
    "damping",
    "n_floors",
    "period",
    "mass",
    "height",
    "base",
)
_CONTACT_KEYS = tuple(f.name for f in dataclasses.fields(Contact))
_ANALYTIC_KEYS = ("type", "amplitude", "units", "period", "duration", "dt", "cycles", "t0", "scale")
_RECORD_KEYS = ("file", "record", "units", "dt", "format", "scale")
_TOP_KEYS = ("title", "building", "contact", "ground_motion", "analysis", "study", "separation")


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

    @property
    def buildings(self) -> tuple[ShearBuilding, ...]:
        return self.system.buildings

    @property
    def contacts(self) -> tuple[Contact, ...]:
        return self.system.contacts


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
    _check_keys(spec, ("ratio", "modes", "ratios"), f"{where}.damping")
    if "ratios" in spec:
        if "ratio" in spec or "modes" in spec:
            raise CaseError(
                f"{where}.damping: give either ratios (modal) or ratio/modes (Rayleigh)"
            )
        return ModalDamping(ratios=tuple(float(r) for r in spec["ratios"]))
    return RayleighDamping(
        ratio=float(spec.get("ratio", 0.05)), modes=tuple(int(m) for m in spec.get("modes", (1, 2)))
    )


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


def _building(spec: Mapping[str, Any], where: str) -> ShearBuilding:
    _check_keys(spec, _BUILDING_KEYS, where)
    if "name" not in spec:
        raise CaseError(f"{where}.name is required")
    damping = _damping(spec.get("damping"), where)
    base = _base(spec.get("base"), where)
    uniform = [k for k in ("n_floors", "period", "mass") if k in spec]
    if uniform:
        missing = [k for k in ("n_floors", "period", "mass") if k not in spec]
        if missing or "masses" in spec or "stiffnesses" in spec:
            raise CaseError(
                f"{where}: a uniform building takes n_floors, period [s] and mass [kg] together "
                "(instead of masses and stiffnesses)"
            )
        return ShearBuilding.uniform(
            str(spec["name"]),
            int(spec["n_floors"]),
            period=float(spec["period"]),
            mass=float(spec["mass"]),
            height=float(spec.get("height", 3.0)),
            damping=damping,
            base=base,
        )
    for key in ("masses", "stiffnesses"):
        if key not in spec:
            raise CaseError(
                f"{where}.{key} is required (or n_floors, period and mass for a uniform building)"
            )
    return ShearBuilding(
        name=str(spec["name"]),
        masses=spec["masses"],
        stiffnesses=spec["stiffnesses"],
        heights=spec.get("heights"),
        damping=damping,
        base=base,
    )


def _contact(spec: Mapping[str, Any], where: str) -> Contact:
    _check_keys(spec, _CONTACT_KEYS, where)
    for key in ("left", "right", "gap"):
        if key not in spec:
            raise CaseError(f"{where}.{key} is required")
    return Contact(**dict(spec))


def _ground_motion(spec: Mapping[str, Any], base_dir: Path | None) -> GroundMotion:
    where = "ground_motion"
    if "type" in spec:
        _check_keys(spec, _ANALYTIC_KEYS, where)
        kind = spec["type"]
        if kind not in ANALYTIC_MOTIONS:
            raise CaseError(
                f"{where}.type = {kind!r}; allowed: {', '.join(ANALYTIC_MOTIONS)} "
                "(or give file = ... / record = ... instead of type)"
            )
        params = {k: v for k, v in spec.items() if k not in ("type", "units", "scale")}
        if "amplitude" in params:
            params["amplitude"] = float(params["amplitude"]) * acceleration_factor(
                spec.get("units", "g")
            )
        gm = analytic(kind, **params)
    elif "file" in spec or "record" in spec:
        _check_keys(spec, _RECORD_KEYS, where)
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
        _check_keys(data, _TOP_KEYS, "top level")
        blds = data.get("building")
        if not blds or not isinstance(blds, list):
            raise CaseError("at least one [[building]] table is required")
        buildings = []
        for i, spec in enumerate(blds):
            try:
                buildings.append(_building(spec, f"building[{i}]"))
            except CaseError:
                raise
            except (ValueError, TypeError) as exc:
                raise CaseError(f"building[{i}]: {exc}") from None
        contacts = []
        for i, spec in enumerate(data.get("contact", [])):
            try:
                contacts.append(_contact(spec, f"contact[{i}]"))
            except CaseError:
                raise
            except (ValueError, TypeError) as exc:
                raise CaseError(f"contact[{i}]: {exc}") from None
        try:
            system = assemble(buildings, contacts)
        except ValueError as exc:
            raise CaseError(str(exc)) from None
        if "ground_motion" not in data:
            raise CaseError("a [ground_motion] table is required")
        try:
            ground = _ground_motion(data["ground_motion"], base_dir)
        except CaseError:
            raise
        except (ValueError, TypeError) as exc:
            raise CaseError(f"ground_motion: {exc}") from None
        try:
            analysis = AnalysisOptions.from_mapping(dict(data.get("analysis", {})))
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
    )


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


def load_case(path: str | Path) -> Case:
    """Read and validate a TOML case file."""
    path = Path(path)
    data = read_case_file(path)
    case = case_from_dict(data, base_dir=path.parent, source=str(path))
    return dataclasses.replace(case, path=path)
