"""The data side's output: DataIR, the records it holds, and the constants that define them."""

from __future__ import annotations

import enum
from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Optional

from btgen.diagnostics import Loc
from btgen.ir import dataops as ops
from btgen.ir.script_types import TypedScript
from btgen.lang import script as sc
from btgen.lang.kind import KindLike
from btgen.lang.model import Attr

DEFAULT_STRING_CAPACITY = 128
DEFAULT_QUEUE_CAPACITY = 16
# Growths of a string capacity before it is taken to grow without bound (see size_slots).
WIDEN_AFTER = 8


@dataclass(frozen=True)
class DataOptions:
    """Capacities the generator cannot compute: strings and queues written by robot code
    (or growing without bound) get these; no string of the mission is longer."""

    string_capacity: int = DEFAULT_STRING_CAPACITY
    queue_capacity: int = DEFAULT_QUEUE_CAPACITY


class ScriptSlot(enum.IntEnum):
    """The script places of a node (runtime/include/btgen/blackboard.hpp `ScriptSlot`): the
    value is the bit of NodeInfo::scripts (CODE, the node's own script, has no bit there)."""

    FAILURE_IF = 0
    SUCCESS_IF = 1
    SKIP_IF = 2
    WHILE = 3
    ON_SUCCESS = 4
    ON_FAILURE = 5
    POST = 6
    ON_HALTED = 7
    CODE = 8  # Script/ScriptCondition `code`, Precondition `if`


# The script place of each attribute holding a script.
SCRIPT_SLOTS = MappingProxyType(
    {
        "_failureIf": ScriptSlot.FAILURE_IF,
        "_successIf": ScriptSlot.SUCCESS_IF,
        "_skipIf": ScriptSlot.SKIP_IF,
        "_while": ScriptSlot.WHILE,
        "_onSuccess": ScriptSlot.ON_SUCCESS,
        "_onFailure": ScriptSlot.ON_FAILURE,
        "_post": ScriptSlot.POST,
        "_onHalted": ScriptSlot.ON_HALTED,
        "code": ScriptSlot.CODE,
        "if": ScriptSlot.CODE,
    }
)

# Built-in ports that take a literal only in the C++ back end (4.6.2 reads them on every tick).
# Ports read as `{key}` at run time: the engine reads the entry when 4.6.2's node calls getInput
# (every tick of Repeat, RetryUntilSuccessful, Timeout, Delay, RunOnce and Precondition, the start
# of a Sleep, the halt of a TryCatch).
PARAM_PORTS = frozenset(
    {
        ("Repeat", "num_cycles"),
        ("RetryUntilSuccessful", "num_attempts"),
        ("Timeout", "msec"),
        ("Delay", "delay_msec"),
        ("Sleep", "msec"),
        ("RunOnce", "then_skip"),
        ("TryCatch", "catch_on_halt"),
        ("RecoveryNode", "number_of_retries"),  # Nav2's: read on every tick
        ("PersistentSequence", "current_child_idx"),  # Nav2's: read on every tick (and written: IndexWrite)
        ("RateController", "hz"),  # Nav2's: a double, read when the node starts
        ("Precondition", "else"),  # getInput<NodeStatus> on every tick, before `if`
        ("Parallel", "success_count"),  # both read at the start of every tick (ParallelRead)
        ("Parallel", "failure_count"),
    }
)
# The bool ports among them, and what the node uses when getInput<bool> fails (the port's default).
BOOL_PARAM_DEFAULTS = MappingProxyType({"then_skip": 1, "catch_on_halt": 0})
LITERAL_ONLY = frozenset(
    {
        ("ParallelAll", "max_failures"),
        ("LoopInt", "if_empty"),
        ("LoopBool", "if_empty"),
        ("LoopDouble", "if_empty"),
        ("LoopString", "if_empty"),
        ("RoundRobin", "wrap_around"),  # Nav2's: read once, when the node is created
    }
)
# NodeInfo p2 bit of a Parallel whose thresholds are read from the blackboard (ParallelRead)
PARALLEL_READS = 2
LOOPS = MappingProxyType({"LoopInt": "int", "LoopBool": "bool", "LoopDouble": "double", "LoopString": "string"})
ENTRY_NODES = ("WasEntryUpdated", "SkipUnlessUpdated", "WaitValueUpdate")


# ================================================================ IR


@dataclass(frozen=True)
class SlotIR:
    """One blackboard entry of the mission: a member of the generated Blackboard struct (the
    back end names it from `owner` and `key`: backend_cpp/naming.py)."""

    index: int
    key: str  # its key on its blackboard
    owner: str  # "root" or the SubTree instance path
    declared: str  # declared type (values.py canonical name; `any` when none)
    kind: KindLike  # ir.kinds kind
    origin: str  # why it has its type, for the header comment (without the place)
    origin_loc: Optional[Loc]  # where that is
    capacity: int  # strings: bytes; queues: elements
    owner_uid: int = 0  # UID of the SubTree node whose blackboard holds it; 0: the root blackboard
    elem_capacity: int = 0  # queues of strings: bytes per element
    initial: Optional[str] = None  # a SubTree constant: the entry exists with this text from the start
    at_load: bool = False  # the entry exists from the start (a port created it when the tree loaded)
    user_cpp: str = ""  # a user port type's C++ spelling (--type)
    may_be_missing: bool = False  # the entry may not exist when a script runs
    origin_text: str = ""  # why it has its type, for messages
    provided: bool = False  # the application sets it before the first tick (--entry): it has a setter
    may_be_bt_any: bool = False  # typed BT::Any at load (bt_any_at_load), or by 4.7.0's SetBlackboard string
    bt_any_at_load: bool = False  # an `entry` port (InputPort<BT::Any>) created it at load: typed BT::Any
    pool: str = ""  # a queue entry sharing its deque (queue_share.py): the LocalIR of its QueuePool


