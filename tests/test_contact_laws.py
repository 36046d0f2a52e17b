"""Tests for pounding.contact.laws: registry, kernel properties, and the e -> damping relations
against independent integrations written here (not the package's kernels or impact simulator).

References: Maison & Kasai (1992) EESD 21(9); Goldsmith (1960) Impact; Lankarani & Nikravesh (1990)
J. Mech. Des. 112(3); Ye, Li & Zhu (2009) EESD 38(9); Flores et al. (2011) MSD 25(3);
Anagnostopoulos (1988) EESD 16(3); Hunt & Crossley (1975) J. Appl. Mech. 42(2);
Muthukumar & DesRoches (2006) EESD 35(7).
"""

from __future__ import annotations

import functools
import math
import re

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

from pounding.contact.calibrate import contact_parameters
from pounding.contact.laws import (
    CONTACT_LAWS,
    LAWS_BY_ID,
    V0_FLOOR,
    alpha_flores,
    alpha_gonthier,
    alpha_hu_guo,
    alpha_hunt_crossley,
    alpha_lankarani_nikravesh,
    bilinear_kernel,
    bilinear_stiffnesses,
    contact_force,
    get_contact_law,
    hunt_crossley_residual,
    restitution_kelvin_approach,
    stored_energy,
    xi_anagnostopoulos,
    xi_jankowski,
    xi_kelvin_approach,
)

LAW_NAMES = [law.name for law in LAWS_BY_ID]
DAMPED = [law.name for law in LAWS_BY_ID if law.has_damping]

# Reference problem for the property tests: m = 1e4 kg, v = 1 m/s, so δ* = (m v²/k)^(1/(n+1)) is
# 25 mm for k = 1e8 N/m^1.5 and 32 mm for k = 1e7 N/m.
MASS = 1.0e4
K_HERTZ = 1.0e8
K_LINEAR = 1.0e7


# --------------------------------------------------------------------------------------------------
# Independent single-impact integration (force law written in each test)
# --------------------------------------------------------------------------------------------------


def free_impact(force, *, mass, v0, t_max, method="DOP853", y0=None):
    """m δ̈ = −F(δ, δ̇) from δ = 0, δ̇ = v0 until δ returns to 0 (no clamping unless F clamps).

    Returns (rebound speed / v0, max δ, contact duration).
    """

    def rhs(t, y):
        return [y[1], -force(y[0], y[1]) / mass]

    def back_to_zero(t, y):
        return y[0]

    back_to_zero.terminal = True
    back_to_zero.direction = -1.0
    sol = solve_ivp(
        rhs,
        (0.0, t_max),
        [0.0, v0] if y0 is None else y0,
        method=method,
        events=back_to_zero,
        dense_output=True,
        rtol=1e-12,
        atol=[1e-16, 1e-14 * v0],
    )
    assert sol.t_events[0].size == 1, "no separation"
    t_end = sol.t_events[0][0]
    ts = np.linspace(0.0, t_end, 20001)
    return -sol.y_events[0][0][1] / v0, sol.sol(ts)[0].max(), t_end


# --------------------------------------------------------------------------------------------------
# Registry
# --------------------------------------------------------------------------------------------------


def test_registry_names_fixed_by_issue_2():
    expected = {
        "linear", "kelvin", "kelvin_approach", "hertz", "hertz_kelvin", "lankarani_nikravesh",
        "flores", "hu_guo", "gonthier", "hunt_crossley", "jankowski", "bilinear",
        "bumper", "filler",  # issue 18
    }  # fmt: skip
    assert set(LAW_NAMES) == expected
    assert len(LAW_NAMES) == len(expected)


@pytest.mark.parametrize(
    ("alias", "name"),
    [("hertzdamp", "lankarani_nikravesh"), ("ye", "flores"), ("impact_material", "bilinear")],
)
def test_aliases(alias, name):
    assert get_contact_law(alias) is get_contact_law(name)
    assert alias in get_contact_law(name).aliases


