"""The results schema as plain arrays, without xarray: what :func:`pounding.results.build_dataset`
wraps in an ``xr.Dataset`` and what the ``pounding run`` console process writes and summarises
directly (xarray and pandas cost ~0.3 s to import, a third of a warm run).

:class:`ResultVariables` holds each variable as (dimension names, values, attributes), the names of
the coordinates and the global attributes; :func:`summary` computes the headline numbers of
``ds.pounding.summary()`` from it.
"""

from __future__ import annotations

import dataclasses
import json
import math
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np

from pounding.ground_motion import GroundMotion
from pounding.integrators.base import ENERGY_TERMS, RawResult
from pounding.stories import park_ang
from pounding.structure import reference_floors
from pounding.system import PoundingSystem, end_label

#: CF-style attributes of every variable and coordinate the schema defines.
ATTRS: dict[str, dict[str, str]] = {
    "time": {"units": "s", "long_name": "time"},
    "building": {"long_name": "building"},
    "floor": {"long_name": "floor number (1 = lowest)"},
    "story": {"long_name": "story number (1 = lowest)"},
    "contact": {"long_name": "gap element"},
    "term": {"long_name": "energy term"},
    "mode": {"long_name": "mode number"},
    "impact": {"long_name": "impact number"},
    "impact_point": {"long_name": "kept integration step of the impact path"},
    "floor_elevation": {"units": "m", "long_name": "floor elevation above ground"},
    "story_height": {"units": "m", "long_name": "story height"},
    "floor_mass": {"units": "kg", "long_name": "floor mass"},
    "story_stiffness": {"units": "N/m", "long_name": "story stiffness"},
    "natural_period": {"units": "s", "long_name": "natural period (contacts open)"},
    "effective_modal_mass": {"units": "kg", "long_name": "effective modal mass"},
    "mode_shape": {"units": "1", "long_name": "mode shape (roof = 1)"},  # see build_dataset
    "contact_left": {"long_name": "left end of gap element (building or wall)"},
    "contact_right": {"long_name": "right end of gap element (building or wall)"},
    "contact_left_floor": {"long_name": "floor of the left end (0 = wall or base slab)"},
    "contact_right_floor": {"long_name": "floor of the right end (0 = wall or base slab)"},
    "contact_gap": {"units": "m", "long_name": "initial gap"},
    "contact_law": {"long_name": "contact law"},
    "contact_k": {"units": "N/m^n", "long_name": "contact stiffness"},
    "contact_n": {"units": "1", "long_name": "contact exponent n"},
    "contact_e": {"units": "1", "long_name": "nominal coefficient of restitution"},
    "contact_effective_mass": {"units": "kg", "long_name": "effective mass of the impact"},
    "contact_a": {"units": "1", "long_name": "bilinear yield fraction delta_y/delta_m"},
    "contact_delta_m": {"units": "m", "long_name": "bilinear maximum penetration delta_m"},
    "contact_calibration": {"long_name": "damping calibration to e: nominal or exact"},
    "displacement": {"units": "m", "long_name": "floor displacement relative to ground"},
    "velocity": {"units": "m/s", "long_name": "floor velocity relative to ground"},
    "absolute_acceleration": {"units": "m/s^2", "long_name": "absolute floor acceleration"},
    "drift": {"units": "m", "long_name": "inter-story drift"},
    "drift_ratio": {"units": "1", "long_name": "inter-story drift ratio"},
    "penetration": {"units": "m", "long_name": "penetration (gap closure beyond contact)"},
    "contact_force": {"units": "N", "long_name": "contact force"},
    "ground_acceleration": {"units": "m/s^2", "long_name": "ground acceleration"},
    "energy": {"units": "J", "long_name": "energy"},
    "peak_displacement": {"units": "m", "long_name": "peak absolute floor displacement"},
    "peak_drift_ratio": {"units": "1", "long_name": "peak absolute inter-story drift ratio"},
    "peak_absolute_acceleration": {
        "units": "m/s^2",
        "long_name": "peak absolute floor acceleration",
    },
    "peak_contact_force": {"units": "N", "long_name": "peak contact force"},
    "story_shear": {
        "units": "N",
        "long_name": "story shear (spring and damping force the story carries, from equilibrium of the floors above)",
    },
    "base_shear": {"units": "N", "long_name": "base shear (story shear of the lowest story)"},
    "peak_story_shear": {
        "units": "N",
        "long_name": "peak absolute story shear (over the stored output steps)",
    },
    "peak_base_shear": {
        "units": "N",
        "long_name": "peak absolute base shear (over the stored output steps)",
    },
    "peak_penetration": {"units": "m", "long_name": "peak penetration"},
    "impact_count": {"units": "1", "long_name": "number of impacts"},
    "impact_contact": {"units": "1", "long_name": "gap element of the impact"},
    "impact_start": {"units": "s", "long_name": "impact start time"},
    "impact_end": {"units": "s", "long_name": "impact end time"},
    "impact_v0": {"units": "m/s", "long_name": "approach speed at impact onset"},
    "impact_v_end": {"units": "m/s", "long_name": "penetration rate at separation"},
    "impact_peak_force": {"units": "N", "long_name": "peak force of the impact"},
    "impact_max_penetration": {"units": "m", "long_name": "maximum penetration of the impact"},
    "impact_impulse": {"units": "N s", "long_name": "impulse of the impact"},
    "impact_path_penetration": {
        "units": "m",
        "long_name": "penetration at integration steps through the impact (closure to separation)",
    },
    "impact_path_force": {
        "units": "N",
        "long_name": "contact force at integration steps through the impact (closure to separation)",
    },
    "base_type": {"long_name": "base: fixed, flat (slider) or friction_pendulum"},
    "friction_law": {"long_name": "friction law of the isolation bearings"},
    "base_mass": {"units": "kg", "long_name": "mass of the base slab"},
    "base_radius": {"units": "m", "long_name": "radius of the friction pendulum surface"},
    "base_normal_force": {"units": "N", "long_name": "normal force on the bearings (weight W)"},
    "base_displacement": {
        "units": "m",
        "long_name": "base slab (bearing) displacement relative to ground",
    },
    "base_velocity": {
        "units": "m/s",
        "long_name": "base slab (bearing) velocity relative to ground",
    },
    "friction_force": {
        "units": "N",
        "long_name": "bearing friction force (resisting; reaction while stuck)",
    },
    "stick": {"units": "1", "long_name": "bearings stuck (1) or sliding (0)"},
    "link_force": {"units": "N", "long_name": "coupling link force (positive pushing apart)"},
    "peak_link_force": {"units": "N", "long_name": "peak absolute coupling link force"},
    "link": {"long_name": "coupling link (one per linked floor pair)"},
    "link_left": {"long_name": "building on the left of the link"},
    "link_right": {"long_name": "building on the right of the link"},
    "link_left_floor": {"long_name": "floor of the left building the link joins"},
    "link_right_floor": {"long_name": "floor of the right building the link joins"},
    "link_type": {"long_name": "coupling link law"},
    "residual_drift": {"units": "m", "long_name": "inter-story drift at the end of the analysis"},
    "residual_drift_ratio": {
        "units": "1",
        "long_name": "inter-story drift ratio at the end of the analysis",
    },
    "story_model": {"long_name": "story model (elastic or hysteretic)"},
    "collapse_time": {
        "units": "s",
        "long_name": "first time a story drift ratio exceeds collapse_drift (NaN: no collapse)",
    },
    "story_spring_force": {
        "units": "N",
        "long_name": "story spring (restoring) force, without damping",
    },
    "peak_story_spring_force": {
        "units": "N",
        "long_name": "peak absolute story spring (restoring) force",
    },
    "yield_force": {"units": "N", "long_name": "story yield force F_y"},
    "yield_drift": {"units": "m", "long_name": "story yield drift F_y/k"},
    "story_ductility": {"units": "1", "long_name": "story ductility: peak drift / yield drift"},
    "hysteretic_energy": {
        "units": "J",
        "long_name": "story hysteretic energy: work of the spring less its recoverable F²/(2k)",
    },
    "park_ang_damage": {
        "units": "1",
        "long_name": "Park-Ang damage index δ_m/δ_u + β E_h/(F_y δ_u)",
    },
    "peak_base_displacement": {
        "units": "m",
        "long_name": "peak absolute base slab (bearing) displacement",
    },
    "foundation_sway": {
        "units": "m",
        "long_name": "foundation sway u_0 on the soil, relative to the ground",
    },
    "foundation_rocking": {
        "units": "rad",
        "long_name": "foundation rocking rotation θ on the soil",
    },
    "peak_foundation_sway": {"units": "m", "long_name": "peak absolute foundation sway"},
    "peak_foundation_rocking": {
        "units": "rad",
        "long_name": "peak absolute foundation rocking rotation",
    },
    "soil_sway_stiffness": {"units": "N/m", "long_name": "soil sway spring K_x"},
    "soil_rocking_stiffness": {"units": "N m/rad", "long_name": "soil rocking spring K_θ"},
    "soil_sway_damping": {"units": "N s/m", "long_name": "soil sway dashpot C_x"},
    "soil_rocking_damping": {"units": "N m s/rad", "long_name": "soil rocking dashpot C_θ"},
    "column": {"long_name": "struck column (impact node between two floors)"},
    "segment": {"long_name": "column segment: below or above the impact point"},
    "column_building": {"long_name": "building of the struck column"},
    "column_story": {"long_name": "story of the struck column (1 = lowest)"},
    "column_elevation": {"units": "m", "long_name": "elevation of the impact point"},
    "column_xi": {"units": "1", "long_name": "impact point's height in its story, a/h"},
    "contact_left_column": {"long_name": "struck column at the left end (-1: a floor)"},
    "contact_right_column": {"long_name": "struck column at the right end (-1: a floor)"},
    "column_displacement": {
        "units": "m",
        "long_name": "displacement of the column's impact point relative to the ground",
    },
    "column_shear": {
        "units": "N",
        "long_name": "shear (spring force) of the struck column's segment below / above the impact",
    },
    "peak_column_drift_shear": {
        "units": "N",
        "long_name": "peak of the struck column's share of its story's shear, k_c × story drift "
        "(its shear were it not struck between floors)",
    },
    "peak_column_displacement": {
        "units": "m",
        "long_name": "peak absolute displacement of the column's impact point",
    },
    "peak_column_shear": {
        "units": "N",
        "long_name": "peak absolute shear of the struck column, either segment (output steps)",
    },
    "peak_struck_column_shear": {
        "units": "N",
        "long_name": "peak shear of the column a contact strikes between floors (NaN: it strikes a "
        "floor)",
    },
    "column_capacity": {
        "units": "N",
        "long_name": "shear capacity of the struck column segments (NaN: not given)",
    },
    "column_capacity_exceeded": {
        "units": "1",
        "long_name": "1 where the peak column shear exceeds the capacity",
    },
    "flexible_base_period": {
        "units": "s",
        "long_name": "fundamental period on the soil springs (NaN: fixed base)",
    },
}
# The separation check's variables (pounding.separation) and the study Dataset's per-record and
# per-run variables (pounding.studies): one vocabulary for every Dataset the package writes.
ATTRS.update(
    {
        "record": {"long_name": "ground motion record"},
        "pair": {"long_name": "facing pair"},
        "pair_label": {"long_name": "facing pair (building:floor-building:floor)"},
        "pair_left": {"long_name": "left end of the facing pair (building or wall)"},
        "pair_right": {"long_name": "right end of the facing pair (building or wall)"},
        "pair_left_floor": {"units": "1", "long_name": "floor of the left end (0 = wall)"},
        "pair_right_floor": {"units": "1", "long_name": "floor of the right end (0 = wall)"},
        "pair_left_elevation": {"units": "m", "long_name": "elevation of the left end"},
        "pair_right_elevation": {"units": "m", "long_name": "elevation of the right end"},
        "pair_interface": {"long_name": "interface (neighbours or building and wall) of the pair"},
        "pair_same_level": {"units": "1", "long_name": "floors of the pair at the same elevation"},
        "interface": {"long_name": "interface between neighbours (or a building and a wall)"},
        "building": {"long_name": "building"},
        "floor": {"long_name": "floor number (1 = lowest)"},
        "mode": {"long_name": "mode number"},
        "estimate": {"long_name": "estimate of the required gap"},
        "estimate_label": {"long_name": "estimate of the required gap, description"},
        "estimate_basis": {"long_name": "formula, clause and edition of the estimate"},
        "statistic": {"long_name": "statistic over the records (median, 84th percentile, maximum)"},
        "gap": {"units": "m", "long_name": "clear gap at rest"},
        "modal_damping_ratio": {"units": "1", "long_name": "modal damping ratio"},
        "spectral_displacement": {
            "units": "m",
            "long_name": "spectral displacement Sd(T_n, zeta_n)",
        },
        "peak_displacement_time_history": {
            "units": "m",
            "long_name": "peak floor displacement, time history without contact",
        },
        "peak_displacement_srss": {
            "units": "m",
            "long_name": "peak floor displacement, spectral, SRSS over modes",
        },
        "peak_displacement_cqc": {
            "units": "m",
            "long_name": "peak floor displacement, spectral, CQC over modes",
        },
        "exact_gap": {
            "units": "m",
            "long_name": "minimum gap avoiding contact (max over time of u_left - u_right)",
        },
        "pair_correlation": {
            "units": "1",
            "long_name": "CQC correlation of the fundamental modes of the pair's buildings (DDC)",
        },
        "required_gap_pair": {"units": "m", "long_name": "required gap of each facing pair"},
        "required_gap": {
            "units": "m",
            "long_name": "required gap (largest over the interface's pairs)",
        },
        "required_gap_statistic": {
            "units": "m",
            "long_name": "required gap, statistic over the records",
        },
        "pounding_probability": {
            "units": "1",
            "long_name": "fraction of records with contact (empirical probability of pounding)",
        },
        "pounding_probability_lognormal": {
            "units": "1",
            "long_name": "probability of pounding, lognormal fit of the exact gaps",
        },
        "lognormal_median": {
            "units": "m",
            "long_name": "median of the lognormal fit of the exact gap",
        },
        "lognormal_beta": {"units": "1", "long_name": "logarithmic standard deviation of the fit"},
        "lognormal_fraction": {
            "units": "1",
            "long_name": "fraction of records whose exact gap is positive",
        },
        "gap_for_target_probability": {
            "units": "m",
            "long_name": "gap with the target probability of pounding (lognormal fit)",
        },
        "case_gap": {
            "units": "m",
            "long_name": "gap of the case's contacts (smallest per interface)",
        },
        "record_acceleration": {"units": "m/s^2", "long_name": "ground acceleration of the record"},
        "record_dt": {"units": "s", "long_name": "record sampling interval"},
        "record_reference": {"long_name": "record reference"},
        "record_processing": {"long_name": "processing chain of the record (JSON list)"},
        "run_status": {
            "long_name": "run status (ok, failed; unused: a hunt-and-fill slot not needed)"
        },
        "run_error": {"long_name": "error message of a failed run"},
        "run_key": {"long_name": "key of the run in the store"},
        "baseline_key": {"long_name": "key of the no-contact run in the store"},
    }
)


