"""Lowering: the checked Mission -> a frozen IR of tables for the C++ back end.

The IR is what the generated code is made of: the node table in
BehaviorTree.CPP creation order (depth first, a SubTree node before the
nodes of its tree, so index + 1 is the node's UID), the child table, the
leaf models, and the capacities of the mission's state (counter slots,
timer slots, stack depth). Port literals are converted here, and the rules
BehaviorTree.CPP only enforces at run time (a Parallel threshold larger than
its children, an IfThenElse condition that can be SKIPPED) are rejected with
a `path:line:col` diagnostic.

The data side (blackboard entries, ports, scripts, pre/post conditions) is
resolved by dataflow.py; its DataIR travels in the Program.
"""

from __future__ import annotations

import struct
from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Optional

from btgen.diagnostics import Diagnostic, DiagnosticSink, InternalError, Loc
from btgen.ir.data.records import PARALLEL_READS, DataIR, DataOptions
from btgen.ir.dataflow import analyze
from btgen.ir.numbering import number_nodes
from btgen.ir.treexml import Groot2Tree, groot2_tree
from btgen.lang import values
from btgen.lang.model import Attr, Mission, Node, SubTreeNode
from btgen.lang.nav2 import builtins_for, round_robin_wraps_always

# Built-in node ID -> NodeKind enumerator of runtime/include/btgen/node.hpp,
# with the number of counter slots and timer slots its state needs.
SUPPORTED: Mapping[str, tuple[str, int, int]] = MappingProxyType(
    {
        "Sequence": ("Sequence", 2, 0),  # current child, "a child did not skip" (all_skipped_)
        "AsyncSequence": ("AsyncSequence", 2, 0),
        "SequenceWithMemory": ("SequenceWithMemory", 2, 0),
        "ReactiveSequence": ("ReactiveSequence", 0, 0),
        "Fallback": ("Fallback", 2, 0),
        "AsyncFallback": ("AsyncFallback", 2, 0),
        "ReactiveFallback": ("ReactiveFallback", 0, 0),
        "Parallel": ("Parallel", 2, 0),  # successes, failures
        "ParallelAll": ("ParallelAll", 1, 0),  # failures
        "IfThenElse": ("IfThenElse", 1, 0),  # branch being run
        "WhileDoElse": ("WhileDoElse", 0, 0),
        "Inverter": ("Inverter", 0, 0),
        "ForceSuccess": ("ForceSuccess", 0, 0),
        "ForceFailure": ("ForceFailure", 0, 0),
        "Repeat": ("Repeat", 2, 0),  # cycles done, "a child did not skip" (all_skipped_)
        "RetryUntilSuccessful": ("RetryUntilSuccessful", 2, 0),  # attempts done, as Repeat
        "KeepRunningUntilFailure": ("KeepRunningUntilFailure", 0, 0),
        "RunOnce": ("RunOnce", 2, 0),  # already ran, stored status
        "Timeout": ("Timeout", 2, 1),  # started, timer armed; start time
        "Delay": ("Delay", 1, 1),  # started; start time
        "SubTree": ("SubTree", 0, 0),
        "Switch2": ("Switch", 1, 0),  # the case RUNNING + 1 (0: none)
        "Switch3": ("Switch", 1, 0),
        "Switch4": ("Switch", 1, 0),
        "Switch5": ("Switch", 1, 0),
        "Switch6": ("Switch", 1, 0),
        "Precondition": ("Precondition", 1, 0),  # child started (4.7.0, versions.py precondition_if_until_started)
        "LoopInt": ("Loop", 1, 0),  # child RUNNING
        "LoopBool": ("Loop", 1, 0),
        "LoopDouble": ("Loop", 1, 0),
        "LoopString": ("Loop", 1, 0),
        "SkipUnlessUpdated": ("SkipUnlessUpdated", 1, 1),  # child RUNNING; update counter seen
        "WaitValueUpdate": ("WaitValueUpdate", 1, 1),
        "AlwaysSuccess": ("AlwaysSuccess", 0, 0),
        "AlwaysFailure": ("AlwaysFailure", 0, 0),
        "Sleep": ("Sleep", 0, 1),  # start time
        "Script": ("Script", 0, 0),
        "ScriptCondition": ("ScriptCondition", 0, 0),
        "SetBlackboard": ("SetBlackboard", 0, 0),
        "UnsetBlackboard": ("UnsetBlackboard", 0, 0),
        "WasEntryUpdated": ("WasEntryUpdated", 0, 1),  # update counter seen
        "TryCatch": ("TryCatch", 3, 0),  # current try child, skipped try children, in the catch child (4.9.0)
        # Nav2's (lang/nav2.py), built in when a mission selects them
        "PipelineSequence": ("PipelineSequence", 1, 0),  # furthest child RUNNING
        "RecoveryNode": ("RecoveryNode", 4, 0),  # child being run, recoveries done, `{key}` value, read
        "RoundRobin": ("RoundRobin", 2, 0),  # next child, failures in a row
        "NonblockingSequence": ("NonblockingSequence", 0, 0),
        "PersistentSequence": ("PersistentSequence", 0, 0),  # (its place lives in its entry)
        "RateController": ("RateController", 1, 2),  # first tick of a run; start of the period, hz in use
        "SingleTrigger": ("SingleTrigger", 1, 0),  # the child completed
        # Nav2's Decorators with an input of the environment (lang/nav2.py ENV_INPUTS)
        "DistanceController": ("DistanceController", 1, 0),  # the first tick of a run
        "SpeedController": ("SpeedController", 1, 0),  # the first tick of a run
        "GoalUpdatedController": ("GoalUpdatedController", 0, 0),
        "PathLongerOnApproach": ("PathLongerOnApproach", 1, 0),  # ticked before (Nav2's first_time_ over)
        "GoalUpdater": ("GoalUpdater", 0, 0),
    }
)
NAV2_INPUT_KINDS = frozenset({"DistanceController", "SpeedController", "GoalUpdatedController", "PathLongerOnApproach"})
# Nodes whose count or duration may be a `{key}` (data/records.py PARAM_PORTS): NodeInfo p1 is 1 then,
# and the node has one more counter slot, after those of SUPPORTED, holding the value read.
PARAM_NODES = ("Repeat", "RetryUntilSuccessful", "Timeout", "Delay", "Sleep")
_EVERY = frozenset(builtins_for("4.10.0", "lyrical"))  # (Nav2's newest families included)
assert set(SUPPORTED) == _EVERY, sorted(set(SUPPORTED) ^ _EVERY)


