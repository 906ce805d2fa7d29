"""The reference interpreter: runs a checked mission with BehaviorTree.CPP 4.6.2 semantics.

It builds one object per node, the way 4.6.2's ``XMLParser`` does (SubTrees
instantiated recursively, UIDs in creation order, one blackboard per tree
instance), and walks the tree with parents ticking and halting children as
4.6.2's node classes do. Every status change goes to an observer that writes
the trace lines of ``tests/conformance/FORMAT.md``.

Each node class follows one 4.6.2 source (named in its docstring); where
4.6.2 has a bug that later releases fixed and FORMAT.md says to follow the
later behaviour, the comment says so.

Leaves declared in TreeNodesModel take their results from a scenario: an
Action behaves as a ``StatefulActionNode`` (a result is taken in ``onStart``
and ``onRunning``), a Condition takes one every tick. Time (Sleep, Delay,
Timeout) comes from a virtual clock: 4.6.2's timer threads become deadlines
checked when the node is ticked, so a run never sleeps.

Statuses are kept as the small integers of ``NodeStatus`` (``.value``) inside
the hot paths and converted at the edges: a tick of a 10,000-node tree visits
every node, and an Enum hash per status change would cost seconds.

Nothing here is shared with the C++ back end: the interpreter walks the
model (lang/model.py) directly. The node classes live by family, as in
BehaviorTree.CPP's sources: ``tree.py`` (the TreeNode base, statuses, the run
context), ``controls.py``, ``decorators.py`` and ``actions.py``; this module
builds the tree from them and runs it.
"""

from __future__ import annotations

import sys
from typing import Callable, Optional

from btgen.diagnostics import UserError
from btgen.interp.actions import (
    AlwaysNode,
    ScriptConditionNode,
    ScriptedAction,
    ScriptedCondition,
    ScriptNode,
    SetBlackboardNode,
    SleepNode,
    UnsetBlackboardNode,
    WasEntryUpdatedNode,
)
from btgen.interp.controls import (
    ControlNode,
    FallbackNode,
    IfThenElseNode,
    ParallelAllNode,
    ParallelNode,
    ReactiveFallbackNode,
    ReactiveSequenceNode,
    SequenceNode,
    SequenceWithMemoryNode,
    SwitchNode,
    TryCatchNode,
    WhileDoElseNode,
)
from btgen.interp.decorators import (
    DecoratorNode,
    DelayNode,
    EntryUpdatedDecorator,
    ForceFailureNode,
    ForceSuccessNode,
    InverterNode,
    KeepRunningUntilFailureNode,
    LoopNode,
    PreconditionNode,
    RepeatNode,
    RetryNode,
    RunOnceNode,
    SubTreeRunNode,
    TimeoutNode,
)
from btgen.interp.nav2 import FACTORIES as NAV2_FACTORIES
from btgen.interp.scenario import Scenario
from btgen.interp.tree import _BY_VALUE, FAILURE, RUNNING, SKIPPED, SUCCESS, Runtime, TreeNode, _Port, _run_error
from btgen.lang import blackboard as bbmod
from btgen.lang import values
from btgen.lang.instance import instance_ports, subtree_remapping
from btgen.lang.leaves import is_scripted_leaf, leaf_kind, user_node_kind, user_node_message
from btgen.lang.model import Mission, Node, SubTreeNode
from btgen.lang.status import NodeStatus

