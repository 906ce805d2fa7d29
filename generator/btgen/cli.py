"""The `btgen` command line.

Exit status: 0 success, 1 invalid input (diagnostics on stderr),
2 command-line misuse, 3 internal error (a bug in btgen).
"""

from __future__ import annotations

import argparse
import sys
import traceback
from collections.abc import Sequence
from typing import Callable

from btgen.cmdline import Parser
from btgen.diagnostics import Diagnostic, InternalError, UserError, new_run, print_diagnostics
from btgen.pipeline import add_mission_options
from btgen.version import __version__

EXIT_OK, EXIT_INPUT, EXIT_INTERNAL = 0, 1, 3


class _PrintCMakeDir(argparse.Action):
    def __call__(self, parser, namespace, values, option_string=None):
        from btgen.resources import CMAKE_DIR

        print(CMAKE_DIR)
        raise SystemExit(EXIT_OK)


def _cmd_validate(args: argparse.Namespace) -> int:
    from btgen import pipeline
    from btgen.compiler import generate_checked

    opts = pipeline.options_from_args(args)
    status = EXIT_OK
    for path in args.missions:
        try:
            # Every step of `btgen compile` but writing (the data side: blackboard entries, port
            # and entry types, scripts, capacities; lowering; rendering): validate rejects all
            # it rejects.
            said: list[Diagnostic] = []  # the program's warnings: what throws only when a node runs
            mission, _ = generate_checked(
                path,
                opts,
                loaded=lambda m: None if args.quiet else print_diagnostics(m.warnings),
                lowered=lambda p, said=said: said.extend(p.warnings),  # type: ignore[misc]
            )
            if not args.quiet:
                from btgen.tools.analyze import unwritten_script_reads

                print_diagnostics(said)
                lines = {(d.loc.path, d.loc.line) for d in said}  # (said once)
                print_diagnostics(
                    [d for d in unwritten_script_reads(mission, opts.data) if (d.loc.path, d.loc.line) not in lines]
                )
                trees = f"{len(mission.trees)} tree{'' if len(mission.trees) == 1 else 's'}"
                print(f"{path}: ok ({trees}, main `{mission.main_tree}`)")
        except UserError as e:
            print_diagnostics(e.diagnostics)
            status = EXIT_INPUT
    return status


def _cmd_analyze(args: argparse.Namespace) -> int:
    from btgen.tools.analyze import analyze_command, stop_quietly_on_broken_pipe

    return stop_quietly_on_broken_pipe(analyze_command, args)


def _cmd_explore(args: argparse.Namespace) -> int:
    from btgen.tools.analyze import stop_quietly_on_broken_pipe
    from btgen.tools.explore import explore_command

    return stop_quietly_on_broken_pipe(explore_command, args)


def _cmd_verify(args: argparse.Namespace) -> int:
    from btgen.tools.analyze import stop_quietly_on_broken_pipe
    from btgen.tools.verify import verify_command

    return stop_quietly_on_broken_pipe(verify_command, args)


def _cmd_tests(args: argparse.Namespace) -> int:
    from btgen.tools.gtests import tests_command

    return tests_command(args)


def _cmd_mutate(args: argparse.Namespace) -> int:
    from btgen.tools.analyze import stop_quietly_on_broken_pipe
    from btgen.tools.mutate import mutate_command

    return stop_quietly_on_broken_pipe(mutate_command, args)


def _cmd_cover(args: argparse.Namespace) -> int:
    from btgen.tools.analyze import stop_quietly_on_broken_pipe
    from btgen.tools.cover import cover_command

    return stop_quietly_on_broken_pipe(cover_command, args)


def _cmd_scenario_from_log(args: argparse.Namespace) -> int:
    from btgen.tools.analyze import stop_quietly_on_broken_pipe
    from btgen.tools.cover import scenario_from_log_command

    return stop_quietly_on_broken_pipe(scenario_from_log_command, args)


