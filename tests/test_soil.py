"""Flexible bases (sway-rocking foundations on soil): the footing springs and cone dashpots against
their closed forms, the assembled system against Veletsos & Meek's period and static flexibility,
the fixed-base limit, and a pounding run against an independent solve_ivp integration written in
other coordinates (foundation sway, rocking and story deformations, with a coupled mass matrix)."""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from pounding import PoundingInputError, simulate
from pounding.case import CaseError, case_from_dict
from pounding.ground_motion import sine_pulse
from pounding.soil import SoilFoundation, cone_dashpots, flexible_base_period, footing_stiffness
from pounding.stories import Stories
from pounding.structure import IsolationBase, ShearBuilding
from pounding.system import Contact, assemble
from pounding.units import G


def _ground(gm):
    """``gm.at`` for a scalar time: the same np.interp, without rebuilding the time axis per call
    (a reference's right-hand side asks for it some 10^5 times)."""
    t, a = gm.time, gm.acceleration
    return lambda s: np.interp(s, t, a, left=0.0, right=0.0)


def _soil(**kw) -> SoilFoundation:
    spec = dict(shear_wave_velocity=120.0, density=1800.0, poisson=0.35, width=14.0, length=14.0)
    spec.update(mass=4.0e5)
    spec.update(kw)
    return SoilFoundation(**spec)


def test_footing_springs_of_g80mpa_r6m_footing_match_veletsos_wei():
    # G = 80 MPa (ρ = 2000 kg/m³, V_s = 200 m/s), ν = 0.3, R = 6 m: K_x = 8GR/(2−ν) = 2.259e9 N/m,
    # K_θ = 8GR³/(3(1−ν)) = 6.583e10 N m/rad, worked by hand
    soil = SoilFoundation(
        shear_wave_velocity=200.0, density=2000.0, poisson=0.3, radius=6.0, mass=1e5
    )
    assert soil.shear_modulus == pytest.approx(8.0e7)
    k_x, k_t = soil.springs
    assert k_x == pytest.approx(2.259e9, rel=2e-4)
    assert k_t == pytest.approx(6.583e10, rel=2e-4)


@pytest.mark.parametrize("nu", [0.0, 0.25, 1.0 / 3.0, 0.45])
def test_wolf_cones_of_the_stated_aspect_ratios_give_the_footing_springs(nu):
    # Wolf (1994): a truncated cone of apex height z0 has static stiffness ρ c² A/z0
    # (translation, c = V_s, z0/R = π(2−ν)/8) and 3ρ c² I/z0 (rocking, z0/R = 9π(1−ν)(c/V_s)²/32):
    # the same springs as the half-space formulas, reached another way
    g, rho, r = 5.0e7, 1900.0, 4.0
    vs = math.sqrt(g / rho)
    vp = vs * math.sqrt(2 * (1 - nu) / (1 - 2 * nu))
    c = vp if nu <= 1 / 3 else 2 * vs
    area, inertia = math.pi * r**2, math.pi * r**4 / 4
    k_x = rho * vs**2 * area / (math.pi * (2 - nu) / 8 * r)
    k_t = 3 * rho * c**2 * inertia / (9 * math.pi * (1 - nu) * (c / vs) ** 2 / 32 * r)
    got = footing_stiffness(g, nu, r, r)
    assert got == pytest.approx((k_x, k_t), rel=1e-12)
    c_x, c_t, trapped = cone_dashpots(rho, vs, nu, r, r)
    # the cones' high-frequency dashpots ρ V_s A and ρ c I; trapped rocking mass above ν = 1/3
    assert (c_x, c_t) == pytest.approx((rho * vs * area, rho * c * inertia), rel=1e-12)
    expected = 0.3 * math.pi * (nu - 1 / 3) * rho * inertia * r if nu > 1 / 3 else 0.0
    assert trapped == pytest.approx(expected, abs=1e-9)


