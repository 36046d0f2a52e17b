"""The compiled Newmark core against its sources: the law dispatch id by id against the registries,
and the cache stamp that keeps a kernel from loading machine code compiled from older callees."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest
from _laws import layer

from pounding import _numba
from pounding import friction as fr
from pounding.contact.calibrate import contact_parameters
from pounding.contact.laws import LAWS_BY_ID
from pounding.integrators._kernels import (
    contact_eval,
    friction_eval,
    friction_hysteretic_eval,
)

ROOT = Path(__file__).resolve().parents[1] / "pounding"
FRICTION_VALUES = {"mu_s": 0.12, "mu_d": 0.1, "mu_min": 0.04, "mu_max": 0.1, "a": 20.0, "mu_v": 0.01,
                   "k_v": 1e4, "v_s": 0.05}  # fmt: skip


@pytest.mark.parametrize("law", LAWS_BY_ID, ids=lambda law: law.name)
def test_compiled_contact_dispatch_calls_the_registered_kernel(law):
    p = contact_parameters(law, k=1e9, e=0.7, mass=1e5, delta_m=5e-3, **layer(law.name, 5e-3))
    for d, dd, v0, d_prev, f_prev in [(1e-3, 0.3, 0.5, 8e-4, 2e4), (2e-3, -0.2, 0.5, 2.1e-3, 9e4),
                                      (-1e-3, 0.2, 0.5, 0.0, 0.0)]:  # fmt: skip
        got = contact_eval(law.kernel_id, d, dd, v0, d_prev, f_prev, p)
        assert got == law.kernel(d, dd, v0, d_prev, f_prev, p)


@pytest.mark.parametrize("law", fr.LAWS_BY_ID, ids=lambda law: law.name)
def test_compiled_friction_dispatch_calls_the_registered_kernel(law):
    p = fr.friction_parameters(
        law,
        **{q.name: FRICTION_VALUES[q.name] for q in law.parameters if q.name in FRICTION_VALUES},
    )
    for v in (-0.3, -1e-4, 0.0, 2e-4, 0.5):
        assert friction_eval(law.kernel_id, v, 2e6, p) == law.kernel(v, 2e6, p)
        if law.hysteretic_kernel is not None:
            got = friction_hysteretic_eval(law.kernel_id, v, 2e6, 0.4, p)
            assert got == law.hysteretic_kernel(v, 2e6, 0.4, p)


def test_every_module_with_compiled_code_is_in_the_cache_stamp():
    stamped = {p.resolve() for pattern in _numba.COMPILED_SOURCES for p in ROOT.glob(pattern)}
    users = set()
    for path in ROOT.rglob("*.py"):
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and node.module == "pounding._numba":
                users.add(path.resolve())
    assert users and users <= stamped
    # the laws compiled by the dispatch are stamped too
    assert {ROOT / "contact" / "laws.py", ROOT / "friction.py"} <= stamped


def test_an_edit_to_any_compiled_source_changes_the_cache_stamp(tmp_path, monkeypatch):
    (tmp_path / "contact").mkdir()
    (tmp_path / "contact" / "laws.py").write_text("x = 1\n")
    (tmp_path / "friction.py").write_text("y = 1\n")
    monkeypatch.setattr(_numba, "_PACKAGE", tmp_path)
    monkeypatch.setattr(_numba, "_stamp", None)
    before = _numba.source_stamp()
    (tmp_path / "contact" / "laws.py").write_text("x = 22\n")  # another size
    monkeypatch.setattr(_numba, "_stamp", None)
    assert _numba.source_stamp() != before


def test_the_package_locator_stamps_the_kernels_and_only_them():
    from numba.core import caching

    from pounding.integrators._kernels import _integrate as newmark_run

    impl = getattr(caching, "CacheImpl", None) or caching._CacheImpl
    ours = [c for c in impl._locator_classes if c.__name__.startswith("Package")]
    assert ours, "the package's cache locators are not installed"
    loc = ours[1].from_function(newmark_run.py_func, newmark_run.py_func.__code__.co_filename)
    assert loc is not None and loc.get_source_stamp() == _numba.source_stamp()
    assert ours[1].from_function(ast.parse, ast.__file__) is None


def _block_then_twice(x):
    y = 0.0
    for i in range(3):
        if x > i:
            y += x
    return y


def test_the_inliner_memo_copies_a_scope_once_per_function_ir():
    import copy

    from numba.core.compiler import run_frontend

    blocks = run_frontend(_block_then_twice).blocks
    assert len(blocks) > 3
    scope = next(iter(blocks.values())).scope
    # numba's own copies: one scope per block
    plain = [copy.deepcopy(b) for b in blocks.values()]
    assert len({id(b.scope) for b in plain}) == len(blocks)
    # one memo per scope: the blocks share one new scope, with the same variables
    one = _numba._OneMemoCopy()
    shared = [one.deepcopy(b) for b in blocks.values()]
    assert len({id(b.scope) for b in shared}) == 1 and shared[0].scope is not scope
    assert set(shared[0].scope.localvars._con) == set(scope.localvars._con)
    for old, new in zip(blocks.values(), shared, strict=True):
        assert new is not old and [str(s) for s in new.body] == [str(s) for s in old.body]
        assert all(a is not b for a, b in zip(old.body, new.body, strict=True))
    # the blocks of those copies (another scope) get a memo of their own
    again = [one.deepcopy(b) for b in shared]
    assert again[0].scope is not shared[0].scope
    assert len({id(b.scope) for b in again}) == 1


def test_the_inliner_memo_acts_on_this_package_s_functions_only(monkeypatch):
    import sys
    import types

    import numba

    made = []

    class Counted(_numba._OneMemoCopy):
        def __init__(self):
            super().__init__()
            made.append(self)

    monkeypatch.setattr(_numba, "_OneMemoCopy", Counted)
    _numba._inline_with_one_memo()
    source = (
        "def twice(x):\n    return 2.0 * x if x > 0 else -x\n\n"
        "def caller(x):\n    return twice(x) + twice(-x)\n"
    )
    for name, used in (("not_pounding_probe", False), ("pounding._inline_probe", True)):
        module = types.ModuleType(name)
        monkeypatch.setitem(sys.modules, name, module)
        exec(compile(source, f"<{name}>", "exec"), module.__dict__)
        module.twice = numba.njit(inline="always")(module.twice)
        caller = numba.njit(module.caller)
        made.clear()
        assert caller(1.5) == 4.5 and caller(-2.0) == 6.0
        assert bool(made) == used, name


EXAMPLES = ROOT.parent / "examples"


def _simulated(name, monkeypatch, lean, **options):
    import pounding
    from pounding.integrators import newmark

    monkeypatch.setattr(newmark, "LEAN_CORE", lean)
    case = pounding.load_case(EXAMPLES / name)
    return pounding.simulate(case, **options)


@pytest.mark.parametrize(
    ("name", "options"),
    [("three_vs_eight_story.toml", {}), ("two_sdof.toml", {"method": "hht", "duration": 3.0})],
)
def test_gaps_alone_take_the_core_compiled_without_families_with_the_whole_core_s_results(
    name, options, monkeypatch
):
    # the core of gaps alone is the whole core with its friction and family code dropped: the
    # same arithmetic step by step, so the same bits
    from pounding.integrators._kernels import _integrate
    from pounding.warmup import _core_of

    lean = _simulated(name, monkeypatch, True, **options)
    whole = _simulated(name, monkeypatch, False, **options)
    assert {_core_of(sig) for sig in _integrate.signatures} == {"gaps", "families"}
    assert int(lean["impact_count"].sum()) > 0
    for var in ("displacement", "contact_force", "energy", "peak_contact_force"):
        assert var in lean and lean[var].equals(whole[var]), var
    assert lean["impact_start"].size > 0 and lean["impact_start"].equals(whole["impact_start"])


@pytest.mark.parametrize(
    ("name", "core"),
    [("two_sdof.toml", "gaps"), ("bumper.toml", "gaps"), ("floor_to_column.toml", "gaps"),
     ("three_vs_eight_yielding.toml", "families"), ("base_isolated_moat.toml", "families")],
)  # fmt: skip
def test_compiled_core_is_the_lean_one_for_gaps_alone(name, core):
    import pounding
    from pounding.integrators.base import compiled_core

    system = pounding.load_case(EXAMPLES / name).system
    assert compiled_core(system) == core
    assert compiled_core(system, lean=False) == "families"


def test_is_warm_reads_each_core_from_the_cache_index(monkeypatch):
    from numba.core import types

    import pounding.warmup as w

    gaps_sig = (types.int64,) * 3 + (types.none,)
    whole_sig = (types.int64,) * 4

    class Index:
        def __init__(self, keys):
            self.keys = keys

        def _load_index(self):
            return {(sig, "magic", ("a", "b")): "file" for sig in self.keys}

    class Dispatcher:
        signatures = []

        def __init__(self, keys):
            self._cache = type("Cache", (), {"_cache_file": Index(keys)})()

    for keys, warm in (([gaps_sig], {"gaps"}), ([whole_sig], {"families"}), ([], set()),
                       ([gaps_sig, whole_sig], {"gaps", "families"})):  # fmt: skip
        monkeypatch.setattr(w, "_dispatcher", lambda keys=keys: Dispatcher(keys))
        assert {core for core in ("gaps", "families") if w.is_warm(core)} == warm
    assert "about 60 s" in w.notice("gaps") and "about 130 s" in w.notice("families")


def test_a_study_compiles_the_cores_its_runs_need(tmp_path):
    from pounding.studies import load_study, plan_study
    from pounding.studies.plan import study_cores

    # the demo study's 3-story building: elastic stories (gaps alone) or Takeda stories
    demo = load_study(EXAMPLES / "demo_study.toml")
    plan = plan_study(demo, tmp_path / "demo.runs")
    assert {task["core"] for task in plan.tasks.values()} == {"gaps", "families"}
    assert study_cores(demo) == {"gaps", "families"}
    assert study_cores(load_study(EXAMPLES / "ida_hunt.toml")) == {"families"}
    assert study_cores(load_study(EXAMPLES / "bumper_study.toml")) == {"gaps"}


@pytest.mark.parametrize(
    ("name", "lean"), [("three_vs_eight_yielding.toml", False), ("two_sdof.toml", True)]
)
def test_the_baseline_and_free_impact_check_run_on_the_analysis_s_core(name, lean, monkeypatch):
    # the check's free impact is a system of gaps alone: on the core of an analysis with yielding
    # stories it must not compile the other one (an unannounced compile of ~60 s)
    import pounding
    from pounding.integrators import _kernels as kn

    seen = []
    real = kn.newmark_run

    def spy(sy, sch, gaps, fr, el, *rest):
        seen.append(fr is None and el is None)
        return real(sy, sch, gaps, fr, el, *rest)

    monkeypatch.setattr(kn, "newmark_run", spy)
    pounding.simulate(pounding.load_case(EXAMPLES / name), baseline=True)
    assert len(seen) == 3 and set(seen) == {lean}  # the analysis, its baseline, one free impact
