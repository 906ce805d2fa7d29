"""tests/conformance/oracle-diff/: the divergences differential testing against the real library
found (scripts/oracle_random.py, scripts/oracle_minimize.py; docs/testing.md), each shrunk to a
minimal mission and recorded on 4.6.2 and 4.10.0 (scripts/record_releases.py), through both
engines (release_cases.py): the trace, cut short where the library threw, and whether it failed.
"""

import os
import re
import sys

import pytest

import release_cases as rc
from conftest import ROOT

HERE = os.path.join(ROOT, "tests", "conformance", "oracle-diff")
CASES = rc.recorded(HERE)
# What the C++ back end still refuses (listed by scripts/refusal_share.py).
REFUSED: dict[tuple[str, str], str] = {}
# Recordings neither engine follows yet, each a strict expected failure with its reason.
_DUMP = (
    "the library prints its blackboard on stdout (Blackboard::debugMessage) before it throws on a "
    "write that changes an entry's type; btgen does not (test_changing_types.py KNOWN)"
)
_QUEUE_COPY = (
    "4.6.2 copies a string entry as it is into a queue entry (blackboard.py set_blackboard: queue "
    "destinations still convert), so the Loop's cast throws; btgen converts it"
)
KNOWN = {
    ("set_text_into_status_entry", "4.6.2"): _DUMP,
    ("set_text_into_status_entry", "4.10.0"): _DUMP,
    ("queue_copy_of_text", "4.6.2"): _QUEUE_COPY,
}
CPP_KNOWN = {
    ("queue_copy_of_text", "4.6.2"): _QUEUE_COPY + " (the C++ fails at the copy: the capacity of `q`)",
    ("set_text_into_status_entry", "4.6.2"): _DUMP,
    ("set_text_into_status_entry", "4.10.0"): _DUMP,
}
# The blackboard's lines in the library's trace (`key (type)`)
DUMP_LINE = re.compile(r"^[^ \n]+ \((?:BT::|std::)?[\w:<>, ]+\)\n", re.M)


def _params(refused):
    return [
        pytest.param(s, v, marks=[pytest.mark.xfail(strict=True, reason=refused[(s, v)])] if (s, v) in refused else [])
        for s, v in CASES
    ]


def _compiles(stem: str, version: str) -> bool:
    from btgen import pipeline
    from btgen.diagnostics import UserError
    from btgen.ir.lower import lower

    try:
        lower(pipeline.load(os.path.join(HERE, stem + ".xml"), pipeline.CompileOptions(btcpp=version)))
    except UserError:
        return False
    return True


def test_every_case_is_recorded_on_both_releases_and_says_what_it_shows():
    assert len(rc.stems(HERE)) >= 2
    assert len(CASES) == 2 * len(rc.stems(HERE))
    for stem in rc.stems(HERE):
        with open(os.path.join(HERE, stem + ".xml"), encoding="utf-8") as f:
            assert f.read().startswith("<!--"), f"{stem}: say what it shows"


@pytest.mark.parametrize("stem,version", _params(KNOWN))
def test_interpreter(stem, version):
    rc.check_interp(HERE, stem, version)


@pytest.mark.parametrize("stem,version", [k for k, why in KNOWN.items() if why == _DUMP])
def test_interpreter_fails_where_the_library_does_but_for_its_blackboard_dump(stem, version):
    """4.10.0 too throws at a SetBlackboard of text into a NodeStatus entry (the interpreter left
    the entry empty and failed later, at the Precondition reading it)."""
    trace, failed = rc.expected(HERE, stem, version)
    assert DUMP_LINE.search(trace)
    assert failed
    got = rc.interp(HERE, stem, version)
    assert (got[0], got[1]) == (DUMP_LINE.sub("", trace), True)
    assert "SetBlackboard" in got[2], got[2]


@pytest.fixture(scope="module")
def batches(tmp_path_factory):
    return rc.Batches(HERE, tmp_path_factory.mktemp("oracle_diff"), _compiles).build()


