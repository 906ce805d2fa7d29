"""Running a script on a blackboard with 4.6.2's value rules (the interpreter's evaluator;
`analyze` uses it on constant scripts): its run-time errors, and a result as a condition.

Runtime values follow 4.6.2's ``BT::Any`` (see :mod:`btgen.lang.values`): integer
literals are integers, ``true``/``false`` are the integers 1/0, real literals
and the result of every arithmetic, comparison and logical operator are
doubles. ``None`` is 4.6.2's empty value."""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Optional, TypeVar

from btgen.lang import values
from btgen.lang.blackboard import Blackboard, Entry
from btgen.lang.script.nodes import (
    BIT_OPS,
    LOGIC_OPS,
    Assign,
    Binary,
    Compare,
    Expr,
    Literal,
    Name,
    Script,
    Ternary,
    Unary,
)
from btgen.lang.values import ConversionError, Queue, Value

# The longest string the interpreter builds (a script doubling a string 40 times ran out of
# memory: MemoryError, exit 3). Generated C++ holds far less: its strings have fixed
# capacities of at most --string-capacity (1 MiB) or a bound the mission shows.
MAX_STRING_BYTES = 1 << 26


def _joined(a: str, b: str, op: str, offset: int) -> str:
    if len(a) + len(b) > MAX_STRING_BYTES // 4:
        size = len(a.encode("utf-8")) + len(b.encode("utf-8"))
        if size > MAX_STRING_BYTES:
            raise ScriptRuntimeError(
                f"`{op}` would make a string of {size} bytes; the interpreter holds "
                f"strings of at most {MAX_STRING_BYTES} bytes",
                offset,
            )
    return a + b


class ScriptRuntimeError(Exception):
    """A script that fails while running, where 4.6.2 throws; ``offset`` indexes the code."""

    def __init__(self, message: str, offset: int) -> None:
        super().__init__(message)
        self.message = message
        self.offset = offset


# ================================================================ evaluation

FLT_EPSILON = 1.1920928955078125e-07


