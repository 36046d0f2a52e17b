"""Newmark (compiled, default settings) and solve_ivp agree on a two-building pounding problem.

Issue 2 acceptance: for every contact law, peak displacements within 0.5 % and peak contact force
within 2 %, with the energy balance error below 1 % of the input energy on both paths.
"""

from __future__ import annotations

import functools

import pytest
from _laws import with_layer

from pounding.contact.laws import LAWS_BY_ID
from pounding.ground_motion import sine_pulse
from pounding.simulate import simulate
from pounding.structure import ShearBuilding
from pounding.system import Contact, assemble

LINEAR_FAMILY = {"linear": 1.0e9, "kelvin": 1.0e9, "kelvin_approach": 1.0e9}


def _ground():
    return sine_pulse(amplitude=0.35 * 9.80665, period=0.6, duration=3.0, dt=0.005)


@functools.cache
def _ivp(law: str):
    """The pair of ``law`` on the solve_ivp path (rtol 1e-9), shared by the tests; only read."""
    return simulate(_pair(law), _ground(), method="ivp", rtol=1e-9)


def _pair(law: str):
    a = ShearBuilding.uniform("A", 2, period=0.3, mass=2.0e5)
    b = ShearBuilding.uniform("B", 3, period=0.7, mass=2.0e5)
    params = {"k": LINEAR_FAMILY.get(law, 2.75e9), "e": 0.6}
    if law in ("linear", "hertz"):
        params.pop("e")
    if law == "bilinear":
        params["delta_m"] = 0.004
    return assemble([a, b], [Contact("A", "B", 0.01, law, **with_layer(law, params))])


@pytest.mark.parametrize("law", [law.name for law in LAWS_BY_ID])
def test_newmark_defaults_agree_with_ivp(law):
    nm = simulate(_pair(law), _ground())
    ivp = _ivp(law)
    assert int(nm["impact_count"].sum()) >= 2
    # a grazing touch may register on one path only
    assert abs(int(nm["impact_count"].sum()) - int(ivp["impact_count"].sum())) <= 1
    peak_nm = nm["peak_displacement"].max("floor")
    peak_ivp = ivp["peak_displacement"].max("floor")
    assert float(abs(peak_nm / peak_ivp - 1).max()) < 5e-3
    f_nm = float(nm["peak_contact_force"].max())
    f_ivp = float(ivp["peak_contact_force"].max())
    assert f_nm == pytest.approx(f_ivp, rel=2e-2)
    assert nm.attrs["energy_balance_error"] < 1e-2
    assert ivp.attrs["energy_balance_error"] < 1e-2


@pytest.mark.parametrize("law", ["linear", "lankarani_nikravesh", "jankowski", "bilinear"])
@pytest.mark.parametrize(
    ("options", "tol_u", "tol_f"),
    [
        # HHT's α f0 term carried through the condensed contact step; numerical damping at α = −0.05
        ({"method": "hht", "alpha": -0.05}, 3e-3, 1e-2),
        ({"method": "hht", "alpha": -0.05, "adaptive": False, "dt": 2e-4}, 2e-4, 2e-3),
        ({"adaptive": False, "dt": 2e-4}, 2e-4, 2e-3),
    ],
)
def test_hht_and_fixed_step_agree_with_ivp(law, options, tol_u, tol_f):
    nm = simulate(_pair(law), _ground(), **options)
    ivp = _ivp(law)
    assert int(nm["impact_count"].sum()) == int(ivp["impact_count"].sum()) >= 2
    peak_nm = nm["peak_displacement"].max("floor")
    peak_ivp = ivp["peak_displacement"].max("floor")
    assert float(abs(peak_nm / peak_ivp - 1).max()) < tol_u
    f_nm = float(nm["peak_contact_force"].max())
    assert f_nm == pytest.approx(float(ivp["peak_contact_force"].max()), rel=tol_f)
