r"""Normal contact laws for gap elements, each written once.

Sign convention (defined in :mod:`pounding.system`): penetration δ > 0 in contact, its rate δ̇ > 0 while
the bodies approach, v0 = δ̇ at the onset of the current impact. Every law returns a force that pushes
the bodies apart, is zero for δ <= 0 and is never negative (clamped at zero, whatever the law).

Each law is a *kernel*: a scalar function of plain floats written with ``math`` only, so the same source
runs in Python and compiles with numba (:mod:`pounding.integrators._kernels`). The signature is

``kernel(d, dd, v0, d_prev, f_prev, p) -> (force, dforce_dd, dforce_ddd)``

with ``d`` = δ [m], ``dd`` = δ̇ [m/s], ``v0`` the impact velocity [m/s], ``(d_prev, f_prev)`` the
penetration and force at the last converged state (history of the hysteretic bilinear law; ignored by
the others) and ``p`` a float array of kernel parameters packed by :func:`pounding.contact.calibrate.
contact_parameters`. Layout of ``p``: ``p[0]`` = k [N/m^n], ``p[1]`` = n [-] for every law but
``bilinear`` (whose ``p`` is K1, K2, δ_y); ``p[2]`` the law's damping coefficient in kernel form;
``p[3]`` the effective mass m̄ [kg] where the law needs it; ``p[4:7]`` the layer in the gap of
``bumper`` (k_r, its χ v0, the compression d_thr at which the crushed contact starts) and of
``filler`` (k_f, c_f, d_thr), ``p[7]`` = 1 for the filler; zero for the others.

The registry :data:`CONTACT_LAWS` maps names (and aliases) to :class:`ContactLaw` records: kernel,
kernel id (the index the compiled dispatcher switches on), the relation between the nominal
coefficient of restitution e and the law's damping parameter, and the literature reference.

References
----------
.. [1] Anagnostopoulos, S.A. (1988). Pounding of buildings in series during earthquakes. Earthquake
   Eng. Struct. Dyn. 16(3), 443-456. doi:10.1002/eqe.4290160311
.. [2] Hunt, K.H., Crossley, F.R.E. (1975). Coefficient of restitution interpreted as damping in
   vibroimpact. J. Appl. Mech. 42(2), 440-445. doi:10.1115/1.3423596
.. [3] Lankarani, H.M., Nikravesh, P.E. (1990). A contact force model with hysteresis damping for impact
   analysis of multibody systems. J. Mech. Des. 112(3), 369-376. doi:10.1115/1.2912617
.. [4] Muthukumar, S., DesRoches, R. (2006). A Hertz contact model with non-linear damping for pounding
   simulation. Earthquake Eng. Struct. Dyn. 35(7), 811-828. doi:10.1002/eqe.557
.. [5] Ye, K., Li, L., Zhu, H. (2009). A note on the Hertz contact model with nonlinear damping for
   pounding simulation. Earthquake Eng. Struct. Dyn. 38(9), 1135-1142. doi:10.1002/eqe.883
.. [6] Flores, P., Machado, M., Silva, M.T., Martins, J.M. (2011). On the continuous contact force
   models for soft materials in multibody dynamics. Multibody Syst. Dyn. 25(3), 357-375.
   doi:10.1007/s11044-010-9237-4
.. [7] Hu, S., Guo, X. (2015). A dissipative contact force model for impact analysis in multibody
   dynamics. Multibody Syst. Dyn. 35(2), 131-151. doi:10.1007/s11044-015-9453-z
.. [8] Gonthier, Y., McPhee, J., Lange, C., Piedboeuf, J.-C. (2004). A regularized contact model with
   asymmetric damping and dwell-time dependent friction. Multibody Syst. Dyn. 11(3), 209-233.
   doi:10.1023/B:MUBO.0000029392.21648.bc
.. [9] Jankowski, R. (2005). Non-linear viscoelastic modelling of earthquake-induced structural
   pounding. Earthquake Eng. Struct. Dyn. 34(6), 595-611. doi:10.1002/eqe.434
.. [10] Jankowski, R. (2006). Analytical expression between the impact damping ratio and the
   coefficient of restitution in the non-linear viscoelastic model of structural pounding. Earthquake
   Eng. Struct. Dyn. 35(4), 517-524. doi:10.1002/eqe.537
.. [11] Mahmoud, S., Jankowski, R. (2011). Modified linear viscoelastic model of earthquake-induced
   structural pounding. Iranian J. Sci. Technol. Trans. B Eng. 35(C1), 51-62.
.. [12] Muthukumar, S. (2003). A contact element approach with hysteresis damping for the analysis and
   design of pounding in bridges. PhD thesis, Georgia Institute of Technology.
.. [13] Maison, B.F., Kasai, K. (1992). Dynamics of pounding when two buildings collide. Earthquake
   Eng. Struct. Dyn. 21(9), 771-786. doi:10.1002/eqe.4290210903
.. [14] Hertz, H. (1882). Über die Berührung fester elastischer Körper. J. reine angew. Math. 92,
   156-171.
.. [15] Goldsmith, W. (1960). Impact: the theory and physical behaviour of colliding solids. Edward
   Arnold, London.
.. [16] Gilardi, G., Sharf, I. (2002). Literature survey of contact dynamics modelling. Mech. Mach.
   Theory 37(10), 1213-1239.
.. [17] Polycarpou, P.C., Komodromos, P., Polycarpou, A.C. (2013). A nonlinear impact model for
   simulating the use of rubber shock absorbers for mitigating the effects of structural pounding
   during earthquakes. Earthquake Eng. Struct. Dyn. 42(1), 81-100. doi:10.1002/eqe.2194
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable

import numpy as np

from pounding.errors import PoundingInputError

#: Impact velocities below this [m/s] are raised to it in the v0-scaled damping terms, so a grazing
#: contact (v0 -> 0) does not give the Hunt-Crossley family an infinite damping coefficient.
V0_FLOOR = 1.0e-4

#: Length of the kernel parameter array.
N_KERNEL_PARAMS = 8


# --------------------------------------------------------------------------------------------------
# Kernels (plain floats and ``math`` only: compiled by numba from this same source)
# --------------------------------------------------------------------------------------------------


def linear_kernel(d, dd, v0, d_prev, f_prev, p):
    r"""Linear spring [13]: :math:`F = k\delta`."""
    if d <= 0.0:
        return 0.0, 0.0, 0.0
    return p[0] * d, p[0], 0.0


def kelvin_kernel(d, dd, v0, d_prev, f_prev, p):
    r"""Kelvin-Voigt [1]: :math:`F = \max(k\delta + c\dot\delta, 0)`, c = p[2]."""
    if d <= 0.0:
        return 0.0, 0.0, 0.0
    f = p[0] * d + p[2] * dd
    if f <= 0.0:
        return 0.0, 0.0, 0.0
    return f, p[0], p[2]


def kelvin_approach_kernel(d, dd, v0, d_prev, f_prev, p):
    r"""Kelvin with damping only while approaching: :math:`F = k\delta + c\dot\delta` for δ̇ > 0 [11]."""
    if d <= 0.0:
        return 0.0, 0.0, 0.0
    if dd > 0.0:
        return p[0] * d + p[2] * dd, p[0], p[2]
    return p[0] * d, p[0], 0.0


def hertz_kernel(d, dd, v0, d_prev, f_prev, p):
    r"""Hertz [14], [15]: :math:`F = k_h\delta^n`."""
    if d <= 0.0:
        return 0.0, 0.0, 0.0
    dn1 = d ** (p[1] - 1.0)
    return p[0] * dn1 * d, p[1] * p[0] * dn1, 0.0


def hertz_kelvin_kernel(d, dd, v0, d_prev, f_prev, p):
    r"""Hertz spring with a linear dashpot [16]: :math:`F = \max(k_h\delta^n + c\dot\delta, 0)`.

    c = ζ m̄ v0 / δ*, δ* = (m̄ v0² / k_h)^(1/(n+1)): in units of δ* and δ*/v0 the impact depends on
    ζ = p[2] alone, so one numerically calibrated ζ gives the requested e at every impact speed.
    """
    if d <= 0.0:
        return 0.0, 0.0, 0.0
    k = p[0]
    n = p[1]
    v = max(v0, V0_FLOOR)
    m = p[3]
    c = p[2] * m * v / (m * v * v / k) ** (1.0 / (n + 1.0))
    dn1 = d ** (n - 1.0)
    f = k * dn1 * d + c * dd
    if f <= 0.0:
        return 0.0, 0.0, 0.0
    return f, n * k * dn1, c


def hunt_crossley_kernel(d, dd, v0, d_prev, f_prev, p):
    r"""Hunt-Crossley family [2]: :math:`F = k_h\delta^n (1 + \chi\dot\delta)`.

    χ = α / v0 with α = p[2]; the members of the family differ only in α(e) ([2]-[8]).
    """
    if d <= 0.0:
        return 0.0, 0.0, 0.0
    k = p[0]
    n = p[1]
    chi = p[2] / max(v0, V0_FLOOR)
    g = 1.0 + chi * dd
    if g <= 0.0:
        return 0.0, 0.0, 0.0
    dn1 = d ** (n - 1.0)
    dn = dn1 * d
    return k * dn * g, n * k * dn1 * g, k * dn * chi


def jankowski_kernel(d, dd, v0, d_prev, f_prev, p):
    r"""Jankowski non-linear viscoelastic [9]: :math:`F = k_h\delta^{n} + c(\delta)\dot\delta` for δ̇ > 0.

    c(δ) = 2ξ √(k_h δ^(n-1) m̄) (= 2ξ√(k_h √δ m̄) for n = 3/2), ξ = p[2], m̄ = p[3]; no damping while
    the bodies separate, so the force is never tensile.
    """
    if d <= 0.0:
        return 0.0, 0.0, 0.0
    k = p[0]
    n = p[1]
    dn1 = d ** (n - 1.0)
    f = k * dn1 * d
    kd = n * k * dn1
    if dd > 0.0:
        c0 = 2.0 * p[2] * math.sqrt(k * p[3])
        h = 0.5 * (n - 1.0)
        dh = d**h
        f += c0 * dh * dd
        return f, kd + c0 * h * dh / d * dd, c0 * dh
    return f, kd, 0.0


def bilinear_kernel(d, dd, v0, d_prev, f_prev, p):
    r"""Muthukumar bilinear loop (OpenSees ImpactMaterial) [4], [12].

    Elastic slope K1 = p[0] between the bounds K2 δ (unloading line) and K2 δ + (K1 − K2) δ_y
    (loading line), K2 = p[1], δ_y = p[2]: loading follows K1 to δ_y then K2; unloading follows K1 down
    to the line K2 δ, then that line to zero. Needs the last converged (δ, F).
    """
    if d <= 0.0:
        return 0.0, 0.0, 0.0
    k1 = p[0]
    k2 = p[1]
    lower = k2 * d
    upper = lower + (k1 - k2) * p[2]
    f = f_prev + k1 * (d - max(d_prev, 0.0))
    if f >= upper:
        return upper, k2, 0.0
    if f <= lower:
        return lower, k2, 0.0
    return f, k1, 0.0


def bumper_kernel(d, dd, v0, d_prev, f_prev, p):
    r"""Rubber bumper of limited thickness, then the crushed contact [17], [3]:

    .. math:: F = k_r\delta^n(1 + \chi_r\dot\delta)
              + k_h\langle\delta - d_{thr}\rangle^n(1 + \chi_h\dot\delta)

    δ is the bumper's compression (the element's gap is the clear gap less the bumper thickness),
    k_r = p[4], χ_r = p[5]/v0, d_thr = p[6] (the compression at which the structures meet through
    the crushed layer), k_h = p[0], n = p[1], χ_h = p[2]/v0 with v0 the speed at which the bumper was
    struck; each term is a Hunt-Crossley force, never tensile.
    """
    if d <= 0.0:
        return 0.0, 0.0, 0.0
    n = p[1]
    v = max(v0, V0_FLOOR)
    f = 0.0
    kd = 0.0
    kv = 0.0
    chi = p[5] / v
    g = 1.0 + chi * dd
    if g > 0.0:
        dn1 = d ** (n - 1.0)
        f += p[4] * dn1 * d * g
        kd += n * p[4] * dn1 * g
        kv += p[4] * dn1 * d * chi
    dc = d - p[6]
    if dc > 0.0:
        chi = p[2] / v
        g = 1.0 + chi * dd
        if g > 0.0:
            dn1 = dc ** (n - 1.0)
            f += p[0] * dn1 * dc * g
            kd += n * p[0] * dn1 * g
            kv += p[0] * dn1 * dc * chi
    return f, kd, kv


def filler_kernel(d, dd, v0, d_prev, f_prev, p):
    r"""Viscoelastic filler filling the whole gap, then the structures meeting through it [9]:

    .. math:: F = \max(k_f\delta + c_f\dot\delta, 0)
              + k_h\langle\delta - d_{thr}\rangle^n + c(\delta)\dot\delta\,[\dot\delta > 0]

    δ is the filler's compression (the element gap is zero), k_f = p[4] [N/m], c_f = p[5] [N s/m],
    d_thr = p[6] (the compression at which the structures meet), and the crushed contact is
    Jankowski's: k_h = p[0], n = p[1], c(δ) = 2ξ√(k_h ⟨δ − d_thr⟩^(n−1) m̄), ξ = p[2], m̄ = p[3],
    damped while approaching only (its damping does not depend on an impact speed the filler's
    own contact would set).
    """
    if d <= 0.0:
        return 0.0, 0.0, 0.0
    f = p[4] * d + p[5] * dd
    if f > 0.0:
        kd, kv = p[4], p[5]
    else:
        f, kd, kv = 0.0, 0.0, 0.0
    dc = d - p[6]
    if dc > 0.0:  # Jankowski's law on dc (written out: a compiled kernel calls no Python function)
        k = p[0]
        n = p[1]
        dn1 = dc ** (n - 1.0)
        f += k * dn1 * dc
        kd += n * k * dn1
        if dd > 0.0:
            c0 = 2.0 * p[2] * math.sqrt(k * p[3])
            h = 0.5 * (n - 1.0)
            dh = dc**h
            f += c0 * dh * dd
            kd += c0 * h * dh / dc * dd
            kv += c0 * dh
    return f, kd, kv


def bilinear_rate(d, dd, f, p):
    """dF/dt [N/s] of the bilinear loop at state (δ, F) moving at δ̇ (the ivp form of the same law)."""
    if d <= 0.0:
        return 0.0
    lower = p[1] * d
    upper = lower + (p[0] - p[1]) * p[2]
    if (f >= upper and dd > 0.0) or (f <= lower and dd < 0.0):
        return p[1] * dd
    return p[0] * dd


def stored_energy(is_bilinear, d, f, p):
    r"""Recoverable energy [J] held by a contact at penetration δ and force F.

    Elastic laws: :math:`k\delta^{n+1}/(n+1)` (n = 1 for the linear family); the bumper adds its
    rubber's and the crushed contact's. Bilinear: the area under the unloading path from (δ, F) along
    K1 to the line K2 δ and down it to the origin.
    """
    if d <= 0.0:
        return 0.0
    if p[7] > 0.0:  # filler: its spring, and the crushed contact beyond d_thr
        dc = max(d - p[6], 0.0)
        return 0.5 * p[4] * d * d + p[0] * dc ** (p[1] + 1.0) / (p[1] + 1.0)
    if p[4] > 0.0:  # bumper: the rubber layer, and the crushed contact beyond d_thr
        dc = max(d - p[6], 0.0)
        return (p[4] * d ** (p[1] + 1.0) + p[0] * dc ** (p[1] + 1.0)) / (p[1] + 1.0)
    if is_bilinear:
        k1 = p[0]
        k2 = p[1]
        d1 = min(max((k1 * d - f) / (k1 - k2), 0.0), d)
        return 0.5 * (f + k2 * d1) * (d - d1) + 0.5 * k2 * d1 * d1
    return p[0] * d ** (p[1] + 1.0) / (p[1] + 1.0)


# --------------------------------------------------------------------------------------------------
# Damping relations: nominal restitution e -> the law's damping parameter
# --------------------------------------------------------------------------------------------------


def _check_e(e: float) -> float:
    e = float(e)
    if not (0.0 < e <= 1.0):
        raise PoundingInputError(f"coefficient of restitution e = {e}; allowed: 0 < e <= 1")
    return e


def xi_anagnostopoulos(e: float) -> float:
    r"""Kelvin damping ratio from e [1]: :math:`\xi = -\ln e / \sqrt{\pi^2 + \ln^2 e}`."""
    le = math.log(_check_e(e))
    return -le / math.sqrt(math.pi**2 + le * le)


def restitution_kelvin_approach(xi: float) -> float:
    r"""Exact e of a linear oscillator damped only on approach (damped quarter, undamped rebound).

    .. math:: e = \exp\!\left(-\frac{\xi}{\sqrt{1-\xi^2}}\arctan\frac{\sqrt{1-\xi^2}}{\xi}\right)

    for ξ < 1, and with the hyperbolic functions for ξ > 1 (overdamped approach).
    """
    if xi <= 0.0:
        return 1.0
    if xi < 1.0:
        s = math.sqrt(1.0 - xi * xi)
        return math.exp(-xi / s * math.atan2(s, xi))
    if xi == 1.0:
        return math.exp(-1.0)
    s = math.sqrt(xi * xi - 1.0)
    return math.exp(-xi / s * math.atanh(s / xi))


def xi_kelvin_approach(e: float) -> float:
    """Damping ratio ξ that gives restitution e for ``kelvin_approach`` (inverse of the exact relation)."""
    e = _check_e(e)
    if e == 1.0:
        return 0.0
    from scipy.optimize import brentq  # here, not at import: scipy.optimize loads slowly

    hi = 1.0
    while restitution_kelvin_approach(hi) > e:
        hi *= 2.0
    return brentq(lambda x: restitution_kelvin_approach(x) - e, 0.0, hi, xtol=1e-14, rtol=1e-14)


def alpha_lankarani_nikravesh(e: float) -> float:
    """χ v0 = 3(1 − e²)/4, Lankarani & Nikravesh [3] ('Hertzdamp' of Muthukumar & DesRoches [4])."""
    e = _check_e(e)
    return 0.75 * (1.0 - e * e)


def alpha_flores(e: float) -> float:
    """χ v0 = 8(1 − e)/(5 e), Ye, Li & Zhu [5]; Flores et al. [6]."""
    e = _check_e(e)
    return 1.6 * (1.0 - e) / e


def alpha_hu_guo(e: float) -> float:
    """χ v0 = 3(1 − e)/(2 e) [7]."""
    e = _check_e(e)
    return 1.5 * (1.0 - e) / e


def alpha_gonthier(e: float) -> float:
    """χ v0 = (1 − e²)/e [8]."""
    e = _check_e(e)
    return (1.0 - e * e) / e


def hunt_crossley_residual(u: float, e: float) -> float:
    """Residual of the exact Hunt-Crossley relation 1 − e u − (1 + u) exp(−(1 + e) u), u = χ v0."""
    return 1.0 - e * u - (1.0 + u) * math.exp(-(1.0 + e) * u)


def alpha_hunt_crossley(e: float) -> float:
    r"""χ v0 = u solving the exact Hunt-Crossley energy relation [2].

    .. math:: 1 - e u = (1 + u)\, e^{-(1+e)u}

    obtained by integrating m v dv / (1 + χ v) = −k δ^n dδ over a whole impact; it holds for any n, k
    and mass. Small damping gives u ≈ 3(1 − e)/2.
    """
    e = _check_e(e)
    if e == 1.0:
        return 0.0
    # The residual is u²(1 − e²)/2 + O(u³) near 0 (lost to round-off for tiny u) and negative at 1/e;
    # the root is above (1 − e), so bracket from there.
    from scipy.optimize import brentq

    return brentq(
        hunt_crossley_residual, 0.5 * (1.0 - e), 1.0 / e, args=(e,), xtol=1e-15, rtol=1e-15
    )


def xi_jankowski(e: float) -> float:
    r"""Jankowski's damping ratio from e [10]: :math:`\xi = \frac{9\sqrt5}{2}\frac{1-e^2}{e(e(9\pi-16)+16)}`."""
    e = _check_e(e)
    return 4.5 * math.sqrt(5.0) * (1.0 - e * e) / (e * (e * (9.0 * math.pi - 16.0) + 16.0))


