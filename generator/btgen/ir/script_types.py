"""The typing pass of scripts: every expression's static kind, and the scripts that fail
whenever they run reported as compile errors (ScriptTypeError), before any C++ is written.

It walks a script as backend_cpp/script_cpp.py compiles it, with the same rules
(ir/kinds.py: what each operator gives, which stores are possible), keeping of
each value only what the rules read: its kind, its value when it is a literal,
and whether it is certain to have none. The C++ writer then meets no script it
cannot compile.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Optional

from btgen.ir.kinds import (
    DYN,
    binary_kind,
    check_compound,
    check_condition,
    check_dynamic_update,
    check_ternary_condition,
    compare_check,
    need_number,
    static_binary_ok,
    static_update_ok,
    store_route,
    ternary_is_dynamic,
)
from btgen.lang import script as sc


@dataclass(frozen=True)
class SlotType:
    """A slot as the typing pass sees it."""

    key: str
    kind: str
    declared: str  # values.py type name
    capacity: int  # strings: bytes
    origin: str = ""  # why it has its kind (for messages)


@dataclass(frozen=True)
class Typed:
    kind: str
    literal: object = None  # the value of a literal


def _literal(node: sc.Literal) -> Typed:
    v = node.value
    if isinstance(v, str):
        return Typed("string", v)
    if isinstance(v, float):
        return Typed("double", v)
    return Typed("int", v)


class ScriptTyper:
    """`slots[names[key]]` is the slot a name refers to (key, kind, declared, capacity, origin)."""

    def __init__(self, slots: Sequence[Any], names: Mapping[str, int]) -> None:
        self.slots = slots
        self.names = names

    def check(self, script: sc.Script, condition: bool) -> None:
        last: Optional[Typed] = None
        for stmt in script.statements:
            last = self.expr(stmt)
        if condition and last is not None and last.kind not in (DYN, "string", "none", "int"):
            check_condition(last.kind)

    def expr(self, node: sc.Expr) -> Typed:
        if isinstance(node, sc.Literal):
            return _literal(node)
        if isinstance(node, sc.Name):
            return Typed(self.slots[self.names[node.name]].kind)
        if isinstance(node, sc.Unary):
            v = self.expr(node.operand)
            if not (v.kind in (DYN, "string", "none") or (node.op == "~" and v.kind == "double")):
                need_number(node.op, v.kind, node.offset, "operand")
            return Typed("double")
        if isinstance(node, sc.Binary):
            lk, rk = self.expr(node.left).kind, self.expr(node.right).kind
            kind = binary_kind(node.op, lk, rk, node.op_offset)
            if DYN in (lk, rk) or not static_binary_ok(node.op, lk, rk) or kind in ("none", "string"):
                return Typed(kind)
            return Typed("double")
        if isinstance(node, sc.Compare):
            lk = self.expr(node.operands[0]).kind
            for op, off, operand in zip(node.ops, node.op_offsets, node.operands[1:]):
                rk = self.expr(operand).kind
                compare_check(op, lk, rk, off)
                lk = rk
            return Typed("double")
        if isinstance(node, sc.Ternary):
            ck = self.expr(node.cond).kind
            check_ternary_condition(ck, node.op_offset)
            tk, ek = self.expr(node.then).kind, self.expr(node.orelse).kind
            return Typed(DYN if ternary_is_dynamic(tk, ek, node.op_offset) else tk)
        return self.assign(node)

    def assign(self, node: sc.Assign) -> Typed:
        op, off = node.op, node.op_offset
        s = self.slots[self.names[node.target]]
        v = self.expr(node.value)
        if v.kind == "none":  # fails whenever it runs, as in 4.6.2: a run-time error
            return Typed("none")
        if (op not in (":=", "=") and not static_update_ok(op, s.kind, v.kind)) or DYN in (s.kind, v.kind):
            if s.kind != DYN:
                check_dynamic_update(s, op, node.target, off)
            return Typed(s.kind)
        if op in (":=", "="):
            store_route(s, v.kind, v.literal, off, f"`{node.target} {op} ...`")
        else:
            check_compound(s, node.target, op, v.kind, off)
        return Typed(s.kind)


def check_script(script: sc.Script, slots: Sequence[Any], names: Mapping[str, int], condition: bool) -> None:
    """Raises ScriptTypeError for the first part of `script` that fails whenever it runs."""
    ScriptTyper(slots, names).check(script, condition)
