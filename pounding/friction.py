r"""Friction laws for sliding interfaces (isolation bearings, slabs on walls), each written once.

Sign convention (defined here, once): ``v`` is the sliding speed of the upper body relative to the
surface it slides on [m/s], signed. Every law returns the *resisting* force f [N] with the sign of v
(f is odd in v), so the sliding body obeys m v̇ = p − f with p the resultant of all other forces along
the slide. ``normal`` = N >= 0 is the normal force [N]; the kernels treat N < 0 (uplift) as no contact.

Each law is a *kernel*: a scalar function of plain floats written with ``math`` only, so the same
source runs in Python and compiles with numba (``jit(law.kernel)`` in :mod:`pounding.integrators`;
this layer-2 module does not import numba). The signature is

``kernel(v, normal, p) -> (f, df_dv)``

with ``p`` a float64 array packed, in the order of :attr:`FrictionLaw.parameters`, by
:func:`friction_parameters` (which validates it). ``df_dv`` [N·s/m] is the Newton tangent. The public
functions (:func:`coulomb`, :func:`andersson`, ...) take keyword arguments, broadcast over arrays and
call the same kernels. True Coulomb stick-slip uses :func:`coulomb_stick_slip_kernel`; the hysteretic
Constantinou model uses :func:`constantinou_bouc_wen_kernel` with the Bouc-Wen variable z, whose rate
is :func:`bouc_wen_rate`.

The static and dynamic Coulomb laws, viscous friction and its normal-force-proportional variant
are the classical forms reviewed by Olsson et al. [7]; the regularised laws cite their papers.

References
----------
.. [1] Andersson, S., Söderberg, A., Björklund, S. (2007). Friction models for sliding dry, boundary
   and mixed lubricated contacts. Tribology International 40(4), 580-587.
   doi:10.1016/j.triboint.2005.11.014
.. [2] Brown, P., McPhee, J. (2016). A continuous velocity-based friction model for dynamics and
   control with physically meaningful parameters. ASME J. Comput. Nonlinear Dyn. 11(5), 054502.
   doi:10.1115/1.4033658
.. [3] Constantinou, M., Mokha, A., Reinhorn, A. (1990). Teflon bearings in base isolation II:
   Modeling. J. Struct. Eng. 116(2), 455-474. doi:10.1061/(ASCE)0733-9445(1990)116:2(455)
.. [4] Wen, Y.-K. (1976). Method for random vibration of hysteretic systems. J. Eng. Mech. Div.
   ASCE 102(2), 249-263.
.. [5] Drake (MIT / Toyota Research Institute). MultibodyPlant continuous Stribeck approximation,
   ``StribeckModel::ComputeFrictionCoefficient``. https://drake.mit.edu
.. [6] Karnopp, D. (1985). Computer simulation of stick-slip friction in mechanical dynamic systems.
   J. Dyn. Syst. Meas. Control 107(1), 100-103. doi:10.1115/1.3140698
.. [7] Olsson, H., Åström, K.J., Canudas de Wit, C., Gäfvert, M., Lischinsky, P. (1998). Friction
   models and friction compensation. Eur. J. Control 4(3), 176-195.
"""

from __future__ import annotations

import dataclasses
import math
import numbers
from collections.abc import Callable

import numpy as np

from pounding.errors import PoundingInputError

__all__ = [
    "FRICTION_LAWS",
    "LAWS_BY_ID",
    "BOUC_WEN_PARAMETERS",
    "FrictionLaw",
    "Parameter",
    "get_friction_law",
    "friction_parameters",
    "bouc_wen_parameters",
    "coulomb",
    "coulomb_stick_force_limit",
    "coulomb_stick_slip",
    "viscous",
    "viscous_normal",
    "stribeck",
    "andersson",
    "brown_mcphee",
    "constantinou",
    "bouc_wen_rate",
    "coulomb_kernel",
    "coulomb_stick_slip_kernel",
    "viscous_kernel",
    "viscous_normal_kernel",
    "stribeck_kernel",
    "andersson_kernel",
    "brown_mcphee_kernel",
    "constantinou_kernel",
    "constantinou_bouc_wen_kernel",
]


# --------------------------------------------------------------------------------------------------
# Kernels (plain floats and ``math`` only, no helpers: numba compiles each from this same source)
# --------------------------------------------------------------------------------------------------