#: Peaks compared with the no-contact run: name -> (its building-maximum ratio, the ratio per
#: story or floor). The building ratios are the study Dataset's names.
AMPLIFIED = {
    "peak_displacement": ("displacement_amplification", None),
    "peak_drift_ratio": ("drift_amplification", "story_drift_amplification"),
    "peak_absolute_acceleration": (
        "acceleration_amplification",
        "floor_acceleration_amplification",
    ),
}
ATTRS.update(
    {
        "displacement_amplification": {
            "units": "1",
            "long_name": "peak displacement with contact / without (building maximum)",
        },
        "drift_amplification": {
            "units": "1",
            "long_name": "peak drift ratio with contact / without (building maximum)",
        },
        "acceleration_amplification": {
            "units": "1",
            "long_name": "peak absolute floor acceleration with contact / without (building maximum)",
        },
        "story_drift_amplification": {
            "units": "1",
            "long_name": "peak drift ratio of the story with contact / without",
        },
        "floor_acceleration_amplification": {
            "units": "1",
            "long_name": "peak absolute acceleration of the floor with contact / without",
        },
        "impact_story_shear": {
            "units": "N",
            "long_name": "peak story shear with contact minus without (the part the impacts add)",
        },
    }
)
for _name in (*AMPLIFIED, "peak_story_shear", "peak_base_shear"):
    ATTRS["no_contact_" + _name] = {
        "units": ATTRS[_name]["units"],
        "long_name": ATTRS[_name]["long_name"] + ", no contact",
    }


