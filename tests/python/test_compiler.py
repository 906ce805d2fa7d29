"""The C++ back end in Python: naming, lowering, emission, `btgen compile`, generated/."""

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import cppbuild
from btgen.backend_cpp import literals, naming
from btgen.backend_cpp.emit import render
from btgen.compiler import committed_outputs, compile_command, generate, generator_inputs, main, mission_files
from btgen.diagnostics import UserError
from btgen.frontend.loader import load_mission
from btgen.ir.lower import creation_order, lower
from btgen.pipeline import CompileOptions
from btgen.version import RUNTIME_ABI, __version__
from conftest import CASES, ROOT, case_file, conformance_stems


def _write(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return str(p)


def _mission(body, models='<Action ID="Act"/><Condition ID="Cond"/>', extra=""):
    return (
        f'<root BTCPP_format="4" main_tree_to_execute="Main"><BehaviorTree ID="Main">{body}</BehaviorTree>'
        f"{extra}<TreeNodesModel>{models}</TreeNodesModel></root>\n"
    )


def _col(path, needle):
    """1-based column of `needle` on the first line of the file at `path`."""
    with open(path, encoding="utf-8") as f:
        return f.readline().index(needle) + 1


def _errors(path):
    with pytest.raises(UserError) as e:
        lower(load_mission(path))
    return [str(d) for d in e.value.diagnostics]


# ------------------------------------------------------------------------ naming
@pytest.mark.parametrize(
    "stem,snake,pascal",
    [
        ("LabTour", "lab_tour", "LabTour"),
        ("lab_tour", "lab_tour", "LabTour"),
        ("PickPlaceBall", "pick_place_ball", "PickPlaceBall"),
        ("HTTPServer2", "http_server2", "HttpServer2"),
        ("robot-lab tour", "robot_lab_tour", "RobotLabTour"),
        ("seq_basic", "seq_basic", "SeqBasic"),
        ("01_mission", "01_mission", "Mission_01Mission"),
        ("___", "mission", "Mission"),
    ],
)
def test_file_and_class_names(stem, snake, pascal):
    assert naming.snake_case(stem) == snake
    assert naming.header_name(stem) == snake + ".hpp"
    assert naming.source_name(stem) == snake + ".cpp"
    assert naming.pascal_case(stem) == pascal


def test_namespace_and_guard_are_identifiers():
    assert naming.namespace_name("LabTour") == "lab_tour"
    assert naming.namespace_name("01 go") == "mission_01_go"
    assert naming.include_guard("LabTour") == "BTGEN_GENERATED_LAB_TOUR_HPP"


@pytest.mark.parametrize(
    "text,ident",
    [
        ("FindBall", "FindBall"),
        ("IV. VisitExhibit", "IV_VisitExhibit"),
        ("9lives", "n_9lives"),
        ("_Reserved", "n_Reserved"),
        ("a__b", "a_b"),
        ("class", "class_"),
        ("Ünïcode", "n_n_code"),
        ("", "n"),
    ],
)
def test_cpp_identifier(text, ident):
    assert naming.cpp_identifier(text) == ident
    assert re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*", naming.cpp_identifier(text))


def test_unique_identifiers_disambiguate():
    assert naming.unique_identifiers(["a b", "a-b", "a_b", "Leaf"], taken=["Leaf"]) == (
        "a_b",
        "a_b_2",
        "a_b_3",
        "Leaf_2",
    )


def test_cpp_string_is_ascii_and_exact():
    assert literals.cpp_string('say "hi"\\') == '"say \\"hi\\"\\\\"'
    assert literals.cpp_string("a\nb\tc??=") == '"a\\012b\\011c\\?\\?="'
    assert literals.cpp_string("é") == '"\\303\\251"'
    assert naming.cpp_comment("x\n\\") == "x?"


# ---------------------------------------------------------------------- lowering
def _trace_nodes(stem):
    """(uid, ID, name) of every node the recorded trace of a case mentions."""
    seen = {}
    line_re = re.compile(r'^(\d+) (\S+) "((?:[^"\\]|\\.)*)" [A-Z]+ -> [A-Z]+$')
    with open(case_file(stem, ".trace"), encoding="utf-8") as f:
        for line in f:
            m = line_re.match(line.rstrip("\n"))
            if m:
                name = re.sub(r"\\(.)", r"\1", m.group(3))
                seen[int(m.group(1))] = (m.group(2), name)
    return seen


@pytest.mark.parametrize("stem", conformance_stems())
def test_uids_are_behaviortree_cpp_creation_order(stem):
    order = {uid: (rid, name) for uid, rid, name in creation_order(load_mission(case_file(stem, ".xml")))}
    recorded = _trace_nodes(stem)
    assert recorded, "the trace names no node"
    for uid, (rid, name) in recorded.items():
        assert order.get(uid) == (rid, name), f"UID {uid}"


def test_lowered_table_of_nested_subtrees_matches_the_trace():
    program = lower(load_mission(os.path.join(CASES, "decorators_halted.xml")))
    for uid, (rid, name) in _trace_nodes("decorators_halted").items():
        node = program.nodes[uid - 1]
        assert (node.uid, node.id, node.name) == (uid, rid, name)
    sub = next(n for n in program.nodes if n.kind == "SubTree")
    assert sub.id == "SubTree" and sub.name == "LongJobInstance"
    assert [program.nodes[c].name for c in sub.children] == ["LongTaskSteps"]
    assert program.nodes[sub.children[0]].tree == "LongJob"


def test_lowering_tables(tmp_path):
    path = _write(
        tmp_path,
        "m.xml",
        _mission(
            '<Sequence name="Root"><SubTree ID="Sub" name="S1"/><Repeat num_cycles="3"><Act/></Repeat>'
            '<SubTree ID="Sub" name="S2"/><Timeout msec="250"><Act name="Slow"/></Timeout><RunOnce><Cond/></RunOnce>'
            '<Parallel success_count="-1"><Act/><Act/><Act/></Parallel></Sequence>',
            extra='<BehaviorTree ID="Sub"><Inverter><Cond name="Inner"/></Inverter></BehaviorTree>',
        ),
    )
    p = lower(load_mission(path))
    assert [(n.uid, n.id, n.name) for n in p.nodes][:6] == [
        (1, "Sequence", "Root"),
        (2, "SubTree", "S1"),
        (3, "Inverter", "Inverter"),
        (4, "Cond", "Inner"),
        (5, "Repeat", "Repeat"),
        (6, "Act", "Act"),
    ]
    by_name = {n.name: n for n in p.nodes}
    assert by_name["Repeat"].params == (3, 0, 0)
    assert by_name["Timeout"].params == (250, 0, 0) and by_name["Timeout"].timer >= 0
    assert by_name["RunOnce"].params == (1, 0, 0)  # then_skip defaults to true
    assert by_name["Parallel"].params == (3, 1, 1)  # success_count=-1 of 3 children, failure_count default 1
    assert p.max_depth == 4 and p.has_parallel
    # counter slots do not overlap
    used = []
    for n in p.nodes:
        if n.slot >= 0:
            used.append(n.slot)
    assert len(used) == len(set(used)) and max(used) < p.counter_count
    # each node's children are in the child table at its offset
    for n in p.nodes:
        assert p.child_table[n.child_begin : n.child_begin + len(n.children)] == n.children
        for c in n.children:
            assert p.nodes[c].parent == n.index
    assert [m.id for m in p.actions] == ["Act"] and [m.id for m in p.conditions] == ["Cond"]


def test_parallel_that_can_never_succeed_is_rejected(tmp_path):
    path = _write(tmp_path, "m.xml", _mission('<Parallel success_count="3"><Act/><Act/></Parallel>'))
    col = _col(path, '3"><Act/>')
    assert _errors(path) == [
        f'{path}:1:{col}: error: `Parallel` "Parallel" has 2 children but needs 3 successes (success_count=3): it '
        f"can never succeed (BehaviorTree.CPP throws when it is ticked)"
    ]


def test_skippable_if_condition_compiles(tmp_path):
    # The library throws only on a run where the condition answers SKIPPED (RunOnce: its second
    # run), so the executor does, at run time (tests/conformance/both-releases).
    path = _write(tmp_path, "m.xml", _mission("<IfThenElse><RunOnce><Cond/></RunOnce><Act/></IfThenElse>"))
    lower(load_mission(path))


def test_loop_counts_and_durations_read_from_the_blackboard(tmp_path):
    # `{key}` for num_cycles, num_attempts, msec and delay_msec: read when 4.6.2 reads it
    # (tests/regressions/key_loop_counts_and_durations runs it on both engines).
    path = _write(
        tmp_path,
        "m.xml",
        _mission(
            '<Sequence>\n<Script code="n := 2"/>\n<Repeat num_cycles="{n}"><Act/></Repeat>\n'
            '<SubTree ID="Sub"/><SubTree ID="Sub"/></Sequence>',
            extra='<BehaviorTree ID="Sub"><Sleep msec="{n}"/></BehaviorTree>',
        ),
    )
    header, _ = generate(path)
    assert header.text.count('// Repeat "Repeat" num_cycles={n}') == 1
    assert header.text.count('// Sleep "Sleep" msec={n}') == 2  # one per instance of Sub


def test_key_count_from_a_text_entry_compiles_and_a_status_one_is_refused(tmp_path):
    """getInput<int> of a string entry parses it (conformance: o2_count_casts); an entry holding
    a NodeStatus is still refused, with the kinds the C++ back end reads."""
    for port_type, refused in (("std::string", False), ("BT::NodeStatus", True)):
        path = _write(
            tmp_path,
            "m.xml",
            _mission(
                '<Sequence><Get out="{n}"/><Repeat num_cycles="{n}"><Act/></Repeat></Sequence>',
                models=f'<Action ID="Act"/><Action ID="Get"><output_port name="out" type="{port_type}"/></Action>',
            ),
        )
        if not refused:
            program = lower(load_mission(path))
            assert any(c.op.kind == "string" for c in program.data.param_reads)
            continue
        # (the library refuses this one too, at load: a NodeStatus entry read as int)
        [err] = [e for e in _errors(path) if "C++ back end" in e]
        assert err.startswith(f'{path}:1:122: error: port `num_cycles` of `Repeat` "Repeat" reads `n` ('), err
        assert err.endswith(
            "the C++ back end reads it from an int, bool, double or string entry, or one whose type changes"
        )


# ---------------------------------------------------------------------- emission
def test_generation_is_deterministic(tmp_path):
    mission = os.path.join(ROOT, "tests", "cpp", "missions", "control_flow.xml")
    first = generate(mission, relative_to=ROOT)
    second = generate(mission, relative_to=ROOT)
    assert [(o.name, o.text) for o in first] == [(o.name, o.text) for o in second]
    # and through the command line, into two directories, byte for byte
    for d in ("a", "b"):
        subprocess.run(
            [sys.executable, "-m", "btgen", "compile", mission, "-o", str(tmp_path / d), "--relative-to", ROOT],
            check=True,
            cwd=str(tmp_path),
        )
    for name in ("control_flow.hpp", "control_flow.cpp"):
        assert (tmp_path / "a" / name).read_bytes() == (tmp_path / "b" / name).read_bytes()
        assert (tmp_path / "a" / name).read_text() == dict((o.name, o.text) for o in first)[name]


def test_banner_abi_and_shape_of_the_header():
    mission = os.path.join(ROOT, "tests", "cpp", "missions", "control_flow.xml")
    header, source = generate(mission, relative_to=ROOT)
    assert header.text.startswith(
        f"// control_flow.hpp: generated by btgen {__version__} from tests/cpp/missions/control_flow.xml\n"
    )
    assert source.text.startswith(f"// control_flow.cpp: generated by btgen {__version__} from ")
    assert f"static_assert(btgen::kRuntimeAbi == {RUNTIME_ABI}," in header.text
    runtime = (Path(ROOT) / "runtime" / "include" / "btgen" / "version.hpp").read_text()
    assert f"inline constexpr int kRuntimeAbi = {RUNTIME_ABI};" in runtime
    assert (
        "template <class Leaves, class Clock = btgen::SteadyClock, class Observer = btgen::NoObserver>\n"
        "class ControlFlow : public btgen::Engine<detail::Spec, Leaves, Clock, Observer>" in header.text
    )
    # the class of virtual hooks: a line per model (btgen/mission_base.hpp)
    assert "class ControlFlowLeaves : public btgen::VirtualLeaves {" in header.text
    assert "  BTGEN_VIRTUAL_ACTION(leaf::Move);\n" in header.text
    assert "  BTGEN_VIRTUAL_CONDITION(leaf::IsDone);\n" in header.text
    # the contract right under the banner, before the include guard
    contract = header.text.index("// What your `Leaves` implements")
    assert contract < header.text.index("#ifndef ") and "check(leaf::C&, const btgen::NodeInfo&)" in header.text
    assert "/work/" not in header.text and "/tmp/" not in header.text  # no absolute paths
    assert "template class btgen::Engine<control_flow::detail::Spec, control_flow::ControlFlowLeaves" in source.text


def test_names_in_tables_are_escaped(tmp_path):
    path = _write(
        tmp_path,
        "odd name.xml",
        _mission('<Sequence name="say &quot;hi&quot;&#10;\\"><IV.Act-2/></Sequence>', models='<Action ID="IV.Act-2"/>'),
    )
    header, _ = render(lower(load_mission(path)), "odd name", str(tmp_path))
    assert header.name == "odd_name.hpp"
    assert '"say \\"hi\\"\\012\\\\"' in header.text
    assert "class IV_Act_2 : public btgen::ModelBase<" in header.text and 'kId = "IV.Act-2"' in header.text


# --------------------------------------------------------------- btgen compile
# `a` and `b` only copied from each other: the C++ back end cannot tell their type
CYCLE = (
    '<Sequence><Act/><SetBlackboard output_key="a" value="{b}"/><SetBlackboard output_key="b" value="{a}"/></Sequence>'
)


class _Args:
    def __init__(self, mission, out, rel=None):
        self.mission, self.output_dir, self.relative_to = mission, out, rel


def test_compile_writes_only_what_changed_and_nothing_on_error(tmp_path):
    good = _write(tmp_path, "m.xml", _mission("<Sequence><Act/><Cond/></Sequence>"))
    out = tmp_path / "out"
    assert compile_command(_Args(good, str(out))) == 0
    hpp, cpp = out / "m.hpp", out / "m.cpp"
    before = (hpp.read_bytes(), cpp.read_bytes())
    os.utime(hpp, (1_000_000, 1_000_000))
    assert compile_command(_Args(good, str(out))) == 0
    assert hpp.stat().st_mtime == 1_000_000  # unchanged: not rewritten
    # A mission that fails leaves the previous outputs byte-identical and writes no temporary file.
    Path(good).write_text(_mission(CYCLE))
    with pytest.raises(UserError):
        compile_command(_Args(good, str(out)))
    assert (hpp.read_bytes(), cpp.read_bytes()) == before
    assert sorted(p.name for p in out.iterdir()) == ["m.cpp", "m.hpp"]
    Path(good).write_text(_mission("<Sequence><Act/><Cond/><Cond/></Sequence>"))
    assert compile_command(_Args(good, str(out))) == 0
    assert hpp.read_bytes() != before[0]


def test_cli_compile_reports_errors_with_exit_1(tmp_path):
    # (a read of an entry nothing creates is a warning now: the library throws only when it runs)
    bad = _write(
        tmp_path,
        "bad.xml",
        _mission(CYCLE),
    )
    proc = subprocess.run(
        [sys.executable, "-m", "btgen", "compile", bad, "-o", str(tmp_path / "o")],
        capture_output=True,
        text=True,
        cwd=str(tmp_path),
        check=False,
    )
    assert proc.returncode == 1
    untyped = "every write copies another entry of unknown type; write it with a literal first"
    col_b, col_a = _col(bad, 'value="{a}"') + 7, _col(bad, 'value="{b}"') + 7
    assert proc.stderr == (
        f"{bad}:1:{col_b}: error: cannot tell the type of blackboard entry `b`: {untyped}\n"
        f"{bad}:1:{col_a}: error: cannot tell the type of blackboard entry `a`: {untyped}\n"
    )
    assert not (tmp_path / "o").exists()


def test_deps_outputs_and_inputs_for_build_systems(tmp_path):
    (tmp_path / "sub").mkdir()
    _write(
        tmp_path,
        "sub/lib.xml",
        '<root BTCPP_format="4"><BehaviorTree ID="Lib"><Act/></BehaviorTree>'
        '<TreeNodesModel><Action ID="Act"/></TreeNodesModel></root>\n',
    )
    main_xml = _write(
        tmp_path,
        "Main.xml",
        '<root BTCPP_format="4" main_tree_to_execute="Main">'
        '<include path="sub/lib.xml"/><BehaviorTree ID="Main">'
        '<SubTree ID="Lib"/></BehaviorTree></root>\n',
    )
    assert mission_files(main_xml) == [os.path.abspath(main_xml), str(tmp_path / "sub" / "lib.xml")]
    inputs = generator_inputs()
    assert any(p.endswith("lower.py") for p in inputs) and any(p.endswith("mission.hpp.j2") for p in inputs)
    assert any(p.endswith(".xsd") for p in inputs)
    for argv, expected in (
        (["--outputs", main_xml], "main.hpp\nmain.cpp\n"),
        (["--outputs", main_xml, "--cmake"], "main.hpp;main.cpp"),
        (["--template", main_xml], "main_::Main\n"),
    ):
        proc = subprocess.run(
            [sys.executable, "-m", "btgen.compiler", *argv], stdout=subprocess.PIPE, text=True, check=True
        )
        assert proc.stdout == expected
    assert main(["--check", main_xml]) == 0


# ------------------------------------------------------------------- generated/
def test_committed_generated_matches_a_fresh_run():
    """generated/ holds exactly what `python -m btgen.compiler --update-generated` writes."""
    root = Path(ROOT)
    expected = committed_outputs(root)
    present = {
        p.name: p.read_text(encoding="utf-8") for p in (root / "generated").glob("*") if p.suffix in (".hpp", ".cpp")
    }
    assert sorted(present) == sorted(expected), "run `python -m btgen.compiler --update-generated`"
    for name, text in expected.items():
        assert present[name] == text, f"generated/{name} is stale: run `python -m btgen.compiler --update-generated`"


def test_committed_generated_compiles_warning_free(tmp_path):
    root = Path(ROOT)
    sources = sorted((root / "generated").glob("*.cpp"))
    if not sources:
        pytest.skip("no shipped mission compiles on the C++ back end yet")
    for src in sources:
        cppbuild.syntax_check([src], cxx="c++", includes=[root / "generated"])


@pytest.mark.parametrize("compiler", ["g++", "clang++"])
@pytest.mark.parametrize(
    "stem",
    [
        "script_expressions",
        "robot_lab_tour",
        "loop_double_string",
        "entry_updated",
        "unset_blackboard",
        "root_blackboard_at",
        "pick_and_place",
        "post_conditions",
    ],
)
def test_data_side_code_compiles_warning_free(stem, compiler, tmp_path):
    """Scripts, ports, slots and the data nodes' functions: no warning with either compiler."""
    if shutil.which(compiler) is None:
        pytest.skip(f"no {compiler}")
    for out in generate(os.path.join(CASES, stem + ".xml"), relative_to=ROOT):
        (tmp_path / out.name).write_text(out.text, encoding="utf-8")
    cppbuild.syntax_check(
        [tmp_path / (naming.snake_case(stem) + ".cpp")], cxx=compiler, flags=["-Wshadow"], includes=[tmp_path]
    )


def test_generated_code_refuses_a_runtime_of_another_abi(tmp_path):
    mission = os.path.join(ROOT, "tests", "cpp", "missions", "timing.xml")
    header, source = generate(mission, relative_to=ROOT)
    (tmp_path / header.name).write_text(header.text)
    (tmp_path / source.name).write_text(source.text)
    runtime = tmp_path / "runtime"
    shutil.copytree(Path(ROOT) / "runtime" / "include", runtime)
    cmd = cppbuild.command(
        [tmp_path / source.name], cxx="c++", mode="syntax", warnings=False, runtime=False, includes=[runtime, tmp_path]
    )
    cppbuild.check(cmd)  # the matching runtime compiles
    version = runtime / "btgen" / "version.hpp"
    version.write_text(
        version.read_text().replace(f"kRuntimeAbi = {RUNTIME_ABI};", f"kRuntimeAbi = {RUNTIME_ABI + 1};")
    )
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, check=False)
    assert proc.returncode != 0
    assert "regenerate it with the btgen that matches your runtime headers" in proc.stdout


