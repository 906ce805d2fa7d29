"""Steps 1 and 2 of the data analysis: the main tree loaded onto blackboards as 4.6.2's
XML loader does it, and every key a node reads or writes resolved to one slot."""

from __future__ import annotations

import functools
from typing import Callable, Optional, Union

from btgen.diagnostics import DiagnosticSink, Loc
from btgen.ir import kinds
from btgen.ir.data.records import ENTRY_NODES, LITERAL_ONLY, LOOPS, PARAM_PORTS, DataOptions, script_loc
from btgen.ir.data.state import (
    EntryUse,
    IndexWriteUse,
    Inst,
    LoopUse,
    NodeUse,
    ParamUse,
    PortUse,
    SetCopyUse,
    SetKeyUse,
    SetLiteralUse,
    Slot,
    StatusParam,
    SwitchUse,
    UnsetUse,
    Write,
    no_bound,
    ports_of,
)
from btgen.ir.kinds import DYN, ScriptTypeError, is_queue, is_user, kind_of_type
from btgen.ir.numbering import Numbering, number_nodes
from btgen.ir.script_types import SlotType
from btgen.lang import blackboard as bbmod
from btgen.lang import script as sc
from btgen.lang import values
from btgen.lang.catalogue import BUILTINS, ENTRY_PORTS
from btgen.lang.instance import subtree_remapping
from btgen.lang.kind import KindLike
from btgen.lang.model import Attr, Mission, SubTreeNode
from btgen.lang.status import NodeStatus