def _padded(values: list[np.ndarray], width: int, lead: tuple[int, ...] = ()) -> np.ndarray:
    """Stack per-building arrays (..., n_b) into (..., n_buildings, width) padded with NaN."""
    out = np.full((*lead, len(values), width), np.nan)
    for i, v in enumerate(values):
        out[..., i, : v.shape[-1]] = v
    return out


def _attr_value(value: Any) -> Any:
    """NetCDF-safe attribute value (strings, numbers, JSON for the rest)."""
    if isinstance(value, bool):
        return int(value)
    if isinstance(value, (str, int, float, np.integer, np.floating)):
        return value
    if value is None:
        return "none"
    return json.dumps(value, default=str)


@dataclasses.dataclass
class ResultVariables:
    """A result as plain arrays: ``variables[name] = (dims, values, attrs)`` (data variables
    first, then coordinates, in the Dataset's order), the coordinate names and global attrs."""

    variables: dict[str, tuple[tuple[str, ...], np.ndarray, dict[str, Any]]]
    coords: list[str]
    attrs: dict[str, Any]


def result_variables(
    system: PoundingSystem,
    ground: GroundMotion,
    raw: RawResult,
    *,
    provenance: dict[str, Any] | None = None,
) -> ResultVariables:
    """Turn a :class:`RawResult` into the schema's variables, CF attributes on each."""
    bl = system.buildings
    width = max(b.n_floors for b in bl)
    slices = [slice(o, o + b.n_floors) for b, o in zip(bl, system.dof_offset, strict=True)]

    def per_building(arr: np.ndarray) -> np.ndarray:
        return _padded([arr[..., s] for s in slices], width, arr.shape[:-1])

    drift = per_building(system.drift(raw.displacement))
    peak_drift = per_building(raw.peak_drift)
    heights = _padded([b.heights for b in bl], width)
    shear = per_building(_floor_shears(system, raw, slices))
    d: dict[str, tuple] = {
        **_isolation_variables(system, raw),
        **_foundation_variables(system, raw),
        **_column_variables(system, raw),
        **_link_variables(system, raw),
        **_story_variables(system, raw, drift, peak_drift),
        **_response_variables(system, raw, per_building, drift, peak_drift, heights, shear),
        **_model_variables(system, width),
        **_impact_variables(raw.impacts),
    }
    coords = _result_coords(system, raw, width, heights)
    variables = {}
    for name, spec in (*d.items(), *coords.items()):
        dims, values = spec if isinstance(spec, tuple) else ((name,), spec)
        variables[name] = (dims, np.asarray(values), dict(ATTRS.get(name, {})))
    return ResultVariables(variables, list(coords), _result_attrs(ground, raw, provenance))


