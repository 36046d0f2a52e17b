"""Coupling links: the first element family beyond gaps and friction, integrated by the Newmark core
without a change to its time loop; each law checked against a closed form or an independent
solve_ivp integration."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from pounding import PoundingInputError, simulate
from pounding.case import case_from_dict
from pounding.ground_motion import sine_pulse
from pounding.links import LINK_LAWS, N_LINK_STATE, maxwell_link_kernel, viscous_link_kernel
from pounding.simulate import AnalysisOptions, run
from pounding.structure import RayleighDamping, ShearBuilding
from pounding.system import LEFT_SIGN, RIGHT_SIGN, Contact, Link, assemble


def _pair(n_left: int = 3, n_right: int = 5):
    return [
        ShearBuilding.uniform("A", n_left, period=0.3, mass=2.0e5),
        ShearBuilding.uniform("B", n_right, period=0.9, mass=2.0e5),
    ]


def _with_link_in_matrices(system, k: float, c: float):
    """The same system with each link's spring and dashpot assembled into K and C instead."""
    K = system.stiffness.copy()
    C = system.damping.copy()
    for (a, b), (sa, sb) in zip(system.links.dof, system.links.sign, strict=True):
        bvec = np.zeros(system.n_dof)
        bvec[a] += sa
        bvec[b] += sb
        K += k * np.outer(bvec, bvec)
        C += c * np.outer(bvec, bvec)
    return dataclasses.replace(
        system, stiffness=K, damping=C, links=type(system.links).empty(), link_specs=()
    )


@pytest.mark.parametrize("method", ["newmark", "hht"])
def test_linear_link_family_equals_the_spring_and_dashpot_assembled_into_k_and_c(method):
    # the toy family of the element-family design: a linear spring-dashpot between two dofs, integrated
    # as a family by Newton/Woodbury, against the same spring and dashpot written into K and C
    k, c = 4.0e7, 3.0e5
    gm = sine_pulse(amplitude=0.3 * 9.80665, period=0.6, duration=3.0, dt=0.005)
    linked = assemble(_pair(), [], [Link("A", "B", "kelvin", k=k, c=c)])
    assert len(linked.links) == 3  # floors 1-3 at common elevations
    assert np.all(linked.links.sign == [LEFT_SIGN, RIGHT_SIGN])
    in_matrices = _with_link_in_matrices(linked, k, c)
    opts = dict(method=method, dt=0.002, output_dt=0.01)
    a = simulate(linked, gm, **opts)
    b = simulate(in_matrices, gm, **opts)
    scale = float(abs(b["displacement"]).max())
    assert scale > 0.005
    assert float(abs(a["displacement"] - b["displacement"]).max()) < 1e-8 * scale
    np.testing.assert_allclose(a["peak_drift_ratio"], b["peak_drift_ratio"], rtol=1e-7)
    # the ledger moves the link's energy from strain and damping to its own terms, and still closes
    ea, eb = a["energy"].isel(time=-1), b["energy"].isel(time=-1)
    e_in = float(eb.sel(term="input"))
    for term in ("input", "kinetic"):
        assert float(ea.sel(term=term)) == pytest.approx(float(eb.sel(term=term)), rel=1e-6)
    strain = float(ea.sel(term="strain") + ea.sel(term="link_stored"))
    assert strain == pytest.approx(float(eb.sel(term="strain")), abs=1e-6 * e_in)
    damping = float(ea.sel(term="damping") + ea.sel(term="link_dissipated"))
    assert damping == pytest.approx(float(eb.sel(term="damping")), abs=1e-6 * e_in)
    assert float(ea.sel(term="link_dissipated")) > 0.01 * e_in
    assert a.attrs["energy_balance_error"] < 1e-6
    # the link force: k δ + c δ̇ of the floors it joins, with the gap elements' sign convention
    u = a["displacement"]
    v = a["velocity"]
    for j in range(3):
        d = u.sel(building="A", floor=j + 1) - u.sel(building="B", floor=j + 1)
        dd = v.sel(building="A", floor=j + 1) - v.sel(building="B", floor=j + 1)
        np.testing.assert_allclose(
            a["link_force"].isel(link=j), k * d + c * dd, rtol=0, atol=1e-6 * k * scale
        )
    assert float(a["peak_link_force"].max()) >= float(abs(a["link_force"]).max())


