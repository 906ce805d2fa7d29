"""`btgen verify`: properties of the shipped tree file proved by SPIN, probabilities by Storm.

    btgen verify MISSION.xml [--property P ...] [--properties FILE] [--counterexample DIR]
                 [--running-bound K] [--ticks N] [--clock-ms MS] [--contract FILE] [--replay-cpp]
    btgen verify MISSION.xml --probabilities FILE [--within N] [--ever NAME ...]

The lowered program (the node table the C++ back end prints, for the selected --btcpp) is
translated into Promela (`promela.py`), properties in SPIN's LTL over per-tick atoms
(`props.py`) are checked by SPIN (`spin.py`), and every counterexample becomes a scenario, a
.btlog and a trace, replayed on the interpreter and, with --replay-cpp, on the generated C++
(`replay.py`): it is shown only when it shows the violation there. `markov.py` builds the
Markov chain of a mission whose leaves answer with given probabilities and asks Storm.

Exit status: 0 when every property holds, 1 when one is violated (or on bad input, or when a
search is incomplete: no proof is claimed then), 2 when none is violated but a bitstate search
(`--search bitstate|auto`) found no violation where no proof was made: partial, not a proof.
"""

from __future__ import annotations

import json
import os
import sys
import tempfile
import time
from typing import Optional

from btgen import cmdline
from btgen.diagnostics import Diagnostic, InternalError, Loc, UserError, did_you_mean, print_diagnostics, read_bounded
from btgen.ir.lower import Program
from btgen.tools.verify import props as P
from btgen.tools.verify import spin
from btgen.tools.verify.promela import STATUS, ModelOptions, Observe, emit_model


def add_arguments(v) -> None:
    v.add_argument(
        "--property",
        dest="properties_inline",
        action="append",
        default=[],
        metavar="P",
        help="an LTL property in SPIN syntax over ticked(N), running(N), returned(N, S), root(S), "
        "or a template: absence(F), response(F, G), mutex(A, B), eventually_success",
    )
    v.add_argument(
        "--properties",
        dest="property_files",
        action="append",
        default=[],
        metavar="FILE",
        help="a file of properties, one a line (`name: property`, # comments)",
    )
    v.add_argument(
        "--counterexample", metavar="DIR", help="write each counterexample there (.scenario, .btlog, .trace)"
    )
    v.add_argument(
        "--running-bound",
        type=int,
        metavar="K",
        help="an Action answers RUNNING at most K times in a row (default: unbounded)",
    )
    v.add_argument(
        "--failure-bound",
        type=int,
        metavar="K",
        help="a leaf answers FAILURE at most K times in a row (a fairness: retried, it succeeds)",
    )
    v.add_argument("--ticks", type=int, metavar="N", help="check runs of at most N ticks (default: unbounded)")
    v.add_argument("--clock-ms", type=int, default=100, metavar="MS", help="virtual time per tick (default 100)")
    v.add_argument(
        "--contract",
        metavar="FILE",
        help='leaf contract, JSON: {"LeafName": ["SUCCESS", "FAILURE"]} (the statuses it may return), '
        '{"Condition": {"success_if": "SCRIPT"}} (a function of the blackboard)',
    )
    v.add_argument(
        "--search",
        choices=("exhaustive", "bitstate", "auto"),
        default="exhaustive",
        metavar="HOW",
        help="exhaustive (a proof, default); bitstate (pan -DBITSTATE: finds violations, proves nothing; "
        "exit 2 when none is found); auto (bitstate for a property whose exhaustive search does not fit)",
    )
    v.add_argument("--replay-cpp", action="store_true", help="also replay every counterexample on the generated C++")
    v.add_argument("--model", metavar="FILE", help="write the Promela model there")
    v.add_argument(
        "--probabilities",
        metavar="FILE",
        help='per-leaf outcome probabilities, JSON: {"Grasp": {"SUCCESS": 0.6, "FAILURE": 0.4}}: Storm',
    )
    v.add_argument("--within", type=int, metavar="N", help="with --probabilities: also P(root SUCCESS within N ticks)")
    v.add_argument(
        "--ever", action="append", default=[], metavar="NAME", help="with --probabilities: P(NAME is ever ticked)"
    )


