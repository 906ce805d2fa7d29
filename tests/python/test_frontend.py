"""Front end: secure parsing, positions, structural/semantic checks, exact diagnostics."""

import glob
import inspect
import os
import subprocess
import sys
from pathlib import Path

import pytest

from btgen.diagnostics import Loc, UserError, did_you_mean
from btgen.frontend import xmlsource
from btgen.frontend.loader import load_mission
from btgen.frontend.xsd import mission_xsd
from conftest import CASES, ROOT, case_file, conformance_stems

BAD = os.path.join(ROOT, "tests", "bad_missions")


def btgen(*args, cwd=ROOT):
    return subprocess.run(
        [sys.executable, "-m", "btgen", *args], cwd=cwd, capture_output=True, text=True, timeout=120, check=False
    )


def errors_of(path):
    with pytest.raises(UserError) as e:
        load_mission(path)
    return [str(d) for d in e.value.diagnostics]


def write(tmp_path, text, name="m.xml"):
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return str(p)


MINI = """<root BTCPP_format="4">
  <BehaviorTree ID="Main">
{body}
  </BehaviorTree>
  <TreeNodesModel>
    <Action ID="Say"><input_port name="text" type="std::string"/></Action>
    <Condition ID="IsReady"/>
  </TreeNodesModel>
</root>
"""


@pytest.mark.parametrize("stem", conformance_stems())
def test_conformance_missions_validate(stem):
    m = load_mission(case_file(stem, ".xml"))
    assert m.main_tree in {t.id for t in m.trees}


@pytest.mark.parametrize("path", sorted(glob.glob(os.path.join(ROOT, "missions", "*.xml"))), ids=os.path.basename)
def test_shipped_missions_validate_clean(path):
    # Not even an upgrade note: the missions load on every release btgen follows.
    m = load_mission(path)
    assert [str(w) for w in m.warnings] == []


def _bad_cases():
    return sorted(p for p in glob.glob(os.path.join(BAD, "*.xml")) if os.path.exists(p[:-4] + ".stderr"))


@pytest.mark.parametrize("path", _bad_cases(), ids=os.path.basename)
def test_bad_mission_exact_stderr(path, capsys, monkeypatch):
    from btgen.cli import main

    monkeypatch.chdir(ROOT)
    status = main(["validate", os.path.relpath(path, ROOT)])
    err = capsys.readouterr().err
    expected = Path(path[:-4] + ".stderr").read_text(encoding="utf-8")
    assert err == expected
    assert status == 1


def test_every_bad_mission_has_expected_stderr():
    missing = [
        os.path.basename(p) for p in glob.glob(os.path.join(BAD, "*.xml")) if not os.path.exists(p[:-4] + ".stderr")
    ]
    assert missing == []


def test_deep_nesting_rejected_before_any_recursion(tmp_path):
    depth = 10000
    text = (
        '<root BTCPP_format="4"><BehaviorTree ID="M">'
        + "<Inverter>" * depth
        + "<AlwaysSuccess/>"
        + "</Inverter>" * depth
        + "</BehaviorTree></root>"
    )
    p = write(tmp_path, text)
    # The depth check runs before any recursive walk of the tree: with Python's recursion
    # limit far below the nesting depth, the answer is still the clean error.
    limit = sys.getrecursionlimit()
    sys.setrecursionlimit(len(inspect.stack()) + 200)
    try:
        errs = errors_of(p)
    finally:
        sys.setrecursionlimit(limit)
    prefix = '<root BTCPP_format="4"><BehaviorTree ID="M">'
    col = len(prefix) + 254 * len("<Inverter>") + 1  # root and BehaviorTree are levels 1 and 2
    assert errs == [
        f"{p}:1:{col}: error: elements nested deeper than 256 levels (BehaviorTree.CPP refuses such trees too)"
    ]


def test_huge_file_rejected_without_reading_it(tmp_path):
    p = tmp_path / "huge.xml"
    with open(p, "wb") as f:
        f.write(b'<root BTCPP_format="4"><!--')
        f.write(b"x" * (50 * 1024 * 1024))
        f.write(b"--></root>")
    errs = errors_of(str(p))
    assert errs == [
        f"{p}:1:1: error: file is {os.path.getsize(p)} bytes; missions are limited to {xmlsource.MAX_FILE_BYTES} bytes"
    ]


