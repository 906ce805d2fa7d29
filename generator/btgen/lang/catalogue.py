"""The built-in node catalogue of BehaviorTree.CPP 4.6.2, as data.

Every node that 4.6.2's ``BehaviorTreeFactory`` registers, with its kind,
the number of children it takes and its ports (direction, canonical type,
default). Validation, the XSD writer, the interpreter and the generator all
read this one table.

``required`` marks ports without a default that the node cannot work
without: 4.6.2 accepts a missing one when it loads the tree and fails (or
throws) when the node first runs; btgen rejects it when it checks the
mission.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

from btgen.diagnostics import Loc

KINDS = ("Action", "Condition", "Control", "Decorator", "SubTree")
DIRECTIONS = ("input", "output", "inout")


@dataclass(frozen=True)
class PortSpec:
    name: str
    direction: str  # "input" | "output" | "inout"
    type: str = "any"  # canonical type name, see values.normalize_type
    default: Optional[str] = None  # default as text, None when there is none
    required: bool = False
    description: str = ""
    loc: Optional[Loc] = None  # where a TreeNodesModel declares it
    # A model's default that does not convert to its type (documentation in a models file:
    # Nav2's `numeric_limits<double>::infinity()`): why it does not. `default` is then None:
    # a node leaving the port unset gets no default, as in BehaviorTree.CPP without one.
    default_problem: str = field(default="", compare=False)
    # An integer port declared with a width other than 32 bits (`uint16`, `int64_t`): its
    # spelling and range, which 4.6.2 checks the port's literals against (values.integer_range).
    int_width: Optional[tuple[str, int, int]] = field(default=None, compare=False)

    @property
    def reads(self) -> bool:
        return self.direction in ("input", "inout")

    @property
    def writes(self) -> bool:
        return self.direction in ("output", "inout")


@dataclass(frozen=True)
class NodeSpec:
    id: str
    kind: str  # one of KINDS
    ports: tuple[PortSpec, ...] = ()
    builtin: bool = True
    min_children: int = 0
    max_children: Optional[int] = 0  # None: no upper bound
    description: str = ""
    loc: Optional[Loc] = None  # where a TreeNodesModel declares it
    _index: dict = field(default=None, compare=False, hash=False, repr=False)  # type: ignore[arg-type]  # filled in __post_init__

    def __post_init__(self) -> None:
        object.__setattr__(self, "_index", {p.name: p for p in self.ports})

    def port(self, name: str) -> Optional[PortSpec]:
        return self._index.get(name)

    @property
    def port_names(self) -> tuple[str, ...]:
        return tuple(p.name for p in self.ports)

    @property
    def is_leaf(self) -> bool:
        return self.kind in ("Action", "Condition")

    def children_text(self) -> str:
        """Human description of the allowed child count."""
        lo, hi = self.min_children, self.max_children
        if hi == lo:
            return "no children" if lo == 0 else ("exactly 1 child" if lo == 1 else f"exactly {lo} children")
        if hi is None:
            return f"at least {lo} child" + ("" if lo == 1 else "ren")
        return f"{lo} or {hi} children" if hi == lo + 1 else f"{lo} to {hi} children"


def _in(
    name: str, type_: str = "any", default: Optional[str] = None, required: bool = False, description: str = ""
) -> PortSpec:
    return PortSpec(name, "input", type_, default, required, description)


def _out(name: str, type_: str = "any", description: str = "") -> PortSpec:
    return PortSpec(name, "output", type_, None, False, description)


def _inout(name: str, type_: str = "any", required: bool = False, description: str = "") -> PortSpec:
    return PortSpec(name, "inout", type_, None, required, description)


def _control(
    id_: str, ports: tuple[PortSpec, ...] = (), lo: int = 1, hi: Optional[int] = None, d: str = ""
) -> NodeSpec:
    return NodeSpec(id_, "Control", ports, True, lo, hi, d)


def _decorator(id_: str, ports: tuple[PortSpec, ...] = (), d: str = "") -> NodeSpec:
    return NodeSpec(id_, "Decorator", ports, True, 1, 1, d)


def _action(id_: str, ports: tuple[PortSpec, ...] = (), d: str = "") -> NodeSpec:
    return NodeSpec(id_, "Action", ports, True, 0, 0, d)


def _condition(id_: str, ports: tuple[PortSpec, ...] = (), d: str = "") -> NodeSpec:
    return NodeSpec(id_, "Condition", ports, True, 0, 0, d)


def _switch(n: int) -> NodeSpec:
    ports = (_in("variable", "string", required=True, description="value matched against the cases"),) + tuple(
        # 4.6.2 loads a Switch with a case_N missing; that case never matches (edges table, S1).
        _in(f"case_{i}", "string")
        for i in range(1, n + 1)
    )
    return NodeSpec(
        f"Switch{n}",
        "Control",
        ports,
        True,
        n + 1,
        n + 1,
        "ticks the child of the first case equal to `variable`, else the last (default) child",
    )


def _loop(id_: str, elem: str) -> NodeSpec:
    return _decorator(
        id_,
        (
            _inout("queue", f"queue<{elem}>", required=True, description="`;`-separated literal or a blackboard queue"),
            _in(
                "if_empty",
                "NodeStatus",
                "SUCCESS",
                description="status when the queue is empty: SUCCESS, FAILURE or SKIPPED",
            ),
            _out("value", elem, "the element popped for this run of the child"),
        ),
        "pops one element per run of its child",
    )


_BUILTINS: tuple[NodeSpec, ...] = (
    # -- controls
    _control("Sequence", d="ticks children in order; fails at the first failure"),
    _control("SequenceWithMemory", d="like Sequence, but keeps its place after a failure"),
    _control("AsyncSequence", d="like Sequence, but yields RUNNING after each synchronous success"),
    _control("ReactiveSequence", d="re-ticks every child from the first on every tick"),
    _control("Fallback", d="ticks children in order; succeeds at the first success"),
    _control("AsyncFallback", d="like Fallback, but yields RUNNING after each synchronous failure"),
    _control("ReactiveFallback", d="re-ticks every child from the first on every tick"),
    _control(
        "Parallel",
        (
            _in(
                "success_count",
                "int",
                "-1",
                description="successes needed; negative counts from the number of children",
            ),
            _in(
                "failure_count",
                "int",
                "1",
                description="failures that fail the node; negative counts from the number of children",
            ),
        ),
    ),
    _control(
        "ParallelAll",
        (
            _in(
                "max_failures",
                "int",
                "1",
                description="failures tolerated before failing; negative counts from the number of children",
            ),
        ),
    ),
    _control("IfThenElse", lo=2, hi=3, d="condition, then-branch, optional else-branch"),
    _control("WhileDoElse", lo=2, hi=3, d="condition re-checked each tick, do-branch, optional else-branch"),
    _switch(2),
    _switch(3),
    _switch(4),
    _switch(5),
    _switch(6),
    # -- decorators
    _decorator("Inverter"),
    _decorator("ForceSuccess"),
    _decorator("ForceFailure"),
    _decorator("KeepRunningUntilFailure"),
    _decorator("Repeat", (_in("num_cycles", "int", required=True, description="repetitions, -1 for ever"),)),
    _decorator(
        "RetryUntilSuccessful", (_in("num_attempts", "int", required=True, description="attempts, -1 for ever"),)
    ),
    _decorator(
        "RunOnce",
        (_in("then_skip", "bool", "true", description="SKIPPED after the first run instead of the stored status"),),
    ),
    _decorator(
        "Precondition",
        (
            _in("if", "string", required=True, description="script condition"),
            _in("else", "NodeStatus", "FAILURE", description="status returned when the condition is false"),
        ),
    ),
    _decorator("Timeout", (_in("msec", "unsigned", required=True, description="time limit in milliseconds"),)),
    _decorator(
        "Delay",
        (_in("delay_msec", "unsigned", required=True, description="delay in milliseconds before the child is ticked"),),
    ),
    _loop("LoopInt", "int"),
    _loop("LoopBool", "bool"),
    _loop("LoopDouble", "double"),
    _loop("LoopString", "string"),
    _decorator(
        "SkipUnlessUpdated", (_in("entry", "any", required=True, description="blackboard entry to watch, as {key}"),)
    ),
    _decorator(
        "WaitValueUpdate", (_in("entry", "any", required=True, description="blackboard entry to watch, as {key}"),)
    ),
    # -- leaves
    _action("AlwaysSuccess"),
    _action("AlwaysFailure"),
    _action("Script", (_in("code", "string", required=True, description="script to execute"),)),
    _condition(
        "ScriptCondition", (_in("code", "string", required=True, description="script whose result is the condition"),)
    ),
    _action(
        "SetBlackboard",
        (
            _in("value", "any", required=True, description="value to write: a literal or {key}"),
            _inout("output_key", "any", required=True, description="entry to write"),
        ),
    ),
    _action("UnsetBlackboard", (_in("key", "string", required=True, description="entry to remove"),)),
    _action("Sleep", (_in("msec", "unsigned", required=True, description="time to sleep in milliseconds"),)),
    _condition(
        "WasEntryUpdated", (_in("entry", "any", required=True, description="blackboard entry to check, as {key}"),)
    ),
    # -- SubTree: its ports are the remappings; checked separately
    NodeSpec("SubTree", "SubTree", (), True, 0, 0, "instance of another BehaviorTree"),
)

BUILTINS: dict[str, NodeSpec] = {n.id: n for n in _BUILTINS}

# Attributes with a fixed meaning on every node (not ports).
PRE_CONDITIONS = ("_failureIf", "_successIf", "_skipIf", "_while")
POST_CONDITIONS = ("_onHalted", "_onFailure", "_onSuccess", "_post")
SPECIAL_ATTRIBUTES = ("name", "ID") + PRE_CONDITIONS + POST_CONDITIONS
# Editor metadata on node elements: BehaviorTree.CPP's own XML writer adds `_uid` and
# `_fullpath` (WriteTreeToXML with metadata, as Groot2 receives a running tree) and Groot2
# keeps `_description`; 4.6.2's loader ignores them, and so does btgen.
# Built-in NodeStatus ports the library converts only when the node reads them (on a tick), not
# when it loads the file: a literal that is no NodeStatus loads, and the read throws.
STATUS_READ_WHEN_TICKED = frozenset(
    {("Precondition", "else"), ("LoopInt", "if_empty"), ("LoopBool", "if_empty")}
    | {("LoopDouble", "if_empty"), ("LoopString", "if_empty")}
)

METADATA_ATTRIBUTES = ("_uid", "_fullpath", "_description")
# What editors (Groot2, MoveIt Pro) write on node elements for themselves; 4.6.2 reads no
# attribute that does not start with a letter, and btgen ignores these without a word.
EDITOR_ATTRIBUTES = ("_collapsed", "_external", "_favorite", "_hardcoded")
# Names that a TreeNodesModel may not use for a port.
RESERVED_PORT_NAMES = frozenset(SPECIAL_ATTRIBUTES + ("_autoremap",) + METADATA_ATTRIBUTES)

# Ports whose literal value is a script.
SCRIPT_PORTS = {("Script", "code"), ("ScriptCondition", "code"), ("Precondition", "if")}
# Ports whose raw text names a blackboard entry, with or without braces
# (the node reads it with getRawPortValue, not getInput/setOutput).
ENTRY_PORTS = {("SkipUnlessUpdated", "entry"), ("WaitValueUpdate", "entry"), ("WasEntryUpdated", "entry")}
KEY_NAME_PORTS = ENTRY_PORTS | {("SetBlackboard", "output_key")}

# Children allowed per kind for user-declared nodes.
KIND_CHILDREN = {"Action": (0, 0), "Condition": (0, 0), "Control": (1, None), "Decorator": (1, 1), "SubTree": (0, 0)}


# ---------------------------------------------------------------- other versions
# What later releases register differently (lang/versions.py names each difference):
# TryCatch (4.9.0), and the Loop nodes' `queue` port, untyped from 4.9.1 so that a vector or
# a string may feed it.
TRYCATCH = NodeSpec(
    "TryCatch",
    "Control",
    (_in("catch_on_halt", "bool", "false", description="tick the catch child when halted in the try block"),),
    True,
    2,
    None,
    "children but the last run as a Sequence; on a failure the last (catch) child runs and the node fails",
)


def _untyped_queue(spec: NodeSpec) -> NodeSpec:
    ports = tuple(
        PortSpec(p.name, p.direction, "any", p.default, p.required, p.description) if p.name == "queue" else p
        for p in spec.ports
    )
    return NodeSpec(spec.id, spec.kind, ports, True, spec.min_children, spec.max_children, spec.description)


def _builtins_410() -> dict[str, NodeSpec]:
    out = dict(BUILTINS)
    for loop in ("LoopInt", "LoopBool", "LoopDouble", "LoopString"):
        out[loop] = _untyped_queue(BUILTINS[loop])
    out["TryCatch"] = TRYCATCH
    return out


_BUILTINS_BY_VERSION = {"4.6.2": BUILTINS, "4.10.0": _builtins_410()}


def builtins_for(version: str) -> dict[str, NodeSpec]:
    """The built-in nodes a version registers (BUILTINS is 4.6.2's); with Nav2's families of a
    distro: `lang.nav2.builtins_for`."""
    return _BUILTINS_BY_VERSION[version]
