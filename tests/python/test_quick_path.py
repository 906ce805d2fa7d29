"""`scripts/test.sh --quick`: pytest without the tests marked slow, sanitize and qemu (the marks
are given in conftest.py); the full `scripts/test.sh`, what CI runs, still runs every test."""

import os
import re
import subprocess
import sys

from conftest import ROOT

QUICK = "not slow and not sanitize and not qemu"


def _collected(*args: str) -> set[str]:
    p = subprocess.run(
        [sys.executable, "-m", "pytest", "--collect-only", "-q", "-p", "no:cacheprovider", *args, "tests/python"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    assert p.returncode == 0, p.stdout[-2000:] + p.stderr[-2000:]
    return {line for line in p.stdout.splitlines() if "::" in line}


def test_the_quick_selection_leaves_out_the_long_runs():
    every = _collected()
    quick = _collected("-m", QUICK)
    assert quick < every

    def files(tests):
        return {t.split("::")[0].rsplit("/", 1)[-1] for t in tests}

    left_out = files(every - quick)
    for name in (
        "test_diff_random.py",
        "test_diff_sanitize.py",
        "test_mcu.py",
        "test_fuzz_frontend.py",
        "test_bench.py",
    ):
        assert name in left_out and name not in files(quick), name
    for name in ("test_help.py", "test_frontend.py", "test_compiler.py", "test_explore.py", "test_script.py"):
        assert name in files(quick), name
    # the sanitized form of a test goes, its plain form stays
    assert any("test_catch_on_halt_cases_on_every_form[interpreted-sanitized]" in t for t in every - quick)
    assert any("test_catch_on_halt_cases_on_every_form[straight-line-boundary]" in t for t in quick)


def test_test_sh_quick_runs_that_selection_and_the_full_run_everything():
    with open(os.path.join(ROOT, "scripts", "test.sh"), encoding="utf-8") as f:
        text = f.read()
    quick, full = text.split('if [ "$quick" = 1 ]; then\n  start=', 1)[1].split("\nfi\n", 1)
    assert f'-m "{QUICK}"' in quick
    for left_out in ("ctest", "test_ros1.sh", "fuzz_cpp.sh", "test_mcu.sh"):
        assert left_out not in quick
    pytest_lines = [line for line in full.splitlines() if re.match(r"\s*pytest ", line)]
    # no -m: every test; both on every core, a test file's tests in one process (pytest-xdist)
    assert pytest_lines == ['pytest -q -p no:cacheprovider -n "$jobs" --dist loadfile --durations=25']
    assert '-n "$jobs" --dist loadfile' in quick
    for step in ("ctest --test-dir build/test", "ctest --test-dir build/asan", "test_ros1.sh", "test_mcu.sh"):
        assert step in full
