"""The C++ spelling of the data side: Jinja2 filters over the IR's slots, locals and ports.

ir/dataflow.py decides what every blackboard entry holds and what every data
operation does (ir/dataops.py); templates/_data.j2 writes the statements, and
these filters give it the C++ types, enumerators and literals it needs.
"""

from __future__ import annotations

from btgen.backend_cpp.literals import cpp_int64, cpp_string, cpp_string_chunks, cpp_value, cpp_view
from btgen.backend_cpp.naming import CppSlot, cpp_comment_lines
from btgen.backend_cpp.script_cpp import CPP_SCALAR, Val, to_ref
from btgen.diagnostics import InternalError
from btgen.ir.data.records import LocalIR, PortIR, SlotIR
from btgen.ir.dataops import TextOperand
from btgen.ir.kinds import BOOL, DOUBLE, DYN, INT, NONE, STRING, is_numeric, is_queue, is_user, queue_element
from btgen.lang import values
from btgen.lang.kind import KindLike

# btgen::Declared enumerators (runtime/include/btgen/port.hpp), by declared type.
DECLARED_ENUM = {
    values.ANY: "kAny",
    values.INT: "kInt",
    values.UNSIGNED: "kUnsigned",
    values.DOUBLE: "kDouble",
    values.BOOL: "kBool",
    values.STRING: "kString",
    values.NODE_STATUS: "kStatus",
}

# The C++ type of a typed port's accessors.
CPP_PORT_TYPE = {
    values.INT: "std::int32_t",
    values.UNSIGNED: "std::uint32_t",
    values.DOUBLE: "double",
    values.BOOL: "bool",
    values.NODE_STATUS: "btgen::Status",
    values.STRING: "std::string_view",
}

ELEMENT_TYPE: dict[KindLike, str] = {INT: "std::int64_t", DOUBLE: "double", BOOL: "bool"}


def declared_enum(type_name: str) -> str:
    """The btgen::Declared enumerator of a declared type (how a write converts into the entry)."""
    if type_name in DECLARED_ENUM:
        return DECLARED_ENUM[type_name]
    if values.queue_element_type(type_name) is not None:
        return "kQueue"
    return "kOpaque"


def slot_type(s: SlotIR) -> str:
    """The C++ type of a slot's value (btgen::Slot<T>)."""
    k = s.kind
    if is_user(k):
        return s.user_cpp
    if k == STRING:
        return f"btgen::FixedString<{s.capacity}>"
    if k == NONE:
        return "btgen::NoValue"
    if k == DYN:
        return f"btgen::Dyn<{max(s.capacity, 1)}>"
    if is_queue(k) and s.pool:
        return "btgen::QueueRef"  # its queue is in the pool it shares (btgen::QueuePool)
    if is_queue(k):
        elem = queue_element(k)
        etype = ELEMENT_TYPE.get(elem, f"btgen::FixedString<{s.elem_capacity}>")
        return f"btgen::FixedQueue<{etype}, {s.capacity}>"
    return CPP_SCALAR[k]


def slot_init(s: SlotIR) -> str:
    """The braced initializer of a slot: a SubTree constant's value, or an entry that exists from the start."""
    if s.initial is not None:
        if s.kind in (INT, DOUBLE):
            # 4.9.1 stores a SubTree literal that is wholly a number as that number
            from btgen.lang.blackboard import typed_literal

            number = typed_literal(s.initial)
            if not isinstance(number, (int, float)):
                raise InternalError(f"the SubTree constant `{s.initial}` is no number")
            value = cpp_value(float(number)) if s.kind == DOUBLE else cpp_int64(int(number))
            return f"{{{value}, 1, true, true}}"
        if s.kind != STRING:
            raise InternalError(f"a SubTree constant of kind {s.kind}")
        return f"{{{slot_type(s)}({cpp_view(s.initial)}), 1, true, true}}"
    if s.at_load:
        # an `entry` port's entry is typed BT::Any from the start (a script's string throws)
        return "{{}, 0, true, false, btgen::EntryType::kBtAny}" if s.bt_any_at_load else "{{}, 0, true, false}"
    return "{}"


def local_type(local: LocalIR) -> str:
    if local.pool:
        queue = f"btgen::FixedQueue<{element_type(local.elem, local.elem_capacity)}, {local.length}>"
        return f"btgen::QueuePool<{queue}, {local.pool}>"
    if local.user_cpp:
        return f"btgen::UserLiteral<{local.user_cpp}>"
    if local.text_capacity:
        return f"btgen::port::TextQueue<{local.text_capacity}>"
    return f"btgen::FixedQueue<{element_type(local.elem, local.elem_capacity)}, {local.length}>"


def element_type(elem: str, capacity: int) -> str:
    return ELEMENT_TYPE.get(elem, f"btgen::FixedString<{capacity}>")


