"""The reference interpreter reproduces every recorded BehaviorTree.CPP 4.6.2 trace byte for byte.

The cases live in ``tests/conformance/btcpp-4.6.2`` (``tests/conformance/FORMAT.md`` is
the contract): ``<stem>.xml``, ``<stem>.scenario``, ``<stem>.trace``; the shared folder beside
the checkout, when present, adds the stems the repository does not hold (conftest.py).
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
from conftest import CASES, ROOT, case_file, conformance_stems

NO_CASES = f"conformance cases not found at {CASES}"


STEMS = conformance_stems(".trace")


def _case(stem, ext):
    return case_file(stem, ext)


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
    # The repository holds the cases: a missing corpus is a failure, never a run whose golden
    # tests silently vanished.
    assert os.path.isdir(CASES), NO_CASES
    assert len(STEMS) >= 40, f"only {len(STEMS)} cases with a .trace in {CASES}"


@pytest.mark.parametrize("stem", STEMS)
def test_trace_matches_recording(stem):
    mission = load_mission(_case(stem, ".xml"))
    scenario, warnings = load_scenario(_case(stem, ".scenario"), mission)
    assert [str(w) for w in warnings] == []
    got = trace_text(mission, scenario)
    expected = _read_trace(stem)
    assert got == expected, f"{stem}: trace differs from the recording\n{_diff(expected, got)}"


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


def test_cli_default_engine_is_the_interpreter():
    stem = STEMS[0]
    args = [sys.executable, "-m", "btgen", "run", _case(stem, ".xml"), "--scenario", _case(stem, ".scenario")]
    a = subprocess.run(args, cwd=ROOT, capture_output=True, timeout=300, check=False)
    b = subprocess.run(args + ["--engine", "interp"], cwd=ROOT, capture_output=True, timeout=300, check=False)
    assert a.returncode == b.returncode == 0
    assert a.stdout == b.stdout == _read_trace(stem).encode("utf-8")
