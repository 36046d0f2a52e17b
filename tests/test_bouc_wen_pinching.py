"""Pinching Bouc–Wen stories (Foliente 1995; Baber & Noori 1985): the kernel against an independent
fine-step integration of the (ζ, ε) equations in the drift, the pinched loop (a soft reloading at
zero force, less energy per cycle), ζ_s = 0 as the unpinched model bit for bit, an independent
solve_ivp of a 3-storey building pounding on a wall for both the Newmark and the ivp paths,
OpenSees' BWBN material re-implemented from its source, and the case-file checks.

The model, in the normalised drift x = δ/δ_y (δ_y = F_y/k), ζ = z/δ_y and ε:

    dζ/dx = h(ζ, ε) [A − ν (β sgn(ẋ ζ) + γ) |ζ|^n]/η,   dε/dx = (1 − α) ζ,
    A = A0 − δ_A ε,  ν = 1 + δ_ν ε,  η = 1 + δ_η ε,
    h = 1 − ζ1 exp(−(ζ sgn(ẋ) − q ζ_u)²/ζ2²),  ζ1 = ζ_s (1 − exp(−p ε)),
    ζ2 = (ψ + δ_ψ ε)(λ + ζ1),  ζ_u = [A/(ν (β + γ))]^(1/n),
    F = α k δ + (1 − α) F_y ζ.

OpenSees ``BWBN`` (SRC/material/uniaxial/BWBN.cpp, Foliente's model without strength and stiffness
degradation) in our terms. It integrates z = δ_y ζ [m] by backward Euler over each strain increment,
z₁ = z₀ + Φ(z₁) h(z₁, e₁) Δδ with Φ = Ao − |z|^n (γ + β sgn(Δδ z)), its energy e = (1 − α) k ∫z dδ
[J] = F_y δ_y ε taken at the end of the increment too, and ζ_u = (1/(β + γ))^(1/n) (no Ao, no ν);
the stress is α k δ + (1 − α) k z. So, with δ_A = δ_ν = δ_η = 0 and A = 1:

    uniaxialMaterial BWBN tag alpha ko n gamma beta Ao q zetas p Shi deltaShi lamda tol maxIter
        alpha = α, ko = k, n = n, gamma = γ/δ_y^n, beta = β/δ_y^n, Ao = A (= 1),
        q = q, zetas = ζ_s, p = p/(F_y δ_y), Shi = ψ δ_y, deltaShi = δ_ψ/F_y, lamda = λ

(ζ2 is in units of z there: Shi + deltaShi e = δ_y (ψ + δ_ψ ε)). BWBN has no δ_A, δ_ν, δ_η; with
A ≠ 1 its ζ_u = (1/(β + γ))^(1/n) differs from ours. The cross-check below runs its update, with
its residual written from the .cpp, along a slow cyclic history.
"""

from __future__ import annotations

import functools
import math
import re

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from pounding import simulate
from pounding.case import CaseError, case_from_dict
from pounding.ground_motion import sine_pulse
from pounding.stories import (
    N_STORY_PARAMS,
    N_STORY_STATE,
    SS_E,
    SS_EPS,
    SS_F,
    SS_W,
    SS_Z,
    Stories,
    bouc_wen_story_kernel,
)
from pounding.structure import ShearBuilding
from pounding.system import Contact, assemble

K, FY = 1.0e7, 1.0e4
DY = FY / K
#: Model parameters in the kernel's order after k and F_y: α, n, β, γ, A, δ_A, δ_ν, δ_η, ζ_s, p, q,
#: ψ, δ_ψ, λ; case-file keys alongside.
KEYS = ("hardening", "n", "beta", "gamma", "A", "delta_a", "delta_nu", "delta_eta",
        "zeta_s", "p", "q", "psi", "delta_psi", "lambda")  # fmt: skip
#: Strong pinching (ζ_s = 0.9) with mild strength, stiffness and energy degradation.
PINCHED = {"hardening": 0.05, "n": 1.5, "beta": 0.6, "gamma": 0.4, "A": 1.0, "delta_a": 0.002,
           "delta_nu": 0.005, "delta_eta": 0.005, "zeta_s": 0.9, "p": 1.0, "q": 0.1, "psi": 0.2,
           "delta_psi": 0.005, "lambda": 0.5}  # fmt: skip


