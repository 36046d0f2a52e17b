"""Start-up cost of pounding, each measured in fresh processes (issue 12 §2).

* ``import pounding``;
* ``pounding --help``;
* warm ``pounding run examples/three_vs_eight_story.toml -o OUT.nc`` (numba cache filled);
* cold run of the same: a fresh, empty ``NUMBA_CACHE_DIR`` (numba compiles the kernels), wall and
  CPU (user + system of the child, from ``resource.getrusage(RUSAGE_CHILDREN)``);
* ``results.save`` of the 3-vs-8 result (h5netcdf), in-process, after one unmeasured write;
* with ``--install``: what a new user meets. ``pip install .`` of this checkout into a fresh venv
  (the wheel build compiles the kernels into the package, ``setup.py``), then the first and the
  second ``pounding run`` of the example in that venv with an empty ``NUMBA_CACHE_DIR``.

Each figure is over ``--repeats`` processes (``--cold-repeats`` for the cold run), min and median.

    python benchmarks/startup.py                # writes benchmarks/results/startup.json
    python benchmarks/startup.py --quick        # fewer repeats, results/quick/
    python benchmarks/startup.py --cold-repeats 0   # warm figures only; the cold run's figures
                                                    # are kept from the previous startup.json
    python benchmarks/startup.py --install      # + pip install . and the first run after it
"""

from __future__ import annotations

import argparse
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _common import machine, machine_markdown, out_dirs, write_json  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
CASE = ROOT / "examples" / "three_vs_eight_story.toml"
SCRATCH = Path(tempfile.gettempdir())


def _pounding_cmd() -> list[str]:
    # the console script of this interpreter's environment, else the module entry point
    exe = shutil.which("pounding", path=str(Path(sys.executable).parent))
    return [exe] if exe else [sys.executable, "-c", "from pounding.cli import main; main()"]


