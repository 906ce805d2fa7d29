"""`btgen tests MISSION -o DIR`: a GoogleTest suite for the real BehaviorTree.CPP.

The scenarios are the covering set `btgen explore` finds (every node ticked, every possible
outcome; the same search and bounds), or scenario files given with --scenarios. For each one
the suite holds one TEST that, at test time, reads the mission file from its path unchanged,
registers a scripted leaf (support.hpp) for every user Action and Condition the mission uses,
ticks the tree with `Tree::tickExactlyOnce()` and compares every status change, seen through
the library's StatusChangeLogger, and the root's results with the trace btgen's interpreter
gives for the scenario (embedded as expected data). Tick-exact: no timers, threads or sleeps,
so a mission with Sleep, Delay or Timeout is refused.

DIR receives CMakeLists.txt (find_package(behaviortree_cpp), GTest, one ctest entry per
TEST), `<stem>_tests.cpp`, `btgen_gtest_support.hpp`, `scenarios/<TEST>.scenario` (each TEST's
scenario in btgen's scenario format, which `btgen run`, `cover` and `mutate` read) and
`.btgen-tests` (the marker that lets a later run replace the folder). Everything is written to
a temporary folder beside DIR and renamed into place: DIR is whole or unchanged.

With --executor, DIR/executor/ also holds the interpreter's trace of each TEST's scenario, and
CMakeLists.txt one more ctest entry per TEST that runs scenarios/<TEST>.scenario on btgen's compiled
executor (`btgen run --engine cpp`) through executor/check.cmake: one suite checks both
runtimes; -DBTGEN_LIBRARY_TESTS=OFF leaves the BehaviorTree.CPP suite out. --coverage selects
the criteria the explored scenarios reach (tools/obligations.py).
"""

from __future__ import annotations

import os
import re
import shutil
import sys
import tempfile
from dataclasses import dataclass, field
from typing import Optional

from btgen import cmdline
from btgen.diagnostics import Diagnostic, Loc, UserError, print_diagnostics
from btgen.fileio import xml_files_of
from btgen.lang.leaves import is_scripted_leaf, leaf_kind
from btgen.lang.model import Mission, Node, SubTreeNode

MARKER = ".btgen-tests"
SUPPORT = "btgen_gtest_support.hpp"
SCENARIOS = "scenarios"  # DIR/scenarios/<TEST>.scenario: each TEST's scenario, as a scenario file
_TIMERS = ("Sleep", "Delay", "Timeout")
_LINE = re.compile(r"([0-9]+) (\S+) (\".*\") (IDLE|RUNNING|SUCCESS|FAILURE) -> (IDLE|RUNNING|SUCCESS|FAILURE)\Z")
_DIRS = {"input": "INPUT", "output": "OUTPUT", "inout": "INOUT"}


@dataclass
class Case:
    name: str  # the TEST's name
    covers: list[str]  # what it covers first, in words
    ticks: int
    lists: list[tuple[str, list[str]]]  # leaf name -> statuses, in first-call order
    trace: list[str]  # the expected lines: tick N, status changes, result S
    trace_text: str = ""  # the interpreter's trace as `btgen run` prints it
    obligations: list[str] = field(default_factory=list)  # condition / MC/DC goals it reaches first
    text: str = ""  # the scenario file's text
    error: str = ""  # the run-time error that ends the run (the expectation's last line is `error`)


@dataclass
class LeafDecl:
    id: str
    condition: bool
    ports: list[tuple[str, str]]  # (INPUT|OUTPUT|INOUT, name)


# ---------------------------------------------------------------- the mission's leaves
def _walk(mission: Mission) -> list[Node]:
    trees = {t.id: t for t in mission.trees}
    out: list[Node] = []
    seen: set[str] = set()

    def visit(node: Node) -> None:
        out.append(node)
        if isinstance(node, SubTreeNode):
            if node.target not in seen and node.target in trees:
                seen.add(node.target)
                visit(trees[node.target].root)
            return
        for c in node.children:
            visit(c)

    seen.add(mission.main_tree)
    visit(trees[mission.main_tree].root)
    return out


def _all_nodes(mission: Mission) -> list[Node]:
    out: list[Node] = []
    for tree in mission.trees:
        stack = [tree.root]
        while stack:
            node = stack.pop()
            out.append(node)
            stack.extend(reversed(node.children))
    return out


