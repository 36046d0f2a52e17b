"""Typed checks of user input: each key of a table with its type, unit, range and meaning.

A case file is TOML, so a value may arrive with any type: ``adaptive = "false"`` (a non-empty
string, true in Python), ``n_floors = 2.7``, ``dt = true`` (``bool`` is an ``int`` in Python),
``max_iter = 1e20``. :func:`check_table` refuses each such value before anything is built, with one
line naming the key, the value and what is allowed; the same :class:`Key` lists generate the
case-file reference (:func:`reference`).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping, Sequence
from typing import Any

from pounding.errors import PoundingInputError

#: The kinds of value a key takes.
KINDS = ("number", "integer", "bool", "string", "numbers", "integers", "table", "any")


def finite_number(value: object, field: str, unit: str) -> float:
    """``value`` as a finite float, else :class:`PoundingInputError` naming ``field`` and its unit."""
    if isinstance(value, bool):
        raise PoundingInputError(f"{field} = {value!r}; allowed: a number [{unit}]")
    try:
        x = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise PoundingInputError(f"{field} = {value!r}; allowed: a number [{unit}]") from None
    if not math.isfinite(x):
        raise PoundingInputError(f"{field} = {value!r}; allowed: a finite number [{unit}]")
    return x


@dataclasses.dataclass(frozen=True)
class Key:
    """One key of an input table.

    ``kind`` is one of :data:`KINDS` (``numbers``/``integers``: a non-empty list of them); ``low``
    and ``high`` bound a number (``open_low``: strictly above ``low``); ``choices`` lists the
    allowed strings; ``unit`` is printed in brackets."""

    name: str
    kind: str
    meaning: str
    unit: str = ""
    low: float | None = None
    high: float | None = None
    open_low: bool = False
    choices: tuple[str, ...] = ()
    required: bool = False

    def allowed(self) -> str:
        """What the key takes, in words (the text of an error and of the reference)."""
        unit = f" [{self.unit}]" if self.unit else ""
        if self.kind == "bool":
            return "true or false"
        if self.kind == "string":
            if self.choices:
                return "one of " + ", ".join(repr(c) for c in self.choices)
            return "a text (no control characters)"
        if self.kind == "table":
            return "a table"
        if self.kind == "any":
            return self.meaning
        noun = {"number": "a number", "integer": "an integer"}.get(self.kind)
        if noun is None:
            noun = "a list of " + ("numbers" if self.kind == "numbers" else "integers")
        return noun + self._range() + unit

    def _range(self) -> str:
        lo = None if self.low is None else f"{'>' if self.open_low else '>='} {self.low:g}"
        hi = None if self.high is None else f"<= {self.high:g}"
        parts = [p for p in (lo, hi) if p]
        return " " + " and ".join(parts) if parts else ""

    def check(self, value: Any, where: str) -> Any:
        """``value`` if it is of this key's kind and range (numbers as float), else raise."""
        ok, out = _convert(self, value)
        if not ok and self.kind in ("numbers", "integers") and isinstance(value, (list, tuple)):
            for i, item in enumerate(value):
                if not _number(item, self, self.kind == "integers")[0]:
                    single = "a number" if self.kind == "numbers" else "an integer"
                    raise PoundingInputError(
                        f"{where}.{self.name}[{i}] = {_shown(item)}; allowed: "
                        f"{single}{self._range()}{f' [{self.unit}]' if self.unit else ''}"
                    )
        if not ok:
            raise PoundingInputError(
                f"{where}.{self.name} = {_shown(value)}; allowed: {self.allowed()}"
            )
        return out


def _shown(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def _number(value: Any, key: Key, integer: bool) -> tuple[bool, Any]:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return False, None
    if integer and not isinstance(value, int):
        return False, None
    if not math.isfinite(value):
        return False, None
    if key.low is not None and (value <= key.low if key.open_low else value < key.low):
        return False, None
    if key.high is not None and value > key.high:
        return False, None
    return True, int(value) if integer else float(value)


def _convert(key: Key, value: Any) -> tuple[bool, Any]:
    kind = key.kind
    if kind in ("number", "integer"):
        return _number(value, key, kind == "integer")
    if kind == "bool":
        return isinstance(value, bool), value
    if kind == "string":
        if not isinstance(value, str) or not value or any(ord(c) < 32 for c in value):
            return False, None
        return (not key.choices or value in key.choices), value
    if kind in ("numbers", "integers"):
        if not isinstance(value, (list, tuple)) or not value:
            return False, None
        out = [_number(v, key, kind == "integers") for v in value]
        return all(ok for ok, _ in out), [v for _, v in out]
    if kind == "table":
        return isinstance(value, Mapping), value
    return True, value


def check_table(
    table: Any, keys: Sequence[Key], where: str, *, extra: bool = False
) -> dict[str, Any]:
    """Check every key of ``table`` against ``keys``: unknown keys (unless ``extra``), missing
    required ones and wrong kinds or ranges raise :class:`PoundingInputError` naming ``where.key``.
    Returns the table with numbers as float (integers as int)."""
    if not isinstance(table, Mapping):
        raise PoundingInputError(f"{where} must be a table, got {_shown(table)}")
    spec = {k.name: k for k in keys}
    unknown = sorted(set(table) - set(spec))
    if unknown and not extra:
        raise PoundingInputError(
            f"{where}: unknown key(s) {', '.join(unknown)}; allowed: {', '.join(spec)}"
        )
    for key in keys:
        if key.required and key.name not in table:
            raise PoundingInputError(f"{where}.{key.name} is required: {key.allowed()}")
    return {
        name: spec[name].check(value, where) if name in spec else value
        for name, value in table.items()
    }


def reference(tables: Mapping[str, Sequence[Key]]) -> str:
    """The keys of each table as Markdown (one table per input table)."""
    lines = []
    for title, keys in tables.items():
        lines += [f"### `{title}`", "", "| key | takes | meaning |", "|---|---|---|"]
        for key in keys:
            req = " (required)" if key.required else ""
            lines.append(f"| `{key.name}`{req} | {key.allowed()} | {key.meaning} |")
        lines.append("")
    return "\n".join(lines)
