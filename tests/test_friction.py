"""Tests for pounding.friction against closed forms, independent integrations and law properties.

Sources: Coulomb and viscous friction as reviewed by Olsson et al. (1998) Eur. J. Control 4(3);
Karnopp (1985) J. Dyn. Syst. Meas. Control 107(1);
Brown & McPhee (2016) ASME JCND 11(5); Andersson et al. (2007) Tribol. Int. 40(4); Constantinou et
al. (1990) J. Struct. Eng. 116(2); Wen (1976) J. Eng. Mech. Div. 102(2); Drake's Stribeck model.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp
from scipy.optimize import brentq, minimize_scalar

from pounding import friction as fr
from pounding._numba import jit
from pounding.friction import FRICTION_LAWS, friction_parameters

G = 9.80665

#: One realistic parameter set per law (keys must cover the registry: a new law needs a case here).
CASES = {
    "coulomb": dict(mu_s=0.5, mu_d=0.4, v_reg=1e-3),
    "viscous": dict(mu_v=2.0e4),
    "viscous_normal": dict(k_v=0.05),
    "stribeck": dict(mu_s=0.15, mu_d=0.1, v_s=1e-3),
    "andersson": dict(mu_s=0.15, mu_d=0.1, v_s=1e-3, exponent=2.0, k_t=1e4, mu_v=100.0),
    "brown_mcphee": dict(mu_s=0.15, mu_d=0.1, v_t=1e-3, mu_v=100.0, f_nt=1.0),
    "constantinou": dict(mu_min=0.04, mu_max=0.1, a=20.0, v_reg=1e-3),
}
NAMES = sorted(CASES)
N_REF = 5.0e5 * G  # weight of a 500 t building [N]

speeds = st.floats(min_value=-5.0, max_value=5.0, allow_nan=False)
normals = st.floats(min_value=0.0, max_value=1.0e8, allow_nan=False)


def _kernel(name, v, normal=N_REF):
    return FRICTION_LAWS[name].kernel(v, normal, friction_parameters(name, **CASES[name]))


def test_every_registered_law_has_a_test_case():
    assert set(CASES) == set(FRICTION_LAWS)
    assert [law.kernel_id for law in fr.LAWS_BY_ID] == list(range(len(fr.LAWS_BY_ID)))


# ---------------------------------------------------------------------------------------------
# Closed forms of the individual laws
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("v_t", [1e-4, 1e-3, 0.05])
def test_brown_mcphee_stribeck_term_peaks_at_exactly_v_t(v_t):
    # Brown & McPhee (2016): d/dv_r [16 v_r / (v_r² + 3)²] = 48 (1 − v_r²)/(v_r² + 3)³ = 0 at v_r = 1,
    # peak value (μ_s − μ_d) N. The Stribeck term is isolated as f(μ_s, μ_d) − f(μ_d, μ_d).
    n = 2.0e6
    full = friction_parameters("brown_mcphee", mu_s=0.15, mu_d=0.1, v_t=v_t, mu_v=50.0)
    flat = friction_parameters("brown_mcphee", mu_s=0.1, mu_d=0.1, v_t=v_t, mu_v=50.0)

    def term(v):
        return fr.brown_mcphee_kernel(v, n, full)[0] - fr.brown_mcphee_kernel(v, n, flat)[0]

    def slope(v):
        return fr.brown_mcphee_kernel(v, n, full)[1] - fr.brown_mcphee_kernel(v, n, flat)[1]

    best = minimize_scalar(
        lambda v: -term(v), bounds=(0.0, 10 * v_t), method="bounded", options={"xatol": 1e-10 * v_t}
    )
    assert best.x == pytest.approx(v_t, rel=1e-4)
    assert brentq(slope, 0.5 * v_t, 2.0 * v_t, xtol=1e-15 * v_t) == pytest.approx(v_t, rel=1e-12)
    assert term(v_t) == pytest.approx(0.05 * n, rel=1e-12)


@settings(max_examples=60, deadline=None)
@given(
    mu_d=st.floats(0.02, 0.6),
    ratio=st.floats(1.05, 2.0),
    v_s=st.floats(1e-4, 1e-2),
    exponent=st.floats(0.5, 2.0),
    k_t_v_s=st.floats(1.0, 100.0),
)
def test_andersson_peak_below_mu_s_N_and_tends_to_mu_d_N(mu_d, ratio, v_s, exponent, k_t_v_s):
    # Andersson et al. 2007: h(v) <= μ_s and tanh < 1 keep the peak below μ_s N; at
    # high speed exp(−(|v|/v_s)^p) -> 0 and tanh -> 1, so f -> μ_d N (μ_v = 0 here).
    mu_s = mu_d * ratio
    p = friction_parameters(
        "andersson", mu_s=mu_s, mu_d=mu_d, v_s=v_s, exponent=exponent, k_t=k_t_v_s / v_s
    )
    n = 1.0e6
    v = v_s * np.logspace(-4, 3, 800)
    f = np.array([fr.andersson_kernel(x, n, p)[0] for x in v])
    assert f.max() < mu_s * n
    assert fr.andersson_kernel(1e4 * v_s, n, p)[0] == pytest.approx(mu_d * n, rel=1e-12)
    assert fr.andersson_kernel(-1e4 * v_s, n, p)[0] == pytest.approx(-mu_d * n, rel=1e-12)


def test_andersson_typical_parameters_peak_a_little_below_mu_s_N():
    # Andersson et al. 2007's typical values: with v_s = 1e-3 m/s, p = 2, k_t = 1e4 s/m the Stribeck bump survives: the peak
    # exceeds μ_d N clearly but stays below μ_s N.
    v = np.logspace(-6, 0, 4000)
    f = fr.andersson(v, normal=1.0, mu_s=0.15, mu_d=0.1)
    assert 0.14 < f.max() < 0.15


def test_drake_stribeck_closed_form_values():
    # Drake's quintic steps: s(1) = 1, s(1/2) = 1/2, s(0) = 0 => f(v_s) = μ_s N,
    # f(2 v_s) = (μ_s + μ_d) N / 2, f(>= 3 v_s) = μ_d N; f(v_s/2) = μ_s N s(1/2).
    kw = dict(normal=2.0, mu_s=0.3, mu_d=0.2, v_s=2e-3)
    v = np.array([1e-3, 2e-3, 4e-3, 6e-3, 1.0, -2e-3])
    expected = 2.0 * np.array([0.15, 0.3, 0.25, 0.2, 0.2, -0.3])
    np.testing.assert_allclose(fr.stribeck(v, **kw), expected, rtol=1e-14)


def test_coulomb_regularised_tends_to_mu_d_N_sign_v():
    # Dynamic Coulomb (Olsson et al. 1998): f = μ_d N sign(v) once |v| >> v_reg; tanh(1) of it at v = v_reg.
    kw = dict(normal=1000.0, mu_s=0.5, mu_d=0.4, v_reg=1e-3)
    np.testing.assert_allclose(
        fr.coulomb([-1.0, 0.05, 1e-3], **kw), [-400, 400, 400 * math.tanh(1)]
    )


def test_viscous_laws_closed_forms():
    # Viscous friction f = μ_v v and f = k_v N v (Olsson et al. 1998).
    v = np.array([-0.3, 0.0, 0.7])
    np.testing.assert_allclose(fr.viscous(v, mu_v=2.0e4), 2.0e4 * v, rtol=1e-15)
    np.testing.assert_allclose(fr.viscous_normal(v, normal=3.0e6, k_v=0.05), 1.5e5 * v, rtol=1e-15)


def test_constantinou_mu_limits_and_e_folding_speed():
    # Constantinou et al. (1990): μ(0) = μ_min, μ(∞) = μ_max, μ(1/a) = μ_max − (μ_max − μ_min)/e,
    # monotonic in |v|; with z = 1 and N = 1 the force is μ(v).
    kw = dict(normal=1.0, mu_min=0.04, mu_max=0.1, a=20.0, z=1.0)
    assert fr.constantinou(0.0, **kw) == 0.04
    assert fr.constantinou(10.0, **kw) == pytest.approx(0.1, rel=1e-15)
    assert fr.constantinou(1 / 20.0, **kw) == pytest.approx(0.1 - 0.06 / math.e, rel=1e-14)
    v = np.linspace(0.0, 1.0, 200)
    assert np.all(np.diff(fr.constantinou(v, **kw)) > 0)
    np.testing.assert_allclose(fr.constantinou(v, **kw), fr.constantinou(-v, **kw))  # μ even in v
    # Rigid-plastic form: z replaced by tanh(v/v_reg) -> μ(v) N sign(v) well above v_reg.
    rigid = fr.constantinou([-0.5, 0.5], normal=1.0, mu_min=0.04, mu_max=0.1, a=20.0)
    np.testing.assert_allclose(rigid, [-(0.1 - 0.06 * math.exp(-10)), 0.1 - 0.06 * math.exp(-10)])


# ---------------------------------------------------------------------------------------------
# Properties of every law
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", NAMES)
@settings(max_examples=40, deadline=None)
@given(v=speeds, normal=normals)
def test_every_law_is_odd_in_v(name, v, normal):
    f, df = _kernel(name, v, normal)
    fm, dfm = _kernel(name, -v, normal)
    assert fm == pytest.approx(-f, rel=1e-14, abs=1e-300)
    assert dfm == pytest.approx(df, rel=1e-14, abs=1e-300)
    if v != 0.0:
        assert f * v >= 0.0  # friction resists the motion


@pytest.mark.parametrize("name", NAMES)
def test_every_law_is_continuous_at_zero_and_at_its_breakpoints(name):
    # A discontinuous law (e.g. unregularised sign(v)) jumps by ~2 μ N across v = 0; these are smooth.
    scale = 1e-3
    for v0 in (0.0, scale, 3 * scale, -scale, 0.1):
        eps = 1e-10
        jump = abs(_kernel(name, v0 + eps)[0] - _kernel(name, v0 - eps)[0])
        slope = max(abs(_kernel(name, v0 + s)[1]) for s in (-eps, 0.0, eps))
        assert jump <= 2.0 * eps * slope * 1.01 + 1e-12 * N_REF


@pytest.mark.parametrize("name", NAMES)
@settings(max_examples=60, deadline=None)
@given(log_v=st.floats(-5.0, 0.5), negative=st.booleans(), normal=st.floats(1.0, 1.0e7))
def test_every_law_derivative_equals_central_difference(name, log_v, negative, normal):
    v = -(10.0**log_v) if negative else 10.0**log_v
    h = 1e-6 * abs(v)
    f, df = _kernel(name, v, normal)
    fd = (_kernel(name, v + h, normal)[0] - _kernel(name, v - h, normal)[0]) / (2 * h)
    assert fd == pytest.approx(df, rel=1e-4, abs=1e-6 * (abs(df) + abs(f) / abs(v)))


@settings(max_examples=60, deadline=None)
@given(log_v=st.floats(-5.0, 0.5), negative=st.booleans(), z=st.floats(-1.0, 1.0))
def test_constantinou_bouc_wen_kernel_derivatives_equal_central_differences(log_v, negative, z):
    p = friction_parameters("constantinou", **CASES["constantinou"])
    v = -(10.0**log_v) if negative else 10.0**log_v
    f, dfdv, dfdz = fr.constantinou_bouc_wen_kernel(v, N_REF, z, p)
    h = 1e-6 * abs(v)
    fd_v = (
        fr.constantinou_bouc_wen_kernel(v + h, N_REF, z, p)[0]
        - fr.constantinou_bouc_wen_kernel(v - h, N_REF, z, p)[0]
    ) / (2 * h)
    fd_z = (
        fr.constantinou_bouc_wen_kernel(v, N_REF, z + 1e-6, p)[0]
        - fr.constantinou_bouc_wen_kernel(v, N_REF, z - 1e-6, p)[0]
    ) / 2e-6
    assert fd_v == pytest.approx(dfdv, rel=1e-4, abs=1e-6 * abs(f / v) + 1e-12 * N_REF)
    assert fd_z == pytest.approx(dfdz, rel=1e-6)
    assert fr.constantinou_bouc_wen_kernel(-v, N_REF, -z, p)[0] == pytest.approx(-f, rel=1e-14)


# ---------------------------------------------------------------------------------------------
# Coulomb stick-slip
# ---------------------------------------------------------------------------------------------


def test_block_on_floor_stick_or_slip_hand_example():
    # Hand example (Karnopp 1985 logic): 100 kg block, μ_s = 0.5, μ_d = 0.4, N = m g = 980.665 N,
    # so f_s = μ_s N = 490.3325 N. A push of 400 N is held (f = 400 N); at exactly f_s it still
    # sticks; 500 N breaks it loose against μ_d N = 392.266 N (a = 1.07734 m/s²); −600 N the other way.
    m, n = 100.0, 100.0 * G
    assert fr.coulomb_stick_force_limit(0.5, n) == pytest.approx(490.3325, rel=1e-15)
    stuck, f = fr.coulomb_stick_slip([400.0, 490.3325, 500.0, -600.0], normal=n, mu_s=0.5, mu_d=0.4)
    assert stuck.tolist() == [True, True, False, False]
    np.testing.assert_allclose(f, [400.0, 490.3325, 392.266, -392.266], rtol=1e-15)
    assert (500.0 - f[2]) / m == pytest.approx(1.07734, rel=1e-12)
    p = friction_parameters("coulomb", mu_s=0.5, mu_d=0.4)
    assert fr.coulomb_stick_slip_kernel(-600.0, n, p) == (False, -392.266)
    assert fr.coulomb_stick_slip_kernel(0.0, 0.0, p) == (True, 0.0)  # no normal force, no push


# ---------------------------------------------------------------------------------------------
# Bouc-Wen
# ---------------------------------------------------------------------------------------------


def _integrate_bouc_wen(p, velocity, t_end, extra_work=False):
    """Integrate (u, z[, ∫ z du]) with solve_ivp at tight tolerances; velocity(t) [m/s]."""

    def rhs(t, y):
        v = velocity(t)
        zdot = fr.bouc_wen_rate(y[1], v, p)[0]
        return [v, zdot, y[1] * v] if extra_work else [v, zdot]

    y0 = [0.0, 0.0, 0.0] if extra_work else [0.0, 0.0]
    return solve_ivp(
        rhs,
        (0.0, t_end),
        y0,
        method="DOP853",
        rtol=1e-11,
        atol=1e-13,
        dense_output=True,
        max_step=t_end / 2000,
    )


@pytest.mark.parametrize(("beta", "gamma"), [(0.5, 0.5), (0.1, 0.9), (0.9, 0.1)])
def test_bouc_wen_monotonic_slide_follows_tanh_and_reaches_one(beta, gamma):
    # Wen (1976) with A = 1, β + γ = 1, η = 2: for v > 0, z >= 0, dz/du = (1 − z²)/u_y, so
    # z(u) = tanh(u/u_y) whatever the speed history (rate independence) and z -> 1.
    u_y = 5e-4
    p = fr.bouc_wen_parameters(u_y=u_y, beta=beta, gamma=gamma, eta=2.0)
    sol = _integrate_bouc_wen(p, lambda t: 0.01 * (1.0 + 0.8 * math.sin(7.0 * t)), 1.0)
    u, z = sol.y
    np.testing.assert_allclose(z, np.tanh(u / u_y), atol=1e-8)
    assert z[-1] == pytest.approx(1.0, abs=1e-8)


def test_bouc_wen_monotonic_slide_eta_one_is_exponential():
    # η = 1, A = 1, β + γ = 1: dz/du = (1 − z)/u_y => z = 1 − exp(−u/u_y).
    u_y = 1e-3
    p = fr.bouc_wen_parameters(u_y=u_y, beta=0.3, gamma=0.7, eta=1.0)
    u, z = _integrate_bouc_wen(p, lambda t: 0.02, 0.5).y
    np.testing.assert_allclose(z, 1.0 - np.exp(-u / u_y), atol=1e-8)


@settings(max_examples=40, deadline=None)
@given(
    A=st.floats(0.5, 2.0),
    beta=st.floats(0.0, 1.0),
    gamma=st.floats(-0.2, 1.0),
    eta=st.floats(1.0, 3.0),
    v=st.floats(1e-3, 1.0),
)
def test_bouc_wen_steady_value_is_a_root_of_the_rate(A, beta, gamma, eta, v):
    # Steady sliding: 0 = A − (β + γ) z^η => z_ss = (A/(β + γ))^(1/η), for either direction of slip.
    assume(beta + gamma > 0.05)
    p = fr.bouc_wen_parameters(u_y=1e-3, A=A, beta=beta, gamma=gamma, eta=eta)
    z_ss = (A / (beta + gamma)) ** (1.0 / eta)
    scale = A * v / 1e-3
    assert fr.bouc_wen_rate(z_ss, v, p)[0] == pytest.approx(0.0, abs=1e-12 * scale)
    assert fr.bouc_wen_rate(-z_ss, -v, p)[0] == pytest.approx(0.0, abs=1e-12 * scale)
    # Below the steady value z grows towards it, above it z decays (a stable attractor).
    assert fr.bouc_wen_rate(0.5 * z_ss, v, p)[0] > 0.0 > fr.bouc_wen_rate(1.5 * z_ss, v, p)[0]


def test_bouc_wen_steady_cycle_area_and_peak_closed_form():
    # Derived for A = 1, β = γ = 1/2, η = 2 under u = D sin ωt: after a reversal z falls linearly,
    # dz/du = 1/u_y, to 0, then follows −tanh; symmetry gives the peak Z0 = tanh(S), S = 2D/u_y − Z0,
    # and the loop area ∮ z du = 2 u_y ln cosh S − u_y Z0² (-> 4D − (3 + 2 ln 2) u_y for D >> u_y;
    # times μN this is the energy per cycle, 4 μ N D for a rigid-plastic slider).
    u_y, d, w = 1e-3, 5e-3, 2.0 * math.pi
    p = fr.bouc_wen_parameters(u_y=u_y, beta=0.5, gamma=0.5, eta=2.0)
    sol = _integrate_bouc_wen(p, lambda t: d * w * math.cos(w * t), 4.0, extra_work=True)
    z0 = brentq(lambda z: z - math.tanh(2 * d / u_y - z), 0.0, 1.0, xtol=1e-15)
    s = 2 * d / u_y - z0
    area = 2 * u_y * math.log(math.cosh(s)) - u_y * z0**2
    work = sol.sol(4.0)[2] - sol.sol(3.0)[2]
    assert work == pytest.approx(area, rel=1e-7)
    assert sol.sol(3.25)[1] == pytest.approx(z0, abs=1e-8)  # u = +D at t = 3.25
    assert sol.sol(3.75)[1] == pytest.approx(-z0, abs=1e-8)
    assert area == pytest.approx(4 * d - (3 + 2 * math.log(2)) * u_y, rel=1e-5)


@settings(max_examples=60, deadline=None)
@given(
    z=st.floats(-1.0, 1.0),
    log_v=st.floats(-4.0, 0.5),
    negative=st.booleans(),
    eta=st.floats(1.0, 3.0),
    beta=st.floats(0.0, 1.0),
)
def test_bouc_wen_rate_derivatives_equal_central_differences(z, log_v, negative, eta, beta):
    assume(abs(z) > 1e-3)
    v = -(10.0**log_v) if negative else 10.0**log_v
    p = fr.bouc_wen_parameters(u_y=1e-3, beta=beta, gamma=1.0 - beta, eta=eta)
    zdot, dz, dv = fr.bouc_wen_rate(z, v, p)
    hz, hv = 1e-7, 1e-6 * abs(v)
    fd_z = (fr.bouc_wen_rate(z + hz, v, p)[0] - fr.bouc_wen_rate(z - hz, v, p)[0]) / (2 * hz)
    fd_v = (fr.bouc_wen_rate(z, v + hv, p)[0] - fr.bouc_wen_rate(z, v - hv, p)[0]) / (2 * hv)
    scale = abs(v) / 1e-3
    assert fd_z == pytest.approx(dz, rel=1e-5, abs=1e-7 * scale)
    assert fd_v == pytest.approx(dv, rel=1e-6, abs=1e-7 / 1e-3)


# ---------------------------------------------------------------------------------------------
# Registry, validation, public wrappers and the compiled path
# ---------------------------------------------------------------------------------------------


def test_unknown_law_lists_the_valid_names():
    with pytest.raises(ValueError, match="unknown friction law 'hertz'.*andersson.*brown_mcphee"):
        fr.get_friction_law("hertz")
    assert fr.get_friction_law(" Andersson ") is FRICTION_LAWS["andersson"]


@pytest.mark.parametrize(
    ("name", "params", "match"),
    [
        ("coulomb", dict(mu_d=0.3), "missing parameter 'mu_s'"),
        ("andersson", dict(mu_s=0.2, mu_d=0.1, mu_x=1.0), "unknown parameter 'mu_x'.*k_t"),
        ("coulomb", dict(mu_s=0.5, mu_d=-0.1), "mu_d = -0.1.*>= 0"),
        ("brown_mcphee", dict(mu_s=0.5, mu_d=0.1, v_t=float("nan")), "v_t = nan.*> 0"),
        ("stribeck", dict(mu_s=0.5, mu_d=0.1, v_s=0.0), "v_s = 0.0.*> 0"),
        ("coulomb", dict(mu_s=0.2, mu_d=0.3), "mu_d = 0.3 > mu_s = 0.2; allowed: mu_d <= mu_s"),
        ("constantinou", dict(mu_min=0.1, mu_max=0.05, a=20.0), "mu_min = 0.1 > mu_max = 0.05"),
        ("viscous", dict(mu_v="fast"), "mu_v = 'fast'; allowed: a number"),
    ],
)
def test_bad_parameters_are_named(name, params, match):
    with pytest.raises(ValueError, match=match):
        friction_parameters(name, **params)


def test_bouc_wen_and_wrapper_validation():
    with pytest.raises(ValueError, match="missing parameter 'u_y'"):
        fr.bouc_wen_parameters()
    with pytest.raises(ValueError, match="eta = 0.5.*>= 1"):
        fr.bouc_wen_parameters(u_y=1e-3, eta=0.5)
    with pytest.raises(ValueError, match="beta \\+ gamma = 0"):
        fr.bouc_wen_parameters(u_y=1e-3, beta=0.3, gamma=-0.3)
    with pytest.raises(ValueError, match="normal = -1.0 \\[N\\]"):
        fr.coulomb(0.1, normal=[1.0, -1.0], mu_s=0.5, mu_d=0.4)


def test_parameters_pack_in_registry_order_with_defaults():
    law = FRICTION_LAWS["andersson"]
    assert law.parameter_names == ("mu_s", "mu_d", "v_s", "exponent", "k_t", "mu_v")
    p = friction_parameters("andersson", mu_d=0.1, mu_s=0.2)
    np.testing.assert_array_equal(p, [0.2, 0.1, 1e-3, 2.0, 1e4, 0.0])
    assert p.dtype == np.float64


@pytest.mark.parametrize("name", NAMES)
def test_public_function_broadcasts_and_matches_kernel(name):
    law = FRICTION_LAWS[name]
    v = np.array([[-0.2], [1e-4], [0.3]])
    normal = np.array([1.0e5, 2.0e6])
    kw = {} if name == "viscous" else {"normal": normal}
    out = law.function(v, **kw, **CASES[name])
    p = friction_parameters(name, **CASES[name])
    expected = [[law.kernel(vi, ni, p)[0] for ni in normal] for vi in v[:, 0]]
    if name == "viscous":  # no normal force argument: f depends on v alone
        expected = np.array(expected)[:, :1]
    assert out.shape == np.shape(expected)
    np.testing.assert_array_equal(out, expected)
    assert isinstance(law.function(0.1, **{k: 1.0e5 for k in kw}, **CASES[name]), float)


def test_kernels_compile_with_numba_and_agree_with_python():
    # Guide habit 12: the physics is written once; the compiled path must equal the Python one.
    v = [-1.0, -2e-3, -1e-3, -2e-4, 0.0, 5e-4, 1e-3, 2.5e-3, 0.7]
    for name in NAMES:
        law = FRICTION_LAWS[name]
        p = friction_parameters(name, **CASES[name])
        compiled = jit(law.kernel)
        for x in v:
            np.testing.assert_allclose(compiled(x, N_REF, p), law.kernel(x, N_REF, p), rtol=1e-13)
    p = friction_parameters("constantinou", **CASES["constantinou"])
    hyst = jit(fr.constantinou_bouc_wen_kernel)
    stick = jit(fr.coulomb_stick_slip_kernel)
    rate = jit(fr.bouc_wen_rate)
    pc = friction_parameters("coulomb", **CASES["coulomb"])
    pb = fr.bouc_wen_parameters(u_y=1e-3, beta=0.1, gamma=0.9)
    for x in v:
        np.testing.assert_allclose(
            hyst(x, N_REF, 0.3, p), fr.constantinou_bouc_wen_kernel(x, N_REF, 0.3, p), rtol=1e-13
        )
        np.testing.assert_allclose(rate(0.4, x, pb), fr.bouc_wen_rate(0.4, x, pb), rtol=1e-13)
        assert stick(x * N_REF, N_REF, pc) == fr.coulomb_stick_slip_kernel(x * N_REF, N_REF, pc)
