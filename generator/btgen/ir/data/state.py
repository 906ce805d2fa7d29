"""The working records of the data analysis: node instances, slots and their writes, and
what each node does with data (one frozen record per use, found by resolve.py)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Optional, Union

from btgen.diagnostics import Loc
from btgen.ir import dataops as ops
from btgen.lang import blackboard as bbmod
from btgen.lang.catalogue import NodeSpec, PortSpec
from btgen.lang.instance import instance_ports
from btgen.lang.kind import KindLike
from btgen.lang.model import Attr, Mission, Node
from btgen.lang.status import NodeStatus

# ================================================================ helpers


@dataclass
class Port:
    """A port of one node instance (the interpreter's Port): its text and where it is written."""

    name: str
    raw: str
    attr: Optional[Attr]
    spec: Optional[PortSpec]

    @property
    def loc_or(self) -> Optional[Loc]:
        return self.attr.value_loc if self.attr is not None else None


@dataclass
class Inst:
    index: int
    node: Node
    reg_id: str
    spec: Optional[NodeSpec]
    bb: bbmod.Blackboard
    ports: dict[str, Port]

    @property
    def what(self) -> str:
        return f'`{self.reg_id}` "{self.node.display_name}"'


def no_bound() -> Optional[int]:
    return None


@dataclass
class Write:
    """A place that writes a slot."""

    slot: int
    order: int
    loc: Loc
    what: str  # e.g. "`x := 1` in `code` of `Script` \"Init\""
    kind: Callable[..., Optional[KindLike]]  # the kind it writes, given the kinds known so far
    determining: bool  # may be the entry's first value (decides the type of an untyped entry)
    bound: Callable[..., Optional[int]]  # strings: most bytes written (None: no bound)
    literal: Optional[str] = None  # the text written, when it is a literal
    source: str = "script"  # script | constant | set | copy | loop | port
    type_name: str = ""  # a typed write (loop, a node's port): the T of its Blackboard::set<T>


@dataclass
class Slot:
    entry: bbmod.Entry
    first_loc: Loc
    at_load: bool = False
    bt_any_at_load: bool = False  # created at load by an `entry` port (InputPort<BT::Any>): typed BT::Any
    initial: Optional[str] = None  # SubTree constant
    origin: str = ""  # why it has its type (without the place)
    origin_loc: Optional[Loc] = None
    writes: list[Write] = field(default_factory=list)
    unset: bool = False
    kind: Optional[KindLike] = None
    capacity: int = 0
    elem_capacity: int = 0
    queue_literals: list[int] = field(default_factory=list)  # element counts written as literals
    elem_literals: list[int] = field(default_factory=list)
    queue_unbounded: bool = False
    untyped_text: bool = False  # only untyped ports write it: robot code passes text
    provided: bool = False  # the application sets it before the first tick (--entry)
    failed: bool = False  # its type could not be told (reported): scripts using it are not compiled
    key: str = ""
    owner: str = ""
    owner_uid: int = 0

    @property
    def origin_text(self) -> str:
        return f"{self.origin} at {self.origin_loc}" if self.origin_loc is not None else self.origin


# ---------------------------------------------------------------- what each node does with data
# Found by the resolve pass (one record per use, in creation order), compiled by Compiler.


@dataclass(frozen=True)
class IndexWriteUse:
    """Nav2's PersistentSequence writing its place into the entry `current_child_idx` names."""

    slot: int
    key: str
    loc: Loc


@dataclass(frozen=True)
class ParamUse:
    """A count or duration of Repeat, RetryUntilSuccessful, Timeout, Delay, Sleep given as `{key}`."""

    slot: int
    port: str
    key: str
    loc: Loc


@dataclass(frozen=True)
class StatusParam:
    """p0 of the node's row: a converted literal (Precondition `else`, Loop `if_empty`) or a count."""

    p0: Optional[Union[int, NodeStatus]]  # None: the literal did not convert (reported)
    # A literal the library loads but cannot convert (no NodeStatus): the node throws this
    # message where it reads the port, at `where`
    throws: Optional[str] = None
    where: Optional[Loc] = None


@dataclass(frozen=True)
class UnsetUse:
    key: str
    loc: Loc


@dataclass(frozen=True)
class EntryUse:
    """WasEntryUpdated, SkipUnlessUpdated, WaitValueUpdate: the entry they watch."""

    slot: int
    key: str


@dataclass(frozen=True)
class SetLiteralUse:
    dst: int
    text: str
    loc: Loc
    key: str


@dataclass(frozen=True)
class SetCopyUse:
    dst: int
    src: int
    loc: Loc
    key: str
    src_key: str
    raw: str  # the `value` attribute as written


@dataclass(frozen=True)
class SetKeyUse:
    """SetBlackboard output_key="{key}" (UnsetBlackboard key="{key}"): the key is read from entry
    `key` when the node runs; `cases`: one operation per text that entry can hold (every value
    it is given is a literal), each as if that text were written in the port."""

    slot: int  # the entry holding the key
    key: str
    loc: Loc  # the port's attribute
    cases: tuple[tuple[str, Union[SetLiteralUse, SetCopyUse, UnsetUse]], ...]
    port: str = "output_key"


@dataclass(frozen=True)
class SwitchUse:
    reads: tuple[tuple[str, Optional[str], Optional[int]], ...]  # (port, text, slot): variable, then cases
    cases: int


@dataclass(frozen=True)
class LoopUse:
    elem: str
    static: Optional[tuple]  # the queue's items, when the port is a literal
    qslot: Optional[int]
    vslot: Optional[int]
    loc: Loc
    qkey: Optional[str]  # the key `queue` names, when it is not a literal


@dataclass(frozen=True)
class PortUse:
    """A port of a user leaf, Control or Decorator."""

    port: PortSpec
    slot: Optional[int]
    raw: str
    p: Port


@dataclass
class PortAccess:
    """What the accessors of one port of a user model do, node by node (gathered into a PortIR)."""

    spec: PortSpec
    reads: list[tuple[int, ops.PortRead]] = field(default_factory=list)
    writes: list[tuple[int, ops.PortWrite]] = field(default_factory=list)
    scratch: bool = False  # a getter writes a number's text into a member


NodeUse = Union[
    IndexWriteUse,
    ParamUse,
    StatusParam,
    UnsetUse,
    EntryUse,
    SetLiteralUse,
    SetCopyUse,
    SetKeyUse,
    SwitchUse,
    LoopUse,
    PortUse,
]


def ports_of(mission: Mission, model: Node) -> dict[str, Port]:
    """The ports of an instance as the interpreter builds them (lang/instance.py)."""
    return {p.name: Port(p.name, p.raw, p.attr, p.spec) for p in instance_ports(mission, model)}
