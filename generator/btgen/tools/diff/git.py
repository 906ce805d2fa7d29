"""`btgen diff --git REV [PATH ...]`: the working tree against a git revision, mission by mission.

The files under each PATH (default: the current folder) are found and planned as `btgen check`
finds them (tools/check/discovery.py: by content; the models files and tree libraries of a
mission's folder count), once in the working tree and once in REV's tree (`git archive REV` of
the same paths, unpacked into a temporary folder). A mission is the pair (path relative to the
repository, main tree). For each:

- in both, and every file it loads (the mission, its includes, models files, tree libraries)
  byte-identical and both sides under one release: `unchanged` (no search: the same input);
- in both otherwise: `btgen diff`'s product search (REV's file is OLD, the working tree's NEW);
- only in the working tree: `added`; only in REV: `removed`;
- a side that does not load: its located errors (paths inside REV written `REV:path`).

Exit 1 when a mission is different or does not load on a side where it exists, else 0.
"""

from __future__ import annotations

import dataclasses
import io
import json
import os
import subprocess
import sys
import tarfile
import tempfile
from dataclasses import dataclass, field
from typing import Optional

from btgen import cmdline, pipeline
from btgen.diagnostics import Diagnostic, InternalError, Loc, UserError, print_diagnostics
from btgen.lang.model import Mission
from btgen.tools.check import discovery
from btgen.tools.diff.product import Differ, difference_record, first_difference, observe

MAX_ARCHIVE = 256 * 1024 * 1024


def _git(top: str, *argv: str, binary: bool = False):
    return subprocess.run(["git", "-C", top, *argv], capture_output=True, check=False, text=not binary)


@dataclass
class Row:
    path: str  # shown (relative to the current folder)
    main_tree: Optional[str]
    answer: str  # unchanged | equivalent | bounded | partial | different | added | removed | error
    verdict: str
    detail: dict = field(default_factory=dict)


def _rev_tree(args, top: str, rels: list[str], into: str) -> None:
    """REV's files under the repository-relative `rels` unpacked into `into`."""
    rev = args.git
    present = [r for r in rels if r == "." or _git(top, "cat-file", "-e", f"{rev}:{r}").returncode == 0]
    if not present:
        return
    p = _git(top, "archive", "--format=tar", rev, "--", *present, binary=True)
    if p.returncode != 0:
        msg = p.stderr.decode("utf-8", "replace").strip().splitlines()
        raise cmdline.error(args, rev, f"--git {rev}: git archive failed: {msg[-1] if msg else p.returncode}")
    if len(p.stdout) > MAX_ARCHIVE:
        raise cmdline.error(args, rev, f"--git {rev}: the files under the paths exceed {MAX_ARCHIVE >> 20} MiB")
    with tarfile.open(fileobj=io.BytesIO(p.stdout)) as tar:
        tar.extractall(into, filter="data")


def _units(paths: list[str], args) -> dict[tuple[str, Optional[str]], discovery.Unit]:
    project = discovery.survey(paths)
    units = discovery.plan(project, tuple(args.models or ()), tuple(args.trees or ()))
    return {(os.path.realpath(u.path), u.main_tree): u for u in units}


def _options(args, unit: discovery.Unit, version: str, projects) -> pipeline.CompileOptions:
    base = pipeline.options_from_args(args)
    models = tuple(projects.models_for(m) if m in unit.projects else m for m in unit.models)
    return dataclasses.replace(
        base, models=models, trees=unit.trees, main_tree=unit.main_tree or base.main_tree, btcpp=version
    )


def _read(path: str) -> Optional[bytes]:
    try:
        with open(path, "rb") as f:
            return f.read()
    except OSError:
        return None


