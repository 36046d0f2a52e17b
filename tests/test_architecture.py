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
