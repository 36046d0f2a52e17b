"""Sphinx configuration of the pounding documentation (``make docs``)."""

project = "pounding"
author = "the pounding developers"
extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.napoleon",  # numpydoc-style sections
    "sphinx.ext.mathjax",
    "myst_parser",  # the README, the design and the case-file reference are Markdown
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build"]
autodoc_member_order = "bysource"
autodoc_typehints = "description"
napoleon_numpy_docstring = True
napoleon_google_docstring = False
myst_heading_anchors = 3
html_theme = "alabaster"
html_static_path: list[str] = []
# a module docstring lists every reference of its functions, not all cited in its own text
suppress_warnings = ["myst.header", "ref.footnote", "ref.citation"]


import re  # noqa: E402

_TARGET = re.compile(r"^(\s*\.\. )\[(\d+)\]")


def _unique_citations(app, what, name, obj, options, lines):
    """Number a docstring's own references per object: on a module's page, every function that
    lists its ``.. [1]`` would otherwise define the same target."""
    own = {m.group(2) for line in lines if (m := _TARGET.match(line))}
    if not own or what == "module":  # a module's references are the ones its functions cite
        return
    tag = name.rsplit(".", 1)[-1].strip("_")
    for i, line in enumerate(lines):
        line = re.sub(
            r"\[(\d+)\]_",
            lambda m: f"[{tag}-{m.group(1)}]_" if m.group(1) in own else m.group(0),
            line,
        )
        lines[i] = _TARGET.sub(lambda m: f"{m.group(1)}[{tag}-{m.group(2)}]", line)


def setup(app):
    app.connect("autodoc-process-docstring", _unique_citations)
