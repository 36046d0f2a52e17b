"""Tests for pounding.contact.calibrate: parameter validation, single-impact effective restitution
against closed forms and independent integrations, and exact calibration for every damped law.

References: Goldsmith (1960) Impact (Hertz
impact); Anagnostopoulos (1988) EESD 16(3); Hunt & Crossley (1975) J. Appl. Mech. 42(2);
Jankowski (2006) EESD 35(4) 517-524; Muthukumar & DesRoches (2006) EESD 35(7).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.special import beta

from pounding.contact import calibrate
from pounding.contact.calibrate import (
    ImpactResult,
    contact_parameters,
    effective_restitution,
    hertz_max_penetration,
)
from pounding.contact.laws import (
    LAWS_BY_ID,
    alpha_flores,
    alpha_hunt_crossley,
    bilinear_stiffnesses,
    get_contact_law,
    xi_anagnostopoulos,
    xi_jankowski,
    xi_kelvin_approach,
)

DAMPED = [law.name for law in LAWS_BY_ID if law.has_damping]
LINEAR_FAMILY = [law.name for law in LAWS_BY_ID if not law.has_exponent]
NEEDS_MASS = ["kelvin", "kelvin_approach", "hertz_kelvin", "jankowski"]

# Hertz contact time constant. Energy: δ̇² = v0² (1 − (δ/δ_max)^(n+1)), so
# t_c = 2 ∫_0^δ_max dδ/δ̇ = 2 (δ_max/v0) ∫_0^1 dx/√(1 − x^(n+1)); with y = x^(n+1),
# dx = y^(1/(n+1) − 1) dy/(n+1) this is (2/(n+1)) B(1/(n+1), 1/2) δ_max/v0.
# For n = 3/2: (4/5) B(2/5, 1/2) = (4/5) Γ(2/5) Γ(1/2)/Γ(9/10) = 2.943275...; n = 1 gives π.
HERTZ_TC = 2.943275


def hertz_tc_constant(n):
    return 2.0 / (n + 1.0) * beta(1.0 / (n + 1.0), 0.5)


def free_impact(force, *, mass, v0, t_max):
    """Independent m δ̈ = −F(δ, δ̇) from (0, v0) until δ = 0; returns rebound speed / v0."""

    def back(t, y):
        return y[0]

    back.terminal = True
    back.direction = -1.0
    sol = solve_ivp(
        lambda t, y: [y[1], -force(y[0], y[1]) / mass],
        (0.0, t_max),
        [0.0, v0],
        method="LSODA",
        events=back,
        rtol=1e-12,
        atol=[1e-16, 1e-14 * v0],
    )
    assert sol.t_events[0].size == 1
    return -sol.y_events[0][0][1] / v0


# --------------------------------------------------------------------------------------------------
# contact_parameters: validation and packing
# --------------------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", DAMPED)
def test_damped_law_needs_e(name):
    extra = {"delta_m": 0.01} if get_contact_law(name).is_bilinear else {}
    with pytest.raises(ValueError, match=rf"law '{name}' needs e \(0 < e <= 1\)"):
        contact_parameters(name, k=1e8, mass=1e4, **extra)


@pytest.mark.parametrize("e", [1.2, 0.0, -0.5, math.nan, math.inf])
def test_e_out_of_range_names_e(e):
    with pytest.raises(ValueError, match=r"e = .*allowed: 0 < e <= 1"):
        contact_parameters("flores", k=1e8, e=e)


@pytest.mark.parametrize("k", [-1.0e8, 0.0, math.nan, math.inf])
@pytest.mark.parametrize("name", ["linear", "hertz", "flores"])
def test_bad_k_names_k(name, k):
    with pytest.raises(ValueError, match=rf"law '{name}': k = .*allowed: > 0"):
        contact_parameters(name, k=k, e=0.6)


def test_missing_k_names_k():
    with pytest.raises(ValueError, match=r"needs k"):
        contact_parameters("hertz", k=None)


@pytest.mark.parametrize("name", LINEAR_FAMILY)
def test_exponent_rejected_for_linear_laws(name):
    with pytest.raises(
        ValueError, match=rf"law '{name}' is linear .* no exponent n \(got n = 1.5\)"
    ):
        contact_parameters(name, k=1e7, e=0.6, n=1.5, mass=1e4)
    # n = 1 is what they are: accepted
    p = contact_parameters(name, k=1e7, e=0.6, n=1.0, mass=1e4)
    assert p[1] == 1.0


@pytest.mark.parametrize("n", [0.5, 3.5, math.nan])
def test_exponent_out_of_range(n):
    with pytest.raises(ValueError, match=r"law 'hertz': n = .*allowed: 1 <= n <= 3"):
        contact_parameters("hertz", k=1e8, n=n)


@pytest.mark.parametrize("name", NEEDS_MASS)
def test_mass_required_by_mass_dependent_damping(name):
    with pytest.raises(ValueError, match=rf"law '{name}' needs mass"):
        contact_parameters(name, k=1e8, e=0.6)


@pytest.mark.parametrize("name", ["flores", "hunt_crossley", "bilinear"])
def test_mass_required_by_exact_calibration(name):
    extra = {"delta_m": 0.01} if name == "bilinear" else {}
    # nominal works without a mass ...
    contact_parameters(name, k=1e8, e=0.6, **extra)
    # ... exact needs it
    with pytest.raises(ValueError, match=rf"law '{name}' needs mass"):
        contact_parameters(name, k=1e8, e=0.6, calibration="exact", **extra)


@pytest.mark.parametrize("mass", [-1.0, 0.0])
def test_bad_mass_names_mass(mass):
    with pytest.raises(ValueError, match=r"law 'kelvin': mass .* = .*allowed: > 0"):
        contact_parameters("kelvin", k=1e8, e=0.6, mass=mass)


def test_bilinear_needs_delta_m():
    with pytest.raises(ValueError, match=r"law 'bilinear' needs delta_m"):
        contact_parameters("bilinear", k=1e8, e=0.6)
    with pytest.raises(ValueError, match=r"delta_m .* = -0.01"):
        contact_parameters("bilinear", k=1e8, e=0.6, delta_m=-0.01)


@pytest.mark.parametrize("a", [0.0, 1.0, -0.1, 1.5])
def test_bilinear_yield_fraction(a):
    with pytest.raises(ValueError, match=r"law 'bilinear': a = .*allowed: 0 < a < 1"):
        contact_parameters("bilinear", k=1e8, e=0.6, a=a, delta_m=0.01)


def test_bilinear_non_positive_k2_is_rejected():
    with pytest.raises(ValueError, match=r"K2"):
        contact_parameters("bilinear", k=1e8, e=0.1, a=0.7, delta_m=0.01)


@pytest.mark.parametrize("calibration", ["exakt", "", "Exact", None])
def test_bad_calibration_string(calibration):
    with pytest.raises(ValueError, match=r"calibration = .*allowed: nominal, exact"):
        contact_parameters("flores", k=1e8, e=0.6, mass=1.0, calibration=calibration)


def test_unknown_law():
    with pytest.raises(ValueError, match=r"unknown contact law 'hertzian'.*allowed: .*bilinear"):
        contact_parameters("hertzian", k=1e8)


@pytest.mark.parametrize(
    ("kwargs", "field"), [({"v0": 0.0}, "v0"), ({"v0": -1.0}, "v0"), ({"mass": 0.0}, "mass")]
)
def test_effective_restitution_validates_before_integrating(kwargs, field):
    args = {"k": 1e8, "mass": 1.0, "v0": 1.0, "e": 0.6} | kwargs
    with pytest.raises(ValueError, match=rf"{field} = "):
        effective_restitution("flores", **args)


def test_packing_of_the_damping_parameters():
    k, m, e = 2.75e9, 3.0e5, 0.65
    p = contact_parameters("kelvin", k=k, e=e, mass=m)
    assert p[:2].tolist() == [k, 1.0]
    assert p[2] == pytest.approx(2 * xi_anagnostopoulos(e) * math.sqrt(k * m), rel=1e-14)
    p = contact_parameters("kelvin_approach", k=k, e=e, mass=m)
    assert p[2] == pytest.approx(2 * xi_kelvin_approach(e) * math.sqrt(k * m), rel=1e-14)
    p = contact_parameters("ye", k=k, e=e)
    assert p[:3].tolist() == [k, 1.5, alpha_flores(e)]
    p = contact_parameters("jankowski", k=k, e=e, mass=m)
    assert p.tolist() == [k, 1.5, xi_jankowski(e), m, 0.0, 0.0, 0.0, 0.0]
    p = contact_parameters("hertz", k=k, n=2.0, e=e)
    assert p.tolist() == [k, 2.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]


# --------------------------------------------------------------------------------------------------
# Closed forms of undamped impacts
# --------------------------------------------------------------------------------------------------


def test_hertz_contact_time_constant_is_the_beta_function():
    assert hertz_tc_constant(1.5) == pytest.approx(HERTZ_TC, abs=5e-7)
    assert 0.8 * beta(0.4, 0.5) == pytest.approx(2.943275, abs=5e-7)
    assert hertz_tc_constant(1.0) == pytest.approx(math.pi, rel=1e-14)


@pytest.mark.parametrize(
    ("k", "mass", "v0"),
    [(2.75e9, 3.0e5, 0.5), (1.0e8, 1.0e4, 1.0), (5.0e10, 2.0, 3.0)],
)
def test_undamped_hertz_impact_goldsmith(k, mass, v0):
    # Goldsmith (1960): δ_max = (5 m v0²/(4 k))^(2/5), t_c = 2.943275 δ_max/v0, e = 1.
    res = effective_restitution("hertz", k=k, mass=mass, v0=v0)
    d_max = (5 * mass * v0**2 / (4 * k)) ** 0.4
    assert res.max_penetration == pytest.approx(d_max, rel=1e-6)
    assert res.contact_duration == pytest.approx(HERTZ_TC * d_max / v0, rel=1e-6)
    assert res.peak_force == pytest.approx(k * d_max**1.5, rel=1e-6)
    assert res.e_effective == pytest.approx(1.0, abs=1e-8)
    assert hertz_max_penetration(k=k, n=1.5, mass=mass, v0=v0) == pytest.approx(d_max, rel=1e-14)


@pytest.mark.parametrize("n", [1.0, 2.0, 3.0])
def test_undamped_power_law_impact_any_exponent(n):
    # Same energy argument for F = k δ^n: δ_max = ((n+1) m v0²/(2k))^(1/(n+1)),
    # t_c = (2/(n+1)) B(1/(n+1), 1/2) δ_max/v0.
    k, mass, v0 = 1.0e9, 50.0, 2.0
    res = effective_restitution("hertz", k=k, n=n, mass=mass, v0=v0)
    d_max = ((n + 1) * mass * v0**2 / (2 * k)) ** (1 / (n + 1))
    assert res.max_penetration == pytest.approx(d_max, rel=1e-6)
    assert res.contact_duration == pytest.approx(hertz_tc_constant(n) * d_max / v0, rel=1e-6)


@pytest.mark.parametrize(("k", "mass", "v0"), [(1.0e9, 3.0e5, 0.4), (2.0e3, 1.5, 10.0)])
def test_linear_impact_half_period(k, mass, v0):
    # Maison & Kasai (1992): half a period of √(k/m), δ_max = v0 √(m/k), no loss.
    res = effective_restitution("linear", k=k, mass=mass, v0=v0)
    assert res.contact_duration == pytest.approx(math.pi * math.sqrt(mass / k), rel=1e-6)
    assert res.max_penetration == pytest.approx(v0 * math.sqrt(mass / k), rel=1e-6)
    assert res.peak_force == pytest.approx(v0 * math.sqrt(k * mass), rel=1e-6)
    assert res.e_effective == pytest.approx(1.0, abs=1e-8)


def test_impact_result_keys_for_the_cli():
    res = effective_restitution("linear", k=1e6, mass=1.0, v0=1.0)
    assert isinstance(res, ImpactResult)
    assert set(res.as_dict()) == {
        "e_effective",
        "max_penetration",
        "peak_force",
        "contact_duration",
        "force_duration",
        "overlap_duration",
    }
    assert res.as_dict()["contact_duration"] == res.force_duration


# --------------------------------------------------------------------------------------------------
# Damped laws: nominal relations and what the clamped law really does
# --------------------------------------------------------------------------------------------------


@pytest.mark.parametrize(("e", "gap"), [(0.3, 0.05), (0.6, 0.02), (0.9, 1e-3)])
def test_kelvin_clamped_rebounds_more_than_nominal_e(e, gap):
    # Anagnostopoulos 1988, Gilardi & Sharf 2002: with ξ of Anagnostopoulos the unclamped force turns tensile near the end of
    # restitution; clamping it removes that pull, so the clamped law's effective e exceeds e.
    k, mass, v0 = 2.75e9 / 10, 3.0e5, 0.5  # linear impact spring [N/m]
    res = effective_restitution("kelvin", k=k, e=e, mass=mass, v0=v0)
    c = 2 * xi_anagnostopoulos(e) * math.sqrt(k * mass)
    clamped = free_impact(
        lambda d, dd: max(k * d + c * dd, 0.0) if d > 0 else 0.0,
        mass=mass,
        v0=v0,
        t_max=20 * math.sqrt(mass / k),
    )
    assert res.e_effective == pytest.approx(clamped, rel=1e-6)
    # observed e_eff − e: 0.097 at e = 0.3, 0.033 at 0.6, 0.002 at 0.9
    assert res.e_effective > e + gap
    # with calibration="exact" the clamped law returns e
    exact = effective_restitution("kelvin", k=k, e=e, mass=mass, v0=v0, calibration="exact")
    assert exact.e_effective == pytest.approx(e, rel=5e-3)


def kelvin_free_impact_closed_form(k, c, mass, v0):
    """Clamped Kelvin-Voigt impact of a mass on a rigid wall, underdamped (ξ < 1/√2).

    Until the force ends δ(t) = (v0/ω_d) exp(−ξωt) sin ω_d t. The force m(ω²δ + 2ξωδ̇) is
    proportional to exp(−ξωt)[(1 − 2ξ²)ω sin ω_d t + 2ξ ω_d cos ω_d t]/ω_d, zero at
    ω_d t_f = π − atan(2ξ√(1 − ξ²)/(1 − 2ξ²)); then the mass flies free at δ̇(t_f) < 0 and
    leaves the overlap at t_f + δ(t_f)/|δ̇(t_f)|. Without the clamp it would leave at π/ω_d.
    Returns (t_f, t_overlap, e = −δ̇(t_f)/v0).
    """
    w = math.sqrt(k / mass)
    xi = c / (2.0 * math.sqrt(k * mass))
    wd = w * math.sqrt(1.0 - xi * xi)
    t_f = (math.pi - math.atan(2 * xi * math.sqrt(1 - xi * xi) / (1 - 2 * xi * xi))) / wd
    decay = math.exp(-xi * w * t_f)
    d_f = v0 / wd * decay * math.sin(wd * t_f)
    v_f = v0 * decay * (math.cos(wd * t_f) - xi * w / wd * math.sin(wd * t_f))
    return t_f, t_f + d_f / -v_f, -v_f / v0


@pytest.mark.parametrize(
    ("e", "k", "mass", "v0"), [(0.65, 1.0e8, 1.0e5, 1.0), (0.3, 2.0e9, 3.0e5, 0.4)]
)
def test_kelvin_force_and_overlap_durations_against_closed_form(e, k, mass, v0):
    # Issue 12 §6: the clamped Kelvin force ends before the overlap does; both durations and the
    # restitution (speed when the force ends = speed at separation) follow the underdamped
    # oscillator's closed form (Anagnostopoulos 1988) to 1e-6.
    res = effective_restitution("kelvin", k=k, e=e, mass=mass, v0=v0)
    c = 2 * xi_anagnostopoulos(e) * math.sqrt(k * mass)
    t_f, t_overlap, e_eff = kelvin_free_impact_closed_form(k, c, mass, v0)
    assert res.force_duration == pytest.approx(t_f, rel=1e-6)
    assert res.contact_duration == res.force_duration
    assert res.overlap_duration == pytest.approx(t_overlap, rel=1e-6)
    assert res.e_effective == pytest.approx(e_eff, rel=1e-6)
    # the overlap outlasts the force (by 9 % at e = 0.65) but ends before the unclamped π/ω_d
    w_d = math.sqrt(k / mass) * math.sqrt(1 - xi_anagnostopoulos(e) ** 2)
    assert t_f < 0.95 * t_overlap and t_overlap < math.pi / w_d


@pytest.mark.parametrize("law", ["linear", "hertz", "jankowski", "kelvin_approach"])
def test_force_and_overlap_end_together_when_never_clamped(law):
    # Laws whose force stays positive while δ > 0 release at separation: both durations agree.
    params = {} if law in ("linear", "hertz") else {"e": 0.6}
    res = effective_restitution(law, k=1e8, mass=1e4, v0=1.0, **params)
    assert res.force_duration == pytest.approx(res.overlap_duration, rel=1e-9)


@pytest.mark.parametrize("e", [0.3, 0.65, 0.9])
def test_kelvin_approach_nominal_is_exact(e):
    # Damping only while approaching: never tensile, and the exact ξ(e) holds with the clamp.
    res = effective_restitution("kelvin_approach", k=1e7, e=e, mass=1e4, v0=0.7)
    assert res.e_effective == pytest.approx(e, rel=1e-6)


@pytest.mark.parametrize(
    ("n", "e", "k", "mass", "v0"),
    [(1.0, 0.4, 1.0e4, 2.0, 0.5), (1.5, 0.65, 2.75e9, 3.0e5, 0.4), (2.0, 0.85, 1.0e9, 10.0, 3.0)],
)
def test_hunt_crossley_law_returns_e_for_any_exponent(n, e, k, mass, v0):
    # The exact Hunt-Crossley relation holds for any n, k and mass (the HC force never turns
    # tensile in a free impact: 1 + χ δ̇ >= 1 − e u > 0), so the nominal law is exact.
    res = effective_restitution("hunt_crossley", k=k, n=n, e=e, mass=mass, v0=v0)
    assert res.e_effective == pytest.approx(e, rel=1e-6)
    chi = alpha_hunt_crossley(e) / v0
    independent = free_impact(
        lambda d, dd: k * max(d, 0.0) ** n * (1 + chi * dd),
        mass=mass,
        v0=v0,
        t_max=50 * res.contact_duration,
    )
    assert res.e_effective == pytest.approx(independent, rel=1e-7)


@pytest.mark.parametrize("e", [0.3, 0.5, 0.65, 0.8, 0.95])
def test_jankowski_2006_xi_approximates_e(e):
    # Jankowski (2006) derived ξ(e) as an approximation for the non-linear viscoelastic model.
    # Observed (k = 2.75e9 N/m^1.5, m = 3e5 kg, v0 = 0.5 m/s, self-similar in k, m, v0): the
    # effective e is slightly below e, by 8.3e-3 at e = 0.3, 5.4e-3 at 0.5, 3.1e-3 at 0.65,
    # 1.1e-3 at 0.8 and 7e-5 at 0.95; so |e_eff − e| < 1e-2 over 0.3-0.95, < 4e-3 for e >= 0.6,
    # and the gap closes as 0.017-0.028 (1 − e)² towards the elastic limit.
    res = effective_restitution("jankowski", k=2.75e9, e=e, mass=3.0e5, v0=0.5)
    assert res.e_effective < e
    assert e - res.e_effective < (1e-2 if e < 0.6 else 4e-3)
    assert e - res.e_effective < 0.035 * (1 - e) ** 2


def test_hertz_kelvin_has_no_closed_form_and_is_calibrated_numerically():
    law = get_contact_law("hertz_kelvin")
    assert law.damping_from_e is None
    # nominal = numerical calibration (e = 0.3 shares the cached solution with the exact tests)
    res = effective_restitution("hertz_kelvin", k=2.75e9, e=0.3, mass=3.0e5, v0=0.5)
    assert res.e_effective == pytest.approx(0.3, rel=5e-3)


@pytest.mark.parametrize(
    ("name", "direction"),
    [("lankarani_nikravesh", +1), ("flores", -1), ("gonthier", -1), ("hu_guo", -1)],
)
def test_hunt_crossley_variants_differ_from_e_as_documented(name, direction):
    # Lankarani-Nikravesh under-damps at low e (valid near e = 1 only), the others over-damp
    # (χ v0 above the exact Hunt-Crossley u), so their effective e falls on either side of e.
    e = 0.5
    res = effective_restitution(name, k=1e8, e=e, mass=1e4, v0=1.0)
    assert direction * (res.e_effective - e) > 1e-3


# --------------------------------------------------------------------------------------------------
# calibration="exact" for every damped law
# --------------------------------------------------------------------------------------------------

# One physical scale per e, so the self-similarity of the cached calibration is exercised too.
# Every damped law at e = 0.3 and 0.9 (bilinear: 0.5 and 0.9, its loop cannot rebound below 0.354
# at a = 0.1); kelvin and flores also at 0.6 (their calibration at 0.6 is shared with other tests
# through the cache). Exact calibration costs ~10-15 impacts per (law, e).
SCALES = {
    0.3: {"mass": 1.0e4, "v0": 1.0, "k_linear": 1.0e7, "k_hertz": 1.0e8},
    0.5: {"mass": 3.0e5, "v0": 0.5, "k_linear": 2.75e8, "k_hertz": 2.75e9},
    0.6: {"mass": 3.0e5, "v0": 0.4, "k_linear": 2.75e8, "k_hertz": 2.75e9},
    0.9: {"mass": 1.0, "v0": 5.0, "k_linear": 1.0e6, "k_hertz": 1.0e9},
}


def _exact_cases():
    for name in DAMPED:
        for e in (0.3, 0.5, 0.6, 0.9):
            if e == 0.5 and name != "bilinear":
                continue
            if e == 0.6 and name not in ("kelvin", "flores"):
                continue
            if name == "bilinear" and e == 0.3:
                continue  # below the loop's reach at a = 0.1: see the bilinear section below
            if name in ("bumper", "filler"):
                continue  # the layer in the gap sets the rebound: refused (tests/test_bumper.py)
            yield pytest.param(name, e, id=f"{name}-{e}")


@pytest.mark.parametrize(("name", "e"), list(_exact_cases()))
def test_exact_calibration_returns_e(name, e):
    s = SCALES[e]
    law = get_contact_law(name)
    k = s["k_linear"] if not law.has_exponent else s["k_hertz"]
    res = effective_restitution(name, k=k, e=e, mass=s["mass"], v0=s["v0"], calibration="exact")
    assert res.e_effective == pytest.approx(e, rel=5e-3)


@pytest.mark.parametrize("e", [0.7])
def test_exact_bilinear_at_the_given_speed(e):
    # Muthukumar's loop calibrated at v0 with the user's δ_m; the nominal loop rebounds faster
    # than e because the mass stops short of δ_m (loading work K_eff δ_m²/2 > k δ_m^2.5/2.5).
    k, mass, v0 = 2.75e9, 3.0e5, 0.5
    delta_m = 1.2 * hertz_max_penetration(k=k, n=1.5, mass=mass, v0=v0)
    nominal = effective_restitution("bilinear", k=k, e=e, mass=mass, v0=v0, delta_m=delta_m)
    exact = effective_restitution(
        "bilinear", k=k, e=e, mass=mass, v0=v0, delta_m=delta_m, calibration="exact"
    )
    assert nominal.e_effective > e + 1e-3
    assert exact.e_effective == pytest.approx(e, rel=5e-3)


# --------------------------------------------------------------------------------------------------
# Bilinear loop: closed-form single impact
# --------------------------------------------------------------------------------------------------


def bilinear_impact_closed_form(k1, k2, d_y, mass, v0):
    """Energy solution of a mass hitting Muthukumar's loop (no integration).

    Loading: K1 up to δ_y, then the line F = K2 δ + (K1 − K2) δ_y; δ_max from
    ½ m v0² = ½ K1 δ_y² + ½ K2 (δ² − δ_y²) + (K1 − K2) δ_y (δ − δ_y) (a quadratic in δ).
    Unloading: along K1 from (δ_max, F_max) down to the line K2 δ, which it meets at
    δ_max − δ_y, then along K2 δ to 0; the area under that path comes back as kinetic energy.
    Returns (e, δ_max, F_max).
    """
    ke = 0.5 * mass * v0 * v0
    w_y = 0.5 * k1 * d_y * d_y
    if ke <= w_y:
        d_max = math.sqrt(2 * ke / k1)
        return 1.0, d_max, k1 * d_max
    a2, b = 0.5 * k2, (k1 - k2) * d_y
    c = ke - w_y + 0.5 * k2 * d_y**2 + (k1 - k2) * d_y**2
    d_max = (-b + math.sqrt(b * b + 4 * a2 * c)) / (2 * a2)
    f_max = k2 * d_max + (k1 - k2) * d_y
    d1 = d_max - d_y
    returned = 0.5 * (f_max + k2 * d1) * d_y + 0.5 * k2 * d1 * d1
    return math.sqrt(returned / ke), d_max, f_max


@pytest.mark.parametrize("e", [0.3, 0.7, 0.95])
def test_bilinear_impact_against_energy_closed_form(e):
    k, mass, v0 = 2.75e9, 3.0e5, 0.5
    res = effective_restitution("bilinear", k=k, e=e, mass=mass, v0=v0)
    d_m = hertz_max_penetration(k=k, n=1.5, mass=mass, v0=v0)
    p = contact_parameters("bilinear", k=k, e=e, delta_m=d_m)
    e_cf, d_max, f_max = bilinear_impact_closed_form(*p[:3], mass, v0)
    assert res.e_effective == pytest.approx(e_cf, rel=1e-8)
    assert res.max_penetration == pytest.approx(d_max, rel=1e-6)
    assert res.peak_force == pytest.approx(f_max, rel=1e-6)
    # the nominal loop rebounds faster than e: the mass stops short of δ_m (loading work
    # ≈ K_eff δ_m²/2 exceeds k δ_m^2.5/2.5), so less than the loop's ΔE is dissipated
    assert d_max < d_m
    assert res.e_effective > e


def test_bilinear_lowest_reachable_restitution():
    # The dissipation parameter D (1 − e² nominally) may go up to (n + 1)(1 − a) = 2.25 before K2
    # reaches 0. With a = 0.1 the closed form gives e = 0.606 at D = 1, e = 0.491 at D = 1.4 and
    # e -> 0.3536 as D -> 2.25: exact calibration can reach e in (0.354, 1], never 0.3.
    k, mass, v0 = 2.75e9, 3.0e5, 0.5
    d_m = hertz_max_penetration(k=k, n=1.5, mass=mass, v0=v0)

    def e_of(dissipation):
        p = bilinear_stiffnesses(k=k, n=1.5, e=1.0, a=0.1, delta_m=d_m, dissipation=dissipation)
        return bilinear_impact_closed_form(*p, mass, v0)[0]

    assert e_of(1.0) == pytest.approx(0.6058, abs=1e-4)
    assert e_of(1.4) == pytest.approx(0.4909, abs=1e-4)
    assert e_of(2.25 * (1 - 1e-9)) == pytest.approx(0.3536, abs=1e-4)


def _closed_form_impact(law, p, mass, v0, k, n):
    e_cf, d_max, f_max = bilinear_impact_closed_form(*p[:3], mass, v0)
    return ImpactResult(e_cf, d_max, f_max, math.nan)


def test_exact_bilinear_below_unit_dissipation(monkeypatch):
    # e = 0.5 needs D ≈ 1.37 > 1 (closed form above), which the calibration must search beyond
    # D = 1 (up to the K2 > 0 limit) to find. The solver runs here on the closed form (exact for
    # this loop, checked against the integration in test_bilinear_impact_against_energy_closed_form);
    # the integrated path at e = 0.5 is in test_exact_calibration_returns_e.
    monkeypatch.setattr(calibrate, "_impact", _closed_form_impact)
    k, mass, v0 = 1.2345e9, 3.0e5, 0.5  # a k no other test uses: the cache is keyed on it
    d_m = hertz_max_penetration(k=k, n=1.5, mass=mass, v0=v0)
    p = contact_parameters(
        "bilinear", k=k, e=0.5, mass=mass, delta_m=d_m, v0=v0, calibration="exact"
    )
    assert bilinear_impact_closed_form(*p[:3], mass, v0)[0] == pytest.approx(0.5, rel=1e-6)
    d_1 = bilinear_stiffnesses(k=k, n=1.5, e=1.0, a=0.1, delta_m=d_m, dissipation=1.0)
    assert p[0] > d_1[0] and p[1] < d_1[1]  # D > 1: steeper K1, flatter K2


def test_exact_bilinear_out_of_reach_is_an_error(monkeypatch):
    # e = 0.3 < 0.3536, the loop's floor at a = 0.1 (test_bilinear_lowest_reachable_restitution):
    # a clear error naming e, not a silent wrong loop.
    monkeypatch.setattr(calibrate, "_impact", _closed_form_impact)
    k, mass, v0 = 1.2345e9, 3.0e5, 0.5
    d_m = hertz_max_penetration(k=k, n=1.5, mass=mass, v0=v0)
    with pytest.raises(ValueError, match=r"law 'bilinear'.*e = 0.3"):
        contact_parameters(
            "bilinear", k=k, e=0.3, mass=mass, delta_m=d_m, v0=v0, calibration="exact"
        )


def test_exact_calibration_is_self_similar():
    # One calibrated damping parameter serves every k, m, v0 (units δ*, δ*/v0): the damped free
    # impact of flores calibrated once returns e at scales six orders of magnitude apart.
    for k, mass, v0 in [(2.75e9, 3.0e5, 0.3), (1.0e6, 1.0, 5.0)]:
        res = effective_restitution("flores", k=k, e=0.6, mass=mass, v0=v0, calibration="exact")
        assert res.e_effective == pytest.approx(0.6, rel=5e-3)


def test_exact_is_tighter_than_required():
    # The 0.5 % of issue 2 is a ceiling; the solver actually lands within 1e-6.
    res = effective_restitution("kelvin", k=1e7, e=0.6, mass=1e4, v0=1.0, calibration="exact")
    assert res.e_effective == pytest.approx(0.6, abs=1e-6)
    assert np.isfinite(res.peak_force) and res.peak_force > 0
