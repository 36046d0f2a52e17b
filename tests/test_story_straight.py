"""The straight story increment (``story_straight``): an increment that continues the last one short
of the next point where the path may turn is taken on the slope up to it, skipping the model's
kernel. Checked against the kernel itself, from the same committed state, at every such step of
fine and coarse drift histories through yielding, reversals, reloads, crossings and deterioration;
and inside the compiled element loop, where a kernel's trial row from an earlier pass must not leak
into a straight one."""

from __future__ import annotations

import numba
import numpy as np
import pytest
from _histories import piecewise

from pounding.ground_motion import sine_pulse
from pounding.integrators import _kernels as kn
from pounding.integrators._families import eval_elements
from pounding.integrators._steps import SLOPE_REFRESH, on_line, slopes_prepare, slopes_update
from pounding.simulate import AnalysisOptions, run
from pounding.stories import (
    BW_NEAR,
    FAMILY_STORY,
    N_STORY_PARAMS,
    N_STORY_STATE,
    SS_D,
    SS_DIR,
    SS_E,
    SS_EK,
    SS_KT,
    SS_KU_NEG,
    SS_KU_POS,
    SS_NEXT,
    SS_PEAK_NEG,
    SS_PEAK_POS,
    SS_T_NEG,
    SS_T_POS,
    SS_W,
    SS_WX,
    STORY_MODELS,
    Stories,
    bouc_wen_story_near,
    story_energy,
    story_straight,
)
from pounding.structure import ShearBuilding
from pounding.system import assemble

K, FY = 2.0e7, 1.0e5
DY = FY / K


def _params(*values: float) -> np.ndarray:
    return np.array([K, FY, *values, *np.zeros(N_STORY_PARAMS - 2 - len(values))])


#: (model, parameters beyond k and F_y): every model with straight branches, the IMK one with and
#: without cyclic deterioration (energy capacities γ = 30 F_y δ_y) and on a post-cap branch.
_CASES = {
    "bilinear": ("bilinear", (0.03,)),
    "bilinear_epp": ("bilinear", (0.0,)),
    "takeda": ("takeda", (0.03, 0.4)),
    "clough": ("takeda", (0.0, 0.0)),
    "imk": ("imk", (0.03, 2.0 * DY, 10.0 * DY, 0.2, 0.0, 0.0, 0.0, 0.0, 1.0)),
    "imk_deteriorating": ("imk", (0.03, 2.0 * DY, 10.0 * DY, 0.2, 30.0, 30.0, 30.0, 30.0, 1.0)),
}

#: Vertices (units δ_y): yielding both ways, partial unloadings and reloads, inner loops, a push
#: past the cap.
_HAND = [2.5, -0.5, 1.5, -3.0, 0.8, -1.2, 4.0, 1.0, 3.5, -2.0, -0.2, -4.5, 0.5, 6.0, -1.0]


def _histories(seed: int) -> np.ndarray:
    fine = piecewise(_HAND, DY, 40)[0]
    # then a response-like drift: random sines, reversals every ~20-200 steps, with every 50th
    # step a jump of up to 2 δ_y (a long increment through several turns)
    rng = np.random.default_rng(seed)
    t = np.arange(4000) / 4000.0
    walk = sum(
        rng.uniform(0.5, 2.5)
        * np.sin(2.0 * np.pi * rng.uniform(2.0, 40.0) * t + rng.uniform(0.0, 6.3))
        for _ in range(4)
    )
    walk[::50] += rng.uniform(-2.0, 2.0, walk[::50].size)
    return np.concatenate((fine, fine[-1] + (walk - walk[0]) * DY))