def _response_variables(
    system: PoundingSystem,
    raw: RawResult,
    per_building: Callable[[np.ndarray], np.ndarray],
    drift: np.ndarray,
    peak_drift: np.ndarray,
    heights: np.ndarray,
    shear: np.ndarray,
) -> dict[str, tuple]:
    """The response histories and their peaks: floors, stories, contacts, energy and collapse."""
    nt = raw.time.size
    n_el = len(system.elements)
    u = per_building(raw.displacement)
    a_abs = per_building(raw.acceleration + raw.ground_acceleration[:, None] * system.influence)
    return {
        "displacement": (("time", "building", "floor"), u),
        "velocity": (("time", "building", "floor"), per_building(raw.velocity)),
        "absolute_acceleration": (("time", "building", "floor"), a_abs),
        "drift": (("time", "building", "story"), drift),
        "drift_ratio": (("time", "building", "story"), drift / heights),
        "story_shear": (("time", "building", "story"), shear),
        "base_shear": (("time", "building"), shear[:, :, 0]),
        "collapse_time": (
            ("building",),
            _collapse_times(
                raw,
                drift / heights,
                peak_drift / heights,
                np.array([b.can_collapse for b in system.buildings]),
            ),
        ),
        "residual_drift": (("building", "story"), drift[-1]),
        "residual_drift_ratio": (("building", "story"), drift[-1] / heights),
        "penetration": (("time", "contact"), raw.penetration.reshape(nt, n_el)),
        "contact_force": (("time", "contact"), raw.contact_force.reshape(nt, n_el)),
        "ground_acceleration": (("time",), raw.ground_acceleration),
        "energy": (("time", "term"), raw.energy),
        "peak_displacement": (("building", "floor"), per_building(raw.peak_displacement)),
        "peak_drift_ratio": (("building", "story"), peak_drift / heights),
        "peak_absolute_acceleration": (
            ("building", "floor"),
            per_building(raw.peak_absolute_acceleration),
        ),
        "peak_story_shear": (("building", "story"), _abs_max(shear)),
        "peak_base_shear": (("building",), _abs_max(shear[:, :, 0])),
        "peak_contact_force": (("contact",), raw.peak_contact_force),
        "peak_penetration": (("contact",), raw.peak_penetration),
        "impact_count": (
            ("contact",),
            np.bincount(raw.impacts["element"], minlength=n_el).astype(np.int64)[:n_el],
        ),
    }


def _model_variables(system: PoundingSystem, width: int) -> dict[str, tuple]:
    """The buildings' masses, stiffnesses, periods, modal masses and mode shapes."""
    bl = system.buildings
    modes = [b.modal() for b in bl]
    # scaled to 1 at the roof (at the top-most moving floor for a mode that leaves the roof still)
    shapes = [
        m.shapes / m.shapes[reference_floors(m.shapes), np.arange(m.shapes.shape[1])] for m in modes
    ]
    mode_shape = np.full((len(bl), width, width), np.nan)
    for i, s in enumerate(shapes):
        mode_shape[i, : s.shape[0], : s.shape[1]] = s
    return {
        "floor_mass": (("building", "floor"), _padded([b.masses for b in bl], width)),
        "story_stiffness": (("building", "story"), _padded([b.stiffnesses for b in bl], width)),
        "natural_period": (("building", "mode"), _padded([m.periods for m in modes], width)),
        "effective_modal_mass": (
            ("building", "mode"),
            _padded([m.effective_masses for m in modes], width),
        ),
        "mode_shape": (("building", "floor", "mode"), mode_shape),
    }


def _impact_variables(imp: Mapping[str, np.ndarray]) -> dict[str, tuple]:
    """The per-impact table: times, speeds, peaks, impulse, contact (and the path when kept)."""
    out: dict[str, tuple] = {}
    for name in ("start", "end", "v0", "v_end", "peak_force", "max_penetration", "impulse"):
        out[f"impact_{name}"] = (("impact",), np.asarray(imp[name], dtype=float))
    out["impact_contact"] = (("impact",), np.asarray(imp["element"], dtype=np.int64))
    if "path_force" in imp:
        for name in ("path_penetration", "path_force"):
            out[f"impact_{name}"] = (("impact", "impact_point"), np.asarray(imp[name], dtype=float))
    return out


def _result_coords(
    system: PoundingSystem, raw: RawResult, width: int, heights: np.ndarray
) -> dict[str, Any]:
    """The coordinates: dimension axes, then the floors', contacts' and bases' labels."""
    bl = system.buildings
    imp = raw.impacts
    return {
        "time": raw.time,
        "building": list(system.building_names),
        "floor": np.arange(1, width + 1),
        "story": np.arange(1, width + 1),
        "contact": np.arange(len(system.elements)),
        "term": list(ENERGY_TERMS),
        "mode": np.arange(1, width + 1),
        "impact": np.arange(len(imp["element"])),
        **({"impact_point": np.arange(imp["path_force"].shape[1])} if "path_force" in imp else {}),
        **_column_coords(system),
        "floor_elevation": (("building", "floor"), _padded([b.elevations for b in bl], width)),
        "story_height": (("building", "story"), heights),
        **_contact_coords(system),
        "base_type": (
            ("building",),
            np.array([b.base.type if b.base is not None else "fixed" for b in bl], dtype=str),
        ),
        "friction_law": (
            ("building",),
            np.array([b.base.friction if b.base is not None else "none" for b in bl], dtype=str),
        ),
    }


