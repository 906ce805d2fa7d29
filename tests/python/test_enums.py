"""Scripting enums (`--enum`, `--enums FILE`; BehaviorTree.CPP's registerScriptingEnum):
the same values on both engines, undeclared names still errors in validate and compile."""

import subprocess
import sys

import pytest

import cppbuild
from btgen.diagnostics import UserError
from btgen.frontend import enums

MISSION = """<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence>
      <Script code="color := GREEN; name := 'BLUE'; big := LARGE"/>
      <ScriptCondition code="color == 1 &amp;&amp; name == 2 &amp;&amp; big == 7 &amp;&amp; color != RED"/>
      <Script code="msg := 'c=' .. color .. ' ' .. (name == BLUE)"/>
      <Fallback>
        <ScriptCondition code="color == RED"/>
        <ScriptCondition code="size := SMALL; size == 5"/>
      </Fallback>
    </Sequence>
  </BehaviorTree>
</root>
"""
ENUMS = ["--enum", "Color=RED,GREEN,BLUE", "--enum", "Size=SMALL=5,MEDIUM,LARGE"]


def _btgen(*args, cwd):
    return subprocess.run(
        [sys.executable, "-m", "btgen", *args], cwd=str(cwd), capture_output=True, text=True, check=False
    )


@pytest.mark.parametrize(
    "text, table",
    [
        ("Color=RED,GREEN,BLUE", [("RED", 0), ("GREEN", 1), ("BLUE", 2)]),
        ("Size = SMALL=5, MEDIUM ,LARGE", [("SMALL", 5), ("MEDIUM", 6), ("LARGE", 7)]),
        ("M=A=-1,B,C=0x10,D", [("A", -1), ("B", 0), ("C", 16), ("D", 17)]),
    ],
)
def test_declarations_number_as_register_scripting_enum(text, table):
    assert enums.parse_declaration(text) == table


@pytest.mark.parametrize(
    "text, message",
    [
        ("RED,GREEN", "is not an enum declaration"),
        ("Color=RED,2X", "`2X` in enum `Color` is not a name"),
        ("Color=RED=x", "the value of `RED` in enum `Color` is not an integer"),
        ("Color=RED=4294967296", "does not fit an int"),
        # int() takes these; no C++ enum declaration spells them
        ("Color=RED=1_000", "the value of `RED` in enum `Color` is not an integer: `1_000`"),
        # (found by scripts/fuzz_frontend.py: int -> str refuses past 4,300 digits)
        ("Color=RED=0x" + "f" * 4400, "the value of `RED` \\(0xfff"),
        ("Color=RED=\u0665", "the value of `RED` in enum `Color` is not an integer: `\u0665`"),
        ("Color=RED=\uff11\uff12", "the value of `RED` in enum `Color` is not an integer: `\uff11\uff12`"),
    ],
)
def test_bad_declarations(text, message):
    with pytest.raises(enums.EnumSyntaxError, match=message):
        enums.parse_declaration(text)


def test_a_name_with_two_values_is_an_error(tmp_path):
    f = tmp_path / "e.enums"
    f.write_text("# enums\nColor=RED,GREEN\n  Light=GREEN=5\n", encoding="utf-8")
    with pytest.raises(UserError) as e:
        enums.load(files=[str(f)])
    assert str(e.value) == f"{f}:3:3: error: enum value `GREEN` is declared twice, as 1 and as 5"
    f.write_text("Color=RED,\n", encoding="utf-8")
    with pytest.raises(UserError) as e:
        enums.load(files=[str(f)])
    assert str(e.value).startswith(f"{f}:1:11: error: ")


def test_an_enums_file_with_a_byte_order_mark(tmp_path):
    # (the BOM was read as part of the first declaration's type name, and quoted invisibly)
    f = tmp_path / "e.enums"
    f.write_bytes(b"\xef\xbb\xbfColor=RED,GREEN\n")
    assert enums.load(files=[str(f)]) == (("RED", 0), ("GREEN", 1))
    f.write_bytes(b"Color=RED,GREEN\n# caf\xe9\n")
    with pytest.raises(UserError) as e:
        enums.load(files=[str(f)])
    assert str(e.value) == f"{f}:2:6: error: invalid UTF-8 (byte 0xe9); enums files must be UTF-8"
    with pytest.raises(UserError) as e:
        enums.load(files=[str(tmp_path)])
    assert str(e.value) == f"{tmp_path}:1:1: error: is a directory, not an enums file"


