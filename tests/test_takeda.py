"""Modified Takeda (Clough at a = 0) story springs: the kernel against an independent rule-by-rule
implementation on hand-made and random drift histories, a hand-computed Clough cycle, the unloading
slope k μ^(−a), the loop area, an independent event-driven solve_ivp of a 3-storey Takeda building
pounding on a wall, the elastic limit and the case file."""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest
from _histories import piecewise
from scipy.integrate import solve_ivp

from pounding import simulate
from pounding.case import CaseError, case_from_dict
from pounding.ground_motion import GroundMotion, sine_pulse
from pounding.stories import (
    N_STORY_PARAMS,
    N_STORY_STATE,
    SS_E,
    SS_F,
    SS_W,
    Stories,
    takeda_story_kernel,
)
from pounding.structure import ShearBuilding
from pounding.system import Contact, assemble


def _drive(history: np.ndarray, k: float, fy: float, b: float, a: float) -> np.ndarray:
    """Run the kernel along a drift history; rows (F, tangent, W, E)."""
    p = np.array([k, fy, b, a, *np.zeros(N_STORY_PARAMS - 4)])
    s0, s1 = np.zeros(N_STORY_STATE), np.zeros(N_STORY_STATE)
    out = []
    for d in history:
        corr, dk, _ = takeda_story_kernel(d, 0.0, 0.01, s0, s1, p)
        assert corr == pytest.approx(s1[SS_F] - k * d, abs=1e-12 * fy)
        out.append((s1[SS_F], dk + k, s1[SS_W], s1[SS_E]))
        s0[:] = s1
    return np.array(out)


class _Takeda:
    """Independent modified Takeda spring, written from the rules: each drift increment is applied
    in sub-increments of at most ``sub`` δ_y, so every branch change is followed incrementally.
    Memory: peaks dp ≥ δ_y, dn ≤ −δ_y, zero-force points zp, zn, the last motion (±1, 0)."""

    def __init__(self, k: float, fy: float, b: float, a: float, sub: float = 0.05):
        self.k, self.fy, self.b, self.a = k, fy, b, a
        self.dy = fy / k
        self.sub = sub
        self.d = self.f = 0.0
        self.dp, self.dn = self.dy, -self.dy
        self.zp = self.zn = 0.0
        self.motion = 0
        self.slope = k  # of the branch that gave the last force

    def env(self, d: float) -> float:
        if abs(d) <= self.dy:
            return self.k * d
        return math.copysign(self.fy + self.b * self.k * (abs(d) - self.dy), d)

    def k_up(self) -> float:
        return self.k * (self.dp / self.dy) ** -self.a

    def k_un(self) -> float:
        return self.k * (-self.dn / self.dy) ** -self.a

    def line_slope(self, direction: int) -> float:
        """Slope of L+ (through (zp, 0) and the positive peak) or L− (zn, the negative peak)."""
        if direction > 0:
            return self.env(self.dp) / (self.dp - self.zp)
        return self.env(self.dn) / (self.dn - self.zn)

    def line(self, d: float, direction: int) -> float:
        return self.line_slope(direction) * (d - (self.zp if direction > 0 else self.zn))

    def recoverable(self) -> float:
        return 0.5 * self.f**2 / (self.k_up() if self.f > 0.0 else self.k_un())

    def _increment(self, d: float) -> None:
        d0, f0 = self.d, self.f
        if d > d0:
            if self.motion <= 0 and f0 <= 0.0:  # a reversal at zero or negative force
                self.zp = d0 - f0 / self.k_un()
            if d >= self.dp:  # the backbone, the peak follows
                f, s = self.env(d), self.b * self.k
                self.dp = d
            elif f0 < 0.0 and d < self.zp:  # unloading the negative side
                f, s = f0 + self.k_un() * (d - d0), self.k_un()
            elif f0 <= 0.0:  # reload from (zp, 0) toward the positive peak
                f, s = self.line(d, 1), self.line_slope(1)
            else:  # inner reload at k_up until it meets L+
                inner, line = f0 + self.k_up() * (d - d0), self.line(d, 1)
                f, s = (inner, self.k_up()) if inner < line else (line, self.line_slope(1))
            self.motion = 1
        elif d < d0:
            if self.motion >= 0 and f0 >= 0.0:
                self.zn = d0 - f0 / self.k_up()
            if d <= self.dn:
                f, s = self.env(d), self.b * self.k
                self.dn = d
            elif f0 > 0.0 and d > self.zn:
                f, s = f0 + self.k_up() * (d - d0), self.k_up()
            elif f0 >= 0.0:
                f, s = self.line(d, -1), self.line_slope(-1)
            else:
                inner, line = f0 + self.k_un() * (d - d0), self.line(d, -1)
                f, s = (inner, self.k_un()) if inner > line else (line, self.line_slope(-1))
            self.motion = -1
        else:
            return
        self.d, self.f, self.slope = d, f, s

    def step(self, d: float) -> None:
        d0 = self.d
        n = max(1, math.ceil(abs(d - d0) / (self.sub * self.dy)))
        for j in range(1, n):
            self._increment(d0 + (d - d0) * j / n)
        self._increment(d)

    def at_kink(self) -> bool:
        """True when the force's slope just after δ (continuing the motion) is not the slope of
        the branch that reached δ: a corner, where either tangent is right."""
        if self.motion == 0:
            return False
        ahead = copy.copy(self)
        eps = 1e-7 * self.dy * self.motion
        ahead._increment(self.d + eps)
        return abs((ahead.f - self.f) / eps - self.slope) > 1e-5 * self.k


