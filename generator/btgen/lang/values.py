"""Values and types of ports and blackboard entries, with BehaviorTree.CPP 4.6.2 rules.

Canonical type names (what :func:`normalize_type` returns):

============== ==================================================================
``int``        32-bit signed (4.6.2 ``int``; ``int64_t``/``long`` are narrowed)
``unsigned``   32-bit unsigned (4.6.2 ``unsigned int``; ``uint64_t`` narrowed)
``double``     IEEE double (``float`` ports are read as double)
``bool``       ``bool``
``string``     ``std::string``
``NodeStatus`` ``BT::NodeStatus``
``any``        ``BT::AnyTypeAllowed`` / no ``type`` attribute: takes any value
``queue<T>``   ``BT::SharedQueue<T>`` for T in int, double, bool, string
other text     a user type btgen cannot see into: kept as its text and handled
               as an opaque string (its literal is stored unconverted)
============== ==================================================================

Python representation of values (``None`` is never a value: it stands for
"no value yet", 4.6.2's empty ``BT::Any``):

- ``int``: integers (4.6.2 keeps every integer as ``int64_t`` inside ``Any``);
- ``float``: doubles; ``bool``: booleans (4.6.2 stores them as the integers
  1 and 0, so they count as numbers and print as ``1``/``0``);
- ``str``: strings, and values of opaque user types;
- :class:`~btgen.lang.status.NodeStatus`: statuses (an integer in 4.6.2);
- :class:`Queue`: a ``collections.deque`` that knows its element type; like
  4.6.2's ``SharedQueue`` (a ``shared_ptr<deque>``) it is shared, not copied,
  when read from the blackboard, so popping an element changes the entry.

Two conversions exist in 4.6.2 and both are here: :func:`convert_from_string`
(``BT::convertFromString<T>``: port literals, strings read through a typed
port) and :func:`cast` (``BT::Any::cast<T>``: a stored value read as another
type, with 4.6.2's range and precision checks). :func:`to_text` is
``Any::cast<std::string>`` (``std::to_string`` for numbers).
"""

from __future__ import annotations

import collections
import math
import re
from collections.abc import Iterable
from typing import Optional, Union

from btgen.lang.status import NodeStatus

INT = "int"
UNSIGNED = "unsigned"
DOUBLE = "double"
BOOL = "bool"
STRING = "string"
NODE_STATUS = "NodeStatus"
ANY = "any"
QUEUE_ELEMENT_TYPES = (INT, DOUBLE, BOOL, STRING)
QUEUE_TYPES = tuple(f"queue<{t}>" for t in QUEUE_ELEMENT_TYPES)
SCALAR_TYPES = (INT, UNSIGNED, DOUBLE, BOOL, STRING, NODE_STATUS)
CANONICAL_TYPES = SCALAR_TYPES + (ANY,) + QUEUE_TYPES

INT_MIN, INT_MAX = -(2**31), 2**31 - 1
UNSIGNED_MAX = 2**32 - 1
INT64_MIN, INT64_MAX = -(2**63), 2**63 - 1
UINT64_MAX = 2**64 - 1
_DBL_MIN_NORMAL = 2.2250738585072014e-308


class ConversionError(ValueError):
    """A value that cannot be converted; ``str()`` is a complete message."""


class Queue(collections.deque[object]):
    """A queue value (4.6.2 ``SharedQueue<T>``): a deque plus its element type."""

    def __init__(self, element_type: str, items: Iterable[object] = ()) -> None:
        super().__init__(items)
        if element_type not in QUEUE_ELEMENT_TYPES:
            raise ValueError(f"no queue of `{element_type}`")
        self.element_type = element_type

    @property
    def type_name(self) -> str:
        return f"queue<{self.element_type}>"

    def __repr__(self) -> str:
        return f"Queue({self.element_type!r}, {list(self)!r})"

    def __eq__(self, other: object) -> bool:
        if isinstance(other, Queue):
            return self.element_type == other.element_type and list(self) == list(other)
        return NotImplemented


Value = Union[int, float, bool, str, NodeStatus, Queue]

# --------------------------------------------------------------------- types

