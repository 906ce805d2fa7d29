"""`btgen verify --probabilities FILE`: the mission as a discrete-time Markov chain, asked of Storm.

Each leaf answers with the probabilities the file gives, call by call, independently
(`{"Grasp": {"SUCCESS": 0.6, "FAILURE": 0.3, "RUNNING": 0.1}}`: a RUNNING answer with
probability p makes the Action's run last a geometric number of ticks). A state of the chain
is the state of the reference interpreter after a tick (explore's state key: every node's
status and members, the blackboard), found by replaying plans of leaf answers on the
interpreter, as `btgen explore` does; one transition is one tick, with the probability of the
answers that lead there. The run ends in an absorbing state when the root returns SUCCESS or
FAILURE. Storm (stormpy) then computes

    P(root SUCCESS)            P=? [F "success"]      (and FAILURE)
    P(root SUCCESS within N)   P=? [F<=N "success"]   (--within N)
    expected ticks to the end  R=? [F "done"]         (one per tick; infinite if the run may never end)
    P(NAME is ever ticked)     P=? [F "ticked_k"]     (--ever NAME)

Nodes that read the clock (Sleep, Delay, Timeout) are refused: their state is the time.
"""

from __future__ import annotations

import json
import math
import os
import random
import re
import sys
import tempfile
from collections import deque
from dataclasses import dataclass, field

from btgen.diagnostics import Diagnostic, Loc, UserError, read_bounded
from btgen.interp import actions as iactions
from btgen.interp.engine import Interpreter
from btgen.interp.tree import FAILURE, SUCCESS
from btgen.ir.lower import Program
from btgen.lang.model import Mission
from btgen.tools.verify.promela import STATUS

MAX_STATES = 200_000
_TIMERS = ("Sleep", "Delay", "Timeout", "RateController")  # the nodes that read the clock


class _Branch(Exception):
    def __init__(self, name: str) -> None:
        self.name = name


class _Cursor:
    __slots__ = ("run", "name")

    def __init__(self, run: _Replay, name: str) -> None:
        self.run = run
        self.name = name

    def next(self) -> int:
        r = self.run
        if r.pos < len(r.plan):
            v = r.plan[r.pos]
            r.pos += 1
            return v
        raise _Branch(self.name)


class _Replay:
    """A fresh interpreter taking the leaves' answers from a plan."""

    def __init__(self, mission: Mission, plan: tuple[int, ...]) -> None:
        self.plan = plan
        self.pos = 0
        self.interp = Interpreter(mission, None)
        self.chain: list = []
        self.seen_return: set = set()
        for node in self.interp.nodes:
            if isinstance(node, (iactions.ScriptedAction, iactions.ScriptedCondition)):
                node.cursor = _Cursor(self, node.name)


def load_probabilities(path: str, program: Program) -> dict[str, list[tuple[int, float]]]:
    data = read_bounded(path, 1 << 20, "probabilities", cannot="cannot read the probabilities")
    text = data.decode("utf-8", "replace")
    try:
        doc = json.loads(text)
    except json.JSONDecodeError as e:
        raise UserError(Diagnostic(Loc(path, e.lineno, e.colno), f"not JSON: {e.msg}")) from None

    def at(key: str) -> Loc:
        k = text.find(json.dumps(key))
        if k < 0:
            return Loc(path, 1, 1)
        return Loc(path, text.count("\n", 0, k) + 1, k - (text.rfind("\n", 0, k) + 1) + 1)

    if not isinstance(doc, dict):
        raise UserError(Diagnostic(Loc(path, 1, 1), 'a JSON object: {"Leaf": {"SUCCESS": 0.6, "FAILURE": 0.4}}'))
    leaves = {n.name: n.kind for n in program.nodes if n.kind in ("Action", "Condition")}
    out: dict[str, list[tuple[int, float]]] = {}
    for name, dist in doc.items():
        if name not in leaves:
            raise UserError(Diagnostic(at(name), f"`{name}` is no leaf of the mission"))
        allowed = ("SUCCESS", "FAILURE") if leaves[name] == "Condition" else ("SUCCESS", "FAILURE", "RUNNING")
        if not isinstance(dist, dict) or not dist:
            raise UserError(Diagnostic(at(name), f'`{name}`: an object of probabilities {{"SUCCESS": p, ...}}'))
        pairs = []
        for s, p in dist.items():
            if s not in allowed:
                raise UserError(Diagnostic(at(name), f"`{name}` ({leaves[name]}) cannot return `{s}`"))
            if not isinstance(p, (int, float)) or isinstance(p, bool) or not 0 <= p <= 1:
                raise UserError(Diagnostic(at(name), f"`{name}`: the probability of {s} is not a number from 0 to 1"))
            if p > 0:
                pairs.append((STATUS[s], float(p)))
        if abs(sum(p for _, p in pairs) - 1.0) > 1e-9:
            raise UserError(
                Diagnostic(at(name), f"`{name}`: the probabilities add up to {sum(p for _, p in pairs)}, not 1")
            )
        out[name] = pairs
    missing = sorted(set(leaves) - set(out))
    if missing:
        raise UserError(Diagnostic(Loc(path, 1, 1), f"no probabilities for the leaves {', '.join(missing)}"))
    return out


