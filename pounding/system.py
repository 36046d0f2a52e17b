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

**Base isolation.** A building on an :class:`~pounding.structure.IsolationBase` gets one more degree
of freedom, the base slab's displacement u_b relative to the ground, placed just before its floors
(so ``dof(building, 0)`` is the base and ``dof(building, floor)`` keeps its meaning). Floor
displacements stay relative to the ground; the superstructure's K and C act on the floor displacements
relative to the slab: with T mapping [u_b, u_1..u_n] to [u_1 − u_b, ..., u_n − u_b],

.. math:: K_{ext} = T^T K T + \frac{W}{R} e_b e_b^T, \qquad C_{ext} = T^T C T, \qquad
          M_{ext} = \mathrm{diag}(m_b, m_1, \dots, m_n)

(the W/R term for a friction pendulum only; W = g (m_b + Σ m_i)). The influence vector stays ones.
The friction force f of the bearings acts on the base dof, f with the sign of u̇_b (it resists the
sliding): :math:`M\ddot u + C\dot u + K u + B^T F + E f(\dot u_b) = -M\iota a_g` with E the
columns e_b (:class:`FrictionElements`). A contact may end at a base slab: floor 0 in a contact's
``floors`` (a moat wall, or an explicit pair between neighbours).

**Flexible base.** A building on a :class:`~pounding.soil.SoilFoundation` gets two more degrees of
freedom just before its floors, the foundation's sway u_0 (relative to the ground, the building's
``dof(building, 0)`` is not it: floor 0 stays the base slab of isolation) and its rocking θ [rad].
Floor displacements stay relative to the ground, x_i = u_0 + H_i θ + (story deformations), so the
contacts, links and the mass matrix are as on a fixed base; the superstructure's K and C act on the
story deformations x_i − x_(i−1) − h_i θ (x_0 = u_0): with T_e mapping [u_0, θ, x_1..x_n] to
[x_i − u_0 − H_i θ] and T_g to [x_i − u_0] (the total tilt, on which gravity acts),

.. math:: K_{ext} = T_e^T K T_e + T_g^T K_G T_g + K_x e_0 e_0^T + K_\theta e_\theta e_\theta^T,
          \qquad C_{ext} = T_e^T C T_e + C_x e_0 e_0^T + C_\theta e_\theta e_\theta^T,
          \qquad M_{ext} = \mathrm{diag}(m_0, I_0, m_1, \dots, m_n)

(K_G: the P-Δ geometric stiffness with ``p_delta``, which then also reduces the rocking stiffness by
Σ m_i g H_i). ι is 1 on u_0 and the floors, 0 on θ. The story drift of floor i is
x_i − x_(i−1) − h_i θ: ``below`` and ``tilt``/``tilt_height`` (:meth:`PoundingSystem.drift`).

**Floor-to-column impacts.** A contact with ``floors = "elevation"`` lets a floor slab strike the
neighbour's column between its floors (:func:`_elevation_pairs`). The struck story j gets a node at
the impact point, at ξ = a/h_j above its lower floor (η = 1 − ξ), a degree of freedom after the
building's floors (:class:`ColumnNodes`). Only the struck column line, a share k_c = s k_j of the
story's stiffness, is split (the hit column of Karayannis & Favvata 2005, Earthquake Eng. Struct.
Dyn. 34(1), 1-20, in the shear idealisation of a column between rigid floors): k_j − k_c stays
floor to floor, k_c/ξ joins the lower floor to the node and k_c/η the node to the upper floor, in
series k_c, so the story's lateral stiffness is unchanged while nothing strikes it (the node's static condensation gives back K). With the floors
held, a force F at the node meets the local stiffness k_c/(ξη) and reactions ηF below, ξF above.
The node carries a share of the column's mass (``column_mass``) and, with Rayleigh damping, the
same a0 m + a1 k damping as the rest of the building. A yielding story yields on its chord drift
(floor to floor) as without the node, and the struck column carries its share s of that hysteretic
force: the column's local deformation between its floors stays elastic.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from pounding.contact.calibrate import CALIBRATIONS, contact_parameters
from pounding.contact.laws import N_KERNEL_PARAMS, ContactLaw, get_contact_law
from pounding.errors import PoundingInputError
from pounding.friction import BOUC_WEN_PARAMETERS, FRICTION_LAWS
from pounding.links import LINK_LAWS, N_LINK_PARAMS
from pounding.stories import N_STORY_PARAMS, STORY_MODELS
from pounding.structure import ShearBuilding

#: Sign of the left point's displacement in δ.
LEFT_SIGN = 1.0
#: Sign of the right point's displacement in δ.
RIGHT_SIGN = -1.0
#: Name that stands for a rigid wall in a contact definition.
WALL = "wall"
#: Floors whose elevations differ by less than this [m] are at a common level.
LEVEL_TOLERANCE = 1e-6
#: Floor number that stands for an isolated building's base slab in a contact definition.
BASE_FLOOR = 0
#: ``floors`` of a contact that pairs the slabs with the neighbour's floors or columns by elevation.
ELEVATION = "elevation"
#: Default distance [m] within which a slab is level with a floor (``level_tolerance``).
LEVEL_TOLERANCE_DEFAULT = 0.1
#: Default mass of a column's impact node, as a fraction of the floor above the struck story.
COLUMN_MASS_FRACTION = 0.02