_STRING_NAMES = {
    "std::string",
    "string",
    "std::__cxx11::string",
    "std::basic_string<char>",
    "std::basic_string<char,std::char_traits<char>,std::allocator<char>>",
    "std::__cxx11::basic_string<char,std::char_traits<char>,std::allocator<char>>",
    "std::string_view",
    "std::basic_string_view<char>",
    "std::basic_string_view<char,std::char_traits<char>>",
    "BT::StringView",
    "SafeAny::SimpleString",
}
_INT_NAMES = {
    "int",
    "signed",
    "signed int",
    "int32_t",
    "std::int32_t",
    "int64_t",
    "std::int64_t",
    "long",
    "long int",
    "signed long",
    "long long",
    "long long int",
    "short",
    "short int",
    "int16_t",
    "std::int16_t",
    "int8_t",
    "std::int8_t",
    "char",
    "signed char",
}
_UNSIGNED_NAMES = {
    "unsigned",
    "unsigned int",
    "uint32_t",
    "std::uint32_t",
    "uint64_t",
    "std::uint64_t",
    "unsigned long",
    "unsigned long int",
    "unsigned long long",
    "unsigned long long int",
    "size_t",
    "std::size_t",
    "unsigned short",
    "unsigned short int",
    "uint16_t",
    "std::uint16_t",
    "uint8_t",
    "std::uint8_t",
    "unsigned char",
}
_DOUBLE_NAMES = {"double", "float", "long double"}
_BOOL_NAMES = {"bool"}
_STATUS_NAMES = {"BT::NodeStatus", "NodeStatus"}
_ANY_NAMES = {"", "any", "BT::AnyTypeAllowed", "AnyTypeAllowed", "BT::Any", "Any"}


def _compact(text: str) -> str:
    """Whitespace-insensitive form for matching: no blanks around `<>,:*&`."""
    text = re.sub(r"\s+", " ", text.strip())
    return re.sub(r"\s*([<>,:*&])\s*", r"\1", text)


def _template_args(compact: str, names: tuple[str, ...]) -> Optional[list[str]]:
    """Top-level template arguments when ``compact`` is ``N<...>`` for N in names."""
    for name in names:
        if compact.startswith(name + "<") and compact.endswith(">"):
            inner = compact[len(name) + 1 : -1]
            args, depth, start = [], 0, 0
            for i, c in enumerate(inner):
                if c == "<":
                    depth += 1
                elif c == ">":
                    depth -= 1
                    if depth < 0:
                        return None
                elif c == "," and depth == 0:
                    args.append(inner[start:i])
                    start = i + 1
            if depth != 0:
                return None
            args.append(inner[start:])
            return args
    return None


def _queue_element(compact: str) -> Optional[str]:
    """The element type text of a queue type spelling, or None."""
    args = _template_args(compact, ("std::shared_ptr", "shared_ptr"))
    if args is not None and len(args) == 1:
        inner = _template_args(args[0], ("std::deque", "deque"))
        if inner is not None and 1 <= len(inner) <= 2:
            return inner[0]
        return None
    args = _template_args(compact, ("BT::SharedQueue", "SharedQueue", "queue", "std::deque", "deque"))
    if args is not None and 1 <= len(args) <= 2:
        return args[0]
    return None


# Integer types of every width (BehaviorTree.CPP converts each with its own convertFromString):
# <cstdint>'s names, with or without `std::` and `_t` (ROS writes `uint16`), and the words of
# C++'s integer types in any order the language allows (`long unsigned int`).
_FIXED_WIDTH = re.compile(r"(?:std::)?(u?)int(?:_least|_fast)?(8|16|32|64)(?:_t)?|(?:std::)?(u?)int(max|ptr)_t")
_INTEGER_WORDS = frozenset(("signed", "unsigned", "short", "long", "int", "char"))


def _integer_type(compact: str) -> Optional[str]:
    """INT or UNSIGNED for a spelling of an integer type that the name sets do not list, or None."""
    m = _FIXED_WIDTH.fullmatch(compact)
    if m:
        return UNSIGNED if (m.group(1) or m.group(3)) else INT
    if compact in ("ptrdiff_t", "std::ptrdiff_t", "ssize_t"):
        return INT
    words = compact.split(" ")
    if not words or any(w not in _INTEGER_WORDS for w in words):
        return None
    n = {w: words.count(w) for w in _INTEGER_WORDS}
    sign = n["signed"] + n["unsigned"]
    if sign > 1 or n["short"] > 1 or n["int"] > 1 or n["char"] > 1 or n["long"] > 2:
        return None
    if n["short"] and n["long"]:
        return None
    if n["char"] and len(words) != 1 + sign:  # char, signed char, unsigned char
        return None
    return UNSIGNED if n["unsigned"] else INT


