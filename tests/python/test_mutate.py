"""`btgen mutate MISSION --tests DIR`: the mutants, the kills, the equivalence proofs.

Fast (seconds): small missions. The shipped missions and the Nav2 trees at full size run with
BTGEN_MUTATE_FULL=1 (docs/tests.md records their scores and times).
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from btgen.cli import main

ROOT = Path(__file__).resolve().parents[2]
SMALL = ROOT / "tests" / "mutate" / "Small.xml"
GUARD = ROOT / "tests" / "gtests" / "Guard.xml"


def _mutate(capsys, mission: Path, tests: Path, *extra: str) -> tuple[int, str, str]:
    rc = main(["mutate", str(mission), "--tests", str(tests), *extra])
    out = capsys.readouterr()
    return rc, out.out, out.err


def _json(capsys, mission: Path, tests: Path, *extra: str) -> dict:
    rc, out, err = _mutate(capsys, mission, tests, "--format", "json", *extra)
    assert rc == 0, err
    return json.loads(out)


def _suite(tmp_path: Path, *scenarios: str) -> Path:
    folder = tmp_path / "suite"
    (folder / "scenarios").mkdir(parents=True, exist_ok=True)
    for i, text in enumerate(scenarios, start=1):
        (folder / "scenarios" / f"S{i:02d}.scenario").write_text(text)
    return folder


def _by_change(report: dict) -> dict[tuple[str, str, str], dict]:
    return {(r["operator"], r["path"], r["change"]): r for r in report["results"]}


def test_operators_on_a_small_mission(capsys, tmp_path):
    assert main(["tests", str(SMALL), "-o", str(tmp_path / "suite")]) == 0
    capsys.readouterr()
    report = _json(capsys, SMALL, tmp_path / "suite")
    got = [(r["id"], r["operator"], r["line"], r["col"], r["path"], r["change"]) for r in report["results"]]
    main_ = "Small/Sequence#Main"
    par = main_ + "/Parallel"
    sub = main_ + "/SubTree(Finish)"
    assert got == [
        ("M001", "swap-kind", 5, 5, main_, "Sequence -> Fallback"),
        ("M002", "swap-form", 5, 5, main_, "Sequence -> ReactiveSequence"),
        ("M003", "swap-form", 5, 5, main_, "Sequence -> SequenceWithMemory"),
        ("M004", "drop-child", 6, 7, main_, "child 1 of 4 (Script) removed"),
        ("M005", "drop-child", 7, 7, main_, "child 2 of 4 (Fallback) removed"),
        ("M006", "drop-child", 15, 7, main_, "child 3 of 4 (Parallel) removed"),
        ("M007", "drop-child", 23, 7, main_, "child 4 of 4 (SubTree(Finish)) removed"),
        ("M008", "reorder", 7, 7, main_, "children 1 and 2 swapped"),
        ("M009", "reorder", 15, 7, main_, "children 2 and 3 swapped"),
        ("M010", "reorder", 23, 7, main_, "children 3 and 4 swapped"),
        ("M011", "script-constant", 6, 30, main_ + "/Script", "code: `2` -> `1`"),
        ("M012", "script-constant", 6, 30, main_ + "/Script", "code: `2` -> `3`"),
        ("M013", "script-constant", 6, 41, main_ + "/Script", "code: `false` -> `true`"),
        ("M014", "swap-kind", 7, 7, main_ + "/Fallback", "Fallback -> Sequence"),
        ("M015", "swap-form", 7, 7, main_ + "/Fallback", "Fallback -> ReactiveFallback"),
        ("M016", "drop-child", 8, 9, main_ + "/Fallback", "child 1 of 2 (Inverter) removed"),
        ("M017", "drop-child", 11, 9, main_ + "/Fallback", "child 2 of 2 (RetryUntilSuccessful) removed"),
        ("M018", "reorder", 11, 9, main_ + "/Fallback", "children 1 and 2 swapped"),
        ("M019", "remove-decorator", 8, 9, main_ + "/Fallback/Inverter", "Inverter removed (its child in its place)"),
        ("M020", "parallel", 15, 17, par, 'success_count="2" -> "1"'),
        ("M021", "parallel", 15, 17, par, 'success_count="2" -> "3"'),
        ("M022", "parallel", 15, 35, par, 'failure_count="1" -> "0"'),
        ("M023", "parallel", 15, 35, par, 'failure_count="1" -> "2"'),
        ("M024", "drop-child", 16, 9, par, "child 1 of 2 (ForceSuccess) removed"),
        ("M025", "drop-child", 19, 9, par, "child 2 of 2 (Repeat) removed"),
        ("M026", "reorder", 19, 9, par, "children 1 and 2 swapped"),
        ("M027", "remove-decorator", 16, 9, par + "/ForceSuccess", "ForceSuccess removed (its child in its place)"),
        ("M028", "count", 19, 17, par + "/Repeat", 'num_cycles="2" -> "1"'),
        ("M029", "count", 19, 17, par + "/Repeat", 'num_cycles="2" -> "3"'),
        ("M030", "precondition", 23, 44, sub, "_skipIf negated: `!(tries == 0)`"),
        ("M031", "script-operator", 23, 59, sub, "_skipIf: `==` -> `!=`"),
        ("M032", "script-constant", 23, 62, sub, "_skipIf: `0` -> `1`"),
        ("M033", "remap", 23, 28, sub, 'result="{done}" removed'),
        ("M034", "remap", 23, 7, sub, '_autoremap="true"'),
        ("M035", "script-constant", 27, 29, "Finish/Script", "code: `true` -> `false`"),
    ]
    status = {r["id"]: r["status"] for r in report["results"]}
    # a Parallel that can never succeed does not load: discarded, with the reason
    for m in ("M021", "M024", "M025"):
        assert status[m] == "discarded"
    reasons = {r["id"]: r.get("reason", "") for r in report["results"]}
    assert "needs 3 successes" in reasons["M021"]
    # true equivalents (each proved by the exhaustive product search): the second child of the
    # Parallel (ForceSuccess) never fails, so failure_count 2 changes nothing; `tries` is always
    # 2, so `tries == 1` skips as `tries == 0` does; Finish writes only its remapped port
    assert {m for m, s in status.items() if s == "equivalent"} == {"M023", "M032", "M034"}
    assert report["discarded"] == 3 and report["loaded"] == 32
    assert report["killed"] == report["non_equivalent"] == 29 and report["score"] == 100.0
    assert report["summary"] == "killed 29 of 29 non-equivalent mutants (3 equivalent, 0 undecided)"


def test_a_missing_behaviour_survives_and_its_scenario_kills_it(capsys, tmp_path):
    # no scenario where Move is RUNNING: a ReactiveSequence turned into a Sequence (which does
    # not re-check the battery while Move runs) is not seen
    suite = _suite(
        tmp_path,
        "ticks 2\nleaf BatteryOk SUCCESS\nleaf Move SUCCESS\n",
        "ticks 1\nleaf BatteryOk FAILURE\nleaf Recover SUCCESS\n",
        "ticks 1\nleaf BatteryOk SUCCESS\nleaf Move FAILURE\nleaf Recover FAILURE\n",
    )
    out_dir = tmp_path / "mutants"
    rc, out, err = _mutate(capsys, GUARD, suite, "-o", str(out_dir), "--min-score", "100")
    assert rc == 1 and "mutation score" in err and "below --min-score 100" in err
    assert "non-equivalent mutants (0 equivalent, 0 undecided)" in out
    report = _json(capsys, GUARD, suite)
    survivors = [r for r in report["results"] if r["status"] == "survived"]
    changes = {r["change"] for r in survivors}
    assert "ReactiveSequence -> Sequence" in changes
    sequence = next(r for r in survivors if r["change"] == "ReactiveSequence -> Sequence")
    scenario = sequence["scenario"]
    # replayed on the compiled C++ executor too (the original and each survivor built): each
    # run is the interpreter's, and the mutant's leaves change status otherwise there as well
    # (the Sequence does not re-tick BatteryOk while Move runs)
    for r in survivors:
        assert r["cpp_replay"].startswith("killed on the C++ executor too: the leaves' status changes differ"), r
    assert 'line 4: `BatteryOk "BatteryOk" SUCCESS -> IDLE` / `result RUNNING`' in sequence["cpp_replay"]
    assert "(killed on the C++ executor too" in out
    # shortest: Move RUNNING once, and the second tick shows whether the battery is re-checked
    assert "ticks 2\n" in scenario and "leaf Move RUNNING" in scenario
    # the mutant is written, and so is its killing scenario
    stem = f"{sequence['id']}-swap-form"
    assert (out_dir / f"{stem}.scenario").read_text() == scenario
    assert b'<Sequence name="Guarded">' in (out_dir / f"{stem}.xml").read_bytes()
    assert main(["validate", "-q", str(out_dir / f"{stem}.xml")]) == 0
    # added to the suite, every survivor's scenario kills its mutant
    for i, r in enumerate(survivors):
        (suite / "scenarios" / f"T{i:02d}.scenario").write_text(r["scenario"])
    again = _json(capsys, GUARD, suite)
    assert again["survived"] == 0 and again["killed"] == again["non_equivalent"] == report["non_equivalent"]
    assert again["score"] == 100.0
    assert _mutate(capsys, GUARD, suite, "--min-score", "100")[0] == 0


EQUIVALENT = """<root BTCPP_format="4" main_tree_to_execute="T">
  <BehaviorTree ID="T">
    <Sequence>
      <AlwaysSuccess/>
      <Work/>
    </Sequence>
  </BehaviorTree>
  <TreeNodesModel><Action ID="Work"/></TreeNodesModel>
