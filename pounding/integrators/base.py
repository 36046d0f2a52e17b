"""What every integrator returns, and the options they share."""

from __future__ import annotations

import dataclasses
import math
from typing import TYPE_CHECKING, Any

import numpy as np

from pounding.errors import ConvergenceError

if TYPE_CHECKING:
    from pounding.ground_motion import GroundMotion
    from pounding.system import PoundingSystem

__all__ = [
    "CORES",
    "ENERGY_TERMS",
    "IMPACT_FIELDS",
    "PATH_POINTS",
    "ConvergenceError",
    "RawResult",
    "compiled_core",
    "decimated_path",
    "path_table",
]

#: The two compilations of the Newmark/HHT core (:func:`compiled_core`).
CORES = ("gaps", "families")


def compiled_core(system: PoundingSystem, lean: bool = True) -> str:
    """Which compilation of the Newmark/HHT core integrates ``system``: ``"gaps"`` for gaps alone
    (no friction element, no link, no yielding story: most pounding analyses), else
    ``"families"``. The core of gaps alone is compiled with ``None`` for the friction and family
    groups: numba drops their code before typing it, so it compiles in about half the time of the
    whole one. ``lean=False`` gives every system the whole core."""
    plain = len(system.friction) == 0 and len(system.links) == 0 and len(system.stories) == 0
    return "gaps" if lean and plain else "families"


#: Columns of :attr:`RawResult.energy`, in order.
ENERGY_TERMS = (
    "input",
    "kinetic",
    "strain",
    "damping",
    "contact_dissipated",
    "contact_stored",
    "friction_dissipated",
    "algorithmic",
    "link_dissipated",
    "link_stored",
    "hysteretic",
)

#: Fields of :attr:`RawResult.impacts`, one array per field, one entry per impact.
IMPACT_FIELDS = (
    "element",
    "start",
    "end",
    "v0",
    "v_end",
    "peak_force",
    "max_penetration",
    "impulse",
)


#: Most (penetration, force) points kept per impact at integration steps (``path_penetration``,
#: ``path_force`` of :attr:`RawResult.impacts`): a force-penetration loop drawn from the output grid
#: missed the peak of a 70-90 ms impact by up to 40 %.
PATH_POINTS = 48