@dataclass(frozen=True)
class LeafModel:
    """An Action, Condition, Control or Decorator of TreeNodesModel: one set of hooks."""

    index: int
    id: str
    kind: str  # "Action" | "Condition" | "Control" | "Decorator"
    loc: Optional[Loc]


@dataclass(frozen=True)
class IRNode:
    index: int  # position in the table; uid - 1
    uid: int
    kind: str  # NodeKind enumerator
    id: str  # registration ID
    name: str  # name attribute, else the ID
    parent: int  # -1 for the root
    children: tuple[int, ...]
    child_begin: int  # offset of the children in Program.child_table
    depth: int  # root: 1
    params: tuple[int, int, int]
    slot: int  # first counter slot, -1 when none
    timer: int  # timer slot, -1 when none
    model: int  # leaf model index, -1 when not a user leaf
    loc: Loc
    tree: str  # the BehaviorTree the node is written in
    scripts: int = 0  # NodeInfo::scripts: pre/post conditions present (the bits of data/records.py ScriptSlot)


@dataclass(frozen=True)
class Program:
    """Everything emission needs, nothing it must compute."""

    mission_path: str
    files: tuple[str, ...]
    main_tree: str
    nodes: tuple[IRNode, ...]
    child_table: tuple[int, ...]
    leaf_models: tuple[LeafModel, ...]
    max_depth: int
    counter_count: int
    timer_count: int
    has_parallel: bool
    # (leaf name, BehaviorTree) of scripted leaves only in trees the main tree does not
    # run, for the scenario check's warning (scenario.check_scenario says the same).
    unrun_leaves: tuple[tuple[str, str], ...] = ()
    # The data side: blackboard slots, compiled scripts, port accessors (dataflow.py).
    data: Optional[DataIR] = None
    # The tree as BehaviorTree.CPP shows it to Groot2: XML with _uid, tree instances (treexml.py).
    groot2: Optional[Groot2Tree] = None
    # The BehaviorTree.CPP release followed (lang/versions.py): the header's Semantics flags.
    btcpp: str = "4.6.2"
    # Every user model the mission declares (used or not), in declaration order: the back end
    # names the leaf classes over all of them.
    model_ids: tuple[str, ...] = ()
    # What the library meets only when a node runs (both engines throw there): said, not refused
    # (`btgen check` reports them at their rule's level).
    warnings: tuple[Diagnostic, ...] = ()

    @property
    def actions(self) -> tuple[LeafModel, ...]:
        return tuple(m for m in self.leaf_models if m.kind == "Action")

    @property
    def conditions(self) -> tuple[LeafModel, ...]:
        return tuple(m for m in self.leaf_models if m.kind == "Condition")

    @property
    def user_nodes(self) -> tuple[LeafModel, ...]:
        """The mission's own Controls and Decorators."""
        return tuple(m for m in self.leaf_models if m.kind in ("Control", "Decorator"))

    @property
    def nav2_inputs(self) -> bool:
        """A node asks Leaves for an input of the environment (btgen/nav2.hpp)."""
        return any(n.kind in NAV2_INPUT_KINDS for n in self.nodes)

    @property
    def used_user_nodes(self) -> tuple[LeafModel, ...]:
        """The mission's own Controls and Decorators that a node of the main tree is: the
        engine dispatches to these only, so leaves without a tick() for a model no node
        uses (a models file declaring every Control of a project) still compile."""
        used = {n.model for n in self.nodes}
        return tuple(m for m in self.user_nodes if m.index in used)


