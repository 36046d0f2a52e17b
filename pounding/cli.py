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


# --- records verbs (ground motions) --- owned by the ground-motion work; keep inside these markers
# --- end records verbs ---


def main() -> None:
    """Console-script entry point."""
    try:
        app()
    except KeyboardInterrupt:
        typer.echo("interrupted", err=True)
        sys.exit(130)
