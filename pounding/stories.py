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
``p`` = (k [N/m], F_y [N], model parameters...). The piecewise-linear models also write the next
point ahead where the path may turn and the slope up to it: the compiled core takes a further
increment short of it as a straight line without the kernel (:func:`story_straight`).

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
    ``A``, ``delta_a``, ``delta_nu``, ``delta_eta``; pinching [8]_ multiplies δ_y dζ/dδ by
    h = 1 − ζ1 exp(−(ζ sgn δ̇ − q ζ_u)²/ζ2²), ζ1 = ζ_s (1 − exp(−p ε)), ζ2 = (ψ + δ_ψ ε)(λ + ζ1),
    ζ_u = [A/(ν (β + γ))]^(1/n): ``zeta_s`` (0, no pinching, to < 1), ``p``, ``q``, ``psi``,
    ``delta_psi``, ``lambda`` (ψ and ζ_u in units of δ_y, ε normalised as below).
``takeda`` [6]_, [7]_
    Peak-oriented stiffness degradation of reinforced concrete on the bilinear backbone k,
    (δ_y, F_y), b k: unloading at k_u = k (δ_m/δ_y)^(−a) (δ_m the peak drift on that side) down to
    zero force, reloading along the line to the opposite side's peak (the yield point before it
    yields), a partial unloading reloads at k_u until it meets that line; ``hardening`` b,
    ``unloading_exponent`` a (0.4 Takeda; 0 is Clough's model). Exact for any monotone drift
    increment (the branch changes within it are followed); OpenSees ``Hysteretic`` with
    pinchX = pinchY = 1, damage1 = damage2 = 0, beta = a on the same backbone.
``imk`` [9]_
    Ibarra–Medina–Krawinkler peak-oriented model with capping and cyclic deterioration (the
    collapse-capable model). Backbone per side: k to (δ_y, F_y), α_s k (``hardening``) to the cap at
    δ_y + δ_p (``plastic_drift`` δ_p/h), then the post-cap slope −F_c/δ_pc (``post_cap_drift``
    δ_pc/h from the cap to zero force) down to the residual κ F_y (``residual``). Unloading at K_u
    to zero force, reloading to the target (the peak drift reached on that side) on the current
    backbone; through the side's local peak first (where its last unloading began below the
    target) when the line to that point is the steeper, as OpenSees ``ModIMKPeakOriented``; a
    partial unloading reloads at K_u until it meets that path. Each mode x (strength s, post-cap
    c, accelerated reloading a, unloading stiffness k) has an energy capacity E_t = γ_x F_y δ_y
    (``gamma_s`` ... ``gamma_k``; 0 = off) and β = (E_i/(E_t − ΣE))^c (``c``): at each zero-force
    crossing the side about to be loaded loses F_y, α_s ← (1 − β_s), F_ref ← (1 − β_c) (the
    post-cap line moves in), its target drift grows by (1 + β_a); at each reversal
    K_u ← (1 − β_k) K_u (E_i: hysteretic energy since the last crossing, resp. reversal), but no
    lower than the line from the reversal to the target (and to the local peak) ahead: a softer
    unloading line passes inside the target, the reload from its zero-force drift is steeper than
    the unloading and the loop runs backwards, generating energy. A spent capacity (β = 1) fails
    the story: no force from then on.

The bilinear update bounds the trial force by the two hardening lines, so it is exact for any
step (the return map of kinematic hardening; OpenSees ``Steel01`` with a1 = a3 = 0): unloading is
elastic with slope k over an elastic range of 2 F_y, the tangent is k inside it and b k on the
hardening lines.