def test_rectangular_plan_uses_radii_of_equal_area_and_equal_moment_of_inertia():
    soil = _soil(width=10.0, length=24.0)
    assert math.pi * soil.radius_sway**2 == pytest.approx(240.0)
    assert math.pi * soil.radius_rocking**4 / 4 == pytest.approx(10.0 * 24.0**3 / 12)
    assert soil.inertia == pytest.approx(4.0e5 * 24.0**2 / 12)  # thin slab about its axis


def test_veletsos_meek_period_g80mpa_k4e8_h12m_is_1_4325_times_fixed_base():
    # single story k = 4e8 N/m at h = 12 m on the G = 80 MPa, R = 6 m footing: T̃/T = 1.4325;
    # the eigen-analysis of the assembled system, with a (nearly) massless foundation, must match
    m = 2.0e6
    soil = SoilFoundation(
        shear_wave_velocity=200.0, density=2000.0, poisson=0.3, radius=6.0, mass=1e-4 * m,
        inertia=1e-4 * m, dashpots=False,
    )  # fmt: skip
    b = ShearBuilding("S", [m], [4.0e8], heights=[12.0], soil=soil)
    system = assemble([b])
    t = float(b.modal().periods[0])
    t_flex = float(system.building_periods(0)[0])
    assert t_flex / t == pytest.approx(1.4325, abs=1e-4)
    assert t_flex == pytest.approx(flexible_base_period(t, 4.0e8, 12.0, *soil.springs), rel=1e-4)


def test_static_roof_load_deflects_by_sway_rocking_and_story_flexibilities():
    # P at the roof: u_roof = P/K_x + P H²/K_θ + Σ P/k_i (series flexibilities, statics)
    soil = _soil()
    b = ShearBuilding("A", [3e5] * 4, [2e8, 1.5e8, 1.2e8, 1e8], heights=[4.0, 3.0, 3.0, 3.0],
                      soil=soil)  # fmt: skip
    system = assemble([b])
    p = 1.0e6
    f = np.zeros(system.n_dof)
    f[system.dof(0, 4)] = p
    x = np.linalg.solve(system.stiffness, f)
    k_x, k_t = soil.springs
    expected = p / k_x + p * 13.0**2 / k_t + p * sum(1 / k for k in b.stiffnesses)
    assert x[system.dof(0, 4)] == pytest.approx(expected, rel=1e-10)
    assert x[system.soil_dof[0, 0]] == pytest.approx(p / k_x, rel=1e-10)
    assert x[system.soil_dof[0, 1]] == pytest.approx(p * 13.0 / k_t, rel=1e-10)
    # the drift is the story deformation: the story shear over k_i, without the rigid rotation
    drift = system.drift(x)
    floors = slice(system.dof(0, 1), system.dof(0, 4) + 1)
    np.testing.assert_allclose(drift[floors], p / b.stiffnesses, rtol=1e-9)


def test_p_delta_reduces_the_rocking_stiffness_by_the_gravity_moment():
    # rigid stories: a moment M on the foundation rocks it by M/(K_θ − Σ m_i g H_i)
    soil = _soil()
    b = ShearBuilding("A", [3e5] * 3, [1e14] * 3, heights=[3.0] * 3, soil=soil, p_delta=True)
    system = assemble([b])
    f = np.zeros(system.n_dof)
    f[system.soil_dof[0, 1]] = 1.0e7
    x = np.linalg.solve(system.stiffness, f)
    k_eff = soil.springs[1] - G * 3e5 * (3.0 + 6.0 + 9.0)
    assert x[system.soil_dof[0, 1]] == pytest.approx(1.0e7 / k_eff, rel=1e-6)


def _pair(soil: SoilFoundation | None):
    a = ShearBuilding.uniform("A", 3, period=0.4, mass=3.0e5, height=3.5, soil=soil)
    b = ShearBuilding.uniform("B", 4, period=0.6, mass=3.0e5, height=3.5)
    return assemble([a, b], [Contact("A", "B", gap=0.005, law="hertz", k=2.0e9)])


