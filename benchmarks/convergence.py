"""Convergence (issue 5, item 4): error versus dt (Newmark) and versus rtol (solve_ivp), every law.

Model ``b`` (3-story beside 8-story, 3 contacts) under the benchmark record, 30 s.

Reference: the ``ivp`` path (DOP853, rtol = 1e-12, atol = 1e-14, events at every closure and
separation, restarts at every record sample), output every 0.1 ms. Its peak floor displacements are
refined by a parabola through the three output samples around each maximum (the dense-output
sampling of the ivp path alone leaves ~4e-6 relative error on them); its peak contact forces are
the ivp path's own (refined by a bounded search on the dense output). A Newmark run at a tiny step is
*not* used as the reference: below dt ≈ 2e-5 s its error grows again (round-off, see RESULTS.md).

Errors of a run against the reference:

* ``pointwise``: max over time (the run's output grid) and floors of |u − u_ref| / max |u_ref|;
* ``peak_u``: max over buildings of |peak|u| / peak|u_ref| − 1| (peaks tracked at every step);
* ``peak_f``: |max F / max F_ref − 1| over all gap elements.

Runs: Newmark average acceleration at fixed steps (``adaptive=False``), the default settings
(``simulate(system, record)`` with no options: the step control of pounding.simulate), and ivp
at a range of rtol (default rtol 1e-8). Plots mark the defaults.

    python benchmarks/convergence.py           # 12 laws, 7 steps, 6 tolerances (~3 min)
    python benchmarks/convergence.py --quick   # 4 laws, 4 steps, 3 tolerances
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _common import (  # noqa: E402
    fixed_step,
    fmt_time,
    machine,
    machine_markdown,
    out_dirs,
    write_json,
)
from models import ALL_LAW_PARAMS, DURATION, build, model_spec, record  # noqa: E402

from pounding.simulate import AnalysisOptions, run, simulate  # noqa: E402

REF_OUTPUT_DT = 1e-4
REF_RTOL = 1e-12
REF_ATOL = 1e-14
DEFAULT_RTOL = AnalysisOptions().rtol


def parabolic_peaks(u: np.ndarray) -> np.ndarray:
    """Peak |u| per column, refined by the parabola through the largest sample and its neighbours."""
    a = np.abs(u)
    out = a.max(axis=0)
    for j in range(u.shape[1]):
        i = int(np.argmax(a[:, j]))
        if 0 < i < len(u) - 1:
            y0, y1, y2 = u[i - 1, j], u[i, j], u[i + 1, j]
            den = y0 - 2.0 * y1 + y2
            if den != 0.0:
                out[j] = max(out[j], abs(y1 - 0.125 * (y2 - y0) ** 2 / den))
    return out


def per_building(system, values: np.ndarray) -> np.ndarray:
    return np.array(
        [
            values[int(o) : int(o) + b.n_floors].max()
            for b, o in zip(system.buildings, system.dof_offset, strict=True)
        ]
    )


class Reference:
    def __init__(self, system, gm):
        opts = AnalysisOptions(
            method="ivp",
            rtol=REF_RTOL,
            atol=REF_ATOL,
            dt=REF_OUTPUT_DT,  # sets the output grid of the ivp path
            output_dt=REF_OUTPUT_DT,
            duration=DURATION,
        )
        t0 = time.perf_counter()
        raw, _ = run(system, gm, opts)
        self.seconds = time.perf_counter() - t0
        self.time = raw.time
        self.u = raw.displacement
        self.scale = float(np.abs(raw.displacement).max())
        self.peak_u = per_building(
            system, np.maximum(parabolic_peaks(raw.displacement), raw.peak_displacement)
        )
        self.peak_f = float(raw.peak_contact_force.max())
        self.system = system

    def errors(self, raw) -> dict[str, float]:
        idx = np.rint(raw.time / REF_OUTPUT_DT).astype(int)
        ok = idx < len(self.time)
        diff = np.abs(raw.displacement[ok] - self.u[idx[ok]]).max()
        pu = per_building(self.system, raw.peak_displacement)
        return {
            "pointwise": float(diff / self.scale),
            "peak_u": float(np.abs(pu / self.peak_u - 1.0).max()),
            "peak_f": float(abs(raw.peak_contact_force.max() / self.peak_f - 1.0)),
        }


def observed_order(dts: list[float], errs: list[float], floor: float) -> float:
    """Least-squares slope of log(error) on log(dt), over errors above ``floor``."""
    x = np.log(np.asarray(dts))
    y = np.asarray(errs)
    keep = y > floor
    if keep.sum() < 2:
        return float("nan")
    return float(np.polyfit(x[keep], np.log(y[keep]), 1)[0])


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--model", default="b")
    ap.add_argument("--laws", help="comma-separated (default: all 12; quick: 4)")
    ap.add_argument(
        "--dts", help="fixed steps [s] (default 2e-3,1e-3,5e-4,2.5e-4,1e-4,5e-5,2.5e-5)"
    )
    ap.add_argument("--rtols", help="ivp tolerances (default 1e-4,...,1e-9)")
    ap.add_argument("--repeats", type=int, default=5, help="timing repeats of the default run")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--out", default=None)
    args = ap.parse_args(argv)
    quick = {
        "laws": "linear,kelvin,lankarani_nikravesh,jankowski",
        "dts": "2e-3,1e-3,5e-4,1e-4",
        "rtols": "1e-4,1e-6,1e-8",
    }
    full = {
        "laws": ",".join(ALL_LAW_PARAMS),
        "dts": "2e-3,1e-3,5e-4,2.5e-4,1e-4,5e-5,2.5e-5",
        "rtols": "1e-4,1e-5,1e-6,1e-7,1e-8,1e-9",
    }
    for key, value in (quick if args.quick else full).items():
        if getattr(args, key) is None:
            setattr(args, key, value)
    if args.quick:
        args.repeats = min(args.repeats, 2)
    out_name = args.out or "convergence"
    json_dir, png_dir = out_dirs(args.quick)
    laws = args.laws.split(",")
    dts = [float(x) for x in args.dts.split(",")]
    rtols = [float(x) for x in args.rtols.split(",")]

    gm, ref_name = record()
    info = machine()
    print(f"record {ref_name}; model {args.model}; {machine_markdown(info)}", flush=True)
    t_start = time.perf_counter()
    results = {}
    for law in laws:
        system = build(args.model, law)
        ref = Reference(system, gm)
        res = {"reference_seconds": ref.seconds, "newmark": [], "ivp": []}
        for dt in dts:
            opts = AnalysisOptions(**fixed_step(dt, duration=DURATION, output_dt=max(dt, 1e-3)))
            t0 = time.perf_counter()
            raw, rinfo = run(system, gm, opts)
            res["newmark"].append(
                {"dt": dt, "seconds": time.perf_counter() - t0, **ref.errors(raw)}
            )
        # the default settings: no options at all (compile cached by a first call)
        simulate(system, gm, duration=DURATION)
        times = []
        for _ in range(args.repeats):
            t0 = time.perf_counter()
            simulate(system, gm, duration=DURATION)
            times.append(time.perf_counter() - t0)
        raw, dinfo = run(system, gm, AnalysisOptions(duration=DURATION))
        res["default"] = {
            "seconds_simulate": float(np.median(times)),
            "seconds_all": times,
            "base_dt": dinfo["dt"],
            "n_substeps": dinfo.get("n_substeps"),
            "mean_dt": DURATION / dinfo["n_substeps"] if dinfo.get("n_substeps") else dinfo["dt"],
            "adaptive": dinfo.get("adaptive"),
            **ref.errors(raw),
        }
        for rtol in rtols:
            opts = AnalysisOptions(
                method="ivp", rtol=rtol, dt=1e-3, output_dt=1e-3, duration=DURATION
            )
            t0 = time.perf_counter()
            raw, iinfo = run(system, gm, opts)
            res["ivp"].append(
                {
                    "rtol": rtol,
                    "seconds": time.perf_counter() - t0,
                    "n_rhs": iinfo.get("n_rhs"),
                    **ref.errors(raw),
                }
            )
        nm = res["newmark"]
        res["order"] = {
            key: observed_order([r["dt"] for r in nm], [r[key] for r in nm], 1e-8)
            for key in ("pointwise", "peak_u", "peak_f")
        }
        results[law] = res
        d = res["default"]
        print(
            f"{law:20s} order (pointwise, peak u, peak F) = "
            + ", ".join(f"{v:.2f}" for v in res["order"].values())
            + f"; default: {fmt_time(d['seconds_simulate'])}, mean step {d['mean_dt']:.2e} s, "
            f"errors {d['pointwise']:.1e} / {d['peak_u']:.1e} / {d['peak_f']:.1e}; "
            f"reference {ref.seconds:.1f} s",
            flush=True,
        )
    payload = {
        "command": "python benchmarks/convergence.py "
        + " ".join(sys.argv[1:] if argv is None else argv),
        "machine": info,
        "record": ref_name,
        "model": args.model,
        "model_description": model_spec(args.model).description,
        "reference": {
            "method": "ivp DOP853",
            "rtol": REF_RTOL,
            "atol": REF_ATOL,
            "output_dt": REF_OUTPUT_DT,
        },
        "default_rtol": DEFAULT_RTOL,
        "laws": results,
        "wall_time": time.perf_counter() - t_start,
    }
    path = write_json(out_name + ".json", payload, json_dir)
    plot(payload, png_dir / f"{out_name}_dt.png", png_dir / f"{out_name}_rtol.png")
    print(f"wrote {path} and plots ({payload['wall_time']:.0f} s)")
    return 0


def plot(payload: dict, path_dt: Path, path_rtol: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    laws = list(payload["laws"])
    ncol = min(4, len(laws))
    nrow = -(-len(laws) // ncol)
    fig, axes = plt.subplots(nrow, ncol, figsize=(3.4 * ncol, 2.9 * nrow), squeeze=False)
    styles = {"pointwise": ("C0", "o"), "peak_u": ("C1", "s"), "peak_f": ("C2", "^")}
    labels = {
        "pointwise": "max |u − u_ref| / max |u_ref|",
        "peak_u": "peak |u|",
        "peak_f": "peak F",
    }
    for ax, law in zip(axes.flat, laws, strict=False):
        res = payload["laws"][law]
        dts = [r["dt"] for r in res["newmark"]]
        for key, (color, marker) in styles.items():
            ax.loglog(dts, [max(r[key], 1e-12) for r in res["newmark"]], color=color,
                      marker=marker, ms=3, label=labels[key])  # fmt: skip
            d = res["default"]
            ax.loglog([d["mean_dt"]], [max(d[key], 1e-12)], color=color, marker="*", ms=11,
                      mec="k", ls="none")  # fmt: skip
        x = np.array([min(dts), max(dts)])
        ax.loglog(x, 1e-2 * (x / x[-1]) ** 2, "k:", lw=0.8, label="slope 2")
        o = res["order"]
        ax.set_title(f"{law}\norder {o['pointwise']:.2f} / {o['peak_u']:.2f} / {o['peak_f']:.2f}",
                     fontsize=8)  # fmt: skip
        ax.tick_params(labelsize=7)
        ax.grid(True, which="major", lw=0.3)
    for ax in axes.flat[len(laws) :]:
        ax.axis("off")
    for ax in axes[-1]:
        ax.set_xlabel("dt [s] (★ default settings at their mean step)", fontsize=7)
    for ax in axes[:, 0]:
        ax.set_ylabel("relative error", fontsize=8)
    handles, lbls = axes.flat[0].get_legend_handles_labels()
    fig.legend(handles, lbls, loc="lower center", ncol=4, fontsize=8)
    fig.suptitle(
        f"Newmark (fixed dt) vs ivp reference (rtol {REF_RTOL:g}); model {payload['model']}, "
        f"{payload['record']}",
        fontsize=9,
    )
    fig.tight_layout(rect=(0, 0.05, 1, 0.96))
    fig.savefig(path_dt, dpi=110)
    plt.close(fig)

    fig, axes = plt.subplots(1, 3, figsize=(12, 3.6))
    for ax, key in zip(axes, styles, strict=True):
        for i, law in enumerate(laws):
            res = payload["laws"][law]["ivp"]
            ax.loglog([r["rtol"] for r in res], [max(r[key], 1e-12) for r in res],
                      marker="o", ms=3, color=f"C{i % 10}", ls="-" if i < 10 else "--",
                      label=law)  # fmt: skip
        ax.axvline(payload["default_rtol"], color="k", lw=1, ls=":")
        ax.set_title(labels[key] + " (dotted: default rtol)", fontsize=9)
        ax.set_xlabel("rtol", fontsize=8)
        ax.grid(True, which="major", lw=0.3)
        ax.tick_params(labelsize=7)
    axes[0].set_ylabel("relative error", fontsize=8)
    axes[-1].legend(fontsize=6, ncol=2)
    fig.suptitle(f"solve_ivp (DOP853) vs reference (rtol {REF_RTOL:g}); model {payload['model']}",
                 fontsize=9)  # fmt: skip
    fig.tight_layout()
    fig.savefig(path_rtol, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    raise SystemExit(main())