def mission_leaves(mission: Mission) -> list[LeafDecl]:
    """The user Actions and Conditions of every BehaviorTree the mission loads (the main tree's
    and the others: BehaviorTreeFactory checks every tree of a file it reads, and refuses a node
    it does not know even in a tree the main one never uses), by ID, with the ports the models
    declare (as the oracle harness registers them: by name, any type). A timer the main tree
    uses (SubTrees followed) is refused."""
    found: dict[str, LeafDecl] = {}
    for node in _walk(mission):
        if node.id in _TIMERS and node.id in mission.builtins:
            raise UserError(
                Diagnostic(
                    node.loc,
                    f"`{node.id}` waits on the wall clock: a tick-exact suite cannot run it "
                    "(BehaviorTree.CPP takes no test clock)",
                )
            )
    for node in _all_nodes(mission):
        if not is_scripted_leaf(mission, node) or node.id in found:
            continue
        try:
            spec = mission.spec(node.id)
        except KeyError:
            raise UserError(
                Diagnostic(node.loc, f"`{node.id}` has no model: declare it in <TreeNodesModel> or pass --models")
            ) from None
        ports = [(_DIRS[p.direction], p.name) for p in spec.ports]
        found[node.id] = LeafDecl(node.id, leaf_kind(mission, node) == "Condition", ports)
    return [found[k] for k in sorted(found)]


def refuse_462_scripts(mission: Mission) -> None:
    """The scripts BehaviorTree.CPP 4.6.2's parser refuses and btgen loads on purpose (an operator
    in a comparison's operand: `a + 1 == 4`, `x == -1`; grammar462.Strict462Parser): the real
    library would refuse the mission, so no suite for it could pass. UserError, each located."""
    from btgen.lang.script.grammar462 import Strict462Parser
    from btgen.lang.script.nodes import ScriptSyntaxError
    from btgen.lang.script.parse import raw_attr_value, script_error_loc

    problems: list[Diagnostic] = []
    for node in _all_nodes(mission):
        for attr in (*node.ports, *node.pre, *node.post):
            if attr.script is None or attr.value == "":
                continue  # (an empty script loads on 4.6.2: frontend/loader/checks.py _with_script)
            try:
                Strict462Parser(attr.value).script()
            except ScriptSyntaxError as e:
                where = script_error_loc(attr.value_loc, attr.value, e.offset, raw_attr_value(attr.value_loc))
                problems.append(
                    Diagnostic(
                        where,
                        f"BehaviorTree.CPP 4.6.2 refuses this script in `{attr.name}` of `{node.id}` ({e.message}: "
                        "its parser takes no operator in an operand of a comparison); btgen loads it as 4.9.0 "
                        "does, but the suite's library would not: parenthesise it, e.g. `(a + 1) == 4`, `x == (-1)`",
                    )
                )
    if problems:
        raise UserError(problems)


# ---------------------------------------------------------------- scenarios and names
def _ident(text: str) -> str:
    words = re.findall(r"[A-Za-z0-9]+", text)
    out = "".join(w[:1].upper() + w[1:] for w in words)
    return out or "Node"


def name_cases(cases: list[Case]) -> None:
    """Each TEST is named after the first thing it covers that no earlier one did: a halt of a
    RUNNING node, else an outcome (FAILURE, RUNNING, SUCCESS) of the deepest such node."""
    uids: dict[str, set[str]] = {}
    for case in cases:
        for line in case.trace:
            m = _LINE.match(line)
            if m:
                uids.setdefault(m.group(3), set()).add(m.group(1))
    seen: set[tuple] = set()
    for i, case in enumerate(cases, start=1):
        goals: list[tuple[int, tuple, str]] = []
        status: dict[str, str] = {}
        for line in case.trace:
            m = _LINE.match(line)
            if not m:
                continue
            uid, _, quoted, frm, to = m.groups()
            label = f"`{quoted[1:-1]}`"
            if len(uids[quoted]) > 1:  # a name several nodes share: the UID says which
                label += f" (UID {uid})"
            if frm == "RUNNING" and to == "IDLE":
                goals.append((0, ("halt", uid), f"{label} halted while RUNNING"))
            if to != "IDLE":
                rank = {"FAILURE": 1, "RUNNING": 2, "SUCCESS": 3}[to]
                goals.append((rank, ("out", uid, to), f"{label} returns {to}"))
            status[uid] = to
        new = []
        for rank, key, words in goals:
            if key not in seen:
                seen.add(key)
                new.append((rank, -int(key[1]), words))
        new.sort(key=lambda g: (g[0], g[1]))
        case.covers = [w for _, _, w in new]
        head = new[0][2] if new else "the same as before, another path"
        words = head.replace(" returns ", " ").replace(" while ", " ")
        for st in ("SUCCESS", "FAILURE", "RUNNING"):
            words = words.replace(st, st.capitalize())
        case.name = f"S{i:02d}" + _ident(words)