def test_stiff_soil_limit_equals_the_fixed_base_model():
    gm = sine_pulse(amplitude=0.4 * G, period=0.5, duration=3.0, dt=0.005)
    rock = _soil(shear_wave_velocity=3.0e4, density=2500.0, poisson=0.25)
    flexible = simulate(_pair(rock), gm, output_dt=0.01)
    fixed = simulate(_pair(None), gm, output_dt=0.01)
    assert int(fixed.impact_count.sum()) > 0
    for name in ("peak_displacement", "peak_drift_ratio", "peak_contact_force"):
        np.testing.assert_allclose(flexible[name], fixed[name], rtol=2e-3, err_msg=name)
    assert float(flexible.peak_foundation_rocking[0]) < 1e-6


def _reference(system_soil: SoilFoundation, gm, t_end: float):
    """Building A on soil and B fixed, hertz contact between common floors, integrated in the
    coordinates q = [u_0, θ, w_1..w_3 (A's story deformations), x_1..x_4 (B)] by DOP853."""
    a = ShearBuilding.uniform("A", 3, period=0.4, mass=3.0e5, height=3.5)
    b = ShearBuilding.uniform("B", 4, period=0.6, mass=3.0e5, height=3.5)
    soil = system_soil
    g_mod = soil.density * soil.shear_wave_velocity**2
    nu, area = soil.poisson, soil.width * soil.length
    r_x = math.sqrt(area / math.pi)
    i_f = soil.width * soil.length**3 / 12.0
    r_t = (4 * i_f / math.pi) ** 0.25
    k_x = 8 * g_mod * r_x / (2 - nu)
    k_t = 8 * g_mod * r_t**3 / (3 * (1 - nu))
    c_x = soil.density * soil.shear_wave_velocity * area
    c_t = soil.density * 2 * soil.shear_wave_velocity * i_f  # ν > 1/3: c = 2 V_s
    i_0 = soil.inertia + 0.3 * math.pi * (nu - 1 / 3) * soil.density * i_f * r_t
    n = 2 + 3 + 4
    heights = a.elevations
    # positions of A's floors relative to the ground: u_0 + H_i θ + w_i
    pos = np.zeros((3, n))
    pos[:, 0] = 1.0
    pos[:, 1] = heights
    pos[:, 2:5] = np.eye(3)
    mass = soil.mass * np.outer(np.eye(n)[0], np.eye(n)[0])
    mass[1, 1] += i_0
    mass += pos.T @ np.diag(a.masses) @ pos
    mass[5:, 5:] += np.diag(b.masses)
    stiff = np.zeros((n, n))
    damp = np.zeros((n, n))
    stiff[0, 0], stiff[1, 1], damp[0, 0], damp[1, 1] = k_x, k_t, c_x, c_t
    stiff[2:5, 2:5] = a.stiffness_matrix()
    damp[2:5, 2:5] = a.damping_matrix()
    stiff[5:, 5:] = b.stiffness_matrix()
    damp[5:, 5:] = b.damping_matrix()
    load = soil.mass * np.eye(n)[0] + pos.T @ a.masses
    load[5:] += b.masses
    k_c = 2.0e9
    minv = np.linalg.inv(mass)
    ground = _ground(gm)

    def contact(q):
        delta = pos @ q - q[5:8] - 0.005  # A's floors 1-3 against B's (q: a state or columns)
        f = k_c * np.maximum(delta, 0.0) ** 1.5
        gen = -pos.T @ f
        gen[5:8] += f
        return gen, f

    def rhs(t, y):
        q, v = y[:n], y[n:]
        gen, _ = contact(q)
        acc = minv @ (-stiff @ q - damp @ v + gen - load * ground(t))
        return np.concatenate((v, acc))

    sol = solve_ivp(rhs, (0.0, t_end), np.zeros(2 * n), method="DOP853", rtol=1e-10,
                    atol=1e-13, max_step=5e-4, dense_output=True)  # fmt: skip
    t = np.arange(0.0, t_end + 1e-9, 2.5e-4)
    q = sol.sol(t)[:n]
    x_a = pos @ q
    force = contact(q)[1]  # every sample at once
    return dict(
        sway=np.abs(q[0]).max(),
        rocking=np.abs(q[1]).max(),
        displacement_a=np.abs(x_a).max(axis=1),
        drift_a=np.abs(np.diff(np.vstack((np.zeros(t.size), q[2:5])), axis=0)).max(axis=1),
        displacement_b=np.abs(q[5:]).max(axis=1),
        force=force.max(axis=1),
    )