@pytest.mark.parametrize("compiler", ["g++", "clang++"])
def test_every_declared_leaf_port_has_accessors(compiler, tmp_path):
    """A model's ports get their getter/setter whether or not the mission sets them:
    the same leaf code builds against tests/cpp/missions/leaf_api_{wired,unwired}.xml."""
    if shutil.which(compiler) is None:
        pytest.skip(f"no {compiler}")
    header, source = generate(os.path.join(ROOT, "tests", "cpp", "missions", "leaf_api_unwired.xml"), relative_to=ROOT)
    for accessor in (
        "btgen::Input<std::string_view> target() const",
        "btgen::Input<std::int32_t> retries() const",
        "bool set_retries(std::int32_t value) const",
        "bool set_error_code(std::int32_t value) const",
        "bool set_pose(const T& value) const",
    ):
        assert accessor in header.text
    # A model no node uses has no class (a palette of 600 cost g++ 45 s): `Unused`.
    assert "threshold() const" not in header.text and "class Unused" not in header.text
    assert "error_code() const" not in header.text  # an output port has no getter, as in 4.6.2
    (tmp_path / header.name).write_text(header.text, encoding="utf-8")
    (tmp_path / source.name).write_text(source.text, encoding="utf-8")
    cppbuild.syntax_check([tmp_path / source.name], cxx=compiler, flags=["-Wshadow"], includes=[tmp_path])