def coulomb_kernel(v, normal, p):
    r"""Regularised dynamic Coulomb [7]: :math:`f = \mu_d N \tanh(v / v_{reg})`.

    p = [mu_s, mu_d, v_reg]; mu_s is used by :func:`coulomb_stick_slip_kernel` only.
    """
    n = normal if normal > 0.0 else 0.0
    t = math.tanh(v / p[2])
    f0 = p[1] * n
    return f0 * t, f0 * (1.0 - t * t) / p[2]


def coulomb_stick_slip_kernel(force_to_stick, normal, p):
    """Exact Coulomb stick test [6], [7]: ``(stuck, f)`` at v = 0.

    ``force_to_stick`` is the friction force [N] that keeps the slip acceleration zero (p in
    m v̇ = p − f). Stuck while ``|force_to_stick| <= mu_s N``, friction then equals it; otherwise slip
    starts towards sign(force_to_stick) against f = mu_d N sign(force_to_stick). p as in
    :func:`coulomb_kernel`.
    """
    n = normal if normal > 0.0 else 0.0
    if abs(force_to_stick) <= p[0] * n:
        return True, force_to_stick
    return False, math.copysign(p[1] * n, force_to_stick)


def viscous_kernel(v, normal, p):
    r"""Viscous friction [7]: :math:`f = \mu_v v`; p = [mu_v]."""
    return p[0] * v, p[0]


def viscous_normal_kernel(v, normal, p):
    r"""Viscous friction proportional to N: :math:`f = k_v N v`; p = [k_v]."""
    n = normal if normal > 0.0 else 0.0
    return p[0] * n * v, p[0] * n


def stribeck_kernel(v, normal, p):
    r"""Drake's piecewise-quintic Stribeck law [5]; p = [mu_s, mu_d, v_s].

    With :math:`x = |v|/v_s` and s(x) = 10x³ − 15x⁴ + 6x⁵: μ = μ_s s(x) for x < 1,
    μ_s − (μ_s − μ_d) s((x − 1)/2) for 1 <= x < 3, μ_d beyond; f = μ N sign(v).
    """
    n = normal if normal > 0.0 else 0.0
    mu_s = p[0]
    mu_d = p[1]
    v_s = p[2]
    x = abs(v) / v_s
    sign = 1.0 if v >= 0.0 else -1.0
    if x >= 3.0:
        return sign * mu_d * n, 0.0
    if x >= 1.0:
        y = 0.5 * (x - 1.0)
        step = y * y * y * (10.0 + y * (6.0 * y - 15.0))
        dstep = 30.0 * y * y * (1.0 - y) * (1.0 - y)
        return sign * (mu_s - (mu_s - mu_d) * step) * n, -(mu_s - mu_d) * n * dstep / (2.0 * v_s)
    step = x * x * x * (10.0 + x * (6.0 * x - 15.0))
    dstep = 30.0 * x * x * (1.0 - x) * (1.0 - x)
    return sign * mu_s * n * step, mu_s * n * dstep / v_s


def andersson_kernel(v, normal, p):
    r"""Andersson-Söderberg-Björklund [1]; p = [mu_s, mu_d, v_s, exponent, k_t, mu_v].

    :math:`f = N[\mu_d + (\mu_s - \mu_d) e^{-(|v|/v_s)^{p}}] \tanh(k_t v) + \mu_v v`.
    """
    n = normal if normal > 0.0 else 0.0
    dmu = p[0] - p[1]
    expo = p[3]
    x = abs(v) / p[2]
    e = math.exp(-(x**expo))
    h = (p[1] + dmu * e) * n
    t = math.tanh(p[4] * v)
    dh = 0.0
    if x > 0.0:  # dh/dv -> 0 times tanh(0) = 0 at v = 0 even where x^(exponent-1) diverges
        dh = -math.copysign(dmu * n * e * expo * x ** (expo - 1.0) / p[2], v)
    return h * t + p[5] * v, dh * t + h * p[4] * (1.0 - t * t) + p[5]


def brown_mcphee_kernel(v, normal, p):
    r"""Brown-McPhee [2]; p = [mu_s, mu_d, v_t, mu_v, f_nt].

    :math:`f = \mu_d N \tanh(4 v_r) + (\mu_s - \mu_d) N \frac{16 v_r}{(v_r^2 + 3)^2}
    + \mu_v v \tanh(4 N / f_{nt})`, :math:`v_r = v / v_t`.
    """
    n = normal if normal > 0.0 else 0.0
    v_t = p[2]
    r = v / v_t
    t = math.tanh(4.0 * r)
    q = r * r + 3.0
    c = p[3] * math.tanh(4.0 * n / p[4])
    f = p[1] * n * t + (p[0] - p[1]) * n * 16.0 * r / (q * q) + c * v
    df = (
        4.0 * p[1] * n * (1.0 - t * t) / v_t
        + 48.0 * (p[0] - p[1]) * n * (1.0 - r * r) / (q * q * q * v_t)
        + c
    )
    return f, df


