"""Build hook: compile the numba kernels while the wheel is built, so that the first analysis after
``pip install .`` loads machine code instead of compiling for a minute and a half.

The compiled code goes into the wheel beside the sources (``__pycache__``, numba's own cache
format), with the marker ``pounding/_shipped_kernels.json``; the cache is keyed on the contents of
the sources, the numba version and the CPU, so it serves an install on the machine that built it and
is ignored (the kernels compile on first use, with a notice) anywhere else. Editable installs keep
compiling on first use or by ``pounding warmup``. ``POUNDING_BUILD_KERNELS=0`` skips the step; a
failure to compile only warns: the package works without the cache.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

from setuptools import setup
from setuptools.command.build_py import build_py

_COMPILE = (
    "import json, numba, sys; from pounding.warmup import warm_up; warm_up(every_path=True); "
    "import pounding; assert pounding.__file__.startswith(sys.argv[1]), pounding.__file__; "
    "from pounding._numba import SHIPPED_MARKER, source_stamp; "
    "print(json.dumps({'numba': numba.__version__, 'python': sys.version.split()[0], "
    "'source_stamp': source_stamp(), 'marker': SHIPPED_MARKER}))"
)


class build_py_with_kernels(build_py):
    """``build_py``, then the warm-up case run from the build directory to fill numba's cache."""

    def run(self) -> None:
        super().run()
        if self.editable_mode or os.environ.get("POUNDING_BUILD_KERNELS", "1") == "0":
            return
        package = Path(self.build_lib).resolve() / "pounding"
        for stale in package.rglob("__pycache__"):
            shutil.rmtree(stale)  # an earlier build's kernels would ride along in the wheel
        # the build directory first (the source tree is the working directory: it would win)
        env = {k: v for k, v in os.environ.items() if not k.startswith("NUMBA_")}
        path = [str(package.parent), *filter(None, [env.get("PYTHONPATH")])]
        env.update(PYTHONPATH=os.pathsep.join(path), PYTHONDONTWRITEBYTECODE="1")
        print(
            "compiling the numerical kernels into the wheel (about two minutes, once)", flush=True
        )
        start = time.perf_counter()
        res = subprocess.run(
            [sys.executable, "-c", _COMPILE, str(package)],
            env=env,
            cwd=package.parent,
            capture_output=True,
            text=True,
        )
        if res.returncode != 0:
            tail = (res.stderr.strip().splitlines() or ["?"])[-1]
            print(
                f"warning: kernels not compiled into the wheel ({tail}); they compile on first use"
            )
            return
        info = json.loads(res.stdout.strip().splitlines()[-1])
        marker = info.pop("marker")  # the package names its own marker file
        info["compile_seconds"] = round(time.perf_counter() - start, 1)
        (package / marker).write_text(json.dumps(info, indent=1) + "\n")
        print(f"kernels compiled in {info['compile_seconds']} s", flush=True)


setup(cmdclass={"build_py": build_py_with_kernels})
