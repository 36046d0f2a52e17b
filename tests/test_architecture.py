"""The layering of docs/design.md, enforced by the import-linter contract in pyproject.toml."""

from __future__ import annotations

import ast
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_import_linter_contract_holds():
    exe = shutil.which("lint-imports", path=str(Path(sys.executable).parent)) or shutil.which(
        "lint-imports"
    )
    assert exe, "import-linter is part of the test extra"
    res = subprocess.run([exe], cwd=ROOT, capture_output=True, text=True)
    assert res.returncode == 0, res.stdout + res.stderr
    assert "KEPT" in res.stdout
    # the layers, the physics' forbidden imports and the report package's own layering
    assert res.stdout.count(" KEPT") >= 3, res.stdout
    assert "physics is plain numpy" in res.stdout


def _imports(path: Path) -> set[str]:
    names = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            names.update(alias.name.split(".")[0] for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module:
            names.add(node.module.split(".")[0])
    return names


def test_numba_is_imported_only_by_the_numba_module():
    users = {p.name for p in (ROOT / "pounding").rglob("*.py") if "numba" in _imports(p)}
    assert users == {"_numba.py"}


def test_every_public_name_resolves():
    import pounding

    missing = [name for name in pounding.__all__ if getattr(pounding, name, None) is None]
    assert missing == []


# The functions allowed past the limits, each with its reason (docs/design.md, "Layout").
_LONG_OR_WIDE = {
    # typer: one parameter per CLI flag of `pounding separation`
    ("cli.py", "separation"),
    # called by solve_ivp at every stage: numba dispatches a namedtuple argument through its slow
    # path (2.27 µs a call for one group of 10 arrays against 1.03 µs flat)
    ("ivp.py", "_rhs_kernel"),
    # one compiled kernel: its helpers are closures, as the physics layer does not import numba
    # and numba cannot call a plain module function
    ("stories.py", "imk_story_kernel"),
}


def test_no_function_takes_more_than_15_parameters_or_a_body_over_150_lines():
    found = set()
    for path in (ROOT / "pounding").rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            if not isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                continue
            a = node.args
            n_args = len(a.posonlyargs) + len(a.args) + len(a.kwonlyargs)
            n_args += (a.vararg is not None) + (a.kwarg is not None)
            body = node.body
            if isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
                body = body[1:]  # the docstring
            lines = body[-1].end_lineno - body[0].lineno + 1 if body else 0
            if n_args > 15 or lines > 150:
                found.add((path.name, node.name))
    assert found == _LONG_OR_WIDE