def constantinou_kernel(v, normal, p):
    r"""Constantinou μ(v) in its rigid-plastic form [3]; p = [mu_min, mu_max, a, v_reg].

    :math:`f = \mu(v) N \tanh(v / v_{reg})`, :math:`\mu(v) = \mu_{max} - (\mu_{max} - \mu_{min})
    e^{-a|v|}`: the Bouc-Wen variable z replaced by its steady sliding value ±1.
    """
    n = normal if normal > 0.0 else 0.0
    e = math.exp(-p[2] * abs(v))
    mu = p[1] - (p[1] - p[0]) * e
    dmu = math.copysign((p[1] - p[0]) * p[2] * e, v)
    t = math.tanh(v / p[3])
    return mu * n * t, n * (dmu * t + mu * (1.0 - t * t) / p[3])


def constantinou_bouc_wen_kernel(v, normal, z, p):
    r"""Constantinou friction with a Bouc-Wen variable [3]: ``(f, df_dv, df_dz)``, :math:`f = \mu(v) N z`.

    p as in :func:`constantinou_kernel` (v_reg unused); z from :func:`bouc_wen_rate`. df_dv is the
    one-sided (v >= 0) value at v = 0, where μ(v) has a kink.
    """
    n = normal if normal > 0.0 else 0.0
    e = math.exp(-p[2] * abs(v))
    mu = p[1] - (p[1] - p[0]) * e
    return mu * n * z, math.copysign((p[1] - p[0]) * p[2] * e, v) * n * z, mu * n


def bouc_wen_rate(z, v, p):
    r"""Bouc-Wen hysteretic variable rate [4]: ``(zdot, dzdot_dz, dzdot_dv)``.

    :math:`u_y \dot z = A v - \beta |v| |z|^{\eta-1} z - \gamma v |z|^\eta`,
    p = [u_y, A, beta, gamma, eta] from :func:`bouc_wen_parameters`; zdot [1/s].
    """
    u_y = p[0]
    beta = p[2]
    gamma = p[3]
    eta = p[4]
    az = abs(z)
    zn1 = az ** (eta - 1.0)
    zn = zn1 * az
    zdot = (p[1] * v - beta * abs(v) * zn1 * z - gamma * v * zn) / u_y
    dz = -eta * zn1 * (beta * abs(v) + gamma * v * math.copysign(1.0, z)) / u_y
    dv = (p[1] - beta * math.copysign(1.0, v) * zn1 * z - gamma * zn) / u_y
    return zdot, dz, dv


# --------------------------------------------------------------------------------------------------
# Parameters, registry and validation
# --------------------------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class Parameter:
    """One entry of a law's parameter array.

    ``default`` None means required. Values must be finite and >= ``minimum`` (> when ``strict``).
    """

    name: str
    unit: str
    description: str
    default: float | None = None
    minimum: float = 0.0
    strict: bool = False
    typical: str = ""

    @property
    def allowed(self) -> str:
        bound = "-inf" if self.minimum == -math.inf else f"{self.minimum:g}"
        return f"finite, {'>' if self.strict else '>='} {bound}"


@dataclasses.dataclass(frozen=True)
class FrictionLaw:
    """A registered friction law.

    Attributes
    ----------
    name : str
        Registry name.
    kernel_id : int
        Stable index a compiled dispatcher may switch on.
    kernel : callable
        ``kernel(v, normal, p) -> (f, df_dv)``, plain ``math``, numba-compilable.
    function : callable
        The public keyword-argument, vectorised form.
    parameters : tuple of Parameter
        The layout of ``p``, in order, with units, defaults and typical ranges.
    equation : str
        Equation label (the paper or the classical law it comes from).
    reference : str
        Short literature reference.
    formula : str
        One-line force law, for ``pounding laws`` and reports.
    ordered : tuple of (str, str)
        Pairs (small, large) that must satisfy small <= large.
    hysteretic_kernel : callable or None
        ``(v, normal, z, p) -> (f, df_dv, df_dz)`` when the law is used with a Bouc-Wen variable z.
    """

    name: str
    kernel_id: int
    kernel: Callable
    function: Callable
    parameters: tuple[Parameter, ...]
    equation: str
    reference: str
    formula: str
    ordered: tuple[tuple[str, str], ...] = ()
    hysteretic_kernel: Callable | None = None

    @property
    def parameter_names(self) -> tuple[str, ...]:
        return tuple(par.name for par in self.parameters)


