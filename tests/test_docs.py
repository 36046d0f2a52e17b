"""The documentation site builds without a warning: the README as the user guide, the case-file
reference, the design, and the API from every public module's docstrings (equations, references)."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def test_make_docs_builds_the_site_with_warnings_as_errors(tmp_path):
    pytest.importorskip("sphinx")
    pytest.importorskip("myst_parser")
    out = tmp_path / "html"
    res = subprocess.run(
        [sys.executable, "-m", "sphinx", "-b", "html", "-W", "--keep-going", "-q",
         str(ROOT / "docs"), str(out)],
        capture_output=True, text=True, cwd=ROOT,
    )  # fmt: skip
    assert res.returncode == 0, res.stderr[-3000:]
    for page in ("index", "guide", "case_file", "design", "api/contact.laws", "api/separation"):
        assert (out / f"{page}.html").is_file(), page
    laws = (out / "api" / "contact.laws.html").read_text()
    # the laws' equations reach the page as math and their references as citations
    assert "hunt_crossley_kernel" in laws and 'class="math' in laws
    guide = (out / "guide.html").read_text()
    text = " ".join(re.sub(r"<[^>]+>", " ", guide).split())
    assert (
        "pounding run examples/three_vs_eight_story.toml -o out.nc" in text
        and "demo_amplification.png" in guide
    )
