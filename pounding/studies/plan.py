"""What a study runs: every combination's run key, what the store already holds, what is left."""

from __future__ import annotations

import dataclasses
import itertools
import json
from pathlib import Path
from typing import Any

import numpy as np

from pounding.case import CaseError, case_from_dict
from pounding.integrators.base import compiled_core
from pounding.studies.spec import (
    NO_CONTACT,
    Record,
    Study,
    StudyError,
    _combination_data,
    _label,
    run_key,
)
from pounding.studies.store import _damaged, _stored_ok


@dataclasses.dataclass(frozen=True, eq=False)
class StudyPlan:
    """Every combination with its run key and no-contact baseline key, and the runs to do.

    ``tasks`` maps run keys to the work of each unique run (baselines included), in order of first
    use; ``todo`` lists the keys not yet in the store; ``failed_records`` maps keys of runs that cannot
    start (their record could not be read) to the error.
    """

    study: Study
    store: Path
    keys: np.ndarray  # run key per combination, shape study.shape
    baseline_keys: np.ndarray | None  # None: no baselines (a hunt-and-fill IDA)
    tasks: dict[str, dict[str, Any]]
    todo: tuple[str, ...]
    failed_records: dict[str, str]
    #: stored runs found damaged (unreadable, a null summary, a truncated history file): rerun
    damaged: tuple[str, ...] = ()

    @property
    def n_runs(self) -> int:
        return len(self.tasks) + len(self.failed_records)


def default_store(result: str | Path) -> Path:
    """The store directory of a study result file: ``results.nc`` -> ``results.runs/``."""
    result = Path(result)
    return result.with_name(f"{result.stem}.runs")


class _TaskBuilder:
    """Each combination's case data, run key and run task, every distinct case validated once."""

    def __init__(self, study: Study) -> None:
        self.study = study
        self.buildings = study.case.system.building_names
        self.history_dt = study.history_dt if study.keep_histories else None
        # case text -> (its buildings, the compilation of the core its runs need)
        self.checked: dict[str, tuple[tuple[str, ...], str]] = {}

    def key(self, combo: dict[str, Any], record: Record, scale: float | None, label: str) -> tuple:
        """(run key, case data) of one combination (``law = "none"`` in ``combo`` for a
        baseline); raises :class:`StudyError` naming the combination when it is invalid."""
        try:
            data = _combination_data(self.study, combo)
        except StudyError as exc:
            raise StudyError(f"{exc} (study combination {label})") from None
        return run_key(data, record, scale), data

    def task(
        self, key: str, data: dict[str, Any], record: Record, scale: float | None, label: str
    ) -> dict[str, Any]:
        """The work of one run, after validating its case."""
        study = self.study
        text = json.dumps(data, sort_keys=True, default=str)
        if text not in self.checked:
            try:
                case = case_from_dict(
                    data, base_dir=study.base_dir, source=f"{study.source} ({label})"
                )
            except CaseError as exc:
                law = data.get("contact", [{}])[0].get("law") if data.get("contact") else None
                hint = (
                    f"; parameters of one law go in [study.law_params.{law}]"
                    if "law" in study.axes
                    and law not in (None, NO_CONTACT)
                    and "contact" in str(exc)
                    else ""
                )
                raise StudyError(f"{exc}{hint}") from None
            self.checked[text] = (case.system.building_names, compiled_core(case.system))
        names, core = self.checked[text]
        if names != self.buildings:
            raise StudyError(
                f"{study.source} ({label}): the buildings are {', '.join(names)}; a "
                f"study keeps the case's buildings {', '.join(self.buildings)}"
            )
        return {
            "key": key,
            "label": label,
            "data": data,
            "base_dir": None if study.base_dir is None else str(study.base_dir),
            "motion": None if study.motion_from_case else record.motion,
            "scale": scale,
            "history_dt": self.history_dt,
            "core": core,
        }


def study_cores(study: Study) -> set[str]:
    """The compilations of the Newmark core (:func:`pounding.integrators.base.compiled_core`) that
    the variants of ``study`` need, whatever the record (a hunt-and-fill IDA, whose runs are found
    as it goes)."""
    builder = _TaskBuilder(study)
    names = [n for n in study.axes if n != "record"]
    record = study.axes["record"][0]
    cores = set()
    for values in itertools.product(*(study.axes[n] for n in names)):
        key, data = builder.key(dict(zip(names, values, strict=True)), record, None, "variant")
        cores.add(builder.task(key, data, record, None, "variant")["core"])
    return cores


def plan_study(study: Study, store: str | Path, *, retry_failed: bool = False) -> StudyPlan:
    """Validate every combination and find the runs the store does not hold yet.

    Raises :class:`StudyError` naming the combination when one is invalid; nothing has run then.
    ``retry_failed`` runs again the runs stored as failed.
    """
    store = Path(store)
    names = list(study.axes)
    keys = np.empty(study.shape, dtype=object)
    base_keys = np.empty(study.shape, dtype=object)
    tasks: dict[str, dict[str, Any]] = {}
    bad: dict[str, str] = {}
    builder = _TaskBuilder(study)
    for index in itertools.product(*(range(n) for n in study.shape)):
        combo = {name: study.axes[name][i] for name, i in zip(names, index, strict=True)}
        record: Record = combo.pop("record")
        scale = combo.get("scale")
        if "im_level" in combo and record.motion is not None:
            scale = study.scale_factor(record, combo["im_level"])
        label = _label({**combo, "record": record})
        for baseline in (False, True):
            sub = dict(combo)
            if baseline:
                sub["law"] = NO_CONTACT
            key, data = builder.key(sub, record, scale, label)
            (base_keys if baseline else keys)[index] = key
            if record.motion is None and not study.motion_from_case:
                bad[key] = record.error
                continue
            if key in tasks:
                continue
            run_label = label if not baseline else f"{label} [no contact]"
            tasks[key] = builder.task(key, data, record, scale, run_label)
    need = builder.history_dt is not None
    todo = tuple(
        k for k in tasks if not _stored_ok(store, k, need_histories=need, retry=retry_failed)
    )
    damaged = tuple(k for k in todo if _damaged(store, k))
    return StudyPlan(study, store, keys, base_keys, tasks, todo, bad, damaged)
