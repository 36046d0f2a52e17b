"""Ibarra–Medina–Krawinkler story springs (peak-oriented, cyclic deterioration): the kernel against
an independent rule-by-rule implementation (monotonic backbone in closed form, cyclic and random
histories with the four deterioration modes), the strength deterioration of a cycle and the reload
through a local peak by hand, the loop area, an independent event-driven solve_ivp of a 3-storey
IMK building pounding on a wall, a sidesway collapse with P-Δ and the case file."""

from __future__ import annotations

import copy
import functools
import math

import numpy as np
import pytest
from _histories import piecewise
from scipy.integrate import solve_ivp

from pounding import simulate
from pounding.case import CaseError, case_from_dict
from pounding.ground_motion import GroundMotion, harmonic, sine_pulse
from pounding.stories import (
    N_STORY_PARAMS,
    N_STORY_STATE,
    SS_D,
    SS_E,
    SS_F,
    SS_FAILED,
    SS_WX,
    Stories,
    imk_failure_ahead,
    imk_story_kernel,
)
from pounding.structure import ShearBuilding
from pounding.system import Contact, assemble

K, FY = 2.0e7, 3.0e4
DY = FY / K


def _params(
    hardening: float = 0.03,
    plastic: float = 4.0,
    post_cap: float = 8.0,
    residual: float = 0.2,
    gammas: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0),
    c: float = 1.0,
) -> np.ndarray:
    """Kernel row (k, F_y0, α_s, δ_p, δ_pc, κ, γ_s, γ_c, γ_a, γ_k, c); drifts in units of δ_y."""
    row = [K, FY, hardening, plastic * DY, post_cap * DY, residual, *gammas, c]
    return np.array([*row, *np.zeros(N_STORY_PARAMS - len(row))])


