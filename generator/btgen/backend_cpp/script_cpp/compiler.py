"""Scripts -> C++: the 4.6.2 script language compiled with static types.

Every script of a mission (Script and ScriptCondition `code`, Precondition
`if`, Switch-free pre/post conditions `_skipIf` ... `_post`) is parsed by the
front end (script.py). Here its AST becomes straight-line C++ over the
mission's typed blackboard: the static kind of every subexpression is known
(the blackboard entries have one type each, see dataflow.py), so each
operator compiles to the one operation 4.6.2 would pick at run time for
those kinds. What 4.6.2 can only find out at run time (an entry that does
not exist yet or has no value, an integer that does not fit, a string that
is not a number) becomes a check that reports through the mission's error
hook and fails the node; what is certain to fail whenever the script runs
(a string where a number is needed, `..` of two numbers used as a value)
is a compile error, reported by the typing pass (ir/script_types.py). The
script arrives typed (a TypedScript: every expression's kind and how it is
computed, static or dynamic, the route of every store); this module only
prints C++ from it and reports nothing.

Kinds (the static types of values):

    int       std::int64_t   integers (script literals, int/unsigned entries)
    double    double         real literals; every arithmetic, comparison, logic result
    bool      bool           (only in conversions: bool entries hold integers, as 4.6.2's Any does)
    status    btgen::Status  entries declared NodeStatus
    string    FixedString<N> / std::string_view
    queue<T>  FixedQueue     entries of Loop nodes (scripts cannot use them)
    none      -              no value ever (`1 .. 2`, an entry nothing writes)

Evaluation order, short-circuiting (only comparison chains stop early; `&&`
and `||` evaluate both sides), the double arithmetic and the text of numbers
are those of btgen/lang/script.py, which is the reference.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

from btgen.backend_cpp.literals import cpp_double, cpp_int64, cpp_view
from btgen.backend_cpp.naming import slot_members
from btgen.backend_cpp.script_cpp.stores import dyn_slot_bound, guard_type_change, store_number, store_value
from btgen.backend_cpp.script_cpp.writer import (
    CPP_SCALAR,
    DYN_FIELD,
    DYN_TAG,
    CodeWriter,
    ErrorTable,
    ScriptContext,
    SlotView,
    Val,
)
from btgen.diagnostics import Loc
from btgen.ir.data.records import DataIR, ScriptSlot, script_loc
from btgen.ir.kinds import DYN, TEXT_BOUND, is_queue
from btgen.ir.script_types import ExprType, TypedScript
from btgen.lang import script as sc
from btgen.lang import values
from btgen.lang.blackboard import RAW_COPY_TYPES
from btgen.lang.kind import KindLike

# btgen::Declared of the declared types RAW_COPY_TYPES names (data_cpp.DECLARED_ENUM has them all).
DECLARED_ENUM_OF = {values.INT: "kInt", values.UNSIGNED: "kUnsigned", values.DOUBLE: "kDouble", values.BOOL: "kBool"}


class ScriptCompiler(CodeWriter):
    """Compiles one script to the body of `int f(Blackboard& bb, const btgen::NodeInfo& n,
    const btgen::ErrorSink& err)`: -1 after an error was reported, else 1 (a statement
    script) or the truth of the last statement (a condition)."""

    def __init__(self, ctx: ScriptContext, typed: TypedScript) -> None:
        super().__init__(ctx.where, ctx.prefix)
        self.ctx = ctx
        self.typed = typed
        self.errors = ctx.errors
        if ctx.enums:
            self.msg_args = ", detail::kScriptingEnums.data(), detail::kScriptingEnums.size()"
        self.assigned: dict[int, int] = {}  # slot -> assignments in the current statement

    def slot(self, name: str) -> SlotView:
        return self.ctx.slots[self.ctx.names[name]]

    # ------------------------------------------------------------ entry points
    def type_of(self, node: sc.Expr) -> ExprType:
        return self.typed.of(node)

    def compile(self) -> list[str]:
        script, condition = self.typed.script, self.typed.condition
        last: Optional[Val] = None
        for stmt in script.statements:
            self.assigned = {}
            for node in sc.walk(stmt):
                if isinstance(node, sc.Assign):
                    idx = self.ctx.names[node.target]
                    self.assigned[idx] = self.assigned.get(idx, 0) + 1
            last = self.expr(stmt)
        if not condition:
            self.emit("return 1;")
            return self.lines
        if last is None:  # an empty ScriptCondition / Precondition: it throws whenever it runs
            self.emit(self.fail(0, "the script gives no value, so it cannot be used as a condition"))
            return self.lines
        self.truth(last)
        return self.lines

    def truth(self, v: Val) -> None:
        """script_truth of the last statement's value, returned."""
        if v.kind in (DYN, "string", "none", "int", "double"):  # a negative number is an error
            t = self.temp()
            self.emit(f"btgen::dyn::Msg {t}m({self.prefix_view()});")
            self.emit(f"const int {t} = btgen::dyn::truth({self.to_ref(v)}, {t}m);")
            self.emit(f"if ({t} < 0) return err.fail(n, {self.where_at(0)}, {t}m.view());")
            self.emit(f"return {t};")
            return
        if v.has is not None:
            self.check(f"!{v.has}", 0, "the script gives no value, so it cannot be used as a condition")
        if v.kind == "bool":
            self.emit(f"return btgen::script::truth({v.expr});")
            return
        t = self.temp()
        self.emit(f"const int {t} = btgen::script::truth({v.expr});")
        self.check(
            f"{t} < 0",
            0,
            "the script's result cannot be used as a condition: only the integers 0 and 1 convert to bool",
        )
        self.emit(f"return {t};")

    # ------------------------------------------------------------ expressions
    def expr(self, node: sc.Expr) -> Val:
        if isinstance(node, sc.Literal):
            return self.literal(node)
        if isinstance(node, sc.Name):
            return self.name(node)
        if isinstance(node, sc.Unary):
            return self.unary(node)
        if isinstance(node, sc.Binary):
            return self.binary(node)
        if isinstance(node, sc.Compare):
            return self.compare(node)
        if isinstance(node, sc.Ternary):
            return self.ternary(node)
        return self.assign(node)

    def literal(self, node: sc.Literal) -> Val:
        v = node.value
        if isinstance(v, str):
            return Val("string", cpp_view(v), None, len(v.encode("utf-8")), v)
        if isinstance(v, float):
            return Val("double", cpp_double(v), None, 0, v)
        return Val("int", cpp_int64(v), None, 0, v)

    def name(self, node: sc.Name) -> Val:
        s = self.slot(node.name)
        if s.may_be_missing:
            self.check(
                f"!{s.member}.exists",
                node.offset,
                f"unknown variable `{node.name}` (no blackboard entry of that name; create it with "
                f"`{node.name} := ...`)",
            )
        if s.kind == "none":
            return Val("none", None, "false")
        if is_queue(s.kind):
            return Val(s.kind, None, None)
        if s.kind == DYN:
            t = self.temp()
            if self.assigned.get(self.ctx.names[node.name], 0) > 0:
                self.emit(f"const auto {t}c = {s.member};")
                self.emit(f"const btgen::dyn::Ref {t} = btgen::dyn::ref({t}c);")
            else:
                self.emit(f"const btgen::dyn::Ref {t} = btgen::dyn::ref({s.member});")
            return Val(DYN, t, None, dyn_slot_bound(s))
        h = self.temp() + "h"
        self.emit(f"[[maybe_unused]] const bool {h} = {s.member}.has_value;")
        if s.kind == "string":
            if self.assigned.get(self.ctx.names[node.name], 0) > 0:
                t = self.temp()
                self.emit(f"btgen::FixedString<{s.capacity}> {t};")
                self.emit(f"(void){t}.assign({s.member}.value.view());")
                return Val("string", f"{t}.view()", h, s.capacity)
            return Val("string", f"{s.member}.value.view()", h, s.capacity)
        t = self.temp()
        self.emit(f"[[maybe_unused]] const {CPP_SCALAR[s.kind]} {t} = {s.member}.value;")
        return Val(s.kind, t, h)

    def need_value(self, v: Val, offset: int, what: str) -> None:
        if v.has is not None:
            self.check(f"!{v.has}", offset, f"{what} has no value")

    def as_int64(self, v: Val, offset: int, message: str) -> str:
        if v.kind == "int":
            return v.expr  # type: ignore[return-value]
        t = self.temp()
        self.emit(f"std::int64_t {t} = 0;")
        if v.kind == "double":
            self.errc_check(f"btgen::script::whole({v.expr}, {t})", offset, message)
        else:
            self.emit(f"(void)btgen::script::whole({v.expr}, {t});")
        return t

    def as_text(self, v: Val) -> tuple[str, int]:
        """A std::string_view of the value's text (std::to_string for numbers) and its bound."""
        if v.kind == "string":
            return v.expr, v.bound  # type: ignore[return-value]
        if v.literal is not None:
            text = values.to_text(v.literal)  # type: ignore[arg-type]
            return cpp_view(text), len(text)
        t = self.temp()
        self.emit(f"const btgen::NumberText {t}({v.expr});")
        return f"{t}.view()", TEXT_BOUND[v.kind]

    def unary(self, node: sc.Unary) -> Val:
        v = self.expr(node.operand)
        if self.type_of(node).dynamic:
            t = self.temp()
            self.emit(f"double {t} = 0.0;")
            self.dyn_call(f"btgen::dyn::unary('{node.op}', {self.to_ref(v)}, {t}, dm)", node.offset)
            return Val("double", t, None)
        self.need_value(v, node.offset, f"the operand of `{node.op}`")
        d = self.as_double(v, node.offset, f"operand of `{node.op}`")
        t = self.temp()
        if node.op == "-":
            self.emit(f"const double {t} = -({d});" if d.startswith("-") else f"const double {t} = -{d};")
        elif node.op == "!":
            self.emit(f"const double {t} = btgen::script::logical_not({d});")
        else:
            self.emit(f"double {t} = 0.0;")
            self.errc_check(f"btgen::script::complement({d}, {t})", node.offset, "the operand of `~` is out of range")
        return Val("double", t, None)

    def binary(self, node: sc.Binary) -> Val:
        op, off = node.op, node.op_offset
        lv = self.expr(node.left)
        rv = self.expr(node.right)
        typed = self.type_of(node)
        kind = typed.kind
        if typed.dynamic:
            return self.dyn_binary(op, off, lv, rv, kind)
        self.need_value(lv, off, f"the left operand of `{op}`")
        self.need_value(rv, off, f"the right operand of `{op}`")
        if kind == "none":
            return Val("none", None, "false")
        if kind == "string":
            lt, lb = self.as_text(lv)
            rt, rb = self.as_text(rv)
            grown = self._grow_concat(lv, rt, lb + rb)
            if grown is not None:
                return grown
            t = self.temp()
            self._concats[f"{t}.view()"] = (self.lines, len(self.lines), self.indent, t)
            self.emit(f"btgen::FixedString<{lb + rb}> {t};")
            self.emit(f"(void){t}.assign({lt});")
            self.emit(f"(void){t}.append({rt});")
            return Val("string", f"{t}.view()", None, lb + rb)
        t = self.temp()
        if op in ("+", "-", "*", "/"):
            a = self.as_double(lv, off, f"left operand of `{op}`")
            b = self.as_double(rv, off, f"right operand of `{op}`")
            rhs = f"btgen::script::div({a}, {b})" if op == "/" else f"{a} {op} {b}"
            self.emit(f"const double {t} = {rhs};")
        elif op in sc.BIT_OPS:
            msg = f"`{op}` needs whole-number operands"
            a = self.as_int64(lv, off, msg)
            b = self.as_int64(rv, off, msg)
            self.emit(f"const double {t} = static_cast<double>({a} {op} {b});")
        else:  # && ||
            a = self.as_truth(lv, off, op)
            b = self.as_truth(rv, off, op)
            cop = "&&" if op == "&&" else "||"
            self.emit(f"const double {t} = ({a} {cop} {b}) ? 1.0 : 0.0;")
        return Val("double", t, None)

    def _grow_concat(self, lv: Val, rt: str, bound: int) -> Optional[Val]:
        """`a .. b .. c` is `(a .. b) .. c`: when the left operand is the buffer of a
        concatenation just made in this block, widen that buffer and append to it, so a
        chain of n terms needs one buffer (linear stack) instead of n growing ones (their
        sizes add up to the square: a 1 MiB capacity and five terms overflowed the stack)."""
        made = self._concats.pop(lv.expr or "", None)
        if made is None:
            return None
        lines, at, indent, t = made
        if lines is not self.lines or indent != self.indent:
            return None
        lines[at] = "  " * indent + f"btgen::FixedString<{bound}> {t};"
        self.emit(f"(void){t}.append({rt});")
        self._concats[lv.expr] = made  # type: ignore[index]
        return Val("string", lv.expr, None, bound)

    def dyn_bound(self, v: Val) -> int:
        if v.kind in (DYN, "string"):
            return v.bound
        return TEXT_BOUND.get(v.kind, 0)

    def dyn_binary(self, op: str, off: int, lv: Val, rv: Val, kind: KindLike) -> Val:
        code = {"..": "c", "&&": "a", "||": "o"}.get(op, op)
        bound = self.dyn_bound(lv) + self.dyn_bound(rv) if kind == DYN else 1
        t = self.temp()
        self.emit(f"btgen::FixedString<{bound}> {t}b;")
        self.emit(f"btgen::dyn::Ref {t};")
        self.dyn_call(f"btgen::dyn::binary('{code}', {self.to_ref(lv)}, {self.to_ref(rv)}, {t}, {t}b, dm)", off)
        if kind == DYN:
            return Val(DYN, t, None, bound)
        return Val("double", f"{t}.d", None)

    def as_truth(self, v: Val, offset: int, op: str) -> str:
        if v.kind == "bool":
            return v.expr  # type: ignore[return-value]
        t = self.temp()
        self.emit(f"bool {t} = false;")
        self.dyn_call(f"btgen::dyn::logic_operand({cpp_view(op)}, {self.to_ref(v)}, {t}, dm)", offset)
        return t

    def compare(self, node: sc.Compare) -> Val:
        r = self.temp()
        self.emit(f"double {r} = 0.0;")
        self.emit("do {")
        self.indent += 1
        lv = self.expr(node.operands[0])
        links = self.type_of(node).links
        for op, off, operand, dynamic in zip(node.ops, node.op_offsets, node.operands[1:], links):
            rv = self.expr(operand)
            if dynamic:
                c = self.temp()
                self.emit(f"bool {c} = false;")
                self.dyn_call(
                    f"btgen::dyn::compare({cpp_view(op)}, {self.to_ref(lv)}, {self.to_ref(rv)}, {c}, dm)", off
                )
                self.emit(f"if (!{c}) break;")
                lv = rv
                continue
            self.need_value(lv, off, f"the left operand of `{op}`")
            self.need_value(rv, off, f"the right operand of `{op}`")
            fn = {"==": "eq", "!=": "ne", "<": "lt", ">": "gt", "<=": "le", ">=": "ge"}[op]
            if lv.kind == "string" and rv.kind == "string":
                a, b = lv.expr, rv.expr
            else:
                a = (
                    self.text_number(lv, off, op, "left")
                    if lv.kind == "string"
                    else self.as_double(lv, off, f"left operand of `{op}`")
                )
                b = (
                    self.text_number(rv, off, op, "right")
                    if rv.kind == "string"
                    else self.as_double(rv, off, f"right operand of `{op}`")
                )
            self.emit(f"if (!btgen::script::{fn}({a}, {b})) break;")
            lv = rv
        self.emit(f"{r} = 1.0;")
        self.indent -= 1
        self.emit("} while (false);")
        return Val("double", r, None)

    def ternary(self, node: sc.Ternary) -> Val:
        cv = self.expr(node.cond)
        if cv.kind == DYN:
            c = self.temp()
            self.emit(f"double {c} = 0.0;")
            self.dyn_call(f"btgen::dyn::condition({cv.expr}, {c}, dm)", node.op_offset)
            return self.ternary_branches(node, c)
        self.need_value(cv, node.op_offset, "the condition of `?:`")
        if cv.kind == "string":
            c = self.temp()
            self.emit(f"double {c} = 0.0;")
            self.errc_check(
                f"btgen::cast_double({cv.expr}, {c})",
                node.op_offset,
                "the condition of `?:` is a string that is not a number",
            )
        else:
            c = self.as_double(cv, node.op_offset, "condition of `?:`")
        return self.ternary_branches(node, c)

    def ternary_branches(self, node: sc.Ternary, c: str) -> Val:
        # The result's kind: both branches must agree (checked once both are compiled), or
        # one is dynamic and the result is too.
        r = self.temp()
        rh = r + "h"
        decl_at = len(self.lines)
        self.emit(f"bool {rh} = false;")
        self.emit(f"if ({c} != 0.0) {{")
        self.indent += 1
        tv = self.expr(node.then)
        then_at = len(self.lines)
        self.indent -= 1
        self.emit("} else {")
        self.indent += 1
        ev = self.expr(node.orelse)
        else_at = len(self.lines)
        self.indent -= 1
        self.emit("}")
        pad = "  " * self.indent
        dynamic = self.type_of(node).dynamic
        # The takes, inserted at the end of each branch (the else branch first: indexes stay valid).
        for at, v in ((else_at, ev), (then_at, tv)):
            saved, self.lines = self.lines, []
            self.indent += 1
            self._ternary_take(r, rh, v, dynamic)
            self.indent -= 1
            take, self.lines = self.lines, saved
            self.lines[at:at] = take
        kind = tv.kind
        if dynamic:
            bound = max(self.dyn_bound(tv), self.dyn_bound(ev), 1)
            self.lines.insert(decl_at, f"{pad}btgen::Dyn<{bound}> {r};")
            return Val(DYN, f"({rh} ? {r}.ref() : btgen::dyn::Ref{{}})", None, bound)
        if kind == "none" or is_queue(kind):
            return Val(kind, None, "false" if kind == "none" else None)
        if kind == "string":
            bound = max(tv.bound, ev.bound)
            self.lines.insert(decl_at, f"{pad}btgen::FixedString<{bound}> {r};")
            return Val("string", f"{r}.view()", rh, bound)
        self.lines.insert(decl_at, f"{pad}{CPP_SCALAR[kind]} {r}{{}};")
        return Val(kind, r, rh)

    def _ternary_take(self, r: str, rh: str, v: Val, dynamic: bool = False) -> None:
        if dynamic:
            ref = self.to_ref(v)
            self.emit(f"(void){r}.set({ref});")
            self.emit(
                f"{rh} = !{r}.ref().none();" if v.kind == DYN else f"{rh} = {v.has if v.has is not None else 'true'};"
            )
            return
        if v.kind == "none" or is_queue(v.kind):
            return
        if v.kind == "string":
            self.emit(f"(void){r}.assign({v.expr});")
        else:
            self.emit(f"{r} = {v.expr};")
        self.emit(f"{rh} = {v.has if v.has is not None else 'true'};")

    # ------------------------------------------------------------ assignment
    def assign(self, node: sc.Assign) -> Val:
        op, off = node.op, node.op_offset
        idx = self.ctx.names[node.target]
        s = self.ctx.slots[idx]
        if op == ":=":
            if s.may_be_missing and self.ctx.counts_births:  # (a new entry: when, for the storage's order)
                self.emit(f"if (!{s.member}.exists) {{")
                self.emit(f"  {s.member}.exists = true;")
                self.emit(f"  {s.member}.born = ++bb.births_;")
                self.emit("}")
            elif s.may_be_missing:
                self.emit(f"{s.member}.exists = true;")
        elif s.may_be_missing:
            self.check(
                f"!{s.member}.exists",
                off,
                f"blackboard entry `{node.target}` does not exist yet; use `:=` to create it",
            )
        v = self.expr(node.value)
        typed = self.type_of(node)
        if typed.route == "none":  # `x := 1 .. 2`: 4.6.2 fails whenever this runs
            self.emit(self.fail(off, f"the right operand of `{op}` has no value"))
            return Val("none", None, "false")
        if typed.route == "dynamic":
            return self.dyn_assign(node, idx, s, v)
        self.need_value(v, off, f"the right operand of `{op}`")
        if typed.route == "no value":  # an update of an entry that never has a value
            self.emit(self.fail(off, f"`{node.target}` has no value yet, so `{op}` cannot update it"))
            return Val("none", None, "false")
        if op in (":=", "="):
            store_value(self, s, v, off, f"`{node.target} {op} ...`", op, typed)
        else:
            self.compound(s, node.target, op, v, off)
        self.emit(f"{s.member}.mark_written();")
        return self.stored(idx, s)

    def stored(self, idx: int, s: SlotView) -> Val:
        """The value of an assignment to the statically typed slot `s` (index `idx`)."""
        if s.kind == "none" or is_queue(s.kind):
            return Val(s.kind, None, None)
        if self.assigned.get(idx, 0) <= 1:  # nothing later in the statement changes it
            expr = f"{s.member}.value.view()" if s.kind == "string" else f"{s.member}.value"
            return Val(s.kind, expr, None, s.capacity)
        t = self.temp()
        if s.kind == "string":
            self.emit(f"btgen::FixedString<{s.capacity}> {t};")
            self.emit(f"(void){t}.assign({s.member}.value.view());")
            return Val("string", f"{t}.view()", None, s.capacity)
        self.emit(f"[[maybe_unused]] const {CPP_SCALAR[s.kind]} {t} = {s.member}.value;")
        return Val(s.kind, t, None)

    def dyn_assign(self, node: sc.Assign, idx: int, s: SlotView, v: Val) -> Val:
        """An assignment whose target or value is dynamic (the entry exists by now)."""
        op, off, key = node.op, node.op_offset, node.target
        ref = self.to_ref(v)
        if v.kind == DYN or v.has is not None:
            self.check(f"({ref}).none()", off, f"the right operand of `{op}` has no value")
        if s.kind == DYN:
            if op in (":=", "=") and s.declared in RAW_COPY_TYPES:
                # a typed entry a 4.6.2 SetBlackboard copy made dynamic: it keeps its converter
                self.dyn_call(
                    f"btgen::port::store_declared<detail::Semantics::double_from_chars>({s.member}, "
                    f"btgen::Declared::{DECLARED_ENUM_OF[s.declared]}, {cpp_view(s.declared)}, {ref}, "
                    f"{cpp_view(key)}, dm)",
                    off,
                )
            elif op in (":=", "="):  # (dyn::store checks an entry typed BT::Any)
                store = "btgen::dyn::store<detail::Semantics::double_from_chars>"
                self.dyn_call(f"{store}({s.member}, {ref}, {cpp_view(key)}, dm)", off)
            else:
                t = self.temp()
                # room for the text of whatever the entry holds, so that only the store reports
                # a text that does not fit
                self.emit(f"btgen::FixedString<{dyn_slot_bound(s) + self.dyn_bound(v)}> {t}b;")
                self.emit(f"btgen::dyn::Ref {t};")
                self.dyn_call(
                    f"btgen::dyn::compound('{op[0]}', btgen::dyn::ref({s.member}), {ref}, "
                    f"{cpp_view(key)}, {t}, {t}b, dm)",
                    off,
                )
                self.dyn_call(f"btgen::dyn::put({s.member}, {t}, {cpp_view(key)}, dm)", off)
            if self.assigned.get(idx, 0) <= 1:
                return Val(DYN, f"btgen::dyn::ref({s.member})", None, dyn_slot_bound(s))
            t = self.temp()
            self.emit(f"const auto {t}c = {s.member};")
            self.emit(f"const btgen::dyn::Ref {t} = btgen::dyn::ref({t}c);")
            return Val(DYN, t, None, dyn_slot_bound(s))
        if op in (":=", "="):
            return self.dyn_store(node, idx, s, v, ref)
        # A dynamic value into a statically typed entry: an update (`+=` ...), whose result
        # keeps the entry's kind (or fails as 4.6.2 does).
        cur = Val(
            s.kind,
            f"{s.member}.value.view()" if s.kind == "string" else f"{s.member}.value",
            f"{s.member}.has_value",
            s.capacity,
        )
        t = self.temp()
        # the text of the entry (a number's, when `+=` appends a string) and the value
        self.emit(f"btgen::FixedString<{self.dyn_bound(cur) + self.dyn_bound(v)}> {t}b;")
        self.emit(f"btgen::dyn::Ref {t};")
        self.dyn_call(
            f"btgen::dyn::compound('{op[0]}', {self.to_ref(cur)}, {ref}, {cpp_view(key)}, {t}, {t}b, dm)", off
        )
        if s.kind == "string":
            self.check(
                f"!{s.member}.value.assign({t}.s)",
                off,
                f"the text of `{key}` would be longer than its capacity ({s.capacity} bytes)",
            )
        elif s.kind == "double":
            self.emit(f"{s.member}.value = {t}.d;")
        elif s.kind == "status":
            self.emit(f"{s.member}.value = static_cast<btgen::Status>({t}.i);")
        elif s.kind == "bool":
            self.emit(f"{s.member}.value = {t}.i != 0;")
        else:
            self.emit(f"{s.member}.value = {t}.i;")
        self.emit(f"{s.member}.mark_written();")
        return Val(s.kind, f"{s.member}.value.view()" if s.kind == "string" else f"{s.member}.value", None, s.capacity)

    def dyn_store(self, node: sc.Assign, idx: int, s: SlotView, v: Val, ref: str) -> Val:
        """`key := value` (and `=`) of a value of changing type into the statically typed
        entry `s`: at run time, the store a value of the kind it holds would get (store_value,
        by the route the typing pass chose for each kind it may hold: ExprType.routes)."""
        op, off, key = node.op, node.op_offset, node.target
        what = f"`{key} {op} ...`"
        t = self.temp()
        self.emit(f"const btgen::dyn::Ref {t} = {ref};")
        bound = self.dyn_bound(v)
        for n, (r, route) in enumerate(self.type_of(node).routes):
            self.emit(f"{'} else if' if n else 'if'} ({t}.tag == btgen::DynTag::{DYN_TAG[r]}) {{")
            self.indent += 1
            rv = Val(r, DYN_FIELD[r].format(t), None, bound if r == "string" else 0)
            if route == "refused":
                # Any::copyInto refuses a number where a string is (an empty entry would change
                # its type, which a static store reports too)
                guard_type_change(self, s, r, off, what)
                self.emit(f"btgen::dyn::Ref {t}r;")
                self.dyn_call(
                    f"btgen::dyn::store_into({t}, btgen::dyn::of_string({{}}), {cpp_view(op)}, "
                    f"{cpp_view(key)}, {t}r, dm)",
                    off,
                )
            else:
                store_value(self, s, rv, off, what, op, ExprType(s.kind, route=route))
            self.indent -= 1
        self.emit("}")
        self.emit(f"{s.member}.mark_written();")
        return self.stored(idx, s)

    def compound(self, s: SlotView, key: str, op: str, v: Val, off: int) -> None:
        """`+= -= *= /=`: 4.6.2's ExprAssignment for an entry that has a value."""
        self.check(f"!{s.member}.has_value", off, f"`{key}` has no value yet, so `{op}` cannot update it")
        if v.kind == "string":
            self.check(
                f"!{s.member}.value.append({v.expr})",
                off,
                f"the text of `{key}` would be longer than its capacity ({s.capacity} bytes)",
            )
            return
        exact = 2**53  # integers up to this convert to double and back without loss
        if s.kind == "int" and op in ("+=", "-=") and isinstance(v.literal, int) and abs(v.literal) <= exact:
            # `n += 1` on an integer: 4.6.2 computes in double and stores the whole result back;
            # while n and the result stay within 2^53 that is the integer sum itself, one
            # statement. Outside, the double arithmetic below (its errors included).
            c = v.literal if op == "+=" else -v.literal
            lo, hi = max(-exact, -exact - c), min(exact, exact - c)
            m = f"{s.member}.value"
            self.emit(f"if ({m} >= {cpp_int64(lo)} && {m} <= {cpp_int64(hi)}) {{")
            self.emit(f"  {m} {op} {cpp_int64(v.literal)};")
            self.emit("} else {")
            self.indent += 1
            self._compound_number(s, key, op, v, off)
            self.indent -= 1
            self.emit("}")
            return
        self._compound_number(s, key, op, v, off)

    def _compound_number(self, s: SlotView, key: str, op: str, v: Val, off: int) -> None:
        cur = Val(s.kind, f"{s.member}.value", None)
        a = self.as_double(cur, off, f"`{key}`")
        b = self.as_double(v, off, f"right operand of `{op}`")
        t = self.temp()
        rhs = f"btgen::script::div({a}, {b})" if op[0] == "/" else f"{a} {op[0]} {b}"
        self.emit(f"const double {t} = {rhs};")
        store_number(self, s, Val("double", t, None), off, f"`{key} {op} ...`", op, guard=False)


