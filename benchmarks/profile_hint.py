"""Where pounding's time per step goes (a hint for kernel work): model b, fixed dt, 30 s record.

Variants, each timed as the median of ``--repeats`` calls of ``pounding.simulate.run`` after a
warm-up call:

* ``free``: gaps x1000, no contact ever closes (the linear step: one solve with the stored inverse);
* ``free, output 50 ms``: the same with 10x fewer output rows (cost of storing output);
* ``contact``: the benchmark gaps (the law's Newton iterations during contact);
* ``contact, no onset location``: ``locate_onset=False``.

Per contact step = (t_contact − t_free · (N − N_c)) / N_c, with N_c = (time with at least one gap
closed) / dt: the extra cost of a step inside a contact.

    python benchmarks/profile_hint.py             # laws linear, lankarani_nikravesh, jankowski
    python benchmarks/profile_hint.py --quick
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _common import (  # noqa: E402
    contact_time,
    fixed_step,
    fmt_time,
    machine,
    machine_markdown,
    out_dirs,
    write_json,
)
from models import DURATION, build, record  # noqa: E402

from pounding.simulate import AnalysisOptions, run  # noqa: E402


def timed(system, gm, repeats: int, **options) -> tuple[float, dict, object]:
    opts = AnalysisOptions(**options)
    run(system, gm, opts)
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        raw, info = run(system, gm, opts)
        times.append(time.perf_counter() - t0)
    return float(np.median(times)), info, raw


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--model", default="b")
    ap.add_argument("--dt", type=float, default=1e-4)
    ap.add_argument("--laws", default="linear,lankarani_nikravesh,jankowski")
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args(argv)
    if args.quick:
        args.repeats = 2
    gm, ref = record()
    info = machine()
    print(f"record {ref}; model {args.model}; dt {args.dt:g}; {machine_markdown(info)}")
    n = int(round(DURATION / args.dt))
    base = fixed_step(args.dt, duration=DURATION)
    free = build(args.model, "linear", gap_scale=1000.0)
    t_free, _, _ = timed(free, gm, args.repeats, **base)
    t_free50, _, _ = timed(free, gm, args.repeats, **{**base, "output_dt": 0.05})
    out = {"n_steps": n, "free_per_step": t_free / n, "free_output50_per_step": t_free50 / n}
    print(
        f"free: {fmt_time(t_free / n)}/step; with output every 50 ms: {fmt_time(t_free50 / n)}/step"
    )
    out["laws"] = {}
    for law in args.laws.split(","):
        system = build(args.model, law)
        t_c, cinfo, raw = timed(system, gm, args.repeats, **base)
        t_nl, _, _ = timed(system, gm, args.repeats, **{**base, "locate_onset": False})
        tc = contact_time(raw.impacts["start"], raw.impacts["end"], DURATION)
        n_c = tc / args.dt
        per_contact = (t_c - t_free / n * (n - n_c)) / n_c
        row = {
            "per_step": t_c / n,
            "per_step_no_onset_location": t_nl / n,
            "contact_time": tc,
            "contact_steps": n_c,
            "per_contact_step": per_contact,
            "newton_iterations": cinfo.get("n_newton_iterations"),
            "substeps": cinfo.get("n_substeps"),
            "impacts": int(raw.impacts["element"].size),
        }
        # steps with every gap open take the exact linear map (no Newton iteration counted)
        row["newton_per_contact_step"] = (row["newton_iterations"] or 0) / n_c if n_c else 0.0
        out["laws"][law] = row
        print(
            f"{law:20s} {fmt_time(t_c / n)}/step overall, {fmt_time(per_contact)} per step in contact "
            f"({tc:.2f} s in contact = {100 * tc / DURATION:.0f} % of steps, "
            f"~{row['newton_per_contact_step']:.1f} Newton iterations per contact step); "
            f"without onset location {fmt_time(t_nl / n)}/step"
        )
    payload = {
        "command": "python benchmarks/profile_hint.py "
        + " ".join(sys.argv[1:] if argv is None else argv),
        "machine": info,
        "record": ref,
        "model": args.model,
        "dt": args.dt,
        **out,
    }
    path = write_json("profile_hint.json", payload, out_dirs(args.quick)[0])
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
