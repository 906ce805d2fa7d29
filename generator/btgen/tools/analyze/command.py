"""`btgen analyze`: the executor's sizes from the tables, the report (text or --json) and the
exit status."""

from __future__ import annotations

import json
import struct
import sys
from typing import Optional

from btgen.diagnostics import Diagnostic, UserError, print_diagnostics
from btgen.ir.kinds import is_queue
from btgen.ir.lower import IRNode, Program
from btgen.tools.analyze.checks import analyze_program
from btgen.tools.analyze.results import ORDER, UNBOUNDED, Finding


def memory(program: Program) -> dict:
    """The compiled executor's sizes from the tables (runtime/include/btgen/engine.hpp: statuses are
    bytes, counters int32, timers uint64; the blackboard as data_cpp.py spells its slots)."""
    n = len(program.nodes)
    bb = 0
    if program.data is not None:
        for s in program.data.slots:
            if s.kind == "string":
                bb += s.capacity + 8
            elif is_queue(s.kind):
                bb += s.capacity * max(s.elem_capacity + 8, 8) + 16
            elif s.kind == "bool":
                bb += 2
            else:
                bb += 16
    return {
        "nodes": n,
        "stack_depth": program.max_depth,
        "counters": program.counter_count,
        "timers": program.timer_count,
        "state_bytes": n + 4 * program.counter_count + 8 * program.timer_count,
        "blackboard_slots": len(program.data.slots) if program.data is not None else 0,
        "blackboard_bytes_estimate": bb,
    }


# ====================================================================== command
def stop_quietly_on_broken_pipe(command, args) -> int:
    """Run a command whose reader may go away (`btgen explore ... | head`): stop quietly, exit 1."""
    import os

    try:
        return command(args)
    except BrokenPipeError:
        try:
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, sys.stdout.fileno())
        except (OSError, ValueError):
            pass
        return 1


def _fmt(v: int) -> str:
    return "unbounded" if v == UNBOUNDED else str(v)


def rate_limits(program: Program) -> list[tuple[IRNode, Optional[float]]]:
    """Each Nav2 RateController and its hz (None: read from the blackboard when it starts): once
    its child has succeeded, the child is ticked again only after 1/hz seconds of the clock
    (while the child is RUNNING, on every tick)."""
    out: list[tuple[IRNode, Optional[float]]] = []
    for n in program.nodes:
        if n.kind == "RateController":
            out.append((n, None if n.params[1] else struct.unpack("<d", struct.pack("<q", n.params[0]))[0]))
    return out


def analyze_command(args) -> int:
    from btgen import pipeline

    opts = pipeline.options_from_args(args)
    options = opts.data
    status = 0
    reports = []
    for path in args.missions:
        try:
            mission = pipeline.load(path, opts)
            print_diagnostics(mission.warnings)
            program = pipeline.program(mission, opts)
        except UserError as e:
            print_diagnostics(e.diagnostics)
            status = 1
            continue
        result = analyze_program(mission, program, options)
        worst = result.worst()
        if args.tick_budget is not None:
            for name, v in zip(("nodes visited", "leaf hooks called", "script evaluations"), worst):
                if v == UNBOUNDED or v > args.tick_budget:
                    culprit = ""
                    if v == UNBOUNDED and result.unbounded_by is not None:
                        u = program.nodes[result.unbounded_by]
                        culprit = f' ({u.id} "{u.name}" may tick its children any number of times)'
                    result.findings.append(
                        Finding(
                            program.nodes[0].loc,
                            "budget",
                            f"a tick can take {_fmt(v)} {name}, over the budget of {args.tick_budget}{culprit}",
                        )
                    )
        mem = memory(program)
        reports.append((path, result, worst, mem))
        if args.json:
            continue
        print_diagnostics([Diagnostic(f.loc, f.message, "warning") for f in result.findings])
        if result.findings and args.werror:
            status = 1
    if args.json:
        doc = []
        for path, result, worst, mem in reports:
            unb = result.unbounded_by
            doc.append(
                {
                    "mission": path,
                    "findings": [f.as_json() for f in result.findings],
                    "worst_tick": {
                        "nodes_visited": None if worst[0] == UNBOUNDED else worst[0],
                        "leaf_hooks": None if worst[1] == UNBOUNDED else worst[1],
                        "script_evaluations": None if worst[2] == UNBOUNDED else worst[2],
                        "unbounded_by": None if unb is None else result.program.nodes[unb].uid,
                    },
                    "root_outcomes": {st: list(c) for st, c in result.outcomes[0].items()},
                    "unreachable_nodes": sum(1 for r in result.reachable if not r),
                    "rate_limits": [{"uid": n.uid, "name": n.name, "hz": hz} for n, hz in rate_limits(result.program)],
                    "memory": mem,
                }
            )
            if result.findings and args.werror:
                status = 1
        json.dump(doc if len(doc) != 1 else doc[0], sys.stdout, indent=2)
        sys.stdout.write("\n")
        return status
    for path, result, worst, mem in reports:
        counts: dict[str, int] = {}
        for f in result.findings:
            counts[f.category] = counts.get(f.category, 0) + 1
        unreachable = sum(1 for r in result.reachable if not r)
        rows = [
            ("nodes (SubTrees expanded)", str(mem["nodes"])),
            ("unreachable nodes", str(unreachable)),
            ("worst tick: nodes visited", _fmt(worst[0])),
            ("worst tick: leaf hooks called", _fmt(worst[1])),
            ("worst tick: script evaluations", _fmt(worst[2])),
            ("root can return", ", ".join(st for st in ORDER if st in result.outcomes[0]) or "-"),
            ("stack depth", str(mem["stack_depth"])),
            ("state (statuses, counters, timers)", f"{mem['state_bytes']} bytes"),
            ("blackboard", f"{mem['blackboard_slots']} entries, ~{mem['blackboard_bytes_estimate']} bytes"),
            ("findings", ", ".join(f"{v} {k}" for k, v in sorted(counts.items())) or "none"),
        ]
        if result.unbounded_by is not None:
            n = result.program.nodes[result.unbounded_by]
            rows.insert(5, ("unbounded because of", f'{n.id} "{n.name}" ({n.loc})'))
        for n, hz in rate_limits(result.program):
            how = (
                "as often a second as its `hz` entry says when the node starts"
                if hz is None
                else f"at most {hz:g} times a second (every {1.0 / hz if hz else float('inf'):g} s of the clock"
                "; ticked on every tick while RUNNING)"
            )
            rows.append(("rate limit", f'RateController "{n.name}": its child starts again {how}'))
        width = max(len(r[0]) for r in rows)
        print(f"{path}:")
        for label, text in rows:
            print(f"  {label.ljust(width)}  {text}")
    return status