def collect_cases(mission: Mission, scenario_texts: list[tuple[str, str]]) -> list[Case]:
    from btgen.interp.engine import run_trace
    from btgen.interp.scenario import parse_scenario_text

    cases: list[Case] = []
    for path, text in scenario_texts:
        sc = parse_scenario_text(text, path)
        if sc.clock_ms:
            raise UserError(Diagnostic(Loc(path, 1, 1), "clock_ms: a tick-exact suite has no clock"))
        if sc.default != "SUCCESS":
            where = sc.default_loc or Loc(path, 1, 1)
            raise UserError(Diagnostic(where, "`default` other than SUCCESS: not supported by `btgen tests`"))
        parts: list[str] = []
        error = ""
        try:
            run_trace(mission, sc, parts.append)
        except UserError as e:  # a run-time error ends the run: the library throws there too
            error = e.diagnostics[0].message if e.diagnostics else "run-time error"
        trace = "".join(parts)
        lines = trace.splitlines() + (["error"] if error else [])
        lists = [(s.name, list(s.statuses)) for s in sc.leaves]
        cases.append(Case("", [], sc.ticks, lists, lines, trace, text=text, error=error))
    name_cases(cases)
    return cases


def explored_scenarios(mission: Mission, args) -> list[tuple[str, str]]:
    from btgen.tools.explore import Explorer, _possible, criteria_of, scenario_text

    criteria = criteria_of(args)
    ex = Explorer(
        mission, args.ticks, args.depth, 0, args.max_states, (), _possible(mission, args), True, criteria=criteria
    )
    result = ex.explore()
    if result.truncated:
        print(
            f"{args.mission}: warning: exploration stopped at --max-states {args.max_states}: the suite "
            "covers what was reached",
            file=sys.stderr,
        )
    return [(f"<scenario {i}>", scenario_text(p, 0)) for i, p in enumerate(result.paths, start=1)]


def name_obligations(mission: Mission, args, texts: list[tuple[str, str]], cases: list[Case]) -> None:
    """With --coverage condition or mcdc: each case's comment names the pre- and post-condition
    ways and the MC/DC evaluations (operand values of an `&&`/`||` expression) no earlier case
    reaches (the interpreter's replay of the scenario)."""
    from btgen.interp.scenario import parse_scenario_text
    from btgen.tools import obligations
    from btgen.tools.explore import Explorer, Places, _possible, criteria_of

    criteria = criteria_of(args)
    if not {"condition", "mcdc"} & set(criteria):
        return
    ex = Explorer(mission, possible=_possible(mission, args), criteria=criteria)
    places = Places(mission, ex.nodes)
    seen: set = set()
    for (path, text), case in zip(texts, cases):
        goals = ex.replay(parse_scenario_text(text, path))
        new = sorted((g for g in goals - seen if g[0] in ("pre", "post", "eval")), key=str)
        seen |= goals
        for g in new:
            who = places.path(g[1]).rsplit("/", 1)[-1]
            if g[0] == "eval":
                site = ex.obligations.sites[(g[1], g[2])][g[3]]
                vals = ", ".join("T" if v else "F" for v in g[4])
                operands = ", ".join(f"`{t}`" for t in site.text)
                result = "true" if g[5] else "false"
                case.obligations.append(f"`{who}` {g[2]}: operands {operands} = ({vals}) -> {result}")
            elif g in ex.obligations.goals:
                case.obligations.append(f"`{who}` {obligations.describe(g)}")


# ---------------------------------------------------------------- rendering
def _c_string(text: str) -> str:
    out = []
    for ch in text:
        if ch in '"\\':
            out.append("\\" + ch)
        elif ch == "\n":
            out.append("\\n")
        elif ord(ch) < 0x20 or ord(ch) == 0x7F:
            out.append(f'\\x{ord(ch):02X}""')
        elif ch == "?":
            out.append("\\?")  # no trigraphs
        else:
            out.append(ch)
    return '"' + "".join(out) + '"'


