"""`btgen verify --probabilities FILE`: the mission as a discrete-time Markov chain, asked of Storm.

Each leaf answers with the probabilities the file gives, call by call, independently
(`{"Grasp": {"SUCCESS": 0.6, "FAILURE": 0.3, "RUNNING": 0.1}}`: a RUNNING answer with
probability p makes the Action's run last a geometric number of ticks). A state of the chain
is the state of the reference interpreter after a tick (explore's state key: every node's
status and members, the blackboard), found on explore's interpreter: each state's saved
snapshot is restored and ticked once per path of leaf answers (`build_chain`); one transition
is one tick, with the probability of the answers that lead there. The run ends in an absorbing
state when the root returns SUCCESS or FAILURE. Storm (stormpy) then computes

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
MAX_TICK_ANSWERS = 1_000  # leaf answers in one tick: past them a loop repeats within the tick
MAX_TICK_PATHS = 20_000  # paths of leaf answers through one tick
_TIMERS = ("Sleep", "Delay", "Timeout", "RateController")  # the nodes that read the clock


class _Branch(Exception):
    def __init__(self, name: str) -> None:
        self.name = name


class _Feed:
    """The leaves' answers of the tick being played: a leaf asked past them is a branch."""

    __slots__ = ("plan", "pos")

    def __init__(self) -> None:
        self.plan: tuple[int, ...] = ()
        self.pos = 0


class _Cursor:
    __slots__ = ("feed", "name")

    def __init__(self, feed: _Feed, name: str) -> None:
        self.feed = feed
        self.name = name

    def next(self) -> int:
        f = self.feed
        if f.pos < len(f.plan):
            v = f.plan[f.pos]
            f.pos += 1
            return v
        raise _Branch(self.name)


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
    """The chain, breadth first over the interpreter's states at tick ends. The interpreter is
    explore's (`Explorer`: one interpreter whose whole state is saved and restored, keyed as
    explore keys it): each state is expanded from its saved snapshot, one tick per path of
    leaf answers through it, so no run is replayed from the start."""
    from btgen.interp.nav2 import EnvInputDecorator
    from btgen.tools.explore import Explorer
    from btgen.tools.verify.replay import _Watch

    for n in program.nodes:
        if n.id in _TIMERS:
            raise UserError(Diagnostic(n.loc, f"`{n.id}` reads the clock: --probabilities does not translate it"))
    ex = Explorer(mission)
    interp = ex.interp
    feed = _Feed()
    for node in interp.nodes:
        if isinstance(node, (iactions.ScriptedAction, iactions.ScriptedCondition)):
            node.cursor = _Cursor(feed, node.name)
        elif isinstance(node, EnvInputDecorator):
            node.cursor = None  # its default, as an interpreter without a scenario answers
    # the counter of an endless loop (a literal -1) is never read: forgotten at each tick end,
    # so the states it alone tells apart are one (as in the Promela model); else the chain of
    # a mission with `num_attempts="-1"` grows by one state per attempt
    from_bb = set(program.data.params) if program.data is not None else set()
    endless = [
        (node, "count" if program.nodes[node.uid - 1].kind == "Repeat" else "tries")
        for node in interp.nodes
        if program.nodes[node.uid - 1].kind in ("Repeat", "RetryUntilSuccessful")
        and program.nodes[node.uid - 1].params[0] == -1
        and node.uid - 1 not in from_bb
    ]
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
    queue: deque[tuple[int, tuple]] = deque([(start, ex._save())])
    watch = _Watch(interp)
    try:
        while queue:
            sid, snapshot = queue.popleft()
            stack: list[tuple[tuple[int, ...], float]] = [((), 1.0)]
            paths = 0
            while stack:
                ext, p = stack.pop()
                paths += 1
                if len(ext) > MAX_TICK_ANSWERS or paths > MAX_TICK_PATHS:
                    raise _unbounded_tick(program, len(ext) > MAX_TICK_ANSWERS)
                ex._restore(snapshot)
                feed.plan, feed.pos = ext, 0
                watch.ticked.clear()
                watch.returned.clear()
                watch.inside.clear()
                try:
                    result = interp.tick_once()
                except _Branch as b:
                    for status, q in probs[b.name]:
                        stack.append((ext + (status,), p * q))
                    continue
                for node, counter in endless:
                    setattr(node, counter, 0)
                flags = frozenset(i for i in watched if i in watch.ticked)
                labels = {f"ticked_{i}" for i in flags}
                code = STATUS[result.name]
                if code in ends:
                    target, new = state(("end", code, flags), labels | {ends[code], "done"})
                    if new:
                        chain.transitions[target][target] = 1.0
                else:
                    target, new = state((ex.key_of_interpreter(interp), flags), labels)
                    if new:
                        if len(chain.transitions) > MAX_STATES:
                            raise UserError(
                                Diagnostic(program.nodes[0].loc, f"the Markov chain has more than {MAX_STATES} states")
                            )
                        queue.append((target, ex._save()))
                row = chain.transitions[sid]
                row[target] = row.get(target, 0.0) + p
    finally:
        watch.restore()
    return chain


def _unbounded_tick(program: Program, answers: bool) -> UserError:
    """A tick whose paths do not end: a loop that asks its child again within the tick, for ever
    (RetryUntilSuccessful or Repeat with -1) or very many times. Refused, located at the loop."""
    what = (
        f"more than {MAX_TICK_ANSWERS} leaf answers in one tick"
        if answers
        else f"more than {MAX_TICK_PATHS} paths of leaf answers through one tick"
    )
    loops = [n for n in program.nodes if n.kind in ("Repeat", "RetryUntilSuccessful") and n.params[0] < 0]
    if loops and answers:
        n = loops[0]
        port = "num_cycles" if n.kind == "Repeat" else "num_attempts"
        return UserError(
            Diagnostic(
                n.loc,
                f'`{n.kind}` "{n.name}" ({port}="-1") may tick its child again and again within one tick: {what}; '
                "--probabilities builds the chain tick by tick and does not translate a loop inside a tick",
            )
        )
    return UserError(
        Diagnostic(
            program.nodes[0].loc,
            f"{what}: --probabilities builds the chain tick by tick, one run per path; the mission is too wide",
        )
    )


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
