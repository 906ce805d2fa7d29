"""The one table of `btgen check`'s diagnostic codes.

The front end and the IR report problems as `Diagnostic`s with a message and a severity; their
texts are asserted by many tests and stay as they are. `check` gives each a stable code by the
first rule of `RULES` whose pattern matches its message (a code never changes meaning: a new
kind of problem gets a new code, a retired one is never reused). The analysis findings of
`btgen analyze`, the upgrade findings of `btgen upgrade-check` and check's own findings are in the
same table. `docs/rules/` is generated from it (`python -m btgen.tools.check.rules_doc`), and
`tests/python/test_check_rules.py` runs every example through `check` and asserts its code, so
table, pages and behaviour cannot drift apart.

Codes: E1xx the file as XML, E2xx files, trees and includes, E3xx nodes and models, E4xx ports,
E5xx scripts and blackboard data, E6xx what BehaviorTree.CPP's release or the C++ back end
refuses; W1xx warnings; A1xx analysis findings; U1xx upgrade findings; C1xx check's own
findings about the project (C0xx: the configuration file). E999/W999 are the fallback of a
message no rule knows yet: a bug of the table, to be reported.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Optional

M = '<root BTCPP_format="4">\n  <BehaviorTree ID="Main">\n'
E = "  </BehaviorTree>\n</root>\n"


def tree(body: str, extra: str = "") -> str:
    """A one-tree mission whose tree is `body` (indented by the caller), then `extra` in <root>."""
    return M + body + "  </BehaviorTree>\n" + extra + "</root>\n"


@dataclass(frozen=True)
class Rule:
    code: str
    name: str
    severity: str  # the default level: "error" | "warning"
    summary: str
    patterns: tuple[str, ...]  # re.search over the message, in order
    bad: dict[str, str] = field(default_factory=dict)  # files of a folder where `check` reports the code
    good: dict[str, str] = field(default_factory=dict)  # the same folder fixed
    why: str = ""
    source: str = "loader"  # loader | analysis | upgrade | check | config
    default: bool = True  # reported without --select (False: only when selected by code or prefix)

    def matches(self, message: str) -> bool:
        return any(re.search(p, message) for p in self.patterns)


def _m(body: str, extra: str = "") -> dict[str, str]:
    return {"mission.xml": tree(body, extra)}


MODELS_SAY = '<root BTCPP_format="4">\n  <TreeNodesModel>\n    <Action ID="Say">\n      <input_port name="text"/>\n    </Action>\n  </TreeNodesModel>\n</root>\n'  # noqa: E501

RULES: tuple[Rule, ...] = (
    # ------------------------------------------------------------------ E1: the file as XML
    Rule(
        "E101",
        "xml-syntax",
        "error",
        "the file is not well-formed XML",
        (
            r"closing tag",
            r"appears twice",
            r"^attribute name `",
            r"^a raw `",
            r"not well-formed|expected '>'|^unclosed|^mismatched|^premature end|^XML|^Extra content|not XML",
            r"^elements nested deeper",
            r"^control character",
            r"^invalid character|^unescaped",
        ),
        bad={"mission.xml": M + "    <Sequence>\n      <AlwaysSuccess/>\n    </Fallback>\n" + E},
        good=_m("    <Sequence>\n      <AlwaysSuccess/>\n    </Sequence>\n"),
        why="BehaviorTree.CPP's tinyxml2 refuses it, or tolerates it where other XML tools (Groot2, "
        "editors, XSD validators) do not.",
    ),
    Rule(
        "E102",
        "encoding",
        "error",
        "the file is not UTF-8 text",
        (r"UTF-8|UTF-16|^encoding `", r"^file is empty"),
        bad={"mission.xml": '<?xml version="1.0" encoding="latin-1"?>\n' + tree("    <AlwaysSuccess/>\n")},
        good={"mission.xml": '<?xml version="1.0" encoding="UTF-8"?>\n' + tree("    <AlwaysSuccess/>\n")},
    ),
    Rule(
        "E103",
        "doctype",
        "error",
        "a document type declaration (entities could expand without bound or read other files)",
        (r"^document type declarations",),
        bad={"mission.xml": '<!DOCTYPE root [<!ENTITY a "b">]>\n' + tree("    <AlwaysSuccess/>\n")},
        good=_m("    <AlwaysSuccess/>\n"),
    ),
    Rule(
        "E104",
        "unreadable-file",
        "error",
        "the file cannot be read (a folder, a socket, too large, no permission)",
        (r"^cannot read file|^is a directory, not|^is a socket|^file is (larger than )?\d+ bytes|^file is larger",),
    ),
    Rule(
        "E105",
        "root-element",
        "error",
        'the root element is not <root BTCPP_format="4">',
        (r"^the root element", r'^BTCPP_format="'),
        bad={"mission.xml": tree("    <AlwaysSuccess/>\n").replace('BTCPP_format="4"', 'BTCPP_format="3"')},
        good=_m("    <AlwaysSuccess/>\n"),
    ),
    Rule(
        "E106",
        "structure",
        "error",
        "an element or attribute where the file format allows none (the XML Schema of BehaviorTree.CPP files)",
        (r"^<\w+> (is not allowed|needs|cannot|must)", r"^element <", r"^unknown element|^unexpected element"),
    ),
    # ------------------------------------------------------------------ E2: files, trees, includes
    Rule(
        "E201",
        "include",
        "error",
        "an <include> names a file that cannot be loaded, or the includes form a cycle",
        (r"^included file `", r"^include cycle", r"^includes nested deeper"),
        bad=_m("    <AlwaysSuccess/>\n", '  <include path="missing.xml"/>\n'),
        good=_m("    <AlwaysSuccess/>\n"),
    ),
    Rule(
        "E202",
        "include-ros-pkg",
        "error",
        "an <include ros_pkg=...> whose package cannot be found here",
        (r"^<include ros_pkg=",),
        bad=_m("    <AlwaysSuccess/>\n", '  <include ros_pkg="no_such_btgen_pkg" path="trees/x.xml"/>\n'),
        good=_m("    <AlwaysSuccess/>\n"),
        why="Give the package's folder in `ros-packages` of [tool.btgen], or a path relative to the file.",
    ),
    Rule(
        "E203",
        "tree-id",
        "error",
        "a <BehaviorTree> without ID, with an ID defined twice, or with an ID BehaviorTree.CPP refuses",
        (
            r"^<BehaviorTree> needs an ID",
            r"^BehaviorTree (ID )?`.*` (is defined twice|must not be empty)",
            r"is a registered",
            r"a built-in node: BehaviorTree\.CPP refuses",
        ),
        bad={
            "mission.xml": '<root BTCPP_format="4" main_tree_to_execute="Main">\n'
            '  <BehaviorTree ID="Main">\n    <AlwaysSuccess/>\n  </BehaviorTree>\n'
            '  <BehaviorTree ID="Main">\n    <AlwaysFailure/>\n  </BehaviorTree>\n</root>\n'
        },
        good=_m("    <AlwaysSuccess/>\n"),
    ),
    Rule(
        "E204",
        "main-tree",
        "error",
        "the tree to run is not known: main_tree_to_execute names no tree, or the file defines none",
        (
            r"^main_tree_to_execute names",
            r"^the mission defines no <BehaviorTree>",
            r"^--main-tree names",
            r"^the mission defines \d+ BehaviorTrees",
        ),
        bad={"mission.xml": tree("    <AlwaysSuccess/>\n").replace('"4">', '"4" main_tree_to_execute="Mian">')},
        good={"mission.xml": tree("    <AlwaysSuccess/>\n").replace('"4">', '"4" main_tree_to_execute="Main">')},
    ),
    Rule(
        "E205",
        "subtree-missing",
        "error",
        "a <SubTree> names a BehaviorTree that no loaded file defines",
        (r"^SubTree `.*` does not exist", r"is a BehaviorTree, not a node", r"^SubTree model `.*` names no"),
        bad=_m('    <SubTree ID="Dock"/>\n'),
        good=_m('    <SubTree ID="Dock"/>\n', '  <BehaviorTree ID="Dock">\n    <AlwaysSuccess/>\n  </BehaviorTree>\n'),
    ),
    Rule(
        "E206",
        "subtree-recursion",
        "error",
        "SubTrees that call each other without end",
        (r"^SubTree recursion", r"^SubTree calls itself"),
        bad=_m('    <SubTree ID="Main"/>\n'),
        good=_m("    <AlwaysSuccess/>\n"),
    ),
    Rule(
        "E207",
        "models-file",
        "error",
        "a models file holds something else than <TreeNodesModel>",
        (r"models file", r"^the file name is empty"),
    ),
    Rule(
        "E208",
        "tree-shape",
        "error",
        "a <BehaviorTree> must have exactly one child",
        (r"^BehaviorTree `.*` must have exactly 1 child",),
        bad={"mission.xml": M + E},
        good=_m("    <AlwaysSuccess/>\n"),
    ),
    # ------------------------------------------------------------------ E3: nodes and models
    Rule(
        "E301",
        "unknown-node",
        "error",
        "a node that is neither built in nor declared, whose name is close to one that is (a typo)",
        (r"^unknown node `.*(did you mean|have no namespace|built in from)",),
        bad=_m("    <AlwaysSucess/>\n"),
        good=_m("    <AlwaysSuccess/>\n"),
    ),
    Rule(
        "E302",
        "children",
        "error",
        "a node with a number of children its kind does not take",
        (r" takes (exactly \d+|no|\d+ or \d+|at least \d+|\d+ to \d+) child",),
        bad=_m("    <Inverter/>\n"),
        good=_m("    <Inverter>\n      <AlwaysSuccess/>\n    </Inverter>\n"),
    ),
    Rule(
        "E303",
        "node-id",
        "error",
        'a node ID btgen cannot hold (a tab, a line break, `"` or `\\`: status traces print IDs unquoted; a word '
        "of the file format)",
        (r"^node ID `", r"cannot be a node ID", r"needs an ID attribute naming the node"),
        bad=_m(
            '    <Action ID="Say&#9;Hi"/>\n', '  <TreeNodesModel>\n    <Action ID="Say&#9;Hi"/>\n  </TreeNodesModel>\n'
        ),
        good=_m('    <Action ID="SayHi"/>\n', '  <TreeNodesModel>\n    <Action ID="SayHi"/>\n  </TreeNodesModel>\n'),
    ),
    Rule(
        "E304",
        "model",
        "error",
        "a <TreeNodesModel> declaration that is wrong: a port twice, an invalid or reserved port name",
        (r"is declared twice", r"^invalid port name", r"is reserved and cannot be a port name"),
        bad=_m(
            '    <Say text="hi"/>\n',
            '  <TreeNodesModel>\n    <Action ID="Say">\n      <input_port name="text"/>\n'
            '      <input_port name="text"/>\n    </Action>\n  </TreeNodesModel>\n',
        ),
        good=_m(
            '    <Say text="hi"/>\n',
            '  <TreeNodesModel>\n    <Action ID="Say">\n      <input_port name="text"/>\n'
            "    </Action>\n  </TreeNodesModel>\n",
        ),
    ),
    # ------------------------------------------------------------------ E4: ports
    Rule(
        "E401",
        "unknown-port",
        "error",
        "an attribute that names no port of the node",
        (r" has no port `", r"^unknown attribute `"),
        bad=_m('    <Repeat num_cycles="2" times="3">\n      <AlwaysSuccess/>\n    </Repeat>\n'),
        good=_m('    <Repeat num_cycles="2">\n      <AlwaysSuccess/>\n    </Repeat>\n'),
    ),
    Rule(
        "E402",
        "missing-port",
        "error",
        "a required port is not given",
        (r" needs port `",),
        bad=_m("    <Repeat>\n      <AlwaysSuccess/>\n    </Repeat>\n"),
        good=_m('    <Repeat num_cycles="2">\n      <AlwaysSuccess/>\n    </Repeat>\n'),
    ),
    Rule(
        "E403",
        "port-value",
        "error",
        "a port's literal is not a value of the port's type",
        (
            r"^port `[^`]*` of `[^`]*`: `.*` is not a valid",
            r"^(?!.*is declared \w+: ).*is not a valid (int|unsigned|double|bool|float)",
            r"must name a blackboard entry as",
        ),
        bad=_m('    <Repeat num_cycles="two">\n      <AlwaysSuccess/>\n    </Repeat>\n'),
        good=_m('    <Repeat num_cycles="2">\n      <AlwaysSuccess/>\n    </Repeat>\n'),
    ),
    Rule(
        "E404",
        "blackboard-key",
        "error",
        "a blackboard key BehaviorTree.CPP cannot name",
        (r"blackboard key|is not a valid key|not a valid blackboard|^key `",),
    ),
    # ------------------------------------------------------------------ E5: scripts and data
    Rule(
        "E501",
        "script-syntax",
        "error",
        "a script that does not parse",
        (r"^invalid script",),
        bad=_m('    <Script code="x := "/>\n'),
        good=_m('    <Script code="x := 1"/>\n'),
    ),
    Rule(
        "E502",
        "script-error",
        "error",
        "a script that fails whenever it runs (a type error, a value out of range)",
        (r"^script error in", r"needs whole-number operands|cannot be applied to"),
        why="Such a script loads in BehaviorTree.CPP and fails when it runs; both engines of btgen report it "
        "then (`btgen run`), with this message.",
    ),
    Rule(
        "E503",
        "entry-never-written",
        "error",
        "a blackboard entry is read that nothing creates, or that never has a value",
        (
            r"nothing creates that blackboard entry",
            r"which has no value yet",
            r"is only updated",
            r"^cannot tell the type",
        ),
        bad=_m('    <Script code="y := x + 1"/>\n'),
        good=_m('    <Sequence>\n      <Script code="x := 1"/>\n      <Script code="y := x + 1"/>\n    </Sequence>\n'),
    ),
    Rule(
        "E504",
        "entry-type",
        "error",
        "a blackboard entry used with two types, or a value that does not convert",
        (
            r"was created as",
            r"which holds a ",
            r", which is declared ",
            r"reads blackboard entry `.*`, a ",
            r"is declared \w+: ",
        ),
        bad=_m(
            '    <Sequence>\n      <Count out="{k}"/>\n      <Gate in="{k}"/>\n    </Sequence>\n',
            '  <TreeNodesModel>\n    <Action ID="Count"><output_port name="out" type="int"/></Action>\n'
            '    <Action ID="Gate"><input_port name="in" type="bool"/></Action>\n  </TreeNodesModel>\n',
        ),
        good=_m(
            '    <Sequence>\n      <Count out="{k}"/>\n      <Gate in="{k}"/>\n    </Sequence>\n',
            '  <TreeNodesModel>\n    <Action ID="Count"><output_port name="out" type="int"/></Action>\n'
            '    <Action ID="Gate"><input_port name="in" type="int"/></Action>\n  </TreeNodesModel>\n',
        ),
    ),
    Rule(
        "E505",
        "capacity",
        "error",
        "a string or queue longer than the capacity btgen gives it",
        (r"does not fit blackboard entry", r"capacity"),
        why="btgen's strings have a fixed capacity (128 bytes by default); `string-capacity` and `queue-capacity` "
        "in [tool.btgen] raise it.",
    ),
    # ------------------------------------------------------------------ E6: releases, back end
    Rule(
        "E601",
        "cpp-backend",
        "error",
        "something BehaviorTree.CPP loads that the C++ back end cannot compile (it says how to write it)",
        (r"C\+\+ back end",),
    ),
    Rule(
        "E602",
        "release-rule",
        "error",
        "something the selected BehaviorTree.CPP release refuses",
        (r"BehaviorTree\.CPP \d+\.\d+(\.\d+)? (refuses|throws)|refused (from|by|since)|from BehaviorTree\.CPP",),
    ),
    Rule(
        "E603",
        "limits",
        "error",
        "a mission larger than btgen's limits",
        (r"at most \d+|more than \d+|too many|too large",),
    ),
    # ------------------------------------------------------------------ W1: warnings
    Rule(
        "W101",
        "ignored-text",
        "warning",
        "text between elements, which BehaviorTree.CPP never reads",
        (r"^text `.*` inside <",),
        bad=_m("    <Sequence>\n      stray\n      <AlwaysSuccess/>\n    </Sequence>\n"),
        good=_m("    <Sequence>\n      <AlwaysSuccess/>\n    </Sequence>\n"),
    ),
    Rule(
        "W102",
        "ignored-attribute",
        "warning",
        "an attribute BehaviorTree.CPP ignores",
        (r"^attribute `.*` (of|on) .* is ignored", r"is BehaviorTree\.CPP v3's"),
        bad=_m('    <AlwaysSuccess _comment="x"/>\n'),
        good=_m('    <AlwaysSuccess name="x"/>\n'),
    ),
    Rule(
        "W103",
        "no-format",
        "warning",
        "<root> without BTCPP_format (read as format 4)",
        (r"^<root> has no BTCPP_format",),
        bad={"mission.xml": tree("    <AlwaysSuccess/>\n").replace(' BTCPP_format="4"', "")},
        good=_m("    <AlwaysSuccess/>\n"),
    ),
    Rule(
        "W104",
        "model-ignored",
        "warning",
        "a model BehaviorTree.CPP never reads (a built-in redeclared, an unknown port element, another element "
        "in a model: MoveIt Pro's `<description>`)",
        (
            r"is a built-in node of BehaviorTree\.CPP",
            r"^<bidirectional_port>",
            r"can never be given",
            r"^default of port",
            r"in the model of `.*` is not read by BehaviorTree\.CPP",
        ),
        bad=_m("    <AlwaysSuccess/>\n", '  <TreeNodesModel>\n    <Action ID="AlwaysSuccess"/>\n  </TreeNodesModel>\n'),
        good=_m("    <AlwaysSuccess/>\n"),
    ),
    Rule(
        "W105",
        "model-conflict",
        "warning",
        "a node written as another kind than its model, or declared twice with different details",
        (r"is a \w+, but is written <", r"declarations differ"),
    ),
    Rule(
        "W106",
        "literal-text",
        "warning",
        "a value that looks like a blackboard reference but is read as literal text",
        (r"is not a blackboard reference", r"reads it as this literal text"),
        bad=_m(
            '    <Sequence>\n      <Script code="n := 1"/>\n      <SetBlackboard output_key="m" value="{n"/>\n'
            "    </Sequence>\n"
        ),
        good=_m(
            '    <Sequence>\n      <Script code="n := 1"/>\n      <SetBlackboard output_key="m" value="{n}"/>\n'
            "    </Sequence>\n"
        ),
    ),
    Rule(
        "W107",
        "subtree-port",
        "warning",
        "a SubTree port that is not declared, or an entry the SubTree reads that its caller does not map",
        (r"^SubTree `.*` declares no port", r"^SubTree `.*` reads `"),
    ),
    Rule(
        "W108",
        "placeholder",
        "warning",
        "a `${arg}` placeholder left in a value (substituted by the program before loading)",
        (r"\$\{",),
    ),
    Rule(
        "W109",
        "later-release",
        "warning",
        "something the selected release loads and a later release of BehaviorTree.CPP refuses",
        (r"refused from (BehaviorTree\.CPP )?\d",),
        source="loader",
    ),
    Rule(
        "W110",
        "tinyxml2-only",
        "warning",
        "XML that tinyxml2 (BehaviorTree.CPP's parser) reads and other XML tools refuse: a raw `&` or `<` in "
        "an attribute value, `--` inside a comment, two attributes without a space, an element name with a "
        "colon whose prefix the file does not declare (`<arm:Grasp/>`), an XML declaration of a version that "
        'does not exist (`<?xml version="2.0"?>`)',
        (r"tinyxml2 \(BehaviorTree\.CPP\) reads it",),
        bad=_m(
            '    <Sequence>\n      <Script code="a := true"/>\n      <ScriptCondition code="a && a"/>\n'
            "    </Sequence>\n"
        ),
        good=_m(
            '    <Sequence>\n      <Script code="a := true"/>\n      <ScriptCondition code="a &amp;&amp; a"/>\n'
            "    </Sequence>\n"
        ),
        why="The library loads such a file (recorded on 4.6.2 and 4.10.0), and so does btgen, reading it as "
        "tinyxml2 does; Groot2, editors and XML Schema validators refuse it. The message says what to write.",
    ),
    Rule(
        "W111",
        "literal-output",
        "warning",
        "a literal on an output or inout port of a node the program registers: its writes go nowhere",
        (r"port given the literal",),
        bad=_m(
            '    <WaitForEvent result=""/>\n',
            '  <TreeNodesModel>\n    <Action ID="WaitForEvent">\n      <output_port name="result"/>\n'
            "    </Action>\n  </TreeNodesModel>\n",
        ),
        good=_m(
            '    <WaitForEvent result="{result}"/>\n',
            '  <TreeNodesModel>\n    <Action ID="WaitForEvent">\n      <output_port name="result"/>\n'
            "    </Action>\n  </TreeNodesModel>\n",
        ),
        why="BehaviorTree.CPP 4.6.2 and 4.10.0 load it (recorded: "
        "tests/conformance/both-releases/output_port_literal): the node's setOutput fails and writes nothing, "
        "so btgen loads an output port given a literal as not given, and an inout port's literal as the value "
        "it reads. A built-in node's output port given a literal stays an error (E403).",
    ),
    Rule(
        "W112",
        "empty-condition",
        "warning",
        "an empty ScriptCondition `code` or Precondition `if`: the library loads it and throws when it is ticked",
        (r"is empty: BehaviorTree\.CPP loads it and throws when the node is ticked",),
        bad=_m('    <Fallback>\n      <ScriptCondition code=""/>\n      <AlwaysSuccess/>\n    </Fallback>\n'),
        good=_m('    <Fallback>\n      <ScriptCondition code="true"/>\n      <AlwaysSuccess/>\n    </Fallback>\n'),
        why="BehaviorTree.CPP 4.6.2 and 4.10.0 load it and throw (bad_function_call) whenever the node is "
        "ticked (recorded: tests/conformance/both-releases/empty_condition_*); both btgen engines load it too "
        "and stop with an error when it runs. A script of spaces, or an empty `_skipIf` & co., the library "
        "refuses to load, and so does btgen.",
    ),
    # ------------------------------------------------------------------ A1: analysis findings
    Rule(
        "A101",
        "unreachable",
        "warning",
        "a node that can never be ticked, or a main tree that never ends",
        (r"can never be ticked", r"never returns SUCCESS or FAILURE"),
        bad=_m("    <Sequence>\n      <AlwaysFailure/>\n      <AlwaysSuccess/>\n    </Sequence>\n"),
        good=_m("    <Fallback>\n      <AlwaysFailure/>\n      <AlwaysSuccess/>\n    </Fallback>\n"),
        source="analysis",
    ),
    Rule(
        "A102",
        "constant-condition",
        "warning",
        "a condition or precondition that is always true or always false",
        (r"` of .* is always (true|false)",),
        bad=_m('    <Sequence>\n      <ScriptCondition code="1 == 2"/>\n      <AlwaysSuccess/>\n    </Sequence>\n'),
        good=_m('    <Sequence>\n      <Script code="n := 1"/>\n      <AlwaysSuccess/>\n    </Sequence>\n'),
        source="analysis",
    ),
    Rule(
        "A103",
        "reactive-async",
        "warning",
        "two children of a ReactiveSequence/ReactiveFallback that can both be RUNNING "
        "(BehaviorTree.CPP cannot check it: its issue #1184)",
        (r"can both return RUNNING under",),
        bad=_m('    <ReactiveSequence>\n      <Sleep msec="10"/>\n      <Sleep msec="20"/>\n    </ReactiveSequence>\n'),
        good=_m('    <ReactiveSequence>\n      <AlwaysSuccess/>\n      <Sleep msec="20"/>\n    </ReactiveSequence>\n'),
        source="analysis",
    ),
    Rule(
        "A104",
        "read-before-write",
        "warning",
        "a blackboard entry read before any node can have written it (or that no node writes)",
        (r"before anything can have written it",),
        bad=_m(
            '    <Sequence>\n      <Delay delay_msec="{d}">\n        <AlwaysSuccess/>\n      </Delay>\n'
            '      <SetBlackboard output_key="d" value="5"/>\n    </Sequence>\n'
        ),
        good=_m(
            '    <Sequence>\n      <SetBlackboard output_key="d" value="5"/>\n      <Delay delay_msec="{d}">\n'
            "        <AlwaysSuccess/>\n      </Delay>\n    </Sequence>\n"
        ),
        source="analysis",
    ),
    Rule(
        "A105",
        "write-never-read",
        "warning",
        "a blackboard entry written but never read by the mission",
        (r"but never read by the mission",),
        bad=_m('    <SetBlackboard output_key="unused" value="5"/>\n'),
        good=_m("    <AlwaysSuccess/>\n"),
        source="analysis",
        default=False,
        why="Not reported unless selected (`--extend-select A105`): output ports a program reads in C++ "
        "(Nav2's `error_code_id`) are written and never read by the tree, by design.",
    ),
    Rule(
        "A108",
        "entry-from-program",
        "warning",
        "a blackboard entry the tree reads and no node writes: the program must set it before the first tick",
        (r"but no node of the mission writes it",),
        bad=_m('    <Delay delay_msec="{d}">\n      <AlwaysSuccess/>\n    </Delay>\n'),
        good=_m(
            '    <Sequence>\n      <SetBlackboard output_key="d" value="5"/>\n      <Delay delay_msec="{d}">\n'
            "        <AlwaysSuccess/>\n      </Delay>\n    </Sequence>\n"
        ),
        source="analysis",
        default=False,
        why="Not reported unless selected (`--extend-select A108`): most programs set entries such as a goal "
        "before the first tick; declare them with `entry` in [tool.btgen] and select A108 to check the rest.",
    ),
    Rule(
        "A106",
        "read-types",
        "warning",
        "a blackboard entry read with two different types",
        (r"^blackboard entry `.*` is read as `",),
        source="analysis",
    ),
    Rule(
        "A107",
        "tick-budget",
        "warning",
        "a tick that may do more work than the configured budget",
        (r"tick budget|exceeds the budget|budget of",),
        source="analysis",
    ),
    # ------------------------------------------------------------------ U1: upgrade findings
    Rule(
        "U101",
        "upgrade",
        "warning",
        "a place where moving to the release of `upgrade-to` changes loading or behaviour (`btgen upgrade-check`)",
        (r".",),
        source="upgrade",
    ),
    # ------------------------------------------------------------------ C1: check's own
    Rule(
        "C101",
        "cpp-only-node",
        "error",
        "a node registered only in C++: no model declares it in the project",
        (r"^unknown node `",),
        bad=_m('    <Say text="hi"/>\n'),
        good={"mission.xml": tree('    <Say text="hi"/>\n'), "nodes.xml": MODELS_SAY},
        why="BehaviorTree.CPP loads the file only in the program that registers the node. Declare it: "
        "`btgen models .` writes a models file for every such node (commit it beside the trees), or name the "
        "program's own models file (`BT::writeTreeNodesModelXML`) under `models` in [tool.btgen].",
        source="check",
    ),
    Rule(
        "C102",
        "library-entry",
        "warning",
        "a tree library checked on its own reads an entry its caller or the program creates",
        (r"\(tree library\)",),
        source="check",
    ),
    Rule(
        "C001",
        "config",
        "error",
        "an unknown key or a bad value in the configuration ([tool.btgen] or btgen.toml)",
        (),
        source="config",
    ),
    Rule("E999", "other-error", "error", "an error no rule of the table knows yet (please report it)", (r".",)),
    Rule("W999", "other-warning", "warning", "a warning no rule of the table knows yet (please report it)", (r".",)),
)

BY_CODE: dict[str, Rule] = {r.code: r for r in RULES}
_LOADER_ERRORS = [r for r in RULES if r.source in ("loader", "check") and r.severity == "error" and r.code != "E999"]
_LOADER_WARNINGS = [r for r in RULES if r.source == "loader" and r.severity == "warning" and r.code != "W999"]
_ANALYSIS = [r for r in RULES if r.source == "analysis"]

# C101 (a node no model declares) takes the messages E301 leaves: check the typo first.
_ERROR_ORDER = sorted(_LOADER_ERRORS, key=lambda r: (r.code == "C101", r.code))


def classify(message: str, severity: str, source: str = "loader") -> str:
    """The code of a diagnostic: `source` is "loader" (front end and IR), "analysis" or "upgrade"."""
    if source == "upgrade":
        return "U101"
    if source == "analysis":
        rule = next((r for r in _ANALYSIS if r.matches(message)), None)
        return rule.code if rule else "W999"
    rules = _ERROR_ORDER if severity == "error" else _LOADER_WARNINGS
    rule = next((r for r in rules if r.matches(message)), None)
    if rule is None and severity == "error":  # a warning-shaped message raised as an error (or back)
        rule = next((r for r in _LOADER_WARNINGS if r.matches(message)), None)
    elif rule is None:
        rule = next((r for r in _ERROR_ORDER if r.matches(message)), None)
    if rule is None:
        return "E999" if severity == "error" else "W999"
    return rule.code


def selected(code: str, select: tuple[str, ...], ignore: tuple[str, ...]) -> bool:
    """Whether `code` is reported: by the longest matching prefix of --select / --ignore (ruff's rule:
    the more specific wins; on a tie, ignore wins). An empty select means every default code; a rule
    that is not a default one is reported only when a select names it or a prefix of two characters
    or more (`A1`, `A105`)."""

    def longest(prefixes: tuple[str, ...]) -> int:
        return max((0 if p == "ALL" else len(p) for p in prefixes if p == "ALL" or code.startswith(p)), default=-1)

    s = longest(select) if select else 0
    if not BY_CODE[code].default and s < 2:
        s = -1
    i = longest(ignore)
    return s >= 0 and i < s


def valid_selector(text: str) -> Optional[str]:
    """The problem with a --select/--ignore entry, or None: a code, a prefix of codes, or ALL."""
    if text == "ALL" or any(r.code.startswith(text) for r in RULES) and re.fullmatch(r"[A-Z]\d{0,3}", text):
        return None
    near = [r.code for r in RULES if r.code[:1] == text[:1]][:3]
    return f"`{text}` is no code or prefix of codes" + (f" (codes look like {', '.join(near)})" if near else "")