@pytest.mark.parametrize("alpha", [0.35, 0.5, 1.0])
def test_viscous_damper_dissipates_soong_dargush_energy_per_harmonic_cycle(alpha):
    # E = λ c ω^α X^(1+α), λ = 2^(2+α) Γ²(1+α/2)/Γ(2+α) (Soong & Dargush 1997): π for α = 1
    c, x_amp, omega = 2.0e5, 0.02, 2.0 * math.pi / 0.8
    lam = 2.0 ** (2.0 + alpha) * math.gamma(1.0 + alpha / 2.0) ** 2 / math.gamma(2.0 + alpha)
    expected = lam * c * omega**alpha * x_amp ** (1.0 + alpha)
    p = np.array([c, alpha, 1e-6])
    t = np.linspace(0.0, 2.0 * math.pi / omega, 200001)
    dd = x_amp * omega * np.cos(omega * t)
    s = np.zeros(2)
    f = np.array([viscous_link_kernel(0.0, v, 0.0, s, s, p)[0] for v in dd])
    work = float(np.sum(0.5 * (f[1:] * dd[1:] + f[:-1] * dd[:-1]) * np.diff(t)))
    assert work == pytest.approx(expected, rel=1e-5)
    if alpha == 1.0:
        assert lam == pytest.approx(math.pi)


def test_maxwell_link_update_is_the_exact_solution_at_a_constant_rate():
    # k(δ − x_d) = c ẋ_d = F with δ̇ constant: F(t) = c δ̇ (1 − e^(−t/τ)) + F0 e^(−t/τ), τ = c/k
    k, c, rate, f0, h = 3.0e7, 6.0e5, 0.05, 1.2e4, 0.013
    tau = c / k
    s0 = np.array([f0, 0.001])
    s1 = np.zeros(2)
    f, kd, cd = maxwell_link_kernel(0.001 + rate * h, rate, h, s0, s1, np.array([k, c, 0.0]))
    exact = c * rate * (1.0 - math.exp(-h / tau)) + f0 * math.exp(-h / tau)
    assert f == pytest.approx(exact, rel=1e-12)
    assert s1[0] == f and cd == 0.0
    assert kd == pytest.approx(c / h * (1.0 - math.exp(-h / tau)), rel=1e-12)
    assert kd < k  # softer than the spring alone: the dashpot relaxes within the step


def _two_sdof_with_link(link: Link):
    blds = [
        ShearBuilding.uniform("A", 1, period=0.5, mass=2.0e5),
        ShearBuilding.uniform("B", 1, period=1.1, mass=3.0e5),
    ]
    return assemble(blds, [], [link])


def _reference(system, gm, t_end, law: str, p):
    """An independent 2-dof integration (DOP853, rtol 1e-11) with the link force written out."""
    M, C, K = system.mass, system.damping, system.stiffness
    m_inv = np.linalg.inv(M)

    def force(y):
        dd = y[2] - y[3]
        if law == "viscous":
            v = abs(dd)
            return c_lin * dd if v < p[2] else math.copysign(p[0] * v ** p[1], dd)
        return y[4]  # maxwell: F is a state, Ḟ = k δ̇ − F/τ

    c_lin = p[0] * p[2] ** p[1] / p[2] if law == "viscous" else 0.0

    def rhs(t, y):
        u, v = y[:2], y[2:4]
        f = force(y)
        load = -M @ np.ones(2) * gm.at(t) - C @ v - K @ u - np.array([f, -f])
        out = [*v, *(m_inv @ load)]
        if law == "maxwell":
            out.append(p[0] * (v[0] - v[1]) - f * p[0] / p[1])
        # the work of the link force on the relative motion
        out.append(f * (v[0] - v[1]))
        return out

    y0 = np.zeros(6 if law == "maxwell" else 5)
    breaks = np.arange(0.0, t_end + 1e-12, gm.dt)
    ys = [y0]
    for t0, t1 in zip(breaks[:-1], breaks[1:], strict=True):  # restart at every record sample
        sol = solve_ivp(rhs, (t0, t1), ys[-1], method="DOP853", rtol=1e-11, atol=1e-13)
        ys.append(sol.y[:, -1])
    return breaks, np.array(ys)


@pytest.mark.parametrize(
    "link",
    [
        Link("A", "B", "viscous", c=8.0e5, alpha=0.5, v_lin=1e-3),
        Link("A", "B", "maxwell", k=2.0e7, c=1.0e6),
    ],
    ids=["viscous_alpha_0.5", "maxwell"],
)
def test_nonlinear_links_match_an_independent_solve_ivp_integration(link):
    system = _two_sdof_with_link(link)
    gm = sine_pulse(amplitude=0.35 * 9.80665, period=0.7, duration=2.0, dt=0.01)
    ds = simulate(system, gm, method="newmark", dt=2.5e-4, output_dt=0.01)
    t_ref, y = _reference(system, gm, float(ds["time"][-1]), link.type, system.links.params[0])
    u = ds["displacement"].sel(floor=1).transpose("time", "building").values
    scale = float(np.abs(y[:, :2]).max())
    assert scale > 0.01
    np.testing.assert_allclose(u, y[:, :2], rtol=0, atol=2e-4 * scale)
    # the link's work: dissipated plus stored equals the reference's ∫F δ̇ dt
    e = ds["energy"].isel(time=-1)
    work = float(e.sel(term="link_dissipated") + e.sel(term="link_stored"))
    assert work == pytest.approx(float(y[-1, -1]), rel=2e-3)
    assert float(e.sel(term="link_dissipated")) > 0.0
    assert ds.attrs["energy_balance_error"] < 1e-4


