"""Sliding base isolation: friction in both integrators, moat walls, results and case files.

Sources: Den Hartog, J.P. (1931). Forced vibrations with combined Coulomb and viscous friction.
Trans. ASME 53, 107-115 (stick-slip of a friction-driven mass under harmonic excitation, the
closed form derived below for a rigid block); Zayas, Low & Mahin (1990) Earthquake Spectra 6(2)
(friction pendulum: restoring force W/R u, period 2π √(R/g), energy 4 μ W D per cycle); Wen (1976)
J. Eng. Mech. Div. 102(2) and Constantinou, Mokha & Reinhorn (1990) J. Struct. Eng. 116(2)
(Bouc-Wen sliding bearing); Chopra (2017) Dynamics of Structures §2.4 (Coulomb-damped free vibration:
half period unchanged, amplitude drop 2 f/k per half cycle).

A "rigid block" here is an isolated building whose one floor weighs 10⁻⁶ of the slab, on a spring of
period 0.02 s: its force on the slab is ~10⁻⁶ of the friction, far below every tolerance used.
"""

from __future__ import annotations

import copy
import math
import os
import subprocess
import sys

import numpy as np
import pytest
from scipy.optimize import brentq

from pounding.case import CaseError, case_from_dict
from pounding.friction import FRICTION_LAWS
from pounding.ground_motion import harmonic, sine_pulse
from pounding.integrators import METHODS
from pounding.integrators.base import ENERGY_TERMS
from pounding.simulate import simulate
from pounding.structure import IsolationBase, ModalDamping, ShearBuilding
from pounding.system import (
    FRICTION_BOUC_WEN,
    FRICTION_COULOMB,
    FRICTION_REGULARISED,
    Contact,
    assemble,
)
from pounding.units import G

SLAB = 1.0e5  # kg

#: every Newmark-family method of the registry (the compiled loop)
NEWMARK_METHODS = [m for m in METHODS if m != "ivp"]


def _block(base: IsolationBase, name: str = "R") -> ShearBuilding:
    """A rigid block: the slab carries one floor of 1e-6 of its mass on a 0.02 s spring."""
    m1 = SLAB * 1e-6
    k1 = m1 * (2.0 * math.pi / 0.02) ** 2
    return ShearBuilding(name, [m1], [k1], damping=ModalDamping((0.05,)), base=base)


def _coulomb_block(mu_s: float, mu_d: float, **kw) -> ShearBuilding:
    return _block(IsolationBase(mass=SLAB, friction="coulomb", mu_s=mu_s, mu_d=mu_d, **kw))


def _base(ds, name: str = "R"):
    sel = ds.sel(building=name)
    return (
        sel["base_displacement"].values,
        sel["base_velocity"].values,
        sel["stick"].values,
        sel["friction_force"].values,
    )


# --------------------------------------------------------------------------------------------------
# Rigid block on a flat Coulomb surface under a_g = A sin ωt (den Hartog type solution)
# --------------------------------------------------------------------------------------------------

MU_S, MU_D, PERIOD = 0.3, 0.2, 1.0
AMPLITUDE = 0.4 * G  # μ_s g / A = 0.75, μ_d g / A = 0.5: slides, then sticks again every half cycle


