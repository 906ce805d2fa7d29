"""Substitution rules: BehaviorTree.CPP 4.x's JSON `TestNodeConfigs` and `SubstitutionRules`
(`BehaviorTreeFactory::loadSubstitutionRuleFromJSON`), for `btgen run --substitute FILE.json`.

    {
      "TestNodeConfigs": {
        "SlowOk": {"return_status": "SUCCESS", "async_delay": 2000,
                   "success_script": "done := true", "post_script": "calls += 1"}
      },
      "SubstitutionRules": {
        "Navigate": "SlowOk",           // by node name or registration ID
        "IV_VisitExhibit/*": "AlwaysFailure",  // by path, with * and ? wildcards
        "talk": "MyOtherAction"
      }
    }

A rule's filter matches a node when it equals the node's name or its registration ID, or when
it matches, as a wildcard pattern, the node's path (`SubTreePath/name`, a node without a name
attribute being `ID::UID`, as 4.6.2's `config.path`). The first rule that matches, in the
file's order, applies (BehaviorTree.CPP keeps the rules in an unordered map, so which of two
matching rules wins is not defined there). A rule naming a TestNodeConfig makes the node a
`TestNode`: a StatefulActionNode that returns `return_status` at once, or after `async_delay`
milliseconds of the run's virtual clock (RUNNING until then), and on completion runs
`success_script` or `failure_script`, then `post_script`, on the node's blackboard. A rule naming
another node ID builds that node instead: a built-in leaf, or a scripted leaf of the mission
(which takes its results from the scenario under the node's own name). The node keeps its
registration ID, name and UID in the trace, as `setRegistrationID` keeps them.

Only leaves are substituted: a rule that matches a Control, a Decorator or a SubTree is an
error (a TestNode cannot hold their children).
"""

from __future__ import annotations

import bisect
import functools
import itertools
import json
import re
from dataclasses import dataclass, field
from functools import cached_property
from typing import Callable, Optional

from btgen.diagnostics import Diagnostic, Loc, UserError
from btgen.fileio import read_json
from btgen.interp import actions as iactions
from btgen.interp import engine as iengine
from btgen.interp.scenario import Scenario
from btgen.interp.tree import FAILURE, RUNNING, SUCCESS, TreeNode
from btgen.lang import script as sc
from btgen.lang.catalogue import BUILTINS
from btgen.lang.model import Attr, Mission, Node, SubTreeNode
from btgen.lang.status import NodeStatus

MAX_RULES_BYTES = 1 << 20
_STATUS = {"SUCCESS": SUCCESS, "FAILURE": FAILURE, "RUNNING": RUNNING}


@dataclass(frozen=True)
class TestConfig:
    name: str
    return_status: int
    async_delay: int
    success_script: Optional[Attr]
    failure_script: Optional[Attr]
    post_script: Optional[Attr]
    grammar_49: bool = False


class Wildcard:
    """A filter as a wildcard pattern, compiled once: `*` any run of characters, `?` one,
    `\\` escapes the next (the library's wildcards::match). Matching takes time linear in the
    text for a given pattern (no backtracking): the pattern is cut at its stars into pieces of
    fixed length; the first must start the text, the last end it, and each other is found
    leftmost after the one before (a fixed-length piece found earlier never spoils a match)."""

    __slots__ = ("pieces", "literal", "prefix")

    def __init__(self, pattern: str) -> None:
        pieces: list[list[Optional[str]]] = [[]]
        i = 0
        while i < len(pattern):
            c = pattern[i]
            if c == "\\" and i + 1 < len(pattern):
                pieces[-1].append(pattern[i + 1])
                i += 2
                continue
            if c == "*":
                pieces.append([])
            else:
                pieces[-1].append(None if c == "?" else c)
            i += 1
        self.literal = not any(c in pattern for c in "*?\\")  # matches the text equal to it only
        # the characters every text it matches starts with (to index many patterns)
        self.prefix = "".join(c for c in itertools.takewhile(lambda c: c is not None, pieces[0]) if c is not None)
        # each piece: (length, its text when it has no `?`, else a regex of it); literal
        # pieces are found with str methods, and only pieces with `?` compile a regex
        self.pieces: list[tuple[int, Optional[str], Optional[re.Pattern[str]]]] = [
            (len(p), "".join(c for c in p if c is not None), None)
            if None not in p
            else (len(p), None, re.compile("".join("." if c is None else re.escape(c) for c in p), re.DOTALL))
            for p in pieces
        ]

    @staticmethod
    def _at(text: str, piece: tuple[int, Optional[str], Optional[re.Pattern[str]]], pos: int) -> bool:
        n, lit, rx = piece
        if lit is not None:
            return text.startswith(lit, pos)
        return rx is not None and rx.match(text, pos) is not None

    def match(self, text: str) -> bool:
        pieces = self.pieces
        n0 = pieces[0][0]
        if len(pieces) == 1:
            return len(text) == n0 and self._at(text, pieces[0], 0)
        nl = pieces[-1][0]
        if len(text) < n0 + nl or not self._at(text, pieces[0], 0) or not self._at(text, pieces[-1], len(text) - nl):
            return False
        pos, end = n0, len(text) - nl
        for n, lit, rx in pieces[1:-1]:
            if n == 0:
                continue
            if lit is not None:
                at = text.find(lit, pos, end)
                if at < 0:
                    return False
                pos = at + n
                continue
            m = rx.search(text, pos, end) if rx is not None else None
            if m is None:
                return False
            pos = m.end()
        return True


