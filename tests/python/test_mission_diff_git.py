"""`btgen diff --git REV [PATH ...]`: the working tree against a revision, mission by mission, in a
temporary git repository: unchanged, equivalent refactoring, behavioural change, added, removed,
a models file changed, a file that no longer loads, and the command's mistakes."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import pytest

from btgen.cli import main

MODELS = (
    '<root BTCPP_format="4">\n  <TreeNodesModel><Condition ID="Ok"/><Action ID="Work"/><Action ID="Beep"/>'
    "{extra}</TreeNodesModel>\n</root>\n"
)


def _mission(folder: Path, name: str, body: str) -> None:
    (folder / f"{name}.xml").write_text(
        '<root BTCPP_format="4" main_tree_to_execute="Main">\n'
        f'  <BehaviorTree ID="Main">\n    {body}\n  </BehaviorTree>\n</root>\n'
    )


def _git(repo: Path, *argv: str) -> None:
    subprocess.run(["git", "-C", str(repo), *argv], check=True, capture_output=True)


@pytest.fixture
def repo(tmp_path, monkeypatch):
    r = tmp_path / "repo"
    m = r / "missions"
    m.mkdir(parents=True)
    _git(r, "init", "-q")
    _git(r, "config", "user.email", "t@example.com")
    _git(r, "config", "user.name", "t")
    (m / "models.xml").write_text(MODELS.format(extra=""))
    _mission(m, "same", "<Sequence><Ok/><Work/></Sequence>")
    _mission(m, "refactor", "<Sequence><Ok/><Sequence><Work/><Beep/></Sequence></Sequence>")
    _mission(m, "change", "<ReactiveSequence><Ok/><Work/></ReactiveSequence>")
    _mission(m, "gone", "<Work/>")
    (r / "notes.txt").write_text("not a mission\n")
    _git(r, "add", "-A")
    _git(r, "commit", "-qm", "first")
    _mission(m, "refactor", "<Sequence><Ok/><Work/><Beep/></Sequence>")
    _mission(m, "change", "<Sequence><Ok/><Work/></Sequence>")
    (m / "gone.xml").unlink()
    _mission(m, "new", "<Beep/>")
    monkeypatch.chdir(r)
    return r


def _json(capsys, *argv: str) -> tuple[int, dict, str]:
    rc = main(["diff", "--format", "json", *argv])
    out, err = capsys.readouterr()
    return rc, json.loads(out) if out.strip() else {}, err


def test_mission_by_mission(capsys, repo):
    rc, report, err = _json(capsys, "--git", "HEAD")
    assert rc == 1, err
    answers = {m["path"]: m["answer"] for m in report["missions"]}
    assert answers == {
        "missions/change.xml": "different",
        "missions/gone.xml": "removed",
        "missions/new.xml": "added",
        "missions/refactor.xml": "equivalent",
        "missions/same.xml": "unchanged",
    }
    change = next(m for m in report["missions"] if m["answer"] == "different")
    # ReactiveSequence ticks Ok again while Work runs; Sequence does not
    assert change["first_difference"] == {"tick": 2, "event": 1, "old": "Ok() -> SUCCESS", "new": "Work() -> SUCCESS"}
    assert "leaf Work RUNNING" in change["scenario"]
    # the paths given: only that file, from a subfolder too
    rc, report, _ = _json(capsys, "--git", "HEAD", "missions/refactor.xml")
    assert rc == 0 and [m["answer"] for m in report["missions"]] == ["equivalent"]
    # text and markdown
    assert main(["diff", "--git", "HEAD", "missions"]) == 1
    out = capsys.readouterr().out
    assert out.startswith("btgen diff --git HEAD (BehaviorTree.CPP 4.6.2): 1 added, 1 different, 1 equivalent")
    assert "  missions/same.xml: unchanged\n" in out
    assert main(["diff", "--git", "HEAD", "--format", "markdown"]) == 1
    md = capsys.readouterr().out
    assert "| `missions/change.xml` | different: tick 2, event 1:" in md and "```text" in md


def test_a_models_file_change_is_searched_not_skipped(capsys, repo):
    _git(repo, "add", "-A")
    _git(repo, "commit", "-qm", "second")
    # Work becomes a Condition: it can no longer run, so the missions calling it differ
    models = repo / "missions" / "models.xml"
    models.write_text(MODELS.format(extra="").replace('<Action ID="Work"/>', '<Condition ID="Work"/>'))
    rc, report, _ = _json(capsys, "--git", "HEAD")
    answers = {m["path"]: m["answer"] for m in report["missions"]}
    assert rc == 1
    assert answers["missions/same.xml"] == "different"
    assert answers["missions/new.xml"] == "equivalent"  # Beep only: the models change does not touch it


def test_the_same_tree_under_two_releases(capsys, repo):
    _git(repo, "add", "-A")
    _git(repo, "commit", "-qm", "second")
    (repo / "missions" / "v.xml").write_text(
        '<root BTCPP_format="4" main_tree_to_execute="Main">\n  <BehaviorTree ID="Main">\n'
        "    <Sequence><Script code='a := 1; b := 0; c := 0'/>"
        '<ScriptCondition code="a || b &amp;&amp; c"/></Sequence>\n'
        "  </BehaviorTree>\n</root>\n"
    )
    _git(repo, "add", "-A")
    _git(repo, "commit", "-qm", "third")
    rc, report, _ = _json(capsys, "--git", "HEAD", "--btcpp-new", "4.10.0")
    answers = {m["path"]: m["answer"] for m in report["missions"]}
    assert rc == 1
    assert answers["missions/v.xml"] == "different"  # 4.9.0's precedence
    assert answers["missions/same.xml"] == "equivalent"  # searched: the versions differ


def test_a_file_that_no_longer_loads(capsys, repo):
    (repo / "missions" / "same.xml").write_text('<root BTCPP_format="4">\n  <BehaviorTree ID="Main">\n    <Nope/>\n')
    rc, report, err = _json(capsys, "--git", "HEAD", "missions/same.xml")
    assert rc == 1
    assert report["missions"][0]["answer"] == "error"
    assert "missions/same.xml:" in err and "error:" in err and "Traceback" not in err


def test_an_error_inside_the_revision_is_shown_as_rev_path(capsys, repo):
    (repo / "missions" / "same.xml").write_text(
        '<root BTCPP_format="4">\n  <BehaviorTree ID="Main"><Nope/></BehaviorTree>\n</root>\n'
    )
    _git(repo, "add", "-A")
    _git(repo, "commit", "-qm", "broken")
    _mission(repo / "missions", "same", "<Work/>")
    rc, _, err = _json(capsys, "--git", "HEAD", "missions/same.xml")
    assert rc == 1
    assert "HEAD:missions/same.xml:2:27: error:" in err and "btgen-diff-git" not in err


def test_mistakes(capsys, repo, tmp_path):
    assert main(["diff", "--git", "no-such-rev"]) == 1
    assert "--git no-such-rev: no such revision" in capsys.readouterr().err
    assert main(["diff", "--git", "HEAD", "--rename", "A=B"]) == 1
    assert "not with --git" in capsys.readouterr().err
    assert main(["diff", "--git", "HEAD", str(tmp_path)]) == 1
    assert "not inside the repository" in capsys.readouterr().err
    assert main(["diff", "missions/same.xml"]) == 1
    assert "diff needs OLD.xml and NEW.xml" in capsys.readouterr().err
    assert main(["diff", "missions/same.xml", "missions/same.xml", "missions/new.xml"]) == 1
    assert "PATHs go with --git" in capsys.readouterr().err


def test_a_difference_that_does_not_replay_is_never_reported(capsys, repo, monkeypatch):
    """The search's answer is replayed; were the replay to show no difference, `diff --git` must
    fail as a bug (as `btgen diff` does), not print "different" without a witness."""
    from btgen.tools.diff import git as diff_git

    monkeypatch.setattr(diff_git, "first_difference", lambda a, b: None)
    rc = main(["diff", "--git", "HEAD", "missions/change.xml"])
    out, err = capsys.readouterr()
    assert rc != 0 and rc != 1
    assert "different" not in out
    assert "does not replay" in err
