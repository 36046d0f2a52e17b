"""The results schema: names, CF attributes, padding, accessor, NetCDF round trip."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from pounding.ground_motion import harmonic, sine_pulse
from pounding.results import open_result, save
from pounding.simulate import simulate
from pounding.structure import ModalDamping, ShearBuilding
from pounding.system import Contact, assemble
from pounding.units import G

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def pair() -> xr.Dataset:
    a = ShearBuilding.uniform("A", 3, period=0.3, mass=3e5)
    b = ShearBuilding.uniform("B", 5, period=0.8, mass=3e5)
    contacts = [
        Contact("A", "B", 0.01, "flores", k=2.75e9, e=0.65),
        Contact("B", "wall", 0.05, "linear", floors=[5], k=2e9),
    ]
    gm = sine_pulse(amplitude=4.0, period=0.7, duration=4.0, dt=0.005)
    return simulate(assemble([a, b], contacts), gm, output_dt=0.01)


ISSUE_VARIABLES = {
    "displacement": ("time", "building", "floor"),
    "velocity": ("time", "building", "floor"),
    "absolute_acceleration": ("time", "building", "floor"),
    "drift": ("time", "building", "story"),
    "drift_ratio": ("time", "building", "story"),
    "penetration": ("time", "contact"),
    "contact_force": ("time", "contact"),
    "ground_acceleration": ("time",),
    "peak_displacement": ("building", "floor"),
    "peak_drift_ratio": ("building", "story"),
    "peak_contact_force": ("contact",),
    "impact_count": ("contact",),
    "energy": ("time", "term"),
}


def test_schema_has_the_issue_names_and_dims(pair):
    for name, dims in ISSUE_VARIABLES.items():
        assert pair[name].dims == dims, name
    for coord in (
        "contact_left",
        "contact_right",
        "contact_left_floor",
        "contact_right_floor",
        "contact_gap",
        "contact_law",
    ):
        assert pair[coord].dims == ("contact",)
    assert list(pair["building"].values) == ["A", "B"]
    assert list(pair["floor"].values) == [1, 2, 3, 4, 5]
    assert list(pair["term"].values) == [
        "input",
        "kinetic",
        "strain",
        "damping",
        "contact_dissipated",
        "contact_stored",
        "friction_dissipated",
        "algorithmic",
        "link_dissipated",
        "link_stored",
        "hysteretic",
    ]
    assert "energy_balance_error" in pair.attrs


def test_every_variable_has_units_and_long_name(pair):
    for name, var in pair.data_vars.items():
        assert "long_name" in var.attrs, name
        assert "units" in var.attrs, name


def test_short_building_is_padded_with_nan(pair):
    u = pair["displacement"].sel(building="A")
    assert np.isnan(u.sel(floor=[4, 5])).all()
    assert np.isfinite(u.sel(floor=[1, 2, 3])).all()


def test_contact_coordinates_follow_the_definition(pair):
    # three common floors between A and B, then B's roof against the wall
    assert list(pair["contact_left"].values) == ["A", "A", "A", "B"]
    assert list(pair["contact_right"].values) == ["B", "B", "B", "wall"]
    assert list(pair["contact_right_floor"].values) == [1, 2, 3, 0]
    assert list(pair["contact_law"].values) == ["flores"] * 3 + ["linear"]


def test_peaks_bound_the_output_histories(pair):
    # peaks are taken at every integration step, so they bound the decimated output
    u = np.abs(pair["displacement"]).max("time")
    assert (pair["peak_displacement"] >= u - 1e-12).where(np.isfinite(u), True).all()
    f = pair["contact_force"].max("time")
    assert (pair["peak_contact_force"] >= f - 1e-9).all()


def test_drift_is_floor_difference(pair):
    u = pair["displacement"].sel(building="B")
    d = pair["drift"].sel(building="B")
    np.testing.assert_allclose(d.sel(story=3), u.sel(floor=3) - u.sel(floor=2))
    np.testing.assert_allclose(d.sel(story=1), u.sel(floor=1))
    np.testing.assert_allclose(
        pair["drift_ratio"].sel(building="B"), d / pair["story_height"].sel(building="B")
    )


def test_accessor_impacts_agree_with_counts(pair):
    imp = pair.pounding.impacts()
    assert len(imp) == int(pair["impact_count"].sum()) > 0
    assert list(imp.columns) == [
        "contact",
        "start",
        "end",
        "v0",
        "peak_force",
        "max_penetration",
        "impulse",
        "rebound_ratio",
        "nominal_e",
        "restitution",
    ]
    # the former name is an alias; the law's nominal e stands beside the measured ratio
    assert imp["restitution"].equals(imp["rebound_ratio"])
    assert set(imp["nominal_e"].dropna()) == {0.65}
    assert (imp["end"].dropna() > imp["start"][imp["end"].notna()]).all()
    for c, grp in imp.groupby("contact"):
        assert grp["peak_force"].max() == pytest.approx(float(pair["peak_contact_force"][c]))
    # in a multi-storey pair one rebound may be faster than its approach (other floors push), but the
    # Flores law dissipates: on average rebounds are slower, and the ledger shows dissipated energy
    assert imp[imp["contact"] < 3]["rebound_ratio"].median() < 1.0
    assert float(pair["energy"].isel(time=-1).sel(term="contact_dissipated")) > 0.0


def test_netcdf_round_trip(pair, tmp_path):
    path = save(pair, tmp_path / "out.nc")
    back = open_result(path)
    xr.testing.assert_allclose(pair, back)
    assert back["displacement"].attrs["units"] == "m"
    assert back.attrs["energy_balance_error"] == pytest.approx(pair.attrs["energy_balance_error"])
    with pytest.raises(FileNotFoundError):
        open_result(tmp_path / "missing.nc")


def test_save_writes_what_to_netcdf_writes(pair, tmp_path):
    # results.save writes NetCDF-4 with h5py directly: the file must read back identical to the
    # Dataset and to the one xarray's own h5netcdf writer makes, with netCDF-4's dimension scales
    import h5py

    path = save(pair, tmp_path / "fast.nc")
    pair.to_netcdf(tmp_path / "xr.nc", engine="h5netcdf")
    fast, ref = open_result(path), open_result(tmp_path / "xr.nc")
    xr.testing.assert_identical(fast, pair)
    xr.testing.assert_identical(fast, ref)
    assert set(fast.coords) == set(pair.coords)  # non-dimension coordinates stay coordinates
    with h5py.File(path) as f:
        dimids = [int(f[d].attrs["_Netcdf4Dimid"]) for d in pair.dims]
        assert dimids == list(range(len(pair.dims)))
        assert f["time"].is_scale and f["term"].is_scale
        assert [d[0].name for d in f["displacement"].dims] == [
            "/time",
            "/building",
            "/floor",
        ]
        assert list(f["drift"].attrs["_Netcdf4Coordinates"]) == [0, 1, 3]
        assert f.attrs["_NCProperties"].startswith(b"version=2,")
        assert h5py.check_string_dtype(f["contact_law"].dtype).encoding == "utf-8"


def test_save_leaves_other_datasets_to_xarray(tmp_path):
    # a dtype the direct writer does not handle (bool), a compression encoding and a dimension
    # without coordinates all go through to_netcdf and still round-trip
    ds = xr.Dataset(
        {
            "flag": ("time", np.array([True, False]), {"long_name": "flag"}),
            "x": ("time", np.array([1.0, 2.0]), {"units": "m", "long_name": "x"}),
            "y": ("n", np.arange(3.0), {"units": "m", "long_name": "y"}),
        },
        coords={"time": [0.0, 0.1]},
    )
    for case in (ds, ds.drop_vars("flag")):
        back = open_result(save(case, tmp_path / "other.nc"))
        xr.testing.assert_identical(back, case)
    packed = ds.drop_vars(["flag", "y"])
    packed["x"].encoding = {"zlib": True, "dtype": "float32"}
    back = open_result(save(packed, tmp_path / "packed.nc"))
    assert back["x"].dtype == np.float32 and back["x"].encoding["zlib"]


def test_a_failed_write_leaves_the_previous_result_untouched(pair, tmp_path):
    # Results used to be written in place: a write that failed (a NUL in a building name, a full
    # disk) left a corrupt file and destroyed the good result already at that path.
    from pounding.errors import ResultWriteError

    path = tmp_path / "out.nc"
    save(pair, path)
    before = path.read_bytes()
    bad = pair.assign_coords(building=["A\x00x", "B"])
    with pytest.raises(ResultWriteError, match="previous file there is untouched"):
        save(bad, path)
    assert path.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.nc"]  # no temporary file left


def test_a_failed_fallback_write_leaves_the_previous_result_untouched(tmp_path, monkeypatch):
    from pounding.errors import ResultWriteError

    ds = xr.Dataset({"flag": ("x", np.array([True, False]))}, coords={"x": [0, 1]})
    path = tmp_path / "other.nc"
    save(ds, path)  # booleans go through xarray's writer
    before = path.read_bytes()

    def full_disk(self, target, *args, **kwargs):
        with open(target, "wb") as fh:
            fh.write(b"\x89HDF\r\n\x1a\n partial")
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(xr.Dataset, "to_netcdf", full_disk)
    with pytest.raises(ResultWriteError, match="No space left on device"):
        save(ds, path)
    assert path.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["other.nc"]


# --- story and base shear (equilibrium of the floors above, with the contact forces) ---


@pytest.mark.parametrize("method", ["newmark", "ivp"])
def test_story_shear_of_an_undamped_pair_is_story_stiffness_times_drift(method):
    # Without damping the force a story carries is its spring's, k_i (u_i − u_{i−1}), computed here
    # from the drift history; the schema takes it from the floors' inertia and contact forces
    # (Hunt–Crossley impacts at floors 1–3), so the two meet only if the contact forces' signs and
    # the absolute accelerations are right.
    def undamped(name, n, period):
        b = ShearBuilding.uniform(name, n, period=period, mass=3e5)
        return ShearBuilding(name, b.masses, b.stiffnesses, damping=ModalDamping((0.0,) * n))

    system = assemble(
        [undamped("A", 3, 0.3), undamped("B", 6, 0.8)],
        [Contact("A", "B", gap=0.01, law="hunt_crossley", k=2.75e9, e=0.65)],
    )
    ds = simulate(
        system, harmonic(amplitude=0.4 * G, period=0.7, duration=6.0, dt=0.01), method=method
    )
    assert len(ds.pounding.impacts()) > 5
    spring = (ds["story_stiffness"] * ds["drift"]).transpose(*ds["story_shear"].dims).values
    shear = ds["story_shear"].values
    scale = np.nanmax(np.abs(spring))
    assert np.nanmax(np.abs(shear - spring)) < 1e-6 * scale
    assert np.array_equal(ds["base_shear"].values, shear[:, :, 0])
    assert np.allclose(ds["peak_base_shear"].values, np.nanmax(np.abs(shear[:, :, 0]), axis=0))


def test_story_shear_is_the_spring_and_damping_force_of_the_story(pair):
    # Rayleigh damping and a wall contact at B's roof: V_i = Σ_{j ≥ i} (K u + C v)_j from the
    # assembled matrices, to the Newton tolerance.
    a = ShearBuilding.uniform("A", 3, period=0.3, mass=3e5)
    b = ShearBuilding.uniform("B", 5, period=0.8, mass=3e5)
    system = assemble(
        [a, b],
        [
            Contact("A", "B", 0.01, "flores", k=2.75e9, e=0.65),
            Contact("B", "wall", 0.05, "linear", floors=[5], k=2e9),
        ],
    )
    u = np.concatenate([pair["displacement"].sel(building=n).dropna("floor") for n in "AB"], axis=1)
    v = np.concatenate([pair["velocity"].sel(building=n).dropna("floor") for n in "AB"], axis=1)
    force = u @ system.stiffness.T + v @ system.damping.T
    for name, n in (("A", 3), ("B", 5)):
        o = int(system.dof_offset[list(system.building_names).index(name)])
        expected = np.cumsum(force[:, o : o + n][:, ::-1], axis=1)[:, ::-1]
        got = pair["story_shear"].sel(building=name).values[:, :n]
        assert np.max(np.abs(got - expected)) < 1e-6 * np.max(np.abs(expected))
    assert pair["story_shear"].attrs["units"] == "N"


def test_baseline_peaks_are_those_of_the_same_analysis_without_contacts():
    # simulate(baseline=True) adds the no-contact run's peaks; here that run is made independently
    # (the buildings assembled with no contacts) and every ratio and difference is checked from it.
    a = ShearBuilding.uniform("A", 3, period=0.3, mass=3e5)
    b = ShearBuilding.uniform("B", 5, period=0.8, mass=3e5)
    gm = sine_pulse(amplitude=4.0, period=0.7, duration=4.0, dt=0.005)
    contacts = [Contact("A", "B", 0.01, "flores", k=2.75e9, e=0.65)]
    ds = simulate(assemble([a, b], contacts), gm, output_dt=0.01, baseline=True)
    free = simulate(assemble([a, b]), gm, output_dt=0.01)
    for peak in ("peak_displacement", "peak_drift_ratio", "peak_absolute_acceleration"):
        np.testing.assert_array_equal(ds["no_contact_" + peak].values, free[peak].values)
    ratio = ds["peak_drift_ratio"].max("story") / free["peak_drift_ratio"].max("story")
    np.testing.assert_allclose(ds["drift_amplification"].values, ratio.values)
    np.testing.assert_allclose(
        ds["floor_acceleration_amplification"].values,
        (ds["peak_absolute_acceleration"] / free["peak_absolute_acceleration"]).values,
    )
    np.testing.assert_allclose(
        ds["impact_story_shear"].values,
        (ds["peak_story_shear"] - free["peak_story_shear"]).values,
    )
    assert float(ds["drift_amplification"].sel(building="A")) > 1.1  # A is struck
    for name, var in ds.data_vars.items():
        assert var.attrs.get("units") and var.attrs.get("long_name"), name
    # a system without contacts has nothing to compare with
    assert "drift_amplification" not in simulate(assemble([a, b]), gm, baseline=True)


def test_study_statistics_pool_records_but_never_scales(tmp_path):
    # Three records at two scales: the statistics are over the records only (a scale axis is
    # intensity), each equal to numpy's median, 84th percentile and max of the study's own values.
    from test_studies import PULSE, RICKER, _study

    from pounding.errors import PoundingInputError
    from pounding.studies import run_study

    third = {"type": "sine_pulse", "amplitude": 0.4, "units": "g", "period": 0.7, "duration": 2.5}
    study = _study(
        law=["none", "hertz"], gap=[0.005], record=[PULSE, RICKER, third], scale=[0.3, 1.0]
    )
    ds = run_study(study, tmp_path / "runs", jobs=1)
    st = ds.pounding.statistics()
    assert "record" not in st.dims and st.sizes["scale"] == 2
    assert list(st["statistic"].values) == ["median", "p84", "max"]
    for scale in (0.3, 1.0):
        sel = {"law": "hertz", "gap": 0.005, "scale": scale}
        drift = ds["drift_amplification"].sel(sel).transpose("record", "building").values
        got = st["drift_amplification"].sel(sel).transpose("statistic", "building").values
        np.testing.assert_allclose(got[0], np.median(drift, axis=0))
        np.testing.assert_allclose(got[1], np.percentile(drift, 84, axis=0))
        np.testing.assert_allclose(got[2], drift.max(axis=0))
        force = ds["peak_contact_force"].sel(sel).max("contact").values
        np.testing.assert_allclose(
            st["peak_impact_force"].sel(sel).values,
            [np.median(force), np.percentile(force, 84), force.max()],
        )
        hits = (ds["impact_count"].sel(sel).sum("contact") > 0).values
        assert float(st["pounding_fraction"].sel(sel)) == pytest.approx(hits.mean())
    # a weaker shaking pounds in no more records than a stronger one
    frac = st["pounding_fraction"].sel(law="hertz", gap=0.005)
    assert float(frac.sel(scale=0.3)) <= float(frac.sel(scale=1.0))
    assert int(st["n_runs"].sel(law="hertz", gap=0.005, scale=1.0)) == 3
    for name, var in st.data_vars.items():
        assert var.attrs.get("units") and var.attrs.get("long_name"), name
    single = simulate(
        assemble([ShearBuilding.uniform("A", 2, period=0.3, mass=1e5)]),
        sine_pulse(amplitude=2.0, period=0.5, duration=1.0, dt=0.01),
    )
    with pytest.raises(PoundingInputError, match="study"):
        single.pounding.statistics()


def test_floor_response_spectrum_of_the_roof_matches_an_independent_sdof_solution():
    # [output] floor_spectra = "roof": the 5 % damped PSa of the roof's absolute acceleration, checked
    # against scipy's lsim of the same oscillator on the same (linear between output steps)
    # acceleration, sampled 20 times finer so the reference sees the peaks between output steps,
    # with one period of free vibration after the record, as the spectra take it.
    import tomllib

    from scipy import signal

    from pounding.case import case_from_dict

    root = __import__("pathlib").Path(__file__).resolve().parents[1]
    data = tomllib.loads((root / "examples" / "three_vs_eight_story.toml").read_text())
    data["output"] = {"floor_spectra": "roof"}
    ds = simulate(case_from_dict(data))
    frs = ds["floor_spectrum"]
    assert frs.dims == ("building", "floor", "period") and frs.attrs["units"] == "m/s^2"
    assert ds.pounding.summary()["buildings"]["A"]["peak_drift_ratio"] > 0  # the extra dimension
    assert list(frs.sel(building="A").dropna("floor", how="all")["floor"].values) == [3]
    assert list(frs.sel(building="B").dropna("floor", how="all")["floor"].values) == [8]
    acc = ds["absolute_acceleration"].sel(building="A", floor=3).values
    t = ds["time"].values
    dt = t[1] - t[0]
    for i in (10, 30, 50):
        period = float(ds["period"][i])
        w = 2 * np.pi / period
        extra = int(np.ceil(period / dt)) + 1
        coarse = np.arange(t.size + extra) * dt
        fine = np.linspace(0.0, coarse[-1], 20 * (coarse.size - 1) + 1)
        drive = np.interp(fine, coarse, np.concatenate([acc, np.zeros(extra)]))
        _, x, _ = signal.lsim(signal.lti([-1.0], [1.0, 2 * 0.05 * w, w * w]), drive, fine)
        ref = w * w * np.abs(x).max()
        assert float(frs.sel(building="A", floor=3).isel(period=i)) == pytest.approx(ref, rel=2e-3)


def test_every_dataset_kind_speaks_one_vocabulary(tmp_path):
    # Analysis, study and separation Datasets take units and long names from one table
    # (pounding._schema.ATTRS); separately kept tables once disagreed ("natural period" against
    # "natural period (contacts open)"). Study axes describe the sweep and keep their own.
    import tomllib

    from test_studies import _study

    from pounding._schema import ATTRS
    from pounding.case import case_from_dict
    from pounding.separation import separation_analysis
    from pounding.studies import run_study

    data = tomllib.loads((ROOT / "examples" / "two_sdof.toml").read_text())
    data["ground_motion"]["duration"] = 1.0
    case = case_from_dict(data)
    study = run_study(_study(gap=[0.005, 0.01]), tmp_path / "runs", jobs=1)
    kinds = {
        "analysis": simulate(case),
        "study": study,
        "separation": separation_analysis(case),
    }
    axes = set(json.loads(study.attrs["axes"]))
    for kind, ds in kinds.items():
        checked = 0
        for name, var in ds.variables.items():
            if name in ATTRS and not (kind == "study" and name in axes):
                for key, value in ATTRS[name].items():
                    assert var.attrs.get(key) == value, (kind, name, key)
                checked += 1
        assert checked >= 10, kind
    assert (
        kinds["separation"]["natural_period"].attrs["long_name"] == "natural period (contacts open)"
    )
