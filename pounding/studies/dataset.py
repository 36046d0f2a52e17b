"""One run's summary variables and the study Dataset assembled from the store."""

from __future__ import annotations

import dataclasses
import datetime
import json
import warnings
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from pounding._version import __version__
from pounding.case import Case, schema_key
from pounding.contact.laws import get_contact_law
from pounding.errors import PoundingInputError
from pounding.results import ATTRS
from pounding.studies.plan import StudyPlan
from pounding.studies.spec import LAW_PARAM_KEYS, NO_CONTACT, Record, Study, _combination_data
from pounding.studies.store import _read_record, open_run
from pounding.units import G

_AXIS_ATTRS: dict[str, dict[str, str]] = {
    "law": {"long_name": "contact law (every contact)"},
    "gap": {"units": "m", "long_name": "initial gap (every contact)"},
    "e": {"units": "1", "long_name": "nominal coefficient of restitution (every contact)"},
    "k": {"units": "N/m^n", "long_name": "contact stiffness (every contact)"},
    "record": {"long_name": "ground motion record"},
    "scale": {"units": "1", "long_name": "record scale factor"},
    "im_level": {"units": "g", "long_name": "target intensity of the scaled records"},
    "ida_run": {"units": "1", "long_name": "run of a record's hunt-and-fill trace, in order"},
}
# Units of dotted-path axes, by their last key.
_PATH_UNITS = {
    "k": "N/m^n",
    "gap": "m",
    "e": "1",
    "n": "1",
    "a": "1",
    "delta_m": "m",
    "ratio": "1",
    "ratios": "1",
    "mass": "kg",
    "masses": "kg",
    "stiffnesses": "N/m",
    "period": "s",
    "height": "m",
    "heights": "m",
    "dt": "s",
    "output_dt": "s",
    "duration": "s",
    "scale": "1",
}

#: Summary variables of one run: name -> (dims, units, long_name).
SUMMARY: dict[str, tuple[tuple[str, ...], str, str]] = {
    "peak_displacement": (("building", "floor"), "m", ATTRS["peak_displacement"]["long_name"]),
    "peak_drift_ratio": (("building", "story"), "1", ATTRS["peak_drift_ratio"]["long_name"]),
    "peak_absolute_acceleration": (
        ("building", "floor"),
        "m/s^2",
        ATTRS["peak_absolute_acceleration"]["long_name"],
    ),
    "peak_story_shear": (("building", "story"), "N", ATTRS["peak_story_shear"]["long_name"]),
    "peak_contact_force": (("contact",), "N", "peak contact force"),
    "peak_penetration": (("contact",), "m", "peak penetration"),
    "impact_count": (("contact",), "1", "number of impacts"),
    "total_impulse": (("contact",), "N s", "total impulse of the impacts"),
    "max_impact_velocity": (("contact",), "m/s", "largest approach speed at impact onset"),
    "input_energy": ((), "J", "input energy at the end of the record"),
    "damping_energy": ((), "J", "energy dissipated by structural damping"),
    "contact_dissipated_energy": ((), "J", "energy dissipated by the contacts"),
    "energy_balance_error": ((), "1", "energy balance error (fraction of the input energy)"),
    "fundamental_period": (("building",), "s", "fundamental period (contacts open)"),
    "hysteretic_dissipated_energy": ((), "J", "energy dissipated by the yielding stories"),
    "collapse_time": (("building",), "s", ATTRS["collapse_time"]["long_name"]),
    "peak_struck_column_shear": (
        ("contact",),
        "N",
        ATTRS["peak_struck_column_shear"]["long_name"],
    ),
    "peak_foundation_sway": (("building",), "m", ATTRS["peak_foundation_sway"]["long_name"]),
    "peak_foundation_rocking": (
        ("building",),
        "rad",
        ATTRS["peak_foundation_rocking"]["long_name"],
    ),
}
# Peaks whose ratio to the no-contact run is reported: summary name -> (study name, long_name).
_AMPLIFIED = {
    "peak_displacement": (
        "displacement_amplification",
        "peak displacement with contact / without (building maximum)",
    ),
    "peak_drift_ratio": (
        "drift_amplification",
        "peak drift ratio with contact / without (building maximum)",
    ),
    "peak_absolute_acceleration": (
        "acceleration_amplification",
        "peak absolute floor acceleration with contact / without (building maximum)",
    ),
}