#: How the integrators treat a friction element (``fr_kind``): a regularised law f(v) from its
#: kernel, exact Coulomb stick-slip, or a law with a Bouc-Wen variable z.
FRICTION_REGULARISED, FRICTION_COULOMB, FRICTION_BOUC_WEN = 0, 1, 2
#: Width of the friction parameter rows (the longest law's parameter array).
N_FRICTION_PARAMS = max(len(law.parameters) for law in FRICTION_LAWS.values())


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
        ``"all"`` or a list of the building's floors. Floor 0 (:data:`BASE_FLOOR`) is the base slab
        of an isolated building, in explicit pairs and wall lists (``"common"`` and ``"all"`` take
        floors only): ``floors = [0]`` with a wall is a moat wall.
    k, e, n, a, delta_m, calibration
        Law parameters, see :func:`pounding.contact.calibrate.contact_parameters`.
    thickness, k_rubber, e_rubber, crush
        The rubber bumper of ``law = "bumper"``: thickness [m] (on one face; it shortens the gap),
        Hertz stiffness [N/m^n] and restitution of the rubber, and the fraction of the thickness
        compressed when the structures meet through the crushed layer (default 1: all of it).
    k_filler, c_filler
        The viscoelastic filler of ``law = "filler"``, filling the whole gap: stiffness [N/m] and
        damping [N s/m] (``crush``: the fraction of the gap compressed when the structures meet).
    column_share, column_mass, column_capacity, level_tolerance
        With ``floors = "elevation"`` (module docstring, floor-to-column impacts): the share
        k_c/k (0 < s ≤ 1, default 1) of a struck story's stiffness in the struck column line, the
        mass of its impact node [kg] (default 2 % of the floor above), the column segments' shear
        capacity [N] (a peak above it is flagged; default none), and the distance [m] within which
        a slab counts as level with a floor (default 0.1).
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
    thickness: float | None = None
    k_rubber: float | None = None
    e_rubber: float | None = None
    crush: float = 1.0
    k_filler: float | None = None
    c_filler: float | None = None
    column_share: float | None = None
    column_mass: float | None = None
    column_capacity: float | None = None
    level_tolerance: float | None = None

    @property
    def filler(self) -> tuple[float, float, float] | None:
        """(k_filler, c_filler, compression at which the structures meet) of a filler, else None."""
        if not get_contact_law(self.law).is_filler:
            return None
        return (self.k_filler, self.c_filler or 0.0, self.crush * self.gap)  # type: ignore[return-value]

    @property
    def bumper(self) -> tuple[float, float, float, float] | None:
        """(thickness, k_rubber, e_rubber, crush) of a bumper, None for other laws."""
        if not get_contact_law(self.law).is_bumper:
            return None
        return (self.thickness, self.k_rubber, self.e_rubber, self.crush)  # type: ignore[return-value]

    @property
    def slab_tolerance(self) -> float:
        """Distance [m] within which a slab is level with a floor (``level_tolerance`` or 0.1)."""
        return LEVEL_TOLERANCE_DEFAULT if self.level_tolerance is None else self.level_tolerance

    @property
    def element_gap(self) -> float:
        """The gap [m] the elements close before any force acts: the clear gap less a bumper."""
        if self.filler is not None:
            return 0.0  # the filler touches both faces from the start
        return self.gap - (self.thickness or 0.0) if self.bumper is not None else self.gap

    def __post_init__(self) -> None:
        where = f"contact {self.left!r}-{self.right!r}"
        if self.left == WALL and self.right == WALL:
            raise PoundingInputError(f"{where}: at least one side must be a building")
        gap = float(self.gap)
        if not (math.isfinite(gap) and gap >= 0.0):
            raise PoundingInputError(
                f"{where}: gap = {self.gap}; allowed: a finite number >= 0 [m]"
            )
        object.__setattr__(self, "gap", gap)
        try:
            law = get_contact_law(self.law)
        except ValueError as exc:
            raise PoundingInputError(f"{where}: {exc}") from None
        object.__setattr__(self, "law", law.name)
        if self.k is None:
            raise PoundingInputError(f"{where}: k (contact stiffness [N/m^n]) is required")
        if self.calibration not in CALIBRATIONS:
            raise PoundingInputError(
                f"{where}: calibration = {self.calibration!r}; allowed: {', '.join(CALIBRATIONS)}"
            )
        keys = ("thickness", "k_rubber", "e_rubber")
        if law.is_bumper:
            missing = [key for key in keys if getattr(self, key) is None]
            if missing:
                raise PoundingInputError(
                    f"{where}: law 'bumper' needs {', '.join(missing)} (bumper thickness [m], "
                    "rubber Hertz stiffness [N/m^n], rubber restitution 0 < e <= 1)"
                )
            if not float(self.thickness) <= gap:  # type: ignore[arg-type]
                raise PoundingInputError(
                    f"{where}: thickness = {self.thickness} m is more than the gap = {gap} m; "
                    "allowed: a bumper no thicker than the gap"
                )
        elif law.is_filler:
            if self.k_filler is None:
                raise PoundingInputError(
                    f"{where}: law 'filler' needs k_filler (filler stiffness [N/m]; c_filler "
                    "[N s/m] optional)"
                )
            if not gap > 0.0:
                raise PoundingInputError(f"{where}: law 'filler' fills a gap: allowed gap > 0 [m]")
            given = [key for key in keys if getattr(self, key) is not None]
            if given:
                raise PoundingInputError(
                    f"{where}: {', '.join(given)} belong to law 'bumper' (law is 'filler')"
                )
        else:
            given = [key for key in (*keys, "crush") if getattr(self, key) not in (None, 1.0)]
            if given:
                raise PoundingInputError(
                    f"{where}: {', '.join(given)} belong to law 'bumper' (law is {law.name!r})"
                )
        if not law.is_filler:
            given = [key for key in ("k_filler", "c_filler") if getattr(self, key) is not None]
            if given:
                raise PoundingInputError(
                    f"{where}: {', '.join(given)} belong to law 'filler' (law is {law.name!r})"
                )
        column_keys = ("column_share", "column_mass", "column_capacity", "level_tolerance")
        if self.floors != ELEVATION:
            given = [key for key in column_keys if getattr(self, key) is not None]
            if given:
                raise PoundingInputError(
                    f"{where}: {', '.join(given)} apply to floor-to-column impacts, floors = "
                    f"'elevation' (floors is {self.floors!r})"
                )
            return
        # a column node lighter than a floor may be (1 kg) gave an overflowing frequency
        for key, unit, allowed, ok in (
            ("column_share", "", "0 < column_share <= 1", lambda v: 0.0 < v <= 1.0),
            ("column_mass", " [kg]", "1 <= column_mass <= 1e12", lambda v: 1.0 <= v <= 1e12),
            ("column_capacity", " [N]", "a positive number", lambda v: v > 0.0),
        ):
            value = getattr(self, key)
            if value is not None and not ok(float(value)):
                raise PoundingInputError(f"{where}: {key} = {value!r}{unit}; allowed: {allowed}")
        tol = self.level_tolerance
        if tol is not None and not (math.isfinite(float(tol)) and float(tol) >= 0.0):
            raise PoundingInputError(
                f"{where}: level_tolerance = {tol!r} [m]; allowed: a finite number >= 0"
            )