The Bouc–Wen variable is normalised, ζ = z/δ_y (δ_y = F_y/k), so β and γ are dimensionless
(β + γ = 1 with A = 1 bounds abs(ζ) by 1: the force tends to the yield force F_y on the α-line) and
the degradation acts on the normalised hysteretic energy ε = (1 − α) ∫ζ dδ/δ_y, the work of the
hysteretic spring over F_y δ_y. OpenSees ``BoucWen``: alpha = α, ko = k, n, gamma = γ/δ_y^n,
beta = β/δ_y^n, Ao = A, deltaA = δ_A/(F_y δ_y), deltaNu = δ_ν/(F_y δ_y), deltaEta = δ_η/(F_y δ_y).
With n = 1 or 2 and neither degradation nor pinching (Wen's model, the default), each drift
increment is integrated exactly: on each side of ζ = 0, ψ is constant and dζ/dx = A − ψ abs(ζ)^n
is a Riccati equation (n = 2: ζ = u/v with (u, v)' = (A v, ψ u), a linear system whose propagator
is cosh/sinh, or cos/sin) or a linear one (n = 1: an exponential), each summed by its series to
round-off in sub-steps of at most ``BW_STEP`` δ_y (shorter for a large ψ), and an increment through
ζ = 0 is split there.
Otherwise ζ and ε are integrated by classical RK4 in those sub-steps (the monotonic closed forms
are met to 1e-9).

Recoverable energy of a story is F²/(2k) (unloading at slope k; Takeda F²/(2 k_u)); the rest of
∫F dδ is its hysteretic (dissipated) energy E_h = W − F²/(2k), the ledger term ``hysteretic``
(Bouc–Wen: α k δ²/2 + (1 − α) F_y δ_y ζ²/2 is recoverable).

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
.. [6] Takeda, T., Sozen, M.A., Nielsen, N.N. (1970). Reinforced concrete response to simulated
   earthquakes. J. Struct. Div. 96(ST12), 2557-2573.
.. [7] Otani, S. (1981). Hysteresis models of reinforced concrete for earthquake response analysis.
   J. Fac. Eng. Univ. Tokyo 36(2), 407-441 (Clough & Johnston 1966 and Takeda rules).
.. [8] Foliente, G.C. (1995). Hysteresis modeling of wood joints and structural systems. J. Struct.
   Eng. 121(6), 1013-1022. doi:10.1061/(ASCE)0733-9445(1995)121:6(1013)
.. [9] Ibarra, L.F., Medina, R.A., Krawinkler, H. (2005). Hysteretic models that incorporate
   strength and stiffness deterioration. Earthquake Eng. Struct. Dyn. 34(12), 1489-1511.
   doi:10.1002/eqe.495
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
#: the recoverable energy E [J] it holds; then the model's own (Bouc–Wen: ζ, ε, the rate
#: δ_y dζ/dδ at the state and the direction it was taken in (0: none yet); Takeda: the peak
#: drifts [m] reached on each side, the zero-force drifts [m] the reloads start from, the direction
#: of the last increment).
SS_F, SS_D, SS_W, SS_E, SS_Z, SS_EPS, SS_G, SS_G_DIR = 0, 1, 2, 3, 4, 5, 6, 7
SS_PEAK_POS, SS_PEAK_NEG, SS_ZERO_POS, SS_ZERO_NEG, SS_DIR = 4, 5, 6, 7, 8
#: Takeda: the unloading stiffnesses [N/m] at those peaks, 0 until first computed (pow() of a
#: non-integer exponent was most of the kernel's cost at every call; the peaks rarely change).
SS_KU_POS, SS_KU_NEG = 9, 10
#: IMK: the direction and the zero-force drifts as Takeda's, then the strength and post-cap
#: fractions lost on each side, the unloading-stiffness fraction lost, the target drifts [m], the
#: hysteretic energy [J] at the last reversal and the work [J] at the last zero-force crossing, a
#: failed flag (an energy capacity spent: no force any more), and the exact work ∫F dδ [J] along
#: the path (W is the trapezoid per step, the energy ledger's own quadrature).
SS_DS_POS, SS_DS_NEG, SS_DC_POS, SS_DC_NEG, SS_DK = 9, 10, 11, 12, 13
SS_T_POS, SS_T_NEG, SS_E_REV, SS_W_CROSS, SS_FAILED, SS_WX = 14, 15, 16, 17, 18, 19
#: IMK: the local peak of each side (drift [m] and force [N] where its last unloading began below
#: its target; a force of 0 when there is none).
SS_LD_POS, SS_LF_POS, SS_LD_NEG, SS_LF_NEG = 20, 21, 22, 23
#: Every model with straight branches (bilinear, Takeda, IMK): after each evaluation, the drift [m]
#: of the next point ahead where the path may turn, in the direction of the increment (``SS_DIR``),
#: the slope [N/m] of the path up to it, and 1/(2 k_e) [m/N] of the recoverable energy F²/(2 k_e)
#: along it: a further increment in that direction short of that point is straight
#: (:func:`story_straight`). ``SS_NEXT`` at the drift itself bars the shortcut (a branch that moves
#: other state: a failed story). A Takeda peak or IMK target pushed along the backbone is left
#: behind by such increments and brought up to the drift at the kernel's next call.
SS_NEXT, SS_KT, SS_EK = 24, 25, 26
N_STORY_STATE = 27
#: Takeda's model id (:data:`STORY_MODELS`), for :func:`story_energy`.
TAKEDA_ID = 3
#: Parameters per story element: k [N/m], F_y [N], then the model's own (Bouc–Wen: 14;
#: drift parameters in metres).
N_STORY_PARAMS = 16
#: Largest Bouc–Wen sub-step, as a fraction of δ_y (classical RK4 per sub-step).
BW_STEP = 0.02
#: Park–Ang β when ``ultimate_drift`` is given without it (Park & Ang 1985: 0.05-0.15).
PARK_ANG_BETA = 0.05


def story_straight(d, state, trial, p, e):
    """A drift increment of story row ``e`` (of the committed ``state``, ``trial`` state and
    parameter ``p`` rows) to ``d`` [m] that continues the last one short of the next point where
    the path may turn (``SS_NEXT``): F = F_n + k_t Δδ on the slope up to it (``SS_KT``), and only F,
    δ, the work, the exact work ``SS_WX`` and E = F²/(2 k_e) change. Returns (True, F − k δ,
    k_t − k) then, what the model's kernel gives to round-off; (False, 0, 0) when the increment is
    not such (the kernel takes it). Most increments of an analysis are: this skips the kernel's
    branches. (Rows by index, not views: a view per call costs the element loop its reference
    counts.)"""
    f0 = state[e, SS_F]
    dx = d - state[e, SS_D]
    if not (dx * state[e, SS_DIR] > 0.0 and dx * (d - state[e, SS_NEXT]) < 0.0):
        return False, 0.0, 0.0
    kt = state[e, SS_KT]
    f = f0 + kt * dx
    dw = 0.5 * (f0 + f) * dx
    trial[e, SS_F] = f
    trial[e, SS_D] = d
    trial[e, SS_W] = state[e, SS_W] + dw
    trial[e, SS_WX] = state[e, SS_WX] + dw
    trial[e, SS_E] = state[e, SS_EK] * f * f
    return True, f - p[e, 0] * d, kt - p[e, 0]


def bilinear_story_kernel(d, dd, h, s0, s1, p):
    """Bilinear kinematic hardening (ratio b = p[2]; elastic–perfectly plastic at b = 0), exact:
    the trial force F_n + k Δδ bounded by the hardening lines b k δ ± (1 − b) F_y."""
    k, fy, b = p[0], p[1], p[2]
    dx = d - s0[SS_D]
    f = s0[SS_F] + k * dx
    kt = k
    upper = b * k * d + (1.0 - b) * fy
    lower = b * k * d - (1.0 - b) * fy
    sgn = 1.0 if dx > 0.0 else -1.0
    # ahead: the other hardening line, reached at slope k; on a hardening line, straight on
    ahead = d + (upper - f if dx > 0.0 else lower - f) / (k - b * k) if b < 1.0 else sgn * math.inf
    if f > upper:
        f = upper
        kt = b * k
        ahead = math.inf
    elif f < lower:
        f = lower
        kt = b * k
        ahead = -math.inf
    s1[SS_F] = f
    s1[SS_D] = d
    s1[SS_W] = s0[SS_W] + 0.5 * (s0[SS_F] + f) * dx
    s1[SS_E] = 0.5 * f * f / k
    # the straight path ahead (story_straight)
    s1[SS_DIR] = sgn
    s1[SS_NEXT] = ahead if dx != 0.0 else d
    s1[SS_KT] = kt
    s1[SS_EK] = 0.5 / k
    return f - k * d, kt - k, 0.0


def bouc_wen_story_rate(z, eps, sgn, p, e):
    """δ_y dζ/dδ of a Bouc–Wen story [4]_, [5]_ at (ζ, ε) moving in direction sgn (±1):
    h(ζ, ε) [A − ν (β sgn(δ̇ ζ) + γ) abs(ζ)^n]/η with A = A0 − δ_A ε, ν = 1 + δ_ν ε,
    η = 1 + δ_η ε and the pinching factor h of Foliente [8]_ (1 when ζ_s = 0); ``p`` the parameter
    rows, ``e`` the story's."""
    n, beta, gamma = p[e, 3], p[e, 4], p[e, 5]
    a = p[e, 6] - p[e, 7] * eps
    nu = 1.0 + p[e, 8] * eps
    psi = gamma + (beta if sgn * z > 0.0 else -beta if sgn * z < 0.0 else 0.0)
    az = abs(z)
    zn = az * az if n == 2.0 else az if n == 1.0 else az**n  # pow() is most of the cost
    g = a - nu * psi * zn
    if p[e, 9] != 0.0:  # a division on every RK4 stage's dependency chain otherwise
        g /= 1.0 + p[e, 9] * eps
    zeta_s = p[e, 10]
    if zeta_s > 0.0:
        # h = 1 − ζ1 exp(−(ζ sgn − q ζ_u)²/ζ2²), ζ1 = ζ_s (1 − e^(−p ε)), ζ2 = (ψ + δ_ψ ε)(λ + ζ1)
        z_u = (max(a, 0.0) / (nu * (beta + gamma))) ** (1.0 / n)
        z1 = zeta_s * (1.0 - math.exp(-p[e, 11] * eps))
        z2 = (p[e, 13] + p[e, 14] * eps) * (p[e, 15] + z1)
        x = (sgn * z - p[e, 12] * z_u) / z2
        g *= 1.0 - z1 * math.exp(-x * x)
    return g


def bouc_wen_story_finish(d, dx, z, eps, g, sgn, state, trial, p, e):
    """The end of a Bouc–Wen increment dx [m] to drift d at (ζ, ε) with rate g in direction sgn:
    F = α k δ + (1 − α) F_y ζ, its work and recoverable energy written into row ``e`` of
    ``trial`` (from that of the committed ``state``; ``p`` the parameter rows); returns
    (F − k δ, k_t − k), k_t = α k + (1 − α) k δ_y dζ/dx."""
    k, fy, alpha = p[e, 0], p[e, 1], p[e, 2]
    c = 1.0 - alpha
    f = alpha * k * d + c * fy * z
    trial[e, SS_F] = f
    trial[e, SS_D] = d
    trial[e, SS_W] = state[e, SS_W] + 0.5 * (state[e, SS_F] + f) * dx
    trial[e, SS_E] = 0.5 * alpha * k * d * d + 0.5 * c * fy * (fy / k) * z * z
    trial[e, SS_Z] = z
    trial[e, SS_EPS] = eps
    trial[e, SS_G] = g
    trial[e, SS_G_DIR] = sgn
    return f - k * d, k * (alpha + c * g) - k


#: The state columns a Bouc–Wen story writes (F, δ, W, E, ζ, ε, the rate and its direction).
BW_COLUMNS = 8


def bouc_wen_piece(z, x, a, beta, gamma, side, sgn, n2):
    """ζ after a drift x [δ_y] (direction sgn) from ζ on one side of ζ = 0 (side +1: loading,
    sgn ζ ≥ 0; −1: unloading) of a Bouc–Wen story with n = 2 (``n2``) or 1 and neither
    degradation nor pinching, and ∫ζ dx over it; (ζ, 0, False) when x is too long for the series.

    On a side, ψ is constant and ζ' = A + q ζ² (n = 2, q = −ψ) is a Riccati equation: ζ = u/v with
    (u, v)' = (A v, −q u), so ζ(x) = (C ζ + A S)/(C − q S ζ), C = cosh(λx), S = sinh(λx)/λ,
    λ² = −A q (cos and sin for λ² < 0; their series in t = λ² x², to round-off for abs(t) ≤ 0.01).
    With n = 1, ζ' = A + q ζ (q = −ψ sign ζ) is linear: ζ(x) = ζ + x ζ' (eˣᵠ − 1)/(x q). Both exact;
    ∫ζ dx from the Taylor series of ζ to x⁵."""
    q = -(gamma + side * beta)
    if n2:
        g1 = a + q * z * z
        t = -a * q * x * x
        c = 1.0 + t * (0.5 + t * (1 / 24 + t * (1 / 720 + t * (1 / 40320 + t * (1 / 3628800)))))
        s = x * (
            1.0
            + t * (1 / 6 + t * (1 / 120 + t * (1 / 5040 + t * (1 / 362880 + t * (1 / 39916800)))))
        )
        den = c - q * s * z
        if abs(t) > 0.01 or den < 0.5:
            return z, 0.0, False
        z1 = (c * z + a * s) / den
        q *= 2.0
        z2 = q * z * g1
        z3 = q * (g1 * g1 + z * z2)
        z4 = q * (3.0 * g1 * z2 + z * z3)
    else:
        q *= side * sgn
        g1 = a + q * z
        y = q * x
        if abs(y) > 0.05:
            return z, 0.0, False
        e1 = 1.0  # (eʸ − 1)/y = 1 + y/2 (1 + y/3 (1 + …)), to y⁸/9!
        for j in range(9, 1, -1):
            e1 = 1.0 + y * e1 / j
        z1 = z + x * g1 * e1
        z2 = q * g1
        z3 = q * z2
        z4 = q * z3
    w = x * (z + x * (0.5 * g1 + x * (z2 * (1 / 6) + x * (z3 * (1 / 24) + x * (z4 * (1 / 120))))))
    return z1, w, True


def bouc_wen_zero(z, a, beta, gamma, sgn, n2):
    """The drift [δ_y] at which ζ (unloading: sgn ζ < 0) of :func:`bouc_wen_piece` reaches 0 (A > 0):
    C ζ + A S = 0 (n = 2) or (ζ + A/q) e^(q x) = A/q (n = 1)."""
    q = beta - gamma  # −ψ on the unloading side
    if n2:
        lam2 = -a * q
        if lam2 > 0.0:
            r = math.sqrt(lam2)
            y = -r * z / a
            return math.atanh(y) / r if abs(y) < 1.0 else math.copysign(math.inf, y)
        if lam2 < 0.0:
            r = math.sqrt(-lam2)
            return math.atan(-r * z / a) / r
        return -z / a
    q *= -sgn  # −ψ sign ζ, sign ζ = −sgn
    return -math.log1p(q * z / a) / q if q != 0.0 else -z / a


def make_bouc_wen_path(piece, zero):
    """The exact Bouc–Wen increment of :func:`bouc_wen_piece` over sub-steps and through ζ = 0, on
    a given ``piece`` and ``zero`` (:func:`bouc_wen_zero`; plain or compiled)."""

    def bouc_wen_path(z, hx, m, a, beta, gamma, sgn, n2):
        """ζ after m sub-steps of hx [δ_y] from ζ, each split where ζ crosses 0 on the unloading
        side (ψ changes there), and ∫ζ dx over them; (ζ, 0, False) when a sub-step is too long
        for the series."""
        w = 0.0
        for _ in range(m):
            x = hx
            for _ in range(2):  # up to ζ = 0 on the unloading side, then on
                side = -1.0 if sgn * z < 0.0 else 1.0
                z1, wx, ok = piece(z, x, a, beta, gamma, side, sgn, n2)
                rest = 0.0
                if ok and side < 0.0 and sgn * z1 > 0.0 and a > 0.0:
                    x0 = zero(z, a, beta, gamma, sgn, n2)
                    if 0.0 < x0 * sgn < x * sgn:
                        _, wx, ok = piece(z, x0, a, beta, gamma, side, sgn, n2)
                        z1 = 0.0
                        rest = x - x0
                if not ok:
                    return z, 0.0, False
                z = z1
                w += wx
                if rest == 0.0:
                    break
                x = rest
        return z, w, True

    return bouc_wen_path


def make_bouc_wen_story_exact(piece, path, finish):
    """The exact Bouc–Wen increment of a story row on a given ``piece``, ``path`` and ``finish``
    (:func:`bouc_wen_piece`, :func:`make_bouc_wen_path`, :func:`bouc_wen_story_finish`; plain or
    compiled)."""

    def bouc_wen_story_exact(d, state, trial, p, e):
        """A Bouc–Wen story with n = 1 or 2 and neither degradation nor pinching (row ``e`` of the
        committed ``state``, ``trial`` and parameter ``p`` rows) at drift ``d`` [m], each sub-step
        exact (:func:`bouc_wen_piece`, split where ζ crosses 0 and ψ changes). Returns (True,
        F − k δ, k_t − k); (False, 0, 0) for other parameters or where ζ grows too fast for the
        series (RK4 takes it: :func:`make_bouc_wen_story_rk4`)."""
        n = p[e, 3]
        if not ((n == 2.0 or n == 1.0) and p[e, 7] == p[e, 8] == p[e, 9] == p[e, 10] == 0.0):
            return False, 0.0, 0.0
        k, fy, alpha = p[e, 0], p[e, 1], p[e, 2]
        a, beta, gamma = p[e, 6], p[e, 4], p[e, 5]
        n2 = n == 2.0
        dx = d - state[e, SS_D]
        sgn = 1.0 if dx >= 0.0 else -1.0
        hx = dx * (k / fy)  # the increment in units of δ_y
        z = state[e, SS_Z]
        # sub-steps within the series' range (bouc_wen_piece) for the largest ψ
        psi = abs(gamma) + abs(beta)
        h_max = BW_STEP
        if n2 and a * psi * BW_STEP * BW_STEP > 0.0098:
            h_max = 0.099 / math.sqrt(a * psi)
        elif not n2 and psi * BW_STEP > 0.049:
            h_max = 0.049 / psi
        ok = False
        if abs(hx) <= h_max:  # most increments of a step: one piece
            side = -1.0 if sgn * z < 0.0 else 1.0  # at ζ = 0 the path leaves on the loading side
            z1, w, ok = piece(z, hx, a, beta, gamma, side, sgn, n2)
            ok = ok and (side > 0.0 or sgn * z1 <= 0.0 or a <= 0.0)
        if not ok:  # sub-steps, or ζ crossed 0 (where ψ changes)
            m = max(1, min(int(math.ceil(abs(hx) / h_max)), 100000))
            z1, w, ok = path(z, hx / m, m, a, beta, gamma, sgn, n2)
            if not ok:
                return False, 0.0, 0.0
        q = -(gamma - beta if sgn * z1 < 0.0 else gamma + beta)  # the rate at the end
        g = a + q * (z1 * z1 if n2 else abs(z1))
        eps = state[e, SS_EPS] + (1.0 - alpha) * w  # dε/dx δ_y = (1 − α) ζ
        g, kd = finish(d, dx, z1, eps, g, sgn, state, trial, p, e)
        return True, g, kd

    return bouc_wen_story_exact


def make_bouc_wen_story_rk4(rate, finish):
    """The Bouc–Wen story kernel on rows by classical RK4, on a given ``rate`` and ``finish``
    (:func:`bouc_wen_story_rate`, :func:`bouc_wen_story_finish`, plain or compiled: numba
    compiles the kernel with them as constants)."""

    def bouc_wen_story_rk4(d, state, trial, p, e):
        """Bouc–Wen story [4]_, [5]_, [8]_ of row ``e`` (of the committed ``state``, ``trial`` and
        parameter ``p`` rows: a view per call costs the element loop its reference counts) at
        drift ``d`` [m]: F = α k δ + (1 − α) F_y ζ, ζ and ε integrated over the drift increment by
        classical RK4 in sub-steps of at most BW_STEP δ_y; tangent α k + (1 − α) k δ_y dζ/dx at
        the end. Returns (F − k δ, k_t − k)."""
        k, fy, alpha = p[e, 0], p[e, 1], p[e, 2]
        dx = d - state[e, SS_D]
        sgn = 1.0 if dx >= 0.0 else -1.0
        m = max(1, min(int(math.ceil(abs(dx) * k / (BW_STEP * fy))), 100000))
        hx = dx * (k / fy) / m  # the sub-step in units of δ_y
        z = state[e, SS_Z]
        eps = state[e, SS_EPS]
        c = 1.0 - alpha  # dε/dx δ_y = (1 − α) ζ
        h6 = hx * (1.0 / 6.0)  # RK4's weights
        # the rate at the committed state in this direction: the last call's end rate, when it went
        # this way (every trial of a step starts there)
        g1 = state[e, SS_G] if state[e, SS_G_DIR] == sgn else rate(z, eps, sgn, p, e)
        for i in range(m):
            if i > 0:
                g1 = rate(z, eps, sgn, p, e)
            z2 = z + 0.5 * hx * g1
            g2 = rate(z2, eps + 0.5 * hx * c * z, sgn, p, e)
            z3 = z + 0.5 * hx * g2
            g3 = rate(z3, eps + 0.5 * hx * c * z2, sgn, p, e)
            z4 = z + hx * g3
            g4 = rate(z4, eps + hx * c * z3, sgn, p, e)
            eps += h6 * c * (z + 2.0 * z2 + 2.0 * z3 + z4)
            z += h6 * (g1 + 2.0 * g2 + 2.0 * g3 + g4)
        return finish(d, dx, z, eps, rate(z, eps, sgn, p, e), sgn, state, trial, p, e)

    return bouc_wen_story_rk4


def make_bouc_wen_story_row(exact, rk4):
    """The Bouc–Wen story kernel on rows: ``exact`` (:func:`make_bouc_wen_story_exact`) where it
    applies, else ``rk4`` (:func:`make_bouc_wen_story_rk4`)."""

    def bouc_wen_story_row(d, state, trial, p, e):
        """Bouc–Wen story of row ``e`` at drift ``d`` [m] (:func:`make_bouc_wen_story_rk4`), exact
        with n = 1 or 2 and neither degradation nor pinching (:func:`make_bouc_wen_story_exact`).
        Returns (F − k δ, k_t − k)."""
        done, g, kd = exact(d, state, trial, p, e)
        if done:
            return g, kd
        return rk4(d, state, trial, p, e)

    return bouc_wen_story_row


def make_bouc_wen_story_kernel(row):
    """The Bouc–Wen story kernel ``kernel(d, dd, h, s0, s1, p)`` of the registry on one state
    row, on a given row kernel (:func:`make_bouc_wen_story_row`)."""

    def bouc_wen_story_kernel(d, dd, h, s0, s1, p):
        """Bouc–Wen story [4]_, [5]_, [8]_ (:func:`make_bouc_wen_story_row`) from the committed
        row ``s0`` into ``s1``."""
        g, kd = row(d, s0[np.newaxis, :], s1[np.newaxis, :], p[np.newaxis, :], 0)
        return g, kd, 0.0

    return bouc_wen_story_kernel


bouc_wen_story_exact = make_bouc_wen_story_exact(
    bouc_wen_piece, make_bouc_wen_path(bouc_wen_piece, bouc_wen_zero), bouc_wen_story_finish
)
bouc_wen_story_rk4 = make_bouc_wen_story_rk4(bouc_wen_story_rate, bouc_wen_story_finish)
bouc_wen_story_row = make_bouc_wen_story_row(bouc_wen_story_exact, bouc_wen_story_rk4)
bouc_wen_story_kernel = make_bouc_wen_story_kernel(bouc_wen_story_row)

#: A Bouc–Wen drift this close to the story's trial drift, as a fraction of δ_y, continues that
#: trial along its rate (:func:`make_bouc_wen_story_near`): the terms dropped are of order
#: (Δ/δ_y)² ≤ 1e-16 of ζ.
BW_NEAR = 1e-8


def make_bouc_wen_story_near(rate, finish):
    """The Bouc–Wen story's re-evaluation near its trial drift on a given ``rate`` and ``finish``
    (plain or compiled, as :func:`make_bouc_wen_story_row`)."""

    def bouc_wen_story_near(d, state, trial, p, e):
        """A Bouc–Wen story (row ``e``, as :func:`make_bouc_wen_story_row`) at drift ``d`` [m]
        within BW_NEAR δ_y of the trial drift, which the kernel wrote from the committed state in
        one sub-step: ζ and ε continue that trial along their rates, ζ = ζ_t + (Δ/δ_y) dζ/dx,
        ε = ε_t + (Δ/δ_y)(1 − α) ζ_t, and F, the work, E and the tangent follow as in the kernel.
        Returns (True, F − k δ, k_t − k) then, what the kernel gives from the committed state to
        round-off; (False, 0, 0) otherwise (the kernel takes it). A pass of the fixed-point step
        re-evaluates each story by a correction of round-off size: this skips its sub-step."""
        k, fy, alpha = p[e, 0], p[e, 1], p[e, 2]
        dy = fy / k
        dx = d - state[e, SS_D]
        sgn = 1.0 if dx >= 0.0 else -1.0
        x = (d - trial[e, SS_D]) / dy
        if not (
            abs(x) <= BW_NEAR
            and trial[e, SS_G_DIR] == sgn
            and abs(dx) <= BW_STEP * dy
            and abs(trial[e, SS_D] - state[e, SS_D]) <= BW_STEP * dy
        ):
            return False, 0.0, 0.0
        z = trial[e, SS_Z] + x * trial[e, SS_G]
        eps = trial[e, SS_EPS] + x * (1.0 - alpha) * trial[e, SS_Z]
        g, kd = finish(d, dx, z, eps, rate(z, eps, sgn, p, e), sgn, state, trial, p, e)
        return True, g, kd

    return bouc_wen_story_near


bouc_wen_story_near = make_bouc_wen_story_near(bouc_wen_story_rate, bouc_wen_story_finish)


def takeda_story_kernel(d, dd, h, s0, s1, p):
    """Modified Takeda peak-oriented story [6]_, [7]_ on a bilinear backbone (hardening b = p[2],
    unloading exponent a = p[3]; Clough's model at a = 0), exact for a monotone drift increment.

    Unloading from the side of peak drift δ_m is at k (δ_m/δ_y)^(−a) down to zero force; the reload
    then aims at the other side's peak (δ_m', F_env(δ_m')), the yield point if that side never
    yielded; after a partial unloading it reloads at the unloading stiffness until it meets that
    line. Past the peak it follows the backbone."""
    k, fy, b, a = p[0], p[1], p[2], p[3]
    dy = fy / k

    def unloading(mu):
        # k μ^(−a) from a peak of μ = δ_m/δ_y ≥ 1
        return k if a == 0.0 else k * mu**-a

    def same_line(zero, peak, f_peak, k_here, k_other):
        # the unloading line through zero force at ``zero`` and the reload line from there to
        # (peak, f_peak) are one line, with one unloading stiffness either side of zero (the
        # elastic range): the zero crossing is no turn
        z = max(zero, peak - f_peak / k) if peak < 0.0 else min(zero, peak - f_peak / k)
        return (
            abs(z - zero) <= 1e-12 * dy
            and abs(f_peak / (peak - z) - k_here) <= 1e-12 * k
            and abs(k_other - k_here) <= 1e-12 * k
        )

    d0 = s0[SS_D]
    f0 = s0[SS_F]
    # a peak follows the drift along the backbone, and straight increments there (story_straight)
    # leave it behind: it is never short of the drift reached on its side
    pos = max(s0[SS_PEAK_POS], d0, dy)
    neg = min(s0[SS_PEAK_NEG], d0, -dy)
    pushed_pos, pushed_neg = d0 > s0[SS_PEAK_POS], d0 < s0[SS_PEAK_NEG]
    k_pos = s0[SS_KU_POS] if s0[SS_KU_POS] > 0.0 and not pushed_pos else unloading(pos / dy)
    k_neg = s0[SS_KU_NEG] if s0[SS_KU_NEG] > 0.0 and not pushed_neg else unloading(-neg / dy)
    zero_pos, zero_neg = s0[SS_ZERO_POS], s0[SS_ZERO_NEG]
    direction = s0[SS_DIR]
    dx = d - d0
    f = f0
    kt = k_pos if f0 > 0.0 else k_neg
    ahead = d  # the point ahead up to which the path is straight (story_straight); d: none
    if dx > 0.0:
        if direction <= 0.0 and f0 <= 0.0:
            zero_pos = d0 - f0 / k_neg
        direction = 1.0
        if d >= pos:
            f = fy + b * k * (d - dy)
            kt = b * k
            ahead = math.inf  # up the backbone, pushing the peak
        elif f0 < 0.0 and d < zero_pos:
            f = f0 + k_neg * dx
            kt = k_neg
            ahead = zero_pos
            if same_line(zero_pos, pos, fy + b * k * (pos - dy), k_neg, k_pos):
                ahead = pos
        else:
            f_peak = fy + b * k * (pos - dy)
            # a reload line steeper than k (beyond the checked ductility) would divide by ~0
            zero_pos = min(zero_pos, pos - f_peak / k)
            kt = f_peak / (pos - zero_pos)
            f = kt * (d - zero_pos)
            ahead = pos
            if f0 > 0.0 and f0 + k_pos * dx < f:
                f = f0 + k_pos * dx
                # up the unloading line until it meets the reload line
                if kt < k_pos:  # (a steeper reload line runs away from it)
                    ahead = min(pos, (f - k_pos * d + kt * zero_pos) / (kt - k_pos))
                kt = k_pos
    elif dx < 0.0:
        if direction >= 0.0 and f0 >= 0.0:
            zero_neg = d0 - f0 / k_pos
        direction = -1.0
        if d <= neg:
            f = -fy + b * k * (d + dy)
            kt = b * k
            ahead = -math.inf
        elif f0 > 0.0 and d > zero_neg:
            f = f0 + k_pos * dx
            kt = k_pos
            ahead = zero_neg
            if same_line(zero_neg, neg, -fy + b * k * (neg + dy), k_pos, k_neg):
                ahead = neg
        else:
            f_peak = -fy + b * k * (neg + dy)
            zero_neg = max(zero_neg, neg - f_peak / k)
            kt = f_peak / (neg - zero_neg)
            f = kt * (d - zero_neg)
            ahead = neg
            if f0 < 0.0 and f0 + k_neg * dx > f:
                f = f0 + k_neg * dx
                if kt < k_neg:
                    ahead = max(neg, (f - k_neg * d + kt * zero_neg) / (kt - k_neg))
                kt = k_neg
    if d > pos:
        pos = d
        k_pos = unloading(pos / dy)
    if d < neg:
        neg = d
        k_neg = unloading(-neg / dy)
    k_u = k_pos if f > 0.0 else k_neg
    s1[SS_F] = f
    s1[SS_D] = d
    s1[SS_W] = s0[SS_W] + 0.5 * (f0 + f) * dx
    s1[SS_E] = 0.5 * f * f / k_u
    s1[SS_PEAK_POS] = pos
    s1[SS_PEAK_NEG] = neg
    s1[SS_ZERO_POS] = zero_pos
    s1[SS_ZERO_NEG] = zero_neg
    s1[SS_DIR] = direction
    s1[SS_KU_POS] = k_pos
    s1[SS_KU_NEG] = k_neg
    s1[SS_NEXT] = ahead
    s1[SS_KT] = kt
    # (the force keeps its sign up to the point ahead)
    s1[SS_EK] = 0.5 / (k_pos if f > 0.0 or (f == 0.0 and direction > 0.0) else k_neg)
    return f - k * d, kt - k, 0.0


def imk_story_kernel(d, dd, h, s0, s1, p):
    """Ibarra–Medina–Krawinkler peak-oriented story [9]_ with cyclic deterioration of strength,
    post-cap strength, unloading stiffness and accelerated reloading; p = (k, F_y, α_s, δ_p [m],
    δ_pc [m], κ, γ_s, γ_c, γ_a, γ_k, c). Worked in the frame of the increment (the side being loaded
    is +), exact for a monotone drift increment: the deterioration is applied where it happens
    within it (the reversal, the zero-force crossing) and its energies are the exact work along the
    piecewise-linear path (``SS_WX``; ``SS_W`` is the ledger's trapezoid per step). The reload
    path runs from the zero-force drift through the local peak (``SS_LD_*``, ``SS_LF_*``) to the
    target when the line to the local peak is steeper than the line to the target. Writes the
    next point where the path may turn and the slope up to it (:func:`story_straight`)."""
    k, fy0 = p[0], p[1]
    dy = fy0 / k
    d0, f0, w0, wx0 = s0[SS_D], s0[SS_F], s0[SS_W], s0[SS_WX]
    dx = d - d0
    for i in range(N_STORY_STATE):
        s1[i] = s0[i]
    alpha, d_p, d_pc, kappa = p[2], p[3], p[4], p[5]
    g_s, g_c, g_a, g_k, c = p[6], p[7], p[8], p[9], p[10]
    e_y = fy0 * dy
    f_cap = fy0 + alpha * k * d_p
    k_c = -f_cap / d_pc
    f_ref0 = f_cap - k_c * (dy + d_p)
    f_res = kappa * fy0

    def deterioration(e_i, remaining):
        # β = (E_i/(E_t − ΣE))^c, 1 once the capacity is spent
        if remaining <= 0.0:
            return 1.0
        r = max(e_i, 0.0) / remaining
        if r >= 1.0:
            return 1.0
        return r if c == 1.0 else r**c

    def envelope(y, fy, hard, f_ref):
        # max(κ F_y0, min(k y, F_y + α k (y − F_y/k), F_ref + k_c y)) and its slope
        fe, se = k * y, k
        fh = fy + hard * (y - fy / k)
        if fh < fe:
            fe, se = fh, hard
        fc = f_ref + k_c * y
        if fc < fe:
            fe, se = fc, k_c
        if f_res > fe:
            fe, se = f_res, 0.0
        return fe, se

    dk = s0[SS_DK]
    failed = s0[SS_FAILED] > 0.0
    ku = k * (1.0 - dk)
    if failed or dx == 0.0:
        f = 0.0 if failed else f0
        s1[SS_F] = f
        s1[SS_D] = d
        s1[SS_W] = w0 + 0.5 * (f0 + f) * dx
        s1[SS_WX] = wx0 + 0.5 * (f0 + f) * dx
        s1[SS_E] = 0.0 if failed else 0.5 * f * f / ku
        s1[SS_NEXT] = d
        return f - k * d, (0.0 if failed else ku) - k, 0.0
    sgn = 1.0 if dx > 0.0 else -1.0
    # a target follows the drift while it pushes the envelope, and straight increments along the
    # envelope (story_straight) leave it behind: it is never short of the drift reached on its side
    t_pos, t_neg = max(s0[SS_T_POS], d0), min(s0[SS_T_NEG], d0)
    s1[SS_T_POS], s1[SS_T_NEG] = t_pos, t_neg
    # the frame of the increment: x moves up, the loaded side is "a"
    x, x0, g = sgn * d, sgn * d0, sgn * f0
    if sgn > 0.0:
        z_a, ds_a, dc_a, t_a = s0[SS_ZERO_POS], s0[SS_DS_POS], s0[SS_DC_POS], t_pos
        l_x, l_f, t_b = s0[SS_LD_POS], s0[SS_LF_POS], -t_neg
    else:
        z_a, ds_a, dc_a, t_a = -s0[SS_ZERO_NEG], s0[SS_DS_NEG], s0[SS_DC_NEG], -t_neg
        l_x, l_f, t_b = -s0[SS_LD_NEG], -s0[SS_LF_NEG], t_pos
    t_a = max(t_a, dy)
    direction = sgn * s0[SS_DIR]
    if direction < 0.0:
        # a reversal: unloading-stiffness deterioration by the energy dissipated since the last
        # reversal
        e_now = max(wx0 - 0.5 * f0 * f0 / ku, 0.0)
        if g_k > 0.0:
            beta = deterioration(e_now - s0[SS_E_REV], g_k * e_y - e_now)
            failed = beta >= 1.0
            if failed:
                dk = 1.0
            else:
                # no softer than the line from here to the target ahead (and to the local peak
                # before it): softer, the reload would be steeper than the unloading and the loop
                # would run backwards, generating energy
                f_t = envelope(
                    t_a, fy0 * (1.0 - ds_a), k * alpha * (1.0 - ds_a), f_ref0 * (1.0 - dc_a)
                )[0]
                k_min = (f_t - g) / (t_a - x0) if t_a > x0 else 0.0
                if x0 < l_x < t_a and 0.0 < l_f < f_t:
                    k_min = max(k_min, (l_f - g) / (l_x - x0))
                ku = max(ku * (1.0 - beta), min(ku, k_min))
                dk = 1.0 - ku / k
        s1[SS_E_REV] = e_now
        # the other side starts to unload here, below its target: its local peak
        if g < 0.0 and -x0 < max(t_b, dy):
            if sgn > 0.0:
                s1[SS_LD_NEG], s1[SS_LF_NEG] = d0, f0
            else:
                s1[SS_LD_POS], s1[SS_LF_POS] = d0, f0
    if direction <= 0.0 and g <= 0.0:
        z_a = x0 - g / ku
    # (a force rounded to exactly 0 an ulp short of z' still has its crossing ahead)
    crossing = not failed and (g < 0.0 or (g == 0.0 and x0 < z_a)) and x >= z_a
    if crossing:
        # the force crosses zero in this increment: deterioration of the side now loaded
        w_cross = wx0 + 0.5 * g * (z_a - x0)
        e_i = w_cross - s0[SS_W_CROSS]
        if g_s > 0.0:
            beta = deterioration(e_i, g_s * e_y - w_cross)
            failed = failed or beta >= 1.0
            ds_a = 1.0 - (1.0 - ds_a) * (1.0 - beta)
        if g_c > 0.0:
            beta = deterioration(e_i, g_c * e_y - w_cross)
            failed = failed or beta >= 1.0
            dc_a = 1.0 - (1.0 - dc_a) * (1.0 - beta)
        if g_a > 0.0:
            t_a *= 1.0 + deterioration(e_i, g_a * e_y - w_cross)
        s1[SS_W_CROSS] = w_cross
    fy = fy0 * (1.0 - ds_a)
    hard = alpha * k * (1.0 - ds_a)
    f_ref = f_ref0 * (1.0 - dc_a)

    # the reload line from (z', 0) to the target on the current backbone; through the local peak
    # first when the line to it is steeper
    f_t = envelope(t_a, fy, hard, f_ref)[0]
    z_use = min(z_a, t_a - f_t / k)
    k_line = f_t / (t_a - z_use) if f_t > 0.0 else 0.0
    local = f_t > 0.0 and z_use < l_x < t_a and 0.0 < l_f < f_t and l_f > k_line * (l_x - z_use)
    k_1 = l_f / (l_x - z_use) if local else k_line
    k_2 = (f_t - l_f) / (t_a - l_x) if local else k_line

    def force_at(y):
        # the force and its slope at drift y of this increment (frame units)
        if failed:
            return 0.0, 0.0
        if y >= t_a:
            return envelope(y, fy, hard, f_ref)
        if g < 0.0 and y < z_a:
            return g + ku * (y - x0), ku
        if local and y >= l_x:
            line, slope = l_f + k_2 * (y - l_x), k_2
        else:
            line, slope = k_1 * (y - z_use), k_1
        if g > 0.0 and g + ku * (y - x0) < line:
            return g + ku * (y - x0), ku
        return line, slope

    gx, kt = force_at(x)
    # exact work along the path: trapezoids between the kinks it can pass (force_at is linear
    # between them): the zero crossing, the inner reload meeting the line, the target, and the
    # corners of the backbone
    meet_1 = (g - ku * x0 + k_1 * z_use) / (k_1 - ku) if k_1 != ku else x0
    meet_2 = (g - ku * x0 - l_f + k_2 * l_x) / (k_2 - ku) if k_2 != ku else x0
    corners = (
        z_a, meet_1, meet_2, l_x, t_a, fy / k, f_ref / (k - k_c), f_res / k,
        (f_ref - fy + hard * fy / k) / (hard - k_c),
        (f_res - f_ref) / k_c,
        (f_res - fy + hard * fy / k) / hard if hard > 0.0 else x0,
    )  # fmt: skip
    # a story failed here carries no force from then on: only the unloading to z' before the
    # crossing that failed it did work
    w = 0.5 * g * (z_a - x0) if failed and crossing else 0.0
    lo, f_lo = (x, gx) if failed else (x0, g)
    while lo < x:
        hi = x
        for cx in corners:
            if lo < cx < hi:
                hi = cx
        f_hi = force_at(hi)[0] if hi < x else gx
        w += 0.5 * (f_lo + f_hi) * (hi - lo)
        lo, f_lo = hi, f_hi
    # the straight path ahead (story_straight): up to the next corner where the path turns (its
    # slope changes) or the state moves (the target; the zero crossing, with the force below
    # zero), past corners of other branches. On the envelope too: its target is brought up to the
    # drift at the next call. None once failed.
    ahead = math.inf
    for cx in corners:
        if x < cx < ahead:
            ahead = cx
    lo = x
    while ahead < math.inf and ahead != t_a and not (ahead == z_a and gx <= 0.0):
        beyond = math.inf
        for cx in corners:
            if ahead < cx < beyond:
                beyond = cx
        # the lines before and after it, each from its middle: the force at the corner and the
        # slope (one call site: force_at is inlined at each)
        f_before = k_before = 0.0
        same = True
        for j in range(2):
            y = 0.5 * (lo + ahead) if j == 0 else 0.5 * (ahead + min(beyond, ahead + 2.0 * dy))
            f_y, k_y = force_at(y)
            f_at = f_y + k_y * (ahead - y)
            if j == 0:
                f_before, k_before = f_at, k_y
            else:
                same = k_y == k_before and abs(f_at - f_before) <= 1e-9 * fy0
        if not same:
            break
        lo, ahead = ahead, beyond
    s1[SS_NEXT] = d if failed else sgn * ahead
    # the slope beyond x (at a kink force_at gives the one before it)
    s1[SS_KT] = force_at(0.5 * (x + ahead) if ahead < math.inf else x + dy)[1]
    s1[SS_EK] = 0.5 / ku
    if x >= t_a:  # the envelope pushed: no local peak on this side
        t_a = x
        l_x = l_f = 0.0
    f = sgn * gx
    if sgn > 0.0:
        s1[SS_ZERO_POS], s1[SS_DS_POS], s1[SS_DC_POS], s1[SS_T_POS] = z_a, ds_a, dc_a, t_a
        s1[SS_LD_POS], s1[SS_LF_POS] = l_x, l_f
    else:
        s1[SS_ZERO_NEG], s1[SS_DS_NEG], s1[SS_DC_NEG], s1[SS_T_NEG] = -z_a, ds_a, dc_a, -t_a
        s1[SS_LD_NEG], s1[SS_LF_NEG] = -l_x, -l_f
    s1[SS_DK] = dk
    s1[SS_DIR] = sgn
    s1[SS_FAILED] = 1.0 if failed else 0.0
    s1[SS_F] = f
    s1[SS_D] = d
    s1[SS_W] = w0 + 0.5 * (f0 + f) * dx
    s1[SS_WX] = wx0 + w
    s1[SS_E] = 0.0 if failed else 0.5 * f * f / ku
    return f - k * d, kt - k, 0.0


def imk_failure_ahead(s0: np.ndarray, p: np.ndarray, direction: float) -> tuple[bool, float]:
    """Where an IMK story at committed state ``s0`` moving in ``direction`` (±1) next spends an
    energy capacity: (True, NaN) when already failed or at the start of that motion (a reversal
    that spends the unloading stiffness: the force drops from where it is to zero); (False, z) when
    its zero-force crossing at drift z [m] ahead does; (False, NaN) when neither. Both found by the
    kernel over an increment 1e-9 δ_y long, or reaching 1e-9 δ_y past z."""
    if s0[SS_FAILED] > 0.0:
        return True, math.nan
    trial = np.zeros_like(s0)
    tiny = direction * 1e-9 * p[1] / p[0]
    imk_story_kernel(s0[SS_D] + tiny, 0.0, 0.0, s0, trial, p)
    if trial[SS_FAILED] > 0.0:
        return True, math.nan
    z = trial[SS_ZERO_POS if direction > 0.0 else SS_ZERO_NEG]
    if direction * s0[SS_F] < 0.0 and direction * (z - s0[SS_D]) > 0.0:
        imk_story_kernel(z + tiny, 0.0, 0.0, s0, trial, p)
        if trial[SS_FAILED] > 0.0:
            return False, float(z)
    return False, math.nan


def story_energy(law, s, p):
    """Recoverable energy E [J] of a story of model id ``law`` at its committed state row ``s``:
    the row's E, except for a Takeda story pushed along its backbone past the peak its row holds by
    straight increments, whose E = F²/(2 k_u) with the unloading stiffness k_u of the drift reached
    (its row's E is the one at the peak held, ``SS_EK`` being that peak's)."""
    if law == TAKEDA_ID and (s[SS_D] > s[SS_PEAK_POS] or s[SS_D] < s[SS_PEAK_NEG]):
        k, fy, a = p[0], p[1], p[3]
        mu = abs(s[SS_D]) * k / fy
        return 0.5 * s[SS_F] * s[SS_F] * (mu**a if a != 0.0 else 1.0) / k
    return s[SS_E]


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


#: Unit of a parameter given as a drift ratio (δ/h) and passed to the kernel in metres.
_DRIFT = "δ/h"

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
                ("delta_nu", "", 0.0, 0.0, 10.0), ("delta_eta", "", 0.0, 0.0, 10.0),
                ("zeta_s", "", 0.0, 0.0, 0.99), ("p", "", 1.0, 0.0, 100.0),
                ("q", "", 0.0, 0.0, 1.0), ("psi", "", 0.2, 1e-6, 10.0),
                ("delta_psi", "", 0.0, 0.0, 10.0), ("lambda", "", 0.5, 0.0, 10.0)),
               "F = α k δ + (1 − α) F_y ζ, δ_y ζ' = h(ζ, ε) [A − ν (β sgn(δ̇ ζ) + γ) |ζ|^n]/η",
               "Wen 1976; Baber & Noori 1985 (degradation); Foliente 1995 (pinching h)",
               "BoucWen alpha=α ko=k n gamma=γ/δ_y^n beta=β/δ_y^n Ao=A (deltas: see docs); "
               "BWBN with pinching"),
    StoryModel("takeda", TAKEDA_ID, takeda_story_kernel,
               (("hardening", "", 0.0, 0.0, 1.0), ("unloading_exponent", "", 0.4, 0.0, 2.0)),
               "peak-oriented: unload at k (δ_m/δ_y)^(−a) to F = 0, reload to the opposite peak",
               "Takeda, Sozen & Nielsen 1970; Clough & Johnston 1966 (a = 0); Otani 1981",
               "Hysteretic (bilinear backbone) pinchX=pinchY=1 damage1=damage2=0 beta=a"),
    StoryModel("imk", 4, imk_story_kernel,
               (("hardening", "", 0.03, 0.0, 1.0), ("plastic_drift", _DRIFT, 0.02, 1e-6, 1.0),
                ("post_cap_drift", _DRIFT, 0.1, 1e-6, 10.0), ("residual", "", 0.2, 0.0, 1.0),
                ("gamma_s", "", 0.0, 0.0, 1e6), ("gamma_c", "", 0.0, 0.0, 1e6),
                ("gamma_a", "", 0.0, 0.0, 1e6), ("gamma_k", "", 0.0, 0.0, 1e6),
                ("c", "", 1.0, 0.1, 10.0)),
               "backbone k, α_s k to the cap, post-cap slope to κ F_y; peak-oriented; "
               "β = (E_i/(γ F_y δ_y − ΣE))^c per mode",
               "Ibarra, Medina & Krawinkler 2005; Lignos & Krawinkler 2011",
               "ModIMKPeakOriented (Lamda = γ δ_y, Lamda_K = γ_K δ_y/2, theta in drift × h)"),
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