# ================================================================ building the tree
_BUILTIN_FACTORIES = {
    "Sequence": lambda rt, m, bb, r, p: SequenceNode(rt, m, bb, r, p, False),
    "AsyncSequence": lambda rt, m, bb, r, p: SequenceNode(rt, m, bb, r, p, True),
    "SequenceWithMemory": SequenceWithMemoryNode,
    "ReactiveSequence": ReactiveSequenceNode,
    "Fallback": lambda rt, m, bb, r, p: FallbackNode(rt, m, bb, r, p, False),
    "AsyncFallback": lambda rt, m, bb, r, p: FallbackNode(rt, m, bb, r, p, True),
    "ReactiveFallback": ReactiveFallbackNode,
    "Parallel": ParallelNode,
    "ParallelAll": ParallelAllNode,
    "IfThenElse": IfThenElseNode,
    "WhileDoElse": WhileDoElseNode,
    "Switch2": lambda rt, m, bb, r, p: SwitchNode(rt, m, bb, r, p, 2),
    "Switch3": lambda rt, m, bb, r, p: SwitchNode(rt, m, bb, r, p, 3),
    "Switch4": lambda rt, m, bb, r, p: SwitchNode(rt, m, bb, r, p, 4),
    "Switch5": lambda rt, m, bb, r, p: SwitchNode(rt, m, bb, r, p, 5),
    "Switch6": lambda rt, m, bb, r, p: SwitchNode(rt, m, bb, r, p, 6),
    "Inverter": InverterNode,
    "ForceSuccess": ForceSuccessNode,
    "ForceFailure": ForceFailureNode,
    "KeepRunningUntilFailure": KeepRunningUntilFailureNode,
    "Repeat": RepeatNode,
    "RetryUntilSuccessful": RetryNode,
    "RunOnce": RunOnceNode,
    "Precondition": PreconditionNode,
    "Timeout": TimeoutNode,
    "Delay": DelayNode,
    "LoopInt": lambda rt, m, bb, r, p: LoopNode(rt, m, bb, r, p, "int"),
    "LoopBool": lambda rt, m, bb, r, p: LoopNode(rt, m, bb, r, p, "bool"),
    "LoopDouble": lambda rt, m, bb, r, p: LoopNode(rt, m, bb, r, p, "double"),
    "LoopString": lambda rt, m, bb, r, p: LoopNode(rt, m, bb, r, p, "string"),
    "SkipUnlessUpdated": lambda rt, m, bb, r, p: EntryUpdatedDecorator(rt, m, bb, r, p, SKIPPED),
    "WaitValueUpdate": lambda rt, m, bb, r, p: EntryUpdatedDecorator(rt, m, bb, r, p, RUNNING),
    "AlwaysSuccess": lambda rt, m, bb, r, p: AlwaysNode(rt, m, bb, r, p, SUCCESS),
    "AlwaysFailure": lambda rt, m, bb, r, p: AlwaysNode(rt, m, bb, r, p, FAILURE),
    "Script": ScriptNode,
    "ScriptCondition": ScriptConditionNode,
    "SetBlackboard": SetBlackboardNode,
    "UnsetBlackboard": UnsetBlackboardNode,
    "Sleep": SleepNode,
    "WasEntryUpdated": WasEntryUpdatedNode,
    "TryCatch": TryCatchNode,  # 4.9.0; only in the catalogue of versions that have it
    **NAV2_FACTORIES,  # only in the catalogue of a mission that selects Nav2's nodes (lang/nav2.py)
}


class _Builder:
    """Instantiates the main tree as 4.6.2's XMLParser::instantiateTree does."""

    def __init__(self, rt: Runtime, mission: Mission) -> None:
        self.rt = rt
        self.mission = mission
        self.trees = {t.id: t for t in mission.trees}
        self.nodes: list[TreeNode] = []

    def build(self, root_bb) -> TreeNode:
        return self._node(self.trees[self.mission.main_tree].root, root_bb)

    def _ports_of(self, model: Node) -> dict[str, _Port]:
        return {p.name: _Port(p.name, p.raw, p.attr, p.spec) for p in instance_ports(self.mission, model)}

    def _node(self, model: Node, bb) -> TreeNode:
        rt = self.rt
        node: TreeNode
        if isinstance(model, SubTreeNode):
            subtree = SubTreeRunNode(rt, model, bb, "SubTree", {})
            self.nodes.append(subtree)
            child_bb = self._subtree_blackboard(model, bb)
            subtree.child = self._node(self.trees[model.target].root, child_bb)
            return subtree
        ports = self._ports_of(model)
        self._create_entries(model, ports, bb)
        if model.id in _BUILTIN_FACTORIES and model.id in self.mission.builtins:
            factory = _BUILTIN_FACTORIES[model.id]
            node = factory(rt, model, bb, model.id, ports)
        elif is_scripted_leaf(self.mission, model):
            cls = ScriptedCondition if leaf_kind(self.mission, model) == "Condition" else ScriptedAction
            node = cls(rt, model, bb, model.id, ports)
        else:
            raise _run_error(model.loc, user_node_message(model.id, user_node_kind(self.mission, model) or "node"))
        self.nodes.append(node)
        kids = [self._node(c, bb) for c in model.children]
        if isinstance(node, ControlNode):
            node.children = kids
        elif isinstance(node, (DecoratorNode, EntryUpdatedDecorator)):
            if len(kids) != 1:
                raise _run_error(model.loc, f"`{model.id}` needs exactly one child")
            node.child = kids[0]
        elif kids:
            raise _run_error(model.loc, f"`{model.id}` takes no children")
        return node

    def _create_entries(self, model: Node, ports: dict[str, _Port], bb) -> None:
        """Load time: every {key} port creates its entry (with the port's type) when missing."""
        for p in ports.values():
            if p.attr is None:
                continue
            try:
                bbmod.create_port_entry(bb, p.raw, p.spec.type if p.spec is not None else "any", p.name, model.id)
            except (values.ConversionError, bbmod.BlackboardError) as e:
                raise _run_error(p.attr.value_loc, f"port `{p.name}` of `{model.id}`: {e}") from None

    def _subtree_blackboard(self, model: SubTreeNode, parent_bb):
        """recursivelyCreateSubtree: a child blackboard with the SubTree's remappings."""
        remap, missing = subtree_remapping(self.mission, model)
        if missing:
            raise _run_error(
                model.loc,
                f"SubTree `{model.target}` declares port `{missing[0]}` "
                f"without a default, and this instance does not remap it",
            )
        try:
            bb = bbmod.Blackboard.for_subtree(
                parent_bb,
                [(n, v) for n, v, _ in remap],
                model.autoremap,
                typed_literals=self.rt.sem.subtree_literals_typed,
            )
            provide(self.mission, bb, model.target, False)
            return bb
        except (values.ConversionError, bbmod.BlackboardError) as e:
            raise _run_error(model.loc, f"SubTree `{model.target}`: {e}") from None