def _neighbour_pulse():
    return sine_pulse(amplitude=0.35 * G, period=0.5, duration=3.0, dt=0.005)


@functools.cache
def _neighbour_reference() -> dict:
    """_reference of the soft-soil pair on _neighbour_pulse, shared by both methods (only read)."""
    return _reference(_soil(), _neighbour_pulse(), 3.0)


@pytest.mark.parametrize("method", ["newmark", "ivp"])
def test_building_on_soft_soil_pounding_its_neighbour_matches_an_independent_ivp(method):
    gm = _neighbour_pulse()
    soil = _soil()
    ref = _neighbour_reference()
    ds = simulate(_pair(soil), gm, method=method, output_dt=0.005)
    assert ref["force"].max() > 1e5  # it pounds
    assert ref["rocking"] * 10.5 > 0.1 * ref["displacement_a"][-1]  # rocking matters
    tol = 1e-3  # measured: 8e-5 (Newmark, the peak force), 1.2e-5 (ivp)
    assert float(ds.peak_foundation_sway[0]) == pytest.approx(ref["sway"], rel=tol)
    assert float(ds.peak_foundation_rocking[0]) == pytest.approx(ref["rocking"], rel=tol)
    peak = ds.peak_displacement
    np.testing.assert_allclose(peak.sel(building="A")[:3], ref["displacement_a"], rtol=tol)
    np.testing.assert_allclose(peak.sel(building="B"), ref["displacement_b"], rtol=tol)
    drift = ds.peak_drift_ratio.sel(building="A")[:3] * 3.5
    np.testing.assert_allclose(drift, ref["drift_a"], rtol=tol)
    np.testing.assert_allclose(ds.peak_contact_force, ref["force"], rtol=tol)
    energy = ds.energy.isel(time=-1).to_series()
    out = energy.drop(["input"]).sum()
    assert abs(out - energy["input"]) < 5e-3 * energy["input"]


def test_soil_in_a_case_file_runs_and_reports_the_foundation():
    case = case_from_dict(
        {
            "building": [
                {"name": "A", "n_floors": 3, "period": 0.4, "mass": 3e5,
                 "soil": {"shear_wave_velocity": 150, "density": 1800, "poisson": 0.3,
                          "radius": 8, "mass": 4e5}},
                {"name": "B", "n_floors": 4, "period": 0.6, "mass": 3e5},
            ],
            "contact": [{"left": "A", "right": "B", "gap": 0.01, "law": "hertz", "k": 2e9}],
            "ground_motion": {"type": "sine_pulse", "amplitude": 3.0, "period": 0.5,
                              "duration": 2.0},
        }
    )  # fmt: skip
    b = case.buildings[0]
    assert b.soil is not None and b.soil.radius == 8.0
    ds = simulate(case.system, case.ground_motion)
    for name in ("foundation_sway", "foundation_rocking", "peak_foundation_sway",
                 "flexible_base_period", "soil_sway_stiffness", "soil_rocking_damping"):  # fmt: skip
        assert ds[name].attrs["units"] and ds[name].attrs["long_name"], name
    assert np.isnan(float(ds.peak_foundation_sway.sel(building="B")))
    assert float(ds.flexible_base_period[0]) > float(ds.natural_period[0, 0])


