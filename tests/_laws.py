"""Parameters that let every registered contact law run in the tests that sweep them all."""

from __future__ import annotations

from typing import Any

#: A bumper that fits gaps of 5 mm and more: 4 mm of rubber, met through it at 90 % compression.
BUMPER = {"thickness": 0.004, "k_rubber": 5.0e8, "e_rubber": 0.8, "crush": 0.9}


def bumper_tuple(scale: float = 1.0) -> tuple[float, float, float, float]:
    """:data:`BUMPER` as ``contact_parameters(bumper=...)`` takes it, lengths × ``scale``."""
    return (BUMPER["thickness"] * scale, BUMPER["k_rubber"] / scale**0.5, BUMPER["e_rubber"],
            BUMPER["crush"])  # fmt: skip


def with_bumper(law: str, params: dict[str, Any], scale: float = 1.0) -> dict[str, Any]:
    """``params`` plus the bumper's keys when ``law`` is the bumper (a Contact's keyword form)."""
    if law not in ("bumper", "rubber_bumper"):
        return params
    t, k_r, e_r, crush = bumper_tuple(scale)
    return {**params, "thickness": t, "k_rubber": k_r, "e_rubber": e_r, "crush": crush}