def render_tests(
    stem: str,
    suite: str,
    leaves: list[LeafDecl],
    cases: list[Case],
    version: str,
    enums=(),
    trees=(),
    entries: Optional[tuple[list[str], list[str]]] = None,
) -> str:
    head = []
    if entries is not None:
        includes, creates = entries
        head += [
            *includes,
            "#include <behaviortree_cpp/blackboard.h>",
            "// The entries the application sets before the first tick (--entry): created on the root",
            "// blackboard, with their type and no value, before the tree (as btgen's engines create them).",
            "inline void btgen_entries(BT::Blackboard& blackboard)",
            "{",
            *creates,
            "}",
            "#define BTGEN_ENTRIES btgen_entries",
        ]
    if trees:
        head += [
            "// The tree libraries (--trees), relative to the suite's folder: registered before the mission.",
            f"#define BTGEN_TREES {{ {', '.join(_c_string(t) for t in trees)} }}",
        ]
    if enums:
        pairs = ", ".join(f"{{ {_c_string(name)}, {value} }}" for name, value in enums)
        head += [
            "// The scripting enums (--enum / --enums): registerScriptingEnum before the tree is created.",
            f"#define BTGEN_ENUMS {{ {pairs} }}",
        ]
    out = [
        f"// Written by `btgen tests` for BehaviorTree.CPP {version}: {len(cases)} scenarios of {stem}.",
        "// Each TEST reads the mission file (BTGEN_MISSION, set by CMakeLists.txt), scripts every",
        "// user leaf, ticks the tree with tickExactlyOnce() and checks every status change and the",
        "// root's results against the trace btgen's interpreter gives for the same scenario.",
        "// Regenerate with `btgen tests`; do not edit.",
        *head,
        f'#include "{SUPPORT}"',
        "",
        "namespace",
        "{",
        "using btgen_tests::Leaf;",
        "using BT::NodeStatus;",
        "using BT::PortDirection;",
        "constexpr NodeStatus S = NodeStatus::SUCCESS;",
        "constexpr NodeStatus F = NodeStatus::FAILURE;",
        "constexpr NodeStatus R = NodeStatus::RUNNING;",
        "",
        "// The user leaves the mission uses: registered as scripted Actions and Conditions.",
        "const std::vector<Leaf>& leaves()",
        "{",
        "  static const std::vector<Leaf> all = {",
    ]
    for leaf in leaves:
        ports = ", ".join(f"{{ PortDirection::{d}, {_c_string(n)} }}" for d, n in leaf.ports)
        cond = "true" if leaf.condition else "false"
        port_list = f"{{ {ports} }}" if ports else "{}"
        out.append(f"    {{ {_c_string(leaf.id)}, {cond}, {port_list} }},")
    out += ["  };", "  return all;", "}", "}  // namespace", ""]
    letter = {"SUCCESS": "S", "FAILURE": "F", "RUNNING": "R"}
    for k, case in enumerate(cases, start=1):
        out.append(f"// Scenario {k} of {len(cases)}. Covers first: " + ("; ".join(case.covers[:3]) or "-"))
        if len(case.covers) > 3:
            out.append(f"// ... and {len(case.covers) - 3} more outcomes or halts no earlier scenario shows.")
        for line in case.obligations:
            out.append(f"// Reaches first: {line}")
        if case.error:
            out.append(f"// Ends with a run-time error (the library throws): {' '.join(case.error.split())}")
        width = max([4] + [len(n) for n, _ in case.lists])
        out.append(f"//   ticks at most {case.ticks}")
        out.append(f"//   {'leaf'.ljust(width)} | results, call by call (the last repeats; unlisted: SUCCESS)")
        out.append(f"//   {'-' * width}-+-{'-' * 40}")
        for name, statuses in case.lists:
            out.append(f"//   {name.ljust(width)} | {' '.join(statuses)}")
        out.append(f"TEST({suite}, {case.name})")
        out.append("{")
        out.append("  btgen_tests::Script script;")
        for name, statuses in case.lists:
            out.append(f"  script.lists[{_c_string(name)}] = {{ {', '.join(letter[s] for s in statuses)} }};")
        out.append("  static const char* const expected[] = {")
        for line in case.trace:
            out.append(f"    {_c_string(line)},")
        out.append("  };")
        out.append(f"  btgen_tests::runAndCheck(leaves(), script, {case.ticks}, expected);")
        out.append("}")
        out.append("")
    return "\n".join(out)