@pytest.mark.parametrize(
    ("soil", "message"),
    [
        ({"density": 1800, "poisson": 0.3, "radius": 8, "mass": 4e5}, "shear_wave_velocity"),
        ({"shear_wave_velocity": 150, "density": 1800, "poisson": 0.7, "radius": 8, "mass": 1},
         "soil.poisson = 0.7; allowed: a number >= 0 and <= 0.5"),
        ({"shear_wave_velocity": -1, "density": 1800, "poisson": 0.3, "radius": 8, "mass": 1},
         "shear_wave_velocity = -1"),
        ({"shear_wave_velocity": 150, "density": 1800, "poisson": 0.3, "mass": 1},
         "radius [m], or width and length"),
        ({"shear_wave_velocity": 150, "density": 1800, "poisson": 0.3, "mass": 1, "radius": 5,
          "width": 3}, "not both"),
        ({"shear_wave_velocity": 150, "density": 1800, "poisson": 0.3, "mass": 1, "radius": 5,
          "vs": 3}, "unknown key(s) vs"),
        ("soft", "must be a table"),
    ],
)  # fmt: skip
def test_bad_soil_tables_name_the_field_and_the_allowed_values(soil, message):
    spec = {
        "building": [{"name": "A", "n_floors": 3, "period": 0.4, "mass": 3e5, "soil": soil}],
        "ground_motion": {"type": "sine_pulse", "amplitude": 3.0, "period": 0.5},
    }
    with pytest.raises(CaseError, match="building") as info:
        case_from_dict(spec)
    assert message in str(info.value)


def test_soil_refuses_isolation_bearings():
    with pytest.raises(PoundingInputError, match="soil and base"):
        ShearBuilding.uniform("A", 2, period=0.3, mass=1e5, soil=_soil(),
                              base=IsolationBase(mass=1e5, mu_s=0.1, mu_d=0.08))  # fmt: skip


BW = {"yield_drift": 0.003, "hardening": 0.05, "n": 1.5, "beta": 0.6, "gamma": 0.4}


def _reference_bouc_wen_on_soil(b, soil, gm, duration, wall_k, gap):
    """Independent solve_ivp of a Bouc–Wen-story building on soil against a Hertz wall at its roof,
    in the coordinates [u_0, θ, w_1..w_n] (w: story deformations from the foundation up) with the
    coupled mass matrix; story force f_i = α k δ_i + (1 − α) F_y z_i, δ_i = w_i − w_(i−1),
    ż = δ̇/δ_y [1 − (β sgn(δ̇ z) + γ)|z|^n] (Bouc–Wen without degradation)."""
    n = b.n_floors
    p = b.story_parameters()
    k, fy, al, nn, be, ga = p[:, :6].T
    dy = fy / k
    g_mod = soil.density * soil.shear_wave_velocity**2
    nu, area = soil.poisson, soil.width * soil.length
    i_f = soil.width * soil.length**3 / 12.0
    r_x, r_t = math.sqrt(area / math.pi), (4 * i_f / math.pi) ** 0.25
    k_x, k_t = 8 * g_mod * r_x / (2 - nu), 8 * g_mod * r_t**3 / (3 * (1 - nu))
    c_x = soil.density * soil.shear_wave_velocity * area
    c_t = soil.density * 2 * soil.shear_wave_velocity * i_f
    i_0 = soil.inertia + 0.3 * math.pi * (nu - 1 / 3) * soil.density * i_f * r_t
    size = n + 2
    pos = np.zeros((n, size))
    pos[:, 0], pos[:, 1], pos[:, 2:] = 1.0, b.elevations, np.eye(n)
    mass = pos.T @ np.diag(b.masses) @ pos
    mass[0, 0] += soil.mass
    mass[1, 1] += i_0
    damp = np.zeros((size, size))
    damp[2:, 2:] = b.damping_matrix()
    damp[0, 0], damp[1, 1] = c_x, c_t
    load = pos.T @ b.masses
    load[0] += soil.mass
    minv = np.linalg.inv(mass)
    ground = _ground(gm)

    def rhs(t, y):
        q, v, z = y[:size], y[size : 2 * size], y[2 * size :]
        w, dw = q[2:], v[2:]
        drift = np.diff(np.concatenate(([0.0], w)))
        rate = np.diff(np.concatenate(([0.0], dw)))
        zdot = rate / dy * (1 - (be * np.sign(rate * z) + ga) * np.abs(z) ** nn)
        f = al * k * drift + (1 - al) * fy * z
        gen = np.zeros(size)
        gen[2:] = -(f - np.append(f[1:], 0.0))
        gen[0] -= k_x * q[0]
        gen[1] -= k_t * q[1]
        pen = pos[-1] @ q - gap
        if pen > 0.0:
            gen -= pos[-1] * wall_k * pen**1.5
        acc = minv @ (gen - damp @ v - load * ground(t))
        return np.concatenate((v, acc, zdot))

    t_eval = np.arange(0.0, duration + 1e-12, 0.01)
    sol = solve_ivp(rhs, (0.0, duration), np.zeros(2 * size + n), method="DOP853", t_eval=t_eval,
                    rtol=1e-10, atol=1e-13, max_step=1e-3)  # fmt: skip
    assert sol.success
    q, z = sol.y[:size], sol.y[2 * size :]
    drift = np.diff(np.vstack((np.zeros(q.shape[1]), q[2:])), axis=0)
    force = al[:, None] * k[:, None] * drift + ((1 - al) * fy)[:, None] * z
    return (pos @ q).T, force.T, np.abs(q[1]).max()