def _reference(
    history: np.ndarray, k: float, fy: float, b: float, a: float, kinks: bool = True
) -> tuple:
    """Rows (F, tangent, E) of the reference along a history, and a mask of the kinks."""
    spring = _Takeda(k, fy, b, a)
    rows, at_kink = [], []
    for d in history:
        spring.step(d)
        rows.append((spring.f, spring.slope, spring.recoverable()))
        at_kink.append(kinks and spring.at_kink())
    return np.array(rows), np.array(at_kink)


def test_clough_cycle_by_hand():
    # a = 0, b = 0, k = F_y = 1 (δ_y = 1): yield to (3, 1); unload at k to zero force at z− = 2;
    # reload on L− from (2, 0) toward the negative yield point (−1, −1) (slope 1/3: F(0) = −2/3);
    # on the backbone to (−3, −1); unload at k to z+ = −3 + 1/k = −2; reload on L+ from (−2, 0) to
    # the peak (3, 1) (slope 1/5: F(0) = 0.4). Work to (3, 1): ½ + 2 = 2.5; around the loop (3, 1),
    # (2, 0), (−1, −1), (−3, −1), (−2, 0): −½ + 1.5 + 2 − ½ + 2.5 = 5.0 (its shoelace area);
    # hysteretic energy at the end W − F²/(2k) = 7.5 − 0.5 = 7.0
    vertices = [3.0, 2.0, 0.0, -1.0, -3.0, -2.0, 0.0, 3.0]
    forces = [1.0, 0.0, -2.0 / 3.0, -1.0, -1.0, 0.0, 0.4, 1.0]
    history, ends = piecewise(vertices, 1.0, per_dy=100)
    rows = _drive(history, 1.0, 1.0, 0.0, 0.0)
    np.testing.assert_allclose(rows[ends, 0], forces, rtol=0.0, atol=1e-12)
    assert rows[ends[0], 2] == pytest.approx(2.5, rel=1e-12)
    assert rows[-1, 2] - rows[ends[0], 2] == pytest.approx(5.0, rel=1e-12)
    assert rows[-1, 2] - rows[-1, 3] == pytest.approx(7.0, rel=1e-12)
    # tangents away from the corners: the backbone, L− and L+
    np.testing.assert_allclose(rows[ends[[0, 2, 6]], 1], [0.0, 1.0 / 3.0, 0.2], rtol=1e-12)
    # one step per segment lands on the same forces
    coarse = _drive(np.array(vertices), 1.0, 1.0, 0.0, 0.0)
    np.testing.assert_allclose(coarse[:, 0], forces, rtol=0.0, atol=1e-12)


