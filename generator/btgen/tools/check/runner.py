"""Run the loads of `discovery.plan` in one process and turn what they report into findings.

Each unit goes through `pipeline.load` and `ir.lower.lower` (what `validate` and `compile` check),
then `btgen analyze`'s analysis (A1xx) and, when `upgrade-to` is set, `btgen upgrade-check`'s static
findings (U101). A diagnostic seen by several units (a file included by two missions, a file loaded
once per tree) is one finding. Then the inline suppressions (`<!-- btgen: ignore[CODE] -->` on the
line), `per-file-ignores`, `select` and `ignore` apply. The findings are sorted by file, line, column
and code, so they never depend on the order of the walk.
"""

from __future__ import annotations

import functools
import os
import re
import sys
import tempfile
from dataclasses import dataclass, field, replace
from typing import Callable, Optional

from btgen import pipeline
from btgen.diagnostics import Diagnostic, UserError
from btgen.frontend.xmlsource import shared_sources
from btgen.tools.check import discovery
from btgen.tools.check.codes import BY_CODE, classify, selected
from btgen.tools.check.config import Settings

_SUPPRESS = re.compile(r"<!--\s*btgen:\s*ignore\[([A-Za-z0-9_, ]+)\]\s*-->")
_NO_MODELS = (
    "; the mission declares no node models: if they are in a file of their own, pass it with `--models FILE.xml`"
)
CPP_HINT = (
    "; if the program registers it in C++, declare it: `btgen models DIR` writes a models file of every such "
    "node for check to find beside the trees, or name the program's models file under `models` in [tool.btgen]"
)


@dataclass(frozen=True, order=True)
class Finding:
    path: str
    line: int
    col: int
    code: str
    severity: str
    message: str

    @property
    def rule(self):
        return BY_CODE[self.code]

    def __str__(self) -> str:
        from btgen.diagnostics import one_line

        return f"{self.path}:{self.line}:{self.col}: {self.severity}: {one_line(self.message)} [{self.code}]"


@dataclass
class Report:
    files: list[str]  # every BehaviorTree.CPP file found (shown paths), sorted
    kinds: dict[str, str]  # path -> what the file is
    findings: list[Finding] = field(default_factory=list)
    units: int = 0

    @property
    def errors(self) -> int:
        return sum(1 for f in self.findings if f.severity == "error")


class _ProjectModels:
    """A Groot2 project's <TreeNodesModel> as a models file the loader reads: the project's text with
    its <include> elements blanked out (same length, same lines), so positions stay those of the
    `.btproj`, and the temporary file's name is put back in the findings."""

    def __init__(self) -> None:
        self.dir: Optional[tempfile.TemporaryDirectory] = None
        self.made: dict[str, str] = {}  # temporary path -> project path

    def models_for(self, project: str) -> str:
        for tmp, proj in self.made.items():
            if proj == project:
                return tmp
        if self.dir is None:
            self.dir = tempfile.TemporaryDirectory(prefix="btgen-check-")
        with open(project, encoding="utf-8", errors="replace") as f:
            text = f.read()
        blank = re.sub(r"<[Ii]nclude\b[^>]*?(/>|>\s*</[Ii]nclude>)", lambda m: re.sub(r"[^\n]", " ", m.group(0)), text)
        blank = re.sub(r"\s(project_name)\s*=\s*(\"[^\"]*\"|'[^']*')", lambda m: " " * len(m.group(0)), blank, count=1)
        tmp = os.path.join(self.dir.name, f"project{len(self.made)}.xml")
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(blank)
        self.made[tmp] = project
        return tmp

    def shown(self, path: str) -> str:
        return self.made.get(path, path)

    def close(self) -> None:
        if self.dir is not None:
            self.dir.cleanup()


def _options(s: Settings, unit: discovery.Unit, models: tuple[str, ...]) -> pipeline.CompileOptions:
    return pipeline.CompileOptions(
        models=models,
        main_tree=unit.main_tree,
        trees=unit.trees,
        entries=s.entry,
        enum_decls=s.enum,
        enum_files=s.enums,
        types=s.type,
        string_capacity=s.string_capacity,
        queue_capacity=s.queue_capacity,
        btcpp=s.btcpp,
        ros_packages=tuple(sorted(s.ros_packages.items())),
        # the models files found beside or above the file, or elsewhere in the project (not those
        # the configuration names): a palette whose SubTree models may be other missions' trees
        palettes=tuple(m for m in unit.models if m not in s.models and m not in unit.projects),
    )


