"""Coverage criteria beyond nodes and outcomes: what `explore`, `tests` and `cover` share.

A criterion is a set of *obligations* (goals); a run of the interpreter *reaches* some of them.

    node       each node ticked                          ("node", uid)
    outcome    each status a node can return, returned   ("outcome", uid, status)
    halt       each node that can be RUNNING (the root   ("halt", uid)
               excepted: only the application halts it)
               halted while RUNNING (RUNNING -> IDLE)
    condition  each pre-condition (_failureIf,           ("pre", uid, attr, True|False)
               _successIf, _skipIf, _while) evaluated
               true and evaluated false; each
               post-condition decided each way:          ("post", uid, attr, True|False)
               _onSuccess and _onFailure run and not
               run (the node completed the other way),
               _post run after SUCCESS and after
               FAILURE, _onHalted run (halted while
               RUNNING) and not run (completed)
    mcdc       each operand of each `&&`/`||`            ("mcdc", uid, attr, site, operand)
               expression written in a script of the
               mission shown to decide the result on
               its own (masking MC/DC, below)

A pre- or post-condition obligation exists only where the library can decide it: a
post-condition's obligations follow the statuses `btgen analyze` finds possible for its node
(an `_onSuccess` of a node that never fails has no "not run" obligation).

MC/DC. BehaviorTree.CPP's scripts evaluate both operands of `&&` and `||` (no short circuit),
so every evaluation of an expression gives a full vector of operand values. A *site* is a
maximal `&&`/`||` expression of one script attribute of one node instance (a SubTree used
twice has two sites per expression); its operands are the subexpressions that are not
`&&`/`||` themselves (comparisons, names, `!x`, ...). Operand i of a site is shown when two
reached evaluations A and B differ in operand i and in the result, and in each of them
flipping operand i alone flips the result (operand i is not masked): *masking MC/DC*
(DO-178C's accepted form for coupled operands). When A and B differ in operand i only, the
pair is also *unique-cause*; `cover` says which form each shown operand has. Scripts read from
the blackboard at run time (`code="{entry}"`) have no site: their text is not known before.

How a run reaches the obligations: `node` and `outcome` by the explorer's hook on every
`execute_tick`; `halt` by each node's status changes (RUNNING -> IDLE); `pre` by a hook on
`TreeNode.truth` (the attribute is one of the node's pre-conditions); `post` follows from the
outcomes and halts (a node that returns SUCCESS ran its `_onSuccess`, BehaviorTree.CPP's
checkPostConditions); `mcdc` by a hook on the script evaluator that records each site's
operand values, as ("eval", uid, attr, site, values, result) goals. Traces and .btlog files
show status changes only: `node`, `outcome`, `halt` and `post` are measured on them directly,
`pre` and `mcdc` by replaying the run (a scenario file; a .btlog through `scenario-from-log`).
"""

from __future__ import annotations

import importlib
from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Callable, Optional

from btgen.interp.tree import FAILURE, RUNNING, SKIPPED, SUCCESS, TreeNode
from btgen.lang import values
from btgen.lang.script.format import format_expr
from btgen.lang.script.nodes import LOGIC_OPS, Binary, Expr, walk

# the evaluator's module (its package exports a function of the same name)
script_eval = importlib.import_module("btgen.lang.script.evaluate")

CRITERIA = ("node", "outcome", "halt", "condition", "mcdc")
DEFAULT = ("node", "outcome")
# the goal kinds each criterion holds
KINDS = {"node": ("node",), "outcome": ("outcome",), "halt": ("halt",), "condition": ("pre", "post"), "mcdc": ("mcdc",)}
PRE_KINDS = ("_failureIf", "_successIf", "_skipIf", "_while")
POST_KINDS = ("_onSuccess", "_onFailure", "_post", "_onHalted")
TITLES = {
    "node": "nodes",
    "outcome": "outcomes",
    "halt": "halts",
    "pre": "pre-conditions",
    "post": "post-conditions",
    "mcdc": "MC/DC",
}


def parse_criteria(text: str) -> tuple[str, ...]:
    """`node,outcome,halt,condition,mcdc` (any order, `all` for every one) -> the criteria in
    CRITERIA's order; ValueError with the reason."""
    from btgen.diagnostics import did_you_mean

    out: set[str] = set()
    for word in (w.strip() for w in text.split(",")):
        if word == "all":
            out.update(CRITERIA)
            continue
        if word not in CRITERIA:
            guess = did_you_mean(word, CRITERIA + ("all",)) if word else None
            hint = f" (did you mean `{guess}`?)" if guess else ""
            shown = f"`{word}`" if word else "an empty name"
            raise ValueError(f"{shown} is not a criterion{hint}: use {', '.join(CRITERIA)} or all")
        out.add(word)
    return tuple(c for c in CRITERIA if c in out)


