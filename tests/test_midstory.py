"""Floor-to-column (mid-story) impacts: a slab striking the neighbour's column between its floors, the
struck story split at the impact point into two column segments. Checked against statics (the split
leaves the story's stiffness unchanged; the local stiffness and reactions of a shear column), the
floor-to-floor contact it reduces to, and an independent solve_ivp integration of a 3-vs-2-story row."""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from pounding import PoundingInputError, simulate
from pounding.case import CaseError, case_from_dict
from pounding.ground_motion import sine_pulse
from pounding.structure import ShearBuilding
from pounding.system import Contact, assemble
from pounding.units import G

K_HERTZ = 2.0e9
GAP = 0.005
M_COLUMN = 5.0e3
SHARE = 0.5


def _row(floors="elevation", **kw):
    """A: 3 stories of 3 m (floors at 3, 6, 9 m); B: 2 stories of 4.5 m (4.5, 9 m). A's floor 1
    strikes B's story-1 column at ξ = 2/3, floor 2 B's story-2 column at ξ = 1/3, floor 3 B's roof."""
    a = ShearBuilding.uniform("A", 3, period=0.35, mass=3.0e5, height=3.0)
    b = ShearBuilding.uniform("B", 2, period=0.3, mass=4.0e5, height=4.5)
    spec = dict(column_share=SHARE, column_mass=M_COLUMN)
    spec.update(kw)
    contact = Contact("A", "B", gap=GAP, law="hertz", k=K_HERTZ, floors=floors, **spec)
    return assemble([a, b], [contact])


def test_elevation_pairs_floors_with_floors_and_columns():
    system = _row()
    col = system.columns
    assert list(col.story) == [1, 2]
    np.testing.assert_allclose(col.xi, [2 / 3, 1 / 3])
    np.testing.assert_allclose(col.elevation, [3.0, 6.0])
    el = system.elements
    assert list(el.left_floor) == [1, 2, 3]
    assert list(el.right_floor) == [1, 2, 2]  # the struck stories, then B's roof
    assert list(el.right_column) == [0, 1, -1]
    assert el.el_dof[0, 1] == col.dof[0] and el.el_dof[2, 1] == system.dof(1, 2)
    # the contact's effective mass is that of the slab and the column node
    assert el.el_mass[0] == pytest.approx(3.0e5 * M_COLUMN / (3.0e5 + M_COLUMN))


def test_split_story_keeps_its_stiffness_when_nothing_strikes_it():
    # static condensation of the column nodes gives back the shear building's K exactly
    system = _row()
    s = system.building_dofs(1)
    k = system.stiffness[s, s]
    floors = [0, 1]
    nodes = [2, 3]
    kff, kfn, knn = k[np.ix_(floors, floors)], k[np.ix_(floors, nodes)], k[np.ix_(nodes, nodes)]
    condensed = kff - kfn @ np.linalg.solve(knn, kfn.T)
    b = system.buildings[1]
    np.testing.assert_allclose(condensed, b.stiffness_matrix(), rtol=1e-12)


@pytest.mark.parametrize("xi", [0.3, 0.5, 0.8])
def test_struck_shear_column_with_floors_held_has_stiffness_kc_over_xi_eta(xi):
    # a force F at the node with both floors held: u_m = F ξ η / k_c, reactions η F below, ξ F above
    h = 4.0
    a = ShearBuilding("A", [3e5], [4e8], heights=[xi * h])
    b = ShearBuilding("B", [3e5], [6e8], heights=[h])
    system = assemble([a, b], [Contact("A", "B", gap=0.01, law="linear", k=1e9,
                                       floors="elevation", column_share=0.4)])  # fmt: skip
    col = system.columns
    assert col.xi[0] == pytest.approx(xi)
    k = system.stiffness
    m, top = int(col.dof[0]), system.dof(1, 1)
    k_c = 0.4 * 6e8
    assert k[m, m] == pytest.approx(k_c / (xi * (1 - xi)), rel=1e-12)
    f = 1.0e5
    u_m = f / k[m, m]  # floor held: the node alone moves
    assert u_m == pytest.approx(f * xi * (1 - xi) / k_c, rel=1e-12)
    below = k_c / xi * u_m  # segment forces: the reactions at the ground and at the floor
    above = -k[top, m] * u_m
    assert below == pytest.approx((1 - xi) * f, rel=1e-12)
    assert above == pytest.approx(xi * f, rel=1e-12)