@dataclass(frozen=True)
class Rule:
    filter: str
    target: str  # a TestNodeConfig's name or a node ID
    loc: Loc
    config: Optional[TestConfig]
    pattern: Wildcard = field(init=False, compare=False, repr=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "pattern", Wildcard(self.filter))


class Rules(tuple):
    """The rules of a file, in its order, with their index (built once: a node is matched
    against a dict of the exact filters and the list of the wildcard ones)."""

    @cached_property
    def exact(self) -> dict[str, int]:
        out: dict[str, int] = {}
        for i, r in enumerate(self):
            out.setdefault(r.filter, i)
        return out

    @cached_property
    def literal(self) -> dict[str, int]:
        out: dict[str, int] = {}
        for i, r in enumerate(self):
            if r.pattern.literal:
                out.setdefault(r.filter, i)
        return out

    @cached_property
    def wild(self) -> list[int]:
        return [i for i, r in enumerate(self) if not r.pattern.literal]

    @cached_property
    def _trie(self) -> dict:
        """The wildcard rules by the literal prefix of their pattern (key None: the indexes
        of the rules whose prefix ends there)."""
        root: dict = {}
        for i in self.wild:
            node = root
            for c in self[i].pattern.prefix:
                node = node.setdefault(c, {})
            node.setdefault(None, []).append(i)
        return root

    def wild_candidates(self, path: str) -> list[int]:
        """The wildcard rules whose literal prefix starts `path`, in file order: the only ones
        that may match it (one walk down the path, not one try per rule)."""
        node: Optional[dict] = self._trie
        out: list[int] = []
        for c in itertools.chain((None,), path):
            if c is not None:
                node = node.get(c) if node is not None else None
            if node is None:
                break
            out.extend(node.get(None, ()))
        out.sort()
        return out


class _Obj(list):
    """A JSON object as its (key, value) pairs in file order (arrays stay plain lists)."""


@functools.lru_cache(maxsize=2)
def _line_starts(text: str) -> list[int]:
    return [0] + [m.end() for m in re.finditer("\n", text)]


def _loc_of(text: str, path: str, needle: str, start: int = 0) -> tuple[Loc, int]:
    """Where `needle` first is in `text` from `start` (a table of line starts: 20,000 rules
    cost 20,000 lookups, not 20,000 counts of the lines before each)."""
    at = text.find(needle, start)
    if at < 0:
        return Loc(path, 1, 1), start
    starts = _line_starts(text)
    line = bisect.bisect_right(starts, at)
    return Loc(path, line, at - starts[line - 1] + 1), at


def _plain(value):
    """A JSON value as Python's reader gives it without the pairs hook (objects as dicts)."""
    if isinstance(value, _Obj):
        return {k: _plain(v) for k, v in value}
    if isinstance(value, list):
        return [_plain(v) for v in value]
    return value


def _dumps(value) -> str:
    return json.dumps(_plain(value), ensure_ascii=False)


