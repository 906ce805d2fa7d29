"""`btgen diff OLD.xml NEW.xml`: the command line, the report and the counterexample files."""

from __future__ import annotations

import dataclasses
import json
import os
import sys
from typing import Optional

from btgen import cmdline
from btgen.diagnostics import Diagnostic, InternalError, Loc, UserError, print_diagnostics
from btgen.interp.scenario import parse_scenario_text
from btgen.lang.leaves import mission_leaves
from btgen.lang.model import Mission
from btgen.tools.diff.common import parse_observe, scenario_texts
from btgen.tools.diff.product import (
    Differ,
    Event,
    difference_record,
    event_text,
    first_difference,
    observe,
)

WIDTH = 44


def _load(path: str, args, version: str, models: Optional[list] = None) -> Mission:
    from btgen import pipeline

    opts = dataclasses.replace(pipeline.options_from_args(args), btcpp=version)
    if models:  # --models-old / --models-new: this side's models files
        opts = dataclasses.replace(opts, models=tuple(models))
    mission = pipeline.load(path, opts)
    print_diagnostics(mission.warnings)
    return mission


def pipeline_options(args):
    from btgen import pipeline

    return pipeline.options_from_args(args)


def _leaf_names(mission: Mission) -> set[str]:
    return {use.name for use in mission_leaves(mission)}


def _renames(args, old: Mission, new: Mission) -> dict[str, str]:
    out: dict[str, str] = {}
    old_names, new_names = _leaf_names(old), _leaf_names(new)
    for text in args.rename:
        a, sep, b = text.partition("=")
        a, b = a.strip(), b.strip()
        if not sep or not a or not b:
            raise cmdline.error(args, text, f"--rename `{text}`: write OLD_ID=NEW_ID")
        if a not in old_names:
            raise cmdline.error(args, text, f"--rename `{text}`: `{a}` is no leaf of {args.old}")
        if b not in new_names:
            raise cmdline.error(args, text, f"--rename `{text}`: `{b}` is no leaf of {args.new}")
        if a in out:
            raise cmdline.error(args, text, f"--rename `{text}`: `{a}` is renamed twice")
        if b in out.values():
            raise cmdline.error(args, text, f"--rename `{text}`: another leaf is renamed `{b}` already")
        out[a] = b
    for text in args.rename:
        a, _, b = (x.strip() for x in text.partition("="))
        if b in old_names and b not in out:
            # OLD's own `b` and the renamed `a` would share one name: the scenario could not tell them apart
            raise cmdline.error(args, text, f"--rename `{text}`: {args.old} has a leaf `{b}` too; rename it as well")
    return out


def _side_by_side(old: list[list[Event]], new: list[list[Event]], at: Optional[tuple[int, int]]) -> list[str]:
    rows: list[str] = []
    for t in range(max(len(old), len(new))):
        rows.append(f"  {'tick ' + str(t + 1):<{WIDTH}} | tick {t + 1}")
        eo = old[t] if t < len(old) else []
        en = new[t] if t < len(new) else []
        for i in range(max(len(eo), len(en))):
            a = event_text(eo[i]) if i < len(eo) else ""
            b = event_text(en[i]) if i < len(en) else ""
            mark = "!" if at == (t, i) else " "
            line = f"{mark}   {a:<{WIDTH - 2}} |   {b}"
            if at == (t, i):
                line += "   <- first difference"
            rows.append(line.rstrip())
    return rows


def _write(path: str, text: str) -> None:
    from btgen.tools.graph import _write as write_atomic

    write_atomic(path, text.encode("utf-8"))


