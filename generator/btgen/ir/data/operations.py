"""Step 5 of the data analysis: every data operation decided over the typed, sized slots."""

from __future__ import annotations

import dataclasses
import struct
from collections.abc import Mapping
from types import MappingProxyType
from typing import Optional

from btgen.diagnostics import Loc, did_you_mean
from btgen.ir import dataops as ops
from btgen.ir import kinds
from btgen.ir.data.queue_share import SHARED_WRITES, share_classes
from btgen.ir.data.records import (
    BOOL_PARAM_DEFAULTS,
    PARALLEL_READS,
    SCRIPT_SLOTS,
    DataIR,
    DataOp,
    LocalIR,
    PortIR,
    ScriptIR,
    ScriptSlot,
    SlotIR,
    script_loc,
)
from btgen.ir.data.resolve import Analysis
from btgen.ir.data.state import (
    EntryUse,
    IndexWriteUse,
    Inst,
    LoopUse,
    ParamUse,
    PortAccess,
    PortUse,
    SetCopyUse,
    SetKeyUse,
    SetLiteralUse,
    Slot,
    StatusParam,
    SwitchUse,
    UnsetUse,
)
from btgen.ir.data.types import TYPED_WRITE_TYPES
from btgen.ir.kinds import DYN, ScriptTypeError, describe_kind, is_numeric, is_queue, is_user
from btgen.ir.script_types import type_script
from btgen.lang import blackboard as bbmod
from btgen.lang import script as sc
from btgen.lang import values
from btgen.lang.blackboard import RAW_COPY_TYPES
from btgen.lang.catalogue import PortSpec
from btgen.lang.hashorder import std_hash
from btgen.lang.kind import KindLike
from btgen.lang.model import Attr
from btgen.lang.status import NodeStatus

DYN_WRITE_TYPES = TYPED_WRITE_TYPES  # (btgen::port::write of a Dyn slot: Dyn::typed, Dyn::typed_string)
_DYN_TAG: Mapping[str, str] = MappingProxyType(
    {values.INT: "kInt", values.DOUBLE: "kDouble", values.BOOL: "kBool", values.NODE_STATUS: "kStatus"}
)

TYPE_NAME_OF_KIND: Mapping[KindLike, str] = MappingProxyType(
    {
        "int": values.INT,
        "double": values.DOUBLE,
        "bool": values.BOOL,
        "string": values.STRING,
        "status": values.NODE_STATUS,
    }
)