@pytest.mark.parametrize("name", sorted(CONTACT_LAWS))
def test_every_registered_name_resolves(name):
    law = get_contact_law(name)
    assert law is CONTACT_LAWS[name]
    assert name == law.name or name in law.aliases
    assert get_contact_law(f"  {name.upper()} ") is law
    assert get_contact_law(law) is law


def test_kernel_ids_are_the_dispatch_table_index():
    assert [law.kernel_id for law in LAWS_BY_ID] == list(range(len(LAWS_BY_ID)))


@pytest.mark.parametrize("bad", ["hertz-damp", "", "kelvin voigt", None])
def test_unknown_law_lists_valid_names(bad):
    with pytest.raises(ValueError, match="unknown contact law") as info:
        get_contact_law(bad)
    for name in CONTACT_LAWS:
        assert re.search(rf"\b{name}\b", str(info.value))


# --------------------------------------------------------------------------------------------------
# Property tests over every registered law
# --------------------------------------------------------------------------------------------------


def _k(name):
    return K_LINEAR if get_contact_law(name).default_n == 1.0 else K_HERTZ


def _d_star(name):
    n = get_contact_law(name).default_n
    return (MASS / _k(name)) ** (1.0 / (n + 1.0))


def _f_ref(name):
    return _k(name) * _d_star(name) ** get_contact_law(name).default_n


@functools.cache
def _params(name, e):
    law = get_contact_law(name)
    kwargs = {"e": e} if law.has_damping else {}
    if law.is_bilinear:
        kwargs["delta_m"] = _d_star(name)
    if law.is_bumper:  # a layer of half the reference penetration, met through at 90 %
        kwargs["bumper"] = (0.5 * _d_star(name), 0.05 * _k(name), 0.8, 0.9)
    if law.is_filler:  # a filler as stiff as a tenth of the reference force, crushed at δ*/2
        k_f = 0.1 * _f_ref(name) / _d_star(name)
        kwargs["filler"] = (k_f, 0.2 * math.sqrt(k_f * MASS), 0.5 * _d_star(name))
    return contact_parameters(name, k=_k(name), mass=MASS, **kwargs)


# e from a small set so hertz_kelvin's numerical calibration is computed once per value
restitution = st.sampled_from([0.3, 0.9, 1.0])
speed = st.floats(min_value=-2.0, max_value=2.0)
impact_speed = st.floats(min_value=0.05, max_value=2.0)
fraction = st.floats(min_value=0.0, max_value=1.0)


@st.composite
def history(draw, name, p):
    """(δ_prev, F_prev) inside the bilinear loop (the only law that reads it), else arbitrary."""
    d_star = _d_star(name)
    if not get_contact_law(name).is_bilinear:
        return draw(st.floats(-d_star, 2 * d_star)), draw(st.floats(0.0, 10.0 * _f_ref(name)))
    if draw(st.booleans()):
        return 0.0, 0.0  # fresh contact
    d_prev = draw(st.floats(1e-3 * d_star, 2.0 * d_star))
    lower = p[1] * d_prev
    upper = lower + (p[0] - p[1]) * p[2]
    return d_prev, lower + draw(fraction) * (upper - lower)


props = settings(deadline=None, max_examples=60)


@pytest.mark.parametrize("name", LAW_NAMES)
@props
@given(data=st.data())
def test_zero_force_and_tangents_before_contact(name, data):
    p = _params(name, data.draw(restitution))
    d = data.draw(st.floats(-2.0 * _d_star(name), 0.0))
    hist = data.draw(st.tuples(st.floats(-1.0, 1.0), st.floats(0.0, 1e6)))
    out = get_contact_law(name).kernel(d, data.draw(speed), data.draw(impact_speed), *hist, p)
    assert out == (0.0, 0.0, 0.0)


@pytest.mark.parametrize("name", LAW_NAMES)
@props
@given(data=st.data())
def test_force_never_negative(name, data):
    p = _params(name, data.draw(restitution))
    d = data.draw(st.floats(-_d_star(name), 3.0 * _d_star(name)))
    f, kd, kv = get_contact_law(name).kernel(
        d, data.draw(speed), data.draw(impact_speed), *data.draw(history(name, p)), p
    )
    assert f >= 0.0
    assert all(math.isfinite(x) for x in (f, kd, kv))


