"""The reference interpreter reproduces every recorded BehaviorTree.CPP 4.6.2 trace byte for byte.

The cases live in ``<repo>/../shared/conformance/cases`` (FORMAT.md next to
them is the contract): ``<stem>.xml``, ``<stem>.scenario``, ``<stem>.trace``.
Each runs in-process for speed; one also goes through the real command line.
"""

import difflib
import os
import subprocess
import sys

import pytest

from btgen.frontend.loader import load_mission
from btgen.interp.engine import trace_text
from btgen.interp.scenario import load_scenario
from conftest import CASES, ROOT, case_stems

NO_CASES = f"conformance cases not found at {CASES} (expected <repo>/../shared/conformance/cases)"


STEMS = case_stems(CASES, ".trace")


def _case(stem, ext):
    return os.path.join(CASES, stem + ext)


def _read_trace(stem):
    with open(_case(stem, ".trace"), "rb") as f:
        return f.read().decode("utf-8")


def _diff(expected, got):
    return "".join(
        difflib.unified_diff(
            expected.splitlines(True), got.splitlines(True), "expected (BehaviorTree.CPP 4.6.2)", "interpreter", n=2
        )
    )


def test_cases_present():
    # CI always has ../shared beside the checkout: there a missing corpus is a
    # failure, not a run whose golden tests silently vanished.
    if not os.path.isdir(CASES):
        if os.environ.get("CI", "").lower() in ("1", "true", "yes"):
            pytest.fail(NO_CASES)
        pytest.skip(NO_CASES)
    assert STEMS, f"no cases with a .trace in {CASES}"


@pytest.mark.skipif(not STEMS, reason=NO_CASES)
@pytest.mark.parametrize("stem", STEMS or ["(none)"])
def test_trace_matches_recording(stem):
    mission = load_mission(_case(stem, ".xml"))
    scenario, warnings = load_scenario(_case(stem, ".scenario"), mission)
    assert [str(w) for w in warnings] == []
    got = trace_text(mission, scenario)
    expected = _read_trace(stem)
    assert got == expected, f"{stem}: trace differs from the recording\n{_diff(expected, got)}"


@pytest.mark.skipif(not STEMS, reason=NO_CASES)
def test_cli_run_reproduces_a_trace():
    """Through the installed command line: stdout is the trace, byte for byte; nothing on stderr."""
    stem = "robot_lab_tour" if "robot_lab_tour" in STEMS else STEMS[0]
    proc = subprocess.run(
        [sys.executable, "-m", "btgen", "run", _case(stem, ".xml"), "--scenario", _case(stem, ".scenario")],
        cwd=ROOT,
        capture_output=True,
        timeout=300,
        check=False,
    )
    assert proc.returncode == 0, proc.stderr.decode()
    assert proc.stderr == b""
    expected = _read_trace(stem).encode("utf-8")
    assert proc.stdout == expected, _diff(expected.decode(), proc.stdout.decode())


@pytest.mark.skipif(not STEMS, reason=NO_CASES)
def test_cli_default_engine_is_the_interpreter():
    stem = STEMS[0]
    args = [sys.executable, "-m", "btgen", "run", _case(stem, ".xml"), "--scenario", _case(stem, ".scenario")]
    a = subprocess.run(args, cwd=ROOT, capture_output=True, timeout=300, check=False)
    b = subprocess.run(args + ["--engine", "interp"], cwd=ROOT, capture_output=True, timeout=300, check=False)
    assert a.returncode == b.returncode == 0
    assert a.stdout == b.stdout == _read_trace(stem).encode("utf-8")
