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


def _loaded_after(code: str, env: dict[str, str] | None = None) -> dict:
    """Run ``code`` in a fresh interpreter; return which HEAVY modules it left in sys.modules."""
    probe = (
        f"{code}\nimport json, sys\nprint(json.dumps({{m: m in sys.modules for m in {HEAVY!r}}}))"
    )
    res = subprocess.run(
        [sys.executable, "-c", probe],
        capture_output=True,
        text=True,
        cwd=ROOT,
        env={**os.environ, "PYTHONPATH": str(ROOT), **(env or {})},
        timeout=120,
    )
    assert res.returncode == 0, res.stderr
    return json.loads(res.stdout.strip().splitlines()[-1])


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
        "assert not w.is_warm(), 'empty cache reported warm'\n"
        f"assert str(w.cache_dir()).startswith({str(tmp_path)!r}), w.cache_dir()\n"
        "assert 'compiling numerical kernels, one time' in w.notice()"
    )
    _loaded_after(code, env={"NUMBA_CACHE_DIR": str(tmp_path)})


def test_run_on_cold_cache_prints_the_notice_first(tmp_path, monkeypatch):
    calls = []
    monkeypatch.setattr(pounding.warmup, "is_warm", lambda: False)
    monkeypatch.setattr(pounding.warmup, "warm_up", lambda: calls.append("warm_up") or 0.0)
    case = ROOT / "examples" / "two_sdof.toml"
    res = CliRunner().invoke(app, ["run", str(case)])
    assert res.exit_code == 0, res.output
    assert calls == ["warm_up"]
    first = res.output.splitlines()[0]
    assert first.startswith("compiling numerical kernels, one time, about ")
    assert "cache in " in first


def test_warmup_verb_reports_time_and_cache(monkeypatch):
    monkeypatch.setattr(pounding.warmup, "is_warm", lambda: True)
    monkeypatch.setattr(pounding.warmup, "warm_up", lambda: 0.25)
    res = CliRunner().invoke(app, ["warmup"])
    assert res.exit_code == 0, res.output
    assert "already cached: loaded in 0.2 s; cache in " in res.output
