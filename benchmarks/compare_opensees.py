"""Side by side with OpenSeesPy (issue 5, item 2): time per step and agreement, per law and dt.

For every model, law and fixed step dt, in one run:

* pounding: ``pounding.simulate.run`` (the compiled Newmark loop plus option handling; no Dataset)
  timed over ``--repeats`` calls after a warm-up call (compilation cached), and ``simulate`` (the
  whole analysis, Dataset included); time per step = run time / number of steps.
* OpenSeesPy: the same model (benchmarks/opensees_model.py), ``analyze(N, dt)`` timed on a freshly
  built model ``--os-repeats`` times (model building not timed), then a separate run for the
  histories (not timed).
* agreement: peak |u| per building, peak contact force, and the largest pointwise difference of the
  floor displacements on a 1 ms grid divided by the largest |u|; optionally both codes against a
  tight reference, pounding at ``--reference-dt`` (fixed step, located onsets).

Same scheme in both (Newmark γ = 1/2, β = 1/4, Newton), same fixed dt (pounding with
``adaptive=False``), same Rayleigh damping of the buildings and none on the contacts, same record
(linear between samples), both from rest with zero initial acceleration.

    python benchmarks/compare_opensees.py            # models a and b, 7 laws, dt 1e-3, 5e-4, 1e-4 (~5 min)
    python benchmarks/compare_opensees.py --quick    # model b, 3 laws, dt 1e-3 and 1e-4, 1 repeat
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import opensees_model as om  # noqa: E402
from _common import (  # noqa: E402
    contact_time,
    fixed_step,
    fmt_time,
    machine,
    machine_markdown,
    write_run,
)
from models import DURATION, LAW_PARAMS, build, model_spec, record  # noqa: E402

from pounding.simulate import AnalysisOptions, run, simulate  # noqa: E402

OUTPUT_DT = 1e-3


def per_building(system, values: np.ndarray) -> np.ndarray:
    return np.array(
        [
            values[int(o) : int(o) + b.n_floors].max()
            for b, o in zip(system.buildings, system.dof_offset, strict=True)
        ]
    )


def timed_pair(ops, system, gm, dt: float, repeats: int, os_repeats: int) -> dict:
    """Interleaved timings of pounding's run()/simulate() and OpenSees's analyze(N, dt).

    pounding runs with the default output step (5 ms); each OpenSees repeat rebuilds the model
    (not timed) and times ``analyze(N, dt)``. Interleaving spreads load from other processes over
    both codes.
    """
    opts = AnalysisOptions(**fixed_step(dt, duration=DURATION))
    sim_opts = fixed_step(dt, duration=DURATION)
    n_steps = int(round(DURATION / dt))
    run(system, gm, opts)  # compile / load the cache
    simulate(system, gm, **sim_opts)
    t_run, t_sim, t_os = [], [], []
    info = {}
    for i in range(max(repeats, os_repeats)):
        if i < repeats:
            t0 = time.perf_counter()
            _, info = run(system, gm, opts)
            t_run.append(time.perf_counter() - t0)
            t0 = time.perf_counter()
            simulate(system, gm, **sim_opts)
            t_sim.append(time.perf_counter() - t0)
        if ops is not None and i < os_repeats:
            om.build(ops, system, gm)
            t_os.append(om.time_analysis(ops, n_steps, dt))
    out = {
        "n_steps": n_steps,
        "ours_run": float(np.median(t_run)),
        "ours_run_all": t_run,
        "ours_simulate": float(np.median(t_sim)),
        "ours_substeps": info.get("n_substeps"),
        "ours_newton": info.get("n_newton_iterations"),
    }
    out["ours_per_step"] = out["ours_run"] / n_steps
    if t_os:
        out["os_analyze"] = float(np.median(t_os))
        out["os_analyze_all"] = t_os
        out["os_per_step"] = out["os_analyze"] / n_steps
        out["ratio"] = out["os_per_step"] / out["ours_per_step"]
    return out


def histories(ops, system, gm, dt: float, per_step: bool = False) -> tuple:
    """pounding's RawResult and OpenSees's histories on the 1 ms output grid (not timed);
    ``per_step``: OpenSees's story forces and Newton iterations too (:func:`om.run_histories`)."""
    opts = AnalysisOptions(**fixed_step(dt, duration=DURATION, output_dt=OUTPUT_DT))
    raw, _ = run(system, gm, opts)
    tags = om.build(ops, system, gm)
    n_steps = int(round(DURATION / dt))
    h = om.run_histories(ops, tags, n_steps, dt, int(round(OUTPUT_DT / dt)), per_step=per_step)
    return raw, h


def loadavg() -> float:
    try:
        return float(Path("/proc/loadavg").read_text().split()[0])
    except OSError:
        return float("nan")