def compile_script(typed: TypedScript, ctx: ScriptContext) -> list[str]:
    """The C++ body of one typed script (see ScriptCompiler)."""
    return ScriptCompiler(ctx, typed).compile()


@dataclass(frozen=True)
class CompiledScript:
    """A script written as C++: the body of its (possibly shared) function, and the places and
    messages of its errors (ErrorTable) with the prefix, for its node's ScriptSite."""

    node: int
    which: ScriptSlot
    comment: str
    body: tuple[str, ...]
    errors: tuple[tuple[str, str], ...]
    prefix: str


def compile_scripts(data: DataIR) -> tuple[list[CompiledScript], tuple[Loc, ...]]:
    """Every typed script of the mission as C++, and the places run-time errors name: the
    data side's (DataIR.where) followed by the scripts' own, each once."""
    where = list(data.where)
    index = {loc: i for i, loc in enumerate(where)}

    def place(loc: Loc) -> str:
        i = index.get(loc)
        if i is None:
            i = index[loc] = len(where)
            where.append(loc)
        return f"detail::kWhere[{i}]"

    views = [
        SlotView(
            f"bb.{member}", s.key, s.kind, s.declared, s.capacity, s.may_be_missing, s.origin_text, s.may_be_bt_any
        )
        for s, member in zip(data.slots, slot_members(data.slots))
    ]
    out = []
    for c in data.scripts:
        table = ErrorTable()
        ctx = ScriptContext(
            views,
            dict(c.names),
            lambda off, at=c.attr: place(script_loc(at, off)),
            c.prefix,
            dict(data.enums),
            table,
            data.counts_births,
        )
        body = compile_script(c.typed, ctx)
        out.append(CompiledScript(c.node, c.which, c.comment, tuple(body), tuple(table.entries), c.prefix))
    return out, tuple(where)
