"""The typing pass of scripts: every expression's static kind and how it is computed, and
the scripts that fail whenever they run reported as compile errors (ScriptTypeError),
before any C++ is written.

Scripts are typed here once, by the rules of ir/kinds.py (what each operator gives,
which stores are possible). The result, a TypedScript, records for every expression
its kind and the decisions the C++ writer needs (static or dynamic operation, the
route of a store, a literal converted through the entry's type); the writer
(backend_cpp/script_cpp/) only prints from it and reports nothing.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Optional

from btgen.ir.kinds import (
    DOUBLE,
    DYN,
    INT,
    NONE,
    STRING,
    binary_kind,
    check_compound,
    check_condition,
    check_dynamic_update,
    check_ternary_condition,
    compare_check,
    converted_literal,
    dynamic_store_route,
    dynamic_value_kinds,
    need_number,
    static_binary_ok,
    static_update_ok,
    store_route,
    ternary_is_dynamic,
)
from btgen.lang import script as sc
from btgen.lang.kind import KindLike


@dataclass(frozen=True)
class SlotType:
    """A slot as the typing pass sees it."""

    key: str
    kind: KindLike
    declared: str  # values.py type name
    capacity: int  # strings: bytes
    origin: str = ""  # why it has its kind (for messages)
    declared_kind: Optional[KindLike] = None  # the kind of the declared type (kinds.kind_of_type)
    # the release's convertFromString<double> (versions.Semantics.double_from_chars)
    double_from_chars: bool = False


@dataclass(frozen=True)
class ExprType:
    """What the typing pass decided about one expression of a script.

    kind:      its static kind (ir/kinds.py)
    literal:   its value, when it is a literal
    dynamic:   `-`/`!`/`~`, a binary operator, `?:`: computed on btgen::dyn values at run
               time (a dynamic operand, or a combination 4.6.2 only refuses when it runs)
    links:     a comparison chain: for each operator, whether it compares dynamically
    route:     an assignment: "none" (its value has none: fails whenever it runs),
               "dynamic" (a dynamic value or entry, or an update decided at run time),
               "compound" (`+= -= *= /=` of numbers, or `+=` of strings), "no value" (an
               update of an entry that never has one: fails where it runs), else how the
               value is stored (kinds.store_route: "same", "converted", "number_text",
               "number")
    converted: an assignment routed "converted": the string literal's converted value
    routes:    `:=`/`=` of a value of changing type into a statically typed entry: for each kind
               the value may hold, the store it gets (kinds.dynamic_store_route)
    """

    kind: KindLike
    literal: object = None
    dynamic: bool = False
    links: tuple[bool, ...] = ()
    route: str = ""
    converted: object = None
    routes: tuple[tuple[KindLike, str], ...] = ()


class TypedScript:
    """A script and the ExprType of each of its expressions (by identity: equal
    subexpressions at two places are two entries). The C++ writer prints from it."""

    def __init__(self, script: sc.Script, condition: bool) -> None:
        self.script = script
        self.condition = condition
        self._types: dict[int, ExprType] = {}

    def of(self, node: sc.Expr) -> ExprType:
        return self._types[id(node)]

    def record(self, node: sc.Expr, t: ExprType) -> ExprType:
        self._types[id(node)] = t
        return t


def _literal(node: sc.Literal) -> ExprType:
    v = node.value
    if isinstance(v, str):
        return ExprType(STRING, v)
    if isinstance(v, float):
        return ExprType(DOUBLE, v)
    return ExprType(INT, v)


class ScriptTyper:
    """`slots[names[key]]` is the slot a name refers to (key, kind, declared, capacity, origin)."""

    def __init__(self, slots: Sequence[Any], names: Mapping[str, int], typed: TypedScript) -> None:
        self.slots = slots
        self.names = names
        self.typed = typed

    def check(self, script: sc.Script, condition: bool) -> None:
        last: Optional[ExprType] = None
        for stmt in script.statements:
            last = self.expr(stmt)
        if condition and last is not None and last.kind not in (DYN, STRING, NONE, INT):
            check_condition(last.kind)

    def expr(self, node: sc.Expr) -> ExprType:
        return self.typed.record(node, self._expr(node))

    def _expr(self, node: sc.Expr) -> ExprType:
        if isinstance(node, sc.Literal):
            return _literal(node)
        if isinstance(node, sc.Name):
            return ExprType(self.slots[self.names[node.name]].kind)
        if isinstance(node, sc.Unary):
            v = self.expr(node.operand)
            # (a string, or no value: fails at run time as in 4.6.2; a double under `~` may be
            # out of range, which the dynamic operation words as the interpreter does)
            if v.kind in (DYN, STRING, NONE) or (node.op == "~" and v.kind == DOUBLE):
                return ExprType(DOUBLE, dynamic=True)
            need_number(node.op, v.kind, node.offset, "operand")
            return ExprType(DOUBLE)
        if isinstance(node, sc.Binary):
            lk, rk = self.expr(node.left).kind, self.expr(node.right).kind
            kind = binary_kind(node.op, lk, rk, node.op_offset)
            # (a double operand of a bit operator may not be whole: the dynamic operation names
            # the value in the error, as the interpreter does)
            if (
                DYN in (lk, rk)
                or not static_binary_ok(node.op, lk, rk)
                or (node.op in sc.BIT_OPS and DOUBLE in (lk, rk))
            ):
                return ExprType(DYN if kind == DYN else DOUBLE, dynamic=True)
            return ExprType(kind if kind in (NONE, STRING) else DOUBLE)
        if isinstance(node, sc.Compare):
            lk = self.expr(node.operands[0]).kind
            links = []
            for op, off, operand in zip(node.ops, node.op_offsets, node.operands[1:]):
                rk = self.expr(operand).kind
                compare_check(op, lk, rk, off)
                links.append(DYN in (lk, rk) or NONE in (lk, rk))
                lk = rk
            return ExprType(DOUBLE, links=tuple(links))
        if isinstance(node, sc.Ternary):
            ck = self.expr(node.cond).kind
            check_ternary_condition(ck, node.op_offset)
            tk, ek = self.expr(node.then).kind, self.expr(node.orelse).kind
            dynamic = ternary_is_dynamic(tk, ek, node.op_offset)
            return ExprType(DYN if dynamic else tk, dynamic=dynamic)
        return self.assign(node)

    def assign(self, node: sc.Assign) -> ExprType:
        op, off = node.op, node.op_offset
        s = self.slots[self.names[node.target]]
        v = self.expr(node.value)
        if v.kind == NONE:  # fails whenever it runs, as in 4.6.2: a run-time error
            return ExprType(NONE, route="none")
        if s.kind == NONE and op not in (":=", "="):  # `x += 1` of an entry that never has a value
            return ExprType(NONE, route="no value")
        if (op not in (":=", "=") and not static_update_ok(op, s.kind, v.kind)) or DYN in (s.kind, v.kind):
            if s.kind != DYN:
                kinds = dynamic_value_kinds(node.value, lambda n: self.typed.of(n).kind) if v.kind == DYN else ()
                check_dynamic_update(s, op, node.target, off, kinds)
                if op in (":=", "="):
                    routes = tuple((k, dynamic_store_route(s, k) or "") for k in kinds)
                    return ExprType(s.kind, route="dynamic", routes=routes)
            return ExprType(s.kind, route="dynamic")
        if op in (":=", "="):
            what = f"`{node.target} {op} ...`"
            route = store_route(s, v.kind, v.literal, off, what)
            converted = converted_literal(s, v.literal, off, what) if route == "converted" else None
            return ExprType(s.kind, route=route, converted=converted)
        check_compound(s, node.target, op, v.kind, off)
        return ExprType(s.kind, route="compound")


def type_script(script: sc.Script, slots: Sequence[Any], names: Mapping[str, int], condition: bool) -> TypedScript:
    """`script` typed; raises ScriptTypeError for the first part of it that fails whenever it runs."""
    typed = TypedScript(script, condition)
    ScriptTyper(slots, names, typed).check(script, condition)
    return typed