def kinds_of(criteria: Iterable[str]) -> frozenset[str]:
    return frozenset(k for c in criteria for k in KINDS[c])


# ---------------------------------------------------------------- MC/DC sites
@dataclass
class Site:
    """One maximal `&&`/`||` expression of one script of one node instance."""

    uid: int
    attr: str
    index: int  # its place among the script's sites
    expr: Expr
    leaves: list[Expr]  # the operands, left to right
    text: list[str]  # each operand as written
    loc: object  # the attribute's value (a Loc)

    def value(self, vals: tuple[bool, ...]) -> bool:
        """The site's result for these operand values."""
        pos = {id(leaf): v for leaf, v in zip(self.leaves, vals)}

        def ev(e: Expr) -> bool:
            if id(e) in pos:
                return pos[id(e)]
            assert isinstance(e, Binary)
            a, b = ev(e.left), ev(e.right)
            return (a and b) if e.op == "&&" else (a or b)

        return ev(self.expr)


def _is_logic(e: Expr) -> bool:
    return isinstance(e, Binary) and e.op in LOGIC_OPS


def _sites_of(expr_roots: Iterable[Expr]) -> list[tuple[Expr, list[Expr]]]:
    found: list[tuple[Expr, list[Expr]]] = []
    inner: set[int] = set()
    for root in expr_roots:
        for e in walk(root):
            if not _is_logic(e) or id(e) in inner:
                continue
            leaves: list[Expr] = []
            stack = [e]
            while stack:
                n = stack.pop()
                if _is_logic(n):
                    inner.add(id(n))
                    assert isinstance(n, Binary)
                    stack.extend((n.right, n.left))
                else:
                    leaves.append(n)
            found.append((e, leaves))
    return found


def _operand_text(leaf: Expr) -> str:
    """An operand as text (fully parenthesized, the outer pair dropped), for messages."""
    text = format_expr(leaf)
    return text[1:-1] if text.startswith("(") and text.endswith(")") else text


def mcdc_pair(site: Site, operand: int, evals: set[tuple[tuple[bool, ...], bool]]):
    """(A, B, unique) showing the operand (masking MC/DC; unique-cause when A and B differ in
    it only), preferring a unique-cause pair; None when the reached evaluations show none."""
    best = None
    by_value: dict[bool, list[tuple[bool, ...]]] = {True: [], False: []}
    for vals, _ in evals:
        flipped = vals[:operand] + (not vals[operand],) + vals[operand + 1 :]
        if site.value(flipped) != site.value(vals):  # the operand decides it here (not masked)
            by_value[vals[operand]].append(vals)
    for a in sorted(by_value[True]):
        for b in sorted(by_value[False]):
            if site.value(a) == site.value(b):
                continue
            unique = all(x == y for k, (x, y) in enumerate(zip(a, b)) if k != operand)
            if unique:
                return a, b, True
            if best is None:
                best = (a, b, False)
    return best


# ---------------------------------------------------------------- the obligations of a mission
@dataclass
class Obligations:
    """The goals of the selected criteria for an interpreter's nodes (creation order), and the
    hooks that record what a run reaches."""

    kinds: frozenset[str]
    goals: set = field(default_factory=set)  # every goal but the MC/DC ones
    mcdc: list[tuple] = field(default_factory=list)  # ("mcdc", uid, attr, site, operand)
    sites: dict[tuple[int, str], list[Site]] = field(default_factory=dict)
    halt_uids: set[int] = field(default_factory=set)
    post: dict[tuple[int, int], list[tuple]] = field(default_factory=dict)  # (uid, status) -> post goals

    @property
    def all_goals(self) -> set:
        return self.goals | set(self.mcdc)

    def site(self, goal: tuple) -> Site:
        return self.sites[(goal[1], goal[2])][goal[3]]