def _cmake_string(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"').replace("$", "\\$").replace(";", "\\;") + '"'


def render_cmake(
    stem: str,
    suite: str,
    mission_ref: str,
    main_tree: Optional[str],
    cases: list[Case],
    executor: Optional[list[str]] = None,
    trees: bool = False,
    register: tuple[str, ...] = (),
) -> str:
    """CMakeLists.txt; with `executor` (btgen's options for `btgen run`), a second ctest entry
    per scenario that runs it on btgen's compiled executor, and the library's suite optional."""
    target = f"{suite}_tests"
    lines = [
        "# Written by `btgen tests`: the GoogleTest suite of " + stem + " for BehaviorTree.CPP.",
        "#   cmake -S . -B build -DCMAKE_PREFIX_PATH=<BehaviorTree.CPP prefix> && cmake --build build",
        "#   ctest --test-dir build",
        "cmake_minimum_required(VERSION 3.16)",
        f"project({target} CXX)",
        "set(CMAKE_CXX_STANDARD 17)",
        "set(CMAKE_CXX_STANDARD_REQUIRED ON)",
    ]
    if executor is not None:
        lines += [
            "# OFF: only the scenarios on btgen's compiled executor (no BehaviorTree.CPP needed)",
            'option(BTGEN_LIBRARY_TESTS "the GoogleTest suite on BehaviorTree.CPP" ON)',
            "if(BTGEN_LIBRARY_TESTS)",
            "  find_package(behaviortree_cpp REQUIRED)",
            "  find_package(GTest REQUIRED)",
            "endif()",
        ]
    else:
        lines += ["find_package(behaviortree_cpp REQUIRED)", "find_package(GTest REQUIRED)"]
    lines += [
        "enable_testing()",
        "",
        "# The mission the tests read at run time: absolute, or relative to this folder.",
        f"set(BTGEN_MISSION {_cmake_string(mission_ref)} CACHE STRING "
        '"the mission file the tests read (absolute, or relative to this folder)")',
        'get_filename_component(BTGEN_MISSION_PATH "${BTGEN_MISSION}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_SOURCE_DIR}")',
        "",
    ]
    lines += [
        "# The project's own nodes: registration sources compiled into the suite (each adds a",
        "# btgen_tests::Hook, btgen_gtest_support.hpp), BT_REGISTER_NODES plugins loaded with",
        "# registerFromPlugin, and the folders their headers are in (lists; relative to this folder).",
        f"set(BTGEN_REGISTER {_cmake_string(';'.join(register))} CACHE STRING "
        '"registration sources of the project nodes (relative to this folder)")',
        'set(BTGEN_PLUGINS "" CACHE STRING "plugin libraries of the project nodes (registerFromPlugin)")',
        'set(BTGEN_INCLUDE_DIRS "" CACHE STRING "include folders of the registration sources")',
        "",
    ]
    library = [
        "set(btgen_register_sources)",
        "foreach(file IN LISTS BTGEN_REGISTER)",
        '  get_filename_component(file "${file}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_SOURCE_DIR}")',
        '  list(APPEND btgen_register_sources "${file}")',
        "endforeach()",
        f"add_executable({target} {suite}_tests.cpp ${{btgen_register_sources}})",
        f"target_link_libraries({target} PRIVATE BT::behaviortree_cpp GTest::gtest GTest::gtest_main)",
        f'target_include_directories({target} PRIVATE "${{CMAKE_CURRENT_SOURCE_DIR}}" ${{BTGEN_INCLUDE_DIRS}})',
        "if(BTGEN_REGISTER)",
        f"  set_target_properties({target} PROPERTIES ENABLE_EXPORTS ON)  # a plugin may call back into it",
        "endif()",
        "if(BTGEN_PLUGINS)",
        "  set(btgen_plugins)",
        "  foreach(file IN LISTS BTGEN_PLUGINS)",
        '    get_filename_component(file "${file}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_SOURCE_DIR}")',
        '    string(REPLACE "\\\\" "\\\\\\\\" file "${file}")',
        '    string(REPLACE "\\"" "\\\\\\"" file "${file}")',
        '    string(APPEND btgen_plugins "\\"${file}\\",\\n")',
        "  endforeach()",
        '  file(WRITE "${CMAKE_CURRENT_BINARY_DIR}/btgen_plugins.inc" "${btgen_plugins}")',
        f"  target_compile_definitions({target} PRIVATE "
        '"BTGEN_PLUGINS_FILE=\\"${CMAKE_CURRENT_BINARY_DIR}/btgen_plugins.inc\\"")',
        "endif()",
        f'target_compile_definitions({target} PRIVATE "BTGEN_MISSION=\\"${{BTGEN_MISSION_PATH}}\\""',
    ]
    if main_tree is not None:
        library.append(f"  {_cmake_string('BTGEN_MAIN_TREE=' + _c_string(main_tree))}")
    if trees:
        library.append('  "BTGEN_SOURCE_DIR=\\"${CMAKE_CURRENT_SOURCE_DIR}\\""')
    library.append(")")
    for case in cases:
        library.append(f"add_test(NAME {suite}.{case.name} COMMAND {target} --gtest_filter={suite}.{case.name})")
    if executor is None:
        lines += library
        return "\n".join(lines) + "\n"
    lines += ["if(BTGEN_LIBRARY_TESTS)"] + [f"  {line}" for line in library] + ["endif()", ""]
    lines += [
        "# The same scenarios on btgen's compiled executor: `btgen run --engine cpp` (built once,",
        "# cached) on scenarios/<TEST>.scenario, its trace compared with executor/<TEST>.trace (the interpreter's).",
        'set(BTGEN_COMMAND "btgen" CACHE STRING "the command that runs btgen (e.g. `python3 -m btgen`)")',
        f"set(BTGEN_RUN_OPTIONS {_cmake_string(' '.join(executor))})",
    ]
    for case in cases:
        scenario = f"${{CMAKE_CURRENT_SOURCE_DIR}}/{SCENARIOS}/{case.name}.scenario"
        trace = f"${{CMAKE_CURRENT_SOURCE_DIR}}/executor/{case.name}.trace"
        lines.append(
            f"add_test(NAME {suite}.{case.name}.executor COMMAND ${{CMAKE_COMMAND}} "
            '"-DBTGEN=${BTGEN_COMMAND}" "-DMISSION=${BTGEN_MISSION_PATH}" "-DOPTIONS=${BTGEN_RUN_OPTIONS}" '
            f'"-DSCENARIO={scenario}" "-DEXPECTED={trace}" '
            '-P "${CMAKE_CURRENT_SOURCE_DIR}/executor/check.cmake")'
        )
    return "\n".join(lines) + "\n"


CHECK_CMAKE = """# Written by `btgen tests --executor`: one scenario on btgen's compiled executor.
# cmake -DBTGEN=<command> -DMISSION=<file> -DOPTIONS=<options> -DSCENARIO=<file> -DEXPECTED=<file> -P check.cmake
separate_arguments(btgen UNIX_COMMAND "${BTGEN}")
separate_arguments(options UNIX_COMMAND "${OPTIONS}")
execute_process(
  COMMAND ${btgen} run "${MISSION}" --scenario "${SCENARIO}" --engine cpp ${options}
  OUTPUT_VARIABLE got
  ERROR_VARIABLE err
  RESULT_VARIABLE rc)
string(REGEX REPLACE "\\\\.trace$" ".error" error_file "${EXPECTED}")
if(EXISTS "${error_file}")
  # the run ends with a run-time error: exit status 1 and that error on stderr
  file(READ "${error_file}" want_error)
  string(STRIP "${want_error}" want_error)
  string(FIND "${err}" "error: ${want_error}" at)
  if(NOT rc EQUAL 1 OR at EQUAL -1)
    message(FATAL_ERROR "expected the run to end with `error: ${want_error}`; the executor gave (${rc}):\\n${err}")
  endif()
elseif(NOT rc EQUAL 0)
  message(FATAL_ERROR "btgen run --engine cpp failed (${rc}):\\n${err}")
endif()
file(READ "${EXPECTED}" want)
if(NOT got STREQUAL want)
  string(REPLACE "\\n" ";" got_lines "${got}")
  string(REPLACE "\\n" ";" want_lines "${want}")
  list(LENGTH want_lines n)
  set(k 0)
  foreach(line IN LISTS want_lines)
    list(LENGTH got_lines m)
    if(k LESS m)
      list(GET got_lines ${k} other)
    else()
      set(other "(nothing)")
    endif()
    if(NOT other STREQUAL line)
      math(EXPR shown "${k} + 1")
      message(FATAL_ERROR "line ${shown}: expected `${line}`, the executor gave `${other}`")
    endif()
    math(EXPR k "${k} + 1")
  endforeach()
  message(FATAL_ERROR "the executor's trace is longer than the expected one")
endif()
"""


# ---------------------------------------------------------------- the command
def _inside(path: str, folder: str) -> bool:
    path, folder = os.path.realpath(path), os.path.realpath(folder)
    return path == folder or path.startswith(folder.rstrip(os.sep) + os.sep)


def _check_paths(args, mission: Mission) -> None:
    out = args.output_dir
    inputs = list(mission.files) + list(args.models) + list(args.scenarios or [])
    for f in inputs:
        if _inside(f, out):
            raise cmdline.error(
                args, "-o", f"-o {out}: the folder holds an input ({f}); it would be replaced: choose another folder"
            )
    if os.path.lexists(out):
        if not os.path.isdir(out) or os.path.islink(out):
            raise cmdline.error(args, "-o", f"-o {out}: exists and is not a folder")
        if os.listdir(out) and not os.path.isfile(os.path.join(out, MARKER)):
            raise cmdline.error(
                args, "-o", f"-o {out}: a folder `btgen tests` did not write (no {MARKER}): refusing to replace it"
            )


def _mission_ref(args) -> str:
    out = os.path.abspath(args.output_dir)
    ref = args.mission_path
    if ref is None:
        ref = os.path.relpath(os.path.abspath(args.mission), out)
    else:
        resolved = ref if os.path.isabs(ref) else os.path.join(out, ref)
        if not (os.path.isfile(resolved) and os.path.samefile(resolved, args.mission)):
            raise cmdline.error(
                args, "--mission-path", f"--mission-path {ref}: does not name {args.mission} from {args.output_dir}"
            )
    if any(ord(c) < 0x20 or c in '"\\$;' for c in ref):
        raise cmdline.error(args, "--mission-path", f"the mission path {ref!r} has characters CMake cannot carry")
    return ref


def write_suite(out: str, files: dict[str, str]) -> None:
    """DIR whole or unchanged: written beside it, then renamed into place."""
    parent = os.path.dirname(os.path.abspath(out))
    try:
        os.makedirs(parent, exist_ok=True)
        tmp = tempfile.mkdtemp(dir=parent, prefix=".btgen-tests-")
    except OSError as e:
        raise UserError(Diagnostic(Loc(out, 1, 1), f"cannot create the output folder: {e.strerror or e}")) from None
    old = None
    try:
        for name, text in files.items():
            path = os.path.join(tmp, name)
            os.makedirs(os.path.dirname(path), exist_ok=True)
            with open(path, "w", encoding="utf-8", newline="\n") as f:
                f.write(text)
            if os.path.dirname(name):
                os.chmod(os.path.dirname(path), 0o777 & ~_umask())
        os.chmod(tmp, 0o777 & ~_umask())
        if os.path.exists(out):
            old = tempfile.mkdtemp(dir=parent, prefix=".btgen-tests-old-")
            os.rename(out, os.path.join(old, "suite"))
        os.rename(tmp, out)
    except OSError as e:
        if old is not None and not os.path.exists(out):
            os.rename(os.path.join(old, "suite"), out)
        shutil.rmtree(tmp, ignore_errors=True)
        raise UserError(Diagnostic(Loc(out, 1, 1), f"cannot write the suite: {e.strerror or e}")) from None
    finally:
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)