def _p(**params: float) -> np.ndarray:
    """The kernel's parameter row (k, F_y, then :data:`KEYS`) of K, FY and ``params``."""
    return np.array([K, FY, *(params[key] for key in KEYS)])


def _slope(zeta: float, eps: float, s: float, q: tuple) -> tuple[float, float]:
    """(dζ/dx, dε/dx) on a branch of direction s = sgn(ẋ), the model of the module docstring."""
    al, n, be, ga, a0, d_a, d_nu, d_eta, zs, pp, qq, psi, d_psi, lam = q
    a = a0 - d_a * eps
    nu = 1.0 + d_nu * eps
    eta = 1.0 + d_eta * eps
    z1 = zs * (1.0 - math.exp(-pp * eps))
    z2 = (psi + d_psi * eps) * (lam + z1)
    zu = (a / (nu * (be + ga))) ** (1.0 / n)
    h = 1.0 - z1 * math.exp(-(((zeta * s - qq * zu) / z2) ** 2))
    sign = 1.0 if s * zeta > 0.0 else -1.0 if s * zeta < 0.0 else 0.0
    return h * (a - nu * (be * sign + ga) * abs(zeta) ** n) / eta, (1.0 - al) * zeta


def _reference_pinching(x: np.ndarray, params: dict) -> tuple[np.ndarray, np.ndarray]:
    """ζ and ε at the drifts x [δ_y] (x[0] = 0, reversals on samples) by DOP853 in x along each
    monotone segment, restarted where ζ changes sign (where β's sgn(ẋ ζ) switches)."""
    q = tuple(params[key] for key in KEYS)
    zeta, eps = np.zeros(x.size), np.zeros(x.size)
    step = np.diff(x)
    ends = np.flatnonzero(step[:-1] * step[1:] < 0.0) + 1
    y = np.zeros(2)
    for i0, i1 in zip(np.r_[0, ends], np.r_[ends, x.size - 1], strict=True):
        s = 1.0 if x[i1] > x[i0] else -1.0
        start, i = x[i0], i0 + 1

        def crossing(t, y, s):
            return y[0]

        crossing.terminal, crossing.direction = True, s
        while i <= i1:
            sol = solve_ivp(lambda t, y, s: _slope(y[0], y[1], s, q), (start, x[i1]), y,
                            method="DOP853", t_eval=x[i : i1 + 1], args=(s,), rtol=1e-11,
                            atol=1e-13, events=crossing if s * y[0] < 0.0 else None)  # fmt: skip
            assert sol.success
            m = sol.t.size
            zeta[i : i + m], eps[i : i + m] = sol.y
            i += m
            if sol.status == 1:  # ζ = 0: go on from there
                start, y = sol.t_events[0][0], np.array([0.0, sol.y_events[0][0][1]])
            else:
                y = sol.y[:, -1]
    return zeta, eps


def _cycles(amplitudes, step: float) -> np.ndarray:
    """Drift history [δ_y]: one cycle 0 → a → −a → 0 per amplitude, in increments of about step."""
    x = [0.0]
    for a in amplitudes:
        for target in (a, -a, 0.0):
            m = max(1, round(abs(target - x[-1]) / step))
            x.extend(np.linspace(x[-1], target, m + 1)[1:])
    return np.array(x)


