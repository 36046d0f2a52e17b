"""Time integrators by name, as scipy's ``solve_ivp`` takes its ``METHODS``: the Newmark family run by
the compiled loop (:mod:`pounding.integrators.newmark`) and ``ivp``, scipy's ``solve_ivp`` with
contact events (:mod:`pounding.integrators.ivp`, the reference path).

The registry is built on first use (PEP 562), so importing :mod:`pounding.integrators.base` alone
does not load the compiled kernels.
"""

from __future__ import annotations

from typing import Any

#: The integration methods, one name per integrator (``average_acceleration`` is an alias of
#: ``newmark``); tests parametrise over these.
METHODS = ("newmark", "linear_acceleration", "hht", "ivp")


def _registry() -> dict[str, type]:
    from pounding.integrators.ivp import SolveIVP
    from pounding.integrators.newmark import SCHEMES

    return {**SCHEMES, "ivp": SolveIVP}


def get_integrator(method: Any, /, **options: Any) -> Any:
    """An integrator instance from a name of :data:`INTEGRATORS`, a class or an instance; an unknown
    name lists the allowed ones. ``options`` go to the class (``alpha`` of ``hht``; ``method``,
    ``rtol``, ``atol`` of ``ivp``)."""
    from pounding.errors import PoundingInputError

    registry = _registry()
    classes = tuple(registry.values())
    if isinstance(method, classes):
        return method
    if isinstance(method, type) and issubclass(method, classes):
        return method(**options)
    if method not in registry:
        raise PoundingInputError(f"analysis.method = {method!r}; allowed: {', '.join(registry)}")
    return registry[method](**options)


def __getattr__(name: str) -> Any:
    if name == "INTEGRATORS":
        return _registry()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