def _prop_loc(args, text: str) -> Loc:
    """Where the text of a --property starts on the command line."""
    argv = list(getattr(args, "argv", None) or sys.argv[1:])
    col = 1
    for k, a in enumerate(argv):
        if a == text and k > 0 and argv[k - 1] == "--property":
            return Loc(cmdline.COMMAND_LINE, 1, col)
        if a == "--property=" + text:
            return Loc(cmdline.COMMAND_LINE, 1, col + len("--property="))
        col += len(a) + 1
    return Loc(cmdline.COMMAND_LINE, 1, 1)


def load_contract(path: str, program: Program) -> tuple[tuple[str, tuple[int, ...]], ...]:
    """{"Leaf": ["SUCCESS", ...]}: the statuses each named leaf may return."""
    return load_contract_full(path, program)[0]


def load_contract_full(
    path: str, program: Program
) -> tuple[tuple[tuple[str, tuple[int, ...]], ...], tuple[tuple[str, str, Loc], ...]]:
    """The statuses each named leaf may return, and the Conditions that are a function of the
    blackboard: {"Low": {"success_if": "battery < 20"}} (a script, true: SUCCESS)."""
    data = read_bounded(path, 1 << 20, "contract", "contracts", cannot="cannot read the contract")
    text = data.decode("utf-8", "replace")
    try:
        doc = json.loads(text)
    except json.JSONDecodeError as e:
        raise UserError(Diagnostic(Loc(path, e.lineno, e.colno), f"not JSON: {e.msg}")) from None

    def at(key: str) -> Loc:
        k = text.find(json.dumps(key))
        if k < 0:
            return Loc(path, 1, 1)
        line = text.count("\n", 0, k) + 1
        return Loc(path, line, k - (text.rfind("\n", 0, k) + 1) + 1)

    if not isinstance(doc, dict):
        raise UserError(Diagnostic(Loc(path, 1, 1), 'the contract is a JSON object: {"Leaf": ["SUCCESS", "FAILURE"]}'))
    leaves = {n.name: n.kind for n in program.nodes if n.kind in ("Action", "Condition")}
    out: list[tuple[str, tuple[int, ...]]] = []
    functions: list[tuple[str, str, Loc]] = []
    for name, statuses in doc.items():
        if name not in leaves:
            hint = did_you_mean(name, list(leaves))
            extra = f" (did you mean `{hint}`?)" if hint else ""
            raise UserError(
                Diagnostic(at(name), f"the contract names `{name}`, which is no leaf of the mission{extra}")
            )
        if isinstance(statuses, dict):
            script = statuses.get("success_if")
            if leaves[name] != "Condition" or set(statuses) != {"success_if"} or not isinstance(script, str):
                raise UserError(
                    Diagnostic(
                        at(name),
                        f'`{name}`: a Condition\'s function of the blackboard is {{"success_if": "SCRIPT"}}'
                        + ("" if leaves[name] == "Condition" else f" (`{name}` is an Action)"),
                    )
                )
            functions.append((name, script, at(name)))
            out.append((name, (STATUS["SUCCESS"], STATUS["FAILURE"])))
            continue
        if not isinstance(statuses, list) or not statuses or not all(isinstance(s, str) for s in statuses):
            raise UserError(Diagnostic(at(name), f"`{name}`: a non-empty list of statuses"))
        allowed = ("SUCCESS", "FAILURE") if leaves[name] == "Condition" else ("SUCCESS", "FAILURE", "RUNNING")
        for s in statuses:
            if s not in allowed:
                raise UserError(
                    Diagnostic(at(name), f"`{name}` ({leaves[name]}) cannot return `{s}`: use {', '.join(allowed)}")
                )
        out.append((name, tuple(STATUS[s] for s in statuses)))
    return tuple(out), tuple(functions)