class Compiler:
    """Step 5: every data operation decided over the typed and sized slots (ir/dataops.py
    records; scripts: compiled by backend_cpp/script_cpp/), and the errors that would
    happen whenever one runs reported."""

    def __init__(self, a: Analysis) -> None:
        self.a = a
        self.types = [a.slot_type(i) for i in range(len(a.slots))]
        self.where_locs: list[Loc] = []
        self.where_index: dict[Loc, int] = {}
        self.user_locals: list[LocalIR] = []  # converted literals of user-typed ports
        self.user_inits: list[DataOp] = []
        self.bt_any_slots: set[int] = set()  # slots a SetBlackboard string may leave typed BT::Any
        self.pool_of: dict[int, str] = {}  # queue slots sharing one deque: slot -> its pool member

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
    def typed_write_ok(
        self, slot: int, type_name: str, loc: Loc, what: str, owner: Optional[tuple[Inst, str, str]] = None
    ) -> bool:
        """Blackboard::set<T> of a T into the slot: what btgen::port::write does, checked where it
        fails (or would change the entry's type) whenever it runs. `owner`: the writing node and
        its port's name and text as written, to tell whether its blackboard holds the entry."""
        s = self.a.slots[slot]
        declared = s.entry.type_name
        k = self.a.kind_of_type(type_name)
        if s.kind == DYN and declared == type_name and declared in RAW_COPY_TYPES:
            return True  # an entry of its own type that a 4.6.2 copy may leave holding a string
        if s.kind == DYN and declared == values.ANY and type_name in DYN_WRITE_TYPES and self._owns(s, owner):
            return True  # btgen::port::write of a Dyn slot follows the entry's run-time type
        if s.kind == DYN:
            self.error(
                loc,
                f"{what} writes {describe_kind(k or 'none')} ({type_name}) to blackboard entry "
                f"`{s.key}`, whose type changes at run time ({s.origin_text}); typed writes into "
                f"such entries are not supported by the C++ back end yet"
                + ("" if type_name in DYN_WRITE_TYPES else " but for int, double, bool and string values"),
            )
            return False
        if declared == values.ANY or values.is_opaque_type(declared) or declared == type_name:
            ok = k == s.kind
        elif type_name == values.STRING:
            ok = declared != values.NODE_STATUS and self.a.kind_of_type(declared) == s.kind
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

    @staticmethod
    def _owns(s: Slot, owner: Optional[tuple[Inst, str, str]]) -> bool:
        """Whether the writer's blackboard holds the entry itself: Blackboard::set<T> of an entry
        reached through a SubTree's remapping stores the value without typing it, which a
        dynamic slot does not follow."""
        if owner is None:
            return False
        inst, port, raw = owner
        key = bbmod.remapped_key(port, raw)
        if key is None:
            return False
        target = inst.bb.root if key.startswith("@") else inst.bb
        return target.local_entry(key[1:] if key.startswith("@") else key) is s.entry

    # ------------------------------------------------------------ scripts
    def scripts(self) -> tuple[list[ScriptIR], dict[int, int]]:
        out: list[ScriptIR] = []
        bits: dict[int, int] = {}
        for inst, attr, which, script, names, condition in self.a.script_uses:
            self.check_reads(inst, attr, script, names)
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
            if enum != ScriptSlot.CODE:
                bits[inst.index] = bits.get(inst.index, 0) | (1 << enum)
        return out, bits

    def check_user_free(self, inst: Inst, attr: Attr, script: sc.Script, names: dict[str, int]) -> bool:
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

    def check_reads(self, inst: Inst, attr: Attr, script: sc.Script, names: dict[str, int]) -> None:
        """A name read that can never find its entry (nothing anywhere creates it): a run-time
        error of both engines where the script runs, and a warning of the program."""
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
                        # The library loads it and throws when the script runs ("Variable not
                        # found"): so does the C++ (the slot may be missing), and `check` says so.
                        self.a.run_time(
                            script_loc(attr, node.offset),
                            f"`{attr.name}` of {inst.what} reads `{node.name}`, but nothing creates that "
                            f"blackboard entry: no port, script or SetBlackboard writes it ({advice})",
                        )

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
    def unset(self, inst: Inst, op: UnsetUse) -> DataOp:
        key = op.key
        entry = inst.bb.local_entry(key)
        slot = self.a.slot_of_entry[id(entry)] if entry is not None else None
        return DataOp(inst.index, f'UnsetBlackboard "{inst.node.display_name}" key={key}', ops.Unset(slot, key))

    def mark_unsets(self) -> None:
        """Entries UnsetBlackboard can remove may be missing when a script runs."""
        unsets = [(inst, op) for inst, op in self.a.node_ops if isinstance(op, UnsetUse)]
        for inst, op in self.a.node_ops:  # a key read from an entry: each key it may hold
            if isinstance(op, SetKeyUse):
                unsets.extend((inst, u) for _, u in op.cases if isinstance(u, UnsetUse))
        for inst, op in unsets:
            entry = inst.bb.local_entry(op.key)
            if entry is None:
                continue
            s = self.a.slots[self.a.slot_of_entry[id(entry)]]
            key = op.key
            if s.initial is not None and (key in inst.bb.remapping or (inst.bb.autoremap and not key.startswith("_"))):
                self.error(
                    op.loc,
                    f"UnsetBlackboard of `{key}`, a constant port of its SubTree, would make "
                    f"`{key}` reach the parent's entry afterwards; the C++ back end resolves keys "
                    f"once, so it cannot follow that",
                )
            s.unset = True

    def set_literal(self, inst: Inst, op: SetLiteralUse) -> Optional[DataOp]:
        dst, text, loc = op.dst, op.text, op.loc
        s = self.a.slots[dst]
        declared = s.entry.type_name
        what = f'`SetBlackboard` "{inst.node.display_name}"'
        comment = f'SetBlackboard "{inst.node.display_name}" {s.key} = {text!r}'
        prefix = f"{what}: SetBlackboard: cannot convert {values.describe(text)}: "
        untyped = self._untyped_dst(inst, op.key, loc, s, prefix)
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
            v410 = self._dyn_410(inst, op.key, s, text)
            return DataOp(inst.index, comment, ops.SetDynLiteral(dst, text, op.key, what + ": ", self.where(loc), v410))
        if declared not in (values.ANY, values.STRING) and not values.is_opaque_type(declared):
            if declared == values.NODE_STATUS:
                throws = self._status_text_throws(op.key, text) if s.at_load and not s.unset else None
                if throws is not None:
                    # The entry exists whenever the node runs (a port created it when the tree
                    # loaded, nothing removes it): both releases throw there, on every tick
                    return DataOp(inst.index, comment, ops.Throw(self.fail(loc, f"{what}: {throws}")))
                self.error(
                    loc,
                    f"{what} writes the text `{text}` to `{s.key}`, a NodeStatus entry, which "
                    f"BehaviorTree.CPP cannot convert text into",
                )
                return None
            sem = self.a.m.semantics
            try:
                values.convert_from_string(declared, text, double_from_chars=sem.double_from_chars)
            except values.ConversionError as e:
                # The library throws when the node runs (not on load): so does the executor, with
                # the interpreter's message (lang/blackboard.py Blackboard.set, set_blackboard_410).
                if sem.setblackboard_converts_to_entry_type:
                    message = f"{what}: SetBlackboard: cannot convert {values.describe(text)}: {e}"
                else:
                    message = f"{what}: cannot write {values.describe(text)} to `{op.key}` ({declared}): {e}"
                return DataOp(inst.index, comment, ops.SetText(dst, declared, text, self.fail(loc, message), untyped))
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

    def _status_text_throws(self, key: str, text: str) -> Optional[str]:
        """The interpreter's error for SetBlackboard of `text` into an existing NodeStatus entry
        (lang/blackboard.py, on a scratch blackboard holding only that entry); None if it has none."""
        sem = self.a.m.semantics
        scratch = bbmod.Blackboard(double_from_chars=sem.double_from_chars)
        scratch.create_entry(key[1:] if key.startswith("@") else key, values.NODE_STATUS)
        setter = bbmod.set_blackboard_410 if sem.setblackboard_converts_to_entry_type else bbmod.set_blackboard
        try:
            setter(scratch, key, text)
        except (values.ConversionError, bbmod.BlackboardError) as e:
            return str(e)
        return None

    def set_key(self, inst: Inst, op: SetKeyUse) -> Optional[DataOp]:
        """SetBlackboard output_key="{key}": getInput<std::string> of the key's entry, then the
        operation of a SetBlackboard written with that text as its output_key."""
        k = self.a.slots[op.slot]
        what = f'`{inst.reg_id}` "{inst.node.display_name}"'
        if k.kind != kinds.STRING:
            self.error(
                op.loc,
                f"port `{op.port}` of {what} reads the key from blackboard entry `{op.key}`, which holds "
                f"{describe_kind(k.kind or 'none')} ({k.origin_text}); the C++ back end follows a key read "
                f"from a string entry",
            )
            return None
        cases: list[tuple[str, ops.DataLeafOp]] = []
        for text, use in op.cases:
            if isinstance(use, UnsetUse):
                code: Optional[DataOp] = self.unset(inst, use)
            elif isinstance(use, SetLiteralUse):
                code = self.set_literal(inst, use)
            else:
                code = self.set_copy(inst, use)
            if code is None:
                return None
            assert isinstance(
                code.op,
                (
                    ops.Unset,
                    ops.SetUserLiteral,
                    ops.SetDynLiteral,
                    ops.SetText,
                    ops.SetCopy,
                    ops.SetCopyDyn,
                    ops.SetCopyDynTyped410,
                ),
            ), code
            cases.append((text, code.op))
        prefix = f"{what}: port `{op.port}` reads blackboard entry `{op.key}`, which"
        return DataOp(
            inst.index,
            f'{inst.reg_id} "{inst.node.display_name}" {{{op.key}}}',
            ops.SetKey(
                op.slot,
                self.fail(op.loc, f"{prefix} does not exist"),
                self.fail(op.loc, f"{prefix} has no value yet"),
                tuple(cases),
            ),
        )

    def overflow_message(self, text: str, s: Slot) -> str:
        return kinds.overflow_message(text, s.key, s.capacity)

    def set_copy(self, inst: Inst, op: SetCopyUse) -> Optional[DataOp]:
        dst, src, loc = op.dst, op.src, op.loc
        d, s = self.a.slots[dst], self.a.slots[src]
        what = f'`SetBlackboard` "{inst.node.display_name}"'
        declared = d.entry.type_name if d.at_load else s.entry.type_name
        untyped = None
        if s.kind == "string":
            prefix = f"{what}: SetBlackboard: cannot convert {values.describe(op.raw)}: "
            untyped = self._untyped_dst(inst, op.key, loc, d, prefix, s)
        strong = values.is_strongly_typed(declared)
        convert = False
        if is_queue(s.kind):
            return self.share_queue(inst, op, d, s, what)
        if DYN in (d.kind, s.kind) and not (is_user(d.kind) or is_user(s.kind)):
            return self.set_copy_dynamic(inst, op, d, s, what)
        if s.kind in (kinds.INT, kinds.DOUBLE, kinds.STRING) and d.at_load and d.entry.type_name in RAW_COPY_TYPES:
            into_typed = self.set_copy_dyn_typed_410(inst, op, d, s, what)
            if into_typed is not None:
                return into_typed
            if (
                self.a.m.semantics.setblackboard_converts_to_entry_type
                and s.entry.type_name == values.ANY
                and (
                    (s.kind == kinds.INT and self.holds_script_integers(src))
                    or (s.kind == kinds.DOUBLE and d.entry.type_name != values.DOUBLE)
                )
            ):
                # (a script's int64_t, or any double, into an entry of another type: the library
                # prints its blackboard and throws, which the C++ back end cannot print here)
                self.error(
                    loc,
                    f"{what} copies `{s.key}` ({describe_kind(s.kind)}, {s.origin_text}) to `{d.key}` "
                    f"(declared {d.entry.type_name}); BehaviorTree.CPP {self.a.m.semantics.version} throws "
                    f"there after printing its blackboard, which the C++ back end follows only for an "
                    f"entry that exists from load on, on a blackboard without SubTree remappings whose "
                    f"entries all exist from load on: not supported by the C++ back end yet",
                )
                return None
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
        missing = self.fail(loc, f"{what}: `value` reads blackboard entry `{op.src_key}`, which does not exist")
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

    def set_copy_dynamic(self, inst: Inst, op: SetCopyUse, d: Slot, s: Slot, what: str) -> Optional[DataOp]:
        """SetBlackboard value="{src}" where the destination's or the source's type changes at run time."""
        loc = op.loc
        src_decl = s.entry.type_name
        # From a static entry a port declared int, double, bool or NodeStatus: 4.6.2 copies its
        # value as it is (`dst_entry->value = src_entry->value`); from 4.7.0 it is set<BT::Any>
        # (btgen::dyn::set_copy_410), but a missing destination would take the source's type,
        # which a dynamic slot does not keep: only into one that exists from load on.
        # A missing destination typed int, double or bool: Dyn::typed (set_copy_410's src_tag).
        typed_src = s.kind != DYN and src_decl in (values.INT, values.DOUBLE, values.BOOL, values.NODE_STATUS)
        exists = d.at_load and not d.unset
        src_tag = _DYN_TAG.get(src_decl, "") if typed_src else ""
        converts = self.a.m.semantics.setblackboard_converts_to_entry_type
        typed_ok = typed_src and (not converts or exists or src_tag != "")
        if d.entry.type_name in RAW_COPY_TYPES:
            into_typed = self.set_copy_dyn_typed_410(inst, op, d, s, what)
            if into_typed is not None:
                return into_typed
            if converts:
                # (from 4.7.0 never a raw copy: it converts, or throws after printing the blackboard)
                self.error(
                    loc,
                    f"{what} copies `{s.key}` ({describe_kind(s.kind or 'none')}, {s.origin_text}) to `{d.key}` "
                    f"(declared {d.entry.type_name}); BehaviorTree.CPP {self.a.m.semantics.version} may throw "
                    f"there after printing its blackboard, which the C++ back end follows only for an entry "
                    f"that exists from load on, on a blackboard without SubTree remappings whose entries all "
                    f"exist from load on, from a source whose integers are a script's: not supported by the "
                    f"C++ back end yet",
                )
                return None
        if d.kind != DYN or (s.kind != DYN and src_decl not in (values.ANY, values.STRING) and not typed_ok):
            self.error(
                loc,
                f"{what} copies `{s.key}` ({describe_kind(s.kind or 'none')}, {s.origin_text}) to "
                f"`{d.key}` ({describe_kind(d.kind or 'none')}, {d.origin_text}); copies between "
                f"typed entries and entries whose type changes at run time are not supported by the "
                f"C++ back end yet",
            )
            return None
        v410 = self._dyn_410(inst, op.key, d, op.raw)
        if v410 is not None:
            # (a typed source: never read, the destination exists from load on)
            src_type = "typed" if typed_ok else self._dyn_410_src_type(s)
            if src_type is None:
                self.error(
                    loc,
                    f"{what} copies `{s.key}` ({describe_kind(s.kind or 'none')}, {s.origin_text}) to "
                    f"`{d.key}`, an entry created without a type whose type changes at run time "
                    f"({d.origin_text}); BehaviorTree.CPP {self.a.m.semantics.version} creates a missing "
                    f"destination with the source's own type, which the C++ back end does not follow for "
                    f"this source: not supported by the C++ back end yet",
                )
                return None
            v410 = dataclasses.replace(v410, src_type=src_type, src_tag=src_tag if typed_ok else "")
        missing = self.fail(
            loc, f"{what}: SetBlackboard: `value` reads blackboard entry `{op.src_key}`, which does not exist"
        )
        return DataOp(
            inst.index,
            f'SetBlackboard "{inst.node.display_name}" {d.key} = {{{s.key}}}',
            ops.SetCopyDyn(
                op.dst,
                op.src,
                src_decl == values.STRING,
                op.key,
                what + ": ",
                missing,
                self.where(loc),
                self._empty_copy_succeeds(),
                v410,
                src_tag,
            ),
        )

    def set_copy_dyn_typed_410(self, inst: Inst, op: SetCopyUse, d: Slot, s: Slot, what: str) -> Optional[DataOp]:
        """From 4.7.0, a copy of an entry no port declared (its type changes at run time, or a
        script gives it an integer, a double or a string) into an entry a port declared int,
        unsigned, double or bool (ops.SetCopyDynTyped410), or None where the C++ back end does
        not follow it (the caller says what then): a source that may hold an integer must be
        written by scripts and literals only (the integer is then a script's int64_t), the
        destination must exist from load on, on the node's blackboard, and that blackboard's
        debugMessage must be known (debug_entries) where the library may print it."""
        declared = d.entry.type_name
        if (
            not self.a.m.semantics.setblackboard_converts_to_entry_type
            or declared not in bbmod.RAW_COPY_TYPES
            or d.kind not in (self.a.kind_of_type(declared), DYN)  # (Dyn: a script gave it the other number)
            or not d.at_load
            or d.unset
            or s.entry.type_name != values.ANY
            or s.kind not in (DYN, kinds.INT, kinds.DOUBLE, kinds.STRING)
            or (s.kind in (DYN, kinds.INT) and not self.holds_script_integers(self.a.slots.index(s)))
        ):
            return None
        target = inst.bb.root if op.key.startswith("@") else inst.bb
        if target.local_entry(op.key[1:] if op.key.startswith("@") else op.key) is not d.entry:
            return None
        debug = self.debug_entries(target)
        if debug is None:
            if s.kind in (DYN, kinds.INT) or (s.kind == kinds.DOUBLE and declared != values.DOUBLE):
                return None
            debug = ()  # (a string is converted, a double stored in a double entry: it never throws)
        loc = op.loc
        missing = self.fail(
            loc, f"{what}: SetBlackboard: `value` reads blackboard entry `{op.src_key}`, which does not exist"
        )
        return DataOp(
            inst.index,
            f'SetBlackboard "{inst.node.display_name}" {d.key} = {{{s.key}}}',
            ops.SetCopyDynTyped410(
                op.dst, op.src, declared, op.raw, op.key, what + ": ", missing, self.where(loc), debug
            ),
        )

    def holds_script_integers(self, idx: int, seen: Optional[set[int]] = None) -> bool:
        """Whether an integer slot `idx` may hold is a script's int64_t (never an `int` from a
        port): no port declared the entry, and only scripts, SetBlackboard literals and
        SetBlackboard copies of such entries write it."""
        seen = set() if seen is None else seen
        if idx in seen:
            return True  # (a cycle of copies adds no other writer)
        seen.add(idx)
        s = self.a.slots[idx]
        if s.entry.type_name != values.ANY:
            return False
        if any(w.source not in ("script", "set", "copy") for w in s.writes):
            return False
        if not any(w.source == "copy" for w in s.writes):
            return True
        copies: list[SetCopyUse] = []
        for _, use in self.a.node_ops:
            if isinstance(use, SetCopyUse):
                copies.append(use)
            elif isinstance(use, SetKeyUse):
                copies.extend(c for _, c in use.cases if isinstance(c, SetCopyUse))
        return all(self.holds_script_integers(c.src, seen) for c in copies if c.dst == idx)

    def debug_entries(self, bb: bbmod.Blackboard) -> Optional[tuple[ops.DebugEntry, ...]]:
        """What Blackboard::debugMessage prints for `bb` whenever it runs, in the order the
        loader inserted its entries (the generated code replays the storage's order when it
        prints, btgen::storage_order), or None where that is not known: every entry must exist
        from load on or be created by scripts, SetBlackboard literals or copies (whose creations
        the generated code counts: Slot::born; a literal or a copy only into a string or dynamic
        slot, whose Slot::entry_type names its type), none may be unset, the blackboard must have
        no SubTree remappings, and each entry's type must be one whose name is known (an entry no
        port declared is named by its Slot::entry_type; it must not be typed by a port)."""
        if bb.remapping or bb.autoremap:
            return None
        out = []
        for key in bb.local_keys():  # (in insertion order: the loader's entries first)
            entry = bb.local_entry(key)
            idx = self.a.slot_of_entry.get(id(entry))
            if entry is None or idx is None:
                return None
            sl = self.a.slots[idx]
            runtime = not sl.at_load
            creators = ("script", "set", "copy") if sl.kind in (kinds.STRING, DYN) else ("script",)
            if sl.unset or (runtime and (not sl.writes or any(w.source not in creators for w in sl.writes))):
                return None
            t = entry.type_name
            if t == values.ANY:
                if sl.kind in (kinds.STRING, DYN):
                    typed = bbmod.CPP_TYPE_NAMES[values.STRING]  # (a SetBlackboard literal types it)
                elif all(w.source in ("script", "constant") for w in sl.writes):
                    typed = bbmod.CPP_TYPE_NAMES[values.ANY]  # (nothing gives it a type)
                else:
                    return None
                out.append(ops.DebugEntry(idx, key, "", typed, std_hash(key), runtime))
            elif t in bbmod.CPP_TYPE_NAMES and not runtime:
                out.append(ops.DebugEntry(idx, key, bbmod.CPP_TYPE_NAMES[t], "", std_hash(key)))
            else:
                return None
        return tuple(out)

    def _untyped_dst(
        self, inst: Inst, key: str, loc: Loc, d: Slot, prefix: str, src: Optional[Slot] = None
    ) -> Optional[ops.UntypedDst]:
        """From 4.7.0 SetBlackboard converts a string with the converter of the entry it writes;
        an entry that exists without a type (created at load by an untyped `{key}` port, by a
        Script, or holding a SubTree literal) has none: the library leaves it empty and typed
        BT::Any, and throws on the next such write. Whether an entry no port declared is typed
        is known at run time only (Slot::entry_type): the record of what the write does then,
        for a string slot declared `any` (None for any other). `key`: the `output_key` as
        written."""
        if not self.a.m.semantics.setblackboard_converts_to_entry_type or d.entry.type_name != values.ANY:
            return None
        if d.kind != "string":
            return None
        target = inst.bb.root if key.startswith("@") else inst.bb
        local = target.local_entry(key[1:] if key.startswith("@") else key) is d.entry
        src_type = "typed"
        if src is not None and src.entry.type_name == values.ANY:
            src_type = "dynamic"
        if local or src_type == "dynamic":  # (a copy creates a missing entry with the source's type)
            self.bt_any_slots.add(self.a.slots.index(d))
        return ops.UntypedDst(local, src_type, prefix, self.where(loc))

    def _dyn_410(self, inst: Inst, key: str, d: Slot, raw: str) -> Optional[ops.DynSet410]:
        """The rule of _untyped_dst for an entry whose type changes at run time (a dynamic slot)
        that no port declared: its run-time type is Slot::entry_type, kept by
        btgen::dyn::set_text_410 / set_copy_410 (None before 4.7.0, or for a declared entry).
        `key`: the `output_key` as written; `raw`: the `value` port as written."""
        if not self.a.m.semantics.setblackboard_converts_to_entry_type or d.entry.type_name != values.ANY:
            return None
        if d.kind != DYN:
            return None
        target = inst.bb.root if key.startswith("@") else inst.bb
        local = target.local_entry(key[1:] if key.startswith("@") else key) is d.entry
        return ops.DynSet410(local, raw, d.key)

    def _dyn_410_src_type(self, s: Slot) -> Optional[str]:
        """The type a copy's source has at run time, which a missing dynamic destination takes
        (ops.DynSet410.src_type), or None where the generated C++ does not know it: a static
        entry of another kind than string that something other than Scripts writes (a port, a
        copy or a SubTree literal may give it its own type)."""
        decl = s.entry.type_name
        if decl == values.STRING:
            return "typed"
        if decl != values.ANY:
            return None
        if s.kind in (DYN, "string"):
            return "entry"  # kept by set_text_410 / set_copy_410, and by set_string_410 and SetCopy
        if all(w.source == "script" for w in s.writes):
            return "untyped"
        return None

    def share_queue(self, inst: Inst, op: SetCopyUse, d: Slot, s: Slot, what: str) -> Optional[DataOp]:
        """SetBlackboard value="{q}" output_key="r" of a queue entry: both releases copy the shared
        pointer, so both entries hold one deque (queue_share.py; a pool of queues in the C++)."""
        pool = self.pool_of.get(op.src)
        if d.kind != s.kind or pool is None:
            self.error(
                op.loc,
                f"{what} copies the queue `{s.key}` ({s.kind}) into `{d.key}`, which holds "
                f"{describe_kind(d.kind or 'none')} ({d.origin_text}); BehaviorTree.CPP would share one "
                f"queue between both entries, which the C++ back end does only between entries of one "
                f"queue type",
            )
            return None
        if pool == "":
            return None  # (its class is refused, at the write that is not a queue port's or a copy's)
        missing = self.fail(op.loc, f"{what}: `value` reads blackboard entry `{op.src_key}`, which does not exist")
        return DataOp(
            inst.index,
            f'SetBlackboard "{inst.node.display_name}" {d.key} = {{{s.key}}} (one queue)',
            ops.ShareQueue(op.dst, op.src, pool, missing, self._empty_copy_succeeds()),
        )

    def queue_pools(self) -> list[LocalIR]:
        """The pools of the queue entries that copies connect (queue_share.py): their LocalIRs,
        and self.pool_of (slot -> pool member, "" for a class refused here)."""
        out: list[LocalIR] = []
        for group in share_classes(self.a):
            other = [(i, w) for i in group for w in self.a.slots[i].writes if w.source not in SHARED_WRITES]
            provided = [i for i in group if self.a.slots[i].provided]
            if provided and not other:  # (the application's setter writes the entry's own queue)
                s = self.a.slots[provided[0]]
                self.error(
                    s.first_loc,
                    f"the application provides the queue entry `{s.key}` (--entry), which a SetBlackboard copy "
                    f"shares with another entry: not supported by the C++ back end yet",
                )
                for j in group:
                    self.pool_of[j] = ""
                continue
            if other:
                i, w = other[0]
                self.error(
                    w.loc,
                    f"{w.what} writes the queue entry `{self.a.slots[i].key}`, which a SetBlackboard copy shares "
                    f"with another entry; the C++ back end shares a queue between entries that only queue "
                    f"ports of user nodes and copies write: not supported by the C++ back end yet",
                )
                for j in group:
                    self.pool_of[j] = ""
                continue
            if len(group) > 255:
                self.error(self.a.slots[group[0]].first_loc, "more than 255 queue entries share one queue")
                for j in group:
                    self.pool_of[j] = ""
                continue
            first = self.a.slots[group[0]]
            member = f"qpool{len(out)}_"
            keys = ", ".join(f"`{self.a.slots[j].key}`" for j in group)
            out.append(
                LocalIR(
                    member,
                    f"the queues of {keys}, which SetBlackboard copies share",
                    str(kinds.queue_element(first.kind or "none")),
                    first.capacity,
                    first.elem_capacity,
                    pool=len(group),
                )
            )
            for j in group:
                self.pool_of[j] = member
        return out

    def _empty_copy_succeeds(self) -> bool:
        """4.6.2 copies an empty value; from 4.7.0 the node fails (setblackboard_converts_to_entry_type)."""
        return bbmod.EMPTY_COPY_SUCCEEDS and not self.a.m.semantics.setblackboard_converts_to_entry_type

    def param_read(self, inst: Inst, op: ParamUse) -> Optional[DataOp]:
        """A port given as `{key}` that the node reads with getInput whenever the library does:
        a loop count or duration (getInput<int|unsigned>; a failed read is an error), or RunOnce
        then_skip / TryCatch catch_on_halt (getInput<bool>, RunOnce on every tick, TryCatch when
        it is halted; a failed read, no entry, no value or a value that does not convert, keeps
        the port's default, then_skip true, catch_on_halt false, without an error)."""
        s = self.a.slots[op.slot]
        what = f'`{inst.reg_id}` "{inst.node.display_name}": port `{op.port}` reads blackboard entry `{op.key}`'
        default = BOOL_PARAM_DEFAULTS.get(op.port)
        unsigned = op.port in ("msec", "delay_msec")
        constant: Optional[int] = None
        if inst.reg_id == "RateController":
            return self.hz_read(inst, op, what)
        if op.port == "else":
            return self.status_read(inst, op, what)
        if (
            s.kind == "string"
            and s.initial is not None
            and not s.unset
            and all(w.source == "constant" for w in s.writes)
        ):
            # A SubTree's constant port (`n="3"`): text that never changes, converted once here
            # as getInput converts it on every read.
            if default is not None:
                try:
                    constant = 1 if values.convert_from_string(values.BOOL, s.initial) else 0
                except values.ConversionError:
                    constant = default
            else:
                try:
                    converted = values.convert_from_string(values.UNSIGNED if unsigned else values.INT, s.initial)
                except values.ConversionError as e:
                    self.error(op.loc, f"{what}: {e}")
                    return None
                constant = converted if isinstance(converted, int) else 0  # (int and unsigned convert to int)
        elif s.kind not in ("int", "bool", "double", "string", "dyn"):
            self.error(
                op.loc,
                f"port `{op.port}` of {inst.what} reads `{s.key}` ({describe_kind(s.kind or 'none')}, "
                f"{s.origin_text}); the C++ back end reads it from an int, bool, double or string entry, "
                f"or one whose type changes",
            )
            return None
        kind = "" if constant is not None else str(s.kind)
        missing = self.fail(op.loc, f"{what}, which does not exist")
        no_value = self.fail(op.loc, f"{what}, which has no value yet")
        if default is not None:
            read = ops.ParamRead(op.slot, missing, no_value, constant, as_bool=kind, bool_default=default)
        else:
            convert = self.fail(op.loc, f"{what}: ")
            read = ops.ParamRead(op.slot, missing, no_value, constant, kind=kind, unsigned=unsigned, convert=convert)
        return DataOp(inst.index, f'{inst.reg_id} "{inst.node.display_name}" {op.port}={{{op.key}}}', read)

    def parallel_read(self, inst: Inst, uses: dict[str, ParamUse]) -> Optional[DataOp]:
        """Parallel's thresholds, one or both as `{key}`: read at the start of every tick."""
        reads: list[ops.ParamRead] = []
        for port in ("success_count", "failure_count"):
            op = uses.get(port)
            if op is None:  # a literal (or the port's default)
                raw = inst.ports[port].raw
                try:
                    value = values.convert_from_string(values.INT, raw)
                except values.ConversionError as e:
                    self.error(inst.ports[port].loc_or or inst.node.loc, f"port `{port}` of {inst.what}: {e}")
                    return None
                assert isinstance(value, int)
                never = self.fail(inst.node.loc, "")
                reads.append(ops.ParamRead(-1, never, never, value))
                continue
            read = self.param_read(inst, op)
            if read is None:
                return None
            assert isinstance(read.op, ops.ParamRead)
            reads.append(read.op)
        name = inst.node.display_name
        loc_s = inst.ports["success_count"].loc_or or inst.node.loc
        loc_f = inst.ports["failure_count"].loc_or or inst.node.loc
        keys = ", ".join(f"{p}={{{u.key}}}" for p, u in uses.items())
        return DataOp(
            inst.index,
            f'Parallel "{name}" {keys}',
            ops.ParallelRead(
                reads[0],
                reads[1],
                self.fail(loc_s, f'`Parallel` "{name}" needs '),
                self.fail(loc_f, f'`Parallel` "{name}" fails after '),
            ),
        )

    def status_read(self, inst: Inst, op: ParamUse, what: str) -> Optional[DataOp]:
        """Precondition `else` as `{key}`: getInput<NodeStatus> on every tick, before `if`; the
        library throws when the entry does not exist or has no value (the node fails there)."""
        s = self.a.slots[op.slot]
        missing = self.fail(op.loc, f"{what}, which does not exist")
        no_value = self.fail(op.loc, f"{what}, which has no value yet")
        if (
            s.kind == "string"
            and s.initial is not None
            and not s.unset
            and all(w.source == "constant" for w in s.writes)
        ):
            # A SubTree's constant port: the text getInput converts on every read, converted here
            try:
                status = values.convert_from_string(values.NODE_STATUS, s.initial)
            except values.ConversionError as e:
                fail = self.fail(op.loc, f"{what}: {e}")
                always = ops.ParamRead(-1, fail, fail, always=fail)
                return DataOp(inst.index, f'{inst.reg_id} "{inst.node.display_name}" else', always)
            assert isinstance(status, NodeStatus), status
            read = ops.ParamRead(op.slot, missing, no_value, status.value)
        elif s.kind == "status":
            read = ops.ParamRead(op.slot, missing, no_value, as_status=True)
        else:
            self.error(
                op.loc,
                f"port `else` of {inst.what} reads `{s.key}` ({describe_kind(s.kind or 'none')}, {s.origin_text}); "
                f"the C++ back end reads it from a NodeStatus entry",
            )
            return None
        return DataOp(inst.index, f'{inst.reg_id} "{inst.node.display_name}" else={{{op.key}}}', read)

    def hz_read(self, inst: Inst, op: ParamUse, what: str) -> Optional[DataOp]:
        """Nav2's RateController hz as `{key}`: getInput<double>, 1.0 when it fails."""
        s = self.a.slots[op.slot]
        constant: Optional[int] = None
        if (
            s.kind == "string"
            and s.initial is not None
            and not s.unset
            and all(w.source == "constant" for w in s.writes)
        ):
            try:
                hz = float(values.convert_from_string(values.DOUBLE, s.initial))  # type: ignore[arg-type]
            except values.ConversionError:
                hz = 1.0
            constant = struct.unpack("<q", struct.pack("<d", hz))[0]
        elif s.kind not in ("int", "bool", "double", "string", "dyn"):
            self.error(
                op.loc,
                f"port `hz` of {inst.what} reads `{s.key}` ({describe_kind(s.kind or 'none')}, {s.origin_text}); "
                f"the C++ back end reads it from an int, bool, double or string entry, or one whose type changes",
            )
            return None
        kind = "" if constant is not None else str(s.kind)
        missing = self.fail(op.loc, f"{what}, which does not exist")
        no_value = self.fail(op.loc, f"{what}, which has no value yet")
        read = ops.ParamRead(op.slot, missing, no_value, constant, as_double=kind or "constant")
        return DataOp(inst.index, f'{inst.reg_id} "{inst.node.display_name}" hz={{{op.key}}}', read)

    def index_write(self, inst: Inst, op: IndexWriteUse) -> Optional[DataOp]:
        """setOutput of Nav2's PersistentSequence place (an int) into its entry."""
        what = f"port `current_child_idx` of {inst.what}"
        if not self.typed_write_ok(op.slot, values.INT, op.loc, what):
            return None
        s = self.a.slots[op.slot]
        fail = self.fail(op.loc, f"{what} cannot write `{s.key}`", errc=True)
        return DataOp(
            inst.index,
            f'{inst.reg_id} "{inst.node.display_name}" current_child_idx={{{op.key}}}',
            ops.WriteEntry(op.slot, s.entry.type_name, fail),
        )

    def entry(self, inst: Inst, op: EntryUse) -> DataOp:
        return DataOp(inst.index, f'{inst.reg_id} "{inst.node.display_name}" entry={op.key}', ops.EntrySeq(op.slot))

    @staticmethod
    def operand(slot: Optional[int], raw: Optional[str]) -> ops.TextOperand:
        """getInput<std::string> of a Switch's variable or case label."""
        if raw is None:
            return ops.TextOperand()
        return ops.TextOperand(slot, raw if slot is None else None)

    def switch(self, inst: Inst, op: SwitchUse) -> DataOp:
        reads = op.reads
        _name, raw, slot = reads[0]
        labels = tuple(self.operand(cslot, craw) for _cname, craw, cslot in reads[1:])
        return DataOp(
            inst.index,
            f'{inst.reg_id} "{inst.node.display_name}"',
            ops.SwitchCases(op.cases, self.operand(slot, raw), labels),
        )

    def loop(self, inst: Inst, op: LoopUse, locals_: list[LocalIR]) -> Optional[DataOp]:
        elem, static, qslot, vslot, loc = op.elem, op.static, op.qslot, op.vslot, op.loc
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
            want = kinds.queue_kind(elem)
            if s.kind != want and self.a.m.semantics.loop_queue_untyped and not is_user(s.kind):
                return self.loop_untyped(inst, op, locals_)
            if s.kind != want:
                self.error(
                    loc,
                    f"port `queue` of {what} reads blackboard entry `{s.key}`, which holds "
                    f"{describe_kind(s.kind or 'none')} ({s.origin_text}), not a {want}",
                )
                return None
            if self.a.m.semantics.loop_queue_untyped:  # (the interpreter's _queue_from_blackboard_410)
                no_value = self.fail(
                    loc,
                    f"port `queue` of {what} reads blackboard entry `{op.qkey}`, which has no value: it must "
                    f"hold a {want} or a string",
                )
            else:
                no_value = self.fail(
                    loc, f"port `queue` of {what} reads blackboard entry `{s.key}`, which has no value yet"
                )
        value = self.loop_value(inst, vslot, elem, what)
        if value is None:
            return None
        declared, write_fail = value
        return DataOp(
            inst.index,
            f"{what} queue={inst.ports['queue'].raw}",
            ops.LoopPop(elem, local, items, qslot, no_value, vslot, declared, write_fail),
        )

    def loop_value(
        self, inst: Inst, vslot: Optional[int], elem: str, what: str
    ) -> Optional[tuple[str, Optional[ops.Fail]]]:
        """A Loop's `value` port: the declared type of its entry and the failure of a write into
        it ("" and None without the port); None when the write is refused (reported)."""
        if vslot is None:
            return "", None
        vloc = inst.ports["value"].loc_or or inst.node.loc
        owner = (inst, "value", inst.ports["value"].raw)
        if not self.typed_write_ok(vslot, elem, vloc, f"port `value` of {what}", owner):
            return None
        if self.a.slots[vslot].kind == DYN:  # the prefix of btgen::port::write's message
            return self.a.slots[vslot].entry.type_name, self.fail(vloc, f"{what}: ")
        return self.a.slots[vslot].entry.type_name, self.fail(vloc, f"{what} cannot write its `value`", errc=True)

    def loop_untyped(self, inst: Inst, op: LoopUse, locals_: list[LocalIR]) -> Optional[DataOp]:
        """From 4.9.1 a Loop's `queue` port is untyped: an entry holding a string is converted
        into a private queue each time the loop starts (the interpreter's
        _queue_from_blackboard_410); one without a value, or holding anything but a string or
        a queue of the element type, makes the node throw."""
        elem, qslot, vslot, loc = op.elem, op.qslot, op.vslot, op.loc
        assert qslot is not None
        s = self.a.slots[qslot]
        what = f'`{inst.reg_id}` "{inst.node.display_name}"'
        read = f"port `queue` of {what} reads blackboard entry `{op.qkey}`, which"
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
        value = self.loop_value(inst, vslot, elem, what)
        if value is None:
            return None
        declared, write_fail = value
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
        k = self.a.kind_of_type(type_name)
        return self.a.user[k].cpp if is_user(k) else ""

    def user_read(self, inst: Inst, ps: PortSpec, slot: Optional[int], raw: str, loc: Loc) -> Optional[ops.PortRead]:
        """The getter statement of an input port where a user type (--type) is involved: a literal
        converted once when the mission is constructed, or the entry's value as it is."""
        pk = self.a.kind_of_type(ps.type)
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

    def user_literal(self, inst: Inst, ps: PortSpec, raw: str, loc: Loc, what: str) -> ops.PortRead:
        """A user-typed port's literal: converted once, when the mission is constructed (Spec::init)."""
        t = self.a.user[self.a.kind_of_type(ps.type) or ""]
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

    def user_write(self, inst: Inst, ps: PortSpec, slot: int, loc: Loc) -> Optional[ops.PortWrite]:
        """The setter of an output port where a user type (--type) is involved."""
        s = self.a.slots[slot]
        pk = self.a.kind_of_type(ps.type)
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
    def queue_port(self, inst: Inst, ps: PortSpec, entry: PortAccess, slot: Optional[int], loc: Loc) -> None:
        """A port of a user leaf declared BT::SharedQueue<T>: the accessors give a view of the
        queue entry it names (runtime/include/btgen/queue_view.hpp), as getInput and setOutput
        of the library's shared pointer do."""
        if slot is None:
            self.error(
                loc,
                f"port `{ps.name}` of {inst.what} is a queue ({ps.type}) given a literal; the C++ back "
                f"end connects a queue port of a user node only to a blackboard entry: not supported "
                f"by the C++ back end yet",
            )
            return
        s = self.a.slots[slot]
        if s.kind != self.a.kind_of_type(ps.type):
            if not any(at == loc for at, _ in self.a.reported):
                self.error(
                    loc,
                    f"port `{ps.name}` of {inst.what} ({ps.type}) is connected to blackboard entry "
                    f"`{s.key}`, which holds {describe_kind(s.kind or 'none')} ({s.origin_text}); a queue "
                    f"port of a user node reads and writes only a queue entry of its element type in the "
                    f"C++ back end",
                )
            return
        if ps.reads:
            entry.reads.append((inst.index, ops.ReadQueue(slot)))
        if ps.writes:
            fail = self.fail(
                loc,
                f"output port `{ps.name}` of {inst.what} cannot write `{s.key}` (at most {s.capacity} "
                f"elements" + (f" of {s.elem_capacity} bytes)" if s.elem_capacity else ")"),
                errc=True,
            )
            entry.writes.append((inst.index, ops.WriteQueue(slot, fail)))

    def ports(self) -> dict[str, tuple[PortIR, ...]]:
        by_model: dict[str, dict[str, PortAccess]] = {}
        for inst, op in self.a.node_ops:
            if not isinstance(op, PortUse):
                continue
            ps: PortSpec = op.port
            model = by_model.setdefault(inst.reg_id, {})
            entry = model.setdefault(ps.name, PortAccess(ps))
            slot, raw, p = op.slot, op.raw, op.p
            loc = p.loc_or or inst.node.loc
            if values.queue_element_type(ps.type) is not None:
                self.queue_port(inst, ps, entry, slot, loc)
                continue
            pk = self.a.kind_of_type(ps.type)
            # Ports read as text: string and opaque types, and untyped ports (whose T may be text).
            textual = ps.type in (values.ANY, values.STRING) or (values.is_opaque_type(ps.type) and not is_user(pk))
            if ps.reads and (is_user(pk) or (slot is not None and is_user(self.a.slots[slot].kind))):
                read = self.user_read(inst, ps, slot, raw, loc)
                if read is None:
                    continue
                entry.reads.append((inst.index, read))
            elif ps.reads:
                if slot is not None:
                    s = self.a.slots[slot]
                    if is_queue(s.kind):
                        self.error(loc, f"port `{ps.name}` of {inst.what} reads blackboard entry `{s.key}`, a {s.kind}")
                        continue
                    text = textual and (is_numeric(s.kind) or s.kind == DYN)
                    if text:
                        entry.scratch = True
                    entry.reads.append((inst.index, ops.ReadEntry(slot, text)))
                elif ps.type != values.ANY:
                    try:
                        value = values.convert_from_string(
                            ps.type if not values.is_opaque_type(ps.type) else values.STRING,
                            raw,
                            double_from_chars=self.a.m.semantics.double_from_chars,
                        )
                        entry.reads.append((inst.index, ops.ReadLiteral(ps.type, value)))
                    except values.ConversionError:
                        entry.reads.append((inst.index, ops.ReadLiteral(ps.type, None, ok=False)))
                else:
                    entry.reads.append((inst.index, ops.ParseLiteral(raw)))
            if ps.writes and slot is not None and (is_user(pk) or is_user(self.a.slots[slot].kind)):
                write = self.user_write(inst, ps, slot, loc)
                if write is not None:
                    entry.writes.append((inst.index, write))
            elif ps.writes and slot is not None:
                if ps.type != values.ANY and not self.typed_write_ok(
                    slot,
                    ps.type if not values.is_opaque_type(ps.type) else values.STRING,
                    loc,
                    f"output port `{ps.name}` of {inst.what}",
                    (inst, ps.name, raw),
                ):
                    continue
                s = self.a.slots[slot]
                if s.kind == DYN:  # the prefix of btgen::port::write's message
                    fail = self.fail(loc, f"{inst.what}: ")
                else:
                    fail = self.fail(loc, f"output port `{ps.name}` of {inst.what} cannot write `{s.key}`", errc=True)
                entry.writes.append((inst.index, ops.WriteEntry(slot, s.entry.type_name, fail)))
        # Every port a leaf model declares gets its accessors, wired here or not (one leaf
        # implementation builds against every mission using the model): in declaration order,
        # with 4.6.2's result on an instance that does not set it (getInput fails: kNotSet;
        # setOutput fails: false). Queue ports: a QueueView getter and a setter of any range.
        declared: dict[str, dict[str, PortAccess]] = {}
        for spec in self.a.m.used_user_models():
            used = by_model.get(spec.id, {})
            model = declared.setdefault(spec.id, {})
            for ps in spec.ports:
                model[ps.name] = used.get(ps.name, PortAccess(ps))
        by_model = declared
        out: dict[str, tuple[PortIR, ...]] = {}
        for model_id, ports in by_model.items():
            irs = []
            for pname, e in ports.items():
                ps = e.spec
                irs.append(
                    PortIR(
                        pname,
                        ps.direction,
                        ps.type,
                        ps.description,
                        e.scratch,
                        tuple(e.reads),
                        tuple(e.writes),
                        self.user_cpp(ps.type),
                        _narrow_range(ps.int_width),
                    )
                )
            out[model_id] = tuple(irs)
        return out

    # ------------------------------------------------------------ all
    def run(self) -> DataIR:
        self.mark_unsets()
        pools = self.queue_pools()
        scripts, bits = self.scripts()
        data_leaves: list[DataOp] = []
        entries: list[DataOp] = []
        switches: list[DataOp] = []
        loops: list[DataOp] = []
        param_reads: list[DataOp] = []
        index_writes: list[DataOp] = []
        locals_: list[LocalIR] = []
        params: dict[int, tuple[int, int, int]] = {}
        parallel_uses: dict[int, tuple[Inst, dict[str, ParamUse]]] = {}
        for inst, op in self.a.node_ops:
            code: Optional[DataOp] = None
            if isinstance(op, UnsetUse):
                data_leaves.append(self.unset(inst, op))
            elif isinstance(op, SetLiteralUse):
                code = self.set_literal(inst, op)
                if code is not None:
                    data_leaves.append(code)
            elif isinstance(op, SetCopyUse):
                code = self.set_copy(inst, op)
                if code is not None:
                    data_leaves.append(code)
            elif isinstance(op, SetKeyUse):
                code = self.set_key(inst, op)
                if code is not None:
                    data_leaves.append(code)
            elif isinstance(op, EntryUse):
                entries.append(self.entry(inst, op))
            elif isinstance(op, SwitchUse):
                switches.append(self.switch(inst, op))
            elif isinstance(op, LoopUse):
                code = self.loop(inst, op, locals_)
                if code is not None:
                    loops.append(code)
            elif isinstance(op, ParamUse) and inst.reg_id == "Parallel":
                parallel_uses.setdefault(inst.index, (inst, {}))[1][op.port] = op
            elif isinstance(op, ParamUse):
                read = self.param_read(inst, op)
                if read is not None:
                    param_reads.append(read)
                    params[inst.index] = (0, 1, 0)  # p1: read p0 from the blackboard (btgen::param)
            elif isinstance(op, IndexWriteUse):
                write = self.index_write(inst, op)
                if write is not None:
                    index_writes.append(write)
            elif isinstance(op, StatusParam):
                p0 = op.p0
                if op.throws is not None and op.where is not None:
                    # p1: Spec::read_param reports the error where the node reads the port
                    fail = self.fail(op.where, op.throws)
                    always = ops.ParamRead(-1, fail, fail, always=fail)
                    param_reads.append(DataOp(inst.index, f'{inst.reg_id} "{inst.node.display_name}"', always))
                    params[inst.index] = (0, 1, 0)
                elif p0 is not None:
                    params[inst.index] = (p0.value if isinstance(p0, NodeStatus) else p0, 0, 0)
        for inst, uses in parallel_uses.values():
            pread = self.parallel_read(inst, uses)
            if pread is not None:
                param_reads.append(pread)
                params[inst.index] = (0, 0, PARALLEL_READS)
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
                i in self.bt_any_slots or s.bt_any_at_load,
                s.at_load and s.bt_any_at_load,
                self.pool_of.get(i, ""),
            )
            for i, s in enumerate(self.a.slots)
        )
        used = {self.a.kind_of_type(ps.type) for spec in self.a.m.user_models() for ps in spec.ports} | {
            s.kind for s in self.a.slots
        }
        user_types = tuple(t for t in self.a.m.user_types if t.kind in used)
        return DataIR(
            slots,
            tuple(locals_ + self.user_locals + pools),
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
            tuple(index_writes),
        )


def _narrow_range(int_width: Optional[tuple[str, int, int]]) -> Optional[tuple[int, int]]:
    """The range of an integer port narrower than 32 bits (PortSpec.int_width), else None."""
    if int_width is None:
        return None
    _, lo, hi = int_width
    narrower = values.INT_MIN < lo < 0 if lo < 0 else hi < values.UNSIGNED_MAX
    return (lo, hi) if narrower else None
