"""Yielding stories beside OpenSeesPy (issue 15): agreement and time per step.

Model b (3-story T1 0.3 s beside 8-story T1 1.0 s, 4 cm gap, contacts at floors 1-3) with the
``linear`` law (OpenSees ``ElasticPPGap``) and every story of both buildings yielding, under the
30 s benchmark record (:func:`models.record`), fixed dt, Newmark γ = 1/2, β = 1/4, Newton in both.

Cases (3 % hardening everywhere):

* ``bilinear`` yield drift 0.5 % and 0.2 % → OpenSees ``Steel01``;
* ``bouc_wen`` yield drift 0.5 %, n = 2, β = γ = 0.5, A = 1, no degradation → ``BoucWen``;
* ``takeda`` yield drift 0.5 %, unloading exponent a = 0.4 → ``Hysteretic``;
* ``imk`` yield drift 0.5 %, plastic drift 2 %, post-cap drift 10 %, residual 0.2, γ = 50 for all
  four deterioration modes, c = 1 → ``ModIMKPeakOriented``.

Also timed: the same model with elastic stories (``elastic_baseline`` in the JSON), both codes.

OpenSees arguments (read from SRC/material/uniaxial/*.cpp of OpenSees/OpenSees; see
:func:`opensees_model.story_material`), with k the story stiffness, F_y = k δ_y, δ_y = drift × h:

* ``Steel01 Fy=F_y E0=k b=0.03 a1=0 a2=1 a3=0 a4=1``: the trial stress σ_n + E0 Δε bounded by the
  hardening lines b E0 ε ± (1 − b) Fy, shifts 1 (no isotropic hardening), i.e. pounding's bilinear
  return map. a2 = a4 = 1 only keep the (zero) isotropic term finite.
* ``BoucWen alpha=0.03 ko=k n=2 gamma=γ/δ_y² beta=β/δ_y² Ao=1 deltaA=deltaNu=deltaEta=0
  tol=1e-13 maxIter=50``: OpenSees's z is in metres (z = δ_y ζ), F = α k x + (1 − α) k z =
  α k x + (1 − α) F_y ζ, dz/dx = A − |z|^n (γ' + β' sgn(Δx z)) so γ' = γ/δ_y^n, β' = β/δ_y^n.
  The tolerance is on z [m] (default 1e-8 m ≈ 7e-7 δ_y here).
* ``Hysteretic s1p=F_y e1p=δ_y s2p e2p=10 δ_y s3p e3p=20 δ_y`` (s = F_y + b k (e − δ_y)), the
  negative side mirrored, ``pinchX=pinchY=1 damage1=damage2=0 beta=a``: unloading at
  k (peak/δ_y)^(−a), reload from the zero-force drift to the peak (the yield point before the side
  yields), a partial unload reloads at the unloading stiffness until it meets that line.
* ``ModIMKPeakOriented Ke=k alfaPos=alfaNeg=0.03 My_pos=F_y My_neg=−F_y Ls=Ld=La=50 δ_y
  Lk=50 δ_y/2 Cs=Cd=Ca=Ck=1 thetaP±=0.02 h thetaPC±=0.10 h Resfac±=0.2 fracDisp±=1e3 m D±=1``:
  energy capacities Ls My etc. and 2 Lk My = γ F_y δ_y; cap at My/Ke + thetaP, post-cap slope
  −F_cap/thetaPC. Both reload through the last unloading point (OpenSees dlst, flst) when that
  line is steeper than the line to the peak. They differ in the unloading-stiffness loss at a
  reversal between two zero-force crossings: OpenSees takes the energy dissipated since the last
  crossing at every such reversal, pounding the energy since the last reversal (see RESULTS.md).

Damping: pounding's Rayleigh C = a0 M + a1 K0 is constant; OpenSees gets
``region ... -rayleigh a0 0 a1 0`` (β on the initial stiffness, not the tangent).

Per case and dt: peak |u| per building, peak story spring force per building (the largest |F| of
its stories: pounding ``raw.peak_story_force``, OpenSees ``EnvelopeElement ... force``), the
largest pointwise difference of floor displacements and of story forces on the 1 ms grid over
their peaks, µs per step of each code (minimum of ``--repeats``, alternating the two codes:
pounding ``simulate.run`` after a warm-up call, OpenSees ``analyze(N, dt)`` on a freshly built
model, building not timed), their ratio, pounding's peak story ductility and both codes' Newton
iterations (OpenSees: ``testIter()`` summed over ``analyze(1, dt)`` in the untimed history run).

    python benchmarks/compare_opensees_yielding.py                 # dt 1e-3 and 1e-4, 3 repeats
    python benchmarks/compare_opensees_yielding.py --repeats 5
    python benchmarks/compare_opensees_yielding.py --quick         # dt 1e-3 only, 1 repeat
    python benchmarks/compare_opensees_yielding.py --cases bouc_wen --dts 1e-3,5e-4,2.5e-4,1e-4
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import opensees_model as om  # noqa: E402
from _common import (  # noqa: E402
    fixed_step,
    machine,
    machine_markdown,
    write_run,
)
from compare_opensees import histories, loadavg, per_building  # noqa: E402
from models import DURATION, build, record  # noqa: E402

from pounding import Stories, assemble  # noqa: E402
from pounding.simulate import AnalysisOptions, run  # noqa: E402

OUTPUT_DT = 1e-3
LAW = "linear"
HARDENING = 0.03
#: label → (story model, yield drift, extra parameters)
CASES = {
    "bilinear": ("bilinear", 0.005, {}),
    "bilinear_low": ("bilinear", 0.002, {}),
    "bouc_wen": ("bouc_wen", 0.005, {"n": 2.0, "beta": 0.5, "gamma": 0.5, "A": 1.0}),
    "takeda": ("takeda", 0.005, {"unloading_exponent": 0.4}),
    "imk": ("imk", 0.005, {f"gamma_{m}": 50.0 for m in "scak"}),
}
TARGETS = {"peak_u": 0.005, "story_force": 0.01, "ratio": 50.0}


def yielding_system(model: str, yield_drift: float, extra: dict):
    base = build("b", LAW)
    stories = Stories(model, {"yield_drift": yield_drift, "hardening": HARDENING, **extra})
    buildings = [dataclasses.replace(b, stories=stories) for b in base.buildings]
    return assemble(buildings, base.contacts)


def story_peaks(system, peak: np.ndarray) -> np.ndarray:
    """Largest story force per building from per-row peaks."""
    b = system.stories.building
    return np.array([float(np.abs(peak[b == i]).max()) for i in range(len(system.buildings))])


def timed(ops, system, gm, dt: float, repeats: int) -> dict:
    opts = AnalysisOptions(**fixed_step(dt, duration=DURATION))
    n_steps = int(round(DURATION / dt))
    run(system, gm, opts)  # compile / load the cache
    t_ours, t_os = [], []
    info = {}
    for _ in range(repeats):
        t0 = time.perf_counter()
        _, info = run(system, gm, opts)
        t_ours.append(time.perf_counter() - t0)
        om.build(ops, system, gm)
        t_os.append(om.time_analysis(ops, n_steps, dt))
    out = {
        "n_steps": n_steps,
        "ours_run_all": t_ours,
        "os_analyze_all": t_os,
        "ours_us_per_step": 1e6 * min(t_ours) / n_steps,
        "os_us_per_step": 1e6 * min(t_os) / n_steps,
        "ours_newton": info.get("n_newton_iterations"),
    }
    out["ratio"] = out["os_us_per_step"] / out["ours_us_per_step"]
    return out


def compare(ops, system, gm, dt: float) -> dict:
    raw, h = histories(ops, system, gm, dt, per_step=True)
    pu_a = per_building(system, raw.peak_displacement)
    pu_b = per_building(system, h["peak_u"])
    pf_a = story_peaks(system, np.asarray(raw.peak_story_force))
    pf_b = story_peaks(system, h["peak_story_force"])
    n = min(len(raw.displacement), len(h["u"]))
    u_a, u_b = raw.displacement[:n], h["u"][:n]
    f_a, f_b = np.asarray(raw.story_force)[:n], h["story_force"][:n]
    st = system.stories
    drift = np.asarray(raw.peak_drift)[st.dof[:, 0]]
    ductility = drift / (st.params[:, 1] / st.params[:, 0])
    return {
        "ours_peak_u": pu_a.tolist(),
        "os_peak_u": pu_b.tolist(),
        "peak_u_rel": ((pu_b - pu_a) / pu_a).tolist(),
        "ours_peak_story_force": pf_a.tolist(),
        "os_peak_story_force": pf_b.tolist(),
        "story_force_rel": ((pf_b - pf_a) / pf_a).tolist(),
        "max_pointwise_u_rel": float(np.abs(u_a - u_b).max() / np.abs(u_a).max()),
        "max_pointwise_story_force_rel": float(np.abs(f_a - f_b).max() / np.abs(f_a).max()),
        "ours_peak_ductility": [
            float(ductility[st.building == i].max()) for i in range(len(system.buildings))
        ],
        "impacts": int(raw.impacts["element"].size),
        "ours_peak_contact_force": float(raw.peak_contact_force.max()),
        "os_peak_contact_force": float(h["peak_f"].max()),
        "os_newton": int(h["newton_iterations"]),
    }


def meets(row: dict) -> dict:
    return {
        "peak_u": max(abs(x) for x in row["peak_u_rel"]) <= TARGETS["peak_u"],
        "story_force": max(abs(x) for x in row["story_force_rel"]) <= TARGETS["story_force"],
        "ratio": row["ratio"] >= TARGETS["ratio"],
    }


def table(rows: list[dict]) -> str:
    lines = [
        "| case | dt [s] | peak u A, B: rel. diff | peak story F A, B: rel. diff | "
        "pointwise u / peak | pointwise F / peak | µs/step pounding | µs/step OpenSees | ratio | "
        "ductility A, B | Newton pounding / OpenSees |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r['case']} | {r['dt']:.0e} | "
            + ", ".join(f"{100 * x:+.3f} %" for x in r["peak_u_rel"])
            + " | "
            + ", ".join(f"{100 * x:+.3f} %" for x in r["story_force_rel"])
            + f" | {r['max_pointwise_u_rel']:.2e} | {r['max_pointwise_story_force_rel']:.2e} | "
            f"{r['ours_us_per_step']:.2f} | {r['os_us_per_step']:.1f} | {r['ratio']:.0f}× | "
            + ", ".join(f"{x:.2f}" for x in r["ours_peak_ductility"])
            + f" | {r['ours_newton']} / {r['os_newton']} |"
        )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cases", default=",".join(CASES), help="comma-separated labels")
    ap.add_argument("--dts", help="comma-separated fixed steps [s] (default 1e-3,1e-4)")
    ap.add_argument("--repeats", type=int, default=3, help="timing repeats per code (minimum)")
    ap.add_argument("--quick", action="store_true", help="dt 1e-3 only, 1 repeat")
    ap.add_argument("--out", default="opensees_yielding.json")
    args = ap.parse_args(argv)
    if args.dts is None:
        args.dts = "1e-3" if args.quick else "1e-3,1e-4"
    if args.quick:
        args.repeats = 1
    dts = [float(x) for x in args.dts.split(",")]
    ops = om.load_opensees()
    gm, ref = record()
    info = machine()
    print(f"record {ref}; {machine_markdown(info)}", flush=True)
    t_start = time.perf_counter()
    rows = []
    baseline = []
    for dt in dts:
        # the same model with elastic stories: the cost the yielding stories add, in both codes
        row = {"case": "elastic stories", "dt": dt, "loadavg": [loadavg()]}
        row.update(timed(ops, build("b", LAW), gm, dt, args.repeats))
        baseline.append(row)
        print(
            f"elastic stories dt={dt:.0e}: pounding {row['ours_us_per_step']:.2f} µs/step, "
            f"OpenSees {row['os_us_per_step']:.1f} µs/step, ×{row['ratio']:.0f}",
            flush=True,
        )
    for label in args.cases.split(","):
        model, yield_drift, extra = CASES[label]
        system = yielding_system(model, yield_drift, extra)
        for dt in dts:
            load0 = loadavg()
            row = {"case": label, "model": model, "yield_drift": yield_drift, "dt": dt}
            row.update(timed(ops, system, gm, dt, args.repeats))
            row.update(compare(ops, system, gm, dt))
            row["loadavg"] = [load0, loadavg()]
            row["meets"] = meets(row)
            rows.append(row)
            print(table([row]).splitlines()[-1], flush=True)
    print(table(rows))
    fields = {
        "duration": DURATION,
        "output_dt": OUTPUT_DT,
        "law": LAW,
        "hardening": HARDENING,
        "cases": {k: {"model": v[0], "yield_drift": v[1], **v[2]} for k, v in CASES.items()},
        "opensees_materials": om.STORY_MATERIALS,
        "targets": TARGETS,
        "rows": rows,
        "elastic_baseline": baseline,
    }
    write_run("compare_opensees_yielding", argv, info, ref, fields, args.out, args.quick, t_start)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