class Analysis:
    def __init__(self, mission: Mission, options: DataOptions, numbering: Optional[Numbering] = None) -> None:
        self.m = mission
        self.opt = options
        self.numbering = numbering if numbering is not None else number_nodes(mission)
        self.sink = DiagnosticSink()
        self.reported: set[tuple[Loc, str]] = set()
        self.insts: list[Inst] = []
        self.bb_labels: dict[int, str] = {}
        self.bb_uid: dict[int, int] = {}  # UID of the SubTree node of a blackboard (Groot2 names it)
        self.bbs: list[bbmod.Blackboard] = []
        self.slots: list[Slot] = []
        self.slot_of_entry: dict[int, int] = {}
        self.order = 0
        # per-node uses, filled by _collect
        self.script_uses: list[tuple[Inst, Attr, str, sc.Script, dict[str, int], bool]] = []
        self.node_ops: list[tuple[Inst, NodeUse]] = []
        # SetBlackboard nodes whose output_key names an entry: (inst, its slot, key, place, order)
        self.pending_keys: list[tuple[Inst, int, str, Loc, int]] = []
        self.user = {t.kind: t for t in mission.user_types}  # kind -> usertypes.UserType
        self.user_kinds = kinds.UserKinds.of(mission.user_types)

    def error(self, loc: Loc, message: str) -> None:
        if (loc, message) not in self.reported:
            self.reported.add((loc, message))
            self.sink.error(loc, message)

    def run_time(self, loc: Loc, message: str) -> None:
        """A problem the library meets only when the node runs (it loads the mission): both
        engines throw there, with the interpreter's message. Not a refusal: a warning of the
        program (`btgen check` reports it at its rule's level)."""
        if (loc, message) not in self.reported:
            self.reported.add((loc, message))
            self.sink.warning(loc, message)

    def kind_of_type(self, type_name: str) -> Optional[KindLike]:
        """The kind an entry of a declared type holds in this mission (its --type names too)."""
        return kind_of_type(type_name, self.user_kinds)

    def _kind_of_slot(self, slot: int) -> Optional[KindLike]:
        return self.slots[slot].kind

    def _capacity_of_slot(self, slot: int) -> Optional[int]:
        return self.slots[slot].capacity

    def next_order(self) -> int:
        self.order += 1
        return self.order

    # ------------------------------------------------------------ 1. load
    def load(self) -> None:
        root = bbmod.Blackboard(double_from_chars=self.m.semantics.double_from_chars)
        self._add_bb(root, "root")
        self._provide(root, self.m.main_tree, True, self.m.main.loc)
        # per tree instance (the index of its SubTree node, -1: the main tree): its blackboard
        # and its path of SubTree names (the owner of its slots in the header's comments)
        bb_of: dict[int, bbmod.Blackboard] = {-1: root}
        path_of: dict[int, str] = {-1: ""}
        for n in self.numbering:
            node, index = n.node, n.index
            bb, path = bb_of[n.instance], path_of[n.instance]
            if isinstance(node, SubTreeNode):
                inst = Inst(index, node, "SubTree", BUILTINS["SubTree"], bb, {})
                self.insts.append(inst)
                sub_path = f"{path}/{node.display_name}" if path else node.display_name
                child_bb = self._subtree_blackboard(node, bb, sub_path)
                self.bb_uid[id(child_bb)] = n.uid
                bb_of[index], path_of[index] = child_bb, sub_path
                continue
            ports = ports_of(self.m, node)
            try:
                spec = self.m.spec(node.id)
            except KeyError:
                spec = None
            inst = Inst(index, node, node.id, spec, bb, ports)
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
                    if before is None and (node.id, p.name) in ENTRY_PORTS:
                        # InputPort<BT::Any>: the entry is typed BT::Any, whose string converter
                        # throws (lang/blackboard.create_port_entry); the analysis types it as any
                        s.bt_any_at_load = True

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
            kind = self.kind_of_type(p.type)
            s.writes.append(
                Write(
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
            constant_kind = {values.INT: kinds.INT, values.DOUBLE: kinds.DOUBLE}.get(entry.type_name, kinds.STRING)
            s.initial = text
            s.origin = f'the constant port `{key}` of SubTree "{model.display_name}"'
            s.origin_loc = locs.get(key, model.loc)
            s.writes.append(
                Write(
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

    def _slot(self, entry: bbmod.Entry, loc: Loc) -> Slot:
        idx = self.slot_of_entry.get(id(entry))
        if idx is None:
            idx = len(self.slots)
            self.slot_of_entry[id(entry)] = idx
            self.slots.append(Slot(entry, loc))
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
        self.collect_set_keys()

    def _collect_node(self, inst: Inst) -> None:
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
                        self.node_ops.append((inst, ParamUse(slot, p.name, key, loc)))
                        if nid == "PersistentSequence":
                            self.node_ops.append((inst, IndexWriteUse(slot, key, loc)))
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
    def _script_use(self, inst: Inst, attr: Attr, which: str, condition: bool) -> None:
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
                text = attr.value[n.offset : end_offset(n, attr.value)].strip() or attr.value
                what = f"`{text}` in {prefix}"
                if n.op in (":=", "="):
                    kind_fn: Callable[..., Optional[KindLike]] = functools.partial(self._expr_kind, value, names)
                    bound_fn: Callable[..., Optional[int]] = functools.partial(self._expr_bound, value, names)
                else:
                    kind_fn = functools.partial(self._kind_of_slot, target)
                    bound_fn = no_bound if n.op == "+=" else functools.partial(self._capacity_of_slot, target)
                lit = value.value if isinstance(value, sc.Literal) and isinstance(value.value, str) else None
                if lit is not None and n.op in (":=", "="):
                    self._queue_literal(target, lit)
                self.slots[target].writes.append(
                    Write(target, self.next_order(), loc, what, kind_fn, determining, bound_fn, lit)
                )

    def _bound_of(self, slot: int) -> Optional[int]:
        s = self.slots[slot]
        if s.kind == DYN:  # its text, or the text of a number it holds
            return max(s.capacity, kinds.TEXT_BOUND[kinds.DOUBLE])
        return s.capacity if s.kind == kinds.STRING else kinds.TEXT_BOUND.get(s.kind or "", 0)

    def _kind_of(self, names: dict[str, int]) -> Callable[[str], Optional[KindLike]]:
        return lambda name: self.slots[names[name]].kind

    def _expr_kind(self, expr: sc.Expr, names: dict[str, int]) -> Optional[KindLike]:
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
                return max(s.capacity, kinds.TEXT_BOUND[kinds.DOUBLE])
            if s.kind == kinds.STRING:
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
                return max(s.capacity, kinds.TEXT_BOUND[kinds.DOUBLE])
            return s.capacity if s.kind == kinds.STRING else kinds.TEXT_BOUND.get(s.kind or "", 0)
        return kinds.TEXT_BOUND[kinds.DOUBLE]  # unary, comparison: numbers

    # -- built-in nodes
    def _literal(self, inst: Inst, name: str, type_name: str) -> object:
        p = inst.ports.get(name)
        assert p is not None, (inst.reg_id, name)
        try:
            return values.convert_from_string(type_name, p.raw, double_from_chars=self.m.semantics.double_from_chars)
        except values.ConversionError as e:
            self.error(p.loc_or or inst.node.loc, f"port `{name}` of {inst.what}: {e}")
            return None

    def _status_param(self, inst: Inst, name: str) -> StatusParam:
        p = inst.ports.get(name)
        assert p is not None, (inst.reg_id, name)
        try:
            values.convert_from_string(values.NODE_STATUS, p.raw)
        except values.ConversionError as e:
            if bbmod.remapped_key(name, p.raw) is None:
                # The library loads it and the node throws where it reads the port (the front
                # end warns; the interpreter throws there, with this message)
                message = f'`{inst.reg_id}` "{inst.node.display_name}": port `{name}`: {e}'
                return StatusParam(None, message, p.loc_or or inst.node.loc)
        value = self._literal(inst, name, values.NODE_STATUS)
        assert value is None or isinstance(value, NodeStatus), value
        return StatusParam(value)

    def _collect_builtin(self, inst: Inst) -> None:
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
            if bbmod.remapped_key("else", inst.ports["else"].raw) is None:  # `{key}`: a ParamUse
                self.node_ops.append((inst, self._status_param(inst, "else")))
        elif nid == "SetBlackboard":
            self._collect_set_blackboard(inst)
        elif nid == "UnsetBlackboard":
            p = inst.ports["key"]
            key = p.raw
            if bbmod.is_blackboard_pointer(key):
                # The key is read from an entry when the node runs (collect_set_keys).
                name = bbmod.strip_blackboard_pointer(key) or key
                slot = self.resolve(inst.bb, name, p.loc_or or node.loc)
                if slot is not None:
                    self.pending_keys.append((inst, slot, name, p.loc_or or node.loc, self.next_order()))
                return
            self.node_ops.append((inst, UnsetUse(key, p.loc_or or node.loc)))
        elif nid in ENTRY_NODES:
            p = inst.ports["entry"]
            key = bbmod.strip_blackboard_pointer(p.raw) or p.raw
            slot = self.resolve(inst.bb, key, p.loc_or or node.loc)
            if slot is not None:
                self.node_ops.append((inst, EntryUse(slot, key)))
        elif nid.startswith("Switch"):
            self._collect_switch(inst)
        elif nid in LOOPS:
            self._collect_loop(inst, LOOPS[nid])

    def _port_slot(self, inst: Inst, name: str) -> Optional[int]:
        """The slot a `{key}` port names, or None for a literal (or an unset port)."""
        p = inst.ports.get(name)
        if p is None:
            return None
        key = bbmod.remapped_key(name, p.raw)
        if key is None:
            return None
        return self.resolve(inst.bb, key, p.loc_or or inst.node.loc)

    def _collect_set_blackboard(self, inst: Inst) -> None:
        node = inst.node
        out = inst.ports["output_key"]
        out_loc = out.loc_or or node.loc
        if bbmod.is_blackboard_pointer(out.raw):
            # The key is read from an entry when the node runs: its writes are only all known
            # once every node is collected (collect_set_keys).
            key = bbmod.strip_blackboard_pointer(out.raw) or out.raw
            slot = self.resolve(inst.bb, key, out_loc)
            if slot is not None:
                self.pending_keys.append((inst, slot, key, out_loc, self.next_order()))
            return
        dst = self.resolve(inst.bb, out.raw, out_loc)
        if dst is None:
            return
        use = self._set_blackboard_use(inst, dst, out.raw, self.next_order())
        if use is not None:
            self.node_ops.append((inst, use))

    def _set_blackboard_use(
        self, inst: Inst, dst: int, out_key: str, order: int
    ) -> Optional[Union[SetLiteralUse, SetCopyUse]]:
        """The write of a SetBlackboard into slot `dst` (named `out_key`), and its use."""
        node = inst.node
        value = inst.ports["value"]
        src_key = bbmod.strip_blackboard_pointer(value.raw)
        loc = value.loc_or or node.loc
        if src_key is None:
            text = value.raw
            what = f'`value="{text}"` of {inst.what}'

            def lit_kind(d=dst) -> Optional[KindLike]:
                s = self.slots[d]
                declared = s.entry.type_name
                if declared not in (values.ANY, values.STRING) and not values.is_opaque_type(declared):
                    return self.kind_of_type(declared)
                return kinds.STRING

            self.slots[dst].writes.append(
                Write(
                    dst,
                    order,
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
            return SetLiteralUse(dst, text, loc, out_key)
        src = self.resolve(inst.bb, src_key, loc)
        if src is None:
            return None
        what = f'`value="{value.raw}"` of {inst.what}'
        self.slots[dst].writes.append(
            Write(
                dst,
                order,
                loc,
                what,
                lambda s=src: self.slots[s].kind,
                True,
                lambda s=src: self._bound_of(s),
                None,
                "copy",
            )
        )
        return SetCopyUse(dst, src, loc, out_key, src_key, value.raw)

    def collect_set_keys(self) -> None:
        """SetBlackboard output_key="{key}": the library reads the key when the node runs and
        writes the entry of that name. The C++ back end follows it when every value the key's
        entry is given is a literal (a script's `key := 'name'`, a SetBlackboard literal, a
        SubTree's constant port): each such name is a destination resolved from the node's
        blackboard, picked at run time by the entry's text."""
        key_slots = {slot for _, slot, _, _, _ in self.pending_keys}
        for inst, slot, key, loc, order in self.pending_keys:
            unset = inst.reg_id == "UnsetBlackboard"
            port = "key" if unset else "output_key"
            ks = self.slots[slot]
            texts: list[str] = []
            for w in sorted(ks.writes, key=lambda w: w.order):
                if w.literal is None or not w.determining or w.source not in ("script", "set", "constant"):
                    self.error(
                        loc,
                        f"port `{port}` of {inst.what} reads the key from blackboard entry `{key}`, "
                        f"which {w.what} writes with a value btgen cannot know before the run; the C++ "
                        f"back end follows a key read from an entry when every value it is given is a "
                        f"literal",
                    )
                    texts = []
                    break
                if w.literal not in texts:
                    texts.append(w.literal)
            else:
                cases: list[tuple[str, Union[SetLiteralUse, SetCopyUse, UnsetUse]]] = []
                for text in texts:
                    if bbmod.is_blackboard_pointer(text) or not text:
                        self.error(
                            loc,
                            f"port `{port}` of {inst.what} reads the key `{text}` from blackboard entry "
                            f"`{key}`, which names no entry the C++ back end can write",
                        )
                        break
                    if unset:  # (the entry need not exist: then nothing is removed)
                        cases.append((text, UnsetUse(text, loc)))
                        continue
                    dst = self.resolve(inst.bb, text, loc)
                    if dst is None:
                        break
                    if dst in key_slots:
                        self.error(
                            loc,
                            f"port `{port}` of {inst.what} may write blackboard entry `{text}`, which "
                            f"holds the key of a SetBlackboard; the C++ back end cannot follow that",
                        )
                        break
                    use = self._set_blackboard_use(inst, dst, text, order)
                    if use is None:
                        break
                    cases.append((text, use))
                else:
                    self.node_ops.append((inst, SetKeyUse(slot, key, loc, tuple(cases), port)))
        self.pending_keys.clear()

    def _queue_literal(self, slot: int, text: str) -> None:
        s = self.slots[slot]
        elem = values.queue_element_type(s.entry.type_name)
        if elem is None:
            return
        parts = values._split_queue(text)
        s.queue_literals.append(len(parts))
        if elem == values.STRING:
            s.elem_literals.extend(len(x.encode("utf-8")) for x in parts)

    def _collect_switch(self, inst: Inst) -> None:
        n_cases = int(inst.reg_id[len("Switch") :])
        reads = []
        for name in ["variable"] + [f"case_{i}" for i in range(1, n_cases + 1)]:
            p = inst.ports.get(name)
            slot = self._port_slot(inst, name)
            reads.append((name, p.raw if p is not None else None, slot))
        self.node_ops.append((inst, SwitchUse(tuple(reads), n_cases)))
        self.node_ops.append((inst, StatusParam(n_cases)))

    def _collect_loop(self, inst: Inst, elem: str) -> None:
        node = inst.node
        queue_port = inst.ports["queue"]
        qkey = bbmod.remapped_key("queue", queue_port.raw)
        static: Optional[tuple] = None
        qslot = None
        loc = queue_port.loc_or or node.loc
        if qkey is None:
            try:
                queue = values.convert_from_string(
                    f"queue<{elem}>", queue_port.raw, double_from_chars=self.m.semantics.double_from_chars
                )
                assert isinstance(queue, values.Queue)
                static = tuple(queue)
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
                return s.elem_capacity if is_queue(s.kind) else s.capacity if s.kind in (kinds.STRING, DYN) else 0

            self.slots[vslot].writes.append(
                Write(
                    vslot,
                    self.next_order(),
                    vloc,
                    what,
                    lambda e=elem: self.kind_of_type(e),
                    True,
                    bound,
                    None,
                    "loop",
                    elem,
                )
            )
        self.node_ops.append((inst, LoopUse(elem, static, qslot, vslot, loc, qkey)))
        self.node_ops.append((inst, self._status_param(inst, "if_empty")))

    # -- user leaves
    def _collect_leaf(self, inst: Inst) -> None:
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
                    kind = self.kind_of_type(ps.type)
                    if is_queue(kind):
                        self.slots[slot].queue_unbounded = True
                    self.slots[slot].writes.append(
                        Write(
                            slot,
                            self.next_order(),
                            loc,
                            what,
                            (lambda k=kind: k),
                            kind is not None,
                            (lambda: None),
                            None,
                            "port",
                            ps.type,
                        )
                    )
            self.node_ops.append((inst, PortUse(ps, slot, p.raw, p)))

    # ------------------------------------------------------------ owners
    def find_owners(self) -> None:
        """Each slot's key and the blackboard holding it: "root" or its SubTree instance's path
        (and the SubTree node's UID, which Groot2 names its blackboard by)."""
        owner_of: dict[int, tuple[str, str, int]] = {}
        for bb in self.bbs:
            for key in bb.local_keys():
                entry = bb.local_entry(key)
                owner_of[id(entry)] = (self.bb_labels[id(bb)], key, self.bb_uid.get(id(bb), 0))
        for s in self.slots:
            s.owner, s.key, s.owner_uid = owner_of.get(id(s.entry), ("root", "?", 0))

    # ------------------------------------------------------------ 5. decide
    def slot_type(self, i: int) -> SlotType:
        s = self.slots[i]
        return SlotType(
            s.key,
            s.kind or kinds.NONE,
            s.entry.type_name,
            s.capacity,
            s.origin_text,
            self.kind_of_type(s.entry.type_name),
            self.m.semantics.double_from_chars,
        )


def end_offset(node: sc.Expr, code: str) -> int:
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
