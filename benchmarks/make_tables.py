"""Markdown tables for RESULTS.md from the JSON files in benchmarks/results/.

python benchmarks/make_tables.py                 # all tables, to stdout and results/tables.md
python benchmarks/make_tables.py --dir results/quick
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _common import HERE, RESULTS, machine_markdown  # noqa: E402


def _load(directory: Path, name: str) -> dict | None:
    path = directory / name
    return json.loads(path.read_text()) if path.exists() else None


def _us(x: float) -> str:
    return f"{x * 1e6:.2f}"


def _pct(x: float) -> str:
    return f"{100 * x:+.4f}"


def _e(x: float) -> str:
    return f"{x:.1e}"


def header(payload: dict) -> str:
    return (
        f"Command: `{payload['command'].strip()}`  \nMachine: {machine_markdown(payload['machine'])}"
        f"  \nRecord: `{payload['record']}`; wall time of the command {payload['wall_time']:.0f} s"
    )


def opensees_tables(p: dict) -> str:
    out = [header(p), ""]
    models = sorted({r["model"] for r in p["rows"]}, key=list(p["models"]).index)
    for model in models:
        rows = [r for r in p["rows"] if r["model"] == model]
        out += [
            f"**Model {model}**: {p['models'][model]}. Timing (median; pounding "
            f"{len(rows[0]['ours_run_all'])} runs, OpenSees {len(rows[0]['os_analyze_all'])} runs):",
            "",
            "| law | dt [s] | steps | pounding µs/step | pounding run [ms] | pounding simulate [ms] "
            "| OpenSees µs/step | OpenSees analyze [s] | OpenSees / pounding | impacts | load avg |",
            "|---|---|---|---|---|---|---|---|---|---|---|",
        ]
        for r in rows:
            out.append(
                f"| {r['law']} | {r['dt']:.0e} | {r['n_steps']} | {_us(r['ours_per_step'])} "
                f"| {1e3 * r['ours_run']:.1f} | {1e3 * r['ours_simulate']:.1f} "
                f"| {_us(r['os_per_step'])} | {r['os_analyze']:.2f} | **{r['ratio']:.1f}** "
                f"| {r['impacts']} | {r['loadavg'][0]:.1f} |"
            )
        for r in [x for x in p.get("no_contact", []) if x["model"] == model]:
            out.append(
                f"| no contact (gaps ×1000) | {r['dt']:.0e} | {r['n_steps']} "
                f"| {_us(r['ours_per_step'])} | {1e3 * r['ours_run']:.1f} "
                f"| {1e3 * r['ours_simulate']:.1f} | {_us(r['os_per_step'])} "
                f"| {r['os_analyze']:.2f} | **{r['ratio']:.1f}** | 0 | {r['loadavg'][0]:.1f} |"
            )
        names = ", ".join(f"peak u {i + 1}" for i in range(len(rows[0]["ours_peak_u"])))
        out += [
            "",
            f"Agreement, OpenSees relative to pounding ({names} = per building, in %; peak F in %; "
            "pointwise = max |u_OS − u| / max |u| on the 1 ms grid)"
            + (
                "; and each code's error against the reference (pounding at dt = 1e-5 s): "
                "pointwise / peak F"
                if "ours_vs_ref" in rows[0]
                else ""
            )
            + ":",
            "",
        ]
        ref_cols = "| pounding vs ref | OpenSees vs ref " if "ours_vs_ref" in rows[0] else ""
        out += [
            "| law | dt [s] | pounding peak u [m] | pounding peak F [MN] "
            + " ".join(f"| Δ peak u {i + 1}" for i in range(len(rows[0]["ours_peak_u"])))
            + f" | Δ peak F | pointwise {ref_cols}|",
            "|---" * (6 + len(rows[0]["ours_peak_u"]) + (2 if ref_cols else 0)) + "|",
        ]
        for r in rows:
            ag = r["os_vs_ours"]
            cells = [
                r["law"],
                f"{r['dt']:.0e}",
                ", ".join(f"{x:.4f}" for x in r["ours_peak_u"]),
                f"{r['ours_peak_f'] / 1e6:.3f}",
                *(_pct(x) for x in ag["peak_u_rel"]),
                _pct(ag["peak_f_rel"]),
                _e(ag["max_pointwise_rel"]),
            ]
            if "ours_vs_ref" in r:
                for key in ("ours_vs_ref", "os_vs_ref"):
                    cells.append(
                        f"{_e(r[key]['max_pointwise_rel'])} / {_e(abs(r[key]['peak_f_rel']))}"
                    )
            out.append("| " + " | ".join(cells) + " |")
        out.append("")
    return "\n".join(out)


def profile_table(p: dict) -> str:
    out = [
        header({**p, "wall_time": float("nan")}).rsplit(";", 1)[0],
        "",
        f"Model {p['model']}, fixed dt = {p['dt']:g} s, {p['n_steps']} steps. "
        f"No contact (gaps ×1000): **{_us(p['free_per_step'])} µs/step**; the same with output "
        f"every 50 ms instead of 5 ms: {_us(p['free_output50_per_step'])} µs/step.",
        "",
        "| law | µs/step overall | time in contact [s] | µs per step in contact | Newton iterations "
        "per contact step | µs/step without onset location |",
        "|---|---|---|---|---|---|",
    ]
    for law, r in p["laws"].items():
        out.append(
            f"| {law} | {_us(r['per_step'])} | {r['contact_time']:.2f} "
            f"| {_us(r['per_contact_step'])} | {r['newton_per_contact_step']:.1f} "
            f"| {_us(r['per_step_no_onset_location'])} |"
        )
    return "\n".join(out)


def scaling_table(p: dict) -> str:
    out = [
        header(p),
        "",
        f"Law {p['law']}, fixed dt = {p['dt']:g} s (per step), and the default settings (per "
        "analysis).",
        "",
        "| model | dofs | gap elements | impacts | pounding µs/step (contact / none) "
        "| OpenSees µs/step (contact / none) | OpenSees / pounding (contact / none) "
        "| pounding default analysis [ms] | default base dt [s], substeps |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in p["rows"]:
        c, f = r["contact"], r["free"]
        os_cells = (
            f"{_us(c['os_per_step'])} / {_us(f['os_per_step'])} | {c['ratio']:.0f} / {f['ratio']:.0f}"
            if "os_per_step" in c
            else "– | –"
        )
        d = r["default"]
        out.append(
            f"| {r['model']} | {r['n_dof']} | {r['n_contacts']} | {r['impacts']} "
            f"| {_us(c['ours_per_step'])} / {_us(f['ours_per_step'])} | {os_cells} "
            f"| {1e3 * d['seconds_simulate']:.1f} | {d['base_dt']:.2e}, {d['n_substeps']} |"
        )
    out += [
        "",
        "Fitted exponent of time per step against dofs (1 = linear): "
        + ", ".join(f"{k.replace('_', ' ')} {v:.2f}" for k, v in p["exponents"].items()),
    ]
    return "\n".join(out)


def convergence_tables(p: dict) -> str:
    out = [
        header(p),
        "",
        f"Model {p['model']}: {p['model_description']}. Reference: {p['reference']['method']}, "
        f"rtol {p['reference']['rtol']:g}, atol {p['reference']['atol']:g}, output every "
        f"{p['reference']['output_dt']:g} s. Errors: pointwise / peak |u| / peak F (relative).",
        "",
    ]
    laws = list(p["laws"])
    dts = [r["dt"] for r in p["laws"][laws[0]]["newmark"]]
    out += [
        "Newmark (average acceleration), fixed dt:",
        "",
        "| law | "
        + " | ".join(f"dt = {dt:.1e}" for dt in dts)
        + " | observed order (pointwise / peak u / peak F) |",
        "|---" * (len(dts) + 2) + "|",
    ]
    for law in laws:
        res = p["laws"][law]
        cells = [
            f"{_e(r['pointwise'])} / {_e(r['peak_u'])} / {_e(r['peak_f'])}" for r in res["newmark"]
        ]
        o = res["order"]
        out.append(
            f"| {law} | "
            + " | ".join(cells)
            + f" | {o['pointwise']:.2f} / {o['peak_u']:.2f} / {o['peak_f']:.2f} |"
        )
    out += [
        "",
        "Default settings (`simulate(system, record)`, no options; time = median of the "
        "whole call after a first, compiling call):",
        "",
        "| law | time per analysis [ms] | base dt [s] | substeps | mean step [s] | pointwise "
        "| peak u | peak F |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for law in laws:
        d = p["laws"][law]["default"]
        out.append(
            f"| {law} | {1e3 * d['seconds_simulate']:.1f} | {d['base_dt']:.2e} | {d['n_substeps']} "
            f"| {d['mean_dt']:.2e} | {_e(d['pointwise'])} | {_e(d['peak_u'])} | {_e(d['peak_f'])} |"
        )
    rtols = [r["rtol"] for r in p["laws"][laws[0]]["ivp"]]
    out += [
        "",
        f"solve_ivp (DOP853) error against the reference, by rtol (default rtol "
        f"{p['default_rtol']:g}); last column: time per analysis at the default rtol:",
        "",
        "| law | " + " | ".join(f"rtol = {r:.0e}" for r in rtols) + " | time [s] |",
        "|---" * (len(rtols) + 2) + "|",
    ]
    for law in laws:
        res = p["laws"][law]["ivp"]
        t_def = [r["seconds"] for r in res if r["rtol"] == p["default_rtol"]]
        out.append(
            f"| {law} | "
            + " | ".join(
                f"{_e(r['pointwise'])} / {_e(r['peak_u'])} / {_e(r['peak_f'])}" for r in res
            )
            + f" | {t_def[0]:.1f} |"
            if t_def
            else " | – |"
        )
    return "\n".join(out)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--dir", default=str(RESULTS))
    args = ap.parse_args(argv)
    directory = Path(args.dir)
    if not directory.is_absolute() and not directory.exists():
        directory = HERE / args.dir
    parts = []
    for name, func, title in (
        ("opensees.json", opensees_tables, "OpenSeesPy side by side"),
        ("profile_hint.json", profile_table, "Profile hint"),
        ("scaling.json", scaling_table, "Cost scaling"),
        ("convergence.json", convergence_tables, "Convergence"),
    ):
        payload = _load(directory, name)
        if payload is not None:
            parts.append(f"### {title}\n\n" + func(payload))
    text = "\n\n".join(parts) + "\n"
    (directory / "tables.md").write_text(text)
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