# ================================================================ running
def expanded_depth(mission: Mission) -> int:
    """The depth of the main tree with its SubTrees expanded (a SubTree node counts as a level)."""
    trees = {t.id: t for t in mission.trees}
    memo: dict[str, int] = {}

    def tree_depth(tree_id: str) -> int:
        if tree_id in memo:
            return memo[tree_id]
        memo[tree_id] = 0  # the front end rejects recursive SubTrees; never loop here anyway
        best = 0
        stack = [(trees[tree_id].root, 1)]
        while stack:
            node, d = stack.pop()
            if isinstance(node, SubTreeNode):
                d += tree_depth(node.target) if node.target in trees else 0
            best = max(best, d)
            stack.extend((c, d + 1) for c in node.children)
        memo[tree_id] = best
        return best

    return tree_depth(mission.main_tree) if mission.main_tree in trees else 0


def provide(mission: Mission, bb, tree_id: str, root: bool) -> None:
    """The entries the application sets in this blackboard (--entry): created with their type
    and no value (a scenario run has no application to set them)."""
    for p in mission.provided:
        if p.applies_to(tree_id, root):
            bb.create_entry(p.key, p.type)


def _ensure_recursion_depth(depth: int) -> None:
    """Ticking and halting recurse about three Python frames per tree level; a tree nested deeper
    than the default limit allows gets a higher limit (Python 3.11+ keeps such frames off the C
    stack)."""
    needed = 4 * depth + 200
    if sys.getrecursionlimit() < needed:
        sys.setrecursionlimit(needed)


class Interpreter:
    """A mission instantiated for running: `tick_once()` is BehaviorTree.CPP's tickExactlyOnce."""

    def __init__(self, mission: Mission, scenario: Optional[Scenario] = None) -> None:
        self.mission = mission
        self.scenario = scenario
        _ensure_recursion_depth(expanded_depth(mission))
        self.rt = Runtime(mission, scenario)
        self.root_bb = bbmod.Blackboard(
            double_from_chars=mission.semantics.double_from_chars,
            false_into_int_unsafe=mission.semantics.false_into_int_unsafe,
        )
        provide(mission, self.root_bb, mission.main_tree, True)
        builder = self._builder()
        self.root = builder.build(self.root_bb)
        self.nodes = builder.nodes
        self.ticks_sent = 0

    def _builder(self) -> _Builder:
        """What builds the tree (interp/substitute.py gives its own)."""
        return _Builder(self.rt, self.mission)

    def take_text(self) -> str:
        """The trace lines produced since the last call, as text."""
        return self.rt.take_text()

    def take_lines(self) -> list[str]:
        """The trace lines produced since the last call."""
        return self.rt.take_text().splitlines()

    def advance_clock(self, ms: int) -> None:
        self.rt.now_ms += ms

    def tick_once(self) -> NodeStatus:
        """Tree::tickRoot(EXACTLY_ONCE): one executeTick of the root; a completed root is reset."""
        self.ticks_sent += 1
        status = self.root.execute_tick()
        if status in (SUCCESS, FAILURE):
            self.root.reset_status()
        return _BY_VALUE[status]


def run_trace(mission: Mission, scenario: Scenario, write: Callable[[str], object]) -> NodeStatus:
    """Run as FORMAT.md says and write the trace through `write` (one call per tick).

    Returns the last root status. A run-time error raises RunError after the
    lines of the failing tick so far have been written."""
    return run_ticks(Interpreter(mission, scenario), scenario, write)


def run_ticks(interp: Interpreter, scenario: Scenario, write: Callable[[str], object]) -> NodeStatus:
    """run_trace's ticks on a built interpreter (interp/substitute.py builds its own)."""
    last = NodeStatus.IDLE
    for n in range(1, scenario.ticks + 1):
        if n > 1 and scenario.clock_ms:
            interp.advance_clock(scenario.clock_ms)
        interp.rt.write_line(f"tick {n}")
        try:
            last = interp.tick_once()
        except UserError:
            write(interp.take_text())
            raise
        interp.rt.write_line(f"result {last.name}")
        write(interp.take_text())
        if last is NodeStatus.SUCCESS or last is NodeStatus.FAILURE:
            break
    return last


def trace_text(mission: Mission, scenario: Scenario) -> str:
    """The whole trace as one string (for tests and tools)."""
    parts: list[str] = []
    run_trace(mission, scenario, parts.append)
    return "".join(parts)
