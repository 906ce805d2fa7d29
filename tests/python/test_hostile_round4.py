"""Hostile inputs, round 4: the tools that read logs, rules and folders, and write files.

Each test is a public reproducer of issue 43 (it failed before the fix: a traceback, a silent
wrong answer, a lost or stale file, or a run without bound), grouped by the class fixed at its
root: one bounded JSON reader, one output-file guard, one scenario writer and reader, one trace
reader, and the option checks every command shares.
"""

from __future__ import annotations

import os
import random
import re
import shutil
import struct
import subprocess
import sys
from pathlib import Path

import pytest

from btgen.cli import main
from btgen.diagnostics import UserError
from btgen.frontend.loader import load_mission
from btgen.interp.engine import trace_text
from btgen.interp.scenario import MAX_VALUE, format_scenario, parse_scenario, parse_scenario_text
from btgen.ir.treexml import groot2_tree
from btgen.lang.substitution import Wildcard
from btgen.tools.cover import trace_transitions

ROOT = Path(__file__).resolve().parents[2]
CODES = {"IDLE": 0, "RUNNING": 1, "SUCCESS": 2, "FAILURE": 3, "SKIPPED": 4}

MISSION = """<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence>
      <Find/>
      <Act/>
      <Check/>
    </Sequence>
  </BehaviorTree>
  <TreeNodesModel>
    <Action ID="Find"/>
    <Action ID="Act"/>
    <Condition ID="Check"/>
  </TreeNodesModel>
</root>
"""


def _files(tmp_path: Path, mission: str = MISSION, scenario: str = "ticks 5\n") -> tuple[str, str]:
    (tmp_path / "m.xml").write_text(mission, encoding="utf-8")
    (tmp_path / "s.scenario").write_text(scenario, encoding="utf-8")
    return str(tmp_path / "m.xml"), str(tmp_path / "s.scenario")


def _btlog(mission_path: str, moves, out: Path) -> Path:
    """A .btlog as btgen::btlog::FileLogger writes it: header, tree XML, 9-byte records."""
    xml = groot2_tree(load_mission(mission_path)).xml.encode()
    body = b"".join(
        struct.pack("<Q", 1000 * i)[:6] + struct.pack("<HB", uid, CODES[to]) for i, (uid, _, to) in enumerate(moves)
    )
    out.write_bytes(b"BTCPP4-FileLogger2\x01" + struct.pack("<i", len(xml)) + xml + struct.pack("<q", 0) + body)
    return out


def _err_lines(capsys) -> list[str]:
    return capsys.readouterr().err.splitlines()


# ====================================================================== substitution rules
def _run_rules(tmp_path: Path, rules: str, *extra: str, mission: str = MISSION, scenario: str = "ticks 5\n") -> int:
    m, s = _files(tmp_path, mission, scenario)
    (tmp_path / "r.json").write_text(rules, encoding="utf-8")
    return main(["run", m, "--scenario", s, "--substitute", str(tmp_path / "r.json"), *extra])


@pytest.mark.parametrize(
    "rules, where",
    [
        ("[" * 100_000 + "]" * 100_000, ":1:65: error: arrays and objects nested deeper than 64 levels"),
        ('{"TestNodeConfigs": {"X": {"return_status": ["SUCCESS"]}}, "SubstitutionRules": {"Find": "X"}}', ":1:45:"),
        ('{"TestNodeConfigs": {"X": {"return_status": {"a": 1}}}, "SubstitutionRules": {}}', ":1:45:"),
        ('{"TestNodeConfigs": {"X": {"return_status": "SUCCESS", "async_delay": NaN}}}', ":1:71: error: invalid JSON"),
        ('{"TestNodeConfigs": {"X": {"async_delay": ' + "9" * 5000 + "}}}", ":1:43: error: invalid JSON"),
        ('{"TestNodeConfigs": {"X": {"return_status": "SUCCESS", "post_script": 3}}, "SubstitutionRules": {}}', ":1:"),
    ],
)
def test_every_malformed_rules_file_is_a_located_error(tmp_path, capsys, rules, where):
    """RecursionError (deep nesting), TypeError (a list as return_status) and ValueError (a
    4,300-digit number) were tracebacks with exit 3."""
    assert _run_rules(tmp_path, rules) == 1
    err = _err_lines(capsys)
    assert err and all(line.startswith(str(tmp_path / "r.json") + ":") for line in err), err
    assert where in err[0]