@pytest.mark.parametrize("compiler", ["g++", "clang++"])
def test_user_controls_and_decorators_compile(compiler, tmp_path):
    """A Control or Decorator of TreeNodesModel gets a model class with typed ports and child
    operations and a tick()/halt() hook; it used to be an internal error."""
    if shutil.which(compiler) is None:
        pytest.skip(f"no {compiler}")
    header, source = generate(os.path.join(ROOT, "tests", "cpp", "missions", "user_nodes.xml"), relative_to=ROOT)
    for text in (
        "public btgen::ControlModelBase<detail::Blackboard, btgen::LeafKind::Control> {",
        "public btgen::ControlModelBase<detail::Blackboard, btgen::LeafKind::Decorator> {",
        "btgen::Input<std::int32_t> number_of_retries() const",
        "btgen::Input<double> hz() const",
        "using ControlModelBase::ControlModelBase;",
        "namespace control = leaf;",
        "BTGEN_VIRTUAL_USER_NODE(control::RecoveryNode);",
        "NodeKind::UserControl",
        "NodeKind::UserDecorator",
    ):
        assert text in header.text, text
    (tmp_path / header.name).write_text(header.text, encoding="utf-8")
    (tmp_path / source.name).write_text(source.text, encoding="utf-8")
    cppbuild.syntax_check([tmp_path / source.name], cxx=compiler, flags=["-Wshadow"], includes=[tmp_path])