def load_rules(path: str, grammar_49: bool = False) -> Rules:
    """Read a substitution file; UserError with `path:line:col` for every problem found.
    Its scripts are parsed with the grammar of the selected release (`grammar_49`: the
    mission's `semantics.script_grammar_49`), as the same text in the mission would be."""
    doc, text = read_json(path, MAX_RULES_BYTES, "substitution", object_pairs_hook=_Obj)
    errors: list[Diagnostic] = []

    def err(loc: Loc, message: str) -> None:
        errors.append(Diagnostic(loc, message))

    top = dict(doc) if isinstance(doc, _Obj) else {}
    if not isinstance(doc, _Obj):
        raise UserError(Diagnostic(Loc(path, 1, 1), "the file must hold a JSON object"))
    configs: dict[str, TestConfig] = {}
    pos = 0
    raw_configs = top.get("TestNodeConfigs", [])
    if key_missing := "TestNodeConfigs" not in top:
        err(Loc(path, 1, 1), "the file has no `TestNodeConfigs` (BehaviorTree.CPP requires it: `{}` when empty)")
    if not isinstance(raw_configs, _Obj):
        if not key_missing:
            err(_loc_of(text, path, '"TestNodeConfigs"')[0], "`TestNodeConfigs` must be an object")
        raw_configs = []
    for name, body in raw_configs:
        loc, pos = _loc_of(text, path, _dumps(name), pos)
        if not isinstance(body, _Obj):
            err(loc, f"test node config `{name}` must be an object")
            continue
        fields = dict(body)
        for key in fields:
            if key not in ("return_status", "async_delay", "success_script", "failure_script", "post_script"):
                err(
                    _loc_of(text, path, _dumps(key), pos)[0],
                    f"unknown field `{key}` of `{name}`: use return_status, async_delay, success_script, "
                    "failure_script or post_script",
                )
        status = fields.get("return_status")
        if status is None:
            err(loc, f"test node config `{name}` has no `return_status` (BehaviorTree.CPP requires it)")
            continue
        if not isinstance(status, str) or status not in _STATUS:
            err(
                _loc_of(text, path, _dumps(status), pos)[0],
                f"`return_status` of `{name}` is {_dumps(status)}: use SUCCESS, FAILURE or RUNNING",
            )
            continue
        delay = fields.get("async_delay", 0)
        if not isinstance(delay, int) or isinstance(delay, bool) or not -(2**31) <= delay < 2**31:
            err(_loc_of(text, path, '"async_delay"', pos)[0], f"`async_delay` of `{name}` must be a whole number")
            continue
        scripts: dict[str, Optional[Attr]] = {}
        for key in ("success_script", "failure_script", "post_script"):
            code = fields.get(key)
            if code is None or code == "":
                scripts[key] = None
                continue
            kloc = _loc_of(text, path, _dumps(key), pos)[0]
            if not isinstance(code, str):
                err(kloc, f"`{key}` of `{name}` must be a string")
                continue
            vloc = _loc_of(text, path, _dumps(code), pos)[0]
            try:
                parsed = sc.parse_script(code, grammar_49)
            except sc.ScriptSyntaxError as e:
                err(vloc, f"`{key}` of `{name}`: {e.message}")
                continue
            scripts[key] = Attr(key, code, kloc, vloc, parsed)
        configs[name] = TestConfig(
            name,
            _STATUS[status],
            delay,
            scripts.get("success_script"),
            scripts.get("failure_script"),
            scripts.get("post_script"),
            grammar_49,
        )
    rules: list[Rule] = []
    raw_rules = top.get("SubstitutionRules", [])
    if key_missing := "SubstitutionRules" not in top:
        err(Loc(path, 1, 1), "the file has no `SubstitutionRules` (BehaviorTree.CPP requires it: `{}` when empty)")
    if not isinstance(raw_rules, _Obj):
        if not key_missing:
            err(_loc_of(text, path, '"SubstitutionRules"')[0], "`SubstitutionRules` must be an object")
        raw_rules = []
    rules_at = _loc_of(text, path, '"SubstitutionRules"')[1]
    pos = rules_at
    for filt, target in raw_rules:
        loc, pos = _loc_of(text, path, _dumps(filt), pos)
        if not isinstance(target, str):
            err(loc, f"the rule `{filt}` must name a test node config or a node ID")
            continue
        rules.append(Rule(filt, target, loc, configs.get(target)))
    if errors:
        raise UserError(errors)
    return Rules(rules)