def _options(args, program: Program) -> ModelOptions:
    if args.running_bound is not None and args.running_bound < 0:
        raise cmdline.error(args, "--running-bound", "--running-bound cannot be negative")
    if args.failure_bound is not None and args.failure_bound < 0:
        raise cmdline.error(args, "--failure-bound", "--failure-bound cannot be negative")
    if args.ticks is not None and args.ticks < 1:
        raise cmdline.error(args, "--ticks", "--ticks must be at least 1")
    if args.clock_ms < 0:
        raise cmdline.error(args, "--clock-ms", "--clock-ms cannot be negative")
    contract, functions = load_contract_full(args.contract, program) if args.contract else ((), ())
    return ModelOptions(
        args.running_bound, args.ticks, args.clock_ms, contract, True, args.failure_bound, functions=functions
    )


def parse_properties(args, program: Program, mission=None) -> list[P.Property]:
    entries: dict[str, str] = {}
    if mission is not None:
        from btgen.tools.verify.blackboard import build_tables, entries_of

        entries = entries_of(build_tables(mission, program, ticks=args.ticks, clock_ms=args.clock_ms))
    names = P.Names(program, entries)
    out: list[P.Property] = []
    for text in args.properties_inline:
        out.append(P.parse_property(text, _prop_loc(args, text), names, len(out)))
    for path in args.property_files:
        out.extend(P.parse_file(path, names, len(out)))
    return out


def build_model(mission, program: Program, options: ModelOptions, properties: list[P.Property]) -> str:
    from btgen.tools.verify.promela import Emitter

    emitter = Emitter(mission, program, options)
    emitter.check_scenario_names()
    print_diagnostics(emitter.bbt.warnings)
    obs = Observe(bb_values=emitter.bbt.values)
    ltl = []
    for p in properties:
        f = P.to_spin(p.formula, obs)
        if not P.start_insensitive(p.formula):  # read from the end of the first tick on
            started = obs.atom("true")
            f = f"(!{started}) U (({started}) && ({f}))"
        ltl.append((p.name, f))
    return emit_model(mission, program, options, obs, ltl)