def git_diff_command(args, v_old: str, v_new: str) -> int:
    from btgen.interp.scenario import parse_scenario_text
    from btgen.tools.check.runner import _ProjectModels
    from btgen.tools.diff.common import parse_observe, scenario_texts

    observables = parse_observe(args)

    if args.rename:
        raise cmdline.error(args, "--rename", "--rename names leaves of two missions: not with --git")
    if args.models_old or args.models_new:
        option = "--models-old" if args.models_old else "--models-new"
        raise cmdline.error(args, option, "each mission's models are found: not with --git")
    if args.counterexample:
        raise cmdline.error(args, "--counterexample", "--counterexample writes one pair: not with --git")
    here = os.getcwd()
    p = _git(here, "rev-parse", "--show-toplevel")
    if p.returncode != 0:
        raise cmdline.error(args, "--git", "--git: the current folder is not in a git repository")
    top = os.path.realpath(p.stdout.strip())
    rev = args.git
    if rev.startswith("-") or _git(top, "rev-parse", "--verify", "--quiet", f"{rev}^{{commit}}").returncode != 0:
        raise cmdline.error(args, rev, f"--git {rev}: no such revision in {top}")
    paths = [a for a in (args.old, args.new, *args.paths) if a is not None] or ["."]
    rels: list[str] = []
    for path in paths:
        real = os.path.realpath(path)
        if os.path.relpath(real, top).startswith(".."):
            raise cmdline.error(args, path, f"{path}: not inside the repository {top}")
        rel = os.path.relpath(real, top)
        # a file is loaded with its folder's models files and libraries: bring the folder
        rels.append(os.path.dirname(rel) or "." if not os.path.isdir(real) and os.path.splitext(rel)[1] else rel)
    rows: list[Row] = []
    problems: list[Diagnostic] = []
    with tempfile.TemporaryDirectory(prefix="btgen-diff-git-") as tmp:
        _rev_tree(args, top, sorted(set(rels)), tmp)

        def shown(path: str) -> str:
            real = os.path.realpath(path)
            if real.startswith(os.path.realpath(tmp) + os.sep):
                return f"{rev}:{os.path.relpath(real, os.path.realpath(tmp))}"
            return os.path.relpath(real, here) if real.startswith(top + os.sep) else path

        def located(diags) -> list[Diagnostic]:
            return [dataclasses.replace(d, loc=dataclasses.replace(d.loc, path=shown(d.loc.path))) for d in diags]

        existing = [p for p in paths if os.path.exists(p)]
        work = _units(existing, args) if existing else {}
        old_paths = []
        for path in paths:
            rel = os.path.relpath(os.path.realpath(path), top)
            q = os.path.join(tmp, rel)
            if os.path.exists(q):
                old_paths.append(q)
        before = _units(old_paths, args) if old_paths else {}

        def key(real: str, main: Optional[str], base: str) -> tuple[str, Optional[str]]:
            return os.path.relpath(real, base), main

        w = {key(r, m, top): u for (r, m), u in work.items()}
        b = {key(r, m, os.path.realpath(tmp)): u for (r, m), u in before.items()}
        projects = _ProjectModels()
        try:
            for k in sorted(set(w) | set(b), key=lambda k: (k[0], k[1] or "")):
                rel, main = k
                show = os.path.relpath(os.path.join(top, rel), here)
                if k not in b:
                    rows.append(Row(show, main, "added", f"added (not in {rev})"))
                    continue
                if k not in w:
                    rows.append(Row(show, main, "removed", f"removed (only in {rev})"))
                    continue
                missions: list[Optional[Mission]] = []
                failed = False
                for unit, version, side in ((b[k], v_old, rev), (w[k], v_new, "the working tree")):
                    try:
                        m = pipeline.load(unit.path, _options(args, unit, version, projects))
                        missions.append(m)
                    except UserError as e:
                        problems.extend(located(e.diagnostics))
                        problems.append(
                            Diagnostic(Loc(shown(unit.path), 1, 1), f"while loading {side}'s under {version}", "note")
                        )
                        failed = True
                        missions.append(None)
                if failed:
                    rows.append(Row(show, main, "error", "does not load (see the errors)"))
                    continue
                old, new = missions
                assert old is not None and new is not None
                if v_old == v_new and _same_inputs(old, new, b[k], w[k], tmp, top):
                    rows.append(Row(show, main, "unchanged", "unchanged"))
                    continue
                try:
                    outcome = Differ(old, new, {}, args.max_ticks, args.clock_ms, args.max_states, observables).decide()
                except UserError as e:
                    problems.extend(located(e.diagnostics))
                    rows.append(Row(show, main, "error", "cannot be run (see the errors)"))
                    continue
                stats = {"runs": outcome.runs, "states": outcome.states, "seconds": round(outcome.seconds, 3)}
                if outcome.equivalent:
                    if outcome.exhaustive:
                        rows.append(Row(show, main, "equivalent", "equivalent (exhaustively)", stats))
                    elif outcome.why_bounded == "states":
                        rows.append(
                            Row(
                                show,
                                main,
                                "partial",
                                f"no difference found (stopped at --max-states {args.max_states}: "
                                "a partial search, not a proof)",
                                stats,
                            )
                        )
                    else:
                        rows.append(Row(show, main, "bounded", f"equivalent (up to {outcome.bound} ticks)", stats))
                    continue
                _, text_new = scenario_texts(outcome, {}, args.clock_ms)
                sc = parse_scenario_text(text_new, "scenario")
                seen_old = observe(old, sc, observables=observables)
                seen_new = observe(new, sc, observables=observables)
                at = first_difference(seen_old, seen_new)
                if at is None:  # the search and the replay disagree: never report a difference that is none
                    raise InternalError(f"btgen diff --git: {show}: the difference found does not replay")
                first = difference_record(seen_old, seen_new, at)
                detail: dict = dict(stats, scenario=text_new, first_difference=first)
                where = (
                    f": tick {first['tick']}, event {first['event']}: {rev} {first['old'] or '(nothing)'}, "
                    f"working tree {first['new'] or '(nothing)'}"
                )
                rows.append(Row(show, main, "different", "different" + where, detail))
        finally:
            projects.close()
    print_diagnostics(problems)
    _report(args, rows, rev, v_old, v_new)
    return 1 if any(r.answer in ("different", "error") for r in rows) or problems else 0