def _umask() -> int:
    m = os.umask(0)
    os.umask(m)
    return m


def build_suite(args) -> tuple[dict[str, str], list[Case]]:
    from btgen import pipeline
    from btgen.interp.scenario import _read_text, load_scenario
    from btgen.tools.explore import criteria_of

    criteria_of(args)  # a bad --coverage is refused before anything else
    opts = pipeline.options_from_args(args)
    mission = pipeline.load(args.mission, opts)
    print_diagnostics(mission.warnings)
    entries = entry_lines(args, mission)
    leaves = mission_leaves(mission)
    if not mission.semantics.script_grammar_49:
        refuse_462_scripts(mission)
    _check_paths(args, mission)
    ref = _mission_ref(args)
    if args.scenarios:
        texts = []
        for p in args.scenarios:
            _, warnings = load_scenario(p, mission)  # raises on errors
            print_diagnostics(warnings)
            texts.append((p, _read_text(p)))
    else:
        texts = explored_scenarios(mission, args)
    cases = collect_cases(mission, texts)
    name_obligations(mission, args, texts, cases)
    stem = os.path.splitext(os.path.basename(args.mission))[0]
    suite = _ident(stem)
    if suite[0].isdigit():
        suite = "M" + suite  # an identifier
    with open(os.path.join(os.path.dirname(__file__), "support.hpp"), encoding="utf-8") as f:
        support = f.read()
    executor = _run_options(args, opts) if getattr(args, "executor", False) else None
    trees = tree_files(args, opts, mission)
    register = register_files(args)
    # with tree libraries the mission is registered too and its main tree created by name
    main_tree = opts.main_tree if not trees else mission.main_tree
    files = {
        "CMakeLists.txt": render_cmake(stem, suite, ref, main_tree, cases, executor, bool(trees), register),
        f"{suite}_tests.cpp": render_tests(stem, suite, leaves, cases, opts.btcpp, mission.enums, trees, entries),
        SUPPORT: support,
        **{f"{SCENARIOS}/{case.name}.scenario": case.text for case in cases},
        MARKER: f"written by btgen tests for {os.path.basename(args.mission)} (BehaviorTree.CPP {opts.btcpp})\n",
    }
    if executor is not None:
        files["executor/check.cmake"] = CHECK_CMAKE
        for case in cases:  # the scenario is the TEST's own, scenarios/<TEST>.scenario
            files[f"executor/{case.name}.trace"] = case.trace_text
            if case.error:  # the run ends with this error (stderr, exit status 1)
                files[f"executor/{case.name}.error"] = case.error + "\n"
    return files, cases


