"""The compiled Newmark/HHT loop against closed-form structural-dynamics and impact solutions."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from _laws import FILLED, layer, with_layer

from pounding.contact.calibrate import effective_restitution
from pounding.contact.laws import LAWS_BY_ID
from pounding.ground_motion import GroundMotion, harmonic, sine_pulse
from pounding.integrators import METHODS
from pounding.integrators.base import ConvergenceError
from pounding.integrators.newmark import HHT, get_scheme, integrate_newmark
from pounding.simulate import simulate
from pounding.stories import Stories
from pounding.structure import ModalDamping, ShearBuilding
from pounding.system import Contact, assemble
from pounding.units import G

ELCENTRO = (
    Path(__file__).resolve().parents[2]
    / "shared"
    / "data"
    / "ground_motions"
    / "elcentro_1940_ns_g_dt002.txt"
)

#: every Newmark-family method of the registry (the compiled loop)
NEWMARK_METHODS = [m for m in METHODS if m != "ivp"]


def _sdof(period: float, mass: float = 1.0e5, xi: float = 0.05, name: str = "A") -> ShearBuilding:
    return ShearBuilding.uniform(name, 1, period=period, mass=mass, damping=ModalDamping((xi,)))


@pytest.mark.parametrize("method", NEWMARK_METHODS)
def test_chopra_harmonic_steady_state_amplitude(method):
    # Chopra, Dynamics of Structures, §3.2: steady-state amplitude of u'' + 2ξωu' + ω²u = -A sin Ωt
    # is A / (ω² sqrt((1 - r²)² + (2ξr)²)), r = Ω/ω.
    T, xi, A, Tg = 0.5, 0.05, 1.0, 0.6
    system = assemble([_sdof(T, xi=xi)])
    gm = harmonic(amplitude=A, period=Tg, duration=25.0, dt=0.002)
    ds = simulate(system, gm, method=method, dt=T / 400, output_dt=0.002, alpha=-0.02)
    w, r = 2 * math.pi / T, T / Tg
    expected = A / (w**2 * math.sqrt((1 - r**2) ** 2 + (2 * xi * r) ** 2))
    u = ds["displacement"].sel(building="A", floor=1)
    steady = float(np.abs(u.sel(time=slice(20.0, 25.0))).max())
    tol = 3e-3 if method != "hht" else 1e-2  # HHT damps numerically; α = −0.02 is mild
    assert steady == pytest.approx(expected, rel=tol)


def test_free_vibration_after_pulse_matches_closed_form():
    # After the pulse (t > Tp) the SDOF is in damped free vibration (Chopra §2.2):
    # u(τ) = e^{-ξωτ} (u_p cos ω_D τ + (v_p + ξω u_p)/ω_D sin ω_D τ).
    T, xi, Tp = 0.4, 0.03, 0.3
    system = assemble([_sdof(T, xi=xi)])
    gm = sine_pulse(amplitude=2.0, period=Tp, duration=3.0, dt=0.001)
    ds = simulate(system, gm, dt=2.5e-4, output_dt=0.001)
    u = ds["displacement"].sel(building="A", floor=1)
    v = ds["velocity"].sel(building="A", floor=1)
    tp = 0.4  # a grid time after the pulse
    up, vp = float(u.sel(time=tp)), float(v.sel(time=tp))
    w = 2 * math.pi / T
    wd = w * math.sqrt(1 - xi**2)
    tau = ds["time"].values[ds["time"].values >= tp] - tp
    exact = np.exp(-xi * w * tau) * (
        up * np.cos(wd * tau) + (vp + xi * w * up) / wd * np.sin(wd * tau)
    )
    got = u.sel(time=slice(tp, None)).values
    assert np.max(np.abs(got - exact)) < 2e-3 * np.max(np.abs(exact))


def _wall_case(law: str, *, period: float = 2.0, xi: float = 0.0, gap: float = 0.01, **params):
    building = _sdof(period, xi=xi)
    contact = Contact("A", "wall", gap, law, floors=[1], **params)
    return assemble([building], [contact])


def test_linear_impact_of_undamped_sdof_on_wall_duration_closed_form():
    # During contact the SDOF (k_b) and the impact spring (k) act together about the shifted
    # equilibrium u_eq = k g/(k_b + k): u - u_eq = A sin(ωt + φ), ω = sqrt((k_b + k)/m).
    # Contact starts at u = g with speed v0 and ends when u = g again: t_c = (π − 2 atan(ω Δ / v0))/ω,
    # Δ = g − u_eq, with rebound speed v0 (elastic).
    k, gap, m = 2.0e8, 0.01, 1.0e5
    system = _wall_case("linear", gap=gap, k=k)
    gm = sine_pulse(amplitude=3.0, period=0.5, duration=1.5, dt=0.001)
    ds = simulate(system, gm, dt=1e-4, output_dt=0.001)
    imp = ds.pounding.impacts()
    first = imp.iloc[0]
    assert first["start"] > 0.5  # the pulse is over: free motion into the wall
    kb = float(system.stiffness[0, 0])
    w = math.sqrt((kb + k) / m)
    delta = gap - k * gap / (kb + k)
    tc = (math.pi - 2 * math.atan(w * delta / first["v0"])) / w
    assert first["end"] - first["start"] == pytest.approx(tc, rel=1e-3)
    assert first["rebound_ratio"] == pytest.approx(1.0, abs=2e-3)


def test_onset_time_located_inside_the_step():
    # Free vibration from the pulse's end state reaches the gap at a time found by a root solve of
    # the closed form; with dt = 2 ms the located onset must match to far better than dt.
    T, gap = 2.0, 0.01
    system = _wall_case("linear", period=T, gap=gap, k=2.0e8)
    gm = sine_pulse(amplitude=3.0, period=0.5, duration=1.5, dt=0.001)
    coarse = simulate(system, gm, dt=2e-3, output_dt=0.01, steps_per_contact=1)
    fine = simulate(system, gm, dt=2e-5, output_dt=0.01)
    t_fine = fine.pounding.impacts().iloc[0]["start"]
    t_coarse = coarse.pounding.impacts().iloc[0]["start"]
    assert abs(t_coarse - t_fine) < 2e-5  # without location the error is up to one step (2e-3 s)


@pytest.mark.parametrize("law", [law.name for law in LAWS_BY_ID])
def test_single_impact_matches_independent_free_impact(law):
    # A very flexible undamped SDOF (T = 20 s) hits a rigid wall after the pulse; its own spring is
    # ~1e-5 of the contact stiffness, so the impact is the free impact that calibrate.py integrates
    # independently with DOP853 at rtol 1e-11: duration, max penetration, peak force and e agree.
    if law in FILLED:
        pytest.skip("a filler touches both faces from the start: no free impact to compare with")
    params = {"k": 2.0e9 if law in ("linear", "kelvin", "kelvin_approach") else 2.75e9, "e": 0.6}
    if law in ("linear", "hertz"):
        params.pop("e")
    if law == "bilinear":
        params["delta_m"] = 0.004
    system = _wall_case(law, period=20.0, gap=0.05, **with_layer(law, params))
    # the ground kicks left, so the building moves right (relative) into the wall after the kick
    gm = GroundMotion(np.r_[0.0, -2.0, 0.0], 0.1, name="kick")
    ds = simulate(system, gm, dt=2e-5, output_dt=1e-3, duration=1.0)
    first = ds.pounding.impacts().iloc[0]
    ref = effective_restitution(law, mass=1.0e5, v0=first["v0"], **layer(law, 0.05), **params)
    # the impact log spans the overlap δ > 0, which outlasts the force of the clamped laws
    assert first["end"] - first["start"] == pytest.approx(ref.overlap_duration, rel=5e-3)
    assert first["max_penetration"] == pytest.approx(ref.max_penetration, rel=5e-3)
    assert first["peak_force"] == pytest.approx(ref.peak_force, rel=5e-3)
    assert first["rebound_ratio"] == pytest.approx(ref.e_effective, abs=5e-3)


def test_hht_with_alpha_zero_is_newmark():
    system = _wall_case("hunt_crossley", period=0.5, xi=0.05, k=2.75e9, e=0.7)
    gm = sine_pulse(amplitude=4.0, period=0.5, duration=2.0, dt=0.002)
    a = integrate_newmark(system, gm, dt=5e-4, output_every=4, n_steps=4000)
    b = integrate_newmark(system, gm, dt=5e-4, output_every=4, n_steps=4000, scheme=HHT(alpha=0.0))
    np.testing.assert_allclose(a.displacement, b.displacement, rtol=0, atol=1e-12)
    assert get_scheme("hht", alpha=-0.1).gamma == pytest.approx(0.6)


def test_hht_rejects_alpha_out_of_range():
    with pytest.raises(ValueError, match="alpha"):
        HHT(alpha=-0.5)
    with pytest.raises(ValueError, match="allowed"):
        get_scheme("leapfrog")


def test_newton_failure_raises_convergence_error_with_time():
    system = _wall_case("hertz", period=0.5, xi=0.05, gap=0.001, k=1e12)
    gm = sine_pulse(amplitude=5.0, period=0.5, duration=1.0, dt=0.01)
    with pytest.raises(ConvergenceError, match=r"t = ") as err:
        integrate_newmark(
            system, gm, dt=0.01, output_every=1, n_steps=100, max_iter=1, max_halvings=0,
            locate_onset=True, adaptive=True,
        )  # fmt: skip
    # the remedies name what is below its default, not what the run already uses
    msg = str(err.value)
    assert "max_halvings = 12" in msg and "max_iter = 25" in msg
    assert "locate_onset" not in msg and "adaptive" not in msg and "a smaller dt" in msg


def test_newton_failure_without_contacts_does_not_suggest_a_softer_contact():
    stories = Stories("bilinear", {"yield_drift": 1e-5, "hardening": 0.03})
    system = assemble([ShearBuilding.uniform("A", 3, period=0.05, mass=2e5, stories=stories)])
    gm = sine_pulse(amplitude=0.3 * 9.81, period=0.6, duration=1.0, dt=0.005)
    with pytest.raises(ConvergenceError, match="no contact") as err:
        integrate_newmark(system, gm, dt=0.005, output_every=1, n_steps=200, max_iter=1,
                          max_halvings=0)  # fmt: skip
    assert "a smaller dt" in str(err.value) and "contact k" not in str(err.value)


def test_energy_balance_closes_for_pounding_pair():
    a = ShearBuilding.uniform("A", 3, period=0.3, mass=3e5)
    b = ShearBuilding.uniform("B", 8, period=1.0, mass=3e5)
    system = assemble([a, b], [Contact("A", "B", 0.02, "kelvin", k=5e9, e=0.6)])
    gm = sine_pulse(amplitude=0.4 * 9.81, period=0.8, duration=6.0, dt=0.005)
    ds = simulate(system, gm)
    assert int(ds["impact_count"].sum()) > 0
    assert ds.attrs["energy_balance_error"] < 1e-2
    e = ds["energy"].isel(time=-1)
    assert float(e.sel(term="contact_dissipated")) > 0.0


def test_step_halving_recovers_and_matches_a_fine_run():
    # With only 2 Newton iterations allowed, large steps into a stiff Hertz contact fail and are
    # halved; the halved run must still match a fine-step reference.
    system = _wall_case("hertz", period=0.5, xi=0.05, gap=0.005, k=1e11)
    gm = sine_pulse(amplitude=4.0, period=0.5, duration=1.0, dt=0.005)
    coarse = integrate_newmark(system, gm, dt=2e-3, output_every=5, n_steps=500, max_iter=2)
    fine = integrate_newmark(system, gm, dt=1e-5, output_every=1000, n_steps=100_000)
    assert coarse.info["n_halvings"] > 0
    np.testing.assert_allclose(coarse.peak_displacement, fine.peak_displacement, rtol=5e-3)
    assert coarse.peak_contact_force[0] == pytest.approx(fine.peak_contact_force[0], rel=2e-2)


def test_record_not_starting_at_zero_gets_a_zero_prepended():
    gm = GroundMotion(np.full(200, 1.0), 0.01, name="step")
    ds = simulate(assemble([_sdof(0.5)]), gm, output_dt=0.01)
    assert float(ds["ground_acceleration"].isel(time=0)) == 0.0
    assert float(ds["ground_acceleration"].sel(time=0.01)) == pytest.approx(1.0)
    assert "prepended a zero sample" in ds.attrs["record_processing"]


def test_adaptive_refines_only_inside_impacts():
    # Event-aware stepping: base steps (the record's 0.1 s here) while the gap is open, t_c(v0)/40
    # inside the impact (steps_per_contact 40 here; the default 160 resolves restitution to 1e-4). The free-impact reference (independent DOP853; the T = 20 s building's own
    # spring is negligible) is met as with a fine fixed step, and the number of steps is set by the
    # impact, not by a global tiny dt.
    system = _wall_case("hertz", period=20.0, gap=0.05, k=2.75e9)
    gm = GroundMotion(np.r_[0.0, -2.0, 0.0], 0.1, name="kick")
    opts = dict(output_dt=0.1, duration=1.0, steps_per_period=20, steps_per_contact=40)
    ds = simulate(system, gm, **opts)
    fixed = simulate(system, gm, **opts, adaptive=False)
    first = ds.pounding.impacts().iloc[0]
    ref = effective_restitution("hertz", mass=1.0e5, v0=first["v0"], k=2.75e9)
    assert first["max_penetration"] == pytest.approx(ref.max_penetration, rel=5e-3)
    assert first["end"] - first["start"] == pytest.approx(ref.contact_duration, rel=5e-3)
    n_open = round(1.0 / ds.attrs["dt"])
    assert 40 <= ds.attrs["n_substeps"] - n_open <= 100
    # the fixed step resolves the same impact only because it is small everywhere
    assert fixed.attrs["n_substeps"] > 5 * ds.attrs["n_substeps"]
    assert float(fixed["peak_contact_force"][0]) == pytest.approx(
        float(ds["peak_contact_force"][0]), rel=2e-2
    )


def test_adaptive_false_keeps_one_step():
    system = _wall_case("linear", period=0.5, xi=0.05, gap=0.01, k=1e9)
    gm = sine_pulse(amplitude=3.0, period=0.5, duration=2.0, dt=0.005)
    ds = simulate(system, gm, dt=1e-3, output_dt=0.005, adaptive=False)
    # only the located closures split a step
    assert ds.attrs["n_substeps"] == 2000 + ds.attrs["n_located_onsets"]


@pytest.mark.parametrize("bw", [0, 1, 3])
def test_band_factors_solve_like_a_dense_solver(bw):
    from pounding.integrators._kernels import _band_matvec_add, band_ldl, band_solve, to_band

    rng = np.random.default_rng(bw)
    n = 12
    A = np.zeros((n, n))
    for i in range(n):
        for j in range(max(0, i - bw), min(n, i + bw + 1)):
            A[i, j] = A[j, i] = rng.normal()
    A += np.diag(np.abs(A).sum(axis=1) + 1.0)  # diagonally dominant: SPD
    r = rng.normal(size=n)
    L, D = band_ldl(to_band(A, bw), bw)
    x = np.zeros(n)
    band_solve(L, D, bw, r, x)
    np.testing.assert_allclose(x, np.linalg.solve(A, r), rtol=1e-12)
    y = np.zeros(n)
    _band_matvec_add(to_band(A, bw), bw, r, 2.0, y)
    np.testing.assert_allclose(y, 2.0 * A @ r, rtol=1e-13)


def test_band_blocks_are_the_uncoupled_diagonal_blocks():
    """Three blocks of 4, 5 and 3 rows in a band of half width 2 (buildings without a shared dof);
    one coupling entry across a boundary merges the two blocks it joins."""
    from pounding.integrators._kernels import band_blocks, to_band

    bw, sizes = 2, (4, 5, 3)
    n = sum(sizes)
    A = np.zeros((n, n))
    start = 0
    for m in sizes:
        for i in range(start, start + m):
            for j in range(max(start, i - bw), min(start + m, i + bw + 1)):
                A[i, j] = 1.0
        start += m
    blk = band_blocks(to_band(A, bw), bw)
    bounds = [(0, 4)] * 4 + [(4, 9)] * 5 + [(9, 12)] * 3
    assert [tuple(p) for p in blk.T] == bounds
    A[8, 10] = A[10, 8] = 0.5  # the second and third blocks now share a coupling
    blk = band_blocks(to_band(A, bw), bw)
    assert [tuple(p) for p in blk.T] == [(0, 4)] * 4 + [(4, 12)] * 8


@pytest.mark.parametrize(
    ("hs", "narrow"), [(2.0e-5, True), (0.5, False)], ids=["contact_substep", "long_step"]
)
def test_unit_column_of_an_80_story_building_stops_where_it_has_decayed(hs, narrow):
    """J⁻¹ e_k of a shear building's step tangent J = c0 M + c1 C + K against np.linalg.solve: at a
    contact's sub-step the entries fall ~1e-5 per floor and the solve stops a few floors from k
    (the dropped entries below 2⁻⁶⁴ of the largest); at a long step they decay slowly and it runs
    over the whole block. Two buildings in one band: the column stays in k's."""
    from pounding.integrators import _kernels as kn
    from pounding.integrators._linalg import DECAY, unit_column

    a_bld = ShearBuilding.uniform("A", 80, period=4.0, mass=1.0e6)
    b_bld = ShearBuilding.uniform("B", 30, period=1.5, mass=5.0e5)
    system = assemble([a_bld, b_bld], [Contact("A", "B", 0.05, "linear", k=1e9)])
    M, C, K = system.mass, system.damping, system.stiffness
    beta, gamma = 0.25, 0.5
    J = M / (beta * hs**2) + gamma / (beta * hs) * C + K
    bw = kn.bandwidth(M, C, K)
    assert bw == 1
    L, D = kn.band_ldl(kn.to_band(J, bw), bw)
    blk = kn.band_blocks(sum(np.abs(kn.to_band(m, bw)) for m in (M, C, K)), bw)
    n = system.n_dof
    for k in (0, 37, 79, 95):
        y = np.zeros(n)
        lo, hi = unit_column.py_func(L, D, bw, k, blk[0, k], blk[1, k], y)
        ref = np.linalg.solve(J, np.eye(n)[k])
        assert blk[0, k] <= lo <= k < hi <= blk[1, k]
        assert np.all(y[:lo] == 0.0) and np.all(y[hi:] == 0.0)
        big = abs(ref).max()
        dropped = np.concatenate([ref[:lo], ref[hi:]])
        assert dropped.size == 0 or abs(dropped).max() <= 4 * DECAY * big
        np.testing.assert_allclose(y[lo:hi], ref[lo:hi], rtol=1e-10, atol=1e-15 * big)
        if narrow:
            assert hi - lo <= 20  # of 80 floors
        else:
            assert (lo, hi) == (blk[0, k], blk[1, k])


