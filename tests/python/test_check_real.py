"""`btgen check` over the real projects of tests/real_files, folder by folder, with no flag: what
loads, and why each other file does not (the library refuses it too, on the release recorded in
expected*/, or its nodes are registered in C++ and the finding says how to declare them). Then the
same folders after `btgen models .` (and, for the library's 4.10.0 test trees, `btcpp = "4.10.0"` in
a btgen.toml), as docs/check.md reports them."""

import collections
import os
import shutil
from pathlib import Path
from typing import Optional

import pytest

from btgen.cli import main
from btgen.tools.check import runner
from btgen.tools.check.config import Settings, load_settings

REAL = Path(__file__).resolve().parents[2] / "tests" / "real_files"


def outcome(folder: Path, settings: Optional[Settings] = None):
    """(files of trees, those that load, {file: error codes} of the others), paths relative to `folder`."""
    old = os.getcwd()
    os.chdir(folder)
    try:
        report = runner.check(["."], settings or Settings())
    finally:
        os.chdir(old)
    errors = collections.defaultdict(set)
    messages = collections.defaultdict(list)
    for f in report.findings:
        if f.severity == "error":
            errors[os.path.normpath(f.path)].add(f.code)
            messages[os.path.normpath(f.path)].append(f.message)
    files = sorted(os.path.normpath(p) for p in report.files if report.kinds[p] != "models file")
    loads = [p for p in files if p not in errors]
    return files, loads, dict(errors), messages


def recorded_refusals(version_dir: str, prefix: str) -> set:
    return {
        f[len(prefix) : -len(".refused")] + ".xml"
        for f in os.listdir(REAL / version_dir)
        if f.startswith(prefix) and f.endswith(".refused")
    }


@pytest.mark.parametrize("folder", ["nav2", "btcpp/trees"])
def test_every_file_loads(folder):
    files, loads, errors, _ = outcome(REAL / folder)
    assert files and loads == files, errors


def test_fuzzing_seeds_refused_as_the_library_refuses_them():
    files, loads, errors, _ = outcome(REAL / "btcpp" / "fuzzing")
    assert loads == ["corpus1.xml"]
    assert set(errors) == recorded_refusals("expected", "btcpp__fuzzing__")
    assert set(errors) == recorded_refusals("expected-4.10.0", "btcpp__fuzzing__")


@pytest.mark.parametrize("folder", ["plansys2", "btcpp/examples/subtrees"])
def test_cpp_registered_nodes_say_how_to_declare_them(folder, tmp_path, capsys):
    files, loads, errors, messages = outcome(REAL / folder)
    assert loads == [] and set().union(*errors.values()) == {"C101"}
    assert all("`btgen models DIR`" in m for ms in messages.values() for m in ms)
    # after `btgen models .`, every file loads
    copy = tmp_path / "project"
    shutil.copytree(REAL / folder, copy)
    assert main(["models", str(copy), "-o", str(copy / "nodes.xml")]) == 0
    files, loads, errors, _ = outcome(copy)
    assert loads == files, errors


def test_library_4_10_trees(tmp_path, capsys):
    """The library's own 4.10.0 test trees: under the default 4.6.2, what does not load is TryCatch
    (built in from 4.9.0) or a test node registered in C++; with `btcpp = "4.10.0"` and the models of
    `btgen models`, every file loads but those the real 4.10.0 refuses (its recordings)."""
    folder = REAL / "btcpp" / "tests-4.10.0"
    files, loads, errors, messages = outcome(folder)
    assert len(files) == 27 and len(loads) == 13
    for path, codes in errors.items():
        assert codes <= {"C101", "E301"}, (path, codes)
        assert all("TryCatch" in m or "`btgen models DIR`" in m for m in messages[path]), messages[path]
    copy = tmp_path / "tests-4.10.0"
    shutil.copytree(folder, copy)
    (copy / "btgen.toml").write_text('btcpp = "4.10.0"\n')
    assert main(["models", str(copy), "--btcpp", "4.10.0", "-o", str(copy / "nodes.xml")]) == 0
    capsys.readouterr()
    files, loads, errors, _ = outcome(copy, load_settings(str(copy / "btgen.toml")))
    assert set(errors) == recorded_refusals("expected-4.10.0", "btcpp__tests-4.10.0__")
    assert len(loads) == 15