@pytest.mark.parametrize("stem,version", _params({**REFUSED, **CPP_KNOWN}))
def test_compiled_executor(stem, version, batches):
    if rc.loads(HERE, stem, version):
        assert _compiles(stem, version), "the C++ back end refuses it"
    rc.check_cpp(batches, stem, version)


@pytest.mark.parametrize("stem,version", [k for k, why in CPP_KNOWN.items() if why == _DUMP])
def test_compiled_executor_fails_where_the_library_does_but_for_its_blackboard_dump(stem, version, batches):
    """Text written into an entry a port typed NodeStatus: the C++ back end compiles it (it
    refused the file) and throws at the SetBlackboard, with the interpreter's trace and message."""
    trace, failed = rc.expected(HERE, stem, version)
    assert DUMP_LINE.search(trace) and failed
    assert _compiles(stem, version)
    got = batches.run(stem, version)
    assert got is not None
    assert (got.stdout, got.rc) == (DUMP_LINE.sub("", trace), 1), got.stderr
    _, _, message = rc.interp(HERE, stem, version)
    assert "SetBlackboard" in message and message in got.stderr, (message, got.stderr)


def _load(tmp_path, text, version="4.6.2"):
    from btgen.frontend.loader import load_mission

    path = tmp_path / "m.xml"
    path.write_text(text, encoding="utf-8")
    return load_mission(str(path), btcpp=version)


UNUSED = """<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main"><AlwaysSuccess/></BehaviorTree>
  <BehaviorTree ID="Unused">{body}</BehaviorTree>
</root>
"""


@pytest.mark.parametrize("version", rc.VERSIONS)
def test_an_uncreated_tree_with_creation_errors_is_left_out_with_warnings(tmp_path, version):
    m = _load(tmp_path, UNUSED.format(body='<Repeat num_cycles="xyz"><AlwaysSuccess/></Repeat>'), version)
    assert [t.id for t in m.trees] == ["Main"]
    about = [w for w in m.warnings if "num_cycles" in w.message]
    assert len(about) == 1, about  # the loader's, not the mission XSD's again
    assert "never runs BehaviorTree `Unused`" in about[0].message


@pytest.mark.parametrize(
    "body,message",
    [
        ("<Inverter><AlwaysSuccess/><AlwaysSuccess/></Inverter>", "takes exactly 1 child"),
        ("<Sequence/>", "but has no children"),
        ("<NoSuchNode/>", "unknown node `NoSuchNode`"),
    ],
)
def test_what_verify_xml_checks_still_refuses_an_uncreated_tree(tmp_path, body, message):
    from btgen.diagnostics import UserError

    with pytest.raises(UserError) as e:
        _load(tmp_path, UNUSED.format(body=body))
    assert any(message in d.message for d in e.value.diagnostics if d.severity == "error")


@pytest.mark.parametrize("version", rc.VERSIONS)
@pytest.mark.parametrize(
    "node",
    [
        '<Precondition if="true" else="3"><AlwaysSuccess/></Precondition>',
        '<LoopDouble queue="1" value="{v}" if_empty="success"><AlwaysSuccess/></LoopDouble>',
        '<LoopBool queue="1" value="{v}" if_empty=""><AlwaysSuccess/></LoopBool>',
    ],
)
def test_a_status_literal_that_does_not_convert_loads_with_a_warning(tmp_path, node, version):
    """Both releases load it (status_literal_*): the node throws where it reads the port."""
    text = f'<root BTCPP_format="4" main_tree_to_execute="Main"><BehaviorTree ID="Main">{node}</BehaviorTree></root>'
    m = _load(tmp_path, text, version)
    assert any("is not a valid NodeStatus" in w.message and "loads it" in w.message for w in m.warnings)


def test_a_created_tree_keeps_its_errors(tmp_path):
    from btgen.diagnostics import UserError

    text = UNUSED.replace("<AlwaysSuccess/></BehaviorTree>", '<SubTree ID="Unused"/></BehaviorTree>', 1)
    with pytest.raises(UserError):
        _load(tmp_path, text.format(body='<Repeat num_cycles="xyz"><AlwaysSuccess/></Repeat>'))


