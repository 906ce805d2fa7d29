"""`btgen mutate`: the mutants loaded, the suite run on each, survivors decided by `btgen diff`."""

from __future__ import annotations

import dataclasses
import glob
import json
import os
import re
import sys
import tempfile
import time
from dataclasses import dataclass, field
from typing import Optional

from btgen import cmdline
from btgen.diagnostics import Diagnostic, InternalError, Loc, UserError, print_diagnostics
from btgen.fileio import xml_files_of
from btgen.interp.scenario import Scenario, format_scenario, load_scenario, parse_scenario_text
from btgen.lang.model import Mission
from btgen.tools.diff.product import Differ, Event, first_difference, observe
from btgen.tools.mutate.operators import Mutant, all_mutants

MARKER = ".btgen-mutants"
_NAMES = {0: "IDLE", 1: "RUNNING", 2: "SUCCESS", 3: "FAILURE"}


@dataclass
class Verdict:
    mutant: Mutant
    status: str  # killed | equivalent | undecided | survived | discarded
    reason: str = ""  # discarded: the first error; undecided: why the search stopped
    killed_by: str = ""  # killed: the suite's scenario that kills it
    scenario: str = ""  # survived: a scenario that kills it (from the product search)
    states: int = 0  # the product search's states, when one ran
    seconds: float = 0.0  # the product search's time
    cpp: str = ""  # survived: what the scenario's replay on the compiled C++ executor showed


@dataclass
class Report:
    mission: str
    suite: str
    scenarios: int
    clock_ms: int
    verdicts: list[Verdict] = field(default_factory=list)
    seconds: dict[str, float] = field(default_factory=dict)

    def count(self, status: str) -> int:
        return sum(1 for v in self.verdicts if v.status == status)

    @property
    def loaded(self) -> int:
        return len(self.verdicts) - self.count("discarded")

    @property
    def non_equivalent(self) -> int:
        return self.loaded - self.count("equivalent")

    @property
    def score(self) -> float:
        n = self.non_equivalent
        return 100.0 if n == 0 else 100.0 * self.count("killed") / n

    def headline(self) -> str:
        return (
            f"killed {self.count('killed')} of {self.non_equivalent} non-equivalent mutants "
            f"({self.count('equivalent')} equivalent, {self.count('undecided')} undecided)"
        )


# ---------------------------------------------------------------- the suite
def suite_files(args) -> list[str]:
    folder = args.tests
    if not os.path.isdir(folder):
        raise cmdline.error(args, "--tests", f"--tests {folder}: not a folder")
    inner = os.path.join(folder, "scenarios")
    where = inner if os.path.isdir(inner) else folder
    files = sorted(glob.glob(os.path.join(glob.escape(where), "*.scenario")))
    if not files:
        raise UserError(
            Diagnostic(
                Loc(folder, 1, 1),
                "no scenarios: expected DIR/scenarios/*.scenario (what `btgen tests -o DIR` writes) "
                "or DIR/*.scenario (what `btgen explore -o DIR` writes)",
            )
        )
    return files


def read_suite(files: list[str], mission: Mission) -> list[tuple[str, Scenario]]:
    out = []
    problems: list[Diagnostic] = []
    for f in files:
        try:
            sc, warnings = load_scenario(f, mission)
        except UserError as e:
            problems.extend(e.diagnostics)
            continue
        print_diagnostics(warnings)
        out.append((f, sc))
    if problems:
        raise UserError(problems)
    return out


# ---------------------------------------------------------------- loading a mutant
def _relocator(mission_path: str):
    base = os.path.dirname(os.path.realpath(mission_path))

    def relocate(root) -> None:
        for inc in root.iter("include"):
            rel = inc.get("path")
            if rel is not None and inc.get("ros_pkg") is None and not os.path.isabs(rel):
                inc.set("path", os.path.join(base, rel))

    return relocate


