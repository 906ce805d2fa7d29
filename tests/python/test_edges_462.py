"""The edges of BehaviorTree.CPP 4.6.2 (docs/btcpp-4.6.2-edges.md), in both engines.

Every mission of tests/conformance/edges-4.6.2/ was run on the real 4.6.2: a `.trace`
is what it printed, which the interpreter and the compiled executor must print byte for
byte; a `.refused` is the library's refusal (at load, or a throw while ticking), for
which both engines must report an error and no complete trace.
"""

import difflib
import os

import pytest

from btgen.diagnostics import UserError
from btgen.frontend.loader import load_mission
from btgen.interp.engine import trace_text
from btgen.interp.scenario import load_scenario
from conftest import ROOT, case_stems

EDGES = os.path.join(ROOT, "tests", "conformance", "edges-4.6.2")
TRACED = case_stems(EDGES, ".trace")
REFUSED = case_stems(EDGES, ".refused")


def _path(stem, ext):
    return os.path.join(EDGES, stem + ext)


def _read(stem, ext):
    with open(_path(stem, ext), encoding="utf-8") as f:
        return f.read()


def _diff(expected, got, what):
    return "".join(difflib.unified_diff(expected.splitlines(True), got.splitlines(True), "4.6.2", what, n=2))


def test_every_case_is_recorded_and_indexed():
    stems = case_stems(EDGES)
    assert len(stems) >= 30
    assert sorted(TRACED + REFUSED) == stems  # each mission has exactly one recording
    index = _read("INDEX", ".md")
    assert all(f"`{s}`" in index for s in stems)


@pytest.mark.parametrize("stem", TRACED)
def test_interpreter_matches_462(stem):
    mission = load_mission(_path(stem, ".xml"))
    scenario, _ = load_scenario(_path(stem, ".scenario"), mission)
    got = trace_text(mission, scenario)
    expected = _read(stem, ".trace")
    assert got == expected, _diff(expected, got, "interpreter")


@pytest.mark.parametrize("stem", REFUSED)
def test_interpreter_reports_what_462_refuses(stem):
    with pytest.raises(UserError):
        mission = load_mission(_path(stem, ".xml"))
        scenario, _ = load_scenario(_path(stem, ".scenario"), mission)
        trace_text(mission, scenario)


# Random missions of fuzzgen's `edges` set, recorded on 4.6.2 by scripts/record_random_edges.py
# (those it runs without a timed node); the compiled executor is held to the interpreter on the
# same generator by test_diff_random.py.
RANDOM = os.path.join(EDGES, "random")
RANDOM_STEMS = case_stems(RANDOM, ".trace")


def test_random_sample_is_there():
    assert len(RANDOM_STEMS) >= 100


@pytest.mark.parametrize("stem", RANDOM_STEMS)
def test_interpreter_matches_462_on_random_edges(stem):
    base = os.path.join(RANDOM, stem)
    mission = load_mission(base + ".xml")
    scenario, _ = load_scenario(base + ".scenario", mission)
    with open(base + ".trace", encoding="utf-8") as f:
        expected = f.read()
    got = trace_text(mission, scenario)
    assert got == expected, _diff(expected, got, "interpreter")


# ------------------------------------------------------------------ the compiled executor
# One build per mission (about two seconds each, cached by btgen.tools.cppengine).
@pytest.fixture(scope="module")
def cpp():
    """build_cpp, with every case's executor built up front on two threads."""
    import concurrent.futures
    import contextlib

    from btgen.tools.cppengine import build_cpp

    def build(stem):
        with contextlib.suppress(UserError):  # refused at compile time: the tests say which may be
            build_cpp(_path(stem, ".xml"))

    with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
        list(pool.map(build, TRACED + REFUSED))
    return build_cpp


def _run(binary, scenario):
    import subprocess

    proc = subprocess.run([str(binary), scenario], capture_output=True, check=False, timeout=120)
    return proc.returncode, proc.stdout.decode("utf-8"), proc.stderr.decode("utf-8")


@pytest.mark.parametrize("stem", TRACED)
def test_cpp_matches_462(stem, cpp):
    rc, out, err = _run(cpp(_path(stem, ".xml")), _path(stem, ".scenario"))
    expected = _read(stem, ".trace")
    assert (rc, err) == (0, "")
    assert out == expected, _diff(expected, out, "C++ executor")


@pytest.mark.parametrize("stem", REFUSED)
def test_cpp_reports_what_462_refuses(stem, cpp):
    try:
        binary = cpp(_path(stem, ".xml"))
    except UserError:
        return  # refused at compile time
    rc, out, err = _run(binary, _path(stem, ".scenario"))
    assert rc != 0 and err.strip(), out
    # the same error as the interpreter's, at the same place
    with pytest.raises(UserError) as e:
        mission = load_mission(_path(stem, ".xml"))
        trace_text(mission, load_scenario(_path(stem, ".scenario"), mission)[0])
    assert str(e.value).splitlines()[0] in err.splitlines()


def test_what_4_6_2_reads_differently_loads_with_a_warning():
    """I1, B1, M1: loaded as 4.6.2 loads them, each with a warning saying how it is read."""
    warnings = {
        stem: [str(w) for w in load_mission(_path(stem, ".xml")).warnings]
        for stem in ("i1_repeat_3_5", "b1_key_with_blanks", "m1_subtree_undeclared_remap", "i1_loopint_1_5_2")
    }
    assert any("`3.5` is not a valid int" in w and "reads it as 3" in w for w in warnings["i1_repeat_3_5"])
    assert any("names the blackboard key ` n `" in w for w in warnings["b1_key_with_blanks"])
    assert any("declares no port `extra`" in w for w in warnings["m1_subtree_undeclared_remap"])
    assert any("`1.5` is not a valid int" in w for w in warnings["i1_loopint_1_5_2"])


# Row O1 (RunOnce then_skip from an entry): 4.10.0 runs these missions exactly as 4.6.2 (each
# recorded on the 4.10.0 harness too, byte-identical), so both engines under `--btcpp 4.10.0`
# must print the 4.6.2 trace as well.
O1 = [s for s in TRACED if s.startswith("o1_")]


@pytest.mark.parametrize("stem", O1)
def test_o1_under_4_10_0_in_both_engines(stem):
    from dataclasses import replace

    from btgen.pipeline import DEFAULTS
    from btgen.tools.cppengine import build_cpp

    expected = _read(stem, ".trace")
    mission = load_mission(_path(stem, ".xml"), btcpp="4.10.0")
    assert trace_text(mission, load_scenario(_path(stem, ".scenario"), mission)[0]) == expected
    binary = build_cpp(_path(stem, ".xml"), opts=replace(DEFAULTS, btcpp="4.10.0"))
    rc, out, err = _run(binary, _path(stem, ".scenario"))
    assert (rc, err) == (0, "")
    assert out == expected, _diff(expected, out, "C++ executor, 4.10.0")