def build(nodes: list[TreeNode], possible: Optional[dict[int, set[int]]], kinds: frozenset[str]) -> Obligations:
    """The obligations of `kinds` for these nodes; `possible` (index -> statuses) as the
    explorer has it (None: every status)."""
    ob = Obligations(kinds)
    for i, n in enumerate(nodes):
        can = possible.get(i, set()) if possible is not None else {SUCCESS, FAILURE, RUNNING}
        if possible is not None and not can:
            continue  # never ticked
        if "halt" in kinds and RUNNING in can and i > 0:
            ob.goals.add(("halt", n.uid))
        if "pre" in kinds:
            for kind, _ in n.pre:
                ob.goals.update({("pre", n.uid, kind, True), ("pre", n.uid, kind, False)})
        if "post" in kinds:
            wanted = []
            if n.on_success is not None:
                wanted += [("_onSuccess", True, SUCCESS), ("_onSuccess", False, FAILURE)]
            if n.on_failure is not None:
                wanted += [("_onFailure", True, FAILURE), ("_onFailure", False, SUCCESS)]
            if n.post_always is not None:
                wanted += [("_post", True, SUCCESS), ("_post", False, FAILURE)]
            if n.on_halted is not None:
                wanted += [("_onHalted", False, SUCCESS), ("_onHalted", False, FAILURE)]
                if RUNNING in can and i > 0:
                    ob.goals.add(("post", n.uid, "_onHalted", True))
            for kind, way, status in wanted:
                if status in can:
                    goal = ("post", n.uid, kind, way)
                    ob.goals.add(goal)
                    ob.post.setdefault((n.uid, status), []).append(goal)
        if "mcdc" in kinds:
            model = n.model
            for attr in (*model.ports, *model.pre, *model.post):
                script = attr.script
                if script is None or not hasattr(script, "statements"):
                    continue
                if attr.value.strip().startswith("{") and attr.value.strip().endswith("}"):
                    continue  # read from the blackboard at run time
                found = _sites_of(script.statements)
                if not found:
                    continue
                sites = ob.sites.setdefault((n.uid, attr.name), [])
                for expr, leaves in found:
                    site = Site(
                        n.uid,
                        attr.name,
                        len(sites),
                        expr,
                        leaves,
                        [_operand_text(leaf) for leaf in leaves],
                        attr.value_loc,
                    )
                    sites.append(site)
                    for k in range(len(leaves)):
                        ob.mcdc.append(("mcdc", n.uid, attr.name, site.index, k))
    ob.halt_uids = {g[1] for g in ob.goals if g[0] == "halt"} | {
        g[1] for g in ob.goals if g[0] == "post" and g[2] == "_onHalted" and g[3]
    }
    return ob


def derived(ob: Obligations, goals: Iterable[tuple]) -> set:
    """The post-condition goals that follow from outcomes and halts reached."""
    out: set = set()
    if "post" not in ob.kinds:
        return out
    for g in goals:
        if g[0] == "outcome":
            out.update(ob.post.get((g[1], g[2]), ()))
        elif g[0] == "halt":
            goal = ("post", g[1], "_onHalted", True)
            if goal in ob.goals:
                out.add(goal)
    return out


def evaluations(goals: Iterable[tuple]) -> dict[tuple[int, str, int], set]:
    """The MC/DC evaluations reached, by site: (uid, attr, site) -> {(values, result)}."""
    out: dict[tuple[int, str, int], set] = {}
    for g in goals:
        if g[0] == "eval":
            out.setdefault((g[1], g[2], g[3]), set()).add((g[4], g[5]))
    return out


def mcdc_shown(ob: Obligations, reached: Iterable[tuple]) -> dict[tuple, tuple]:
    """Each MC/DC obligation shown by the reached evaluations -> (A, B, unique)."""
    evals = evaluations(reached)
    out: dict[tuple, tuple] = {}
    for goal in ob.mcdc:
        got = evals.get((goal[1], goal[2], goal[3]))
        if not got:
            continue
        pair = mcdc_pair(ob.site(goal), goal[4], got)
        if pair is not None:
            out[goal] = pair
    return out


def eval_goal(site: Site, vals: tuple[bool, ...]) -> tuple:
    return ("eval", site.uid, site.attr, site.index, vals, site.value(vals))