@pytest.mark.parametrize("name", LAW_NAMES)
@props
@given(data=st.data())
def test_tangents_equal_central_differences(name, data):
    law = get_contact_law(name)
    p = _params(name, data.draw(restitution))
    d_star = _d_star(name)
    d = d_star * data.draw(st.floats(1e-2, 2.0))
    dd = data.draw(speed)
    v0 = data.draw(impact_speed)
    hist = data.draw(history(name, p))

    def kern(x, xd):
        return law.kernel(x, xd, v0, *hist, p)

    hd, hv = 1e-6 * d_star, 1e-6  # FD steps [m], [m/s]
    bd, bv = 100 * hd, 100 * hv  # band around kinks that must not be straddled

    # Skip points whose neighbourhood straddles a kink: the clamp F = 0 (kelvin, hertz_kelvin, HC
    # family), the approach/separation switch δ̇ = 0 (kelvin_approach, jankowski: ∂F/∂δ̇ drops to 0),
    # and the bilinear loop's bounds (slope changes K1 <-> K2). A straight kink line crossing the box
    # puts its corners on both sides, so comparing the corners' branch signatures detects it.
    def branch(x, xd):
        f, kd, kv = kern(x, xd)
        # the filler's crushed contact switches its damping at δ̇ = 0 behind the filler's dashpot,
        # and starts at d_thr = p[6] with Jankowski's c(δ)δ̇, whose ∂/∂δ ~ δ^(-3/4) is unbounded there
        switch = (xd > 0.0, x > p[6]) if law.is_filler else None
        if (
            law.is_bumper
        ):  # each Hunt-Crossley term clamps on its own (1 + χ δ̇ = 0), behind the other
            v = max(v0, V0_FLOOR)
            switch = (1.0 + p[5] / v * xd > 0.0, 1.0 + p[2] / v * xd > 0.0, x > p[6])
        return (f == 0.0, kv == 0.0, kd if law.is_bilinear else None, switch)

    corners = {branch(d + sd * bd, dd + sv * bv) for sd in (-1, 0, 1) for sv in (-1, 0, 1)}
    assume(len(corners) == 1)

    f, kd, kv = kern(d, dd)
    fd_d = (kern(d + hd, dd)[0] - kern(d - hd, dd)[0]) / (2 * hd)
    fd_v = (kern(d, dd + hv)[0] - kern(d, dd - hv)[0]) / (2 * hv)
    f_ref = _f_ref(name)
    assert kd == pytest.approx(fd_d, rel=1e-6, abs=1e-7 * f_ref / d_star)
    assert kv == pytest.approx(fd_v, rel=1e-6, abs=1e-7 * f_ref)


# Laws whose force itself vanishes as δ -> 0+; the others (kelvin, kelvin_approach, hertz_kelvin)
# jump to the damping force c δ̇ at first touch (Anagnostopoulos 1988; the Kelvin model's
# tensile force at the end of restitution, Gilardi & Sharf 2002), which is tested below.
VANISHING_AT_CONTACT = {
    "linear", "hertz", "lankarani_nikravesh", "flores", "hu_guo", "gonthier", "hunt_crossley",
    "jankowski", "bilinear", "bumper",
}  # fmt: skip


def _damping_at_contact(name, p, v0):
    """c [N·s/m] of the Kelvin-type laws as their docstrings define it."""
    if name == "hertz_kelvin":
        # c = ζ m̄ v0/δ*, δ* = (m̄ v0²/k_h)^(1/(n+1)), ζ = p[2], m̄ = p[3]
        k, n, zeta, m = p[:4]
        v = max(v0, V0_FLOOR)
        return zeta * m * v / (m * v * v / k) ** (1.0 / (n + 1.0))
    if name == "filler":
        return p[5]  # the filler's own dashpot
    return p[2]  # kelvin, kelvin_approach: c = 2ξ√(k m̄), packed