def _drive(history: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Run the kernel along a drift history; rows (F, tangent, W, E): W the exact path work
    (SS_WX, what the deterioration uses; SS_W is the ledger's trapezoid per step)."""
    s0, s1 = np.zeros(N_STORY_STATE), np.zeros(N_STORY_STATE)
    out = []
    for d in history:
        corr, dk, _ = imk_story_kernel(d, 0.0, 3.0, s0, s1, p)
        assert corr == pytest.approx(s1[SS_F] - p[0] * d, abs=1e-12 * p[1])
        out.append((s1[SS_F], dk + p[0], s1[SS_WX], s1[SS_E]))
        s0[:] = s1
    return np.array(out)


class _IMK:
    """Independent IMK spring written from the rules: each drift increment is applied in
    sub-increments of at most ``sub`` δ_y (a reversal only ever starts the first), and the work
    W = ∫F dδ of a sub-increment is integrated exactly, on the straight pieces between the points
    where the force path may turn (zero point, target drift, envelope corners, where an inner
    reload meets the reload line). Sides are m = +1, −1; every side quantity is kept signed."""

    def __init__(self, p: np.ndarray, sub: float = 0.05):
        k, fy0, a_s, d_p, d_pc, kappa, g_s, g_c, g_a, g_k, c = (float(x) for x in p[:11])
        self.k, self.fy0, self.a_s, self.kappa, self.c = k, fy0, a_s, kappa, c
        self.gamma = {"s": g_s, "c": g_c, "a": g_a, "k": g_k}
        self.dy = fy0 / k
        d_c0 = self.dy + d_p  # the cap of the monotonic backbone
        f_c0 = fy0 + a_s * k * d_p
        self.kc = -f_c0 / d_pc  # post-cap slope
        self.fref0 = f_c0 - self.kc * d_c0  # the post-cap line F_ref + k_c δ through the cap
        self.sub = sub
        self.d = self.f = self.w = 0.0
        self.motion = 0
        self.dk = self.ek = self.wlast = 0.0
        self.failed = False
        self.ds = {1: 0.0, -1: 0.0}
        self.dc = {1: 0.0, -1: 0.0}
        self.t = {1: self.dy, -1: -self.dy}
        self.z = {1: 0.0, -1: 0.0}
        self.peak = {1: (0.0, 0.0), -1: (0.0, 0.0)}  # local peaks (δ, F); F = 0: none
        self.slope = k  # of the branch that gave the last force

    @property
    def ku(self) -> float:
        return self.k * (1.0 - self.dk)

    def _lines(self, m: int) -> list[tuple[float, float]]:
        """(value at y = 0, slope) of the envelope's lines on side m, in y = m δ ≥ 0."""
        fy = self.fy0 * (1.0 - self.ds[m])
        alpha = self.a_s * (1.0 - self.ds[m])
        fref = self.fref0 * (1.0 - self.dc[m])
        return [(0.0, self.k), (fy * (1.0 - alpha), alpha * self.k), (fref, self.kc)]

    def env(self, x: float, m: int) -> tuple[float, float]:
        """F_env and its slope on side m at drift x (m x ≥ 0)."""
        y = m * x
        value, slope = y * self.k, self.k
        for a, b in self._lines(m)[1:]:
            if a + b * y < value:
                value, slope = a + b * y, b
        if value < self.kappa * self.fy0:
            return m * self.kappa * self.fy0, 0.0
        return m * value, slope

    def corners(self, m: int) -> list[float]:
        """Drifts where any two of the envelope's four lines (with the residual) intersect."""
        lines = [*self._lines(m), (self.kappa * self.fy0, 0.0)]
        out = []
        for i, (a1, b1) in enumerate(lines):
            for a2, b2 in lines[i + 1 :]:
                if b1 != b2:
                    out.append(m * (a2 - a1) / (b1 - b2))
        return out

    def path(self, m: int) -> tuple[list[tuple[float, float]], float | None]:
        """The reload path L_m from (z', 0) to the target (t_m, F_env(t_m)) as lines (value at
        δ = 0, slope), two of them when it runs through the local peak (δ_l, F_l) first, a point
        above the straight line; and δ_l then."""
        t = self.t[m]
        ft = self.env(t, m)[0]
        zp = m * min(m * self.z[m], m * t - m * ft / self.k)
        if ft == 0.0:
            return [(0.0, 0.0)], None
        s = ft / (t - zp)
        dl, fl = self.peak[m]
        if m * zp < m * dl < m * t and 0.0 < m * fl < m * ft and m * fl > s * m * (dl - zp):
            s1, s2 = fl / (dl - zp), (ft - fl) / (t - dl)
            return [(-s1 * zp, s1), (fl - s2 * dl, s2)], dl
        return [(-s * zp, s)], None

    def line(self, x: float, m: int) -> tuple[float, float]:
        """The reload path L_m at drift x, and its slope there."""
        lines, dl = self.path(m)
        a, s = lines[1] if dl is not None and m * (x - dl) >= 0.0 else lines[0]
        return a + s * x, s

    def meets(self, m: int) -> list[float]:
        """Drifts where an inner reload at K_u from the committed state meets the reload path's
        lines, and the local peak the path turns at."""
        lines, dl = self.path(m)
        out = [] if dl is None else [dl]
        if m * self.f > 0.0:
            out += [
                (self.f - self.ku * self.d - a) / (s - self.ku) for a, s in lines if s != self.ku
            ]
        return out

    def beta(self, e_i: float, e_tot: float, mode: str) -> float:
        e_t = self.gamma[mode] * self.fy0 * self.dy
        if e_t - e_tot <= 0.0:
            return 1.0
        return min((max(e_i, 0.0) / (e_t - e_tot)) ** self.c, 1.0)

    def _force(self, x: float) -> tuple[float, float]:
        """Step 4 at drift x of the increment from the committed (δ_n, F_n), after steps 1-3."""
        m, d0, f0 = self.motion, self.d, self.f
        if self.failed:
            return 0.0, 0.0
        if m * (x - self.t[m]) >= 0.0:
            return self.env(x, m)
        if m * f0 < 0.0 and m * (x - self.z[m]) < 0.0:
            return f0 + self.ku * (x - d0), self.ku
        f, s = self.line(x, m)
        if m * f0 > 0.0:
            inner = f0 + self.ku * (x - d0)
            if m * inner < m * f:
                return inner, self.ku
        return f, s

    def _begin(self, m: int) -> None:
        """Steps 1 and 2: a reversal (or the first increment) in direction m."""
        f0 = self.f
        if self.motion == -m:
            e_now = max(self.w - f0 * f0 / (2.0 * self.ku), 0.0) if self.ku > 0.0 else 0.0
            if self.gamma["k"] > 0.0 and not self.failed:
                b = self.beta(e_now - self.ek, e_now, "k")
                self.failed = b >= 1.0
                # K_u no lower than the secants from here to the points the reload aims at
                t, ft = self.t[m], self.env(self.t[m], m)[0]
                floor = (ft - f0) / (t - self.d) if m * (t - self.d) > 0.0 else 0.0
                dl, fl = self.peak[m]
                if m * self.d < m * dl < m * t and 0.0 < m * fl < m * ft:
                    floor = max(floor, (fl - f0) / (dl - self.d))
                ku = max((1.0 - b) * self.ku, min(self.ku, floor))
                self.dk = 1.0 if self.failed else 1.0 - ku / self.k
            self.ek = e_now
            # side −m starts to unload here, below its target: its local peak
            if m * f0 < 0.0 and -m * (self.d - self.t[-m]) < 0.0:
                self.peak[-m] = (self.d, f0)
        if self.motion != m and m * f0 <= 0.0 and not self.failed:
            self.z[m] = self.d - f0 / self.ku
        self.motion = m

    def _cross(self) -> float:
        """Step 3: the force crosses zero at z_m; the deterioration of side m. Returns W_c."""
        m = self.motion
        wc = self.w + 0.5 * self.f * (self.z[m] - self.d)
        e_i = wc - self.wlast
        for mode, damage in (("s", self.ds), ("c", self.dc)):
            if self.gamma[mode] > 0.0:
                b = self.beta(e_i, wc, mode)
                damage[m] = 1.0 - (1.0 - damage[m]) * (1.0 - b)
                self.failed = self.failed or b >= 1.0
        if self.gamma["a"] > 0.0:
            self.t[m] *= 1.0 + self.beta(e_i, wc, "a")
        self.wlast = wc
        return wc

    def _increment(self, d: float) -> None:
        d0, f0 = self.d, self.f
        self.turns = []
        if d == d0:
            return
        m = 1 if d > d0 else -1
        self._begin(m)
        start, w = d0, self.w
        ahead = m * f0 < 0.0 or (f0 == 0.0 and m * (d0 - self.z[m]) < 0.0)
        crossing = not self.failed and ahead and m * (d - self.z[m]) >= 0.0
        if crossing:
            start, w = self.z[m], self._cross()
        # the exact work: the path is straight between the points where it may turn
        cuts = [self.t[m], self.z[m]]
        if m * d > m * self.t[m]:
            cuts += self.corners(m)
        cuts += self.meets(m)
        inside = sorted((x for x in cuts if m * start < m * x < m * d), key=lambda x: m * x)
        self.turns = ([start] if crossing else []) + inside
        xs = [start, *inside, d]
        path = [self._force(x) for x in xs]
        if not self.failed:  # the force is continuous: the rules are well posed here
            jump = path[0][0] - (0.0 if crossing else f0)
            assert abs(jump) < 1e-9 * self.fy0, "a reload line steeper than k or K_u"
        w += sum(
            0.5 * (path[j][0] + path[j + 1][0]) * (xs[j + 1] - xs[j]) for j in range(len(xs) - 1)
        )
        f, s = path[-1]
        if not self.failed and m * (d - self.t[m]) >= 0.0:
            self.t[m] = d
            self.peak[m] = (0.0, 0.0)  # the envelope pushed
        self.d, self.f, self.w, self.slope = d, f, w, s

    def step(self, d: float) -> None:
        d, d0 = float(d), self.d
        n = max(1, math.ceil(abs(d - d0) / (self.sub * self.dy)))
        for j in range(1, n):
            self._increment(d0 + (d - d0) * j / n)
        self._increment(d)

    def recoverable(self) -> float:
        return 0.5 * self.f**2 / self.ku if self.f else 0.0

    def copy(self) -> _IMK:
        other = copy.copy(self)
        for name in ("ds", "dc", "t", "z", "peak"):
            setattr(other, name, dict(getattr(self, name)))
        return other

    def at_kink(self) -> bool:
        """True when the slope just after δ (continuing the motion) is not the slope of the branch
        that reached δ: a corner, where either tangent is right."""
        if self.motion == 0:
            return False
        ahead = self.copy()
        eps = 1e-7 * self.dy * self.motion
        ahead._increment(self.d + eps)
        return abs((ahead.f - self.f) / eps - self.slope) > 1e-5 * self.k


def _reference(history: np.ndarray, p: np.ndarray, sub: float = 0.05, kinks: bool = True) -> tuple:
    """Rows (F, tangent, W, E) of the reference along a history, and a mask of the kinks."""
    spring = _IMK(p, sub)
    rows, mask = [], []
    for d in history:
        spring.step(d)
        rows.append((spring.f, spring.slope, spring.w, spring.recoverable()))
        mask.append(kinks and spring.at_kink())
    return np.array(rows), np.array(mask)


def _aligned(history: np.ndarray, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The history with the drifts where the force path of the rules may turn inserted (zero
    points, targets, envelope corners, inner-reload meets): every increment is then straight. And
    a mask of the inserted points (corners: either tangent is right there)."""
    spring = _IMK(p, sub=math.inf)
    out, inserted = [], []
    for d in history:
        spring.step(d)
        for x, turn in [*((x, True) for x in spring.turns), (d, False)]:
            if not out or x != out[-1]:
                out.append(x)
                inserted.append(turn)
    return np.array(out), np.array(inserted)


def _trapezoid(history: np.ndarray, f: np.ndarray) -> np.ndarray:
    """Cumulative ∫F dδ along the history from (0, 0), trapezoidal."""
    d = np.concatenate(([0.0], history))
    f = np.concatenate(([0.0], f))
    return np.cumsum(0.5 * (f[1:] + f[:-1]) * np.diff(d))


# ---------------------------------------------------------------------------------------------
# the monotonic backbone


@pytest.mark.parametrize("side", [1.0, -1.0])
@pytest.mark.parametrize("gammas", [(0.0, 0.0, 0.0, 0.0), (20.0, 20.0, 20.0, 20.0)])
def test_monotonic_push_to_15_yield_drifts_follows_the_backbone_to_the_residual(side, gammas):
    # α_s = 0.03, δ_p = 4 δ_y, δ_pc = 8 δ_y, κ = 0.2 (units F_y0, δ_y, k = 1): elastic to (1, 1);
    # hardening 1 + 0.03 (x − 1) to the cap (5, 1.12); post-cap slope k_c = −1.12/8 = −0.14,
    # F = 1.12 − 0.14 (x − 5), down to the residual 0.2 at x_r = 5 + 0.92/0.14 = 11.5714; then 0.2.
    # No reversal, no zero crossing: the deterioration modes never act on a monotonic push.
    p = _params(gammas=gammas)
    x = np.array([0.5, 3.0, 5.0, 8.0, 11.0, 13.0, 15.0])
    force = np.array([0.5, 1.06, 1.12, 0.70, 0.28, 0.2, 0.2])
    tangent = np.array([1.0, 0.03, np.nan, -0.14, -0.14, 0.0, 0.0])  # the cap is a corner
    fine = side * np.linspace(0.0, 15.0, 151)[1:] * DY
    at = np.searchsorted(np.abs(fine), x * DY * (1 - 1e-9))
    for history, rows in ((fine, _drive(fine, p)[at]), (side * x * DY, _drive(side * x * DY, p))):
        np.testing.assert_allclose(rows[:, 0], side * force * FY, rtol=1e-12, atol=1e-12 * FY)
        ok = ~np.isnan(tangent)
        np.testing.assert_allclose(rows[ok, 1], tangent[ok] * K, rtol=1e-12, atol=1e-12 * K)
        ref, _ = _reference(history, p)
        np.testing.assert_allclose(ref[-1, 0], rows[-1, 0], rtol=1e-12)
    # work along the corners (each step straight): ½ + (1 + 1.12)/2 × 4 + (1.12 + 0.2)/2 × 6.5714
    # + 0.2 × 3.4286 = 9.762857 F_y0 δ_y; recoverable at the end 0.2²/2 = 0.02 (unloading at k)
    x_r = 5.0 + 0.92 / 0.14
    corners = side * np.array([1.0, 5.0, x_r, 15.0]) * DY
    rows = _drive(corners, p)
    w = 0.5 + 0.5 * (1.0 + 1.12) * 4.0 + 0.5 * (1.12 + 0.2) * (x_r - 5.0) + 0.2 * (15.0 - x_r)
    assert w == pytest.approx(9.762857, rel=1e-6)
    assert rows[-1, 2] == pytest.approx(w * FY * DY, rel=1e-12)
    assert rows[-1, 3] == pytest.approx(0.02 * FY * DY, rel=1e-12)
    assert _reference(corners, p)[0][-1, 2] == pytest.approx(w * FY * DY, rel=1e-12)


def test_before_any_yielding_the_story_is_linear_elastic():
    # cycles inside ±δ_y with every mode on: no energy is dissipated, nothing deteriorates
    p = _params(gammas=(5.0, 5.0, 5.0, 5.0))
    history = 0.99 * DY * np.sin(np.linspace(0.0, 12.0 * np.pi, 400)) * np.linspace(0.2, 1.0, 400)
    rows = _drive(history, p)
    np.testing.assert_allclose(rows[:, 0], K * history, rtol=0.0, atol=1e-12 * FY)
    np.testing.assert_allclose(rows[:, 1], K, rtol=1e-12)
    np.testing.assert_allclose(rows[:, 2] - rows[:, 3], 0.0, atol=1e-12 * FY * DY)


# ---------------------------------------------------------------------------------------------
# cyclic histories against the rules

# growing amplitude with partial unloadings on both sides and inner loops; past the cap (5 δ_y)
# from the fourth cycle on (units δ_y)
_HAND = [0.5, -0.3, 0.8, 2.5, 1.8, 2.2, 2.6, 1.0, -0.5, 0.2, -0.8, -3.0, -2.5, -3.5, 0.5, 0.0,
         1.5, 4.0, 3.0, 3.5, -1.0, 1.0, -6.0, -5.0, -5.5, 6.0, 2.0, 2.4, 1.0, -2.0, 0.3, 7.5, 6.0,
         -8.0, -6.5, -7.0, 3.0, 1.0, 9.0, -9.5, 4.0, -2.0, 10.0]  # fmt: skip
# (γ_s, γ_c, γ_a, γ_k), c, κ
_SETS = {
    "off": ((0.0, 0.0, 0.0, 0.0), 1.0, 0.2),
    "all_modes": ((60.0, 80.0, 100.0, 250.0), 1.0, 0.2),
    "all_modes_c1.6": ((50.0, 60.0, 70.0, 200.0), 1.6, 0.2),
    "strength_no_residual": ((60.0, 0.0, 0.0, 0.0), 1.0, 0.0),
}


@pytest.mark.parametrize("name", list(_SETS))
@pytest.mark.parametrize("per_dy", [0, 7])
def test_hand_history_with_inner_loops_equals_the_rules(name, per_dy):
    gammas, c, kappa = _SETS[name]
    p = _params(residual=kappa, gammas=gammas, c=c)
    history, turns = _aligned(piecewise(_HAND, DY, per_dy)[0], p)
    ours = _drive(history, p)
    ref, kinks = _reference(history, p)
    kinks |= turns
    np.testing.assert_allclose(ours[:, 0], ref[:, 0], rtol=0.0, atol=1e-9 * FY)
    np.testing.assert_allclose(ours[~kinks, 1], ref[~kinks, 1], rtol=1e-9, atol=1e-9 * K)
    np.testing.assert_allclose(ours[:, 2], ref[:, 2], rtol=1e-9, atol=1e-9 * FY * DY)
    np.testing.assert_allclose(ours[:, 3], ref[:, 3], rtol=1e-9, atol=1e-12 * FY * DY)
    assert ref[:, 0].max() > FY and (ref[~kinks, 1] < 0.0).any()  # on a post-cap branch


def _random_history(seed: int) -> np.ndarray:
    """A random walk with inner loops, then jumps anywhere within ±7 δ_y, then a walk again."""
    rng = np.random.default_rng(seed)
    jumps = rng.uniform(-7.0, 7.0, 60)
    walk = 7.0 * np.tanh(np.cumsum(rng.normal(0.0, 1.0, 100)) / 7.0)
    return np.concatenate((walk[:50], jumps, walk[50:])) * DY


@pytest.mark.parametrize("name", ["off", "all_modes", "all_modes_c1.6"])
@pytest.mark.parametrize("seed", [1, 2])
def test_random_large_steps_through_the_turning_points_equal_the_rules(name, seed):
    # large steps, each straight: the branch logic of a long increment, free of any question of
    # how the work of an increment with a corner inside is integrated
    gammas, c, kappa = _SETS[name]
    p = _params(residual=kappa, gammas=gammas, c=c)
    history, turns = _aligned(_random_history(seed), p)
    ours = _drive(history, p)
    ref, kinks = _reference(history, p)
    kinks |= turns
    np.testing.assert_allclose(ours[:, 0], ref[:, 0], rtol=0.0, atol=1e-9 * FY)
    np.testing.assert_allclose(ours[~kinks, 1], ref[~kinks, 1], rtol=1e-9, atol=1e-9 * K)
    np.testing.assert_allclose(ours[:, 2], ref[:, 2], rtol=1e-9, atol=1e-9 * FY * DY)
    np.testing.assert_allclose(ours[:, 3], ref[:, 3], rtol=1e-9, atol=1e-12 * FY * DY)
    assert np.abs(ref[:, 0]).max() > FY and (ref[~kinks, 1] < 0.0).any()


@pytest.mark.parametrize("name", ["off", "all_modes", "all_modes_c1.6"])
@pytest.mark.parametrize("seed", [1, 2])
def test_random_large_steps_equal_the_fine_sub_stepping(name, seed):
    # the same random history in its own large steps, corners inside them: the force and the work
    # W = ∫F dδ (on which the deterioration feeds) of the rules followed in 0.02 δ_y sub-increments
    gammas, c, kappa = _SETS[name]
    p = _params(residual=kappa, gammas=gammas, c=c)
    history = _random_history(seed)
    ours = _drive(history, p)
    ref, _ = _reference(history, p, sub=0.02)
    np.testing.assert_allclose(ours[:, 0], ref[:, 0], rtol=0.0, atol=1e-9 * FY)
    np.testing.assert_allclose(ours[:, 2], ref[:, 2], rtol=1e-9, atol=1e-9 * FY * DY)
    np.testing.assert_allclose(ours[:, 3], ref[:, 3], rtol=1e-9, atol=1e-12 * FY * DY)


# ---------------------------------------------------------------------------------------------
# deterioration and energy by hand


def test_strength_lost_in_a_constant_amplitude_cycle_by_hand():
    # ±4 δ_y, strength mode only (γ_s = 20: E_t = 20 F_y0 δ_y), c = 1, α_s = 0.03, cap at 11 δ_y
    # (units F_y0, δ_y, k = 1). To −4: F = −1.09, W = ½ + ½ (1 + 1.09) 3 = 3.635; unloading at k
    # to z+ = −2.91, where E_1 = 3.635 − 1.09²/2 = 3.04095 is all dissipated: β_1 = E_1/(20 − E_1)
    # = 0.179311, the + side keeps F_y = 1 − β_1 and α = 0.03 (1 − β_1). Reload on the line from
    # (z+, 0) to the target (1, F_t), F_t = F_y + α (1 − F_y); the envelope to 4: F_y + α (4 − F_y)
    # = 0.898966 instead of 1.09. Back to z− = 4 − F(4): E_2 = ½ F_t (1 + 2.91) + ½ (F_t + F(4)) 3
    # − F(4)²/2 = 3.795111, β_2 = E_2/(20 − E_1 − E_2) = 0.288296 for the − side; its target is −4
    # already (the first excursion): the reload line runs straight to its deteriorated envelope,
    # 0.781913 instead of 1.09.
    p = _params(plastic=10.0, post_cap=30.0, gammas=(20.0, 0.0, 0.0, 0.0))
    e_1 = 3.635 - 1.09**2 / 2.0
    b_1 = e_1 / (20.0 - e_1)
    assert b_1 == pytest.approx(0.179311, abs=1e-6)
    fy, al = 1.0 - b_1, 0.03 * (1.0 - b_1)
    f_t = fy + al * (1.0 - fy)
    f_4 = fy + al * (4.0 - fy)
    assert f_4 == pytest.approx(0.898966, abs=1e-6)
    e_2 = 0.5 * f_t * (1.0 + 2.91) + 0.5 * (f_t + f_4) * 3.0 - f_4**2 / 2.0
    b_2 = e_2 / (20.0 - e_1 - e_2)
    fy2, al2 = 1.0 - b_2, 0.03 * (1.0 - b_2)
    z_neg = 4.0 - f_4
    f_neg = fy2 + al2 * (4.0 - fy2)
    assert (e_2, b_2, f_neg) == pytest.approx((3.795111, 0.288296, 0.781913), abs=1e-6)
    vertices = [-1.0, -4.0, -2.91, 1.0, 4.0, z_neg, -1.0, -4.0]  # each step straight
    forces = [-1.0, -1.09, 0.0, f_t, f_4, 0.0, -f_neg * (z_neg + 1.0) / (z_neg + 4.0), -f_neg]
    for per_dy in (0, 20):
        history, ends = piecewise(vertices, DY, per_dy)
        rows = _drive(history, p)
        np.testing.assert_allclose(rows[ends, 0], np.array(forces) * FY, rtol=1e-12, atol=1e-9 * FY)
        assert rows[ends[2], 2] == pytest.approx(e_1 * FY * DY, rel=1e-12)  # W at the crossings
        assert rows[ends[5], 2] == pytest.approx((e_1 + e_2) * FY * DY, rel=1e-12)
        ref, _ = _reference(history, p)
        np.testing.assert_allclose(ref[ends, 0], rows[ends, 0], rtol=1e-12, atol=1e-9 * FY)


def test_reload_after_an_inner_cycle_runs_through_the_local_peak_by_hand():
    # no deterioration, α_s = 0.03, cap at 11 δ_y (units F_y0, δ_y, k = 1), vertices
    # 4, −2, 3, −1.5, 3, 3.5, 4.5. To 4: 1.09; to −2: unload to 2.91, reload to the yield point
    # (−1, −1), then the backbone: −1.03. To 3: unload to −0.97, reload toward (4, 1.09):
    # 1.09 × 3.97/4.97 = 0.870684, where the + side's unloading begins below its target: its local
    # peak. To −1.5: unload to z = 3 − 0.870684, reload toward (−2, −1.03): −0.905282. To 3: unload
    # to z = −1.5 + 0.905282; the line to the local peak, slope 0.870684/(3 − z) = 0.242213, is
    # steeper than the line to the target, 1.09/(4 − z) = 0.237228: the reload runs through
    # (3, 0.870684), then on to (4, 1.09): 0.980342 at 3.5 (0.971381 on the straight line, as
    # ModIMKPeakOriented's "towards local peak"), the backbone 1.105 at 4.5.
    p = _params(plastic=10.0, post_cap=30.0)
    f_3 = 1.09 * 3.97 / 4.97
    z_1 = 3.0 - f_3
    f_m = -1.03 * (z_1 + 1.5) / (z_1 + 2.0)
    z_2 = -1.5 - f_m
    assert (f_3, f_m) == pytest.approx((0.870684, -0.905282), abs=1e-6)
    assert f_3 / (3.0 - z_2) > 1.09 / (4.0 - z_2)
    f_35 = f_3 + 0.5 * (1.09 - f_3)
    assert f_35 == pytest.approx(0.980342, abs=1e-6)
    forces = [1.09, -1.03, f_3, f_m, f_3, f_35, 1.105]
    for per_dy in (0, 20):
        history, ends = piecewise([4.0, -2.0, 3.0, -1.5, 3.0, 3.5, 4.5], DY, per_dy)
        rows = _drive(history, p)
        np.testing.assert_allclose(rows[ends, 0], np.array(forces) * FY, rtol=1e-12)
        assert rows[ends[5], 1] == pytest.approx((1.09 - f_3) * K, rel=1e-12)
        ref, _ = _reference(history, p)
        np.testing.assert_allclose(ref[ends, 0], rows[ends, 0], rtol=1e-12)


def test_unloading_stiffness_lost_below_the_secant_to_the_target_unloads_along_it_by_hand():
    # unloading-stiffness mode only (γ_k = 5, c = 1), α_s = 0.03, cap at 11 δ_y (units F_y0, δ_y,
    # k = 1). To 3: F = 1.06, W = ½ + ½ (1 + 1.06) 2 = 2.56, E = 1.06²/2: e = 1.9982 dissipated,
    # β_k = e/(5 − e) = 0.665668, K_u would be 0.334332. The line from (3, 1.06) to the target
    # (−1, −1) is steeper, 2.06/4 = 0.515: at the lower K_u the zero-force drift (−0.170) would lie
    # past it and every later cycle would run backwards. K_u = 0.515 instead: the story unloads
    # straight to (−1, −1) (−0.485 at 0), then follows the backbone (−1.03 at −2).
    p = _params(plastic=10.0, post_cap=30.0, gammas=(0.0, 0.0, 0.0, 5.0))
    e = 2.56 - 1.06**2 / 2.0
    assert 1.0 - e / (5.0 - e) == pytest.approx(0.334332, abs=1e-6)
    for per_dy in (0, 20):
        history, ends = piecewise([3.0, 0.0, -1.0, -2.0], DY, per_dy)
        rows = _drive(history, p)
        np.testing.assert_allclose(
            rows[ends, 0], np.array([1.06, -0.485, -1.0, -1.03]) * FY, rtol=1e-12
        )
        assert rows[ends[1], 1] == pytest.approx(0.515 * K, rel=1e-12)
        ref, _ = _reference(history, p)
        np.testing.assert_allclose(ref[ends, 0], rows[ends, 0], rtol=1e-12)


@pytest.mark.parametrize(
    "gammas", [(0.0, 0.0, 0.0, 12.0), (60.0, 60.0, 0.0, 12.0), (100.0, 100.0, 100.0, 12.0)]
)
def test_cycles_past_the_unloading_stiffness_floor_never_generate_energy(gammas):
    # eight ±4 δ_y cycles with a fast unloading-stiffness deterioration: each cycle's work ∮F dδ
    # (the exact path work at the cycle ends) is ≥ 0; unbounded, K_u fell to 0.22 k, below the
    # 0.36 k of the reload lines, and each cycle returned 1.77 F_y δ_y
    p = _params(plastic=10.0, post_cap=30.0, gammas=gammas)
    history, ends = piecewise(np.tile([4.0, -4.0], 8), DY, 10)
    rows = _drive(history, p)
    work = rows[ends[1::2], 2]
    assert np.all(np.diff(work) >= -1e-9 * FY * DY)
    ref, _ = _reference(history, p)
    np.testing.assert_allclose(ref[:, 0], rows[:, 0], rtol=1e-9, atol=1e-9 * FY)


def test_a_spent_strength_capacity_fails_the_story():
    # γ_s = 12: E_t = 12 F_y0 δ_y is spent within a few ±4 δ_y cycles; from the crossing where
    # β_s reaches 1 the story carries no force and has no stiffness, whatever the drift does
    p = _params(plastic=10.0, post_cap=30.0, gammas=(12.0, 0.0, 0.0, 0.0))
    history, turns = _aligned(np.tile([4.0, -4.0], 6) * DY, p)
    ours = _drive(history, p)
    ref, kinks = _reference(history, p)
    np.testing.assert_allclose(ours[:, 0], ref[:, 0], rtol=0.0, atol=1e-9 * FY)
    np.testing.assert_allclose(ours[:, 2], ref[:, 2], rtol=1e-9)
    spring, i = _IMK(p), 0
    while not spring.failed:
        spring.step(history[i])
        i += 1
    i -= 1  # the step that failed it
    assert 4 < i < history.size - 4  # after a few cycles, before the end
    assert not np.any(ours[i:, 0]) and not np.any(ours[i + 1 :, 1])
    assert np.abs(ours[:i, 0]).max() > FY


@pytest.mark.parametrize("gammas", [(12.0, 0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 6.0)])
def test_the_failure_ahead_is_the_crossing_or_reversal_where_the_kernel_fails_the_story(gammas):
    # a strength capacity is spent at a zero-force crossing, an unloading-stiffness one at a
    # reversal: before every step, imk_failure_ahead names where the coming motion fails the story
    # (the start of the motion, or the crossing drift z), and the step fails it exactly when it
    # starts there or reaches z
    p = _params(plastic=10.0, post_cap=30.0, gammas=gammas)
    history, _ = piecewise(np.tile([4.0, -4.0], 8), DY, 10)
    s0, s1 = np.zeros(N_STORY_STATE), np.zeros(N_STORY_STATE)
    failed_at = None
    for j, d in enumerate(history):
        m = 1.0 if d > s0[SS_D] else -1.0
        now, z = imk_failure_ahead(s0, p, m)
        imk_story_kernel(d, 0.0, 3.0, s0, s1, p)
        reaches = math.isfinite(z) and m * (d - z) >= 0.0
        assert bool(s1[SS_FAILED]) == (now or reaches), j
        if s1[SS_FAILED] and failed_at is None:
            failed_at = (j, now, z)
        s0[:] = s1
    assert failed_at is not None and 20 < failed_at[0] < history.size - 20
    assert failed_at[1] == (gammas[3] > 0.0)  # at a reversal, or at a crossing z
    assert math.isfinite(failed_at[2]) == (gammas[0] > 0.0)


_CYCLES = [6.0, -6.0, 6.0, -6.0, 2.0, 4.0, -1.0, 6.0, -6.0, 6.0]  # units δ_y
_CYCLE_ENDS = [0, 2, 7, 9]  # back at +6 δ_y after each closed cycle


@functools.cache
def _loop_areas(gammas: tuple) -> np.ndarray:
    """Hysteretic energy of the rules at the cycle ends: the trapezoid ∫F dδ of the reference's
    forces on a 1/500 δ_y history, less the recoverable F²/(2 K_u)."""
    fine, ends = piecewise(_CYCLES, DY, 500)
    ref, _ = _reference(fine, _params(gammas=gammas), kinks=False)
    return (_trapezoid(fine, ref[:, 0]) - ref[:, 3])[ends[_CYCLE_ENDS]]


@pytest.mark.parametrize("steps", ["turning_points", "vertices"])
@pytest.mark.parametrize("gammas", [(0.0, 0.0, 0.0, 0.0), (40.0, 40.0, 40.0, 150.0)])
def test_closed_cycles_dissipate_the_loop_area_of_the_rules(steps, gammas):
    # three cycles ±6 δ_y (past the cap), one with an inner loop: the kernel's W − E at the end of
    # each cycle against the loop areas of the rules; the kernel driven in one step per vertex, or
    # with the turning points of the rules inserted (every step straight)
    history = np.array(_CYCLES) * DY
    vertex = np.arange(history.size)
    if steps == "turning_points":
        history, turns = _aligned(history, _params(gammas=gammas))
        vertex = np.flatnonzero(~turns)
    rows = _drive(history, _params(gammas=gammas))
    expected = _loop_areas(gammas)
    np.testing.assert_allclose((rows[:, 2] - rows[:, 3])[vertex[_CYCLE_ENDS]], expected, rtol=1e-6)
    assert np.all(np.diff(expected) > 2.0 * FY * DY)  # fat loops


# ---------------------------------------------------------------------------------------------
# a building


class _StoryEvents:
    """Discrete memory of one story of the event-driven reference: an :class:`_IMK` spring
    committed at the last event, the direction the drift moves in and the next drift where the
    force path turns; the force itself is an ODE state with Ḟ = slope δ̇ in between."""

    def __init__(self, p: np.ndarray):
        self.spring = _IMK(p, sub=math.inf)
        self.m = 0  # 0 before the first yield: elastic both ways up to ±δ_y, no memory
        self.slope, self.turn = self.spring.k, math.inf

    def plan(self) -> None:
        """Slope and next turning point of an increment from the committed state in direction m
        (steps 1-2 of a reversal applied to a copy)."""
        s, m = self.spring.copy(), self.m
        d0, f0 = s.d, s.f
        s._begin(m)
        assert not s.failed
        cuts = [s.z[m], s.t[m], *(x for x in s.corners(m) if m * x > m * s.t[m]), *s.meets(m)]
        ahead = [x for x in cuts if m * (x - d0) > 1e-9 * s.dy]
        self.turn = min(ahead, key=lambda x: m * x) if ahead else m * math.inf
        probe = self.spring.copy()
        x = d0 + m * min(abs(self.turn - d0) / 2.0, s.dy)
        probe._increment(x)
        self.slope = (probe.f - f0) / (x - d0)

    def event(self, kind: str, d: float) -> float:
        """Commit the spring at an event of this story; the force to restart from."""
        if kind == "yield":  # from the origin straight to the yield point: elastic, no memory
            self.m = 1 if d > 0.0 else -1
            self.spring._increment(self.m * self.spring.dy)
        elif kind == "turn":
            self.spring._increment(self.turn)
        else:  # the drift reverses
            if self.m * (d - self.spring.d) > 0.0:
                self.spring._increment(d)
            self.m = -self.m
        self.plan()
        return self.spring.f

    def events(self, i: int, n: int) -> list:
        """(g(y), direction, kind) of story i's possible events."""

        def drift(y):
            return y[i] - (y[i - 1] if i else 0.0)

        dy, m = self.spring.dy, self.m
        if m == 0:
            return [
                (lambda y: drift(y) - dy, 1.0, "yield"),
                (lambda y: drift(y) + dy, -1.0, "yield"),
            ]
        out = [(lambda y: y[n + i] - (y[n + i - 1] if i else 0.0), -m, "reverse")]
        if math.isfinite(self.turn):
            out.append((lambda y: drift(y) - self.turn, m, "turn"))
        return out


def _event_driven_reference(building, c, gm: GroundMotion, duration: float, wall_k, gap):
    """Independent solve_ivp of an IMK-story building against a Hertz wall, restarted at every
    drift reversal and turning point of the rules: state (u, v, F) with Ḟ = slope δ̇."""
    n = building.n_floors
    m = building.masses
    stories = [_StoryEvents(row) for row in building.story_parameters()]
    slopes = np.array([st.slope for st in stories])
    t_rec = gm.dt * np.arange(gm.acceleration.size)
    grid = np.arange(0.0, duration + 1e-12, 0.01)

    def rhs(t, y):
        u, v, f = y[:n], y[n : 2 * n], y[2 * n :]
        dv = np.diff(np.concatenate(([0.0], v)))
        internal = f - np.append(f[1:], 0.0)
        pen = u[-1] - gap
        contact = np.zeros(n)
        if pen > 0.0:
            contact[-1] = wall_k * pen**1.5
        a = (-internal - c @ v - contact) / m - np.interp(t, t_rec, gm.acceleration)
        return np.concatenate((v, a, slopes * dv))

    t0, y0 = 0.0, np.zeros(3 * n)
    ts, ys, restarts = [], [], 0
    while True:
        events, owner = [], []
        for i, st in enumerate(stories):
            for g, direction, kind in st.events(i, n):

                def event(t, y, g=g):
                    return g(y)

                event.terminal, event.direction = True, direction
                events.append(event)
                owner.append((i, kind))
        t_eval = grid[grid > t0] if t0 > 0.0 else grid
        sol = solve_ivp(rhs, (t0, duration), y0, method="DOP853", t_eval=t_eval, events=events,
                        rtol=1e-10, atol=1e-13, max_step=1e-3)  # fmt: skip
        assert sol.status >= 0, sol.message
        if len(sol.t):
            ts.append(sol.t)
            ys.append(sol.y.T)
        if sol.status == 0:
            break
        j = next(j for j, te in enumerate(sol.t_events) if te.size)
        t0, y0 = float(sol.t_events[j][0]), sol.y_events[j][0].copy()
        i, kind = owner[j]
        d = y0[i] - (y0[i - 1] if i else 0.0)
        f = stories[i].event(kind, d)
        assert abs(f - y0[2 * n + i]) < 1e-6 * stories[i].spring.fy0  # the slopes were right
        y0[2 * n + i] = f
        slopes[i] = stories[i].slope
        restarts += 1
    t = np.concatenate(ts)
    assert np.allclose(t, grid)
    y = np.concatenate(ys)
    return y[:, :n], y[:, 2 * n :], stories, restarts


def test_imk_building_pounding_on_a_wall_matches_an_independent_event_driven_solve_ivp():
    params = {"yield_drift": 0.004, "hardening": 0.03, "plastic_drift": 0.02,
              "post_cap_drift": 0.08, "residual": 0.2, "gamma_s": 25, "gamma_c": 25,
              "gamma_a": 25, "gamma_k": 60, "c": 1.0}  # fmt: skip
    building = ShearBuilding.uniform("A", 3, period=0.4, mass=2.0e5, stories=Stories("imk", params))
    gap, wall_k = 0.02, 2.0e9
    system = assemble(
        [building], [Contact("A", "wall", gap=gap, law="hertz", k=wall_k, floors=[3])]
    )
    gm = sine_pulse(amplitude=0.6 * 9.80665, period=0.6, duration=3.0, dt=0.002)
    ds = simulate(system, gm, dt=2e-4, output_dt=0.01, duration=3.0)
    u_ref, f_ref, stories, restarts = _event_driven_reference(
        building, system.damping, gm, 3.0, wall_k, gap
    )
    u = ds.displacement.sel(building="A").values
    f = ds.story_spring_force.sel(building="A").values
    assert restarts > 10
    assert int(ds.impact_count.sum()) >= 1
    assert float(ds.story_ductility.max()) > 2.0
    first = stories[0].spring  # the deterioration shows: strength and unloading stiffness lost
    assert max(first.ds.values()) > 0.05 and first.dk > 0.02
    assert np.abs(u - u_ref).max() < 0.01 * np.abs(u_ref).max()
    assert np.abs(f - f_ref).max() < 0.01 * np.abs(f_ref).max()
    np.testing.assert_allclose(np.abs(u).max(axis=0), np.abs(u_ref).max(axis=0), rtol=5e-3)
    np.testing.assert_allclose(
        ds.peak_story_spring_force.sel(building="A"), np.abs(f_ref).max(axis=0), rtol=5e-3
    )
    assert float(ds.energy.sel(term="hysteretic")[-1]) > 0.0
    assert ds.attrs["energy_balance_error"] < 5e-3


def _collapse_building(deteriorating: bool, p_delta: bool) -> ShearBuilding:
    params = {"yield_drift": 0.005, "hardening": 0.03, "plastic_drift": 0.02,
              "post_cap_drift": 0.08, "residual": 0.2}  # fmt: skip
    if deteriorating:  # small capacities: a few cycles spend them
        params |= {"gamma_s": 8, "gamma_c": 8, "gamma_a": 8, "gamma_k": 20}
    stories = Stories("imk", params)
    return ShearBuilding.uniform("A", 3, period=0.6, mass=2.0e5, stories=stories, p_delta=p_delta)


def test_deteriorating_building_with_p_delta_collapses_under_a_long_pulse_and_the_run_stops():
    gm = sine_pulse(amplitude=0.3 * 9.80665, period=1.0, duration=6.0, dt=0.005)
    opts = dict(output_dt=0.01, collapse_drift=0.08)
    ds = simulate(assemble([_collapse_building(True, True)]), gm, **opts)
    t_c = float(ds.collapse_time.sel(building="A"))
    assert 0.5 < t_c < 3.0
    assert float(ds.peak_drift_ratio.max()) >= 0.08
    after = ds.time > t_c + 0.02
    assert bool(np.isnan(ds.displacement.where(after, drop=True)).all())
    assert not bool(np.isnan(ds.displacement.where(ds.time < t_c, drop=True)).any())
    summary = ds.pounding.summary()
    assert summary["buildings"]["A"]["collapse_time"] == pytest.approx(t_c)
    assert any("beyond [analysis] collapse_drift = 0.08" in w for w in summary["warnings"])
    # the same building and pulse, without P-Δ and without deterioration: well short of it
    intact = simulate(assemble([_collapse_building(False, False)]), gm, **opts)
    assert np.isnan(float(intact.collapse_time.sel(building="A")))
    assert float(intact.peak_drift_ratio.max()) < 0.05
    assert not bool(np.isnan(intact.displacement).any())
    assert float(intact.story_ductility.max()) > 3.0  # yet well past yield


@pytest.mark.parametrize("options", [{"dt": 5e-3}, {"dt": 1e-3}, {"method": "ivp"}])
def test_stories_spent_at_their_reversal_end_the_run_as_a_collapse_at_any_step(options):
    # a stiff 3-story building (T1 0.05 s) yielding at 1e-5 drift with γ = 30 for the four modes:
    # the 0.3 g pulse drives every story to 18-107 δ_y, and its capacity is spent at the reversal
    # there (K_u deteriorated to nothing: the force would drop from 1.5-4.2 F_y to zero). At
    # dt = 5 ms Newton cannot take that drop; at 1 ms it can; the ivp integration stops at the
    # reversal event. Each way the building has lost its stories: a collapse at the same time,
    # the rows after it NaN, not a ConvergenceError.
    params = {"yield_drift": 1e-5, **{f"gamma_{m}": 30.0 for m in "scak"}}
    building = ShearBuilding.uniform("A", 3, period=0.05, mass=2e5, stories=Stories("imk", params))
    gm = sine_pulse(amplitude=0.3 * 9.80665, period=0.6, duration=1.0, dt=0.005)
    ds = simulate(assemble([building]), gm, output_dt=0.01, duration=1.0, **options)
    t_c = float(ds.collapse_time.sel(building="A"))
    assert t_c == pytest.approx(0.20503, abs=5e-5 if "method" in options else options["dt"])
    summary = ds.pounding.summary()
    assert summary["buildings"]["A"]["collapse_time"] == pytest.approx(t_c)
    assert any("energy capacity spent" in w for w in summary["warnings"])
    assert bool(np.isnan(ds.displacement.where(ds.time > t_c + 0.01, drop=True)).all())
    assert float(ds.story_ductility.max()) > 100.0


def test_strength_spent_at_a_zero_force_crossing_ends_both_integrators_at_that_crossing():
    # γ_s = 10 only (the unloading stiffness keeps k): a 0.25 g harmonic at 0.4 s spends the
    # strength capacity of a story at a zero-force crossing, where its force is zero anyway; the
    # story has no strength left, the building collapses there. Newmark at dt 1e-4 ends in the
    # step holding the crossing, the ivp integration at the located crossing.
    params = {"yield_drift": 0.002, "gamma_s": 10.0, "plastic_drift": 0.05}
    building = ShearBuilding.uniform("A", 3, period=0.3, mass=2e5, stories=Stories("imk", params))
    system = assemble([building])
    gm = harmonic(amplitude=0.25 * 9.80665, period=0.4, duration=4.0, dt=0.005)
    fixed = simulate(system, gm, dt=1e-4, output_dt=0.01, duration=4.0)
    events = simulate(system, gm, method="ivp", output_dt=0.01, duration=4.0)
    t_n = float(fixed.collapse_time.sel(building="A"))
    t_e = float(events.collapse_time.sel(building="A"))
    assert 2.0 < t_e < 3.5 and t_e <= t_n < t_e + 1.0001e-4
    for ds, t_c in ((fixed, t_n), (events, t_e)):
        before = ds.story_spring_force.where(ds.time < t_c, drop=True)
        assert float(np.abs(before).max()) > 3e5 and not bool(np.isnan(before).any())
        assert bool(np.isnan(ds.displacement.where(ds.time > t_c + 0.01, drop=True)).all())
    assert float(events.story_ductility.max()) == pytest.approx(
        float(fixed.story_ductility.max()), rel=1e-3
    )


# ---------------------------------------------------------------------------------------------
# the case file


def test_imk_case_file_drifts_become_metres_and_the_defaults():
    stories = {"model": "imk", "yield_drift": 0.004, "plastic_drift": [0.02, 0.03],
               "post_cap_drift": 0.08, "gamma_s": 50}  # fmt: skip
    spec = {"name": "A", "n_floors": 2, "period": 0.3, "mass": 1e5, "height": 3.5,
            "stories": stories}  # fmt: skip
    case = case_from_dict({"building": [spec], "ground_motion": {"type": "sine_pulse"}})
    b = case.system.buildings[0]
    assert b.stories.model == "imk"
    p = b.story_parameters()
    np.testing.assert_allclose(p[:, 1], b.stiffnesses * 0.004 * 3.5)
    np.testing.assert_allclose(p[:, 3], [0.02 * 3.5, 0.03 * 3.5])  # δ_p = θ_p h
    np.testing.assert_allclose(p[:, 4], [0.08 * 3.5, 0.08 * 3.5])  # δ_pc = θ_pc h
    # α_s = 0.03, κ = 0.2, γ_c = γ_a = γ_k = 0 (off), c = 1 by default
    np.testing.assert_allclose(p[0, [2, 5, 6, 7, 8, 9, 10]], [0.03, 0.2, 50, 0, 0, 0, 1.0])
    assert not np.any(p[:, 11:])


@pytest.mark.parametrize(
    "extra, message",
    [
        ({"post_cap_drift": 0}, "stories.post_cap_drift[0] = 0"),
        ({"residual": 1.5}, "stories.residual[0] = 1.5; allowed: 0 to 1"),
        ({"theta_p": 0.02}, "stories.theta_p: not a parameter of the 'imk' story model"),
    ],
)
def test_inconsistent_imk_tables_are_refused_naming_the_key(extra, message):
    stories = {"model": "imk", "yield_drift": 0.004, **extra}
    spec = {"name": "A", "n_floors": 2, "period": 0.3, "mass": 1e5, "stories": stories}
    with pytest.raises(CaseError, match="building") as err:
        case_from_dict({"building": [spec], "ground_motion": {"type": "sine_pulse"}})
    assert message in str(err.value)