def bilinear_stiffnesses(
    *, k: float, n: float, e: float, a: float, delta_m: float, dissipation: float | None = None
) -> tuple[float, float, float]:
    r"""K1, K2 [N/m] and δ_y [m] of the Muthukumar bilinear loop [12].

    .. math:: K_{eff} = k_h\sqrt{\delta_m},\quad \Delta E = k_h\delta_m^{n+1}(1-e^2)/(n+1),\quad
              K_1 = K_{eff} + \frac{\Delta E}{a\delta_m^2},\quad K_2 = K_{eff} - \frac{\Delta E}{(1-a)\delta_m^2},
              \quad \delta_y = a\delta_m

    (K_eff = k_h δ_m^(n−1) in general; √δ_m for the Hertz n = 3/2). ``dissipation`` replaces 1 − e²
    when the loop is calibrated numerically.
    """
    d = (1.0 - _check_e(e) ** 2) if dissipation is None else float(dissipation)
    keff = k * delta_m ** (n - 1.0)
    de = k * delta_m ** (n + 1.0) * d / (n + 1.0)
    k1 = keff + de / (a * delta_m**2)
    k2 = keff - de / ((1.0 - a) * delta_m**2)
    if k2 <= 0.0:
        raise PoundingInputError(
            f"bilinear law: e = {e} and a = {a} give a non-positive post-yield stiffness K2 = {k2:.4g} N/m;"
            " raise e or lower a"
        )
    return k1, k2, a * delta_m