@dataclass(frozen=True)
class ScriptIR:
    """A script of one node, typed (script_types.py): its expression tree over the slots it
    names, for backend_cpp/script_cpp/ to write as C++."""

    node: int
    comment: str
    which: ScriptSlot  # the script place it fills (SCRIPT_SLOTS)
    attr: Attr  # the attribute holding it: the places of its run-time errors (script_loc)
    script: sc.Script
    names: tuple[tuple[str, int], ...]  # name -> slot index
    condition: bool  # its last value is a condition's result
    prefix: str  # the prefix of its run-time error messages
    typed: TypedScript  # every expression's kind and how it is computed (script_types.py)


@dataclass(frozen=True)
class LocalIR:
    """Node-local storage in the Blackboard struct: the copy of a Loop's literal queue
    (`elem`, `length`, `elem_capacity`), a Loop's queue converted from a string entry
    (`text_capacity`), a user-typed literal (`user_cpp`), or the pool of queues of entries
    that SetBlackboard copies share (`pool`)."""

    member: str
    comment: str
    elem: str = ""  # int, bool, double, string
    length: int = 0
    elem_capacity: int = 0
    user_cpp: str = ""
    text_capacity: int = 0  # a Loop's queue converted from a string entry (from 4.9.1)
    pool: int = 0  # a btgen::QueuePool of this many queues (`elem`, `length`, `elem_capacity`)


@dataclass(frozen=True)
class DataOp:
    """The data operation of one node (a case of its dispatcher in the generated header)."""

    node: int
    comment: str
    op: object  # a record of ir/dataops.py


@dataclass(frozen=True)
class PortIR:
    """A port of a user leaf model: a typed getter and/or setter of the generated model class
    (the back end names them: backend_cpp/naming.py)."""

    port: str  # the port's name
    direction: str
    type_name: str
    description: str
    needs_scratch: bool  # a getter writes a number's text into a member of the model class
    reads: tuple[tuple[int, ops.PortRead], ...]  # (node index, what the getter returns there)
    writes: tuple[tuple[int, ops.PortWrite], ...]  # (node index, what the setter does there)
    user_cpp: str = ""  # a user port type (--type): its C++ spelling; the setter takes `const T&`
    # An integer port narrower than its 32-bit accessor (`uint16`, `int8_t`): the range a value
    # read from an entry must fit (4.6.2's getInput<T> fails outside it).
    int_range: Optional[tuple[int, int]] = None


@dataclass(frozen=True)
class DataIR:
    slots: tuple[SlotIR, ...]
    locals: tuple[LocalIR, ...]
    scripts: tuple[ScriptIR, ...]
    data_leaves: tuple[DataOp, ...]  # SetBlackboard, UnsetBlackboard
    entries: tuple[DataOp, ...]  # WasEntryUpdated & co.: EntrySeq
    switches: tuple[DataOp, ...]  # SwitchN: SwitchCases
    loops: tuple[DataOp, ...]  # LoopX: LoopPop
    ports: Mapping[str, tuple[PortIR, ...]]  # model id -> its ports' accessors
    script_bits: Mapping[int, int]  # node index -> NodeInfo::scripts bits
    params: Mapping[int, tuple[int, int, int]]  # node index -> (p0, p1, p2) for data nodes
    string_capacity: int
    queue_capacity: int
    where: tuple[Loc, ...]  # the places run-time errors name (Fail.where indexes them)
    enums: tuple[tuple[str, int], ...] = ()  # scripting enums: `detail::kScriptingEnums`
    user_types: tuple = ()  # the user port types (usertypes.UserType) the mission uses: headers, checks
    inits: tuple[DataOp, ...] = ()  # UserInit: user-typed literals, converted when the mission is constructed
    param_reads: tuple[DataOp, ...] = ()  # ParamRead: loop counts and durations given as `{key}`
    index_writes: tuple[DataOp, ...] = ()  # WriteEntry: Nav2's PersistentSequence writing its place

    @property
    def counts_births(self) -> bool:
        """Whether the generated code counts the entries created at run time (Blackboard::births_,
        Slot::born): only where a 4.10.0 SetBlackboard may print its blackboard with such entries
        in it (ops.SetCopyDynTyped410's debug entries), so other missions' state does not grow."""
        leaves = [d.op for d in self.data_leaves]
        leaves += [c for op in leaves if isinstance(op, ops.SetKey) for _, c in op.cases]
        return any(isinstance(op, ops.SetCopyDynTyped410) and any(e.runtime for e in op.debug) for op in leaves)


def script_loc(attr: Attr, offset: int) -> Loc:
    if offset <= 0:
        return attr.value_loc
    return sc.script_error_loc(attr.value_loc, attr.value, offset, sc.raw_attr_value(attr.value_loc))