def test_elevation_equals_common_when_the_floors_line_up():
    gm = sine_pulse(amplitude=0.4 * G, period=0.5, duration=2.0, dt=0.005)
    a = ShearBuilding.uniform("A", 3, period=0.35, mass=3.0e5)
    b = ShearBuilding.uniform("B", 5, period=0.6, mass=3.0e5)
    runs = [
        simulate(
            assemble([a, b], [Contact("A", "B", gap=GAP, law="hertz", k=K_HERTZ, floors=f)]), gm
        )  # fmt: skip
        for f in ("common", "elevation")
    ]
    assert int(runs[0].impact_count.sum()) > 0
    np.testing.assert_array_equal(runs[0].displacement.values, runs[1].displacement.values)
    assert runs[1].sizes.get("column", 0) == 0


def test_a_slab_within_the_level_tolerance_strikes_the_floor():
    # A's floors at 3.05 and 6.05 m, B's at 3.0 and 7.5 m: 3.05 m is B's floor 1 (within the default
    # 0.1 m), 6.05 m strikes B's story-2 column at ξ = 3.05/4.5
    a = ShearBuilding("A", [3e5, 3e5], [4e8, 4e8], heights=[3.05, 3.0])
    b = ShearBuilding("B", [3e5, 3e5], [4e8, 4e8], heights=[3.0, 4.5])
    contact = dict(gap=GAP, law="hertz", k=K_HERTZ, floors="elevation")
    system = assemble([a, b], [Contact("A", "B", **contact)])
    assert list(system.elements.right_floor) == [1, 2]
    assert list(system.elements.right_column) == [-1, 0]
    assert system.columns.xi[0] == pytest.approx(3.05 / 4.5)
    with pytest.raises(PoundingInputError, match="story 2 of 'B'"):  # two points in one story
        assemble([a, b], [Contact("A", "B", **contact, level_tolerance=0.01)])


BW = {"yield_drift": 0.002, "hardening": 0.05, "n": 1.5, "beta": 0.6, "gamma": 0.4}


