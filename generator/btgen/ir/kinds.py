"""The static kinds of the script language and of blackboard entries: btgen's typing rules.

btgen gives every blackboard entry one type (dataflow.py) and every script
expression one static kind. The kinds, what each operator gives for the
kinds of its operands, and which combinations fail whenever they run (a
`ScriptTypeError`, reported as a compile error) are defined here, with no
C++ in them; backend_cpp/script_cpp/ turns typed scripts into C++.

Kinds:

    int       integers (script literals, int/unsigned/bool entries)
    double    real literals; every arithmetic, comparison, logic result
    bool      (only in conversions: bool entries hold integers, as 4.6.2's Any does)
    status    entries declared NodeStatus
    string    text
    queue<T>  entries of Loop nodes (scripts cannot use them)
    dyn       entries whose type changes at run time
    user:NAME a user port type (--type)
    none      no value ever (`1 .. 2`, an entry nothing writes)
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Callable, Optional

from btgen.lang import script as sc
from btgen.lang import values
from btgen.lang.kind import Kind, KindLike, QueueKind, Scalar, UserKind, render

INT, DOUBLE, BOOL, STATUS, STRING, NONE = (
    Scalar.INT,
    Scalar.DOUBLE,
    Scalar.BOOL,
    Scalar.STATUS,
    Scalar.STRING,
    Scalar.NONE,
)
NUMERIC = (INT, DOUBLE, BOOL, STATUS)
# The kind of a dynamic slot (btgen::Dyn<N>: its type changes at run time) and of
# expressions over one: btgen::dyn::Ref values, operated on by runtime/include/btgen/dynamic.hpp.
DYN = Scalar.DYN
# Longest text of a value of each kind (std::to_string): bool and status print one digit.
TEXT_BOUND: Mapping[KindLike, int] = MappingProxyType({INT: 20, DOUBLE: 317, BOOL: 1, STATUS: 1})

INT32_MIN, INT32_MAX = -(2**31), 2**31 - 1
UINT32_MAX = 2**32 - 1


def is_numeric(kind: Optional[KindLike]) -> bool:
    return kind in NUMERIC


def is_queue(kind: object) -> bool:
    return isinstance(kind, QueueKind)


def queue_kind(elem: str) -> QueueKind:
    """The kind of a queue of `elem` (int, bool, double, string) values."""
    return QueueKind(Scalar(elem))


def queue_element(kind: KindLike) -> Scalar:
    """The element of a queue kind: `queue<int>` -> `int`."""
    assert isinstance(kind, QueueKind), kind
    return kind.element


def user_type_name(kind: KindLike) -> str:
    """The user port type a `user:NAME` kind holds (blanks removed): NAME."""
    assert isinstance(kind, UserKind), kind
    return kind.name


@dataclass(frozen=True)
class UserKinds:
    """The user port types (usertypes.py) of one mission, as kinds: type name (blanks around
    `<>,:*&` removed) -> kind (`user:NAME`). A value the data analysis builds once and
    passes along; nothing here changes while a mission is compiled."""

    by_type: Mapping[str, UserKind] = field(default_factory=lambda: MappingProxyType({}))

    @staticmethod
    def of(user_types: Iterable) -> UserKinds:
        """From the mission's `usertypes.UserType`s."""
        return UserKinds(MappingProxyType({values._compact(t.name): t.kind for t in user_types}))

    def get(self, type_name: str) -> Optional[UserKind]:
        return self.by_type.get(values._compact(type_name)) if self.by_type else None


NO_USER_KINDS = UserKinds()


def is_user(kind: object) -> bool:
    """A kind of a user port type (`--type`): the value is the user's C++ type, held as is."""
    return isinstance(kind, UserKind)


