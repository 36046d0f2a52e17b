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

from pounding.integrators import _kernels as kn
from pounding.integrators._families import eval_elements
from pounding.stories import (
    FAMILY_STORY,
    N_STORY_PARAMS,
    N_STORY_STATE,
    SS_DIR,
    SS_NEXT,
    SS_WX,
    STORY_MODELS,
    story_straight,
)

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
            np.testing.assert_allclose(fast[0, kept], s1[0, kept], rtol=1e-9, atol=1e-9 * FY * DY)
        s0[:] = s1
    assert taken > 0.8 * history.size


def test_bouc_wen_has_no_straight_branch():
    p = _params(0.05, 2.0, 0.5, 0.5, 1.0)
    s0, s1 = np.zeros(N_STORY_STATE), np.zeros(N_STORY_STATE)
    for d in piecewise([1.0, 0.5, 2.0], DY, 40)[0]:
        STORY_MODELS["bouc_wen"].kernel(d, 0.0, 0.01, s0, s1, p)
        assert s1[SS_DIR] == 0.0 and s1[SS_NEXT] == 0.0
        s0[:] = s1


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
