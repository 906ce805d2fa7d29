"""The C++ writer under the script compiler and the port readers and writers: the values it
handles (Val, and SlotView for a blackboard slot), a value as a btgen::dyn::Ref, where a
script is and how its errors read (ScriptContext, ErrorTable), and CodeWriter, which keeps
lines, temporaries and error exits."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Callable, Optional

from btgen.backend_cpp.literals import cpp_double, cpp_string, cpp_view
from btgen.ir.kinds import DYN, is_queue
from btgen.lang import values
from btgen.lang.kind import KindLike

# The btgen::dyn constructor of a value of each static kind.
DYN_OF: dict[KindLike, str] = {
    "int": "of_int",
    "double": "of_double",
    "bool": "of_bool",
    "status": "of_status",
    "string": "of_string",
}
CPP_SCALAR: dict[KindLike, str] = {"int": "std::int64_t", "double": "double", "bool": "bool", "status": "btgen::Status"}


@dataclass(frozen=True)
class SlotView:
    """What script compilation needs to know of a blackboard slot."""

    member: str  # C++ lvalue of the btgen::Slot, e.g. `bb.visits`
    key: str  # the key, for messages
    kind: KindLike
    declared: str  # declared type (values.py canonical name; `any` when none)
    capacity: int  # strings: bytes
    may_be_missing: bool  # the entry may not exist when a script runs
    origin: str = ""  # why it has its type (for messages)
    may_be_bt_any: bool = False  # 4.10.0's SetBlackboard may leave it empty and typed BT::Any


@dataclass
class Val:
    kind: KindLike
    expr: Optional[str]  # C++ expression of the value (string: a std::string_view); None for none/queues
    has: Optional[str]  # C++ bool expression "it has a value"; None: it always has
    bound: int = 0  # strings: most bytes
    literal: object = None  # the Python value when the expression is a literal


# A dynamic value's tag for each kind it may hold, and its value as that kind (`{}`: the Ref).
DYN_TAG: dict[KindLike, str] = {
    "int": "kInt",
    "double": "kDouble",
    "bool": "kBool",
    "status": "kStatus",
    "string": "kString",
}
DYN_FIELD: dict[KindLike, str] = {
    "int": "{}.i",
    "double": "{}.d",
    "bool": "({}.i != 0)",
    "status": "static_cast<btgen::Status>({}.i)",
    "string": "{}.s",
}


def to_ref(v: Val) -> str:
    """The value as a btgen::dyn::Ref (empty when it has none)."""
    if v.kind == DYN:
        return v.expr  # type: ignore[return-value]
    if v.kind == "none" or is_queue(v.kind) or v.has == "false":
        return "btgen::dyn::Ref{}"
    fn = DYN_OF[v.kind]
    r = f"btgen::dyn::{fn}({v.expr})"
    if v.has is not None:
        r = f"({v.has} ? {r} : btgen::dyn::Ref{{}})"
    return r


@dataclass
class ScriptContext:
    """Where a script is and how its errors read."""

    slots: Sequence[SlotView]
    names: Mapping[str, int]  # name as written (with `@`) -> slot index
    where: Callable[..., str]  # offset in the code -> C++ expression of its "path:line:col"
    prefix: str  # message prefix, e.g. 'script error in `code` of `Script` "Init": '
    enums: Mapping[str, int] = field(default_factory=dict)  # scripting enums (enums.py)
    # Given: the script is compiled to a body that identical scripts elsewhere share; its
    # places, messages and prefix go to this table (a ScriptSite in the generated code).
    errors: Optional[ErrorTable] = None
    # Given: entries created at run time are counted (DataIR.counts_births, Slot::born).
    counts_births: bool = False


class ErrorTable:
    """What makes a shared script function report one node's errors: the places and the
    messages (prefix included) its error exits name, by number, and the message prefix of
    the dynamic operations. The body says `s.at[j].where` and `s.at[j].message` and
    `s.prefix`, where `s` is the node's ScriptSite; two scripts whose bodies read the same
    are one function."""

    def __init__(self) -> None:
        self.entries: list[tuple[str, str]] = []  # (C++ expression of the place, message text or "")
        self._index: dict[tuple[str, str], int] = {}

    def ref(self, where: str, message: str = "") -> int:
        key = (where, message)
        j = self._index.get(key)
        if j is None:
            j = self._index[key] = len(self.entries)
            self.entries.append(key)
        return j


class CodeWriter:
    """Lines of C++ with temporaries and error exits: the base of the script compiler and of
    the port readers and writers (ports_cpp.py).

    Generated functions see `bb` (the Blackboard), `n` (the NodeInfo) and `err` (the
    ErrorSink). An error reports `where(offset)` (a C++ expression naming the place, e.g.
    `detail::kWhere[3]`) and `prefix + message`, then returns
    `error_return` (None: the -1 that ErrorSink::fail gives)."""

    def __init__(
        self, where: Callable[[int], str], prefix: str, error_return: Optional[str] = None, indent: int = 1
    ) -> None:
        self.where = where
        self.prefix = prefix
        self.error_return = error_return
        self.lines: list[str] = []
        # String concatenation buffers by their view expression: (lines, index, indent, name).
        self._concats: dict[str, tuple[list[str], int, int, str]] = {}
        self.indent = indent
        self.n = 0
        self.msg_args = ""  # more arguments of btgen::dyn::Msg (the scripting enums table)
        self.errors: Optional[ErrorTable] = None  # a shared body's error table (ScriptContext.errors)

    def where_at(self, offset: int) -> str:
        """The C++ expression of the place of `offset` in run-time errors."""
        if self.errors is None:
            return self.where(offset)
        return f"s.at[{self.errors.ref(self.where(offset))}].where"

    def prefix_view(self) -> str:
        """The message prefix as a C++ std::string_view."""
        return "s.prefix" if self.errors is not None else cpp_view(self.prefix)

    def emit(self, line: str) -> None:
        self.lines.append("  " * self.indent + line)

    def temp(self) -> str:
        self.n += 1
        return f"t{self.n}"

    def fail(self, offset: int, message: str) -> str:
        if self.errors is None:
            call = f"err.fail(n, {self.where(offset)}, {cpp_string(self.prefix + message)})"
        else:
            j = self.errors.ref(self.where(offset), self.prefix + message)
            call = f"err.fail(n, s.at[{j}].where, s.at[{j}].message)"
        if self.error_return is None:
            return f"return {call};"
        return f"{{ (void){call}; return {self.error_return}; }}"

    def check(self, cond: str, offset: int, message: str) -> None:
        self.emit(f"if ({cond}) {self.fail(offset, message)}")

    def dyn_call(self, call: str, offset: int) -> None:
        """A fallible btgen::dyn operation: `call` uses `dm`, the message it fills on failure
        (after this writer's prefix), which is then reported."""
        report = f"err.fail(n, {self.where_at(offset)}, dm.view())"
        fail = (
            f"return {report};" if self.error_return is None else f"{{ (void){report}; return {self.error_return}; }}"
        )
        self.emit(f"if (btgen::dyn::Msg dm({self.prefix_view()}{self.msg_args}); !({call})) {fail}")

    def to_ref(self, v: Val) -> str:
        return to_ref(v)

    def errc_check(self, call: str, offset: int, message: str) -> None:
        self.check(f"{call} != btgen::Errc::kOk", offset, message)

    def text_number(self, v: Val, offset: int, op: str, side: str) -> str:
        """A string read as a number (StringToDouble: `true`, `false`, else from_chars)."""
        if v.literal is not None:
            text = v.literal
            assert isinstance(text, str)
            if text == "true":
                return "1.0"
            if text == "false":
                return "0.0"
            enums = getattr(getattr(self, "ctx", None), "enums", {})
            if text in enums:
                return cpp_double(float(enums[text]))
            try:
                return cpp_double(values.to_double(text))
            except values.ConversionError:
                # 4.6.2 fails whenever this runs: at run time, as the interpreter does.
                self.emit(self.fail(offset, f"the string {values.describe(text)} is not a number"))
                return "0.0"
        t = self.temp()
        self.emit(f"double {t} = 0.0;")
        self.dyn_call(f"btgen::dyn::string_to_double({v.expr}, {t}, dm)", offset)
        return t

    def as_double(self, v: Val, offset: int, what: str) -> str:
        if v.kind == "double":
            return v.expr  # type: ignore[return-value]
        if v.kind == "int" and isinstance(v.literal, int) and abs(v.literal) <= 2**53:
            return cpp_double(float(v.literal))
        t = self.temp()
        self.emit(f"double {t} = 0.0;")
        if v.kind == "int":
            self.errc_check(
                f"btgen::script::num_v<Semantics::int_to_double_53_bits>({v.expr}, {t})",
                offset,
                f"{what}: cannot convert the integer to double: precision would be lost",
            )
        else:
            self.emit(f"(void)btgen::script::num_v<Semantics::int_to_double_53_bits>({v.expr}, {t});")
        return t
