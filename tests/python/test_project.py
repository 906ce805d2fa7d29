"""btgen as a project: one version everywhere, a licence, a changelog, and the small things a
new user meets first (the misuse hint, `demo.sh --help`, plurals)."""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import pytest

from btgen.cli import main
from btgen.version import __version__
from conftest import ROOT

REPO = Path(ROOT)


def test_one_version_everywhere():
    found = {
        "runtime/include/btgen/version.hpp": re.search(
            r'kRuntimeVersion = "([^"]+)"', (REPO / "runtime/include/btgen/version.hpp").read_text()
        ),
        "CMakeLists.txt": re.search(
            r"project\(btgen LANGUAGES CXX VERSION ([0-9.]+)\)", (REPO / "CMakeLists.txt").read_text()
        ),
        "cmake/btgenConfigVersion.cmake": re.search(
            r'set\(PACKAGE_VERSION "([^"]+)"\)', (REPO / "cmake/btgenConfigVersion.cmake").read_text()
        ),
        "CHANGELOG.md": re.search(r"^## ([0-9][0-9.]*) ", (REPO / "CHANGELOG.md").read_text(), re.M),
    }
    assert {where: m.group(1) if m else None for where, m in found.items()} == dict.fromkeys(found, __version__)


def test_licence_is_stated_once_and_the_same_everywhere():
    licence = (REPO / "LICENSE").read_text()
    assert licence.lstrip().startswith("Apache License") and "Version 2.0, January 2004" in licence
    assert 'license = {text = "Apache-2.0"}' in (REPO / "pyproject.toml").read_text()
    for package in REPO.glob("ros/*/package.xml"):
        assert "<license>Apache-2.0</license>" in package.read_text(), package
    assert "LICENSE" in (REPO / "MANIFEST.in").read_text()


def test_wheels_never_land_in_the_checkout():
    """`pip wheel .` writes the dependencies' wheels beside btgen's: docs/getting-started.md says
    `--no-deps -w dist`, and git ignores wheels and dist/ should one be made anyway."""
    for path in ("lxml-5.0-cp311.whl", "dist/btgen-0.3.0-py3-none-any.whl"):
        assert subprocess.run(["git", "check-ignore", "-q", path], cwd=ROOT, check=False).returncode == 0, path
    assert "pip wheel --no-deps -w dist ." in (REPO / "docs" / "getting-started.md").read_text()


@pytest.mark.parametrize(
    "argv, hint",
    [
        ([], "note: try 'btgen --help'"),
        (["bogus"], "note: try 'btgen --help'"),
        (["validate"], "note: try 'btgen validate --help'"),
        (["validate", "--nope", "m.xml"], "note: try 'btgen validate --help'"),  # reported by the top parser
        (["graph", "m.xml"], "note: try 'btgen graph --help'"),
    ],
)
def test_misuse_names_the_help_to_read(argv, hint, capsys):
    """The top-level hint read `try 'btgen  --help'` (two spaces), and an unknown option of a
    command pointed to the top-level help."""
    with pytest.raises(SystemExit) as e:
        main(argv)
    assert e.value.code == 1
    assert capsys.readouterr().err.splitlines()[-1].split(": ", 1)[1] == hint


def test_validate_counts_trees_in_english(capsys):
    one = REPO / "tests" / "conformance" / "btcpp-4.6.2" / "seq_basic.xml"
    assert main(["validate", str(one)]) == 0
    assert capsys.readouterr().out == f"{one}: ok (1 tree, main `MainTree`)\n"


def test_demo_help_answers_without_building():
    """`demo.sh --help` validated, linted and built for 15 s before printing the robot's help."""
    proc = subprocess.run(
        ["bash", str(REPO / "scripts" / "demo.sh"), "--help"], capture_output=True, text=True, timeout=60, check=False
    )
    assert proc.returncode == 0
    assert "== demo:" not in proc.stderr  # no step ran
    assert proc.stdout.startswith(("usage: lab_tour_robot", "The main job:")), proc.stdout[:200]
    assert "--language" in proc.stdout


def test_init_writes_a_whole_project_or_nothing(tmp_path, capsys):
    assert main(["init", str(tmp_path / "my-robot")]) == 0
    project = tmp_path / "my-robot"
    files = sorted(str(p.relative_to(project)) for p in project.rglob("*") if p.is_file())
    assert files == [
        ".gitignore",
        "CMakeLists.txt",
        "README.md",
        "mission/mission.scenario",
        "mission/mission.xml",
        "mission/models.xml",
        "src/main.cpp",
    ]
    assert "NAMESPACE my_robot" in (project / "CMakeLists.txt").read_text()
    main_cpp = (project / "src" / "main.cpp").read_text()
    for hook in ("Status check(leaf::BatteryOk&", "Status onStart(leaf::MoveTo&", "Status onRunning(leaf::MoveTo&"):
        assert hook in main_cpp
    mission, models = str(project / "mission" / "mission.xml"), str(project / "mission" / "models.xml")
    capsys.readouterr()
    assert main(["validate", mission, "--models", models]) == 0
    assert main(["run", mission, "--models", models, "--scenario", str(project / "mission" / "mission.scenario")]) == 0
    assert capsys.readouterr().out.endswith("result SUCCESS\n")

    # Not over an existing project, nor over a file; nothing is left behind.
    before = {p: p.read_bytes() for p in project.rglob("*") if p.is_file()}
    assert main(["init", str(project)]) == 1
    assert "is not empty" in capsys.readouterr().err
    assert {p: p.read_bytes() for p in project.rglob("*") if p.is_file()} == before
    (tmp_path / "file").write_text("x")
    assert main(["init", str(tmp_path / "file")]) == 1
    assert sorted(p.name for p in tmp_path.iterdir()) == ["file", "my-robot"]  # no temporary folder left
    (tmp_path / "empty").mkdir()
    assert main(["init", str(tmp_path / "empty"), "--name", "class"]) == 0  # an empty folder is fine
    assert "NAMESPACE class_" in (tmp_path / "empty" / "CMakeLists.txt").read_text()  # a C++ keyword is not