def _carried(model: str, row: np.ndarray, p: np.ndarray) -> np.ndarray:
    """``row`` with what a straight increment leaves for the kernel's next call to bring up: an
    IMK target or a Takeda peak pushed along the backbone is the drift reached (and Takeda's E
    the one of that peak)."""
    row = row.copy()
    if model == "imk":
        row[SS_T_POS] = max(row[SS_T_POS], row[SS_D])
        row[SS_T_NEG] = min(row[SS_T_NEG], row[SS_D])
    if model == "takeda" and not row[SS_PEAK_NEG] <= row[SS_D] <= row[SS_PEAK_POS]:
        row[SS_E] = story_energy(STORY_MODELS[model].kernel_id, row, p)
        k_u = p[0] * (abs(row[SS_D]) * p[0] / p[1]) ** -p[3]
        side = 0 if row[SS_D] > 0.0 else 1
        row[(SS_PEAK_POS, SS_PEAK_NEG)[side]] = row[SS_D]
        row[(SS_KU_POS, SS_KU_NEG)[side]] = k_u
        row[SS_EK] = 0.5 / k_u
    return row


@pytest.mark.parametrize("case", list(_CASES))
@pytest.mark.parametrize("seed", [1, 2])
def test_a_straight_increment_equals_the_kernel_from_the_same_state(case, seed):
    model, extra = _CASES[case]
    kernel = STORY_MODELS[model].kernel
    p = _params(*extra)
    s0 = np.zeros((1, N_STORY_STATE))
    s1 = np.zeros((1, N_STORY_STATE))
    fast = np.zeros((1, N_STORY_STATE))
    taken = 0
    kept = np.arange(N_STORY_STATE) != SS_NEXT
    if model != "imk":
        kept[SS_WX] = False
    history = _histories(seed)
    for d in history:
        fast[:] = s0
        straight, g, kd = story_straight(d, s0, fast, p[None, :], 0)
        got = kernel(d, 0.0, 0.01, s0[0], s1[0], p)
        if straight:
            taken += 1
            assert (g, kd) == pytest.approx(got[:2], rel=1e-9, abs=1e-9 * FY)
            # the whole row as the kernel leaves it, the slope ahead included; IMK's exact work
            # SS_WX too (a column the other models neither write nor read). Not the point ahead:
            # the kernel may find a corner at its own drift a rounding ahead and stop short there,
            # a stop that only costs a kernel call (one too far would fail the force here)
            np.testing.assert_allclose(
                _carried(model, fast[0], p)[kept], s1[0, kept], rtol=1e-9, atol=1e-9 * FY * DY
            )
        s0[:] = s1
    assert taken > 0.8 * history.size


def _walk(model: str, p: np.ndarray, history: np.ndarray) -> dict:
    """The compiled core's way along a drift history: straight increments on its own committed
    state (on an envelope too, leaving the pushed target or peak behind), the kernel only where the
    path may turn; beside the kernel at every step. Forces g and recoverable energies of both, the
    kernel calls of the first, the works at the end."""
    kernel = STORY_MODELS[model].kernel
    law = STORY_MODELS[model].kernel_id
    ref0, ref1 = np.zeros(N_STORY_STATE), np.zeros(N_STORY_STATE)
    s0, s1 = np.zeros((1, N_STORY_STATE)), np.zeros((1, N_STORY_STATE))
    out = {"g": [], "g_ref": [], "e": [], "e_ref": [], "kernel_calls": 0}
    for d in history:
        out["g_ref"].append(kernel(d, 0.0, 0.01, ref0, ref1, p)[0])
        s1[:] = s0
        straight, g, _ = story_straight(d, s0, s1, p[None, :], 0)
        if not straight:
            out["kernel_calls"] += 1
            g = kernel(d, 0.0, 0.01, s0[0], s1[0], p)[0]
        out["g"].append(g)
        out["e"].append(story_energy(law, s1[0], p))
        out["e_ref"].append(ref1[SS_E])
        ref0[:] = ref1
        s0[:] = s1
    out["w"], out["w_ref"] = s0[0, SS_W], ref0[SS_W]
    return out


