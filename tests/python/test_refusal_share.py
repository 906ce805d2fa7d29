"""scripts/refusal_share.py: the folders it counts (issue 44's measure). Nav2's recorded cases load
only with Nav2's nodes of their distro; a real-file corpus is loaded as `btgen check` loads it."""

import json
import os
import shutil
import sys

import pytest

from conftest import ROOT

sys.path.insert(0, os.path.join(ROOT, "scripts"))
import refusal_share

REAL_REFUSALS = os.path.join(ROOT, "tests", "conformance", "real-refusals")


def test_nav2_cases_are_counted_with_nav2_nodes(monkeypatch):
    """They counted 0 loaded before (loaded without Nav2's node models); two cases per row here."""
    everything = refusal_share._missions
    monkeypatch.setattr(refusal_share, "_missions", lambda folder: everything(folder)[:2])
    rows = list(refusal_share.nav2_rows())
    assert [r.name for r in rows] == [
        f"tests/conformance/nav2 {d} ({v})" for d in ("jazzy", "kilted", "lyrical") for v in ("4.6.2", "4.10.0")
    ]
    assert [(r.loaded, len(r.refused)) for r in rows] == [(2, 0)] * 6


@pytest.fixture
def corpus(tmp_path):
    """Two projects: a file the library runs (MoveIt Pro's errorcheckvectorsize, ours), and a
    file the C++ back end refuses that the oracle file says the library refuses too."""
    run = tmp_path / "run"
    (run / "moveit").mkdir(parents=True)
    shutil.copy(os.path.join(REAL_REFUSALS, "precondition_reads_own_model_port.xml"), run / "moveit" / "check.xml")
    (run / "cycle").mkdir()
    (run / "cycle" / "cycle.xml").write_text(
        '<root BTCPP_format="4"><BehaviorTree ID="Main"><Sequence><SetBlackboard output_key="a" value="{b}"/>'
        '<SetBlackboard output_key="b" value="{a}"/></Sequence></BehaviorTree></root>\n',
        encoding="utf-8",
    )
    oracle = {"moveit": {"check.xml": [["CheckSize", "loaded"]]}, "cycle": {"cycle.xml": [["Main", "refused: x"]]}}
    (tmp_path / "oracle_462.json").write_text(json.dumps(oracle), encoding="utf-8")
    return str(run)


def test_a_corpus_is_loaded_as_check_loads_it(corpus):
    rows = {r.name: r for r in refusal_share.corpus_rows(corpus, ("4.6.2",))}
    assert sorted(rows) == ["cycle (4.6.2)", "moveit (4.6.2)"]
    assert (rows["moveit (4.6.2)"].loaded, rows["moveit (4.6.2)"].refused) == (1, [])
    cycle = rows["cycle (4.6.2)"]
    assert (cycle.loaded, len(cycle.refused), cycle.library_refuses, cycle.ran) == (1, 1, 1, 0)
    assert cycle.refused[0][0] == "cycle/cycle.xml"
    assert "cannot tell the type of blackboard entry" in cycle.refused[0][1]
