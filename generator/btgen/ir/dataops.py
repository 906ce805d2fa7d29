"""The data side's operations as the IR holds them: what each data node and port does, decided.

dataflow.py resolves every key to a slot, types and sizes the slots, and
decides per node what its data operation is (which conversion, which check,
which error message at which place). The records below say that with no
C++ in them; backend_cpp turns each into statements (templates/_data.j2).
Slots are indices into DataIR.slots; places are indices into DataIR.where.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional, Union


@dataclass(frozen=True)
class Fail:
    """A run-time error: reported through the mission's error hook, then the operation gives up."""

    where: int  # index into DataIR.where
    message: str
    errc: bool = False  # the failed write's btgen::Errc description follows the message


# ------------------------------------------------------------ SetBlackboard, UnsetBlackboard


@dataclass(frozen=True)
class Unset:
    slot: Optional[int]  # None: not an entry of this blackboard (4.6.2 removes nothing)
    key: str


@dataclass(frozen=True)
class SetUserLiteral:
    """SetBlackboard of a user-typed entry: the literal, converted at construction, copied in."""

    slot: int
    literal: str  # the UserLiteral local holding it (LocalIR.member)
    fail: Fail  # it did not convert


@dataclass(frozen=True)
class DynSet410:
    """From 4.7.0, SetBlackboard into an entry whose type changes at run time and that no port
    declared (btgen::dyn::set_text_410 / set_copy_410): its run-time type (Slot::entry_type)
    decides whether a string is stored, left empty (untyped) or refused (BT::Any)."""

    local: bool  # stored on the node's own blackboard: an untyped entry becomes BT::Any
    raw: str  # the `value` port as written (the conversion message names it)
    entry_key: str  # the entry's key on the blackboard that holds it
    # a copy's source type, which a missing destination takes: "entry" (the source's
    # Slot::entry_type), "typed" (std::string) or "untyped"
    src_type: str = ""
    # a source a port declared int, double or bool: the btgen::DynTag a missing destination
    # is typed with ("kInt", "kDouble", "kBool"; "" otherwise)
    src_tag: str = ""


@dataclass(frozen=True)
class SetDynLiteral:
    """SetBlackboard of text into an entry whose type changes at run time."""

    slot: int
    text: str
    key: str
    prefix: str  # the message prefix of the run-time errors
    where: int
    v410: Optional[DynSet410] = None  # an entry no port declared, from 4.7.0


@dataclass(frozen=True)
class UntypedDst:
    """From 4.7.0, SetBlackboard of a string into an entry no port declared (a string slot
    declared `any`): what its run-time type (Slot::entry_type) makes of the write
    (btgen::set_string_410): stored (typed), left empty (untyped), or an error (BT::Any)."""

    local: bool  # stored on the node's own blackboard: an untyped entry becomes BT::Any
    src_type: str  # a copy's source: "dynamic" (its Slot::entry_type) or "typed" (declared)
    prefix: str  # the message when the entry is typed BT::Any, up to the value's text
    where: int  # the place that message names


@dataclass(frozen=True)
class SetText:
    """SetBlackboard of text into a typed (or string) entry: converted by its declared type."""

    slot: int
    declared: str  # values.py type name
    text: str
    fail: Fail
    untyped: Optional[UntypedDst] = None  # an entry no port declared, from 4.7.0


@dataclass(frozen=True)
class Throw:
    """A SetBlackboard the library throws at whenever it runs (text into a NodeStatus entry)."""

    fail: Fail


@dataclass(frozen=True)
class SetCopy:
    """SetBlackboard value="{src}" between entries of static types."""

    dst: int
    src: int
    how: str  # "convert" (text into a declared type), "string", "value", "none" (no value to copy)
    declared: str  # the declared type `convert` converts into
    missing: Fail  # the source does not exist
    fail: Optional[Fail]  # the conversion fails, or the text does not fit
    empty_succeeds: bool = True  # a source without value empties `dst` (4.6.2) or fails the node
    untyped: Optional[UntypedDst] = None  # a string into an entry no port declared, from 4.7.0


@dataclass(frozen=True)
class ShareQueue:
    """SetBlackboard value="{src}" of a queue entry: `dst` holds the same deque (QueuePool::share)."""

    dst: int
    src: int
    pool: str  # the LocalIR member of the pool
    missing: Fail  # the source does not exist
    empty_succeeds: bool = True  # a source without value empties `dst` (4.6.2) or fails the node