def kind_of_type(type_name: str, user: UserKinds = NO_USER_KINDS) -> Optional[Kind]:
    """The kind an entry of a declared type holds; None for `any` (inferred from writes).
    `user`: the mission's user port types (a `--type` name gives its `user:NAME` kind).

    A bool entry holds an integer: 4.6.2 keeps bools as the integers 0 and 1
    (its Any holds an int64), a script writes `true` as the integer 1 into
    it, and every operation (arithmetic, `..`, conditions, casts to a port's
    type) treats both alike."""
    if type_name in (values.INT, values.UNSIGNED, values.BOOL):
        return INT
    if type_name == values.DOUBLE:
        return DOUBLE
    if type_name == values.NODE_STATUS:
        return STATUS
    if type_name == values.ANY:
        return None
    elem = values.queue_element_type(type_name)
    if elem is not None:
        return queue_kind(elem)
    return user.get(type_name) or STRING  # string and opaque user types


_DESCRIPTION: Mapping[KindLike, str] = MappingProxyType(
    {
        INT: "an integer",
        DOUBLE: "a double",
        BOOL: "a bool",
        STATUS: "a NodeStatus",
        STRING: "a string",
        NONE: "no value",
        DYN: "a value of changing type",
    }
)


def describe_kind(kind: KindLike) -> str:
    """A kind in messages: `an integer`, `a queue<int>`, `a Pose2D`."""
    if is_user(kind):
        return f"a {user_type_name(kind)}"
    return _DESCRIPTION.get(kind, f"a {render(kind)}")


def value_kind(value: object) -> Kind:
    """The kind of a Python value (values.py representation)."""
    t = values.type_of(value)  # type: ignore[arg-type]
    elem = values.queue_element_type(t)
    if elem is not None:
        return queue_kind(elem)
    return {"int": INT, "double": DOUBLE, "bool": BOOL, "string": STRING, "NodeStatus": STATUS}[t]


class ScriptTypeError(Exception):
    """A script that fails whenever it runs; ``offset`` indexes its code."""

    def __init__(self, message: str, offset: int) -> None:
        super().__init__(message)
        self.message = message
        self.offset = offset


# ================================================================ kinds


def expr_kind(node: sc.Expr, kind_of: Callable[[str], Optional[KindLike]]) -> Optional[KindLike]:
    """The static kind of an expression's value; None while a name's kind is unknown.

    Raises ScriptTypeError when the kinds make the expression fail whenever it
    is evaluated."""
    if isinstance(node, sc.Literal):
        return value_kind(node.value)
    if isinstance(node, sc.Name):
        return kind_of(node.name)
    if isinstance(node, sc.Unary):
        k = expr_kind(node.operand, kind_of)
        if k is None:
            return None
        if is_queue(k):
            need_number(node.op, k, node.offset, "operand")
        return DOUBLE
    if isinstance(node, sc.Binary):
        lk = expr_kind(node.left, kind_of)
        rk = expr_kind(node.right, kind_of)
        if lk is None or rk is None:
            return None
        return binary_kind(node.op, lk, rk, node.op_offset)
    if isinstance(node, sc.Compare):
        kinds = [expr_kind(o, kind_of) for o in node.operands]
        if any(k is None for k in kinds):
            return None
        for op, off, a, b in zip(node.ops, node.op_offsets, kinds, kinds[1:]):
            compare_check(op, a, b, off)  # type: ignore[arg-type]
        return DOUBLE
    if isinstance(node, sc.Ternary):
        ck = expr_kind(node.cond, kind_of)
        tk = expr_kind(node.then, kind_of)
        ek = expr_kind(node.orelse, kind_of)
        if ck is None:
            return None
        if ck == NONE:
            raise ScriptTypeError("the condition of `?:` has no value", node.op_offset)
        if is_queue(ck):
            raise ScriptTypeError(f"the condition of `?:` is {describe_kind(ck)}", node.op_offset)
        if tk is None or ek is None:
            return None
        if DYN in (tk, ek) or (tk != ek and not is_queue(tk) and not is_queue(ek)):
            return DYN
        if tk != ek:
            raise ScriptTypeError(ternary_message(tk, ek), node.op_offset)
        return tk
    if isinstance(node, sc.Assign):
        expr_kind(node.value, kind_of)  # (no value: fails at run time, as in 4.6.2)
        return kind_of(node.target)
    raise TypeError(node)


def static_update_ok(op: str, k: KindLike, r: KindLike) -> bool:
    """Whether `k op= r` compiles statically (else it fails whenever it runs, or is dynamic)."""
    if is_numeric(r):
        return is_numeric(k)
    if r == STRING:
        return op == "+=" and k == STRING
    return r == DYN and False