def _pack(
    what: str,
    specs: tuple[Parameter, ...],
    ordered: tuple[tuple[str, str], ...],
    params: dict[str, object],
) -> np.ndarray:
    names = [s.name for s in specs]
    unknown = sorted(set(params) - set(names))
    if unknown:
        raise PoundingInputError(
            f"{what}: unknown parameter {unknown[0]!r}; allowed: {', '.join(names)}"
        )
    values: dict[str, float] = {}
    for s in specs:
        value = params.get(s.name, s.default)
        if value is None:
            raise PoundingInputError(
                f"{what}: missing parameter {s.name!r} [{s.unit}] ({s.description}; {s.allowed}, "
                f"typical {s.typical}); parameters: {', '.join(names)}"
            )
        if isinstance(value, bool) or not isinstance(value, numbers.Real):
            raise PoundingInputError(f"{what}: {s.name} = {value!r}; allowed: a number [{s.unit}]")
        value = float(value)
        above = value > s.minimum if s.strict else value >= s.minimum
        if not (math.isfinite(value) and above):
            raise PoundingInputError(
                f"{what}: {s.name} = {value!r} [{s.unit}]; allowed: {s.allowed}"
            )
        values[s.name] = value
    for small, large in ordered:
        if values[small] > values[large]:
            raise PoundingInputError(
                f"{what}: {small} = {values[small]:g} > {large} = {values[large]:g}; "
                f"allowed: {small} <= {large}"
            )
    return np.array([values[n] for n in names], dtype=np.float64)


def get_friction_law(name: str | FrictionLaw) -> FrictionLaw:
    """The registered law called ``name``; an unknown name raises ValueError listing the valid ones."""
    if isinstance(name, FrictionLaw):
        return name
    key = str(name).strip().lower()
    try:
        return FRICTION_LAWS[key]
    except KeyError:
        allowed = ", ".join(FRICTION_LAWS)
        raise PoundingInputError(f"unknown friction law {name!r}; allowed: {allowed}") from None


def friction_parameters(name: str | FrictionLaw, **params: float) -> np.ndarray:
    """Validate a law's parameters and pack its kernel array ``p`` (float64, registry order).

    Missing, unknown, negative or NaN parameters, μ_d > μ_s and μ_min > μ_max raise ValueError naming
    the parameter, its value and what is allowed. Omitted parameters take their defaults.
    """
    law = get_friction_law(name)
    return _pack(f"friction law {law.name!r}", law.parameters, law.ordered, params)


#: Bouc-Wen parameter layout (p of :func:`bouc_wen_rate`).
BOUC_WEN_PARAMETERS: tuple[Parameter, ...] = (
    Parameter(
        "u_y", "m", "yield displacement", None, 0.0, True, "2.5e-4 to 1e-3 m for PTFE sliders"
    ),
    Parameter("A", "-", "initial stiffness factor", 1.0, 0.0, True, "1"),
    Parameter("beta", "-", "loop shape", 0.5, 0.0, False, "0.1 to 0.9 with beta + gamma = 1"),
    Parameter(
        "gamma", "-", "loop shape", 0.5, -math.inf, False, "0.9 to 0.1 with beta + gamma = 1"
    ),
    Parameter("eta", "-", "sharpness of yield", 2.0, 1.0, False, "1 to 2 (2 for PTFE)"),
)


def bouc_wen_parameters(**params: float) -> np.ndarray:
    """Validate Bouc-Wen parameters (``u_y`` [m], ``A``, ``beta``, ``gamma``, ``eta``) and pack p.

    Requires u_y > 0, A > 0, beta >= 0, beta + gamma > 0 (bounded z, steady value
    (A / (beta + gamma))^(1/eta)) and eta >= 1.
    """
    p = _pack("Bouc-Wen", BOUC_WEN_PARAMETERS, (), params)
    if p[2] + p[3] <= 0.0:
        raise PoundingInputError(
            f"Bouc-Wen: beta + gamma = {p[2] + p[3]:g}; allowed: beta + gamma > 0"
        )
    return p


# --------------------------------------------------------------------------------------------------
# Public, vectorised functions (keyword arguments, same kernels)
# --------------------------------------------------------------------------------------------------