def _errors_in_a_process_limited_to(path, megabytes):
    """load_mission(path)'s diagnostics from a child process whose address space is capped."""
    code = (
        "import resource, sys\n"
        f"resource.setrlimit(resource.RLIMIT_AS, ({megabytes} << 20, {megabytes} << 20))\n"
        "from btgen.diagnostics import UserError\n"
        "from btgen.frontend.loader import load_mission\n"
        "try:\n    load_mission(sys.argv[1])\n"
        "except UserError as e:\n    print('\\n'.join(str(d) for d in e.diagnostics))\n"
    )
    proc = subprocess.run([sys.executable, "-c", code, path], capture_output=True, text=True, check=False)
    assert proc.returncode == 0, proc.stderr
    return proc.stdout.splitlines()


def test_billion_laughs_rejected_without_expanding(tmp_path):
    ents = "".join(f'<!ENTITY l{i} "{f"&l{i - 1};" * 10}">' for i in range(1, 10))
    p = write(
        tmp_path,
        f'<?xml version="1.0"?>\n<!DOCTYPE root [<!ENTITY l0 "lol">{ents}]>\n'
        f'<root BTCPP_format="4"><BehaviorTree ID="M"><Say text="&l9;"/></BehaviorTree></root>\n',
    )
    # Expanded, &l9; is 3 GB of text: in 256 MiB of address space only a reader that never
    # expands the entities can answer.
    errs = _errors_in_a_process_limited_to(p, 256)
    assert errs == [
        f"{p}:2:1: error: document type declarations are not allowed in a mission "
        f"(entities could expand without bound or read other files)"
    ]


def test_positions_of_attributes_with_entities_and_newlines(tmp_path):
    say_line = '      <Say name="a&amp;b" text="x"/>'
    script_line = '      <Script code="a := 1;&#10;b := a +"/>'
    body = f"    <Sequence>\n{say_line}\n{script_line}\n    </Sequence>"
    p = write(tmp_path, MINI.format(body=body))
    src = xmlsource.read_source(p)
    say = src.root.find("BehaviorTree/Sequence/Say")
    assert src.loc(say) == Loc(p, 4, say_line.index("<Say") + 1)
    assert src.attr_loc(say, "text") == Loc(p, 4, say_line.index("text") + 1)
    assert say.get("name") == "a&b"
    assert src.value_loc(say, "name", 2) == Loc(p, 4, say_line.index('b"') + 1)  # `&amp;` is one character
    script = src.root.find("BehaviorTree/Sequence/Script")
    assert script.get("code")[8] == "b"
    assert src.value_loc(script, "code", 8) == Loc(p, 5, script_line.index("b :=") + 1)


def test_compact_and_explicit_forms_are_the_same_node(tmp_path):
    body = (
        '    <Sequence>\n      <Action ID="Say" text="hi"/>\n      <Say text="hi"/>\n'
        '      <Condition ID="IsReady"/>\n    </Sequence>'
    )
    m = load_mission(write(tmp_path, MINI.format(body=body)))
    kids = m.main.root.children
    assert [(k.id, k.kind, k.display_name) for k in kids] == [
        ("Say", "Action", "Say"),
        ("Say", "Action", "Say"),
        ("IsReady", "Condition", "IsReady"),
    ]


def test_explicit_form_with_wrong_kind(tmp_path):
    # 4.6.2 creates the registered node whatever the element says: a warning, not an error.
    p = write(tmp_path, MINI.format(body='    <Condition ID="Say" text="x"/>'))
    assert [str(w) for w in load_mission(p).warnings] == [
        f"{p}:3:5: warning: `Say` is an Action, but is written <Condition>; it runs as the Action it is"
    ]


def test_all_errors_of_a_file_reported_in_order(tmp_path):
    body = '    <Sequence>\n      <Sey text="x"/>\n      <Say txt="x"/>\n      <Inverter/>\n    </Sequence>'
    p = write(tmp_path, MINI.format(body=body))
    assert errors_of(p) == [
        f"{p}:4:7: error: unknown node `Sey`: it is neither built in nor declared in TreeNodesModel; "
        f"`Say` is declared in TreeNodesModel (did you mean it?)",
        f"{p}:5:12: error: `Say` has no port `txt` (its ports: `text`); did you mean `text`?",
        f"{p}:6:7: error: `Inverter` is a decorator and takes exactly 1 child, but has no children",
    ]


def test_script_error_points_into_the_attribute(tmp_path):
    p = write(tmp_path, MINI.format(body='    <Script code="x := 1 +"/>'))
    errs = errors_of(p)
    assert len(errs) == 1 and errs[0].startswith(f"{p}:3:") and "invalid script in `code` of `Script`" in errs[0]