def test_large_row_takes_the_band_path_and_agrees_with_ivp():
    # 2 × 15 floors: the open-gap steps use the band factors (O(n)), not the dense map
    from pounding.integrators import _kernels as kn

    a = ShearBuilding.uniform("A", 15, period=1.2, mass=3e5)
    b = ShearBuilding.uniform("B", 15, period=1.6, mass=3e5)
    system = assemble([a, b], [Contact("A", "B", 0.02, "hunt_crossley", k=2.75e9, e=0.6)])
    bw = kn.bandwidth(system.mass, system.damping, system.stiffness)
    assert bw == 1 and 3 * (2 * bw + 1) * system.n_dof < kn.DENSE_MAP_RATIO * system.n_dof**2
    gm = sine_pulse(amplitude=0.3 * 9.80665, period=1.0, duration=4.0, dt=0.01)
    nm = simulate(system, gm)
    ivp = simulate(system, gm, method="ivp", rtol=1e-9)
    assert int(nm["impact_count"].sum()) > 0
    assert float(abs(nm["peak_displacement"] / ivp["peak_displacement"] - 1).max()) < 5e-3
    f_nm, f_ivp = float(nm["peak_contact_force"].max()), float(ivp["peak_contact_force"].max())
    assert f_nm == pytest.approx(f_ivp, rel=2e-2)
    assert nm.attrs["energy_balance_error"] < 1e-2