</root>
"""


def test_equivalent_mutants_are_proved(capsys, tmp_path):
    # AlwaysSuccess does nothing anyone sees: ticked before or after Work, the Sequence calls
    # Work with the same results and returns the same status, halted or not
    mission = tmp_path / "eq.xml"
    mission.write_text(EQUIVALENT)
    suite = _suite(tmp_path, "ticks 2\nleaf Work RUNNING SUCCESS\n", "ticks 1\nleaf Work FAILURE\n")
    report = _json(capsys, mission, suite)
    by = {r["change"]: r for r in report["results"]}
    assert by["children 1 and 2 swapped"]["status"] == "equivalent"
    assert by["child 1 of 2 (AlwaysSuccess) removed"]["status"] == "equivalent"
    # a ReactiveSequence re-ticks AlwaysSuccess while Work runs: nothing anyone sees either
    assert by["Sequence -> ReactiveSequence"]["status"] == "equivalent"
    # these do differ: a Fallback never reaches Work; 4.6.2's SequenceWithMemory returns RUNNING
    # after a child's SUCCESS (`btgen diff` shows it in one tick)
    assert by["Sequence -> Fallback"]["status"] == "killed"
    assert by["Sequence -> SequenceWithMemory"]["status"] == "killed"
    assert report["equivalent"] == 3
    assert report["summary"] == "killed 3 of 3 non-equivalent mutants (3 equivalent, 0 undecided)"


COUNTER = """<root BTCPP_format="4" main_tree_to_execute="T">
  <BehaviorTree ID="T">
    <Sequence>
      <Script code="n := 0"/>
      <KeepRunningUntilFailure>
        <Sequence>
          <Script code="n := n + 1"/>
          <Work _skipIf="n &gt; 4"/>
        </Sequence>
      </KeepRunningUntilFailure>
    </Sequence>
  </BehaviorTree>
  <TreeNodesModel><Action ID="Work"/></TreeNodesModel>
