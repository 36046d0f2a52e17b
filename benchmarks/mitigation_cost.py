"""Per-step cost of the mitigation elements on model b: a rubber bumper or a filler in the gap,
coupling links, and the 8-story building on soft soil, against the bare gap (issue 18's per-step
benchmark).

Fixed dt = 1e-4 s over the 30 s benchmark record, the median of ``--repeats`` runs after a first
(compiling) one; the same analysis as ``yielding_cost.py``'s elastic row with the contacts changed.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _common import finish_per_step, fixed_step, median_time  # noqa: E402
from models import DURATION, build, record  # noqa: E402

from pounding import Link, SoilFoundation, assemble  # noqa: E402
from pounding.simulate import AnalysisOptions, run  # noqa: E402


def _linked(system, link_type: str, **params):
    links = [Link("A", "B", type=link_type, floors="common", **params)]
    return assemble(system.buildings, system.contacts, links)


#: The soft clay of examples/soft_soil.toml under an 18 m x 18 m mat.
SOFT_CLAY = dict(shear_wave_velocity=120.0, density=1800.0, poisson=0.4, width=18.0, length=18.0,
                 mass=1.2e6)  # fmt: skip


def _on_soil(system, links=()):
    """The same row with its last (tallest) building on soft clay."""
    *rest, tall = system.buildings
    buildings = [*rest, dataclasses.replace(tall, soil=SoilFoundation(**SOFT_CLAY))]
    return assemble(buildings, system.contacts, links)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--dt", type=float, default=1e-4)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args(argv)
    repeats = 2 if args.quick else args.repeats
    gm, rec = record()
    opts = AnalysisOptions(**fixed_step(args.dt), duration=DURATION)
    n_steps = round(DURATION / args.dt)
    base = build("b", "lankarani_nikravesh")
    cases = (
        ("bare gap (lankarani_nikravesh)", base),
        ("rubber bumper", build("b", "bumper")),
        ("viscoelastic filler", build("b", "filler")),
        ("kelvin links + bare gap", _linked(base, "kelvin", k=5e7, c=5e5)),
        ("viscous dampers (alpha 0.5) + bare gap", _linked(base, "viscous", c=2e6, alpha=0.5)),
        ("kelvin links + bumper", _linked(build("b", "bumper"), "kelvin", k=5e7, c=5e5)),
        ("8-story on soft soil + bare gap", _on_soil(base)),
        (
            "soft soil + kelvin links + bumper",
            _on_soil(
                build("b", "bumper"), [Link("A", "B", type="kelvin", floors="common", k=5e7, c=5e5)]
            ),
        ),  # fmt: skip
    )
    rows = {}
    for label, system in cases:
        run(system, gm, opts)  # compiled and cached before the timing
        seconds, _, (raw, _info) = median_time(lambda s=system: run(s, gm, opts), repeats)
        rows[label] = {
            "seconds": seconds,
            "us_per_step": 1e6 * seconds / n_steps,
            "newton_iterations": int(raw.info["n_newton_iterations"]),
            "impacts": int(len(raw.impacts["v0"])),
        }
        print(f"{label:40s} {rows[label]['us_per_step']:6.2f} µs/step  ({seconds:.3f} s, "
              f"{rows[label]['impacts']} impacts)")  # fmt: skip
    finish_per_step("mitigation_cost", rows, next(iter(rows)), "ratio_to_bare_gap", rec, args.dt,
                    argv, args.quick)  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