def _same_inputs(old: Mission, new: Mission, bu: discovery.Unit, wu: discovery.Unit, tmp: str, top: str) -> bool:
    def rels(files, base):
        return [os.path.relpath(os.path.realpath(f), os.path.realpath(base)) for f in files]

    a = (*old.files, *bu.models, *bu.trees)
    b = (*new.files, *wu.models, *wu.trees)
    if rels(a, tmp) != rels(b, top):
        return False
    return all(_read(x) == _read(y) and _read(x) is not None for x, y in zip(a, b))


def _name(r: Row) -> str:
    return r.path + (f" ({r.main_tree})" if r.main_tree else "")


def _report(args, rows: list[Row], rev: str, v_old: str, v_new: str) -> None:
    versions = f"BehaviorTree.CPP {v_old}" + (f" -> {v_new}" if v_new != v_old else "")
    if args.format == "json":
        out = {
            "git": rev,
            "btcpp_old": v_old,
            "btcpp_new": v_new,
            "missions": [
                {"path": r.path, "main_tree": r.main_tree, "answer": r.answer, "verdict": r.verdict, **r.detail}
                for r in rows
            ],
        }
        json.dump(out, sys.stdout, indent=2)
        sys.stdout.write("\n")
        return
    if args.format == "markdown":
        print(f"**btgen diff --git {rev}** ({versions}): {_summary(rows)}")
        print()
        if rows:
            print("| mission | answer |")
            print("|---|---|")
            for r in rows:
                print(f"| `{_name(r)}` | {r.verdict.replace('|', '&#124;')} |")
        for r in rows:
            if r.answer == "different":
                print()
                print(f"Scenario for `{_name(r)}` (shortest):")
                print()
                print("```text")
                sys.stdout.write(r.detail["scenario"])
                print("```")
        return
    print(f"btgen diff --git {rev} ({versions}): {_summary(rows)}")
    for r in rows:
        stats = f" ({r.detail['runs']} runs, {r.detail['states']} states)" if "runs" in r.detail else ""
        print(f"  {_name(r)}: {r.verdict}{stats}")
        if r.answer == "different":
            for line in r.detail["scenario"].splitlines():
                print(f"      {line}")


def _summary(rows: list[Row]) -> str:
    if not rows:
        return "no mission found"
    counts: dict[str, int] = {}
    for r in rows:
        counts[r.answer] = counts.get(r.answer, 0) + 1
    return ", ".join(f"{n} {a}" for a, n in sorted(counts.items()))