def load_mutant(folder: str, name: str, mutant: Mutant, opts) -> Mission | str:
    """The mutant checked as `btgen validate` checks it, or the first error's message."""
    from btgen.compiler import generate_checked

    path = os.path.join(folder, name)
    with open(path, "wb") as f:
        f.write(mutant.xml)
    try:
        mission, _ = generate_checked(path, opts, relative_to=folder)
    except UserError as e:
        errors = [d for d in e.diagnostics if d.severity == "error"] or e.diagnostics
        return errors[0].message if errors else "does not load"
    return mission


def library_files(trees: tuple[str, ...], mission_path: str) -> tuple[str, ...]:
    """--trees for a mutant: each folder as its `*.xml` files (name order, as the loader reads
    it) without the mission itself, which the loader leaves out of a library by its path; the
    mutant, written elsewhere, would otherwise meet the original's trees."""
    mission = os.path.realpath(mission_path)
    out: list[str] = []
    for path in trees:
        found = xml_files_of(path) if os.path.isdir(path) else [path]
        out += [f for f in found if os.path.realpath(f) != mission]
    return tuple(out)


# ---------------------------------------------------------------- killing
def _observe(mission: Mission, sc: Scenario) -> list[list[Event]]:
    try:
        return observe(mission, sc)
    except UserError as e:  # the scenario cannot even start on this mission: that is a difference
        d = e.diagnostics[0] if e.diagnostics else None
        return [[("error", d.message if d is not None else "does not run")]]


def killer(mission: Mission, suite: list[tuple[str, Scenario]], seen: list[list[list[Event]]]) -> Optional[str]:
    """The first scenario of the suite whose observed run differs on `mission`, or None."""
    for (path, sc), want in zip(suite, seen):
        if first_difference(want, _observe(mission, sc)) is not None:
            return path
    return None


def _interp_trace(mission: Mission, sc: Scenario) -> str:
    """The interpreter's trace (`btgen run`'s output); a run-time error ends it with its message."""
    from btgen.interp.engine import Interpreter, run_ticks

    parts: list[str] = []
    try:
        run_ticks(Interpreter(mission, sc), sc, parts.append)
    except UserError as e:
        return "".join(parts) + "".join(str(d) + "\n" for d in e.diagnostics)
    return "".join(parts)


def _cpp_trace(path: str, opts, scenario_path: str) -> str:
    """The compiled C++ executor's trace of the scenario (`btgen run --engine cpp`: built once
    per mission, cached); its errors, as the interpreter gives them, end it (its warnings, about
    the scenario's lines, are the interpreter's too and are left out)."""
    import subprocess

    from btgen.tools.cppengine import build_cpp

    binary = build_cpp(path, None, opts)
    proc = subprocess.run([str(binary), scenario_path], capture_output=True, check=False)
    errors = [ln for ln in proc.stderr.decode("utf-8", "replace").splitlines(True) if ": error: " in ln]
    return proc.stdout.decode("utf-8", "replace") + "".join(errors)


def _first_line(a: str, b: str) -> str:
    la, lb = a.splitlines(), b.splitlines()
    for i in range(max(len(la), len(lb))):
        x = la[i] if i < len(la) else "(nothing)"
        y = lb[i] if i < len(lb) else "(nothing)"
        if x != y:
            return f"line {i + 1}: `{x}` / `{y}`"
    return "the same"


_CHANGE = re.compile(r"[0-9]+ (\S+) (\".*\") (\S+) -> (\S+)\Z")
_ERROR = re.compile(r".*?:[0-9]+:[0-9]+: (error: .*)\Z")


def visible(trace: str, leaves: set[str]) -> list[str]:
    """What a trace shows of the run that a mutant cannot change by its edit alone: the ticks,
    the status changes of the user leaves (ID, name, from, to: no UID, which a dropped node
    renumbers), the root's results and the errors (without the file's path)."""
    out = []
    for line in trace.splitlines():
        m = _CHANGE.match(line)
        if m is not None:
            if m.group(1) in leaves:
                out.append("{} {} {} -> {}".format(*m.groups()))
            continue
        e = _ERROR.match(line)
        out.append(e.group(1) if e is not None else line)
    return out