@dataclass(frozen=True)
class SetCopyDyn:
    """SetBlackboard value="{src}" where the destination's (or the source's) type changes at run time."""

    dst: int
    src: int
    src_is_string: bool  # the source is declared std::string (a dynamic source knows itself)
    key: str
    prefix: str
    missing: Fail
    where: int
    empty_succeeds: bool = True  # as SetCopy's
    v410: Optional[DynSet410] = None  # into an entry no port declared, from 4.7.0
    # a source a port declared int, double, bool or NodeStatus: the btgen::DynTag a missing
    # destination is typed with ("kInt", ...; "" otherwise)
    src_tag: str = ""


@dataclass(frozen=True)
class DebugEntry:
    """One line of Blackboard::debugMessage: an entry and its type's name (BT::demangle)."""

    slot: int
    key: str
    type_name: str  # "": the entry has no declared type; its Slot::entry_type tells the name
    typed_name: str = ""  # with type_name "": the name when entry_type is kTyped
    key_hash: int = 0  # std::hash of the key (lang/hashorder.py)
    runtime: bool = False  # a script creates it when it runs (Slot::born); else it exists from load on


@dataclass(frozen=True)
class SetCopyDynTyped410:
    """From 4.7.0, SetBlackboard value="{src}" from an entry whose type changes at run time
    (scripts and literals write it) into an entry a port declared int, unsigned, double or
    bool that exists from load on: Blackboard::set<BT::Any>. An empty source fails the node; a
    string goes through the entry's converter; another value must have the entry's type (a
    script's integer is an int64_t, never an int): else the library prints its blackboard
    (`debug`, in storage order) and throws (btgen::port::set_dyn_typed_410)."""

    dst: int
    src: int
    declared: str
    raw: str  # the `value` port as written (the conversion message names it)
    key: str  # the output_key as written
    prefix: str
    missing: Fail
    where: int
    debug: tuple[DebugEntry, ...]


@dataclass(frozen=True)
class SetKey:
    """SetBlackboard output_key="{key}": the text of string entry `slot` picks one of `cases`
    (each the operation of a SetBlackboard written with that output_key)."""

    slot: int
    missing: Fail  # the key's entry does not exist
    empty: Fail  # it has no value
    cases: tuple[tuple[str, DataLeafOp], ...]


DataLeafOp = Union[
    Unset, SetUserLiteral, SetDynLiteral, SetText, SetCopy, SetCopyDyn, SetCopyDynTyped410, SetKey, ShareQueue
]


# ------------------------------------------------------------ other data nodes


@dataclass(frozen=True)
class EntrySeq:
    """WasEntryUpdated, SkipUnlessUpdated, WaitValueUpdate: the update counter of the entry."""

    slot: int


@dataclass(frozen=True)
class TextOperand:
    """getInput<std::string> of a Switch's `variable` or a case: a literal, an entry, or not set."""

    slot: Optional[int] = None
    literal: Optional[str] = None


@dataclass(frozen=True)
class SwitchCases:
    cases: int
    variable: TextOperand
    labels: tuple[TextOperand, ...]


@dataclass(frozen=True)
class LoopPop:
    """LoopInt/Bool/Double/String: pop the queue's front into `value`."""

    elem: str  # int, bool, double, string
    local: str  # the literal queue's LocalIR.member ("" when the queue is an entry)
    items: tuple  # the literal queue's elements (values.py values)
    queue: Optional[int]  # the queue's slot
    no_value: Optional[Fail]  # the queue entry exists but has no value
    value: Optional[int]  # the slot `value` writes, if wired
    value_declared: str
    write_fail: Optional[Fail]
    # From 4.9.1 (loop_queue_untyped) an entry that holds no queue<elem>: "text" (a string or
    # dynamic slot: converted into `text_local`, a btgen::port::TextQueue, when the loop
    # starts), "none" (never a value), "scalar" (a number or status: an error whenever it runs)
    source: str = "queue"
    text_local: str = ""
    holds: str = ""  # the message when the entry holds something else, up to its value
    convert: str = ""  # the message prefix when the text does not convert
    where: int = 0  # the place both name