def test_rule_scripts_follow_the_selected_release(tmp_path, capsys):
    """A trailing `;` (4.9.0 and later accept it) was refused under --btcpp 4.10.0 with a
    message naming 4.6.2."""
    rules = '{"TestNodeConfigs": {"X": {"return_status": "SUCCESS", "post_script": "a := 1;"}}, '
    rules += '"SubstitutionRules": {"Find": "X"}}'
    assert _run_rules(tmp_path, rules, "--btcpp", "4.10.0") == 0
    assert capsys.readouterr().out.endswith("result SUCCESS\n")
    assert _run_rules(tmp_path, rules) == 1
    assert "4.6.2 rejects a trailing `;`" in capsys.readouterr().err


def test_a_rule_that_changes_a_leafs_kind_is_refused_by_both_engines(tmp_path, capsys):
    """`Act` (an Action) built as the mission's Condition `Check`: the interpreter and the
    compiled executor printed different traces."""
    rules = '{"TestNodeConfigs": {}, "SubstitutionRules": {"Act": "Check"}}'
    assert _run_rules(tmp_path, rules, scenario="ticks 5\nleaf Act RUNNING SUCCESS\nleaf Check FAILURE\n") == 1
    interp = capsys.readouterr()
    assert interp.out == ""
    want = 'the rule `Act` builds `Act` "Act" (' + str(tmp_path / "m.xml") + ":5:7), an Action, as `Check`"
    assert want in interp.err
    # the compiled executor's path (`compile --substitute`, as `run --engine cpp` builds it)
    out = tmp_path / "out"
    assert main(["compile", str(tmp_path / "m.xml"), "-o", str(out), "--substitute", str(tmp_path / "r.json")]) == 1
    assert want in capsys.readouterr().err and not out.exists()
    # the same kind stays allowed
    (tmp_path / "r.json").write_text('{"TestNodeConfigs": {}, "SubstitutionRules": {"Act": "Find"}}')
    assert main(["compile", str(tmp_path / "m.xml"), "-o", str(out), "--substitute", str(tmp_path / "r.json")]) == 0


def _reference_match(text: str, pattern: str) -> bool:
    """Wildcard matching by dynamic programming (quadratic, obviously right)."""
    toks: list[tuple[str, str]] = []
    i = 0
    while i < len(pattern):
        if pattern[i] == "\\" and i + 1 < len(pattern):
            toks.append(("c", pattern[i + 1]))
            i += 2
            continue
        toks.append(("*", "") if pattern[i] == "*" else ("?", "") if pattern[i] == "?" else ("c", pattern[i]))
        i += 1
    row = [True] + [False] * len(text)
    for kind, c in toks:
        new = [False] * (len(text) + 1)
        if kind == "*":
            new[0] = row[0]
            for j in range(1, len(text) + 1):
                new[j] = new[j - 1] or row[j]
        else:
            for j in range(1, len(text) + 1):
                new[j] = row[j - 1] and (kind == "?" or text[j - 1] == c)
        row = new
    return row[len(text)]


def test_wildcards_match_as_the_reference_and_without_backtracking():
    """A 20-byte wildcard against a 60-character name took 62 s at 8 stars (backtracking
    regex) and grew with every star; it is now one pass per piece."""
    hostile = "*o" * 9 + "*X"
    assert Wildcard(hostile).match("o" * 60) is False  # before: did not return
    assert Wildcard("*o" * 30 + "*").match("o" * 60) is True
    rng = random.Random(43)
    for _ in range(3000):
        text = "".join(rng.choice("ab/*?\\") for _ in range(rng.randint(0, 8)))
        pattern = "".join(rng.choice("ab/*?\\") for _ in range(rng.randint(0, 7)))
        assert Wildcard(pattern).match(text) == _reference_match(text, pattern), (text, pattern)


