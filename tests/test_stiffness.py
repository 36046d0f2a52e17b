"""Tests for pounding.contact.stiffness: springs in series and Hertz stiffness of
spheres (Hertz 1882; Goldsmith 1960; Lankarani & Nikravesh 1990), against hand-worked numbers and Johnson's E*, R* form of Hertz theory.

Johnson, K.L. (1985). Contact Mechanics, Cambridge University Press, Sec. 4.2:
F = (4/3) E* √R* δ^(3/2), 1/E* = (1 − ν1²)/E1 + (1 − ν2²)/E2, 1/R* = 1/R1 + 1/R2.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from pounding.contact.stiffness import (
    hertz_compliance,
    hertz_sphere_plane,
    hertz_sphere_sphere,
    springs_in_series,
)

STEEL = {"E": 2.1e11, "nu": 0.3}
CONCRETE = {"E": 3.0e10, "nu": 0.2}

stiffness = st.floats(min_value=1.0e3, max_value=1.0e12)
modulus = st.floats(min_value=1.0e8, max_value=1.0e12)
poisson = st.floats(min_value=-0.9, max_value=0.5)
radius = st.floats(min_value=1.0e-3, max_value=10.0)


def _johnson(E1, nu1, R1, E2, nu2, R2=math.inf):
    """Johnson (1985) Sec. 4.2: k = (4/3) E* √R*, written independently of the package."""
    e_star = 1.0 / ((1.0 - nu1**2) / E1 + (1.0 - nu2**2) / E2)
    r_star = R1 if math.isinf(R2) else R1 * R2 / (R1 + R2)
    return 4.0 / 3.0 * e_star * math.sqrt(r_star)


# --- springs in series (Goldsmith 1960) -------------------------------------------------------


def test_two_equal_springs_give_half():
    assert springs_in_series(2.75e9, 2.75e9) == pytest.approx(1.375e9, rel=1e-15)


def test_three_springs_by_hand():
    # 1/k = 1/1 + 1/2 + 1/4 = 7/4 -> k = 4/7
    assert springs_in_series(1.0, 2.0, 4.0) == pytest.approx(4.0 / 7.0, rel=1e-15)


def test_single_spring_is_returned_and_rigid_part_drops_out():
    assert springs_in_series(3.0e8) == pytest.approx(3.0e8, rel=1e-15)
    assert springs_in_series(3.0e8, np.inf) == pytest.approx(3.0e8, rel=1e-15)
    assert springs_in_series(np.inf, np.inf) == np.inf


@given(stiffness, stiffness)
def test_series_equals_eq11_product_form(k1, k2):
    # Eq. 11 as printed: k = k1 k2 / (k1 + k2)
    expected = k1 * k2 / (k1 + k2)
    assert springs_in_series(k1, k2) == pytest.approx(expected, rel=1e-12)
    assert springs_in_series(k2, k1) == pytest.approx(expected, rel=1e-12)
    assert springs_in_series(k1, k2) < min(k1, k2)


@given(stiffness, stiffness, stiffness)
def test_series_is_associative(k1, k2, k3):
    nested = springs_in_series(springs_in_series(k1, k2), k3)
    assert springs_in_series(k1, k2, k3) == pytest.approx(nested, rel=1e-12)


def test_series_vectorised():
    out = springs_in_series([1.0, 2.0], [3.0, 6.0])
    np.testing.assert_allclose(out, [0.75, 1.5], rtol=1e-15)


@pytest.mark.parametrize(
    ("args", "field"),
    [
        ((1.0, 0.0), "stiffnesses[1]"),
        ((-2.0, 1.0), "stiffnesses[0]"),
        ((1.0, math.nan), "stiffnesses[1]"),
        ((1.0, "stiff"), "stiffnesses[1]"),
        ((1.0, [2.0, -1.0]), "stiffnesses[1]"),
    ],
)
def test_series_rejects_bad_stiffness(args, field):
    with pytest.raises(ValueError, match=re.escape(field)):
        springs_in_series(*args)


def test_series_needs_a_spring():
    with pytest.raises(ValueError, match="at least one"):
        springs_in_series()


# --- Hertz stiffness (Hertz 1882; Goldsmith 1960) -----------------------------------------------------


def test_hertz_compliance_steel():
    # h = (1 − 0.3²)/(π · 2.1e11) = 0.91 / 6.5973e11 = 1.37935e-12 1/Pa
    assert hertz_compliance(**STEEL) == pytest.approx(0.91 / (math.pi * 2.1e11), rel=1e-15)
    assert hertz_compliance(**STEEL) == pytest.approx(1.379351e-12, rel=1e-6)


def test_steel_sphere_on_steel_plane_by_hand():
    # Worked example: R = 0.1 m steel sphere on a steel plate, E = 210 GPa, ν = 0.3.
    # h_i + h_j = 2 · 0.91/(π · 2.1e11), so 3π(h_i + h_j) = 6 · 0.91 / 2.1e11 = 2.6e-11 1/Pa and
    # 4 / 2.6e-11 = 1.5384615e11 Pa (= (4/3) E* with E* = 2.1e11 / (2 · 0.91) = 1.1538e11 Pa).
    # k_h = 1.5384615e11 · √0.1 = 1.5384615e11 · 0.31622777 = 4.8650426e10 N/m^1.5.
    k = hertz_sphere_plane(E_sphere=2.1e11, nu_sphere=0.3, R=0.1, E_plane=2.1e11, nu_plane=0.3)
    assert k == pytest.approx(4.8650426e10, rel=1e-7)


def test_two_steel_spheres_by_hand():
    # Same material, R_i = R_j = 0.1 m: √(R R/(2R)) = √0.05 = 0.2236068, k_h = 1.5384615e11 · 0.2236068.
    k = hertz_sphere_sphere(E1=2.1e11, nu1=0.3, R1=0.1, E2=2.1e11, nu2=0.3, R2=0.1)
    assert k == pytest.approx(1.5384615e11 * math.sqrt(0.05), rel=1e-7)
    assert k == pytest.approx(3.4401046e10, rel=1e-7)


def test_concrete_sphere_on_steel_plate_against_johnson():
    k = hertz_sphere_plane(E_sphere=3.0e10, nu_sphere=0.2, R=0.5, E_plane=2.1e11, nu_plane=0.3)
    assert k == pytest.approx(_johnson(3.0e10, 0.2, 0.5, 2.1e11, 0.3), rel=1e-13)


@given(modulus, poisson, radius, modulus, poisson, radius)
def test_sphere_sphere_against_johnson_and_symmetric(E1, nu1, R1, E2, nu2, R2):
    k = hertz_sphere_sphere(E1=E1, nu1=nu1, R1=R1, E2=E2, nu2=nu2, R2=R2)
    swapped = hertz_sphere_sphere(E1=E2, nu1=nu2, R1=R2, E2=E1, nu2=nu1, R2=R1)
    assert k == pytest.approx(_johnson(E1, nu1, R1, E2, nu2, R2), rel=1e-12)
    assert swapped == pytest.approx(k, rel=1e-14)


@given(modulus, poisson, radius, modulus, poisson)
def test_sphere_sphere_tends_to_sphere_plane(E1, nu1, R1, E2, nu2):
    plane = hertz_sphere_plane(E_sphere=E1, nu_sphere=nu1, R=R1, E_plane=E2, nu_plane=nu2)
    assert plane == pytest.approx(_johnson(E1, nu1, R1, E2, nu2), rel=1e-12)
    # √(R_i R_j/(R_i + R_j)) = √R_i (1 − R_i/(2 R_j) + ...): relative gap ≈ R_i/(2 R_j)
    for ratio in (1.0e3, 1.0e6):
        k = hertz_sphere_sphere(E1=E1, nu1=nu1, R1=R1, E2=E2, nu2=nu2, R2=ratio * R1)
        assert k < plane
        assert (plane - k) / plane == pytest.approx(0.5 / ratio, rel=1e-3)
    flat = hertz_sphere_sphere(E1=E1, nu1=nu1, R1=R1, E2=E2, nu2=nu2, R2=np.inf)
    assert flat == pytest.approx(plane, rel=1e-15)


def test_hertz_scales_with_sqrt_radius():
    ks = hertz_sphere_plane(
        E_sphere=2.1e11, nu_sphere=0.3, R=np.array([0.1, 0.4]), E_plane=3.0e10, nu_plane=0.2
    )
    assert ks[1] / ks[0] == pytest.approx(2.0, rel=1e-14)


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"E1": -1.0}, "E1"),
        ({"E2": 0.0}, "E2"),
        ({"E1": math.inf}, "E1"),
        ({"nu1": 0.6}, "nu1"),
        ({"nu2": -1.0}, "nu2"),
        ({"R1": 0.0}, "R1"),
        ({"R2": -0.1}, "R2"),
        ({"R1": math.nan}, "R1"),
        ({"R1": math.inf, "R2": math.inf}, "R1"),
    ],
)
def test_sphere_sphere_rejects_bad_input(kwargs, field):
    args = {"E1": 2.1e11, "nu1": 0.3, "R1": 0.1, "E2": 2.1e11, "nu2": 0.3, "R2": 0.1} | kwargs
    with pytest.raises(ValueError, match=rf"^{field} = "):
        hertz_sphere_sphere(**args)


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"E_sphere": 0.0}, "E_sphere"),
        ({"nu_plane": 0.51}, "nu_plane"),
        ({"R": math.inf}, "R"),
        ({"R": -1.0}, "R"),
    ],
)
def test_sphere_plane_rejects_bad_input(kwargs, field):
    args = {"E_sphere": 2.1e11, "nu_sphere": 0.3, "R": 0.1, "E_plane": 2.1e11, "nu_plane": 0.3}
    with pytest.raises(ValueError, match=rf"^{field} = "):
        hertz_sphere_plane(**(args | kwargs))