def _contact_coords(system: PoundingSystem) -> dict[str, tuple]:
    """Per gap element: its ends, gap, law and the law's parameters."""
    el = system.elements
    group = [system.contacts[g] for g in el.group]
    return {
        "contact_left": (("contact",), np.array(el.left, dtype=object).astype(str)),
        "contact_right": (("contact",), np.array(el.right, dtype=object).astype(str)),
        "contact_left_floor": (("contact",), el.left_floor),
        "contact_right_floor": (("contact",), el.right_floor),
        **(
            {
                "contact_left_column": (("contact",), el.left_column),
                "contact_right_column": (("contact",), el.right_column),
            }
            if len(system.columns)
            else {}
        ),
        "contact_gap": (("contact",), el.el_gap),
        "contact_law": (("contact",), np.array(el.law, dtype=object).astype(str)),
        "contact_k": (("contact",), np.array([float(c.k) for c in group])),
        "contact_n": (
            ("contact",),
            np.array([np.nan if c.n is None else float(c.n) for c in group]),
        ),
        "contact_e": (
            ("contact",),
            np.array([np.nan if c.e is None else float(c.e) for c in group]),
        ),
        "contact_effective_mass": (("contact",), el.el_mass),
        "contact_a": (("contact",), np.array([float(c.a) for c in group])),
        "contact_delta_m": (
            ("contact",),
            np.array([np.nan if c.delta_m is None else float(c.delta_m) for c in group]),
        ),
        "contact_calibration": (("contact",), np.array([c.calibration for c in group], dtype=str)),
    }


def _result_attrs(
    ground: GroundMotion, raw: RawResult, provenance: dict[str, Any] | None
) -> dict[str, Any]:
    """The global attributes: energy balance, record, conventions and the run's provenance."""
    attrs: dict[str, Any] = {
        "energy_balance_error": energy_balance_error(raw.energy),
        "record": ground.name,
        "record_dt": ground.dt,
        "record_processing": _attr_value(list(ground.metadata.get("processing", []))),
        "sign_convention": (
            "displacements relative to ground, positive to the right; "
            "penetration = u_left - u_right - gap"
        ),
        "Conventions": "CF-1.8",
    }
    for key, value in (provenance or {}).items():
        attrs[key] = _attr_value(value)
    return attrs


def with_baseline(result: ResultVariables, baseline: ResultVariables) -> ResultVariables:
    """``result`` with the peaks of the same analysis without contacts (``no_contact_peak_*``), the
    amplifications (with / without: per building as in a study, per story and floor) and the story
    shear the impacts add; ``baseline`` is that no-contact run's result."""
    out = dict(result.variables)
    attrs = dict(result.attrs)

    def put(name: str, dims: tuple[str, ...], values: np.ndarray) -> None:
        out[name] = (dims, np.asarray(values), dict(ATTRS[name]))

    with np.errstate(divide="ignore", invalid="ignore"):
        for peak, (building_ratio, local_ratio) in AMPLIFIED.items():
            dims, with_contact, _ = result.variables[peak]
            without = baseline.variables[peak][1]
            put("no_contact_" + peak, dims, without)
            put(building_ratio, ("building",), _row_max(with_contact) / _row_max(without))
            if local_ratio:
                put(local_ratio, dims, with_contact / without)
        for peak in ("peak_story_shear", "peak_base_shear"):
            put("no_contact_" + peak, result.variables[peak][0], baseline.variables[peak][1])
        dims, shear, _ = result.variables["peak_story_shear"]
        put("impact_story_shear", dims, shear - baseline.variables["peak_story_shear"][1])
    # data variables before the coordinates, as the writer expects them
    ordered = {k: v for k, v in out.items() if k not in result.coords}
    ordered.update({k: out[k] for k in result.coords})
    attrs["baseline"] = "no-contact run of the same analysis (peaks no_contact_*)"
    return ResultVariables(ordered, list(result.coords), attrs)


def _row_max(values: np.ndarray) -> np.ndarray:
    """Maximum over the last axis ignoring NaN padding (NaN for an all-NaN row)."""
    out = np.full(values.shape[:-1], np.nan)
    finite = ~np.all(np.isnan(values), axis=-1)
    out[finite] = np.nanmax(values[finite], axis=-1)
    return out


#: Floor response spectra: 5 % damped pseudo-spectral acceleration of the absolute floor
#: acceleration over these periods [s]; periods shorter than FRS_MIN_STEPS output steps are NaN (the
#: stored history does not resolve them).
FRS_PERIODS = np.geomspace(0.02, 5.0, 60)
FRS_DAMPING = 0.05
FRS_MIN_STEPS = 4
ATTRS["period"] = {"units": "s", "long_name": "oscillator period"}
ATTRS["floor_spectrum"] = {
    "units": "m/s^2",
    "long_name": "floor response spectrum: 5 % damped pseudo-spectral acceleration of the absolute "
    "floor acceleration",
}


def with_floor_spectra(result: ResultVariables, floors: Any) -> ResultVariables:
    """``result`` with ``floor_spectrum`` (building, floor, period) for the chosen floors: "roof"
    (each building's top floor), "all", or a list of floor numbers (those a building has). NaN for
    the other floors and for periods shorter than FRS_MIN_STEPS output steps. From the stored
    absolute acceleration, linear between output steps (Nigam and Jennings 1969 recurrence, one
    period of free vibration after the record)."""
    from pounding.integrators.sdof import spectral_peaks

    _, acc, _ = result.variables["absolute_acceleration"]
    time = result.variables["time"][1]
    dt = float(time[1] - time[0]) if time.size > 1 else float("nan")
    heights = result.variables["floor_mass"][1]  # NaN beyond a building's top floor
    n_b, width = heights.shape
    out = np.full((n_b, width, FRS_PERIODS.size), np.nan)
    resolved = FRS_PERIODS >= FRS_MIN_STEPS * dt
    for b in range(n_b):
        n_floors = int(np.sum(~np.isnan(heights[b])))
        if floors == "roof":
            chosen = [n_floors]
        elif floors == "all":
            chosen = list(range(1, n_floors + 1))
        else:
            chosen = [f for f in floors if 1 <= f <= n_floors]
        for f in chosen:
            if resolved.any():
                peaks = spectral_peaks(acc[:, b, f - 1], dt, FRS_PERIODS[resolved], FRS_DAMPING)
                w = 2.0 * np.pi / FRS_PERIODS[resolved]
                out[b, f - 1, resolved] = w**2 * peaks[:, 0]
    variables = {k: v for k, v in result.variables.items() if k not in result.coords}
    variables["floor_spectrum"] = (
        ("building", "floor", "period"),
        out,
        dict(ATTRS["floor_spectrum"]),
    )
    variables.update({k: result.variables[k] for k in result.coords})
    variables["period"] = (("period",), FRS_PERIODS.copy(), dict(ATTRS["period"]))
    attrs = {**result.attrs, "floor_spectra_damping": FRS_DAMPING}
    return ResultVariables(variables, [*result.coords, "period"], attrs)


