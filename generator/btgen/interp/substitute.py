"""The interpreter with substitution rules applied while the tree is built (`btgen run
--substitute`): a rule naming a TestNodeConfig makes the node a `TestNode`, a StatefulActionNode
that returns `return_status` at once, or after `async_delay` milliseconds of the run's virtual
clock (RUNNING until then), and on completion runs `success_script` or `failure_script`, then
`post_script`, on the node's blackboard. A rule naming another node ID builds that node instead:
a built-in leaf, or a scripted leaf of the mission (which takes its results from the scenario
under the node's own name). The node keeps its registration ID, name and UID in the trace, as
`setRegistrationID` keeps them.
"""

from __future__ import annotations

import sys
from typing import Callable, Optional

from btgen.diagnostics import Diagnostic, UserError
from btgen.interp import actions as iactions
from btgen.interp import engine as iengine
from btgen.interp.scenario import Scenario
from btgen.interp.tree import FAILURE, RUNNING, SUCCESS, TreeNode
from btgen.lang.catalogue import BUILTINS
from btgen.lang.model import Mission, Node, SubTreeNode
from btgen.lang.status import NodeStatus
from btgen.lang.substitution import Rule, Rules, TestConfig, check_leaf, match_index, node_path


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


class _SubstitutingBuilder(iengine._Builder):
    def __init__(self, rt, mission: Mission, rules: tuple[Rule, ...]) -> None:
        super().__init__(rt, mission)
        self.rules = rules if isinstance(rules, Rules) else Rules(rules)
        self.prefix = [""]
        self.used: set[int] = set()

    def _rule(self, model: Node, uid: int) -> Optional[Rule]:
        i = match_index(self.rules, model, node_path(self.prefix[-1], model, uid))
        if i is None:
            return None
        self.used.add(i)
        return self.rules[i]

    def _node(self, model: Node, bb) -> TreeNode:
        uid = self.rt.uid + 1
        rule = self._rule(model, uid)
        if rule is not None:
            check_leaf(rule, model, self.mission)
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
        print(f"{r.loc}: warning: the rule `{r.filter}` matches no node of the mission", file=sys.stderr)
    return iengine.run_ticks(interp, scenario, write)
