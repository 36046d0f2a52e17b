"""Typed input checks: every case-file key's type and range, refused before anything is built.

The reproducers of a reliability campaign: wrong TOML types reached the code (tracebacks) or were
silently read as something else (``adaptive = "false"`` meant true, ``n_floors = 2.7`` built two
floors, ``dt = true`` became 1 s, ``contact = ""`` meant no contacts).
"""

from __future__ import annotations

import copy
import json
import math
import os
import signal
import tomllib
import warnings
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from pounding.case import CASE_SCHEMA, CaseError, case_file_reference, case_from_dict
from pounding.cli import app
from pounding.errors import PoundingError, PoundingInputError
from pounding.simulate import simulate
from pounding.validation import Key, check_table

ROOT = Path(__file__).resolve().parents[1]
TWO_SDOF = ROOT / "examples" / "two_sdof.toml"
BASE = tomllib.loads(TWO_SDOF.read_text())


def edited(base: dict, path: tuple, value) -> dict:
    """A deep copy of ``base`` with the value at ``path`` replaced (deleted for ``KeyError``)."""
    data = copy.deepcopy(base)
    node = data
    for key in path[:-1]:
        node = node[key]
    if value is KeyError:
        node.pop(path[-1], None)
    else:
        node[path[-1]] = value
    return data


def _with(path: tuple, value) -> dict:
    return edited(BASE, path, value)


_DELETE = KeyError

# (path in the case, value, the key the one-line error must name)
WRONG = [
    (("contact",), 5, "contact = 5"),
    (("contact",), "", "contact = ''"),
    (("contact", 0, "left"), ["A"], "contact[0].left"),
    (("contact", 0, "floors"), True, "contact[0].floors"),
    (("contact", 0, "floors"), [], "contact[0].floors"),
    (("contact", 0, "e"), {}, "contact[0].e"),
    (("contact", 0, "e"), 1.5, "contact[0].e"),
    (("ground_motion", "units"), 1, "ground_motion.units"),
    (("ground_motion", "units"), "x", "ground_motion.units = 'x'"),
    (("ground_motion", "amplitude"), True, "ground_motion.amplitude"),
    (("ground_motion", "dt"), 1e-300, "ground_motion.dt"),
    (("analysis", "max_halvings"), math.inf, "analysis.max_halvings"),
    (("analysis", "max_iter"), 1e20, "analysis.max_iter"),
    (("analysis", "adaptive"), "false", "analysis.adaptive"),
    (("analysis", "dt"), True, "analysis.dt"),
    (("analysis", "steps_per_contact"), 2**63 - 1, "analysis.steps_per_contact"),
    (("analysis", "duration"), 1e9, "analysis.duration"),
    (("building", 0, "n_floors"), -math.inf, "building[0].n_floors"),
    (("building", 0, "n_floors"), 2.7, "building[0].n_floors"),
    (("building", 0, "n_floors"), 100_000, "building[0].n_floors"),
    (("building", 0, "heights"), [3.0], "heights"),
    (("building", 0, "damping", "ratio"), "5%", "building[0].damping.ratio"),
    (("title",), 3, "title"),
    (("output",), {"drift_limit": -1}, "output.drift_limit"),
    (("output",), {"floor_spectra": "top"}, "output.floor_spectra"),
    (("output",), {"floor_spectra": [0]}, "output.floor_spectra"),
]


@pytest.mark.parametrize(("path", "value", "names"), WRONG, ids=[w[2] for w in WRONG])
def test_wrong_type_or_range_is_refused_naming_the_key(path, value, names):
    with pytest.raises(CaseError) as err:
        case_from_dict(_with(path, value))
    assert names in str(err.value) and "allowed" in str(err.value) or "uniform" in str(err.value)


def test_cli_prints_one_line_and_exits_2_for_a_wrong_type(tmp_path):
    case = tmp_path / "bad.toml"
    case.write_text(TWO_SDOF.read_text().replace('method = "newmark"', 'adaptive = "false"'))
    res = CliRunner().invoke(app, ["run", str(case), "-o", str(tmp_path / "out.nc")])
    assert res.exit_code == 2
    lines = res.output.strip().splitlines()
    assert len(lines) == 1 and "analysis.adaptive = 'false'; allowed: true or false" in lines[0]
    assert not (tmp_path / "out.nc").exists()