def wildcard_match(text: str, pattern: str) -> bool:
    """`*` any run of characters, `?` one, `\\` escapes the next (the library's wildcards::match)."""
    return Wildcard(pattern).match(text)


class TestNode(iactions.StatefulActionNode):
    """4.6.2 ``TestNode`` on the virtual clock."""

    __slots__ = ("config", "deadline")

    def __init__(self, rt, model, bb, reg_id, ports, config: TestConfig) -> None:
        super().__init__(rt, model, bb, reg_id, ports)
        self.config = config
        self.deadline: Optional[int] = None

    def on_start(self) -> int:
        if self.config.async_delay <= 0:
            return self.completed()
        self.deadline = self.rt.now_ms + self.config.async_delay
        return RUNNING

    def on_running(self) -> int:
        if self.deadline is not None and self.rt.now_ms >= self.deadline:
            self.deadline = None
            return self.completed()
        return RUNNING

    def on_halted_action(self) -> None:
        self.deadline = None

    def completed(self) -> int:
        c = self.config
        status = c.return_status
        if status == SUCCESS and c.success_script is not None:
            self.run_script(c.success_script)
        elif status == FAILURE and c.failure_script is not None:
            self.run_script(c.failure_script)
        if c.post_script is not None:
            self.run_script(c.post_script)
        return status


def _path(prefix: str, node: Node, uid: int) -> str:
    name = node.name if node.name is not None else f"{node.id}::{uid}"
    return prefix + name


class _SubstitutingBuilder(iengine._Builder):
    def __init__(self, rt, mission: Mission, rules: tuple[Rule, ...]) -> None:
        super().__init__(rt, mission)
        self.rules = rules if isinstance(rules, Rules) else Rules(rules)
        self.prefix = [""]
        self.used: set[int] = set()

    def _rule(self, model: Node, uid: int) -> Optional[Rule]:
        i = _match_index(self.rules, model, _path(self.prefix[-1], model, uid))
        if i is None:
            return None
        self.used.add(i)
        return self.rules[i]

    def _node(self, model: Node, bb) -> TreeNode:
        uid = self.rt.uid + 1
        rule = self._rule(model, uid)
        if rule is not None:
            _check_leaf(rule, model, self.mission)
        if isinstance(model, SubTreeNode):
            name = model.name if model.name is not None else f"{model.target}::{uid}"
            self.prefix.append(f"{self.prefix[-1]}{name}/")
            try:
                return super()._node(model, bb)
            finally:
                self.prefix.pop()
        if rule is None:
            return super()._node(model, bb)
        ports = self._ports_of(model)
        self._create_entries(model, ports, bb)
        node: TreeNode
        if rule.config is not None:
            node = TestNode(self.rt, model, bb, model.id, ports, rule.config)
        elif rule.target in BUILTINS and rule.target in iengine._BUILTIN_FACTORIES:
            if BUILTINS[rule.target].kind not in ("Action", "Condition") or any(
                p.required for p in BUILTINS[rule.target].ports
            ):
                raise UserError(
                    Diagnostic(rule.loc, f"`{rule.target}` cannot stand for a leaf: use a leaf without required ports")
                )
            node = iengine._BUILTIN_FACTORIES[rule.target](self.rt, model, bb, model.id, ports)
        else:
            try:
                target = self.mission.spec(rule.target)
            except KeyError:
                raise UserError(
                    Diagnostic(
                        rule.loc,
                        f"substituted node ID `{rule.target}` is neither a test node config nor a node of the mission",
                    )
                ) from None
            if target.kind == "Condition":
                node = iactions.ScriptedCondition(self.rt, model, bb, model.id, ports)
            elif target.kind == "Action":
                node = iactions.ScriptedAction(self.rt, model, bb, model.id, ports)
            else:
                raise UserError(Diagnostic(rule.loc, f"`{rule.target}` is a {target.kind}, not a leaf"))
        self.nodes.append(node)
        return node


