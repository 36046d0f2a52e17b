"""The errors a user can cause, under one base class.

Everything raised because of the input (a case file, a record, a study, an option) or because an
analysis cannot be carried out with the chosen settings derives from :class:`PoundingError`. The
command line turns these into one line on stderr and exit code 2; any other exception is a bug in
``pounding`` and keeps its traceback.

:class:`PoundingInputError` also derives from ``ValueError`` (and :class:`ConvergenceError` from
``RuntimeError``), so code that caught those before keeps working.
"""

from __future__ import annotations

__all__ = [
    "PoundingError",
    "PoundingInputError",
    "ConvergenceError",
    "IntegrationError",
    "ResultWriteError",
]


class PoundingError(Exception):
    """Base of every error caused by the input or the analysis settings; its message is one line
    that names the field, the value and what is allowed (or what to try)."""


class PoundingInputError(PoundingError, ValueError):
    """Bad input: the message names the field, the value and the allowed values."""


class ConvergenceError(PoundingError, RuntimeError):
    """Newton–Raphson did not converge even after the allowed step subdivisions."""


class IntegrationError(PoundingError, RuntimeError):
    """The ``solve_ivp`` path could not advance (solver failure or events that make no progress)."""


class ResultWriteError(PoundingError, OSError):
    """A result file could not be written (disk full, permissions, a name HDF5 refuses); the
    previous file at that path, if any, is untouched."""