class _Evaluator:
    def __init__(self, bb: Blackboard, enums: Mapping[str, int], int53: bool = False) -> None:
        self.bb = bb
        self.enums = enums
        self.int53 = int53

    def eval(self, node: Expr) -> Optional[Value]:
        if isinstance(node, Literal):
            return node.value
        if isinstance(node, Name):
            return self.name(node)
        if isinstance(node, Unary):
            return self.unary(node)
        if isinstance(node, Binary):
            return self.binary(node)
        if isinstance(node, Compare):
            return self.compare(node)
        if isinstance(node, Ternary):
            return self.ternary(node)
        return self.assign(node)

    # -- helpers
    def double(self, v: Value, offset: int, what: str) -> float:
        if self.int53 and isinstance(v, int) and abs(int(v)) > _MAX_EXACT_53:
            # 4.7.0 (versions.py int_to_double_53_bits): a limit, exact or not
            raise ScriptRuntimeError(
                f"{what}: loss of precision when converting the large integer {int(v)} to floating point "
                f"(at most 2^53-1)",
                offset,
            )
        try:
            return values.to_double(v)
        except ConversionError as e:
            raise ScriptRuntimeError(f"{what}: {e}", offset) from None

    def string_to_double(self, s: str, offset: int) -> float:
        """4.6.2 ``StringToDouble``: `true`/`false`, an enum name, else from_chars."""
        if s == "true":
            return 1.0
        if s == "false":
            return 0.0
        if s in self.enums:
            return float(self.enums[s])
        try:
            return values.to_double(s)
        except ConversionError:
            raise ScriptRuntimeError(f"the string {values.describe(s)} is not a number", offset) from None

    @staticmethod
    def kind(v: Optional[Value]) -> str:
        return "an empty value" if v is None else f"a {values.type_of(v)}"

    # -- nodes
    def name(self, node: Name) -> Optional[Value]:
        if node.name in self.enums:
            return float(self.enums[node.name])
        entry = self.bb.get_entry(node.name)
        if entry is None:
            raise ScriptRuntimeError(
                f"unknown variable `{node.name}` (no blackboard entry of that name; "
                f"create it with `{node.name} := ...`)",
                node.offset,
            )
        return entry.value

    def unary(self, node: Unary) -> Value:
        v = self.eval(node.operand)
        if values.is_number(v):
            assert v is not None
            x = self.double(v, node.offset, f"operand of `{node.op}`")
            if node.op == "-":
                return -x
            if node.op == "!":
                return 1.0 if x == 0.0 else 0.0
            if math.isnan(x) or not float(values.INT64_MIN) <= x < 2.0**63:
                raise ScriptRuntimeError(f"{values.describe(v)} is out of range for `~`", node.offset)
            return float(~int(x))
        if v is None:
            raise ScriptRuntimeError(f"the operand of `{node.op}` has no value", node.offset)
        raise ScriptRuntimeError(f"`{node.op}` cannot be applied to {self.kind(v)}", node.offset)

    def binary(self, node: Binary) -> Optional[Value]:
        op, off = node.op, node.op_offset
        lv = self.eval(node.left)
        rv = self.eval(node.right)
        if lv is None:
            raise ScriptRuntimeError(f"the left operand of `{op}` has no value", off)
        if rv is None:
            raise ScriptRuntimeError(f"the right operand of `{op}` has no value", off)
        if values.is_number(lv) and values.is_number(rv):
            if op in ("+", "-", "*", "/"):
                a = self.double(lv, off, f"left operand of `{op}`")
                b = self.double(rv, off, f"right operand of `{op}`")
                return _arith(op, a, b)
            if op in BIT_OPS:
                try:
                    a, b = values.to_int64(lv), values.to_int64(rv)
                except ConversionError as e:
                    raise ScriptRuntimeError(f"`{op}` needs whole-number operands: {e}", off) from None
                return float(a & b if op == "&" else a | b if op == "|" else a ^ b)
            if op in LOGIC_OPS:
                try:
                    a_b = script_bool(lv)
                    b_b = script_bool(rv)
                except ConversionError as e:
                    raise ScriptRuntimeError(f"`{op}` needs operands that convert to bool: {e}", off) from None
                return float(bool(a_b and b_b) if op == "&&" else bool(a_b or b_b))
            return None  # `..` of two numbers: 4.6.2 yields an empty value
        if isinstance(lv, str) and isinstance(rv, str) and op in ("+", ".."):
            return _joined(lv, rv, op, off)
        if (
            op == ".."
            and (isinstance(lv, str) or isinstance(rv, str))
            and (values.is_number(lv) or isinstance(lv, str))
            and (values.is_number(rv) or isinstance(rv, str))
        ):
            return _joined(values.to_text(lv), values.to_text(rv), op, off)
        raise ScriptRuntimeError(f"`{op}` cannot be applied to {self.kind(lv)} and {self.kind(rv)}", off)

    def compare(self, node: Compare) -> float:
        lv = self.eval(node.operands[0])
        for op, off, operand in zip(node.ops, node.op_offsets, node.operands[1:]):
            rv = self.eval(operand)
            if lv is None:
                raise ScriptRuntimeError(f"the left operand of `{op}` has no value", off)
            if rv is None:
                raise ScriptRuntimeError(f"the right operand of `{op}` has no value", off)
            if values.is_number(lv) and values.is_number(rv):
                ok = _compare(
                    op,
                    self.double(lv, off, f"left operand of `{op}`"),
                    self.double(rv, off, f"right operand of `{op}`"),
                    True,
                )
            elif isinstance(lv, str) and isinstance(rv, str):
                ok = _compare(op, lv.encode(), rv.encode(), False)
            elif isinstance(lv, str) and values.is_number(rv):
                ok = _compare(
                    op, self.string_to_double(lv, off), self.double(rv, off, f"right operand of `{op}`"), True
                )
            elif values.is_number(lv) and isinstance(rv, str):
                ok = _compare(op, self.double(lv, off, f"left operand of `{op}`"), self.string_to_double(rv, off), True)
            else:
                raise ScriptRuntimeError(f"cannot compare {self.kind(lv)} with {self.kind(rv)} using `{op}`", off)
            if not ok:
                return 0.0
            lv = rv
        return 1.0

    def ternary(self, node: Ternary) -> Optional[Value]:
        v = self.eval(node.cond)
        if v is None:
            raise ScriptRuntimeError("the condition of `?:` has no value", node.op_offset)
        if isinstance(v, str):
            try:
                x = values.to_double(v)
            except ConversionError:
                raise ScriptRuntimeError(
                    f"the condition of `?:` is the string {values.describe(v)}, which is not a number", node.op_offset
                ) from None
        elif values.is_number(v):
            x = self.double(v, node.op_offset, "condition of `?:`")
        else:
            raise ScriptRuntimeError(f"the condition of `?:` is {self.kind(v)}", node.op_offset)
        return self.eval(node.then if x != 0.0 else node.orelse)

    def assign(self, node: Assign) -> Optional[Value]:
        op, key, off = node.op, node.target, node.op_offset
        entry = self.bb.get_entry(key)
        if entry is None:
            if op != ":=":
                raise ScriptRuntimeError(f"blackboard entry `{key}` does not exist yet; use `:=` to create it", off)
            self.bb.create_entry(key, values.ANY)
            entry = self.bb.get_entry(key)
            assert entry is not None
        value = self.eval(node.value)
        if value is None:
            raise ScriptRuntimeError(f"the right operand of `{op}` has no value", off)
        if op in (":=", "="):
            entry.value = self._store(entry, key, value, off)
        else:
            entry.value = self._compound(entry, key, op, value, off)
        entry.bump()
        return entry.value

    def _store(self, entry: Entry, key: str, value: Value, off: int) -> Value:
        dst = entry.value
        # The first value of an entry created untyped (AnyTypeAllowed) is taken as it is; an
        # empty entry typed BT::Any (4.7.0's SetBlackboard, blackboard.ANY_TYPED) is not one.
        if dst is None and entry.type_name == values.ANY:
            return value
        if isinstance(value, str) and not isinstance(dst, str):
            if entry.has_converter:
                try:
                    return entry.convert(value)
                except ConversionError as e:
                    raise ScriptRuntimeError(
                        f"cannot assign {values.describe(value)} to `{key}` ({entry.type_name}): {e}", off
                    ) from None
            if values.is_number(dst):
                return self.string_to_double(value, off)
            raise ScriptRuntimeError(
                f"cannot assign the string {values.describe(value)} to `{key}`, which holds {self.kind(dst)}", off
            )
        try:
            return values.copy_into(value, dst)
        except ConversionError as e:
            raise ScriptRuntimeError(f"cannot assign {values.describe(value)} to `{key}`: {e}", off) from None

    def _compound(self, entry: Entry, key: str, op: str, value: Value, off: int) -> Value:
        current = entry.value
        if current is None:
            raise ScriptRuntimeError(f"`{key}` has no value yet, so `{op}` cannot update it", off)
        result: Value = current
        if values.is_number(value):
            if not values.is_number(current):
                raise ScriptRuntimeError(
                    f"`{op}` with a number needs a numeric `{key}`, but it holds {self.kind(current)}", off
                )
            a = self.double(current, off, f"`{key}`")
            b = self.double(value, off, f"right operand of `{op}`")
            result = _arith(op[0], a, b)
        elif isinstance(value, str):
            if op != "+=":
                raise ScriptRuntimeError(f"`{op}` cannot be used with a string", off)
            try:
                result = values.to_text(current) + value
            except ConversionError as e:
                raise ScriptRuntimeError(f"`+=` on `{key}`: {e}", off) from None
        try:
            return values.copy_into(result, current)
        except ConversionError as e:
            raise ScriptRuntimeError(f"cannot store the result of `{op}` in `{key}`: {e}", off) from None


