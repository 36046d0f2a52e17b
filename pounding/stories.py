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

Models (``stories.model``) and their parameters beyond ``yield_drift`` (δ_y/h) or ``yield_force``
(F_y [N]):

``elastic``
    F = k δ (no parameters).
``bilinear`` [1]_, [2]_
    F = min(max(F_n + k Δδ, b k δ − (1 − b) F_y), b k δ + (1 − b) F_y): kinematic hardening,
    elastic–perfectly plastic at b = 0; ``hardening`` b.
``bouc_wen`` [4]_, [5]_
    F = α k δ + (1 − α) F_y ζ with δ_y dζ/dδ = [A − ν (β sgn(δ̇ ζ) + γ) abs(ζ)^n]/η,
    A(ε) = A − δ_A ε, ν = 1 + δ_ν ε, η = 1 + δ_η ε; ``hardening`` α, ``n``, ``beta``, ``gamma``,
    ``A``, ``delta_a``, ``delta_nu``, ``delta_eta``.

The bilinear update bounds the trial force by the two hardening lines, so it is exact for any
step (the return map of kinematic hardening; OpenSees ``Steel01`` with a1 = a3 = 0): unloading is
elastic with slope k over an elastic range of 2 F_y, the tangent is k inside it and b k on the
hardening lines.

The Bouc–Wen variable is normalised, ζ = z/δ_y (δ_y = F_y/k), so β and γ are dimensionless
(β + γ = 1 with A = 1 bounds abs(ζ) by 1: the force tends to the yield force F_y on the α-line) and
the degradation acts on the normalised hysteretic energy ε = (1 − α) ∫ζ dδ/δ_y, the work of the
hysteretic spring over F_y δ_y. OpenSees ``BoucWen``: alpha = α, ko = k, n, gamma = γ/δ_y^n,
beta = β/δ_y^n, Ao = A, deltaA = δ_A/(F_y δ_y), deltaNu = δ_ν/(F_y δ_y), deltaEta = δ_η/(F_y δ_y).
ζ and ε are integrated over each drift increment by classical RK4 in sub-steps of at most
``BW_STEP`` δ_y (the monotonic closed forms are met to 1e-9).

Recoverable energy of a story is F²/(2k) (unloading at slope k); the rest of ∫F dδ is its
hysteretic (dissipated) energy E_h = W − F²/(2k), the ledger term ``hysteretic`` (Bouc–Wen:
α k δ²/2 + (1 − α) F_y δ_y ζ²/2 is recoverable).

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
.. [4] Wen, Y.-K. (1976). Method for random vibration of hysteretic systems. J. Eng. Mech. Div.
   102(EM2), 249-263.
.. [5] Baber, T.T., Noori, M.N. (1985). Random vibration of degrading, pinching systems. J. Eng.
   Mech. 111(8), 1010-1026. doi:10.1061/(ASCE)0733-9399(1985)111:8(1010)
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
#: Columns of a story's state row: spring force F [N] (the force it reports), δ [m], W = ∫F dδ [J],
#: the recoverable energy E [J] it holds; then the model's own (Bouc–Wen: ζ, ε).
SS_F, SS_D, SS_W, SS_E, SS_Z, SS_EPS = 0, 1, 2, 3, 4, 5
N_STORY_STATE = 6
#: Parameters per story element: k [N/m], F_y [N], then the model's own (Bouc–Wen: 8).
N_STORY_PARAMS = 10
#: Largest Bouc–Wen sub-step, as a fraction of δ_y (classical RK4 per sub-step).
BW_STEP = 0.02
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
    s1[SS_E] = 0.5 * f * f / k
    return f - k * d, kt - k, 0.0