def _struck_column_shear(var: Any, n_el: int) -> np.ndarray:
    """Per contact, the peak shear of the column it strikes between floors, NaN for a floor."""
    out = np.full(n_el, np.nan)
    if "peak_column_shear" not in var:
        return out
    peak = var["peak_column_shear"].values
    for side in ("left", "right"):
        column = var[f"contact_{side}_column"].values
        hit = column >= 0
        out[hit] = peak[column[hit]]
    return out


def run_summary(ds: xr.Dataset) -> xr.Dataset:
    """The summary variables (:data:`SUMMARY`) of one analysis Dataset from :func:`simulate`."""
    # read through ds.variables (plain Variables) and build the Dataset in one go: DataArray
    # look-ups and coordinate assignment after construction cost more than the analysis itself
    var = ds.variables
    n_el = ds.sizes["contact"]
    imp_contact = var["impact_contact"].values.astype(np.int64)
    impulse = np.bincount(imp_contact, weights=var["impact_impulse"].values, minlength=n_el)[:n_el]
    v_max = np.full(n_el, np.nan)
    imp_v0 = var["impact_v0"].values
    for c in np.unique(imp_contact):
        v_max[c] = np.nanmax(imp_v0[imp_contact == c])
    terms = list(var["term"].values)
    energy = var["energy"].values
    final = energy[np.isfinite(energy).all(axis=1)][-1]  # rows after a collapse are NaN
    values = {
        "peak_displacement": var["peak_displacement"].values,
        "peak_drift_ratio": var["peak_drift_ratio"].values,
        "peak_absolute_acceleration": var["peak_absolute_acceleration"].values,
        "peak_story_shear": var["peak_story_shear"].values,
        "peak_contact_force": var["peak_contact_force"].values,
        "peak_penetration": var["peak_penetration"].values,
        "impact_count": var["impact_count"].values.astype(float),
        "total_impulse": impulse,
        "max_impact_velocity": v_max,
        "input_energy": final[terms.index("input")],
        "damping_energy": final[terms.index("damping")],
        "contact_dissipated_energy": final[terms.index("contact_dissipated")],
        "energy_balance_error": float(ds.attrs.get("energy_balance_error", np.nan)),
        "fundamental_period": var["natural_period"].values[:, 0],
        "hysteretic_dissipated_energy": final[terms.index("hysteretic")],
        "collapse_time": var["collapse_time"].values,
        "peak_struck_column_shear": _struck_column_shear(var, n_el),
        **{
            name: var[name].values if name in var else np.full(ds.sizes["building"], np.nan)
            for name in ("peak_foundation_sway", "peak_foundation_rocking")
        },
    }
    data = {
        name: (
            SUMMARY[name][0],
            np.asarray(v, dtype=float),
            {"units": units, "long_name": long_name},
        )
        for name, v in values.items()
        for (_, units, long_name) in [SUMMARY[name]]
    }
    coord_names = ("building", "floor", "story", "contact", "contact_left", "contact_right")
    coords = {name: var[name].copy() for name in coord_names}
    coords.update(
        {name: var[name].copy() for name in ("contact_left_floor", "contact_right_floor")}
    )
    out = xr.Dataset(data, coords=coords)
    for key in ("dt", "output_dt", "duration", "record", "method"):
        if key in ds.attrs:
            out.attrs[key] = ds.attrs[key]
    return out


# --------------------------------------------------------------------------------------------------
# Assembly
# --------------------------------------------------------------------------------------------------