def verify_command(args) -> int:
    from btgen import pipeline
    from btgen.tools.verify import replay as R

    opts = pipeline.options_from_args(args)
    mission, program = pipeline.build(args.mission, opts)
    print_diagnostics(mission.warnings)
    options = _options(args, program)
    if args.probabilities:
        from btgen.tools.verify.markov import markov_command

        return markov_command(args, mission, program, options)
    properties = parse_properties(args, program, mission)
    if args.search != "exhaustive" and not properties:
        raise cmdline.error(
            args, "--search", "--search bitstate|auto checks properties: give --property or --properties"
        )
    text = build_model(mission, program, options, properties)
    if args.model:
        from btgen.tools.graph import _write

        _write(args.model, text.encode("utf-8"))
    stem = os.path.splitext(os.path.basename(args.mission))[0]
    status = 0
    with tempfile.TemporaryDirectory(prefix="btgen-verify-") as work:
        try:
            if not properties:
                try:
                    res = spin.reachable(text, work)
                except spin.Incomplete as e:
                    raise UserError(Diagnostic(Loc(args.mission, 1, 1), f"no state count: {e}")) from None
                print(
                    f"{args.mission}: {res.states} states, {res.transitions} transitions, depth {res.depth}, "
                    f"{res.memory_mb:.1f} MB, {res.seconds:.2f} s search + {res.compile_seconds:.2f} s to build pan"
                )
                return 0
            compile_s = spin.compile_model(text, work, spin.BITSTATE if args.search == "bitstate" else ())
        except spin.SpinMissing as e:
            raise UserError(
                Diagnostic(
                    Loc(args.mission, 1, 1), f"btgen verify needs `{e}` (scripts/setup.sh installs spin and tcc)"
                )
            ) from None
        search = " (bitstate search: no proofs)" if args.search == "bitstate" else ""
        print(f"{args.mission}: {len(program.nodes)} nodes, model built in {compile_s:.2f} s{search}")
        bit_work = work if args.search == "bitstate" else None
        for prop in properties:
            t0 = time.perf_counter()
            res = spin.check(work, prop.name, bitstate=args.search == "bitstate")
            why = ""
            if res.holds is None and not res.partial and args.search == "auto":
                why = f" (the exhaustive search did not fit: {res.incomplete})"
                if bit_work is None:
                    bit_work = os.path.join(work, "bitstate")
                    spin.compile_model(text, bit_work, spin.BITSTATE)
                res = spin.check(bit_work, prop.name, bitstate=True)
            cost = f"{res.memory_mb:.1f} MB, {time.perf_counter() - t0:.2f} s"
            stats = f"states {res.states}, depth {res.depth}, {cost}" + (", bitstate search" if why else "")
            if res.partial:
                print(f"  partial   {prop.text}  ({res.partial}{why}; depth {res.depth}, {cost})")
                status = status or 2
                continue
            if res.holds is None:
                print(
                    f"{prop.loc}: error: `{prop.text}`: no proof, the search is incomplete: {res.incomplete}",
                    file=sys.stderr,
                )
                status = 1
                continue
            if res.holds:
                print(f"  holds     {prop.text}  ({stats})")
                continue
            status = 1
            if res.trail is None:
                raise InternalError(f"SPIN found `{prop.text}` violated but left no trail")
            trail = spin.parse_trail(res.trail)
            cx = R.replay(mission, program, prop, trail, res.trail, options.clock_ms)
            files: list[str] = []
            if args.counterexample:
                files = R.write_files(cx, program, args.counterexample, f"{stem}-{prop.name}", options.clock_ms)
            if args.replay_cpp:
                scen = files[0] if files else _temp_scenario(work, prop.name, cx.scenario)
                R.replay_cpp(cx, args.mission, opts, scen, len(program.nodes))
            print(f"  VIOLATED  {prop.text}  ({stats})")
            where = "loops back to tick" if trail.lasso and trail.cycle_ticks else "ends at tick"
            target = cx.loop + 1 if trail.lasso and trail.cycle_ticks else cx.ticks
            print(f"    counterexample: {cx.ticks} ticks, {where} {target}")
            for f in files:
                print(f"    {f}")
            if cx.problems:
                raise InternalError(
                    f"the counterexample of `{prop.text}` does not replay as SPIN found it: "
                    + "; ".join(cx.problems)
                    + "\n"
                    + cx.scenario
                )
            shown = "interpreter" + (", generated C++" if cx.shown_cpp else "")
            print(f"    replayed on the {shown}: the violation shows")
    return status


def _temp_scenario(work: str, name: str, text: str) -> str:
    path = os.path.join(work, f"{name}.scenario")
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)
    return path


def run_properties(
    mission, program: Program, properties: list[P.Property], options: ModelOptions, work: str
) -> list[tuple[P.Property, spin.SpinResult, Optional[object]]]:
    """Check each property; (property, SPIN's result, the replayed Counterexample or None)."""
    from btgen.tools.verify import replay as R

    text = build_model(mission, program, options, properties)
    spin.compile_model(text, work)
    out: list[tuple[P.Property, spin.SpinResult, Optional[object]]] = []
    for prop in properties:
        res = spin.check(work, prop.name)
        cx = None
        if res.holds is False and res.trail is not None:
            cx = R.replay(mission, program, prop, spin.parse_trail(res.trail), res.trail, options.clock_ms)
        out.append((prop, res, cx))
    return out