def test_link_input_errors_name_the_field_and_the_allowed_values():
    blds = _pair()
    with pytest.raises(
        PoundingInputError, match="type = 'spring'; allowed: kelvin, viscous, maxwell"
    ):
        assemble(blds, [], [Link("A", "B", "spring", k=1e7)])
    with pytest.raises(
        PoundingInputError, match=r"c \[N \(s/m\)\^alpha\] is required by 'viscous'"
    ):
        assemble(blds, [], [Link("A", "B", "viscous")])
    with pytest.raises(PoundingInputError, match="k = -1.0; allowed: a finite number >= 0"):
        assemble(blds, [], [Link("A", "B", "kelvin", k=-1.0)])
    with pytest.raises(PoundingInputError, match="needs k > 0 and c > 0"):
        assemble(blds, [], [Link("A", "B", "maxwell", k=1e7, c=0.0)])
    with pytest.raises(PoundingInputError, match="alpha not used by type = 'kelvin'"):
        assemble(blds, [], [Link("A", "B", "kelvin", k=1e7, alpha=0.5)])
    with pytest.raises(PoundingInputError, match="right = 'C': unknown building"):
        assemble(blds, [], [Link("A", "C", k=1e7)])
    with pytest.raises(PoundingInputError, match="not immediately left of"):
        assemble(blds, [], [Link("B", "A", k=1e7)])
    linked = assemble(blds, [], [Link("A", "B", k=1e7)])
    gm = sine_pulse(amplitude=1.0, period=0.5, duration=0.5, dt=0.01)
    with pytest.raises(PoundingInputError, match="allowed with links: newmark"):
        simulate(linked, gm, method="ivp")
    assert set(LINK_LAWS) == {"kelvin", "viscous", "maxwell"}


def test_case_file_link_table_runs_with_contacts_and_a_baseline():
    case = case_from_dict(
        {
            "building": [
                {"name": "A", "n_floors": 2, "period": 0.3, "mass": 2e5},
                {"name": "B", "n_floors": 4, "period": 0.8, "mass": 2e5},
            ],
            "contact": [{"left": "A", "right": "B", "gap": 0.01, "law": "linear", "k": 2e9}],
            "link": [
                {
                    "left": "A",
                    "right": "B",
                    "type": "viscous",
                    "c": 4e5,
                    "alpha": 0.4,
                    "floors": [[2, 2]],
                },
            ],  # fmt: skip
            "ground_motion": {
                "type": "sine_pulse",
                "amplitude": 0.4,
                "units": "g",
                "period": 0.7,
                "duration": 2.0,
            },  # fmt: skip
            "analysis": {"method": "newmark", "dt": 0.001, "output_dt": 0.01},
        },
        source="test",
    )
    assert case.system.links.law == ("viscous",)
    ds = simulate(case, baseline=True)
    assert ds.sizes["link"] == 1 and str(ds["link_type"].values[0]) == "viscous"
    assert int(ds["link_left_floor"][0]) == 2 and ds["link_force"].attrs["units"] == "N"
    assert float(ds["energy"].isel(time=-1).sel(term="link_dissipated")) > 0.0
    assert "no_contact_peak_displacement" in ds  # the baseline keeps the link, drops the contact
    with pytest.raises(PoundingInputError, match=r"link\[0\]"):
        case_from_dict(
            {**case.data, "link": [{"left": "A", "right": "B", "kind": "kelvin", "k": 1.0}]},
            source="test",
        )
    with pytest.raises(PoundingInputError, match=r"link\[0\].floors"):
        case_from_dict(
            {**case.data, "link": [{"left": "A", "right": "B", "k": 1.0, "floors": [1]}]},
            source="test",
        )


def test_a_system_without_links_has_no_link_axis():
    system = assemble(_pair(), [Contact("A", "B", 0.01, "linear", k=2e9)])
    ds = simulate(system, sine_pulse(amplitude=2.0, period=0.6, duration=1.0, dt=0.01), dt=0.002)
    assert "link" not in ds.dims and "link_force" not in ds
    assert float(abs(ds["energy"].sel(term=["link_dissipated", "link_stored"])).max()) == 0.0