def test_a_step_that_cannot_represent_the_structure_is_refused():
    # dt = 100 s gave all-zero peaks and "energy balance error 0 %"
    case = case_from_dict(_with(("analysis", "output_dt"), _DELETE))
    with pytest.raises(PoundingInputError, match="half the shortest natural period"):
        simulate(case, dt=0.4)
    # so short a step that its round-off swamps the response (balance error 27 at dt = 1.2e-7 s;
    # 9e-6 at 1e-6 s): refused with the case-file key's range
    with pytest.raises(CaseError, match=r"analysis\.dt = 1\.2e-07; allowed: a number >= 1e-06"):
        case_from_dict(_with(("analysis", "dt"), 1.2e-7))
    # a step between a tenth and half of it runs, with a warning in the result
    ds = simulate(case, dt=0.06)
    assert "a tenth of the shortest natural period" in ds.attrs["warnings"]


def test_a_result_too_large_for_memory_is_refused_with_its_estimate():
    case = case_from_dict(_with(("analysis", "output_dt"), 1e-6))
    with pytest.raises(PoundingInputError, match=r"would need about [0-9.]+ GiB"):
        simulate(case, duration=1e4)


def test_drift_beyond_the_limit_is_flagged():
    # examples/two_sdof.toml: 6.7 % drift from elastic stories, which nothing said
    ds = simulate(case_from_dict(BASE))
    warnings = ds.pounding.summary()["warnings"]
    assert any("building B: peak drift ratio" in w and "0.02" in w for w in warnings)
    relaxed = simulate(case_from_dict(_with(("output",), {"drift_limit": 0.5})))
    assert relaxed.attrs["drift_limit"] == 0.5
    assert relaxed.pounding.summary()["warnings"] == []


def test_a_list_names_the_bad_element():
    keys = (Key("masses", "numbers", "floor masses", "kg", 0.0, open_low=True),)
    with pytest.raises(ValueError, match=r"x\.masses\[1\] = -1; allowed: a number > 0 \[kg\]"):
        check_table({"masses": [1.0, -1]}, keys, "x")
    assert check_table({"masses": [1, 2.5]}, keys, "x") == {"masses": [1.0, 2.5]}


def test_case_file_reference_is_generated_from_the_schema():
    # docs/case_file.md is the schema's own text: regenerate it with
    # python -c "from pounding.case import case_file_reference; print(case_file_reference())"
    doc = (ROOT / "docs" / "case_file.md").read_text()
    assert doc == case_file_reference() + "\n"
    for table, keys in CASE_SCHEMA.items():
        for key in keys:
            assert f"`{key.name}`" in doc, (table, key.name)


# --- the fuzzer: valid case files perturbed key by key ---

_PATHS = [
    ("title",),
    *[("building", i, k) for i in (0, 1) for k in ("name", "n_floors", "period", "mass", "height")],
    ("building", 0, "damping", "ratio"),
    ("building", 0, "damping", "modes"),
    ("building", 1, "heights"),
    *[("contact", 0, k) for k in ("left", "right", "gap", "law", "k", "e", "n", "floors", "a")],
    ("contact", 0, "calibration"),
    ("contact",),
    *[("ground_motion", k) for k in ("type", "amplitude", "units", "period", "duration", "dt")],
    *[("analysis", k) for k in ("method", "dt", "output_dt", "duration", "alpha", "tol")],
    *[("analysis", k) for k in ("max_iter", "max_halvings", "locate_onset", "adaptive")],
    ("analysis", "steps_per_contact"),
    ("output", "drift_limit"),
    ("output", "floor_spectra"),
]
_VALUES = st.one_of(
    st.sampled_from(
        [True, False, "", "x", "false", [], {}, [1], [[1, 1]], -1, 0, 1, 2.7, -2.7, 1e-300, 1e300]
    ),
    st.sampled_from([math.inf, -math.inf, math.nan, 2**63 - 1, -(2**63), "\x00", _DELETE]),
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(min_value=-(2**63), max_value=2**63 - 1),
)


def _perturbed(path: tuple, value) -> dict:
    base = copy.deepcopy(BASE)
    base["building"][0]["damping"] = {"ratio": 0.05, "modes": [1, 2]}
    base["output"] = {"drift_limit": 0.5}
    base["ground_motion"]["duration"] = 1.5  # s: a 500-floor building must run within the alarm
    return edited(base, path, value)