</root>
"""


def test_a_bounded_search_is_never_equivalent(capsys, tmp_path):
    # n grows at every tick (the loop goes on after each SUCCESS of Work): no state repeats, so
    # the product search ends only at the tick bound. `n > 4` -> `n >= 4` differs at tick 4 (Work skipped a tick early).
    mission = tmp_path / "counter.xml"
    mission.write_text(COUNTER)
    suite = _suite(tmp_path, "ticks 1\nleaf Work SUCCESS\n")
    pick = "_skipIf: `>` -> `>=`"
    short = _json(capsys, mission, suite, "--max-ticks", "3", "--replay", "interp")
    long = _json(capsys, mission, suite, "--max-ticks", "8", "--replay", "interp")
    s = {r["change"]: r for r in short["results"]}[pick]
    g = {r["change"]: r for r in long["results"]}[pick]
    assert s["status"] == "undecided" and "within 3 ticks" in s["reason"] and "not a proof" in s["reason"]
    assert g["status"] == "survived" and "ticks 4" in g["scenario"]
    # what a longer search shows different was never called equivalent by a shorter one
    for a, b in zip(short["results"], long["results"]):
        if b["status"] in ("survived", "undecided"):
            assert a["status"] != "equivalent", a
    tiny = _json(capsys, mission, suite, "--max-states", "1", "--replay", "interp")
    assert all("cpp_replay" not in r for r in long["results"])
    t = {r["change"]: r for r in tiny["results"]}[pick]
    assert t["status"] == "undecided" and "--max-states 1" in t["reason"]
    assert tiny["equivalent"] == 0 and short["undecided"] >= 1


def test_bad_input(capsys, tmp_path):
    bad = tmp_path / "bad.xml"
    bad.write_text("<root BTCPP_format='4'><BehaviorTree ID='T'><Nope/></BehaviorTree></root>")
    suite = _suite(tmp_path, "ticks 1\n")
    rc, _, err = _mutate(capsys, bad, suite)
    assert rc == 1 and f"{bad}:1:" in err and "error:" in err and "Traceback" not in err
    empty = tmp_path / "empty"
    empty.mkdir()
    rc, _, err = _mutate(capsys, GUARD, empty)
    assert rc == 1 and f"{empty}:1:1: error: no scenarios" in err
    wrong = _suite(tmp_path, "ticks 1\nleaf Move MAYBE\n")
    rc, _, err = _mutate(capsys, GUARD, wrong)
    assert rc == 1 and "S01.scenario:2:" in err and "error:" in err
    with pytest.raises(SystemExit) as e:
        _mutate(capsys, GUARD, _suite(tmp_path, "ticks 1\n"), "--min-score", "150")
    assert e.value.code == 1 and "<command-line>:1:" in capsys.readouterr().err
    foreign = tmp_path / "foreign"
    foreign.mkdir()
    (foreign / "keep.txt").write_text("mine\n")
    rc, _, err = _mutate(capsys, GUARD, _suite(tmp_path, "ticks 1\n"), "-o", str(foreign), "--replay", "interp")
    assert rc == 1 and "refusing to replace it" in err and (foreign / "keep.txt").read_text() == "mine\n"


def _full_missions() -> list[tuple[str, tuple[str, ...]]]:
    from btgen.lang.nav2 import ROS_NODES

    nav2 = ROOT / "tests" / "real_files" / "nav2"
    models = nav2 / "nav2_tree_nodes.xml"
    out = [("missions/Reception.xml", ()), ("missions/LabTour.xml", ())]
    for p in sorted(nav2.glob("*.xml")):
        if p != models and not any(f"<{r}" in p.read_text() for r in ROS_NODES):
            out.append((str(p.relative_to(ROOT)), ("--models", str(models))))
    return out


@pytest.mark.skipif(not os.environ.get("BTGEN_MUTATE_FULL"), reason="set BTGEN_MUTATE_FULL=1: the full runs")
@pytest.mark.parametrize("mission,extra", _full_missions(), ids=[Path(m).stem for m, _ in _full_missions()])
def test_shipped_missions_and_nav2_trees_score(capsys, tmp_path, mission, extra):
    assert main(["tests", str(ROOT / mission), *extra, "-o", str(tmp_path / "suite")]) == 0
    capsys.readouterr()
    report = _json(capsys, ROOT / mission, tmp_path / "suite", *extra)
    assert report["score"] >= 95.0, report["summary"]


def test_an_edit_that_changes_nothing_is_no_mutant(tmp_path):
    from btgen.frontend.xmlsource import read_source
    from btgen.lang.catalogue import BUILTINS
    from btgen.tools.mutate.operators import all_mutants

    mission = tmp_path / "twice.xml"
    mission.write_text(
        '<root BTCPP_format="4" main_tree_to_execute="T"><BehaviorTree ID="T">'
        "<Sequence><Beep/><Beep/><Stop/></Sequence></BehaviorTree></root>"
    )
    got = [(m.operator, m.change) for m in all_mutants(read_source(str(mission)), frozenset(BUILTINS), lambda r: None)]
    # swapping the two equal Beeps gives the file back; removing either gives one mutant
    assert got == [
        ("swap-kind", "Sequence -> Fallback"),
        ("swap-form", "Sequence -> ReactiveSequence"),
        ("swap-form", "Sequence -> SequenceWithMemory"),
        ("drop-child", "child 1 of 3 (Beep[1]) removed"),
        ("drop-child", "child 3 of 3 (Stop) removed"),
        ("reorder", "children 2 and 3 swapped"),
    ]


def test_a_nav2_control_turned_plain_loses_its_own_ports(tmp_path):
    # RecoveryNode -> Fallback: `number_of_retries` is no Fallback port (the mutant would not load)
    from btgen.frontend.xmlsource import read_source
    from btgen.lang.nav2 import builtins_for
    from btgen.tools.mutate.operators import all_mutants

    mission = tmp_path / "nav.xml"
    mission.write_text(
        '<root BTCPP_format="4" main_tree_to_execute="T"><BehaviorTree ID="T">'
        '<RecoveryNode number_of_retries="2" name="R"><Go/><Clear/></RecoveryNode></BehaviorTree></root>'
    )
    mutants = list(all_mutants(read_source(str(mission)), frozenset(builtins_for("4.6.2", "jazzy")), lambda r: None))
    (fallback,) = [m for m in mutants if m.change == "RecoveryNode -> Fallback"]
    assert b'<Fallback name="R"><Go/><Clear/></Fallback>' in fallback.xml
    assert [m.change for m in mutants if m.operator == "count"] == [
        'number_of_retries="2" -> "1"',
        'number_of_retries="2" -> "3"',
    ]


def test_mission_options_are_taken_as_tests_takes_them(capsys, tmp_path):
    """--entry and --trees: the mission and every mutant load as `btgen tests` loaded them. A
    --trees folder that holds the mission itself (the loader leaves the mission out of it) gives
    mutants that load too: the mutant, written elsewhere, does not meet the original's trees."""
    entry = ROOT / "tests" / "gtests" / "Entry.xml"
    assert main(["tests", str(entry), "--entry", "level=int", "-o", str(tmp_path / "entry")]) == 0
    capsys.readouterr()
    report = _json(capsys, entry, tmp_path / "entry", "--entry", "level=int")
    assert report["loaded"] == report["mutants"] == 20 and report["score"] == 100.0

    folder = tmp_path / "project"
    folder.mkdir()
    library = ROOT / "tests" / "gtests" / "library"
    for f in [ROOT / "tests" / "gtests" / "UsesLibrary.xml", *library.glob("*.xml")]:
        (folder / f.name).write_text(f.read_text())
    mission = folder / "UsesLibrary.xml"
    assert main(["tests", str(mission), "--trees", str(folder), "-o", str(tmp_path / "lib")]) == 0
    capsys.readouterr()
    report = _json(capsys, mission, tmp_path / "lib", "--trees", str(folder))
    assert report["discarded"] == 0 and report["loaded"] == 6 and report["killed"] == 5 and report["equivalent"] == 1
