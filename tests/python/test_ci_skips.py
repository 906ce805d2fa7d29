"""In CI a skip must be on the allow-list (conftest.py, CI_SKIP_ALLOWED); the list is printed."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from conftest import CI_SKIP_ALLOWED, ROOT

TESTS = """
import pytest

def test_allowed():
    pytest.skip("one mission is enough")

def test_refused():
    pytest.skip("no frobnicator installed")

@pytest.mark.skipif(True, reason="frobnicator missing")
def test_refused_by_marker():
    pass

@pytest.mark.xfail(strict=True, reason="a known gap")
def test_known_gap():
    assert False
"""


def _pytest(tmp_path: Path, ci: str, *files: str) -> subprocess.CompletedProcess:
    (tmp_path / "test_sample.py").write_text(TESTS)
    (tmp_path / "test_whole_module.py").write_text('import pytest\npytest.importorskip("no_such_module_xyz")\n')
    env = dict(os.environ, CI=ci)
    env["PYTHONPATH"] = os.pathsep.join([str(Path(ROOT) / "tests" / "python"), str(Path(ROOT) / "generator")])
    return subprocess.run(
        [sys.executable, "-m", "pytest", "-p", "conftest", "-p", "no:cacheprovider", "-q", "-rfEs", *files],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )


def test_in_ci_only_the_listed_skips_pass(tmp_path):
    proc = _pytest(tmp_path, "true", "test_sample.py")
    assert proc.returncode == 1, proc.stdout
    # a skip in the test fails it; one decided in set-up (a skipif marker) is an error
    assert proc.stdout.strip().splitlines()[-1].startswith("1 failed, 1 skipped, 1 xfailed, 1 error"), proc.stdout
    assert "FAILED test_sample.py::test_refused - skipped in CI (no frobnicator installed)" in proc.stdout
    assert "ERROR test_sample.py::test_refused_by_marker - skipped in CI (frobnicator missing)" in proc.stdout
    assert "not on the allow-list" in proc.stdout


def test_in_ci_a_module_skipped_as_a_whole_is_an_error(tmp_path):
    proc = _pytest(tmp_path, "1", "test_whole_module.py")
    assert proc.returncode not in (0, 5), proc.stdout
    assert "ERROR collecting test_whole_module.py" in proc.stdout
    assert "could not import 'no_such_module_xyz'" in proc.stdout and "not on the allow-list" in proc.stdout


def test_outside_ci_a_skip_is_a_skip_and_the_list_is_printed(tmp_path):
    proc = _pytest(tmp_path, "", ".")
    assert proc.returncode == 0, proc.stdout
    assert proc.stdout.strip().splitlines()[-1].startswith("4 skipped, 1 xfailed"), proc.stdout
    assert "skips allowed in CI" in proc.stdout
    for prefix, why in CI_SKIP_ALLOWED:
        assert f"- {prefix!r}: {why}" in proc.stdout