@settings(max_examples=int(os.environ.get("POUNDING_FUZZ_EXAMPLES", "200")), deadline=None)
@given(path=st.sampled_from(_PATHS), value=_VALUES)
def test_fuzzed_case_file_is_refused_in_one_line_or_runs_with_a_closed_ledger(path, value):
    # Every perturbed case either fails before the run with an error naming the key (or the
    # table that holds it), or runs and reports an energy balance error below 1 %; nothing else:
    # no other exception, no hang (30 s alarm), no NaN.
    data = _perturbed(path, value)
    try:
        case = case_from_dict(data)
    except CaseError as exc:
        message = str(exc)
        named = [str(p) for p in path if isinstance(p, str)]
        assert "\n" not in message
        assert any(n in message for n in named) or "building" in message or "uniform" in message
        return
    ds = _simulated_or_refused(case)
    if ds is None:
        return
    assert ds.attrs["energy_balance_error"] < 1e-2
    assert np.isfinite(ds["displacement"].values[:, :, 0]).all()


def _simulated_or_refused(case):
    """The analysis of ``case``, or None when it is refused in one line; none may take 30 s."""
    signal.signal(signal.SIGALRM, _timeout)
    signal.alarm(30)
    try:
        return simulate(case)
    except PoundingError as exc:
        assert "\n" not in str(exc)
        return None
    finally:
        signal.alarm(0)


# --- the same over every key of the examples with yielding stories, bumpers, soil, bearings and
# struck columns (campaign of 2026-11-28: heights, column masses, soil masses and pendulum radii of
# 1e-300 overflowed or asked for 1e150 steps; a 1 kg floor on a 1e15 N/m story hung) ---

_EXAMPLES = [
    "three_vs_eight_yielding", "bumper", "soft_soil", "base_isolated_moat", "floor_to_column",
    "building_wall",
]  # fmt: skip


def _leaves(node, path=()):
    """Paths of the values of a parsed case (a list of tables is walked, a list of numbers is one)."""
    if isinstance(node, dict):
        for key, value in node.items():
            yield from _leaves(value, (*path, key))
    elif isinstance(node, list) and node and all(isinstance(v, dict) for v in node):
        for i, value in enumerate(node):
            yield from _leaves(value, (*path, i))
    elif path and path[0] not in ("title", "study", "ida"):
        yield path


def _example(name: str) -> dict:
    data = tomllib.loads((ROOT / "examples" / f"{name}.toml").read_text())
    # s: a valid model made 1e6 times stiffer takes 1e3 times more steps; they end within the alarm
    data.setdefault("analysis", {})["duration"] = 0.05
    return data


_EXAMPLE_PATHS = [
    (name, path)
    for name in _EXAMPLES
    for path in _leaves(_example(name))
    if path != ("analysis", "duration")  # pinned above (7130 s ran past the alarm)
]
#: A value or a factor on the value there (numbers out of their plausible range by decades).
_EXAMPLE_VALUES = st.one_of(
    _VALUES, st.tuples(st.just("x"), st.sampled_from([0, 1e-300, 1e-6, 1e-3, 1e3, 1e6, -1]))
)


@settings(max_examples=int(os.environ.get("POUNDING_FUZZ_EXAMPLES", "150")), deadline=None)
@given(where=st.sampled_from(_EXAMPLE_PATHS), value=_EXAMPLE_VALUES)
def test_fuzzed_example_is_refused_in_one_line_or_runs_without_a_numpy_warning(where, value):
    name, path = where
    data = _example(name)
    if isinstance(value, tuple):  # a factor on the number(s) there
        node = data
        for key in path:
            node = node[key]
        factor = value[1]
        if isinstance(node, bool) or not isinstance(node, int | float | list):
            return
        value = [v * factor for v in node] if isinstance(node, list) else node * factor
    if path[-1] == "n_floors" and isinstance(value, int) and 100 < value <= 500:
        # valid, but a uniform building's top mode shortens the step as 1/n: 496 floors on soil
        # take ~45 s a second of record (the two-SDOF fuzzer runs the 500-floor bound)
        return
    data = edited(data, path, value)
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        try:
            case = case_from_dict(data)
        except (CaseError, FileNotFoundError) as exc:  # (a record reference to no file)
            assert "\n" not in str(exc)
            return
        ds = _simulated_or_refused(case)
    assert ds is None or ds.attrs["energy_balance_error"] < 1e-2


def _timeout(signum, frame):
    raise AssertionError("the analysis took longer than 30 s")


