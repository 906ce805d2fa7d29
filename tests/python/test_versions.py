"""The BehaviorTree.CPP versions: one record of named switches (lang/versions.py), the 4.9.0
script grammar, and the version a generated header carries (and refuses to mix)."""

import dataclasses
import os
import re
import shutil
import subprocess
import sys

import pytest

import cppbuild
from btgen.backend_cpp.emit import render
from btgen.frontend.loader import load_mission
from btgen.ir.lower import lower
from btgen.lang import script as sc
from btgen.lang import versions
from conftest import ROOT

MISSION = """<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence>
      <Script code="a := 1; b := 0"/>
      <ScriptCondition code="a || b &amp;&amp; b"/>
    </Sequence>
  </BehaviorTree>
</root>
"""


def test_every_switch_is_named_with_its_release_and_differs_between_the_versions():
    old, new = versions.semantics("4.6.2"), versions.semantics("4.10.0")
    names = versions.switch_names()
    assert set(names) == set(versions.SINCE)
    assert all(not getattr(old, n) for n in names)
    assert all(getattr(new, n) for n in names)
    assert [f.name for f in dataclasses.fields(versions.Semantics)][1:] == list(names)
    with pytest.raises(ValueError, match="unsupported BehaviorTree.CPP version `4.9.0`"):
        versions.semantics("4.9.0")
    assert versions.version_number("4.10.0") == 41000


@pytest.mark.parametrize(
    "code,old,new",
    [
        ("a || b && c", "((a || b) && c)", "(a || (b && c))"),
        ("'wp' .. 1 + 2", "('wp' .. (1 + 2))", "(('wp' .. 1) + 2)"),
        ("x := c1 ? 3 : (c2 ? 2 : 1)", "(x := (c1 ? 3 : (c2 ? 2 : 1)))", "(x := (c1 ? 3 : (c2 ? 2 : 1)))"),
        ("1 < a < 10", "(1 < a < 10)", "(1 < a < 10)"),
    ],
)
def test_the_two_grammars(code, old, new):
    assert "; ".join(sc.format_expr(s) for s in sc.parse_script(code).statements) == old
    assert "; ".join(sc.format_expr(s) for s in sc.parse_script(code, True).statements) == new


@pytest.mark.parametrize(
    "code,parsed",
    [
        ("a := 1 b := 2", "(a := 1); (b := 2)"),
        ("c1 ? 3 : c2 ? 2 : 1", "(c1 ? 3 : (c2 ? 2 : 1))"),
        ("a - b == 2", "((a - b) == 2)"),
        ("x := 1 & 3 + 1", "(x := (1 & (3 + 1)))"),
        ("trueValue := 1;", "(trueValue := 1)"),
    ],
)
def test_what_only_the_49_grammar_reads(code, parsed):
    assert "; ".join(sc.format_expr(s) for s in sc.parse_script(code, True).statements) == parsed


@pytest.mark.parametrize(
    "code,message",
    [
        ('room := "lab"', "double-quoted string"),
        ("offset := +2", "no unary `+`"),
        ("x := 1.", "invalid number `1.`"),
        ("", "empty script"),
        ("; a := 1", "expected a value"),
        ("x := 'open", "unterminated string"),
    ],
)
def test_what_the_49_grammar_refuses(code, message):
    with pytest.raises(sc.ScriptSyntaxError, match=re.escape(message)):
        sc.parse_script(code, True)


def test_true_is_a_double_and_negation_too_in_49():
    [stmt] = sc.parse_script("true", True).statements
    assert isinstance(stmt, sc.Literal) and stmt.value == 1.0 and isinstance(stmt.value, float)
    [stmt] = sc.parse_script("true").statements
    assert stmt.value == 1 and isinstance(stmt.value, int)


def _header(tmp_path, version, stem):
    path = tmp_path / f"{stem}.xml"
    path.write_text(MISSION, encoding="utf-8")
    header = render(lower(load_mission(str(path), btcpp=version)), stem, str(tmp_path))[0]
    (tmp_path / header.name).write_text(header.text, encoding="utf-8")
    return header


def test_the_header_carries_the_version_and_its_switches(tmp_path):
    new = _header(tmp_path, "4.10.0", "m410").text
    assert "static constexpr std::uint32_t kBtcppVersion = 41000;" in new
    assert "#define BTGEN_BTCPP_VERSION 41000" in new
    for name in versions.switch_names():
        assert f"static constexpr bool {name} = true;" in new
    old = _header(tmp_path, "4.6.2", "m462").text
    assert "static constexpr std::uint32_t kBtcppVersion = 40602;" in old
    assert "static constexpr bool skipped_by_count = false;" in old


@pytest.mark.skipif(shutil.which("c++") is None, reason="no C++ compiler")
def test_headers_of_two_versions_refuse_to_share_a_translation_unit(tmp_path):
    _header(tmp_path, "4.10.0", "m410")
    _header(tmp_path, "4.6.2", "m462")
    both = tmp_path / "both.cpp"
    both.write_text('#include "m462.hpp"\n#include "m410.hpp"\nint main() { return 0; }\n')
    one = tmp_path / "one.cpp"
    one.write_text('#include "m410.hpp"\nint main() { return 0; }\n')
    bad = cppbuild.run(cppbuild.command([both], cxx="c++", mode="syntax", warnings=False, includes=[tmp_path]))
    assert bad.returncode != 0
    assert "m410.hpp follows BehaviorTree.CPP 4.10.0, but a mission header generated for another release" in (
        bad.stderr
    )
    good = cppbuild.run(cppbuild.command([one], cxx="c++", mode="syntax", warnings=False, includes=[tmp_path]))
    assert good.returncode == 0, good.stderr


def test_the_option_takes_only_the_supported_versions():
    p = subprocess.run(
        [sys.executable, "-m", "btgen", "validate", "missions/PickPlaceBall.xml", "--btcpp", "4.9.0"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=False,
    )
    assert p.returncode == 1
    assert "invalid choice: '4.9.0'" in p.stderr


@pytest.mark.parametrize("compiler", ["g++", "clang++"])
def test_410_code_compiles_warning_free(compiler, tmp_path):
    """A mission of the 4.10.0 rows (TryCatch, Precondition, `_while` under a Sequence, typed
    SubTree literals, a Switch) with the engine instantiated by the scenario runner: no warning
    at -O2 with -Wall -Wextra -Wpedantic -Wshadow -Werror."""
    if shutil.which(compiler) is None:
        pytest.skip(f"no {compiler}")
    from btgen.backend_cpp import naming
    from btgen.tools.cppengine import DRIVER

    cases = os.path.join(ROOT, "tests", "conformance", "btcpp-4.10.0")
    for stem in ("v410_r11_trycatch_failure", "v410_r4_if_turns_false", "v410_b1_literal_arithmetic"):
        mission = load_mission(os.path.join(cases, stem + ".xml"), btcpp="4.10.0")
        outputs = render(lower(mission), stem, ROOT)
        for out in outputs:
            (tmp_path / out.name).write_text(out.text, encoding="utf-8")
        template = f"{naming.mission_namespace(stem, None)}::{naming.pascal_case(stem)}"
        cmd = cppbuild.command(
            [DRIVER],
            tmp_path / f"{stem}.o",
            cxx=compiler,
            opt="-O2",
            flags=["-Wshadow"],
            defines=[f'BTGEN_MISSION_HEADER="{outputs[0].name}"', f"BTGEN_MISSION_TEMPLATE={template}"],
            includes=[tmp_path],
            mode="object",
        )
        proc = cppbuild.run(cmd)
        assert proc.returncode == 0, proc.stderr[-4000:]
