"""Cold compile of the Newmark kernels as a user meets it, for one or more checkouts in turns.

For each round and each tree: ``pounding run CASE -o OUT.nc`` in a fresh process with an empty
``NUMBA_CACHE_DIR`` (numba compiles the core the case needs), the tree's package first on
``PYTHONPATH``; wall and CPU (user + system of the child, ``resource.getrusage(RUSAGE_CHILDREN)``).
Trees alternate so that the host's drift (±15 % within minutes on a shared 2-core machine) falls on
each alike. ``--profile`` adds, per tree, one in-process ``simulate(case, baseline=True)`` with
numba's compile events: seconds per compiled function, exclusive of the functions it compiled.

    python benchmarks/cold_compile.py examples/three_vs_eight_story.toml --rounds 3
    python benchmarks/cold_compile.py CASE --tree /tmp/old-checkout --tree . --rounds 2 --profile
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _common import machine, machine_markdown  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
_CLI = "import sys; from pounding.cli import main; sys.argv = ['pounding', *sys.argv[1:]]; main()"
_PROFILE = """
import collections, sys, time
from numba.core import event
stack, own, calls = [], collections.Counter(), collections.Counter()
class Timer(event.Listener):
    def on_start(self, e):
        d = e.data.get("dispatcher")
        stack.append([d.py_func.__qualname__ if d is not None else "?", time.process_time(), 0.0])
    def on_end(self, e):
        name, t0, inner = stack.pop()
        spent = time.process_time() - t0
        own[name] += spent - inner
        calls[name] += 1
        if stack:
            stack[-1][2] += spent
event.register("numba:compile", Timer())
start = time.process_time()
import pounding
pounding.simulate(pounding.load_case(sys.argv[1]), baseline=True)
print(f"{time.process_time() - start:8.1f} s CPU in all, {sum(calls.values())} specialisations")
for name, seconds in own.most_common(int(sys.argv[2])):
    print(f"{seconds:8.2f} s  {calls[name]:3d}  {name}")
"""


def cold_run(tree: Path, case: Path, out: Path) -> tuple[float, float]:
    """(wall, CPU) [s] of ``pounding run case`` from ``tree`` with an empty kernel cache."""
    with tempfile.TemporaryDirectory() as cache:
        env = {**os.environ, "NUMBA_CACHE_DIR": cache, "PYTHONPATH": str(tree)}
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        start = time.perf_counter()
        subprocess.run([sys.executable, "-c", _CLI, "run", str(case), "-o", str(out)], env=env,
                       check=True, capture_output=True)  # fmt: skip
        wall = time.perf_counter() - start
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu


def profile(tree: Path, case: Path, top: int) -> str:
    """numba's compile time per function for ``simulate(case, baseline=True)`` from ``tree``."""
    with tempfile.TemporaryDirectory() as cache:
        env = {**os.environ, "NUMBA_CACHE_DIR": cache, "PYTHONPATH": str(tree)}
        done = subprocess.run([sys.executable, "-c", _PROFILE, str(case), str(top)], env=env,
                              check=True, capture_output=True, text=True)  # fmt: skip
    return done.stdout


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("case", type=Path, help="case file to run")
    ap.add_argument("--tree", type=Path, action="append", help="checkout (repeatable); default .")
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--profile", action="store_true", help="compile seconds per function")
    ap.add_argument("--top", type=int, default=25, help="functions listed by --profile")
    args = ap.parse_args(argv)
    trees = [t.resolve() for t in (args.tree or [ROOT])]
    case = args.case.resolve()
    print(machine_markdown(machine()))
    with tempfile.TemporaryDirectory() as tmp:
        for r in range(args.rounds):
            for tree in trees:
                wall, cpu = cold_run(tree, case, Path(tmp) / "out.nc")
                print(f"round {r + 1}  {tree}  {case.name}  {wall:7.1f} s wall  {cpu:7.1f} s CPU",
                      flush=True)  # fmt: skip
    if args.profile:
        for tree in trees:
            print(f"\n{tree}:\n{profile(tree, case, args.top)}", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