def test_many_rules_are_indexed_once(tmp_path, capsys):
    """20,000 rules that match nothing: each wildcard was rebuilt as a regex for every node.
    Now the exact filters are one dict and only the wildcard ones are tried; the first
    matching rule in file order still wins."""
    filters = [f"NoSuch{i}*" for i in range(20_000)] + ["Act", "A*"]
    body = ", ".join(f'"{f}": "AlwaysFailure"' for f in filters[:-1]) + ', "A*": "AlwaysSuccess"'
    assert _run_rules(tmp_path, '{"TestNodeConfigs": {}, "SubstitutionRules": {' + body + "}}") == 0
    out = capsys.readouterr().out
    assert '3 Act "Act" IDLE -> FAILURE' in out  # `Act` (exact, earlier) wins over `A*`


# ====================================================================== command-line checks
@pytest.mark.parametrize("value", ["nan", "150", "-5", "inf", "x"])
def test_cover_min_is_a_percentage(tmp_path, capsys, value):
    """`--min nan` passed whatever the coverage, 150 always failed, -5 always passed."""
    m, s = _files(tmp_path)
    with pytest.raises(SystemExit) as e:
        main(["cover", m, s, f"--min={value}"])
    assert e.value.code == 1
    err = capsys.readouterr().err
    assert re.match(r"<command-line>:1:\d+: error: argument --min: ", err), err


def test_run_checks_entries_as_validate_does(tmp_path, capsys):
    """`--entry Patrol:timeout=int --entry timeout=std::string` with Patrol the main tree:
    BlackboardError, exit 3, on `run`; validate gave a located error."""
    m, s = _files(tmp_path, MISSION.replace('"Main"', '"Patrol"'))
    entries = ["--entry", "Patrol:timeout=int", "--entry", "timeout=std::string"]
    assert main(["validate", m, *entries]) == 1
    validate = capsys.readouterr().err
    assert main(["run", m, "--scenario", s, *entries]) == 1
    assert capsys.readouterr().err == validate
    assert validate.startswith(f"{m}:2:3: error: --entry timeout=string: blackboard entry `timeout` is declared as int")


def test_models_checks_options_as_validate_does(tmp_path, capsys):
    """`models` read the mission without loading it, and took any --entry, --enum, --type."""
    m, _ = _files(tmp_path)
    for option in (["--entry", "bad"], ["--enum", "X"], ["--type", "Q"]):
        assert main(["validate", m, *option]) == 1
        validate = capsys.readouterr().err
        assert main(["models", m, *option]) == 1
        assert capsys.readouterr().err == validate


def test_upgrade_check_of_a_missing_scenario_is_an_error(tmp_path, capsys):
    """Both versions failed to read the scenario, and the report said the traces were the
    same and nothing changes, exit 0."""
    m, _ = _files(tmp_path)
    missing = str(tmp_path / "no-such.scenario")
    assert main(["upgrade-check", m, "--scenario", missing]) == 1
    out, err = capsys.readouterr()
    assert "nothing changes" not in out and "the same" not in out
    assert err == f"{missing}:1:1: error: cannot read scenario: No such file or directory\n"
    # a mission neither version loads, with a good scenario: not a comparison either
    (tmp_path / "bad.xml").write_text(MISSION.replace("<Check/>", "<Unknown/>"))
    assert main(["upgrade-check", str(tmp_path / "bad.xml"), "--scenario", str(tmp_path / "s.scenario")]) == 1
    assert "nothing changes" not in capsys.readouterr().out


# ====================================================================== one trace reader
def test_cover_reads_a_trace_as_graph_checks_it(tmp_path, capsys):
    """A trace whose spaces became tabs was accepted by the checker and counted as nothing
    by the counter (0%, exit 0)."""
    m, s = _files(tmp_path)
    assert main(["run", m, "--scenario", s]) == 0
    trace = capsys.readouterr().out
    (tmp_path / "spaces.trace").write_text(trace)
    (tmp_path / "tabs.trace").write_text(trace.replace(" ", "\t"))
    assert main(["cover", m, str(tmp_path / "spaces.trace"), "--min", "100"]) == 0
    spaces = capsys.readouterr().out
    assert main(["cover", m, str(tmp_path / "tabs.trace"), "--min", "100"]) == 0
    assert capsys.readouterr().out == spaces and "nodes:    4/4 = 100.0%" in spaces