def _user_leaves(mission: Mission) -> set[str]:
    from btgen.lang.leaves import is_scripted_leaf
    from btgen.tools.gtests import _walk

    return {n.id for n in _walk(mission) if is_scripted_leaf(mission, n)}


def replay_cpp(original: Mission, mutant: Mission, text: str, paths: tuple[str, str], opts) -> str:
    """The killing scenario of a survivor on the compiled C++ executor: the original and the mutant
    each built and run on it; each trace must be the interpreter's (else an engine disagreement,
    reported), and the two traces differ (killed there too), or they are the same on both engines
    (the difference is in what `btgen diff` observes besides the statuses: a leaf's input values,
    a blackboard write)."""
    with tempfile.TemporaryDirectory(prefix="btgen-mutate-cpp-") as tmp:
        sc_path = os.path.join(tmp, "kill.scenario")
        with open(sc_path, "w", encoding="utf-8") as f:
            f.write(text)
        sc = parse_scenario_text(text, sc_path)
        got = []
        for mission, path, who in ((original, paths[0], "original"), (mutant, paths[1], "mutant")):
            try:
                cpp = _cpp_trace(path, opts[who], sc_path)
            except UserError as e:
                why = e.diagnostics[0].message if e.diagnostics else "refused"
                return f"not replayed on the C++ executor: the C++ back end refuses the {who} ({why})"
            interp = _interp_trace(mission, sc)
            if cpp != interp:
                raise InternalError(
                    f"btgen mutate: the killing scenario's run of the {who} differs between the interpreter and "
                    f"the C++ executor ({_first_line(interp, cpp)})\n{text}"
                )
            got.append(visible(cpp, _user_leaves(mission)))
    if got[0] != got[1]:
        where = _first_line("\n".join(got[0]), "\n".join(got[1]))
        return f"killed on the C++ executor too: the leaves' status changes differ, {where}"
    return (
        "the C++ executor gives each the interpreter's trace, and the leaves' status changes are the same: "
        "the difference is in the leaves' input values or the blackboard"
    )


def decide(original: Mission, mutant: Mission, args, clock_ms: int, cpp=None) -> Verdict:
    """A survivor through the product search: equivalent (exhaustive), a killing scenario, or
    undecided (the tick bound or the state budget stopped the search). `cpp`: (paths, options)
    of the original and the mutant, to replay a killing scenario on the C++ executor too."""
    differ = Differ(original, mutant, None, args.max_ticks, clock_ms, args.max_states)
    out = differ.decide()
    dummy = Mutant("", "", Loc("", 1, 1), "", "")
    if out.equivalent:
        if out.exhaustive:
            return Verdict(dummy, "equivalent", states=out.states)
        why = (
            f"no difference within {out.bound} ticks (--max-ticks): not a proof"
            if out.why_bounded == "ticks"
            else f"no difference in {out.states} product states (--max-states {args.max_states}): not a proof"
        )
        return Verdict(dummy, "undecided", reason=why, states=out.states)
    leaves = [(name, [_NAMES[s] for s in sts]) for name, sts in out.plan.items()]
    text = format_scenario(out.ticks, leaves, clock_ms, "btgen mutate: a scenario that kills this mutant")
    sc = parse_scenario_text(text, "<survivor>")
    if first_difference(_observe(original, sc), _observe(mutant, sc)) is None:
        raise InternalError("btgen mutate: the product search's scenario does not replay as a difference")
    shown = replay_cpp(original, mutant, text, *cpp) if cpp is not None else ""
    return Verdict(dummy, "survived", scenario=text, states=out.states, cpp=shown)


# ---------------------------------------------------------------- the run
def _progress(i: int, n: int) -> None:
    if sys.stderr.isatty():
        sys.stderr.write(f"\rmutant {i} of {n}")
        sys.stderr.flush()
        if i == n:
            sys.stderr.write("\r" + " " * 30 + "\r")


