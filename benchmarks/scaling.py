"""Cost versus model size (issue 5, item 1c and the scaling target): time per step and per analysis.

Models a (2 dofs, 1 contact), b (11, 3), c3row (23, 11), c20 (40, 20), c40 (80, 40), all with the
``lankarani_nikravesh`` (OpenSees ``Hertzdamp``) law, under the benchmark record, 30 s:

* fixed step ``--dt`` (default 5e-4 s): pounding's ``run`` and OpenSees's ``analyze(N, dt)``
  per step, with the contacts and with the gaps multiplied by 1000 (no contact ever closes);
* pounding's default settings (``simulate(system, record)``): time per analysis.

The exponent of time per step against the number of dofs (least squares, log-log) is printed and
saved; ``scaling.png`` plots it.

    python benchmarks/scaling.py            # 5 models, 3 repeats, OpenSees 2 repeats
    python benchmarks/scaling.py --quick    # a, b, c20; 1 repeat
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
    fmt_time,
    machine,
    machine_markdown,
    out_dirs,
    write_json,
)
from compare_opensees import loadavg, timed_pair  # noqa: E402
from models import DURATION, build, model_spec, record  # noqa: E402

from pounding.simulate import AnalysisOptions, run, simulate  # noqa: E402

LAW = "lankarani_nikravesh"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--models", default=None, help="default a,b,c3row,c20,c40 (quick: a,b,c20)")
    ap.add_argument("--dt", type=float, default=5e-4)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--os-repeats", type=int, default=2)
    ap.add_argument("--no-opensees", action="store_true")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--out", default=None)
    args = ap.parse_args(argv)
    if args.models is None:
        args.models = "a,b,c20" if args.quick else "a,b,c3row,c20,c40"
    if args.quick:
        args.repeats, args.os_repeats = 1, 1
    out_name = args.out or "scaling"
    json_dir, png_dir = out_dirs(args.quick)
    ops = None if args.no_opensees else om.load_opensees()
    gm, ref = record()
    info = machine()
    print(f"record {ref}; law {LAW}; dt {args.dt:g}; {machine_markdown(info)}", flush=True)
    t_start = time.perf_counter()
    rows = []
    for model in args.models.split(","):
        system = build(model, LAW)
        free = build(model, LAW, gap_scale=1000.0)
        row = {
            "model": model,
            "description": model_spec(model).description,
            "n_dof": system.n_dof,
            "n_contacts": len(system.elements),
            "loadavg": loadavg(),
        }
        row["contact"] = timed_pair(ops, system, gm, args.dt, args.repeats, args.os_repeats)
        row["free"] = timed_pair(ops, free, gm, args.dt, args.repeats, args.os_repeats)
        raw, _ = run(system, gm, AnalysisOptions(dt=args.dt, duration=DURATION))
        row["impacts"] = int(raw.impacts["element"].size)
        row["contact_time"] = contact_time(raw.impacts["start"], raw.impacts["end"], DURATION)
        simulate(system, gm, duration=DURATION)
        times = []
        for _ in range(args.repeats):
            t0 = time.perf_counter()
            simulate(system, gm, duration=DURATION)
            times.append(time.perf_counter() - t0)
        _, dinfo = run(system, gm, AnalysisOptions(duration=DURATION))
        row["default"] = {
            "seconds_simulate": float(np.median(times)),
            "base_dt": dinfo["dt"],
            "n_substeps": dinfo.get("n_substeps"),
        }
        rows.append(row)
        c, f = row["contact"], row["free"]
        os_txt = (
            f"OpenSees {fmt_time(c['os_per_step'])} / {fmt_time(f['os_per_step'])}  "
            f"x{c['ratio']:.0f} / x{f['ratio']:.0f}"
            if ops is not None
            else ""
        )
        print(
            f"{model:6s} {system.n_dof:3d} dofs {len(system.elements):3d} contacts "
            f"{row['impacts']:4d} impacts  per step with / without contact: ours "
            f"{fmt_time(c['ours_per_step'])} / {fmt_time(f['ours_per_step'])}  {os_txt}  "
            f"default analysis {fmt_time(row['default']['seconds_simulate'])}",
            flush=True,
        )
    n = np.array([r["n_dof"] for r in rows], dtype=float)
    exponents = {}
    for key in ("contact", "free"):
        for who in ("ours", "os"):
            name = f"{who}_per_step"
            if all(name in r[key] for r in rows) and len(rows) > 1:
                y = np.array([r[key][name] for r in rows])
                exponents[f"{who}_{key}"] = float(np.polyfit(np.log(n), np.log(y), 1)[0])
    if len(rows) > 1:
        y = np.array([r["default"]["seconds_simulate"] for r in rows])
        exponents["ours_default_analysis"] = float(np.polyfit(np.log(n), np.log(y), 1)[0])
    print(
        "exponents of time per step vs dofs: "
        + ", ".join(f"{k} {v:.2f}" for k, v in exponents.items())
    )
    payload = {
        "command": "python benchmarks/scaling.py "
        + " ".join(sys.argv[1:] if argv is None else argv),
        "machine": info,
        "record": ref,
        "law": LAW,
        "dt": args.dt,
        "rows": rows,
        "exponents": exponents,
        "wall_time": time.perf_counter() - t_start,
    }
    path = write_json(out_name + ".json", payload, json_dir)
    plot(payload, png_dir / f"{out_name}.png")
    print(f"wrote {path} ({payload['wall_time']:.0f} s)")
    return 0


def plot(payload: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker

    rows = payload["rows"]
    n = [r["n_dof"] for r in rows]
    fig, ax = plt.subplots(figsize=(6, 4))
    series = [
        ("ours_per_step", "contact", "pounding, with contacts", "C0", "-"),
        ("ours_per_step", "free", "pounding, no contact", "C0", "--"),
        ("os_per_step", "contact", "OpenSeesPy, with contacts", "C3", "-"),
        ("os_per_step", "free", "OpenSeesPy, no contact", "C3", "--"),
    ]
    for name, key, label, color, ls in series:
        if all(name in r[key] for r in rows):
            ax.loglog(n, [r[key][name] * 1e6 for r in rows], color=color, ls=ls, marker="o",
                      label=label)  # fmt: skip
    x = np.array([min(n), max(n)], dtype=float)
    y0 = rows[0]["contact"]["ours_per_step"] * 1e6
    ax.loglog(x, y0 * x / x[0], "k:", lw=0.8, label="linear in dofs")
    ax.set_xticks(n, [f"{r['n_dof']}\n({r['model']}, {r['n_contacts']} c.)" for r in rows])
    ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    ax.tick_params(axis="x", labelsize=7)
    ax.set_xlabel("degrees of freedom (model, gap elements)")
    ax.set_ylabel("time per step [µs]")
    ax.set_title(f"fixed dt = {payload['dt']:g} s, {payload['law']}, 30 s record", fontsize=9)
    ax.grid(True, which="both", lw=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    raise SystemExit(main())
