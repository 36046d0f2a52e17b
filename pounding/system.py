r"""Assembly of buildings in a row and the gap elements between them: M, C, K, ι and the gap topology.

**The sign convention (defined here and nowhere else).** Degrees of freedom are floor displacements
relative to the ground, positive to the right. Buildings are listed left to right. A gap element joins a
point a on its left to a point b on its right with clear distance g >= 0 [m]:

.. math:: \delta = u_a - u_b - g, \qquad \dot\delta = \dot u_a - \dot u_b

so δ > 0 is penetration and δ̇ > 0 means approaching. A rigid wall is a point with u ≡ 0 (it moves with
the ground). The contact force F >= 0 pushes a to the left and b to the right; in the equations of motion

.. math:: M\ddot u + C\dot u + K u + B^T F(\delta, \dot\delta) = -M\iota\, a_g(t), \qquad \delta = B u - g

with B[c, a] = +1, B[c, b] = −1 (:data:`LEFT_SIGN`, :data:`RIGHT_SIGN`). The integrators only use the
arrays built here (``el_dof``, ``el_sign``, ``el_gap``); they never restate the convention.
Contacts carry no Rayleigh damping: C is the block diagonal of the buildings' own damping matrices.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from pounding.contact.calibrate import CALIBRATIONS, contact_parameters
from pounding.contact.laws import N_KERNEL_PARAMS, ContactLaw, get_contact_law
from pounding.structure import ShearBuilding

#: Sign of the left point's displacement in δ.
LEFT_SIGN = 1.0
#: Sign of the right point's displacement in δ.
RIGHT_SIGN = -1.0
#: Name that stands for a rigid wall in a contact definition.
WALL = "wall"
#: Floors whose elevations differ by less than this [m] are at a common level.
LEVEL_TOLERANCE = 1e-6


@dataclasses.dataclass(frozen=True)
class Contact:
    """A contact definition between two neighbours of the row, or a building and a wall.

    Parameters
    ----------
    left, right : str
        Building names, or ``"wall"`` for a rigid wall on that side.
    gap : float
        Clear distance at rest [m], >= 0.
    law : str
        Contact-law registry name (see :data:`pounding.contact.laws.CONTACT_LAWS`).
    floors : "common" or sequence
        Between buildings: ``"common"`` (every pair of floors at the same elevation) or explicit
        ``[(left_floor, right_floor), ...]`` pairs, 1-based, possibly at different heights. With a wall:
        ``"all"`` or a list of the building's floors.
    k, e, n, a, delta_m, calibration
        Law parameters, see :func:`pounding.contact.calibrate.contact_parameters`.
    """

    left: str
    right: str
    gap: float
    law: str = "linear"
    floors: str | Sequence[Any] = "common"
    k: float | None = None
    e: float | None = None
    n: float | None = None
    a: float = 0.1
    delta_m: float | None = None
    calibration: str = "nominal"

    def __post_init__(self) -> None:
        where = f"contact {self.left!r}-{self.right!r}"
        if self.left == WALL and self.right == WALL:
            raise ValueError(f"{where}: at least one side must be a building")
        gap = float(self.gap)
        if not (math.isfinite(gap) and gap >= 0.0):
            raise ValueError(f"{where}: gap = {self.gap}; allowed: a finite number >= 0 [m]")
        object.__setattr__(self, "gap", gap)
        try:
            law = get_contact_law(self.law)
        except ValueError as exc:
            raise ValueError(f"{where}: {exc}") from None
        object.__setattr__(self, "law", law.name)
        if self.k is None:
            raise ValueError(f"{where}: k (contact stiffness [N/m^n]) is required")
        if self.calibration not in CALIBRATIONS:
            raise ValueError(
                f"{where}: calibration = {self.calibration!r}; allowed: {', '.join(CALIBRATIONS)}"
            )


@dataclasses.dataclass(frozen=True, eq=False)
class GapElements:
    """Gap elements in the arrays the integrators use (one row per element, C in all).

    ``el_dof[c]`` = (dof of a, dof of b), −1 for a wall; ``el_sign[c]`` = (LEFT_SIGN, RIGHT_SIGN) where the
    side is a building and 0 for a wall; ``el_gap`` [m]; ``el_law`` kernel ids; ``el_params`` kernel
    parameters (C × 4); ``el_mass`` effective masses m̄ [kg]. Labels: ``left``/``right`` building names
    (or "wall"), ``left_floor``/``right_floor`` (0 for a wall), ``law`` registry names, ``group`` the index
    of the :class:`Contact` definition the element came from.
    """

    el_dof: np.ndarray
    el_sign: np.ndarray
    el_gap: np.ndarray
    el_law: np.ndarray
    el_params: np.ndarray
    el_mass: np.ndarray
    left: tuple[str, ...]
    right: tuple[str, ...]
    left_floor: np.ndarray
    right_floor: np.ndarray
    law: tuple[str, ...]
    group: np.ndarray

    def __len__(self) -> int:
        return int(self.el_gap.size)


@dataclasses.dataclass(frozen=True, eq=False)
class PoundingSystem:
    """Buildings in a row (left to right) with gap elements; the assembled linear matrices.

    Build it with :func:`assemble`.
    """

    buildings: tuple[ShearBuilding, ...]
    contacts: tuple[Contact, ...]
    elements: GapElements
    mass: np.ndarray
    damping: np.ndarray
    stiffness: np.ndarray
    influence: np.ndarray
    dof_offset: np.ndarray
    below: np.ndarray
    story_height: np.ndarray

    @property
    def n_dof(self) -> int:
        return int(self.mass.shape[0])

    @property
    def building_names(self) -> tuple[str, ...]:
        return tuple(b.name for b in self.buildings)

    def dof(self, building: int, floor: int) -> int:
        """Global dof of a building's floor (1-based floor)."""
        return int(self.dof_offset[building]) + floor - 1

    def penetration(self, u: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """δ [m] and δ̇ [m/s] of every gap element for displacements u and velocities v (..., n_dof)."""
        el = self.elements
        ua = np.where(el.el_dof[:, 0] >= 0, u[..., el.el_dof[:, 0]], 0.0)
        ub = np.where(el.el_dof[:, 1] >= 0, u[..., el.el_dof[:, 1]], 0.0)
        va = np.where(el.el_dof[:, 0] >= 0, v[..., el.el_dof[:, 0]], 0.0)
        vb = np.where(el.el_dof[:, 1] >= 0, v[..., el.el_dof[:, 1]], 0.0)
        s = el.el_sign
        return s[:, 0] * ua + s[:, 1] * ub - el.el_gap, s[:, 0] * va + s[:, 1] * vb

    def shortest_period(self) -> float:
        """Shortest natural period of any building [s] (contacts open)."""
        return min(float(b.modal().periods.min()) for b in self.buildings)


def _block_diag(blocks: Sequence[np.ndarray]) -> np.ndarray:
    n = sum(b.shape[0] for b in blocks)
    out = np.zeros((n, n))
    i = 0
    for b in blocks:
        m = b.shape[0]
        out[i : i + m, i : i + m] = b
        i += m
    return out


def _floor_pairs(
    contact: Contact, left: ShearBuilding | None, right: ShearBuilding | None
) -> list[tuple[int, int]]:
    """(left floor, right floor) pairs of a contact, 1-based, 0 on a wall side; validated."""
    where = f"contact {contact.left!r}-{contact.right!r}"
    floors = contact.floors
    if left is not None and right is not None:
        if isinstance(floors, str):
            if floors != "common":
                raise ValueError(
                    f"{where}: floors = {floors!r}; allowed: 'common' or a list of "
                    "[left_floor, right_floor] pairs"
                )
            pairs = [
                (i + 1, j + 1)
                for i, zi in enumerate(left.elevations)
                for j, zj in enumerate(right.elevations)
                if abs(zi - zj) < LEVEL_TOLERANCE
            ]
            if not pairs:
                raise ValueError(
                    f"{where}: the buildings have no floor at a common elevation; give explicit "
                    "floors = [[left_floor, right_floor], ...]"
                )
            return pairs
        pairs = []
        for item in floors:
            if not (isinstance(item, Sequence) and len(item) == 2):
                raise ValueError(
                    f"{where}: floors entry {item!r}; allowed: [left_floor, right_floor] pairs"
                )
            i, j = int(item[0]), int(item[1])
            for f, b in ((i, left), (j, right)):
                if not 1 <= f <= b.n_floors:
                    raise ValueError(
                        f"{where}: floor {f} of building {b.name!r}; allowed: 1..{b.n_floors}"
                    )
            pairs.append((i, j))
        return pairs
    building = left if left is not None else right
    if isinstance(floors, str):
        if floors not in ("all", "common"):
            raise ValueError(
                f"{where}: floors = {floors!r}; allowed with a wall: 'all' or a list of floors"
            )
        chosen = list(range(1, building.n_floors + 1))
    else:
        chosen = []
        for f in floors:
            f = int(f[0] if isinstance(f, Sequence) else f)
            if not 1 <= f <= building.n_floors:
                raise ValueError(
                    f"{where}: floor {f} of building {building.name!r}; allowed: 1..{building.n_floors}"
                )
            chosen.append(f)
    return [(f, 0) if left is not None else (0, f) for f in chosen]


def assemble(
    buildings: Sequence[ShearBuilding], contacts: Sequence[Contact] = ()
) -> PoundingSystem:
    """Assemble buildings (listed left to right) and contacts into a :class:`PoundingSystem`.

    Contacts may join only neighbours in the row (``left`` immediately left of ``right``) or a building
    and a wall on either side. Each contact expands into one gap element per floor pair, with the
    law's parameters computed for the effective mass m̄ = m_a m_b/(m_a + m_b) of the two floors (m_a for a
    wall).
    """
    buildings = tuple(buildings)
    if not buildings:
        raise ValueError("a system needs at least one building")
    names = [b.name for b in buildings]
    dupes = {n for n in names if names.count(n) > 1}
    if dupes:
        raise ValueError(f"building names must be unique; repeated: {', '.join(sorted(dupes))}")
    if WALL in names:
        raise ValueError(f"{WALL!r} is reserved for rigid walls and cannot name a building")
    index = {n: i for i, n in enumerate(names)}
    offsets = np.concatenate(([0], np.cumsum([b.n_floors for b in buildings])[:-1])).astype(
        np.int64
    )

    rows: list[dict[str, Any]] = []
    for g, contact in enumerate(contacts):
        where = f"contact {contact.left!r}-{contact.right!r}"
        for side in (contact.left, contact.right):
            if side != WALL and side not in index:
                raise ValueError(
                    f"{where}: unknown building {side!r}; allowed: {', '.join(names)} or {WALL!r}"
                )
        li = index.get(contact.left)
        ri = index.get(contact.right)
        if li is not None and ri is not None and ri != li + 1:
            raise ValueError(
                f"{where}: contacts join neighbours in the row (buildings are listed left to right: "
                f"{', '.join(names)}); {contact.left!r} is not immediately left of {contact.right!r}"
            )
        lb = buildings[li] if li is not None else None
        rb = buildings[ri] if ri is not None else None
        law: ContactLaw = get_contact_law(contact.law)
        for fl, fr in _floor_pairs(contact, lb, rb):
            ma = lb.masses[fl - 1] if lb is not None else math.inf
            mb = rb.masses[fr - 1] if rb is not None else math.inf
            m_eff = mb if math.isinf(ma) else ma if math.isinf(mb) else ma * mb / (ma + mb)
            try:
                params = contact_parameters(
                    law,
                    k=contact.k,
                    e=contact.e,
                    n=contact.n,
                    mass=m_eff,
                    a=contact.a,
                    delta_m=contact.delta_m,
                    calibration=contact.calibration,
                )
            except ValueError as exc:
                raise ValueError(f"{where}: {exc}") from None
            rows.append(
                dict(
                    dof=(
                        offsets[li] + fl - 1 if lb is not None else -1,
                        offsets[ri] + fr - 1 if rb is not None else -1,
                    ),
                    sign=(
                        LEFT_SIGN if lb is not None else 0.0,
                        RIGHT_SIGN if rb is not None else 0.0,
                    ),
                    gap=contact.gap,
                    law_id=law.kernel_id,
                    params=params,
                    mass=m_eff,
                    left=contact.left,
                    right=contact.right,
                    lf=fl,
                    rf=fr,
                    law=law.name,
                    group=g,
                )
            )

    n_el = len(rows)
    elements = GapElements(
        el_dof=np.array([r["dof"] for r in rows], dtype=np.int64).reshape(n_el, 2),
        el_sign=np.array([r["sign"] for r in rows], dtype=float).reshape(n_el, 2),
        el_gap=np.array([r["gap"] for r in rows], dtype=float),
        el_law=np.array([r["law_id"] for r in rows], dtype=np.int64),
        el_params=np.array([r["params"] for r in rows], dtype=float).reshape(n_el, N_KERNEL_PARAMS),
        el_mass=np.array([r["mass"] for r in rows], dtype=float),
        left=tuple(r["left"] for r in rows),
        right=tuple(r["right"] for r in rows),
        left_floor=np.array([r["lf"] for r in rows], dtype=np.int64),
        right_floor=np.array([r["rf"] for r in rows], dtype=np.int64),
        law=tuple(r["law"] for r in rows),
        group=np.array([r["group"] for r in rows], dtype=np.int64),
    )
    # dof of the floor below each floor (-1 for a first floor, whose story stands on the ground)
    below = np.concatenate(
        [
            np.concatenate(([-1], o + np.arange(b.n_floors - 1)))
            for b, o in zip(buildings, offsets, strict=True)
        ]
    ).astype(np.int64)
    return PoundingSystem(
        buildings=buildings,
        contacts=tuple(contacts),
        elements=elements,
        mass=_block_diag([b.mass_matrix() for b in buildings]),
        damping=_block_diag([b.damping_matrix() for b in buildings]),
        stiffness=_block_diag([b.stiffness_matrix() for b in buildings]),
        influence=np.ones(int(sum(b.n_floors for b in buildings))),
        dof_offset=offsets,
        below=below,
        story_height=np.concatenate([b.heights for b in buildings]),
    )
