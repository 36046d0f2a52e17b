"""Parameters that let every registered contact law run in the tests that sweep them all: the layer
in the gap of ``bumper`` and ``filler``."""

from __future__ import annotations

from typing import Any

#: A bumper that fits gaps of 5 mm and more: 4 mm of rubber, met through it at 90 % compression.
BUMPER = {"thickness": 0.004, "k_rubber": 5.0e8, "e_rubber": 0.8, "crush": 0.9}
#: A filler in the whole gap, the structures meeting at 80 % of it.
FILLER = {"k_filler": 2.0e7, "c_filler": 2.0e5, "crush": 0.8}
#: Laws whose layer touches both faces from the start: no free impact to compare with.
FILLED = ("filler", "gap_filler")


def bumper_tuple(scale: float = 1.0) -> tuple[float, float, float, float]:
    """:data:`BUMPER` as ``contact_parameters(bumper=...)`` takes it, lengths × ``scale``."""
    return (BUMPER["thickness"] * scale, BUMPER["k_rubber"] / scale**0.5, BUMPER["e_rubber"],
            BUMPER["crush"])  # fmt: skip


def layer(law: str, gap: float, scale: float = 1.0) -> dict[str, Any]:
    """``bumper=`` or ``filler=`` for ``contact_parameters``/``effective_restitution`` (empty for
    the other laws); ``gap`` [m] is the clear gap (a filler fills it)."""
    if law in ("bumper", "rubber_bumper"):
        return {"bumper": bumper_tuple(scale)}
    if law in FILLED:
        return {"filler": (FILLER["k_filler"], FILLER["c_filler"], FILLER["crush"] * gap)}
    return {}


def with_layer(law: str, params: dict[str, Any], scale: float = 1.0) -> dict[str, Any]:
    """``params`` plus the bumper's or filler's keys (a Contact's keyword form)."""
    if law in ("bumper", "rubber_bumper"):
        t, k_r, e_r, crush = bumper_tuple(scale)
        return {**params, "thickness": t, "k_rubber": k_r, "e_rubber": e_r, "crush": crush}
    if law in FILLED:
        return {**params, **FILLER}
    return params