def _floor_shears(system: PoundingSystem, raw: RawResult, slices: list[slice]) -> np.ndarray:
    """Story shear [N] under every floor dof (time × dof): V_i = Σ_{j ≥ i} (K u + C v)_j over the
    building's floors, taken from their equilibrium, −Σ_{j ≥ i} (m_j ü_j^abs + Σ_c s_cj f_c), so the
    damping (whatever its form) and the contact and link forces on the floors above are in it. For
    an elastic shear building Σ_{j ≥ i} (K u)_j = k_i (u_i − u_{i−1}): the spring part is k_i
    times the drift (``story_spring_force`` for a yielding story)."""
    m = np.diag(system.mass)
    floor_force = m * (raw.acceleration + raw.ground_acceleration[:, None] * system.influence)
    el = system.elements
    nt = raw.time.size
    rows = [(el.el_dof, el.el_sign, raw.contact_force.reshape(nt, len(el)))]
    if len(system.links) and raw.link_force is not None:
        rows.append((system.links.dof, system.links.sign, raw.link_force))
    for dofs, signs, f in rows:
        for side in range(2):
            dof = dofs[:, side]
            hit = dof >= 0
            np.add.at(floor_force.T, dof[hit], (signs[hit, side] * f[:, hit]).T)
    shear = np.zeros_like(floor_force)
    for s in slices:
        # floors of a building are consecutive dofs, lowest first: sum from the roof down
        shear[:, s] = -np.cumsum(floor_force[:, s][:, ::-1], axis=1)[:, ::-1]
    return shear


def _abs_max(values: np.ndarray) -> np.ndarray:
    """max_t |x| over the first axis, NaN where every value is NaN (padding)."""
    out = np.full(values.shape[1:], np.nan)
    finite = ~np.all(np.isnan(values), axis=0)
    out[finite] = np.nanmax(np.abs(values[:, finite]), axis=0)
    return out


def _isolation_variables(system: PoundingSystem, raw: RawResult) -> dict[str, tuple]:
    """Base slab and bearing variables per building (NaN for fixed-base buildings)."""
    bl = system.buildings
    nt = raw.time.size
    base = np.asarray(system.base_dof)
    iso = base >= 0
    out = {}
    for name, arr in (("base_displacement", raw.displacement), ("base_velocity", raw.velocity)):
        values = np.full((nt, len(bl)), np.nan)
        values[:, iso] = arr[:, base[iso]]
        out[name] = (("time", "building"), values)
    force = np.full((nt, len(bl)), np.nan)
    stick = np.full((nt, len(bl)), np.nan)
    fr = system.friction
    if len(fr):
        force[:, fr.building] = raw.friction_force
        stick[:, fr.building] = raw.stick
    out["friction_force"] = (("time", "building"), force)
    out["stick"] = (("time", "building"), stick)
    peak = np.full(len(bl), np.nan)
    peak[iso] = np.asarray(raw.peak_displacement)[base[iso]]
    out["peak_base_displacement"] = (("building",), peak)
    nan = np.nan
    out["base_mass"] = (("building",), np.array([b.base.mass if b.base else nan for b in bl]))
    out["base_radius"] = (
        ("building",),
        np.array([b.base.radius if b.base and b.base.radius else nan for b in bl], dtype=float),
    )
    out["base_normal_force"] = (("building",), np.array([b.weight if b.base else nan for b in bl]))
    return out


def _foundation_variables(system: PoundingSystem, raw: RawResult) -> dict[str, tuple]:
    """Sway and rocking of the buildings on soil (NaN for the others); none without any."""
    if not system.flexible_base:
        return {}
    bl = system.buildings
    nt = raw.time.size
    on = np.flatnonzero(system.soil_dof[:, 0] >= 0)
    out = {}
    for k, name in enumerate(("foundation_sway", "foundation_rocking")):
        dof = system.soil_dof[on, k]
        values = np.full((nt, len(bl)), np.nan)
        values[:, on] = raw.displacement[:, dof]
        out[name] = (("time", "building"), values)
        peak = np.full(len(bl), np.nan)
        peak[on] = np.asarray(raw.peak_displacement)[dof]
        out[f"peak_{name}"] = (("building",), peak)
    soil = [b.soil for b in bl]
    nan = (np.nan, np.nan)
    springs = np.array([s.springs if s else nan for s in soil])
    dashpots = np.array([s.dashpot_coefficients if s else nan for s in soil])
    out["soil_sway_stiffness"] = (("building",), springs[:, 0])
    out["soil_rocking_stiffness"] = (("building",), springs[:, 1])
    out["soil_sway_damping"] = (("building",), dashpots[:, 0])
    out["soil_rocking_damping"] = (("building",), dashpots[:, 1])
    period = np.full(len(bl), np.nan)
    for i in on:
        period[i] = system.building_periods(int(i))[0]
    out["flexible_base_period"] = (("building",), period)
    return out


def _column_coords(system: PoundingSystem) -> dict[str, Any]:
    col = system.columns
    if not len(col):
        return {}
    return {
        "column": np.arange(len(col)),
        "segment": ["below", "above"],
        "column_building": (("column",), col.building),
        "column_story": (("column",), col.story),
        "column_elevation": (("column",), col.elevation),
        "column_xi": (("column",), col.xi),
    }


