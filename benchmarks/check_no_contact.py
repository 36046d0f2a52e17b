"""The OpenSees twin without contact: same masses, stiffnesses, damping and loading as pounding?

Every model with its gaps ×1000 (no contact ever closes), fixed dt = 1e-3 s, 30 s record: the largest
pointwise difference of the floor displacements between pounding and OpenSees, divided by the
largest |u|. Both solve the same linear Newmark recurrence, so only round-off should remain.

    python benchmarks/check_no_contact.py
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import opensees_model as om  # noqa: E402
from _common import fixed_step, machine, machine_markdown, out_dirs, write_json  # noqa: E402
from models import DURATION, MODELS, build, record  # noqa: E402

from pounding.simulate import AnalysisOptions, run  # noqa: E402

DT = 1e-3


def main() -> int:
    gm, ref = record()
    info = machine()
    print(f"record {ref}; dt {DT:g}; {machine_markdown(info)}")
    ops = om.load_opensees()
    out = {}
    for model in MODELS:
        system = build(model, "linear", gap_scale=1000.0)
        raw, _ = run(system, gm, AnalysisOptions(**fixed_step(DT, duration=DURATION, output_dt=DT)))
        tags = om.build(ops, system, gm)
        h = om.run_histories(ops, tags, int(round(DURATION / DT)), DT, 1)
        rel = float(np.abs(raw.displacement - h["u"]).max() / np.abs(raw.displacement).max())
        out[model] = rel
        print(f"{model:6s} {system.n_dof:3d} dofs: max |u_OS − u| / max |u| = {rel:.1e}")
    write_json(
        "no_contact.json",
        {
            "command": "python benchmarks/check_no_contact.py",
            "machine": info,
            "record": ref,
            "dt": DT,
            "max_pointwise_rel": out,
        },  # fmt: skip
        out_dirs(False)[0],
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