def decimated_path(d: np.ndarray, f: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """At most :data:`PATH_POINTS` of an impact's (penetration, force) samples, evenly spread over
    them, the first and the last always kept."""
    if d.size <= PATH_POINTS:
        return d, f
    keep = np.unique(np.round(np.linspace(0, d.size - 1, PATH_POINTS)).astype(np.int64))
    return d[keep], f[keep]


def path_table(paths: list[tuple[np.ndarray, np.ndarray]]) -> tuple[np.ndarray, np.ndarray]:
    """(impact, point) arrays of penetration [m] and force [N], NaN beyond each impact's points."""
    d = np.full((len(paths), PATH_POINTS), np.nan)
    f = np.full((len(paths), PATH_POINTS), np.nan)
    for i, (pd, pf) in enumerate(paths):
        pd, pf = decimated_path(np.asarray(pd, float), np.asarray(pf, float))
        d[i, : pd.size] = pd
        f[i, : pf.size] = pf
    return d, f


@dataclasses.dataclass(eq=False)
class RawResult:
    """Plain-array result of one integration; :mod:`pounding.results` turns it into a Dataset.

    Output-grid arrays (first axis ``time``): ``displacement``, ``velocity``, ``acceleration``
    (relative to the ground) [m, m/s, m/s²] per dof; ``ground_acceleration`` [m/s²];
    ``penetration`` [m] and ``contact_force`` [N] per gap element; ``energy`` [J] with columns
    :data:`ENERGY_TERMS` (cumulative work for input, damping and contact dissipation).
    Peaks are absolute maxima over *every* integration step, not just the output grid:
    ``peak_displacement``, ``peak_drift`` (|u_i − u_below|), ``peak_absolute_acceleration`` per dof;
    ``peak_contact_force``, ``peak_penetration`` per element. ``impacts`` maps :data:`IMPACT_FIELDS`
    to arrays (``end`` and ``v_end`` are NaN for an impact still open when the record ends), and
    ``path_penetration``/``path_force`` to (impact, :data:`PATH_POINTS`) arrays: the impact's
    (penetration, force) at integration steps from closure to separation, NaN-padded.
    Per friction element (isolated building, :class:`pounding.system.FrictionElements`) on the
    output grid: ``friction_force`` [N] (resisting, with the sign of the base velocity; the
    reaction of a stuck slab) and ``stick`` (1 while a Coulomb slab sticks, else 0). The strain
    energy includes a friction pendulum's restoring potential ½ (W/R) u_b²; ``friction_dissipated``
    is the work of the friction forces ∫ f u̇_b dt; ``algorithmic`` the energy the time-stepping
    scheme itself removes (zero for average acceleration and for the ivp path; HHT's numerical
    damping; see :mod:`pounding.integrators.newmark`). Per coupling link
    (:class:`pounding.system.LinkElements`): ``link_force`` [N] on the output grid and
    ``peak_link_force`` (absolute maximum over every step); ``link_stored`` is the energy its
    spring holds, ``link_dissipated`` the rest of the work its force did. Per yielding story
    (:class:`pounding.system.StoryElements`): ``story_force`` [N], its spring force on the output
    grid, ``peak_story_force`` over every step, ``story_hysteretic`` [J] the work ∫F dδ of its
    spring less its recoverable F²/(2k) at the end; the energy columns put that recoverable part
    in ``strain`` and the rest of the stories' work in ``hysteretic``.
    """

    time: np.ndarray
    displacement: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    ground_acceleration: np.ndarray
    penetration: np.ndarray
    contact_force: np.ndarray
    energy: np.ndarray
    peak_displacement: np.ndarray
    peak_drift: np.ndarray
    peak_absolute_acceleration: np.ndarray
    peak_contact_force: np.ndarray
    peak_penetration: np.ndarray
    impacts: dict[str, np.ndarray]
    info: dict[str, Any]
    friction_force: np.ndarray | None = None
    stick: np.ndarray | None = None
    link_force: np.ndarray | None = None
    peak_link_force: np.ndarray | None = None
    story_force: np.ndarray | None = None
    peak_story_force: np.ndarray | None = None
    story_hysteretic: np.ndarray | None = None


def response_scales(system: PoundingSystem, ground: GroundMotion) -> tuple[float, float]:
    """(v_c [m/s], ω1 [rad/s]): the response's velocity scale v_c = min(PGV, PGA/ω1) and the lowest
    natural frequency ω1 of any building (an isolated one's √(g/R) or, on flat sliders, PGA/PGV
    included). Tolerances of both integrators are relative to these, so a model scaled in length
    behaves the same."""
    from pounding.ground_motion import ground_velocity
    from pounding.units import G

    omega1 = 2.0 * math.pi / max(float(b.modal().periods.max()) for b in system.buildings)
    pgv = float(np.abs(ground_velocity(ground)).max()) if ground.npts > 1 else 0.0
    for b in system.buildings:
        # a sliding base moves at the isolated frequency √(g/R), or the ground's own PGA/PGV
        if b.base is not None and b.base.radius is not None:
            omega1 = min(omega1, math.sqrt(G / b.base.radius))
        elif b.base is not None and pgv > 0.0 and ground.pga > 0.0:
            omega1 = min(omega1, ground.pga / pgv)
    return min(pgv, ground.pga / omega1), omega1


#: A v0-scaled law (Kelvin's c, the Hunt-Crossley family's χ = α/v0) is evaluated at the impact's
#: approach speed, but at least this fraction of the response's velocity scale v_c
#: (:func:`response_scales`): a contact that starts from rest or grazes in (buildings touching at
#: zero gap, a push that closes a gap quasi-statically) would otherwise get a damping set by the
#: integrator's numerics (one step's speed, a tolerance) instead of by the problem. Impacts that slow
#: carry under 1e-4 of the response's kinetic energy, so the floor does not change what they dissipate.
V0_FRACTION = 1e-2


def v0_floor(system: PoundingSystem, ground: GroundMotion) -> float:
    """The smallest approach speed [m/s] a v0-scaled law is evaluated at: V0_FRACTION v_c."""
    return V0_FRACTION * response_scales(system, ground)[0]
