"""Stores into the typed blackboard: 4.6.2's script store (`_store`) of a value into an
entry of one static kind, by the route the typing pass picked (ir.kinds.store_route): as it
is, through the entry's converter, a string read as a number, or a number converted as
Any::copyInto converts it."""

from __future__ import annotations

from btgen.backend_cpp.literals import cpp_int64, cpp_value, cpp_view
from btgen.backend_cpp.script_cpp.writer import CodeWriter, SlotView, Val
from btgen.ir.kinds import INT32_MAX, INT32_MIN, TEXT_BOUND, UINT32_MAX, describe_kind, is_queue
from btgen.ir.script_types import ExprType
from btgen.lang import values
from btgen.lang.kind import KindLike


def store_value(c: CodeWriter, s: SlotView, v: Val, off: int, what: str, op: str, typed: ExprType) -> None:
    """4.6.2's script store (`_store`) of `v` into slot `s`, which then holds s.kind, by the
    route ir.kinds.store_route picks: a value of the slot's kind as it is; a string into a typed
    non-string entry through the entry's converter, into an untyped double one read as a
    number; numbers of another kind as Any::copyInto converts them, which 4.6.2 only does when
    the entry already holds a value (an empty entry would change its type: reported at run
    time)."""
    route = typed.route
    if s.may_be_bt_any and v.kind == "string":
        # An entry typed BT::Any (an `entry` port's, or one 4.10.0's SetBlackboard left empty):
        # unless it holds a string, its converter throws.
        c.dyn_call(f"btgen::dyn::store_text_bt_any({s.member}, {v.expr}, {cpp_view(s.key)}, dm)", off)
    if route == "same":
        store_same(c, s, v, off)
    elif route == "converted":
        store_converted(c, s, v, off, what, typed.converted)
    elif route == "status_text":
        # No converter for NodeStatus: both releases throw. The interpreter's message (script/
        # evaluate.py _store): the entry is empty, or holds the number a script stored, which
        # the text (no number: kinds.store_route) cannot be read as
        assert isinstance(v.literal, str), v.literal
        text = values.describe(v.literal)
        empty = f"cannot assign the string {text} to `{s.key}`, which holds an empty value"
        c.check(f"!{s.member}.has_value", off, empty)
        c.emit(c.fail(off, f"the string {text} is not a number"))
    elif route == "number_text":
        guard_type_change(c, s, v.kind, off, what)
        t = c.text_number(v, off, ":=", "right")
        c.emit(f"{s.member}.value = {t};")
    else:
        # An entry a port declared NodeStatus takes a number even while empty (both releases
        # convert it; recorded: oracle-diff/script_number_into_status_entry)
        status = s.kind == "status" and s.declared == values.NODE_STATUS
        store_number(c, s, v, off, what, op, guard=not status)


def guard_type_change(c, s: SlotView, r: KindLike, off: int, what: str) -> None:
    c.check(
        f"!{s.member}.has_value",
        off,
        f"{what} would store {describe_kind(r)} in the empty entry `{s.key}`, which btgen types as "
        f"{describe_kind(s.kind)} (BehaviorTree.CPP would change its type): write {describe_kind(s.kind)}",
    )


def store_same(c, s: SlotView, v: Val, off: int) -> None:
    if s.kind == "string":
        c.check(
            f"!{s.member}.value.assign({v.expr})", off, f"the text does not fit `{s.key}` (capacity {s.capacity} bytes)"
        )
    else:
        c.emit(f"{s.member}.value = {v.expr};")


