"""Impacts that conserve what they should: the reproducers of the impact-fidelity issue, measured.

1. Free impact through ``simulate()``: a nearly free mass (T = 2000 s) kicked into a wall at
   0.32 m/s; rebound/approach ratio against the law's single-impact restitution (independent DOP853
   free impact, ``effective_restitution``), every law, at steps_per_contact 40, 80, 160 (default).
2. Undamped row (3, 6, 10 storeys, T1 0.3/0.65/1.1 s), elastic contacts (linear, hertz), 15 s of
   El Centro NS then 15 s of free vibration: impacts, drift of the mechanical energy over the free
   part, contact_dissipated and the algorithmic term as fractions of the input, the balance error;
   for newmark and hht (α = −0.05).
3. Identical 10-storey buildings at zero gap under a 0.3 g harmonic: impacts counted (both paths).

    python benchmarks/impact_fidelity.py [--elcentro PATH]

Writes results/impact_fidelity.json.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _common import machine, write_json  # noqa: E402

from pounding.contact.calibrate import effective_restitution  # noqa: E402
from pounding.contact.laws import LAWS_BY_ID  # noqa: E402
from pounding.ground_motion import GroundMotion, harmonic  # noqa: E402
from pounding.records import read_record  # noqa: E402
from pounding.simulate import simulate  # noqa: E402
from pounding.structure import ModalDamping, ShearBuilding  # noqa: E402
from pounding.system import Contact, assemble  # noqa: E402
from pounding.units import G  # noqa: E402

ELCENTRO = (
    Path(__file__).resolve().parents[2] / "shared/data/ground_motions/elcentro_1940_ns_g_dt002.txt"
)


def _params(name: str) -> dict:
    p = {"k": 1e9 if name in ("linear", "kelvin", "kelvin_approach", "bilinear") else 2.75e9}
    if name not in ("linear", "hertz"):
        p["e"] = 0.65
    if name == "bilinear":
        p["delta_m"] = 0.005
    return p


def free_impacts() -> list[dict]:
    mass = 1e5
    building = ShearBuilding(
        "A", [mass], [mass * (2 * math.pi / 2000.0) ** 2], damping=ModalDamping((0.0,))
    )
    t = 0.005 * np.arange(101)
    ground = GroundMotion(np.where(t <= 0.05, -10.0 * np.sin(np.pi * t / 0.05), 0.0), 0.005)
    rows = []
    for law in LAWS_BY_ID:
        if law.is_bumper or law.is_filler:
            continue  # a layer in the gap: no single e to compare with (tests/test_bumper.py)
        p = _params(law.name)
        system = assemble([building], [Contact("A", "wall", gap=0.01, law=law.name, **p)])
        row = {"law": law.name}
        for spc in (40, 80, 160):
            ds = simulate(system, ground, steps_per_contact=spc)
            imp = ds.pounding.impacts()
            single = effective_restitution(law.name, mass=mass, v0=float(imp.v0.iloc[0]), **p)
            e = ds["energy"].isel(time=-1)
            row[f"restitution_error_{spc}"] = float(imp.restitution.iloc[0] - single.e_effective)
            row[f"contact_dissipated_over_input_{spc}"] = float(
                e.sel(term="contact_dissipated") / e.sel(term="input")
            )
        rows.append(row)
        print(
            f"{law.name:20s} rebound - single: "
            + "  ".join(f"{row[f'restitution_error_{s}']:+.2e}" for s in (40, 80, 160))
        )
    return rows


def _undamped(name: str, n: int, period: float) -> ShearBuilding:
    b = ShearBuilding.uniform(name, n, period=period, mass=3e5)
    return ShearBuilding(name, b.masses, b.stiffnesses, damping=ModalDamping((0.0,) * n))


def row(elcentro: Path) -> list[dict]:
    rec = read_record(elcentro, units="g", dt=0.02)
    n15 = int(round(15.0 / rec.dt))
    ground = GroundMotion(np.concatenate([rec.acceleration[:n15], np.zeros(n15)]), rec.dt)
    out = []
    for law in ("linear", "hertz"):
        contacts = [
            Contact("A", "B", gap=0.005, law=law, k=2.75e9),
            Contact("B", "C", gap=0.01, law=law, k=2.75e9),
        ]
        system = assemble(
            [_undamped("A", 3, 0.3), _undamped("B", 6, 0.65), _undamped("C", 10, 1.1)], contacts
        )
        for method in ("newmark", "hht"):
            ds = simulate(system, ground, method=method)
            e = ds["energy"]
            e_in = float(e.sel(term="input").max())
            mech = e.sel(term=["kinetic", "strain", "contact_stored"]).sum("term")
            free = mech.sel(time=slice(15.5, None)).values
            r = {
                "law": law,
                "method": method,
                "impacts": len(ds.pounding.impacts()),
                "mechanical_drift_free_over_input": float((free[-1] - free[0]) / e_in),
                "contact_dissipated_over_input": float(e.sel(term="contact_dissipated")[-1] / e_in),
                "algorithmic_over_input": float(e.sel(term="algorithmic")[-1] / e_in),
                "energy_balance_error": float(ds.attrs["energy_balance_error"]),
            }
            out.append(r)
            print(r)
    return out


def zero_gap() -> list[dict]:
    a = ShearBuilding.uniform("A", 10, period=1.0, mass=3e5)
    b = ShearBuilding.uniform("B", 10, period=1.0, mass=3e5)
    ground = harmonic(amplitude=0.3 * G, period=0.6, duration=8.0, dt=0.01)
    out = []
    for law in ("hertz", "hunt_crossley", "jankowski", "kelvin"):
        system = assemble([a, b], [Contact("A", "B", gap=0.0, law=law, k=2.75e9, e=0.65)])
        for method in ("newmark", "ivp"):
            ds = simulate(system, ground, method=method)
            out.append({"law": law, "method": method, "impacts": len(ds.pounding.impacts())})
            print(out[-1])
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--elcentro", type=Path, default=ELCENTRO)
    args = parser.parse_args()
    payload = {"machine": machine(), "free_impact": free_impacts(), "zero_gap": zero_gap()}
    if args.elcentro.is_file():
        payload["row"] = row(args.elcentro)
    print(write_json("impact_fidelity.json", payload))


if __name__ == "__main__":
    main()
