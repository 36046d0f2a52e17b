"""Drift histories shared by the story-model tests."""

from __future__ import annotations

import math

import numpy as np


def piecewise(vertices: list[float], dy: float, per_dy: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Drift history from 0 through the vertices (units δ_y), straight to each one (per_dy = 0) or
    in steps of at most 1/per_dy δ_y; and the indices of the vertices in it."""
    out = []
    for v0, v1 in zip([0.0, *vertices[:-1]], vertices, strict=True):
        n = max(1, math.ceil(abs(v1 - v0) * per_dy))
        out.append(np.linspace(v0, v1, n + 1)[1:])
    return np.concatenate(out) * dy, np.cumsum([o.size for o in out]) - 1
