"""Real BehaviorTree.CPP v4 files from public projects (tests/real_files/, ORIGIN.md): each is
validated, compiled and built (g++ -Werror), and those using only built-in nodes and plain
leaves (runnable.txt) run on both engines and print the trace the real 4.6.2 printed."""

import glob
import os
import shutil
import subprocess
import sys

import pytest

from btgen.cli import main
from conftest import ROOT

HERE = os.path.join(ROOT, "tests", "real_files")
NAV2_MODELS = os.path.join(HERE, "nav2", "nav2_tree_nodes.xml")


def _runnable() -> dict[str, str]:
    out = {}
    with open(os.path.join(HERE, "runnable.txt"), encoding="utf-8") as f:
        for line in f:
            if line.strip() and not line.startswith("#"):
                path, scenario = line.split()
                out[path] = scenario
    return out


RUNNABLE = _runnable()
NAV2 = sorted(os.path.relpath(p, HERE) for p in glob.glob(os.path.join(HERE, "nav2", "*.xml")) if p != NAV2_MODELS)
ALL = NAV2 + sorted(RUNNABLE)


def _options(rel: str, tmp_path) -> list[str]:
    """What the program does in C++ (ORIGIN.md): Nav2's models file; for files whose leaves
    are declared nowhere, the models `btgen models` infers (the first of the two commands)."""
    if rel.startswith("nav2/"):
        return ["--models", NAV2_MODELS]
    if rel.startswith("btcpp/trees/"):
        return []
    models = str(tmp_path / "inferred_models.xml")
    assert main(["models", os.path.join(HERE, rel), "-o", models]) == 0
    return ["--models", models]


def test_every_real_file_is_listed():
    files = sorted(os.path.relpath(p, HERE) for p in glob.glob(os.path.join(HERE, "**", "*.xml"), recursive=True))
    assert files == sorted(ALL + [os.path.relpath(NAV2_MODELS, HERE)])
    assert len(NAV2) == 15 and len(RUNNABLE) == 13


@pytest.mark.parametrize("rel", ALL)
def test_validates_compiles_and_builds(rel, tmp_path, capsys):
    if shutil.which("g++") is None:
        pytest.skip("no g++")
    path = os.path.join(HERE, rel)
    opts = _options(rel, tmp_path)
    assert main(["validate", "-q", path, *opts]) == 0, capsys.readouterr().err
    out = tmp_path / "out"
    assert main(["compile", path, "-o", str(out), *opts]) == 0, capsys.readouterr().err
    [source] = glob.glob(str(out / "*.cpp"))
    subprocess.run(
        ["g++", "-std=c++17", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-O0", "-c"]
        + ["-I", os.path.join(ROOT, "runtime", "include"), "-I", str(out), source, "-o", str(tmp_path / "m.o")],
        check=True,
    )


@pytest.mark.parametrize("engine", ["interp", "cpp"])
@pytest.mark.parametrize("rel", sorted(RUNNABLE))
def test_runs_as_on_4_6_2(rel, engine, tmp_path):
    opts = _options(rel, tmp_path)
    scenario = os.path.join(HERE, "scenarios", RUNNABLE[rel] + ".scenario")
    proc = subprocess.run(
        [sys.executable, "-m", "btgen", "run", os.path.join(HERE, rel), "--scenario", scenario]
        + ["--engine", engine, *opts],
        capture_output=True,
        text=True,
        check=False,
        timeout=600,
    )
    assert proc.returncode == 0, proc.stderr
    expected = os.path.join(HERE, "expected", rel.replace("/", "__")[: -len(".xml")] + ".trace")
    with open(expected, encoding="utf-8") as f:
        assert proc.stdout == f.read()