@pytest.mark.parametrize("name", LAW_NAMES)
@props
@given(data=st.data())
def test_continuity_at_contact_from_above(name, data):
    law = get_contact_law(name)
    p = _params(name, data.draw(restitution))
    dd, v0 = data.draw(speed), data.draw(impact_speed)
    f_ref = _f_ref(name)
    # δ = 1e-20 δ*: Jankowski's c(δ)δ̇ goes as δ^(1/4), the slowest of all, still < 1e-4 F_ref here
    f, kd, kv = law.kernel(1e-20 * _d_star(name), dd, v0, 0.0, 0.0, p)
    # the elastic part F − δ̇ ∂F/∂δ̇ always vanishes at first touch
    assert abs(f - dd * kv) <= 1e-3 * f_ref
    if name in VANISHING_AT_CONTACT:
        assert f <= 1e-3 * f_ref
    else:
        # the documented damping jump of the Kelvin-type laws: F(0+) = max(c δ̇, 0)
        c = _damping_at_contact(name, p, v0)
        assert f == pytest.approx(max(c * dd, 0.0), rel=1e-9, abs=1e-9 * f_ref)


def test_vanishing_set_is_exact():
    # Guard for the list above: a law not in it must really jump at contact.
    p = _params("kelvin", 0.9)
    assert get_contact_law("kelvin").kernel(1e-20, 1.0, 1.0, 0.0, 0.0, p)[0] == pytest.approx(p[2])
    assert VANISHING_AT_CONTACT < set(LAW_NAMES)


def test_contact_force_vectorises_the_kernel():
    p = _params("flores", 0.6)
    d = np.linspace(-0.01, 0.03, 7)
    dd = np.array([[0.5], [-0.5]])
    f, kd, kv = contact_force("ye", d, dd, p, v0=0.8)
    assert f.shape == kd.shape == kv.shape == (2, 7)
    for i in range(2):
        for j in range(7):
            expected = get_contact_law("flores").kernel(d[j], dd[i, 0], 0.8, 0.0, 0.0, p)
            assert (f[i, j], kd[i, j], kv[i, j]) == expected


# --------------------------------------------------------------------------------------------------
# e -> damping relations against independent integrations
# --------------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("e", "k", "mass", "v0"),
    [(0.3, 1.0e7, 1.0e4, 1.0), (0.65, 4.0e9, 3.0e5, 0.3), (0.9, 5.0, 2.0, 7.0)],
)
def test_anagnostopoulos_kelvin_with_tension_returns_e(e, k, mass, v0):
    # Anagnostopoulos (1988): m δ̈ + c δ̇ + k δ = 0 with tension allowed, separation at δ = 0 after
    # half a damped period, rebound speed v0 exp(−ξπ/√(1 − ξ²)) = e v0.
    c = contact_parameters("kelvin", k=k, e=e, mass=mass)[2]
    xi = xi_anagnostopoulos(e)
    assert c == pytest.approx(2.0 * xi * math.sqrt(k * mass), rel=1e-14)
    t_max = 2.0 * math.pi * math.sqrt(mass / k)
    e_ode, _, t_c = free_impact(lambda d, dd: k * d + c * dd, mass=mass, v0=v0, t_max=t_max)
    assert e_ode == pytest.approx(e, rel=1e-8)
    assert t_c == pytest.approx(math.pi / (math.sqrt(k / mass) * math.sqrt(1 - xi * xi)), rel=1e-8)


def _kelvin_approach_ode(xi, *, k=2.0e6, mass=50.0, v0=0.8):
    """Damped approach integrated until δ̇ = 0; the undamped restitution then returns the stored
    k δ_max²/2 as kinetic energy, so the rebound speed is ω δ_max."""
    c = 2.0 * xi * math.sqrt(k * mass)
    omega = math.sqrt(k / mass)

    def stop(t, y):
        return y[1]

    stop.terminal = True
    stop.direction = -1.0
    approach = solve_ivp(
        lambda t, y: [y[1], -(k * y[0] + c * y[1]) / mass],
        (0.0, 50.0 / omega),
        [0.0, v0],
        method="Radau",
        events=stop,
        rtol=1e-12,
        atol=[1e-16, 1e-14],
    )
    return omega * approach.y_events[0][0][0] / v0