def run_mutation(args) -> Report:
    from btgen import pipeline
    from btgen.frontend.xmlsource import read_source

    t0 = time.perf_counter()
    opts = pipeline.options_from_args(args)
    original = pipeline.load(args.mission, opts)
    print_diagnostics(original.warnings)
    files = suite_files(args)
    suite = read_suite(files, original)
    clocks = sorted({sc.clock_ms for _, sc in suite})
    clock_ms = clocks[-1] if clocks else 0
    seen = [_observe(original, sc) for _, sc in suite]
    source = read_source(args.mission)
    mutants = list(all_mutants(source, frozenset(original.builtins), _relocator(args.mission)))
    report = Report(args.mission, args.tests, len(suite), clock_ms)
    t_load = t_runs = t_search = 0.0
    name = os.path.basename(args.mission)
    mutant_opts = dataclasses.replace(opts, trees=library_files(opts.trees, args.mission))
    with tempfile.TemporaryDirectory(prefix="btgen-mutate-") as tmp:
        for i, m in enumerate(mutants, start=1):
            _progress(i, len(mutants))
            t = time.perf_counter()
            loaded = load_mutant(tmp, name, m, mutant_opts)
            t_load += time.perf_counter() - t
            if isinstance(loaded, str):
                report.verdicts.append(Verdict(m, "discarded", reason=loaded))
                continue
            t = time.perf_counter()
            by = killer(loaded, suite, seen)
            t_runs += time.perf_counter() - t
            if by is not None:
                report.verdicts.append(Verdict(m, "killed", killed_by=by))
                continue
            t = time.perf_counter()
            cpp = None
            if getattr(args, "replay", "both") == "both":
                cpp = ((args.mission, os.path.join(tmp, name)), {"original": opts, "mutant": mutant_opts})
            v = decide(original, loaded, args, clock_ms, cpp)
            v.seconds = time.perf_counter() - t
            t_search += v.seconds
            v.mutant = m
            report.verdicts.append(v)
    report.seconds = {
        "total": time.perf_counter() - t0,
        "load": t_load,
        "runs": t_runs,
        "search": t_search,
    }
    return report


# ---------------------------------------------------------------- the report
def _where(m: Mutant) -> str:
    return f"{m.loc.path}:{m.loc.line}:{m.loc.col}"


def _line(m: Mutant) -> str:
    return f"{m.id} {m.operator} {_where(m)} {m.path}: {m.change}"


def print_text(report: Report) -> None:
    r = report
    discarded = [v for v in r.verdicts if v.status == "discarded"]
    print(
        f"{r.mission}: {len(r.verdicts)} mutants, {r.loaded} load, {len(discarded)} discarded (they do not load); "
        f"{r.scenarios} scenarios from {r.suite}"
    )
    print(r.headline())
    print(f"mutation score {r.score:.1f}%")
    survivors = [v for v in r.verdicts if v.status == "survived"]
    if survivors:
        print(f"survivors ({len(survivors)}): each with a scenario that kills it (add it to the suite)")
        for v in survivors:
            print(f"  {_line(v.mutant)}")
            for text in v.scenario.splitlines():
                print(f"      {text}")
            if v.cpp:
                print(f"      ({v.cpp})")
    undecided = [v for v in r.verdicts if v.status == "undecided"]
    if undecided:
        print(f"undecided ({len(undecided)}): survived the suite; the product search stopped before a proof")
        for v in undecided:
            print(f"  {_line(v.mutant)}: {v.reason}")
    equivalent = [v for v in r.verdicts if v.status == "equivalent"]
    if equivalent:
        print(
            f"equivalent ({len(equivalent)}): `btgen diff`'s exhaustive product search finds no scenario where "
            f"they differ (clock {r.clock_ms} ms per tick)"
        )
        for v in equivalent:
            print(f"  {_line(v.mutant)} ({v.states} product states)")
    if discarded:
        print(f"discarded ({len(discarded)}): the mutant does not load (the checks of `btgen validate`)")
        for v in discarded:
            print(f"  {_line(v.mutant)}: {v.reason}")
    s = r.seconds
    print(
        f"{s['total']:.1f} s (loading mutants {s['load']:.1f} s, running the suite {s['runs']:.1f} s, "
        f"product searches {s['search']:.1f} s)"
    )