# partial unloadings on both sides, inner reloads meeting the reload line and the peak, elastic
# cycles first, then reversals beyond the peaks (units δ_y)
_HAND = [0.5, -0.3, 0.8, 2.5, 1.8, 2.2, 2.6, 1.0, -0.5, 0.2, -0.8, -3.0, -2.5, -3.5, 0.5, 0.0,
         1.5, 4.0, 3.0, 3.5, -1.0, 1.0, -6.0, -5.0, -5.5, 6.0, 2.0, 2.4, 1.0, -2.0, 0.3]  # fmt: skip


@pytest.mark.parametrize("a, b", [(0.4, 0.05), (0.0, 0.0), (0.6, 0.02)])
@pytest.mark.parametrize("per_dy", [0, 7, 50])
def test_hand_history_with_inner_loops_equals_the_rules(a, b, per_dy):
    k, fy = 2.0e7, 3.0e4
    history, _ = piecewise(_HAND, fy / k, per_dy)
    ours = _drive(history, k, fy, b, a)
    ref, kinks = _reference(history, k, fy, b, a)
    np.testing.assert_allclose(ours[:, 0], ref[:, 0], rtol=0.0, atol=1e-9 * fy)
    np.testing.assert_allclose(ours[~kinks, 1], ref[~kinks, 1], rtol=1e-12, atol=1e-12 * k)
    np.testing.assert_allclose(ours[:, 3], ref[:, 2], rtol=1e-9, atol=1e-12 * fy * fy / k)


@pytest.mark.parametrize("a, b", [(0.4, 0.05), (0.0, 0.0), (0.6, 0.02), (0.4, 0.3)])
@pytest.mark.parametrize("seed", [1, 2])
def test_random_histories_with_large_steps_equal_the_rules(a, b, seed):
    k, fy = 2.0e7, 3.0e4
    dy = fy / k
    rng = np.random.default_rng(seed)
    jumps = rng.uniform(-8.0, 8.0, 150)  # anywhere within ±8 δ_y at each step
    walk = 8.0 * np.tanh(np.cumsum(rng.normal(0.0, 1.2, 250)) / 8.0)  # inner loops
    history = np.concatenate((walk[:100], jumps, walk[100:])) * dy
    ours = _drive(history, k, fy, b, a)
    ref, kinks = _reference(history, k, fy, b, a)
    np.testing.assert_allclose(ours[:, 0], ref[:, 0], rtol=0.0, atol=1e-9 * fy)
    assert kinks.sum() < 5
    np.testing.assert_allclose(ours[~kinks, 1], ref[~kinks, 1], rtol=1e-12, atol=1e-12 * k)
    assert np.abs(ours[:, 0]).max() >= fy * (1.0 + 5.0 * b)  # beyond 6 δ_y on the backbone


@pytest.mark.parametrize("side", [1.0, -1.0])
def test_unloading_slope_after_a_peak_of_mu_yield_drifts_is_k_mu_to_the_minus_a(side):
    k, fy, a, mu = 1.0e7, 1.0e4, 0.4, 4.0
    dy = fy / k
    history = side * dy * np.array([1.0, 2.0, 3.0, mu, mu - 0.01, mu - 0.02])
    rows = _drive(history, k, fy, 0.05, a)
    measured = (rows[-1, 0] - rows[-2, 0]) / (history[-1] - history[-2])
    assert measured == pytest.approx(k * mu**-a, rel=1e-10)
    assert rows[-1, 1] == pytest.approx(k * mu**-a, rel=1e-12)
    assert rows[-3, 1] == pytest.approx(0.05 * k, rel=1e-12)  # on the backbone at the peak
    # the recoverable energy F²/(2 k_u) at the peak: the force the unloading line gives up
    f_peak = fy * (1.0 + 0.05 * (mu - 1.0))
    assert rows[-3, 3] == pytest.approx(f_peak**2 / (2.0 * k * mu**-a), rel=1e-12)