def _table_label(value: Any) -> str:
    """A table-valued axis value as a short label, its ``model`` first:
    ``takeda yield_drift=0.003 hardening=0.02``; other values as JSON."""
    if not isinstance(value, Mapping):
        return json.dumps(value, sort_keys=True)
    head = [str(value["model"])] if "model" in value else []
    rest = [f"{k}={json.dumps(v)}" for k, v in value.items() if k != "model"]
    return " ".join(head + rest) or "{}"


def _axis_coord(name: str, values: Sequence[Any]) -> tuple[str, np.ndarray, dict[str, str]]:
    if name == "record":
        data = np.array([r.name for r in values], dtype=object).astype(str)
    elif all(isinstance(v, (str, int, float, bool)) for v in values):
        data = np.asarray(values)
        if data.dtype.kind == "U":
            data = data.astype(str)
    else:
        data = np.array([_table_label(v) for v in values], dtype=object).astype(str)
    attrs = dict(_AXIS_ATTRS.get(name, {}))
    if not attrs:
        last = name.split(".")[-1]
        key = schema_key(name)
        # the schema's words (the dim name keeps the path: which building, which contact)
        attrs = {"long_name": key.meaning.split(" (")[0] if key else f"case value {name}"}
        if key and key.unit:
            attrs["units"] = key.unit
        elif last in _PATH_UNITS:
            attrs["units"] = _PATH_UNITS[last]
    return name, data, attrs


def _model_variables(case: Case, width: int) -> dict[str, tuple]:
    """Model description of the base case (periods, mode shapes, masses) for reports."""
    bl = case.system.buildings
    nb = len(bl)

    def padded(rows: list[np.ndarray]) -> np.ndarray:
        out = np.full((nb, width), np.nan)
        for i, r in enumerate(rows):
            out[i, : r.size] = r
        return out

    shape = np.full((nb, width, width), np.nan)
    for i, b in enumerate(bl):
        s = b.modal().shapes
        shape[i, : s.shape[0], : s.shape[1]] = s / s[-1]
    return {
        "natural_period": (("building", "mode"), padded([b.modal().periods for b in bl])),
        "mode_shape": (("building", "floor", "mode"), shape),
        "floor_mass": (("building", "floor"), padded([b.masses for b in bl])),
        "story_stiffness": (("building", "story"), padded([b.stiffnesses for b in bl])),
        "floor_elevation": (("building", "floor"), padded([b.elevations for b in bl])),
        "story_height": (("building", "story"), padded([b.heights for b in bl])),
    }


def _record_variables(records_: Sequence[Record]) -> dict[str, tuple]:
    n = max((r.motion.npts for r in records_ if r.motion is not None), default=1)
    acc = np.full((len(records_), n), np.nan)
    for i, r in enumerate(records_):
        if r.motion is not None:
            acc[i, : r.motion.npts] = r.motion.acceleration
    nan = float("nan")

    def text(values: list[str]) -> np.ndarray:
        return np.array(values, dtype=object).astype(str)

    return {
        "record_acceleration": (("record", "record_sample"), acc),
        "record_dt": (("record",), np.array([r.motion.dt if r.motion else nan for r in records_])),
        "record_reference": (("record",), text([r.reference for r in records_])),
        "record_processing": (
            ("record",),
            text(
                [
                    json.dumps(list(r.motion.metadata.get("processing", []))) if r.motion else "[]"
                    for r in records_
                ]
            ),
        ),
    }


def _law_parameters(study: Study) -> dict[str, dict[str, Any]]:
    """Parameters of the first contact under each law of the study (for reports)."""
    contacts = study.case.data.get("contact", [])
    if not contacts:
        return {}
    laws = [v for v in study.axes.get("law", ()) if v != NO_CONTACT] or [
        get_contact_law(contacts[0].get("law", "linear")).name
    ]
    out = {}
    for law in laws:
        combo = {"law": law} if "law" in study.axes else {}
        c = _combination_data(study, combo).get("contact", [{}])[0]
        out[law] = {k: c[k] for k in LAW_PARAM_KEYS if k in c}
        out[law]["effective_mass"] = float(study.case.system.elements.el_mass[0])
    return out