def store_converted(c, s: SlotView, v: Val, off: int, what: str, value: object) -> None:
    """A string through the converter of the entry's declared type (convertFromString);
    `value`: a literal's converted value (the typing pass converted it)."""
    decl = s.declared
    if is_queue(s.kind):
        c.errc_check(
            f"btgen::port::parse_queue<detail::Semantics::double_from_chars>({v.expr}, {s.member}.value)",
            off,
            f"{what}: the string is not a valid {decl} of at most {s.capacity} elements",
        )
        return
    if v.literal is not None and value is not None:
        if s.kind == "string":
            store_same(c, s, Val("string", cpp_view(str(value)), None, len(str(value)), value), off)
        else:
            c.emit(f"{s.member}.value = {cpp_value(value)};")
        return
    t = c.temp()
    if decl in (values.INT, values.UNSIGNED):
        lo, hi = (INT32_MIN, INT32_MAX) if decl == values.INT else (0, UINT32_MAX)
        c.emit(f"std::int64_t {t} = 0;")
        parse = f"btgen::parse_integer({v.expr}, {cpp_int64(lo)}, {cpp_int64(hi)}, {t})"
    elif decl == values.DOUBLE:
        c.emit(f"double {t} = 0.0;")
        parse = f"btgen::convert_double<detail::Semantics::double_from_chars>({v.expr}, {t})"
    else:  # bool (converted_literal refused the others)
        c.emit(f"bool {t} = false;")
        parse = f"btgen::parse_bool({v.expr}, {t})"
    # the interpreter's message, which names the text and why it does not convert
    c.dyn_call(f"btgen::dyn::converted_text({parse}, {v.expr}, {cpp_view(s.key)}, {cpp_view(decl)}, dm)", off)
    c.emit(f"{s.member}.value = {t};")


def store_number(c, s: SlotView, v: Val, off: int, what: str, op: str, guard: bool) -> None:
    """Any::copyInto of a number into an entry holding another kind of number; a failure
    gets the interpreter's message, which names the value (btgen::dyn::store_into)."""
    k, r = s.kind, v.kind
    if r == k:
        c.emit(f"{s.member}.value = {v.expr};")
        return
    if guard:
        guard_type_change(c, s, r, off, what)
    if k == "double":
        t = c.temp()
        c.emit(f"double {t} = 0.0;")
        if r == "int":
            # The conversion inline; the dynamic store only for its message when it fails.
            c.emit(f"if (btgen::script::num_v<Semantics::int_to_double_53_bits>({v.expr}, {t}) != btgen::Errc::kOk) {{")
            c.indent += 1
            c.emit(f"btgen::dyn::Ref {t}r;")
            c.dyn_call(
                f"btgen::dyn::store_into(btgen::dyn::of_int({v.expr}), btgen::dyn::of_double(0.0), "
                f"{cpp_view(op)}, {cpp_view(s.key)}, {t}r, dm)",
                off,
            )
            c.emit(f"{t} = {t}r.d;")
            c.indent -= 1
            c.emit("}")
        else:
            c.emit(f"(void)btgen::script::num_v<Semantics::int_to_double_53_bits>({v.expr}, {t});")
        c.emit(f"{s.member}.value = {t};")
        return
    n = c.temp()
    c.emit(f"std::int64_t {n} = 0;")
    if r == "double":
        # whole() accepts what copy_into does (a whole double in int64's range); the dynamic
        # store runs only for its message when it fails.
        c.emit(f"if (btgen::script::whole({v.expr}, {n}) != btgen::Errc::kOk) {{")
        c.indent += 1
        c.emit(f"btgen::dyn::Ref {n}r;")
        c.dyn_call(
            f"btgen::dyn::store_into(btgen::dyn::of_double({v.expr}), btgen::dyn::of_int(0), "
            f"{cpp_view(op)}, {cpp_view(s.key)}, {n}r, dm)",
            off,
        )
        c.emit(f"{n} = {n}r.i;")
        c.indent -= 1
        c.emit("}")
    else:
        c.emit(f"(void)btgen::script::whole({v.expr}, {n});")
    if k == "int":
        c.emit(f"{s.member}.value = {n};")
    elif k == "bool":
        c.errc_check(
            f"btgen::script::as_bool({n}, {s.member}.value)",
            off,
            f"{what}: `{s.key}` holds a bool, and the value is neither 0 nor 1 (BehaviorTree.CPP would "
            f"change its type)",
        )
    else:
        c.errc_check(
            f"btgen::script::as_status({n}, {s.member}.value)",
            off,
            f"{what}: `{s.key}` holds a NodeStatus, and the value is no status number (0 to 4)",
        )


def dyn_slot_bound(s: SlotView) -> int:
    """The longest text a dynamic slot's value can have: its string, or a number's text."""
    return max(s.capacity, TEXT_BOUND["double"])
