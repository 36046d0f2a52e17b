"""Is the Kelvin disagreement with OpenSees just the clamp? An independent check on model a.

OpenSees's ``ViscoelasticGap`` applies F = k δ + c δ̇ whenever δ > 0, tension included; pounding's
``kelvin`` clamps it at zero. This script integrates model a (two SDOF buildings, one gap element) with
its own ``scipy.integrate.solve_ivp`` right-hand side, independent of pounding's integrators, for both
variants of the law (events at closure and separation, restarted there, rtol 1e-10), and compares:

* OpenSees (dt = 1e-4) with the **unclamped** independent solution,
* pounding (dt = 1e-4, fixed step) with the **clamped** independent solution,
* the two independent solutions with each other (the size of the definitional difference).

    python benchmarks/check_kelvin_tension.py
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

sys.path.insert(0, str(Path(__file__).resolve().parent))

import opensees_model as om  # noqa: E402
from _common import fixed_step, machine, machine_markdown, out_dirs, write_json  # noqa: E402
from models import DURATION, build, record  # noqa: E402

from pounding.simulate import AnalysisOptions, run  # noqa: E402

DT = 1e-4
OUTPUT_DT = 1e-3


def independent(system, gm, *, clamp: bool) -> np.ndarray:
    """Floor displacements on the 1 ms grid, Kelvin contact clamped at 0 or not."""
    M, C, K = system.mass, system.damping, system.stiffness
    Minv = np.linalg.inv(M)
    iota = system.influence
    el = system.elements
    (ia, ib), (sa, sb) = el.el_dof[0], el.el_sign[0]
    g, k, c = el.el_gap[0], el.el_params[0, 0], el.el_params[0, 2]
    n = system.n_dof
    t_rec = gm.time
    a_rec = gm.acceleration

    def delta(y):
        return sa * y[ia] + sb * y[ib] - g, sa * y[n + ia] + sb * y[n + ib]

    def rhs(t, y, closed):
        u, v = y[:n], y[n:]
        f = np.zeros(n)
        if closed:
            d, dd = delta(y)
            force = k * d + c * dd
            if clamp:
                force = max(force, 0.0)
            f[ia] += sa * force
            f[ib] += sb * force
        ag = np.interp(t, t_rec, a_rec, right=0.0)
        return np.concatenate((v, Minv @ (-M @ iota * ag - C @ v - K @ u - f)))

    def event(t, y, closed):
        return delta(y)[0]

    event.terminal = True
    t_out = OUTPUT_DT * np.arange(int(round(DURATION / OUTPUT_DT)) + 1)
    u_out = np.zeros((t_out.size, n))
    y = np.zeros(2 * n)
    t = 0.0
    closed = False
    while t < DURATION - 1e-12:
        event.direction = -1.0 if closed else 1.0
        mask = (t_out >= t) & (t_out <= DURATION)
        sol = solve_ivp(rhs, (t, DURATION), y, method="DOP853", rtol=1e-10, atol=1e-13,
                        events=event, args=(closed,), dense_output=True,
                        max_step=gm.dt / 2)  # fmt: skip
        t_end = sol.t_events[0][0] if sol.t_events[0].size else DURATION
        sel = mask & (t_out <= t_end)
        u_out[sel] = sol.sol(t_out[sel])[:n].T
        if sol.t_events[0].size:
            # restart just past the event so it does not fire again at the restart point
            y = sol.y_events[0][0]
            t = t_end
            closed = not closed
        else:
            t = DURATION
    return u_out


def main() -> int:
    gm, ref = record()
    system = build("a", "kelvin")
    info = machine()
    print(f"record {ref}; {machine_markdown(info)}")
    unclamped = independent(system, gm, clamp=False)
    clamped = independent(system, gm, clamp=True)
    raw, _ = run(
        system, gm, AnalysisOptions(**fixed_step(DT, duration=DURATION, output_dt=OUTPUT_DT))
    )
    ops = om.load_opensees()
    tags = om.build(ops, system, gm)
    h = om.run_histories(ops, tags, int(round(DURATION / DT)), DT, int(round(OUTPUT_DT / DT)))
    scale = np.abs(clamped).max()

    def diff(a, b):
        return float(np.abs(a - b).max() / scale)

    out = {
        "independent_clamped_vs_unclamped": diff(clamped, unclamped),
        "opensees_vs_unclamped": diff(h["u"], unclamped),
        "opensees_vs_clamped": diff(h["u"], clamped),
        "pounding_vs_clamped": diff(raw.displacement, clamped),
        "pounding_vs_unclamped": diff(raw.displacement, unclamped),
        "pounding_vs_opensees": diff(raw.displacement, h["u"]),
    }
    for key, value in out.items():
        print(f"{key:36s} max |Δu| / max |u| = {value:.2e}")
    write_json(
        "kelvin_tension.json",
        {
            "command": "python benchmarks/check_kelvin_tension.py",
            "machine": info,
            "record": ref,
            "dt": DT,
            **out,
        },
        out_dirs(False)[0],
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