def _cmd_xsd(args: argparse.Namespace) -> int:
    from btgen import pipeline
    from btgen.frontend.xsd import mission_xsd

    mission = pipeline.load(args.mission, pipeline.options_from_args(args))
    sys.stdout.write(mission_xsd(mission))
    return EXIT_OK


def _cmd_run(args: argparse.Namespace) -> int:
    from btgen.tools.run import run_command

    return run_command(args)


def _cmd_compile(args: argparse.Namespace) -> int:
    from btgen.compiler import compile_command

    return compile_command(args)


def _cmd_lint_kb(args: argparse.Namespace) -> int:
    from btgen.kb.lint import lint_kb

    diags = lint_kb(args.kb, config_path=args.config, mission_path=args.mission)
    print_diagnostics(diags)
    return EXIT_INPUT if any(d.severity == "error" for d in diags) else EXIT_OK


def _cmd_bench(args: argparse.Namespace) -> int:
    from btgen.tools.bench import bench_command

    return bench_command(args)


def _cmd_init(args: argparse.Namespace) -> int:
    from btgen.tools.init import init_command

    return init_command(args)


def _cmd_graph(args: argparse.Namespace) -> int:
    from btgen.tools.graph import graph_command

    return graph_command(args)


def _cmd_upgrade_check(args: argparse.Namespace) -> int:
    if args.fix or args.output:
        from btgen.tools.upgrade_fix import fix_command

        return fix_command(args)
    from btgen.tools.upgrade import upgrade_command

    return upgrade_command(args)


def _cmd_diff(args: argparse.Namespace) -> int:
    from btgen.tools.analyze import stop_quietly_on_broken_pipe
    from btgen.tools.diff.command import diff_command

    return stop_quietly_on_broken_pipe(diff_command, args)


def _cmd_models(args: argparse.Namespace) -> int:
    from btgen.tools.models import models_command

    return models_command(args)


SYNC_HELP = (
    "an Action whose leaves implement it synchronously (a `tick()` hook, BehaviorTree.CPP's "
    "SyncActionNode): it never returns RUNNING, so RUNNING is no goal for it (repeatable)"
)
COVERAGE_HELP = (
    "the coverage criteria, comma-separated: node, outcome, halt, condition, mcdc, or all "
    "(default: node,outcome; docs/tests.md says what each asks)"
)


def _count(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"`{text}` is not a whole number") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"{value} is below 1")
    return value