def test_ivp_output_grid_is_the_requested_one():
    # the ivp path has no Newmark step: output_dt must not be raised to the Newmark default step
    system = assemble([_sdof(0.5)])
    gm = sine_pulse(amplitude=1.0, period=0.5, duration=1.0, dt=0.01)
    ds = simulate(system, gm, method="ivp", output_dt=1e-3)
    assert float(ds["time"][1] - ds["time"][0]) == pytest.approx(1e-3)


def test_output_dt_finer_than_the_default_step_is_honoured_two_sdof():
    # issue 12: output_dt = 0.001 gave a 0.01 s grid. examples/two_sdof.toml (T = 0.5 s and 1.0 s,
    # Hunt-Crossley impacts): the default step 0.5/160 s is shortened to 1 ms, the values follow ivp
    from pounding.case import load_case

    case = load_case(Path(__file__).resolve().parents[1] / "examples" / "two_sdof.toml")
    nm = simulate(case, output_dt=1e-3, duration=3.0)
    assert nm.attrs["output_dt"] == pytest.approx(1e-3) and nm.attrs["dt"] == pytest.approx(1e-3)
    np.testing.assert_allclose(np.diff(nm["time"].values), 1e-3, rtol=1e-9)
    assert int(nm["impact_count"].sum()) > 0
    ivp = simulate(case, method="ivp", rtol=1e-11, output_dt=1e-3, duration=3.0)
    assert ivp.sizes["time"] == nm.sizes["time"]
    u, ref = nm["displacement"].values, ivp["displacement"].values
    peak = np.nanmax(np.abs(ref), axis=(0, 2))
    assert np.all(np.nanmax(np.abs(u - ref), axis=(0, 2)) < 3e-3 * peak)