@pytest.mark.parametrize("engine", ["interp", "cpp"])
def test_run_of_a_user_control_says_it_needs_an_implementation(engine, tmp_path):
    mission = _write(
        tmp_path,
        "m.xml",
        _mission(
            "<Sequence><PipelineSequence><AlwaysSuccess/></PipelineSequence></Sequence>",
            models='<Control ID="PipelineSequence"/>',
        ),
    )
    scenario = tmp_path / "m.scenario"
    scenario.write_text("ticks 1\n", encoding="utf-8")
    proc = subprocess.run(
        [sys.executable, "-m", "btgen", "run", str(mission), "--scenario", str(scenario), "--engine", engine],
        capture_output=True,
        text=True,
        cwd=str(tmp_path),
        check=False,
    )
    assert proc.returncode == 1, proc.stderr
    assert re.search(
        r"m\.xml:\d+:\d+: error: `PipelineSequence` is a Control of this mission's TreeNodesModel: it "
        r"needs your implementation",
        proc.stderr,
    ), proc.stderr
    assert "Traceback" not in proc.stderr
    compiled = subprocess.run(
        [sys.executable, "-m", "btgen", "compile", str(mission), "-o", str(tmp_path / "out")],
        capture_output=True,
        text=True,
        cwd=str(tmp_path),
        check=False,
    )
    assert compiled.returncode == 0, compiled.stderr