def run_unit(unit: discovery.Unit, s: Settings, projects: _ProjectModels) -> list[tuple[Diagnostic, str]]:
    """Every diagnostic of one load, with its source ("loader", "analysis" or "upgrade")."""
    models = tuple(projects.models_for(m) if m in unit.projects else m for m in unit.models)
    opts = _options(s, unit, models)
    out: list[tuple[Diagnostic, str]] = []
    mission = None
    lowering = False
    try:
        mission = pipeline.load(unit.path, opts)
        out += [(d, "loader") for d in mission.warnings]
        lowering = True
        program = pipeline.program(mission, opts)
        # What only fails when a node runs (the library loads it; both engines throw there)
        # compiles with a warning; for a team's check it stays at its rule's level.
        given = _caller_given(mission)
        out += [(_given_by_caller(replace(d, severity="error"), given), "loader") for d in program.warnings]
    except UserError as e:
        given = _caller_given(mission) if mission is not None else set()
        # (the program's warnings come with its errors: the same level as above)
        diags = [replace(d, severity="error") if lowering else d for d in e.diagnostics]
        out += [(_given_by_caller(d, given), "loader") for d in diags]
        return out
    if s.analysis:
        from btgen.tools.analyze import analyze_program

        try:
            result = analyze_program(mission, program, opts.data)
            out += [(Diagnostic(f.loc, f.message, "warning"), "analysis") for f in result.findings]
        except UserError as e:
            out += [(d, "loader") for d in e.diagnostics]
    if s.upgrade_to and s.upgrade_to != s.btcpp:
        from btgen.tools.upgrade import static_findings

        try:
            out += [(d, "upgrade") for d in static_findings(unit.path, opts, s.btcpp, s.upgrade_to)]
        except UserError as e:
            out += [(d, "loader") for d in e.diagnostics]
    return out


_CALLER_GIVES = "a port of its own SubTree model"
_READS = re.compile(r"reads `([^`]+)`, but nothing creates that blackboard entry")


def _caller_given(mission) -> set[str]:
    """The ports the main tree's own SubTree model declares (MoveIt Pro declares one for every objective
    that other objectives call): entries a caller gives it when it runs as a SubTree."""
    return {p.name for m in mission.models if m.kind == "SubTree" and m.id == mission.main_tree for p in m.ports}


def _given_by_caller(d: Diagnostic, given: set[str]) -> Diagnostic:
    m = _READS.search(d.message)
    if m is None or m.group(1) not in given:
        return d
    return replace(d, message=f"{d.message} ({_CALLER_GIVES}, which its caller gives)")


def to_finding(d: Diagnostic, source: str, unit: discovery.Unit, projects: _ProjectModels) -> Finding:
    code = classify(d.message, d.severity, source)
    message, severity = d.message, d.severity
    if code == "C101" or (code == "E301" and "neither built in nor declared" in message):
        message = message.replace(_NO_MODELS, "") + CPP_HINT
    if code == "E505" and "--string-capacity" in message:  # check's way to say it
        message += "; for btgen check: `string-capacity = N` in [tool.btgen]"
    elif code == "E505" and "--queue-capacity" in message:
        message += "; for btgen check: `queue-capacity = N` in [tool.btgen]"
    if code == "E503" and (unit.library or _CALLER_GIVES in message):
        # a tree library checked on its own: the entry may come from its caller or the program, and the
        # library loads it all the same; the call site decides
        code, severity = "C102", "warning"
        if _CALLER_GIVES not in message:
            message = f"{message} (tree library): the caller or the program may create it"
    elif d.severity != BY_CODE[code].severity and code not in ("E999", "W999"):
        severity = d.severity  # the level is the front end's; the table gives the default
    path = projects.shown(d.loc.path)
    return Finding(path, d.loc.line, d.loc.col, code, severity, message)


class _Lines:
    def __init__(self) -> None:
        self.cache: dict[str, list[str]] = {}

    def line(self, path: str, n: int) -> str:
        if path not in self.cache:
            try:
                with open(path, encoding="utf-8", errors="replace") as f:
                    self.cache[path] = f.read(discovery.MAX_BYTES).split("\n")
            except OSError:
                self.cache[path] = []
        lines = self.cache[path]
        return lines[n - 1] if 1 <= n <= len(lines) else ""


def suppressed(f: Finding, lines: _Lines) -> bool:
    for m in _SUPPRESS.finditer(lines.line(f.path, f.line)):
        codes = [c.strip() for c in m.group(1).split(",") if c.strip()]
        if any(f.code.startswith(c) or c == "ALL" for c in codes):
            return True
    return False


