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
    for page in (
        "index",
        "guide",
        "gallery",
        "case_file",
        "design",
        "api/contact.laws",
        "api/separation",
    ):
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


def test_gallery_shows_every_example_with_its_command_and_an_existing_figure():
    # docs/gallery.md is written by docs/gallery.py: a new example needs a rerun of it
    text = (ROOT / "docs" / "gallery.md").read_text()
    for example in sorted((ROOT / "examples").glob("*.toml")):
        assert f"## {example.stem}\n" in text, f"{example.name} missing: run python docs/gallery.py"
        assert f"examples/{example.name} -o" in text
    images = re.findall(r"!\[[^\]]*\]\(([^)]+)\)", text)
    assert len(images) == len(list((ROOT / "examples").glob("*.toml")))
    for image in images:
        assert (ROOT / "docs" / image).is_file(), image