def _integer_bits(compact: str) -> Optional[int]:
    """The width in bits of a spelling of an integer type (LP64: `long` is 64 bits), or None."""
    m = _FIXED_WIDTH.fullmatch(compact)
    if m:
        return int(m.group(2)) if m.group(2) else 64
    base = compact[len("std::") :] if compact.startswith("std::") else compact
    if base in ("size_t", "ptrdiff_t", "ssize_t"):
        return 64
    words = compact.split(" ")
    if any(w not in _INTEGER_WORDS for w in words):
        return None
    if "char" in words:
        return 8
    if "short" in words:
        return 16
    return 64 if "long" in words else 32


def integer_range(text: Optional[str]) -> Optional[tuple[int, int]]:
    """The range of the integer type a TreeNodesModel `type=` names (`uint16` -> 0..65535), or
    None when it is no integer type. 4.6.2's convertFromString<T> checks a literal against the
    range of T itself (tests/int_widths/convert-4.6.2.txt)."""
    if text is None:
        return None
    kind = normalize_type(text)
    if kind not in (INT, UNSIGNED):
        return None
    bits = _integer_bits(_compact(text))
    if bits is None:
        return None
    return (0, 2**bits - 1) if kind == UNSIGNED else (-(2 ** (bits - 1)), 2 ** (bits - 1) - 1)


def convert_integer(text: str, name: str, lo: int, hi: int, *, strict: bool = False) -> int:
    """4.6.2's convertFromString<T> for an integer type T of range lo..hi, named `name` in messages."""
    m = _FROM_CHARS_INT_RE.match(text)
    if not m:
        raise ConversionError(f"`{text}` is not a valid {name}")
    _strict_check(text, m.end(), name, strict)
    value = int(m.group(0))
    if not lo <= value <= hi:
        raise ConversionError(f"`{text}` is out of range for {name} ({lo} to {hi})")
    return value


def normalize_type(text: Optional[str]) -> str:
    """The canonical type name for a type as a TreeNodesModel writes it.

    ``None`` (no ``type`` attribute) and ``BT::AnyTypeAllowed`` give ``any``;
    4.6.2's demangled names (``std::string``, ``long``, ``unsigned int``,
    ``BT::NodeStatus``, ``std::shared_ptr<std::deque<int, std::allocator<int> > >``,
    ...) map to the canonical names; anything else is a user type, returned
    as its text with surrounding blanks removed.
    """
    if text is None:
        return ANY
    compact = _compact(text)
    if compact in CANONICAL_TYPES:
        return compact
    for names, canonical in (
        (_STRING_NAMES, STRING),
        (_INT_NAMES, INT),
        (_UNSIGNED_NAMES, UNSIGNED),
        (_DOUBLE_NAMES, DOUBLE),
        (_BOOL_NAMES, BOOL),
        (_STATUS_NAMES, NODE_STATUS),
        (_ANY_NAMES, ANY),
    ):
        if compact in names:
            return canonical
    integer = _integer_type(compact)
    if integer is not None:
        return integer
    elem = _queue_element(compact)
    if elem is not None:
        canonical_elem = normalize_type(elem)
        if canonical_elem in QUEUE_ELEMENT_TYPES:
            return f"queue<{canonical_elem}>"
    return re.sub(r"\s+", " ", text.strip())


def queue_element_type(type_name: str) -> Optional[str]:
    """``int`` for ``queue<int>``; None when ``type_name`` is not a queue type."""
    if type_name in QUEUE_TYPES:
        return type_name[len("queue<") : -1]
    return None


def is_opaque_type(type_name: str) -> bool:
    """A user type btgen knows only by name (handled as an opaque string)."""
    return type_name not in CANONICAL_TYPES


def is_strongly_typed(type_name: str) -> bool:
    """4.6.2 ``TypeInfo::isStronglyTyped``: every type except ``any``."""
    return type_name != ANY