def _reference(gm, t_end, bouc_wen=False):
    """The 3-vs-2 row in its own coordinates [A1..A3, B1, B2, n1, n2], DOP853 at rtol 1e-10. With
    ``bouc_wen``, B's stories are Bouc–Wen (no degradation) on their chord drift δ_j: the split K
    holds k δ, and F − k δ acts floor to floor, the struck column carrying its share of it."""
    a = ShearBuilding.uniform("A", 3, period=0.35, mass=3.0e5, height=3.0)
    b = ShearBuilding.uniform("B", 2, period=0.3, mass=4.0e5, height=4.5)
    k1, k2 = b.stiffnesses
    xi = (2 / 3, 1 / 3)
    n = 7
    kk = np.zeros((n, n))
    kk[:3, :3] = a.stiffness_matrix()

    def spring(i, j, k):  # i, j: dofs (-1 = ground)
        for p, q, s in ((i, i, 1), (j, j, 1), (i, j, -1), (j, i, -1)):
            if p >= 0 and q >= 0:
                kk[p, q] += s * k

    b1, b2, n1, n2 = 3, 4, 5, 6
    spring(-1, b1, (1 - SHARE) * k1)
    spring(-1, n1, SHARE * k1 / xi[0])
    spring(n1, b1, SHARE * k1 / (1 - xi[0]))
    spring(b1, b2, (1 - SHARE) * k2)
    spring(b1, n2, SHARE * k2 / xi[1])
    spring(n2, b2, SHARE * k2 / (1 - xi[1]))
    mass = np.concatenate((a.masses, b.masses, [M_COLUMN, M_COLUMN]))
    cc = np.zeros((n, n))
    cc[:3, :3] = a.damping_matrix()
    a0, a1 = b.rayleigh_coefficients()  # Rayleigh on B's split K and its masses with the nodes
    cc[3:, 3:] = a0 * np.diag(mass[3:]) + a1 * kk[3:, 3:]
    pairs = ((0, n1), (1, n2), (2, b2))
    k = np.array([k1, k2])
    fy = BW["yield_drift"] * 4.5 * k
    al, nn, be, ga = BW["hardening"], BW["n"], BW["beta"], BW["gamma"]

    def chord(u):
        return np.array([u[b1], u[b2] - u[b1]])

    def forces(u, z):
        f = np.zeros(n)
        fc = np.zeros(3)
        for c, (i, j) in enumerate(pairs):
            d = u[i] - u[j] - GAP
            fc[c] = K_HERTZ * d**1.5 if d > 0 else 0.0
            f[i] -= fc[c]
            f[j] += fc[c]
        corr = np.zeros(2)
        if bouc_wen:  # F − k δ = (1 − α)(F_y z − k δ) on each story's chord
            corr = (1 - al) * (fy * z - k * chord(u))
            f[b1] -= corr[0] - corr[1]
            f[b2] -= corr[1]
        return f, fc, corr

    t_gm, a_gm = gm.time, gm.acceleration  # gm.at, without rebuilding the time axis per call

    def rhs(t, y):
        u, v, z = y[:n], y[n : 2 * n], y[2 * n :]
        rate = chord(v)
        zdot = rate / (fy / k) * (1 - (be * np.sign(rate * z) + ga) * np.abs(z) ** nn)
        f = forces(u, z)[0]
        acc = (f - kk @ u - cc @ v) / mass - np.interp(t, t_gm, a_gm, left=0.0, right=0.0)
        return np.concatenate((v, acc, zdot if bouc_wen else np.zeros(2)))

    sol = solve_ivp(rhs, (0.0, t_end), np.zeros(2 * n + 2), method="DOP853", rtol=1e-10,
                    atol=1e-13, max_step=5e-4, dense_output=True)  # fmt: skip
    t = np.arange(0.0, t_end + 1e-9, 2.5e-4)
    y = sol.sol(t)
    u, z = y[:n], y[2 * n :]
    out = [forces(u[:, j], z[:, j]) for j in range(t.size)]
    fc = np.array([o[1] for o in out]).T
    corr = SHARE * np.array([o[2] for o in out]).T  # the column's share of F − k δ
    shear = np.array(
        [
            SHARE * k1 / xi[0] * u[n1] + corr[0],
            SHARE * k1 / (1 - xi[0]) * (u[b1] - u[n1]) + corr[0],
            SHARE * k2 / xi[1] * (u[n2] - u[b1]) + corr[1],
            SHARE * k2 / (1 - xi[1]) * (u[b2] - u[n2]) + corr[1],
        ]
    )
    drift = np.abs(chord(u)).max(axis=1)
    return dict(
        displacement=np.abs(u[:5]).max(axis=1),
        node=np.abs(u[5:]).max(axis=1),
        force=fc.max(axis=1),
        shear=np.abs(shear).max(axis=1).reshape(2, 2),
        ductility=drift / (fy / k),
    )


def _pulse(amplitude_g: float):
    return sine_pulse(amplitude=amplitude_g * G, period=0.5, duration=2.5, dt=0.005)


@functools.cache
def _pulse_reference(amplitude_g: float, bouc_wen: bool) -> dict:
    """_reference on _pulse(amplitude_g), shared by the Newmark and ivp tests (only read)."""
    return _reference(_pulse(amplitude_g), 2.5, bouc_wen=bouc_wen)


