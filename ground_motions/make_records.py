"""Regenerate the synthetic records in this folder: ``python ground_motions/make_records.py``.

Every record is made by :mod:`pounding.synthetic` from the seed and parameters below (also
written in each file's header), so the files can be checked and rebuilt by anyone.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pounding import records, spectra, synthetic
from pounding.ground_motion import GroundMotion
from pounding.units import G

HERE = Path(__file__).resolve().parent


def processed(gm: GroundMotion) -> GroundMotion:
    """Standard processing of a record (Boore & Bommer 2005): 0.1-25 Hz zero-phase band-pass, cubic
    baseline correction, rescaled to the original PGA (:func:`pounding.synthetic.standard_processing`,
    also what ``synthetic:`` record references get unless ``raw=true``)."""
    return synthetic.standard_processing(gm)


def make() -> dict[str, object]:
    """The shipped records by file name (without writing them)."""
    out: dict[str, object] = {}
    out["kanai_tajimi_firm_seed1.txt"] = processed(
        synthetic.kanai_tajimi(
            seed=1,
            duration=20.0,
            dt=0.01,
            omega_g=15.6,
            zeta_g=0.6,
            envelope_name="jennings",
            pga=0.3 * G,
        )
    ).replace(name="Kanai-Tajimi firm soil, seed 1, PGA 0.3 g")
    out["clough_penzien_soft_seed2.txt"] = processed(
        synthetic.clough_penzien(
            seed=2,
            duration=25.0,
            dt=0.01,
            omega_g=6.0,
            zeta_g=0.4,
            omega_f=0.6,
            zeta_f=0.4,
            envelope_name="saragoni-hart",
            pga=0.25 * G,
        )
    ).replace(name="Clough-Penzien soft soil, seed 2, PGA 0.25 g")
    periods = np.geomspace(0.02, 4.0, 100)
    target = spectra.eurocode8_spectrum(periods, a_g=0.3 * G, ground_type="C", spectrum_type=1)
    gm = synthetic.spectrum_compatible(
        periods,
        target.values,
        duration=20.0,
        dt=0.01,
        seed=3,
        tolerance=0.1,
        name="Eurocode 8 Type 1 ground C a_g 0.3 g spectrum-compatible, seed 3",
    )
    gm.metadata["target"] = {"code": "ec8", "a_g": 0.3 * G, "ground_type": "C", "spectrum_type": 1}
    out["ec8_type1_groundC_seed3.txt"] = processed(gm)
    return out


def main() -> None:
    for name, gm in make().items():
        records.write_record(gm, HERE / name, format="text", units="g")
        print(f"wrote {name}: {gm.npts} samples, PGA {gm.pga / G:.3f} g")


if __name__ == "__main__":
    main()