def test_the_driver_counts_documented_differences_apart():
    """scripts/oracle_random.py's verdicts (the differential runs' table depends on them)."""
    sys.path.insert(0, os.path.join(ROOT, "scripts"))
    import oracle_random as orc

    mixed = ("", True, "error: ...\n   ^^ operator cannot be mixed with previous operators")
    assert orc.compare(mixed, ("tick 1\n", False, ""), "4.6.2") == "documented"
    assert orc.compare(mixed, ("tick 1\n", False, ""), "4.10.0") == "divergence"
    assert orc.compare(("t\n", False, ""), ("t\n", False, ""), "4.10.0") == "agree"
    assert orc.compare(("t\n", True, "x"), ("t\n", False, ""), "4.6.2") == "divergence"
    lib = 'tick 2\n2 LoopInt "L" RUNNING -> IDLE\nresult SKIPPED\ntick 3\nresult SKIPPED\n'
    got = 'tick 2\n2 LoopInt "L" RUNNING -> IDLE\nresult SKIPPED\ntick 3\n2 LoopInt "L" IDLE -> RUNNING\n'
    literal = '<LoopInt queue="1;2" value="{v}">'
    assert orc.compare((lib, False, ""), (got, False, ""), "4.6.2", literal) == "documented"
    assert orc.compare((lib, False, ""), (got, False, ""), "4.6.2", literal.replace('"1;2"', '"{q}"')) == "divergence"
    assert orc.compare((lib, False, ""), (got, False, ""), "4.10.0", literal) == "divergence"
    # 4.6.2's entry-update nodes: a SetBlackboard copy is no update, a halt leaves the child running
    updates = '<SkipUnlessUpdated entry="{i}"><SetBlackboard value="{j}" output_key="i"/></SkipUnlessUpdated>'
    lib, got = "tick 2\nresult RUNNING\n", 'tick 2\n3 Fallback "f" IDLE -> RUNNING\n'
    assert orc.compare((lib, False, ""), (got, False, ""), "4.6.2", updates) == "documented"
    assert orc.compare((lib, False, ""), (got, False, ""), "4.10.0", updates) == "divergence"
    assert orc.compare((lib, False, ""), (got, False, ""), "4.6.2", updates.replace("{j}", "5")) == "divergence"


def test_fuzzgen_writes_no_name_410_refuses():
    """fuzzgen's missions for 4.10.0 load there (the differential runs found DEL in node names and
    a SubTree named "" in the main tree, which 4.10.0 refuses)."""
    import re

    from btgen.tools.fuzzgen import FEATURE_SETS, random_case

    for features in FEATURE_SETS:
        for seed in range(100):
            mission = random_case(seed, features, 1, "4.10.0").mission
            assert "\x7f" not in mission, (features, seed)
            assert not re.search(r'<SubTree [^>]*name=""', mission), (features, seed)


def test_the_themes_runner_writes_distinct_loadable_cases_and_counts_the_dump_apart():
    """scripts/oracle_themes.py: every case a unique stem and well-formed XML, and a run that
    differs only by the library's blackboard dump is counted apart."""
    from lxml import etree

    sys.path.insert(0, os.path.join(ROOT, "scripts"))
    import oracle_themes as ot

    stems = set()
    for family, make in ot.FAMILIES.items():
        cases = make()
        assert cases, family
        for stem, text, scenario in cases:
            assert stem not in stems, stem
            stems.add(stem)
            etree.fromstring(text.encode("utf-8"))
            assert scenario.startswith("ticks ")
    assert len(stems) > 4000
    lib = ("tick 1\nv (int)\nw (BT::AnyTypeAllowed)\n", True, "error: ... the type of a port shall not change ...")
    assert ot.verdict_of(lib, ("tick 1\n", True, "x"), "4.10.0", "") == "blackboard dump"
    assert ot.verdict_of(lib, ("tick 1\n", False, ""), "4.10.0", "") == "divergence"
    assert ot.verdict_of(lib, ("tick 1\nv (int)\n", True, "x"), "4.10.0", "") == "divergence"
