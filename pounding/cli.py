"""Command-line interface: the only module that parses argv, prints or exits.

Every error a user can cause (bad case file, unknown law, malformed record) is turned into one line on
stderr and exit code 2, never a traceback.
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from functools import wraps
from typing import Any

import typer

app = typer.Typer(
    help="Seismic pounding analysis of adjacent buildings.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)


class UserError(Exception):
    """An error caused by the user's input; reported as one line, exit code 2."""


def _fail(message: str) -> None:
    typer.echo(f"error: {message}", err=True)
    raise typer.Exit(code=2)


def user_errors(func: Callable[..., Any]) -> Callable[..., Any]:
    """Turn input errors raised by the library into one line on stderr and exit code 2."""

    @wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        try:
            return func(*args, **kwargs)
        except (ValueError, KeyError, FileNotFoundError, IsADirectoryError, UserError) as exc:
            msg = exc.args[0] if isinstance(exc, KeyError) and exc.args else exc
            _fail(str(msg))
        except OSError as exc:
            _fail(f"{exc.filename or ''}: {exc.strerror or exc}".strip(": "))

    return wrapper


# --- analysis verbs ---


def _fmt_si(value: float, unit: str) -> str:
    return f"{value:.4g} {unit}"


def _print_summary(ds: Any, path: str | None) -> None:
    from pounding.results import PoundingAccessor  # noqa: F401  (registers ds.pounding)

    s = ds.pounding.summary()
    title = ds.attrs.get("title") or "analysis"
    typer.echo(f"{title}")
    typer.echo(
        f"  record {ds.attrs.get('record')}, method {ds.attrs.get('method')}, "
        f"dt {ds.attrs.get('dt'):.3g} s, output dt {ds.attrs.get('output_dt'):.3g} s, "
        f"duration {ds.attrs.get('duration'):.4g} s"
    )
    typer.echo("  building      T1 [s]   peak disp [m]   peak drift ratio   peak abs acc [m/s^2]")
    for name, b in s["buildings"].items():
        typer.echo(
            f"  {name:<12s} {b['T1']:7.3f}   {b['peak_displacement']:13.4g}   "
            f"{b['peak_drift_ratio']:16.4g}   {b['peak_absolute_acceleration']:20.4g}"
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
    typer.echo(
        f"  energy balance error {100 * s['energy_balance_error']:.3g} % of the input energy"
    )
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
) -> None:
    """Run one analysis: print a summary (periods, peaks, impacts, energy balance) and write the Dataset."""
    from pounding.case import load_case
    from pounding.results import save
    from pounding.simulate import simulate

    loaded = load_case(case)
    overrides = {
        k: v
        for k, v in {"method": method, "dt": dt, "output_dt": output_dt}.items()
        if v is not None
    }
    ds = simulate(loaded, **overrides)
    if output:
        save(ds, output)
    _print_summary(ds, output)


laws_app = typer.Typer(
    help="Contact laws: list them, or measure one law's single-impact response.",
    invoke_without_command=True,
    no_args_is_help=False,
)
app.add_typer(laws_app, name="laws")


@laws_app.callback()
def laws(ctx: typer.Context) -> None:
    """List the contact laws with their force law and reference."""
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
    as_json: bool = typer.Option(False, "--json", help="Emit JSON instead of text."),
) -> None:
    """Simulate one free impact against a rigid wall: effective e, max penetration, peak force, duration."""
    import json

    from pounding.contact.calibrate import effective_restitution

    r = effective_restitution(
        law, k=k, mass=mass, v0=v0, e=e, n=n, a=a, delta_m=delta_m, calibration=calibration
    )
    if as_json:
        typer.echo(json.dumps(r.as_dict()))
        return
    typer.echo(
        f"law {law}, k {k:.4g} N/m^n, mass {mass:.4g} kg, v0 {v0:.4g} m/s, calibration {calibration}"
    )
    typer.echo(f"  effective restitution  {r.e_effective:.4f}")
    typer.echo(f"  max penetration        {r.max_penetration:.4g} m")
    typer.echo(f"  peak force             {r.peak_force:.4g} N")
    typer.echo(f"  contact duration       {r.contact_duration:.4g} s")


# --- records verbs (ground motions) --- owned by the ground-motion work; keep inside these markers
# --- end records verbs ---


def main() -> None:
    """Console-script entry point."""
    try:
        app()
    except KeyboardInterrupt:
        typer.echo("interrupted", err=True)
        sys.exit(130)
