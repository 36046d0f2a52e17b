"""Cost of yielding stories per step (issue 15: ≤ 2× the elastic model's): model b, fixed dt.

Model b (3-story T1 0.3 s beside 8-story T1 1.0 s, 4 cm gap, lankarani_nikravesh) under the 30 s
benchmark record at dt = 1e-4 s, timed as the median of ``--repeats`` calls of
``pounding.simulate.run`` after a warm-up call, with

* ``elastic``: the stories of :mod:`benchmarks.models`;
* ``bilinear``: every story of both buildings bilinear, yield drift 0.5 % of the height, hardening 3 %
  (the 3-story building yields under this record, the 8-story one does not);
* ``bilinear, low yield``: yield drift 0.2 %, so both buildings yield;
* ``bouc_wen``: Bouc–Wen stories (n = 2, β = γ = 0.5, 3 % hardening), yield drift 0.5 %: smooth,
  so no step is linear (Newton in every step);
* ``takeda``: Takeda stories (a = 0.4, 3 % hardening), yield drift 0.5 %;
* ``imk``: IMK stories (3 % hardening, plastic drift 2 %, post-cap drift 10 %, γ = 50 for all four
  deterioration modes), yield drift 0.5 %.

    python benchmarks/yielding_cost.py [--repeats 5] [--quick]
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _common import finish_per_step, fixed_step, median_time  # noqa: E402
from models import DURATION, build, record  # noqa: E402

from pounding import Stories, assemble  # noqa: E402
from pounding.simulate import AnalysisOptions, run  # noqa: E402

_DETERIORATION = {f"gamma_{m}": 50.0 for m in "scak"}


def _yielding(system, yield_drift: float, model: str = "bilinear"):
    extra = _DETERIORATION if model == "imk" else {}
    stories = Stories(model, {"yield_drift": yield_drift, "hardening": 0.03, **extra})
    buildings = [dataclasses.replace(b, stories=stories) for b in system.buildings]
    return assemble(buildings, system.contacts)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--dt", type=float, default=1e-4)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args(argv)
    repeats = 2 if args.quick else args.repeats
    gm, rec = record()
    base = build("b", "lankarani_nikravesh")
    opts = AnalysisOptions(**fixed_step(args.dt), duration=DURATION)
    n_steps = round(DURATION / args.dt)
    rows = {}
    for label, system in (
        ("elastic", base),
        ("bilinear", _yielding(base, 0.005)),
        ("bilinear, low yield", _yielding(base, 0.002)),
        ("bouc_wen", _yielding(base, 0.005, "bouc_wen")),
        ("takeda", _yielding(base, 0.005, "takeda")),
        ("imk", _yielding(base, 0.005, "imk")),
    ):
        run(system, gm, opts)  # compiled and cached before the timing
        seconds, _, (raw, info) = median_time(lambda s=system: run(s, gm, opts), repeats)
        ductility = (
            np.asarray(raw.peak_drift)[system.stories.dof[:, 0]]
            / (system.stories.params[:, 1] / system.stories.params[:, 0])
            if len(system.stories)
            else np.zeros(0)
        )
        rows[label] = {
            "seconds": seconds,
            "us_per_step": 1e6 * seconds / n_steps,
            "newton_iterations": int(raw.info["n_newton_iterations"]),
            "substeps": int(raw.info["n_substeps"]),
            "peak_ductility": float(ductility.max()) if ductility.size else None,
        }
        print(
            f"{label:22s} {rows[label]['us_per_step']:6.2f} µs/step  "
            f"({seconds:.3f} s, {rows[label]['newton_iterations']} Newton iterations, "
            f"peak story ductility {rows[label]['peak_ductility']})"
        )
    finish_per_step("yielding_cost", rows, "elastic", "ratio_to_elastic", rec, args.dt, argv,
                    args.quick)  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
