"""Every limit of btgen (docs/limits.md): at the limit it works, past it a clear error.

Limits exist so that no input can crash btgen, exhaust its memory or exceed
what BehaviorTree.CPP itself can represent (16-bit node UIDs).
"""

import os
import subprocess
import sys

import pytest

from btgen.diagnostics import UserError
from btgen.frontend import loader as frontend
from btgen.frontend import xmlsource
from btgen.frontend.loader import load_mission
from btgen.interp import scenario as scenario_mod
from btgen.interp.engine import trace_text
from btgen.interp.scenario import parse_scenario, parse_scenario_text
from btgen.ir.lower import lower
from btgen.kb.lint import KB_MAX_FILE_BYTES, lint_kb
from btgen.lang import script
from conftest import ROOT

MODEL = '<TreeNodesModel><Action ID="Act"/></TreeNodesModel>'


def _errors(path):
    with pytest.raises(UserError) as e:
        load_mission(str(path))
    return [str(d) for d in e.value.diagnostics if d.severity == "error"]


def _write(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return p


def test_the_limits_are_the_documented_ones():
    assert frontend.MAX_NODES == 65535
    assert frontend.MAX_INCLUDE_DEPTH == 32
    assert xmlsource.MAX_DEPTH == 256
    assert xmlsource.MAX_FILE_BYTES == 16 * 1024 * 1024
    assert scenario_mod.MAX_SCENARIO_BYTES == 16 * 1024 * 1024
    assert script.MAX_NESTING == 32
    assert script.MAX_DEPTH == 100
    assert KB_MAX_FILE_BYTES == 128 * 1024
    with open(os.path.join(ROOT, "docs", "limits.md"), encoding="utf-8") as f:
        limits = f.read()
    assert limits.startswith("# Limits\n")
    from btgen.ir.data.records import DEFAULT_QUEUE_CAPACITY, DEFAULT_STRING_CAPACITY

    for number in (
        "65,535",
        "256",
        "32",
        "16 MiB",
        "100",
        "128 KiB",
        "2,147,483,647",
        f"{DEFAULT_STRING_CAPACITY} bytes",
        f"{DEFAULT_QUEUE_CAPACITY} elements",
    ):
        assert number in limits, number


# ------------------------------------------------------------------ nodes: 16-bit UIDs
def _many_nodes(calls, leaves):
    """Main: a Sequence of `calls` SubTrees, each a Sequence of `leaves` leaves: 1 + calls * (2 + leaves) nodes."""
    sub = "<Sequence>" + "<AlwaysSuccess/>" * leaves + "</Sequence>"
    main = "<Sequence>" + '<SubTree ID="Leaves"/>' * calls + "</Sequence>"
    return (
        f'<root BTCPP_format="4" main_tree_to_execute="Main"><BehaviorTree ID="Main">{main}</BehaviorTree>'
        f'<BehaviorTree ID="Leaves">{sub}</BehaviorTree></root>\n'
    )


def test_65535_nodes_are_allowed(tmp_path):
    # 1 + 217 * (2 + 300) = 65535
    mission = load_mission(str(_write(tmp_path, "max.xml", _many_nodes(217, 300))))
    program = lower(mission)
    assert len(program.nodes) == 65535
    assert program.nodes[-1].uid == 65535


@pytest.mark.parametrize("cxx", ["c++", "clang++"])
def test_65535_nodes_build_and_run_on_both_engines(tmp_path, monkeypatch, cxx):
    """lower() stopped at 65534 nodes (InternalError) and the engine's static_assert too; clang
    refused the node table from about 10,000 nodes (constexpr step limit: strlen of every name)."""
    import shutil

    from btgen.tools.cppengine import build_cpp

    if shutil.which(cxx) is None:
        pytest.skip(f"{cxx} is not installed")
    monkeypatch.setenv("CXX", cxx)
    mission_path = _write(tmp_path, "max.xml", _many_nodes(217, 300))
    scen = _write(tmp_path, "one.scenario", "ticks 1\n")
    mission = load_mission(str(mission_path))
    expected = trace_text(mission, parse_scenario_text("ticks 1\n"))
    proc = subprocess.run([str(build_cpp(str(mission_path))), str(scen)], capture_output=True, check=False, timeout=300)
    assert (proc.returncode, proc.stderr) == (0, b"")
    assert proc.stdout.decode() == expected
    # Sequences and SubTrees go to RUNNING, SUCCESS and IDLE, leaves to SUCCESS and IDLE; tick and result
    assert expected.count("\n") == 3 * (1 + 2 * 217) + 2 * 217 * 300 + 2


def test_65536_nodes_are_an_error(tmp_path):
    # 1 + 15 * (2 + 4367) = 65536
    p = _write(tmp_path, "over.xml", _many_nodes(15, 4367))
    assert _errors(p) == [
        f"{p}:1:52: error: the main tree expands to 65536 nodes with its SubTrees; "
        f"BehaviorTree.CPP numbers nodes with 16 bits, so at most 65535 are allowed"
    ]


def test_a_subtree_explosion_is_counted_without_building_it(tmp_path):
    """Ten trees each calling the next ten times: 10^10 nodes, reported at once."""
    trees = "".join(
        f'<BehaviorTree ID="T{i}"><Sequence>' + f'<SubTree ID="T{i + 1}"/>' * 10 + "</Sequence></BehaviorTree>"
        for i in range(10)
    )
    trees += '<BehaviorTree ID="T10"><AlwaysSuccess/></BehaviorTree>'
    p = _write(tmp_path, "boom.xml", f'<root BTCPP_format="4" main_tree_to_execute="T0">{trees}</root>\n')
    (err,) = _errors(p)
    assert "nodes with its SubTrees; BehaviorTree.CPP numbers nodes with 16 bits" in err


# ------------------------------------------------------------------ depth
def _nested(depth_of_leaf):
    """One tree whose leaf is at level `depth_of_leaf` (Inverters above it)."""
    d = depth_of_leaf - 1
    return (
        f'<root BTCPP_format="4"><BehaviorTree ID="M">{"<Inverter>" * d}<Act/>{"</Inverter>" * d}'
        f"</BehaviorTree>{MODEL}</root>\n"
    )


def test_xml_nesting_at_the_limit_and_past_it(tmp_path):
    ok = _write(tmp_path, "ok.xml", _nested(254))  # root + BehaviorTree + 254 levels = 256 elements
    load_mission(str(ok))
    bad = _write(tmp_path, "bad.xml", _nested(255))
    assert _errors(bad) == [
        f"{bad}:1:2585: error: elements nested deeper than 256 levels (BehaviorTree.CPP refuses such trees too)"
    ]


def _chain(total, per=100):
    """SubTrees T0 -> T1 -> ... whose expansion puts the leaf exactly at level `total`."""
    trees, remaining, t = [], total, 0
    while remaining > per:
        trees.append((f"T{t}", per - 1, f'<SubTree ID="T{t + 1}"/>'))
        remaining -= per
        t += 1
    trees.append((f"T{t}", remaining - 1, '<Act name="a"/>'))
    body = "".join(
        f'<BehaviorTree ID="{tid}">{"<Inverter>" * d}{inner}{"</Inverter>" * d}</BehaviorTree>'
        for tid, d, inner in trees
    )
    return f'<root BTCPP_format="4" main_tree_to_execute="T0">{body}{MODEL}</root>\n'


def test_expanded_depth_is_bounded_by_the_node_count_alone(tmp_path):
    """A chain of SubTrees nests far deeper than one file may (4800 levels here). It crashed the
    scenario check with a RecursionError; both engines must run it and agree."""
    from btgen.tools.cppengine import build_cpp

    p = _write(tmp_path, "deep.xml", _chain(40 * 120, per=120))
    scen = _write(tmp_path, "s.scenario", "ticks 3\nleaf a RUNNING SUCCESS\n")
    mission = load_mission(str(p))
    assert lower(mission).max_depth == 4800
    proc = subprocess.run(
        [sys.executable, "-m", "btgen", "run", str(p), "--scenario", str(scen)],
        capture_output=True,
        check=False,
        timeout=300,
    )
    assert (proc.returncode, proc.stderr) == (0, b"")
    assert b'4800 Act "a" IDLE -> RUNNING' in proc.stdout and proc.stdout.endswith(b"result SUCCESS\n")
    cpp = subprocess.run([str(build_cpp(str(p))), str(scen)], capture_output=True, check=False, timeout=300)
    assert (cpp.returncode, cpp.stdout, cpp.stderr) == (0, proc.stdout, b"")


def test_script_nesting():
    script.parse_script("x := " + "(" * 32 + "1" + ")" * 32)
    with pytest.raises(script.ScriptSyntaxError) as e:
        script.parse_script("x := " + "(" * 33 + "1" + ")" * 33)
    assert e.value.message == "the expression is nested too deeply (more than 32 levels)"
    with pytest.raises(script.ScriptSyntaxError) as e:
        script.parse_script(" + ".join(["x"] * 150))
    assert e.value.message.startswith("the expression is too deep (")


def test_include_depth(tmp_path):
    for i in range(34):
        nxt = f'<include path="f{i + 1}.xml"/>' if i < 33 else ""
        tree = '<BehaviorTree ID="M"><AlwaysSuccess/></BehaviorTree>' if i == 0 else ""
        _write(tmp_path, f"f{i}.xml", f'<root BTCPP_format="4">{nxt}{tree}</root>\n')
    errors = _errors(tmp_path / "f0.xml")
    assert len(errors) == 1 and errors[0].endswith("error: includes nested deeper than 32 files"), errors


# ------------------------------------------------------------------ file sizes
def _sparse(path, size):
    with open(path, "wb") as f:
        f.truncate(size)
    return path


def test_mission_file_size(tmp_path):
    p = _sparse(tmp_path / "huge.xml", 16 * 1024 * 1024 + 1)
    assert _errors(p) == [f"{p}:1:1: error: file is 16777217 bytes; missions are limited to 16777216 bytes"]


def test_scenario_file_size(tmp_path):
    p = _sparse(tmp_path / "huge.scenario", 16 * 1024 * 1024 + 1)
    with pytest.raises(UserError) as e:
        parse_scenario(str(p))
    assert [str(d) for d in e.value.diagnostics] == [
        f"{p}:1:1: error: file is 16777217 bytes; scenarios are limited to 16777216 bytes"
    ]


def test_scenario_ticks(tmp_path):
    assert parse_scenario_text("ticks 2147483647\n").ticks == 2147483647
    with pytest.raises(UserError) as e:
        parse_scenario_text("ticks 2147483648\n", "s.scenario")
    assert [str(d) for d in e.value.diagnostics] == [
        "s.scenario:1:7: error: ticks 2147483648 is too large (at most 2147483647)"
    ]


def test_knowledge_base_file_size(tmp_path):
    p = _sparse(tmp_path / "huge.dat", KB_MAX_FILE_BYTES + 1)
    errors = [str(d) for d in lint_kb(str(p)) if d.severity == "error"]
    assert errors == [
        f"{p}:1:1: error: file is {KB_MAX_FILE_BYTES + 1} bytes; knowledge base files are limited "
        f"to {KB_MAX_FILE_BYTES} bytes"
    ]
