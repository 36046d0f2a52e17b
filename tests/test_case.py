"""Case files: the examples load and bad input is named before any integration."""

from __future__ import annotations

import copy
from pathlib import Path

import pytest
from test_validation import edited

from pounding.case import CaseError, case_from_dict, load_case
from pounding.units import G

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"

BASE = {
    "title": "t",
    "building": [
        {"name": "A", "masses": [3e5, 3e5], "stiffnesses": [4e8, 4e8]},
        {"name": "B", "n_floors": 3, "period": 0.6, "mass": 3e5},
    ],
    "contact": [{"left": "A", "right": "B", "gap": 0.02, "law": "hertz", "k": 2.75e9}],
    "ground_motion": {"type": "sine_pulse", "amplitude": 0.3, "units": "g", "period": 0.5},
    "analysis": {"method": "newmark", "output_dt": 0.01},
}


SINGLE_RUN_EXAMPLES = [
    p
    for p in sorted(EXAMPLES.glob("*.toml"))
    if not {"[study]", "[ida]"} & set(p.read_text().split())
]


@pytest.mark.parametrize("path", SINGLE_RUN_EXAMPLES, ids=lambda p: p.stem)
def test_examples_load(path):
    case = load_case(path)
    assert case.system.n_dof >= 1
    assert len(case.system.elements) >= 1


def test_case_builds_system_and_converts_units():
    case = case_from_dict(BASE)
    assert case.system.building_names == ("A", "B")
    assert len(case.system.elements) == 2  # floors 1 and 2 are at common elevations
    assert case.ground_motion.pga == pytest.approx(0.3 * G, rel=1e-3)


def _broken(path: list, value) -> dict:
    return edited(BASE, tuple(path), value)


@pytest.mark.parametrize(
    ("path", "value", "message"),
    [
        (["contact", 0, "law"], "hertzz", r"unknown contact law 'hertzz'; allowed: .*flores"),
        (["building", 0, "masses"], [3e5, -1.0], r"masses\[1\]"),
        (["building", 0, "stiffnesses"], [4e8, float("nan")], r"stiffnesses\[1\]"),
        (["building", 0, "masses"], KeyError, r"building\[0\]\.masses is required"),
        (["contact", 0, "gap"], -0.1, r"gap = -0.1"),
        (["contact", 0, "k"], KeyError, r"k \(contact stiffness"),
        (["contact", 0, "right"], "C", r"contact\[0\] 'A'-'C': right = 'C': unknown building 'C'"),
        (["contact", 0, "colour"], "red", r"contact\[0\]: unknown key\(s\) colour"),
        (["analysis", "method"], "euler", r"analysis.method = 'euler'; allowed: .*newmark.*ivp"),
        (["analysis", "dt"], -1.0, r"analysis.dt = -1.0"),
        (["ground_motion", "type"], "square", r"ground_motion.type = 'square'; allowed: harmonic"),
        (
            ["ground_motion", "units"],
            "furlongs",
            r"ground_motion\.units = 'furlongs': unknown acceleration unit 'furlongs'",
        ),
        (["building", 1, "damping"], {"ratio": 1.2}, r"ratio"),
    ],
)
def test_bad_case_names_the_key(path, value, message):
    with pytest.raises(CaseError, match=message):
        case_from_dict(_broken(path, value))


def test_common_floors_that_do_not_exist_name_the_heights():
    # a fuzzed height (campaign of issue 16) left no common floor: the error says which heights
    data = copy.deepcopy(BASE)
    data["building"][1]["height"] = 3.7
    with pytest.raises(
        CaseError, match=r"contact\[0\] 'A'-'B': floors = 'common' but no floor"
    ) as e:
        case_from_dict(data)
    assert "(floors at 3, 6 m)" in str(e.value) and "(3.7, 7.4, 11.1 m)" in str(e.value)


@pytest.mark.parametrize("key", ["height", "heights"])
def test_a_story_height_below_a_centimetre_is_refused(key):
    # a fuzzed height of 1e-300 m overflowed the stiffness of a column struck between floors
    data = copy.deepcopy(BASE)
    data["building"][0][key] = 1e-300 if key == "height" else [1e-300]
    with pytest.raises(CaseError, match=rf"{key}.*allowed: .*>= 0.01 and <= 1000 \[m\]"):
        case_from_dict(data)


def test_contact_between_non_neighbours_is_rejected():
    data = copy.deepcopy(BASE)
    data["building"].append({"name": "C", "n_floors": 2, "period": 0.4, "mass": 3e5})
    data["contact"] = [{"left": "A", "right": "C", "gap": 0.02, "law": "linear", "k": 1e9}]
    with pytest.raises(CaseError, match="neighbours"):
        case_from_dict(data)


def test_missing_and_invalid_files(tmp_path):
    with pytest.raises(FileNotFoundError):
        load_case(tmp_path / "nope.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("title = \n")
    with pytest.raises(CaseError, match="not valid TOML"):
        load_case(bad)


SHARED = Path(__file__).resolve().parents[2] / "shared" / "data" / "ground_motions"


@pytest.mark.skipif(not SHARED.is_dir(), reason="../shared/data not present")
def test_case_with_el_centro_file_in_g(tmp_path):
    # the 1940 El Centro NS record (two columns, time and acceleration in g): PGA 0.3188 g
    data = copy.deepcopy(BASE)
    data["ground_motion"] = {"file": str(SHARED / "elcentro_1940_ns_g_dt002.txt"), "units": "g"}
    case = case_from_dict(data)
    assert case.ground_motion.dt == pytest.approx(0.02)
    assert case.ground_motion.pga == pytest.approx(0.3188 * G, rel=1e-3)