def _normal(normal: float | np.ndarray) -> np.ndarray:
    n = np.asarray(normal, dtype=float)
    bad = ~(np.isfinite(n) & (n >= 0.0))
    if np.any(bad):
        raise PoundingInputError(f"normal = {float(n[bad].flat[0])!r} [N]; allowed: finite, >= 0")
    return n


def _evaluate(name: str, v, normal, params: dict[str, float]) -> np.ndarray | float:
    law = FRICTION_LAWS[name]
    p = friction_parameters(law, **params)
    kernel = law.kernel
    vec = np.vectorize(lambda vi, ni: kernel(vi, ni, p)[0], otypes=[float])
    return vec(np.asarray(v, dtype=float), _normal(normal))[()]


def coulomb(v, *, normal, mu_s: float, mu_d: float, v_reg: float = 1.0e-3):
    r"""Dynamic Coulomb friction, regularised for the compiled loop.

    .. math:: f = \mu_d N \tanh(v / v_{reg})

    Dynamic Coulomb friction (:math:`f = \mu_d N\,\mathrm{sign}(v)`) with the sign function
    smoothed over the regularisation speed :math:`v_{reg}`: f reaches 76 % of μ_d N at v = v_reg and
    99.5 % at 3 v_reg; below v_reg the law acts as a viscous damper of coefficient μ_d N / v_reg, so a
    smaller v_reg is closer to Coulomb but stiffer. The static coefficient μ_s enters the
    exact stick test, :func:`coulomb_stick_slip`.

    Parameters
    ----------
    v : array_like
        Sliding speed [m/s], signed.
    normal : array_like
        Normal force N [N], >= 0.
    mu_s : float
        Static coefficient [-], >= mu_d. Typical: 0.05-0.2 PTFE on steel, 0.6-0.8 concrete on
        concrete.
    mu_d : float
        Dynamic coefficient [-]. Typical: 0.03-0.15 PTFE on steel, 0.4-0.6 concrete on concrete.
    v_reg : float, default 1e-3
        Regularisation speed [m/s], > 0. Typical 1e-4 to 1e-2 m/s.

    Returns
    -------
    ndarray or float
        Resisting friction force f [N], with the sign of v.

    References
    ----------
    Olsson et al. (1998) Eur. J. Control 4(3), 176-195 (Coulomb friction, static and dynamic);
    Karnopp, D. (1985). J. Dyn. Syst. Meas. Control 107(1), 100-103.
    """
    return _evaluate("coulomb", v, normal, dict(mu_s=mu_s, mu_d=mu_d, v_reg=v_reg))


def coulomb_stick_force_limit(mu_s, normal):
    r"""Largest friction force a stuck contact can carry, :math:`f_s = \mu_s N` [N] (static Coulomb friction [7]).

    Parameters
    ----------
    mu_s : array_like
        Static coefficient [-], >= 0.
    normal : array_like
        Normal force N [N], >= 0.
    """
    mu = np.asarray(mu_s, dtype=float)
    if np.any(~(np.isfinite(mu) & (mu >= 0.0))):
        raise PoundingInputError(f"mu_s = {mu_s!r}; allowed: finite, >= 0")
    return (mu * _normal(normal))[()]


def coulomb_stick_slip(force_to_stick, *, normal, mu_s: float, mu_d: float):
    r"""Decide stick or slip at v = 0 and give the friction force (exact Coulomb, Karnopp [6]).

    .. math::
        |p| \le \mu_s N:\ \text{stick},\ f = p; \qquad
        |p| > \mu_s N:\ \text{slip},\ f = \mu_d N\,\mathrm{sign}(p)

    where p = ``force_to_stick`` is the friction force that would keep the slip acceleration zero,
    i.e. the resultant of all other forces on the sliding body along the slide (m v̇ = p − f). When
    slipping, the body accelerates towards sign(p). The break-away event of an ivp integration is
    :func:`coulomb_stick_force_limit` − :math:`|p|` = 0; re-sticking is tested when v returns to 0.

    Parameters
    ----------
    force_to_stick : array_like
        Force p needed to keep v = 0 [N], signed.
    normal : array_like
        Normal force N [N], >= 0.
    mu_s, mu_d : float
        Static and dynamic coefficients [-], 0 <= mu_d <= mu_s.

    Returns
    -------
    stuck : ndarray of bool or bool
        True where the contact sticks.
    force : ndarray or float
        Friction force f [N].

    References
    ----------
    Karnopp, D. (1985). Computer simulation of stick-slip friction in mechanical dynamic systems.
    J. Dyn. Syst. Meas. Control 107(1), 100-103.
    """
    p = friction_parameters("coulomb", mu_s=mu_s, mu_d=mu_d)
    vec = np.vectorize(lambda fi, ni: coulomb_stick_slip_kernel(fi, ni, p), otypes=[bool, float])
    stuck, force = vec(np.asarray(force_to_stick, dtype=float), _normal(normal))
    return stuck[()], force[()]


