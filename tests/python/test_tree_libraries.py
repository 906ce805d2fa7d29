"""`--trees FILE|DIR`: BehaviorTrees defined outside the mission, lent to its SubTrees as a
program's registerBehaviorTreeFromFile lends them (tests/tree_libraries/; its trace was recorded
on the real 4.6.2 with the library pasted into the mission, see record.sh there)."""

import os
import subprocess
import sys

import pytest

from btgen.compiler import mission_files
from btgen.diagnostics import UserError
from btgen.frontend.loader import load_mission
from btgen.pipeline import CompileOptions
from conftest import ROOT

HERE = os.path.join(ROOT, "tests", "tree_libraries")


@pytest.mark.parametrize("engine", ["interp", "cpp"])
def test_library_trees_run_as_on_4_6_2(engine):
    proc = subprocess.run(
        [sys.executable, "-m", "btgen", "run", "mission.xml", "--trees", "lib", "--scenario", "mission.scenario"]
        + ["--engine", engine],
        cwd=HERE,
        capture_output=True,
        text=True,
        check=False,
        timeout=600,
    )
    assert proc.returncode == 0, proc.stderr
    with open(os.path.join(HERE, "mission.trace"), encoding="utf-8") as f:
        assert proc.stdout == f.read()


def test_without_the_library_the_subtrees_are_unknown():
    with pytest.raises(UserError) as e:
        load_mission(os.path.join(HERE, "mission.xml"))
    assert [d.message.split(":")[0] for d in e.value.diagnostics] == [
        "SubTree `Other` does not exist",
        "SubTree `Greet` does not exist",
    ]


def test_a_file_and_a_folder_alike():
    lib = os.path.join(HERE, "lib")
    by_folder = load_mission(os.path.join(HERE, "mission.xml"), trees=[lib])
    by_files = load_mission(
        os.path.join(HERE, "mission.xml"),
        trees=[os.path.join(lib, "other.xml"), os.path.join(lib, "common.xml"), lib],
    )
    assert {t.id for t in by_folder.trees} == {t.id for t in by_files.trees} == {"Main", "Greet", "Other"}
    assert by_folder.main_tree == "Main"  # the library's trees never count as the mission's only tree
    assert [m.id for m in by_folder.models] == ["Say"]  # the library's TreeNodesModel counts
    deps = mission_files(os.path.join(HERE, "mission.xml"), CompileOptions(trees=(lib,)))
    assert sorted(os.path.basename(f) for f in deps) == ["common.xml", "mission.xml", "other.xml"]


def test_conflicting_ids_name_both_places(tmp_path):
    dup = tmp_path / "dup.xml"
    dup.write_text('<root BTCPP_format="4">\n  <BehaviorTree ID="Other"><AlwaysSuccess/></BehaviorTree>\n</root>\n')
    with pytest.raises(UserError) as e:
        load_mission(os.path.join(HERE, "mission.xml"), trees=[os.path.join(HERE, "lib"), str(dup)])
    [d] = e.value.diagnostics
    first = os.path.join(HERE, "lib", "other.xml")
    assert str(d) == f"{dup}:2:21: error: BehaviorTree `Other` is defined twice (first at {first}:1:24)"


def test_missing_and_empty_libraries(tmp_path):
    (tmp_path / "empty").mkdir()
    with pytest.raises(UserError) as e:
        load_mission(
            os.path.join(HERE, "mission.xml"),
            trees=[str(tmp_path / "nope"), str(tmp_path / "empty"), os.path.join(HERE, "lib")],
        )
    assert [str(d) for d in e.value.diagnostics] == [
        f"{tmp_path / 'nope'}:1:1: error: --trees: no such file or folder",
        f"{tmp_path / 'empty'}:1:1: error: --trees names a folder that holds no .xml file",
    ]