def _arith(op: str, a: float, b: float) -> float:
    """IEEE double arithmetic, as C++ does it (division by zero gives inf or nan)."""
    if op == "+":
        return a + b
    if op == "-":
        return a - b
    if op == "*":
        return a * b
    if b == 0.0:
        if math.isnan(a):
            return a  # a NaN operand comes through as it is
        if a == 0.0:
            # 0/0 gives x86-64's default NaN, whose sign bit is set: std::to_string
            # writes it `-nan` (edges table N1)
            return -math.nan
        return math.copysign(math.inf, a) * math.copysign(1.0, b)
    return a / b


_Ordered = TypeVar("_Ordered", float, bytes)


def _compare(op: str, a: _Ordered, b: _Ordered, numeric: bool) -> bool:
    """4.6.2 ``ExprComparison::SwitchImpl``: ``==``/``!=`` on doubles within FLT_EPSILON."""
    if op in ("==", "!="):
        if isinstance(a, float) and isinstance(b, float):
            same = abs(a - b) <= FLT_EPSILON
        else:
            same = a == b
        return same if op == "==" else not same
    if op == "<":
        return not a >= b
    if op == ">":
        return not a <= b
    if op == "<=":
        return not a > b
    return not a < b


_MAX_EXACT_53 = 2**53 - 1


def evaluate(
    script: Script, blackboard: Blackboard, enums: Optional[Mapping[str, int]] = None, int53: bool = False
) -> Optional[Value]:
    """Run a script on a blackboard; returns the value of its last statement.

    ``enums`` are scripting enums (4.6.2 ``registerScriptingEnum``; none by
    default). The result may be None (an empty value, e.g. a variable that
    has none yet). Raises :class:`ScriptRuntimeError`.
    """
    ev = _Evaluator(blackboard, enums or {}, int53)
    result: Optional[Value] = None
    for stmt in script.statements:
        result = ev.eval(stmt)
    return result


def script_truth(value: Optional[Value]) -> bool:
    """A script result as a condition (``cast<bool>()`` in ScriptCondition,
    Precondition and the ``_skipIf``/``_successIf``/``_failureIf``/``_while``
    checks of 4.6.2): a double is true when non-zero; an integer must be 0
    or 1; a string, a queue or an empty value is an error."""
    if value is None:
        raise ScriptRuntimeError("the script gives no value, so it cannot be used as a condition", 0)
    if isinstance(value, (str, Queue)):
        raise ScriptRuntimeError(
            f"the script gives {values.describe(value)} ({values.type_of(value)}), which is not a condition", 0
        )
    try:
        return script_bool(value)
    except ConversionError as e:
        raise ScriptRuntimeError(f"the script's result cannot be used as a condition: {e}", 0) from None


def script_bool(value: Value) -> bool:
    """``cast<bool>()`` of a script value (a condition's result, an operand of `&&`/`||`): the
    number must not be negative, in both releases ("Value is negative and can't be converted to
    unsigned", a double as much as an integer: tests/conformance/oracle-diff/negative_condition),
    then a double is true when non-zero and an integer must be 0 or 1."""
    if not isinstance(value, bool) and isinstance(value, (int, float)) and value < 0:
        raise ConversionError(
            f"cannot convert {values.describe(value)} ({values.type_of(value)}) to bool: the value is negative"
        )
    return bool(values.cast(value, values.BOOL))