def _column_variables(system: PoundingSystem, raw: RawResult) -> dict[str, tuple]:
    """The struck columns' impact points: displacement, segment shears, peaks and capacity check;
    none without floor-to-column contacts."""
    col = system.columns
    if not len(col):
        return {}
    drift = system.drift(raw.displacement)
    lower = drift[:, col.dof]  # the node's deformation over the segment below it
    upper = np.zeros_like(lower)
    for q in range(len(col)):
        above = system.dof(int(col.building[q]), int(col.story[q]))
        upper[:, q] = drift[:, above] - lower[:, q]  # the story's deformation less the lower part
    k_c = col.k_below * col.xi
    story = k_c * (lower + upper)  # the column's part of the story's spring force
    hysteretic = np.zeros_like(lower)  # its share of a yielding story's F − k δ (on the chord)
    st = system.stories
    for q in range(len(col)):
        row = np.flatnonzero((st.building == col.building[q]) & (st.story == col.story[q]))
        if row.size and raw.story_force is not None:
            k = float(st.params[row[0], 0])
            chord = lower[:, q] + upper[:, q]
            hysteretic[:, q] = col.share[q] * (raw.story_force[:, row[0]] - k * chord)
    shear = np.stack((col.k_below * lower + hysteretic, col.k_above * upper + hysteretic), axis=-1)
    peak = _abs_max(shear.reshape(shear.shape[0], -1)).reshape(len(col), 2).max(axis=1)
    share = _abs_max(story + hysteretic)
    with np.errstate(invalid="ignore"):
        exceeded = (peak > col.capacity).astype(np.int8)
    return {
        "column_displacement": (("time", "column"), raw.displacement[:, col.dof]),
        "column_shear": (("time", "column", "segment"), shear),
        "peak_column_displacement": (
            ("column",),
            np.asarray(raw.peak_displacement)[col.dof],
        ),
        "peak_column_shear": (("column",), peak),
        "peak_column_drift_shear": (("column",), share),
        "column_capacity": (("column",), col.capacity),
        "column_capacity_exceeded": (("column",), exceeded),
    }


def _collapse_times(
    raw: RawResult, ratio: np.ndarray, peak_ratio: np.ndarray, can: np.ndarray
) -> np.ndarray:
    """Per building that can collapse (``can``: yielding stories or P-Δ), the first output time a
    story drift ratio exceeds the run's collapse drift, or the time an analysis stopped past it or
    at the failure of one of its stories (an IMK capacity spent; NaN: no collapse)."""
    limit = float(raw.info.get("collapse_drift", np.inf))
    with np.errstate(invalid="ignore"):
        beyond = np.abs(np.nan_to_num(ratio, nan=0.0)) > limit  # (time, building, story)
    hit = beyond.any(axis=2) & can
    out = np.where(hit.any(axis=0), raw.time[np.argmax(hit, axis=0)], np.nan)
    stopped = float(raw.info.get("stopped_at", np.nan))
    if math.isfinite(stopped):
        past = (np.nan_to_num(peak_ratio, nan=0.0).max(axis=1) > limit) & can
        out = np.where(np.isnan(out) & past, stopped, out)
        for b in raw.info.get("failed_stories", ()):
            if can[b] and np.isnan(out[b]):
                out[b] = stopped
    return out


def _story_variables(
    system: PoundingSystem, raw: RawResult, drift: np.ndarray, peak_drift: np.ndarray
) -> dict[str, tuple]:
    """Story spring forces, ductility, hysteretic energy and damage, only for a system with a
    yielding story (the elastic stories of its buildings read k δ, their ductility NaN)."""
    st = system.stories
    if not len(st) or raw.story_force is None:
        return {}
    nb, width = drift.shape[1:]
    k = _padded([b.stiffnesses for b in system.buildings], width)
    spring = drift * k
    peak_spring = peak_drift * k
    fy, e_h, ultimate, beta = (np.full((nb, width), np.nan) for _ in range(4))
    model = np.full((nb, width), "", dtype=object)
    for i, b in enumerate(system.buildings):
        model[i, : b.n_floors] = b.stories.model
    b_i, s_i = st.building, st.story - 1
    spring[:, b_i, s_i] = raw.story_force
    peak_spring[b_i, s_i] = raw.peak_story_force
    fy[b_i, s_i] = st.params[:, 1]
    # W − E of a story that stayed elastic is round-off of its work: below 1e-9 F_y δ_y it is 0
    tiny = 1e-9 * st.params[:, 1] ** 2 / st.params[:, 0]
    e_h[b_i, s_i] = np.where(np.abs(raw.story_hysteretic) < tiny, 0.0, raw.story_hysteretic)
    ultimate[b_i, s_i] = st.ultimate
    beta[b_i, s_i] = st.park_ang_beta
    yield_drift = fy / k
    out = {
        "story_model": (("building", "story"), model.astype(str)),
        "story_spring_force": (("time", "building", "story"), spring),
        "peak_story_spring_force": (("building", "story"), peak_spring),
        "yield_force": (("building", "story"), fy),
        "yield_drift": (("building", "story"), yield_drift),
        "story_ductility": (("building", "story"), peak_drift / yield_drift),
        "hysteretic_energy": (("building", "story"), e_h),
    }
    if np.isfinite(ultimate).any():
        out["park_ang_damage"] = (
            ("building", "story"),
            park_ang(peak_drift, ultimate, e_h, fy, beta),
        )
    return out


def _link_variables(system: PoundingSystem, raw: RawResult) -> dict[str, tuple]:
    """Link forces and labels, only for a system with coupling links (no empty ``link`` axis)."""
    ln = system.links
    if not len(ln) or raw.link_force is None:
        return {}
    return {
        "link_force": (("time", "link"), raw.link_force),
        "peak_link_force": (("link",), raw.peak_link_force),
        "link": (("link",), np.arange(len(ln))),
        "link_left": (("link",), np.array(ln.left, dtype=str)),
        "link_right": (("link",), np.array(ln.right, dtype=str)),
        "link_left_floor": (("link",), ln.left_floor),
        "link_right_floor": (("link",), ln.right_floor),
        "link_type": (("link",), np.array(ln.law, dtype=str)),
    }


def energy_balance_error(energy: np.ndarray) -> float:
    """max_t |E_input − Σ other terms| / max_t |E_input| (0 when nothing was put in)."""
    energy = energy[np.isfinite(energy).all(axis=1)]  # rows after an analysis stopped are NaN
    residual = energy[:, 0] - energy[:, 1:].sum(axis=1)
    scale = float(np.max(np.abs(energy[:, 0]))) if energy.size else 0.0
    if scale == 0.0 or not math.isfinite(scale):
        return 0.0
    return float(np.max(np.abs(residual)) / scale)


def _nanmax(values: np.ndarray) -> float:
    """Maximum ignoring NaN (NaN when all are), as xarray's ``.max()``."""
    finite = values[~np.isnan(values)]
    return float(finite.max()) if finite.size else math.nan