# ====================================================================== btgen models
def test_models_of_a_long_include_chain_is_validates_error(tmp_path, capsys):
    """1,000 chained includes: RecursionError in `models`; validate: a located error."""
    for i in range(1000):
        inner = f'<include path="f{i + 1}.xml"/>' if i < 999 else '<BehaviorTree ID="T"><Foo/></BehaviorTree>'
        (tmp_path / f"f{i}.xml").write_text(f'<root BTCPP_format="4">{inner}</root>\n')
    main_xml = tmp_path / "main.xml"
    main_xml.write_text(
        '<root BTCPP_format="4" main_tree_to_execute="Main"><include path="f0.xml"/>'
        '<BehaviorTree ID="Main"><SubTree ID="T"/></BehaviorTree></root>\n'
    )
    assert main(["validate", str(main_xml)]) == 1
    validate = _err_lines(capsys)
    assert main(["models", str(main_xml)]) == 1
    models = _err_lines(capsys)
    assert models == validate[:1] and models[0].endswith("error: includes nested deeper than 32 files")


def test_what_models_writes_under_4_10_validate_accepts(tmp_path, capsys):
    """`my.note` (4.10.0 ignores it: not a port name) was written as a port, which
    `validate --models` then refused."""
    mission = tmp_path / "note.xml"
    mission.write_text(
        '<root BTCPP_format="4" main_tree_to_execute="Main">\n'
        '  <BehaviorTree ID="Main"><Foo my.note="hi" goal="1"/></BehaviorTree>\n</root>\n'
    )
    out = tmp_path / "models.xml"
    assert main(["models", "--btcpp", "4.10.0", str(mission), "-o", str(out)]) == 0
    assert "my.note" not in out.read_text() and 'name="goal"' in out.read_text()
    assert main(["validate", "--btcpp", "4.10.0", str(mission), "--models", str(out)]) == 0


# ====================================================================== the output-file guard
def test_scenario_from_log_does_not_overwrite_its_log(tmp_path, capsys):
    """`-o run.btlog` replaced the robot's only log with the scenario."""
    m, s = _files(tmp_path)
    mission = load_mission(m)
    log = _btlog(m, trace_transitions(trace_text(mission, parse_scenario(s))), tmp_path / "run.btlog")
    before = log.read_bytes()
    assert main(["scenario-from-log", m, str(log), "-o", str(log)]) == 1
    assert capsys.readouterr().err == (
        f"{log}:1:1: error: `-o {log}` would overwrite this input file: choose another output file\n"
    )
    assert log.read_bytes() == before
    # nor the mission, through another spelling of its path
    assert main(["scenario-from-log", m, str(log), "-o", str(tmp_path / "." / "m.xml")]) == 1
    assert "would overwrite this input file" in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.xml", "run.btlog", "s.scenario"]  # no temporary file


def test_graph_and_compile_do_not_overwrite_their_inputs(tmp_path, capsys):
    m, s = _files(tmp_path)
    assert main(["run", m, "--scenario", s]) == 0
    trace = tmp_path / "run.dot"  # a trace named like the output
    trace.write_text(capsys.readouterr().out)
    before = trace.read_text()
    assert main(["graph", m, "--trace", str(trace), "-o", str(trace)]) == 1
    assert "would overwrite this input file" in capsys.readouterr().err and trace.read_text() == before
    assert main(["cover", m, str(trace), "--graph", str(trace)]) == 1
    assert "would overwrite this input file" in capsys.readouterr().err and trace.read_text() == before
    (tmp_path / "r.json").write_text('{"TestNodeConfigs": {}, "SubstitutionRules": {}}')
    rules = tmp_path / "m.hpp"  # rules named like the generated header
    (tmp_path / "r.json").rename(rules)
    assert main(["compile", m, "-o", str(tmp_path), "--substitute", str(rules)]) == 1
    assert "would overwrite this input file" in capsys.readouterr().err
    assert rules.read_text() == '{"TestNodeConfigs": {}, "SubstitutionRules": {}}'


