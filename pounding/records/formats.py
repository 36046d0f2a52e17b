"""The record formats registry: detection, :func:`read_record` and :func:`write_record`."""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from pathlib import Path
from typing import Any

from pounding.errors import PoundingInputError
from pounding.ground_motion import GroundMotion
from pounding.records.common import RecordFormatError, _read_lines
from pounding.records.cosmos import _sniff_cosmos, read_cosmos
from pounding.records.knet import _sniff_knet, read_knet
from pounding.records.peer import _sniff_peer, read_peer, write_peer
from pounding.records.text import _sniff_text, read_text, write_text


@dataclasses.dataclass(frozen=True)
class RecordFormat:
    """A record file format: how to recognise, read and (optionally) write it."""

    name: str
    description: str
    extensions: tuple[str, ...]
    reader: Callable[..., GroundMotion]
    sniff: Callable[[list[str]], bool]
    writer: Callable[..., None] | None = None


#: Record formats by name. Detection tries the specific header signatures first.
RECORD_FORMATS: dict[str, RecordFormat] = {
    "peer": RecordFormat(
        "peer",
        "PEER NGA .AT2/.VT2/.DT2 (both header styles)",
        (".at2", ".vt2", ".dt2"),
        read_peer,
        _sniff_peer,
        write_peer,
    ),
    "cosmos": RecordFormat(
        "cosmos", "COSMOS V2 single channel", (".v2c", ".v2"), read_cosmos, _sniff_cosmos
    ),
    "knet": RecordFormat(
        "knet",
        "K-NET / KiK-net ASCII",
        (".ns", ".ew", ".ud", ".ns1", ".ew1", ".ud1", ".ns2", ".ew2", ".ud2"),
        read_knet,
        _sniff_knet,
    ),
    "text": RecordFormat(
        "text",
        "plain text, one column (dt given) or two (time, acceleration)",
        (".txt", ".csv", ".dat", ".acc", ".tsv"),
        read_text,
        _sniff_text,
        write_text,
    ),
}


def _format(name: str) -> RecordFormat:
    try:
        return RECORD_FORMATS[name]
    except KeyError:
        allowed = ", ".join(RECORD_FORMATS)
        raise PoundingInputError(f"unknown record format {name!r}; allowed: {allowed}") from None


def detect_format(path: str | Path, lines: list[str] | None = None) -> str:
    """Name of the format of ``path``: a header signature first, then the extension, else text."""
    path = Path(path)
    if lines is None:
        lines = _read_lines(path)
    head = lines[:20]
    for fmt in RECORD_FORMATS.values():
        if fmt.name != "text" and fmt.sniff(head):
            return fmt.name
    suffix = path.suffix.lower()
    for fmt in RECORD_FORMATS.values():
        if suffix in fmt.extensions:
            return fmt.name
    return "text"


#: Largest record file read [bytes]: an hour at 200 Hz in text is under 3 MiB.
MAX_RECORD_BYTES = 64 * 2**20


def read_record(
    path: str | Path,
    *,
    format: str | None = None,
    units: str | None = None,
    dt: float | None = None,
) -> GroundMotion:
    """Read a ground-motion record file into a :class:`GroundMotion` (SI units).

    Parameters
    ----------
    path : str or Path
        The file.
    format : str, optional
        A key of :data:`RECORD_FORMATS`; detected from the header and extension when omitted.
    units : str, optional
        Unit of the values in the file (``g``, ``m/s2``, ``cm/s2``, ``gal``, ...); overrides the
        header. Required for plain text without a ``# units:`` line.
    dt : float, optional
        Time step [s]; required for one-column text without a ``# dt:`` line, otherwise checked
        against the file.

    Raises
    ------
    RecordFormatError
        The file does not follow its format (names the file, the line and what was expected).
    FileNotFoundError
    """
    path = Path(path)
    if not path.exists():
        raise FileNotFoundError(f"record file not found: {path}")
    if path.is_dir():
        raise IsADirectoryError(f"record path is a directory, not a file: {path}")
    if not path.is_file():  # a named pipe or /dev/zero would block or never end
        raise RecordFormatError(path, None, "a regular file (not a pipe, device or socket)")
    size = path.stat().st_size
    if size > MAX_RECORD_BYTES:
        raise RecordFormatError(
            path,
            None,
            f"a record file of at most {MAX_RECORD_BYTES / 2**20:.0f} MiB",
            f"{size / 2**20:.0f} MiB",
        )
    lines = _read_lines(path)
    if not any(line.strip() for line in lines):
        raise RecordFormatError(path, 1, "a record, the file is empty")
    fmt = _format(format) if format is not None else _format(detect_format(path, lines))
    gm = fmt.reader(path, lines, units=units, dt=dt)
    gm.metadata.setdefault("format", fmt.name)
    return gm


def write_record(
    gm: GroundMotion, path: str | Path, *, format: str | None = None, **options: Any
) -> None:
    """Write ``gm`` to ``path`` in ``format`` (from the extension when omitted: .at2 -> peer,
    anything else -> text). ``options`` go to the writer (e.g. ``units="cm/s2"`` for text)."""
    path = Path(path)
    if format is None:
        format = "peer" if path.suffix.lower() == ".at2" else "text"
    fmt = _format(format)
    if fmt.writer is None:
        writable = ", ".join(name for name, f in RECORD_FORMATS.items() if f.writer is not None)
        raise PoundingInputError(
            f"record format {format!r} cannot be written; writable: {writable}"
        )
    if format == "peer" and path.suffix.lower() in (".vt2", ".dt2"):
        raise PoundingInputError(f"{path}: only acceleration (.AT2) is written in the PEER format")
    # a file must read back as what was written: an extension another format claims (.VT2, .V2,
    # .NS ...) would be read by that format's reader, which refuses this content
    claimed = [f.name for f in RECORD_FORMATS.values() if path.suffix.lower() in f.extensions]
    if claimed and fmt.name not in claimed:
        raise PoundingInputError(
            f"{path}: a {fmt.name} record cannot be written under the extension {path.suffix!r} "
            f"(that of {claimed[0]} files, which would not read it back); allowed: "
            + ", ".join(fmt.extensions)
            + (" or .AT2 (PEER)" if fmt.name == "text" else "")
        )
    fmt.writer(gm, path, **options)