# The element a QueueView of a queue port gives (runtime/include/btgen/queue_view.hpp).
QUEUE_VIEW_ELEMENT = {
    values.INT: "std::int32_t",
    values.DOUBLE: "double",
    values.BOOL: "bool",
    values.STRING: "std::string_view",
}


def queue_view(p: PortIR) -> str:
    """The btgen::QueueView of a queue port (BT::SharedQueue<T>); "" for another port."""
    elem = values.queue_element_type(p.type_name)
    return f"btgen::QueueView<{QUEUE_VIEW_ELEMENT[elem]}>" if elem is not None else ""


def port_type(p: PortIR) -> str:
    """The C++ type of a port's accessors; "" for an untyped port (template accessors)."""
    if p.user_cpp:
        return p.user_cpp
    if queue_view(p):
        return queue_view(p)
    if p.type_name == values.ANY:
        return ""
    return CPP_PORT_TYPE.get(p.type_name, "std::string_view")  # opaque user types are strings


def port_literal(type_name: str, value: object) -> str:
    """A typed port's converted literal as its getter returns it."""
    if type_name == values.INT:
        return f"std::int32_t{{{value}}}"
    if type_name == values.UNSIGNED:
        return f"std::uint32_t{{{value}u}}"
    if isinstance(value, str):
        return cpp_view(value)
    return cpp_value(value)


def element_literal(value: object, elem: str, capacity: int) -> str:
    """An element of a Loop's literal queue."""
    if elem == STRING:
        return f"{element_type(elem, capacity)}({cpp_view(str(value))})"
    return cpp_value(value)


def dyn_ref(s: CppSlot) -> str:
    """A slot's value as a btgen::dyn::Ref (the source of a copy into a dynamic entry)."""
    m = f"bb.{s.member}"
    if s.kind == DYN:
        return f"btgen::dyn::ref({m})"
    expr = f"{m}.value.view()" if s.kind == STRING else f"{m}.value"
    return to_ref(Val(s.kind, expr, f"{m}.has_value"))


def text_ok(o: TextOperand, var: str, slots: tuple[SlotIR, ...]) -> str:
    """Whether a Switch operand read as text has a value: `var`_ok, or a constant."""
    if o.slot is not None:
        k = slots[o.slot].kind
        return f"{var}_ok" if k in (DYN, STRING) or is_numeric(k) else "false"
    return "true" if o.literal is not None else "false"


_BLACKBOARD_READS = ("ReadEntry", "ReadUser", "ReadUserLiteral", "ReadQueue")


def debug_capacity(op) -> int:
    """The bytes of the longest Blackboard::debugMessage an ops.SetCopyDynTyped410 prints."""
    longest = max(len(n.encode("utf-8")) for n in ("BT::AnyTypeAllowed", "BT::Any"))
    return max(
        1,
        sum(
            len(e.key.encode("utf-8"))
            + 4
            + max(len(e.type_name.encode("utf-8")), len(e.typed_name.encode("utf-8")), longest)
            for e in op.debug
        ),
    )


def debug_type(e, member: str) -> str:
    """The type name of one debugMessage line (ops.DebugEntry); `member`: its slot."""
    if e.type_name:
        return cpp_view(e.type_name)
    return (
        f"({member}.entry_type == btgen::EntryType::kUntyped ? {cpp_view('BT::AnyTypeAllowed')} : "
        f"{member}.entry_type == btgen::EntryType::kBtAny ? {cpp_view('BT::Any')} : {cpp_view(e.typed_name)})"
    )


FILTERS = dict(
    op_kind=lambda op: type(op).__name__,
    # whether a getter's cases read the blackboard (the others return literals)
    reads_blackboard=lambda reads: any(type(r).__name__ in _BLACKBOARD_READS for _, r in reads),
    text_ok=text_ok,
    declared_enum=declared_enum,
    slot_type=slot_type,
    slot_init=slot_init,
    local_type=local_type,
    element_type_of=lambda elem: ELEMENT_TYPE[elem],
    port_type=port_type,
    queue_view=queue_view,
    queue_view_element=lambda p: QUEUE_VIEW_ELEMENT[values.queue_element_type(p.type_name) or ""],
    port_literal=port_literal,
    element_literal=element_literal,
    dyn_ref=dyn_ref,
    debug_capacity=debug_capacity,
    debug_type=debug_type,
    cpp_view=cpp_view,
    cpp_message=cpp_string,
    byte_length=lambda text: len(text.encode("utf-8")),
    cpp_string_chunks=cpp_string_chunks,
    cpp_comment_lines=cpp_comment_lines,
)
TESTS = dict(numeric_kind=is_numeric, queue_kind=is_queue, queue_port=lambda p: bool(queue_view(p)))