def test_cycles_dissipate_the_loop_area_of_the_rules():
    # after the first excursion to ±4 δ_y the cycle ±4 δ_y is a parallelogram with corners at the
    # peaks (±4, ±F_p) and the zero-force points ±(4 − F_p/k_u): area F_p (8 δ_y − 2 F_p/k_u)
    k, fy, b, a = 1.0e7, 1.0e4, 0.05, 0.4
    dy = fy / k
    vertices = [4.0, -4.0, 4.0, -4.0, 4.0, 2.5, 3.2, -1.0, 0.5, -4.0, 4.0]
    history, ends = piecewise(vertices, dy, 500)
    ours = _drive(history, k, fy, b, a)
    ref, _ = _reference(history, k, fy, b, a, kinks=False)
    np.testing.assert_allclose(ours[:, 0], ref[:, 0], rtol=0.0, atol=1e-9 * fy)
    i0, i1, i2 = ends[2], ends[4], ends[-1]  # at 4 δ_y after the first, second and last cycle
    f_p, k_u = fy * (1.0 + 3.0 * b), k * 4.0**-a
    area = f_p * (8.0 * dy - 2.0 * f_p / k_u)
    # the reference's ∫F dδ, trapezoidal on the history from (0, 0)
    w_ref = np.cumsum(0.5 * (ref[:, 0] + np.r_[0.0, ref[:-1, 0]]) * np.diff(np.r_[0.0, history]))
    assert ours[i1, 2] - ours[i0, 2] == pytest.approx(area, rel=1e-6)
    assert ours[i1, 2] - ours[i0, 2] == pytest.approx(w_ref[i1] - w_ref[i0], rel=1e-9)
    # with a partial unloading and an inner loop inside the last cycle: still W − E of the rules
    assert ours[i2, 3] == pytest.approx(ref[i2, 2], rel=1e-9)
    assert ours[i2, 2] - ours[i2, 3] == pytest.approx(w_ref[i2] - ref[i2, 2], rel=1e-9)
    assert ours[-1, 2] - ours[-1, 3] == pytest.approx(w_ref[-1] - ref[-1, 2], rel=1e-9)


# branches of the event-driven reference
_VIRGIN, _BACKBONE, _UNLOAD, _LINE, _INNER = range(5)