def timed(cmd: list[str], env: dict[str, str] | None = None) -> tuple[float, float, str]:
    """(wall [s], CPU user + system [s], stderr) of one fresh process running ``cmd``.

    The process runs in a scratch directory, so ``python -c`` imports the installed (or
    PYTHONPATH) pounding, not a checkout that happens to be the working directory."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    # a user's Python writes and reuses .pyc files: a PYTHONDONTWRITEBYTECODE in the benchmark's
    # own environment would add ~0.3 s of compiling every module from source to each run
    base = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    res = subprocess.run(
        cmd, capture_output=True, text=True, env={**base, **(env or {})}, cwd=SCRATCH
    )
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if res.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed: {res.stderr}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, res.stderr


def stats(samples: list[tuple[float, float, str]]) -> dict[str, float | list[float]]:
    walls = [s[0] for s in samples]
    cpus = [s[1] for s in samples]
    return {
        "wall_min": min(walls),
        "wall_median": statistics.median(walls),
        "cpu_min": min(cpus),
        "cpu_median": statistics.median(cpus),
        "walls": walls,
        "cpus": cpus,
    }


def save_time(repeats: int, out: Path) -> dict[str, float]:
    """In-process time of results.save on the 3-vs-8 Dataset (the kernels warm)."""
    code = (
        "import time, statistics, json\n"
        "from pounding import load_case, simulate, save\n"
        f"ds = simulate(load_case({str(CASE)!r}))\n"
        f"save(ds, {str(out)!r})\n"
        "ts = []\n"
        f"for _ in range({repeats}):\n"
        "    t0 = time.perf_counter()\n"
        f"    save(ds, {str(out)!r})\n"
        "    ts.append(time.perf_counter() - t0)\n"
        "print(json.dumps({'min': min(ts), 'median': statistics.median(ts)}))\n"
    )
    import json

    res = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, cwd=SCRATCH, check=True
    )
    return json.loads(res.stdout.strip().splitlines()[-1])


def after_install(tmp: Path) -> dict[str, dict]:
    """``pip install .`` into a fresh venv, then two runs of the example with an empty cache dir."""
    import venv

    env_dir = tmp / "venv"
    venv.create(env_dir, with_pip=True)
    bin_ = env_dir / "bin"
    env = {"NUMBA_CACHE_DIR": str(tmp / "empty-numba-cache"), "PYTHONPATH": ""}
    out: dict[str, dict] = {}
    install = [str(bin_ / "pip"), "install", "--quiet", str(ROOT)]
    out["pip install . (fresh venv)"] = stats([timed(install, env)])
    run_cmd = [str(bin_ / "pounding"), "run", str(CASE), "-o", str(tmp / "installed.nc")]
    first = timed(run_cmd, env)
    out["first pounding run after install"] = stats([first])
    out["first pounding run after install"]["notice"] = first[2].splitlines()[0] if first[2] else ""
    out["second pounding run after install"] = stats([timed(run_cmd, env)])
    for name, r in out.items():
        print(f"{name:36s} wall {r['wall_min']:.1f} s; CPU {r['cpu_min']:.1f} s")
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeats", type=int, default=7)
    ap.add_argument("--cold-repeats", type=int, default=2)
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--install", action="store_true", help="also pip install . and its first run")
    args = ap.parse_args(argv)
    if args.quick:
        args.repeats, args.cold_repeats = 3, 1
    info = machine()
    print(machine_markdown(info))
    tmp = Path(tempfile.mkdtemp(prefix="pounding-startup-"))
    out_nc = tmp / "out.nc"
    pounding = _pounding_cmd()
    run_cmd = [*pounding, "run", str(CASE), "-o", str(out_nc)]
    results: dict[str, dict] = {}

    def measure(name: str, cmd: list[str], n: int, env: dict[str, str] | None = None) -> None:
        results[name] = stats([timed(cmd, env) for _ in range(n)])
        r = results[name]
        print(
            f"{name:28s} wall min {r['wall_min']:.3f} s, median {r['wall_median']:.3f} s; "
            f"CPU min {r['cpu_min']:.3f} s, median {r['cpu_median']:.3f} s"
        )

    measure("python -c pass", [sys.executable, "-c", "pass"], args.repeats)
    measure("import pounding", [sys.executable, "-c", "import pounding"], args.repeats)
    measure("pounding --help", [*pounding, "--help"], args.repeats)
    timed(run_cmd)  # fills the cache (the default one) when it is cold
    measure("warm pounding run", run_cmd, args.repeats)
    if args.cold_repeats > 0:
        cold = []
        for i in range(args.cold_repeats):
            cache = tmp / f"numba-cache-{i}"
            cold.append(timed(run_cmd, {"NUMBA_CACHE_DIR": str(cache)}))
        results["cold pounding run"] = stats(cold)
        results["cold pounding run"]["notice"] = cold[0][2].splitlines()[0] if cold[0][2] else ""
    else:  # not re-measured: the previous file's figures, marked as such
        import json

        previous = out_dirs(args.quick)[0] / "startup.json"
        old = json.loads(previous.read_text()) if previous.is_file() else {}
        kept = old.get("cold pounding run")
        if kept is not None:
            kept.setdefault(
                "not_remeasured",
                f"kept from the run of commit {old.get('machine', {}).get('commit', '?')}",
            )
            results["cold pounding run"] = kept
    r = results.get("cold pounding run")
    if r is not None:
        print(
            f"{'cold pounding run':28s} wall min {r['wall_min']:.1f} s, median "
            f"{r['wall_median']:.1f} s; CPU min {r['cpu_min']:.1f} s, median {r['cpu_median']:.1f} "
            f"s; notice: {r.get('notice')!r}"
            + (" (not re-measured)" if args.cold_repeats == 0 else "")
        )
    results["results.save (in process)"] = save_time(max(5, args.repeats), out_nc)
    print(f"results.save in process: {results['results.save (in process)']}")
    if args.install:
        results.update(after_install(tmp))
    shutil.rmtree(tmp, ignore_errors=True)
    payload = {
        "command": "python benchmarks/startup.py "
        + " ".join(sys.argv[1:] if argv is None else argv),
        "machine": info,
        "load_average": os.getloadavg(),
        "case": str(CASE.relative_to(ROOT)),
        **results,
    }
    path = write_json("startup.json", payload, out_dirs(args.quick)[0])
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
