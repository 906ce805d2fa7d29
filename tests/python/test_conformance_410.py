"""The reference interpreter under `--btcpp 4.10.0` reproduces every case recorded on the real
BehaviorTree.CPP 4.10.0 (tests/conformance/btcpp-4.10.0), byte for byte.

A stem without a `.trace` is one the library refuses: INDEX.md lists when ("load", or
"run, tick N"); the interpreter must stop with an error there too: at load (before the
first tick), or during tick N after printing that tick's lines so far.
"""

import difflib
import os
import re

import pytest

from btgen.diagnostics import UserError
from btgen.frontend.loader import load_mission
from btgen.interp.engine import run_trace
from btgen.interp.scenario import load_scenario
from conftest import ROOT, case_stems

CASES_410 = os.path.join(ROOT, "tests", "conformance", "btcpp-4.10.0")
STEMS = case_stems(CASES_410)


def _rejections() -> dict[str, str]:
    with open(os.path.join(CASES_410, "INDEX.md"), encoding="utf-8") as f:
        index = f.read()
    return dict(re.findall(r"^\| `(\w+)` \| (load|run, tick \d+) \|", index, re.M))


REJECTED = _rejections()


def _case(stem, ext):
    return os.path.join(CASES_410, stem + ext)


def run_case(stem, version="4.10.0"):
    """(trace so far, None) or (trace so far, (when, message)): when is "load" or "run, tick N"."""
    parts: list[str] = []
    try:
        mission = load_mission(_case(stem, ".xml"), btcpp=version)
        scenario, warnings = load_scenario(_case(stem, ".scenario"), mission)
        assert [str(w) for w in warnings] == []
        run_trace(mission, scenario, parts.append)
    except UserError as e:
        text = "".join(parts)
        ticks = text.count("tick ")
        return text, (f"run, tick {ticks}" if ticks else "load", str(e))
    return "".join(parts), None


def test_every_case_is_either_recorded_or_rejected():
    assert len(STEMS) >= 100
    for stem in STEMS:
        assert os.path.exists(_case(stem, ".trace")) != (stem in REJECTED), stem


@pytest.mark.parametrize("stem", [s for s in STEMS if s not in REJECTED])
def test_trace_matches_the_410_recording(stem):
    got, error = run_case(stem)
    assert error is None, error
    with open(_case(stem, ".trace"), encoding="utf-8") as f:
        expected = f.read()
    assert got == expected, "".join(
        difflib.unified_diff(expected.splitlines(True), got.splitlines(True), "BehaviorTree.CPP 4.10.0", "btgen")
    )


@pytest.mark.parametrize("stem", sorted(REJECTED))
def test_rejected_where_the_410_library_rejects(stem):
    _, error = run_case(stem)
    assert error is not None, f"{stem}: ran to the end; 4.10.0 refuses it ({REJECTED[stem]})"
    assert error[0] == REJECTED[stem], error


# The cases that show a difference give the 4.6.2 behaviour under the default version: the
# switch, not the case, decides (each of these traces differs from 4.10.0's).
DIFFERENT_ON_462 = [
    "set_blackboard_always",
    "v410_r1_while_sequence",
    "v410_r1_while_fallback",
    "v410_r2_repeat_zero",
    "v410_r3_retry_lowered_on_failure",
    "v410_r4_if_turns_false",
    "v410_r7_script_string_queue_reentered",
    "v410_r10_switch_prefix_string",
    "v410_s1_or_and_precedence",
    "v410_s3_true_is_double",
]


@pytest.mark.parametrize("stem", DIFFERENT_ON_462)
def test_the_default_version_keeps_462_behaviour(stem):
    got, error = run_case(stem, "4.6.2")
    with open(_case(stem, ".trace"), encoding="utf-8") as f:
        expected = f.read()
    assert error is not None or got != expected


LOADS_ON_462_ONLY = [
    "v410_s9_double_quoted_string",
    "v410_s9_unary_plus",
    "v410_x1_tree_id_with_space",
    "v410_x2_same_name_siblings",
    "v410_x5_generic_child_tags",
    "v410_x5_two_async_sequences",
]


@pytest.mark.parametrize("stem", LOADS_ON_462_ONLY)
def test_what_410_refuses_at_load_462_loads(stem):
    mission = load_mission(_case(stem, ".xml"))
    assert mission.btcpp == "4.6.2"


def test_462_warns_about_what_484_refuses():
    mission = load_mission(_case("v410_x2_same_name_siblings", ".xml"))
    assert any("refused from BehaviorTree.CPP 4.8.4" in str(w) for w in mission.warnings)
    mission = load_mission(_case("v410_x1_tree_id_with_space", ".xml"))
    assert any(
        "refused from BehaviorTree.CPP 4.8.4: BehaviorTree ID `Go There` contains the forbidden character ` `: "
        "rename it `Go_There`" in str(w)
        for w in mission.warnings
    )
