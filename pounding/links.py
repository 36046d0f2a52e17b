r"""Coupling links between facing floors of adjacent buildings: springs, viscous and fluid dampers.

A link is always connected (unlike a gap element). It acts on δ = u_left − u_right, the relative
displacement of the two floors [m] (positive when they approach, as for a gap), and its force F [N]
pushes them apart when positive, the sign convention of :mod:`pounding.system`. Links are the first
element family of the compiled core beyond gaps and friction (:mod:`pounding.integrators._families`).

Each law is a kernel of plain ``math``, compiled from the same source:

``kernel(d, dd, h, s0, s1, p) -> (F, ∂F/∂δ, ∂F/∂δ̇)``

with ``d`` = δ [m], ``dd`` = δ̇ [m/s] at the end of a step of length ``h`` [s], ``s0`` the committed
state row (read), ``s1`` the trial state row (written) and ``p`` the parameters. For a law with
internal state, ∂F/∂δ is the consistent tangent of its discrete update.

======== ================================================= ============================ ==========
law      force                                             parameters p                 reference
======== ================================================= ============================ ==========
kelvin   F = k δ + c δ̇                                     k [N/m], c [N s/m]           [1]_
viscous  F = c sgn(δ̇) abs(δ̇)^α (linear below v_lin)         c [N (s/m)^α], α, v_lin      [2]_, [3]_
maxwell  k (δ − x_d) = c ẋ_d = F (spring and dashpot        k [N/m], c [N s/m]           [4]_
         in series)
======== ================================================= ============================ ==========

The fluid viscous damper's tangent α c abs(δ̇)^(α−1) is infinite at δ̇ = 0 for α < 1; below
``v_lin`` [m/s] (default 1 mm/s) its force is the chord c v_lin^α δ̇/v_lin, which changes the energy
of a cycle of amplitude X ω by less than (v_lin/(X ω))^(1+α). The Maxwell element integrates
Ḟ = k δ̇ − F/τ (τ = c/k) exactly for δ linear over the step:
F₁ = F₀ e^(−h/τ) + c (δ₁ − δ₀)/h (1 − e^(−h/τ)).

References
----------
.. [1] Xu, Y.L., He, Q., Ko, J.M. (1999). Dynamic response of damper-connected adjacent buildings
   under earthquake excitation. Eng. Struct. 21(2), 135-148. doi:10.1016/S0141-0296(97)00154-5
.. [2] Constantinou, M.C., Symans, M.D. (1993). Experimental study of seismic response of buildings
   with supplemental fluid dampers. Struct. Design Tall Build. 2(2), 93-132.
   doi:10.1002/tal.4320020202
.. [3] Soong, T.T., Dargush, G.F. (1997). Passive energy dissipation systems in structural
   engineering. Wiley, Chichester (energy of a nonlinear viscous damper per cycle, Sec. 6.2).
.. [4] Makris, N., Constantinou, M.C. (1991). Fractional-derivative Maxwell model for viscous
   dampers. J. Struct. Eng. 117(9), 2708-2724. doi:10.1061/(ASCE)0733-9445(1991)117:9(2708)
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

#: Kind id of the link family in the compiled dispatch (pounding.integrators._dispatch).
FAMILY_LINK = 0
#: Columns of a link's state row: force [N] and δ [m] at the committed step end (Maxwell).
LS_F, LS_D = 0, 1
N_LINK_STATE = 2
#: Parameters per link (the widest law).
N_LINK_PARAMS = 3
#: Default speed [m/s] below which a fluid viscous damper is linear (its tangent stays finite).
V_LIN = 1e-3


def kelvin_link_kernel(d, dd, h, s0, s1, p):
    """Spring k and dashpot c in parallel: F = k δ + c δ̇."""
    s1[LS_F] = p[0] * d + p[1] * dd
    s1[LS_D] = d
    return s1[LS_F], p[0], p[1]


def viscous_link_kernel(d, dd, h, s0, s1, p):
    """Fluid viscous damper F = c sgn(δ̇) abs(δ̇)^α [2], the chord c v_lin^α δ̇/v_lin for
    abs(δ̇) < v_lin."""
    c, alpha, v_lin = p[0], p[1], p[2]
    v = abs(dd)
    if v < v_lin:
        slope = c * v_lin**alpha / v_lin
        f = slope * dd
        cd = slope
    else:
        f = math.copysign(c * v**alpha, dd)
        cd = alpha * c * v ** (alpha - 1.0)
    s1[LS_F] = f
    s1[LS_D] = d
    return f, 0.0, cd


def maxwell_link_kernel(d, dd, h, s0, s1, p):
    """Spring k in series with dashpot c [4], exact for δ linear over the step of length h."""
    k, c = p[0], p[1]
    decay = math.exp(-h * k / c)
    kd = c / h * (1.0 - decay)
    f = s0[LS_F] * decay + kd * (d - s0[LS_D])
    s1[LS_F] = f
    s1[LS_D] = d
    return f, kd, 0.0


def kelvin_link_stored(d, f, s, p):
    return 0.5 * p[0] * d * d


def viscous_link_stored(d, f, s, p):
    return 0.0


def maxwell_link_stored(d, f, s, p):
    return 0.5 * f * f / p[0]


@dataclass(frozen=True)
class LinkLaw:
    """A coupling-link law: its kernel, its stored energy and the parameters a case file gives.

    Attributes
    ----------
    name : str
        Registry name (``[[link]] type``).
    kernel_id : int
        Law id within the link family (the compiled dispatch switches on it).
    kernel, stored : callable
        ``kernel(d, dd, h, s0, s1, p)`` and ``stored(d, f, s, p)`` [J].
    parameters : tuple of (key, units, default)
        Case-file keys packed into ``p`` in order; a default of None means required.
    formula, reference : str
        For ``pounding laws`` and reports.
    """

    name: str
    kernel_id: int
    kernel: Callable
    stored: Callable
    parameters: tuple[tuple[str, str, float | None], ...]
    formula: str
    reference: str


_LINKS = (
    LinkLaw("kelvin", 0, kelvin_link_kernel, kelvin_link_stored,
            (("k", "N/m", 0.0), ("c", "N s/m", 0.0)), "F = k δ + c δ̇",
            "Xu, He & Ko 1999, Eng. Struct. 21(2) 135-148"),
    LinkLaw("viscous", 1, viscous_link_kernel, viscous_link_stored,
            (("c", "N (s/m)^alpha", None), ("alpha", "-", 1.0), ("v_lin", "m/s", V_LIN)),
            "F = c |δ̇|^α sgn δ̇",
            "Constantinou & Symans 1993, Struct. Des. Tall Build. 2(2) 93-132"),
    LinkLaw("maxwell", 2, maxwell_link_kernel, maxwell_link_stored,
            (("k", "N/m", None), ("c", "N s/m", None)), "k (δ − x_d) = c ẋ_d = F",
            "Makris & Constantinou 1991, J. Struct. Eng. 117(9) 2708-2724"),
)  # fmt: skip

#: Link laws by name, and by kernel id.
LINK_LAWS: dict[str, LinkLaw] = {law.name: law for law in _LINKS}
LINKS_BY_ID: tuple[LinkLaw, ...] = _LINKS
