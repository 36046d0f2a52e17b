"""The only module that imports numba.

Every module that needs compiled code takes :func:`jit` (or :func:`jit_inline`) from here, so the
caching policy and the switch to run uncompiled (``NUMBA_DISABLE_JIT=1``, used by the tests to
compare both paths) live in one place.

numba's disk cache keys each compiled function on its own source file only, while a kernel carries
the machine code of the functions it calls from other modules: after an edit to a callee's module
(a law, a step), the caller's cached code would be stale. So every compiled function of this
package is stamped with one digest of the contents of all :data:`COMPILED_SOURCES` instead; an edit
to any of them recompiles everything that depends on it. The digest is of the contents, not the
modification times, so a cache compiled when the wheel is built (``setup.py``) stays valid once
pip has installed the files: such an install carries :data:`SHIPPED_MARKER`, and its functions
then keep their cache beside the sources (``__pycache__``) even when ``NUMBA_CACHE_DIR`` is set.
"""

from __future__ import annotations

import copy
import functools
import hashlib
from pathlib import Path
from typing import Any

import numba

_PACKAGE = Path(__file__).resolve().parent
#: Sources whose functions are compiled (or called by compiled code), relative to the package.
COMPILED_SOURCES = (
    "_numba.py",
    "integrators/_kernels.py",
    "integrators/_dispatch.py",
    "integrators/_events.py",
    "integrators/hermite.py",
    "integrators/_linalg.py",
    "integrators/_layout.py",
    "integrators/_coefficients.py",
    "integrators/_families.py",
    "integrators/_steps.py",
    "integrators/_ledger.py",
    "integrators/base.py",  # PATH_POINTS, read by the compiled impact log
    "links.py",
    "stories.py",
    "integrators/ivp.py",
    "integrators/sdof.py",
    "contact/laws.py",
    "friction.py",
    "system.py",
    "ground_motion.py",
    "spectra.py",
    "sdof.py",
)
#: Written into the package by the wheel build (``setup.py``) after it compiled the kernels.
SHIPPED_MARKER = "_shipped_kernels.json"
_stamp: str | None = None


def source_stamp() -> str:
    """Digest of the contents of every file of :data:`COMPILED_SOURCES`."""
    global _stamp
    if _stamp is None:
        digest = hashlib.sha256()
        for pattern in COMPILED_SOURCES:
            for path in sorted(_PACKAGE.glob(pattern)):
                digest.update(f"{pattern}:{path.name}:".encode())
                digest.update(hashlib.sha256(path.read_bytes()).digest())
        _stamp = digest.hexdigest()
    return _stamp


def _package_locators() -> None:
    """Put locators that stamp this package's functions with :func:`source_stamp` ahead of
    numba's own (same cache directories; functions outside the package keep numba's stamp)."""
    from numba.core import caching

    impl = getattr(caching, "CacheImpl", None) or caching._CacheImpl
    ours = []
    names = ["UserProvidedCacheLocator", "InTreeCacheLocator", "UserWideCacheLocator"]
    if (_PACKAGE / SHIPPED_MARKER).is_file():
        names.insert(0, names.pop(1))  # the kernels compiled into the wheel, beside the sources
    for name in names:
        base = getattr(caching, name, None) or getattr(caching, "_" + name, None)
        if base is None:
            return  # an unknown numba layout: keep its default stamps

        def from_function(cls, py_func, py_file, _base=base):
            if not Path(py_file).resolve().is_relative_to(_PACKAGE):
                return None
            return _base.from_function.__func__(cls, py_func, py_file)

        ours.append(
            type(
                "Package" + name,
                (base,),
                {
                    "from_function": classmethod(from_function),
                    "get_source_stamp": lambda self: source_stamp(),
                },
            )
        )
    impl._locator_classes[:0] = [c for c in ours if c not in impl._locator_classes]


_package_locators()


def _load_overload(self, sig, target_context):
    # numba refreshes its whole target context (imports ~100 modules that register the typing and
    # lowering of numpy, lists, dicts..., ~0.3 s) before it reads a cached function, though the
    # machine code read back needs only the reference-counting runtime's symbols (the others are the
    # C API, numba's helper library and libm, registered when the context is created). A miss still
    # compiles, and numba's compiler refreshes the context itself first.
    from numba.core.runtime import rtsys

    rtsys.initialize(target_context)
    with self._guard_against_spurious_io_errors():
        overload = self._load_overload(sig, target_context)
    if overload is None:  # a miss: numba compiles it next
        _inline_with_one_memo()
    return overload


