"""The C++ literals the back end prints: strings, views, integers, doubles, bools, statuses.

One spelling of each, for the templates (emit.py and data_cpp.py's filters), the script
writer (script_cpp/), the data side and the firmware cases (tools/mcu.py). Every literal is
exact: a string keeps its UTF-8 bytes (pure ASCII, no trigraph can form), a double its bits
(NaN's sign included), INT64_MIN its value (C++ has no negative literals).
"""

from __future__ import annotations

import math

from btgen.lang import values

# INT64_MIN as a C++ expression: `-9223372036854775808` would be the negation of a literal
# too large for any signed type.
INT64_MIN_TEXT = "(-9223372036854775807 - 1)"


def cpp_string(text: str) -> str:
    """A C++ narrow string literal holding the UTF-8 bytes of `text`.

    Printable ASCII is kept; everything else is an octal escape, so the
    literal is pure ASCII, and no `?` sequences can form trigraphs.
    """
    return '"' + "".join(map(_CPP_STRING_BYTES.__getitem__, text.encode("utf-8"))) + '"'


def cpp_string_chunks(text: str, width: int = 88) -> list[str]:
    """cpp_string(text) as adjacent literals of at most `width` characters each (C++ joins them),
    so that a long message or XML line stays readable; at least one literal. A literal ends
    after a space where one allows it, so a word is never split (grepping the header for a
    message finds it); only a word longer than the width is cut."""
    chunks: list[str] = []
    part: list[str] = []
    size = 2
    space = -1  # index in `part` just after its last space
    for b in text.encode("utf-8"):
        token = _CPP_STRING_BYTES[b]
        while part and size + len(token) > width:
            cut = space if space > 0 else len(part)
            chunks.append('"' + "".join(part[:cut]) + '"')
            part = part[cut:]
            size = 2 + sum(len(t) for t in part)
            space = -1
        part.append(token)
        size += len(token)
        if b == 0x20:
            space = len(part)
    chunks.append('"' + "".join(part) + '"')
    return chunks


# What cpp_string writes for each byte (a table: a 10,000-node mission has some 70,000 literals).
_CPP_STRING_BYTES = [chr(b) if 0x20 <= b < 0x7F else f"\\{b:03o}" for b in range(256)]
_CPP_STRING_BYTES[ord('"')] = '\\"'
_CPP_STRING_BYTES[ord("\\")] = "\\\\"
_CPP_STRING_BYTES[ord("?")] = "\\?"


def cpp_int(value: int) -> str:
    """An int64 literal (INT64_MIN cannot be written as a literal)."""
    return INT64_MIN_TEXT if value == values.INT64_MIN else str(value)


def cpp_bool(value: bool) -> str:
    """`true` or `false`."""
    return "true" if value else "false"


def cpp_string_view(text: str) -> str:
    """`"..."sv`: a std::string_view whose length the compiler gives, so constant evaluation
    does no strlen. The node table of a large mission would otherwise exceed the compilers'
    constexpr budgets (clang's 1M steps at about 10,000 nodes, g++'s 33M ops later)."""
    return f"{cpp_string(text)}sv"


def cpp_double(value: float) -> str:
    """A C++ primary expression of exactly this double.

    A negative value is parenthesized: C++ has no negative literals, so `-1.0` is a unary
    minus, and glued after another `-` (a negated enumerator, `x - NEG`) it would read `--`.
    """
    if math.isnan(value):  # with its sign: `-nan` and `nan` are different texts
        nan = "std::numeric_limits<double>::quiet_NaN()"
        return f"(-{nan})" if math.copysign(1.0, value) < 0 else nan
    if math.isinf(value):
        text = "std::numeric_limits<double>::infinity()"
    else:
        text = repr(abs(value))
        if "e" not in text and "." not in text:
            text += ".0"
    return f"(-{text})" if math.copysign(1.0, value) < 0 else text


def cpp_int64(value: int) -> str:
    """An std::int64_t of exactly this value."""
    return f"std::int64_t{{{INT64_MIN_TEXT[1:-1]}}}" if value == values.INT64_MIN else f"std::int64_t{{{value}}}"


def cpp_view(text: str) -> str:
    """A std::string_view of exactly these UTF-8 bytes."""
    return f"std::string_view({cpp_string(text)}, {len(text.encode('utf-8'))})"


def cpp_status(status) -> str:
    """A NodeStatus as its btgen::Status enumerator."""
    return f"btgen::Status::{status.name}"


def cpp_value(value: object) -> str:
    """A C++ literal of a scalar Python value (values.py representation)."""
    if isinstance(value, bool):
        return cpp_bool(value)
    if isinstance(value, int) and not hasattr(value, "name"):
        return cpp_int64(value)
    if isinstance(value, float):
        return cpp_double(value)
    if hasattr(value, "name"):  # NodeStatus
        return cpp_status(value)
    raise TypeError(value)