def bouc_wen_story_kernel(d, dd, h, s0, s1, p):
    """Bouc–Wen story [4]_, [5]_: F = α k δ + (1 − α) F_y ζ, ζ and ε integrated over the drift
    increment by classical RK4 sub-steps of at most BW_STEP δ_y; tangent α k + (1 − α) k δ_y dζ/dx
    at the end."""
    k, fy, alpha, n, beta, gamma = p[0], p[1], p[2], p[3], p[4], p[5]
    a0, d_a, d_nu, d_eta = p[6], p[7], p[8], p[9]
    dy = fy / k
    dx = d - s0[SS_D]
    sgn = 1.0 if dx >= 0.0 else -1.0

    def slope(z, eps):
        # δ_y dζ/dx: A = A0 − δ_A ε, ν = 1 + δ_ν ε, η = 1 + δ_η ε; β acts on sgn(δ̇ ζ)
        psi = gamma + (beta if sgn * z > 0.0 else -beta if sgn * z < 0.0 else 0.0)
        az = abs(z)
        zn = az * az if n == 2.0 else az if n == 1.0 else az**n  # pow() is most of the cost
        return ((a0 - d_a * eps) - (1.0 + d_nu * eps) * psi * zn) / (1.0 + d_eta * eps)

    m = max(1, min(int(math.ceil(abs(dx) / (BW_STEP * dy))), 100000))
    hx = dx / m / dy  # the sub-step in units of δ_y
    z = s0[SS_Z]
    eps = s0[SS_EPS]
    c = 1.0 - alpha  # dε/dx δ_y = (1 − α) ζ
    for _ in range(m):
        g1 = slope(z, eps)
        g2 = slope(z + 0.5 * hx * g1, eps + 0.5 * hx * c * z)
        z2 = z + 0.5 * hx * g1
        g3 = slope(z + 0.5 * hx * g2, eps + 0.5 * hx * c * z2)
        z3 = z + 0.5 * hx * g2
        g4 = slope(z + hx * g3, eps + hx * c * z3)
        z4 = z + hx * g3
        eps += hx * c * (z + 2.0 * z2 + 2.0 * z3 + z4) / 6.0
        z += hx * (g1 + 2.0 * g2 + 2.0 * g3 + g4) / 6.0
    g = slope(z, eps)
    f = alpha * k * d + c * fy * z
    s1[SS_F] = f
    s1[SS_D] = d
    s1[SS_W] = s0[SS_W] + 0.5 * (s0[SS_F] + f) * dx
    s1[SS_E] = 0.5 * alpha * k * d * d + 0.5 * c * fy * dy * z * z
    s1[SS_Z] = z
    s1[SS_EPS] = eps
    return f - k * d, k * (alpha + c * g) - k, 0.0


def story_stored(d, f, s, p):
    """Recoverable energy [J] of a story element beyond the k δ²/2 of the assembled K (the whole
    story then holds the E of its state: F²/(2k) for the bilinear model)."""
    return s[SS_E] - 0.5 * p[0] * d * d


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
    StoryModel("bouc_wen", 2, bouc_wen_story_kernel,
               (("hardening", "", 0.0, 0.0, 1.0), ("n", "", 2.0, 0.1, 50.0),
                ("beta", "", 0.5, -10.0, 10.0), ("gamma", "", 0.5, -10.0, 10.0),
                ("A", "", 1.0, 0.0, 10.0), ("delta_a", "", 0.0, 0.0, 10.0),
                ("delta_nu", "", 0.0, 0.0, 10.0), ("delta_eta", "", 0.0, 0.0, 10.0)),
               "F = α k δ + (1 − α) F_y ζ, δ_y ζ' = [A − ν (β sgn(δ̇ ζ) + γ) |ζ|^n]/η",
               "Wen 1976; Baber & Noori 1985 (degradation)",
               "BoucWen alpha=α ko=k n gamma=γ/δ_y^n beta=β/δ_y^n Ao=A (deltas: see docs)"),
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
        beta = self.parameters.get("park_ang_beta", PARK_ANG_BETA)
        if (
            isinstance(beta, bool)
            or not isinstance(beta, int | float)
            or not 0.0 <= beta < math.inf
        ):
            raise PoundingInputError(f"stories.park_ang_beta = {beta!r}; allowed: a number ≥ 0")

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
        if self.model == "bouc_wen" and np.any(rows[:, 4] + rows[:, 5] <= 0.0):
            raise PoundingInputError(
                f"{where}.stories: beta + gamma = {float(np.min(rows[:, 4] + rows[:, 5])):g}; "
                "allowed: beta + gamma > 0 (a bounded ζ; 1 with A = 1 gives the yield force)"
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
        return float(self.parameters.get("park_ang_beta", PARK_ANG_BETA))


def park_ang(
    peak_drift: np.ndarray, ultimate: np.ndarray, e_h: np.ndarray, fy: np.ndarray, beta: float
) -> np.ndarray:
    """Park–Ang damage index D = δ_m/δ_u + β E_h/(F_y δ_u) [3]_: peak and ultimate drift [m],
    hysteretic energy E_h [J], yield force F_y [N]."""
    return peak_drift / ultimate + beta * e_h / (fy * ultimate)
