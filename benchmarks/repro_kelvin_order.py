"""Reproducer: fixed-step Newmark converges at first order for ``kelvin`` after one impact of model b.

Model b with a single Kelvin gap element at floor 3 (roof of the 3-story building), benchmark record,
first 9.4 s. The impact at t = 9.2548 s (v0 = 0.743 m/s, the fastest) is followed by a displacement
error that halves (order ~1), not quarters, with dt when ``adaptive=False``; its onset time and v0
converge at second order, and the same impact converges at second order with ``adaptive=True``
(graded steps after the onset) and for the ``linear`` law at fixed dt. Reference: the ivp path at
rtol 1e-12.

    python benchmarks/repro_kelvin_order.py
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from models import ALL_LAW_PARAMS, model_spec, record  # noqa: E402

from pounding import Contact, assemble  # noqa: E402
from pounding.simulate import AnalysisOptions, run  # noqa: E402


def main() -> int:
    gm, _ = record()
    spec = model_spec("b")
    for law in ("kelvin", "linear"):
        system = assemble(
            spec.buildings,
            [Contact("A", "B", gap=0.04, law=law, floors=[(3, 3)], **ALL_LAW_PARAMS[law])],
        )
        ref, _ = run(
            system,
            gm,
            AnalysisOptions(
                method="ivp", rtol=1e-12, atol=1e-14, dt=1e-3, output_dt=1e-3, duration=9.4
            ),  # fmt: skip
        )
        window = (ref.time > 9.25) & (ref.time < 9.30)
        for adaptive in (False, True):
            errors = []
            for dt in (5e-4, 2.5e-4, 1.25e-4, 6.25e-5):
                raw, _ = run(
                    system,
                    gm,
                    AnalysisOptions(dt=dt, adaptive=adaptive, duration=9.4, output_dt=1e-3),
                )
                errors.append(np.abs(raw.displacement[window] - ref.displacement[window]).max())
            e = np.array(errors)
            print(
                f"{law:7s} adaptive={adaptive!s:5s} max |u - u_ref| in 9.25-9.30 s [m]: "
                + " ".join(f"{x:.2e}" for x in e)
                + "   local orders: "
                + " ".join(f"{x:.2f}" for x in np.log2(e[:-1] / e[1:]))
            )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
