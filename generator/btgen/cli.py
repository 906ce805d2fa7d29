"""The `btgen` command line.

Exit status: 0 success, 1 invalid input (diagnostics on stderr),
2 command-line misuse, 3 internal error (a bug in btgen).
"""
from __future__ import annotations

import argparse
import sys
import traceback
from typing import Callable, Sequence

from .diagnostics import Diagnostic, InternalError, UserError
from .version import __version__

EXIT_OK, EXIT_INPUT, EXIT_USAGE, EXIT_INTERNAL = 0, 1, 2, 3


def print_diagnostics(diags: Sequence[Diagnostic]) -> None:
    for d in diags:
        print(str(d), file=sys.stderr)


def _capacity(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"`{text}` is not a whole number") from None
    if not 1 <= value <= 1 << 20:
        raise argparse.ArgumentTypeError(f"{value} is out of range (1 to {1 << 20})")
    return value


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # exit 2, as argparse does, but no usage spam
        print(f"btgen: error: {message}", file=sys.stderr)
        print(f"btgen: try 'btgen {self.prog.split()[-1] if ' ' in self.prog else ''} --help'".rstrip(), file=sys.stderr)
        raise SystemExit(EXIT_USAGE)


def _cmd_validate(args: argparse.Namespace) -> int:
    from .frontend import load_mission

    status = EXIT_OK
    for path in args.missions:
        try:
            mission = load_mission(path)
            print_diagnostics(mission.warnings)
            if not args.quiet:
                print(f"{path}: ok ({len(mission.trees)} trees, main `{mission.main_tree}`)")
        except UserError as e:
            print_diagnostics(e.diagnostics)
            status = EXIT_INPUT
    return status


def _cmd_xsd(args: argparse.Namespace) -> int:
    from .frontend import load_mission
    from .xsd import mission_xsd

    mission = load_mission(args.mission)
    sys.stdout.write(mission_xsd(mission))
    return EXIT_OK


def _cmd_run(args: argparse.Namespace) -> int:
    from .run import run_command

    return run_command(args)


def _cmd_compile(args: argparse.Namespace) -> int:
    from .compiler import compile_command

    return compile_command(args)


def _cmd_lint_kb(args: argparse.Namespace) -> int:
    from .kb import lint_kb

    diags = lint_kb(args.kb, config_path=args.config, mission_path=args.mission)
    print_diagnostics(diags)
    return EXIT_INPUT if any(d.severity == "error" for d in diags) else EXIT_OK


def _cmd_bench(args: argparse.Namespace) -> int:
    from .bench import bench_command

    return bench_command(args)


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(prog="btgen", description="Compile BehaviorTree.CPP v4 missions to static C++17.")
    p.add_argument("--version", action="version", version=f"btgen {__version__}")
    sub = p.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True

    v = sub.add_parser("validate", help="check missions; print every problem as path:line:col")
    v.add_argument("missions", nargs="+", metavar="MISSION.xml")
    v.add_argument("-q", "--quiet", action="store_true", help="print nothing for valid missions")
    v.set_defaults(func=_cmd_validate)

    x = sub.add_parser("xsd", help="print the XSD of a mission (its nodes and ports) for editors")
    x.add_argument("mission", metavar="MISSION.xml")
    x.set_defaults(func=_cmd_xsd)

    r = sub.add_parser("run", help="run a mission with scripted leaves and print its status trace")
    r.add_argument("mission", metavar="MISSION.xml")
    r.add_argument("--scenario", required=True, metavar="FILE.scenario")
    r.add_argument("--engine", choices=("interp", "cpp"), default="interp")
    r.set_defaults(func=_cmd_run)

    c = sub.add_parser("compile", help="generate C++17 for a mission")
    c.add_argument("mission", metavar="MISSION.xml")
    c.add_argument("-o", "--output-dir", default=".", metavar="DIR")
    c.add_argument("--relative-to", default=None, metavar="DIR",
                   help="directory the banner's input path is relative to (default: the current one)")
    c.add_argument("--string-capacity", type=_capacity, default=None, metavar="N",
                   help="most bytes of a blackboard string (default 128): strings written by robot code or "
                        "growing without bound get N, literals at most N, computed strings the longest value "
                        "they can take; "
                        "a longer value fails the node that writes it")
    c.add_argument("--queue-capacity", type=_capacity, default=None, metavar="N",
                   help="most elements of a blackboard queue written by robot code (default 16)")
    c.set_defaults(func=_cmd_compile)

    k = sub.add_parser("lint-kb", help="validate and lint an environment knowledge base")
    k.add_argument("kb", metavar="FILE.dat")
    k.add_argument("--config", metavar="FILE.ini")
    k.add_argument("--mission", metavar="MISSION.xml")
    k.set_defaults(func=_cmd_lint_kb)

    b = sub.add_parser("bench", help="build a mission with instant leaves and measure ticks")
    b.add_argument("mission", metavar="MISSION.xml")
    b.add_argument("--ticks", type=int, default=100000)
    b.set_defaults(func=_cmd_bench)
    return p


def main(argv: Sequence[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    func: Callable[[argparse.Namespace], int] = args.func
    try:
        return func(args)
    except UserError as e:
        print_diagnostics(e.diagnostics)
        return EXIT_INPUT
    except KeyboardInterrupt:
        return 130
    except (InternalError, Exception):  # noqa: BLE001 - last line of defence
        print("btgen: internal error: this is a bug in btgen, please report it with the input that caused it",
              file=sys.stderr)
        traceback.print_exc(limit=-3, file=sys.stderr)
        return EXIT_INTERNAL