def test_explore_cleans_exactly_what_it_wrote(tmp_path, capsys):
    """A folder named like a stale scenario: IsADirectoryError after the new files were
    written. A counterexample of an earlier run stayed beside the new scenarios."""
    m, _ = _files(tmp_path)
    out = tmp_path / "out"
    out.mkdir()
    (out / "m-999.scenario").mkdir()  # no run wrote it: kept, and no traceback
    (out / "counterexample-7.scenario").write_text("# the user's\n")
    assert main(["explore", m, "-o", str(out), "--assert", "never Act SUCCESS"]) == 1
    assert (out / "counterexample-1.scenario").is_file()
    capsys.readouterr()
    assert main(["explore", m, "-o", str(out)]) == 0
    names = sorted(p.name for p in out.iterdir())
    assert "counterexample-1.scenario" not in names  # the earlier run's, which this one did not write
    assert "m-999.scenario" in names and "counterexample-7.scenario" in names
    # a folder where one of this run's files goes: a located error before any file is written
    shutil.rmtree(out)
    out.mkdir()
    (out / "m-001.scenario").mkdir()
    assert main(["explore", m, "-o", str(out)]) == 1
    assert capsys.readouterr().err.endswith(
        f"{out / 'm-001.scenario'}:1:1: error: -o {out / 'm-001.scenario'}: is a folder, not a file\n"
    )
    assert sorted(p.name for p in out.iterdir()) == ["m-001.scenario"]


def test_a_manifest_never_removes_an_input_nor_blocks_half_way(tmp_path, capsys):
    """A manifest is read as a record, not trusted: one that lists the mission (forged, or a
    mission written into the output folder) never gets it removed; a manifest that cannot be
    written stops the run before any scenario is written."""
    out = tmp_path / "out"
    out.mkdir()
    m, _ = _files(out)
    (out / ".m.btgen-explore").write_text('{"written by": "btgen explore", "files": ["m.xml", "s.scenario"]}')
    assert main(["explore", m, "-o", str(out)]) == 0
    assert (out / "m.xml").read_text() == MISSION
    assert not (out / "s.scenario").exists()  # what the record lists, and this run did not write, goes
    shutil.rmtree(out)
    out.mkdir()
    (out / ".m.btgen-explore").mkdir()
    m, _ = _files(tmp_path)
    assert main(["explore", m, "-o", str(out)]) == 1
    assert "is a folder, not a file" in capsys.readouterr().err
    assert sorted(p.name for p in out.iterdir()) == [".m.btgen-explore"]


def test_missing_rules_sections_are_named(tmp_path, capsys):
    assert _run_rules(tmp_path, '{"SubstitutionRules": {}}') == 1
    assert capsys.readouterr().err == (
        f"{tmp_path / 'r.json'}:1:1: error: the file has no `TestNodeConfigs` (BehaviorTree.CPP requires it: "
        "`{}` when empty)\n"
    )


# ====================================================================== one scenario writer
HOSTILE_LEAVES = MISSION.replace("<Find/>", '<Find name="door open"/>').replace("<Act/>", '<Act name="go#home"/>')


def test_explore_refuses_names_a_scenario_cannot_hold(tmp_path, capsys):
    """`leaf door open SUCCESS` was written for a leaf named `door open` (read back as the
    leaf `door`), and `go#home` was cut at the `#`."""
    m, _ = _files(tmp_path, HOSTILE_LEAVES)
    out = tmp_path / "out"
    assert main(["explore", m, "-o", str(out)]) == 1
    err = _err_lines(capsys)
    assert err[0].startswith(f"{m}:4:7: error: the leaf name `door open` cannot be written in a scenario file")
    assert err[1].startswith(f"{m}:5:7: error: the leaf name `go#home` cannot be written")
    assert not any(out.glob("*.scenario"))
    # scenario-from-log, the other writer, refuses them the same way
    mission = load_mission(m)
    moves = trace_transitions(trace_text(mission, parse_scenario(str(tmp_path / "s.scenario"))))
    log = _btlog(m, moves, tmp_path / "r.btlog")
    assert main(["scenario-from-log", m, str(log)]) == 1
    assert _err_lines(capsys)[0] == err[0]