@dataclass
class Chain:
    """The explicit DTMC: state 0 is the start; `done` states are absorbing."""

    transitions: list[dict[int, float]] = field(default_factory=list)
    labels: list[set[str]] = field(default_factory=list)


def build_chain(
    mission: Mission, program: Program, probs: dict[str, list[tuple[int, float]]], watched: tuple[int, ...] = ()
) -> Chain:
    from btgen.tools.explore import Explorer
    from btgen.tools.verify.replay import _Watch

    for n in program.nodes:
        if n.id in _TIMERS:
            raise UserError(Diagnostic(n.loc, f"`{n.id}` reads the clock: --probabilities does not translate it"))
    keyer = Explorer(mission)
    chain = Chain()
    index: dict[tuple, int] = {}
    ends = {SUCCESS: "success", FAILURE: "failure"}

    def state(key: tuple, labels: set[str]) -> tuple[int, bool]:
        if key in index:
            return index[key], False
        index[key] = len(chain.transitions)
        chain.transitions.append({})
        chain.labels.append(labels)
        return index[key], True

    start, _ = state(("start",), {"init"})
    queue: deque[tuple[int, tuple[int, ...], int]] = deque([(start, (), 0)])
    probe = _Replay(mission, ())
    watch = _Watch(probe.interp)
    try:
        while queue:
            sid, plan, ticks = queue.popleft()
            stack: list[tuple[tuple[int, ...], float]] = [((), 1.0)]
            while stack:
                ext, p = stack.pop()
                run = _Replay(mission, plan + ext)
                watch.index = {id(n): n.uid - 1 for n in run.interp.nodes}
                try:
                    for _ in range(ticks):
                        run.interp.tick_once()
                    watch.ticked.clear()
                    watch.returned.clear()
                    result = run.interp.tick_once()
                except _Branch as b:
                    for status, q in probs[b.name]:
                        stack.append((ext + (status,), p * q))
                    continue
                flags = frozenset(i for i in watched if i in watch.ticked)
                labels = {f"ticked_{i}" for i in flags}
                code = STATUS[result.name]
                if code in ends:
                    target, new = state(("end", code, flags), labels | {ends[code], "done"})
                    if new:
                        chain.transitions[target][target] = 1.0
                else:
                    key = (keyer.key_of_interpreter(run.interp), flags)
                    target, new = state(key, labels)
                    if new:
                        if len(chain.transitions) > MAX_STATES:
                            raise UserError(
                                Diagnostic(program.nodes[0].loc, f"the Markov chain has more than {MAX_STATES} states")
                            )
                        queue.append((target, plan + ext, ticks + 1))
                row = chain.transitions[sid]
                row[target] = row.get(target, 0.0) + p
    finally:
        watch.restore()
    return chain