# ------------------------------------------------------------------ traversal
def creation_order(mission: Mission) -> list[tuple[int, str, str]]:
    """(UID, registration ID, name) of every node of the main tree, SubTrees inlined:
    the numbers BehaviorTree.CPP (and Groot2) give them. Works on any mission,
    including those the C++ back end cannot compile yet."""
    return [(n.uid, n.reg_id, n.node.display_name) for n in number_nodes(mission)]


def _unrun_leaves(mission: Mission) -> tuple[tuple[str, str], ...]:
    """Scripted leaf names the main tree does not run, each with the first tree (in file
    order) that has one: what scenario.check_scenario names in its warning."""
    from btgen.lang.leaves import is_scripted_leaf, mission_leaves

    run = {u.name for u in mission_leaves(mission)}
    found: dict[str, str] = {}
    for tree in mission.trees:
        stack = [tree.root]
        while stack:
            node = stack.pop()
            if is_scripted_leaf(mission, node) and node.display_name not in run:
                found.setdefault(node.display_name, tree.id)
            stack.extend(reversed(node.children))
    return tuple(found.items())


# ------------------------------------------------------------------- lowering
class _Lowerer:
    def __init__(self, mission: Mission, options: DataOptions) -> None:
        self.m = mission
        self.options = options
        self.sink = DiagnosticSink()
        self.reported: set[tuple[Loc, str]] = set()

    def error(self, loc: Loc, message: str) -> None:
        if (loc, message) not in self.reported:
            self.reported.add((loc, message))
            self.sink.error(loc, message)

    def literal(self, node: Node, port_name: str, type_name: str) -> tuple[object, Loc]:
        attr: Optional[Attr] = node.port(port_name)
        if attr is not None:
            text, loc = attr.value, attr.value_loc
        else:
            default = self.m.builtins[node.id].port(port_name)
            if default is None or default.default is None:
                raise InternalError(f"{node.loc}: `{node.id}` has no `{port_name}` and no default")
            text, loc = default.default, node.loc
        try:
            return values.convert_from_string(
                type_name, text, double_from_chars=self.m.semantics.double_from_chars
            ), loc
        except values.ConversionError as e:
            if self.sink.errors:  # `{key}` where the C++ back end needs a literal: reported by dataflow
                return 0, loc
            raise InternalError(f"{loc}: port `{port_name}`: {e}") from None

    def int_literal(self, node: Node, port_name: str, type_name: str = "int") -> tuple[int, Loc]:
        """An `int`/`unsigned` port's literal (0 when it is a `{key}` that dataflow reported)."""
        value, loc = self.literal(node, port_name, type_name)
        if not isinstance(value, int) or isinstance(value, bool):
            raise InternalError(f"{loc}: port `{port_name}` converted to {value!r}, not an int")
        return value, loc

    def params(self, node: Node, n_children: int) -> tuple[int, int, int]:
        if isinstance(node, SubTreeNode) or node.id not in self.m.builtins:
            # A tree, or a node the program registers, named like a built-in of another
            # version (`TryCatch` under 4.6.2): no built-in's parameters.
            return 0, 0, 0
        nid = node.id
        if nid == "Parallel":
            succ, sloc = self.int_literal(node, "success_count")
            fail, floc = self.int_literal(node, "failure_count")
            need_s = max(n_children + succ + 1, 0) if succ < 0 else succ
            need_f = max(n_children + fail + 1, 0) if fail < 0 else fail
            if n_children < need_s:
                self.error(
                    sloc,
                    f'`Parallel` "{node.display_name}" has {n_children} children but needs '
                    f"{need_s} successes (success_count={succ}): it can never succeed "
                    f"(BehaviorTree.CPP throws when it is ticked)",
                )
            if n_children < need_f:
                self.error(
                    floc,
                    f'`Parallel` "{node.display_name}" has {n_children} children but fails after '
                    f"{need_f} failures (failure_count={fail}): it can never fail that way "
                    f"(BehaviorTree.CPP throws when it is ticked)",
                )
            return need_s, need_f, 1 if succ < 0 else 0
        if nid == "ParallelAll":
            mf, loc = self.int_literal(node, "max_failures")
            need = max(n_children + mf + 1, 0) if mf < 0 else mf
            if n_children < need:
                self.error(
                    loc,
                    f'`ParallelAll` "{node.display_name}" has {n_children} children but '
                    f"max_failures={mf}: it can never fail (BehaviorTree.CPP throws when it is ticked)",
                )
            return need, 0, 0
        if nid == "Repeat":
            return self.int_literal(node, "num_cycles")[0], 0, 0
        if nid == "RetryUntilSuccessful":
            return self.int_literal(node, "num_attempts")[0], 0, 0
        if nid == "RunOnce":
            return (1 if self.literal(node, "then_skip", "bool")[0] else 0), 0, 0
        if nid in ("Timeout", "Sleep"):
            return self.int_literal(node, "msec", "unsigned")[0], 0, 0
        if nid == "Delay":
            return self.int_literal(node, "delay_msec", "unsigned")[0], 0, 0
        if nid == "RecoveryNode":
            return self.int_literal(node, "number_of_retries")[0], 0, 0
        if nid == "RoundRobin":
            if self.m.nav2 is None or round_robin_wraps_always(self.m.nav2):
                return 1, 0, 0
            return (1 if self.literal(node, "wrap_around", "bool")[0] else 0), 0, 0
        if nid == "PersistentSequence":
            return self.int_literal(node, "current_child_idx")[0], 0, 0
        if nid == "RateController":
            hz, _ = self.literal(node, "hz", "double")
            bits = struct.unpack("<q", struct.pack("<d", float(hz)))[0]  # type: ignore[arg-type]
            return bits, 0, 0
        if nid == "TryCatch":
            # catch_on_halt: p0 the literal (read when the node is halted); p1 1 when it is a
            # `{key}` (data.params), read then through Spec::read_param.
            return (1 if self.literal(node, "catch_on_halt", "bool")[0] else 0), 0, 0
        return 0, 0, 0

    def lower(self) -> Program:
        m = self.m
        numbering = number_nodes(m)
        data, data_sink = analyze(m, self.options, numbering)
        for d in data_sink.items:
            if d.severity == "error":
                self.error(d.loc, d.message)
        warnings = tuple(d for d in data_sink.items if d.severity == "warning")
        for d in warnings:  # (said with the errors too, when there are any)
            self.sink.warning(d.loc, d.message)

        # Only the models a node of the mission uses get a leaf class, dispatch branches and
        # hooks: a palette of 600 unused Actions cost g++ minutes (the back end names classes
        # over the whole palette, `model_ids`, so a model's class keeps its name whatever else
        # is used).
        models = m.used_user_models()
        leaf_models = tuple(LeafModel(i, s.id, s.kind, s.loc) for i, s in enumerate(models))
        model_index = {s.id: i for i, s in enumerate(models)}

        nodes: list[IRNode] = []
        child_table: list[int] = []
        counter = timer = 0
        for n in numbering:
            node, index = n.node, n.index
            if isinstance(node, SubTreeNode):
                kind, nslots, ntimers, model = "SubTree", 0, 0, -1
            elif node.id in SUPPORTED and node.id in m.builtins:
                kind, nslots, ntimers = SUPPORTED[node.id]
                model = -1
                if data.params.get(index, (0, 0, 0))[1] == 1 and node.id in PARAM_NODES:
                    nslots += 1  # the count or duration read from the blackboard (engine.hpp: param_value)
                if node.id == "Parallel" and data.params.get(index, (0, 0, 0))[2] & PARALLEL_READS:
                    nslots += 3  # the thresholds read this tick, and success_count's sign (rules.hpp)
            elif node.id in model_index:
                kind, nslots, ntimers = leaf_models[model_index[node.id]].kind, 0, 0
                kind = {"Control": "UserControl", "Decorator": "UserDecorator"}.get(kind, kind)
                model = model_index[node.id]
            else:
                raise InternalError(f"{node.loc}: no lowering for node `{node.id}`")
            if index + 1 > 0xFFFF:  # UIDs are 16-bit; index 0xFFFF is kNoNode, so at most 65535 nodes
                raise InternalError("more nodes than the front end allows")
            params = data.params.get(index) or self.params(node, len(n.children))
            nodes.append(
                IRNode(
                    index,
                    n.uid,
                    kind,
                    n.reg_id,
                    node.display_name,
                    n.parent,
                    n.children,
                    len(child_table),
                    n.depth,
                    params,
                    counter if nslots else -1,
                    timer if ntimers else -1,
                    model,
                    node.loc,
                    n.tree,
                    data.script_bits.get(index, 0),
                )
            )
            child_table.extend(n.children)
            counter += nslots
            timer += ntimers
        self.sink.raise_if_errors()
        return Program(
            m.path,
            m.files,
            m.main_tree,
            tuple(nodes),
            tuple(child_table),
            leaf_models,
            max(n.depth for n in nodes),
            counter,
            timer,
            any(n.kind in ("Parallel", "ParallelAll") for n in nodes),
            _unrun_leaves(m),
            data,
            groot2_tree(m, numbering),
            m.btcpp,
            tuple(s.id for s in m.user_models()),
            warnings,
        )


def lower(mission: Mission, options: Optional[DataOptions] = None) -> Program:
    """Lower a checked mission; UserError with every reason it cannot be compiled."""
    return _Lowerer(mission, options or DataOptions()).lower()
