"""Start-up cost: what `import pounding` and `pounding --help` load, and the cold-cache notice.

Timings are in benchmarks/startup.py; these tests check the module sets, which decide the timings.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

from typer.testing import CliRunner

import pounding.warmup
from pounding.cli import app

ROOT = Path(__file__).resolve().parents[1]
HEAVY = ("numba", "xarray", "scipy.integrate", "pandas", "h5netcdf")


def _python(code: str, env: dict[str, str] | None = None, timeout: float = 300) -> str:
    """Run ``code`` in a fresh interpreter on this checkout; its standard output."""
    res = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        cwd=ROOT,
        env={**os.environ, "PYTHONPATH": str(ROOT), **(env or {})},
        timeout=timeout,
    )
    assert res.returncode == 0, res.stderr
    return res.stdout


def _loaded_after(code: str, env: dict[str, str] | None = None) -> dict:
    """Run ``code`` in a fresh interpreter; return which HEAVY modules it left in sys.modules."""
    probe = (
        f"{code}\nimport json, sys\nprint(json.dumps({{m: m in sys.modules for m in {HEAVY!r}}}))"
    )
    return json.loads(_python(probe, env, timeout=120).strip().splitlines()[-1])


def test_import_pounding_loads_no_numba_xarray_or_scipy_integrate():
    assert not any(_loaded_after("import pounding").values())


def test_help_loads_no_numba_or_xarray():
    code = (
        "import sys\nfrom pounding.cli import app\n"
        "try:\n    app(['--help'], prog_name='pounding')\nexcept SystemExit as e:\n"
        "    assert not e.code, e.code"
    )
    assert not any(_loaded_after(code).values())


def test_public_names_load_on_use_and_simulate_stays_the_function():
    import pounding
    import pounding.case  # imports the submodule pounding.simulate, which must not shadow simulate

    assert callable(pounding.simulate) and pounding.simulate.__module__ == "pounding.simulate"
    from pounding import AnalysisOptions, simulate

    assert simulate is pounding.simulate
    assert AnalysisOptions.__module__ == "pounding.simulate"
    assert set(pounding.__all__) <= set(dir(pounding))


def test_empty_numba_cache_dir_is_cold(tmp_path):
    # an empty NUMBA_CACHE_DIR holds no kernel: the notice must show (numba is imported, nothing compiled)
    code = (
        "import pounding.warmup as w\n"
        "assert not w.is_warm('gaps') and not w.is_warm('families'), 'empty cache reported warm'\n"
        f"assert str(w.cache_dir()).startswith({str(tmp_path)!r}), w.cache_dir()\n"
        "assert 'compiling numerical kernels, one time' in w.notice()"
    )
    _loaded_after(code, env={"NUMBA_CACHE_DIR": str(tmp_path)})


def test_run_on_cold_cache_prints_the_notice_first(tmp_path, monkeypatch):
    calls = []
    monkeypatch.setattr(pounding.warmup, "is_warm", lambda core: False)
    monkeypatch.setattr(pounding.warmup, "warm_up", lambda **kw: calls.append(kw) or 0.0)
    case = ROOT / "examples" / "two_sdof.toml"
    res = CliRunner().invoke(app, ["run", str(case)])
    assert res.exit_code == 0, res.output
    assert calls == [{"cores": ("gaps",)}]  # gaps alone: the core without the families
    first = res.output.splitlines()[0]
    assert first.startswith("compiling numerical kernels, one time, about ")
    assert "cache in " in first


def test_run_of_yielding_stories_compiles_the_core_with_families(monkeypatch):
    calls = []
    monkeypatch.setattr(pounding.warmup, "is_warm", lambda core: core == "gaps")
    monkeypatch.setattr(pounding.warmup, "warm_up", lambda **kw: calls.append(kw) or 0.0)
    case = ROOT / "examples" / "three_vs_eight_yielding.toml"
    res = CliRunner().invoke(app, ["run", str(case), "--output-dt", "0.05"])
    assert res.exit_code == 0, res.output
    assert calls == [{"cores": ("families",)}]
    assert res.output.splitlines()[0].startswith(
        "compiling numerical kernels, one time, about 130 s"
    )


def test_kernels_read_from_the_cache_skip_numba_compiler_registries():
    # numba refreshes its whole target context (~0.3 s of imports) before reading a cached function;
    # pounding._numba reads the cache with the runtime alone. The first process may compile (a cold
    # cache after an edit); the second reads every kernel back and must not load the registries,
    # and its results must equal the first's.
    code = (
        "import sys, numpy as np\nimport pounding\n"
        f"r = pounding.simulate(pounding.load_case({str(ROOT / 'examples' / 'two_sdof.toml')!r}))\n"
        "print(repr(float(np.abs(r['displacement']).max())), "
        "'numba.np.polynomial.polynomial_core' in sys.modules)"
    )
    first, second = (_python(code, timeout=600).split() for _ in range(2))
    assert second == [first[0], "False"]


def test_warmup_verb_reports_time_and_cache(monkeypatch):
    monkeypatch.setattr(pounding.warmup, "is_warm", lambda core: True)
    calls = []
    monkeypatch.setattr(pounding.warmup, "warm_up", lambda **kw: calls.append(kw) or 0.25)
    res = CliRunner().invoke(app, ["warmup"])
    assert res.exit_code == 0, res.output
    assert "already cached: loaded in 0.2 s; cache in " in res.output
    assert CliRunner().invoke(app, ["warmup", "--all"]).exit_code == 0
    assert calls == [{"every_path": False}, {"every_path": True}]


def test_warm_up_of_every_path_compiles_the_ivp_and_oscillator_kernels():
    # what the wheel build runs (setup.py): after it, these need no compilation on first use
    from pounding.integrators import ivp, sdof
    from pounding.warmup import warm_up

    warm_up(every_path=True)
    compiled = [ivp._rhs_kernel, sdof.spectral_peaks_kernel, sdof.modal_extremes_kernel]
    assert all(f.signatures for f in compiled)


def test_run_console_process_loads_no_xarray_pandas_or_scipy_linalg(tmp_path):
    # `pounding run` writes and summarises plain arrays (no xr.Dataset) and loads scipy's
    # cython_blas for numba without scipy.linalg's package: ~0.45 s of a ~1 s warm run (the
    # Flores case: a Hunt-Crossley law with a restitution coefficient needs scipy.optimize)
    out = tmp_path / "out.nc"
    code = (
        "import sys\nimport pounding.cli\nfrom pounding.cli import main\n"
        "pounding.cli._exit_now = lambda code: None\n"  # the console process ends here
        f"sys.argv = ['pounding', 'run', {str(ROOT / 'examples' / 'three_vs_eight_story.toml')!r}, "
        f"'-o', {str(out)!r}]\n"
        "try:\n    main()\nexcept SystemExit as e:\n    assert not e.code, e.code\n"
        "import json\nmods = {m: m in sys.modules for m in "
        "('xarray', 'pandas', 'scipy.linalg', 'h5netcdf', 'scipy.linalg.cython_blas')}\n"
        "import scipy.linalg\n"  # still importable afterwards, the preloaded module bound
        "assert scipy.linalg.cython_blas is sys.modules['scipy.linalg.cython_blas']\n"
        "assert float(scipy.linalg.solve([[2.0]], [1.0])[0]) == 0.5\n"
        "print(json.dumps(mods))"
    )
    mods = json.loads(_python(code).strip().splitlines()[-1])
    assert mods == {
        "xarray": False,
        "pandas": False,
        "scipy.linalg": False,
        "h5netcdf": False,
        "scipy.linalg.cython_blas": False,  # loaded for numba, then left to a later import
    }


def test_run_writes_and_prints_what_simulate_and_save_give(tmp_path):
    # the console path (simulate_variables, the writer of results.save) against the public API
    import xarray as xr

    from pounding import load_case, open_result, save, simulate

    case = ROOT / "examples" / "two_sdof.toml"
    res = CliRunner().invoke(app, ["run", str(case), "-o", str(tmp_path / "cli.nc")])
    assert res.exit_code == 0, res.output
    ds = simulate(load_case(case), baseline=True)  # pounding run compares with no contact
    save(ds, tmp_path / "api.nc")
    cli, api = open_result(tmp_path / "cli.nc"), open_result(tmp_path / "api.nc")
    cli.attrs.pop("created"), api.attrs.pop("created")
    xr.testing.assert_identical(cli, api)
    s = ds.pounding.summary()
    for name, b in s["buildings"].items():
        assert f"{b['T1']:7.3f}" in res.output and f"  {name:<12s}" in res.output
    assert f"{100 * s['energy_balance_error']:.3g} % of the input energy" in res.output


def test_run_console_process_ends_at_once_with_its_file_written(tmp_path):
    # main() ends `pounding run` with os._exit (no interpreter teardown): the exit code, the
    # summary on stdout and the file must all be complete
    from pounding import open_result

    out = tmp_path / "sub" / "out.nc"
    cmd = [sys.executable, "-c", "from pounding.cli import main; main()"]
    res = subprocess.run(
        [*cmd, "run", str(ROOT / "examples" / "two_sdof.toml"), "-o", str(out)],
        capture_output=True,
        text=True,
        cwd=ROOT,
        env={**os.environ, "PYTHONPATH": str(ROOT)},
        timeout=300,
    )
    assert res.returncode == 0, res.stderr
    assert res.stdout.rstrip().endswith(f"written {out}")
    assert open_result(out)["displacement"].attrs["units"] == "m"
    bad = subprocess.run(
        [*cmd, "run", str(tmp_path / "missing.toml")],
        capture_output=True,
        text=True,
        cwd=ROOT,
        env={**os.environ, "PYTHONPATH": str(ROOT)},
        timeout=300,
    )
    assert bad.returncode == 2 and bad.stdout.count("\n") + bad.stderr.count("\n") == 1