_CPP_TYPES = {
    "int": "int",
    "unsigned": "unsigned",
    "double": "double",
    "bool": "bool",
    "string": "std::string",
    "NodeStatus": "BT::NodeStatus",
    "any": "BT::AnyTypeAllowed",
    "queue<int>": "std::shared_ptr<std::deque<int>>",
    "queue<double>": "std::shared_ptr<std::deque<double>>",
    "queue<bool>": "std::shared_ptr<std::deque<bool>>",
    "queue<string>": "std::shared_ptr<std::deque<std::string>>",
}


def entry_lines(args, mission: Mission) -> Optional[tuple[list[str], list[str]]]:
    """--entry: the `#include`s of the user types the entries have (--type) and one createEntry
    line per entry; None without --entry. An entry of every instance of a BehaviorTree
    (`TREE:NAME`) is refused: the library creates those blackboards inside createTree, after
    the nodes before them are built, so the suite could not create it when btgen's engines do."""
    if not mission.provided:
        return None
    users = {u.name: u for u in mission.user_types}
    includes: list[str] = []
    creates: list[str] = []
    for entry in mission.provided:
        if entry.tree is not None:
            raise cmdline.error(
                args,
                "--entry",
                f"{entry.option}: an entry of every instance of `{entry.tree}`: not supported by `btgen tests` "
                "(BehaviorTree.CPP creates that blackboard inside createTree; only root entries can be created "
                "before the tree, as btgen's engines do)",
            )
        user = users.get(entry.type)
        if user is not None:
            line = f"#include {user.include}"
            if line not in includes:
                includes.append(line)
            cpp = user.cpp
        else:
            cpp = _CPP_TYPES[entry.type]
        creates.append(f"  blackboard.createEntry({_c_string(entry.key)}, BT::TypeInfo::Create<{cpp}>());")
    return includes, creates