def viscous(v, *, mu_v: float):
    r"""Viscous friction [7].

    .. math:: f = \mu_v v

    Parameters
    ----------
    v : array_like
        Sliding speed [m/s].
    mu_v : float
        Viscous coefficient [N·s/m], >= 0; problem dependent (a linear damper of the bearing).

    Returns
    -------
    ndarray or float
        Friction force f [N].
    """
    return _evaluate("viscous", v, 0.0, dict(mu_v=mu_v))


def viscous_normal(v, *, normal, k_v: float):
    r"""Viscous friction proportional to the normal force (the viscous term of [7] scaled by N).

    .. math:: f = k_v N v

    Parameters
    ----------
    v : array_like
        Sliding speed [m/s].
    normal : array_like
        Normal force N [N], >= 0.
    k_v : float
        Coefficient [s/m], >= 0. k_v v is a speed-dependent friction coefficient; k_v of 0.01-0.1
        s/m keeps it a fraction of μ_d at seismic sliding speeds of 0.1-1 m/s.

    Returns
    -------
    ndarray or float
        Friction force f [N].
    """
    return _evaluate("viscous_normal", v, normal, dict(k_v=k_v))


def stribeck(v, *, normal, mu_s: float, mu_d: float, v_s: float = 1.0e-3):
    r"""Drake's regularised Stribeck law: smooth rise to μ_s at v_s, smooth drop to μ_d at 3 v_s.

    .. math::
        x = |v|/v_s,\quad s(x) = 10x^3 - 15x^4 + 6x^5,\quad
        \mu = \begin{cases} \mu_s\, s(x) & x < 1 \\
        \mu_s - (\mu_s - \mu_d)\, s\!\left(\tfrac{x-1}{2}\right) & 1 \le x < 3 \\
        \mu_d & x \ge 3 \end{cases},\quad f = \mu N\,\mathrm{sign}(v)

    C² continuous; f = μ_s N exactly at :math:`|v| = v_s` and μ_d N from 3 v_s on. This is Drake's
    MultibodyPlant Stribeck model [5]; the classical exponential (Bo-Pavelescu) Stribeck curve with a
    tanh regularisation is :func:`andersson` [1].

    Parameters
    ----------
    v : array_like
        Sliding speed [m/s].
    normal : array_like
        Normal force N [N], >= 0.
    mu_s, mu_d : float
        Static (peak) and dynamic coefficients [-], 0 <= mu_d <= mu_s.
    v_s : float, default 1e-3
        Stiction tolerance [m/s], > 0; typical 1e-4 to 1e-2 m/s.

    Returns
    -------
    ndarray or float
        Friction force f [N].
    """
    return _evaluate("stribeck", v, normal, dict(mu_s=mu_s, mu_d=mu_d, v_s=v_s))


def andersson(
    v,
    *,
    normal,
    mu_s: float,
    mu_d: float,
    v_s: float = 1.0e-3,
    exponent: float = 2.0,
    k_t: float = 1.0e4,
    mu_v: float = 0.0,
):
    r"""Andersson-Söderberg-Björklund regularised Stribeck friction [1].

    .. math::
        f = N\left[\mu_d + (\mu_s - \mu_d)\, e^{-(|v|/v_s)^{p}}\right] \tanh(k_t v) + \mu_v v

    The exponential Stribeck curve (Bo-Pavelescu form) with the sign function replaced by a tanh. The
    peak stays a little below μ_s N because the tanh is not saturated where the exponential decays;
    raise mu_s to compensate. f tends to μ_d N + μ_v v at high speed.

    Parameters
    ----------
    v : array_like
        Sliding speed [m/s].
    normal : array_like
        Normal force N [N], >= 0.
    mu_s, mu_d : float
        Static and dynamic coefficients [-], 0 <= mu_d <= mu_s.
    v_s : float, default 1e-3
        Stribeck speed [m/s], > 0; order 1e-3 m/s.
    exponent : float, default 2
        Decay exponent p [-], > 0; 0.5-2, 2 typical.
    k_t : float, default 1e4
        tanh slope [s/m], > 0; 1e4 typical (must exceed 1/v_s for a visible Stribeck peak).
    mu_v : float, default 0
        Viscous coefficient [N·s/m], >= 0.

    Returns
    -------
    ndarray or float
        Friction force f [N].
    """
    params = dict(mu_s=mu_s, mu_d=mu_d, v_s=v_s, exponent=exponent, k_t=k_t, mu_v=mu_v)
    return _evaluate("andersson", v, normal, params)