def test_clock_ms_that_no_scenario_holds_is_refused(tmp_path, capsys):
    """`explore --clock-ms 3000000000` wrote a value `btgen run` refuses."""
    m, _ = _files(tmp_path)
    assert main(["explore", m, "-o", str(tmp_path / "o"), "--clock-ms", "3000000000"]) == 1
    assert re.match(r"<command-line>:1:\d+: error: --clock-ms 3000000000 is larger", capsys.readouterr().err)
    assert main(["explore", m, "-o", str(tmp_path / "o"), "--ticks", "3000000000"]) == 1
    assert re.match(r"<command-line>:1:\d+: error: --ticks 3000000000 is larger", capsys.readouterr().err)
    assert not (tmp_path / "o").exists()


def test_scenario_writer_round_trips_random_names_and_values():
    """Property: what format_scenario writes, parse_scenario_text reads back to the same
    ticks, clock and leaf lines; what it cannot write it refuses (UserError), never writes."""
    rng = random.Random(4343)
    alphabet = "ab_Z9 \t#\"'\\\r\n\f\v.:/-é€\u2028x"
    for _ in range(2000):
        leaves = []
        for _ in range(rng.randint(0, 4)):
            name = "".join(rng.choice(alphabet) for _ in range(rng.randint(0, 6)))
            leaves.append((name, [rng.choice(("SUCCESS", "FAILURE", "RUNNING")) for _ in range(rng.randint(1, 3))]))
        ticks = rng.choice((0, 1, 7, MAX_VALUE, MAX_VALUE + 1, 3_000_000_000))
        clock = rng.choice((0, 100, MAX_VALUE, MAX_VALUE + 1, -1))
        comment = "".join(rng.choice(alphabet) for _ in range(rng.randint(0, 10)))
        try:
            text = format_scenario(ticks, leaves, clock, comment)
        except UserError:
            continue
        back = parse_scenario_text(text)
        assert (back.ticks, back.clock_ms) == (ticks, clock), text
        assert [(s.name, list(s.statuses)) for s in back.leaves] == leaves, text


def test_every_writer_round_trips_random_leaf_names(tmp_path, capsys):
    """Property, through the commands: for missions whose leaves have random names (blanks,
    `#`, quotes, non-ASCII), `explore -o` and `scenario-from-log` either write scenarios that
    read back to the mission's own names and replay, or both refuse, at the node, with the
    same words."""
    from xml.sax.saxutils import quoteattr

    rng = random.Random(4344)
    alphabet = "ab_Z9 #\"'.:-é€\t"
    seen = set()
    for k in range(10):
        names = ["".join(rng.choice(alphabet) for _ in range(rng.randint(1, 5))).strip() or "x" for _ in range(2)]
        if names[0] == names[1]:
            names[1] += "2"
        xml = MISSION.replace("<Find/>", f"<Find name={quoteattr(names[0])}/>").replace(
            "<Act/>", f"<Act name={quoteattr(names[1])}/>"
        )
        case = tmp_path / f"c{k}"
        case.mkdir()
        m, s = _files(case, xml)
        out = case / "out"
        rc = main(["explore", m, "-o", str(out)])
        explore_err = capsys.readouterr().err
        mission = load_mission(m)
        log = _btlog(m, trace_transitions(trace_text(mission, parse_scenario(s))), case / "r.btlog")
        rc_log = main(["scenario-from-log", m, str(log), "-o", str(case / "back.scenario")])
        log_err = capsys.readouterr().err
        writable = all(re.fullmatch(r"[^ \t\f\v\r\n#]+", n) for n in names)
        seen.add(writable)
        assert (rc, rc_log) == ((0, 0) if writable else (1, 1)), (names, explore_err, log_err)
        if not writable:
            assert explore_err.splitlines()[0] == log_err.splitlines()[0]
            assert "cannot be written in a scenario file" in explore_err
            continue
        for written in [*out.glob("*.scenario"), case / "back.scenario"]:
            back = parse_scenario(str(written))
            assert {leaf.name for leaf in back.leaves} <= {*names, "Check"}, written.read_text()
            trace_text(mission, back)  # replays
    assert seen == {True, False}  # both outcomes were tried