def agreement(system, u_a, peak_u_a, peak_f_a, u_b, peak_u_b, peak_f_b) -> dict:
    """Metrics of b relative to a (a is the reference)."""
    pa = per_building(system, peak_u_a)
    pb = per_building(system, peak_u_b)
    fa = float(peak_f_a.max()) if peak_f_a.size else 0.0
    fb = float(peak_f_b.max()) if peak_f_b.size else 0.0
    n = min(len(u_a), len(u_b))
    return {
        "peak_u_rel": ((pb - pa) / pa).tolist(),
        "peak_f_rel": (fb - fa) / fa if fa else float("nan"),
        "max_pointwise_rel": float(np.abs(u_a[:n] - u_b[:n]).max() / np.abs(u_a[:n]).max()),
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--models", help="comma-separated (default a,b; quick: b)")
    ap.add_argument("--laws", help="comma-separated (default all seven; quick: three)")
    ap.add_argument("--dts", help="comma-separated fixed steps [s] (default 1e-3,5e-4,1e-4)")
    ap.add_argument("--repeats", type=int, default=5, help="pounding timing repeats (median)")
    ap.add_argument("--os-repeats", type=int, default=3, help="OpenSees timing repeats (median)")
    ap.add_argument("--reference-dt", type=float, default=1e-5,
                    help="fixed step of the pounding reference run; 0 to skip")  # fmt: skip
    ap.add_argument("--quick", action="store_true",
                    help="model b, laws linear/jankowski/lankarani_nikravesh, dt 1e-3 and 1e-4, "
                    "1 repeat, no reference")  # fmt: skip
    ap.add_argument("--out", default="opensees.json")
    args = ap.parse_args(argv)
    quick = {
        "models": "b",
        "laws": "linear,jankowski,lankarani_nikravesh",
        "dts": "1e-3,1e-4",
    }
    full = {"models": "a,b", "laws": ",".join(LAW_PARAMS), "dts": "1e-3,5e-4,1e-4"}
    for key, value in (quick if args.quick else full).items():
        if getattr(args, key) is None:
            setattr(args, key, value)
    if args.quick:
        args.repeats, args.os_repeats, args.reference_dt = 1, 1, 0.0
    models = args.models.split(",")
    laws = args.laws.split(",")
    dts = [float(x) for x in args.dts.split(",")]

    ops = om.load_opensees()
    gm, ref = record()
    info = machine()
    t_start = time.perf_counter()
    rows = []
    no_contact = []
    print(f"record {ref}; {machine_markdown(info)}", flush=True)
    for model in models:
        for law in laws:
            system = build(model, law)
            reference = None
            if args.reference_dt:
                opts = AnalysisOptions(
                    **fixed_step(args.reference_dt, duration=DURATION, output_dt=OUTPUT_DT)
                )
                reference, _ = run(system, gm, opts)
            for dt in dts:
                load0 = loadavg()
                row = {"model": model, "law": law, "dt": dt}
                row.update(timed_pair(ops, system, gm, dt, args.repeats, args.os_repeats))
                raw, b = histories(ops, system, gm, dt)
                row.update(
                    {
                        "impacts": int(raw.impacts["element"].size),
                        "contact_time": contact_time(
                            raw.impacts["start"], raw.impacts["end"], DURATION
                        ),
                        "ours_peak_u": per_building(system, raw.peak_displacement).tolist(),
                        "os_peak_u": per_building(system, b["peak_u"]).tolist(),
                        "ours_peak_f": float(raw.peak_contact_force.max()),
                        "os_peak_f": float(b["peak_f"].max()),
                        "os_vs_ours": agreement(
                            system,
                            raw.displacement,
                            raw.peak_displacement,
                            raw.peak_contact_force,
                            b["u"],
                            b["peak_u"],
                            b["peak_f"],
                        ),  # fmt: skip
                    }
                )
                if reference is not None:
                    ref_args = (
                        reference.displacement,
                        reference.peak_displacement,
                        reference.peak_contact_force,
                    )
                    row["ours_vs_ref"] = agreement(
                        system, *ref_args, raw.displacement, raw.peak_displacement,
                        raw.peak_contact_force,
                    )  # fmt: skip
                    row["os_vs_ref"] = agreement(
                        system, *ref_args, b["u"], b["peak_u"], b["peak_f"]
                    )
                row["loadavg"] = [load0, loadavg()]
                rows.append(row)
                ag = row["os_vs_ours"]
                print(
                    f"{model:5s} {law:20s} dt={dt:.0e}  ours {fmt_time(row['ours_per_step'])}/step "
                    f"({fmt_time(row['ours_run'])} run, {fmt_time(row['ours_simulate'])} simulate)  "
                    f"OpenSees {fmt_time(row['os_per_step'])}/step ({fmt_time(row['os_analyze'])})  "
                    f"x{row['ratio']:.1f}  peak u diff "
                    + ", ".join(f"{x:+.2e}" for x in ag["peak_u_rel"])
                    + f"  peak F diff {ag['peak_f_rel']:+.2e}  pointwise {ag['max_pointwise_rel']:.2e}"
                    + f"  load {row['loadavg'][0]:.1f}",
                    flush=True,
                )
        # cost without any contact (gaps x1000): the per-step baseline of the profile hint
        system = build(model, "linear", gap_scale=1000.0)
        for dt in dts:
            row = {"model": model, "law": "none (gaps x1000)", "dt": dt, "loadavg": [loadavg()]}
            row.update(timed_pair(ops, system, gm, dt, args.repeats, args.os_repeats))
            no_contact.append(row)
            print(
                f"{model:5s} {'no contact':20s} dt={dt:.0e}  ours {fmt_time(row['ours_per_step'])}"
                f"/step  OpenSees {fmt_time(row['os_per_step'])}/step  x{row['ratio']:.1f}",
                flush=True,
            )
    fields = {
        "duration": DURATION,
        "output_dt": OUTPUT_DT,
        "models": {m: model_spec(m).description for m in models},
        "law_params": {law: LAW_PARAMS[law] for law in laws},
        "rows": rows,
        "no_contact": no_contact,
    }
    write_run("compare_opensees", argv, info, ref, fields, args.out, args.quick, t_start)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
