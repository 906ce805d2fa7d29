"""Substitution rules on the compiled executor (`btgen compile --substitute`, a test build):
the substituted leaves become built-in nodes of the node table that behave as the TestNode does
(the trace keeps their ID and name, which the table holds apart from the kind): SUCCESS at once
-> AlwaysSuccess, FAILURE at once -> AlwaysFailure, SUCCESS after async_delay -> Sleep (RUNNING
until then, on the executor's clock), RUNNING -> a Sleep that never ends in practice (2^32-1
ms). The TestNode's scripts run before the node's own post-conditions, so they are prepended to
them: `_onSuccess` becomes `success_script; post_script; <its _onSuccess>`, `_onFailure`
likewise; `_post` is unchanged.

Two steps around the one lowering (`pipeline.program` calls them): `prepare` checks the rules
and rewrites the model (the scripts), `apply` rewrites the lowered program's rows.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Optional

from btgen.diagnostics import Diagnostic, UserError
from btgen.ir.lower import Program
from btgen.lang import script as sc
from btgen.lang.model import Attr, Mission, Node
from btgen.lang.status import NodeStatus
from btgen.lang.substitution import Rule, Rules, TestConfig, check_leaf, match, node_path

SUCCESS = NodeStatus.SUCCESS.value
FAILURE = NodeStatus.FAILURE.value
RUNNING = NodeStatus.RUNNING.value
_FOREVER_MS = 2**32 - 1


def _instances(mission: Mission):
    """(index, model node, path) of the expanded main tree in creation order (ir.numbering)."""
    from btgen.ir.numbering import number_nodes

    numbering = number_nodes(mission)
    paths = numbering.instance_paths()
    for n in numbering:
        path = paths[n.instance]
        yield n.index, n.node, node_path(path + "/" if path else "", n.node, n.uid)


def _merged(node: Node, config: TestConfig) -> Node:
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


@dataclass(frozen=True)
class Plan:
    """What `prepare` decided: the mission to lower (scripts merged) and the rule of each
    substituted row of the node table."""

    mission: Mission
    per_index: dict[int, Rule]


def prepare(mission: Mission, rules: tuple[Rule, ...]) -> Plan:
    """The rules checked against the mission's instances (UserError when a rule cannot be
    compiled: a FAILURE after a delay, a rule that matches some instances of a node only) and
    the mission with the TestNodes' scripts merged into the nodes' post-conditions."""
    rules = rules if isinstance(rules, Rules) else Rules(rules)
    decided: dict[int, Optional[Rule]] = {}
    per_index: dict[int, Rule] = {}
    models: dict[int, Node] = {}
    for index, node, path in _instances(mission):
        rule = match(rules, node, path)
        if rule is not None:
            check_leaf(rule, node, mission)
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
    return Plan(replace(mission, trees=trees), per_index)


def apply(plan: Plan, program: Program) -> Program:
    """The lowered program of `plan.mission` with the substituted rows rewritten."""
    mission = plan.mission
    model_index = {m.id: m.index for m in program.leaf_models}
    nodes = list(program.nodes)
    timers = program.timer_count
    for index, rule in plan.per_index.items():
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