@pytest.mark.skipif(shutil.which("clang++") is None and not os.environ.get("CI"), reason="clang++ is not installed")
def test_a_groot2_tree_text_over_64_kib_builds_with_clang_pedantic(tmp_path):
    """The Groot2 tree XML of a 1,000-node mission is a string literal of 130 KB, past the
    65,536 characters C++ compilers must accept: clang -Wpedantic -Werror refused it."""
    mission = Path(ROOT) / "bench" / "missions" / "scripts_1000.xml"
    from btgen.cli import main as btgen_main

    assert btgen_main(["compile", str(mission), "-o", str(tmp_path)]) == 0
    (tmp_path / "t.cpp").write_text('#include "scripts_1000.hpp"\nint main() { return 0; }\n')
    cppbuild.syntax_check([tmp_path / "t.cpp"], cxx="clang++", includes=[tmp_path])


def test_error_places_and_messages_are_sized_string_views(tmp_path):
    """kWhere and the scripts' error messages are `"..."sv` literals, whose length the compiler
    gives: read as plain literals, their strlen in constant evaluation went past clang's step
    limit on a 10,000-node script mission (bench/missions/scripts_10000.xml did not build with
    clang++)."""
    import re

    from btgen.backend_cpp.emit import render
    from btgen.frontend.loader import load_mission
    from btgen.ir.lower import lower
    from btgen.tools import synth

    path = tmp_path / "scripts_40.xml"
    path.write_text(synth.script_mission(40))
    header = render(lower(load_mission(str(path))), "scripts_40")[0].text
    where = header[header.index("kWhere = {") : header.index("};", header.index("kWhere = {"))]
    errors = header[header.index("kScriptErrors = {") : header.index("};", header.index("kScriptErrors = {"))]
    # (the literal may be split into adjacent pieces over several lines)
    literal = r'(?:\s*"(?:[^"\\]|\\[0-7]{3}|\\["\\])*")+'
    rows = {
        "kWhere": len([line for line in where.splitlines()[1:] if line.strip()]),
        # (a message left empty, `{}`, is written at run time by a dynamic operation)
        "kScriptErrors": len([line for line in errors.splitlines() if "ScriptError{" in line and "{}}" not in line]),
    }
    for name, block in (("kWhere", where), ("kScriptErrors", errors)):
        assert rows[name] >= 1 and len(re.findall(literal + "sv", block)) == rows[name], name
        assert '"' not in re.sub(literal + "sv", "", block), name  # no literal left unsized