@pytest.fixture(scope="module")
def elcentro() -> GroundMotion:
    if not ELCENTRO.exists():
        pytest.skip("shared El Centro record (../shared/data/ground_motions) not available")
    data = np.loadtxt(ELCENTRO)
    return GroundMotion(data[:, 1] * G, 0.02, name="El Centro 1940 NS")


def test_default_steps_keep_pointwise_error_within_0p3_percent_of_peak_el_centro(elcentro):
    # issue 12: a one-story building has its fundamental period as its shortest, the worst case of
    # steps_per_period (2 % of the peak at the former 40 per period); first 15 s of El Centro NS
    system = assemble([_sdof(0.2, mass=3e5), _sdof(0.35, mass=3e5, name="B")])
    nm = simulate(system, elcentro, duration=15.0)
    ivp = simulate(system, elcentro, method="ivp", rtol=1e-11, duration=15.0)
    u, ref = nm["displacement"].values[:, :, 0], ivp["displacement"].values[:, :, 0]
    error = np.abs(u - ref).max(axis=0) / np.abs(ref).max(axis=0)
    assert np.all(error < 3e-3), error
    coarse = simulate(system, elcentro, duration=15.0, steps_per_period=40)
    assert (
        np.abs(coarse["displacement"].values[:, 0, 0] - ref[:, 0]).max()
        > 1e-2 * np.abs(ref[:, 0]).max()
    )


