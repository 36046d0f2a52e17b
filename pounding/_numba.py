"""The only module that imports numba.

Every module that needs compiled code takes :func:`jit` (or :func:`jit_inline`) from here, so the
caching policy and the switch to run uncompiled (``NUMBA_DISABLE_JIT=1``, used by the tests to
compare both paths) live in one place.
"""

from __future__ import annotations

import numba


def jit(func):
    """Compile ``func`` in nopython mode, cached on disk; ``func.py_func`` stays the Python original."""
    return numba.njit(cache=True, fastmath=False)(func)


def jit_inline(func):
    """:func:`jit`, inlined into its callers by numba (no call boundary to pass arrays across)."""
    return numba.njit(cache=True, fastmath=False, inline="always")(func)