# --------------------------------------------------------------------------------------------------
# Registry
# --------------------------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class ContactLaw:
    """A contact law: its kernel and how its damping follows from the nominal restitution e.

    Attributes
    ----------
    name : str
        Registry name.
    kernel_id : int
        Index the compiled dispatcher switches on (stable; see :mod:`pounding.integrators._kernels`).
    kernel : callable
        ``kernel(d, dd, v0, d_prev, f_prev, p) -> (F, dF/dδ, dF/dδ̇)``.
    damping : str
        What ``p[2]`` holds: ``"none"``, ``"xi"`` (damping ratio, c = 2ξ√(k m̄)), ``"alpha"``
        (χ v0 of the Hunt-Crossley family), ``"zeta"`` (hertz_kelvin's dimensionless c), ``"xi_jankowski"``
        or ``"loop"`` (bilinear dissipated fraction 1 − e²).
    damping_from_e : callable or None
        Nominal damping parameter as a function of e; None where only numerical calibration exists.
    default_n : float
        Exponent used when the user gives none (1 for the linear family).
    formula, reference : str
        One-line force law and source, for ``pounding laws`` and reports.
    aliases : tuple of str
        Other accepted names.
    """

    name: str
    kernel_id: int
    kernel: Callable
    damping: str
    damping_from_e: Callable[[float], float] | None
    default_n: float
    formula: str
    reference: str
    aliases: tuple[str, ...] = ()

    @property
    def has_damping(self) -> bool:
        return self.damping != "none"

    @property
    def has_exponent(self) -> bool:
        """Whether the user may set n (the linear family is fixed at n = 1)."""
        return self.default_n != 1.0

    @property
    def is_bilinear(self) -> bool:
        return self.damping == "loop"

    @property
    def is_bumper(self) -> bool:
        """A rubber layer in the gap (:func:`bumper_kernel`): thickness, k_rubber, e_rubber."""
        return self.name == "bumper"

    @property
    def is_filler(self) -> bool:
        """A viscoelastic filler filling the gap (:func:`filler_kernel`): k_filler, c_filler."""
        return self.name == "filler"


