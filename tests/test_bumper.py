"""The rubber bumper (Polycarpou, Komodromos & Polycarpou 2013) and the viscoelastic filler:
kernels against the formula, free impacts against the energy closed form and runs against
independent solve_ivp integrations (Newmark and ivp), the gap they take up, a study with and without
the bumper, and their errors."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from pounding import GroundMotion, ShearBuilding, assemble
from pounding.case import CaseError, case_from_dict
from pounding.contact.calibrate import contact_parameters
from pounding.contact.laws import contact_force, get_contact_law
from pounding.errors import PoundingInputError
from pounding.simulate import simulate
from pounding.structure import ModalDamping
from pounding.system import Contact

MASS = 2.0e5  # kg
K_C = 2.0e9  # N/m^1.5, the crushed (concrete) contact
K_R = 5.0e7  # N/m^1.5, the rubber
THICK = 0.02  # m
CRUSH = 0.8
KICK = 0.05  # s, the ground pulse that throws the mass


def _bumper(e: float = 0.65, e_rubber: float = 0.8, gap: float = 0.03, **extra) -> Contact:
    return Contact("m", "wall", gap, law="bumper", floors="all", k=K_C, e=e, thickness=THICK,
                   k_rubber=K_R, e_rubber=e_rubber, crush=CRUSH, **extra)  # fmt: skip


def _force(d: float, dd: float, v0: float, e: float, e_rubber: float) -> float:
    """The bumper force written out: two Hunt-Crossley terms, χ = 3(1 − e²)/(4 v0) each."""
    if d <= 0.0:
        return 0.0
    chi_r = 0.75 * (1.0 - e_rubber**2) / v0
    f = K_R * d**1.5 * max(1.0 + chi_r * dd, 0.0)
    if d > CRUSH * THICK:
        chi_c = 0.75 * (1.0 - e**2) / v0
        f += K_C * (d - CRUSH * THICK) ** 1.5 * max(1.0 + chi_c * dd, 0.0)
    return f


def test_bumper_kernel_is_the_two_term_law_with_exact_tangents():
    p = contact_parameters("bumper", k=K_C, e=0.65, mass=MASS, bumper=(THICK, K_R, 0.8, CRUSH))
    for d, dd in ((0.005, 0.7), (0.012, -0.3), (0.019, 0.4), (0.025, -0.2), (-0.001, 1.0)):
        f, kd, kv = (float(x) for x in contact_force("bumper", d, dd, p, v0=1.2))
        assert f == pytest.approx(_force(d, dd, 1.2, 0.65, 0.8), rel=1e-12, abs=1e-9)
        h = 1e-7
        fd = (_force(d + h, dd, 1.2, 0.65, 0.8) - _force(d - h, dd, 1.2, 0.65, 0.8)) / (2 * h)
        fv = (_force(d, dd + h, 1.2, 0.65, 0.8) - _force(d, dd - h, 1.2, 0.65, 0.8)) / (2 * h)
        assert kd == pytest.approx(fd, rel=1e-5, abs=1e-3)
        assert kv == pytest.approx(fv, rel=1e-5, abs=1e-3)


def _free_impact(contact: Contact, v0: float, method: str):
    """A nearly free mass (T = 2000 s) thrown at the wall at v0 by a half-sine ground pulse."""
    k_b = MASS * (2.0 * math.pi / 2000.0) ** 2
    building = ShearBuilding("m", [MASS], [k_b], damping=ModalDamping((0.0,)))
    gap = THICK + v0 * KICK  # the pulse ends before the mass reaches the bumper
    system = assemble([building], [dataclasses.replace(contact, gap=gap)])
    amplitude = v0 * math.pi / (2.0 * KICK)
    t = np.arange(0.0, KICK + 1e-12, KICK / 20)
    ground = GroundMotion(-amplitude * np.sin(np.pi * t / KICK), KICK / 20)
    duration = KICK + (gap - THICK) / v0 + 2.0  # a slow impact on the rubber lasts ~0.6 s
    return simulate(system, ground, method=method, duration=duration, dt=2e-4)


@pytest.mark.parametrize("v0", [0.05, 1.5])
def test_undamped_bumper_impact_reaches_the_energy_closed_form(v0):
    """½ m v0² = k_r δ^2.5/2.5 + k ⟨δ − d_thr⟩^2.5/2.5 at the largest compression; rebound at v0.
    At 0.05 m/s the rubber alone stops the mass, at 1.5 m/s it is crushed."""
    contact = _bumper(e=1.0, e_rubber=1.0)
    ds = _free_impact(contact, v0, "newmark")
    energy = 0.5 * MASS * v0**2

    def stored(d: float) -> float:
        return (K_R * d**2.5 + K_C * max(d - CRUSH * THICK, 0.0) ** 2.5) / 2.5 - energy

    d_max = brentq(stored, 0.0, 1.0, xtol=1e-15)
    assert (d_max > CRUSH * THICK) == (v0 > 1.0)  # 640 J crush the rubber
    assert float(ds["peak_penetration"].max()) == pytest.approx(d_max, rel=2e-3)
    v_in, v_out = float(ds["impact_v0"][0]), float(ds["impact_v_end"][0])
    assert v_in == pytest.approx(v0, rel=1e-2) and -v_out / v_in == pytest.approx(1.0, abs=2e-3)


def _reference(v0: float, e: float, e_rubber: float) -> tuple[float, float]:
    """(peak force, rebound speed) of the free impact by solve_ivp at rtol 1e-11."""

    def rhs(t, y):
        return [y[1], -_force(y[0], y[1], v0, e, e_rubber) / MASS]

    def leaves(t, y):
        return y[0]

    leaves.terminal, leaves.direction = True, -1
    sol = solve_ivp(rhs, (0.0, 1.0), [0.0, v0], method="DOP853", rtol=1e-11, atol=1e-14,
                    events=leaves, dense_output=True, max_step=1e-4)  # fmt: skip
    t = np.linspace(0.0, sol.t[-1], 20001)
    y = sol.sol(t)
    peak = max(_force(d, dd, v0, e, e_rubber) for d, dd in zip(y[0], y[1], strict=True))
    return peak, -float(sol.y_events[0][0][1])


@pytest.mark.parametrize("method", ["newmark", "ivp"])
def test_damped_bumper_impact_matches_an_independent_solve_ivp(method):
    v0 = 1.5
    ds = _free_impact(_bumper(), v0, method)
    v_in = float(ds["impact_v0"][0])
    peak, v_out = _reference(v_in, 0.65, 0.8)
    assert float(ds["peak_contact_force"].max()) == pytest.approx(peak, rel=5e-3)
    assert -float(ds["impact_v_end"][0]) == pytest.approx(v_out, rel=5e-3)
    assert abs(float(ds.attrs["energy_balance_error"])) < 5e-3


def test_the_bumper_takes_up_its_thickness_of_the_gap():
    k_b = MASS * (2.0 * math.pi / 0.5) ** 2
    system = assemble([ShearBuilding("m", [MASS], [k_b])], [_bumper(gap=0.05)])
    assert system.elements.el_gap[0] == pytest.approx(0.05 - THICK)
    assert get_contact_law("rubber_bumper").name == "bumper"


def _case(contact: dict) -> dict:
    return {
        "building": [{"name": "A", "n_floors": 1, "period": 0.5, "mass": MASS}],
        "contact": [{"left": "A", "right": "wall", "gap": 0.03, "k": K_C, "e": 0.65, **contact}],
        "ground_motion": {
            "type": "sine_pulse",
            "amplitude": 0.6,
            "period": 0.5,
            "duration": 3.0,
            "dt": 0.005,
        },  # fmt: skip
    }


@pytest.mark.parametrize(
    ("contact", "message"),
    [
        ({"law": "bumper", "k_rubber": K_R, "e_rubber": 0.8}, "law 'bumper' needs thickness"),
        ({"law": "bumper", "thickness": 0.04, "k_rubber": K_R, "e_rubber": 0.8},
         "thickness = 0.04 m is more than the gap = 0.03 m"),
        ({"law": "flores", "thickness": 0.01}, "thickness belong to law 'bumper'"),
        ({"law": "bumper", "thickness": 0.01, "k_rubber": K_R, "e_rubber": 0.8,
          "calibration": "exact"}, "calibration = 'exact' is not available"),
        ({"law": "bumper", "thickness": 0.01, "k_rubber": K_R, "e_rubber": 1.5},
         "e_rubber"),
    ],
)  # fmt: skip
def test_bad_bumper_input_names_the_field(contact, message):
    with pytest.raises((CaseError, PoundingInputError), match=message):
        case_from_dict(_case(contact))


def test_a_study_compares_contacts_with_and_without_the_bumper(tmp_path):
    from pounding.studies import run_study, study_from_dict

    data = _case({"law": "flores"})
    data["ground_motion"]["amplitude"] = 0.3
    bumper = {"thickness": 0.025, "k_rubber": 5e8, "e_rubber": 0.8, "crush": 0.9}
    data["study"] = {"law": ["flores", "bumper"], "law_params": {"bumper": bumper}}
    ds = run_study(study_from_dict(data), tmp_path / "runs", jobs=1)
    force = ds["peak_contact_force"].isel(contact=0, record=0)
    acc = ds["peak_absolute_acceleration"].sel(building="A").isel(record=0).max("floor")
    # here the 25 mm bumper in the 30 mm gap softens the impacts (2.0 MN instead of 2.37 MN,
    # 14.6 instead of 18.3 m/s²) though it is struck 25 mm earlier and slightly crushed
    assert float(force.sel(law="bumper")) < 0.9 * float(force.sel(law="flores"))
    assert float(acc.sel(law="bumper")) < 0.9 * float(acc.sel(law="flores"))
    crushed = ds["peak_penetration"].isel(contact=0, record=0).sel(law="bumper")
    assert float(crushed) > 0.9 * 0.025


# --------------------------------------------------------------------------------------------------
# Viscoelastic filler filling the whole gap
# --------------------------------------------------------------------------------------------------

K_F, C_F, GAP = 2.0e7, 2.0e5, 0.03  # N/m, N s/m, m


def _filler_force(d: float, dd: float, e: float = 0.65, crush: float = 0.8) -> float:
    """max(k_f δ + c_f δ̇, 0) + Jankowski's law on δ − crush × gap, written out."""
    if d <= 0.0:
        return 0.0
    f = max(K_F * d + C_F * dd, 0.0)
    dc = d - crush * GAP
    if dc > 0.0:
        xi = 9.0 * math.sqrt(5.0) / 2.0 * (1 - e * e) / (e * (e * (9 * math.pi - 16) + 16))
        f += K_C * dc**1.5 + (2 * xi * math.sqrt(K_C * math.sqrt(dc) * MASS) * dd if dd > 0 else 0)
    return f