# ---------------------------------------------------------------- hooks
class Hooks:
    """Class-level wrappers that add the goals a run reaches to `sink()` (a set, or None when
    no run is being recorded): pre-condition truths (TreeNode.truth) and MC/DC evaluations
    (TreeNode.run_script names the script, the evaluator records its operands). Halts are
    recorded by each node's `emit` (`halt_emit`)."""

    def __init__(self, ob: Obligations, sink: Callable[[], Optional[set]]) -> None:
        self.ob = ob
        self.sink = sink
        self.table: Optional[dict[int, tuple]] = None  # the running script's sites, by AST node id
        self.vals: dict[int, object] = {}
        self._tables: dict[tuple[int, str], dict[int, tuple]] = {}
        for key, sites in ob.sites.items():
            tab: dict[int, tuple] = {}
            for site in sites:
                tab[id(site.expr)] = ("root", site)
                for leaf in site.leaves:
                    tab[id(leaf)] = ("leaf", site)
            self._tables[key] = tab

    def install(self) -> Callable[[], None]:
        patched: list[tuple[type, str, object]] = []
        hooks = self
        if "pre" in self.ob.kinds:
            truth = TreeNode.truth

            def truth_hook(node, attr, parsed=None, from_blackboard=False):
                result = truth(node, attr, parsed, from_blackboard)
                sink = hooks.sink()
                if sink is not None:
                    for kind, a in node.pre:
                        if a is attr:
                            sink.add(("pre", node.uid, kind, result))
                return result

            patched.append((TreeNode, "truth", truth))
            TreeNode.truth = truth_hook  # type: ignore[method-assign]
        if "mcdc" in self.ob.kinds and self._tables:
            run_script = TreeNode.run_script
            ev = script_eval._Evaluator.eval

            def run_script_hook(node, attr, parsed=None, from_blackboard=False):
                tab = hooks._tables.get((node.uid, attr.name))
                if tab is None or hooks.sink() is None:
                    return run_script(node, attr, parsed, from_blackboard)
                outer = hooks.table
                hooks.table, hooks.vals = tab, {}
                try:
                    return run_script(node, attr, parsed, from_blackboard)
                finally:
                    hooks.table = outer

            def eval_hook(evaluator, expr):
                v = ev(evaluator, expr)
                tab = hooks.table
                if tab is not None:
                    hit = tab.get(id(expr))
                    if hit is not None:
                        if hit[0] == "leaf":
                            hooks.vals[id(expr)] = v
                        else:
                            site = hit[1]
                            vals = tuple(bool(values.cast(hooks.vals[id(x)], values.BOOL)) for x in site.leaves)
                            sink = hooks.sink()
                            if sink is not None:
                                sink.add(eval_goal(site, vals))
                return v

            patched.append((TreeNode, "run_script", run_script))
            patched.append((script_eval._Evaluator, "eval", ev))
            TreeNode.run_script = run_script_hook  # type: ignore[method-assign]
            script_eval._Evaluator.eval = eval_hook

        def restore() -> None:
            for cls, name, original in reversed(patched):
                setattr(cls, name, original)
            hooks.table = None

        return restore


def halt_emit(node: TreeNode, inner: Callable, sink: Callable[[], Optional[set]]) -> Callable:
    """An `emit` for `node` that records ("halt", uid) at RUNNING -> IDLE, then calls `inner`."""
    from btgen.interp.tree import _TRANS, IDLE

    halted = _TRANS[RUNNING][IDLE]
    goal = ("halt", node.uid)

    def emit(piece) -> None:
        if piece[1] == halted:
            s = sink()
            if s is not None:
                s.add(goal)
        inner(piece)

    return emit


# ---------------------------------------------------------------- words
def describe(goal: tuple, ob: Optional[Obligations] = None) -> str:
    """What a goal asks, in words (without the node)."""
    kind = goal[0]
    if kind == "node":
        return "ticked"
    if kind == "outcome":
        names = {RUNNING: "RUNNING", SUCCESS: "SUCCESS", FAILURE: "FAILURE", SKIPPED: "SKIPPED"}
        return f"returns {names.get(goal[2], goal[2])}"
    if kind == "input":  # a Nav2 Decorator's input of the environment (interp/nav2.py)
        return f"input {'yes' if goal[2] == SUCCESS else 'no'}"
    if kind == "halt":
        return "halted while RUNNING"
    if kind == "pre":
        return f"{goal[2]} evaluated {'true' if goal[3] else 'false'}"
    if kind == "post":
        attr, way = goal[2], goal[3]
        if attr == "_post":
            return f"_post run after {'SUCCESS' if way else 'FAILURE'}"
        if attr == "_onHalted":
            return "_onHalted run (halted while RUNNING)" if way else "_onHalted not run (completed)"
        return f"{attr} {'run' if way else 'not run (completed the other way)'}"
    if kind == "mcdc":
        text = ""
        if ob is not None:
            site = ob.site(goal)
            text = f" `{site.text[goal[4]]}`"
        return f"{goal[2]} operand {goal[4] + 1}{text} shown to decide its `&&`/`||` (site {goal[3] + 1})"
    return str(goal)


def criterion_of(goal: tuple) -> str:
    return {"pre": "condition", "post": "condition", "input": "outcome"}.get(goal[0], goal[0])