def brown_mcphee(
    v,
    *,
    normal,
    mu_s: float,
    mu_d: float,
    v_t: float = 1.0e-3,
    mu_v: float = 0.0,
    f_nt: float = 1.0,
):
    r"""Brown-McPhee continuous velocity-based friction [2].

    .. math::
        f = \mu_d N \tanh(4 v_r) + (\mu_s - \mu_d) N \frac{16\, v_r}{(v_r^2 + 3)^2}
            + \mu_v v \tanh(4 N / f_{nt}), \qquad v_r = v / v_t

    The Stribeck term peaks at exactly v = v_t with value (μ_s − μ_d) N, and the tanh term is
    tanh(4) = 0.9993 saturated there, so the total peak sits close to μ_s N at v ≈ v_t.

    Parameters
    ----------
    v : array_like
        Sliding speed [m/s].
    normal : array_like
        Normal force N [N], >= 0.
    mu_s, mu_d : float
        Static and dynamic coefficients [-], 0 <= mu_d <= mu_s.
    v_t : float, default 1e-3
        Transition speed [m/s], > 0; 1e-4 to 1e-2 m/s.
    mu_v : float, default 0
        Viscous coefficient [N·s/m], >= 0.
    f_nt : float, default 1
        Normal force [N] above which the viscous term is fully active, > 0; small against N.

    Returns
    -------
    ndarray or float
        Friction force f [N].
    """
    params = dict(mu_s=mu_s, mu_d=mu_d, v_t=v_t, mu_v=mu_v, f_nt=f_nt)
    return _evaluate("brown_mcphee", v, normal, params)


def constantinou(
    v,
    *,
    normal,
    mu_min: float,
    mu_max: float,
    a: float,
    v_reg: float = 1.0e-3,
    z=None,
):
    r"""Velocity-dependent friction of PTFE / friction-pendulum sliders, Constantinou et al. [3].

    .. math::
        \mu(v) = \mu_{max} - (\mu_{max} - \mu_{min})\, e^{-a|v|}, \qquad f = \mu(v)\, N\, z

    with z the Bouc-Wen variable (:func:`bouc_wen_rate`, [4]). Without ``z`` the rigid-plastic form
    z = tanh(v / v_reg) is used (the steady sliding value ±1, regularised at v = 0).

    Parameters
    ----------
    v : array_like
        Sliding speed [m/s].
    normal : array_like
        Normal force N [N], >= 0.
    mu_min : float
        Coefficient at v = 0 [-]; typical 0.02-0.06.
    mu_max : float
        Coefficient at high speed [-], >= mu_min; typical 0.05-0.15.
    a : float
        Rate parameter [s/m], >= 0; typical 10-100 s/m (about 20 s/m for PTFE at high pressure).
    v_reg : float, default 1e-3
        Regularisation speed of the rigid-plastic form [m/s], > 0.
    z : array_like, optional
        Bouc-Wen variable [-], ``|z| <= 1`` in steady sliding.

    Returns
    -------
    ndarray or float
        Friction force f [N].
    """
    params = dict(mu_min=mu_min, mu_max=mu_max, a=a, v_reg=v_reg)
    if z is None:
        return _evaluate("constantinou", v, normal, params)
    p = friction_parameters("constantinou", **params)
    vec = np.vectorize(
        lambda vi, ni, zi: constantinou_bouc_wen_kernel(vi, ni, zi, p)[0], otypes=[float]
    )
    return vec(np.asarray(v, dtype=float), _normal(normal), np.asarray(z, dtype=float))[()]


# --------------------------------------------------------------------------------------------------
# Registry
# --------------------------------------------------------------------------------------------------

_MU_S = Parameter("mu_s", "-", "static coefficient", typical="0.05-0.8")
_MU_D = Parameter("mu_d", "-", "dynamic coefficient", typical="0.03-0.6")
_MU_V = Parameter("mu_v", "N·s/m", "viscous coefficient", 0.0, typical="problem dependent")

