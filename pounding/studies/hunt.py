r"""Hunt-and-fill tracing of IDA curves (Vamvatsikos & Cornell 2004) [1]_.

Each record of an incremental dynamic analysis is traced on its own, run after run, within a budget
of ``max_runs``:

* **hunt**: the first run at ``first``; then IM_{k+1} = IM_k + s + (k − 1) Δs (``step`` s,
  ``step_increase`` Δs) until a run reaches the limit state (collapse by default) or ``max_level``
  is passed;
* **bracket**: bisect between the highest level that did not reach it below the lowest level that
  did, until the two are within ``tolerance``: the capacity is that lowest level (a record that
  "resurrects" above it still counts from its first collapse);
* **fill**: the runs left halve the widest gaps between the levels below, for the shape of the
  curve.

A record that had not reached the limit state at ``max_level`` or when the budget ran out is
censored at its highest level. A run that failed (a Newton iteration that did not converge) counts
as collapse, as in [1]_ (and as reaching any other limit state traced: it ends the hunt). With
``limit_state = "pounding"`` the trace brackets the intensity at which the buildings first touch.

References
----------
.. [1] Vamvatsikos, D., Cornell, C. A. (2004). Applied incremental dynamic analysis. Earthquake
   Spectra 20(2), 523–553. https://doi.org/10.1193/1.1737737
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping, Sequence
from typing import Any

from pounding.errors import PoundingInputError

#: Keys of an ``[ida.hunt]`` table.
HUNT_KEYS = (
    "first",
    "step",
    "step_increase",
    "tolerance",
    "max_runs",
    "max_level",
    "limit_state",
)


def is_limit_state(value: Any) -> bool:
    """``"collapse"``, ``"pounding"`` (any impact) or a story drift ratio (0 < value < 10)."""
    return value in ("collapse", "pounding") or (
        isinstance(value, int | float) and not isinstance(value, bool) and 0.0 < value < 10.0
    )


@dataclasses.dataclass(frozen=True)
class HuntOptions:
    """The hunt-and-fill schedule of one IDA: intensities in g of the study's measure."""

    first: float = 0.1
    step: float = 0.1
    step_increase: float = 0.05
    tolerance: float = 0.05
    max_runs: int = 12
    max_level: float = 5.0
    #: "collapse", "pounding" (the first impact) or a story drift ratio (the largest of any
    #: building's stories)
    limit_state: str | float = "collapse"

    def __post_init__(self) -> None:
        for name in ("first", "step", "tolerance", "max_level"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int | float) or not value > 0:
                raise PoundingInputError(f"ida.hunt.{name} = {value!r}; allowed: a number > 0 [g]")
        inc = self.step_increase
        if isinstance(inc, bool) or not isinstance(inc, int | float) or not inc >= 0:
            raise PoundingInputError(
                f"ida.hunt.step_increase = {inc!r}; allowed: a number >= 0 [g]"
            )
        runs = self.max_runs
        if isinstance(runs, bool) or not isinstance(runs, int) or runs < 2:
            raise PoundingInputError(f"ida.hunt.max_runs = {runs!r}; allowed: an integer >= 2")
        if self.first > self.max_level:
            raise PoundingInputError(
                f"ida.hunt.first = {self.first!r} is above ida.hunt.max_level = "
                f"{self.max_level!r}; allowed: first <= max_level [g]"
            )
        limit = self.limit_state
        if not is_limit_state(limit):
            raise PoundingInputError(
                f'ida.hunt.limit_state = {limit!r}; allowed: "collapse", "pounding" or a story drift ratio '
                "(e.g. 0.05)"
            )

    @classmethod
    def from_table(cls, table: Any) -> HuntOptions:
        """From an ``[ida.hunt]`` table (every key optional)."""
        if not isinstance(table, Mapping):
            raise PoundingInputError(
                f"ida.hunt = {table!r}; allowed: a table with keys {', '.join(HUNT_KEYS)}"
            )
        unknown = sorted(set(table) - set(HUNT_KEYS))
        if unknown:
            raise PoundingInputError(
                f"ida.hunt.{unknown[0]}: unknown; allowed: {', '.join(HUNT_KEYS)}"
            )
        return cls(**dict(table))

    def to_dict(self) -> dict[str, Any]:
        return dataclasses.asdict(self)


def capacity(history: Sequence[tuple[float, bool]]) -> tuple[float, float, float]:
    """(capacity, highest level below it that did not reach the limit state, highest level run)
    of a record's runs as (level, reached) pairs; the capacity is ``inf`` when no run reached it."""
    reached = [level for level, hit in history if hit]
    top = max((level for level, _ in history), default=0.0)
    if not reached:
        return math.inf, top, top
    c = min(reached)
    below = max((level for level, hit in history if not hit and level < c), default=0.0)
    return c, below, top


def next_level(history: Sequence[tuple[float, bool]], options: HuntOptions) -> float | None:
    """The intensity [g] of a record's next run given its runs so far as (level, reached) pairs in
    the order they ran, or None when its trace is complete."""
    k = len(history)
    if k >= options.max_runs:
        return None
    if k == 0:
        return float(options.first)
    c, below, top = capacity(history)
    if math.isinf(c):  # hunt
        last = history[-1][0]
        if last >= options.max_level:
            return None
        return min(last + options.step + (k - 1) * options.step_increase, options.max_level)
    if c - below > options.tolerance:  # bracket
        return 0.5 * (below + c)
    # fill: halve the widest gap below the capacity's lower bound (from zero up)
    points = sorted({0.0, *(level for level, hit in history if not hit and level <= below)})
    gaps = [(b - a, a, b) for a, b in zip(points, points[1:], strict=False)]
    if not gaps:
        return None
    # equal widths (to rounding) fill from the bottom, the elastic part first
    width, a, b = max(gaps, key=lambda g: (round(g[0], 9), -g[1]))
    return 0.5 * (a + b) if width > options.tolerance else None
