"""Cost of a city block: five buildings in a row, contacts at every common floor, default settings.

Rows of five uniform buildings with n floors each (n = 5, 10, 20, 40, 80: 25 to 400 dofs), periods
0.1 n × (0.8, 1.0, 1.2, 0.9, 1.1) s, 3.0e5 kg floors, 5 % damping, 4 cm gaps, the benchmark law
``lankarani_nikravesh`` (k_h = 2.75e9 N/m^1.5, e = 0.65) at every common floor (4 n gap elements),
under the benchmark record (30 s, :func:`models.record`). CPU time per analysis (``run`` with
default options, median of ``--repeats`` after a warm-up call) and the exponent of time against dofs
(least squares, log-log). The issue-14 target: time ∝ dofs^≤1.1 and the 400-dof row ≤ 4 s CPU.

    python benchmarks/row_scaling.py            # n = 5 ... 80, 3 repeats
    python benchmarks/row_scaling.py --quick    # n = 5, 10, 20; 1 repeat
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _common import machine, machine_markdown, out_dirs, write_json  # noqa: E402
from models import ALL_LAW_PARAMS, DAMPING, FLOOR_MASS, record  # noqa: E402

from pounding.simulate import AnalysisOptions, run  # noqa: E402
from pounding.structure import ShearBuilding  # noqa: E402
from pounding.system import Contact, assemble  # noqa: E402

FACTORS = (0.8, 1.0, 1.2, 0.9, 1.1)
LAW = "lankarani_nikravesh"


def row(n: int):
    blds = [
        ShearBuilding.uniform(chr(65 + i), n, period=0.1 * n * f, mass=FLOOR_MASS, damping=DAMPING)
        for i, f in enumerate(FACTORS)
    ]
    contacts = [
        Contact(a.name, b.name, 0.04, LAW, floors="common", **ALL_LAW_PARAMS[LAW])
        for a, b in zip(blds[:-1], blds[1:], strict=True)
    ]
    return assemble(blds, contacts)


def cpu_time(system, gm, repeats: int) -> tuple[float, object]:
    opts = AnalysisOptions()
    raw, _ = run(system, gm, opts)
    times = []
    for _ in range(repeats):
        t0 = time.process_time()
        raw, _ = run(system, gm, opts)
        times.append(time.process_time() - t0)
    return float(np.median(times)), raw


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--floors", default="5,10,20,40,80")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args(argv)
    floors = [int(x) for x in args.floors.split(",")]
    if args.quick:
        floors, args.repeats = [5, 10, 20], 1
    gm, ref = record()
    info = machine()
    print(f"record {ref}; {machine_markdown(info)}")
    print("| floors | dofs | gap elements | impacts | CPU per analysis [s] |")
    print("|---:|---:|---:|---:|---:|")
    rows = []
    for n in floors:
        system = row(n)
        t, raw = cpu_time(system, gm, args.repeats)
        n_imp = len(raw.impacts["element"])
        rows.append({"floors": n, "dofs": system.n_dof, "gaps": len(system.elements),
                     "impacts": n_imp, "cpu_s": t})  # fmt: skip
        print(f"| {n} | {system.n_dof} | {len(system.elements)} | {n_imp} | {t:.3f} |", flush=True)
    dofs = np.array([r["dofs"] for r in rows], dtype=float)
    cpu = np.array([r["cpu_s"] for r in rows])
    slope = float(np.polyfit(np.log(dofs), np.log(cpu), 1)[0]) if len(rows) > 1 else float("nan")
    print(f"time per analysis ∝ dofs^{slope:.2f}")
    results, _ = out_dirs(args.quick)
    write_json("row_scaling.json", {"machine": info, "record": ref, "rows": rows, "exponent": slope},
               results)  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