def test_models_and_ports_named_like_the_leaf_base_classes_compile(tmp_path):
    """Leaf classes derive from btgen::ModelBase / ControlModelBase and name them unqualified
    (`using ModelBase::ModelBase;`): a model or port of that name is renamed, not a clash."""
    models = (
        '<Action ID="ModelBase"><input_port name="ControlModelBase" type="int"/>'
        '<input_port name="ops_" type="int"/></Action>'
        '<Control ID="ControlModelBase"><input_port name="ModelBase" type="int"/></Control>'
    )
    body = '<ControlModelBase ModelBase="1"><ModelBase ControlModelBase="2" ops_="3"/></ControlModelBase>'
    path = _write(tmp_path, "bases.xml", _mission(body, models=models))
    header, source = generate(path, relative_to=str(tmp_path))
    (tmp_path / header.name).write_text(header.text, encoding="utf-8")
    (tmp_path / source.name).write_text(source.text, encoding="utf-8")
    cppbuild.syntax_check([tmp_path / source.name], cxx="g++", flags=["-Wshadow"], includes=[tmp_path])


def test_long_literals_are_split_between_words():
    """A message spread over adjacent literals is cut after a space, never inside a word, so
    grepping the header for a word of a message seen in a log finds it; only a word longer
    than the width is cut. The literals still join to exactly the text."""
    from btgen.backend_cpp.literals import cpp_string, cpp_string_chunks

    text = "the left operand of `+` has no value (an entry nothing writes: é\n) " * 3 + "x" * 50
    chunks = cpp_string_chunks(text, 40)
    assert "".join(c[1:-1] for c in chunks) == cpp_string(text)[1:-1]
    assert all(len(c) <= 40 for c in chunks)
    assert all(c.endswith(' "') for c in chunks[:-3]), chunks
    for path in sorted((Path(ROOT) / "generated").glob("*.hpp")):
        header = path.read_text(encoding="utf-8")
        assert not re.search(r'[A-Za-z0-9_]"\s*\n\s*"[A-Za-z0-9_]', header), path.name