@pytest.mark.parametrize("case", list(_CASES))
@pytest.mark.parametrize("seed", [1, 2])
def test_a_history_taken_straight_where_it_can_equals_the_kernel_at_every_step(case, seed):
    # force and stored energy at each step, the work at the end
    model, extra = _CASES[case]
    history = _histories(seed)
    walk = _walk(model, _params(*extra), history)
    np.testing.assert_allclose(walk["g"], walk["g_ref"], rtol=1e-9, atol=1e-9 * FY)
    np.testing.assert_allclose(walk["e"], walk["e_ref"], rtol=1e-9, atol=1e-9 * FY * DY)
    assert walk["w"] == pytest.approx(walk["w_ref"], rel=1e-9)
    assert walk["kernel_calls"] < 0.2 * history.size


@pytest.mark.parametrize("case", ["takeda", "clough"])
def test_takeda_oscillating_below_yield_crosses_zero_force_straight(case):
    # below yield the unloading and reload lines are the elastic line: the kernel runs at the
    # first increment and at each reversal only, not where the force crosses zero
    model, extra = _CASES[case]
    history = 0.8 * DY * np.sin(2.0 * np.pi * 3.0 * np.arange(1, 2001) / 2000.0)
    walk = _walk(model, _params(*extra), history)
    np.testing.assert_allclose(walk["g"], walk["g_ref"], rtol=1e-9, atol=1e-9 * FY)
    reversals = np.count_nonzero(np.diff(np.sign(np.diff(history))))
    assert walk["kernel_calls"] == 1 + reversals


def test_a_story_turning_inside_a_straight_step_keeps_it_only_on_the_maps_line():
    # the map took g = f0 + kd (d − d0) from the committed state; a kernel that agrees (a reversal
    # on that line) keeps the step, one off it by a slope or an offset does not
    kd, d0, f0, d = -0.97 * K, 1.5 * DY, -0.4 * FY, 1.2 * DY
    line = f0 + kd * (d - d0)
    assert on_line(line, kd, f0, d0, kd, d, K)
    assert on_line(line * (1.0 + 1e-14), kd * (1.0 + 1e-14), f0, d0, kd, d, K)
    assert not on_line(line, 0.0, f0, d0, kd, d, K)
    assert not on_line(line, kd + 1e-9 * K, f0, d0, kd, d, K)
    assert not on_line(line + 1e-6 * FY, kd, f0, d0, kd, d, K)


def test_bouc_wen_has_no_straight_branch():
    p = _params(0.05, 2.0, 0.5, 0.5, 1.0)
    s0, s1 = np.zeros(N_STORY_STATE), np.zeros(N_STORY_STATE)
    for d in piecewise([1.0, 0.5, 2.0], DY, 40)[0]:
        STORY_MODELS["bouc_wen"].kernel(d, 0.0, 0.01, s0, s1, p)
        assert s1[SS_DIR] == 0.0 and s1[SS_NEXT] == 0.0
        s0[:] = s1


#: Bouc–Wen parameter rows (α, n, β, γ, A0, δ_A, δ_ν, δ_η, ζ_s, p, q, ψ, δ_ψ, λ): the default
#: (n = 2), a non-integer n without degradation, and degradation with pinching.
_BOUC_WEN = {
    "n2": (0.05, 2.0, 0.5, 0.5, 1.0),
    "n1.4": (0.05, 1.4, 0.6, 0.4, 1.0),
    "degrading_pinched": (0.05, 2.0, 0.5, 0.5, 1.0, 0.1, 0.1, 0.1, 0.6, 1.0, 0.1, 0.2, 0.01, 0.1),
}


#: Units of a Bouc–Wen row: F [N], δ [m], W and E [J], then ζ, ε, dζ/dx and the direction.
_BW_SCALE = np.ones(N_STORY_STATE)
_BW_SCALE[:4] = FY, DY, FY * DY, FY * DY