def type_of(value: Value) -> str:
    """The canonical type of a Python value (``string`` for opaque values)."""
    if isinstance(value, bool):
        return BOOL
    if isinstance(value, NodeStatus):
        return NODE_STATUS
    if isinstance(value, int):
        return INT
    if isinstance(value, float):
        return DOUBLE
    if isinstance(value, str):
        return STRING
    if isinstance(value, Queue):
        return value.type_name
    raise TypeError(f"not a btgen value: {value!r}")


def is_number(value: object) -> bool:
    """4.6.2 ``Any::isNumber``: integers (bools and statuses included) and doubles."""
    return isinstance(value, (int, float, NodeStatus))


def is_string(value: object) -> bool:
    """4.6.2 ``Any::isString``."""
    return isinstance(value, str)


# ----------------------------------------------------------- text -> number
# Two parsers, as in 4.6.2: std::from_chars (Any::cast from a string, and
# convertFromString for integers) and std::stod (convertFromString<double>).

_FROM_CHARS_INT_RE = FROM_CHARS_INT_RE = re.compile(r"-?[0-9]+")
_FROM_CHARS_DOUBLE_RE = re.compile(
    r"-?(?:(?P<inf>inf(?:inity)?)|(?P<nan>nan(?:\([0-9A-Za-z_]*\))?)"
    r"|(?P<mant>[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?)",
    re.IGNORECASE,
)
_STOD_RE = re.compile(
    r"[ \t\n\v\f\r]*(?P<num>[+-]?(?:"
    r"(?P<hex>0[xX](?P<hmant>[0-9a-fA-F]+\.?[0-9a-fA-F]*|\.[0-9a-fA-F]+)(?:[pP][+-]?[0-9]+)?)"
    r"|(?P<inf>inf(?:inity)?)|(?P<nan>nan(?:\([0-9A-Za-z_]*\))?)"
    r"|(?P<mant>[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?))",
    re.IGNORECASE,
)


def _range_text(type_name: str) -> str:
    if type_name == INT:
        return f" ({INT_MIN} to {INT_MAX})"
    if type_name == UNSIGNED:
        return f" (0 to {UNSIGNED_MAX})"
    return ""


def _strict_check(text: str, end: int, type_name: str, strict: bool) -> None:
    if strict and end != len(text):
        raise ConversionError(f"`{text}` is not a valid {type_name}: unexpected `{text[end:]}` after the number")


def _from_chars_int(text: str, type_name: str, lo: int, hi: int, strict: bool = False) -> int:
    """``std::from_chars`` into an integer type: optional `-`, digits, rest ignored."""
    m = _FROM_CHARS_INT_RE.match(text)
    if not m:
        raise ConversionError(f"`{text}` is not a valid {type_name}")
    _strict_check(text, m.end(), type_name, strict)
    value = int(m.group(0))
    if not lo <= value <= hi:
        raise ConversionError(f"`{text}` is out of range for {type_name}{_range_text(type_name)}")
    return value


def _float_checked(text: str, literal: str, mant: Optional[str], hexa: bool, reject_subnormal: bool) -> float:
    try:
        value = float.fromhex(literal) if hexa else float(literal)
    except OverflowError:
        raise ConversionError(f"`{text}` is out of range for double") from None
    if mant is not None:
        digits = re.sub(r"[^0-9a-fA-F]" if hexa else r"[^0-9]", "", mant)
        nonzero = any(c != "0" for c in digits)
        if math.isinf(value) or (nonzero and value == 0.0) or (reject_subnormal and 0.0 < abs(value) < _DBL_MIN_NORMAL):
            raise ConversionError(f"`{text}` is out of range for double")
    return value


def _from_chars_double(text: str, strict: bool = False) -> float:
    """``std::from_chars`` into a double: no leading blanks or `+`, no hex, rest ignored."""
    m = _FROM_CHARS_DOUBLE_RE.match(text)
    if not m:
        raise ConversionError(f"`{text}` is not a valid double")
    _strict_check(text, m.end(), DOUBLE, strict)
    literal = m.group(0)
    if m.group("nan"):
        return math.copysign(math.nan, -1.0 if literal.startswith("-") else 1.0)
    return _float_checked(text, literal, m.group("mant"), False, False)