def test_no_message_of_a_big_mission_is_split_inside_a_word(tmp_path):
    """The same over the literals of a mission with many script and port error messages."""
    from btgen.tools import synth

    path = tmp_path / "scripts_40.xml"
    path.write_text(synth.script_mission(40))
    header = render(lower(load_mission(str(path))), "scripts_40")[0].text
    assert header.count('"\n') > 40  # (messages spread over several lines are there)
    assert not re.search(r'[A-Za-z0-9_]"\s*\n\s*"[A-Za-z0-9_]', header)


def test_deps_keep_an_include_that_stopped_loading(tmp_path, capsys):
    """When an include stopped loading, `build-info --deps` fell back to the mission alone:
    the include left DEPENDS and CMAKE_CONFIGURE_DEPENDS and the build kept the old header."""
    (tmp_path / "sub").mkdir()
    lib = _write(tmp_path, "sub/lib.xml", '<root BTCPP_format="4"><BehaviorTree ID="Lib"><Act/></BehaviorTree>')
    main_xml = _write(
        tmp_path,
        "Main.xml",
        '<root BTCPP_format="4" main_tree_to_execute="Main">'
        '<include path="sub/lib.xml"/><BehaviorTree ID="Main">'
        '<SubTree ID="Lib"/></BehaviorTree></root>\n',
    )
    models = _write(tmp_path, "models.xml", "<root><TreeNodesModel>")  # does not load either
    assert mission_files(main_xml, CompileOptions(models=(models,))) == [os.path.abspath(main_xml), lib, models]
    capsys.readouterr()
    assert main(["--deps", main_xml, "--models", models, "--cmake"]) == 0
    assert capsys.readouterr().out == f"{os.path.abspath(main_xml)};{lib};{models}"