_LAWS = (
    FrictionLaw(
        "coulomb", 0, coulomb_kernel, coulomb,
        (_MU_S, _MU_D, Parameter("v_reg", "m/s", "regularisation speed", 1.0e-3, strict=True,
                                 typical="1e-4 to 1e-2")),
        "static and dynamic Coulomb", "Coulomb; Karnopp 1985, J. Dyn. Syst. Meas. Control 107(1) 100-103",
        "f = μ_d N tanh(v/v_reg); stuck while |f| <= μ_s N", (("mu_d", "mu_s"),),
    ),
    FrictionLaw(
        "viscous", 1, viscous_kernel, viscous,
        (dataclasses.replace(_MU_V, default=None),),
        "viscous", "Olsson et al. 1998, Eur. J. Control 4(3) 176-195", "f = μ_v v",
    ),
    FrictionLaw(
        "viscous_normal", 2, viscous_normal_kernel, viscous_normal,
        (Parameter("k_v", "s/m", "viscous coefficient per unit normal force", typical="0.01-0.1"),),
        "viscous scaled by N", "viscous term of Olsson et al. 1998 scaled by N", "f = k_v N v",
    ),
    FrictionLaw(
        "stribeck", 3, stribeck_kernel, stribeck,
        (_MU_S, _MU_D, Parameter("v_s", "m/s", "stiction tolerance", 1.0e-3, strict=True,
                                 typical="1e-4 to 1e-2")),
        "Drake Stribeck model", "Drake MultibodyPlant StribeckModel (drake.mit.edu)",
        "f = μ(|v|/v_s) N sign(v), quintic steps: μ_s at v_s, μ_d from 3 v_s", (("mu_d", "mu_s"),),
    ),
    FrictionLaw(
        "andersson", 4, andersson_kernel, andersson,
        (_MU_S, _MU_D,
         Parameter("v_s", "m/s", "Stribeck speed", 1.0e-3, strict=True, typical="1e-3"),
         Parameter("exponent", "-", "Stribeck decay exponent", 2.0, strict=True, typical="0.5-2"),
         Parameter("k_t", "s/m", "tanh slope", 1.0e4, strict=True, typical="1e4"),
         _MU_V),
        "Andersson et al. 2007",
        "Andersson, Söderberg & Björklund 2007, Tribol. Int. 40(4) 580-587",
        "f = N[μ_d + (μ_s − μ_d) exp(−(|v|/v_s)^p)] tanh(k_t v) + μ_v v", (("mu_d", "mu_s"),),
    ),
    FrictionLaw(
        "brown_mcphee", 5, brown_mcphee_kernel, brown_mcphee,
        (_MU_S, _MU_D,
         Parameter("v_t", "m/s", "transition speed", 1.0e-3, strict=True, typical="1e-4 to 1e-2"),
         _MU_V,
         Parameter("f_nt", "N", "normal force scale of the viscous term", 1.0, strict=True,
                   typical="small against N")),
        "Brown & McPhee 2016", "Brown & McPhee 2016, ASME J. Comput. Nonlinear Dyn. 11(5) 054502",
        "f = μ_d N tanh(4v_r) + (μ_s − μ_d) N 16v_r/(v_r² + 3)² + μ_v v tanh(4N/f_nt), v_r = v/v_t",
        (("mu_d", "mu_s"),),
    ),
    FrictionLaw(
        "constantinou", 6, constantinou_kernel, constantinou,
        (Parameter("mu_min", "-", "coefficient at v = 0", typical="0.02-0.06"),
         Parameter("mu_max", "-", "coefficient at high speed", typical="0.05-0.15"),
         Parameter("a", "s/m", "rate parameter", typical="10-100"),
         Parameter("v_reg", "m/s", "regularisation speed of the rigid-plastic form", 1.0e-3,
                   strict=True, typical="1e-4 to 1e-2")),
        "Constantinou et al. 1990",
        "Constantinou, Mokha & Reinhorn 1990, J. Struct. Eng. 116(2) 455-474; Wen 1976",
        "f = μ(v) N z, μ(v) = μ_max − (μ_max − μ_min) exp(−a|v|), z Bouc-Wen (or tanh(v/v_reg))",
        (("mu_min", "mu_max"),), constantinou_bouc_wen_kernel,
    ),
)  # fmt: skip

#: Friction laws by registry name.
FRICTION_LAWS: dict[str, FrictionLaw] = {law.name: law for law in _LAWS}

#: Laws in kernel-id order (a compiled dispatcher's table).
LAWS_BY_ID: tuple[FrictionLaw, ...] = _LAWS