@pytest.mark.parametrize(
    "open_floors", [(), (1,), (0, 2)], ids=["all_closed", "2_open", "1_3_open"]
)
@pytest.mark.parametrize("law", ["linear", "hertz", "lankarani_nikravesh", "jankowski", "bilinear"])
@pytest.mark.parametrize("columns", ["precomputed", "solved_as_gaps_act", "open_gaps_held_open"])
def test_condensed_contact_step_satisfies_the_full_hht_step_equations(law, open_floors, columns):
    """The contact step condensed onto the gaps (Newton on the active gap openings, the open gaps
    back-substituted, then one update of u1) solves the full n-dof HHT step,
    M a1 + w(C v1 + K u1 + B f1) − α(C v + K u + B f0) = −M ι g_eff, written out here with the
    Newmark relations and the laws' Python kernels. Its condensation Z = J⁻¹ B, S = Bᵀ J⁻¹ B either
    given whole (small systems) or solved column by column from J's band factors as gaps act; the
    open gaps among the Newton rows or held open (their openings found after the iterations)."""
    from pounding.integrators import _kernels as kn

    a_bld = ShearBuilding.uniform("A", 3, period=0.3, mass=2.0e5)
    b_bld = ShearBuilding.uniform("B", 5, period=0.8, mass=2.0e5)
    params = {"k": 2.75e9 if law != "linear" else 2.0e9}
    if law in ("lankarani_nikravesh", "jankowski", "bilinear"):
        params["e"] = 0.65
    if law == "bilinear":
        params["delta_m"] = 0.002
    system = assemble([a_bld, b_bld], [Contact("A", "B", 0.01, law, **params)])
    el = system.elements
    n, n_el = system.n_dof, len(el)
    M, C, K, iota = system.mass, system.damping, system.stiffness, system.influence
    sch = get_scheme("hht", alpha=-0.1)
    gamma, beta, alpha = sch.gamma, sch.beta, sch.alpha
    hs, w = 2.0e-4, 1.0 + sch.alpha
    rng = np.random.default_rng(7)
    # a state inside the impacts: A's lower floors 1-2 mm into B, closing at 0.3-0.5 m/s
    u = np.zeros(n)
    v = np.zeros(n)
    u[:3] = 0.011 + rng.uniform(0.0, 1e-3, 3)
    v[:3] = 0.4 + rng.uniform(-0.1, 0.1, 3)
    for i in open_floors:  # 5 mm open, barely moving: no contact force within the step
        u[i], v[i] = 0.005, 0.01
    closed = np.ones(n_el, dtype=bool)
    closed[list(open_floors)] = False
    a = rng.normal(0.0, 2.0, n)
    d0 = el.el_sign[:, 0] * u[el.el_dof[:, 0]] + el.el_sign[:, 1] * u[el.el_dof[:, 1]] - el.el_gap
    dd0 = el.el_sign[:, 0] * v[el.el_dof[:, 0]] + el.el_sign[:, 1] * v[el.el_dof[:, 1]]
    kernels = [LAWS_BY_ID[i].kernel for i in el.el_law]
    v0 = np.maximum(dd0, 0.1)
    f0 = np.array(
        [kernels[c](d0[c], dd0[c], v0[c], 0.0, 0.0, el.el_params[c])[0] for c in range(n_el)]
    )
    assert np.all(f0[closed] > 0) and np.all(f0[~closed] == 0)
    ag, ag_dt, t = np.array([0.0, 2.0, -1.0, 0.5]), 0.01, 0.012
    g0 = np.interp(t, ag_dt * np.arange(4), ag)
    g1 = np.interp(t + hs, ag_dt * np.arange(4), ag)
    g_eff = w * g1 - alpha * g0
    Mi = M @ iota
    scheme = kn.Scheme(gamma, beta, alpha)
    cf = kn.newmark_coefficients(hs, scheme)
    Q, pg = kn.dense_map(hs, M, C, K, Mi, scheme)
    u1, v1, a1 = np.zeros(n), np.zeros(n), np.zeros(n)
    d1, dd1, f1, kd1, cd1 = (np.zeros(n_el) for _ in range(5))
    tr = kn.Trial(u1, v1, a1, d1, dd1, f1, kd1, cd1)
    kn.dense_step(Q, pg, g_eff, cf, (u, v, a), (u1, v1, a1))
    J = M / (beta * hs**2) + w * (gamma / (beta * hs) * C + K)
    Z, S = np.zeros((n_el, n)), np.zeros((n_el, n_el))
    have = np.zeros((n_el, 1 + 2 * el.el_dof.shape[1]), dtype=np.int64)
    if columns == "precomputed":
        kn.condense_map(np.linalg.inv(J), el.el_dof, el.el_sign, Z, S, have)
    bw = kn.bandwidth(M, C, K)
    L, D = kn.band_ldl(kn.to_band(J, bw), bw)
    blk = kn.band_blocks(sum(np.abs(kn.to_band(m, bw)) for m in (M, C, K)), bw)
    assert blk[0, 3] == 3 and blk[1, 0] == 3 and blk[1, 3] == n  # the two buildings' floors
    fac = kn.Factor(np.array([hs]), L, D, np.empty((0, 0)), Z, S, Q, pg, have, blk)
    gaps = kn.Gaps(el.el_dof, el.el_sign, el.el_gap, el.el_law, el.el_params, None, None, closed,
                   v0, d0, f0, None, None, None, f0)  # fmt: skip
    opts = kn.Options(1e-12, 25, 0, True, 0.0, 0.0, False, 20.0, hs)
    wk = kn.Work(None, None, np.zeros((4, n)), None, None, None, np.zeros((4, n_el)),
                 np.zeros(n_el, dtype=np.int64), np.zeros(n_el, dtype=np.int64), np.zeros(n_el),
                 np.zeros((n_el, n_el + 1)), None, None, None, None, None, None, np.zeros(n),
                 None, np.zeros(n_el, dtype=np.int64))  # fmt: skip
    off = ~closed if columns == "open_gaps_held_open" else np.zeros(n_el, dtype=bool)
    ok, its = kn.contact_step(fac, cf, u, gaps, off, opts, tr, wk)
    assert ok and 1 <= its <= 8
    # the columns solved are those of the gaps that acted, and equal J⁻¹ B's
    solved = have[:, 0] == 1
    assert np.array_equal(solved, np.ones(n_el, dtype=bool) if columns == "precomputed" else closed)
    B_el = np.zeros((n, n_el))
    for c in range(n_el):
        for s in range(2):
            if el.el_dof[c, s] >= 0:
                B_el[el.el_dof[c, s], c] = el.el_sign[c, s]
    Z_ref = np.linalg.solve(J, B_el)
    np.testing.assert_allclose(
        Z[solved].T, Z_ref[:, solved], rtol=1e-10, atol=1e-14 * abs(Z_ref).max()
    )
    np.testing.assert_allclose(S[solved].T, (B_el.T @ Z_ref)[:, solved], rtol=1e-10, atol=1e-16)
    # the full step equations, independently
    a_new = (u1 - u) / (beta * hs**2) - v / (beta * hs) - (0.5 / beta - 1.0) * a
    v_new = v + hs * ((1.0 - gamma) * a + gamma * a_new)
    np.testing.assert_allclose(a1, a_new, rtol=1e-8, atol=1e-6)
    np.testing.assert_allclose(v1, v_new, rtol=1e-8, atol=1e-9)
    d_new = (
        el.el_sign[:, 0] * u1[el.el_dof[:, 0]] + el.el_sign[:, 1] * u1[el.el_dof[:, 1]] - el.el_gap
    )
    dd_new = el.el_sign[:, 0] * v_new[el.el_dof[:, 0]] + el.el_sign[:, 1] * v_new[el.el_dof[:, 1]]
    f_new = np.array(
        [
            kernels[c](d_new[c], dd_new[c], v0[c], d0[c], f0[c], el.el_params[c])[0]
            for c in range(n_el)
        ]
    )
    assert np.all(d_new[~closed] < 0) and np.all(f1[~closed] == 0)  # the open gaps stayed open
    np.testing.assert_allclose(d1, d_new, rtol=0, atol=1e-13)
    np.testing.assert_allclose(f1, f_new, rtol=1e-7)
    B = B_el
    residual = M @ a_new + w * (C @ v_new + K @ u1 + B @ f_new) - alpha * (C @ v + K @ u + B @ f0)
    residual += Mi * g_eff
    assert np.abs(residual).max() <= 1e-8 * np.abs(B @ f_new).max()