def assemble(plan: StudyPlan) -> xr.Dataset:
    """The study Dataset from the stored runs: a dimension per axis and the summary variables.

    Variables: the :data:`SUMMARY` variables over (axes..., their own dims), the peaks of the
    no-contact run (``no_contact_peak_*``), the amplifications (``*_amplification``, building
    maxima with contact over without), ``run_status``, ``run_error``, ``run_key``,
    ``baseline_key``; the base case's model (``natural_period``, ``mode_shape``, ...) and the
    records (``record_acceleration``, ``record_dt``, ...). Runs still missing from the store
    count as failed with the error "not run".
    """
    study = plan.study
    loaded, errors = _load_runs(plan)
    ok = [r for r in loaded.values() if r is not None]
    buildings = list(study.case.system.building_names)
    width = max(
        [study.case.system.buildings[i].n_floors for i in range(len(buildings))]
        + [r.sizes["floor"] for r in ok]
    )
    n_contact = max([len(study.case.system.elements)] + [r.sizes["contact"] for r in ok])
    sizes = {"building": len(buildings), "floor": width, "story": width, "contact": n_contact}
    data = _summary_variables(plan, loaded, sizes)
    data.update(_run_variables(plan, errors))
    for name, value in {
        **_model_variables(study.case, width),
        **_record_variables(study.axes["record"]),
    }.items():
        data[name] = (*value, {})
    data.update(_intensity_variables(study))
    coords = _study_coords(study, buildings, width, n_contact)
    ds = xr.Dataset({k: (v[0], v[1]) for k, v in data.items()}, coords=coords)
    for name, value in data.items():
        ds[name].attrs.update(value[2] or ATTRS.get(name, {}))
    for name in (
        "record_acceleration",
        "record_dt",
        "record_reference",
        "record_processing",
        "run_status",
        "run_error",
        "run_key",
        "baseline_key",
    ):
        if name in ds:
            ds[name].attrs.update(ATTRS[name])
    if "im_level" in ds.dims and "collapse_time" in ds:
        _add_collapse_im(ds)
    n_failed = int((data["run_status"][1] == "failed").sum())
    ds.attrs.update(_study_attrs(plan, n_failed))
    return ds


def _load_runs(plan: StudyPlan) -> tuple[dict[str, xr.Dataset | None], dict[str, str]]:
    """Each run's stored summary by key (None: failed or not run) and each failed run's error."""
    loaded: dict[str, xr.Dataset | None] = {}
    errors: dict[str, str] = dict(plan.failed_records)
    baselines = plan.baseline_keys.ravel() if plan.baseline_keys is not None else ()
    for key in (*plan.keys.ravel(), *baselines):
        if key in loaded:
            continue
        loaded[key] = None
        if key in errors:
            continue
        rec = _read_record(plan.store, key)
        if rec is None:
            errors[key] = "not run"
        elif rec["status"] != "ok":
            errors[key] = str(rec.get("error") or "failed")
        else:
            loaded[key] = xr.Dataset.from_dict(rec["summary"])
    return loaded, errors


def _gather(
    loaded: Mapping[str, xr.Dataset | None],
    name: str,
    keys_array: np.ndarray,
    sizes: Mapping[str, int],
) -> np.ndarray:
    """Summary variable ``name`` of every run over (axes..., its dims), NaN-padded."""
    dims = SUMMARY[name][0]
    out = np.full((*keys_array.shape, *(sizes[d] for d in dims)), np.nan)
    for index in np.ndindex(*keys_array.shape):
        r = loaded[keys_array[index]]
        if r is not None and name in r:  # runs stored by older versions may lack a variable
            v = r[name].values
            out[index + tuple(slice(0, n) for n in v.shape)] = v
    return out


