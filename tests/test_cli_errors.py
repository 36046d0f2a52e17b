"""What a user sees when something goes wrong: one line and exit 2 for their errors, a traceback and a
request to report it for ours; help that keeps its units; quiet ends on a closed pipe."""

from __future__ import annotations

import importlib
import os
import re
import subprocess
import sys
from pathlib import Path

import click
import pytest
import typer
from typer.testing import CliRunner

from pounding._version import __version__
from pounding.cli import app
from pounding.errors import ConvergenceError, PoundingError, PoundingInputError

ROOT = Path(__file__).resolve().parents[1]
TWO_SDOF = ROOT / "examples" / "two_sdof.toml"
runner = CliRunner()
# the module, not the function the package exports under the same name
_SIMULATE = importlib.import_module("pounding.simulate")
_CLI = "import sys; from pounding.cli import main; sys.argv[0] = 'pounding'; main()"


def _no_convergence_case(tmp_path: Path) -> Path:
    """The first-hour reproducer: one Newton iteration, no halving, no onset location, a 10 ms step."""
    text = TWO_SDOF.read_text().replace(
        "[analysis]\n",
        "[analysis]\ndt = 0.01\nmax_iter = 1\nmax_halvings = 0\nlocate_onset = false\n"
        "adaptive = false\n",
    )
    path = tmp_path / "no_convergence.toml"
    path.write_text(text)
    return path


def test_error_classes_share_one_base_and_keep_the_builtin_ones():
    from pounding.case import CaseError
    from pounding.records import RecordFormatError, SuiteUnavailableError
    from pounding.studies import StudyError

    for cls in (CaseError, StudyError, RecordFormatError, SuiteUnavailableError):
        assert issubclass(cls, PoundingInputError) and issubclass(cls, ValueError)
    assert issubclass(ConvergenceError, PoundingError) and issubclass(
        ConvergenceError, RuntimeError
    )


def test_run_that_does_not_converge_is_one_line_naming_time_contact_and_remedy(tmp_path):
    out = tmp_path / "out.nc"
    res = runner.invoke(app, ["run", str(_no_convergence_case(tmp_path)), "-o", str(out)])
    assert res.exit_code == 2
    lines = res.output.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: Newton-Raphson did not converge at t =")
    assert "contact 0 (A:1-B:1, hunt_crossley)" in lines[0]
    assert "max_halvings" in lines[0] and "Traceback" not in res.output
    assert not out.exists()


def test_a_bug_shows_its_traceback_and_asks_to_report_it(tmp_path, monkeypatch):
    def broken(*args, **kwargs):
        raise TypeError("an internal mistake")

    monkeypatch.setattr(_SIMULATE, "simulate_variables", broken)  # what `run` calls
    res = runner.invoke(app, ["run", str(TWO_SDOF)])
    assert res.exit_code == 1
    assert "Traceback" in res.output and "TypeError: an internal mistake" in res.output
    assert f"this is a bug in pounding {__version__}" in res.output


def test_a_key_error_from_a_bug_is_not_taken_for_a_user_error(monkeypatch):
    def broken(*args, **kwargs):
        return {}["missing"]

    monkeypatch.setattr(_SIMULATE, "simulate_variables", broken)  # what `run` calls
    res = runner.invoke(app, ["run", str(TWO_SDOF)])
    assert res.exit_code == 1 and "KeyError" in res.output


def test_report_of_a_case_file_says_what_report_takes(tmp_path):
    res = runner.invoke(app, ["report", str(TWO_SDOF), "-o", str(tmp_path / "r")])
    assert res.exit_code == 2
    assert "is not a pounding result" in res.output
    assert "pounding run -o" in res.output and "signature" not in res.output


@pytest.mark.parametrize(
    ("example", "command"),
    [("demo_study.toml", "pounding study FILE"), ("ida_fragility.toml", "pounding ida FILE")],
)
def test_run_of_a_study_or_ida_file_names_the_command_that_runs_it(tmp_path, example, command):
    # it said "top level: unknown key(s) ida" of a key `pounding ida` reads
    res = runner.invoke(
        app, ["run", str(ROOT / "examples" / example), "-o", str(tmp_path / "o.nc")]
    )
    assert res.exit_code == 2
    assert command in res.output and "unknown key" not in res.output
    assert len(res.output.strip().splitlines()) == 1


def test_ida_of_a_study_that_is_not_one_is_refused_before_any_run(tmp_path):
    # it ran the demo study's 100 runs, then said "not an IDA"
    out = tmp_path / "x.nc"
    res = runner.invoke(app, ["ida", str(ROOT / "examples" / "demo_study.toml"), "-o", str(out)])
    assert res.exit_code == 2
    assert "not an IDA" in res.output and "runs" not in res.output
    assert not out.exists() and not list(tmp_path.iterdir())