class _OneMemoCopy:
    """The ``copy`` module as numba's inliner sees it while it inlines into a function of this
    package: consecutive blocks of one scope are deep-copied with one memo.

    numba's ``InlineWorker.inline_ir`` copies the callee's IR block by block, each with a memo of
    its own, so every block drags a copy of the callee's whole scope (all its variables) along:
    the work grows as blocks × variables, and an inlined function that itself inlines others is
    copied in quadratic time (17.4 s of a 103.5 s cold compile, ``_take_step`` into the loop alone
    6.8 s). One memo per scope copies each variable once, as one ``copy.deepcopy`` of the whole
    block map would; the blocks and the code numba builds from them are the same (the asm of every
    compiled function matches numba's own copies', but for ``_prepare``, whose asm differs between
    two unpatched compiles as well). A memo numba passes itself is used as given."""

    def __init__(self) -> None:
        self._scope: object = None
        self._memo: dict = {}

    def deepcopy(self, x: Any, memo: dict | None = None) -> Any:
        if memo is not None:
            return copy.deepcopy(x, memo)
        scope = getattr(x, "scope", None)
        if scope is None or scope is not self._scope:
            self._scope, self._memo = scope, {}
        return copy.deepcopy(x, self._memo)

    def __getattr__(self, name: str) -> Any:
        return getattr(copy, name)


_inline_memo_installed = False


def _inline_with_one_memo() -> None:
    """Give numba's inliner :class:`_OneMemoCopy` for each inlining into a function of this package
    (another module's compilation keeps numba's own copies). Installed at the first cache miss, when
    numba is about to compile anyway; inert if numba's inliner no longer deep-copies through its
    module's ``copy``."""
    global _inline_memo_installed
    if _inline_memo_installed:
        return
    _inline_memo_installed = True
    from numba.core import inline_closurecall as inliner

    worker = getattr(inliner, "InlineWorker", None)
    inline_ir = getattr(worker, "inline_ir", None)
    if inline_ir is None or getattr(inliner, "copy", None) is not copy:
        return

    @functools.wraps(inline_ir)
    def inline_ir_one_memo(self, caller_ir, *args, **kwargs):
        name = getattr(getattr(caller_ir, "func_id", None), "modname", "") or ""
        if name != __package__ and not name.startswith(__package__ + "."):
            return inline_ir(self, caller_ir, *args, **kwargs)
        inliner.copy = _OneMemoCopy()  # a module global, safe: numba compiles under one lock
        try:
            return inline_ir(self, caller_ir, *args, **kwargs)
        finally:
            inliner.copy = copy

    worker.inline_ir = inline_ir_one_memo


def _cached(dispatcher):
    cache = getattr(dispatcher, "_cache", None)
    if hasattr(cache, "_load_overload") and hasattr(cache, "_guard_against_spurious_io_errors"):
        cache.load_overload = _load_overload.__get__(cache)
    return dispatcher


def jit(func):
    """Compile ``func`` in nopython mode, cached on disk; ``func.py_func`` stays the Python original."""
    return _cached(numba.njit(cache=True, fastmath=False, no_cfunc_wrapper=True)(func))


def jit_inline(func):
    """:func:`jit`, inlined into its callers by numba (no call boundary to pass arrays across)."""
    return _cached(
        numba.njit(cache=True, fastmath=False, no_cfunc_wrapper=True, inline="always")(func)
    )


def jit_setup(func):
    """:func:`jit` for a function only compiled code calls, that allocates (set-up, refactoring):
    reference counted, without a CPython entry point."""
    # _nrt is set, not inherited: numba compiles a callee with its caller's _nrt unless it is set
    return _cached(
        numba.njit(
            cache=True, fastmath=False, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=True
        )(func)
    )


def jit_kernel(func):
    """:func:`jit` for a kernel that allocates nothing: compiled without numba's reference counting
    (``_nrt=False``), whose atomic increments on every array of every argument group cost the
    time loop ~4 µs a step. Arrays it receives stay owned by the caller; allocating inside is a
    compile error, not a leak."""
    return _cached(numba.njit(cache=True, fastmath=False, no_cfunc_wrapper=True, _nrt=False)(func))


def jit_internal(func):
    """:func:`jit_kernel` for a function only compiled code calls: no CPython entry point is
    generated (unboxing a group of arrays costs compile time), so ``func`` cannot be called from
    Python."""
    return _cached(
        numba.njit(
            cache=True, fastmath=False, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False
        )(func)
    )
