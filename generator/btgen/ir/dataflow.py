"""The data side of a mission, resolved at compile time.

BehaviorTree.CPP 4.6.2 keeps one blackboard per tree instance, a map from
key to a type-erased entry, and finds entries by string at run time
through SubTree remappings, `_autoremap` and `@` root keys. btgen does all
of that here, once:

1. **Load.** The main tree is instantiated the way 4.6.2's XML loader does
   it, with the reference blackboard (blackboard.py): a blackboard per
   SubTree instance (remappings, constants, model defaults), and every
   `{key}` port creating its entry with the port's type, in creation order.
   Type clashes 4.6.2 throws for at load time are errors here.
2. **Resolve.** Every key any node reads or writes (ports, scripts,
   SetBlackboard, UnsetBlackboard, WasEntryUpdated, ...) is looked up from
   the node's blackboard as 4.6.2 would look it up at run time; an entry
   4.6.2 would create at run time is created where it would land. Each
   distinct entry is one *slot* of the generated Blackboard struct.
3. **Type.** A slot whose entry has a declared type (a typed port created
   it) holds that type. Any other slot takes the type of what writes it:
   the first write in creation order that does not need a value already
   (so not `x += 1` nor `x := x + 1`). Writes of another type that 4.6.2
   would convert are compiled as conversions; writes that would fail, or
   change the entry's type, whenever they run are errors naming both sides.
4. **Size.** Strings and queues get fixed capacities: the longest value the
   writes can produce (literals, concatenations of bounded parts), at most
   the mission's string capacity (`--string-capacity`, default 128); a
   slot written by robot code or growing without bound gets that capacity.
5. **Compile.** Scripts go to script_cpp.py; ports, SetBlackboard,
   UnsetBlackboard, Switch cases, Loop queues and the entry-update nodes
   become small C++ functions over the slots (DataIR), which emit.py places
   in the generated header.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field
from typing import Callable, Optional

from btgen.backend_cpp.naming import entry_identifiers, model_identifiers, port_identifiers
from btgen.diagnostics import DiagnosticSink, InternalError, Loc, did_you_mean
from btgen.ir import dataops as ops
from btgen.ir import kinds
from btgen.ir.kinds import DYN, ScriptTypeError, describe_kind, is_numeric, is_queue, is_user, kind_of_type
from btgen.ir.script_types import SlotType, TypedScript, type_script
from btgen.lang import blackboard as bbmod
from btgen.lang import script as sc
from btgen.lang import values
from btgen.lang.catalogue import BUILTINS, NodeSpec, PortSpec
from btgen.lang.instance import instance_ports, subtree_remapping
from btgen.lang.model import Attr, Mission, Node, SubTreeNode

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


# ScriptSlot enumerators (runtime/include/btgen/blackboard.hpp), by attribute.
SCRIPT_SLOTS = {
    "_failureIf": "kFailureIf",
    "_successIf": "kSuccessIf",
    "_skipIf": "kSkipIf",
    "_while": "kWhile",
    "_onSuccess": "kOnSuccess",
    "_onFailure": "kOnFailure",
    "_post": "kPost",
    "_onHalted": "kOnHalted",
    "code": "kCode",
    "if": "kCode",
}
SCRIPT_BIT = {
    "kFailureIf": 0,
    "kSuccessIf": 1,
    "kSkipIf": 2,
    "kWhile": 3,
    "kOnSuccess": 4,
    "kOnFailure": 5,
    "kPost": 6,
    "kOnHalted": 7,
    "kCode": 8,
}

# Built-in ports that take a literal only in the C++ back end (4.6.2 reads them on every tick).
# Ports read as `{key}` at run time: the engine reads the entry when 4.6.2's node calls getInput
# (every tick of Repeat, RetryUntilSuccessful, Timeout and Delay, the start of a Sleep).
PARAM_PORTS = {
    ("Repeat", "num_cycles"),
    ("RetryUntilSuccessful", "num_attempts"),
    ("Timeout", "msec"),
    ("Delay", "delay_msec"),
    ("Sleep", "msec"),
}
LITERAL_ONLY = {
    ("Parallel", "success_count"),
    ("Parallel", "failure_count"),
    ("ParallelAll", "max_failures"),
    ("RunOnce", "then_skip"),
    ("Precondition", "else"),
    ("LoopInt", "if_empty"),
    ("LoopBool", "if_empty"),
    ("LoopDouble", "if_empty"),
    ("LoopString", "if_empty"),
}
LOOPS = {"LoopInt": "int", "LoopBool": "bool", "LoopDouble": "double", "LoopString": "string"}
ENTRY_NODES = ("WasEntryUpdated", "SkipUnlessUpdated", "WaitValueUpdate")


# ================================================================ IR


@dataclass(frozen=True)
class SlotIR:
    """One blackboard entry of the mission: a member of the generated Blackboard struct."""

    index: int
    member: str  # C++ member name
    key: str  # its key on its blackboard
    owner: str  # "root" or the SubTree instance path
    declared: str  # declared type (values.py canonical name; `any` when none)
    kind: str  # ir.kinds kind
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
    may_be_bt_any: bool = False  # from 4.7.0 a SetBlackboard string may leave it empty and typed BT::Any


@dataclass(frozen=True)
class ScriptIR:
    """A script of one node, typed (script_types.py): its expression tree over the slots it
    names, for backend_cpp/script_cpp.py to write as C++."""

    node: int
    comment: str
    which: str  # the ScriptSlot it fills (SCRIPT_SLOTS)
    attr: Attr  # the attribute holding it: the places of its run-time errors (script_loc)
    script: sc.Script
    names: tuple[tuple[str, int], ...]  # name -> slot index
    condition: bool  # its last value is a condition's result
    prefix: str  # the prefix of its run-time error messages
    typed: TypedScript  # every expression's kind and how it is computed (script_types.py)


@dataclass(frozen=True)
class LocalIR:
    """Node-local storage in the Blackboard struct: the copy of a Loop's literal queue
    (`elem`, `length`, `elem_capacity`), or a user-typed literal (`user_cpp`)."""

    member: str
    comment: str
    elem: str = ""  # int, bool, double, string
    length: int = 0
    elem_capacity: int = 0
    user_cpp: str = ""
    text_capacity: int = 0  # a Loop's queue converted from a string entry (btgen::port::TextQueue)


@dataclass(frozen=True)
class DataOp:
    """The data operation of one node (a case of its dispatcher in the generated header)."""

    node: int
    comment: str
    op: object  # a record of ir/dataops.py


@dataclass(frozen=True)
class PortIR:
    """A port of a user leaf model: a typed getter and/or setter of the generated model class."""

    name: str  # C++ name of the getter (the setter is set_<name>)
    port: str  # the port's name
    direction: str
    type_name: str
    description: str
    scratch: str  # the member the getter writes a number's text into ("" when it never needs one)
    reads: tuple[tuple[int, ops.PortRead], ...]  # (node index, what the getter returns there)
    writes: tuple[tuple[int, ops.PortWrite], ...]  # (node index, what the setter does there)
    user_cpp: str = ""  # a user port type (--type): its C++ spelling; the setter takes `const T&`


@dataclass(frozen=True)
class DataIR:
    slots: tuple[SlotIR, ...]
    locals: tuple[LocalIR, ...]
    scripts: tuple[ScriptIR, ...]
    data_leaves: tuple[DataOp, ...]  # SetBlackboard, UnsetBlackboard
    entries: tuple[DataOp, ...]  # WasEntryUpdated & co.: EntrySeq
    switches: tuple[DataOp, ...]  # SwitchN: SwitchCases
    loops: tuple[DataOp, ...]  # LoopX: LoopPop
    ports: dict  # model id -> tuple[PortIR, ...]
    script_bits: dict  # node index -> NodeInfo::scripts bits
    params: dict  # node index -> (p0, p1, p2) for data nodes
    string_capacity: int
    queue_capacity: int
    where: tuple[Loc, ...]  # the places run-time errors name (Fail.where indexes them)
    enums: tuple[tuple[str, int], ...] = ()  # scripting enums: `detail::kScriptingEnums`
    user_types: tuple = ()  # the user port types (usertypes.UserType) the mission uses: headers, checks
    inits: tuple[DataOp, ...] = ()  # UserInit: user-typed literals, converted when the mission is constructed
    param_reads: tuple[DataOp, ...] = ()  # ParamRead: loop counts and durations given as `{key}`


# ================================================================ helpers


def script_loc(attr: Attr, offset: int) -> Loc:
    if offset <= 0:
        return attr.value_loc
    return sc.script_error_loc(attr.value_loc, attr.value, offset, sc.raw_attr_value(attr.value_loc))


@dataclass
class _Port:
    """A port of one node instance (the interpreter's _Port): its text and where it is written."""

    name: str
    raw: str
    attr: Optional[Attr]
    spec: Optional[PortSpec]

    @property
    def loc_or(self) -> Optional[Loc]:
        return self.attr.value_loc if self.attr is not None else None


@dataclass
class _Inst:
    index: int
    node: Node
    reg_id: str
    spec: Optional[NodeSpec]
    bb: bbmod.Blackboard
    ports: dict[str, _Port]

    @property
    def what(self) -> str:
        return f'`{self.reg_id}` "{self.node.display_name}"'


def _no_bound() -> Optional[int]:
    return None


@dataclass
class _Write:
    """A place that writes a slot."""

    slot: int
    order: int
    loc: Loc
    what: str  # e.g. "`x := 1` in `code` of `Script` \"Init\""
    kind: Callable[..., Optional[str]]  # the kind it writes, given the kinds known so far
    determining: bool  # may be the entry's first value (decides the type of an untyped entry)
    bound: Callable[..., Optional[int]]  # strings: most bytes written (None: no bound)
    literal: Optional[str] = None  # the text written, when it is a literal
    source: str = "script"  # script | constant | set | copy | loop | port


@dataclass
class _Slot:
    entry: bbmod.Entry
    first_loc: Loc
    at_load: bool = False
    initial: Optional[str] = None  # SubTree constant
    origin: str = ""  # why it has its type (without the place)
    origin_loc: Optional[Loc] = None
    writes: list[_Write] = field(default_factory=list)
    unset: bool = False
    kind: Optional[str] = None
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
    member: str = ""

    @property
    def origin_text(self) -> str:
        return f"{self.origin} at {self.origin_loc}" if self.origin_loc is not None else self.origin


def _ports_of(mission: Mission, model: Node) -> dict[str, _Port]:
    """The ports of an instance as the interpreter builds them (lang/instance.py)."""
    return {p.name: _Port(p.name, p.raw, p.attr, p.spec) for p in instance_ports(mission, model)}


# ================================================================ the analysis


class _Analyzer:
    def __init__(self, mission: Mission, options: DataOptions) -> None:
        self.m = mission
        self.opt = options
        self.sink = DiagnosticSink()
        self.reported: set[tuple[Loc, str]] = set()
        self.insts: list[_Inst] = []
        self.bb_labels: dict[int, str] = {}
        self.bb_uid: dict[int, int] = {}  # UID of the SubTree node of a blackboard (Groot2 names it)
        self.bbs: list[bbmod.Blackboard] = []
        self.slots: list[_Slot] = []
        self.slot_of_entry: dict[int, int] = {}
        self.order = 0
        # per-node uses, filled by _collect
        self.script_uses: list[tuple[_Inst, Attr, str, sc.Script, dict[str, int], bool]] = []
        self.node_ops: list[tuple[str, _Inst, dict]] = []
        self.user = {t.kind: t for t in mission.user_types}  # kind -> usertypes.UserType

    def error(self, loc: Loc, message: str) -> None:
        if (loc, message) not in self.reported:
            self.reported.add((loc, message))
            self.sink.error(loc, message)

    def _kind_of_slot(self, slot: int) -> Optional[str]:
        return self.slots[slot].kind

    def _capacity_of_slot(self, slot: int) -> Optional[int]:
        return self.slots[slot].capacity

    def next_order(self) -> int:
        self.order += 1
        return self.order

    # ------------------------------------------------------------ 1. load
    def load(self) -> None:
        root = bbmod.Blackboard()
        self._add_bb(root, "root")
        self._provide(root, self.m.main_tree, True, self.m.main.loc)
        stack: list[tuple[Node, bbmod.Blackboard, str]] = [(self.m.main.root, root, "")]
        while stack:
            node, bb, path = stack.pop()
            index = len(self.insts)
            if isinstance(node, SubTreeNode):
                inst = _Inst(index, node, "SubTree", BUILTINS["SubTree"], bb, {})
                self.insts.append(inst)
                sub_path = f"{path}/{node.display_name}" if path else node.display_name
                child_bb = self._subtree_blackboard(node, bb, sub_path)
                self.bb_uid[id(child_bb)] = index + 1
                stack.append((self.m.tree(node.target).root, child_bb, sub_path))
                continue
            ports = _ports_of(self.m, node)
            try:
                spec = self.m.spec(node.id)
            except KeyError:
                spec = None
            inst = _Inst(index, node, node.id, spec, bb, ports)
            self.insts.append(inst)
            for p in ports.values():
                if p.attr is None:
                    continue
                type_name = p.spec.type if p.spec is not None else values.ANY
                key = bbmod.remapped_key(p.name, p.raw)
                before = bb.get_entry(key) if key is not None else None
                try:
                    entry = bbmod.create_port_entry(bb, p.raw, type_name, p.name)
                except (values.ConversionError, bbmod.BlackboardError) as e:
                    existing = self.slot_of_entry.get(id(before)) if before is not None else None
                    where = f" ({self.slots[existing].origin_text})" if existing is not None else ""
                    self.error(p.attr.value_loc, f"port `{p.name}` of `{node.id}`: {e}{where}")
                    continue
                if entry is not None:
                    s = self._slot(entry, p.attr.value_loc)
                    s.at_load = True
                    if before is None and not s.origin:
                        s.origin = f"created as {entry.type_name} by port `{p.name}` of {inst.what}"
                        s.origin_loc = p.attr.value_loc
            for child in reversed(node.children):
                stack.append((child, bb, path))

    def _provide(self, bb: bbmod.Blackboard, tree_id: str, root: bool, loc: Loc) -> None:
        """The entries the application sets in this blackboard before the first tick (--entry):
        created with their type; robot code writes them."""
        for p in self.m.provided:
            if not p.applies_to(tree_id, root):
                continue
            try:
                entry = bb.create_entry(p.key, p.type)
            except bbmod.BlackboardError as e:
                self.error(loc, f"{p.option}: {e}")
                continue
            s = self._slot(entry, loc)
            s.at_load = True
            s.provided = True
            s.origin = f"provided by the application ({p.option})"
            kind = kind_of_type(p.type)
            s.writes.append(
                _Write(
                    self.slots.index(s),
                    self.next_order(),
                    loc,
                    f"the application ({p.option})",
                    (lambda k=kind: k),
                    kind is not None,
                    (lambda: None),
                    None,
                    "port",
                )
            )

    def _add_bb(self, bb: bbmod.Blackboard, label: str) -> None:
        self.bbs.append(bb)
        self.bb_labels[id(bb)] = label

    def _subtree_blackboard(self, model: SubTreeNode, parent: bbmod.Blackboard, path: str) -> bbmod.Blackboard:
        remapping, missing = subtree_remapping(self.m, model)
        for name in missing:
            self.error(
                model.loc,
                f"SubTree `{model.target}` declares port `{name}` without a "
                f"default, and this instance does not remap it",
            )
        remap = [(n, v, a.value_loc if a is not None else model.loc) for n, v, a in remapping]
        try:
            bb = bbmod.Blackboard.for_subtree(
                parent,
                [(n, v) for n, v, _ in remap],
                model.autoremap,
                typed_literals=self.m.semantics.subtree_literals_typed,
            )
        except (values.ConversionError, bbmod.BlackboardError) as e:
            self.error(model.loc, f"SubTree `{model.target}`: {e}")
            bb = bbmod.Blackboard(parent, autoremap=model.autoremap)
        self._add_bb(bb, path)
        locs = {n: loc for n, _, loc in remap}
        for key in bb.local_keys():  # the constants of the instance
            entry = bb.get_entry(key)
            assert entry is not None
            s = self._slot(entry, locs.get(key, model.loc))
            s.at_load = True
            # 4.9.1 stores a literal that is wholly a number as that number (subtree_literals_typed)
            text = (
                entry.value
                if isinstance(entry.value, str)
                else next((v for n, v, _ in remap if n == key), str(entry.value))
            )
            constant_kind = {values.INT: "int", values.DOUBLE: "double"}.get(entry.type_name, "string")
            s.initial = text
            s.origin = f'the constant port `{key}` of SubTree "{model.display_name}"'
            s.origin_loc = locs.get(key, model.loc)
            s.writes.append(
                _Write(
                    self.slots.index(s),
                    self.next_order(),
                    locs.get(key, model.loc),
                    f'the constant port `{key}="{text}"` of SubTree "{model.display_name}"',
                    lambda k=constant_kind: k,
                    True,
                    lambda t=text: len(t.encode("utf-8")),
                    text,
                    "constant",
                )
            )
        self._provide(bb, model.target, False, model.loc)
        return bb

    def _slot(self, entry: bbmod.Entry, loc: Loc) -> _Slot:
        idx = self.slot_of_entry.get(id(entry))
        if idx is None:
            idx = len(self.slots)
            self.slot_of_entry[id(entry)] = idx
            self.slots.append(_Slot(entry, loc))
        return self.slots[idx]

    # ------------------------------------------------------------ 2. resolve
    def resolve(self, bb: bbmod.Blackboard, key: str, loc: Loc) -> Optional[int]:
        """The slot `key` names from `bb` at run time (created where 4.6.2 would create it)."""
        try:
            entry = bb.get_entry(key)
            if entry is None:
                entry = bb.create_entry(key, values.ANY)
        except bbmod.BlackboardError as e:
            self.error(loc, str(e))
            return None
        self._slot(entry, loc)
        return self.slot_of_entry[id(entry)]

    def collect(self) -> None:
        for inst in self.insts:
            self._collect_node(inst)

    def _collect_node(self, inst: _Inst) -> None:
        node = inst.node
        for attr in node.pre:
            self._script_use(inst, attr, attr.name, condition=True)
        nid = inst.reg_id
        if not isinstance(node, SubTreeNode):
            builtin = inst.spec is not None and inst.spec.builtin
            for p in inst.ports.values():
                key = bbmod.remapped_key(p.name, p.raw)
                if builtin and (nid, p.name) in PARAM_PORTS and key is not None:
                    loc = p.loc_or or node.loc
                    slot = self.resolve(inst.bb, key, loc)
                    if slot is not None:
                        self.node_ops.append(("param", inst, {"slot": slot, "port": p.name, "key": key, "loc": loc}))
                if builtin and (nid, p.name) in LITERAL_ONLY and bbmod.remapped_key(p.name, p.raw) is not None:
                    self.error(
                        p.loc_or or node.loc,
                        f"port `{p.name}` of {inst.what} reads blackboard entry `{p.raw}`; the C++ back end "
                        f"needs a literal value here",
                    )
            if inst.spec is not None and inst.spec.builtin:
                self._collect_builtin(inst)
            elif inst.spec is not None and inst.spec.kind in ("Action", "Condition", "Control", "Decorator"):
                self._collect_leaf(inst)
        for attr in node.post:
            self._script_use(inst, attr, attr.name, condition=False)

    # -- scripts
    def _script_use(self, inst: _Inst, attr: Attr, which: str, condition: bool) -> None:
        script = attr.script
        if script is None:
            if bbmod.is_blackboard_pointer(attr.value):
                self.error(
                    attr.value_loc,
                    f"`{attr.name}` of {inst.what} reads its script from blackboard entry "
                    f"`{attr.value}`; the C++ back end compiles scripts and needs the code "
                    f"written here",
                )
            return  # a syntax error, already reported by the front end
        names: dict[str, int] = {}
        for stmt in script.statements:
            for n in sc.walk(stmt):
                key = n.name if isinstance(n, sc.Name) else (n.target if isinstance(n, sc.Assign) else None)
                if key is not None and key not in names:
                    slot = self.resolve(inst.bb, key, script_loc(attr, n.offset))
                    if slot is None:
                        return
                    names[key] = slot
        self.script_uses.append((inst, attr, which, script, names, condition))
        prefix = f"`{attr.name}` of {inst.what}"
        for stmt in script.statements:
            for n in sc.walk(stmt):
                if not isinstance(n, sc.Assign):
                    continue
                target = names[n.target]
                reads_self = any(isinstance(r, sc.Name) and names[r.name] == target for r in sc.walk(n.value))
                determining = n.op in (":=", "=") and not reads_self
                value = n.value
                loc = script_loc(attr, n.offset)
                text = attr.value[n.offset : _end_offset(n, attr.value)].strip() or attr.value
                what = f"`{text}` in {prefix}"
                if n.op in (":=", "="):
                    kind_fn: Callable[..., Optional[str]] = functools.partial(self._expr_kind, value, names)
                    bound_fn: Callable[..., Optional[int]] = functools.partial(self._expr_bound, value, names)
                else:
                    kind_fn = functools.partial(self._kind_of_slot, target)
                    bound_fn = _no_bound if n.op == "+=" else functools.partial(self._capacity_of_slot, target)
                lit = value.value if isinstance(value, sc.Literal) and isinstance(value.value, str) else None
                if lit is not None and n.op in (":=", "="):
                    self._queue_literal(target, lit)
                self.slots[target].writes.append(
                    _Write(target, self.next_order(), loc, what, kind_fn, determining, bound_fn, lit)
                )

    def _bound_of(self, slot: int) -> Optional[int]:
        s = self.slots[slot]
        if s.kind == DYN:  # its text, or the text of a number it holds
            return max(s.capacity, kinds.TEXT_BOUND["double"])
        return s.capacity if s.kind == "string" else kinds.TEXT_BOUND.get(s.kind or "", 0)

    def _kind_of(self, names: dict[str, int]) -> Callable[[str], Optional[str]]:
        return lambda name: self.slots[names[name]].kind

    def _expr_kind(self, expr: sc.Expr, names: dict[str, int]) -> Optional[str]:
        """The kind of a script value; "error" when it fails whatever the kinds (compiling the script
        reports why), None while a name's kind is unknown."""
        if any(is_user(self.slots[names[n.name]].kind) for n in sc.walk(expr) if isinstance(n, sc.Name)):
            return "error"  # (compiling the script says that user-typed entries are not for scripts)
        try:
            return kinds.expr_kind(expr, self._kind_of(names))
        except ScriptTypeError:
            return "error"

    def _expr_bound(self, expr: sc.Expr, names: dict[str, int]) -> Optional[int]:
        """Most bytes a string expression gives (None: unknown yet)."""
        if isinstance(expr, sc.Literal):
            return (
                len(expr.value.encode("utf-8"))
                if isinstance(expr.value, str)
                else kinds.TEXT_BOUND[kinds.value_kind(expr.value)]
            )
        if isinstance(expr, sc.Name):
            s = self.slots[names[expr.name]]
            if s.kind == DYN:
                return max(s.capacity, kinds.TEXT_BOUND["double"])
            if s.kind == "string":
                return s.capacity
            return kinds.TEXT_BOUND.get(s.kind or "", 0)
        if isinstance(expr, sc.Binary):
            a, b = self._expr_bound(expr.left, names), self._expr_bound(expr.right, names)
            return None if a is None or b is None else a + b
        if isinstance(expr, sc.Ternary):
            a, b = self._expr_bound(expr.then, names), self._expr_bound(expr.orelse, names)
            return None if a is None or b is None else max(a, b)
        if isinstance(expr, sc.Assign):
            s = self.slots[names[expr.target]]
            if s.kind == DYN:  # its text, or the text of a number it holds
                return max(s.capacity, kinds.TEXT_BOUND["double"])
            return s.capacity if s.kind == "string" else kinds.TEXT_BOUND.get(s.kind or "", 0)
        return kinds.TEXT_BOUND["double"]  # unary, comparison: numbers

    # -- built-in nodes
    def _literal(self, inst: _Inst, name: str, type_name: str) -> object:
        p = inst.ports.get(name)
        assert p is not None, (inst.reg_id, name)
        try:
            return values.convert_from_string(type_name, p.raw)
        except values.ConversionError as e:
            self.error(p.loc_or or inst.node.loc, f"port `{name}` of {inst.what}: {e}")
            return None

    def _collect_builtin(self, inst: _Inst) -> None:
        nid = inst.reg_id
        node = inst.node
        if nid in ("Script", "ScriptCondition"):
            p = inst.ports["code"]
            if p.attr is not None:
                self._script_use(inst, p.attr, "code", condition=nid == "ScriptCondition")
        elif nid == "Precondition":
            p = inst.ports["if"]
            if p.attr is not None:
                self._script_use(inst, p.attr, "if", condition=True)
            self.node_ops.append(("params", inst, {"p0": self._literal(inst, "else", values.NODE_STATUS)}))
        elif nid == "SetBlackboard":
            self._collect_set_blackboard(inst)
        elif nid == "UnsetBlackboard":
            p = inst.ports["key"]
            key = p.raw
            if bbmod.is_blackboard_pointer(key):
                self.error(
                    p.loc_or or node.loc,
                    f"port `key` of {inst.what} reads the key from blackboard entry "
                    f"`{key}`; the C++ back end needs the key written here",
                )
                return
            self.node_ops.append(("unset", inst, {"key": key, "loc": p.loc_or or node.loc}))
        elif nid in ENTRY_NODES:
            p = inst.ports["entry"]
            key = bbmod.strip_blackboard_pointer(p.raw) or p.raw
            slot = self.resolve(inst.bb, key, p.loc_or or node.loc)
            if slot is not None:
                self.node_ops.append(("entry", inst, {"slot": slot, "key": key}))
        elif nid.startswith("Switch"):
            self._collect_switch(inst)
        elif nid in LOOPS:
            self._collect_loop(inst, LOOPS[nid])

    def _port_slot(self, inst: _Inst, name: str) -> Optional[int]:
        """The slot a `{key}` port names, or None for a literal (or an unset port)."""
        p = inst.ports.get(name)
        if p is None:
            return None
        key = bbmod.remapped_key(name, p.raw)
        if key is None:
            return None
        return self.resolve(inst.bb, key, p.loc_or or inst.node.loc)

    def _collect_set_blackboard(self, inst: _Inst) -> None:
        node = inst.node
        out = inst.ports["output_key"]
        if bbmod.is_blackboard_pointer(out.raw):
            self.error(
                out.loc_or or node.loc,
                f"port `output_key` of {inst.what} reads the key from blackboard "
                f"entry `{out.raw}`; the C++ back end needs the key written here",
            )
            return
        dst = self.resolve(inst.bb, out.raw, out.loc_or or node.loc)
        if dst is None:
            return
        value = inst.ports["value"]
        src_key = bbmod.strip_blackboard_pointer(value.raw)
        loc = value.loc_or or node.loc
        if src_key is None:
            text = value.raw
            what = f'`value="{text}"` of {inst.what}'

            def lit_kind(d=dst) -> Optional[str]:
                s = self.slots[d]
                declared = s.entry.type_name
                if declared not in (values.ANY, values.STRING) and not values.is_opaque_type(declared):
                    return kind_of_type(declared)
                return "string"

            self.slots[dst].writes.append(
                _Write(
                    dst,
                    self.next_order(),
                    loc,
                    what,
                    lit_kind,
                    True,
                    lambda t=text: len(t.encode("utf-8")),
                    text,
                    "set",
                )
            )
            self._queue_literal(dst, text)
            self.node_ops.append(("set_literal", inst, {"dst": dst, "text": text, "loc": loc, "key": out.raw}))
            return
        src = self.resolve(inst.bb, src_key, loc)
        if src is None:
            return
        what = f'`value="{value.raw}"` of {inst.what}'
        self.slots[dst].writes.append(
            _Write(
                dst,
                self.next_order(),
                loc,
                what,
                lambda s=src: self.slots[s].kind,
                True,
                lambda s=src: self._bound_of(s),
                None,
                "copy",
            )
        )
        self.node_ops.append(
            (
                "set_copy",
                inst,
                {"dst": dst, "src": src, "loc": loc, "key": out.raw, "src_key": src_key, "raw": value.raw},
            )
        )

    def _queue_literal(self, slot: int, text: str) -> None:
        s = self.slots[slot]
        elem = values.queue_element_type(s.entry.type_name)
        if elem is None:
            return
        parts = values._split_queue(text)
        s.queue_literals.append(len(parts))
        if elem == values.STRING:
            s.elem_literals.extend(len(x.encode("utf-8")) for x in parts)

    def _collect_switch(self, inst: _Inst) -> None:
        n_cases = int(inst.reg_id[len("Switch") :])
        reads = []
        for name in ["variable"] + [f"case_{i}" for i in range(1, n_cases + 1)]:
            p = inst.ports.get(name)
            slot = self._port_slot(inst, name)
            reads.append((name, p.raw if p is not None else None, slot))
        self.node_ops.append(("switch", inst, {"reads": reads, "cases": n_cases}))
        self.node_ops.append(("params", inst, {"p0": n_cases}))

    def _collect_loop(self, inst: _Inst, elem: str) -> None:
        node = inst.node
        queue_port = inst.ports["queue"]
        qkey = bbmod.remapped_key("queue", queue_port.raw)
        static = None
        qslot = None
        loc = queue_port.loc_or or node.loc
        if qkey is None:
            try:
                static = values.convert_from_string(f"queue<{elem}>", queue_port.raw)
            except values.ConversionError as e:
                self.error(loc, f"port `queue` of {inst.what}: {e}")
                return
        else:
            qslot = self.resolve(inst.bb, qkey, loc)
        vslot = self._port_slot(inst, "value")
        if vslot is not None:
            vp = inst.ports["value"]
            vloc = vp.loc_or or node.loc
            what = f"port `value` of {inst.what}"

            def bound(q=qslot, st=static) -> Optional[int]:
                if st is not None:
                    return max((len(str(x).encode("utf-8")) for x in st), default=0)
                if q is None:
                    return 0
                s = self.slots[q]
                # (from 4.9.1 a string entry's elements are parts of its text)
                return s.elem_capacity if is_queue(s.kind) else s.capacity if s.kind in ("string", DYN) else 0

            self.slots[vslot].writes.append(
                _Write(vslot, self.next_order(), vloc, what, lambda e=elem: kind_of_type(e), True, bound, None, "loop")
            )
        self.node_ops.append(
            ("loop", inst, {"elem": elem, "static": static, "qslot": qslot, "vslot": vslot, "loc": loc, "qkey": qkey})
        )
        self.node_ops.append(("params", inst, {"p0": self._literal(inst, "if_empty", values.NODE_STATUS)}))

    # -- user leaves
    def _collect_leaf(self, inst: _Inst) -> None:
        spec = inst.spec
        assert spec is not None
        for ps in spec.ports:
            p = inst.ports.get(ps.name)
            if p is None:
                continue
            slot = None
            key = bbmod.remapped_key(ps.name, p.raw)
            if key is not None:
                slot = self.resolve(inst.bb, key, p.loc_or or inst.node.loc)
                if slot is None:
                    continue
                if ps.writes:
                    loc = p.loc_or or inst.node.loc
                    what = f"output port `{ps.name}` of {inst.what}"
                    kind = kind_of_type(ps.type)
                    if is_queue(kind):
                        self.slots[slot].queue_unbounded = True
                    self.slots[slot].writes.append(
                        _Write(
                            slot,
                            self.next_order(),
                            loc,
                            what,
                            (lambda k=kind: k),
                            kind is not None,
                            (lambda: None),
                            None,
                            "port",
                        )
                    )
            self.node_ops.append(("port", inst, {"port": ps, "slot": slot, "raw": p.raw, "p": p}))

    # ------------------------------------------------------------ 3. kinds
    def type_slots(self) -> None:
        for s in self.slots:
            # A `string` entry is no constraint in 4.6.2: a script may store a number in it, and
            # string ports read numbers as text. Its type comes from its writes, as for `any`.
            declared = s.entry.type_name
            s.kind = kind_of_type(declared) if declared != values.STRING else None
            if s.kind is not None and not s.origin:
                s.origin = f"declared {declared}"
        # Entries nothing writes: reading them gives no value. Decided first, so an entry written
        # from one (`x := @missing + 1`) gets a kind and only the real error is reported.
        for s in self.slots:
            if s.kind is None and not s.writes:
                s.kind = "string" if s.entry.type_name == values.STRING else "none"
                s.origin = s.origin or "never written"
        undecided = [i for i, s in enumerate(self.slots) if s.kind is None]
        changed = True
        while changed:
            changed = False
            for i in undecided:
                s = self.slots[i]
                if s.kind is not None:
                    continue
                det = sorted((w for w in s.writes if w.determining), key=lambda w: w.order)
                if not det:
                    continue
                k = det[0].kind()
                if k is not None and k not in ("none", "error"):
                    s.kind = k
                    s.origin = f"first written by {det[0].what}"
                    s.origin_loc = det[0].loc
                    changed = True
        # Cycles (`a := b; b := a` and no other first write): the first write whose kind is known.
        changed = True
        while changed:
            changed = False
            for i in undecided:
                s = self.slots[i]
                if s.kind is not None:
                    continue
                for w in sorted((w for w in s.writes if w.determining), key=lambda w: w.order):
                    k = w.kind()
                    if k is not None and k not in ("none", "error"):
                        s.kind = k
                        s.origin = f"first written by {w.what}"
                        s.origin_loc = w.loc
                        changed = True
                        break
        for s in self.slots:
            if s.kind is not None:
                continue
            w = min(s.writes, key=lambda x: x.order)
            if any(x.determining and x.kind() in ("none", "error") for x in s.writes):
                s.kind = "none"  # a script that fails whatever runs: compiling it says why
                continue
            if all(x.source == "port" for x in s.writes):
                # Robot code writes it through untyped ports only (as TreeNodesModel files
                # exported by Groot2 often have them): it holds text.
                s.kind = "string"
                s.origin = "no declared type, written by untyped ports only: it holds text"
                s.origin_loc = None
                s.untyped_text = True
                continue
            s.failed = True
            if any(x.determining for x in s.writes):
                self.error(
                    w.loc,
                    f"cannot tell the type of blackboard entry `{s.key}`: every write copies "
                    f"another entry of unknown type; write it with a literal first",
                )
            elif all(x.source == "script" for x in s.writes):
                self.error(
                    w.loc,
                    f"blackboard entry `{s.key}` is only updated ({w.what}), never given a first "
                    f"value, so it never has one; initialize it first (e.g. `{s.key} := 0`)",
                )
            else:
                self.error(
                    w.loc,
                    f"cannot tell the type of blackboard entry `{s.key}`: {w.what} writes it, but "
                    f"the port has no type; give the port a type in TreeNodesModel (e.g. "
                    f'type="std::string")',
                )
            s.kind = "string"
        self.mark_dynamic()

    def mark_dynamic(self) -> None:
        """Entries whose type 4.6.2 changes at run time get a dynamic slot (btgen::Dyn).

        Only entries no typed port declared (`any`) can change their type: a write of
        another kind than the entry's (a SetBlackboard literal into an integer entry, a
        string assigned to an entry a script made a number, a copy of such an entry) makes
        it dynamic, and so does a write of a dynamic value; expressions over it are then
        dynamic too, so this runs until nothing changes. Numbers of two kinds (integer and
        double) written by scripts are conversions, not type changes: those entries stay
        static; a SetBlackboard copy of another kind of number replaces the value's type."""
        for s in self.slots:
            self._mark_typed_number_dynamic(s)
        changed = True
        while changed:
            changed = False
            for s in self.slots:
                if (
                    s.kind == DYN
                    or s.failed
                    or s.entry.type_name != values.ANY
                    or s.initial is not None
                    or s.untyped_text
                    or s.kind is None
                    or is_queue(s.kind)
                    or (s.kind == "none" and not s.writes)
                    or is_user(s.kind)
                ):  # (a user type's entry: other writes are errors, reported as such)
                    continue
                for w in s.writes:
                    if w.source in ("port", "loop"):
                        continue
                    k = w.kind()
                    if k is None or k in ("none", "error") or is_queue(k):
                        continue
                    if s.kind == "none" and k != DYN:
                        continue  # (a script that fails whatever runs: compiling it says why)
                    if (
                        k == DYN
                        or (k == "string") != (s.kind == "string")
                        or (k == "status") != (s.kind == "status")
                        or (w.source == "copy" and k != s.kind)
                    ):
                        # (a SetBlackboard copy is set<Any>: it replaces an untyped entry's value with the
                        # source's, an integer stays an integer in a double entry)
                        s.kind = DYN
                        s.origin = f"its type changes at run time ({w.what} writes {describe_kind(k)})"
                        s.origin_loc = w.loc
                        changed = True
                        break

    def _mark_typed_number_dynamic(self, s: _Slot) -> None:
        """A typed number entry (a port declared it `int` or `double`) that a script may give
        its first value with the other kind of number (`speed := 1` for a double port): 4.6.2's
        Any::copyInto into the empty entry stores the value as it is, so the entry then holds
        an integer (and converts later writes to integers). Its slot is dynamic so the C++
        engine follows (it stopped with "would store an integer in the empty entry")."""
        if (
            s.kind not in ("int", "double")
            or s.failed
            or s.initial is not None
            or kind_of_type(s.entry.type_name) != s.kind
        ):
            return
        kinds = [w.kind() for w in s.writes]
        if any(k not in ("int", "double", None) for k in kinds):
            return  # (strings go through the declared type's converter: a static slot does that)
        for w, k in zip(s.writes, kinds):
            if w.source == "script" and w.determining and k in ("int", "double") and k != s.kind:
                s.kind = DYN
                s.origin = (
                    f"4.6.2 stores the other kind of number as it is in the empty entry ({w.what} writes "
                    f"{describe_kind(k)})"
                )
                s.origin_loc = w.loc
                return

    # ------------------------------------------------------------ 4. sizes
    def size_slots(self) -> None:
        cap = self.opt.string_capacity
        for s in self.slots:
            if s.kind in ("string", DYN):
                s.capacity = 0
        # Queues first: a Loop's `value` is as long as the longest element of its queue (edges L3).
        for s in self.slots:
            if is_queue(s.kind):
                qcap = self.opt.queue_capacity
                s.capacity = max(s.queue_literals, default=0)
                if s.queue_unbounded or not s.queue_literals:
                    s.capacity = max(s.capacity, qcap) if s.queue_unbounded else s.capacity
                s.capacity = max(s.capacity, 1)
                if s.kind == "queue<string>":
                    s.elem_capacity = max(s.elem_literals, default=0)
                    if s.queue_unbounded:
                        s.elem_capacity = cap
                    s.elem_capacity = min(s.elem_capacity, cap)
        # Capacities only grow. A literal (and robot code, whose bound is unknown) gets at
        # most `cap`: a longer literal is an error where it is written. A computed value
        # whose bound btgen knows (`'a' .. 1e300`: 318 bytes) gets its bound even above
        # `cap`, or the executor would fail where 4.6.2 succeeds. A slot whose bound
        # depends on itself (`s := s .. 'x'`, possibly through other slots) grows a little
        # every round; after WIDEN_AFTER growths it is taken to grow without bound and gets
        # `cap` for good, so every slot changes at most WIDEN_AFTER + 1 times.
        growths = [0] * len(self.slots)
        changed = True
        rounds = 0
        while changed:
            changed = False
            rounds += 1
            for i, s in enumerate(self.slots):
                if s.kind not in ("string", DYN) or growths[i] > WIDEN_AFTER:
                    continue
                best = s.capacity
                for w in s.writes:
                    if s.kind == DYN and is_numeric(w.kind()):
                        continue  # a dynamic slot holds numbers as numbers
                    b = w.bound()
                    b = cap if b is None else min(b, cap) if w.literal is not None else b
                    best = max(best, b)
                if best > s.capacity:
                    growths[i] += 1
                    s.capacity = cap if growths[i] > WIDEN_AFTER else best
                    changed = True
            if rounds > (WIDEN_AFTER + 2) * len(self.slots) + 2:
                raise InternalError("string capacities do not settle")

    # ------------------------------------------------------------ naming
    def name_slots(self) -> None:
        owner_of: dict[int, tuple[str, str, int]] = {}
        for bb in self.bbs:
            for key in bb.local_keys():
                entry = bb._storage[key]
                owner_of[id(entry)] = (self.bb_labels[id(bb)], key, self.bb_uid.get(id(bb), 0))
        raw_names = []
        for s in self.slots:
            owner, key, s.owner_uid = owner_of.get(id(s.entry), ("root", "?", 0))
            s.owner, s.key = owner, key
            raw_names.append(key if owner == "root" else f"{owner}_{key}")
        members = entry_identifiers(raw_names)
        for s, mname in zip(self.slots, members):
            s.member = mname

    # ------------------------------------------------------------ 5. decide
    def slot_type(self, i: int) -> SlotType:
        s = self.slots[i]
        return SlotType(s.key, s.kind or "none", s.entry.type_name, s.capacity, s.origin_text)


def _end_offset(node: sc.Expr, code: str) -> int:
    """The offset after an assignment's text (for messages): the next `;` at depth 0, or the end."""
    depth = 0
    quote = ""
    for i in range(node.offset, len(code)):
        c = code[i]
        if quote:
            if c == quote:
                quote = ""
            continue
        if c in "'\"":
            quote = c
        elif c == "(":
            depth += 1
        elif c == ")":
            if depth == 0:
                return i
            depth -= 1
        elif c == ";" and depth == 0:
            return i
    return len(code)


# ================================================================ compile

TYPE_NAME_OF_KIND = {
    "int": values.INT,
    "double": values.DOUBLE,
    "bool": values.BOOL,
    "string": values.STRING,
    "status": values.NODE_STATUS,
}


class _Compiler:
    """Step 5: every data operation decided over the typed and sized slots (ir/dataops.py
    records; scripts: compiled by backend_cpp/script_cpp.py), and the errors that would
    happen whenever one runs reported."""

    def __init__(self, a: _Analyzer) -> None:
        self.a = a
        self.types = [a.slot_type(i) for i in range(len(a.slots))]
        self.where_locs: list[Loc] = []
        self.where_index: dict[Loc, int] = {}
        self.user_locals: list[LocalIR] = []  # converted literals of user-typed ports
        self.user_inits: list[DataOp] = []
        self.bt_any_slots: set[int] = set()  # slots a SetBlackboard string may leave typed BT::Any

    def where(self, loc: Loc) -> int:
        """The index of `loc` among the places run-time errors name (DataIR.where)."""
        idx = self.where_index.get(loc)
        if idx is None:
            idx = self.where_index[loc] = len(self.where_locs)
            self.where_locs.append(loc)
        return idx

    def error(self, loc: Loc, message: str) -> None:
        self.a.error(loc, message)

    def fail(self, where: Loc, message: str, errc: bool = False) -> ops.Fail:
        return ops.Fail(self.where(where), message, errc)

    # ------------------------------------------------------------ typed writes
    def typed_write_ok(self, slot: int, type_name: str, loc: Loc, what: str) -> bool:
        """Blackboard::set<T> of a T into the slot: what btgen::port::write does, checked where it
        fails (or would change the entry's type) whenever it runs."""
        s = self.a.slots[slot]
        declared = s.entry.type_name
        k = kind_of_type(type_name)
        if s.kind == DYN:
            self.error(
                loc,
                f"{what} writes {describe_kind(k or 'none')} ({type_name}) to blackboard entry "
                f"`{s.key}`, whose type changes at run time ({s.origin_text}); typed writes into "
                f"such entries are not supported by the C++ back end yet",
            )
            return False
        if declared == values.ANY or values.is_opaque_type(declared) or declared == type_name:
            ok = k == s.kind
        elif type_name == values.STRING:
            ok = declared != values.NODE_STATUS and kind_of_type(declared) == s.kind
        else:
            ok = type_name in (values.INT, values.UNSIGNED, values.DOUBLE, values.BOOL) and declared in (
                values.INT,
                values.UNSIGNED,
                values.DOUBLE,
            )
        if not ok:
            self.error(
                loc,
                f"{what} writes {describe_kind(k or 'none')} ({type_name}) to blackboard entry "
                f"`{s.key}`, which holds {describe_kind(s.kind or 'none')} ({s.origin_text}); btgen "
                f"gives every entry one type",
            )
        return ok

    # ------------------------------------------------------------ scripts
    def scripts(self) -> tuple[list[ScriptIR], dict[int, int]]:
        out: list[ScriptIR] = []
        bits: dict[int, int] = {}
        for inst, attr, which, script, names, condition in self.a.script_uses:
            if not self.check_reads(inst, attr, script, names):
                continue
            if any(self.a.slots[i].failed for i in names.values()):
                continue  # its entry's type is already reported as unknown
            if not self.check_user_free(inst, attr, script, names):
                continue
            try:
                typed = type_script(script, self.types, names, condition)
            except ScriptTypeError as e:
                self.error(script_loc(attr, e.offset), f"`{attr.name}` of {inst.what}: {e.message}")
                continue
            enum = SCRIPT_SLOTS[which]
            out.append(
                ScriptIR(
                    inst.index,
                    f'{inst.reg_id} "{inst.node.display_name}" {attr.name}: {attr.value}',
                    enum,
                    attr,
                    script,
                    tuple(sorted(names.items())),
                    condition,
                    f"script error in `{attr.name}` of {inst.what}: ",
                    typed,
                )
            )
            if enum != "kCode":
                bits[inst.index] = bits.get(inst.index, 0) | (1 << SCRIPT_BIT[enum])
        return out, bits

    def check_user_free(self, inst: _Inst, attr: Attr, script: sc.Script, names: dict[str, int]) -> bool:
        """Scripts neither read nor write entries of user port types (`--type`): the script
        language knows numbers, strings and statuses only. False: reported."""
        for stmt in script.statements:
            for node in sc.walk(stmt):
                key = node.name if isinstance(node, sc.Name) else node.target if isinstance(node, sc.Assign) else None
                if key is None:
                    continue
                s = self.a.slots[names[key]]
                if is_user(s.kind):
                    t = self.a.user[s.kind]
                    verb = "reads" if isinstance(node, sc.Name) else "writes"
                    self.error(
                        script_loc(attr, node.offset),
                        f"`{attr.name}` of {inst.what} {verb} `{key}`, an entry of user type {t.name} "
                        f"({t.cpp_type}, --type {t.name}); scripts cannot use user-typed entries (read and "
                        f"write them from your nodes through their typed ports)",
                    )
                    return False
        return True

    def check_reads(self, inst: _Inst, attr: Attr, script: sc.Script, names: dict[str, int]) -> bool:
        """A name read that can never find its entry: nothing anywhere creates it. False: reported."""
        ok = True
        for stmt in script.statements:
            for node in sc.walk(stmt):
                if isinstance(node, sc.Name):
                    s = self.a.slots[names[node.name]]
                    if not s.at_load and not s.writes:
                        if node.name.startswith("@"):
                            known = {"@" + k for k in self.created_keys(inst.bb.root)}
                        else:
                            known = self.created_keys(inst.bb)
                        hint = did_you_mean(node.name, known - {node.name})
                        advice = f"did you mean `{hint}`?" if hint else f"create it with `{node.name} := ...` first"
                        bb = inst.bb
                        if (
                            bb.parent is not None
                            and not bb.autoremap
                            and not node.name.startswith("@")
                            and node.name not in bb.remapping
                            and node.name in self.created_keys(bb.parent)
                        ):
                            advice = (
                                f"the calling tree's `{node.name}` is not seen here: the SubTree node does "
                                f'not remap it; add {node.name}="{{{node.name}}}" or _autoremap="true"'
                            )
                        self.error(
                            script_loc(attr, node.offset),
                            f"`{attr.name}` of {inst.what} reads `{node.name}`, but nothing creates that "
                            f"blackboard entry: no port, script or SetBlackboard writes it ({advice})",
                        )
                        ok = False
        return ok

    def created_keys(self, bb: bbmod.Blackboard) -> set[str]:
        """The keys a script on `bb` can name whose entries something creates: its own and
        remapped keys, and through `_autoremap` its parent's (the candidates of a hint)."""
        keys: set[str] = set(bb.local_keys()) | set(bb.remapping)
        if bb.parent is not None and bb.autoremap:
            keys |= {k for k in self.created_keys(bb.parent) if not k.startswith("_")}
        out = set()
        for key in keys:
            entry = bb.get_entry(key)
            idx = self.a.slot_of_entry.get(id(entry)) if entry is not None else None
            if idx is not None and (self.a.slots[idx].at_load or self.a.slots[idx].writes):
                out.add(key)
        return out

    # ------------------------------------------------------------ data nodes
    def unset(self, inst: _Inst, op: dict) -> DataOp:
        key = op["key"]
        entry = inst.bb._storage.get(key)
        slot = self.a.slot_of_entry[id(entry)] if entry is not None else None
        return DataOp(inst.index, f'UnsetBlackboard "{inst.node.display_name}" key={key}', ops.Unset(slot, key))

    def mark_unsets(self) -> None:
        """Entries UnsetBlackboard can remove may be missing when a script runs."""
        for kind, inst, op in self.a.node_ops:
            if kind != "unset":
                continue
            entry = inst.bb._storage.get(op["key"])
            if entry is None:
                continue
            s = self.a.slots[self.a.slot_of_entry[id(entry)]]
            key = op["key"]
            if s.initial is not None and (key in inst.bb.remapping or (inst.bb.autoremap and not key.startswith("_"))):
                self.error(
                    op["loc"],
                    f"UnsetBlackboard of `{key}`, a constant port of its SubTree, would make "
                    f"`{key}` reach the parent's entry afterwards; the C++ back end resolves keys "
                    f"once, so it cannot follow that",
                )
            s.unset = True

    def set_literal(self, inst: _Inst, op: dict) -> Optional[DataOp]:
        dst, text, loc = op["dst"], op["text"], op["loc"]
        s = self.a.slots[dst]
        declared = s.entry.type_name
        what = f'`SetBlackboard` "{inst.node.display_name}"'
        comment = f'SetBlackboard "{inst.node.display_name}" {s.key} = {text!r}'
        if self._untyped_dyn_write_unsupported(s, loc, what):
            return None
        prefix = f"{what}: SetBlackboard: cannot convert {values.describe(text)}: "
        untyped = self._untyped_dst(inst, op, s, what, prefix)
        if is_user(s.kind):
            # 4.6.2 converts the text with the entry's convertFromString on every tick; it never
            # changes, so it is converted once, when the mission is constructed, and copied here.
            t = self.a.user[s.kind]
            member = self.user_constant(
                inst.index, t, text, loc, f"`value` of {what} (`{text}`, for `{s.key}`)", f"`value` of {what}"
            )
            fail = self.fail(loc, f"{what}: `{text}` does not convert to {t.name} ({t.cpp_type}) for `{s.key}`")
            return DataOp(inst.index, comment, ops.SetUserLiteral(dst, member, fail))
        if s.kind == DYN:
            if len(text.encode("utf-8")) > s.capacity:
                self.error(loc, self.overflow_message(text, s))
                return None
            return DataOp(inst.index, comment, ops.SetDynLiteral(dst, text, op["key"], what + ": ", self.where(loc)))
        if declared not in (values.ANY, values.STRING) and not values.is_opaque_type(declared):
            if declared == values.NODE_STATUS:
                self.error(
                    loc,
                    f"{what} writes the text `{text}` to `{s.key}`, a NodeStatus entry, which "
                    f"BehaviorTree.CPP cannot convert text into",
                )
                return None
            try:
                values.convert_from_string(declared, text)
            except values.ConversionError as e:
                self.error(loc, f"{what} writes `{text}` to `{s.key}`, which is declared {declared}: {e}")
                return None
        elif s.kind != "string":
            self.error(
                loc,
                f"{what} writes the text `{text}` to blackboard entry `{s.key}`, which holds "
                f"{describe_kind(s.kind or 'none')} ({s.origin_text}); BehaviorTree.CPP would "
                f'replace the value with the string "{text}", and btgen gives every entry one type '
                f"(to write a number, use a Script: `{s.key} := {text}`)",
            )
            return None
        if s.kind == "string" and len(text.encode("utf-8")) > s.capacity:
            self.error(loc, self.overflow_message(text, s))
            return None
        fail = self.fail(loc, f"{what} cannot write `{s.key}`", errc=True)
        return DataOp(inst.index, comment, ops.SetText(dst, declared, text, fail, untyped))

    def overflow_message(self, text: str, s: _Slot) -> str:
        return kinds.overflow_message(text, s.key, s.capacity)

    def set_copy(self, inst: _Inst, op: dict) -> Optional[DataOp]:
        dst, src, loc = op["dst"], op["src"], op["loc"]
        d, s = self.a.slots[dst], self.a.slots[src]
        what = f'`SetBlackboard` "{inst.node.display_name}"'
        declared = d.entry.type_name if d.at_load else s.entry.type_name
        if s.kind == "string" and self._untyped_dyn_write_unsupported(d, loc, what):
            return None
        untyped = None
        if s.kind == "string":
            untyped = self._untyped_dst(
                inst, op, d, what, f"{what}: SetBlackboard: cannot convert {values.describe(op['raw'])}: ", s
            )
        strong = values.is_strongly_typed(declared)
        convert = False
        if is_queue(s.kind):
            self.error(
                loc,
                f"{what} copies the queue `{s.key}`; BehaviorTree.CPP would share one queue between "
                f"both entries, which the C++ back end does not do",
            )
            return None
        if DYN in (d.kind, s.kind) and not (is_user(d.kind) or is_user(s.kind)):
            return self.set_copy_dynamic(inst, op, d, s, what)
        if is_user(d.kind) or is_user(s.kind):
            ok = d.kind == s.kind
        elif not strong:
            ok = s.kind == d.kind
        elif s.kind == "string" and declared != values.STRING:
            ok = declared != values.NODE_STATUS and not values.is_opaque_type(declared)
            convert = True
        else:
            ok = TYPE_NAME_OF_KIND.get(s.kind or "") == declared
        if not ok:
            dst_what = f"declared {declared}" if strong else d.origin_text
            self.error(
                loc,
                f"{what} copies `{s.key}` ({describe_kind(s.kind or 'none')}, {s.origin_text}) to "
                f"`{d.key}` ({describe_kind(d.kind or 'none')}, {dst_what}); BehaviorTree.CPP "
                f"refuses that copy or changes the entry's type",
            )
            return None
        missing = self.fail(loc, f"{what}: `value` reads blackboard entry `{op['src_key']}`, which does not exist")
        fail: Optional[ops.Fail] = None
        if convert:
            how = "convert"
            fail = self.fail(loc, f"{what} cannot convert `{s.key}` for `{d.key}`", errc=True)
        elif d.kind == "string":
            how = "string"
            fail = self.fail(loc, f"{what}: the text of `{s.key}` does not fit `{d.key}` (capacity {d.capacity} bytes)")
        else:
            how = "none" if d.kind == "none" else "value"
        return DataOp(
            inst.index,
            f'SetBlackboard "{inst.node.display_name}" {d.key} = {{{s.key}}}',
            ops.SetCopy(dst, src, how, declared, missing, fail, self._empty_copy_succeeds(), untyped),
        )

    def set_copy_dynamic(self, inst: _Inst, op: dict, d: _Slot, s: _Slot, what: str) -> Optional[DataOp]:
        """SetBlackboard value="{src}" where the destination's or the source's type changes at run time."""
        loc = op["loc"]
        src_decl = s.entry.type_name
        if d.kind != DYN or (s.kind != DYN and src_decl not in (values.ANY, values.STRING)):
            self.error(
                loc,
                f"{what} copies `{s.key}` ({describe_kind(s.kind or 'none')}, {s.origin_text}) to "
                f"`{d.key}` ({describe_kind(d.kind or 'none')}, {d.origin_text}); copies between "
                f"typed entries and entries whose type changes at run time are not supported by the "
                f"C++ back end yet",
            )
            return None
        missing = self.fail(
            loc, f"{what}: SetBlackboard: `value` reads blackboard entry `{op['src_key']}`, which does not exist"
        )
        return DataOp(
            inst.index,
            f'SetBlackboard "{inst.node.display_name}" {d.key} = {{{s.key}}}',
            ops.SetCopyDyn(
                op["dst"],
                op["src"],
                src_decl == values.STRING,
                op["key"],
                what + ": ",
                missing,
                self.where(loc),
                self._empty_copy_succeeds(),
            ),
        )

    def _untyped_dst(
        self, inst: _Inst, op: dict, d: _Slot, what: str, prefix: str, src: Optional[_Slot] = None
    ) -> Optional[ops.UntypedDst]:
        """From 4.7.0 SetBlackboard converts a string with the converter of the entry it writes;
        an entry that exists without a type (created at load by an untyped `{key}` port, by a
        Script, or holding a SubTree literal) has none: the library leaves it empty and typed
        BT::Any, and throws on the next such write. Whether an entry no port declared is typed
        is known at run time only (Slot::entry_type): the record of what the write does then,
        for a string slot declared `any` (None for any other)."""
        if not self.a.m.semantics.setblackboard_converts_to_entry_type or d.entry.type_name != values.ANY:
            return None
        if d.kind != "string":
            return None
        key = op["key"]
        target = inst.bb.root if key.startswith("@") else inst.bb
        local = target._storage.get(key[1:] if key.startswith("@") else key) is d.entry
        src_type = "typed"
        if src is not None and src.entry.type_name == values.ANY:
            src_type = "dynamic"
        if local or src_type == "dynamic":  # (a copy creates a missing entry with the source's type)
            self.bt_any_slots.add(self.a.slots.index(d))
        return ops.UntypedDst(local, src_type, prefix, self.where(op["loc"]))

    def _untyped_dyn_write_unsupported(self, d: _Slot, loc: Loc, what: str) -> bool:
        """The rule of _untyped_dst for an entry whose type changes at run time (a dynamic
        slot): the generated C++ does not model that yet, so it refuses the mission rather than
        run it differently (docs/btcpp-versions.md). True when it reported that."""
        if not self.a.m.semantics.setblackboard_converts_to_entry_type or d.entry.type_name != values.ANY:
            return False
        if d.kind != DYN or not (d.at_load or any(w.source == "script" for w in d.writes)):
            return False
        self.error(
            loc,
            f"{what} writes a string into `{d.key}`, an entry created without a type whose type changes at "
            f"run time ({d.origin_text}); BehaviorTree.CPP {self.a.m.semantics.version} leaves such an entry "
            f"empty and typed BT::Any (and throws on the next such write), which is not supported by the C++ "
            f"back end yet",
        )
        return True

    def _empty_copy_succeeds(self) -> bool:
        """4.6.2 copies an empty value; from 4.7.0 the node fails (setblackboard_converts_to_entry_type)."""
        return bbmod.EMPTY_COPY_SUCCEEDS and not self.a.m.semantics.setblackboard_converts_to_entry_type

    def param_read(self, inst: _Inst, op: dict) -> Optional[DataOp]:
        """A loop count or duration given as `{key}`: getInput<int|unsigned> of an integer entry."""
        s = self.a.slots[op["slot"]]
        what = f'`{inst.reg_id}` "{inst.node.display_name}": port `{op["port"]}` reads blackboard entry `{op["key"]}`'
        constant: Optional[int] = None
        if (
            s.kind == "string"
            and s.initial is not None
            and not s.unset
            and all(w.source == "constant" for w in s.writes)
        ):
            # A SubTree's constant port (`n="3"`): text that never changes, converted once here
            # as 4.6.2's getInput converts it on every read.
            port_type = values.UNSIGNED if op["port"] in ("msec", "delay_msec") else values.INT
            try:
                converted = values.convert_from_string(port_type, s.initial)
            except values.ConversionError as e:
                self.error(op["loc"], f"{what}: {e}")
                return None
            constant = converted if isinstance(converted, int) else 0  # (int and unsigned convert to int)
        elif s.kind != "int":
            self.error(
                op["loc"],
                f"port `{op['port']}` of {inst.what} reads `{s.key}` ({describe_kind(s.kind or 'none')}, "
                f"{s.origin_text}); the C++ back end reads it from an integer entry only",
            )
            return None
        return DataOp(
            inst.index,
            f'{inst.reg_id} "{inst.node.display_name}" {op["port"]}={{{op["key"]}}}',
            ops.ParamRead(
                op["slot"],
                self.fail(op["loc"], f"{what}, which does not exist"),
                self.fail(op["loc"], f"{what}, which has no value yet"),
                constant,
            ),
        )

    def entry(self, inst: _Inst, op: dict) -> DataOp:
        return DataOp(
            inst.index, f'{inst.reg_id} "{inst.node.display_name}" entry={op["key"]}', ops.EntrySeq(op["slot"])
        )

    @staticmethod
    def operand(slot: Optional[int], raw: Optional[str]) -> ops.TextOperand:
        """getInput<std::string> of a Switch's variable or case label."""
        if raw is None:
            return ops.TextOperand()
        return ops.TextOperand(slot, raw if slot is None else None)

    def switch(self, inst: _Inst, op: dict) -> DataOp:
        reads = op["reads"]
        _name, raw, slot = reads[0]
        labels = tuple(self.operand(cslot, craw) for _cname, craw, cslot in reads[1:])
        return DataOp(
            inst.index,
            f'{inst.reg_id} "{inst.node.display_name}"',
            ops.SwitchCases(op["cases"], self.operand(slot, raw), labels),
        )

    def loop(self, inst: _Inst, op: dict, locals_: list[LocalIR]) -> Optional[DataOp]:
        elem, static, qslot, vslot, loc = op["elem"], op["static"], op["qslot"], op["vslot"], op["loc"]
        what = f'`{inst.reg_id}` "{inst.node.display_name}"'
        local, items, no_value = "", (), None
        if static is not None:
            local, items = f"loop_{inst.index}", tuple(static)
            cap = max((len(x.encode("utf-8")) for x in static), default=0) if elem == "string" else 0
            locals_.append(
                LocalIR(
                    local,
                    f"{what}: its literal queue, copied afresh each time it starts (4.7.0)",
                    elem,
                    max(len(static), 1),
                    cap,
                )
            )
        else:
            assert qslot is not None
            s = self.a.slots[qslot]
            want = f"queue<{elem}>"
            if s.kind != want and self.a.m.semantics.loop_queue_untyped and not is_user(s.kind):
                return self.loop_untyped(inst, op, locals_)
            if s.kind != want:
                self.error(
                    loc,
                    f"port `queue` of {what} reads blackboard entry `{s.key}`, which holds "
                    f"{describe_kind(s.kind or 'none')} ({s.origin_text}), not a {want}",
                )
                return None
            no_value = self.fail(
                loc, f"port `queue` of {what} reads blackboard entry `{s.key}`, which has no value yet"
            )
        declared, write_fail = "", None
        if vslot is not None:
            vloc = inst.ports["value"].loc_or or inst.node.loc
            if not self.typed_write_ok(vslot, elem, vloc, f"port `value` of {what}"):
                return None
            declared = self.a.slots[vslot].entry.type_name
            write_fail = self.fail(vloc, f"{what} cannot write its `value`", errc=True)
        return DataOp(
            inst.index,
            f"{what} queue={inst.ports['queue'].raw}",
            ops.LoopPop(elem, local, items, qslot, no_value, vslot, declared, write_fail),
        )

    def loop_untyped(self, inst: _Inst, op: dict, locals_: list[LocalIR]) -> Optional[DataOp]:
        """From 4.9.1 a Loop's `queue` port is untyped: an entry holding a string is converted
        into a private queue each time the loop starts (the interpreter's
        _queue_from_blackboard_410); one without a value, or holding anything but a string or
        a queue of the element type, makes the node throw."""
        elem, qslot, vslot, loc = op["elem"], op["qslot"], op["vslot"], op["loc"]
        s = self.a.slots[qslot]
        what = f'`{inst.reg_id}` "{inst.node.display_name}"'
        read = f"port `queue` of {what} reads blackboard entry `{op['qkey']}`, which"
        must = f": it must hold a queue<{elem}> or a string"
        source, text_local = "scalar", ""
        if s.kind in ("string", DYN):
            source, text_local = "text", f"loopq_{inst.index}"
            locals_.append(
                LocalIR(
                    text_local,
                    f"{what}: its queue, converted from the text of `{s.key}` when it starts (4.9.1)",
                    text_capacity=max(s.capacity, 1),
                )
            )
        elif s.kind == "none":
            source = "none"
        elif is_queue(s.kind):
            self.error(loc, f"port `queue` of {what} reads blackboard entry `{s.key}`, a {s.kind}, not a queue<{elem}>")
            return None
        declared, write_fail = "", None
        if vslot is not None:
            vloc = inst.ports["value"].loc_or or inst.node.loc
            if not self.typed_write_ok(vslot, elem, vloc, f"port `value` of {what}"):
                return None
            declared = self.a.slots[vslot].entry.type_name
            write_fail = self.fail(vloc, f"{what} cannot write its `value`", errc=True)
        return DataOp(
            inst.index,
            f"{what} queue={inst.ports['queue'].raw}",
            ops.LoopPop(
                elem,
                "",
                (),
                qslot,
                self.fail(loc, f"{read} has no value{must}"),
                vslot,
                declared,
                write_fail,
                source,
                text_local,
                f"{read} holds ",
                f"port `queue` of {what}: ",
                self.where(loc),
            ),
        )

    # ------------------------------------------------------------ user port types
    def user_cpp(self, type_name: str) -> str:
        """A user port type's C++ spelling (--type); "" for the built-in types."""
        k = kind_of_type(type_name)
        return self.a.user[k].cpp if is_user(k) else ""

    def user_read(self, inst: _Inst, ps: PortSpec, slot: Optional[int], raw: str, loc: Loc) -> Optional[ops.PortRead]:
        """The getter statement of an input port where a user type (--type) is involved: a literal
        converted once when the mission is constructed, or the entry's value as it is."""
        pk = kind_of_type(ps.type)
        if slot is None:  # a literal (or a TreeNodesModel default) of a user-typed port
            return self.user_literal(inst, ps, raw, loc, f"`{raw}`")
        s = self.a.slots[slot]
        if is_user(pk) and s.initial is not None and not s.unset and all(w.source == "constant" for w in s.writes):
            # A SubTree's constant port that nothing else writes: a literal too (4.6.2 converts its
            # text on every read; it never changes).
            return self.user_literal(
                inst,
                ps,
                s.initial,
                s.writes[0].loc if s.writes else loc,
                f"`{s.initial}` (the constant port `{s.key}` of its SubTree)",
            )
        if is_user(pk) and s.kind == pk:
            return ops.ReadUser(slot)
        if pk is None and is_user(s.kind):  # an untyped port: get<T>() with T the entry's type
            return ops.ReadUser(slot, as_t=True)
        if any(at == loc for at, _ in self.a.reported):
            return None  # (its entry's type clash is reported here already, as 4.6.2's loader reports it)
        if is_user(pk):
            t = self.a.user[pk]
            self.error(
                loc,
                f"port `{ps.name}` of {inst.what} ({t.name}) reads blackboard entry `{s.key}`, which holds "
                f"{describe_kind(s.kind or 'none')} ({s.origin_text}); a {t.name} port reads only "
                f"{t.name} entries in the C++ back end (BehaviorTree.CPP would convert a string with "
                f"convertFromString<{t.name}> on every read)",
            )
        else:
            self.error(
                loc,
                f"port `{ps.name}` of {inst.what} ({ps.type}) reads blackboard entry `{s.key}`, which "
                f"holds {describe_kind(s.kind or 'none')} ({s.origin_text}); it does not convert to "
                f"{ps.type}",
            )
        return None

    def user_literal(self, inst: _Inst, ps: PortSpec, raw: str, loc: Loc, what: str) -> ops.PortRead:
        """A user-typed port's literal: converted once, when the mission is constructed (Spec::init)."""
        t = self.a.user[kind_of_type(ps.type) or ""]
        member = self.user_constant(
            inst.index, t, raw, loc, f"port `{ps.name}` of {inst.what}: {what}", f"port `{ps.name}` of {inst.what}"
        )
        return ops.ReadUserLiteral(member)

    def user_constant(self, node: int, t, raw: str, loc: Loc, what: str, comment: str) -> str:
        """A `btgen::UserLiteral` member of the blackboard holding `raw` converted to the user type `t` when
        the mission is constructed (Spec::init; a failure is reported there, naming `what`); its name."""
        member = f"ulit{len(self.user_locals)}_"
        self.user_locals.append(
            LocalIR(
                member,
                f"{comment}: {values.describe(raw)} as a {t.name}, converted when the mission is constructed",
                user_cpp=t.cpp,
            )
        )
        message = f"{what} does not convert to {t.name} ({t.cpp_type}): its convertFromString returned false"
        self.user_inits.append(DataOp(node, comment, ops.UserInit(member, raw, self.fail(loc, message))))
        return member

    def user_write(self, inst: _Inst, ps: PortSpec, slot: int, loc: Loc) -> Optional[ops.PortWrite]:
        """The setter of an output port where a user type (--type) is involved."""
        s = self.a.slots[slot]
        pk = kind_of_type(ps.type)
        what = f"output port `{ps.name}` of {inst.what}"
        if pk is None and is_user(s.kind):  # an untyped port: set<T>() with T the entry's type
            t = self.a.user[s.kind or ""]
            fail = self.fail(loc, f"{what} writes a value of another type than {t.name} ({t.cpp_type}) to `{s.key}`")
            return ops.WriteUser(slot, t.cpp, fail)
        if any(at == loc for at, _ in self.a.reported):
            return None  # (its entry's type clash is reported here already, as 4.6.2's loader reports it)
        if not self.typed_write_ok(slot, ps.type, loc, what):
            return None
        return ops.WriteUser(slot)

    # ------------------------------------------------------------ user leaf ports
    def ports(self) -> dict:
        by_model: dict[str, dict[str, dict]] = {}
        for kind, inst, op in self.a.node_ops:
            if kind != "port":
                continue
            ps: PortSpec = op["port"]
            model = by_model.setdefault(inst.reg_id, {})
            entry = model.setdefault(ps.name, {"spec": ps, "reads": [], "writes": [], "scratch": False})
            slot, raw, p = op["slot"], op["raw"], op["p"]
            loc = p.loc_or or inst.node.loc
            if values.queue_element_type(ps.type) is not None:
                self.error(
                    loc,
                    f"port `{ps.name}` of {inst.what} is a queue ({ps.type}); queue ports of user "
                    f"nodes are not supported by the C++ back end yet",
                )
                continue
            pk = kind_of_type(ps.type)
            # Ports read as text: string and opaque types, and untyped ports (whose T may be text).
            textual = ps.type in (values.ANY, values.STRING) or (values.is_opaque_type(ps.type) and not is_user(pk))
            if ps.reads and (is_user(pk) or (slot is not None and is_user(self.a.slots[slot].kind))):
                read = self.user_read(inst, ps, slot, raw, loc)
                if read is None:
                    continue
                entry["reads"].append((inst.index, read))
            elif ps.reads:
                if slot is not None:
                    s = self.a.slots[slot]
                    if is_queue(s.kind):
                        self.error(loc, f"port `{ps.name}` of {inst.what} reads blackboard entry `{s.key}`, a {s.kind}")
                        continue
                    text = textual and (is_numeric(s.kind) or s.kind == DYN)
                    if text:
                        entry["scratch"] = True
                    entry["reads"].append((inst.index, ops.ReadEntry(slot, text)))
                elif ps.type != values.ANY:
                    try:
                        value = values.convert_from_string(
                            ps.type if not values.is_opaque_type(ps.type) else values.STRING, raw
                        )
                        entry["reads"].append((inst.index, ops.ReadLiteral(ps.type, value)))
                    except values.ConversionError:
                        entry["reads"].append((inst.index, ops.ReadLiteral(ps.type, None, ok=False)))
                else:
                    entry["reads"].append((inst.index, ops.ParseLiteral(raw)))
            if ps.writes and slot is not None and (is_user(pk) or is_user(self.a.slots[slot].kind)):
                write = self.user_write(inst, ps, slot, loc)
                if write is not None:
                    entry["writes"].append((inst.index, write))
            elif ps.writes and slot is not None:
                if ps.type != values.ANY and not self.typed_write_ok(
                    slot,
                    ps.type if not values.is_opaque_type(ps.type) else values.STRING,
                    loc,
                    f"output port `{ps.name}` of {inst.what}",
                ):
                    continue
                s = self.a.slots[slot]
                fail = self.fail(loc, f"output port `{ps.name}` of {inst.what} cannot write `{s.key}`", errc=True)
                entry["writes"].append((inst.index, ops.WriteEntry(slot, s.entry.type_name, fail)))
        # Every port a leaf model declares gets its accessors, wired here or not (one leaf
        # implementation builds against every mission using the model): in declaration order,
        # with 4.6.2's result on an instance that does not set it (getInput fails: kNotSet;
        # setOutput fails: false). Queue ports have no C++ type yet (rejected when wired).
        declared: dict[str, dict[str, dict]] = {}
        for spec in self.a.m.used_user_models():
            used = by_model.get(spec.id, {})
            model = declared.setdefault(spec.id, {})
            for ps in spec.ports:
                if ps.name in used:
                    model[ps.name] = used[ps.name]
                elif values.queue_element_type(ps.type) is None:
                    model[ps.name] = {"spec": ps, "reads": [], "writes": [], "scratch": False}
        by_model = declared
        out: dict[str, tuple[PortIR, ...]] = {}
        model_ids = [m.id for m in self.a.m.user_models()]
        classes = dict(zip(model_ids, model_identifiers(model_ids)))
        for model_id, ports in by_model.items():
            names = port_identifiers(list(ports), classes.get(model_id, ""))
            irs = []
            for k, (cname, (pname, e)) in enumerate(zip(names, ports.items())):
                ps = e["spec"]
                irs.append(
                    PortIR(
                        cname,
                        pname,
                        ps.direction,
                        ps.type,
                        ps.description,
                        f"scratch{k}_" if e["scratch"] else "",
                        tuple(e["reads"]),
                        tuple(e["writes"]),
                        self.user_cpp(ps.type),
                    )
                )
            out[model_id] = tuple(irs)
        return out

    # ------------------------------------------------------------ all
    def run(self) -> DataIR:
        self.mark_unsets()
        scripts, bits = self.scripts()
        data_leaves: list[DataOp] = []
        entries: list[DataOp] = []
        switches: list[DataOp] = []
        loops: list[DataOp] = []
        param_reads: list[DataOp] = []
        locals_: list[LocalIR] = []
        params: dict[int, tuple[int, int, int]] = {}
        for kind, inst, op in self.a.node_ops:
            code: Optional[DataOp] = None
            if kind == "unset":
                data_leaves.append(self.unset(inst, op))
            elif kind == "set_literal":
                code = self.set_literal(inst, op)
                if code is not None:
                    data_leaves.append(code)
            elif kind == "set_copy":
                code = self.set_copy(inst, op)
                if code is not None:
                    data_leaves.append(code)
            elif kind == "entry":
                entries.append(self.entry(inst, op))
            elif kind == "switch":
                switches.append(self.switch(inst, op))
            elif kind == "loop":
                code = self.loop(inst, op, locals_)
                if code is not None:
                    loops.append(code)
            elif kind == "param":
                read = self.param_read(inst, op)
                if read is not None:
                    param_reads.append(read)
                    params[inst.index] = (0, 1, 0)  # p1: read p0 from the blackboard (btgen::param)
            elif kind == "params":
                p0 = op["p0"]
                if p0 is not None:
                    params[inst.index] = (int(getattr(p0, "value", p0)), 0, 0)
        ports = self.ports()
        for s in self.a.slots:
            for w in s.writes:
                if (
                    w.literal is not None
                    and w.source != "script"
                    and s.kind == "string"
                    and len(w.literal.encode("utf-8")) > s.capacity
                ):  # (scripts: reported as they compile)
                    self.error(w.loc, self.overflow_message(w.literal, s))
        slots = tuple(
            SlotIR(
                i,
                s.member,
                s.key,
                s.owner,
                s.entry.type_name,
                s.kind or "none",
                s.origin,
                s.origin_loc,
                s.capacity,
                s.owner_uid,
                s.elem_capacity,
                s.initial,
                s.at_load,
                self.a.user[s.kind].cpp if is_user(s.kind) else "",
                not s.at_load or s.unset,
                s.origin_text,
                s.provided,
                i in self.bt_any_slots,
            )
            for i, s in enumerate(self.a.slots)
        )
        used = {kind_of_type(ps.type) for spec in self.a.m.user_models() for ps in spec.ports} | {
            s.kind for s in self.a.slots
        }
        user_types = tuple(t for t in self.a.m.user_types if t.kind in used)
        return DataIR(
            slots,
            tuple(locals_ + self.user_locals),
            tuple(scripts),
            tuple(data_leaves),
            tuple(entries),
            tuple(switches),
            tuple(loops),
            ports,
            bits,
            params,
            self.a.opt.string_capacity,
            self.a.opt.queue_capacity,
            tuple(self.where_locs),
            tuple(self.a.m.enums),
            user_types,
            tuple(self.user_inits),
            tuple(param_reads),
        )


def analyze(mission: Mission, options: Optional[DataOptions] = None) -> tuple[DataIR, DiagnosticSink]:
    """The data side of `mission`'s main tree, with the diagnostics found (errors make it unusable)."""
    with kinds.user_kinds(mission.user_types):
        a = _Analyzer(mission, options or DataOptions())
        a.load()
        a.collect()
        a.name_slots()
        a.type_slots()
        a.size_slots()
        ir = _Compiler(a).run()
    return ir, a.sink
