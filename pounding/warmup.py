"""The compiled kernels' disk cache: where it is, whether it is warm, and a warm-up that fills it.

numba compiles the Newmark kernels (:mod:`pounding.integrators._kernels`) on their first call and keeps
the machine code on disk (``cache=True``): in ``pounding/integrators/__pycache__`` beside the sources,
or under ``NUMBA_CACHE_DIR`` when that is set (numba falls back to a per-user directory when the
package directory is read-only). The cache is keyed on the source files, so a reinstall or an upgrade
of pounding (or of numba) empties it and the next analysis compiles again, once. :func:`warm_up`
does that on purpose (``pounding warmup``, run by ``make`` after installing); the CLI calls
:func:`is_warm` first and tells the user when a run is about to compile.
"""

from __future__ import annotations

import time
from pathlib import Path

#: CPU time [s] of a cold compilation of each core, quoted in the notice: the core of gaps alone
#: (most analyses) and the core with friction and element families (yielding stories, links, sliding
#: bases). Measured on a 2-core Intel Xeon at 2.1 GHz (numba 0.68, 2026-11-28); a 2-core AMD EPYC
#: takes about 0.6 times as long.
COMPILE_SECONDS = {"gaps": 60, "families": 130}


def _dispatcher():
    from pounding.integrators import _kernels as kn

    return kn._integrate  # the compiled loop (newmark_run is the Python function that calls it)


def _core_of(signature) -> str:
    """The core (``"gaps"`` or ``"families"``) a compiled signature of the loop belongs to: the core
    of gaps alone takes ``None`` for the friction group (its fourth argument)."""
    return "gaps" if str(signature[3]) == "none" else "families"  # numba's name of NoneType


def cache_dir() -> Path | None:
    """Directory of numba's cache of the kernels, or None when running uncompiled
    (``NUMBA_DISABLE_JIT=1``)."""
    cache = getattr(_dispatcher(), "_cache", None)
    path = getattr(cache, "cache_path", None)
    return Path(path) if path else None


def is_warm(core: str = "gaps") -> bool:
    """True when numba's cache holds the integrator kernel's ``core`` (``"gaps"`` or
    ``"families"``, :func:`pounding.integrators.base.compiled_core`) compiled from the current
    sources.

    Reads the cache index of the compiled loop (numba's own staleness test: the source file's stamp);
    a run then loads the compiled kernels in well under a second. Also True when there is nothing to
    compile (``NUMBA_DISABLE_JIT=1``), or when numba's cache internals cannot be read (no notice
    rather than a wrong one)."""
    disp = _dispatcher()
    try:
        if any(_core_of(sig) == core for sig in disp.signatures):
            return True  # compiled or loaded in this process already
        cache = getattr(disp, "_cache", None)
        if cache is None:
            return True
        return any(_core_of(key[0]) == core for key in cache._cache_file._load_index())
    except Exception:  # a numba version with other internals
        return True


def notice(core: str = "gaps") -> str:
    """The one-line message shown before a cold compilation of ``core``."""
    where = cache_dir()
    return (
        f"compiling numerical kernels, one time, about {COMPILE_SECONDS[core]} s; "
        f"cache in {where if where else 'memory'}"
    )


_WARMUP_CASE = {
    "building": [
        {"name": "A", "n_floors": 1, "period": 0.5, "mass": 2.0e5, "damping": {"ratio": 0.05}},
        {"name": "B", "n_floors": 1, "period": 1.0, "mass": 2.0e5, "damping": {"ratio": 0.05}},
    ],
    "contact": [
        {"left": "A", "right": "B", "gap": 0.002, "law": "hunt_crossley", "k": 2.75e9, "e": 0.65}
    ],
    "ground_motion": {
        "type": "sine_pulse",
        "amplitude": 0.4,
        "units": "g",
        "period": 0.7,
        "duration": 0.5,
    },
    "analysis": {"method": "newmark", "output_dt": 0.01},
}


#: A yielding story in building A of the warm-up case: the core with element families.
_FAMILIES = {"stories": {"model": "bilinear", "yield_drift": 0.002, "hardening": 0.05}}


def warm_up(*, every_path: bool = False, cores: tuple[str, ...] = ("gaps", "families")) -> float:
    """Compile (or load) the Newmark kernels by running a small two-building case with impacts.

    Returns the wall time [s] it took: tens of seconds per core on a cold cache, a fraction of a
    second on a warm one. ``cores``: the compilations of the core to make, ``"gaps"`` (gaps alone)
    and ``"families"`` (friction and element families;
    :func:`pounding.integrators.base.compiled_core`); every analysis of the same kind calls them
    with the same argument types, so one run serves them all. ``every_path`` also compiles the ivp reference path's kernels and the
    oscillator kernels of spectra and separation estimates (``pounding warmup --all``; the wheel
    build)."""
    from pounding.case import case_from_dict
    from pounding.simulate import run

    start = time.perf_counter()
    for core in cores:
        data = _WARMUP_CASE
        if core == "families":
            first = {**_WARMUP_CASE["building"][0], **_FAMILIES}
            data = {**_WARMUP_CASE, "building": [first, *_WARMUP_CASE["building"][1:]]}
        warm = case_from_dict(data, source=f"warm-up case ({core})")
        run(warm.system, warm.ground_motion, warm.analysis)
    if every_path:
        import dataclasses

        import numpy as np

        from pounding.integrators.sdof import modal_extremes, spectral_peaks

        case = case_from_dict(_WARMUP_CASE, source="warm-up case")
        run(case.system, case.ground_motion, dataclasses.replace(case.analysis, method="ivp"))
        ground = case.ground_motion
        spectral_peaks(ground.acceleration, ground.dt, np.array([0.5, 1.0]), 0.05)
        omega, zeta = np.array([6.0, 20.0]), np.array([0.05, 0.05])
        modal_extremes(ground.acceleration, ground.dt, omega, zeta, np.eye(2), ground.duration)
    return time.perf_counter() - start


def ensure_compiled(announce=None, cores: tuple[str, ...] = ("gaps",)) -> float:
    """Warm the cache of each of ``cores`` that is cold, after calling ``announce(notice(core))``;
    returns the seconds spent (0 when already warm). ``pounding run``, ``study`` and ``separation``
    call it before they start with the cores their analyses need
    (:func:`pounding.integrators.base.compiled_core`; a study before its worker processes, so
    the workers load the kernels from the cache instead of each compiling them); library users may
    call it themselves before ``run_study(jobs=N)``."""
    cold = tuple(core for core in cores if not is_warm(core))
    if not cold:
        return 0.0
    if announce is not None:
        for core in cold:
            announce(notice(core))
    return warm_up(cores=cold)