def test_include_resolved_relative_to_including_file(tmp_path):
    sub = tmp_path / "lib"
    sub.mkdir()
    (sub / "parts.xml").write_text(
        '<root BTCPP_format="4"><BehaviorTree ID="Part"><AlwaysSuccess/></BehaviorTree></root>'
    )
    p = write(
        tmp_path,
        '<root BTCPP_format="4" main_tree_to_execute="Main">\n  <include path="lib/parts.xml"/>\n'
        '  <BehaviorTree ID="Main"><SubTree ID="Part"/></BehaviorTree>\n</root>\n',
    )
    m = load_mission(p)
    assert [t.id for t in m.trees] == ["Main", "Part"] or [t.id for t in m.trees] == ["Part", "Main"]
    assert m.files == (p, os.path.join(str(tmp_path), "lib", "parts.xml"))


def test_model_port_defaults_are_type_checked(tmp_path):
    p = write(
        tmp_path,
        '<root BTCPP_format="4">\n  <BehaviorTree ID="M"><Go/></BehaviorTree>\n  <TreeNodesModel>\n'
        '    <Action ID="Go"><input_port name="speed" type="int" default="fast"/></Action>\n'
        "  </TreeNodesModel>\n</root>\n",
    )
    # A leaf's model documents a node registered in C++: warned about, and not used.
    m = load_mission(p)
    [w] = [str(w) for w in m.warnings]
    assert w.startswith(f"{p}:4:66: warning: default of port `speed` of `Go`: ")
    port = m.spec("Go").port("speed")
    assert port is not None and port.default is None and port.default_problem


def test_did_you_mean():
    assert did_you_mean("SayGoodBye", ["SayGoodByeSpeech", "WelcomeSpeech"]) == "SayGoodByeSpeech"
    assert did_you_mean("IV. VisitLandmark", ["IV. VisitExhibit", "V. EndTour"]) == "IV. VisitExhibit"
    assert did_you_mean("sequence", ["Sequence", "Fallback"]) == "Sequence"
    assert did_you_mean("Zzz", ["Sequence", "Fallback"]) is None


def test_mission_xsd_accepts_its_own_mission(tmp_path):
    import xmlschema

    path = os.path.join(CASES, "robot_lab_tour.xml")
    m = load_mission(path)
    schema = xmlschema.XMLSchema(mission_xsd(m))
    assert schema.is_valid(path)
    bad = Path(path).read_text(encoding="utf-8").replace("<Sequence", '<Sequence bogus="1"', 1)
    assert not schema.is_valid(bad)


def test_cli_exit_codes(tmp_path):
    good = write(tmp_path, MINI.format(body='    <Say text="hi"/>'), "good.xml")
    bad = write(tmp_path, MINI.format(body='    <Sai text="hi"/>'), "bad.xml")
    assert btgen("validate", good).returncode == 0
    r = btgen("validate", good, bad)
    assert r.returncode == 1 and r.stderr.startswith(f"{bad}:3:5: error: unknown node `Sai`")
    assert btgen("validate").returncode == 1
    assert btgen("frobnicate").returncode == 1
    r = btgen("validate", str(tmp_path / "missing.xml"))
    assert (
        r.returncode == 1
        and r.stderr == f"{tmp_path / 'missing.xml'}:1:1: error: cannot read file: No such file or directory\n"
    )


def test_xsd_command_prints_schema(tmp_path):
    good = write(tmp_path, MINI.format(body='    <Say text="hi"/>'))
    r = btgen("xsd", good)
    assert r.returncode == 0
    assert '<xs:element name="Say" type="node.Say" substitutionGroup="bt_node"/>' in r.stdout
    assert '<xs:attribute name="text" type="xs:string"/>' in r.stdout


def test_model_id_that_is_not_an_xml_name(tmp_path):
    """Regression: a TreeNodesModel ID that is not an XML name crashed writing the mission XSD."""
    p = write(
        tmp_path,
        '<root BTCPP_format="4">\n  <BehaviorTree ID="M"><Action ID="IV.Act/1"/></BehaviorTree>\n'
        '  <TreeNodesModel><Action ID="IV.Act/1"/></TreeNodesModel>\n</root>\n',
    )
    m = load_mission(p)
    assert m.main.root.id == "IV.Act/1" and m.main.root.kind == "Action"


def test_literal_on_output_port_is_an_error(tmp_path):
    """4.6.2's setOutput writes nothing through a literal; btgen says so at the attribute."""
    line = '    <LoopInt queue="1;2" value="x"><AlwaysSuccess/></LoopInt>'
    p = write(tmp_path, MINI.format(body=line))
    col = line.index('"x"') + 2
    assert errors_of(p) == [
        f"{p}:3:{col}: error: port `value` of `LoopInt` is an output port "
        f"and must name a blackboard entry as `{{key}}` (or `{{=}}`), not the literal `x`"
    ]


def test_set_blackboard_output_key_names_the_entry(tmp_path):
    p = write(tmp_path, MINI.format(body='    <SetBlackboard value="1" output_key="@count"/>'))
    assert load_mission(p).main.root.port("output_key").value == "@count"