# ====================================================================== scenario-from-log
STUCK = """<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence>
      <A/>
      <B/>
    </Sequence>
  </BehaviorTree>
  <TreeNodesModel>
    <Action ID="A"/>
    <Action ID="B"/>
  </TreeNodesModel>
</root>
"""


def test_a_replay_is_bounded_by_the_log(tmp_path, capsys):
    """A log whose run cannot reach its next record (B succeeds while A still runs): up to
    1,000,000 ticks, each appending A's RUNNING answer, then MemoryError."""
    m, _ = _files(tmp_path, STUCK)
    moves = [(1, "IDLE", "RUNNING"), (2, "IDLE", "RUNNING"), (3, "IDLE", "SUCCESS")] * 40
    log = _btlog(m, moves, tmp_path / "stuck.btlog")
    assert main(["scenario-from-log", m, str(log)]) == 1
    err = capsys.readouterr().err
    assert err.startswith(f"{log}:1:1: error: the log is not a run of this mission: record 3: a tick changes nothing")
    # with a clock, as far as the log's own time goes (its records are 1 ms apart), no further
    assert main(["scenario-from-log", m, str(log), "--clock-ms", "1"]) == 1
    assert "a tick changes nothing the log shows (the mission's clock is at" in capsys.readouterr().err


def test_a_log_that_ends_with_a_halt_replays(tmp_path, capsys):
    """A run stopped by the operator (`--max-ticks`): the log ends with the halt's RUNNING ->
    IDLE records, and the replay ticked a million times, then said the log was not used up."""
    m, s = _files(tmp_path, STUCK, "ticks 3\nleaf A RUNNING RUNNING RUNNING\n")
    mission = load_mission(m)
    trace = trace_text(mission, parse_scenario(s))
    halt = [(2, "RUNNING", "IDLE"), (1, "RUNNING", "IDLE")]
    log = _btlog(m, trace_transitions(trace) + halt, tmp_path / "halted.btlog")
    back = tmp_path / "back.scenario"
    assert main(["scenario-from-log", m, str(log), "-o", str(back)]) == 0
    assert "the run was halted before it completed (records 3 to 4" in capsys.readouterr().err
    assert trace_transitions(trace_text(mission, parse_scenario(str(back)))) == trace_transitions(trace)


# ====================================================================== --trees DIR
def test_trees_folder_reads_each_files_real_path_once(tmp_path, monkeypatch):
    """1,500 files 40 levels deep: the real path of every file read so far was computed for
    every file (quadratic: 472 s; 8 s now)."""
    import btgen.frontend.loader as loader

    deep = tmp_path.joinpath(*(f"d{i}" for i in range(10)))
    deep.mkdir(parents=True)
    n = 150
    for i in range(n):
        (deep / f"t{i:03d}.xml").write_text(
            f'<root BTCPP_format="4"><BehaviorTree ID="T{i}"><AlwaysSuccess/></BehaviorTree></root>\n'
        )
    (tmp_path / "m.xml").write_text(
        '<root BTCPP_format="4" main_tree_to_execute="Main"><BehaviorTree ID="Main"><SubTree ID="T7"/>'
        "</BehaviorTree></root>\n"
    )
    calls = []
    real = os.path.realpath

    def counting(path, *args, **kwargs):
        calls.append(path)
        return real(path, *args, **kwargs)

    monkeypatch.setattr(os.path, "realpath", counting)
    mission = loader.load_mission(str(tmp_path / "m.xml"), (), None, (str(deep),))
    assert len(mission.trees) == n + 1
    assert len(calls) <= 3 * n + 10  # before: n * n / 2 + ...


# ====================================================================== btgen init
def test_init_into_the_empty_current_folder(tmp_path, monkeypatch, capsys):
    """`mkdir robot && cd robot && btgen init .`: "Device or resource busy"."""
    robot = tmp_path / "robot"
    robot.mkdir()
    monkeypatch.chdir(robot)
    assert main(["init", "."]) == 0
    assert sorted(p.name for p in robot.iterdir()) == [".gitignore", "CMakeLists.txt", "README.md", "mission", "src"]
    assert "project(robot LANGUAGES CXX)" in (robot / "CMakeLists.txt").read_text()