def den_hartog_block(t, *, amplitude, period, mu_s, mu_d):
    """Relative displacement and velocity of a rigid block on a Coulomb surface, a_g = A sin ωt.

    Derivation (m ẍ = p − f with p = −m a_g the force that would hold the block): it sticks while
    A |sin ωt| <= μ_s g, so it first breaks away at t_s = asin(μ_s g/A)/ω, pushed towards −x. Sliding
    with ẋ < 0 the friction is −μ_d m g, so ẍ = −A sin ωt + μ_d g and, from rest at t_s,

        ẋ(t) = (A/ω)(cos ωt − cos ωt_s) + μ_d g (t − t_s)
        ξ(t) = (A/ω²)(sin ωt − sin ωt_s) − (A/ω) cos ωt_s (t − t_s) + μ_d g (t − t_s)²/2,

    until ẋ(t_e) = 0. If A |sin ωt_e| <= μ_s g it sticks again (the regime of this test, asserted),
    slipping Δ = ξ(t_e) in the half cycle. By the antisymmetry a_g(t + T/2) = −a_g(t) the next slide
    starts at t_s + T/2 and mirrors the first, bringing the block back: x alternates between 0 and Δ.
    """
    w = 2.0 * math.pi / period
    ts = math.asin(mu_s * G / amplitude) / w

    def xi(tau):
        return (
            amplitude / w**2 * (math.sin(w * tau) - math.sin(w * ts))
            - amplitude / w * math.cos(w * ts) * (tau - ts)
            + 0.5 * mu_d * G * (tau - ts) ** 2
        )

    def xi_dot(tau):
        return amplitude / w * (math.cos(w * tau) - math.cos(w * ts)) + mu_d * G * (tau - ts)

    te = brentq(xi_dot, ts + 1e-9, ts + period, xtol=1e-15)
    assert abs(amplitude * math.sin(w * te)) <= mu_s * G  # it sticks at t_e: the regime tested
    assert te < ts + period / 2  # and stays stuck a while before the next break-away
    slip = xi(te)
    x = np.zeros(np.size(t))
    v = np.zeros(np.size(t))
    for i, ti in enumerate(np.atleast_1d(t)):
        if ti < ts:
            continue
        k = int((ti - ts) // (period / 2))
        tau = ti - k * period / 2
        sign = -1.0 if k % 2 else 1.0
        start = slip if k % 2 else 0.0
        if tau <= te:
            x[i] = start + sign * xi(tau)
            v[i] = sign * xi_dot(tau)
        else:
            x[i] = start + sign * slip
    return x, v, ts, te, slip


@pytest.mark.parametrize("method", ["newmark", "ivp"])
def test_rigid_block_below_mu_s_g_never_slides(method):
    # Static Coulomb friction (Karnopp 1985): stuck while |m a_g| <= μ_s m g. At A = 0.95 μ_s g the slab never moves, the
    # friction is the full inertia force −m_total a_g, and nothing is dissipated.
    system = assemble([_coulomb_block(MU_S, MU_D)])
    gm = harmonic(amplitude=0.95 * MU_S * G, period=PERIOD, duration=2.0, dt=0.005)
    ds = simulate(system, gm, method=method, output_dt=0.005)
    x, v, stick, force = _base(ds)
    assert np.all(x == 0.0) and np.all(v == 0.0)
    assert np.all(stick == 1.0)
    ag = ds["ground_acceleration"].values
    np.testing.assert_allclose(force, -SLAB * (1 + 1e-6) * ag, atol=1e-4 * MU_S * SLAB * G)
    assert float(ds["energy"].sel(term="friction_dissipated").max()) == 0.0


@pytest.mark.parametrize("method", NEWMARK_METHODS)
def test_den_hartog_rigid_block_stick_slip_newmark(method):
    # Den Hartog-type closed form (above): break-away at t_s, stop at t_e, slip Δ per half cycle,
    # stuck from t_e to t_s + T/2; three cycles. A fine record (2e-4 s) keeps the linear
    # interpolation of the sine below 1e-7 m; the compiled loop locates each transition.
    system = assemble([_coulomb_block(MU_S, MU_D)])
    gm = harmonic(amplitude=AMPLITUDE, period=PERIOD, duration=3.0, dt=2e-4)
    ds = simulate(system, gm, method=method, output_dt=1e-3, alpha=-0.05)
    t = ds["time"].values
    x_ref, v_ref, ts, te, slip = den_hartog_block(
        t, amplitude=AMPLITUDE, period=PERIOD, mu_s=MU_S, mu_d=MU_D
    )
    x, v, stick, force = _base(ds)
    assert slip == pytest.approx(-0.112890, abs=1e-6)
    np.testing.assert_allclose(x, x_ref, atol=3e-7)
    np.testing.assert_allclose(v, v_ref, atol=1e-6)
    # stick-slip timing on the output grid: stuck exactly where the closed form is at rest (grid
    # points within 1 ms of a transition t_s + kT/2, t_e + kT/2 aside)
    half = PERIOD / 2

    def distance(event):
        return np.abs((t - event + half / 2) % half - half / 2)

    far = (distance(ts) > 1e-3) & (distance(te) > 1e-3)
    np.testing.assert_array_equal(stick[far] == 1.0, v_ref[far] == 0.0)
    # while sliding the friction is ±μ_d N against the motion
    sliding = stick == 0.0
    np.testing.assert_allclose(np.abs(force[sliding]), MU_D * SLAB * (1 + 1e-6) * G, rtol=1e-12)
    assert ds.attrs["n_friction_events"] == 11  # break-aways at t_s + kT/2 (6), stops at t_e + kT/2
    # energy: each slide dissipates μ_d N |Δ|; five are over while stuck at t_e + 2T < t < t_s + 5T/2
    e_f = ds["energy"].sel(term="friction_dissipated")
    stuck_after_five = 0.5 * ((te + 2 * PERIOD) + (ts + 2.5 * PERIOD))
    assert float(e_f.interp(time=stuck_after_five)) == pytest.approx(
        5 * MU_D * SLAB * (1 + 1e-6) * G * abs(slip), rel=1e-6
    )
    assert ds.attrs["energy_balance_error"] < 1e-5


def test_den_hartog_rigid_block_exact_transitions_ivp():
    # The same closed form through the solve_ivp path, whose stick-slip transitions are events
    # (u̇_b = 0 then the stick test; |p| = μ_s N). A coarser record (2e-3 s) keeps it fast: the
    # interpolated sine then differs from the closed form's by up to (ω dt)²/8 ~ 2e-5 relative, so
    # the ivp path is also checked against the Newmark loop on the same record (to 1e-8 m).
    system = assemble([_coulomb_block(MU_S, MU_D)])
    gm = harmonic(amplitude=AMPLITUDE, period=PERIOD, duration=1.3, dt=2e-3)
    ivp = simulate(system, gm, method="ivp", rtol=1e-10, output_dt=1e-3)
    t = ivp["time"].values
    x_ref, v_ref, ts, te, slip = den_hartog_block(
        t, amplitude=AMPLITUDE, period=PERIOD, mu_s=MU_S, mu_d=MU_D
    )
    x, v, stick, _ = _base(ivp)
    np.testing.assert_allclose(x, x_ref, atol=1e-5)
    np.testing.assert_allclose(v, v_ref, atol=3e-5)
    assert ivp.attrs["n_events"] == 5  # break-away, stop, break-away, stop, break-away
    changes = t[1:][np.diff(stick) != 0]
    expected = [ts, te, ts + PERIOD / 2, te + PERIOD / 2, ts + PERIOD]
    np.testing.assert_allclose(changes, expected, atol=1e-3 + 1e-9)  # first grid point after each
    nm = simulate(system, gm, dt=1e-4, output_dt=1e-3)
    xn, vn, stick_n, _ = _base(nm)
    np.testing.assert_allclose(x, xn, atol=2e-8)
    np.testing.assert_allclose(v, vn, atol=2e-8)
    np.testing.assert_array_equal(stick, stick_n)
    assert ivp.attrs["energy_balance_error"] < 1e-8


def test_break_away_jumps_with_static_above_dynamic_coefficient():
    # Static and dynamic Coulomb friction with μ_s > μ_d: at break-away the acceleration jumps from 0 to (μ_s − μ_d) g
    # (the held force μ_s N now meets only μ_d N); with μ_s = μ_d it starts from 0. Checked through
    # the velocity 1 ms after break-away, ≈ (μ_s − μ_d) g · 1 ms.
    gm = harmonic(amplitude=AMPLITUDE, period=PERIOD, duration=0.3, dt=2e-4)
    ts = math.asin(MU_S * G / AMPLITUDE) / (2 * math.pi / PERIOD)
    for mu_d, expected in ((MU_D, (MU_S - MU_D) * G), (MU_S, 0.0)):
        ds = simulate(assemble([_coulomb_block(MU_S, mu_d)]), gm, output_dt=2e-4)
        v = ds["base_velocity"].sel(building="R")
        dv = float(v.interp(time=ts + 1e-3))
        assert -dv == pytest.approx(expected * 1e-3, rel=0.05, abs=2e-5)


@pytest.mark.parametrize("method", ["newmark", "ivp"])
def test_frictionless_flat_slider_leaves_the_block_at_rest(method):
    # Newton's first law: with μ_s = μ_d = 0 and no restoring force nothing pushes the block, so it
    # stays put while the ground moves under it: u_b = −u_g (relative to the ground). u_g is the
    # exact double integral of the piecewise-linear record (ground_motion.ground_displacement).
    from pounding.ground_motion import ground_displacement, ground_velocity

    system = assemble([_coulomb_block(0.0, 0.0)])
    assert system.friction.fr_kind.tolist() == [FRICTION_REGULARISED]  # never stuck, f = 0
    gm = sine_pulse(amplitude=3.0, period=0.5, duration=1.0, dt=0.01)
    ds = simulate(system, gm, method=method, output_dt=0.01)
    x, v, stick, force = _base(ds)
    scale = float(np.abs(ground_displacement(gm)).max())
    np.testing.assert_allclose(x, -ground_displacement(gm), atol=1e-6 * scale)
    np.testing.assert_allclose(v, -ground_velocity(gm), atol=1e-6 * scale / 0.5)
    assert np.all(force == 0.0) and np.all(stick == 0.0)


# --------------------------------------------------------------------------------------------------
# Friction pendulum
# --------------------------------------------------------------------------------------------------

RADIUS = 2.0


def _extremes(t, u, v, after):
    """Times and values of the base displacement's extremes (velocity sign changes) after ``after``,
    from a parabola through the three grid points before each turn (one smooth arc: friction flips
    at the turn, so the motion has a kink in acceleration there)."""
    out_t, out_u = [], []
    i0 = np.searchsorted(t, after)
    for i in range(max(i0, 3), t.size - 1):
        if v[i] != 0.0 and np.sign(v[i]) != np.sign(v[i + 1]):
            coef = np.polyfit(t[i - 2 : i + 1] - t[i], u[i - 2 : i + 1], 2)
            tv = -coef[1] / (2 * coef[0])
            out_t.append(t[i] + tv)
            out_u.append(np.polyval(coef, tv))
    return np.array(out_t), np.array(out_u)


@pytest.mark.parametrize("method", ["newmark", "ivp"])
def test_friction_pendulum_free_vibration_period_and_coulomb_decrement(method):
    # Zayas et al. (1990): restoring force (W/R) u_b, so the sliding period is 2π √(R/g) whatever
    # the mass; Coulomb friction μ W leaves each half period π √(R/g) unchanged and lowers the
    # amplitude by 2 f/k = 2 μ R per half cycle (Chopra §2.4). Free vibration after a 1 s pulse (the
    # record ends there: a_g = 0 afterwards).
    mu = 0.01
    base = IsolationBase(
        type="friction_pendulum", radius=RADIUS, mass=SLAB, friction="coulomb", mu_s=mu, mu_d=mu
    )
    system = assemble([_block(base)])
    gm = sine_pulse(amplitude=0.3 * G, period=1.0, duration=1.0, dt=0.01)
    ds = simulate(system, gm, method=method, duration=9.0, output_dt=5e-4, rtol=1e-10)
    x, v, stick, _ = _base(ds)
    times, peaks = _extremes(ds["time"].values, x, v, after=1.0)
    assert times.size >= 5
    half = math.pi * math.sqrt(RADIUS / G)
    np.testing.assert_allclose(np.diff(times), half, rtol=2e-6)
    np.testing.assert_allclose(np.abs(peaks[:-1]) - np.abs(peaks[1:]), 2 * mu * RADIUS, atol=1e-6)
    assert np.all(stick[ds["time"].values > 1.0] == 0.0)  # |u| > μ R at every turn: no sticking
    assert float(ds["peak_base_displacement"].sel(building="R")) == pytest.approx(
        np.abs(x).max(), rel=1e-3
    )
    assert ds.attrs["energy_balance_error"] < 1e-6


def test_friction_pendulum_steady_cycle_dissipates_4_mu_W_D():
    # Zayas et al. (1990): a sliding cycle of amplitude D under μ W dissipates 4 μ W D. Harmonic
    # forcing (T = 1.5 s, 0.3 g) for 45 s nearly reaches the steady cycle (turning points repeat to
    # ~0.2 %, the transient of a Coulomb-damped oscillator decays slowly); exactly, any cycle between
    # two turning points dissipates μ W times the distance slid.
    mu = 0.05
    base = IsolationBase(
        type="friction_pendulum", radius=RADIUS, mass=SLAB, friction="coulomb", mu_s=mu, mu_d=mu
    )
    system = assemble([_block(base)])
    w = system.friction.fr_normal[0]
    gm = harmonic(amplitude=0.3 * G, period=1.5, duration=45.0, dt=0.01)
    ds = simulate(system, gm, output_dt=1e-3)
    t = ds["time"].values
    x, v, stick, _ = _base(ds)
    e_f = ds["energy"].sel(term="friction_dissipated").values
    times, peaks = _extremes(t, x, v, after=38.0)
    i = int(np.flatnonzero(peaks > 0)[0])
    t0, t1 = times[i], times[i + 2]  # one full cycle from a positive turn to the next
    dissipated = np.interp(t1, t, e_f) - np.interp(t0, t, e_f)
    path = (peaks[i] - peaks[i + 1]) + (peaks[i + 2] - peaks[i + 1])
    assert dissipated == pytest.approx(mu * w * path, rel=2e-5)
    d = 0.5 * (peaks[i] - peaks[i + 1])  # the amplitude of the cycle's first half
    assert abs(peaks[i] - peaks[i + 2]) < 5e-3 * d  # (nearly) steady
    assert abs(peaks[i] + peaks[i + 1]) < 5e-3 * d  # centred: the pendulum recentres
    assert dissipated == pytest.approx(4 * mu * w * d, rel=5e-3)
    assert t1 - t0 == pytest.approx(1.5, rel=1e-3)  # (nearly) steady: the forcing period
    assert np.all(stick[t > 38.0] == 0.0)


def _bouc_wen_map(z, du, u_y):
    """Exact Bouc-Wen (A = 1, β = γ = 1/2, η = 2) update over a monotonic slide du (Wen 1976).

    Sliding with sign s: dz/du = (1 − z²)/u_y while s z >= 0 (z = s tanh(...)), and dz/du = 1/u_y
    (linear) while s z < 0, since β s|z|z + γ z² vanishes there."""
    s = 1.0 if du >= 0.0 else -1.0
    zs, dus = s * z, abs(du) / u_y
    if zs < 0.0:
        if zs + dus <= 0.0:
            return s * (zs + dus)
        dus -= -zs
        zs = 0.0
    return s * math.tanh(math.atanh(min(zs, 1.0 - 1e-16)) + dus)


@pytest.mark.parametrize("method", ["newmark", "ivp"])
def test_bouc_wen_bearing_follows_rate_independent_closed_form(method):
    # Constantinou et al. (1990) bearing with constant μ (μ_min = μ_max): f = μ N z, z the Bouc-Wen
    # variable. Its closed-form path map (above), applied along the computed slab displacement, gives
    # z at every output time; the loop of a steady cycle of amplitude D has the area
    # μ N (2 u_y ln cosh S − u_y Z0²), Z0 = tanh(S), S = 2D/u_y − Z0 (tests/test_friction.py).
    # Newmark steps of 5 ms slide up to 4 u_y: its z must follow the map step by step (output = step,
    # so the reference sees the same monotonic pieces); the ivp output every 1 ms differs from the map
    # by the reversals inside an output interval, O(a dt²/u_y).
    mu, u_y = 0.05, 2e-3
    base = IsolationBase(
        type="friction_pendulum",
        radius=RADIUS,
        mass=SLAB,
        friction="constantinou",
        mu_min=mu,
        mu_max=mu,
        a=0.0,
        u_y=u_y,
    )
    system = assemble([_block(base)])
    normal = system.friction.fr_normal[0]
    assert system.friction.fr_kind[0] == FRICTION_BOUC_WEN
    duration, step, tol = (45.0, 5e-3, 1e-4) if method == "newmark" else (8.0, 1e-3, 2e-3)
    gm = harmonic(amplitude=0.3 * G, period=1.5, duration=duration, dt=0.01)
    ds = simulate(system, gm, method=method, dt=step, output_dt=step, rtol=1e-9)
    t = ds["time"].values
    x, v, stick, force = _base(ds)
    z = force / (mu * normal)
    z_ref = np.zeros_like(z)
    for i in range(1, t.size):
        z_ref[i] = _bouc_wen_map(z_ref[i - 1], x[i] - x[i - 1], u_y)
    assert np.abs(np.diff(x)).max() > (3.0 * u_y if method == "newmark" else 0.5 * u_y)
    np.testing.assert_allclose(z, z_ref, atol=tol)
    assert np.all(stick == 0.0)  # a hysteretic law has no stuck state
    if method == "newmark":
        e_f = ds["energy"].sel(term="friction_dissipated").values
        times, peaks = _extremes(t, x, v, after=38.0)
        i = int(np.flatnonzero(peaks > 0)[0])
        d = 0.25 * ((peaks[i] - peaks[i + 1]) + (peaks[i + 2] - peaks[i + 1]))
        z0 = brentq(lambda q: q - math.tanh(2 * d / u_y - q), 0.0, 1.0, xtol=1e-15)
        s = 2 * d / u_y - z0
        area = mu * normal * (2 * u_y * math.log(math.cosh(s)) - u_y * z0**2)
        dissipated = np.interp(times[i + 2], t, e_f) - np.interp(times[i], t, e_f)
        assert dissipated == pytest.approx(area, rel=2e-4)
    assert ds.attrs["energy_balance_error"] < 1e-5


# --------------------------------------------------------------------------------------------------
# Moat walls and rows: Newmark against solve_ivp
# --------------------------------------------------------------------------------------------------

FRICTION = {
    "coulomb": dict(friction="coulomb", mu_s=0.08, mu_d=0.06),
    "constantinou": dict(friction="constantinou", mu_min=0.04, mu_max=0.1, a=20.0),
    "constantinou_bouc_wen": dict(
        friction="constantinou", mu_min=0.04, mu_max=0.1, a=20.0, u_y=1e-3
    ),
}


def _agree(nm, ivp, *, base_tol=5e-3, force_tol=2e-2):
    assert np.array_equal(nm["impact_count"].values, ivp["impact_count"].values)
    pb_nm = nm["peak_base_displacement"].values
    pb_ivp = ivp["peak_base_displacement"].values
    iso = np.isfinite(pb_nm)
    np.testing.assert_allclose(pb_nm[iso], pb_ivp[iso], rtol=base_tol)
    np.testing.assert_array_equal(np.isnan(pb_nm), np.isnan(pb_ivp))
    f_nm, f_ivp = nm["peak_contact_force"].values, ivp["peak_contact_force"].values
    np.testing.assert_allclose(f_nm, f_ivp, rtol=force_tol)
    np.testing.assert_allclose(
        nm["peak_displacement"].values, ivp["peak_displacement"].values, rtol=base_tol
    )
    assert nm.attrs["energy_balance_error"] < 1e-2
    assert ivp.attrs["energy_balance_error"] < 1e-2


@pytest.mark.parametrize("law", list(FRICTION))
def test_isolated_building_against_moat_walls_newmark_agrees_with_ivp(law):
    # Issue 7 acceptance: a base-isolated 3-story building (friction pendulum, R = 2.2 m) hits the
    # moat walls on both sides of its base slab (12 cm gaps, Hertz-damped contact). Newmark at default
    # settings and solve_ivp agree: peak base displacement < 0.5 %, peak contact force < 2 %; the
    # energy balance closes within 1 % on both paths.
    base = IsolationBase(type="friction_pendulum", radius=2.2, mass=4e5, **FRICTION[law])
    building = ShearBuilding.uniform("A", 3, period=0.5, mass=3e5, base=base)
    walls = [
        Contact("A", "wall", 0.12, "hertz_kelvin", floors=[0], k=5e9, e=0.6),
        Contact("wall", "A", 0.12, "hertz_kelvin", floors=[0], k=5e9, e=0.6),
    ]
    system = assemble([building], walls)
    gm = sine_pulse(amplitude=0.5 * G, period=1.5, duration=4.0, dt=0.01)
    nm = simulate(system, gm)
    ivp = simulate(system, gm, method="ivp", rtol=1e-9)
    assert int(nm["impact_count"].sum()) >= 2  # both walls are hit
    _agree(nm, ivp)
    e = nm["energy"].isel(time=-1)
    assert float(e.sel(term="friction_dissipated")) > 0.1 * float(e.sel(term="input"))
    assert float(e.sel(term="contact_dissipated")) > 0.0


def test_row_of_isolated_and_fixed_base_buildings_with_contacts():
    # A base-isolated building between a moat wall and a fixed-base neighbour: floor-to-floor
    # contacts at the common levels and the isolated slab against the neighbour's first floor
    # (an explicit pair with floor 0). Both paths agree; the fixed-base building has no base data.
    base = IsolationBase(
        type="friction_pendulum", radius=2.2, mass=4e5, friction="coulomb", mu_s=0.08, mu_d=0.06
    )
    a = ShearBuilding.uniform("A", 3, period=0.5, mass=3e5, base=base)
    b = ShearBuilding.uniform("B", 3, period=0.4, mass=3e5)
    contacts = [
        Contact("wall", "A", 0.15, "hertz_kelvin", floors=[0], k=5e9, e=0.6),
        Contact("A", "B", 0.05, "hertz_kelvin", k=2.75e9, e=0.65),
        Contact("A", "B", 0.05, "hertz_kelvin", floors=[[0, 1]], k=2.75e9, e=0.65),
    ]
    system = assemble([a, b], contacts)
    assert system.elements.el_dof.tolist() == [[-1, 0], [1, 4], [2, 5], [3, 6], [0, 4]]
    gm = sine_pulse(amplitude=0.5 * G, period=1.5, duration=4.0, dt=0.01)
    nm = simulate(system, gm)
    ivp = simulate(system, gm, method="ivp", rtol=1e-9)
    assert nm["impact_count"].values.min() >= 1  # every contact, the slab's too, is hit
    _agree(nm, ivp)
    for ds in (nm, ivp):
        sel = ds.sel(building="B")
        for name in ("base_displacement", "base_velocity", "friction_force", "stick"):
            assert np.isnan(sel[name]).all()
        assert np.isnan(sel["peak_base_displacement"])
        assert list(ds["base_type"].values) == ["friction_pendulum", "fixed"]
        # floors stay floors: story 1 of A drifts relative to its slab
        drift = ds["drift"].sel(building="A", story=1)
        expected = ds["displacement"].sel(building="A", floor=1) - ds["base_displacement"].sel(
            building="A"
        )
        np.testing.assert_allclose(drift, expected, atol=1e-15)


@pytest.mark.parametrize("name", sorted(FRICTION_LAWS))
def test_every_friction_law_runs_in_both_paths(name):
    # Each registered law on a flat slider (no restoring force) under a sine pulse: both paths agree
    # on the slab's peak displacement and close the energy balance. Laws with a regularisation speed
    # get 1 cm/s so the explicit ivp solver stays quick.
    params = {
        "coulomb": dict(mu_s=0.12, mu_d=0.1),
        "viscous": dict(mu_v=2.0e5),
        "viscous_normal": dict(k_v=0.2),
        "stribeck": dict(mu_s=0.12, mu_d=0.1, v_s=0.01),
        "andersson": dict(mu_s=0.12, mu_d=0.1, v_s=0.01, k_t=300.0, mu_v=1e3),
        "brown_mcphee": dict(mu_s=0.12, mu_d=0.1, v_t=0.01, mu_v=1e3),
        "constantinou": dict(mu_min=0.06, mu_max=0.1, a=20.0, v_reg=0.01),
    }[name]
    base = IsolationBase(type="flat", mass=4e5, friction=name, **params)
    building = ShearBuilding.uniform("A", 2, period=0.4, mass=3e5, base=base)
    system = assemble([building])
    expected_kind = FRICTION_COULOMB if name == "coulomb" else FRICTION_REGULARISED
    assert system.friction.fr_kind.tolist() == [expected_kind]
    gm = sine_pulse(amplitude=0.4 * G, period=0.8, duration=2.0, dt=0.01)
    nm = simulate(system, gm)
    ivp = simulate(system, gm, method="ivp", rtol=1e-8)
    peak = float(ivp["peak_base_displacement"].sel(building="A"))
    assert peak > 0.01
    assert float(nm["peak_base_displacement"].sel(building="A")) == pytest.approx(peak, rel=5e-3)
    for ds in (nm, ivp):
        e = ds["energy"].isel(time=-1)
        assert float(e.sel(term="friction_dissipated")) > 0.0
        assert ds.attrs["energy_balance_error"] < 1e-3
        assert np.all(np.diff(ds["energy"].sel(term="friction_dissipated").values) >= -1e-9)


# --------------------------------------------------------------------------------------------------
# Assembly, schema, case files
# --------------------------------------------------------------------------------------------------


def test_isolated_matrices_are_T_K_T_with_pendulum_stiffness():
    # system.py: K_ext = Tᵀ K T + (W/R) e_b e_bᵀ, C_ext = Tᵀ C T, M_ext = diag(m_b, m), T mapping
    # [u_b, u_1..u_n] to the story-relative floor displacements [u_i − u_b]; checked on a hand case:
    # 2 floors, k1 = 4e8, k2 = 3e8 N/m, m = 2e5 kg, slab 5e5 kg, R = 2.5 m.
    base = IsolationBase(
        type="friction_pendulum", radius=2.5, mass=5e5, friction="coulomb", mu_s=0.1, mu_d=0.08
    )
    b = ShearBuilding("A", [2e5, 2e5], [4e8, 3e8], base=base)
    fixed = ShearBuilding("F", [1e5], [1e8])
    system = assemble([fixed, b])
    w = G * 9e5
    k = np.array([[4e8 + w / 2.5, -4e8, 0.0], [-4e8, 7e8, -3e8], [0.0, -3e8, 3e8]])
    np.testing.assert_allclose(system.stiffness[1:, 1:], k, rtol=1e-15)
    np.testing.assert_allclose(np.diag(system.mass), [1e5, 5e5, 2e5, 2e5])
    c = b.damping_matrix()
    t = np.array([[-1.0, 1.0, 0.0], [-1.0, 0.0, 1.0]])
    np.testing.assert_allclose(system.damping[1:, 1:], t.T @ c @ t, rtol=1e-12, atol=1e-6)
    assert system.base_dof.tolist() == [-1, 1]
    assert system.dof_offset.tolist() == [0, 2]
    assert system.dof(1, 0) == 1 and system.dof(1, 1) == 2
    assert system.below.tolist() == [-1, -1, 1, 2]
    fr = system.friction
    assert fr.fr_dof.tolist() == [1] and fr.fr_normal[0] == pytest.approx(w)
    assert fr.building.tolist() == [1] and fr.fr_mass.tolist() == [5e5]
    # the rigid-body (sliding) mode of the slab counts for the shortest period
    with pytest.raises(ValueError, match="has no base slab"):
        system.dof(0, 0)
    # a wall at the base and a slab-to-floor pair; floor 0 of a fixed-base building is refused
    walls = assemble([b], [Contact("A", "wall", 0.1, "linear", floors=[0], k=1e9)])
    assert walls.elements.el_dof.tolist() == [[0, -1]]
    assert walls.elements.el_mass.tolist() == [5e5]
    with pytest.raises(ValueError, match=r"floor 0 of building 'F'; allowed: 1..1 \(0, a base"):
        assemble([fixed, b], [Contact("F", "A", 0.1, "linear", floors=[[0, 0]], k=1e9)])
    with pytest.raises(ValueError, match=r"floor 3 of building 'A'; allowed: 0..2 \(0 = the base"):
        assemble([b], [Contact("A", "wall", 0.1, "linear", floors=[3], k=1e9)])


def test_schema_of_an_isolated_result_and_netcdf_round_trip(tmp_path):
    from pounding.results import open_result, save

    base = IsolationBase(type="flat", mass=SLAB, friction="coulomb", mu_s=0.2, mu_d=0.15)
    system = assemble([_block(base), ShearBuilding.uniform("B", 2, period=0.3, mass=1e5)])
    ds = simulate(system, sine_pulse(amplitude=4.0, period=0.5, duration=1.0, dt=0.01))
    assert list(ds["term"].values) == list(ENERGY_TERMS)
    assert "friction_dissipated" in ENERGY_TERMS
    for name in ("base_displacement", "base_velocity", "friction_force", "stick"):
        assert ds[name].dims == ("time", "building"), name
        assert {"units", "long_name"} <= set(ds[name].attrs), name
    for name in ("peak_base_displacement", "base_mass", "base_radius", "base_normal_force"):
        assert ds[name].dims == ("building",)
        assert "units" in ds[name].attrs
    assert list(ds["floor"].values) == [1, 2]  # the slab is not a floor
    assert list(ds["friction_law"].values) == ["coulomb", "none"]
    assert ds.pounding.summary()["buildings"]["R"]["peak_base_displacement"] > 0.0
    assert "peak_base_displacement" not in ds.pounding.summary()["buildings"]["B"]
    back = open_result(save(ds, tmp_path / "iso.nc"))
    np.testing.assert_array_equal(back["stick"].values, ds["stick"].values)


CASE = {
    "title": "isolated building against its moat wall",
    "building": [
        {
            "name": "A",
            "n_floors": 3,
            "period": 0.5,
            "mass": 3e5,
            "base": {
                "type": "friction_pendulum",
                "radius": 2.2,
                "friction": "constantinou",
                "mu_min": 0.04,
                "mu_max": 0.1,
                "a": 20.0,
                "mass": 5e5,
            },
        },
        {"name": "B", "masses": [3e5, 3e5], "stiffnesses": [4e8, 4e8]},
    ],
    "contact": [
        {"left": "wall", "right": "A", "gap": 0.2, "floors": [0], "law": "hertz", "k": 5e9},
        {"left": "A", "right": "B", "gap": 0.05, "law": "hertz", "k": 2.75e9},
    ],
    "ground_motion": {"type": "sine_pulse", "amplitude": 0.3, "units": "g", "period": 1.0},
}


def test_case_file_base_table_exactly_as_the_issue():
    case = case_from_dict(CASE)
    a = case.system.buildings[0]
    assert a.isolated and a.base.radius == 2.2 and a.base.friction == "constantinou"
    assert a.base.to_dict() == CASE["building"][0]["base"] | {"mass": 5e5}
    fr = case.system.friction
    np.testing.assert_allclose(fr.fr_params[0, :4], [0.04, 0.1, 20.0, 1e-3])
    assert fr.fr_normal[0] == pytest.approx(G * (5e5 + 9e5))
    assert case.system.elements.el_dof[0].tolist() == [-1, 0]
    hyst = copy.deepcopy(CASE)
    hyst["building"][0]["base"]["u_y"] = 5e-4
    assert case_from_dict(hyst).system.friction.fr_kind.tolist() == [FRICTION_BOUC_WEN]


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"type": "rolling"}, r"building\[0\]\.base: type = 'rolling'; allowed: flat, friction_p"),
        ({"friction": "hertz"}, r"unknown friction law 'hertz'; allowed: coulomb, viscous"),
        (
            {"mu": 0.1},
            r"unknown key 'mu' for friction law 'constantinou'; allowed: type, mass.*mu_min",
        ),
        ({"mu_min": 0.2}, r"mu_min = 0.2 > mu_max = 0.1"),
        ({"radius": None}, r"radius \[m\] is required for a friction_pendulum"),
        ({"type": "flat"}, r"radius = 2.2 applies to type 'friction_pendulum' only"),
        ({"mass": None}, r"building\[0\]\.base\.mass \[kg\] .* is required"),
        ({"mass": -1.0}, r"mass = -1.0 kg; allowed: a finite number >= 1"),
        # fuzzed: a 1e-12 m pendulum (T = 2 µs) asked for 1e8 steps; a 1e-300 m one overflowed
        ({"radius": 1e-12}, r"radius = 1e-12 m; allowed: a finite number >= 0.05 m"),
        ({"radius": 0.049}, r"radius = 0.049 m; allowed: a finite number >= 0.05 m"),
        ({"mass": 1e-300}, r"mass = 1e-300 kg; allowed: a finite number >= 1"),
        ({"u_y": 0.0}, r"Bouc-Wen: u_y = 0.0 \[m\]; allowed: finite, > 0"),
    ],
)
def test_case_file_base_errors_name_the_key(change, message):
    data = copy.deepcopy(CASE)
    base = data["building"][0]["base"]
    for key, value in change.items():
        if value is None:
            del base[key]
        else:
            base[key] = value
    with pytest.raises(CaseError, match=message):
        case_from_dict(data)