def test_deps_that_a_cmake_list_cannot_hold(tmp_path, capsys):
    """An include under `x;y/` broke the generated build rules with a ninja error about a
    file that does not exist; now build-info says why, at the file."""
    (tmp_path / "x;y").mkdir()
    lib = _write(
        tmp_path,
        "x;y/lib.xml",
        '<root BTCPP_format="4"><BehaviorTree ID="Lib"><AlwaysSuccess/></BehaviorTree></root>',
    )
    main_xml = _write(
        tmp_path,
        "Main.xml",
        '<root BTCPP_format="4" main_tree_to_execute="Main"><include path="x;y/lib.xml"/>'
        '<BehaviorTree ID="Main"><SubTree ID="Lib"/></BehaviorTree></root>\n',
    )
    capsys.readouterr()
    assert main(["--deps", main_xml, "--cmake"]) == 1
    assert capsys.readouterr().err == (
        f"{lib}:1:1: error: the path holds `;`, which a CMake list cannot hold; "
        "btgen_add_mission cannot depend on it (rename it)\n"
    )
    assert main(["--deps", main_xml]) == 0  # (one per line: any path)


# ------------------------------------------------- templates that fail loudly (issue 45)
class Mystery:
    """A data operation no template knows."""


def test_a_template_fails_at_its_line_on_an_unknown_operation(tmp_path):
    """A data operation the templates have no C++ for is an InternalError naming the template
    file and line and the operation, never code that quietly returns SUCCESS (the SetBlackboard
    dispatcher used to fall through to `return btgen::Status::SUCCESS;`)."""
    import dataclasses

    from btgen.diagnostics import InternalError

    path = _write(tmp_path, "m.xml", _mission('<Sequence><SetBlackboard output_key="k" value="1"/><Act/></Sequence>'))
    program = lower(load_mission(path))
    assert program.data is not None and program.data.data_leaves
    header, _ = render(program, "m", str(tmp_path))  # as lowered: renders
    assert "case 1: {  // " in header.text
    leaf = program.data.data_leaves[0]
    broken = dataclasses.replace(
        program, data=dataclasses.replace(program.data, data_leaves=(dataclasses.replace(leaf, op=Mystery()),))
    )
    with pytest.raises(InternalError) as e:
        render(broken, "m", str(tmp_path))
    message = str(e.value)
    lines = (Path(ROOT) / "templates" / "_data.j2").read_text(encoding="utf-8").splitlines()
    m = re.match(
        r"templates/_data\.j2:([0-9]+): the templates have no C\+\+ for the SetBlackboard/UnsetBlackboard "
        r"operation `Mystery`$",
        message,
    )
    assert m, message
    assert "unknown(" in lines[int(m.group(1)) - 1]  # the line that refused it


def test_an_undefined_name_in_a_template_is_located(tmp_path):
    """StrictUndefined's error (a template naming what the context lacks) is located too."""
    import jinja2

    from btgen.backend_cpp.emit import render_template
    from btgen.diagnostics import InternalError

    (tmp_path / "t.j2").write_text("line one\n{{ nothing_here }}\n", encoding="utf-8")
    env = jinja2.Environment(loader=jinja2.FileSystemLoader(str(tmp_path)), undefined=jinja2.StrictUndefined)
    with pytest.raises(InternalError, match=r"t\.j2:2: 'nothing_here' is undefined"):
        render_template(env, "t.j2", {})