@pytest.mark.parametrize("case", list(_BOUC_WEN))
def test_a_bouc_wen_story_a_round_off_from_its_trial_equals_the_kernel(case):
    # the fixed-point passes re-evaluate a story at its trial drift moved by a correction of
    # round-off size: continuing the trial along its rates gives the kernel's whole row from the
    # committed state, to round-off (the registry's kernel as the core compiles it: uncompiled,
    # its calls took most of 10-17 s a case)
    from pounding.integrators._dispatch import _bouc_wen_story as kernel

    p = _params(*_BOUC_WEN[case])
    s0, s1, near, again = (np.zeros(N_STORY_STATE) for _ in range(4))
    rng = np.random.default_rng(3)
    taken = 0
    for d in piecewise(_HAND, DY, 300)[0]:  # steps of ~0.01 δ_y, and a few turns
        kernel(d, 0.0, 0.01, s0, s1, p)
        for x in (1e-12, -3e-10, 0.9 * BW_NEAR, -0.9 * BW_NEAR, rng.uniform(-1.0, 1.0) * BW_NEAR):
            near[:] = s1
            d2 = d + x * DY
            done, g, kd = bouc_wen_story_near(d2, s0[None], near[None], p[None], 0)
            if abs(d - s0[1]) > 0.02 * DY or (d2 - s0[1]) * (d - s0[1]) <= 0.0:
                assert not done  # the kernel took sub-steps, or the increment turned
                continue
            taken += 1
            assert done
            got = kernel(d2, 0.0, 0.01, s0, again, p)
            # (pytest.approx's rel/abs test written out: ~90,000 approx calls were half the test)
            assert abs(g - got[0]) <= 1e-12 * max(abs(got[0]), FY), (g, got[0])
            assert abs(kd - got[1]) <= 1e-12 * max(abs(got[1]), K), (kd, got[1])
            assert np.all(np.abs(near - again) <= 1e-12 * (_BW_SCALE + np.abs(again)))
        near[:] = s1
        assert not bouc_wen_story_near(d + 2.0 * BW_NEAR * DY, s0[None], near[None], p[None], 0)[0]
        s0[:] = s1
    assert taken > 1000
    # a turn a round-off away: the trial a hair ahead of the committed drift, then a hair behind
    kernel(s0[1] + 0.5 * BW_NEAR * DY, 0.0, 0.01, s0, s1, p)
    assert not bouc_wen_story_near(s0[1] - 0.4 * BW_NEAR * DY, s0[None], s1[None], p[None], 0)[0]


def _elements(model: str, extra: tuple) -> kn.Elements:
    """One story between the ground and dof 0."""
    z = np.zeros(1)
    return kn.Elements(np.array([FAMILY_STORY]), np.array([STORY_MODELS[model].kernel_id]),
                       np.array([[0, -1]]), np.array([[1.0, 0.0]]), _params(*extra)[None, :],
                       np.zeros((1, N_STORY_STATE)), np.zeros((1, N_STORY_STATE)), z, z.copy(),
                       z.copy(), z.copy(), z.copy(), z.copy(), z.copy(), np.ones(1, dtype=np.bool_))  # fmt: skip


@numba.njit
def _eval(u1, v1, h, el):
    # (the core's element loop has no Python entry of its own)
    return eval_elements(u1, v1, h, el)


def _commit(el: kn.Elements) -> None:
    el.state[:] = el.trial
    el.written[:] = False