def report_json(report: Report) -> dict:
    r = report
    by_op: dict[str, dict[str, int]] = {}
    for v in r.verdicts:
        by_op.setdefault(v.mutant.operator, {}).setdefault(v.status, 0)
        by_op[v.mutant.operator][v.status] += 1
    return {
        "mission": r.mission,
        "tests": r.suite,
        "scenarios": r.scenarios,
        "clock_ms": r.clock_ms,
        "mutants": len(r.verdicts),
        "loaded": r.loaded,
        "discarded": r.count("discarded"),
        "killed": r.count("killed"),
        "non_equivalent": r.non_equivalent,
        "equivalent": r.count("equivalent"),
        "undecided": r.count("undecided"),
        "survived": r.count("survived"),
        "score": round(r.score, 2),
        "summary": r.headline(),
        "by_operator": by_op,
        "seconds": {k: round(v, 3) for k, v in r.seconds.items()},
        "results": [
            {
                "id": v.mutant.id,
                "operator": v.mutant.operator,
                "file": v.mutant.loc.path,
                "line": v.mutant.loc.line,
                "col": v.mutant.loc.col,
                "path": v.mutant.path,
                "change": v.mutant.change,
                "status": v.status,
                **({"killed_by": v.killed_by} if v.killed_by else {}),
                **({"reason": v.reason} if v.reason else {}),
                **({"scenario": v.scenario} if v.scenario else {}),
                **({"cpp_replay": v.cpp} if v.cpp else {}),
                **(
                    {"product_states": v.states, "search_seconds": round(v.seconds, 3)}
                    if v.status in ("equivalent", "undecided", "survived")
                    else {}
                ),
            }
            for v in r.verdicts
        ],
    }


def write_mutants(args, report: Report) -> None:
    """-o DIR: every mutant's XML (M001-operator.xml) and each survivor's killing scenario."""
    from btgen.tools.gtests import write_suite

    out = args.output_dir
    if os.path.lexists(out):
        if not os.path.isdir(out) or os.path.islink(out):
            raise cmdline.error(args, "-o", f"-o {out}: exists and is not a folder")
        if os.listdir(out) and not os.path.isfile(os.path.join(out, MARKER)):
            raise cmdline.error(
                args, "-o", f"-o {out}: a folder `btgen mutate` did not write (no {MARKER}): refusing to replace it"
            )
    files: dict[str, str] = {MARKER: f"written by btgen mutate for {os.path.basename(args.mission)}\n"}
    for v in report.verdicts:
        stem = f"{v.mutant.id}-{v.mutant.operator}"
        files[f"{stem}.xml"] = v.mutant.xml.decode("utf-8")
        if v.scenario:
            files[f"{stem}.scenario"] = v.scenario
    write_suite(out, files)


def _check_output(args) -> None:
    if args.output_dir is None:
        return
    out = os.path.realpath(args.output_dir)
    for f in [args.mission, args.tests] + list(args.models):
        real = os.path.realpath(f)
        if real == out or real.startswith(out.rstrip(os.sep) + os.sep):
            raise cmdline.error(args, "-o", f"-o {args.output_dir}: the folder holds an input ({f}): choose another")


def mutate_command(args) -> int:
    _check_output(args)
    report = run_mutation(args)
    if args.output_dir is not None:
        write_mutants(args, report)
    if args.format == "json":
        json.dump(report_json(report), sys.stdout, indent=2)
        sys.stdout.write("\n")
    else:
        print_text(report)
    if args.min_score is not None and report.score < args.min_score:
        print(
            f"{args.mission}: mutation score {report.score:.1f}% is below --min-score {args.min_score:g}",
            file=sys.stderr,
        )
        return 1
    return 0