def _stod(text: str, strict: bool = False) -> float:
    """``std::stod``: leading blanks, sign, decimal, hex, inf and nan; rest ignored."""
    m = _STOD_RE.match(text)
    if not m:
        raise ConversionError(f"`{text}` is not a valid double")
    if strict and m.start("num") != 0:
        raise ConversionError(f"`{text}` is not a valid double: unexpected blanks before the number")
    _strict_check(text, m.end(), DOUBLE, strict)
    literal = m.group("num")
    if m.group("nan"):
        return math.copysign(math.nan, -1.0 if literal.startswith("-") else 1.0)
    if m.group("hex"):
        return _float_checked(text, literal, m.group("hmant"), True, True)
    return _float_checked(text, literal, m.group("mant"), False, True)


def string_to_number(text: str, type_name: str) -> Union[int, float]:
    """4.6.2 ``Any::stringToNumber<T>`` (``std::from_chars``), used by :func:`cast`."""
    if type_name == INT:
        return _from_chars_int(text, INT, INT_MIN, INT_MAX)
    if type_name == UNSIGNED:
        if text.startswith("-"):
            raise ConversionError(f"`{text}` is not a valid unsigned")
        return _from_chars_int(text, UNSIGNED, 0, UNSIGNED_MAX)
    if type_name == DOUBLE:
        return _from_chars_double(text)
    if type_name == "int64":
        return _from_chars_int(text, "integer", INT64_MIN, INT64_MAX)
    raise ValueError(f"no string-to-number conversion to `{type_name}`")


# ------------------------------------------------------ convertFromString

_BOOL_TRUE = ("1", "true", "TRUE", "True")
_BOOL_FALSE = ("0", "false", "FALSE", "False")
_STATUS_BY_NAME = {s.name: s for s in NodeStatus}


def _split_queue(text: str) -> list[str]:
    """4.6.2 ``splitString(str, ';')``: no element for an empty text or a final `;`."""
    parts: list[str] = []
    pos = 0
    while pos < len(text):
        end = text.find(";", pos)
        if end < 0:
            end = len(text)
        parts.append(text[pos:end])
        pos = end + 1
    return parts


def convert_from_string(type_name: str, text: str, *, strict: bool = False, double_from_chars: bool = False) -> Value:
    """4.6.2 ``convertFromString<T>(text)`` for a canonical type name.

    - ``int``/``unsigned``: ``std::from_chars`` into a 64-bit integer (an
      optional `-` then digits; no blanks, no `+`; text after the digits is
      ignored) and a range check (``ConvertWithBoundCheck``);
    - ``double``: ``std::stod`` (leading blanks, `+`/`-`, decimal or hex
      digits, ``inf``, ``nan``; text after the number is ignored);
    - ``bool``: exactly ``1 0 true false TRUE FALSE True False``;
    - ``NodeStatus``: exactly ``IDLE RUNNING SUCCESS FAILURE SKIPPED``;
    - ``string``, ``any`` and opaque user types: the text itself;
    - ``queue<T>``: the text split at every `;` (no element for an empty
      text or after a final `;`), each part converted as T.

    ``strict=True`` also rejects text after a number (which 4.6.2 silently
    drops), for linting. Raises :class:`ConversionError`.
    """
    if type_name == INT:
        return _from_chars_int(text, INT, INT_MIN, INT_MAX, strict)
    if type_name == UNSIGNED:
        # 4.6.2 parses as int64 then checks [0, UINT32_MAX].
        return _from_chars_int(text, UNSIGNED, 0, UNSIGNED_MAX, strict)
    if type_name == DOUBLE:
        # 4.9.0 and later: std::from_chars (no leading blank, no `+`, no hex)
        return _from_chars_double(text, strict) if double_from_chars else _stod(text, strict)
    if type_name == BOOL:
        if text in _BOOL_TRUE:
            return True
        if text in _BOOL_FALSE:
            return False
        raise ConversionError(f"`{text}` is not a valid bool (use true or false, 1 or 0)")
    if type_name == NODE_STATUS:
        if text in _STATUS_BY_NAME:
            return _STATUS_BY_NAME[text]
        raise ConversionError(f"`{text}` is not a valid NodeStatus (use IDLE, RUNNING, SUCCESS, FAILURE or SKIPPED)")
    elem = queue_element_type(type_name)
    if elem is not None:
        items = []
        for i, part in enumerate(_split_queue(text), start=1):
            try:
                items.append(convert_from_string(elem, part, strict=strict, double_from_chars=double_from_chars))
            except ConversionError as e:
                raise ConversionError(f"`{text}` is not a valid {type_name}: element {i}: {e}") from None
        return Queue(elem, items)
    return text  # string, any, opaque user types