@pytest.mark.parametrize("xi", [0.05, 0.3, 0.7, 1.0, 1.5, 4.0])
def test_kelvin_approach_exact_relation(xi):
    # Mahmoud & Jankowski (2011): damping only while approaching; both ξ < 1 and ξ > 1 (overdamped
    # approach, closed form with atanh) against an independent two-phase integration.
    e_ode = _kelvin_approach_ode(xi)
    assert restitution_kelvin_approach(xi) == pytest.approx(e_ode, rel=1e-8)
    assert xi_kelvin_approach(e_ode) == pytest.approx(xi, rel=1e-7)


def test_kelvin_approach_relation_is_continuous_at_critical_damping():
    at = restitution_kelvin_approach(1.0)
    assert at == pytest.approx(math.exp(-1.0), rel=1e-15)
    for side in (1.0 - 1e-7, 1.0 + 1e-7):
        assert restitution_kelvin_approach(side) == pytest.approx(at, rel=1e-6)
    assert restitution_kelvin_approach(0.0) == 1.0
    assert xi_kelvin_approach(1.0) == 0.0


@pytest.mark.parametrize("e", [0.05, 0.3, 0.6, 0.9, 0.99])
def test_hunt_crossley_alpha_solves_the_exact_relation(e):
    # 1 − e u = (1 + u) exp(−(1 + e) u) (Hunt & Crossley 1975), checked in its own form.
    u = alpha_hunt_crossley(e)
    assert 0.0 < u < 1.0 / e
    assert 1.0 - e * u == pytest.approx((1.0 + u) * math.exp(-(1.0 + e) * u), rel=1e-12, abs=1e-15)
    assert hunt_crossley_residual(u, e) == pytest.approx(0.0, abs=1e-14)


@pytest.mark.parametrize(
    ("n", "e", "k", "mass", "v0"),
    [
        (1.0, 0.4, 1.0e4, 2.0, 0.5),
        (1.5, 0.65, 2.75e9, 3.0e5, 0.4),
        (1.5, 0.2, 1.0e8, 10.0, 3.0),
        (2.0, 0.85, 1.0e9, 10.0, 3.0),
    ],
)
def test_hunt_crossley_exact_relation_against_independent_impact(n, e, k, mass, v0):
    # m δ̈ = −k δ^n (1 + χ δ̇), χ = u/v0: the rebound speed is e v0 for any n, k, m, v0.
    chi = alpha_hunt_crossley(e) / v0
    d_max0 = ((n + 1) * mass * v0**2 / (2 * k)) ** (1 / (n + 1))
    e_ode, d_max, _ = free_impact(
        lambda d, dd: k * max(d, 0.0) ** n * (1.0 + chi * dd),
        mass=mass,
        v0=v0,
        t_max=20.0 * d_max0 / v0,
    )
    assert e_ode == pytest.approx(e, rel=1e-7)
    assert d_max < d_max0  # damping only removes energy on the way in


@pytest.mark.parametrize("e", [0.99, 0.999])
def test_hunt_crossley_small_damping_limit(e):
    # Expanding ln(1 − e u) − ln(1 + u) + (1 + e) u = 0 to third order in u:
    # (1 − e²) u²/2 − (1 + e³) u³/3 = 0  =>  u = 3(1 − e)/(2(1 − e + e²))  ->  3(1 − e)/2 as e -> 1.
    u = alpha_hunt_crossley(e)
    assert u / (1.5 * (1.0 - e)) == pytest.approx(1.0, abs=2.0 * (1.0 - e))
    assert u == pytest.approx(1.5 * (1.0 - e) / (1.0 - e + e * e), rel=2.0 * (1.0 - e) ** 2)


@pytest.mark.parametrize(
    ("alpha", "expected"),
    [
        # χ v0 of each Hunt-Crossley variant at e = 0.5, worked by hand
        (alpha_lankarani_nikravesh, 0.75 * (1 - 0.25)),  # 3(1 − e²)/4 = 0.5625
        (alpha_flores, 1.6),  # 8(1 − e)/(5e) = 8 · 0.5 / 2.5
        (alpha_hu_guo, 1.5),  # 3(1 − e)/(2e) = 1.5 · 0.5 / 0.5
        (alpha_gonthier, 1.5),  # (1 − e²)/e = 0.75 / 0.5
    ],
)
def test_hunt_crossley_variants_by_hand(alpha, expected):
    assert alpha(0.5) == pytest.approx(expected, rel=1e-15)
    assert alpha(1.0) == 0.0