class SubstitutingInterpreter(iengine.Interpreter):
    """The interpreter with substitution rules applied while the tree is built."""

    def __init__(self, mission: Mission, scenario: Optional[Scenario], rules: tuple[Rule, ...]) -> None:
        self._rules = rules
        self._used: set[int] = set()
        super().__init__(mission, scenario)
        self.unused = [r for i, r in enumerate(rules) if i not in self._used]

    def _builder(self) -> iengine._Builder:
        builder = _SubstitutingBuilder(self.rt, self.mission, self._rules)
        self._used = builder.used  # filled as the tree is built
        return builder


def run_trace(
    mission: Mission, scenario: Scenario, rules: tuple[Rule, ...], write: Callable[[str], object]
) -> NodeStatus:
    """engine.run_trace with the substitution rules applied."""
    interp = SubstitutingInterpreter(mission, scenario, rules)
    for r in interp.unused:
        import sys

        print(f"{r.loc}: warning: the rule `{r.filter}` matches no node of the mission", file=sys.stderr)
    return iengine.run_ticks(interp, scenario, write)


# ====================================================================== compiled executor
# `btgen compile --substitute`: the substituted leaves become built-in nodes of the table that
# behave as the TestNode does (the trace keeps their ID and name, which the table holds apart
# from the kind): SUCCESS at once -> AlwaysSuccess, FAILURE at once -> AlwaysFailure, SUCCESS
# after async_delay -> Sleep (RUNNING until then, on the executor's clock), RUNNING -> a Sleep
# that never ends in practice (2^32-1 ms). The TestNode's scripts run before the node's own
# post-conditions, so they are prepended to them: `_onSuccess` becomes `success_script;
# post_script; <its _onSuccess>`, `_onFailure` likewise; `_post` is unchanged.
_FOREVER_MS = 2**32 - 1


def _instances(mission: Mission):
    """(index, model node, path) of the expanded main tree in creation order (ir.numbering)."""
    from btgen.ir.numbering import number_nodes

    numbering = number_nodes(mission)
    paths = numbering.instance_paths()
    for n in numbering:
        path = paths[n.instance]
        yield n.index, n.node, _path(path + "/" if path else "", n.node, n.uid)


def _match_index(rules: tuple[Rule, ...], node: Node, path: str) -> Optional[int]:
    """The index of the first rule that matches `node` at `path` (its name, its registration ID,
    or its path as a wildcard pattern), or None."""
    if not isinstance(rules, Rules):
        rules = Rules(rules)
    reg = "SubTree" if isinstance(node, SubTreeNode) else node.id
    best: Optional[int] = None
    for i in (rules.exact.get(node.display_name), rules.exact.get(reg), rules.literal.get(path)):
        if i is not None and (best is None or i < best):
            best = i
    for i in rules.wild_candidates(path):
        if best is not None and i > best:
            break
        if rules[i].pattern.match(path):
            return i
    return best


def _match(rules: tuple[Rule, ...], node: Node, path: str) -> Optional[Rule]:
    i = _match_index(rules, node, path)
    return None if i is None else rules[i]


def _check_leaf(rule: Rule, node: Node, mission: Mission) -> None:
    """Only leaves can be substituted (a TestNode cannot hold children): UserError otherwise."""
    kind = "SubTree" if isinstance(node, SubTreeNode) else mission.spec(node.id).kind
    if kind not in ("Action", "Condition"):
        raise UserError(
            Diagnostic(
                rule.loc,
                f'the rule `{rule.filter}` matches `{node.id}` "{node.display_name}" ({node.loc}), a '
                f"{kind}: only leaves can be substituted",
            )
        )
    if rule.config is not None or rule.target in BUILTINS:
        return
    try:
        target = mission.spec(rule.target)
    except KeyError:
        return  # (reported where the node is built)
    if target.kind in ("Action", "Condition") and target.kind != kind:
        # A scripted Action and a scripted Condition answer differently (RUNNING, what is taken
        # from the scenario when): both engines refuse the change rather than differ.
        raise UserError(
            Diagnostic(
                rule.loc,
                f'the rule `{rule.filter}` builds `{node.id}` "{node.display_name}" ({node.loc}), '
                f"{'an' if kind == 'Action' else 'a'} {kind}, as `{rule.target}`, a {target.kind}: a mission's "
                "own leaf can stand only for a leaf of its kind",
            )
        )