_LAWS = (
    ContactLaw("linear", 0, linear_kernel, "none", None, 1.0, "F = k δ",
               "Maison & Kasai 1992, EESD 21(9) 771-786"),
    ContactLaw("kelvin", 1, kelvin_kernel, "xi", xi_anagnostopoulos, 1.0,
               "F = max(k δ + c δ̇, 0), c = 2ξ√(k m̄), ξ = −ln e/√(π² + ln² e)",
               "Anagnostopoulos 1988, EESD 16(3) 443-456"),
    ContactLaw("kelvin_approach", 2, kelvin_approach_kernel, "xi", xi_kelvin_approach, 1.0,
               "F = k δ + c δ̇ (δ̇ > 0), k δ (δ̇ <= 0); exact ξ(e)",
               "Mahmoud & Jankowski 2011, Iran. J. Sci. Technol. 35(C1) 51-62"),
    ContactLaw("hertz", 3, hertz_kernel, "none", None, 1.5, "F = k δ^n",
               "Hertz 1882; Goldsmith 1960, Impact"),
    ContactLaw("hertz_kelvin", 4, hertz_kelvin_kernel, "zeta", None, 1.5,
               "F = max(k δ^n + c δ̇, 0), c calibrated numerically to e at each impact",
               "Hertz spring + linear dashpot, e.g. Gilardi & Sharf 2002, MMT 37(10) 1213-1239"),
    ContactLaw("lankarani_nikravesh", 5, hunt_crossley_kernel, "alpha", alpha_lankarani_nikravesh,
               1.5, "F = k δ^n (1 + χ δ̇), χ = 3(1 − e²)/(4 v0)",
               "Lankarani & Nikravesh 1990, J. Mech. Des. 112(3) 369-376; Muthukumar & DesRoches 2006",
               ("hertzdamp",)),
    ContactLaw("flores", 6, hunt_crossley_kernel, "alpha", alpha_flores, 1.5,
               "F = k δ^n (1 + χ δ̇), χ = 8(1 − e)/(5 e v0)",
               "Ye, Li & Zhu 2009, EESD 38(9) 1135-1142; Flores et al. 2011, MSD 25(3) 357-375",
               ("ye",)),
    ContactLaw("hu_guo", 7, hunt_crossley_kernel, "alpha", alpha_hu_guo, 1.5,
               "F = k δ^n (1 + χ δ̇), χ = 3(1 − e)/(2 e v0)", "Hu & Guo 2015, MSD 35(2) 131-151"),
    ContactLaw("gonthier", 8, hunt_crossley_kernel, "alpha", alpha_gonthier, 1.5,
               "F = k δ^n (1 + χ δ̇), χ = (1 − e²)/(e v0)", "Gonthier et al. 2004, MSD 11(3) 209-233"),
    ContactLaw("hunt_crossley", 9, hunt_crossley_kernel, "alpha", alpha_hunt_crossley, 1.5,
               "F = k δ^n (1 + χ δ̇), χ v0 = u: 1 − e u = (1 + u) exp(−(1 + e) u)",
               "Hunt & Crossley 1975, J. Appl. Mech. 42(2) 440-445"),
    ContactLaw("jankowski", 10, jankowski_kernel, "xi", xi_jankowski, 1.5,
               "F = k δ^1.5 + c δ̇ (δ̇ > 0), c = 2ξ√(k √δ m̄), ξ(e) of Jankowski 2006",
               "Jankowski 2005, EESD 34(6) 595-611; Jankowski 2006, EESD 35(4) 517-524"),
    ContactLaw("bilinear", 11, bilinear_kernel, "loop", lambda e: 1.0 - e * e, 1.5,
               "K1 to δ_y = a δ_m, then K2; unload on K1 to F = K2 δ (loop energy k δ_m^(n+1)(1 − e²)/(n+1))",
               "Muthukumar 2003 (PhD, Georgia Tech); Muthukumar & DesRoches 2006, EESD 35(7) 811-828",
               ("impact_material",)),
    ContactLaw("bumper", 12, bumper_kernel, "alpha", alpha_lankarani_nikravesh, 1.5,
               "F = k_r δ^n (1 + χ_r δ̇) + k ⟨δ − d_thr⟩^n (1 + χ δ̇), χ = 3(1 − e²)/(4 v0) for "
               "the rubber (e_rubber) and the crushed contact (e); gap less the bumper thickness",
               "Polycarpou, Komodromos & Polycarpou 2013, EESD 42(1) 81-100; Lankarani & Nikravesh "
               "1990", ("rubber_bumper",)),
    ContactLaw("filler", 13, filler_kernel, "xi", xi_jankowski, 1.5,
               "F = max(k_f δ + c_f δ̇, 0) + k ⟨δ − d_thr⟩^n + c δ̇ (approaching), c = 2ξ√(k ⟨δ − "
               "d_thr⟩^(n−1) m̄): a viscoelastic filler filling the gap, then the structures "
               "through it", "Jankowski 2005, EESD 34(6) 595-611 (both parts)", ("gap_filler",)),
)  # fmt: skip