@pytest.mark.parametrize(
    ("options", "expected"),
    [
        # 1 ms asked, 2 ms output: 1 ms steps (2 per output) over 0.5 s = 250 outputs
        ({"dt": 1e-3, "output_dt": 2e-3, "duration": 0.5}, (1e-3, 2e-3, 2, 250)),
        # 3 ms does not divide 10 ms: 4 steps of 2.5 ms; 0.501 s rounds up to 51 outputs
        ({"dt": 3e-3, "output_dt": 1e-2, "duration": 0.501}, (2.5e-3, 1e-2, 4, 51)),
        # output finer than the step (issue 12): the step is shortened to the output step
        ({"dt": 4e-3, "output_dt": 1e-3, "duration": 0.2}, (1e-3, 1e-3, 1, 200)),
        # no output step given: 5 ms, or the step when that is longer
        ({"dt": 1e-3, "duration": 0.2}, (1e-3, 5e-3, 5, 40)),
        ({"dt": 8e-3, "duration": 0.2}, (8e-3, 8e-3, 1, 25)),
    ],
)
def test_step_plan_fits_whole_steps_into_each_output_and_run_follows_it(options, expected):
    from pounding.simulate import AnalysisOptions, run, step_plan

    system = assemble([_sdof(0.5)])
    gm = sine_pulse(amplitude=2.0, period=0.4, duration=0.6, dt=1e-3)
    opts = AnalysisOptions(adaptive=False, **options)
    dt, output_dt, every, n_out = step_plan(system, gm.starting_from_rest(), opts)
    assert (every, n_out) == expected[2:]
    assert dt == pytest.approx(expected[0], rel=1e-12)
    assert output_dt == pytest.approx(expected[1], rel=1e-12)
    raw, info = run(system, gm, opts)
    assert info["dt"] == dt and info["duration"] == pytest.approx(n_out * output_dt)
    assert raw.displacement.shape[0] == n_out + 1


