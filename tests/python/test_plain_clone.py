"""A plain clone tests itself: nothing the tests read lives only in ../shared.

The recorded BehaviorTree.CPP cases are in tests/conformance/ (conftest.py); the project's
shared folder beside a checkout, when present, only adds stems the repository does not hold.
These tests copy the files git tracks into a fresh folder with no shared folder beside it and
run the tests that read conformance cases there, in a subprocess, and check that a shared
folder adds its new stems without replacing the repository's.
"""

import os
import re
import shutil
import subprocess
import sys

import pytest

from conftest import CASES, ROOT, case_stems

# The tests that read the conformance cases (and failed or were skipped on a plain clone when
# they lived only in ../shared), without the C++ builds of test_conformance_cpp.py (the same
# stems and paths).
SELECTION = [
    "tests/python/test_conformance_interp.py",
    "tests/python/test_dataflow.py",
    "tests/python/test_frontend.py",
    "tests/python/test_compiler.py",
    "-k",
    "test_conformance_interp.py or conformance or creation_order or lowered_table or xsd_accepts"
    " or resolve_to_one_slot or lab_tour_slots or may_be_missing or (data_side_code and script_expressions)",
]


def _tracked_files() -> list[str]:
    if not os.path.exists(os.path.join(ROOT, ".git")) or shutil.which("git") is None:
        pytest.skip("not a git checkout: no list of the files a clone holds")
    out = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True, check=True).stdout
    return [f for f in out.decode("utf-8").split("\0") if f]


def _pytest(cwd, shared, *args):
    env = dict(os.environ)
    env["BTGEN_SHARED_CASES"] = str(shared)
    env["PYTHONPATH"] = os.path.join(cwd, "generator")  # the copy's btgen, not the checkout's
    env.pop("PYTEST_ADDOPTS", None)
    return subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-rs", *args],
        cwd=cwd,
        env=env,
        capture_output=True,
        text=True,
        timeout=900,
        check=False,
    )


def _counts(output: str) -> dict[str, int]:
    summary = output.strip().splitlines()[-1]
    return {word: int(n) for n, word in re.findall(r"(\d+) (passed|failed|skipped|errors?|deselected)", summary)}


def test_a_copy_of_the_tracked_files_runs_the_conformance_tests_without_shared(tmp_path):
    clone = tmp_path / "clone"
    for rel in _tracked_files():
        src = os.path.join(ROOT, rel)
        if os.path.isfile(src):  # a file deleted in the work tree but not yet from the index
            dst = clone / rel
            dst.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, dst)
    assert not (tmp_path / "shared").exists()
    proc = _pytest(clone, tmp_path / "shared" / "conformance" / "cases", *SELECTION)
    counts = _counts(proc.stdout)
    assert proc.returncode == 0, proc.stdout[-4000:] + proc.stderr[-2000:]
    assert counts.get("failed", 0) == 0 and counts.get("skipped", 0) == 0, proc.stdout[-4000:]
    # Every recorded case ran: once in the interpreter, once in the UID check, once validated.
    stems = case_stems(CASES, ".trace")
    assert len(stems) >= 40
    assert counts["passed"] >= 3 * len(stems), proc.stdout[-2000:]


def test_a_shared_folder_adds_stems_and_never_replaces_the_repository_s(tmp_path):
    shared = tmp_path / "cases"
    shared.mkdir()
    # A new stem (a copy of a recorded case) and a stem the repository holds, with a wrong trace.
    for ext in (".xml", ".scenario", ".trace"):
        shutil.copy(os.path.join(CASES, "seq_basic" + ext), shared / ("zz_added_seq_basic" + ext))
        shutil.copy(os.path.join(CASES, "fallback_halted" + ext), shared / ("fallback_halted" + ext))
    (shared / "fallback_halted.trace").write_text("not the recording\n", encoding="utf-8")
    proc = _pytest(
        ROOT,
        shared,
        "tests/python/test_conformance_interp.py",
        "-k",
        "zz_added_seq_basic or fallback_halted or cases_present",
        "-vv",  # -q -vv: one line per test
    )
    assert proc.returncode == 0, proc.stdout[-4000:] + proc.stderr[-2000:]
    assert "test_trace_matches_recording[zz_added_seq_basic] PASSED" in proc.stdout
    assert "test_trace_matches_recording[fallback_halted] PASSED" in proc.stdout
    assert _counts(proc.stdout)["passed"] == 3


def test_no_tracked_file_names_a_folder_of_one_machine():
    """Scripts, tests, docs and build files speak of paths relative to the checkout (or with a
    placeholder such as ORACLE_462_PREFIX), never of the folders of the machine they were
    written on (`scripts/record_conformance.py` named /work/shared/oracle/README.md)."""
    machine = re.compile(r"(?<![\w.])/(?:work|home/\w+|Users/\w+)/")
    kinds = (".py", ".sh", ".md", ".cmake", ".txt", ".cpp", ".hpp", ".toml", ".cfg")
    found = []
    for rel in _tracked_files():
        if not rel.endswith(kinds) or rel == "tests/python/test_plain_clone.py":
            continue
        with open(os.path.join(ROOT, rel), encoding="utf-8", errors="replace") as f:
            for number, line in enumerate(f, 1):
                if machine.search(line) and "no absolute paths" not in line:
                    found.append(f"{rel}:{number}: {line.strip()}")
    assert found == []