class _StoryBranch:
    """Discrete memory of one story of the event-driven reference: motion, peaks, zero-force
    points (those of a :class:`_Takeda`, for its formulas) and the active branch; the force itself
    is an ODE state with Ḟ = slope δ̇."""

    def __init__(self, k: float, fy: float, b: float, a: float):
        self.spring = _Takeda(k, fy, b, a)
        self.branch = _VIRGIN  # never yielded: k δ whichever way it moves

    def slope(self) -> float:
        s = self.spring
        if self.branch == _VIRGIN:
            return s.k
        if self.branch == _BACKBONE:
            return s.b * s.k
        if self.branch == _LINE:
            return s.line_slope(s.motion)
        unload = self.branch == _UNLOAD  # inner reloads: the same side's unloading stiffness
        return s.k_un() if (s.motion > 0) == unload else s.k_up()

    def _backbone(self, d: float) -> float:
        s = self.spring
        s.dp, s.dn = max(s.dp, d), min(s.dn, d)
        self.branch = _BACKBONE
        return s.env(d)

    def _line(self, d: float) -> float:
        self.branch = _LINE
        return self.spring.line(d, self.spring.motion)

    def reverse(self, d: float, f: float) -> float:
        """The drift turns back at (δ, F): the zero-force point, then the branch of the rules."""
        s = self.spring
        s.dp, s.dn = max(s.dp, d), min(s.dn, d)
        s.motion = -s.motion
        m = s.motion
        if m > 0 and f <= 0.0:
            s.zp = d - f / s.k_un()
        elif m < 0 and f >= 0.0:
            s.zn = d - f / s.k_up()
        zero = s.zp if m > 0 else s.zn
        if m * f < 0.0 and m * (d - zero) < 0.0:
            self.branch = _UNLOAD
            return f
        if m * f <= 0.0 or m * (f - s.line(d, m)) >= 0.0:
            return self._line(d)
        self.branch = _INNER
        return f

    def event(self, kind: str, d: float, f: float) -> float:
        """Update the memory at an event of this story; the force to restart from."""
        s = self.spring
        if kind == "reverse":
            return self.reverse(d, f)
        if kind == "yield":
            s.motion = 1 if d > 0.0 else -1
            return self._backbone(d)
        if kind == "zero":  # the unloading reached F = 0 at the zero-force point
            return self._line(d)
        peak = s.dp if s.motion > 0 else s.dn
        if kind == "peak" or abs(d - peak) < 1e-9 * s.dy:  # a reload met the peak
            return self._backbone(d)
        return self._line(d)  # an inner reload met the reload line

    def events(self, i: int, n: int) -> list:
        """(g(y), direction, kind) of story i's events on its active branch."""
        s, m = self.spring, self.spring.motion

        def drift(y):
            return y[i] - (y[i - 1] if i else 0.0)

        def rate(y):
            return y[n + i] - (y[n + i - 1] if i else 0.0)

        if self.branch == _VIRGIN:  # its turns only for the peak force (not terminal)
            return [
                (lambda y: drift(y) - s.dy, 1.0, "yield"),
                (lambda y: drift(y) + s.dy, -1.0, "yield"),
                (rate, 0.0, "turn"),
            ]
        out = [(rate, -m, "reverse")]
        peak = s.dp if m > 0 else s.dn
        if self.branch in (_LINE, _INNER):
            out.append((lambda y: drift(y) - peak, m, "peak"))
        if self.branch == _UNLOAD:
            out.append((lambda y: y[2 * n + i], m, "zero"))
        if self.branch == _INNER:
            out.append((lambda y: y[2 * n + i] - s.line(drift(y), m), m, "meet"))
        return out