def overflow_message(text: str, key: str, capacity: int) -> str:
    """A string literal longer than the entry it is written to (the deliberate difference from 4.6.2)."""
    return (
        f"the string {values.describe(text)} ({len(text.encode('utf-8'))} bytes) does not fit blackboard entry "
        f"`{key}`, whose capacity is {capacity} bytes (strings have a fixed capacity in btgen; raise it with "
        f"--string-capacity)"
    )


def ternary_message(a: KindLike, b: KindLike) -> str:
    hint = " (e.g. `1.0` rather than `1` next to a double)" if is_numeric(a) and is_numeric(b) else ""
    return (
        f"the branches of `?:` give {describe_kind(a)} and {describe_kind(b)}; btgen gives every value one "
        f"type, so write both with the same type{hint}"
    )


def none_message(op: str, value: sc.Expr) -> str:
    if isinstance(value, sc.Binary) and value.op == "..":
        return (
            f"the right operand of `{op}` has no value: `..` of two numbers gives none in BehaviorTree.CPP "
            f"4.6.2 (start with a string: `'' .. a .. b`)"
        )
    return f"the right operand of `{op}` has no value"


def need_number(op: str, kind: KindLike, offset: int, which: str) -> None:
    if kind == NONE:
        raise ScriptTypeError(f"the {which} of `{op}` has no value", offset)
    if not is_numeric(kind):
        raise ScriptTypeError(f"`{op}` cannot be applied to {describe_kind(kind)}", offset)


def static_binary_ok(op: str, lk: KindLike, rk: KindLike) -> bool:
    if NONE in (lk, rk):
        return False
    if is_numeric(lk) and is_numeric(rk):
        return True
    if lk == STRING and rk == STRING and op in ("+", ".."):
        return True
    return op == ".." and {lk, rk} <= {STRING, *NUMERIC}


def binary_kind(op: str, lk: KindLike, rk: KindLike, offset: int) -> KindLike:
    if not is_queue(lk) and not is_queue(rk) and not static_binary_ok(op, lk, rk) and DYN not in (lk, rk):
        return DYN if op in ("+", "..") else DOUBLE
    if lk == NONE:
        raise ScriptTypeError(f"the left operand of `{op}` has no value", offset)
    if rk == NONE:
        raise ScriptTypeError(f"the right operand of `{op}` has no value", offset)
    if DYN in (lk, rk) and not is_queue(lk) and not is_queue(rk):
        return DYN if op in ("+", "..") else DOUBLE
    if not is_queue(lk) and not is_queue(rk) and not static_binary_ok(op, lk, rk):
        # Fails whenever it runs (a string where a number is needed): compiled as the dynamic
        # operation, which reports the interpreter's error at run time.
        return DYN if op in ("+", "..") else DOUBLE
    if is_numeric(lk) and is_numeric(rk):
        return NONE if op == ".." else DOUBLE
    if lk == STRING and rk == STRING and op in ("+", ".."):
        return STRING
    if op == ".." and {lk, rk} <= {STRING, *NUMERIC} and STRING in (lk, rk):
        return STRING
    raise ScriptTypeError(f"`{op}` cannot be applied to {describe_kind(lk)} and {describe_kind(rk)}", offset)


def compare_check(op: str, a: KindLike, b: KindLike, offset: int) -> None:
    if NONE in (a, b) and not is_queue(a) and not is_queue(b):
        return  # compiled as the dynamic comparison: no value fails at run time, as in 4.6.2
    if a == NONE:
        raise ScriptTypeError(f"the left operand of `{op}` has no value", offset)
    if b == NONE:
        raise ScriptTypeError(f"the right operand of `{op}` has no value", offset)
    ok = {a, b} <= {STRING, DYN, *NUMERIC}
    if not ok:
        raise ScriptTypeError(f"cannot compare {describe_kind(a)} with {describe_kind(b)} using `{op}`", offset)