@pytest.mark.parametrize("law", list(LINK_LAWS.values()), ids=lambda law: law.name)
def test_compiled_link_dispatch_calls_the_registered_kernel(law):
    # the compiled dispatch switches on literal ids: tie each id to the registry's kernel and stored
    from pounding.integrators._dispatch import element_eval, element_stored
    from pounding.links import FAMILY_LINK, N_LINK_STATE

    p = np.array([3.0e7, 0.6, 1e-3]) if law.name == "viscous" else np.array([3.0e7, 6.0e5, 0.0])
    for d, dd in [(2e-3, 0.3), (-1e-3, -2e-4)]:
        s0 = np.array([1.5e4, 1e-3])
        s_c, s_p = np.zeros(N_LINK_STATE), np.zeros(N_LINK_STATE)
        got = element_eval(FAMILY_LINK, law.kernel_id, d, dd, 0.004, s0, s_c, p)
        want = law.kernel(d, dd, 0.004, s0, s_p, p)
        np.testing.assert_allclose(got, want, rtol=1e-14)
        np.testing.assert_allclose(s_c, s_p, rtol=1e-14)
        stored = element_stored(FAMILY_LINK, law.kernel_id, d, got[0], s_c, p)
        assert stored == pytest.approx(law.stored(d, got[0], s_c, p), rel=1e-14)


def test_story_shear_of_linked_undamped_buildings_is_the_story_spring_force():
    # undamped stories: V_i = k_i δ_i exactly, taken from the floors' equilibrium, which must
    # include the link forces acting on the floors above (they were missing)
    bl = [
        ShearBuilding.uniform("A", 3, period=0.3, mass=2.0e5, damping=RayleighDamping(ratio=0.0)),
        ShearBuilding.uniform("B", 5, period=0.9, mass=2.0e5, damping=RayleighDamping(ratio=0.0)),
    ]
    system = assemble(bl, [], [Link("A", "B", "kelvin", k=4.0e7)])
    gm = sine_pulse(amplitude=0.3 * 9.80665, period=0.6, duration=2.0, dt=0.005)
    ds = simulate(system, gm, dt=0.001, output_dt=0.01)
    spring = ds.drift * ds.story_stiffness
    scale = float(abs(spring).max())
    assert float(abs(ds.link_force).max()) > 0.05 * scale
    assert float(abs(ds.story_shear - spring).max()) < 1e-6 * scale


@pytest.mark.parametrize(
    ("law", "params"),
    [("kelvin", {"k": 4.0e7, "c": 5.0e5}), ("viscous", {"c": 2.0e5, "alpha": 0.5}),
     ("maxwell", {"k": 4.0e7, "c": 5.0e5})],
)  # fmt: skip
def test_every_step_of_linked_buildings_ends_in_equilibrium_with_the_link_kernels(law, params):
    """Average acceleration enforces M a1 + C v1 + K u1 + Bᵀ F1 = −M ι a_g at each step's end.
    Without contacts or friction the link forces are settled on the linear step by fixed-point
    passes (no Newton iteration); F1 is found here by driving each link's Python kernel along the
    reported δ and δ̇, and the residual must be the passes' tolerance."""
    bl = [
        ShearBuilding.uniform("A", 3, period=0.3, mass=2.0e5),
        ShearBuilding.uniform("B", 5, period=0.9, mass=2.0e5),
    ]
    system = assemble(bl, [], [Link("A", "B", law, **params)])
    gm = sine_pulse(amplitude=0.3 * 9.80665, period=0.6, duration=2.0, dt=0.002)
    dt = 1e-3
    raw, _ = run(system, gm, AnalysisOptions(method="newmark", dt=dt, output_dt=dt, duration=2.0))
    u, v, a = raw.displacement, raw.velocity, raw.acceleration
    lk = system.links
    B = np.zeros((system.n_dof, len(lk)))
    for r in range(len(lk)):
        for c in range(2):
            if lk.dof[r, c] >= 0:
                B[lk.dof[r, c], r] = lk.sign[r, c]
    d, dd = u @ B, v @ B
    kernel = LINK_LAWS[law].kernel
    force = np.zeros_like(d)
    for r in range(len(lk)):
        s0, s1 = np.zeros(N_LINK_STATE), np.zeros(N_LINK_STATE)
        for j in range(1, d.shape[0]):
            force[j, r] = kernel(d[j, r], dd[j, r], dt, s0, s1, lk.params[r])[0]
            s0[:] = s1
    scale = np.abs(force).max()
    assert scale > 1e5
    np.testing.assert_allclose(raw.link_force, force, rtol=0, atol=1e-7 * scale)
    M, C, K, iota = system.mass, system.damping, system.stiffness, system.influence
    residual = (a + np.outer(raw.ground_acceleration, iota)) @ M + v @ C + u @ K + force @ B.T
    assert np.abs(residual).max() <= 1e-5 * scale
    assert raw.info["n_newton_iterations"] == 0