def test_two_sdof_with_k_in_the_wrong_units_names_the_impact_that_outlasts_the_analysis():
    # examples/two_sdof.toml with k = 2.75e3 N/m^1.5 (2.75e9 typed in kN-ish units): the impact
    # lasts t_c = 2.943275 δ_max/v0, δ_max = (5 m̄ v0²/(4k))^(2/5) (Goldsmith 1960), m̄ = 1e5 kg:
    # ~13 s at ~1.3 m/s, longer than the 6 s analysis. The run warns, naming k, instead of
    # integrating a 40 s free impact to check the law's rebound.
    data = copy.deepcopy(BASE)
    data["contact"][0]["k"] = 2.75e3
    ds = simulate(case_from_dict(data))
    warned = [w for w in json.loads(ds.attrs["warnings"]) if "would last" in w]
    assert len(warned) == 1 and "k = 2.75e+03 N/m^1.5" in warned[0]
    assert "longer than the analysis (6 s)" in warned[0] and "check k and its units" in warned[0]
    v0 = float(warned[0].split("impact at ")[1].split()[0])
    d_max = (5.0 * 1e5 * v0**2 / (4.0 * 2.75e3)) ** 0.4
    t_c = float(warned[0].split("would last ")[1].split()[0])
    assert t_c == pytest.approx(2.943275 * d_max / v0, rel=2e-3)  # v0 printed to 3 digits


def test_two_sdof_with_a_1_kg_floor_on_a_1e15_n_per_m_story_is_refused_before_it_hangs(tmp_path):
    # T = 2π √(1/1e15) = 1.99e-7 s: 160 steps a period over 6 s is 4.8e9 steps (hours); refused
    # with the building and its period instead
    data = copy.deepcopy(BASE)
    a = data["building"][0]
    for key in ("n_floors", "period", "mass"):
        a.pop(key)
    a.update(masses=[1.0], stiffnesses=[1e15])
    with pytest.raises(PoundingInputError) as info:
        simulate(case_from_dict(data))
    assert str(info.value).startswith(
        "the analysis would take 4.83e+09 steps of 1.24e-09 s, more than 1e+09: building 'A' "
        "has a natural period of 1.99e-07 s; allowed:"
    )
    text = TWO_SDOF.read_text().replace(
        "n_floors = 1\nperiod = 0.5          # s\nmass = 2.0e5",
        "masses = [1.0]\nstiffnesses = [1e15]",
    )
    (tmp_path / "stiff.toml").write_text(text)
    res = CliRunner().invoke(app, ["run", str(tmp_path / "stiff.toml")])
    # (a stale kernel cache adds its notice first: the error is the last line)
    assert res.exit_code == 2
    assert res.output.splitlines()[-1].startswith("error: the analysis would take 4.83e+09 steps")


def test_two_sdof_at_dt_1us_for_2000_s_is_refused_naming_the_given_dt():
    with pytest.raises(PoundingInputError) as info:
        simulate(case_from_dict(BASE), dt=1e-6, output_dt=0.01, duration=2000.0)
    assert str(info.value) == (
        "the analysis would take 2e+09 steps of 1e-06 s, more than 1e+09: set by analysis.dt; "
        "allowed: a longer analysis.dt or a shorter analysis.duration"
    )


def test_two_sdof_with_a_subnormal_k_runs_without_an_overflow():
    # the fuzzer's k = 1e-310 overflowed (n+1) m̄/(2k) in the impact-duration scale: the impact
    # never ends (t_c = inf, no step limit) and the run says so, without a RuntimeWarning
    data = copy.deepcopy(BASE)
    data["contact"][0]["k"] = 1e-310
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ds = simulate(case_from_dict(data))
    assert any("would last inf s" in w for w in json.loads(ds.attrs["warnings"]))
    assert ds.attrs["energy_balance_error"] < 1e-6


def test_command_line_overrides_are_checked_like_case_keys(tmp_path):
    res = CliRunner().invoke(app, ["run", str(TWO_SDOF), "--dt", "1e-8"])
    assert res.exit_code == 2
    assert (
        res.output.strip() == "error: analysis.dt = 1e-08; allowed: a number >= 1e-06 and <= 1 [s]"
    )


def test_a_case_file_that_is_not_utf8_is_one_line(tmp_path):
    bad = tmp_path / "latin1.toml"
    bad.write_bytes('title = "Bâtiment"\n'.encode("latin-1"))
    res = CliRunner().invoke(app, ["run", str(bad)])
    assert res.exit_code == 2
    assert (
        res.output.strip()
        == f"error: {bad}: not UTF-8 text (byte 0xe2 at position 10); allowed: a UTF-8 TOML file"
    )