# ================================================================ checks of a script's statements
# Shared by the typing pass (script_types.py), which reports them, and the C++ writer
# (backend_cpp/script_cpp/), which relies on them. `s` is a slot as scripts see it: its
# `key`, `kind`, `declared` type and the kind of that type (`declared_kind`), `capacity` and
# `origin` (why it has its kind).


def origin_text(s) -> str:
    if s.origin:
        return f" ({s.origin})"
    return f" (declared {s.declared})" if s.declared != values.ANY else ""


def check_condition(kind: KindLike) -> None:
    """The last statement's value of a condition script (ScriptCondition, `_skipIf` ...)."""
    if is_queue(kind):
        raise ScriptTypeError(f"the script gives {describe_kind(kind)}, which is not a condition", 0)


def check_ternary_condition(kind: KindLike, offset: int) -> None:
    if kind == NONE:
        raise ScriptTypeError("the condition of `?:` has no value", offset)
    if is_queue(kind):
        raise ScriptTypeError(f"the condition of `?:` is {describe_kind(kind)}", offset)


def ternary_is_dynamic(then_kind: KindLike, else_kind: KindLike, offset: int) -> bool:
    """Whether `c ? a : b` gives a value of changing type; an error when its branches' kinds
    can never agree."""
    dynamic = DYN in (then_kind, else_kind) or (
        then_kind != else_kind and not is_queue(then_kind) and not is_queue(else_kind)
    )
    if not dynamic and then_kind != else_kind:
        raise ScriptTypeError(ternary_message(then_kind, else_kind), offset)
    return dynamic


def dynamic_value_kinds(node: sc.Expr, kind_of: Callable[[sc.Expr], KindLike]) -> tuple[KindLike, ...]:
    """The kinds a value of changing type may have when it runs (`kind_of`: an expression's
    static kind): those of a `?:`'s branches, every scalar kind for a dynamic entry or
    operation. (No value at all is checked at run time before any store.)"""
    if isinstance(node, sc.Ternary):
        out: list[KindLike] = []
        for branch in (node.then, node.orelse):
            out.extend(k for k in dynamic_value_kinds(branch, kind_of) if k not in out)
        return tuple(out)
    k = kind_of(node)
    if k == DYN:
        return (INT, DOUBLE, BOOL, STATUS, STRING)
    return () if k == NONE else (k,)


def dynamic_store_route(s, value_kind: KindLike) -> Optional[str]:
    """How the C++ back end stores a value of changing type that holds `value_kind` at run
    time into the statically typed entry `s`, as the interpreter's `_store` does: a value of
    the entry's kind or a string by the route a static one takes (store_route), a number into
    a numeric entry as Any::copyInto converts it ("number"), into a string one "refused" (it
    fails as copyInto does; an empty entry would change its type, which is reported as a
    static store reports it). None: not covered (the store would change the entry's type)."""
    k = s.kind
    if is_queue(k) or is_user(k) or k in (NONE, DYN):
        return None
    if value_kind in (STRING, k):
        try:
            return store_route(s, value_kind, None, 0, "")
        except ScriptTypeError:
            return None
    if is_numeric(value_kind):
        if is_numeric(k):
            return "number"
        if k == STRING:
            return "refused"
    return None


def check_dynamic_update(s, op: str, key: str, offset: int, value_kinds: Iterable[KindLike] = ()) -> None:
    """A value of changing type into the statically typed entry `s` (not itself dynamic);
    `value_kinds`: the kinds that value may have (dynamic_value_kinds)."""
    if op in (":=", "="):
        kinds = tuple(value_kinds)
        if kinds and all(dynamic_store_route(s, k) for k in kinds):
            return
        raise ScriptTypeError(
            f"`{key} {op} ...` stores a value of changing type in `{key}`, which holds "
            f"{describe_kind(s.kind)}{origin_text(s)}; not supported by the C++ back end "
            f"yet",
            offset,
        )
    if not (is_numeric(s.kind) or s.kind == STRING):
        raise ScriptTypeError(f"`{op}` cannot update `{key}`, which holds {describe_kind(s.kind)}", offset)