@pytest.mark.parametrize("method", ["newmark", "ivp"])
def test_three_vs_two_story_mid_story_impacts_match_an_independent_ivp(method):
    gm = _pulse(0.4)
    ref = _pulse_reference(0.4, bouc_wen=False)
    ds = simulate(_row(), gm, method=method, output_dt=2.5e-4)
    assert ref["force"][:2].min() > 1e5  # both columns are struck
    tol = 1e-4  # measured: 4e-6 (peak forces), both paths
    peak = ds.peak_displacement
    np.testing.assert_allclose(peak.sel(building="A")[:3], ref["displacement"][:3], rtol=tol)
    np.testing.assert_allclose(peak.sel(building="B")[:2], ref["displacement"][3:], rtol=tol)
    np.testing.assert_allclose(ds.peak_column_displacement, ref["node"], rtol=tol)
    np.testing.assert_allclose(ds.peak_contact_force, ref["force"], rtol=tol)
    # column shears from the output samples (the reference's too, on the same 0.25 ms grid)
    shear = np.abs(ds.column_shear).max("time").values
    np.testing.assert_allclose(shear, ref["shear"], rtol=tol)
    energy = ds.energy.isel(time=-1).to_series()
    assert abs(energy.drop(["input"]).sum() - energy["input"]) < 1e-3 * energy["input"]


@pytest.mark.parametrize("method", ["newmark", "ivp"])
def test_yielding_story_struck_between_floors_matches_an_independent_ivp(method):
    from pounding.stories import Stories

    gm = _pulse(0.5)
    ref = _pulse_reference(0.5, bouc_wen=True)
    a = ShearBuilding.uniform("A", 3, period=0.35, mass=3.0e5, height=3.0)
    b = ShearBuilding.uniform("B", 2, period=0.3, mass=4.0e5, height=4.5,
                              stories=Stories("bouc_wen", BW))  # fmt: skip
    contact = Contact("A", "B", gap=GAP, law="hertz", k=K_HERTZ, floors="elevation",
                      column_share=SHARE, column_mass=M_COLUMN)  # fmt: skip
    opts = dict(dt=1e-4) if method == "newmark" else dict(method="ivp", rtol=1e-9)
    ds = simulate(assemble([a, b], [contact]), gm, output_dt=2.5e-4, **opts)
    assert ref["force"][:2].min() > 1e5 and ref["ductility"].max() > 2.0
    tol = 1e-4  # measured: 8e-6 (peak forces), both paths; B's story 1 at ductility 5.5
    peak = ds.peak_displacement
    np.testing.assert_allclose(peak.sel(building="B")[:2], ref["displacement"][3:], rtol=tol)
    np.testing.assert_allclose(ds.peak_contact_force, ref["force"], rtol=tol)
    shear = np.abs(ds.column_shear).max("time").values
    np.testing.assert_allclose(shear, ref["shear"], rtol=tol)
    assert ds.attrs["energy_balance_error"] < 1e-3


def test_column_capacity_is_flagged_when_the_struck_segment_exceeds_it():
    gm = sine_pulse(amplitude=0.4 * G, period=0.5, duration=2.5, dt=0.005)
    ds = simulate(_row(column_capacity=1.0e5), gm)
    assert ds.column_capacity.attrs["units"] == "N"
    assert ds.column_capacity_exceeded.values.all()
    peak = ds.peak_column_shear.values
    assert np.all(peak > 1.0e5)
    summary = ds.pounding.summary()
    assert len(summary["columns"]) == 2 and all(c["exceeded"] for c in summary["columns"])
    assert any("column" in w and "capacity" in w for w in summary["warnings"])


def test_mid_story_in_a_case_file():
    spec = {
        "building": [
            {"name": "A", "n_floors": 3, "period": 0.35, "mass": 3e5, "height": 3.0},
            {"name": "B", "n_floors": 2, "period": 0.3, "mass": 4e5, "height": 4.5},
        ],
        "contact": [{"left": "A", "right": "B", "gap": 0.005, "law": "hertz", "k": 2e9,
                     "floors": "elevation", "column_share": 0.5, "column_mass": 5e3,
                     "column_capacity": 2e6}],
        "ground_motion": {"type": "sine_pulse", "amplitude": 3.0, "period": 0.5},
    }  # fmt: skip
    case = case_from_dict(spec)
    assert len(case.system.columns) == 2
    bad = {**spec["contact"][0], "column_share": 1.5}
    with pytest.raises(CaseError, match="column_share"):
        case_from_dict({**spec, "contact": [bad]})


