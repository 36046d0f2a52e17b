"""The cubic Hermite interpolant of a step (pounding.integrators.hermite): a cubic is reproduced
exactly, and its root and extremum are the cubic's own (closed forms of the quadratic/cubic)."""

from __future__ import annotations

import numpy as np
import pytest

from pounding.integrators._events import hermite_root
from pounding.integrators.hermite import hermite, hermite_extremum, hermite_slope

H = 0.02  # [s]
# p(t) = a + b t + c t² + d t³ on [0, H]: rises from -1 mm, peaks inside the step, falls
A, B, C, D = -1e-3, 0.5, -30.0, 200.0


def p(t):
    return A + B * t + C * t**2 + D * t**3


def dp(t):
    return B + 2 * C * t + 3 * D * t**2


ENDS = (p(0.0), dp(0.0), p(H), dp(H))


@pytest.mark.parametrize("th", [0.0, 0.13, 0.5, 0.87, 1.0])
def test_a_cubic_is_its_own_hermite_interpolant(th):
    assert hermite(*ENDS, H, th) == pytest.approx(p(th * H), abs=1e-15)
    assert hermite_slope(*ENDS, H, th) == pytest.approx(dp(th * H), rel=1e-12)


def test_extremum_of_a_cubic_is_at_the_root_of_its_derivative():
    # dp has roots (-2C ± sqrt(4C² - 12BD)) / 6D; the first one inside [0, H] is the maximum
    roots = np.roots([3 * D, 2 * C, B])
    t_max = min(r.real for r in roots if 0 < r.real < H)
    assert dp(0.0) > 0 > dp(H)
    assert hermite_extremum(*ENDS, H) == pytest.approx(p(t_max), rel=1e-12)


def test_root_of_a_cubic_and_the_slope_there():
    h = 0.005  # p(0) < 0 < p(h): one crossing, as at a located closure
    assert p(0.0) < 0 < p(h)
    roots = np.roots([D, C, B, A])
    t0 = min(r.real for r in roots if abs(r.imag) < 1e-12 and 0 < r.real < h)
    th, slope = hermite_root(p(0.0), dp(0.0), p(h), dp(h), h)
    assert th * h == pytest.approx(t0, abs=1e-14)
    assert slope == pytest.approx(dp(t0), rel=1e-9)