def test_filler_kernel_is_a_kelvin_layer_then_jankowskis_law_with_exact_tangents():
    p = contact_parameters("filler", k=K_C, e=0.65, mass=MASS, filler=(K_F, C_F, 0.8 * GAP))
    for d, dd in ((0.01, 0.5), (0.01, -0.3), (0.026, 0.4), (0.03, -0.2), (-0.001, 1.0)):
        f, kd, kv = (float(x) for x in contact_force("filler", d, dd, p, v0=1.0))
        assert f == pytest.approx(_filler_force(d, dd), rel=1e-12, abs=1e-9)
        h = 1e-8
        fd = (_filler_force(d + h, dd) - _filler_force(d - h, dd)) / (2 * h)
        fv = (_filler_force(d, dd + h) - _filler_force(d, dd - h)) / (2 * h)
        assert kd == pytest.approx(fd, rel=1e-5, abs=1e-3)
        assert kv == pytest.approx(fv, rel=1e-5, abs=1e-3)


def _filler_case(method: str) -> dict:
    return {
        "building": [{"name": "A", "n_floors": 1, "period": 0.5, "mass": MASS,
                      "damping": {"ratio": 0.05}}],
        "contact": [{"left": "A", "right": "wall", "gap": GAP, "law": "filler", "k": K_C,
                     "e": 0.65, "k_filler": K_F, "c_filler": C_F, "crush": 0.8}],
        "ground_motion": {"type": "sine_pulse", "amplitude": 0.6, "period": 0.5, "duration": 3.0,
                          "dt": 0.005},
        "analysis": {"method": method},
    }  # fmt: skip


