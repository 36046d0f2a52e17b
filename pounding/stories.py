r"""Yielding stories: hysteretic story springs of a shear building.

Story i joins floor i − 1 (the ground, or the base slab of an isolated building, for i = 1) and
floor i; its drift is δ = u_i − u_{i−1} [m] and its spring (restoring) force F [N] resists it. A
building's stories are ``elastic`` (F = k δ, the default, assembled into K) or follow a hysteretic
model, the second element family of the compiled core (:mod:`pounding.integrators._families`).

A yielding story stays in the assembled stiffness matrix with its initial stiffness k, and its
element carries the difference F(δ) − k δ (zero while it is elastic). The modes, the Rayleigh
damping (from the initial stiffness, as OpenSees' ``-rayleigh aM 0 bKinit 0``) and an elastic
story are then exactly what they are without the model, and the element's tangent is k_t − k.

Each model is a kernel of plain ``math``, compiled from the same source:

``kernel(d, dd, h, s0, s1, p) -> (F − k δ, k_t − k, 0)``

with ``d`` = δ [m] at the end of the step, ``s0`` the committed state row (read) and ``s1`` the
trial state row (written: the spring force F, δ and the work W = ∫F dδ [J], trapezoidal per step),
``p`` = (k [N/m], F_y [N], model parameters...).

========= ============================================== ========================== =================
model     force                                          parameters                 reference
========= ============================================== ========================== =================
elastic   F = k δ                                        (none)
bilinear  F = min(max(F_n + k Δδ, b k δ − (1 − b) F_y),   yield_drift or yield_force, [1]_, [2]_
          b k δ + (1 − b) F_y); kinematic hardening,     hardening b
          elastic–perfectly plastic at b = 0
========= ============================================== ========================== =================

The bilinear update bounds the trial force by the two hardening lines, so it is exact for any
step (the return map of kinematic hardening; OpenSees ``Steel01`` with a1 = a3 = 0): unloading is
elastic with slope k over an elastic range of 2 F_y, the tangent is k inside it and b k on the
hardening lines.

Recoverable energy of a story is F²/(2k) (unloading at slope k); the rest of ∫F dδ is its
hysteretic (dissipated) energy E_h = W − F²/(2k), the ledger term ``hysteretic``.

Damage: story ductility μ = max|δ|/δ_y, and the Park–Ang index [3]_

    D = δ_m/δ_u + β E_h/(F_y δ_u)

with δ_u the monotonic drift capacity (``ultimate_drift`` × height) and β (``park_ang_beta``,
0.05-0.15 for RC members).

References
----------
.. [1] Filippou, F.C., Popov, E.P., Bertero, V.V. (1983). Effects of bond deterioration on hysteretic
   behavior of reinforced concrete joints. Report UCB/EERC-83/19, University of California,
   Berkeley (the bilinear Menegotto-Pinto bounds of OpenSees ``Steel01``).
.. [2] Chopra, A.K. (2017). Dynamics of Structures, 5th ed. Pearson. Ch. 7 (elastoplastic systems:
   ductility, yield strength reduction).
.. [3] Park, Y.-J., Ang, A.H.-S. (1985). Mechanistic seismic damage model for reinforced concrete.
   J. Struct. Eng. 111(4), 722-740. doi:10.1061/(ASCE)0733-9445(1985)111:4(722)
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from pounding.errors import PoundingInputError

#: Kind id of the story family in the compiled dispatch (pounding.integrators._dispatch).
FAMILY_STORY = 1
#: Columns of a story's state row: spring force F [N] (the force it reports), δ [m], W = ∫F dδ [J].
SS_F, SS_D, SS_W = 0, 1, 2
N_STORY_STATE = 3
#: Parameters per story element: k [N/m], F_y [N], then the model's own.
N_STORY_PARAMS = 3
#: Park–Ang β when ``ultimate_drift`` is given without it (Park & Ang 1985: 0.05-0.15).
PARK_ANG_BETA = 0.05


def bilinear_story_kernel(d, dd, h, s0, s1, p):
    """Bilinear kinematic hardening (ratio b = p[2]; elastic–perfectly plastic at b = 0), exact:
    the trial force F_n + k Δδ bounded by the hardening lines b k δ ± (1 − b) F_y."""
    k, fy, b = p[0], p[1], p[2]
    f = s0[SS_F] + k * (d - s0[SS_D])
    kt = k
    upper = b * k * d + (1.0 - b) * fy
    lower = b * k * d - (1.0 - b) * fy
    if f > upper:
        f = upper
        kt = b * k
    elif f < lower:
        f = lower
        kt = b * k
    s1[SS_F] = f
    s1[SS_D] = d
    s1[SS_W] = s0[SS_W] + 0.5 * (s0[SS_F] + f) * (d - s0[SS_D])
    return f - k * d, kt - k, 0.0


def story_stored(d, f, s, p):
    """Recoverable energy [J] of a story element beyond the k δ²/2 of the assembled K:
    F²/(2k) − k δ²/2 (the whole story then holds F²/(2k))."""
    k = p[0]
    return 0.5 * s[SS_F] * s[SS_F] / k - 0.5 * k * d * d


@dataclass(frozen=True)
class StoryModel:
    """A story model: its kernel and the parameters a case file gives beyond the yield point.

    Attributes
    ----------
    name : str
        Registry name (``[[building]] stories = { model = ... }``).
    kernel_id : int
        Law id within the story family (the compiled dispatch switches on it); −1 for ``elastic``
        (assembled into K, no element).
    kernel : callable or None
        ``kernel(d, dd, h, s0, s1, p)``.
    parameters : tuple of (key, units, default, low, high)
        Model keys packed into ``p`` after k and F_y, in order.
    formula, reference, opensees : str
        For ``pounding laws`` and reports; ``opensees`` names the equivalent uniaxial material.
    """

    name: str
    kernel_id: int
    kernel: Callable | None
    parameters: tuple[tuple[str, str, float, float, float], ...]
    formula: str
    reference: str
    opensees: str


_MODELS = (
    StoryModel("elastic", -1, None, (), "F = k δ", "Chopra 2017, Dynamics of Structures, Sec. 9.2",
               "Elastic"),
    StoryModel("bilinear", 1, bilinear_story_kernel, (("hardening", "", 0.0, 0.0, 1.0),),
               "F_n + k Δδ bounded by b k δ ± (1 − b) F_y",
               "Chopra 2017, Dynamics of Structures, Ch. 7; Filippou et al. 1983 (Steel01)",
               "Steel01 Fy E0 b (a1..a4 = 0)"),
)  # fmt: skip

#: Story models by name.
STORY_MODELS: dict[str, StoryModel] = {m.name: m for m in _MODELS}
#: Keys of a ``stories`` table common to every yielding model (beside ``model``).
_YIELD_KEYS = ("yield_drift", "yield_force")
_DAMAGE_KEYS = ("ultimate_drift", "park_ang_beta")


def _per_story(value: Any, n: int, where: str, unit: str, low: float, high: float) -> np.ndarray:
    """A scalar (every story) or one value per story, finite and within [low, high]."""
    try:
        array = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise PoundingInputError(f"{where} = {value!r}; allowed: a number or {n} numbers") from None
    if isinstance(value, bool) or array.ndim > 1:
        raise PoundingInputError(f"{where} = {value!r}; allowed: a number or {n} numbers")
    if array.ndim == 1 and array.size != n:
        raise PoundingInputError(
            f"{where} has {array.size} values; allowed: one number, or {n} (one per story)"
        )
    array = np.broadcast_to(array, (n,)).copy()
    bad = np.flatnonzero(~(np.isfinite(array) & (array >= low) & (array <= high)))
    if bad.size:
        i = int(bad[0])
        raise PoundingInputError(
            f"{where}[{i}] = {array[i]:g}{' ' + unit if unit else ''}; allowed: {low:g} to {high:g}"
        )
    return array


@dataclass(frozen=True)
class Stories:
    """The story model of a building and its parameters (scalars, or one value per story).

    Parameters
    ----------
    model : str
        A name of :data:`STORY_MODELS` (default ``"elastic"``).
    parameters : mapping
        ``yield_drift`` (δ_y / h, dimensionless) or ``yield_force`` (F_y [N]) for a yielding model,
        the model's own keys (``bilinear``: ``hardening`` b), and optionally ``ultimate_drift``
        (δ_u / h) and ``park_ang_beta`` for the Park–Ang damage index.
    """

    model: str = "elastic"
    parameters: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.model not in STORY_MODELS:
            raise PoundingInputError(
                f"stories.model = {self.model!r}; allowed: {', '.join(STORY_MODELS)}"
            )
        model = STORY_MODELS[self.model]
        allowed = [k for k, *_ in model.parameters] + list(_DAMAGE_KEYS)
        if model.kernel is not None:
            allowed[:0] = _YIELD_KEYS
        unknown = sorted(set(self.parameters) - set(allowed))
        if unknown:
            raise PoundingInputError(
                f"stories.{unknown[0]}: not a parameter of the {self.model!r} story model; "
                f"allowed: {', '.join(allowed) or '(none)'}"
            )
        given = [k for k in _YIELD_KEYS if k in self.parameters]
        if model.kernel is not None and len(given) != 1:
            raise PoundingInputError(
                f"stories: the {self.model!r} model needs exactly one of yield_drift "
                f"(δ_y/h, e.g. 0.005) or yield_force [N]; given: {', '.join(given) or 'neither'}"
            )
        if "park_ang_beta" in self.parameters and "ultimate_drift" not in self.parameters:
            raise PoundingInputError(
                "stories.park_ang_beta needs stories.ultimate_drift (δ_u/h) for the Park–Ang index"
            )

    @property
    def yielding(self) -> bool:
        """True for a hysteretic model (story elements), False for ``elastic``."""
        return STORY_MODELS[self.model].kernel is not None

    def to_dict(self) -> dict[str, Any]:
        """The case file's ``stories`` table."""
        out = {
            k: (v.tolist() if isinstance(v, np.ndarray) else v) for k, v in self.parameters.items()
        }
        return {"model": self.model, **out}

    def element_parameters(
        self, stiffnesses: np.ndarray, heights: np.ndarray, where: str
    ) -> np.ndarray:
        """(n × :data:`N_STORY_PARAMS`) rows (k, F_y, model parameters) of the story elements."""
        n = stiffnesses.size
        model = STORY_MODELS[self.model]
        p = self.parameters
        if "yield_drift" in p:
            drift = _per_story(p["yield_drift"], n, f"{where}.stories.yield_drift", "", 0.0, 1.0)
            if np.any(drift == 0.0):
                raise PoundingInputError(f"{where}.stories.yield_drift must be positive")
            fy = stiffnesses * drift * heights
        else:
            fy = _per_story(p["yield_force"], n, f"{where}.stories.yield_force", "N", 0.0, 1e15)
            if np.any(fy == 0.0):
                raise PoundingInputError(f"{where}.stories.yield_force must be positive [N]")
        rows = np.zeros((n, N_STORY_PARAMS))
        rows[:, 0] = stiffnesses
        rows[:, 1] = fy
        for j, (key, unit, default, low, high) in enumerate(model.parameters):
            rows[:, 2 + j] = _per_story(
                p.get(key, default), n, f"{where}.stories.{key}", unit, low, high
            )
        return rows

    def ultimate_drift(self, n: int, where: str) -> np.ndarray | None:
        """δ_u / h per story, or None when not given."""
        if "ultimate_drift" not in self.parameters:
            return None
        value = self.parameters["ultimate_drift"]
        out = _per_story(value, n, f"{where}.stories.ultimate_drift", "", 0.0, 10.0)
        if np.any(out == 0.0):
            raise PoundingInputError(f"{where}.stories.ultimate_drift must be positive")
        return out

    @property
    def park_ang_beta(self) -> float:
        """β of the Park–Ang index (default :data:`PARK_ANG_BETA`)."""
        beta = float(self.parameters.get("park_ang_beta", PARK_ANG_BETA))
        if not (math.isfinite(beta) and beta >= 0.0):
            raise PoundingInputError(f"stories.park_ang_beta = {beta}; allowed: ≥ 0")
        return beta


def park_ang(
    peak_drift: np.ndarray, ultimate: np.ndarray, e_h: np.ndarray, fy: np.ndarray, beta: float
) -> np.ndarray:
    """Park–Ang damage index D = δ_m/δ_u + β E_h/(F_y δ_u) [3]_: peak and ultimate drift [m],
    hysteretic energy E_h [J], yield force F_y [N]."""
    return peak_drift / ultimate + beta * e_h / (fy * ultimate)