def _drive(history: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Run the kernel along a drift history [m]; rows (F, ζ, W, E, ε, tangent k_t)."""
    s0, s1 = np.zeros(N_STORY_STATE), np.zeros(N_STORY_STATE)
    out = []
    for d in history:
        _, dk, _ = bouc_wen_story_kernel(d, 0.0, 0.01, s0, s1, p)
        out.append((s1[SS_F], s1[SS_Z], s1[SS_W], s1[SS_E], s1[SS_EPS], p[0] + dk))
        s0[:] = s1
    return np.array(out)


def test_case_keys_fill_the_kernel_row_in_the_documented_order():
    row = Stories("bouc_wen", {"yield_force": FY, **PINCHED}).element_parameters(
        np.array([K]), np.array([3.0]), "A"
    )
    assert N_STORY_PARAMS == 16
    np.testing.assert_array_equal(row[0], _p(**PINCHED))
    defaults = Stories("bouc_wen", {"yield_force": FY}).element_parameters(
        np.array([K]), np.array([3.0]), "A"
    )
    np.testing.assert_array_equal(defaults[0, 10:], [0.0, 1.0, 0.0, 0.2, 0.0, 0.5])


@pytest.mark.parametrize("zeta_s", [0.9, 0.0], ids=["pinched", "unpinched"])
def test_pinched_degrading_cycles_of_growing_amplitude_follow_a_fine_step_integration(zeta_s):
    # six cycles 0 → a → −a → 0, a = 1..6 δ_y, in increments of 0.05 δ_y (the kernel takes its
    # own RK4 sub-steps within each); ε-rich: ζ1 = 0.9 (1 − e^(−ε)) is 0.9 after the first cycles
    params = {**PINCHED, "zeta_s": zeta_s}
    x = _cycles(range(1, 7), 0.05)
    rows = _drive(x * DY, _p(**params))
    zeta, eps = _reference_pinching(x, params)
    force = 0.05 * K * x * DY + 0.95 * FY * zeta
    assert eps[-1] > 20.0
    np.testing.assert_allclose(rows[:, 1], zeta, rtol=1e-6, atol=1e-6)
    np.testing.assert_allclose(rows[:, 4], eps, rtol=1e-6, atol=1e-6)
    np.testing.assert_allclose(rows[:, 0], force, rtol=1e-6, atol=1e-6 * FY)


def _reload_and_loops(zeta_s: float) -> tuple[float, float, float, np.ndarray]:
    """Three cycles to ±5 δ_y, then reloading to +5 δ_y, in 0.01 δ_y increments: the secant slope
    dF/dδ [k] across the zero-force crossing of the reloading from −5 δ_y, the kernel's tangent
    there [k], the drift there [δ_y], and the kernel rows at the end of the third cycle (δ = 0)."""
    x = np.concatenate((_cycles([5.0] * 3, 0.01), np.linspace(0.0, 5.0, 501)[1:]))
    end = 6000  # back at δ = 0 after the third cycle
    assert x[end] == 0.0 and x[end - 500] == -5.0
    rows = _drive(x * DY, _p(**{**PINCHED, "zeta_s": zeta_s}))
    f = rows[:, 0]
    j = end - 500 + np.flatnonzero((f[end - 500 : -1] < 0.0) & (f[end - 499 :] >= 0.0))[0]
    slope = (f[j + 1] - f[j]) / ((x[j + 1] - x[j]) * DY * K)
    return slope, rows[j + 1, 5] / K, x[j], rows[: end + 1]


def test_pinching_softens_the_reloading_at_zero_force_and_thins_the_loops():
    # strongly pinched (ζ_s = 0.9) against ζ_s = 0, same cycles: reloading from −5 δ_y crosses
    # F = 0 at x ≈ −1.86 with dF/dδ ≈ 0.127 k (pinched) against x ≈ −3.73 with ≈ 0.708 k;
    # three cycles dissipate ≈ 26.1 F_y δ_y against ≈ 39.3 F_y δ_y
    pinched, unpinched = _reload_and_loops(0.9), _reload_and_loops(0.0)
    for slope, tangent, _, _ in (pinched, unpinched):
        assert tangent == pytest.approx(slope, rel=0.01)  # the kernel's k_t is dF/dδ
    assert pinched[0] < 0.2 and unpinched[0] > 0.6
    assert pinched[0] < 0.25 * unpinched[0]
    assert pinched[2] > unpinched[2] + 1.0  # the force turns later, nearer δ = 0
    x = _cycles([5.0] * 3, 0.01)
    dissipated = []
    for *_, rows in (pinched, unpinched):
        f, w, e, eps = rows[:, 0], rows[-1, 2], rows[-1, 3], rows[-1, 4]
        # δ = 0 again: the trapezoid ∫F dδ is the loop area (the closing segment has dδ = 0),
        # and what the kernel counts as recoverable is what its hysteretic spring still holds
        area = np.trapezoid(f, x * DY)
        held = 0.5 * 0.95 * FY * DY * (f[-1] / (0.95 * FY)) ** 2
        assert w - e == pytest.approx(area - held, rel=1e-9)
        assert w - e == pytest.approx(eps * FY * DY - held, rel=1e-5)  # W = F_y δ_y ε at δ = 0
        dissipated.append((w - e) / (FY * DY))
    assert 20.0 < dissipated[0] < 0.75 * dissipated[1]


def test_zeta_s_zero_leaves_the_unpinched_model_unchanged_bit_for_bit():
    # ζ_s = 0 makes the other pinching keys inert (h = 1): the kernel along cycles and a pounding
    # pair give the very same numbers as the table without them (today's model, whose closed forms
    # and solve_ivp comparisons are tests/test_stories.py's)
    base = {"yield_drift": 0.003, "hardening": 0.05, "n": 1.5, "beta": 0.6, "gamma": 0.4,
            "delta_a": 0.01, "delta_nu": 0.02, "delta_eta": 0.02}  # fmt: skip
    other = {"zeta_s": 0.0, "p": 3.0, "q": 0.4, "psi": 0.05, "delta_psi": 0.2, "lambda": 0.1}
    stories = Stories("bouc_wen", base), Stories("bouc_wen", {**base, **other})
    k, h = np.array([K]), np.array([3.0])
    p0, p1 = (s.element_parameters(k, h, "A")[0] for s in stories)
    x = _cycles(range(1, 7), 0.037)
    np.testing.assert_array_equal(_drive(x * DY, p0), _drive(x * DY, p1))
    gm = sine_pulse(amplitude=0.5 * 9.80665, period=0.6, duration=2.0, dt=0.002)
    runs = []
    for s in stories:
        a = ShearBuilding.uniform("A", 3, period=0.4, mass=2.0e5, stories=s)
        b = ShearBuilding.uniform("B", 5, period=0.8, mass=2.0e5)
        system = assemble([a, b], [Contact("A", "B", gap=0.01, law="hertz", k=2e9)])
        runs.append(simulate(system, gm, dt=5e-4, output_dt=0.01))
    assert int(runs[0].impact_count.sum()) > 0 and float(runs[0].story_ductility.max()) > 2.0
    for name in ("displacement", "story_spring_force", "hysteretic_energy", "energy"):
        np.testing.assert_array_equal(runs[0][name].values, runs[1][name].values, err_msg=name)


#: The pounding example: 3 storeys, pinched and degrading, against a Hertz wall.
BUILDING = {"yield_drift": 0.003, "hardening": 0.05, "n": 1.5, "beta": 0.6, "gamma": 0.4,
            "delta_a": 0.01, "delta_nu": 0.02, "delta_eta": 0.02, "zeta_s": 0.8, "p": 1.0,
            "q": 0.1, "psi": 0.2, "delta_psi": 0.005, "lambda": 0.5}  # fmt: skip
GAP, WALL_K, DURATION = 0.02, 2.0e9, 3.0


def _wall_example():
    building = ShearBuilding.uniform(
        "A", 3, period=0.4, mass=2.0e5, stories=Stories("bouc_wen", BUILDING)
    )
    system = assemble(
        [building], [Contact("A", "wall", gap=GAP, law="hertz", k=WALL_K, floors=[3])]
    )
    gm = sine_pulse(amplitude=0.5 * 9.80665, period=0.6, duration=DURATION, dt=0.002)
    return building, system, gm


@functools.cache
def _reference_pinched_building() -> tuple[np.ndarray, np.ndarray]:
    """Independent solve_ivp of the wall example: states (u, v, ζ, ε) with ζ̇ = ẋ h [A − ν (β
    sgn(ẋ ζ) + γ)|ζ|^n]/η, ε̇ = (1 − α) ẋ ζ, ẋ = δ̇/δ_y; displacements and story forces every 0.01 s."""
    building, system, gm = _wall_example()
    n = building.n_floors
    m = building.masses
    c = system.damping
    k, fy = building.story_parameters()[:, 0], building.story_parameters()[:, 1]
    q = {"A": 1.0, **BUILDING}  # A at its default
    al, nn, be, ga, a0, d_a, d_nu, d_eta, zs, pp, qq, psi, d_psi, lam = (q[key] for key in KEYS)
    dy = fy / k
    t_rec = gm.dt * np.arange(gm.acceleration.size)

    def rhs(t, y):
        u, v, z, e = y[:n], y[n : 2 * n], y[2 * n : 3 * n], y[3 * n :]
        du = np.diff(np.concatenate(([0.0], u)))
        xdot = np.diff(np.concatenate(([0.0], v))) / dy
        a, nu, eta = a0 - d_a * e, 1.0 + d_nu * e, 1.0 + d_eta * e
        z1 = zs * (1.0 - np.exp(-pp * e))
        z2 = (psi + d_psi * e) * (lam + z1)
        zu = (a / (nu * (be + ga))) ** (1.0 / nn)
        h = 1.0 - z1 * np.exp(-(((z * np.sign(xdot) - qq * zu) / z2) ** 2))
        zdot = xdot * h * (a - nu * (be * np.sign(xdot * z) + ga) * np.abs(z) ** nn) / eta
        f = al * k * du + (1.0 - al) * fy * z
        internal = f - np.append(f[1:], 0.0)
        contact = np.zeros(n)
        if u[-1] > GAP:
            contact[-1] = WALL_K * (u[-1] - GAP) ** 1.5
        acc = (-internal - c @ v - contact) / m - np.interp(t, t_rec, gm.acceleration)
        return np.concatenate((v, acc, zdot, (1.0 - al) * xdot * z))

    t_eval = np.arange(0.0, DURATION + 1e-12, 0.01)
    sol = solve_ivp(rhs, (0.0, DURATION), np.zeros(4 * n), method="DOP853", t_eval=t_eval,
                    rtol=1e-10, atol=1e-13, max_step=1e-3)  # fmt: skip
    assert sol.success
    u, z = sol.y[:n].T, sol.y[2 * n : 3 * n].T
    du = np.diff(u, axis=1, prepend=0.0)
    return u, al * k * du + (1.0 - al) * fy * z


def test_pinched_degrading_building_pounding_on_a_wall_matches_an_independent_solve_ivp():
    _, system, gm = _wall_example()
    ds = simulate(system, gm, dt=2e-4, output_dt=0.01, duration=DURATION)
    u_ref, f_ref = _reference_pinched_building()
    u = ds.displacement.sel(building="A").values
    f = ds.story_spring_force.sel(building="A").values
    assert int(ds.impact_count.sum()) >= 1
    assert float(ds.story_ductility.max()) > 2.0
    assert float(ds.hysteretic_energy.sel(building="A").sum()) > 0.0
    assert np.abs(u - u_ref).max() < 0.01 * np.abs(u_ref).max()
    assert np.abs(f - f_ref).max() < 0.01 * np.abs(f_ref).max()
    np.testing.assert_allclose(np.abs(u).max(axis=0), np.abs(u_ref).max(axis=0), rtol=5e-3)
    assert ds.attrs["energy_balance_error"] < 5e-3


def test_ivp_path_integrates_the_pinched_building_like_the_independent_solve_ivp():
    _, system, gm = _wall_example()
    ds = simulate(system, gm, method="ivp", output_dt=0.01, duration=DURATION, rtol=1e-9)
    u_ref, f_ref = _reference_pinched_building()
    u = ds.displacement.sel(building="A").values
    f = ds.story_spring_force.sel(building="A").values
    assert int(ds.impact_count.sum()) >= 1
    assert np.abs(u - u_ref).max() < 1e-3 * np.abs(u_ref).max()
    assert np.abs(f - f_ref).max() < 1e-3 * np.abs(f_ref).max()
    np.testing.assert_allclose(np.abs(u).max(axis=0), np.abs(u_ref).max(axis=0), rtol=1e-3)
    assert ds.attrs["energy_balance_error"] < 1e-6


def _bwbn(history: np.ndarray, alpha, ko, n, gamma, beta, ao, q, zetas, p, shi, delta_shi, lamda):
    """Stress along a strain history of OpenSees' BWBN::setTrialStrain, committing every step: the
    root z₁ of its Newton residual f(z) = z − C_z − Φ(z) h(z, e(z)) Δε with e(z) = C_e + (1 − α)
    k₀ Δε z (backward Euler), here by bracketing instead of its Newton iteration."""
    cz = ce = cstrain = 0.0
    zu = (1.0 / (beta + gamma)) ** (1.0 / n)
    out = []
    for strain in history:
        ds = strain - cstrain
        sgn = 1.0 if ds > 0.0 else -1.0  # BWBN::signum(0) = −1

        def residual(tz, ds=ds, sgn=sgn, cz=cz, ce=ce):
            te = ce + (1.0 - alpha) * ko * ds * tz
            zeta1 = zetas * (1.0 - math.exp(-p * te))
            zeta2 = (shi + delta_shi * te) * (lamda + zeta1)
            h = 1.0 - zeta1 * math.exp(-((tz * sgn - q * zu) ** 2) / (zeta2 * zeta2))
            psi = gamma + beta * (1.0 if ds * tz > 0.0 else -1.0)
            return tz - cz - (ao - abs(tz) ** n * psi) * h * ds

        width = 2.0 * abs(ds) * (ao + 1.0)
        while residual(cz - width) > 0.0 or residual(cz + width) < 0.0:
            width *= 2.0
        tz = brentq(residual, cz - width, cz + width, xtol=1e-15 * DY, rtol=1e-14)
        ce += (1.0 - alpha) * ko * ds * tz
        cz, cstrain = tz, strain
        out.append(alpha * ko * strain + (1.0 - alpha) * ko * tz)
    return np.array(out)


def test_opensees_bwbn_with_the_mapped_parameters_gives_the_same_pinched_loops():
    # no ν/η/A degradation (BWBN has none), A = 1; cycles to ±2, ±4, ±5 δ_y
    params = {**PINCHED, "delta_a": 0.0, "delta_nu": 0.0, "delta_eta": 0.0, "p": 0.5}
    al, n, be, ga = params["hardening"], params["n"], params["beta"], params["gamma"]
    mapped = dict(alpha=al, ko=K, n=n, gamma=ga / DY**n, beta=be / DY**n, ao=1.0, q=params["q"],
                  zetas=params["zeta_s"], p=params["p"] / (FY * DY), shi=params["psi"] * DY,
                  delta_shi=params["delta_psi"] / FY, lamda=params["lambda"])  # fmt: skip
    coarse = _cycles([2.0, 4.0, 5.0], 0.004)
    ours = _drive(coarse * DY, _p(**params))[:, 0]
    errors = []
    for step in (0.004, 0.002):  # backward Euler: its error halves with the increment
        x = _cycles([2.0, 4.0, 5.0], step)
        bwbn = _bwbn(x * DY, **mapped)[:: round(0.004 / step)]
        errors.append(np.abs(bwbn - ours).max() / np.abs(ours).max())
    assert errors[1] < 1e-3
    assert errors[1] == pytest.approx(errors[0] / 2.0, rel=0.1)


@pytest.mark.parametrize(
    "key, value, message",
    [
        ("zeta_s", 1.5, r"stories\.zeta_s\[0\] = 1\.5"),
        ("psi", 0.0, r"stories\.psi\[0\] = 0"),
        ("lambda", -0.1, r"stories\.lambda\[0\] = -0\.1"),
        ("pinch", 0.5, r"stories\.pinch: not a parameter"),
    ],
)
def test_pinching_keys_out_of_range_or_unknown_are_refused_naming_the_key(key, value, message):
    stories = {"model": "bouc_wen", "yield_drift": 0.003, "zeta_s": 0.5, key: value}
    spec = {"name": "A", "n_floors": 2, "period": 0.3, "mass": 1e5, "stories": stories}
    with pytest.raises(CaseError, match="building") as err:
        case_from_dict({"building": [spec], "ground_motion": {"type": "sine_pulse"}})
    assert re.search(message, str(err.value)), str(err.value)
