"""Tests for pounding.structure against closed-form results and independent eigen-solves.

Reference: Chopra, A. K. (2017). Dynamics of Structures, 5th ed., Pearson (cited as Chopra).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pounding.structure import ModalDamping, RayleighDamping, ShearBuilding

M_UNIT = 1.0e5  # [kg]
K_UNIT = 2.0e7  # [N/m]


def _modal_damping_ratios(building: ShearBuilding) -> np.ndarray:
    """ξ_j = φ_jᵀ C φ_j / (2 ω_j) with mass-normalised φ_j (Chopra Sec. 11.4)."""
    modal = building.modal()
    generalised = modal.shapes.T @ building.damping_matrix() @ modal.shapes
    return np.diag(generalised) / (2.0 * modal.circular_frequencies)


def _two_story() -> ShearBuilding:
    # Chopra Example 10.4: m1 = 2m, m2 = m, k1 = 2k, k2 = k.
    return ShearBuilding(
        "chopra 10.4", [2 * M_UNIT, M_UNIT], [2 * K_UNIT, K_UNIT], damping=RayleighDamping(0.05)
    )


def test_chopra_example_10_4_two_story_frequencies_and_shapes():
    # K = [[3k, -k], [-k, k]], M = diag(2m, m). det(K - λM) = 2m²λ² - 5kmλ + 2k² = 0
    # => λ = (5 ± 3) k / (4m) = k/(2m), 2k/m, i.e. ω² = k/(2m)·{1, 4} (Chopra Example 10.4).
    # Shapes from (3k - 2mλ)φ1 = kφ2: φ_1 ∝ (1/2, 1), φ_2 ∝ (-1, 1).
    b = _two_story()
    modal = b.modal()
    lam = K_UNIT / (2 * M_UNIT) * np.array([1.0, 4.0])
    np.testing.assert_allclose(modal.circular_frequencies, np.sqrt(lam), rtol=1e-12)
    np.testing.assert_allclose(modal.periods, 2 * np.pi / np.sqrt(lam), rtol=1e-12)
    for j, expected in enumerate(([0.5, 1.0], [-1.0, 1.0])):
        phi = modal.shapes[:, j]
        np.testing.assert_allclose(phi / phi[-1], expected, rtol=1e-12, atol=1e-12)
    # By hand: M_1 = 1.5m, L_1 = 2m -> Γ_1² = 8m/3; M_2 = 3m, L_2 = -m -> Γ_2² = m/3 (sum 3m).
    np.testing.assert_allclose(modal.effective_masses, [8 * M_UNIT / 3, M_UNIT / 3], rtol=1e-12)
    np.testing.assert_allclose(
        modal.participation_factors,
        [2 * M_UNIT / math.sqrt(1.5 * M_UNIT), -M_UNIT / math.sqrt(3 * M_UNIT)],
        rtol=1e-12,
    )


def test_chopra_example_10_4_rayleigh_coefficients_by_hand():
    # ω_2 = 2ω_1, so a0 = 2ξ ω1·2ω1/(3ω1) = 4ξω1/3 and a1 = 2ξ/(3ω1) (Chopra Sec. 11.4.1).
    b = _two_story()
    w1 = math.sqrt(K_UNIT / (2 * M_UNIT))
    a0, a1 = b.rayleigh_coefficients()
    assert a0 == pytest.approx(4 * 0.05 * w1 / 3, rel=1e-12)
    assert a1 == pytest.approx(2 * 0.05 / (3 * w1), rel=1e-12)
    np.testing.assert_allclose(
        b.damping_matrix(), a0 * b.mass_matrix() + a1 * b.stiffness_matrix(), rtol=1e-14
    )
    np.testing.assert_allclose(b.stiffness_matrix(), [[3 * K_UNIT, -K_UNIT], [-K_UNIT, K_UNIT]])


def test_two_story_uniform_quadratic():
    # m1 = m2 = m, k1 = k2 = k: m²λ² - 3kmλ + k² = 0 -> λ = (3 ∓ √5)/2 · k/m.
    b = ShearBuilding("uniform 2", [M_UNIT] * 2, [K_UNIT] * 2)
    lam = (3 - math.sqrt(5)) / 2, (3 + math.sqrt(5)) / 2
    np.testing.assert_allclose(
        b.modal().circular_frequencies ** 2, np.multiply(lam, K_UNIT / M_UNIT), rtol=1e-12
    )


@pytest.mark.parametrize("n", [1, 2, 3, 5, 12, 30])
def test_uniform_shear_building_all_frequencies_closed_form(n):
    # Fixed-free uniform chain: ω_j = 2√(k/m) sin((2j−1)π / (2(2n+1))), j = 1..n.
    b = ShearBuilding(f"uniform {n}", np.full(n, M_UNIT), np.full(n, K_UNIT))
    j = np.arange(1, n + 1)
    expected = 2 * math.sqrt(K_UNIT / M_UNIT) * np.sin((2 * j - 1) * np.pi / (2 * (2 * n + 1)))
    np.testing.assert_allclose(b.modal().circular_frequencies, expected, rtol=1e-10)


@pytest.mark.parametrize(("n", "period"), [(1, 0.3), (3, 0.4), (8, 1.2), (20, 2.5)])
def test_uniform_hits_fundamental_period(n, period):
    b = ShearBuilding.uniform("u", n, period=period, mass=3.0e5, height=3.5)
    assert b.modal().periods[0] == pytest.approx(period, rel=1e-10)
    assert np.all(b.masses == 3.0e5) and np.ptp(b.stiffnesses) == 0.0
    np.testing.assert_allclose(b.elevations, 3.5 * np.arange(1, n + 1))
    # Periods descend: mode 1 is the longest.
    assert np.all(np.diff(b.modal().periods) < 0)


def test_rayleigh_exact_ratio_at_anchor_modes():
    b = ShearBuilding(
        "irregular",
        [3.0e5, 2.5e5, 2.5e5, 2.0e5, 1.0e5],
        [4.0e8, 3.5e8, 3.0e8, 2.0e8, 1.0e8],
        damping=RayleighDamping(ratio=0.04, modes=(1, 3)),
    )
    xi = _modal_damping_ratios(b)
    assert xi[0] == pytest.approx(0.04, rel=1e-10)
    assert xi[2] == pytest.approx(0.04, rel=1e-10)
    # Between the anchors less, outside more (the Rayleigh curve a0/(2ω) + a1 ω/2).
    assert xi[1] < 0.04 < xi[3] < xi[4]
    np.testing.assert_allclose(b.modal().damping_ratios, xi, rtol=1e-10)
    # a0, a1 from an independent eigen-solve of the symmetric form M^-1/2 K M^-1/2.
    s = 1 / np.sqrt(b.masses)
    w = np.sqrt(np.linalg.eigvalsh(s[:, None] * b.stiffness_matrix() * s[None, :]))
    a0, a1 = b.rayleigh_coefficients()
    assert a0 == pytest.approx(2 * 0.04 * w[0] * w[2] / (w[0] + w[2]), rel=1e-10)
    assert a1 == pytest.approx(2 * 0.04 / (w[0] + w[2]), rel=1e-10)


def test_modal_damping_gives_each_ratio_and_is_classical():
    ratios = (0.02, 0.03, 0.05, 0.07)
    b = ShearBuilding(
        "modal", [2e5, 2e5, 1.5e5, 1e5], [3e8, 2.5e8, 2e8, 1e8], damping=ModalDamping(ratios)
    )
    modal = b.modal()
    generalised = modal.shapes.T @ b.damping_matrix() @ modal.shapes
    np.testing.assert_allclose(
        generalised, np.diag(2 * np.array(ratios) * modal.circular_frequencies), atol=1e-8
    )
    np.testing.assert_allclose(modal.damping_ratios, ratios)
    np.testing.assert_array_equal(b.damping_matrix(), b.damping_matrix().T)
    with pytest.raises(ValueError, match="rayleigh|Rayleigh"):
        b.rayleigh_coefficients()


def test_modal_damping_single_ratio_applies_to_all_modes():
    b = ShearBuilding("modal1", [1e5] * 3, [1e8] * 3, damping=ModalDamping((0.03,)))
    np.testing.assert_allclose(_modal_damping_ratios(b), 0.03, rtol=1e-10)


@pytest.mark.parametrize(
    "damping", [RayleighDamping(0.05), RayleighDamping(0.05, (2, 1)), ModalDamping((0.05,))]
)
def test_sdof_damping_is_critical_fraction(damping):
    # SDOF: c = 2ξ√(km) (Chopra Eq. 2.2.2 with c_cr = 2√(km)); Rayleigh on modes (1, 2) falls back.
    m, k = 4.0e4, 9.0e6
    b = ShearBuilding("sdof", [m], [k], damping=damping)
    np.testing.assert_allclose(b.damping_matrix(), [[2 * 0.05 * math.sqrt(k * m)]], rtol=1e-12)
    assert b.modal().periods[0] == pytest.approx(2 * math.pi * math.sqrt(m / k), rel=1e-12)


def test_rayleigh_on_too_few_modes_falls_back_and_says_so():
    b = ShearBuilding("short", [1e5, 1e5], [1e8, 1e8], damping=RayleighDamping(0.03, (1, 3)))
    np.testing.assert_allclose(_modal_damping_ratios(b), 0.03, rtol=1e-10)
    with pytest.raises(ValueError, match="modal damping"):
        b.rayleigh_coefficients()


buildings = st.integers(1, 8).flatmap(
    lambda n: st.tuples(
        st.lists(st.floats(1e3, 1e6), min_size=n, max_size=n),
        st.lists(st.floats(1e5, 1e9), min_size=n, max_size=n),
    )
)


@settings(max_examples=60, deadline=None)
@given(buildings)
def test_modal_invariants(mk):
    masses, stiffnesses = mk
    b = ShearBuilding("random", masses, stiffnesses)
    modal = b.modal()
    phi, m = modal.shapes, np.asarray(masses)
    np.testing.assert_allclose(phi.T @ b.mass_matrix() @ phi, np.eye(b.n_floors), atol=1e-9)
    np.testing.assert_allclose(
        b.stiffness_matrix() @ phi,
        (b.mass_matrix() @ phi) * modal.circular_frequencies**2,
        rtol=1e-7,
        atol=1e-7 * np.max(stiffnesses) * np.max(np.abs(phi)),
    )
    # roof component > 0, or that of the top-most moving floor where a mode leaves the roof still
    top = [
        max(i for i in range(b.n_floors) if abs(phi[i, j]) > 1e-8 * abs(phi[:, j]).max())
        for j in range(b.n_floors)
    ]
    assert all(phi[top[j], j] > 0 for j in range(b.n_floors))
    gamma = [sum(m[i] * phi[i, j] for i in range(b.n_floors)) for j in range(b.n_floors)]
    np.testing.assert_allclose(modal.participation_factors, gamma, rtol=1e-9, atol=1e-9)
    assert modal.effective_masses.sum() == pytest.approx(sum(masses), rel=1e-9)
    assert np.all(np.diff(modal.circular_frequencies) > 0)


def test_arrays_are_read_only_copies_and_modal_is_cached():
    masses = np.array([1e5, 1e5])
    b = ShearBuilding("ro", masses, [1e8, 1e8])
    masses[0] = -1.0
    assert b.masses[0] == 1e5
    np.testing.assert_array_equal(b.heights, [3.0, 3.0])
    assert b.modal() is b.modal()
    for array in (b.masses, b.stiffnesses, b.heights, b.modal().shapes):
        with pytest.raises(ValueError):
            array[0] = 0.0


@pytest.mark.parametrize(
    ("make", "field"),
    [
        (lambda: ShearBuilding("A", [1e5, 1e5, -3.0], [1e8] * 3), r"masses\[2\] = -3 kg"),
        (lambda: ShearBuilding("A", [1e5, 1e5], [np.nan, 1e8]), r"stiffnesses\[0\] = nan"),
        (lambda: ShearBuilding("A", [1e5, 1e5], [1e8]), "stiffnesses has 1"),
        (lambda: ShearBuilding("A", [1e5], [1e8], heights=[0.0]), r"heights\[0\]"),
        (lambda: ShearBuilding("A", [[1e5]], [[1e8]]), "masses has shape"),
        (lambda: ShearBuilding("A", [], []), "masses has shape"),
        (lambda: ShearBuilding("", [1e5], [1e8]), "name"),
        (lambda: ShearBuilding("A", [1e5], [1e8], damping=0.05), "damping"),
        (
            lambda: ShearBuilding("A", [1e5] * 3, [1e8] * 3, damping=ModalDamping((0.1, 0.2))),
            "damping.ratios",
        ),
        (lambda: RayleighDamping(ratio=1.0), "ratio = 1"),
        (lambda: RayleighDamping(ratio=-0.01), "ratio"),
        (lambda: ModalDamping((0.05, 1.0)), r"ratios\[1\] = 1"),
        (lambda: ModalDamping(()), "ratios"),
        (lambda: RayleighDamping(modes=(1, 1)), "modes"),
        (lambda: RayleighDamping(modes=(0, 2)), "modes"),
        (lambda: RayleighDamping(modes=(1, 2, 3)), "modes"),
        (lambda: RayleighDamping(modes=(1.0, 2.0)), "modes"),
        (lambda: ShearBuilding.uniform("A", 0, period=1.0, mass=1e5), "n_floors"),
        (lambda: ShearBuilding.uniform("A", 3, period=-1.0, mass=1e5), "period"),
        (lambda: ShearBuilding.uniform("A", 3, period=1.0, mass=np.inf), "mass"),
    ],
)
def test_bad_input_names_the_field(make, field):
    with pytest.raises(ValueError, match=field):
        make()


def test_error_message_names_building_and_rule():
    with pytest.raises(ValueError) as info:
        ShearBuilding("A", [1e5, 1e5, -3.0], [1e8] * 3)
    assert str(info.value) == "building 'A': masses[2] = -3 kg; masses must be positive and finite"


def test_mode_leaving_the_roof_still_gets_its_sign_from_the_top_moving_floor():
    # found by hypothesis: a very stiff second story lets one mode leave the roof (numerically) still;
    # its sign and the Dataset's "roof = 1" scaling fall back to the top-most moving floor
    from pounding.structure import reference_floors

    b = ShearBuilding(
        "stiff story",
        [1000.0] * 7,
        [100000.0, 357722355.0, 100006.0, 100005.0, 100021.0, 656665.0, 1803431.0],
    )
    phi = b.modal().shapes
    top = reference_floors(phi)
    assert top[-1] < b.n_floors - 1  # this mode does not move the roof
    assert np.all(phi[top, np.arange(b.n_floors)] > 0)