@dataclasses.dataclass(frozen=True)
class Link:
    """A coupling link between facing floors of two neighbours of the row (:mod:`pounding.links`).

    Parameters
    ----------
    left, right : str
        Building names (``left`` immediately left of ``right``).
    type : str
        Link law (:data:`pounding.links.LINK_LAWS`): ``kelvin``, ``viscous`` or ``maxwell``.
    floors : "common" or sequence
        As for :class:`Contact`: every pair of floors at the same elevation, or explicit
        ``[(left_floor, right_floor), ...]`` pairs.
    k, c, alpha, v_lin
        Law parameters: stiffness [N/m], damping coefficient [N s/m, or N (s/m)^α for the fluid
        viscous damper], velocity exponent α [-], linear range of the damper [m/s].
    """

    left: str
    right: str
    type: str = "kelvin"
    floors: str | Sequence[Any] = "common"
    k: float | None = None
    c: float | None = None
    alpha: float | None = None
    v_lin: float | None = None

    def parameters(self, where: str) -> list[float]:
        """The law's parameter row (:data:`pounding.links.N_LINK_PARAMS` long), validated."""
        law = LINK_LAWS.get(self.type)
        if law is None:
            raise PoundingInputError(
                f"{where}: type = {self.type!r}; allowed: {', '.join(LINK_LAWS)}"
            )
        row = []
        for key, unit, default in law.parameters:
            value = getattr(self, key)
            if value is None:
                if default is None:
                    raise PoundingInputError(f"{where}: {key} [{unit}] is required by {law.name!r}")
                value = default
            value = float(value)
            low_ok = value > 0.0 if key in ("alpha", "v_lin") else value >= 0.0
            if not (math.isfinite(value) and low_ok):
                raise PoundingInputError(
                    f"{where}: {key} = {value!r}; allowed: a finite number "
                    f"{'> 0' if key in ('alpha', 'v_lin') else '>= 0'} [{unit}]"
                )
            row.append(value)
        if law.name == "kelvin" and row[0] == 0.0 and row[1] == 0.0:
            raise PoundingInputError(f"{where}: a kelvin link needs k > 0 or c > 0")
        if law.name == "maxwell" and (row[0] == 0.0 or row[1] == 0.0):
            raise PoundingInputError(f"{where}: a maxwell link needs k > 0 and c > 0")
        extra = sorted(
            key
            for key in ("k", "c", "alpha", "v_lin")
            if getattr(self, key) is not None and key not in {p[0] for p in law.parameters}
        )
        if extra:
            raise PoundingInputError(
                f"{where}: {', '.join(extra)} not used by type = {law.name!r}; its parameters: "
                f"{', '.join(p[0] for p in law.parameters)}"
            )
        return row + [0.0] * (N_LINK_PARAMS - len(row))