@pytest.mark.parametrize("case", ["takeda", "imk_deteriorating"])
def test_a_straight_pass_after_a_kernel_pass_starts_from_the_committed_state(case):
    # the passes of one step evaluate the story at several drifts: a first one past a zero-force
    # crossing (the kernel moves the crossing's state), a second one short of it (straight): the
    # second must carry none of the first one's state
    el = _elements(*_CASES[case])
    v = np.zeros(1)
    for d in piecewise([3.0, 1.0], DY, 20)[0]:  # yield, then unload to + force
        _eval(np.array([d]), v, 0.01, el)
        _commit(el)
    ahead = el.state[0, SS_NEXT]  # the zero-force drift of the unloading
    assert ahead < el.state[0, 1]
    committed = el.state[0].copy()
    past, short = ahead - 0.5 * DY, ahead + 0.01 * DY
    _eval(np.array([past]), v, 0.01, el)
    assert el.written[0] and not np.allclose(el.trial[0], committed)
    _eval(np.array([short]), v, 0.01, el)
    assert not el.written[0]
    expected = committed[None, :].copy()
    story_straight(short, committed[None, :], expected, el.params, 0)
    np.testing.assert_array_equal(el.trial[0], expected[0])


def test_a_bouc_wen_pass_a_round_off_after_a_kernel_pass_continues_its_trial():
    el = _elements("bouc_wen", _BOUC_WEN["n2"])
    v = np.zeros(1)
    for d in piecewise([3.0, 1.0], DY, 20)[0]:
        _eval(np.array([d]), v, 0.01, el)
        _commit(el)
    committed = el.state[0].copy()
    d = committed[1] - 0.01 * DY
    _eval(np.array([d]), v, 0.01, el)
    first = el.trial[0].copy()
    _eval(np.array([d + 1e-3 * BW_NEAR * DY]), v, 0.01, el)
    expected = np.zeros(N_STORY_STATE)
    STORY_MODELS["bouc_wen"].kernel(d + 1e-3 * BW_NEAR * DY, 0.0, 0.01, committed, expected,
                                     el.params[0])  # fmt: skip
    assert el.trial[0, 0] != first[0]
    np.testing.assert_allclose(el.trial[0], expected, rtol=1e-13, atol=1e-13 * FY * DY)


@pytest.mark.parametrize("model", ["bilinear", "takeda", "imk"])
def test_every_hht_step_of_a_yielding_building_meets_its_weighted_equation(model):
    """HHT weights the end of a step by w = 1 + α (α = −0.1): M a1 + w(C v1 + K u1 + Bᵀ g1)
    − α(C v0 + K u0 + Bᵀ g0) = −M ι (w a_g1 − α a_g0), g = F − k δ of each story. A step in which
    every story goes straight on solves it in one product with w kd in the tangent (most steps
    here); the forces F are recomputed by driving each story's Python kernel along the drifts."""
    params = {"yield_drift": 0.002, "hardening": 0.03}
    building = ShearBuilding.uniform(
        "A", 3, period=0.35, mass=2.0e5, stories=Stories(model, params)
    )
    system = assemble([building], [])
    gm = sine_pulse(amplitude=0.3 * 9.80665, period=0.6, duration=2.0, dt=0.002)
    dt, alpha = 1e-3, -0.1
    raw, _ = run(
        system, gm, AnalysisOptions(method="hht", alpha=alpha, dt=dt, output_dt=dt, duration=2.0)
    )
    u, v, a, ag = raw.displacement, raw.velocity, raw.acceleration, raw.ground_acceleration
    st = system.stories
    B = np.zeros((len(st), system.n_dof))
    for r in range(len(st)):
        for c in range(st.dof.shape[1]):
            if st.dof[r, c] >= 0:
                B[r, st.dof[r, c]] = st.sign[r, c]
    drift = u @ B.T
    assert np.abs(drift).max() > 2.5 * params["yield_drift"] * building.heights[0]
    kernel = STORY_MODELS[model].kernel
    g = np.zeros_like(drift)
    for r in range(len(st)):
        s0, s1 = np.zeros(N_STORY_STATE), np.zeros(N_STORY_STATE)
        for j in range(1, drift.shape[0]):
            g[j, r] = kernel(drift[j, r], 0.0, dt, s0, s1, st.params[r])[0]
            s0[:] = s1
    M, C, K, iota = system.mass, system.damping, system.stiffness, system.influence
    w = 1.0 + alpha
    internal = v @ C + u @ K + g @ B
    residual = (
        a[1:] @ M + w * internal[1:] - alpha * internal[:-1]
        + np.outer(w * ag[1:] - alpha * ag[:-1], iota) @ M
    )  # fmt: skip
    scale = np.abs(g).max() + np.abs(u @ K).max()
    assert np.abs(residual).max() <= 1e-7 * scale