#: Contact laws by registry name (aliases included).
CONTACT_LAWS: dict[str, ContactLaw] = {}
for _law in _LAWS:
    CONTACT_LAWS[_law.name] = _law
    for _alias in _law.aliases:
        CONTACT_LAWS[_alias] = _law

#: Laws in kernel-id order (the compiled dispatcher's table).
LAWS_BY_ID: tuple[ContactLaw, ...] = _LAWS


def get_contact_law(name: str | ContactLaw) -> ContactLaw:
    """The registered law called ``name`` (aliases accepted); unknown names list the valid ones."""
    if isinstance(name, ContactLaw):
        return name
    key = str(name).strip().lower()
    try:
        return CONTACT_LAWS[key]
    except KeyError:
        allowed = ", ".join(sorted(CONTACT_LAWS))
        raise PoundingInputError(f"unknown contact law {name!r}; allowed: {allowed}") from None


def contact_force(
    law: str | ContactLaw,
    delta: float | np.ndarray,
    delta_dot: float | np.ndarray,
    params: np.ndarray,
    *,
    v0: float | np.ndarray = 1.0,
    history: tuple[float, float] = (0.0, 0.0),
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Force [N] and tangents ∂F/∂δ [N/m], ∂F/∂δ̇ [N·s/m] of a law, vectorised over δ, δ̇, v0.

    ``params`` is the kernel parameter array from :func:`pounding.contact.calibrate.contact_parameters`.
    ``history`` = (δ, F) at the last converged state, used by ``bilinear`` only.
    """
    law = get_contact_law(law)
    p = np.asarray(params, dtype=float)
    d, dd, v = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (delta, delta_dot, v0)))
    out = np.empty((3, *d.shape))
    for idx in np.ndindex(d.shape):
        out[(slice(None), *idx)] = law.kernel(
            float(d[idx]), float(dd[idx]), float(v[idx]), history[0], history[1], p
        )
    return out[0], out[1], out[2]