def test_case_file_base_floor_of_a_fixed_building_is_refused():
    data = copy.deepcopy(CASE)
    data["contact"].append(
        {"left": "B", "right": "wall", "gap": 0.1, "floors": [0], "law": "linear", "k": 1e9}
    )
    with pytest.raises(CaseError, match=r"floor 0 of building 'B'; allowed: 1..2"):
        case_from_dict(data)
    data["building"][0]["base"] = 5e5
    with pytest.raises(CaseError, match=r"building\[0\]\.base must be a table"):
        case_from_dict(data)


SCRIPT = """
import sys
import numpy as np
from pounding.ground_motion import sine_pulse
from pounding.integrators import _kernels
from pounding.simulate import simulate
from pounding.structure import IsolationBase, ShearBuilding
from pounding.system import Contact, assemble
if sys.argv[2] == "plain":
    assert not hasattr(_kernels._integrate, "py_func"), "numba is still compiling"
a = ShearBuilding.uniform("A", 2, period=0.4, mass=3e5, base=IsolationBase(
    mass=4e5, friction="coulomb", mu_s=0.12, mu_d=0.1))
b = ShearBuilding.uniform("B", 2, period=0.5, mass=3e5, base=IsolationBase(
    type="friction_pendulum", radius=2.0, mass=4e5, friction="constantinou", mu_min=0.04,
    mu_max=0.1, a=20.0, u_y=1e-3))
system = assemble([a, b], [Contact("A", "B", 0.01, "hertz_kelvin", floors=[[0, 0]], k=5e9, e=0.6)])
ds = simulate(system, sine_pulse(amplitude=4.0, period=0.6, duration=0.8, dt=0.01))
np.save(sys.argv[1], np.concatenate([ds[v].values.ravel() for v in sys.argv[3:]]))
"""


def test_compiled_and_uncompiled_friction_loop_agree(tmp_path):
    # Guide habit 12: the compiled Newmark loop with both friction treatments (Coulomb stick-slip
    # and Bouc-Wen) and a slab-to-slab contact equals the same source run by the interpreter.
    names = ["base_displacement", "friction_force", "stick", "contact_force", "energy"]
    out = [tmp_path / "compiled.npy", tmp_path / "plain.npy"]
    for path, env in zip(out, ({}, {"NUMBA_DISABLE_JIT": "1"}), strict=True):
        subprocess.run(
            [sys.executable, "-c", SCRIPT, str(path), "plain" if env else "compiled", *names],
            env={**os.environ, **env},
            check=True,
        )
    compiled, plain = (np.load(p) for p in out)
    assert np.count_nonzero(compiled) > 0
    np.testing.assert_allclose(plain, compiled, rtol=1e-9, atol=1e-9 * np.abs(compiled).max())