def _wall_pulse():
    return sine_pulse(amplitude=0.5 * G, period=0.6, duration=3.0, dt=0.002)


@functools.cache
def _bouc_wen_wall_reference(gap: float, wall_k: float) -> tuple:
    """_reference_bouc_wen_on_soil of the Bouc–Wen building on _wall_pulse, shared by both methods
    (only read)."""
    b = ShearBuilding.uniform("A", 3, period=0.4, mass=2.0e5, stories=Stories("bouc_wen", BW))
    return _reference_bouc_wen_on_soil(b, _soil(), _wall_pulse(), 3.0, wall_k, gap)


@pytest.mark.parametrize("method", ["newmark", "ivp"])
def test_bouc_wen_building_on_soft_soil_pounding_a_wall_matches_an_independent_ivp(method):
    soil = _soil()
    gap, wall_k = 0.03, 2.0e9
    system = assemble([ShearBuilding.uniform("A", 3, period=0.4, mass=2.0e5, soil=soil,
                                             stories=Stories("bouc_wen", BW))],
                      [Contact("A", "wall", gap=gap, law="hertz", k=wall_k, floors=[3])])  # fmt: skip
    gm = _wall_pulse()
    opts = dict(dt=2e-4) if method == "newmark" else dict(method="ivp", rtol=1e-9)
    ds = simulate(system, gm, output_dt=0.01, duration=3.0, **opts)
    u_ref, f_ref, rocking = _bouc_wen_wall_reference(gap, wall_k)
    u = ds.displacement.sel(building="A").values
    f = ds.story_spring_force.sel(building="A").values
    assert int(ds.impact_count.sum()) >= 1
    assert float(ds.story_ductility.max()) > 2.0
    # the reference's peak is over its 0.01 s samples, ours over every step: 9e-4 apart
    assert float(ds.peak_foundation_rocking[0]) == pytest.approx(rocking, rel=5e-3)
    # measured: 1.8e-5 (Newmark, dt = 0.2 ms), 3e-7 (ivp) of the peaks
    assert np.abs(u - u_ref).max() < 1e-3 * np.abs(u_ref).max()
    assert np.abs(f - f_ref).max() < 1e-3 * np.abs(f_ref).max()
    np.testing.assert_allclose(np.abs(u).max(axis=0), np.abs(u_ref).max(axis=0), rtol=5e-3)
    assert ds.attrs["energy_balance_error"] < 5e-3