def summary(variables: Mapping[str, tuple[tuple[str, ...], Any, Any]], attrs: Mapping[str, Any]):
    """Headline numbers of a result: periods, peaks per building, impacts per contact, energy
    balance error (the dict of ``ds.pounding.summary()``).

    ``variables[name] = (dims, values, ...)`` as in :class:`ResultVariables`; the dimension order
    of each variable is the schema's."""

    def val(name: str) -> np.ndarray:
        return np.asarray(variables[name][1])

    out: dict[str, Any] = {"buildings": {}, "contacts": []}
    mode1 = int(np.flatnonzero(val("mode") == 1)[0])
    for i, b in enumerate(val("building")):
        entry = {
            "T1": float(val("natural_period")[i, mode1]),
            "peak_displacement": _nanmax(val("peak_displacement")[i]),
            "peak_drift_ratio": _nanmax(val("peak_drift_ratio")[i]),
            "peak_absolute_acceleration": _nanmax(val("peak_absolute_acceleration")[i]),
        }
        entry["peak_base_shear"] = float(val("peak_base_shear")[i])
        if "drift_amplification" in variables:
            entry["no_contact"] = {
                "peak_displacement": _nanmax(val("no_contact_peak_displacement")[i]),
                "peak_drift_ratio": _nanmax(val("no_contact_peak_drift_ratio")[i]),
                "peak_absolute_acceleration": _nanmax(
                    val("no_contact_peak_absolute_acceleration")[i]
                ),
                "peak_base_shear": float(val("no_contact_peak_base_shear")[i]),
            }
            for ratio in (
                "displacement_amplification",
                "drift_amplification",
                "acceleration_amplification",
            ):
                entry[ratio] = float(val(ratio)[i])
            entry["max_impact_story_shear"] = _nanmax(val("impact_story_shear")[i])
        if "peak_base_displacement" in variables:
            base = float(val("peak_base_displacement")[i])
            if math.isfinite(base):
                entry["peak_base_displacement"] = base
        if "peak_foundation_sway" in variables and math.isfinite(val("peak_foundation_sway")[i]):
            entry["flexible_base_period"] = float(val("flexible_base_period")[i])
            entry["peak_foundation_sway"] = float(val("peak_foundation_sway")[i])
            entry["peak_foundation_rocking"] = float(val("peak_foundation_rocking")[i])
        collapse = float(val("collapse_time")[i]) if "collapse_time" in variables else math.nan
        if math.isfinite(collapse):
            entry["collapse_time"] = collapse
        if "story_ductility" in variables and math.isfinite(_nanmax(val("yield_force")[i])):
            entry["peak_story_ductility"] = _nanmax(val("story_ductility")[i])
            entry["max_residual_drift_ratio"] = _nanmax(np.abs(val("residual_drift_ratio")[i]))
            entry["hysteretic_energy"] = float(np.nansum(val("hysteretic_energy")[i]))
            if "park_ang_damage" in variables:
                entry["max_park_ang_damage"] = _nanmax(val("park_ang_damage")[i])
        out["buildings"][str(b)] = entry
    columns = "contact_left_column" in variables

    def end(side: str, j: int) -> str:
        column = int(val(f"contact_{side}_column")[j]) if columns else -1
        return end_label(str(val(f"contact_{side}")[j]), val(f"contact_{side}_floor")[j], column)

    for j, c in enumerate(val("contact")):
        out["contacts"].append(
            {
                "contact": int(c),
                "left": end("left", j),
                "right": end("right", j),
                "law": str(val("contact_law")[j]),
                "gap": float(val("contact_gap")[j]),
                "impacts": int(val("impact_count")[j]),
                "peak_force": float(val("peak_contact_force")[j]),
            }
        )
    out["columns"] = []
    if "peak_column_shear" in variables:
        buildings = val("building")
        for q in range(val("peak_column_shear").size):
            capacity = float(val("column_capacity")[q])
            out["columns"].append(
                {
                    "building": str(buildings[int(val("column_building")[q])]),
                    "story": int(val("column_story")[q]),
                    "elevation": float(val("column_elevation")[q]),
                    "peak_shear": float(val("peak_column_shear")[q]),
                    "peak_drift_shear": float(val("peak_column_drift_shear")[q]),
                    "capacity": capacity if math.isfinite(capacity) else None,
                    "exceeded": bool(val("column_capacity_exceeded")[q]),
                }
            )
    out["energy_balance_error"] = float(attrs.get("energy_balance_error", np.nan))
    out["warnings"] = _warnings(out, attrs)
    return out


def _warnings(summary: Mapping[str, Any], attrs: Mapping[str, Any]) -> list[str]:
    """The run's own warnings (attribute ``warnings``) and every building whose peak drift ratio
    exceeds the run's ``drift_limit``."""
    raw = attrs.get("warnings", "[]")
    found = list(json.loads(raw) if isinstance(raw, str) else raw)
    limit = float(attrs.get("drift_limit", np.nan))
    for name, b in summary["buildings"].items():
        drift = b["peak_drift_ratio"]
        if "collapse_time" in b:
            limit_c = float(attrs.get("collapse_drift", np.nan))
            # a run collapses past its collapse drift or when a story's capacity is spent
            why = (
                f"a story drift ratio beyond [analysis] collapse_drift = {limit_c:g}"
                if drift > limit_c
                else "a story's energy capacity spent: IMK β = 1, no force from then on"
            )
            found.append(
                f"building {name}: collapse at t = {b['collapse_time']:.4g} s ({why}); the "
                "analysis stops there"
            )
        elif math.isfinite(limit) and drift > limit and "peak_story_ductility" not in b:
            found.append(
                f"building {name}: peak drift ratio {drift:.3g} exceeds the drift limit {limit:g}: "
                "beyond it elastic stories are no model of a real building (the limit: "
                "[output] drift_limit)"
            )
    for c in summary.get("columns", []):
        if c["exceeded"]:
            found.append(
                f"building {c['building']}: the column of story {c['story']} struck at "
                f"{c['elevation']:.3g} m carries a peak shear of {c['peak_shear'] / 1e6:.3g} MN, "
                f"above its capacity {c['capacity'] / 1e6:.3g} MN (a shear failure of the column; "
                f"its share of the story shear alone peaks at {c['peak_drift_shear'] / 1e6:.3g} MN)"
            )
    return found