def test_broken_pipe_ends_quietly():
    # `pounding laws | head -1`: the reader closes the pipe after one line
    proc = subprocess.run(
        f'{sys.executable} -c "{_CLI}" laws | head -1',
        shell=True,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.stdout.startswith("contact laws")
    assert proc.stderr == ""


def test_version_and_short_help():
    res = runner.invoke(app, ["--version"])
    assert res.exit_code == 0 and res.output.strip() == f"pounding {__version__}"
    res = runner.invoke(app, ["-h"])
    assert res.exit_code == 0 and "run" in res.output and "--version" in res.output
    assert runner.invoke(app, ["run", "-h"]).exit_code == 0


def _commands(cmd: click.Command, path: tuple[str, ...] = ()):
    yield path, cmd
    for name, sub in getattr(cmd, "commands", {}).items():
        yield from _commands(sub, (*path, name))


_BRACKETED = re.compile(r"\[[^\]\s]+\]")


@pytest.mark.parametrize(
    "path",
    [p for p, _ in _commands(typer.main.get_command(app))],
    ids=lambda p: " ".join(p) or "pounding",
)
def test_every_help_shows_its_units_and_table_names(path):
    """Units such as [s], [m], [kg], [g] and table names such as [analysis] survive the help
    rendering (rich markup used to take them for tags and drop them)."""
    cmd = dict(_commands(typer.main.get_command(app)))[path]
    texts = [cmd.help or ""] + [getattr(p, "help", None) or "" for p in cmd.params]
    expected = {m for t in texts for m in _BRACKETED.findall(t)}
    if not expected:
        pytest.skip(f"{' '.join(path) or 'pounding'} has no bracketed unit or table name")
    res = runner.invoke(app, [*path, "--help"], terminal_width=200)
    assert res.exit_code == 0, res.output
    shown = " ".join(res.output.split())
    missing = sorted(tok for tok in expected if tok not in shown)
    assert not missing, f"{' '.join(path)} --help lost {missing}"


def test_help_shows_the_units_the_first_hour_report_found_missing():
    out = " ".join(runner.invoke(app, ["run", "--help"], terminal_width=200).output.split())
    assert "Override the integration step [s]" in out
    out = " ".join(runner.invoke(app, ["separation", "--help"], terminal_width=200).output.split())
    assert "ASCE 7 S_DS [g]" in out


def test_run_that_cannot_write_its_result_keeps_the_old_file_and_says_why(tmp_path, monkeypatch):
    out = tmp_path / "out.nc"
    assert runner.invoke(app, ["run", str(TWO_SDOF), "-o", str(out)]).exit_code == 0
    before = out.read_bytes()
    # a full disk: the flush of the new file fails after it was written
    import pounding._netcdf

    def full(fd):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(pounding._netcdf.os, "fsync", full)
    res = runner.invoke(app, ["run", str(TWO_SDOF), "-o", str(out)])
    assert res.exit_code == 2
    line = res.output.strip().splitlines()[-1]
    assert line.startswith("error: ") and "the previous file there is untouched" in line
    assert "No space left on device" in line
    assert out.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.nc"]


@pytest.mark.parametrize(
    "args",
    [
        ["run", "examples/two_sdof.toml", "--dt", "nan"],
        ["separation", "examples/base_isolated_moat.toml", "--dt", "nan"],
    ],
)
def test_a_bad_override_is_refused_before_a_cold_cache_compiles(tmp_path, args):
    # with an empty kernel cache, `pounding run case --dt nan` compiled for 2 minutes before
    # it named the bad value
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)}
    proc = subprocess.run(
        [sys.executable, "-c", _CLI, *args], cwd=ROOT, env=env, capture_output=True, text=True,
        timeout=60,
    )  # fmt: skip
    assert proc.returncode == 2
    assert proc.stderr + proc.stdout == (
        "error: analysis.dt = nan; allowed: a number >= 1e-06 and <= 1 [s]\n"
    )


def test_a_name_with_a_control_character_is_refused_before_the_run(tmp_path):
    # A NUL in a building name reached the HDF5 writer (which refuses it) after the whole run.
    out = tmp_path / "out.nc"
    bad = tmp_path / "nul.toml"
    bad.write_text(
        TWO_SDOF.read_text()
        .replace('name = "A"', 'name = "A\\u0000x"')
        .replace('left = "A"', 'left = "A\\u0000x"')
    )
    res = runner.invoke(app, ["run", str(bad), "-o", str(out)])
    assert res.exit_code == 2
    lines = res.output.strip().splitlines()
    assert len(lines) == 1 and "building[0].name" in lines[0] and "control characters" in lines[0]
    assert not out.exists()
