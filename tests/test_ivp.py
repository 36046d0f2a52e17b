"""Tests for the solve_ivp reference path against closed forms and independent integrations.

References: Chopra, A.K. (2017). Dynamics of Structures, 5th ed., Pearson (cited as Chopra);
Hunt, K.H., Crossley, F.R.E. (1975). J. Appl. Mech. 42(2), 440-445; Nigam, N.C., Jennings, P.C.
(1969). Bull. Seismol. Soc. Am. 59(2), 909-922; Uang, C.-M., Bertero, V.V. (1990). EESD 19(1), 77-90.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from pounding.contact.laws import alpha_hunt_crossley
from pounding.ground_motion import GroundMotion, harmonic, nigam_jennings_coefficients, sine_pulse
from pounding.integrators.base import ENERGY_TERMS, IMPACT_FIELDS, PATH_POINTS
from pounding.integrators.ivp import IVP_METHODS, integrate_ivp
from pounding.structure import ModalDamping, ShearBuilding
from pounding.system import Contact, assemble

MASS = 1.0e5  # [kg]


def _sdof(name: str, period: float, zeta: float, mass: float = MASS) -> ShearBuilding:
    k = mass * (2.0 * math.pi / period) ** 2
    return ShearBuilding(name, [mass], [k], damping=ModalDamping((zeta,)))


def _half_sine(amplitude: float, width: float, duration: float, dt: float) -> GroundMotion:
    """a_g = A sin(π t / width) on [0, width], then 0: a ground velocity step of 2 A width / π."""
    t = dt * np.arange(int(round(duration / dt)) + 1)
    acc = np.where(t <= width, amplitude * np.sin(np.pi * t / width), 0.0)
    return GroundMotion(acc, dt, name="half sine")


PULSE = 0.05  # [s] width of the half-sine pulse of the wall-impact tests


def _wall_impact(law: str, *, gap: float = 0.01, **params):
    """A flexible undamped SDOF (T = 8 s) thrown at a rigid wall on its right by a ground pulse.

    The pulse (a_g < 0 for 0.05 s) gives the mass about 0.32 m/s towards the wall and moves it about
    8 mm; it strikes after the pulse, when the ground is still, so only the building spring acts
    besides the contact.
    """
    building = _sdof("A", period=8.0, zeta=0.0)
    system = assemble([building], [Contact(left="A", right="wall", gap=gap, law=law, **params)])
    ground = _half_sine(-10.0, PULSE, 0.3, 0.005)
    return building, system, ground


# --------------------------------------------------------------------------------------------------
# Linear SDOF: closed forms
# --------------------------------------------------------------------------------------------------


def test_chopra_eq_2_2_4_damped_free_vibration_after_a_pulse():
    # Chopra Eq. 2.2.4: u(τ) = e^(−ζωτ) [u0 cos ωD τ + (u̇0 + ζω u0)/ωD sin ωD τ], from the state
    # just after a short sine pulse (the API starts at rest, so the pulse sets the initial state).
    period, zeta = 0.5, 0.05
    system = assemble([_sdof("A", period, zeta)])
    ground = sine_pulse(amplitude=3.0, period=0.1, duration=2.0, dt=0.005)
    times = np.round(np.arange(0.0, 2.0 + 1e-9, 0.01), 10)
    r = integrate_ivp(system, ground, output_times=times)
    i0 = int(np.searchsorted(times, 0.1))  # pulse over at t = 0.1 s
    u0, v0 = r.displacement[i0, 0], r.velocity[i0, 0]
    omega = 2.0 * math.pi / period
    omega_d = omega * math.sqrt(1.0 - zeta**2)
    tau = times[i0:] - times[i0]
    exact = np.exp(-zeta * omega * tau) * (
        u0 * np.cos(omega_d * tau) + (v0 + zeta * omega * u0) / omega_d * np.sin(omega_d * tau)
    )
    scale = np.abs(exact).max()
    assert scale > 1e-3
    np.testing.assert_allclose(r.displacement[i0:, 0], exact, atol=1e-6 * scale)
    assert r.impacts["start"].size == 0 and r.penetration.shape == (times.size, 0)


def test_chopra_eq_3_2_harmonic_ground_acceleration_from_rest():
    # Chopra Eqs. 3.2.1-3.2.3: u = e^(−ζωt)(A cos ωD t + B sin ωD t) + C sin Ωt + D cos Ωt for
    # p(t) = −m a0 sin Ωt from rest; C, D carry the dynamic amplification 1/√((1−r²)² + (2ζr)²).
    period, zeta, a0, t_force = 0.5, 0.05, 2.0, 0.6
    system = assemble([_sdof("A", period, zeta)])
    dt = 0.004
    ground = harmonic(amplitude=a0, period=t_force, duration=2.0, dt=dt)
    times = ground.time
    r = integrate_ivp(system, ground, output_times=times)

    omega, big_omega = 2.0 * math.pi / period, 2.0 * math.pi / t_force
    omega_d = omega * math.sqrt(1.0 - zeta**2)
    ratio = big_omega / omega
    ust = -a0 / omega**2  # p0/k
    den = (1.0 - ratio**2) ** 2 + (2.0 * zeta * ratio) ** 2
    c = ust * (1.0 - ratio**2) / den
    d = ust * (-2.0 * zeta * ratio) / den
    a = -d
    b = (zeta * omega * a - c * big_omega) / omega_d
    t = times
    exact = np.exp(-zeta * omega * t) * (a * np.cos(omega_d * t) + b * np.sin(omega_d * t)) + (
        c * np.sin(big_omega * t) + d * np.cos(big_omega * t)
    )
    scale = math.hypot(c, d)  # steady-state amplitude = |ust| × dynamic amplification
    assert scale == pytest.approx(abs(ust) / math.sqrt(den))
    # the record is the sine sampled every dt and linear between samples: O((Ω dt)²) difference
    np.testing.assert_allclose(r.displacement[:, 0], exact, atol=2e-3 * scale)

    # exact for the piecewise-linear record: the Nigam-Jennings recurrence (independent method)
    A, B, C, D, Ap, Bp, Cp, Dp = nigam_jennings_coefficients(omega, zeta, dt)
    x = np.zeros(times.size)
    v = np.zeros(times.size)
    acc = ground.acceleration
    for i in range(times.size - 1):
        x[i + 1] = A * x[i] + B * v[i] + C * acc[i] + D * acc[i + 1]
        v[i + 1] = Ap * x[i] + Bp * v[i] + Cp * acc[i] + Dp * acc[i + 1]
    np.testing.assert_allclose(r.displacement[:, 0], x, atol=2e-7 * scale)
    np.testing.assert_allclose(r.velocity[:, 0], v, atol=2e-7 * scale * omega)
    # relative acceleration from the equation of motion, absolute = relative + a_g
    expected_abs = -(omega**2) * x - 2.0 * zeta * omega * v
    np.testing.assert_allclose(
        r.acceleration[:, 0] + r.ground_acceleration, expected_abs, atol=1e-6 * scale * omega**2
    )
    assert r.peak_absolute_acceleration[0] >= np.abs(expected_abs).max() * (1 - 1e-6)
    assert r.peak_displacement[0] == pytest.approx(np.abs(x).max(), rel=1e-3)


# --------------------------------------------------------------------------------------------------
# Single impacts against a rigid wall
# --------------------------------------------------------------------------------------------------


def test_linear_impact_duration_pi_sqrt_m_over_k():
    # Linear spring impact (half period of the contact oscillator, Goldsmith 1960): t_c = π √(m/k). With the building spring k_b acting too,
    # the contact phase is the arc above u = g of an oscillation of frequency ω = √((k + k_b)/m)
    # centred at u* = k g/(k + k_b): t_c = (π − 2 asin(s/A))/ω, s = g − u*, A = √(s² + (v0/ω)²);
    # peak force k (A − s), rebound speed = v0 (undamped).
    k = 1.0e9
    building, system, ground = _wall_impact("linear", k=k)
    r = integrate_ivp(system, ground, output_times=np.linspace(0.0, 0.3, 61))
    imp = r.impacts
    assert imp["start"].size >= 1
    start, end, v0 = imp["start"][0], imp["end"][0], imp["v0"][0]
    assert start > PULSE  # after the pulse: the ground is still during the impact
    kb, g = float(building.stiffnesses[0]), 0.01
    omega = math.sqrt((k + kb) / MASS)
    s = g - k * g / (k + kb)
    amp = math.hypot(s, v0 / omega)
    t_exact = (math.pi - 2.0 * math.asin(s / amp)) / omega
    assert end - start == pytest.approx(t_exact, rel=1e-6)
    assert end - start == pytest.approx(math.pi * math.sqrt(MASS / k), rel=1e-2)
    assert imp["v_end"][0] == pytest.approx(-v0, rel=1e-6)
    assert imp["peak_force"][0] == pytest.approx(k * (amp - s), rel=1e-5)
    assert imp["max_penetration"][0] == pytest.approx(amp - s, rel=1e-5)
    # impulse = m Δv − ∫ k_b u dt over the contact (u = u* + (A cos) ... integrated exactly)
    spring = kb * (k * g / (k + kb) * t_exact + 2.0 * amp / omega)
    assert imp["impulse"][0] == pytest.approx(MASS * 2.0 * v0 - spring, rel=1e-6)


@pytest.mark.parametrize("e", [0.5, 0.8])
def test_hunt_crossley_1975_exact_restitution(e):
    # Hunt & Crossley (1975): with χ = u/v0, 1 − e u = (1 + u) exp(−(1 + e) u), a free mass rebounds
    # at exactly e v0. The building spring (T = 8 s) barely acts over the ~15 ms impact: it adds
    # about ω_b² g t_c / v0 to the ratio. The exact rebound of the sprung mass comes from an
    # independent solve of m ẍ = −k_b x − k δ^1.5 (1 + χ δ̇) over the contact phase.
    k = 1.0e11
    building, system, ground = _wall_impact("hunt_crossley", k=k, e=e)
    r = integrate_ivp(system, ground, output_times=np.linspace(0.0, 0.3, 61))
    imp = r.impacts
    start, end, v0, v_end = (imp[f][0] for f in ("start", "end", "v0", "v_end"))
    assert start > PULSE and v0 > 0.1
    kb, g = float(building.stiffnesses[0]), 0.01
    t_c = end - start
    bias = kb / MASS * (g + imp["max_penetration"][0]) * t_c / v0
    assert bias < 1e-3
    assert -v_end / v0 == pytest.approx(e, abs=1.5 * bias)

    chi = alpha_hunt_crossley(e) / v0

    def rhs(t, y):
        delta = max(y[0] - g, 0.0)
        force = k * delta**1.5 * (1.0 + chi * y[1])
        return [y[1], (-kb * y[0] - max(force, 0.0)) / MASS]

    def leave(t, y):
        return y[0] - g

    leave.terminal, leave.direction = True, -1.0
    ref = solve_ivp(
        rhs,
        (0.0, 1.0),
        [g + 1e-12 * v0, v0],
        method="DOP853",
        events=leave,
        rtol=1e-12,
        atol=1e-15,
        max_step=t_c / 200,
    )
    assert -v_end / v0 == pytest.approx(-ref.y_events[0][0][1] / v0, rel=1e-6)
    assert t_c == pytest.approx(ref.t_events[0][0], rel=1e-6)


def test_impact_still_open_at_the_end_has_nan_end():
    k = 1.0e9
    _, system, ground = _wall_impact("linear", k=k)
    full = integrate_ivp(system, ground, output_times=np.linspace(0.0, 0.3, 61))
    start = full.impacts["start"][0]
    t_stop = start + 0.5 * math.pi * math.sqrt(MASS / k)  # mid-impact
    r = integrate_ivp(system, ground, output_times=np.linspace(0.0, t_stop, 51))
    imp = r.impacts
    assert imp["start"].size == 1
    assert imp["start"][0] == pytest.approx(start, rel=1e-9)
    assert np.isnan(imp["end"][0]) and np.isnan(imp["v_end"][0])
    assert imp["impulse"][0] > 0.0 and imp["peak_force"][0] > 0.0
    assert r.contact_force[-1, 0] > 0.0


def test_zero_gap_contact_starts_at_rest():
    # Gap 0: the building touches the wall at t = 0 and is pushed into it by the pulse; the first
    # contact starts as soon as the penetration exceeds round-off (ten displacement tolerances,
    # within a fraction of a millisecond, δ ∝ t³ under a pulse starting from zero acceleration) at
    # an approach speed of essentially zero, and the run neither stalls nor misses it.
    building = _sdof("A", period=0.5, zeta=0.05)
    system = assemble([building], [Contact(left="A", right="wall", gap=0.0, law="linear", k=1e9)])
    ground = _half_sine(-5.0, 0.1, 0.5, 0.005)
    r = integrate_ivp(system, ground, output_times=np.linspace(0.0, 0.5, 101))
    assert 0.0 <= r.impacts["start"][0] < 1e-3 and 0.0 <= r.impacts["v0"][0] < 1e-5
    assert np.all(r.impacts["end"][:-1] > r.impacts["start"][:-1])
    e_in = r.energy[-1, 0]
    assert abs(e_in - r.energy[-1, 1:].sum()) < 1e-6 * e_in


# --------------------------------------------------------------------------------------------------
# Two buildings: energy balance, impact log, independent integration
# --------------------------------------------------------------------------------------------------

LAWS = {
    "linear": dict(k=2.0e8),
    "kelvin": dict(k=2.0e8, e=0.6),
    "hertz": dict(k=2.75e9),
    "hertz_kelvin": dict(k=2.75e9, e=0.6),
    "flores": dict(k=2.75e9, e=0.6),
    "jankowski": dict(k=2.75e9, e=0.6),
    "bilinear": dict(k=2.75e9, e=0.6, delta_m=0.002),
}
ELASTIC = {"linear", "hertz"}


def _two_buildings(law: str, gap: float = 0.004):
    a = ShearBuilding.uniform("A", 2, period=0.3, mass=2.0e5)
    b = ShearBuilding.uniform("B", 3, period=0.6, mass=2.0e5)
    contact = Contact(left="A", right="B", gap=gap, law=law, **LAWS[law])
    return assemble([a, b], [contact])


@pytest.fixture(scope="module")
def pulse():
    return sine_pulse(amplitude=4.0, period=0.5, duration=1.2, dt=0.005)


@pytest.mark.parametrize("law", sorted(LAWS))
def test_uang_bertero_energy_balance_closes(law, pulse):
    # Relative energy balance (Uang & Bertero 1990): E_in = E_K + E_S + E_D + E_c,dissipated +
    # E_c,stored at every instant; the contact work is split by each law's stored energy.
    system = _two_buildings(law)
    r = integrate_ivp(system, pulse, output_times=np.linspace(0.0, 1.2, 241))
    assert r.energy.shape == (241, len(ENERGY_TERMS))
    e_in = r.energy[:, 0]
    assert e_in[-1] > 0.0
    assert r.impacts["start"].size >= 2
    balance = e_in - r.energy[:, 1:].sum(axis=1)
    assert np.abs(balance).max() < 1e-4 * e_in[-1]
    stored = r.energy[:, ENERGY_TERMS.index("contact_stored")]
    dissipated = r.energy[:, ENERGY_TERMS.index("contact_dissipated")]
    assert stored.min() >= 0.0 and stored.max() > 0.0
    if law in ELASTIC:
        assert np.abs(dissipated).max() < 1e-6 * e_in[-1]
    else:
        assert dissipated[-1] > 1e-3 * e_in[-1]
        assert np.all(np.diff(dissipated) > -1e-7 * e_in[-1])  # never gives energy back
    assert r.info["integrator"] == "ivp" and r.info["n_events"] == 2 * r.impacts["start"].size


def test_impact_log_is_consistent_with_the_histories(pulse):
    system = _two_buildings("flores")  # two gap elements: floors 1-1 and 2-2
    times = np.round(np.arange(0.0, 1.2 + 1e-9, 2e-4), 10)
    r = integrate_ivp(system, pulse, output_times=times)
    imp = r.impacts
    assert set(imp) == {*IMPACT_FIELDS, "path_penetration", "path_force"}
    assert imp["path_force"].shape == (imp["start"].size, PATH_POINTS)
    # each impact's step path stays within its own peaks
    assert np.all(np.nanmax(imp["path_force"], axis=1) <= imp["peak_force"] * (1 + 1e-12))
    assert np.all(
        np.nanmax(imp["path_penetration"], axis=1) <= imp["max_penetration"] * (1 + 1e-12)
    )
    assert np.all(np.diff(imp["start"]) >= 0.0)  # sorted by start
    assert np.all(imp["start"] < imp["end"])
    assert np.all(imp["v0"] > 0.0) and np.all(imp["v_end"] < 0.0)
    for c in range(len(system.elements)):
        mine = imp["element"] == c
        assert mine.sum() >= 2
        assert np.all(imp["end"][mine][:-1] <= imp["start"][mine][1:])  # one impact at a time
        assert imp["peak_force"][mine].max() == r.peak_contact_force[c]
        assert imp["max_penetration"][mine].max() == r.peak_penetration[c]
        force = r.contact_force[:, c]
        in_any = np.zeros(times.size, dtype=bool)
        for i in np.flatnonzero(mine):
            inside = (times >= imp["start"][i]) & (times <= imp["end"][i])
            in_any |= inside
            assert inside.sum() > 20
            # full-resolution peak >= grid peak, and the fine grid is close to it
            assert imp["peak_force"][i] >= force[inside].max()
            assert force[inside].max() == pytest.approx(imp["peak_force"][i], rel=2e-3)
            assert r.penetration[inside, c].max() == pytest.approx(
                imp["max_penetration"][i], rel=2e-3
            )
            tt = np.concatenate(([imp["start"][i]], times[inside], [imp["end"][i]]))
            ff = np.concatenate(([0.0], force[inside], [0.0]))
            assert np.trapezoid(ff, tt) == pytest.approx(imp["impulse"][i], rel=1e-3)
        # outside its impacts an element is open: no force, no penetration
        assert np.all(force[~in_any] == 0.0)
        assert np.all(r.penetration[~in_any, c] <= 1e-12)
    # the penetration stored is the system's δ of the stored displacements
    d, _ = system.penetration(r.displacement, r.velocity)
    np.testing.assert_allclose(r.penetration, d, atol=1e-15)


def test_two_buildings_match_an_independent_integration(pulse):
    # Hertz law (no history variable): the same model integrated by a plain solve_ivp on a
    # hand-assembled right-hand side (top floor of A against the first floor of B... here the
    # common floors 1 and 2), no events, tight tolerances and a small max_step.
    system = _two_buildings("hertz")
    times = np.linspace(0.0, 1.2, 121)
    r = integrate_ivp(system, pulse, output_times=times)
    m, c, k = system.mass, system.damping, system.stiffness
    minv = np.linalg.inv(m)
    kh = LAWS["hertz"]["k"]
    # A's floors are dofs 0, 1; B's are 2, 3, 4; A is on the left: δ = u_A − u_B − g
    pairs = [(0, 2), (1, 3)]
    gap = 0.004

    def rhs(t, y):
        u, v = y[:5], y[5:]
        f = np.zeros(5)
        for a, b in pairs:
            delta = u[a] - u[b] - gap
            if delta > 0.0:
                force = kh * delta**1.5
                f[a] += force
                f[b] -= force
        acc = minv @ (-c @ v - k @ u - f) - pulse.at(t)
        return np.concatenate((v, acc))

    ref = solve_ivp(
        rhs,
        (0.0, 1.2),
        np.zeros(10),
        method="DOP853",
        dense_output=True,
        rtol=1e-11,
        atol=1e-14,
        max_step=2.5e-4,
    )
    y = ref.sol(times)
    scale = np.abs(y[:5]).max()
    np.testing.assert_allclose(r.displacement, y[:5].T, atol=2e-6 * scale)
    assert r.impacts["start"].size >= 2
    # peaks at full resolution against the reference sampled every 20 µs
    fine = ref.sol(np.linspace(0.0, 1.2, 60001))[:5]
    np.testing.assert_allclose(r.peak_displacement, np.abs(fine).max(axis=1), rtol=1e-5)
    below = np.vstack((np.zeros(fine.shape[1]), fine[0], np.zeros(fine.shape[1]), fine[2:4]))
    np.testing.assert_allclose(r.peak_drift, np.abs(fine - below).max(axis=1), rtol=1e-5)
    for c, (a, b) in enumerate(pairs):
        delta = np.maximum(fine[a] - fine[b] - gap, 0.0)
        assert r.peak_penetration[c] == pytest.approx(delta.max(), rel=1e-5)
        assert r.peak_contact_force[c] == pytest.approx(kh * delta.max() ** 1.5, rel=1e-5)


def test_muthukumar_bilinear_loop_dissipates_its_area():
    # Muthukumar (2003) / OpenSees ImpactMaterial loop: loading K1 to δ_y then K2, unloading K1 to
    # the line K2 δ then along it. Reaching δ_max >= δ_y, the loop is a parallelogram of area
    # (K1 − K2) δ_y (δ_max − δ_y): the energy one impact dissipates.
    _, system, ground = _wall_impact("bilinear", k=1.0e11, e=0.6, delta_m=2e-3)
    r = integrate_ivp(system, ground, output_times=np.linspace(0.0, 0.3, 61))
    k1, k2, dy = system.elements.el_params[0, :3]
    imp = r.impacts
    assert imp["start"].size == 1 and imp["max_penetration"][0] > dy
    area = (k1 - k2) * dy * (imp["max_penetration"][0] - dy)
    dissipated = r.energy[-1, ENERGY_TERMS.index("contact_dissipated")]
    assert dissipated == pytest.approx(area, rel=1e-5)
    assert r.energy[-1, ENERGY_TERMS.index("contact_stored")] == 0.0
    assert imp["peak_force"][0] == pytest.approx(k2 * imp["max_penetration"][0] + (k1 - k2) * dy)


def test_every_method_agrees_with_dop853():
    a = _sdof("A", period=0.3, zeta=0.05)
    b = _sdof("B", period=0.6, zeta=0.05)
    system = assemble(
        [a, b], [Contact(left="A", right="B", gap=0.005, law="flores", k=2.75e9, e=0.6)]
    )
    ground = sine_pulse(amplitude=4.0, period=0.4, duration=0.5, dt=0.01)
    times = np.linspace(0.0, 0.5, 51)
    ref = integrate_ivp(system, ground, output_times=times)
    assert ref.impacts["start"].size >= 1
    for method in IVP_METHODS:
        r = integrate_ivp(system, ground, output_times=times, method=method, rtol=1e-7)
        assert r.info["method"] == method
        np.testing.assert_allclose(r.peak_displacement, ref.peak_displacement, rtol=1e-4)
        np.testing.assert_allclose(r.peak_contact_force, ref.peak_contact_force, rtol=1e-3)
        assert r.impacts["start"].size == ref.impacts["start"].size


# --------------------------------------------------------------------------------------------------
# Options
# --------------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("options", "match"),
    [
        (dict(method="Euler"), "method = 'Euler'; allowed: RK45, DOP853, Radau, BDF, LSODA"),
        (dict(rtol=0.0), "rtol = 0.0"),
        (dict(rtol=-1e-6), "rtol"),
        (dict(atol=-1.0), "atol = -1.0"),
        (dict(max_step=0.0), "max_step = 0.0"),
        (dict(output_times=[0.0, 0.2, 0.1]), r"output_times\[2\] = 0.1"),
        (dict(output_times=[-0.1, 0.2]), "output_times starts at -0.1"),
        (dict(output_times=[[0.0, 0.1]]), "output_times has shape"),
    ],
)
def test_bad_options_raise_before_integrating(options, match):
    system = assemble([_sdof("A", 0.5, 0.05)])
    ground = sine_pulse(amplitude=1.0, period=0.2, duration=0.5, dt=0.01)
    kwargs = dict(output_times=np.linspace(0.0, 0.5, 11)) | options
    with pytest.raises(ValueError, match=match):
        integrate_ivp(system, ground, **kwargs)


def test_method_name_is_case_insensitive_and_info_reports_the_run():
    system = assemble([_sdof("A", 0.5, 0.05)])
    ground = sine_pulse(amplitude=1.0, period=0.2, duration=0.3, dt=0.01)
    r = integrate_ivp(system, ground, output_times=[0.0, 0.3], method="rk45", atol=1e-9)
    assert r.info["method"] == "RK45" and r.info["atol"] == 1e-9
    assert r.info["n_rhs"] > 0 and r.info["n_events"] == 0
    assert r.displacement.shape == (2, 1) and r.displacement[0, 0] == 0.0


# --- events inside one solver step (issue: the reference path stepped over a separation) ---


@pytest.mark.parametrize("law", ["hertz", "lankarani_nikravesh"])
def test_grazing_touch_inside_one_step_is_an_impact(law):
    # A building whose contact-free peak exceeds the gap to a wall by 1 µm touches it for about a
    # millisecond, less than one solver step at rtol 1e-8: no sign change of δ at any step end, and
    # the old event scheme logged no impact (and applied the force with a stale v0). The touch is so
    # light (tens of N against ~1e5 kg x 8 m/s²) that the motion is the contact-free one: the impact
    # must be logged once, with its max penetration the 1 µm excess and v0 from the free motion.
    building = _sdof("A", period=0.5, zeta=0.05)
    ground = sine_pulse(amplitude=0.3 * 9.80665, period=0.5).starting_from_rest()
    times = np.linspace(0.0, 3.0, 601)
    far = assemble([building], [Contact("A", "wall", gap=1.0, law="hertz", k=2.75e10)])
    free = integrate_ivp(far, ground, output_times=times, rtol=1e-12)
    excess = 1e-6
    gap = float(free.peak_displacement[0]) - excess
    system = assemble([building], [Contact("A", "wall", gap=gap, law=law, k=2.75e10, e=0.65)])
    r = integrate_ivp(system, ground, output_times=times)
    imp = r.impacts
    assert imp["start"].size == 1
    # (the free peak is known to ~5e-8 m: dense-output peaks are not refined)
    assert imp["max_penetration"][0] == pytest.approx(excess, rel=0.1)
    assert imp["end"][0] > imp["start"][0]
    # v0 of the free motion crossing the gap: |δ̇| = √(2 |ü| excess) near the peak, ü ≈ −ω² u_peak
    omega = 2.0 * math.pi / 0.5
    v_free = math.sqrt(2.0 * omega**2 * (gap + excess) * excess)
    assert imp["v0"][0] == pytest.approx(v_free, rel=0.1)


@pytest.mark.parametrize("law", ["hertz", "hunt_crossley", "jankowski"])
def test_identical_buildings_at_zero_gap_never_impact_ivp(law):
    # Two identical 10-storey buildings touching (gap 0) under the same ground motion move as one:
    # δ ≡ 0 up to round-off. The ivp path used to stop with "restarts made no progress at t = 0 s";
    # a contact that carries no force is no impact.
    a = ShearBuilding.uniform("A", 10, period=1.0, mass=3e5)
    b = ShearBuilding.uniform("B", 10, period=1.0, mass=3e5)
    system = assemble([a, b], [Contact("A", "B", gap=0.0, law=law, k=2.75e9, e=0.65)])
    ground = harmonic(amplitude=3.0, period=0.6, duration=4.0, dt=0.01).starting_from_rest()
    r = integrate_ivp(system, ground, output_times=np.linspace(0.0, 4.0, 401))
    assert r.impacts["start"].size == 0
    assert np.abs(r.contact_force).max() < 1e-3  # [N]