def test_every_method_of_the_registry_is_an_integrator_and_unknown_names_list_them():
    from pounding.integrators import INTEGRATORS, get_integrator
    from pounding.integrators.ivp import SolveIVP
    from pounding.simulate import METHODS as SIMULATE_METHODS

    assert set(METHODS) <= set(INTEGRATORS) and set(INTEGRATORS) == set(SIMULATE_METHODS)
    for name in METHODS:
        assert get_integrator(name).name in (name, "newmark")
    assert isinstance(get_integrator("ivp", rtol=1e-9), SolveIVP)
    assert get_integrator(HHT, alpha=-0.1).alpha == -0.1
    with pytest.raises(ValueError, match="analysis.method = 'leapfrog'; allowed: .*hht.*ivp"):
        get_integrator("leapfrog")
    with pytest.raises(ValueError, match="ivp_method = 'Euler'"):
        get_integrator("ivp", method="Euler")


@pytest.mark.parametrize("bw", [0, 1, 2, 3])
def test_the_energy_ledgers_band_forms_equal_the_dense_products(bw):
    # xᵀ A y from A's diagonals in partial sums (the damping work of every step, the kinetic and
    # strain energies of every output row) against numpy's dense product, for orders that leave
    # every remainder of the four-way sums, A not symmetric
    from pounding.integrators._linalg import _band_bilinear, _band_quadratic

    rng = np.random.default_rng(bw)
    for n in range(1, 12):
        A = rng.uniform(-1.0, 1.0, (n, n))
        A[np.abs(np.subtract.outer(np.arange(n), np.arange(n))) > bw] = 0.0
        AbT = np.zeros((2 * bw + 1, n))
        for k in range(2 * bw + 1):
            for i in range(n):
                if 0 <= i - bw + k < n:
                    AbT[k, i] = A[i, i - bw + k]
        x, y = rng.uniform(-1.0, 1.0, (2, n))
        assert _band_bilinear(AbT, bw, x, y) == pytest.approx(x @ A @ y, rel=1e-13, abs=1e-13)
        assert _band_quadratic(AbT, bw, x) == pytest.approx(x @ A @ x, rel=1e-13, abs=1e-13)