def _summary_variables(
    plan: StudyPlan, loaded: Mapping[str, xr.Dataset | None], sizes: Mapping[str, int]
) -> dict[str, tuple]:
    """The :data:`SUMMARY` variables over the axes, then the no-contact peaks and amplifications."""
    axis_dims = tuple(plan.study.axes)
    data: dict[str, tuple] = {}
    for name, (dims, units, long_name) in SUMMARY.items():
        data[name] = (
            axis_dims + dims,
            _gather(loaded, name, plan.keys, sizes),
            {"units": units, "long_name": long_name},
        )
    if plan.baseline_keys is None:
        return data
    with np.errstate(divide="ignore", invalid="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN slices of failed runs
        for name, (amp, long_name) in _AMPLIFIED.items():
            dims, units, base_long = SUMMARY[name]
            base = _gather(loaded, name, plan.baseline_keys, sizes)
            data[f"no_contact_{name}"] = (
                axis_dims + dims,
                base,
                {"units": units, "long_name": f"{base_long}, no contact"},
            )
            ratio = np.nanmax(data[name][1], axis=-1) / np.nanmax(base, axis=-1)
            data[amp] = (axis_dims + ("building",), ratio, {"units": "1", "long_name": long_name})
    return data


def _key_text(values: Callable[[str], str], keys_array: np.ndarray) -> np.ndarray:
    """``values`` of each run key, as a string array of the keys' shape."""
    return (
        np.array([values(k) for k in keys_array.ravel()], dtype=object)
        .astype(str)
        .reshape(keys_array.shape)
    )


def _run_variables(plan: StudyPlan, errors: Mapping[str, str]) -> dict[str, tuple]:
    """Each combination's ``run_status``, ``run_key``, ``baseline_key`` and ``run_error``."""
    axis_dims = tuple(plan.study.axes)
    # an empty key: a slot of a hunt-and-fill trace that needed no run
    status = _key_text(
        lambda k: "unused" if k == "" else "failed" if k in errors else "ok", plan.keys
    )
    error = _key_text(lambda k: errors.get(k, "") if k else "", plan.keys)
    data: dict[str, tuple] = {
        "run_status": (axis_dims, status, {}),
        "run_key": (axis_dims, plan.keys.astype(str), {}),
    }
    if plan.baseline_keys is not None:
        # a failed baseline leaves the amplification undefined: say so in the error text
        base_err = _key_text(lambda k: errors.get(k, ""), plan.baseline_keys)
        error = np.where(
            (base_err != "") & (error == ""), np.char.add("no-contact run: ", base_err), error
        )
        data["baseline_key"] = (axis_dims, plan.baseline_keys.astype(str), {})
    data["run_error"] = (axis_dims, error, {})
    return data


def _intensity_variables(study: Study) -> dict[str, tuple]:
    """The scale factors of an IDA and each record's intensity and normalisation, as they apply."""
    data: dict[str, tuple] = {}
    if "im_level" in study.axes:
        data["scale_factor"] = _scale_factors(study)
    if study.im is not None:
        im = study.im
        data["record_im"] = (
            ("record",),
            np.array(
                [
                    study.record_intensity(r) / G if r.motion else np.nan
                    for r in study.axes["record"]
                ]
            ),
            {"units": "g", "long_name": f"{im.label.removesuffix(' [g]')} of the record as read"},
        )
    if study.im is not None and study.scaling == "set":
        data["normalisation_factor"] = (
            ("record",),
            np.array(
                [study.normalisation(r) if r.motion else np.nan for r in study.axes["record"]]
            ),
            {"units": "1", "long_name": "PGV normalisation NM = median(PGV)/PGV (FEMA P695)"},
        )
    return data


def _study_coords(
    study: Study, buildings: Sequence[str], width: int, n_contact: int
) -> dict[str, Any]:
    """The axes' coordinates, then the building, floor, story, mode and contact coordinates."""
    coords: dict[str, Any] = {}
    for name in study.axes:
        _, values, attrs = _axis_coord(name, study.axes[name])
        coords[name] = (name, values, attrs)
    if "im_level" in coords:
        coords["im_level"][2]["long_name"] = study.level_label
    coords.update(
        building=("building", np.array(buildings, dtype=object).astype(str), ATTRS["building"]),
        floor=("floor", np.arange(1, width + 1), ATTRS["floor"]),
        story=("story", np.arange(1, width + 1), ATTRS["story"]),
        mode=("mode", np.arange(1, width + 1), ATTRS["mode"]),
        contact=("contact", np.arange(n_contact), ATTRS["contact"]),
    )
    el = study.case.system.elements
    if len(el) == n_contact:  # the base case's contact labels fit every run's contact axis
        for name, values in (
            ("contact_left", np.array(el.left, dtype=object).astype(str)),
            ("contact_right", np.array(el.right, dtype=object).astype(str)),
            ("contact_left_floor", el.left_floor),
            ("contact_right_floor", el.right_floor),
            *(
                (("contact_left_column", el.left_column), ("contact_right_column", el.right_column))
                if len(study.case.system.columns)
                else ()
            ),
        ):
            coords[name] = ("contact", values, ATTRS[name])
    return coords


def _study_attrs(plan: StudyPlan, n_failed: int) -> dict[str, Any]:
    """The study Dataset's global attributes: the study, its size, analysis and provenance."""
    study = plan.study
    return dict(
        title=study.title,
        pounding_kind="study",
        axes=json.dumps(list(study.axes)),
        law_params=json.dumps(study.law_params, sort_keys=True),
        law_parameters=json.dumps(_law_parameters(study), sort_keys=True),
        combinations=int(study.size),
        unique_runs=int(plan.n_runs),
        failed_combinations=n_failed,
        keep_histories=int(study.keep_histories),
        store=str(plan.store.resolve()),
        analysis=json.dumps(dataclasses.asdict(study.case.analysis), default=str),
        intensity_measure=json.dumps(study.im.to_dict() if study.im else {}),
        scaling=study.scaling,
        limit_states=json.dumps(list(study.limit_states)),
        pounding_version=__version__,
        created=datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
        Conventions="CF-1.8",
    )


def _add_collapse_im(ds: xr.Dataset) -> None:
    """Per record and variant of a listed-level IDA: the lowest level at which a building
    collapsed, the highest level below it without collapse, and the highest level analysed (failed
    runs left out), as :func:`assemble_hunt` gives them."""
    ok = ds["run_status"] == "ok"
    level = ds["im_level"].broadcast_like(ok)
    collapsed = np.isfinite(ds["collapse_time"]).any("building") & ok
    label = ds["im_level"].attrs.get("long_name", "intensity")
    ds["collapse_im"] = (
        level.where(collapsed)
        .min("im_level")
        .assign_attrs(units="g", long_name=f"lowest {label} reaching collapse (NaN: not reached)")
    )
    below = ok & ~collapsed & (level < ds["collapse_im"])
    ds["collapse_im_lower"] = (
        level.where(below)
        .max("im_level")
        .assign_attrs(units="g", long_name=f"highest {label} below it not reaching collapse")
    )
    ds["im_max_run"] = (
        level.where(ok)
        .max("im_level")
        .assign_attrs(units="g", long_name=f"highest {label} run (censoring level)")
    )


def _scale_factors(study: Study) -> tuple:
    """(record, im_level) factors that bring each record to each target intensity."""
    recs, levels = study.axes["record"], study.axes["im_level"]
    out = np.full((len(recs), len(levels)), np.nan)
    for i, rec in enumerate(recs):
        if rec.motion is not None:
            out[i] = [study.scale_factor(rec, level) for level in levels]
    attrs = {"units": "1", "long_name": "record scale factor to the target intensity"}
    return ("record", "im_level"), out, attrs


def histories(ds: xr.Dataset, store: str | Path | None = None, **selection: Any) -> xr.Dataset:
    """Decimated time histories of one combination of a study (``keep_histories = true``).

    ``selection`` picks one value on every axis, e.g. ``law="flores", gap=0.02, record=...``.
    """
    key = ds["run_key"].sel(**selection)
    if key.ndim:
        raise PoundingInputError(
            f"histories: select one value on every axis; still free: {', '.join(key.dims)}"
        )
    run = open_run(store or ds.attrs["store"], str(key.item()))
    if not run.attrs.get("has_histories"):
        raise PoundingInputError(
            "histories: this run has no time histories (keep_histories = false)"
        )
    return run


def assemble_hunt(
    study: Study,
    store: str | Path,
    keys: np.ndarray,
    levels: np.ndarray,
    hits: np.ndarray,
    errors: Mapping[str, str],
) -> xr.Dataset:
    """The Dataset of a hunt-and-fill IDA: the study's variables over (variant axes..., record,
    ida_run), each record's runs in the order they ran, with their target intensity ``ida_level``
    [g], ``scale_factor`` and, per record, ``collapse_im`` (the lowest level that reached the hunt's
    limit state; NaN when none did), ``collapse_im_lower`` (the highest level below it that did
    not) and ``im_max_run`` (the highest level run: where a record without collapse is censored).
    Slots a trace did not need have ``run_status`` "unused". ``hits``: whether each run reached
    the limit state, as the hunt decided it (:func:`pounding.studies.run.run_hunt`)."""
    from pounding.studies.hunt import capacity

    assert study.hunt is not None and study.im is not None
    runs = tuple(range(keys.shape[-1]))
    pseudo = dataclasses.replace(study, axes={**study.axes, "ida_run": runs})
    plan = StudyPlan(pseudo, Path(store), keys, None, {}, (), dict(errors))
    ds = assemble(plan)
    dims = ds["run_status"].dims
    limit = study.hunt.limit_state
    hit = hits & (keys != "")
    cap = np.full(keys.shape[:-1], np.nan)
    lower, top = np.full_like(cap, np.nan), np.full_like(cap, np.nan)
    scale = np.full(keys.shape, np.nan)
    for index in np.ndindex(*keys.shape[:-1]):
        used = [j for j in runs if keys[index][j] != "" and np.isfinite(levels[index][j])]
        c, below, highest = capacity([(float(levels[index][j]), bool(hit[index][j])) for j in used])
        if used:
            cap[index] = c if np.isfinite(c) else np.nan
            lower[index], top[index] = below, highest
        record = study.axes["record"][index[-1]]
        for j in used:
            scale[index][j] = study.scale_factor(record, float(levels[index][j]))
    measure = study.im.label.removesuffix(" [g]")
    var_dims = dims[:-1]
    ds["ida_level"] = (dims, levels, {"units": "g", "long_name": study.level_label})
    ds["scale_factor"] = (
        dims,
        scale,
        {"units": "1", "long_name": "record scale factor to the target intensity"},
    )
    what = limit if limit in ("collapse", "pounding") else f"story drift ratio {limit:g}"
    ds["collapse_im"] = (
        var_dims,
        cap,
        {"units": "g", "long_name": f"lowest {measure} reaching {what} (NaN: not reached)"},
    )
    ds["collapse_im_lower"] = (
        var_dims,
        lower,
        {"units": "g", "long_name": f"highest {measure} below it not reaching {what}"},
    )
    ds["im_max_run"] = (
        var_dims,
        top,
        {"units": "g", "long_name": f"highest {measure} run (censoring level)"},
    )
    ds.attrs.update(
        hunt=json.dumps(study.hunt.to_dict()),
        unique_runs=int(len({k for k in keys.ravel() if k})),
    )
    return ds