def storm_queries(chain: Chain, queries: list[str]) -> list[float]:
    """Each query (Storm's property syntax) at the start state."""
    import stormpy

    with tempfile.TemporaryDirectory(prefix="btgen-storm-") as d:
        tra, lab, rew = (os.path.join(d, f) for f in ("m.tra", "m.lab", "m.rew"))
        with open(tra, "w") as f:
            f.write("dtmc\n")
            for s, row in enumerate(chain.transitions):
                total = sum(row.values())
                for t, p in sorted(row.items()):
                    f.write(f"{s} {t} {p / total!r}\n")
        # a label no state carries (a node never ticked) is declared too: Storm refuses an unknown one
        asked = {x for q in queries for x in re.findall(r'"(\w+)"', q)}
        names = sorted({x for ls in chain.labels for x in ls} | {"init", "success", "failure", "done"} | asked)
        with open(lab, "w") as f:
            f.write("#DECLARATION\n" + " ".join(names) + "\n#END\n")
            for s, ls in enumerate(chain.labels):
                if ls:
                    f.write(f"{s} {' '.join(sorted(ls))}\n")
        with open(rew, "w") as f:
            for s, ls in enumerate(chain.labels):
                if "done" not in ls:
                    f.write(f"{s} 1\n")
        model = stormpy.build_model_from_explicit(tra, lab, state_rewards=rew)
        out = []
        for q in queries:
            prop = stormpy.parse_properties(q)
            result = stormpy.model_checking(model, prop[0])
            out.append(float(result.get_value(model.initial_states[0])))
        return out


def monte_carlo(
    mission: Mission, probs: dict[str, list[tuple[int, float]]], runs: int, seed: int, max_ticks: int = 10_000
) -> tuple[int, int, float]:
    """(root SUCCESS count, FAILURE count, mean ticks of the runs that ended) of `runs` interpreter runs."""
    rng = random.Random(seed)

    class _Draw:
        __slots__ = ("dist",)

        def __init__(self, dist: list[tuple[int, float]]) -> None:
            self.dist = dist

        def next(self) -> int:
            x = rng.random()
            for status, p in self.dist:
                x -= p
                if x < 0:
                    return status
            return self.dist[-1][0]

    succ = fail = 0
    total = 0
    for _ in range(runs):
        interp = Interpreter(mission, None)
        for node in interp.nodes:
            if isinstance(node, (iactions.ScriptedAction, iactions.ScriptedCondition)):
                node.cursor = _Draw(probs[node.name])
        for t in range(1, max_ticks + 1):
            code = STATUS[interp.tick_once().name]
            if code in (SUCCESS, FAILURE):
                succ += code == SUCCESS
                fail += code == FAILURE
                total += t
                break
    ended = succ + fail
    return succ, fail, total / ended if ended else math.inf


def markov_command(args, mission: Mission, program: Program, options) -> int:
    from btgen.tools.verify import props as P

    probs = load_probabilities(args.probabilities, program)
    names = P.Names(program)
    watched = tuple(names.resolve(n, Loc("<command-line>", 1, 1), 0) for n in args.ever)
    chain = build_chain(mission, program, probs, watched)
    queries = ['P=? [F "success"]', 'P=? [F "failure"]', 'R=? [F "done"]']
    if args.within is not None:
        queries.append(f'P=? [F<={args.within} "success"]')
    for i in watched:
        queries.append(f'P=? [F "ticked_{i}"]')
    values = storm_queries(chain, queries)
    print(f"{args.mission}: Markov chain of {len(chain.transitions)} states (Storm {_storm_version()})")
    labels = ["P(root SUCCESS)", "P(root FAILURE)", "expected ticks to the end"]
    if args.within is not None:
        labels.append(f"P(root SUCCESS within {args.within} ticks)")
    labels += [f"P({program.nodes[i].name} ever ticked)" for i in watched]
    for label, v in zip(labels, values):
        print(f"  {label:<40} {v:.10g}")
    sys.stdout.flush()
    return 0


def _storm_version() -> str:
    try:
        import stormpy

        return str(stormpy.__version__)
    except ImportError:  # pragma: no cover
        return "?"
