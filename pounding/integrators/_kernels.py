"""Compiled kernels. The only module that imports numba.

Every other module that needs compiled code takes :func:`jit` from here, so the caching policy and
the switch to run uncompiled (``NUMBA_DISABLE_JIT=1``, used by the tests to compare both paths) live
in one place.
"""

from __future__ import annotations

import numba


def jit(func):
    """Compile ``func`` in nopython mode, cached on disk; ``func.py_func`` stays the Python original."""
    return numba.njit(cache=True, fastmath=False)(func)


# --------------------------------------------------------------------------------------------------
# Contact laws: compiled from the single definitions in pounding.contact.laws
# --------------------------------------------------------------------------------------------------
from pounding.contact import laws as _laws  # noqa: E402

_linear = jit(_laws.linear_kernel)
_kelvin = jit(_laws.kelvin_kernel)
_kelvin_approach = jit(_laws.kelvin_approach_kernel)
_hertz = jit(_laws.hertz_kernel)
_hertz_kelvin = jit(_laws.hertz_kelvin_kernel)
_hunt_crossley = jit(_laws.hunt_crossley_kernel)
_jankowski = jit(_laws.jankowski_kernel)
_bilinear = jit(_laws.bilinear_kernel)
_stored = jit(_laws.stored_energy)
bilinear_rate = jit(_laws.bilinear_rate)

BILINEAR_ID = _laws.CONTACT_LAWS["bilinear"].kernel_id


@jit
def contact_eval(law, d, dd, v0, d_prev, f_prev, p):
    """Force and tangents of the law with kernel id ``law`` (ids of pounding.contact.laws.LAWS_BY_ID)."""
    if law == 0:
        return _linear(d, dd, v0, d_prev, f_prev, p)
    if law == 1:
        return _kelvin(d, dd, v0, d_prev, f_prev, p)
    if law == 2:
        return _kelvin_approach(d, dd, v0, d_prev, f_prev, p)
    if law == 3:
        return _hertz(d, dd, v0, d_prev, f_prev, p)
    if law == 4:
        return _hertz_kelvin(d, dd, v0, d_prev, f_prev, p)
    if law <= 9:  # the Hunt-Crossley family shares one kernel
        return _hunt_crossley(d, dd, v0, d_prev, f_prev, p)
    if law == 10:
        return _jankowski(d, dd, v0, d_prev, f_prev, p)
    return _bilinear(d, dd, v0, d_prev, f_prev, p)


@jit
def contact_stored_energy(law, d, f, p):
    """Recoverable energy [J] of a gap element (see pounding.contact.laws.stored_energy)."""
    return _stored(law == BILINEAR_ID, d, f, p)
