"""`btgen check [PATH ...]`: the command line of the repository gate (options, output, exit status).

Exit status 0 when no finding is at error level (warnings alone pass), 1 otherwise, and 1 for a bad
configuration or command line, like any bad input. Quiet when clean; a progress line only when
stderr is a terminal.
"""

from __future__ import annotations

import argparse
import os
import sys
from typing import Optional

from btgen.diagnostics import Loc, UserError
from btgen.lang.versions import SUPPORTED_VERSIONS
from btgen.tools.check import config, discovery, formats, runner
from btgen.tools.check.codes import valid_selector

EXIT_OK, EXIT_FINDINGS = 0, 1


def _selectors(text: str) -> list[str]:
    out = [s.strip() for s in text.split(",") if s.strip()]
    for s in out:
        problem = valid_selector(s)
        if problem:
            raise argparse.ArgumentTypeError(problem)
    return out


def _jobs(text: str) -> int:
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"`{text}` is not a whole number") from None
    if not 0 <= n <= 64:
        raise argparse.ArgumentTypeError(f"{n} is out of range (0 to 64)")
    return n or (os.cpu_count() or 1)


def add_parser(sub) -> argparse.ArgumentParser:
    c = sub.add_parser(
        "check",
        help="find and check every BehaviorTree.CPP file of a repository, as a linter (codes, config, SARIF/JUnit)",
        description="Find every BehaviorTree.CPP file under the paths (by content), work out what each is "
        "(mission, models file, tree library, Groot2 project) and check each the way the project loads it. "
        "Settings: [tool.btgen] of pyproject.toml or btgen.toml, found upwards from the path (docs/check.md).",
    )
    c.add_argument("paths", nargs="*", default=["."], metavar="PATH", help="files or folders (default: .)")
    c.add_argument("--config", metavar="FILE", help="the configuration to use instead of the one found upwards")
    c.add_argument(
        "--select",
        type=_selectors,
        action="append",
        default=[],
        metavar="CODES",
        help="report only these codes or prefixes, comma-separated (e.g. E,A103)",
    )
    c.add_argument(
        "--extend-select",
        type=_selectors,
        action="append",
        default=[],
        metavar="CODES",
        help="add codes to the configuration's selection",
    )
    c.add_argument(
        "--ignore",
        type=_selectors,
        action="append",
        default=[],
        metavar="CODES",
        help="do not report these codes or prefixes",
    )
    c.add_argument(
        "--format",
        choices=formats.FORMATS,
        default="text",
        metavar="FORMAT",
        help="output format: " + ", ".join(formats.FORMATS) + " (default: text)",
    )
    c.add_argument(
        "-o",
        "--output-file",
        metavar="FILE",
        help="write the report there (default: standard output; text findings go to standard error)",
    )
    c.add_argument(
        "--btcpp",
        choices=SUPPORTED_VERSIONS,
        default=None,
        metavar="VERSION",
        help="the BehaviorTree.CPP release to follow (over the configuration's `btcpp`)",
    )
    c.add_argument(
        "-j",
        "--jobs",
        type=_jobs,
        default=1,
        metavar="N",
        help="check with N processes (0: one per core; default 1); the findings are the same",
    )
    c.add_argument("--show-settings", metavar="FILE", help="print what applies to FILE and how it is loaded, then exit")
    c.add_argument("--show-files", action="store_true", help="print the files found and what each is, then exit")
    c.set_defaults(func=check_command)
    return c


def _flat(lists: list[list[str]]) -> list[str]:
    return [x for xs in lists for x in xs]


def settings_for(args: argparse.Namespace) -> config.Settings:
    if args.config is not None:
        if not os.path.isfile(args.config):
            from btgen.cmdline import error

            raise error(args, "--config", f"--config: no such file `{args.config}`")
        path: Optional[str] = args.config
    else:
        start = args.paths[0] if len(args.paths) == 1 else os.path.commonpath([os.path.abspath(p) for p in args.paths])
        path = config.find_config(start)
        if path is not None:
            path = os.path.relpath(path)
    s = config.load_settings(path)
    s = runner.with_cli(s, _flat(args.select), _flat(args.ignore), _flat(args.extend_select))
    if args.btcpp is not None:
        from dataclasses import replace

        s = replace(s, btcpp=args.btcpp)
    return s


def _show_settings(args: argparse.Namespace, s: config.Settings) -> int:
    target = args.show_settings
    if not discovery.sniff(target):
        raise UserError.at(Loc(target, 1, 1), 'not a BehaviorTree.CPP file (no <root BTCPP_format="..."> at its start)')
    top = os.path.dirname(target) or "."
    report_paths = [top] + [p for p in args.paths if p != "."]
    skip, main_for = runner.filters(s)
    project = discovery.survey(report_paths, skip)
    real = os.path.realpath(target)
    f = project.files.get(real) or discovery.read(target)
    units = [u for u in discovery.plan(project, s.models, s.trees, main_for) if os.path.realpath(u.path) == real]
    lines = []
    for u in units:
        lines.append(f"[[load]]  # {'a tree library on its own' if u.library else 'as a mission'}")
        lines.append(f"main-tree = {u.main_tree!r}")
        lines.append(f"models = {list(u.models)!r}")
        lines.append(f"trees = {list(u.trees)!r}")
    if not units and f.included_by:
        lines.append(f"# loaded with the files that include it: {', '.join(sorted(f.included_by))}")
    sys.stdout.write(config.settings_text(s, target, f.kind, lines))
    return EXIT_OK


def check_command(args: argparse.Namespace) -> int:
    s = settings_for(args)
    if args.show_settings:
        return _show_settings(args, s)
    for p in args.paths:
        if not os.path.exists(p):
            from btgen.cmdline import error

            raise error(args, p, f"no such file or folder `{p}`")
    if args.show_files:
        project = discovery.survey(args.paths, runner.filters(s)[0])
        for _real, f in sorted(project.files.items(), key=lambda kv: kv[1].path):
            print(f"{f.path}: {f.kind}")
        return EXIT_OK
    report = runner.check(args.paths, s, runner.progress_printer(), jobs=args.jobs)
    if not report.files:  # (likely a wrong path or an `exclude` too wide: say so, exit 0 as ruff does)
        sys.stderr.write(
            f"btgen check: warning: no BehaviorTree.CPP file (<root BTCPP_format=...>) found under "
            f"{', '.join(args.paths)}\n"
        )
    rendered = formats.RENDER[args.format](report)
    if args.output_file:
        from pathlib import Path

        from btgen.compiler import write_if_changed

        try:
            write_if_changed(Path(args.output_file), rendered)
        except OSError as e:
            raise UserError.at(Loc(args.output_file, 1, 1), f"cannot write the report: {e.strerror or e}") from None
        if args.format != "text":  # the people reading the CI log still see the findings
            sys.stderr.write(formats.text(report))
    elif args.format == "text":
        sys.stderr.write(rendered)
    else:
        sys.stdout.write(rendered)
    return EXIT_FINDINGS if report.errors else EXIT_OK