@pytest.mark.parametrize(
    ("law", "extra", "n"),
    [("linear", {}, 1.0), ("hertz", {}, 1.5),
     ("bilinear", {"e": 0.6, "delta_m": 0.005}, 1.0)],  # the loop's elastic slope K1
)  # fmt: skip
def test_contact_duration_coefficients_match_the_free_impact_closed_forms(law, extra, n):
    # undamped F = k δ^n between two masses: t_c = π √(m̄/k) for n = 1 (the bilinear loop: its
    # elastic slope K1, calibrated from k, e and delta_m); 2.94328 δ_max/v0 for Hertz,
    # δ_max = (5 m̄ v0²/(4 k))^(2/5) (Goldsmith 1960)
    from pounding.integrators.newmark import contact_duration_coefficients, stiffness_exponent
    from pounding.structure import ShearBuilding
    from pounding.system import Contact, assemble

    a, b = ShearBuilding("A", [2e5], [8e7]), ShearBuilding("B", [3e5], [4e7])
    system = assemble([a, b], [Contact("A", "B", 0.01, law, k=2e9, **extra)])
    m = float(system.elements.el_mass[0])
    assert m == pytest.approx(2e5 * 3e5 / 5e5, rel=1e-12)
    assert stiffness_exponent(system, 0) == n
    k = float(system.elements.el_params[0, 0])
    assert k == 2e9 or law == "bilinear"
    coef, expo = contact_duration_coefficients(system)
    for v0 in (0.1, 0.8, 2.0):
        d_max = ((n + 1.0) * m * v0**2 / (2.0 * k)) ** (1.0 / (n + 1.0))
        closed = math.pi * math.sqrt(m / k) if n == 1.0 else 2.94328 * d_max / v0
        assert coef[0] * v0 ** expo[0] == pytest.approx(closed, rel=1e-5)