def _merged(node: Node, config: TestConfig) -> Node:
    from dataclasses import replace

    def join(name: str, first: list[Optional[Attr]]) -> Optional[Attr]:
        own = node.post_condition(name)
        parts = [a for a in first if a is not None] + ([own] if own is not None else [])
        if not parts:
            return None
        code = "; ".join(a.value for a in parts)
        where = parts[0]
        return Attr(name, code, where.loc, where.value_loc, sc.parse_script(code, config.grammar_49))

    on_success = join("_onSuccess", [config.success_script, config.post_script])
    on_failure = join("_onFailure", [config.failure_script, config.post_script])
    post = tuple(a for a in node.post if a.name not in ("_onSuccess", "_onFailure"))
    post += tuple(a for a in (on_success, on_failure) if a is not None)
    return replace(node, post=post)


def lower_substituted(mission: Mission, options, rules: tuple[Rule, ...]):
    """The lowered program of `mission` with the rules applied (UserError when a rule cannot
    be compiled: a FAILURE after a delay, a rule that matches some instances of a node only)."""
    from dataclasses import replace

    from btgen.ir.lower import lower

    rules = rules if isinstance(rules, Rules) else Rules(rules)
    decided: dict[int, Optional[Rule]] = {}
    per_index: dict[int, Rule] = {}
    models: dict[int, Node] = {}
    for index, node, path in _instances(mission):
        rule = _match(rules, node, path)
        if rule is not None:
            _check_leaf(rule, node, mission)
        if id(node) in decided and decided[id(node)] is not rule:
            raise UserError(
                Diagnostic(
                    (rule or decided[id(node)]).loc,  # type: ignore[union-attr]
                    f'`{node.id}` "{node.display_name}" ({node.loc}) is substituted in some SubTree instances '
                    "and not in others (or by different rules): `btgen compile --substitute` needs one rule "
                    "for all the instances of a node (`btgen run --substitute` takes any)",
                )
            )
        decided[id(node)] = rule
        models[id(node)] = node
        if rule is not None:
            per_index[index] = rule
            c = rule.config
            if c is not None and c.return_status == FAILURE and c.async_delay > 0:
                raise UserError(
                    Diagnostic(
                        rule.loc,
                        f"`{c.name}` fails after a delay: `btgen compile --substitute` has no such node yet "
                        "(`btgen run --substitute` runs it)",
                    )
                )
            if c is None and rule.target not in ("AlwaysSuccess", "AlwaysFailure"):
                try:
                    target = mission.spec(rule.target)
                except KeyError:
                    target = None
                if target is None or target.kind not in ("Action", "Condition") or target.builtin:
                    raise UserError(
                        Diagnostic(
                            rule.loc,
                            f"`btgen compile --substitute` substitutes test node configs, AlwaysSuccess, "
                            f"AlwaysFailure and the mission's own leaves, not `{rule.target}`",
                        )
                    )
    # the scripts, at the model level (dataflow types and compiles them with the node's own)
    replaced: dict[int, Node] = {}
    for key, rule in decided.items():
        if rule is not None and rule.config is not None:
            replaced[key] = _merged(models[key], rule.config)

    def rebuild(node: Node) -> Node:
        kids = tuple(rebuild(c) for c in node.children)
        new = replaced.get(id(node), node)
        return replace(new, children=kids) if kids != new.children else new

    trees = tuple(replace(t, root=rebuild(t.root)) for t in mission.trees)
    program = lower(replace(mission, trees=trees), options)
    model_index = {m.id: m.index for m in program.leaf_models}
    nodes = list(program.nodes)
    timers = program.timer_count
    for index, rule in per_index.items():
        n = nodes[index]
        c = rule.config
        if c is None:
            if rule.target in ("AlwaysSuccess", "AlwaysFailure"):
                nodes[index] = replace(n, kind=rule.target, model=-1)
            else:
                target = mission.spec(rule.target)
                nodes[index] = replace(n, kind=target.kind, model=model_index[rule.target])
        elif c.return_status == RUNNING or c.async_delay > 0:
            ms = _FOREVER_MS if c.return_status == RUNNING else c.async_delay
            nodes[index] = replace(n, kind="Sleep", model=-1, params=(ms, 0, 0), timer=timers)
            timers += 1
        else:
            nodes[index] = replace(n, kind="AlwaysSuccess" if c.return_status == SUCCESS else "AlwaysFailure", model=-1)
    return replace(program, nodes=tuple(nodes), timer_count=timers)