def test_jankowski_xi_by_hand():
    # Jankowski (2006) Eq. 21 at e = 0.65: 9√5/2 · (1 − 0.4225) / (0.65 (0.65 (9π − 16) + 16)).
    num = 4.5 * math.sqrt(5.0) * 0.5775
    den = 0.65 * (0.65 * (9.0 * math.pi - 16.0) + 16.0)
    assert xi_jankowski(0.65) == pytest.approx(num / den, rel=1e-15)
    assert xi_jankowski(1.0) == 0.0


@pytest.mark.parametrize(
    "relation",
    [
        xi_anagnostopoulos,
        xi_kelvin_approach,
        xi_jankowski,
        alpha_hunt_crossley,
        alpha_flores,
        alpha_lankarani_nikravesh,
    ],
)
@pytest.mark.parametrize("e", [0.0, -0.2, 1.2, math.nan])
def test_relations_reject_e_out_of_range(relation, e):
    with pytest.raises(ValueError, match=r"restitution e = .*0 < e <= 1"):
        relation(e)


@pytest.mark.parametrize("relation", [xi_anagnostopoulos, xi_kelvin_approach, alpha_hunt_crossley])
def test_relations_decrease_with_e(relation):
    values = [relation(e) for e in (0.2, 0.4, 0.6, 0.8, 1.0)]
    assert all(a > b for a, b in zip(values, values[1:], strict=False))
    assert values[-1] == 0.0


# --------------------------------------------------------------------------------------------------
# Bilinear loop (Muthukumar 2003; Muthukumar & DesRoches 2006; OpenSees ImpactMaterial)
# --------------------------------------------------------------------------------------------------


def _walk(path, p):
    """Drive the bilinear kernel along a δ path, carrying its converged history."""
    d_prev = f_prev = 0.0
    forces = []
    for d in path:
        f = bilinear_kernel(d, 0.0, 0.0, d_prev, f_prev, p)[0]
        forces.append(f)
        d_prev, f_prev = d, f
    return np.array(forces)


@pytest.mark.parametrize(("n", "e", "a"), [(1.5, 0.65, 0.1), (1.5, 0.3, 0.1), (1.0, 0.8, 0.25)])
def test_bilinear_loop_energy_and_peak_force(n, e, a):
    # By hand: the loop is the parallelogram (0, 0), (δ_y, K1 δ_y), (δ_m, F_m), (δ_m − δ_y, K2(δ_m − δ_y))
    # between the parallel lines K2 δ and K2 δ + (K1 − K2) δ_y. Its area is
    # |(δ_y, K1 δ_y) × (δ_m − δ_y, K2(δ_m − δ_y))| = (K1 − K2) δ_y (δ_m − δ_y) = (K1 − K2) a(1 − a) δ_m²,
    # and K1 − K2 = ΔE/(a δ_m²) + ΔE/((1 − a) δ_m²) = ΔE/(a(1 − a) δ_m²), so the area is ΔE
    # = k δ_m^(n+1)(1 − e²)/(n + 1). Peak: F_m = K2 δ_m + (K1 − K2) a δ_m
    # = K_eff δ_m − ΔE/((1 − a) δ_m) + ΔE/((1 − a) δ_m) = K_eff δ_m = k δ_m^n.
    k, d_m = 2.75e9, 0.012
    p = contact_parameters("bilinear", k=k, e=e, n=n, a=a, delta_m=d_m)
    k1, k2, d_y = p[:3]
    assert d_y == pytest.approx(a * d_m, rel=1e-15)
    steps = 2000  # δ_y = a δ_m and δ_m − δ_y fall on grid points, so the trapezoid rule is exact
    up = np.linspace(0.0, d_m, steps + 1)
    path = np.concatenate([up, up[::-1][1:]])
    forces = _walk(path, p)
    peak = forces[steps]
    assert peak == pytest.approx(k * d_m ** (n - 1.0) * d_m, rel=1e-12)
    assert peak == pytest.approx(k * d_m**n, rel=1e-12)
    dissipated = np.trapezoid(forces[: steps + 1], up) - np.trapezoid(forces[steps:][::-1], up)
    assert dissipated == pytest.approx(k * d_m ** (n + 1) * (1 - e * e) / (n + 1), rel=1e-9)
    assert np.all(forces >= k2 * path * (1 - 1e-12))
    assert np.all(forces <= (k2 * path + (k1 - k2) * d_y) * (1 + 1e-12))
    assert forces[-1] == 0.0
    # what the loop keeps at δ_m is what it gives back: W_load − stored(δ_m) = ΔE
    w_load = np.trapezoid(forces[: steps + 1], up)
    assert w_load - stored_energy(True, d_m, peak, p) == pytest.approx(dissipated, rel=1e-9)