@dataclass(frozen=True)
class ParamRead:
    """Repeat num_cycles, RetryUntilSuccessful num_attempts, Timeout/Sleep msec, Delay delay_msec
    given as `{key}`: getInput<int> (durations: getInput<unsigned>) of an int, bool, double,
    string or dynamic entry (`kind`), read whenever the library's node calls getInput; a value
    that does not convert fails with `convert` (the message's start) and the reason. RunOnce
    then_skip (`as_bool`): the same entries as getInput<bool>; when that fails (no entry, no
    value, no conversion) RunOnce keeps its default, true, silently; TryCatch catch_on_halt
    alike, read when the node is halted, with its default, false (`bool_default`)."""

    slot: int
    missing: Fail  # the entry does not exist (UnsetBlackboard removed it)
    no_value: Fail  # it exists without a value
    constant: Optional[int] = None  # a SubTree's constant port (text nothing else writes), converted
    as_bool: str = ""  # RunOnce then_skip, TryCatch catch_on_halt: the entry's kind (int, bool, double, string, dyn)
    bool_default: int = 1  # as_bool: the value when getInput<bool> fails (the port's default)
    kind: str = ""  # a count or duration: the entry's kind (int, bool, double, string, dyn)
    unsigned: bool = False  # a duration (getInput<unsigned>)
    convert: Optional[Fail] = None  # "... reads blackboard entry `k`: " before the reason
    # Nav2's RateController hz: getInput<double> of the entry's kind into `out`'s bits, when the
    # node starts; when it fails Nav2 keeps its local 1.0, silently.
    as_double: str = ""
    # Precondition `else`, a Loop's `if_empty`: a literal that is no NodeStatus, which the
    # library loads and throws on whenever the node reads it (slot -1)
    always: Optional[Fail] = None
    # Precondition `else` as `{key}`: getInput<NodeStatus> of a NodeStatus entry, into `out`
    as_status: bool = False


@dataclass(frozen=True)
class ParallelRead:
    """Parallel `success_count` / `failure_count`, one of them or both given as `{key}`: the
    library reads both at the start of every tick (getInput<int>, throwing when it fails), then
    throws when the children cannot reach a threshold. Each is a ParamRead (a literal: its
    `constant`); `never_succeed` / `never_fail` start the messages of those throws."""

    success: ParamRead
    failure: ParamRead
    never_succeed: Fail
    never_fail: Fail


@dataclass(frozen=True)
class UserInit:
    """A user-typed literal converted when the mission is constructed (Spec::init)."""

    local: str  # LocalIR.member
    text: str
    fail: Fail


# ------------------------------------------------------------ ports of user leaves


@dataclass(frozen=True)
class ReadEntry:
    """getInput from an entry of a built-in kind; `text`: into the getter's number-text scratch."""

    slot: int
    text: bool


@dataclass(frozen=True)
class ReadLiteral:
    """A typed port's literal, converted now; `ok` false: it does not convert (kConversion)."""

    type_name: str
    value: object
    ok: bool = True


@dataclass(frozen=True)
class ParseLiteral:
    """An untyped port's literal, parsed as the T the caller asks for."""

    text: str


@dataclass(frozen=True)
class ReadUser:
    """A user-typed entry; `as_t`: through an untyped port (get<T>() with T the entry's type)."""

    slot: int
    as_t: bool = False


@dataclass(frozen=True)
class ReadUserLiteral:
    local: str  # the UserLiteral local


@dataclass(frozen=True)
class ReadQueue:
    """A queue port (BT::SharedQueue<T>) connected to a queue entry: a view of the entry's own queue."""

    slot: int


PortRead = Union[ReadEntry, ReadLiteral, ParseLiteral, ReadUser, ReadUserLiteral, ReadQueue]


@dataclass(frozen=True)
class WriteEntry:
    slot: int
    declared: str
    fail: Fail


@dataclass(frozen=True)
class WriteUser:
    """Into a user-typed entry; with `fail`: through an untyped setter, whose T must be the entry's."""

    slot: int
    user_cpp: str = ""
    fail: Optional[Fail] = None


@dataclass(frozen=True)
class WriteQueue:
    """setOutput of a new BT::SharedQueue<T> into a queue entry; `fail`: it does not fit the entry."""

    slot: int
    fail: Fail


PortWrite = Union[WriteEntry, WriteUser, WriteQueue]