@pytest.mark.parametrize("method", ["newmark", "ivp"])
def test_sdof_against_a_wall_through_a_filler_matches_an_independent_solve_ivp(method):
    case = case_from_dict(_filler_case(method))
    ds = simulate(case)
    gm = case.ground_motion
    b = case.system.buildings[0]
    m, k = float(b.masses[0]), float(b.stiffnesses[0])
    c = 2 * 0.05 * math.sqrt(k * m)
    t_g = gm.dt * np.arange(gm.acceleration.size)

    def rhs(t, y):  # u > 0 towards the wall; the filler is compressed by u
        a_g = np.interp(t, t_g, gm.acceleration)
        return [y[1], (-m * a_g - c * y[1] - k * y[0] - _filler_force(y[0], y[1])) / m]

    t_out = ds["time"].values
    sol = solve_ivp(rhs, (0.0, t_out[-1]), [0.0, 0.0], method="DOP853", rtol=1e-10, atol=1e-13,
                    t_eval=t_out, max_step=1e-3)  # fmt: skip
    u = ds["displacement"].sel(building="A").isel(floor=0).values
    ref_force = np.array([_filler_force(a, b) for a, b in zip(sol.y[0], sol.y[1], strict=True)])
    assert np.max(np.abs(u)) == pytest.approx(np.max(np.abs(sol.y[0])), rel=5e-3)
    assert float(ds["peak_contact_force"].max()) == pytest.approx(ref_force.max(), rel=5e-3)
    assert np.max(sol.y[0]) > 0.8 * GAP  # the structures met through the crushed filler