@dataclasses.dataclass(frozen=True, eq=False)
class GapElements:
    """Gap elements in the arrays the integrators use (one row per element, C in all).

    ``el_dof[c]`` = (dof of a, dof of b), −1 for a wall; ``el_sign[c]`` = (LEFT_SIGN, RIGHT_SIGN) where the
    side is a building and 0 for a wall; ``el_gap`` [m]; ``el_law`` kernel ids; ``el_params`` kernel
    parameters (C × N_KERNEL_PARAMS); ``el_mass`` effective masses m̄ [kg]. Labels: ``left``/``right`` building names
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
    #: per element, the struck column (index into :class:`ColumnNodes`) on each side, −1 for a floor
    left_column: np.ndarray | None = None
    right_column: np.ndarray | None = None

    def __post_init__(self) -> None:
        for name in ("left_column", "right_column"):
            if getattr(self, name) is None:
                object.__setattr__(self, name, np.full(self.el_gap.size, -1, dtype=np.int64))

    def __len__(self) -> int:
        return int(self.el_gap.size)


@dataclasses.dataclass(frozen=True, eq=False)
class ColumnNodes:
    """The impact nodes of struck columns (module docstring, floor-to-column impacts), one row per
    node: ``dof``; ``building`` index, ``story`` number (1 = lowest), ``xi`` = a/h of the impact
    point, its ``elevation`` [m]; the segment stiffnesses ``k_below`` = k_c/ξ and ``k_above`` =
    k_c/η [N/m] (k_c = ``share`` × story stiffness), the node ``mass`` [kg], the shear
    ``capacity`` [N] (NaN: none given) and the ``group`` of the contact that placed it."""

    dof: np.ndarray
    building: np.ndarray
    story: np.ndarray
    xi: np.ndarray
    elevation: np.ndarray
    share: np.ndarray
    k_below: np.ndarray
    k_above: np.ndarray
    mass: np.ndarray
    capacity: np.ndarray
    group: np.ndarray

    def __len__(self) -> int:
        return int(self.dof.size)

    @classmethod
    def empty(cls) -> ColumnNodes:
        z = np.zeros(0)
        i = np.zeros(0, np.int64)
        return cls(i, i.copy(), i.copy(), z, z.copy(), z.copy(), z.copy(), z.copy(), z.copy(),
                   z.copy(), i.copy())  # fmt: skip


@dataclasses.dataclass(frozen=True, eq=False)
class FrictionElements:
    """The sliding bearings of the isolated buildings, one row per isolated building (F in all).

    ``fr_dof`` the base dof; ``fr_kind`` :data:`FRICTION_REGULARISED`, :data:`FRICTION_COULOMB` or
    :data:`FRICTION_BOUC_WEN`; ``fr_law`` friction kernel ids (:data:`pounding.friction.LAWS_BY_ID`);
    ``fr_params`` law parameters (F × :data:`N_FRICTION_PARAMS`, registry order, zero padded);
    ``fr_bouc_wen`` Bouc-Wen parameters (F × 5, zeros unless hysteretic); ``fr_normal`` the normal
    force N = W [N]; ``fr_mass`` the base slab mass [kg]. Labels: ``building`` (index in the row),
    ``law`` registry names.
    """

    fr_dof: np.ndarray
    fr_kind: np.ndarray
    fr_law: np.ndarray
    fr_params: np.ndarray
    fr_bouc_wen: np.ndarray
    fr_normal: np.ndarray
    fr_mass: np.ndarray
    building: np.ndarray
    law: tuple[str, ...]

    def __len__(self) -> int:
        return int(self.fr_dof.size)


@dataclasses.dataclass(frozen=True, eq=False)
class LinkElements:
    """Coupling links (:mod:`pounding.links`) in the arrays the integrators use, one row per linked
    floor pair (L in all).

    ``dof``/``sign`` as :class:`GapElements` (δ = s_a u_a + s_b u_b, positive as the floors
    approach); ``law_id`` link kernel ids; ``params`` (L × :data:`pounding.links.N_LINK_PARAMS`).
    Labels: ``left``/``right`` building names, ``left_floor``/``right_floor``, ``law`` registry
    names, ``group`` the index of the :class:`Link` definition the row came from.
    """

    dof: np.ndarray
    sign: np.ndarray
    law_id: np.ndarray
    params: np.ndarray
    left: tuple[str, ...] = ()
    right: tuple[str, ...] = ()
    left_floor: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros(0, np.int64))
    right_floor: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros(0, np.int64))
    law: tuple[str, ...] = ()
    group: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros(0, np.int64))

    def __len__(self) -> int:
        return int(self.law_id.size)

    @classmethod
    def empty(cls) -> LinkElements:
        return cls(
            dof=np.zeros((0, 2), np.int64),
            sign=np.zeros((0, 2)),
            law_id=np.zeros(0, np.int64),
            params=np.zeros((0, N_LINK_PARAMS)),
        )


@dataclasses.dataclass(frozen=True, eq=False)
class StoryElements:
    """Yielding stories (:mod:`pounding.stories`) in the arrays the integrators use, one row per
    story of every building with a hysteretic model (S in all).

    ``dof`` = (floor, the dof below: floor, base slab or −1 for the ground[, the rocking dof]),
    ``sign`` (+1, −1; 0 for the ground[, −h]) so that δ = u_floor − u_below [− h θ] is the drift (the
    third column only when a building with yielding stories rocks on soil); ``law_id`` story-model kernel ids;
    ``params`` (S × :data:`pounding.stories.N_STORY_PARAMS`: k, F_y, model parameters). Labels:
    ``building`` index, ``story`` number (1 = lowest), ``model`` registry names; ``ultimate`` the
    drift capacity δ_u [m] (NaN when not given) and ``park_ang_beta`` per row.
    """

    dof: np.ndarray
    sign: np.ndarray
    law_id: np.ndarray
    params: np.ndarray
    building: np.ndarray
    story: np.ndarray
    model: tuple[str, ...] = ()
    ultimate: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros(0))
    park_ang_beta: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros(0))

    def __len__(self) -> int:
        return int(self.law_id.size)

    @classmethod
    def empty(cls) -> StoryElements:
        z = np.zeros(0, np.int64)
        return cls(np.zeros((0, 2), np.int64), np.zeros((0, 2)), z, np.zeros((0, N_STORY_PARAMS)),
                   z.copy(), z.copy())  # fmt: skip


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
    base_dof: np.ndarray
    friction: FrictionElements
    links: LinkElements = dataclasses.field(default_factory=LinkElements.empty)
    link_specs: tuple[Link, ...] = ()
    stories: StoryElements = dataclasses.field(default_factory=StoryElements.empty)
    #: per building, the foundation's sway and rocking dofs (−1, −1 on a fixed or isolated base)
    soil_dof: np.ndarray | None = None
    #: per dof, the rocking dof that tilts its story (−1 if none) and the story height it tilts
    tilt: np.ndarray | None = None
    tilt_height: np.ndarray | None = None
    columns: ColumnNodes = dataclasses.field(default_factory=ColumnNodes.empty)

    def __post_init__(self) -> None:
        n, nb = self.n_dof, len(self.buildings)
        if self.soil_dof is None:
            object.__setattr__(self, "soil_dof", np.full((nb, 2), -1, dtype=np.int64))
        if self.tilt is None:
            object.__setattr__(self, "tilt", np.full(n, -1, dtype=np.int64))
        if self.tilt_height is None:
            object.__setattr__(self, "tilt_height", np.zeros(n))

    @property
    def n_dof(self) -> int:
        return int(self.mass.shape[0])

    @property
    def building_names(self) -> tuple[str, ...]:
        return tuple(b.name for b in self.buildings)

    @property
    def isolated(self) -> bool:
        """True when any building stands on isolation bearings."""
        return bool(np.any(self.base_dof >= 0))

    def dof(self, building: int, floor: int) -> int:
        """Global dof of a building's floor (1-based floor; 0 = the base slab of an isolated building).

        ``dof_offset[building]`` is the dof of floor 1; an isolated building's base dof precedes it.
        """
        if floor == BASE_FLOOR and self.base_dof[building] < 0:
            raise PoundingInputError(
                f"building {self.buildings[building].name!r} has no base slab (floor 0); it is "
                "fixed at the base"
            )
        return int(self.dof_offset[building]) + floor - 1

    @property
    def flexible_base(self) -> bool:
        """True when any building stands on soil (sway and rocking dofs)."""
        return bool(np.any(self.soil_dof >= 0))

    def drift(self, u: np.ndarray) -> np.ndarray:
        """Story deformation [m] at each dof for displacements u (..., n_dof): u_i − u_below, less
        h_i θ on a rocking foundation (rigid-body rotation deforms no story)."""
        below = np.where(self.below >= 0, u[..., np.maximum(self.below, 0)], 0.0)
        tilt = np.where(self.tilt >= 0, u[..., np.maximum(self.tilt, 0)], 0.0)
        return u - below - self.tilt_height * tilt

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
        """Shortest natural period of any building [s] (contacts open).

        An isolated building counts both with its bearings stuck (the fixed-base superstructure) and
        sliding (the free base slab on the superstructure, a shorter period when the slab is light);
        a building on soil with its foundation's sway and rocking, one with struck columns with
        their impact nodes.
        """
        return float(self.shortest_periods().min())

    def shortest_periods(self) -> np.ndarray:
        """Shortest natural period [s] of each building, as :meth:`shortest_period` counts it."""
        periods = np.array([float(b.modal().periods.min()) for b in self.buildings])
        for i, b in enumerate(self.buildings):
            if b.isolated or b.flexible_base or np.any(self.columns.building == i):
                periods[i] = min(periods[i], float(self.building_periods(i).min()))
        return periods

    def building_dofs(self, building: int) -> slice:
        """The consecutive dofs of a building: [base slab | sway, rocking] and its floors."""
        b = self.buildings[building]
        lo = (
            int(self.dof_offset[building])
            - (1 if b.isolated else 0)
            - (2 if b.flexible_base else 0)
        )
        nodes = int(np.count_nonzero(self.columns.building == building))
        return slice(lo, int(self.dof_offset[building]) + b.n_floors + nodes)

    def building_periods(self, building: int) -> np.ndarray:
        """Undamped periods [s] of a building with its base dofs (contacts and links open),
        longest first: on soil, the flexible-base periods; on isolation bearings, with the slab
        free (a flat slider's rigid-body mode is infinite)."""
        s_ = self.building_dofs(building)
        k = self.stiffness[s_, s_]
        s = 1.0 / np.sqrt(np.diag(self.mass)[s_])
        # M is diagonal: the eigenvalues of M^-1/2 K M^-1/2 (K may be singular on a flat slider)
        w2 = np.linalg.eigvalsh(s[:, None] * k * s[None, :])
        with np.errstate(divide="ignore"):
            return 2.0 * math.pi / np.sqrt(np.maximum(w2, 0.0))


def _block_diag(blocks: Sequence[np.ndarray]) -> np.ndarray:
    n = sum(b.shape[0] for b in blocks)
    out = np.zeros((n, n))
    i = 0
    for b in blocks:
        m = b.shape[0]
        out[i : i + m, i : i + m] = b
        i += m
    return out


def end_label(building: str, floor: int, column: int = -1) -> str:
    """A contact end as printed: "B:2" for floor 2 of B (a wall's floor is 0), "B:c2" for the column
    of B's story 2 struck between floors (``column`` >= 0)."""
    return f"{building}:{'c' if column >= 0 else ''}{int(floor)}"


def _check_floor(where: str, f: Any, b: ShearBuilding) -> int:
    """A floor number of building b (0 = its base slab when isolated), validated."""
    lowest = BASE_FLOOR if b.isolated else 1
    try:
        i = int(f)
    except (TypeError, ValueError):
        i = None
    if i is None or i != f or not lowest <= i <= b.n_floors:
        base = (
            " (0 = the base slab)"
            if b.isolated
            else " (0, a base slab, only for an isolated building)"
        )
        raise PoundingInputError(
            f"{where}: floor {f!r} of building {b.name!r}; allowed: {lowest}..{b.n_floors}{base}"
        )
    return i


def _levels(b: ShearBuilding, shown: int = 4) -> str:
    z = [f"{e:.4g}" for e in b.elevations]
    return ", ".join(z if len(z) <= shown else [*z[: shown - 1], "...", z[-1]])


def _floor_pairs(
    contact: Contact | Link, left: ShearBuilding | None, right: ShearBuilding | None, where: str
) -> list[tuple[int, int]]:
    """(left floor, right floor) pairs of a contact, 1-based (0 = a base slab), 0 on a wall side;
    ``where`` names the contact in errors."""
    floors = contact.floors
    if left is not None and right is not None:
        if isinstance(floors, str):
            if floors != "common":
                raise PoundingInputError(
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
                raise PoundingInputError(
                    f"{where}: floors = 'common' but no floor of {left.name!r} (floors at "
                    f"{_levels(left)} m) is at the elevation of a floor of {right.name!r} ("
                    f"{_levels(right)} m); allowed: explicit floors = [[left_floor, right_floor], "
                    "...], or story heights that line up"
                )
            return pairs
        pairs = []
        for item in floors:
            if not (isinstance(item, Sequence) and len(item) == 2):
                raise PoundingInputError(
                    f"{where}: floors entry {item!r}; allowed: [left_floor, right_floor] pairs"
                )
            pairs.append((_check_floor(where, item[0], left), _check_floor(where, item[1], right)))
        return pairs
    building = left if left is not None else right
    if isinstance(floors, str):
        if floors not in ("all", "common"):
            raise PoundingInputError(
                f"{where}: floors = {floors!r}; allowed with a wall: 'all' or a list of floors"
            )
        chosen = list(range(1, building.n_floors + 1))
    else:
        chosen = [
            _check_floor(where, f[0] if isinstance(f, Sequence) else f, building) for f in floors
        ]
    return [(f, 0) if left is not None else (0, f) for f in chosen]


def assemble(
    buildings: Sequence[ShearBuilding],
    contacts: Sequence[Contact] = (),
    links: Sequence[Link] = (),
) -> PoundingSystem:
    """Assemble buildings (listed left to right) and contacts into a :class:`PoundingSystem`.

    Contacts may join only neighbours in the row (``left`` immediately left of ``right``) or a building
    and a wall on either side. Each contact expands into one gap element per floor pair, with the
    law's parameters computed for the effective mass m̄ = m_a m_b/(m_a + m_b) of the two floors (m_a for a
    wall); a base slab (floor 0) counts with its own mass. Isolated buildings get their base dof and
    a friction element (module docstring).
    """
    buildings = tuple(buildings)
    index = _building_index(buildings)
    # the contacts' floor pairs first: a slab striking a column adds a node to the struck building
    nodes: list[list[dict[str, Any]]] = [[] for _ in buildings]
    expanded = [
        _contact_pairs(g, contact, buildings, index, nodes) for g, contact in enumerate(contacts)
    ]
    # each building: [base slab if isolated | sway, rocking on soil] + floors + column nodes;
    # offsets = dof of floor 1
    extra = [(1 if b.isolated else 0) + (2 if b.flexible_base else 0) for b in buildings]
    sizes = [b.n_floors + x + len(q) for b, x, q in zip(buildings, extra, nodes, strict=True)]
    starts = np.concatenate(([0], np.cumsum(sizes)[:-1])).astype(np.int64)
    base_dof = np.array(
        [s if b.isolated else -1 for b, s in zip(buildings, starts, strict=True)], dtype=np.int64
    )
    soil_dof = np.array(
        [
            (s, s + 1) if b.flexible_base else (-1, -1)
            for b, s in zip(buildings, starts, strict=True)
        ],
        dtype=np.int64,
    ).reshape(len(buildings), 2)
    offsets = starts + np.array(extra, dtype=np.int64)
    elements = _gap_elements(contacts, expanded, offsets, nodes)
    below, tilt, tilt_height, influence, heights = _dof_topology(buildings, starts, offsets, nodes)
    blocks = [building_matrices(b, q) for b, q in zip(buildings, nodes, strict=True)]
    return PoundingSystem(
        buildings=buildings,
        contacts=tuple(contacts),
        elements=elements,
        mass=_block_diag([m for m, _, _ in blocks]),
        damping=_block_diag([c for _, c, _ in blocks]),
        stiffness=_block_diag([k for _, _, k in blocks]),
        influence=influence,
        dof_offset=offsets,
        below=below,
        story_height=heights,
        base_dof=base_dof,
        friction=_friction_elements(buildings, base_dof),
        links=_link_elements(links, buildings, index, offsets),
        link_specs=tuple(links),
        stories=_story_elements(buildings, offsets, below),
        soil_dof=soil_dof,
        tilt=tilt,
        tilt_height=tilt_height,
        columns=_column_nodes(buildings, nodes, offsets),
    )


def _building_index(buildings: tuple[ShearBuilding, ...]) -> dict[str, int]:
    """Position of each building in the row by name, after checking the names."""
    if not buildings:
        raise PoundingInputError("a system needs at least one building")
    names = [b.name for b in buildings]
    dupes = {n for n in names if names.count(n) > 1}
    if dupes:
        raise PoundingInputError(
            f"building names must be unique; repeated: {', '.join(sorted(dupes))}"
        )
    if WALL in names:
        raise PoundingInputError(f"{WALL!r} is reserved for rigid walls and cannot name a building")
    return {n: i for i, n in enumerate(names)}


def _contact_pairs(
    g: int,
    contact: Contact,
    buildings: tuple[ShearBuilding, ...],
    index: dict[str, int],
    nodes: list[list[dict[str, Any]]],
) -> tuple:
    """(left index, right index, left building, right building, [(floor l, floor r, struck side,
    column node)]) of contact ``g``; a slab striking a column adds its node to ``nodes``."""
    # contact[g], as in the case file's [[contact]] list (and the caller's contacts sequence)
    where = f"contact[{g}] {contact.left!r}-{contact.right!r}"
    names = [b.name for b in buildings]
    for side in (contact.left, contact.right):
        if side != WALL and side not in index:
            key = "left" if side == contact.left else "right"
            raise PoundingInputError(
                f"{where}: {key} = {side!r}: unknown building {side!r}; allowed: "
                f"{', '.join(names)} or {WALL!r}"
            )
    li = index.get(contact.left)
    ri = index.get(contact.right)
    if li is not None and ri is not None and ri != li + 1:
        raise PoundingInputError(
            f"{where}: contacts join neighbours in the row (buildings are listed left to right: "
            f"{', '.join(names)}); {contact.left!r} is not immediately left of {contact.right!r}"
        )
    lb = buildings[li] if li is not None else None
    rb = buildings[ri] if ri is not None else None
    if contact.floors != ELEVATION:
        return (
            li,
            ri,
            lb,
            rb,
            [(fl, fr, None, -1) for fl, fr in _floor_pairs(contact, lb, rb, where)],
        )
    pairs = []
    for fl, fr, side, xi in _elevation_pairs(contact, lb, rb, where):
        struck = li if side == "left" else ri
        q = -1
        if side is not None:
            story = fl if side == "left" else fr
            q = _column_node(nodes[struck], buildings[struck], story, xi, contact, g, where)
        pairs.append((fl, fr, side, q))
    return li, ri, lb, rb, pairs


def _gap_elements(
    contacts: Sequence[Contact],
    expanded: list[tuple],
    offsets: np.ndarray,
    nodes: list[list[dict[str, Any]]],
) -> GapElements:
    """One gap element per floor pair of every contact, its law's parameters for the pair's m̄."""
    # global column index of each building's first node
    first_node = np.concatenate(([0], np.cumsum([len(q) for q in nodes])[:-1])).astype(np.int64)

    def end(bi: int | None, b: ShearBuilding | None, floor: int, q: int) -> tuple[int, float, int]:
        """(dof, mass, global column index or −1) of a contact end."""
        if b is None:
            return -1, math.inf, -1
        if q >= 0:
            return int(offsets[bi] + b.n_floors + q), nodes[bi][q]["mass"], int(first_node[bi] + q)
        return int(offsets[bi] + floor - 1), _point_mass(b, floor), -1

    rows: list[dict[str, Any]] = []
    for g, (contact, (li, ri, lb, rb, pairs)) in enumerate(zip(contacts, expanded, strict=True)):
        where = f"contact[{g}] {contact.left!r}-{contact.right!r}"
        law: ContactLaw = get_contact_law(contact.law)
        for fl, fr, side, q in pairs:
            dof_a, ma, col_a = end(li, lb, fl, q if side == "left" else -1)
            dof_b, mb, col_b = end(ri, rb, fr, q if side == "right" else -1)
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
                    bumper=contact.bumper,
                    filler=contact.filler,
                )
            except ValueError as exc:
                raise PoundingInputError(f"{where}: {exc}") from None
            rows.append(
                dict(
                    dof=(dof_a, dof_b),
                    sign=(
                        LEFT_SIGN if lb is not None else 0.0,
                        RIGHT_SIGN if rb is not None else 0.0,
                    ),
                    gap=contact.element_gap,
                    law_id=law.kernel_id,
                    params=params,
                    mass=m_eff,
                    left=contact.left,
                    right=contact.right,
                    lf=fl,
                    rf=fr,
                    law=law.name,
                    group=g,
                    columns=(col_a, col_b),
                )
            )
    n_el = len(rows)
    return GapElements(
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
        left_column=np.array([r["columns"][0] for r in rows], dtype=np.int64),
        right_column=np.array([r["columns"][1] for r in rows], dtype=np.int64),
    )


def _dof_topology(
    buildings: tuple[ShearBuilding, ...],
    starts: np.ndarray,
    offsets: np.ndarray,
    nodes: list[list[dict[str, Any]]],
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Per dof of the system: the dof below, the rocking dof that tilts it and the height it tilts
    with, the influence of the ground acceleration and the story height (0: not a story)."""
    # dof below each dof: the floor below, the base slab (or the sway dof) under floor 1, -1 (the
    # ground) for a base slab, a foundation's dofs and floor 1 of a fixed-base building; a rocking
    # foundation tilts each of its stories by h_i θ. A column node sits on its story's lower floor
    # and is tilted by ξ h θ.
    below, tilt, tilt_height, influence, heights = [], [], [], [], []
    for b, s, o, q in zip(buildings, starts, offsets, nodes, strict=True):
        n = b.n_floors
        ground = s if b.isolated or b.flexible_base else -1
        floor_below = np.concatenate(([ground], o + np.arange(n - 1)))
        story = np.array([node["story"] for node in q], dtype=np.int64)
        xi = np.array([node["xi"] for node in q])
        lead = o - s
        rocks = b.flexible_base
        below.append(np.concatenate((np.full(lead, -1), floor_below, floor_below[story - 1])))
        rock_h = np.concatenate((b.heights, xi * b.heights[story - 1]))
        tilt.append(
            np.concatenate((np.full(lead, -1), np.full(n + len(q), s + 1 if rocks else -1)))
        )
        tilt_height.append(
            np.concatenate((np.zeros(lead), rock_h if rocks else np.zeros(n + len(q))))
        )
        influence.append(
            np.concatenate(([1.0, 0.0] if rocks else np.ones(lead), np.ones(n + len(q))))
        )
        # a node's "story" is not checked for collapse (height 0): its segments are in the story's
        heights.append(np.concatenate((np.zeros(lead), b.heights, np.zeros(len(q)))))
    return (
        np.concatenate(below).astype(np.int64),
        np.concatenate(tilt).astype(np.int64),
        np.concatenate(tilt_height),
        np.concatenate(influence),
        np.concatenate(heights),
    )


def _elevation_pairs(
    contact: Contact, left: ShearBuilding | None, right: ShearBuilding | None, where: str
) -> list[tuple[int, int, str | None, float]]:
    """(left floor, right floor, struck side, ξ) of ``floors = "elevation"``: every floor of the
    building with the shorter stories (the left one on a tie), up to the neighbour's roof, paired
    with the neighbour's floor within ``level_tolerance`` of its elevation, or else with the column
    of the neighbour's story at that elevation (struck side "left"/"right", the story number in
    its floor slot, ξ = a/h; side None for a floor pair)."""
    if left is None or right is None:
        raise PoundingInputError(
            f"{where}: floors = 'elevation' pairs the floors of two buildings; allowed with a "
            "wall: 'all' or a list of floors"
        )
    tol = contact.slab_tolerance
    striking_left = float(np.mean(left.heights)) <= float(np.mean(right.heights))
    s, other = (left, right) if striking_left else (right, left)
    side = "right" if striking_left else "left"
    z_other = other.elevations
    bottoms = np.concatenate(([0.0], z_other[:-1]))
    out = []
    for f, z in enumerate(s.elevations, start=1):
        if z > z_other[-1] + tol:
            break  # above the neighbour's roof
        near = int(np.argmin(np.abs(z_other - z)))
        if abs(z_other[near] - z) <= tol:
            pair = (f, near + 1) if striking_left else (near + 1, f)
            out.append((*pair, None, 0.0))
            continue
        j = int(np.searchsorted(z_other, z))  # story j + 1 holds z
        xi = (z - bottoms[j]) / other.heights[j]
        pair = (f, j + 1) if striking_left else (j + 1, f)
        out.append((*pair, side, float(xi)))
    if not out:
        raise PoundingInputError(
            f"{where}: floors = 'elevation' but no floor of {s.name!r} is below the roof of "
            f"{other.name!r} ({z_other[-1]:.4g} m)"
        )
    return out


def _column_node(
    nodes: list[dict[str, Any]],
    building: ShearBuilding,
    story: int,
    xi: float,
    contact: Contact,
    group: int,
    where: str,
) -> int:
    """Index in ``nodes`` of the impact node at ξ of ``story`` (added if new); one node per story."""
    h = float(building.heights[story - 1])
    tol = contact.slab_tolerance
    for q, node in enumerate(nodes):
        if node["story"] != story:
            continue
        if abs(node["xi"] - xi) * h <= max(tol, 1e-9):
            return q
        raise PoundingInputError(
            f"{where}: story {story} of {building.name!r} is struck at {xi * h:.3g} m and at "
            f"{node['xi'] * h:.3g} m above its lower floor; allowed: one impact point per story "
            "(a larger level_tolerance merges them with a floor)"
        )
    share = 1.0 if contact.column_share is None else float(contact.column_share)
    mass = contact.column_mass
    nodes.append(
        dict(
            story=story,
            xi=xi,
            share=share,
            mass=COLUMN_MASS_FRACTION * float(building.masses[story - 1]) if mass is None
            else float(mass),
            capacity=math.nan if contact.column_capacity is None else float(contact.column_capacity),
            group=group,
        )
    )  # fmt: skip
    return len(nodes) - 1


def _column_nodes(
    buildings: tuple[ShearBuilding, ...], nodes: list[list[dict[str, Any]]], offsets: np.ndarray
) -> ColumnNodes:
    rows = [
        (int(offsets[i] + b.n_floors + q), i, node, b)
        for i, (b, q_nodes) in enumerate(zip(buildings, nodes, strict=True))
        for q, node in enumerate(q_nodes)
    ]
    if not rows:
        return ColumnNodes.empty()

    def col(f):
        return np.array([f(node, b) for _, _, node, b in rows])

    k_c = col(lambda node, b: node["share"] * b.stiffnesses[node["story"] - 1])
    xi = col(lambda node, b: node["xi"])
    bottom = col(lambda node, b: b.elevations[node["story"] - 1] - b.heights[node["story"] - 1])
    height = col(lambda node, b: b.heights[node["story"] - 1])
    return ColumnNodes(
        dof=np.array([r[0] for r in rows], dtype=np.int64),
        building=np.array([r[1] for r in rows], dtype=np.int64),
        story=col(lambda node, b: node["story"]).astype(np.int64),
        xi=xi,
        elevation=bottom + xi * height,
        share=col(lambda node, b: node["share"]),
        k_below=k_c / xi,
        k_above=k_c / (1.0 - xi),
        mass=col(lambda node, b: node["mass"]),
        capacity=col(lambda node, b: node["capacity"]),
        group=col(lambda node, b: node["group"]).astype(np.int64),
    )


def _story_elements(
    buildings: tuple[ShearBuilding, ...], offsets: np.ndarray, below: np.ndarray
) -> StoryElements:
    """One row per story of every building with a yielding story model."""
    parts = []
    rocking = any(b.stories.yielding and b.flexible_base for b in buildings)
    for i, (b, o) in enumerate(zip(buildings, offsets, strict=True)):
        if not b.stories.yielding:
            continue
        n = b.n_floors
        floor = o + np.arange(n)
        under = below[floor]
        ultimate = b.stories.ultimate_drift(n, f"building {b.name!r}")
        dof = [floor, under]
        sign = [np.ones(n), np.where(under >= 0, -1.0, 0.0)]
        if rocking:  # the foundation's rocking dof (o − 1) tilts each story by h θ
            dof.append(np.full(n, o - 1 if b.flexible_base else -1))
            sign.append(-b.heights if b.flexible_base else np.zeros(n))
        parts.append(
            (
                np.column_stack(dof),
                np.column_stack(sign),
                np.full(n, STORY_MODELS[b.stories.model].kernel_id),
                b.story_parameters(),
                np.full(n, i),
                np.arange(1, n + 1),
                (b.stories.model,) * n,
                np.full(n, np.nan) if ultimate is None else ultimate * b.heights,
                np.full(n, b.stories.park_ang_beta),
            )
        )
    if not parts:
        return StoryElements.empty()
    cols = list(zip(*parts, strict=True))
    return StoryElements(
        dof=np.concatenate(cols[0]).astype(np.int64),
        sign=np.concatenate(cols[1]),
        law_id=np.concatenate(cols[2]).astype(np.int64),
        params=np.concatenate(cols[3]),
        building=np.concatenate(cols[4]).astype(np.int64),
        story=np.concatenate(cols[5]).astype(np.int64),
        model=sum(cols[6], ()),
        ultimate=np.concatenate(cols[7]),
        park_ang_beta=np.concatenate(cols[8]),
    )


def _link_elements(
    links: Sequence[Link],
    buildings: tuple[ShearBuilding, ...],
    index: dict[str, int],
    offsets: np.ndarray,
) -> LinkElements:
    """One row per linked floor pair: the dofs with the gap elements' signs (δ = u_left − u_right)."""
    rows = []
    names = list(index)
    for g, link in enumerate(links):
        where = f"link[{g}] {link.left!r}-{link.right!r}"
        for key, side in (("left", link.left), ("right", link.right)):
            if side not in index:
                raise PoundingInputError(
                    f"{where}: {key} = {side!r}: unknown building; allowed: {', '.join(names)}"
                )
        li, ri = index[link.left], index[link.right]
        if ri != li + 1:
            raise PoundingInputError(
                f"{where}: links join neighbours in the row (buildings are listed left to right: "
                f"{', '.join(names)}); {link.left!r} is not immediately left of {link.right!r}"
            )
        params = link.parameters(where)
        law = LINK_LAWS[link.type]
        for fl, fr in _floor_pairs(link, buildings[li], buildings[ri], where):
            rows.append((offsets[li] + fl - 1, offsets[ri] + fr - 1, law, params, link, fl, fr, g))
    if not rows:
        return LinkElements.empty()
    return LinkElements(
        dof=np.array([(r[0], r[1]) for r in rows], dtype=np.int64),
        sign=np.array([(LEFT_SIGN, RIGHT_SIGN)] * len(rows), dtype=float),
        law_id=np.array([r[2].kernel_id for r in rows], dtype=np.int64),
        params=np.array([r[3] for r in rows], dtype=float),
        left=tuple(r[4].left for r in rows),
        right=tuple(r[4].right for r in rows),
        left_floor=np.array([r[5] for r in rows], dtype=np.int64),
        right_floor=np.array([r[6] for r in rows], dtype=np.int64),
        law=tuple(r[2].name for r in rows),
        group=np.array([r[7] for r in rows], dtype=np.int64),
    )


def _point_mass(building: ShearBuilding | None, floor: int) -> float:
    """Mass [kg] of a contact end: a floor, a base slab (floor 0), or inf for a wall."""
    if building is None:
        return math.inf
    if floor == BASE_FLOOR:
        return float(building.base.mass)
    return float(building.masses[floor - 1])


def building_matrices(
    building: ShearBuilding, nodes: Sequence[dict[str, Any]] = ()
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """M, C, K of one building in the system's dofs ([u_b, u_1..u_n] when isolated, [u_0, θ,
    u_1..u_n] on soil, then its column ``nodes``; module docstring); K includes the P-Δ geometric
    stiffness of a building with ``p_delta``.

    A fixed-base building's own matrices; an isolated one's K_ext = Tᵀ K T (+ W/R at the base for a
    friction pendulum, Zayas et al. 1990), C_ext = Tᵀ C T, M_ext = diag(m_b, m_1..m_n).
    """
    m, c, k, kg, z = _superstructure(building, nodes)
    if building.soil is not None:
        return _flexible_base_matrices(building, m, c, k, kg, z)
    k = k + kg
    base = building.base
    if base is None:
        return m, c, k
    n = m.shape[0]
    t = np.hstack((-np.ones((n, 1)), np.eye(n)))  # floor displacement relative to the slab
    k_ext = t.T @ k @ t
    c_ext = t.T @ c @ t
    if base.radius is not None:
        k_ext[0, 0] += building.weight / base.radius
    m_ext = np.diag(np.concatenate(([base.mass], np.diag(m))))
    return m_ext, 0.5 * (c_ext + c_ext.T), 0.5 * (k_ext + k_ext.T)


def _superstructure(
    building: ShearBuilding, nodes: Sequence[dict[str, Any]]
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """M, C, K, K_G of the building on a fixed base in [u_1..u_n, column nodes], and the heights
    [m] of those dofs. A node at ξ of story j moves k_c = share k_j from the floor-to-floor spring
    to k_c/ξ below it and k_c/η above (module docstring); with Rayleigh damping (C = a0 M + a1 K)
    its springs and mass are damped alike, with modal damping the node has none of its own."""
    n, nn = building.n_floors, len(nodes)
    size = n + nn
    m = np.zeros((size, size))
    k = np.zeros((size, size))
    kg = np.zeros((size, size))
    c = np.zeros((size, size))
    m[:n, :n] = building.mass_matrix()
    k[:n, :n] = building.stiffness_matrix()
    kg[:n, :n] = building.geometric_stiffness_matrix()
    c[:n, :n] = building.damping_matrix()
    a0, a1 = building.rayleigh_coefficients() if building._uses_rayleigh() else (0.0, 0.0)
    z = np.concatenate((building.elevations, np.zeros(nn)))
    for q, node in enumerate(nodes):
        j, xi = int(node["story"]) - 1, float(node["xi"])  # floor above: index j, below: j - 1
        k_c = float(node["share"]) * float(building.stiffnesses[j])
        dk = np.zeros((size, size))
        for a, b, kk in ((j - 1, j, -k_c), (j - 1, n + q, k_c / xi), (n + q, j, k_c / (1.0 - xi))):
            for p, r, sign in ((a, a, 1.0), (b, b, 1.0), (a, b, -1.0), (b, a, -1.0)):
                if p >= 0 and r >= 0:  # -1: the ground (or the base under floor 1)
                    dk[p, r] += sign * kk
        k += dk
        c += a1 * dk
        m[n + q, n + q] = float(node["mass"])
        c[n + q, n + q] += a0 * float(node["mass"])
        z[n + q] = float(building.elevations[j] - building.heights[j] * (1.0 - xi))
    return m, c, k, kg, z


def _flexible_base_matrices(
    building: ShearBuilding,
    m: np.ndarray,
    c: np.ndarray,
    k: np.ndarray,
    kg: np.ndarray,
    z: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """M, C, K of a building on soil in the dofs [u_0, θ, x_1..x_n, nodes] (module docstring), from
    its fixed-base m, c, k, kg and the heights z of those dofs."""
    soil = building.soil
    assert soil is not None
    n = m.shape[0]
    t_g = np.hstack((-np.ones((n, 1)), np.zeros((n, 1)), np.eye(n)))  # x_i − u_0
    t_e = t_g.copy()
    t_e[:, 1] = -z  # x_i − u_0 − H_i θ: the deformation of the stories
    k_ext = t_e.T @ k @ t_e + t_g.T @ kg @ t_g
    c_ext = t_e.T @ c @ t_e
    k_x, k_t = soil.springs
    c_x, c_t = soil.dashpot_coefficients
    k_ext[0, 0] += k_x
    k_ext[1, 1] += k_t
    c_ext[0, 0] += c_x
    c_ext[1, 1] += c_t
    m_ext = np.diag(np.concatenate(([soil.mass, soil.rotational_inertia], np.diag(m))))
    return m_ext, 0.5 * (c_ext + c_ext.T), 0.5 * (k_ext + k_ext.T)


def _friction_elements(
    buildings: Sequence[ShearBuilding], base_dof: np.ndarray
) -> FrictionElements:
    rows = []
    for i, b in enumerate(buildings):
        base = b.base
        if base is None:
            continue
        law = base.law
        if base.stick_slip and base.friction_array()[0] > 0.0:
            kind = FRICTION_COULOMB
        elif base.stick_slip:  # frictionless (μ_s = μ_d = 0): never stuck, f ≡ 0
            kind = FRICTION_REGULARISED
        elif base.hysteretic:
            kind = FRICTION_BOUC_WEN
        else:
            kind = FRICTION_REGULARISED
        params = np.zeros(N_FRICTION_PARAMS)
        p = base.friction_array()
        params[: p.size] = p
        bw = base.bouc_wen_array()
        rows.append(
            dict(
                dof=base_dof[i],
                kind=kind,
                law=law.kernel_id,
                params=params,
                bw=np.zeros(len(BOUC_WEN_PARAMETERS)) if bw is None else bw,
                normal=b.weight,
                mass=base.mass,
                building=i,
                name=law.name,
            )
        )
    nf = len(rows)
    return FrictionElements(
        fr_dof=np.array([r["dof"] for r in rows], dtype=np.int64),
        fr_kind=np.array([r["kind"] for r in rows], dtype=np.int64),
        fr_law=np.array([r["law"] for r in rows], dtype=np.int64),
        fr_params=np.array([r["params"] for r in rows], dtype=float).reshape(nf, N_FRICTION_PARAMS),
        fr_bouc_wen=np.array([r["bw"] for r in rows], dtype=float).reshape(
            nf, len(BOUC_WEN_PARAMETERS)
        ),
        fr_normal=np.array([r["normal"] for r in rows], dtype=float),
        fr_mass=np.array([r["mass"] for r in rows], dtype=float),
        building=np.array([r["building"] for r in rows], dtype=np.int64),
        law=tuple(r["name"] for r in rows),
    )