@pytest.mark.parametrize("model", ["bilinear", "takeda", "imk"])
def test_piecewise_linear_stories_on_soil_agree_between_newmark_and_ivp(model):
    stories = Stories(model, {"yield_drift": 0.002, "hardening": 0.03})
    a = ShearBuilding.uniform("A", 3, period=0.35, mass=2.0e5, stories=stories, soil=_soil())
    b = ShearBuilding.uniform("B", 5, period=0.8, mass=2.5e5)
    system = assemble([a, b], [Contact("A", "B", gap=0.01, law="hertz", k=2e9)])
    gm = sine_pulse(amplitude=0.5 * G, period=0.6, duration=3.0, dt=0.002)
    newmark = simulate(system, gm, dt=2e-4, output_dt=0.01)
    ivp = simulate(system, gm, method="ivp", output_dt=0.01, rtol=1e-9)
    assert float(newmark.story_ductility.max()) > 1.5 and int(newmark.impact_count.sum()) > 0
    for name in ("displacement", "story_spring_force", "foundation_rocking"):
        x, y = ivp[name].values, newmark[name].values
        assert np.nanmax(np.abs(x - y)) < 0.01 * np.nanmax(np.abs(y)), name
    assert newmark.attrs["energy_balance_error"] < 5e-3


def test_soft_soil_example_report_has_the_soil_section_with_its_periods():
    from pathlib import Path

    from pounding.case import load_case
    from pounding.report import build_report, render_html

    case = load_case(Path(__file__).resolve().parents[1] / "examples" / "soft_soil.toml")
    ds = simulate(case, duration=3.0)
    report = build_report(ds)
    titles = [s.title for s in report.sections]
    section = report.sections[titles.index("Soil flexibility")]
    table, plot = section.blocks
    (row,) = table.rows
    assert row[0] == "B" and float(row[1]) == pytest.approx(1.0, abs=1e-3)
    assert float(row[2]) == pytest.approx(float(ds.flexible_base_period.sel(building="B")), 1e-3)
    assert float(row[2]) > 1.05  # the soft clay lengthens the period
    assert "Soil flexibility" in render_html(report)


def test_a_study_sweeps_the_soils_shear_wave_velocity(tmp_path):
    from pounding.studies import run_study
    from pounding.studies.spec import study_from_dict

    spec = {
        "building": [
            {"name": "A", "n_floors": 3, "period": 0.4, "mass": 3e5},
            {"name": "B", "n_floors": 4, "period": 0.6, "mass": 3e5,
             "soil": {"shear_wave_velocity": 100.0, "density": 1800, "poisson": 0.3,
                      "radius": 8, "mass": 4e5}},
        ],
        "contact": [{"left": "A", "right": "B", "gap": 0.01, "law": "hertz", "k": 2e9}],
        "ground_motion": {"type": "sine_pulse", "amplitude": 3.0, "period": 0.5,
                          "duration": 2.0},
        "study": {"building.1.soil.shear_wave_velocity": [100.0, 400.0]},
    }  # fmt: skip
    ds = run_study(study_from_dict(spec), tmp_path / "s.nc", jobs=1)
    axis = "building.1.soil.shear_wave_velocity"
    assert list(ds[axis].values) == [100.0, 400.0]
    peak = ds["peak_displacement"].sel(building="B").max("floor")
    assert float(peak.sel({axis: 100.0}).max()) > float(peak.sel({axis: 400.0}).max())
    rocking = ds["peak_foundation_rocking"]
    assert rocking.attrs["units"] == "rad"
    assert np.isnan(rocking.sel(building="A")).all()
    assert float(rocking.sel(building="B", **{axis: 100.0}).max()) > float(
        rocking.sel(building="B", **{axis: 400.0}).max()
    )