# ----------------------------------------------------------- value -> text


def format_double(value: float) -> str:
    """``std::to_string(double)``: ``printf("%f")``, e.g. ``6.000000``, ``-nan``."""
    if math.isnan(value):
        return "-nan" if math.copysign(1.0, value) < 0 else "nan"
    return f"{value:f}"


def to_text(value: Value) -> str:
    """4.6.2 ``Any::cast<std::string>()``: what ``..``, ``+=`` on strings and a
    ``string`` port reading a number produce.

    Integers print in decimal, bools as ``1``/``0`` and statuses as their
    number (all are ``int64_t`` inside 4.6.2's ``Any``), doubles with
    ``std::to_string`` (``2.500000``). A queue has no text.
    """
    if isinstance(value, str):
        return value
    if isinstance(value, NodeStatus):
        return str(value.value)
    if isinstance(value, bool):
        return "1" if value else "0"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return format_double(value)
    if value is None:
        raise ConversionError("the value is empty")
    raise ConversionError(f"a {type_of(value)} has no text form")


def describe(value: Optional[Value]) -> str:
    """A value for messages: ``3``, ``2.5``, ``'text'``, ``SUCCESS``, ``queue<int> [1, 2]``."""
    if value is None:
        return "(no value)"
    if isinstance(value, str):
        return repr(value)
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, Queue):
        return f"{value.type_name} {list(value)!r}"
    return str(value)


# ------------------------------------------------------------------- casts


def _number_value(value: Value) -> Union[int, float]:
    if isinstance(value, NodeStatus):
        return value.value
    if isinstance(value, bool):
        return int(value)
    assert isinstance(value, (int, float))
    return value


def _cast_error(value: Value, type_name: str, why: str) -> ConversionError:
    return ConversionError(f"cannot convert {describe(value)} ({type_of(value)}) to {type_name}: {why}")


def _to_integer(value: Value, type_name: str, lo: int, hi: int) -> int:
    """4.6.2 ``convertNumber`` from a number to an integer type."""
    v = _number_value(value)
    if isinstance(v, float):
        if lo == 0 and v < 0:
            raise _cast_error(value, type_name, "the value is negative")
        if math.isnan(v) or math.isinf(v) or v != math.floor(v):
            raise _cast_error(value, type_name, "the value is not a whole number")
        if not lo <= v <= hi:
            raise _cast_error(value, type_name, "the value is out of range")
        return int(v)
    if lo == 0 and v < 0:
        raise _cast_error(value, type_name, "the value is negative")
    if not lo <= v <= hi:
        raise _cast_error(value, type_name, "the value is out of range")
    return v


def _to_double(value: Value) -> float:
    """4.6.2 ``convertNumber`` to double: an integer must be exactly representable."""
    v = _number_value(value)
    if isinstance(v, float):
        return v
    f = float(v)
    if int(f) != v:
        raise _cast_error(value, DOUBLE, "precision would be lost")
    return f