def test_mid_story_errors_name_the_field():
    a = ShearBuilding.uniform("A", 3, period=0.35, mass=3.0e5, height=3.0)
    b = ShearBuilding.uniform("B", 2, period=0.3, mass=4.0e5, height=4.5)
    with pytest.raises(PoundingInputError, match="column_share"):
        Contact("A", "B", gap=0.01, k=1e9, floors="elevation", column_share=0.0)
    with pytest.raises(PoundingInputError, match="elevation"):
        assemble([a], [Contact("A", "wall", gap=0.01, k=1e9, floors="elevation")])
    with pytest.raises(PoundingInputError, match="column"):
        Contact("A", "B", gap=0.01, k=1e9, floors="common", column_capacity=1e6)
    # a fuzzed column_mass of 1e-300 kg overflowed the natural frequencies: a node weighs what a
    # floor may, 1 kg at least
    for mass in (1e-300, 0.5, math.nan, math.inf):
        with pytest.raises(PoundingInputError) as info:
            Contact("A", "B", gap=0.01, k=1e9, floors="elevation", column_mass=mass)
        assert str(info.value).endswith(
            f"column_mass = {mass!r} [kg]; allowed: 1 <= column_mass <= 1e12"
        )
    # the default column mass: a share of the struck story's floor mass
    system = assemble([a, b], [Contact("A", "B", gap=0.01, k=1e9, floors="elevation")])
    assert system.columns.mass[0] == pytest.approx(0.02 * 4.0e5)
    assert math.isfinite(system.shortest_period())


def test_floor_to_column_example_runs_prints_and_reports_the_columns(tmp_path):
    from pathlib import Path

    from typer.testing import CliRunner

    from pounding.case import load_case
    from pounding.cli import app
    from pounding.report import build_report

    example = Path(__file__).resolve().parents[1] / "examples" / "floor_to_column.toml"
    res = CliRunner().invoke(app, ["run", str(example), "-o", str(tmp_path / "r.nc")])
    assert res.exit_code == 0, res.output
    assert "A:2      B:c2" in res.output
    assert "B story 1 at 3 m: peak shear" in res.output and "EXCEEDED" in res.output
    case = load_case(example)
    ds = simulate(case, duration=2.0)
    report = build_report(ds)
    titles = [s.title for s in report.sections]
    table, _plot = report.sections[titles.index("Floor-to-column impacts")].blocks
    assert [row[:2] for row in table.rows] == [["B", "1"], ["B", "2"], ["B", "3"]]
    assert [row[3] for row in table.rows] == ["0.75", "0.5", "0.25"]
    from pounding.report import render_html

    assert "B:c1" in render_html(report)  # the contact tables name the struck column


def test_a_study_sweeps_the_column_share_and_keeps_each_struck_columns_peak_shear(tmp_path):
    from pounding.studies import run_study
    from pounding.studies.spec import study_from_dict

    spec = {
        "building": [
            {"name": "A", "n_floors": 3, "period": 0.35, "mass": 3e5, "height": 3.0},
            {"name": "B", "n_floors": 2, "period": 0.3, "mass": 4e5, "height": 4.5},
        ],
        "contact": [{"left": "A", "right": "B", "gap": 0.005, "law": "hertz", "k": 2e9,
                     "floors": "elevation", "column_mass": 5e3}],
        "ground_motion": {"type": "sine_pulse", "amplitude": 3.9, "period": 0.5,
                          "duration": 2.0},
        "study": {"contact.0.column_share": [0.25, 0.5]},
    }  # fmt: skip
    ds = run_study(study_from_dict(spec), tmp_path / "s.nc", jobs=1)
    shear = ds["peak_struck_column_shear"]
    assert shear.attrs["units"] == "N"
    values = shear.sel({"contact.0.column_share": 0.5}).values.ravel()
    assert np.isfinite(values[:2]).all() and np.isnan(values[2])  # two columns, then B's roof
    assert float(shear.sel({"contact.0.column_share": 0.5}).max()) > float(
        shear.sel({"contact.0.column_share": 0.25}).max()
    )