def check_compound(s, key: str, op: str, value_kind: KindLike, offset: int) -> None:
    """`+= -= *= /=` of a value of `value_kind` into `s`."""
    if is_numeric(value_kind):
        if not is_numeric(s.kind):
            raise ScriptTypeError(
                f"`{op}` with a number needs a numeric `{key}`, but it holds {describe_kind(s.kind)}{origin_text(s)}",
                offset,
            )
    elif value_kind == STRING:
        if op != "+=":
            raise ScriptTypeError(f"`{op}` cannot be used with a string", offset)
        if s.kind != STRING:
            raise ScriptTypeError(
                f"`+=` of a string needs a string `{key}`, but it holds {describe_kind(s.kind)}{origin_text(s)}",
                offset,
            )
    else:
        raise ScriptTypeError(f"`{op}` cannot be used with {describe_kind(value_kind)}", offset)


def _numeric_text(text: str) -> bool:
    """Whether 4.6.2's StringToDouble reads `text` as a number (`true`, `false`, from_chars)."""
    if text in ("true", "false"):
        return True
    try:
        values.to_double(text)
    except values.ConversionError:
        return False
    return True


def store_route(s, value_kind: KindLike, literal: object, offset: int, what: str) -> str:
    """How 4.6.2's script store (`_store`) puts a value of `value_kind` (`literal`: its value when
    it is a literal) into `s`, which then holds s.kind: "same" (as it is), "converted" (a string
    through the declared type's converter), "number_text" (a string read as a number into an
    untyped double entry), "number" (a number of another kind, as Any::copyInto converts it) or
    "status_text" (a string literal into a NodeStatus entry: it throws where it runs).
    What would fail or change the entry's type whenever it runs is an error."""
    k, r = s.kind, value_kind
    if k == NONE:
        raise ScriptTypeError(f"{what}: `{s.key}` cannot hold {describe_kind(r)}", offset)
    if r == k:
        check_store_same(s, literal, offset)
        return "same"
    if r == STRING:
        if s.declared not in (values.ANY, values.NODE_STATUS) and s.declared_kind == k:
            converted_literal(s, literal, offset, what)
            return "converted"
        if k == DOUBLE and s.declared == values.ANY:
            return "number_text"
        if k == STATUS and s.declared == values.NODE_STATUS and isinstance(literal, str) and not _numeric_text(literal):
            return "status_text"  # no converter: both releases throw at the script, every run
    elif is_numeric(r) and is_numeric(k):
        return "number"
    raise ScriptTypeError(
        f"{what} stores {describe_kind(r)} in `{s.key}`, which holds {describe_kind(k)}"
        f"{origin_text(s)}; btgen gives every entry one type",
        offset,
    )


def check_store_same(s, literal: object, offset: int) -> None:
    """A value of the entry's own kind: a string literal must fit; queues are not copied."""
    if s.kind == STRING:
        if literal is not None and len(str(literal).encode("utf-8")) > s.capacity:
            raise ScriptTypeError(overflow_message(str(literal), s.key, s.capacity), offset)
    elif is_queue(s.kind):
        raise ScriptTypeError(f"a script cannot copy the queue `{s.key}`", offset)


CONVERTIBLE_FROM_TEXT = (values.INT, values.UNSIGNED, values.DOUBLE, values.BOOL)


def converted_literal(s, literal: object, offset: int, what: str) -> object:
    """A string stored through the converter of the entry's declared type: a literal is
    converted now (its value returned, None for other strings); a declared type that text
    never converts to is an error. A literal a number type does not take is converted at run
    time (None), where the library throws: only when the script runs."""
    decl = s.declared
    if literal is not None:
        try:
            value = values.convert_from_string(decl, literal, double_from_chars=s.double_from_chars)  # type: ignore[arg-type]
        except values.ConversionError as e:
            if decl in CONVERTIBLE_FROM_TEXT and not is_queue(s.kind) and s.kind != STRING:
                return None
            raise ScriptTypeError(f"{what}: `{s.key}` is declared {decl}: {e}", offset) from None
        if s.kind == STRING:
            check_store_same(s, value, offset)
        return value
    if not is_queue(s.kind) and s.kind != STRING and decl not in CONVERTIBLE_FROM_TEXT:
        raise ScriptTypeError(f"{what}: cannot convert a string to {decl}", offset)
    return None
