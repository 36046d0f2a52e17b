"""What every integrator returns, and the options they share."""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from pounding.errors import ConvergenceError

__all__ = ["ENERGY_TERMS", "IMPACT_FIELDS", "ConvergenceError", "RawResult"]

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
    to arrays (``end`` and ``v_end`` are NaN for an impact still open when the record ends).
    Per friction element (isolated building, :class:`pounding.system.FrictionElements`) on the
    output grid: ``friction_force`` [N] (resisting, with the sign of the base velocity; the
    reaction of a stuck slab) and ``stick`` (1 while a Coulomb slab sticks, else 0). The strain
    energy includes a friction pendulum's restoring potential ½ (W/R) u_b²; ``friction_dissipated``
    is the work of the friction forces ∫ f u̇_b dt; ``algorithmic`` the energy the time-stepping
    scheme itself removes (zero for average acceleration and for the ivp path; HHT's numerical
    damping; see :mod:`pounding.integrators.newmark`).
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
