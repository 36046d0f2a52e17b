"""Regenerate ``elcentro_spectrum_lsim.csv``: an independent response-spectrum snapshot.

Not computed by ``pounding.spectra``: each oscillator is integrated with ``scipy.signal.lsim``
(matrix exponential with first-order hold, exact for linearly interpolated input) on a grid of
at least 400 points per period and 8 per record step, with 1.5 periods of zero input after the record; peaks are read
off that fine grid. Run from the repository root (needs ../shared/data):

    python tests/data/make_elcentro_spectrum.py
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from scipy import signal

G = 9.80665
HERE = Path(__file__).resolve().parent
RECORD = HERE.parents[2] / "shared" / "data" / "ground_motions" / "elcentro_1940_ns_g_dt002.txt"
PERIODS = [0.02, 0.05, 0.1, 0.2, 0.3, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0, 5.0, 10.0]
DAMPINGS = [0.02, 0.05]


def peaks(t, a, period, zeta, per_period=400):
    w = 2 * np.pi / period
    system = signal.StateSpace(
        [[0, 1], [-w * w, -2 * zeta * w]], [[0], [-1]], np.eye(2), [[0], [0]]
    )
    dt = t[1] - t[0]
    m = max(8, int(np.ceil(per_period * dt / period)))
    h = dt / m
    n = int(round((t[-1] + 1.5 * period) / h)) + 1
    fine = h * np.arange(n)
    u = np.interp(fine, t, a, right=0.0)
    _, _, x = signal.lsim(system, u, fine, interp=True)
    sd = np.max(np.abs(x[:, 0]))
    sv = np.max(np.abs(x[:, 1]))
    sa = np.max(np.abs(w * w * x[:, 0] + 2 * zeta * w * x[:, 1]))
    return sd, sv, sa


def main() -> None:
    data = np.loadtxt(RECORD)
    t, a = data[:, 0], data[:, 1] * G
    rows = ["damping,period_s,Sd_m,Sv_m_per_s,Sa_m_per_s2"]
    for zeta in DAMPINGS:
        for period in PERIODS:
            sd, sv, sa = peaks(t, a, period, zeta)
            rows.append(f"{zeta},{period},{sd:.8e},{sv:.8e},{sa:.8e}")
    (HERE / "elcentro_spectrum_lsim.csv").write_text("\n".join(rows) + "\n")


if __name__ == "__main__":
    main()