def _event_driven_reference(building, c, gm: GroundMotion, duration: float, wall_k, gap):
    """Independent solve_ivp of a Takeda-story building against a Hertz wall, restarted at every
    drift reversal and branch change: state (u, v, F, W) with Ḟ = slope δ̇ of the active branch
    and Ẇ = F δ̇. Returns u, F on a 0.01 s grid, the peak |F| (the grid and every drift turn), the
    hysteretic energy W − F²/(2 k_u) at the end and the number of restarts."""
    n = building.n_floors
    m = building.masses
    stories = [_StoryBranch(*row[:4]) for row in building.story_parameters()]
    slopes = np.array([st.slope() for st in stories])
    t_rec = gm.dt * np.arange(gm.acceleration.size)
    grid = np.arange(0.0, duration + 1e-12, 0.01)

    def rhs(t, y):
        u, v, f = y[:n], y[n : 2 * n], y[2 * n : 3 * n]
        dv = np.diff(np.concatenate(([0.0], v)))
        internal = f - np.append(f[1:], 0.0)
        pen = u[-1] - gap
        contact = np.zeros(n)
        if pen > 0.0:
            contact[-1] = wall_k * pen**1.5
        a = (-internal - c @ v - contact) / m - np.interp(t, t_rec, gm.acceleration)
        return np.concatenate((v, a, slopes * dv, f * dv))

    t0, y0 = 0.0, np.zeros(4 * n)
    ts, ys, restarts = [], [], 0
    peak = np.zeros(n)  # |F| at the events too: its peaks are at reversals on the backbone
    while True:
        events, owner = [], []
        for i, st in enumerate(stories):
            for g, direction, kind in st.events(i, n):

                def event(t, y, g=g):
                    return g(y)

                event.terminal, event.direction = kind != "turn", direction
                events.append(event)
                owner.append((i, kind))
        t_eval = grid[grid > t0] if t0 > 0.0 else grid
        sol = solve_ivp(rhs, (t0, duration), y0, method="DOP853", t_eval=t_eval, events=events,
                        rtol=1e-10, atol=1e-13, max_step=1e-3)  # fmt: skip
        assert sol.status >= 0, sol.message
        if len(sol.t):  # a list when no output time fell in the segment
            ts.append(sol.t)
            ys.append(sol.y.T)
        if sol.status == 0:
            break
        for ye in sol.y_events:
            if len(ye):
                peak = np.maximum(peak, np.abs(ye[:, 2 * n : 3 * n]).max(axis=0))
        j = next(j for j, te in enumerate(sol.t_events) if te.size and owner[j][1] != "turn")
        t0, y0 = float(sol.t_events[j][0]), sol.y_events[j][0].copy()
        i, kind = owner[j]
        d = y0[i] - (y0[i - 1] if i else 0.0)
        y0[2 * n + i] = stories[i].event(kind, d, y0[2 * n + i])
        slopes[i] = stories[i].slope()
        restarts += 1
    t = np.concatenate(ts)
    assert np.allclose(t, grid)
    y = np.concatenate(ys)
    u, f = y[:, :n], y[:, 2 * n : 3 * n]
    peak = np.maximum(peak, np.abs(f).max(axis=0))
    hysteretic = []  # W − F²/(2 k_u) at the end
    for st, d, w, fe in zip(
        stories, np.diff(np.r_[0.0, u[-1]]), y[-1, 3 * n :], f[-1], strict=True
    ):
        s = st.spring
        s.dp, s.dn, s.f = max(s.dp, d), min(s.dn, d), fe
        hysteretic.append(w - s.recoverable())
    return u, f, peak, np.array(hysteretic), restarts


def test_takeda_building_pounding_on_a_wall_matches_an_independent_event_driven_solve_ivp():
    params = {"yield_drift": 0.003, "hardening": 0.05, "unloading_exponent": 0.4}
    building = ShearBuilding.uniform(
        "A", 3, period=0.4, mass=2.0e5, stories=Stories("takeda", params)
    )
    gap, wall_k = 0.02, 2.0e9
    system = assemble(
        [building], [Contact("A", "wall", gap=gap, law="hertz", k=wall_k, floors=[3])]
    )
    gm = sine_pulse(amplitude=0.5 * 9.80665, period=0.6, duration=3.0, dt=0.002)
    ds = simulate(system, gm, dt=2e-4, output_dt=0.01, duration=3.0)
    u_ref, f_ref, peak_ref, e_h, restarts = _event_driven_reference(
        building, system.damping, gm, 3.0, wall_k, gap
    )
    u = ds.displacement.sel(building="A").values
    f = ds.story_spring_force.sel(building="A").values
    assert restarts > 10  # reversals and branch changes were followed
    assert int(ds.impact_count.sum()) >= 1
    assert float(ds.story_ductility.max()) > 2.0
    assert np.abs(u - u_ref).max() < 0.01 * np.abs(u_ref).max()
    assert np.abs(f - f_ref).max() < 0.01 * np.abs(f_ref).max()
    np.testing.assert_allclose(np.abs(u).max(axis=0), np.abs(u_ref).max(axis=0), rtol=5e-3)
    np.testing.assert_allclose(ds.peak_story_spring_force.sel(building="A"), peak_ref, rtol=5e-3)
    np.testing.assert_allclose(
        ds.hysteretic_energy.sel(building="A"), e_h, rtol=1e-2, atol=1e-6 * e_h.sum()
    )  # story 2 stays elastic here
    assert float(ds.energy.sel(term="hysteretic")[-1]) == pytest.approx(e_h.sum(), rel=1e-2)
    assert ds.attrs["energy_balance_error"] < 5e-3