def diff_command(args) -> int:
    default = getattr(args, "btcpp", None) or "4.6.2"
    v_old = args.btcpp_old or default
    v_new = args.btcpp_new or default
    if args.clock_ms < 0:
        raise cmdline.error(args, "--clock-ms", "--clock-ms cannot be negative")
    if args.git is not None:
        from btgen.tools.diff.git import git_diff_command

        return git_diff_command(args, v_old, v_new)
    if args.old is None or args.new is None:
        raise cmdline.error(args, None, "diff needs OLD.xml and NEW.xml (or --git REV [PATH ...])")
    if args.paths:
        raise cmdline.error(args, args.paths[0], f"`{args.paths[0]}`: more than two missions (PATHs go with --git)")
    problems: list[Diagnostic] = []
    missions: list[Optional[Mission]] = []
    sides = (("OLD", args.old, v_old, args.models_old), ("NEW", args.new, v_new, args.models_new))
    for side, path, version, models in sides:
        try:
            missions.append(_load(path, args, version, models))
        except UserError as e:  # report both files' problems, not only the first's
            problems.extend(e.diagnostics)
            # which side failed (OLD and NEW may be one file under two versions)
            problems.append(
                Diagnostic(Loc(path, 1, 1), f"while loading {side} under BehaviorTree.CPP {version}", "note")
            )
            missions.append(None)
    if problems:
        raise UserError(problems)
    old, new = missions
    assert old is not None and new is not None
    if old.main_tree != new.main_tree:
        raise UserError(
            Diagnostic(
                Loc(args.new, 1, 1),
                f"the main tree is `{new.main_tree}` here and `{old.main_tree}` in {args.old}: "
                "diff compares the same main tree (choose it with --main-tree)",
            )
        )
    rename = _renames(args, old, new)
    observables = parse_observe(args)
    differ = Differ(old, new, rename, args.max_ticks, args.clock_ms, args.max_states, observables)
    outcome = differ.decide()
    head = f"{args.old} (BehaviorTree.CPP {v_old}) vs {args.new} (BehaviorTree.CPP {v_new})"
    if outcome.exhaustive:
        verdict = "equivalent (exhaustively)"
    elif outcome.why_bounded == "states":
        # a partial search: runs cut as repeats may have their futures still unexplored
        verdict = f"no difference found (stopped at --max-states {args.max_states}: a partial search, not a proof)"
    else:
        verdict = f"equivalent (up to {outcome.bound} ticks)"
    stats = {
        "runs": outcome.runs,
        "states": outcome.states,
        "seconds": round(outcome.seconds, 3),
    }
    if outcome.equivalent:
        if args.format == "json":
            report = {"old": args.old, "new": args.new, "btcpp_old": v_old, "btcpp_new": v_new}
            report.update(
                {
                    "equivalent": True if outcome.why_bounded != "states" else None,
                    "exhaustive": outcome.exhaustive,
                    "max_ticks": outcome.bound,
                    "verdict": verdict,
                    "stopped_at_max_states": outcome.why_bounded == "states",
                    **stats,
                }
            )
            json.dump(report, sys.stdout, indent=2)
            sys.stdout.write("\n")
        elif args.format == "markdown":
            print(f"**btgen diff**: `{args.old}` ({v_old}) vs `{args.new}` ({v_new}): **{verdict}**")
            print()
            print(f"{outcome.runs} runs, {outcome.states} product states, {outcome.seconds:.2f} s")
        else:
            print(f"{head}: {verdict}")
            print(f"  {outcome.runs} runs, {outcome.states} product states, {outcome.seconds:.2f} s")
        return 0

    text_old, text_new = scenario_texts(outcome, rename, args.clock_ms)
    sc_old = parse_scenario_text(text_old, "old.scenario")
    sc_new = parse_scenario_text(text_new, "new.scenario")
    seen_old = observe(old, sc_old, lambda n: rename.get(n, n), observables)
    seen_new = observe(new, sc_new, observables=observables)
    at = first_difference(seen_old, seen_new)
    if at is None:  # the search and the replay disagree: never print a counterexample that is none
        raise InternalError("btgen diff: the counterexample found does not replay as a difference")
    files: list[str] = []
    if args.counterexample:
        files = write_counterexample(args.counterexample, old, new, text_old, text_new, pipeline_options(args))
    rows = _side_by_side(seen_old, seen_new, at)
    where = ""
    first: dict = {}
    if at is not None:
        first = difference_record(seen_old, seen_new, at)
        where = (
            f"tick {first['tick']}, event {first['event']}: OLD {first['old'] or '(nothing)'}, "
            f"NEW {first['new'] or '(nothing)'}"
        )
    if args.format == "json":
        report = {"old": args.old, "new": args.new, "btcpp_old": v_old, "btcpp_new": v_new}
        report.update(
            {
                "equivalent": False,
                "max_ticks": outcome.bound,
                **stats,
                "first_difference": first,
                "scenario": text_new,
                "scenario_old": text_old,
                "old_trace": [[event_text(e) for e in tick] for tick in seen_old],
                "new_trace": [[event_text(e) for e in tick] for tick in seen_new],
                "files": files,
            }
        )
        json.dump(report, sys.stdout, indent=2)
        sys.stdout.write("\n")
        return 1
    if args.format == "markdown":
        print(f"**btgen diff**: `{args.old}` ({v_old}) vs `{args.new}` ({v_new}): **different**")
        print()
        print(f"First difference: {where}.")
        print()
        print("Scenario (shortest):")
        print()
        print("```")
        sys.stdout.write(text_new)
        print("```")
        print()
        print("```text")
    else:
        print(f"{head}: different")
        print(f"  first difference: {where}")
        print("  scenario (shortest):")
        for line in text_new.splitlines():
            print(f"    {line}")
        if text_old != text_new:
            print("  scenario for OLD (its leaf names):")
            for line in text_old.splitlines():
                print(f"    {line}")
    print(f"  {'OLD':<{WIDTH}} | NEW")
    for row in rows:
        print(row)
    if args.format == "markdown":
        print("```")
    for f in files:
        print(f"  wrote {f}", file=sys.stderr)
    return 1