@given(
    steps=st.lists(st.floats(-0.4, 0.4), min_size=1, max_size=40),
    e=st.floats(0.3, 1.0),
    a=st.floats(0.05, 0.5),
)
@settings(deadline=None, max_examples=100)
def test_bilinear_force_stays_within_the_bounds_on_any_path(steps, e, a):
    d_m = 0.01
    # K2 = K_eff (1 − (1 − e²)/(2.5 (1 − a))) > 0 over these ranges
    p = contact_parameters("bilinear", k=2.75e9, e=e, a=a, delta_m=d_m)
    k1, k2, d_y = p[:3]
    path = np.cumsum(np.asarray(steps) * d_m)
    forces = _walk(path, p)
    inside = path > 0.0
    tol = 1e-9 * k1 * d_m
    assert np.all(forces[~inside] == 0.0)
    assert np.all(forces[inside] >= k2 * path[inside] - tol)
    assert np.all(forces[inside] <= k2 * path[inside] + (k1 - k2) * d_y + tol)


def test_bilinear_stiffnesses_by_hand():
    # k = 1e9, n = 3/2, δ_m = 0.01, e = 0.5, a = 0.1:
    # K_eff = 1e9 · 0.1 = 1e8; ΔE = 1e9 · 1e-5 · 0.75 / 2.5 = 3000 J;
    # K1 = 1e8 + 3000/(0.1 · 1e-4) = 4e8; K2 = 1e8 − 3000/(0.9 · 1e-4) = 6.6667e7; δ_y = 1e-3.
    k1, k2, d_y = bilinear_stiffnesses(k=1e9, n=1.5, e=0.5, a=0.1, delta_m=0.01)
    assert k1 == pytest.approx(4e8, rel=1e-12)
    assert k2 == pytest.approx(1e8 - 3000 / 0.9e-4, rel=1e-12)
    assert d_y == pytest.approx(1e-3, rel=1e-15)


def test_bilinear_rejects_non_positive_post_yield_stiffness():
    # K2 = K_eff (1 − (1 − e²)/((n + 1)(1 − a))): 1 − 0.99/(2.5 · 0.3) < 0 for e = 0.1, a = 0.7
    with pytest.raises(ValueError, match="K2"):
        bilinear_stiffnesses(k=1e9, n=1.5, e=0.1, a=0.7, delta_m=0.01)
    # ... and 1 − 0.99/(2.5 · 0.4) = 0.01 > 0 for a = 0.6: accepted
    k1, k2, _ = bilinear_stiffnesses(k=1e9, n=1.5, e=0.1, a=0.6, delta_m=0.01)
    assert k2 == pytest.approx(0.01 * 1e8, rel=1e-9)


@pytest.mark.parametrize("name", ["linear", "hertz", "flores"])
def test_stored_energy_of_elastic_laws_is_the_spring_work(name):
    p = _params(name, 0.6)
    d = 0.7 * _d_star(name)
    xs = np.linspace(0.0, d, 20001)
    work = np.trapezoid(p[0] * xs ** p[1], xs)
    assert stored_energy(False, d, 0.0, p) == pytest.approx(work, rel=1e-7)
    assert stored_energy(False, -d, 0.0, p) == 0.0