def _pair(stories: Stories | None) -> tuple:
    a = ShearBuilding.uniform("A", 3, period=0.35, mass=2.0e5, stories=stories)
    b = ShearBuilding.uniform("B", 6, period=0.8, mass=2.5e5)
    return [a, b], [Contact("A", "B", gap=0.01, law="hertz", k=5.0e9)]


def test_clough_stories_with_full_hardening_equal_elastic_stories():
    # b = 1: the backbone is k δ, the peaks lie on it and every reload line passes through 0
    gm = sine_pulse(amplitude=0.4 * 9.80665, period=0.6, duration=4.0, dt=0.005)
    opts = dict(dt=0.001, output_dt=0.01)
    elastic = simulate(assemble(*_pair(None)), gm, **opts)
    params = {"yield_drift": 0.002, "hardening": 1.0, "unloading_exponent": 0.0}
    takeda = simulate(assemble(*_pair(Stories("takeda", params))), gm, **opts)
    scale = float(abs(elastic.displacement).max())
    assert float(abs(takeda.displacement - elastic.displacement).max()) < 1e-8 * scale
    assert int(takeda.impact_count.sum()) == int(elastic.impact_count.sum()) > 0
    assert float(takeda.story_ductility.max()) > 1.0  # past the nominal yield drift
    hysteretic = float(abs(takeda.energy.sel(term="hysteretic")).max())
    assert hysteretic < 1e-8 * float(takeda.energy[-1, 0])


@pytest.mark.parametrize(
    "extra, message",
    [
        ({"unloading_exp": 0.4}, "stories.unloading_exp: not a parameter of the 'takeda'"),
        ({"unloading_exponent": 3}, "stories.unloading_exponent[0] = 3; allowed: 0 to 2"),
        ({"hardening": 1.5}, "stories.hardening[0] = 1.5; allowed: 0 to 1"),
        # unloading softer than the secant to the peak: the rules would depend on the step
        ({"unloading_exponent": 1.0, "hardening": 0.05}, "from ductility 1.01; allowed: μ^(1−a)"),
        ({"unloading_exponent": 0.4, "hardening": 0.3}, "from ductility 13.7; allowed: μ^(1−a)"),
    ],
)
def test_inconsistent_takeda_tables_are_refused_naming_the_key(extra, message):
    stories = {"model": "takeda", "yield_drift": 0.01, **extra}
    spec = {"name": "A", "n_floors": 2, "period": 0.3, "mass": 1e5, "stories": stories}
    with pytest.raises(CaseError, match="building") as err:
        case_from_dict({"building": [spec], "ground_motion": {"type": "sine_pulse"}})
    assert message in str(err.value)


def test_takeda_case_file_defaults_and_keys():
    stories = {"model": "takeda", "yield_drift": 0.004, "hardening": 0.02}
    spec = {"name": "A", "n_floors": 2, "period": 0.3, "mass": 1e5, "stories": stories}
    case = case_from_dict({"building": [spec], "ground_motion": {"type": "sine_pulse"}})
    b = case.system.buildings[0]
    assert b.stories.model == "takeda"
    p = b.story_parameters()
    np.testing.assert_allclose(p[:, 1], b.stiffnesses * 0.004 * b.heights)
    np.testing.assert_allclose(p[:, 2:4], [[0.02, 0.4], [0.02, 0.4]])  # a = 0.4 by default