def filters(s: Settings) -> tuple[Callable[[str, bool], bool], Callable[[str], Optional[str]]]:
    """What the configuration leaves out of the walk (`exclude`, `include`), and the main tree it
    chooses for a file (`main-tree`), its globs relative to the configuration's folder."""

    def skip(path: str, is_dir: bool) -> bool:
        rel = s.rel(path)
        if discovery.matches(rel, s.exclude):
            return True
        return not is_dir and bool(s.include) and not discovery.matches(rel, s.include)

    def main_for(path: str) -> Optional[str]:
        rel = s.rel(path)
        return next((t for g, t in s.main_tree.items() if discovery.matches(rel, (g,))), None)

    return skip, main_for


def _work(unit: discovery.Unit, s: Settings, made: dict[str, str]) -> list[tuple[Diagnostic, str]]:
    """One unit in a worker process (--jobs): the project models files were made by the parent."""
    from btgen.frontend.xmlsource import shared_sources

    projects = _ProjectModels()
    projects.made = made
    with shared_sources():
        return run_unit(unit, s, projects)


def check(
    paths: list[str], s: Settings, progress: Optional[Callable[[int, int, str], None]] = None, jobs: int = 1
) -> Report:
    """Find, load and check every BehaviorTree.CPP file under `paths` (`jobs` processes)."""
    skip, main_for = filters(s)
    project = discovery.survey(paths, skip)
    units = discovery.plan(project, s.models, s.trees, main_for)
    checked = [f for f in project.files.values() if not f.context]
    report = Report(sorted(f.path for f in checked), {f.path: f.kind for f in checked})
    report.units = len(units)
    seen: set[Finding] = set()
    projects = _ProjectModels()
    with shared_sources():  # (a file included by many missions is parsed once)
        try:
            for unit in units:  # (made before any worker starts: the workers only look them up)
                for proj in unit.projects:
                    projects.models_for(proj)
            if jobs > 1 and len(units) > 1:
                import multiprocessing

                with multiprocessing.get_context().Pool(min(jobs, len(units))) as pool:
                    results = pool.imap(functools.partial(_work, s=s, made=dict(projects.made)), units, chunksize=4)
                    for i, (unit, diags) in enumerate(zip(units, results)):
                        if progress is not None:
                            progress(i, len(units), unit.path)
                        seen.update(to_finding(d, source, unit, projects) for d, source in diags)
            else:
                for i, unit in enumerate(units):
                    if progress is not None:
                        progress(i, len(units), unit.path)
                    for d, source in run_unit(unit, s, projects):
                        seen.add(to_finding(d, source, unit, projects))
        finally:
            projects.close()
    context = {f.path for f in project.files.values() if f.context}
    report.findings = _filter(sorted(f for f in _merge(seen) if f.path not in context), s)
    return report


def _merge(findings: set[Finding]) -> set[Finding]:
    """One finding per place and message: a C102 warning (the library alone) wins over the E503 of the
    same place only when no mission that uses the library reports the error."""
    errors = {(f.path, f.line, f.col) for f in findings if f.code == "E503"}
    return {f for f in findings if not (f.code == "C102" and (f.path, f.line, f.col) in errors)}


def _filter(findings: list[Finding], s: Settings) -> list[Finding]:
    lines = _Lines()
    out = []
    for f in findings:
        ignore = s.ignore + tuple(
            c for g, cs in s.per_file_ignores.items() if discovery.matches(s.rel(f.path), (g,)) for c in cs
        )
        if not selected(f.code, s.select, ignore) or suppressed(f, lines):
            continue
        out.append(f)
    return out


def with_cli(s: Settings, select: list[str], ignore: list[str], extend_select: list[str]) -> Settings:
    """The configuration's settings with the command line's --select / --ignore over them."""
    if select:
        s = replace(s, select=tuple(select))
    if extend_select:
        s = replace(s, select=(s.select or ("ALL",)) + tuple(extend_select))
    if ignore:
        s = replace(s, ignore=s.ignore + tuple(ignore))
    return s


def progress_printer() -> Optional[Callable[[int, int, str], None]]:
    """A one-line progress on stderr when it is a terminal; None otherwise (CI logs stay clean)."""
    if not sys.stderr.isatty():
        return None

    def show(i: int, n: int, path: str) -> None:
        text = f"[{i + 1}/{n}] {path}"[:79]
        sys.stderr.write("\r" + text.ljust(79) + ("\r" + " " * 79 + "\r" if i + 1 == n else ""))
        sys.stderr.flush()

    return show