@numba.njit
def _update(sl, el, w, alpha):
    return slopes_update(sl, el, w, alpha)


@numba.njit
def _prepare_slopes(J_inv, el, Q, pg):
    return slopes_prepare(J_inv, Q, pg, el, True)


def test_rank_one_updates_of_the_stories_condensation_and_straight_map_equal_numpys_solves():
    # a 4-dof chain of 4 stories (one to the ground), random slopes: after each round of changes
    # (some stories only), and across a rebuild from kd = 0, Z = (J + w Bᵀ diag(kd) B)⁻¹ Bᵀ,
    # S = B Zᵀ and the straight map (Qᵀ, pg) of a random linear map (Q0ᵀ = J⁻¹ R, pg0 = J⁻¹ r):
    # Qᵀ = J_s⁻¹ (R + α Bᵀ diag(kd) B [I 0 0]), pg = J_s⁻¹ r, as numpy's solves give them
    rng = np.random.default_rng(7)
    n, w = 4, 0.9
    alpha = w - 1.0
    el = _elements("takeda", _CASES["takeda"][1])
    el = el._replace(kind=np.full(n, FAMILY_STORY), law=np.full(n, el.law[0]),
                     dof=np.array([[0, -1], [1, 0], [2, 1], [3, 2]]),
                     sign=np.tile([1.0, -1.0], (n, 1)), params=np.repeat(el.params, n, axis=0),
                     state=np.zeros((n, N_STORY_STATE)))  # fmt: skip
    el.sign[0, 1] = 0.0
    B = np.zeros((n, n))
    for e in range(n):
        for c in range(2):
            if el.dof[e, c] >= 0:
                B[e, el.dof[e, c]] = el.sign[e, c]
    J = B.T @ np.diag(rng.uniform(1.0, 2.0, n) * K) @ B + np.diag(rng.uniform(0.5, 1.0, n) * K)
    R, r = rng.normal(size=(n, 3 * n)), rng.normal(size=n)
    Q0, pg0 = np.linalg.solve(J, R).T.copy(), np.linalg.solve(J, r)
    sl = _prepare_slopes(np.linalg.inv(J), el, Q0, pg0)
    Eu = np.hstack([np.eye(n), np.zeros((n, 2 * n))])
    for round_ in range(40):
        changed = rng.random(n) < 0.5
        el.state[changed, SS_KT] = K * rng.uniform(-0.3, 1.0, changed.sum())
        if round_ == 25:
            sl.count[0] = SLOPE_REFRESH
        assert _update(sl, el, w, alpha)
        kd = el.state[:, SS_KT] - K
        Js = J + w * B.T @ np.diag(kd) @ B
        Z = np.linalg.solve(Js, B.T).T
        np.testing.assert_allclose(sl.Z, Z, rtol=0, atol=1e-10 * np.abs(Z).max())
        np.testing.assert_allclose(sl.S, B @ Z.T, rtol=0, atol=1e-10 * np.abs(Z).max())
        Q = np.linalg.solve(Js, R + alpha * B.T @ np.diag(kd) @ B @ Eu).T
        np.testing.assert_allclose(sl.Q, Q, rtol=0, atol=1e-10 * np.abs(Q).max())
        pg = np.linalg.solve(Js, r)
        np.testing.assert_allclose(sl.pg, pg, rtol=0, atol=1e-10 * np.abs(pg).max())
    assert sl.count[0] < 40 * n  # the rebuild happened