def write_counterexample(folder: str, old: Mission, new: Mission, text_old: str, text_new: str, opts=None) -> list[str]:
    """DIR/old.scenario, DIR/new.scenario (the same unless --rename), the interpreter's FORMAT.md
    trace of each mission on its scenario (old.trace, new.trace) and the same run of each as a
    Groot2 log (old.btlog, new.btlog: verify's writer, `tools/verify/replay.btlog_bytes`), which
    `btgen scenario-from-log` turns back into the scenario's run on both engines. Each file is
    written whole or not at all."""
    from btgen import pipeline
    from btgen.interp.engine import Interpreter, run_ticks
    from btgen.tools.verify.replay import btlog_bytes

    try:
        os.makedirs(folder, exist_ok=True)
    except OSError as e:
        raise UserError(Diagnostic(Loc(folder, 1, 1), f"cannot create the output folder: {e.strerror or e}")) from None
    out = []
    for stem, mission, text in (("old", old, text_old), ("new", new, text_new)):
        sc = os.path.join(folder, f"{stem}.scenario")
        scenario = parse_scenario_text(text, sc)
        parts: list[str] = []
        try:
            run_ticks(Interpreter(mission, scenario), scenario, parts.append)
            trace = "".join(parts)
        except UserError as e:  # a run-time error ends this side's run: its ticks so far, then why
            trace = "".join(parts) + "".join(str(d) + "\n" for d in e.diagnostics)
        program = pipeline.program(mission, opts or pipeline.DEFAULTS)
        log = btlog_bytes(program, trace, scenario.clock_ms)
        _write(sc, text)
        tr = os.path.join(folder, f"{stem}.trace")
        _write(tr, trace)
        bl = os.path.join(folder, f"{stem}.btlog")
        write_atomic_bytes(bl, log)
        out += [sc, tr, bl]
    return out


def write_atomic_bytes(path: str, data: bytes) -> None:
    from btgen.tools.graph import _write as write_atomic

    write_atomic(path, data)