GROOT2 = """<?xml version="1.0" encoding="UTF-8"?>
<root BTCPP_format="4" project_name="Demo" main_tree_to_execute="MainTree">
  <BehaviorTree ID="MainTree" _fullpath="" _description="the main tree">
    <Sequence name="root" _uid="1">
      <Say text="hello" _uid="2" _description="greets the visitor"/>
      <SubTree ID="Sub" _autoremap="true" _fullpath="Sub::3" _uid="3"/>
    </Sequence>
  </BehaviorTree>
  <BehaviorTree ID="Sub"><IsReady{extra}/></BehaviorTree>
  <!-- Description of Node Models (used by Groot) -->
  <TreeNodesModel>
    <Action ID="Say" editable="true">
      <input_port name="text" type="std::string">what to say</input_port>
      <MetadataFields><Metadata subcategory="speech"/><Metadata icon="mouth"/></MetadataFields>
    </Action>
    <Condition ID="IsReady" editable="true"><MetadataFields/></Condition>
  </TreeNodesModel>
</root>
"""


def test_groot2_metadata_is_accepted_and_ignored(tmp_path):
    """Groot2's <MetadataFields> in node models (an internal error before: read as a port) and the
    `_uid` / `_fullpath` / `_description` attributes BehaviorTree.CPP's XML writer and Groot2 add."""
    path = write(tmp_path, GROOT2.format(extra=""))
    m = load_mission(path)
    say = next(s for s in m.models if s.id == "Say")
    assert [p.name for p in say.ports] == ["text"]
    main = next(t for t in m.trees if t.id == "MainTree")
    assert [a.name for a in main.root.children[0].ports] == ["text"]
    assert main.root.children[1].ports == ()  # `_fullpath` is no remapping of the SubTree
    assert f"{path}: ok" in btgen("validate", path).stdout
    assert btgen("xsd", path).returncode == 0


def test_unknown_underscore_attribute_is_ignored_with_a_warning(tmp_path):
    # 4.6.2 ignores every attribute that does not start with a letter (IsAllowedPortName).
    path = write(tmp_path, GROOT2.format(extra=' _descripton="x"'))
    [w] = [str(w) for w in load_mission(path).warnings]
    assert w.endswith(
        "warning: attribute `_descripton` on `IsReady` is ignored, as BehaviorTree.CPP ignores every "
        "attribute not starting with a letter (did you mean `_description`?)"
    ), w


@pytest.mark.parametrize("lead", ["\n", "\n  \n\t "])
def test_xml_declaration_after_blank_lines_loads(tmp_path, lead):
    """tinyxml2 reads a declaration after white space (BehaviorTree.CPP 4.10.0's own test trees
    are raw strings starting with a line break: gtest_blackboard.cpp); recorded on the real
    4.6.2 and 4.10.0: `result SUCCESS`. lxml refused it ("XML declaration allowed only at the
    start"). Positions after it are unchanged; its encoding is still checked."""
    body = '<?xml version="1.0" encoding="UTF-8"?>\n<root BTCPP_format="4">\n  <BehaviorTree ID="Main">\n'
    path = write(tmp_path, lead + body + "    <Nope/>\n  </BehaviorTree>\n</root>\n")
    with pytest.raises(UserError) as e:
        load_mission(path)
    line = lead.count("\n") + 4
    assert str(e.value.diagnostics[0]).startswith(f"{path}:{line}:5: error: unknown node `Nope`")
    path = write(tmp_path, lead + body + "    <AlwaysSuccess/>\n  </BehaviorTree>\n</root>\n")
    assert load_mission(path).main_tree == "Main"
    path = write(tmp_path, lead + body.replace("UTF-8", "latin-1") + "  </BehaviorTree>\n</root>\n")
    with pytest.raises(UserError, match="encoding `latin-1` is not supported"):
        load_mission(path)


def test_an_empty_tree_id_says_so(tmp_path):
    """BehaviorTree.CPP 4.10.0's gtest_factory.cpp tree with `<BehaviorTree ID="">` beside another
    tree (both releases: "The tag <BehaviorTree> must have the attribute [ID]"); btgen said
    "`` is not a valid value for this port" before."""
    path = write(
        tmp_path,
        '<root BTCPP_format="4">\n  <BehaviorTree ID=""><AlwaysSuccess/></BehaviorTree>\n'
        '  <BehaviorTree ID="Other"><AlwaysSuccess/></BehaviorTree>\n</root>\n',
    )
    with pytest.raises(UserError) as e:
        load_mission(path)
    assert [str(d) for d in e.value.diagnostics] == [
        f"{path}:2:17: error: attribute `ID` is empty: it must name the tree or node"
    ]