def test_both_engines_give_the_same_trace_with_enums(tmp_path):
    (tmp_path / "m.xml").write_text(MISSION, encoding="utf-8")
    (tmp_path / "m.scenario").write_text("ticks 1\n", encoding="utf-8")
    runs = [
        _btgen("run", "m.xml", "--scenario", "m.scenario", "--engine", e, *ENUMS, cwd=tmp_path)
        for e in ("interp", "cpp")
    ]
    for r in runs:
        assert r.returncode == 0, r.stderr
        assert "result SUCCESS" in r.stdout
    assert runs[0].stdout == runs[1].stdout
    # The enums file gives the same.
    (tmp_path / "m.enums").write_text(
        "Color=RED,GREEN,BLUE  # as registerScriptingEnums<Color>\nSize=SMALL=5,MEDIUM,LARGE\n", encoding="utf-8"
    )
    r = _btgen("run", "m.xml", "--scenario", "m.scenario", "--engine", "cpp", "--enums", "m.enums", cwd=tmp_path)
    assert (r.returncode, r.stdout) == (0, runs[0].stdout)


def test_undeclared_names_are_warnings_in_validate_and_compile(tmp_path):
    """An undeclared name is an entry nothing creates: BehaviorTree.CPP loads the mission and
    throws when the script runs, and so do both engines (issue 44); both commands say where."""
    (tmp_path / "m.xml").write_text(MISSION, encoding="utf-8")
    assert _btgen("validate", "m.xml", *ENUMS, cwd=tmp_path).returncode == 0
    v = _btgen("validate", "m.xml", "--enum", "Color=RED,GREEN,BLUE", cwd=tmp_path)
    c = _btgen("compile", "m.xml", "-o", "out", "--enum", "Color=RED,GREEN,BLUE", cwd=tmp_path)
    assert v.returncode == c.returncode == 0
    assert v.stderr == c.stderr
    assert "warning: " in v.stderr and "reads `LARGE`, but nothing creates that blackboard entry" in v.stderr
    assert "GREEN" not in v.stderr


def test_compiled_to_constants(tmp_path):
    (tmp_path / "m.xml").write_text(MISSION, encoding="utf-8")
    r = _btgen("compile", "m.xml", "-o", "out", *ENUMS, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    header = (tmp_path / "out" / "m.hpp").read_text(encoding="utf-8")
    assert 'btgen::dyn::ScriptingEnum{"LARGE", 7.0}' in header
    cppbuild.syntax_check([tmp_path / "out" / "m.cpp"], cxx="c++", includes=[tmp_path / "out"])


def test_a_negated_negative_enum_builds_and_agrees(tmp_path):
    # `-NEG` once generated `--1.0`: C++ has no negative literals, so the constant must compose
    # as a primary expression after any operator.
    (tmp_path / "m.xml").write_text(
        """<root BTCPP_format="4" main_tree_to_execute="M">
  <BehaviorTree ID="M">
    <Sequence>
      <Script code="x := -NEG; y := 1 + -NEG; z := 1 - NEG; w := -(-NEG)"/>
      <ScriptCondition code="x == 1 &amp;&amp; y == 2 &amp;&amp; z == 2 &amp;&amp; w == -1"/>
    </Sequence>
  </BehaviorTree>
</root>
""",
        encoding="utf-8",
    )
    (tmp_path / "m.scenario").write_text("ticks 1\n", encoding="utf-8")
    runs = [
        _btgen("run", "m.xml", "--scenario", "m.scenario", "--engine", e, "--enum", "E=NEG=-1", cwd=tmp_path)
        for e in ("interp", "cpp")
    ]
    for r in runs:
        assert r.returncode == 0, r.stderr
        assert "result SUCCESS" in r.stdout
    assert runs[0].stdout == runs[1].stdout