@pytest.mark.parametrize("name", ["all", "help", "clean", "install", "test", "package", "ALL_BUILD", "btgen_kb"])
def test_init_never_takes_a_name_cmake_reserves(tmp_path, capsys, name):
    assert main(["init", str(tmp_path / "p"), "--name", name]) == 0
    text = (tmp_path / "p" / "CMakeLists.txt").read_text()
    wanted = re.sub(r"[^a-z0-9]+", "_", name.lower())
    assert f"project({wanted}_robot LANGUAGES CXX)" in text, text


def _cmake_env() -> dict[str, str]:
    env = dict(os.environ)
    env["PYTHONPATH"] = str(ROOT / "generator")
    env["PATH"] = os.path.dirname(sys.executable) + os.pathsep + env.get("PATH", "")
    return env


@pytest.mark.skipif(shutil.which("cmake") is None or shutil.which("ninja") is None, reason="no cmake or ninja")
def test_init_all_configures(tmp_path, capsys):
    """`btgen init all` wrote a project whose targets CMake refuses (`all` is reserved)."""
    assert main(["init", str(tmp_path / "all")]) == 0
    proc = subprocess.run(
        ["cmake", "-S", str(tmp_path / "all"), "-B", str(tmp_path / "build"), "-G", "Ninja",
         f"-Dbtgen_DIR={ROOT / 'cmake'}"],
        capture_output=True, text=True, env=_cmake_env(), timeout=300, check=False,
    )  # fmt: skip
    assert proc.returncode == 0, proc.stderr


# ====================================================================== CMake TREES
@pytest.mark.skipif(shutil.which("cmake") is None or shutil.which("ninja") is None, reason="no cmake or ninja")
def test_a_deleted_tree_library_file_fails_the_next_build(tmp_path):
    """Build, delete the library file that defines the mission's SubTree, build again:
    "ninja: no work to do", exit 0, and the program still ran the deleted tree."""
    (tmp_path / "lib").mkdir()
    (tmp_path / "main.xml").write_text(
        '<root BTCPP_format="4" main_tree_to_execute="Main">\n'
        '  <BehaviorTree ID="Main"><Sequence><SubTree ID="Arm"/></Sequence></BehaviorTree>\n</root>\n'
    )
    tree = '<root BTCPP_format="4"><BehaviorTree ID="{}"><AlwaysSuccess/></BehaviorTree></root>\n'
    (tmp_path / "lib" / "arm.xml").write_text(tree.format("Arm"))
    (tmp_path / "lib" / "other.xml").write_text(tree.format("Other"))
    (tmp_path / "CMakeLists.txt").write_text(
        "cmake_minimum_required(VERSION 3.16)\nproject(t LANGUAGES CXX)\nfind_package(btgen CONFIG REQUIRED)\n"
        "btgen_add_mission(m MISSION main.xml TREES lib)\n"
    )
    build = tmp_path / "build"
    env = _cmake_env()

    def run(*cmd: str) -> subprocess.CompletedProcess:
        return subprocess.run(list(cmd), capture_output=True, text=True, env=env, timeout=600, check=False)

    cfg = run("cmake", "-S", str(tmp_path), "-B", str(build), "-G", "Ninja", f"-Dbtgen_DIR={ROOT / 'cmake'}")
    assert cfg.returncode == 0, cfg.stderr
    header = "btgen/m/main.hpp"  # (the generated header only: the C++ compiler adds nothing here)
    first = run("ninja", "-C", str(build), header)
    assert first.returncode == 0, first.stdout
    assert (build / header).is_file()
    (tmp_path / "lib" / "arm.xml").unlink()
    again = run("ninja", "-C", str(build), header)
    assert again.returncode != 0, again.stdout  # before: "ninja: no work to do", exit 0
    assert f"{tmp_path / 'main.xml'}:2:50: error: SubTree `Arm` does not exist" in again.stdout + again.stderr
    # put back: it generates again
    (tmp_path / "lib" / "arm.xml").write_text(tree.format("Arm"))
    assert run("ninja", "-C", str(build), header).returncode == 0