def tree_files(args, opts, mission: Mission) -> list[str]:
    """The files of --trees as the loader reads them (a folder: its `*.xml`, in name order; the
    mission itself and repeats left out), each relative to DIR (absolute when --mission-path
    is), for registerBehaviorTreeFromFile."""
    out: list[str] = []
    seen = {os.path.realpath(mission.path)}
    base = os.path.abspath(args.output_dir)
    absolute = bool(args.mission_path) and os.path.isabs(args.mission_path)
    for path in opts.trees:
        found = xml_files_of(path) if os.path.isdir(path) else [path]
        for f in found:
            real = os.path.realpath(f)
            if real in seen:
                continue
            seen.add(real)
            ref = os.path.abspath(f) if absolute else os.path.relpath(os.path.abspath(f), base)
            if any(ord(c) < 0x20 for c in ref):
                raise cmdline.error(args, "--trees", f"--trees: the path {ref!r} has characters C++ cannot carry")
            out.append(ref)
    return out


def register_files(args) -> tuple[str, ...]:
    """--register FILE.cpp: each relative to DIR (absolute with an absolute --mission-path), for
    the CMake list BTGEN_REGISTER; a file that does not exist is an error."""
    out: list[str] = []
    base = os.path.abspath(args.output_dir)
    absolute = bool(args.mission_path) and os.path.isabs(args.mission_path)
    for path in getattr(args, "register", None) or ():
        if not os.path.isfile(path):
            raise cmdline.error(args, "--register", f"--register {path}: no such file")
        if _inside(path, args.output_dir):
            raise cmdline.error(
                args, "--register", f"--register {path}: inside -o {args.output_dir}, which is replaced"
            )
        ref = os.path.abspath(path) if absolute else os.path.relpath(os.path.abspath(path), base)
        if any(ord(c) < 0x20 or c in '"\\$;' for c in ref):
            raise cmdline.error(args, "--register", f"--register: the path {ref!r} has characters CMake cannot carry")
        out.append(ref)
    return tuple(out)


def _run_options(args, opts) -> list[str]:
    """The options `btgen run` needs to load the mission as this command did: models (absolute),
    main tree, version; each double-quoted for CMake's separate_arguments."""
    out: list[str] = []
    for m in opts.models:
        out += ["--models", os.path.abspath(m)]
    if opts.main_tree is not None:
        out += ["--main-tree", opts.main_tree]
    if opts.btcpp != "4.6.2":
        out += ["--btcpp", opts.btcpp]
    if opts.nodes is not None:
        out += ["--nodes", opts.nodes]
    for decl in opts.enum_decls:
        out += ["--enum", decl]
    for t in opts.trees:
        out += ["--trees", os.path.abspath(t)]
    for f in opts.enum_files:
        out += ["--enums", os.path.abspath(f)]
    for decl in opts.entries:
        out += ["--entry", decl]
    for decl in opts.types:
        out += ["--type", decl]
    for word in out:
        if any(ord(c) < 0x20 or c in '"\\$;' for c in word):
            raise cmdline.error(args, "--executor", f"--executor: {word!r} has characters CMake cannot carry")
    return [f'"{w}"' for w in out]


def tests_command(args) -> int:
    files, cases = build_suite(args)
    write_suite(args.output_dir, files)
    size = sum(len(t.encode("utf-8")) for t in files.values())
    lines = sum(t.count("\n") for t in files.values())
    tests = "1 test" if len(cases) == 1 else f"{len(cases)} tests"
    print(f"{args.output_dir}: {tests}, {len(files)} files, {lines} lines, {size} bytes")
    return 0