#: Largest ductility over which the Takeda rules are checked to be well posed.
TAKEDA_DUCTILITY = 100.0


def _check_takeda(b: np.ndarray, a: np.ndarray, where: str) -> None:
    """The Takeda rules need an unloading stiffness k μ^(−a) no softer than the secant to the peak,
    (1 + b (μ − 1)) k/μ, or a reload line would be steeper than the unloading and the response
    would depend on the step: μ^(1−a) ≥ 1 + b (μ − 1) up to μ = TAKEDA_DUCTILITY."""
    mu = np.geomspace(1.0, TAKEDA_DUCTILITY, 400)[1:]
    for i in range(b.size):
        bad = mu ** (1.0 - a[i]) < 1.0 + b[i] * (mu - 1.0) - 1e-12
        if np.any(bad):
            raise PoundingInputError(
                f"{where}.stories: unloading_exponent = {a[i]:g} with hardening = {b[i]:g} makes "
                f"the unloading stiffness k μ^(−a) softer than the secant to the peak from "
                f"ductility {mu[bad][0]:.3g}; allowed: μ^(1−a) ≥ 1 + b (μ − 1) up to μ = "
                f"{TAKEDA_DUCTILITY:g} (e.g. a ≤ 0.5 with b ≤ 0.05, a ≤ 0.4 with b ≤ 0.1)"
            )


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
            ) * (heights if unit == _DRIFT else 1.0)
        if self.model == "takeda":
            _check_takeda(rows[:, 2], rows[:, 3], where)
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
