"""Scripts whose names are all SubTree constants never written by any node (or no names at
all), evaluated once on the blackboards the data side loads: the node instances and the
entries each reads and writes."""

from __future__ import annotations

from typing import Optional

from btgen.diagnostics import Loc
from btgen.ir.data import records
from btgen.ir.data.resolve import Analysis as DataAnalysis
from btgen.lang import blackboard as bbmod
from btgen.lang import script as sc
from btgen.lang import values
from btgen.lang.model import Attr, Mission, SubTreeNode


def _owner_key(bb: bbmod.Blackboard, key: str) -> str:
    """The key of an entry on the blackboard that holds it (SubTree remaps followed)."""
    if key.startswith("@"):
        return key[1:]
    for _ in range(10000):
        if key in bb.local_keys() or bb.parent is None:
            return key
        remap = bb.remapping
        if key in remap:
            key = remap[key]
            if key.startswith("@"):
                return key[1:]
        elif not bb.autoremap:
            return key
        bb = bb.parent
    return key


class _Data:
    """The node instances of the data side, with the blackboard entries each reads and writes."""

    def __init__(self, mission: Mission, options: records.DataOptions) -> None:
        a = DataAnalysis(mission, options)
        a.load()
        self.insts = a.insts
        # entries the application sets before the first tick (--entry): written from the start
        self.provided = {eid for eid, i in a.slot_of_entry.items() if getattr(a.slots[i], "provided", False)}
        self.enums = dict(mission.enums)
        # id(entry) -> [(node index, loc, type or None)]
        self.reads: dict[int, list[tuple[int, Loc, Optional[str]]]] = {}
        self.writes: dict[int, list[tuple[int, Loc]]] = {}
        self.unsets: set[int] = set()
        self.script_reads: dict[int, list[tuple[int, Loc]]] = {}  # the reads of scripts alone
        self.entry_key: dict[int, str] = {}
        self.entries: dict[int, bbmod.Entry] = {}
        for inst in self.insts:
            self._collect(inst)

    def entry(self, bb: bbmod.Blackboard, key: str) -> Optional[bbmod.Entry]:
        try:
            e = bb.get_entry(key)
            if e is None:
                e = bb.create_entry(key, values.ANY)
        except (bbmod.BlackboardError, values.ConversionError):
            return None
        self.entry_key.setdefault(id(e), _owner_key(bb, key))
        self.entries[id(e)] = e
        return e

    def _read(self, inst, key: str, loc: Loc, type_name: Optional[str]) -> None:
        e = self.entry(inst.bb, key)
        if e is not None and not (key in self.enums and inst.bb.get_entry(key) is e and e.value is None):
            self.reads.setdefault(id(e), []).append((inst.index, loc, type_name))

    def _write(self, inst, key: str, loc: Loc) -> None:
        e = self.entry(inst.bb, key)
        if e is not None:
            self.writes.setdefault(id(e), []).append((inst.index, loc))

    def _script(self, inst, attr: Attr) -> None:
        script = attr.script
        if script is None:
            return
        for name in sc.variables_read(script):
            if name not in self.enums:
                self._read(inst, name, attr.value_loc, None)
                e = self.entry(inst.bb, name)
                if e is not None:
                    self.script_reads.setdefault(id(e), []).append((inst.index, attr.value_loc))
        for name in sc.variables_written(script):
            self._write(inst, name, attr.value_loc)

    def _collect(self, inst) -> None:
        node = inst.node
        for attr in node.pre + node.post:
            self._script(inst, attr)
        if isinstance(node, SubTreeNode) or inst.spec is None:
            return
        nid = inst.reg_id
        if nid in ("Script", "ScriptCondition", "Precondition"):
            p = inst.ports.get("code" if nid != "Precondition" else "if")
            if p is not None and p.attr is not None:
                self._script(inst, p.attr)
            return
        if nid == "SetBlackboard":
            out, val = inst.ports.get("output_key"), inst.ports.get("value")
            if out is not None and not bbmod.is_blackboard_pointer(out.raw):
                self._write(inst, out.raw, out.loc_or or node.loc)
            if val is not None:
                key = bbmod.strip_blackboard_pointer(val.raw)
                if key is not None:
                    self._read(inst, key, val.loc_or or node.loc, None)
            return
        if nid == "UnsetBlackboard":
            p = inst.ports.get("key")
            if p is not None and not bbmod.is_blackboard_pointer(p.raw):
                e = self.entry(inst.bb, p.raw)
                if e is not None:
                    self.unsets.add(id(e))
            return
        for ps in inst.spec.ports:
            p = inst.ports.get(ps.name)
            if p is None:
                continue
            key = bbmod.remapped_key(ps.name, p.raw)
            if key is None:
                continue
            loc = p.loc_or or node.loc
            if nid in records.ENTRY_NODES:  # they read the update counter, not the value
                self._read(inst, key, loc, None)
                continue
            if ps.reads:
                self._read(inst, key, loc, ps.type if ps.type not in (values.ANY, "any") else None)
            if ps.writes:
                self._write(inst, key, loc)

    def constant(self, index: int, attr: Attr) -> Optional[bool]:
        """The value of a condition script that is the same whenever it runs, else None."""
        script = attr.script
        if script is None or sc.variables_written(script):
            return None
        inst = self.insts[index]
        for name in sc.variables_read(script):
            if name in self.enums:
                continue
            e = inst.bb.get_entry(name)
            if e is None or e.value is None or id(e) in self.writes or id(e) in self.unsets:
                return None
        try:
            return sc.script_truth(sc.evaluate(script, inst.bb, self.enums))
        except Exception:  # a script error whenever it runs: the run reports it, not us
            return None
