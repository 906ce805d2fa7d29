"""The generated executors under AddressSanitizer and UBSan (BTGEN_SANITIZE=1).

Every conformance case the C++ back end compiles, every regression case and
every shipped mission scenario is built with `-fsanitize=address,undefined`
(batched: a few compiler runs for all of them, cached beside the plain
builds) and run: the trace must be the recorded one and stderr must stay
empty, so any sanitizer report (which also makes the exit status non-zero)
fails the test. A slice of the random missions of btgen.tools.fuzzgen runs the
same way against the interpreter.
"""

import glob
import os
import sys

import pytest

from conftest import CASES, ROOT, SHARED_CASES

sys.path.insert(0, os.path.join(ROOT, "scripts"))

import difftest
from btgen.tools.cppengine import cxx_flags

REG = os.path.join(ROOT, "tests", "regressions")
SEEDS = range(0, int(os.environ.get("BTGEN_SANITIZE_SEEDS", "25")))


@pytest.fixture(autouse=True)
def sanitize(monkeypatch):
    monkeypatch.chdir(ROOT)  # paths as the expected stderr shows them: relative to the repository
    monkeypatch.setenv("BTGEN_SANITIZE", "1")
    assert "-fsanitize=address,undefined" in cxx_flags()


def _read(path, default=""):
    if not os.path.exists(path):
        return default
    with open(path, encoding="utf-8", newline="") as f:
        return f.read()


def _runs():
    """(mission, scenario, expected (exit, stdout, stderr) or None for the interpreter's) of the
    recorded cases, the regressions and the shipped missions."""
    out = []
    held = {os.path.basename(p) for p in glob.glob(os.path.join(CASES, "*.xml"))}
    shared = [p for p in glob.glob(os.path.join(SHARED_CASES, "*.xml")) if os.path.basename(p) not in held]
    for folder in (CASES, SHARED_CASES, REG):
        xmls = shared if folder == SHARED_CASES else glob.glob(os.path.join(folder, "*.xml"))
        for xml in sorted(xmls):
            stem = xml[:-4]
            if os.path.exists(stem + ".scenario") and os.path.exists(stem + ".trace"):
                expected = (int(_read(stem + ".exit", "0")), _read(stem + ".trace"), _read(stem + ".stderr"))
                out.append((os.path.relpath(xml, ROOT), os.path.relpath(stem + ".scenario", ROOT), expected))
    for xml in sorted(glob.glob(os.path.join(ROOT, "missions", "*.xml"))):
        stem = os.path.splitext(os.path.basename(xml))[0]
        for sc in sorted(glob.glob(os.path.join(ROOT, "missions", "scenarios", stem + ".*scenario"))):
            out.append(
                (os.path.relpath(xml, ROOT), os.path.relpath(sc, ROOT), None)
            )  # expected: what the interpreter prints
    return out


def test_recorded_cases_and_shipped_missions_are_clean():
    runs = _runs()
    missions = sorted({m for m, _, _ in runs})
    compiled = [m for m in missions if difftest.classify(m)[0] == "compiled"]
    skipped = [m for m in missions if m not in compiled]
    print(
        f"\nsanitized executors: {len(compiled)} missions compiled, {len(skipped)} not supported by the C++ "
        f"back end yet: {', '.join(os.path.basename(m) for m in skipped)}"
    )
    assert len(compiled) >= 25
    batches = [compiled[i : i + 20] for i in range(0, len(compiled), 20)]
    index = {}
    for batch in batches:
        binary = difftest.build_batch(batch)
        for i, m in enumerate(batch):
            index[m] = (binary, i)
    checked = 0
    for mission, scenario, expected in runs:
        if mission not in index:
            continue
        binary, i = index[mission]
        got = difftest.run_cpp(binary, i, mission, scenario)
        if expected is None:
            expected = difftest.run_interp(mission, scenario).key()
        assert "Sanitizer" not in got.stderr and "runtime error" not in got.stderr, got.stderr[-4000:]
        assert got.key() == expected, (mission, scenario, got.stderr[-4000:])
        checked += 1
    assert checked >= 27


def test_random_missions_are_clean(tmp_path):
    report = difftest.difftest(SEEDS, "control", 2, keep=tmp_path / "kept")
    print("\n" + report.summary())
    assert len(report.compiled) == len(SEEDS)
    assert report.ok, report.summary()


def test_the_sanitizers_report(tmp_path):
    """The flags BTGEN_SANITIZE=1 builds with catch a use after free and undefined behaviour at run time."""
    import subprocess

    from btgen.tools.cppengine import compiler

    src = tmp_path / "bad.cpp"
    src.write_text(
        "#include <climits>\n#include <cstdlib>\n"
        "int main(int argc, char**) {\n"
        "  if (argc > 1) { int x = INT_MAX; x += argc; return x; }\n"
        "  int* a = new int[2]();\n"
        "  delete[] a;\n"
        "  return a[argc];\n"
        "}\n"
    )
    subprocess.run([compiler(), *cxx_flags(), str(src), "-o", str(tmp_path / "bad")], check=True)
    asan = subprocess.run([str(tmp_path / "bad")], stderr=subprocess.PIPE, check=False)
    assert asan.returncode != 0 and b"AddressSanitizer: heap-use-after-free" in asan.stderr
    ubsan = subprocess.run([str(tmp_path / "bad"), "x"], stderr=subprocess.PIPE, check=False)
    assert ubsan.returncode != 0 and b"runtime error: signed integer overflow" in ubsan.stderr
