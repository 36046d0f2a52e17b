"""Where pounding's IMK stories and OpenSees ``ModIMKPeakOriented`` part (issue 15).

Runs the ``imk`` case of :mod:`compare_opensees_yielding` (model b, law linear, yield drift 0.5 %,
dt 1e-3 s) with γ = 50 for the four deterioration modes and with γ = 1e6 (deterioration
negligible: β ≤ E_i/(1e6 F_y δ_y)), and with the cap moved out (plastic drift 100 %). For each: the
first output step where the story forces differ by more than 1e-3 of their peak, the story, and
the secant slopes dF/dδ of both codes over the steps around it, in units of k, with drift and force
in units of δ_y and F_y.

    python benchmarks/diagnose_imk_reload.py
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import opensees_model as om  # noqa: E402
from _common import fixed_step, machine, write_json  # noqa: E402
from compare_opensees_yielding import yielding_system  # noqa: E402
from models import DURATION, record  # noqa: E402

from pounding.simulate import AnalysisOptions, run  # noqa: E402

DT = 1e-3
VARIANTS = {
    "gamma 50": {f"gamma_{m}": 50.0 for m in "scak"},
    "gamma 1e6": {f"gamma_{m}": 1e6 for m in "scak"},
    "gamma 1e6, no cap": {**{f"gamma_{m}": 1e6 for m in "scak"}, "plastic_drift": 1.0},
}


def main() -> int:
    ops = om.load_opensees()
    gm, ref = record()
    n_steps = int(round(DURATION / DT))
    out = {}
    for name, extra in VARIANTS.items():
        system = yielding_system("imk", 0.005, extra)
        raw, _ = run(system, gm, AnalysisOptions(**fixed_step(DT, duration=DURATION, output_dt=DT)))
        tags = om.build(ops, system, gm)
        h = om.run_histories(ops, tags, n_steps, DT, 1)
        fa, fb = np.asarray(raw.story_force), h["story_force"]
        n = min(len(fa), len(fb))
        diff = np.abs(fa[:n] - fb[:n])
        i = int(np.argmax(diff.max(axis=1) > 1e-3 * np.abs(fa).max()))
        r = int(np.argmax(diff[i]))
        st = system.stories
        floor, below = (int(x) for x in st.dof[r])
        k, fy = float(st.params[r, 0]), float(st.params[r, 1])
        dy = fy / k

        def drift(u, floor=floor, below=below):
            return u[:, floor] - (u[:, below] if below >= 0 else 0.0)

        da, db = drift(raw.displacement[:n]), drift(h["u"][:n])
        steps = []
        for j in range(i - 25, i + 3):
            steps.append(
                {
                    "t": j * DT,
                    "drift_dy": [da[j] / dy, db[j] / dy],
                    "force_fy": [fa[j, r] / fy, fb[j, r] / fy],
                    "slope_k": [
                        (fa[j, r] - fa[j - 1, r]) / (da[j] - da[j - 1]) / k,
                        (fb[j, r] - fb[j - 1, r]) / (db[j] - db[j - 1]) / k,
                    ],
                }
            )
        # OpenSees's dlstNeg/flstNeg: the last local minimum of drift at a negative force before
        # the divergence (where the last unloading from the negative side began), and the line
        # from the zero-force drift sp of the current reload through it
        mins = [
            j for j in range(1, i)
            if db[j] < db[j - 1] and db[j] <= db[j + 1] and fb[j, r] < 0.0
        ]  # fmt: skip
        jmin = mins[-1]
        z = next(j for j in range(i, jmin, -1) if fb[j - 1, r] >= 0.0 > fb[j, r])
        sp = db[z - 1] - fb[z - 1, r] * (db[z] - db[z - 1]) / (fb[z, r] - fb[z - 1, r])
        line_last = fb[jmin, r] / (db[jmin] - sp) / k
        line_yield = 1.0 / (1.0 + sp / dy)
        out[name] = {
            "first_divergence_t": i * DT,
            "story_row": r,
            "building": int(st.building[r]),
            "story": int(st.story[r]),
            "min_drift_before_dy": [float(da[:i].min() / dy), float(db[:i].min() / dy)],
            "max_drift_before_dy": [float(da[:i].max() / dy), float(db[:i].max() / dy)],
            "last_negative_reversal_before": {
                "t": jmin * DT,
                "drift_dy": float(db[jmin] / dy),
                "force_fy": float(fb[jmin, r] / fy),
            },
            "opensees_zero_force_drift_dy": float(sp / dy),
            "slope_to_last_unloading_point_k": float(line_last),
            "slope_to_yield_point_k": float(line_yield),
            "steps": steps,
            "max_pointwise_story_force_rel": float(diff.max() / np.abs(fa).max()),
        }
        print(f"{name}: first divergence at t = {i * DT:.3f} s, building {st.building[r]} story "
              f"{st.story[r]}; min/max drift before it {da[:i].min() / dy:+.4f}/"
              f"{da[:i].max() / dy:+.4f} δ_y; last negative reversal at t = {jmin * DT:.3f} s "
              f"({db[jmin] / dy:+.4f} δ_y, {fb[jmin, r] / fy:+.4f} F_y); OpenSees zero force at "
              f"{sp / dy:+.4f} δ_y; line from there to that point {line_last:.4f} k, to the yield "
              f"point (−δ_y, −F_y) {line_yield:.4f} k")  # fmt: skip
        for s in steps[-10:-6]:
            print(
                f"  t {s['t']:.3f}  drift/δ_y {s['drift_dy'][0]:+.5f} {s['drift_dy'][1]:+.5f}  "
                f"F/F_y {s['force_fy'][0]:+.5f} {s['force_fy'][1]:+.5f}  "
                f"slope/k pounding {s['slope_k'][0]:.4f} OpenSees {s['slope_k'][1]:.4f}"
            )
    path = write_json(
        "opensees_imk_reload.json",
        {"command": "python benchmarks/diagnose_imk_reload.py", "machine": machine(),
         "record": ref, "dt": DT, "variants": out},
    )  # fmt: skip
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
