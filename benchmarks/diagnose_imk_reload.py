"""Where pounding's IMK stories and OpenSees ``ModIMKPeakOriented`` part (issue 15), material by
material.

Runs the ``imk`` case of :mod:`compare_opensees_yielding` (model b, law linear, yield drift 0.5 %,
dt 1e-3 s) with γ = 50 for the four deterioration modes, with γ = 1e6 (deterioration negligible:
β ≤ E_i/(1e6 F_y δ_y)) and with the cap moved out (plastic drift 100 %). Then each story's drift
history of that run is fed, step by step, to both materials: pounding's kernel and OpenSees's
``ModIMKPeakOriented`` (``testUniaxialMaterial``/``setStrain``), so the two see the same drifts and
only their rules can differ. Per story: the largest force difference over the story's peak force,
the first step where it passes 1e-6, and there the force and tangent of both (units F_y, k) with
the drift in δ_y.

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
from pounding.stories import N_STORY_STATE, SS_F, imk_story_kernel  # noqa: E402

DT = 1e-3
VARIANTS = {
    "gamma 50": {f"gamma_{m}": 50.0 for m in "scak"},
    "gamma 1e6": {f"gamma_{m}": 1e6 for m in "scak"},
    "gamma 1e6, no cap": {**{f"gamma_{m}": 1e6 for m in "scak"}, "plastic_drift": 1.0},
}


def both_materials(ops, drift: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Rows (F pounding, F OpenSees, tangent pounding, tangent OpenSees) along a drift history."""
    ops.wipe()
    om.story_material(ops, 1, "imk", p)
    ops.testUniaxialMaterial(1)
    s0, s1 = np.zeros(N_STORY_STATE), np.zeros(N_STORY_STATE)
    rows = np.empty((drift.size, 4))
    for j, x in enumerate(drift):
        _, kd, _ = imk_story_kernel(float(x), 0.0, 0.0, s0, s1, p)
        s0[:] = s1
        ops.setStrain(float(x))
        rows[j] = s1[SS_F], ops.getStress(), kd + p[0], ops.getTangent()
    return rows


def main() -> int:
    ops = om.load_opensees()
    gm, ref = record()
    out = {}
    for name, extra in VARIANTS.items():
        system = yielding_system("imk", 0.005, extra)
        raw, _ = run(system, gm, AnalysisOptions(**fixed_step(DT, duration=DURATION, output_dt=DT)))
        st, u = system.stories, raw.displacement
        stories = []
        for r in range(len(st)):
            floor, below = (int(x) for x in st.dof[r])
            drift = u[:, floor] - (u[:, below] if below >= 0 else 0.0)
            k, fy = float(st.params[r, 0]), float(st.params[r, 1])
            rows = both_materials(ops, drift, st.params[r])
            diff = np.abs(rows[:, 0] - rows[:, 1]) / np.abs(rows[:, 0]).max()
            row = {"building": int(st.building[r]), "story": int(st.story[r]),
                   "ductility": float(np.abs(drift).max() * k / fy),
                   "max_force_diff_rel": float(diff.max())}  # fmt: skip
            if (diff > 1e-6).any():
                i = int(np.argmax(diff > 1e-6))
                row["first_beyond_1e-6"] = {
                    "t": i * DT,
                    "drift_dy": float(drift[i] * k / fy),
                    "force_fy": [float(rows[i, 0] / fy), float(rows[i, 1] / fy)],
                    "tangent_k": [float(rows[i, 2] / k), float(rows[i, 3] / k)],
                }
            stories.append(row)
            print(f"{name}: building {row['building']} story {row['story']} (ductility "
                  f"{row['ductility']:.2f}): largest force difference {diff.max():.2e} of its peak"
                  + (f", first > 1e-6 at t = {row['first_beyond_1e-6']['t']:.3f} s"
                     if "first_beyond_1e-6" in row else ""))  # fmt: skip
        out[name] = stories
    path = write_json(
        "opensees_imk_reload.json",
        {"command": "python benchmarks/diagnose_imk_reload.py", "machine": machine(),
         "record": ref, "dt": DT, "variants": out},
    )  # fmt: skip
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