def _percent(text: str) -> float:
    """A percentage for a CI gate: a finite number from 0 to 100 (never nan, which no
    coverage is below, nor 150, which every coverage is below)."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"`{text}` is not a number") from None
    if not 0.0 <= value <= 100.0:  # (false for nan)
        raise argparse.ArgumentTypeError(f"`{text}` is not a percentage from 0 to 100")
    return value


def build_parser() -> argparse.ArgumentParser:
    p = Parser(prog="btgen", description="Compile BehaviorTree.CPP v4 missions to static C++17.")
    p.add_argument("--version", action="version", version=f"btgen {__version__}")
    p.add_argument(
        "--cmake-dir",
        action=_PrintCMakeDir,
        nargs=0,
        help="print the folder of btgen's CMake package (for -Dbtgen_DIR=...) and exit",
    )
    sub = p.add_subparsers(dest="command", metavar="COMMAND", parser_class=Parser)
    sub.required = True

    v = sub.add_parser("validate", help="check missions; print every problem as path:line:col")
    v.add_argument("missions", nargs="+", metavar="MISSION.xml", help="the missions to check")
    v.add_argument(
        "-q",
        "--quiet",
        action="store_true",
        help="print errors only: nothing for a valid mission, not even its warnings",
    )
    add_mission_options(v)
    v.set_defaults(func=_cmd_validate)

    a = sub.add_parser(
        "analyze",
        help="what a mission can never do, the worst case of a tick, blackboard and reactive checks",
    )
    a.add_argument("missions", nargs="+", metavar="MISSION.xml", help="the missions to analyze")
    add_mission_options(a)
    a.add_argument("--json", action="store_true", help="print the findings and bounds as JSON")
    a.add_argument("--werror", action="store_true", help="exit 1 when there is any finding")
    a.add_argument(
        "--tick-budget", type=_count, metavar="N", help="warn when a bound of a tick (nodes, hooks, scripts) exceeds N"
    )
    a.set_defaults(func=_cmd_analyze)

    e = sub.add_parser(
        "explore",
        help="explore every leaf outcome up to a bound; write scenarios reaching full coverage; check properties",
    )
    e.add_argument("mission", metavar="MISSION.xml", help="the mission to explore")
    add_mission_options(e)
    e.add_argument("--ticks", type=_count, default=8, metavar="N", help="most root ticks of a run (default 8)")
    e.add_argument("--depth", type=_count, default=200, metavar="N", help="most leaf results in a run (default 200)")
    e.add_argument(
        "--max-states", type=_count, default=200000, metavar="N", help="stop after N explored states (default 200000)"
    )
    e.add_argument("--clock-ms", type=int, default=100, metavar="MS", help="virtual time per tick (default 100)")
    e.add_argument("-o", "--output-dir", metavar="DIR", help="write the covering scenarios there")
    e.add_argument(
        "--assert",
        dest="asserts",
        action="append",
        default=[],
        metavar="PROPERTY",
        help="a property to check on every run (docs/analysis.md: `never A SUCCESS before B SUCCESS`, "
        "`at most one child of N RUNNING`, `never A RUNNING`)",
    )
    e.add_argument(
        "--no-merge",
        action="store_true",
        help="do not cut repeated states: every path (slower; the most per tick seen is then exact)",
    )
    e.add_argument("--json", action="store_true", help="print the report as JSON")
    e.add_argument(
        "--keep-going",
        action="store_true",
        help="go on after a property's first violation (default: stop there; its counterexample is printed)",
    )
    e.add_argument("--sync", action="append", default=[], metavar="ID", help=SYNC_HELP)
    e.add_argument("--coverage", metavar="CRITERIA", help=COVERAGE_HELP)
    e.set_defaults(func=_cmd_explore)

    vf = sub.add_parser(
        "verify", help="prove LTL properties of a mission with SPIN; probabilities with Storm (--probabilities)"
    )
    vf.add_argument("mission", metavar="MISSION.xml", help="the mission whose properties to prove")
    add_mission_options(vf)
    from btgen.tools.verify import add_arguments as _verify_arguments

    _verify_arguments(vf)
    vf.set_defaults(func=_cmd_verify)

    from btgen.lang.versions import SUPPORTED_VERSIONS

    df = sub.add_parser(
        "diff",
        help="do two missions (or one under two versions) behave the same for every leaf outcome? "
        "equivalent, or a shortest scenario where they differ",
    )
    df.add_argument("old", nargs="?", metavar="OLD.xml", help="the mission before the change")
    df.add_argument(
        "new",
        nargs="?",
        metavar="NEW.xml",
        help="the mission after the change (may be OLD.xml itself); with --git: paths, like PATH",
    )
    df.add_argument(
        "paths",
        nargs="*",
        metavar="PATH",
        help="with --git: the files or folders of the working tree to compare (default: the current folder)",
    )
    df.add_argument(
        "--git",
        metavar="REV",
        help="compare the working tree with the git revision REV, mission by mission (the files found as "
        "`btgen check` finds them under the PATHs)",
    )
    add_mission_options(df, capacities=False)
    df.add_argument(
        "--btcpp-old",
        choices=SUPPORTED_VERSIONS,
        metavar="VERSION",
        help="the BehaviorTree.CPP release OLD.xml runs under (default: --btcpp, else 4.6.2)",
    )
    df.add_argument(
        "--btcpp-new",
        choices=SUPPORTED_VERSIONS,
        metavar="VERSION",
        help="the BehaviorTree.CPP release NEW.xml runs under (default: --btcpp, else 4.6.2)",
    )
    df.add_argument(
        "--models-old",
        action="append",
        default=[],
        metavar="FILE.xml",
        help="models files of OLD.xml instead of --models (e.g. one Nav2 distro's nav2_tree_nodes.xml; repeatable)",
    )
    df.add_argument(
        "--models-new",
        action="append",
        default=[],
        metavar="FILE.xml",
        help="models files of NEW.xml instead of --models (repeatable)",
    )
    df.add_argument(
        "--rename",
        action="append",
        default=[],
        metavar="OLD_ID=NEW_ID",
        help="a leaf of OLD.xml called NEW_ID in NEW.xml (its scenario name: the name attribute, else "
        "the ID); both get the same outcomes (repeatable)",
    )
    df.add_argument(
        "--counterexample",
        metavar="DIR",
        help="when they differ, write there old.scenario, new.scenario (the same unless --rename), "
        "the interpreter's trace of each (old.trace, new.trace) and the same runs as Groot2 logs "
        "(old.btlog, new.btlog)",
    )
    df.add_argument(
        "--max-ticks",
        type=_count,
        default=10,
        metavar="K",
        help="most root ticks of a run; when runs reach it the answer holds up to K ticks (default 10)",
    )
    df.add_argument(
        "--max-states",
        type=_count,
        default=200000,
        metavar="N",
        help="stop after N product states; the answer is then partial, not a proof, and says so (default 200000)",
    )
    df.add_argument(
        "--observe",
        metavar="WHAT",
        help="what must agree, comma-separated: leaf-calls (names and results), inputs (their input "
        "values), root (its result each tick), writes (main blackboard), transitions (every node's "
        "status changes); default: leaf-calls,inputs,root,writes",
    )
    df.add_argument("--clock-ms", type=int, default=100, metavar="MS", help="virtual time per tick (default 100)")
    df.add_argument(
        "--format",
        choices=("text", "markdown", "json"),
        default="text",
        metavar="FORMAT",
        help="the report: text (default), markdown (a pull-request comment) or json",
    )
    df.set_defaults(func=_cmd_diff)

    ts = sub.add_parser(
        "tests", help="write a GoogleTest suite that checks the mission on the real BehaviorTree.CPP, tick by tick"
    )
    ts.add_argument(
        "mission", metavar="MISSION.xml", help="the mission the suite checks (read from its path at test time)"
    )
    add_mission_options(ts, capacities=False)
    ts.add_argument("-o", "--output-dir", required=True, metavar="DIR", help="the suite's folder (replaced whole)")
    ts.add_argument(
        "--mission-path",
        metavar="PATH",
        help="the mission path the suite reads at test time: absolute, or relative to DIR "
        "(default: MISSION's path relative to DIR)",
    )
    ts.add_argument(
        "--scenarios",
        nargs="+",
        metavar="FILE.scenario",
        help="use these scenario files instead of exploring (default: the covering set `btgen explore` finds)",
    )
    ts.add_argument(
        "--ticks", type=_count, default=8, metavar="N", help="exploration: most root ticks of a run (default 8)"
    )
    ts.add_argument(
        "--depth", type=_count, default=200, metavar="N", help="exploration: most leaf results in a run (default 200)"
    )
    ts.add_argument(
        "--max-states",
        type=_count,
        default=200000,
        metavar="N",
        help="exploration: stop after N explored states (default 200000)",
    )
    ts.add_argument("--coverage", metavar="CRITERIA", help=COVERAGE_HELP)
    ts.add_argument(
        "--register",
        action="append",
        metavar="FILE.cpp",
        help="a source compiled into the suite that registers the project's own nodes (Controls, "
        "Decorators: a btgen_tests::Hook); repeatable (CMake: BTGEN_REGISTER, BTGEN_PLUGINS, BTGEN_INCLUDE_DIRS)",
    )
    ts.add_argument(
        "--executor",
        action="store_true",
        help="also run each scenario on btgen's compiled executor from ctest (`btgen run --engine cpp`; "
        "-DBTGEN_LIBRARY_TESTS=OFF builds no BehaviorTree.CPP suite)",
    )
    ts.set_defaults(func=_cmd_tests)

    mu = sub.add_parser(
        "mutate",
        help="how good a scenario suite is: mutants of the mission, killed by its scenarios or proved equivalent",
    )
    mu.add_argument("mission", metavar="MISSION.xml", help="the mission to mutate")
    add_mission_options(mu, capacities=False)
    mu.add_argument(
        "--tests",
        required=True,
        metavar="DIR",
        help="the suite: DIR/scenarios/*.scenario (what `btgen tests -o DIR` writes) or DIR/*.scenario",
    )
    mu.add_argument(
        "-o",
        "--output-dir",
        metavar="DIR",
        help="write every mutant there (M001-OPERATOR.xml) and, for each survivor, a scenario that kills it",
    )
    mu.add_argument(
        "--min-score",
        type=_percent,
        metavar="S",
        help="exit 1 when the mutation score (killed / non-equivalent, in %%) is below S",
    )
    mu.add_argument(
        "--max-ticks",
        type=_count,
        default=30,
        metavar="K",
        help="product search of a survivor: most root ticks of a run; reaching it leaves the mutant undecided "
        "(default 30)",
    )
    mu.add_argument(
        "--max-states",
        type=_count,
        default=10000,
        metavar="N",
        help="product search of a survivor: most product states; running out leaves the mutant undecided "
        "(default 10000)",
    )
    mu.add_argument(
        "--replay",
        choices=("both", "interp"),
        default="both",
        metavar="ENGINES",
        help="where a survivor's killing scenario is replayed: both (default: the interpreter and the compiled "
        "C++ executor, one build of the original and one of each survivor) or interp",
    )
    mu.add_argument(
        "--format",
        choices=("text", "json"),
        default="text",
        metavar="FORMAT",
        help="the report: text (default) or json",
    )
    mu.set_defaults(func=_cmd_mutate)

    cv = sub.add_parser("cover", help="node and outcome coverage of scenario files, traces and .btlog files")
    cv.add_argument("mission", metavar="MISSION.xml", help="the mission the runs ran")
    cv.add_argument("runs", nargs="+", metavar="RUN", help="FILE.scenario, a trace (`btgen run` output) or FILE.btlog")
    add_mission_options(cv)
    cv.add_argument("--table", action="store_true", help="one line per node: ticked, statuses seen, missing")
    cv.add_argument("--uncovered", action="store_true", help="the table's lines of nodes not fully covered")
    cv.add_argument("--graph", metavar="FILE.svg|FILE.dot", help="draw the mission coloured by coverage")
    cv.add_argument(
        "--min", type=_percent, metavar="PCT", help="exit 1, saying so, when node coverage is below PCT percent"
    )
    cv.add_argument("--sync", action="append", default=[], metavar="ID", help=SYNC_HELP)
    cv.add_argument("--coverage", metavar="CRITERIA", help=COVERAGE_HELP)
    cv.set_defaults(func=_cmd_cover)

    sl = sub.add_parser("scenario-from-log", help="the scenario that replays a .btlog on both engines")
    sl.add_argument("mission", metavar="MISSION.xml", help="the mission the log recorded")
    sl.add_argument("log", metavar="RUN.btlog", help="a Groot2 log (FileLogger2) of a run of the mission")
    sl.add_argument("-o", "--output", metavar="FILE.scenario", help="write it there (default: stdout)")
    sl.add_argument("--clock-ms", type=int, default=0, metavar="MS", help="clock_ms of the scenario (default 0)")
    add_mission_options(sl, capacities=False)
    sl.set_defaults(func=_cmd_scenario_from_log)

    x = sub.add_parser("xsd", help="print the XSD of a mission (its nodes and ports) for editors")
    x.add_argument("mission", metavar="MISSION.xml", help="the mission whose nodes and ports the XSD lists")
    add_mission_options(x, capacities=False)
    x.set_defaults(func=_cmd_xsd)

    r = sub.add_parser("run", help="run a mission with scripted leaves and print its status trace")
    r.add_argument("mission", metavar="MISSION.xml", help="the mission to run")
    r.add_argument(
        "--scenario",
        required=True,
        metavar="FILE.scenario",
        help="what each leaf returns, tick by tick (format: tests/conformance/FORMAT.md)",
    )
    r.add_argument(
        "--engine",
        choices=("interp", "cpp"),
        default="interp",
        metavar="ENGINE",
        help="interp: the reference interpreter (default); cpp: build the generated C++ and run it",
    )
    r.add_argument(
        "--substitute",
        metavar="FILE.json",
        help="BehaviorTree.CPP substitution rules (TestNodeConfigs, SubstitutionRules) applied to the leaves",
    )
    add_mission_options(r)
    r.set_defaults(func=_cmd_run)

    c = sub.add_parser("compile", help="generate C++17 for a mission")
    c.add_argument("mission", metavar="MISSION.xml", help="the mission to compile")
    c.add_argument(
        "-o",
        "--output-dir",
        default=".",
        metavar="DIR",
        help="the folder to write STEM.hpp and STEM.cpp into (default: the current folder)",
    )
    c.add_argument(
        "--substitute",
        metavar="FILE.json",
        help="a test build: BehaviorTree.CPP substitution rules (TestNodeConfigs, SubstitutionRules) "
        "applied to the leaves",
    )
    c.add_argument(
        "--relative-to",
        default=None,
        metavar="DIR",
        help="directory the banner's input path is relative to (default: the current one)",
    )
    add_mission_options(c, namespace=True)
    c.set_defaults(func=_cmd_compile)

    k = sub.add_parser("lint-kb", help="validate and lint an environment knowledge base")
    k.add_argument("kb", metavar="FILE.dat", help="the knowledge base to check")
    k.add_argument("--config", metavar="FILE", help="the lint configuration (which checks run, their severities)")
    k.add_argument(
        "--mission", metavar="MISSION.xml", help="also check the knowledge base against what this mission uses"
    )
    k.set_defaults(func=_cmd_lint_kb)

    from btgen.tools.check.command import add_parser as add_check_parser

    add_check_parser(sub)

    mo = sub.add_parser(
        "models",
        help="write a <TreeNodesModel> of the nodes a mission (or every file of a folder) uses but nowhere "
        "declares, inferred from their use",
    )
    mo.add_argument(
        "paths",
        nargs="+",
        metavar="PATH",
        help="a mission (with its includes), or folders and files: then one models file for all the "
        "BehaviorTree.CPP files found under them (btgen check then finds it beside them)",
    )
    mo.add_argument("-o", "--output", metavar="FILE.xml", help="write it there (default: standard output)")
    add_mission_options(mo, capacities=False)
    mo.set_defaults(func=_cmd_models)

    b = sub.add_parser("bench", help="build a mission with instant leaves and measure ticks")
    b.add_argument("mission", metavar="MISSION.xml", help="the mission to measure")
    b.add_argument("--ticks", type=int, default=100000, metavar="N", help="root ticks to measure (default 100000)")
    add_mission_options(b)
    b.set_defaults(func=_cmd_bench)

    i = sub.add_parser(
        "build-info",
        add_help=False,
        help="for build systems (btgen_add_mission): a mission's dependencies, outputs, class "
        "template; `btgen build-info --help` tells more",
    )
    i.add_argument("args", nargs=argparse.REMAINDER)  # main() hands them to btgen.compiler.main

    g = sub.add_parser("graph", help="draw a mission (Graphviz), optionally with the statuses of a run")
    g.add_argument("mission", metavar="MISSION.xml", help="the mission to draw")
    g.add_argument(
        "-o",
        "--output",
        required=True,
        metavar="FILE.svg|FILE.dot",
        help="the drawing to write: SVG (needs Graphviz's dot) or the dot text",
    )
    src = g.add_mutually_exclusive_group()
    src.add_argument("--trace", metavar="FILE", help="status trace (`btgen run` output): colour by status")
    src.add_argument("--btlog", metavar="FILE", help="Groot2 log (.btlog): colour by status")
    g.add_argument(
        "--tick", type=_count, metavar="N", help="with --trace: statuses at the end of tick N (default: last)"
    )
    g.add_argument("--record", type=_count, metavar="N", help="with --btlog: statuses after N records (default: all)")
    add_mission_options(g, capacities=False)
    g.set_defaults(func=_cmd_graph)

    n = sub.add_parser("init", help="write a starter robot project (mission, models, leaves, CMakeLists.txt)")
    n.add_argument("directory", metavar="DIR", help="the project's folder: new, or empty")
    n.add_argument(
        "--name", metavar="NAME", help="the CMake project, executable and C++ namespace (default: DIR's name)"
    )
    n.set_defaults(func=_cmd_init)
    from btgen.lang.versions import SUPPORTED_VERSIONS

    u = sub.add_parser(
        "upgrade-check",
        help="list where moving between BehaviorTree.CPP releases changes loading or behaviour (exit 1 if anything)",
    )
    u.add_argument("mission", metavar="MISSION.xml", help="the mission to check")
    u.add_argument(
        "--from",
        dest="from_version",
        choices=SUPPORTED_VERSIONS,
        default="4.6.2",
        metavar="VERSION",
        help="the release the mission runs on now: " + " or ".join(SUPPORTED_VERSIONS) + " (default 4.6.2)",
    )
    u.add_argument(
        "--to",
        dest="to_version",
        choices=SUPPORTED_VERSIONS,
        default="4.10.0",
        metavar="VERSION",
        help="the release to move to (default 4.10.0)",
    )
    u.add_argument(
        "--scenario",
        metavar="FILE.scenario",
        help="also run the mission on both versions and print where the traces part",
    )
    u.add_argument(
        "--fix",
        action="store_true",
        help="write the mission rewritten for --to into -o OUT (parenthesised scripts, IDs renamed, "
        "explicit attributes) and prove with `btgen diff` that OUT under --to behaves as the mission "
        "under --from, or say where it cannot",
    )
    u.add_argument("-o", "--output", metavar="FILE.xml", help="with --fix: the file to write (never the input)")
    u.add_argument(
        "--max-ticks",
        type=_count,
        default=10,
        metavar="K",
        help="with --fix: most root ticks of a run of the proof (default 10)",
    )
    u.add_argument(
        "--max-states",
        type=_count,
        default=200000,
        metavar="N",
        help="with --fix: product states the proof may visit before it stops, unfinished (default 200000)",
    )
    add_mission_options(u, capacities=False)
    u.set_defaults(func=_cmd_upgrade_check)

    return p


def main(argv: Sequence[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    new_run()
    if argv[:1] == ["build-info"]:  # argparse's REMAINDER would not pass on `--deps ...`
        from btgen.compiler import main as build_info

        return build_info(argv[1:])
    parser = build_parser()
    commands = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction)).choices
    Parser.command = next((a for a in argv if not a.startswith("-")), "")
    if Parser.command not in commands:
        Parser.command = ""
    args = parser.parse_args(argv)
    func: Callable[[argparse.Namespace], int] = args.func
    try:
        return func(args)
    except UserError as e:
        print_diagnostics(e.diagnostics)
        return EXIT_INPUT
    except KeyboardInterrupt:
        return 130
    except (InternalError, Exception):
        print(
            "btgen: internal error: this is a bug in btgen, please report it with the input that caused it",
            file=sys.stderr,
        )
        traceback.print_exc(limit=-3, file=sys.stderr)
        return EXIT_INTERNAL