def cast(value: Optional[Value], type_name: str) -> Value:
    """4.6.2 ``Any::cast<T>()``: read a stored value as ``type_name``.

    Numbers convert with 4.6.2's checks: to an integer type only whole
    numbers in range (negative values never to ``unsigned``), to ``double``
    only integers a double holds exactly, to ``bool`` any double but only the
    integers 0 and 1. A string converts to a number with ``std::from_chars``
    (to ``bool``: never); a number to ``string`` with :func:`to_text`; a
    queue only to its own type; ``any`` accepts everything; opaque user
    types accept strings. Raises :class:`ConversionError`.
    """
    if value is None:
        raise ConversionError("the value is empty")
    if type_name == ANY:
        return value
    if type_name == STRING or is_opaque_type(type_name):
        if isinstance(value, Queue):
            raise _cast_error(value, type_name, "no known conversion")
        if type_name != STRING and not isinstance(value, str):
            raise _cast_error(value, type_name, "no known conversion")
        return to_text(value)
    elem = queue_element_type(type_name)
    if elem is not None:
        if isinstance(value, Queue) and value.element_type == elem:
            return value
        raise _cast_error(value, type_name, "no known conversion")
    if isinstance(value, Queue):
        raise _cast_error(value, type_name, "no known conversion")
    if isinstance(value, str):
        if type_name in (INT, UNSIGNED, DOUBLE):
            return string_to_number(value, type_name)
        if type_name == NODE_STATUS:
            n = string_to_number(value, "int64")
            assert isinstance(n, int)
            return _status_from_int(n, value)
        raise ConversionError(f"cannot convert the string {describe(value)} to {type_name}")
    # value is a number
    if type_name == INT:
        return _to_integer(value, INT, INT_MIN, INT_MAX)
    if type_name == UNSIGNED:
        return _to_integer(value, UNSIGNED, 0, UNSIGNED_MAX)
    if type_name == DOUBLE:
        return _to_double(value)
    if type_name == BOOL:
        if isinstance(value, bool):
            return value
        v = _number_value(value)
        if isinstance(v, float):
            return v != 0.0  # static_cast<bool>(double); NaN is true
        if v not in (0, 1):
            raise _cast_error(value, BOOL, "only the integers 0 and 1 convert to bool")
        return v == 1
    if type_name == NODE_STATUS:
        if isinstance(value, NodeStatus):
            return value
        return _status_from_int(_to_integer(value, INT, INT_MIN, INT_MAX), value)
    raise ValueError(f"unknown type `{type_name}`")


def _status_from_int(n: int, original: Value) -> NodeStatus:
    for s in NodeStatus:
        if s.value == n:
            return s
    raise _cast_error(original, NODE_STATUS, f"{n} is not a status number (0 to 4)")


def to_int64(value: Value) -> int:
    """``cast<int64_t>`` of a number (script bitwise operators, ``copyInto``)."""
    return _to_integer(value, "integer", INT64_MIN, INT64_MAX)


def to_double(value: Value) -> float:
    """``cast<double>`` of a number or of a string (``std::from_chars``)."""
    if isinstance(value, str):
        return _from_chars_double(value)
    if not is_number(value):
        raise _cast_error(value, DOUBLE, "no known conversion")
    return _to_double(value)


def is_casting_safe(type_name: str, value: Value) -> bool:
    """4.6.2 ``isCastingSafe``: whether a number fits an entry declared ``type_name``."""
    if not is_number(value):
        return False
    v = _number_value(value)
    if type_name in (INT, UNSIGNED):
        lo, hi = (INT_MIN, INT_MAX) if type_name == INT else (0, UNSIGNED_MAX)
        if isinstance(v, float) and (math.isnan(v) or math.isinf(v) or v != math.floor(v)):
            return False
        return lo <= v <= hi
    if type_name == DOUBLE:
        return isinstance(v, float) or int(float(v)) == v
    return False


def _like(n: Union[int, NodeStatus], destination: Value) -> Value:
    """An integer shown with the destination's original type (4.6.2 keeps it on copy)."""
    v = _number_value(n)
    if isinstance(destination, bool):
        return bool(v) if v in (0, 1) else v
    if isinstance(destination, NodeStatus):
        return next((s for s in NodeStatus if s.value == v), v)
    return v


def copy_into(value: Value, destination: Optional[Value]) -> Value:
    """4.6.2 ``Any::copyInto``: the value an entry holding ``destination`` gets.

    An empty destination takes the value as is; two strings, or two values
    of the same stored kind (integer / double), replace; a number into a
    number of the other kind converts to the destination's kind (with
    :func:`cast`'s checks); anything else fails. An integer keeps the
    destination's original type where it can (1 into a bool is True).
    """
    if destination is None:
        return value
    if isinstance(value, str) and isinstance(destination, str):
        return value
    if is_number(value) and is_number(destination):
        if isinstance(destination, float):
            return value if isinstance(value, float) else _to_double(value)
        n = to_int64(value) if isinstance(value, float) else value
        assert isinstance(n, (int, NodeStatus))
        return _like(n, destination)
    if isinstance(value, Queue) and isinstance(destination, Queue) and value.element_type == destination.element_type:
        return value
    raise ConversionError(f"a {type_of(value)} cannot be stored where a {type_of(destination)} is")