@pytest.mark.parametrize(
    ("contact", "message"),
    [
        ({"law": "filler"}, "law 'filler' needs k_filler"),
        ({"law": "filler", "k_filler": K_F, "gap": 0.0}, "law 'filler' fills a gap"),
        ({"law": "flores", "k_filler": K_F}, "k_filler belong to law 'filler'"),
        ({"law": "filler", "k_filler": K_F, "thickness": 0.01}, "thickness belong to law 'bumper'"),
        ({"law": "filler", "k_filler": K_F, "calibration": "exact"},
         "calibration = 'exact' is not available"),
    ],
)  # fmt: skip
def test_bad_filler_input_names_the_field(contact, message):
    with pytest.raises((CaseError, PoundingInputError), match=message):
        case_from_dict(_case(contact))


def test_laws_restitution_and_the_report_take_the_bumpers_layer(tmp_path):
    import json

    from typer.testing import CliRunner

    from pounding.cli import app
    from pounding.contact.calibrate import effective_restitution
    from pounding.report.sections import _single_impact

    args = ["laws", "restitution", "--law", "bumper", "--k", str(K_C), "--mass", str(MASS),
            "--v0", "1.5", "--e", "0.65", "--thickness", str(THICK), "--k-rubber", str(K_R),
            "--e-rubber", "0.8", "--crush", str(CRUSH), "--json"]  # fmt: skip
    res = CliRunner().invoke(app, args)
    assert res.exit_code == 0, res.output
    ref = effective_restitution(
        "bumper", k=K_C, mass=MASS, v0=1.5, e=0.65, bumper=(THICK, K_R, 0.8, CRUSH)
    )
    assert json.loads(res.output)["e_effective"] == pytest.approx(ref.e_effective, rel=1e-12)
    _, v_out = _reference(1.5, 0.65, 0.8)
    assert ref.e_effective == pytest.approx(v_out / 1.5, rel=1e-6)  # the independent DOP853
    row = {"law": "bumper", "k": K_C, "mass": MASS, "v0": 1.5, "e": 0.65, "thickness": THICK,
           "k_rubber": K_R, "e_rubber": 0.8, "crush": CRUSH}  # fmt: skip
    assert _single_impact(row).e_effective == pytest.approx(ref.e_effective, rel=1e-12)
    missing = CliRunner().invoke(app, args[:10] + ["--thickness", "0.01"])
    assert missing.exit_code == 2 and "go together" in missing.output


@pytest.mark.parametrize("law", ["bumper", "filler"])
def test_stored_energy_of_a_layer_is_the_work_of_its_elastic_force(law):
    """The ledger's recoverable energy: ∫₀^δ F(s, δ̇ = 0) ds by quadrature of the written-out laws."""
    from scipy.integrate import quad

    from pounding.contact.laws import stored_energy

    if law == "bumper":
        p = contact_parameters(law, k=K_C, e=0.65, mass=MASS, bumper=(THICK, K_R, 0.8, CRUSH))
        force, kink = (lambda s: _force(s, 0.0, 1.0, 0.65, 0.8)), CRUSH * THICK
    else:
        p = contact_parameters(law, k=K_C, e=0.65, mass=MASS, filler=(K_F, C_F, 0.8 * GAP))
        force, kink = (lambda s: _filler_force(s, 0.0)), 0.8 * GAP
    for d in (0.5 * kink, kink, 1.3 * kink):
        work = quad(force, 0.0, d, points=[kink] if d > kink else None, epsabs=0, epsrel=1e-12)[0]
        f = float(contact_force(law, d, 0.0, p)[0])
        assert stored_energy(False, d, f, p) == pytest.approx(work, rel=1e-9)
