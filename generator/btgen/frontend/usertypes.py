"""User port types: what BehaviorTree.CPP's ``convertFromString<T>`` specialisations give a team.

A port or entry type that TreeNodesModel names and that is not built in (``Pose2D``,
``geometry_msgs::msg::PoseStamped``, ...) is text by default. ``btgen compile --type
NAME=CPP_TYPE@HEADER`` maps it to a C++ type instead:

- NAME is the type exactly as the port's ``type=`` attribute writes it (blanks around
  ``<>,:*&`` do not matter, as for built-in type names);
- CPP_TYPE is the C++ type (``nav::Pose2D``, ``std::array<double, 3>``);
- HEADER declares it and its conversion; the generated header has ``#include "HEADER"``
  (``@<HEADER>`` gives ``#include <HEADER>``).

Entries of that type hold the value itself, in place in the mission object (constructed once,
assigned on writes; the type may own memory, as a ROS message does: then its own copy may
allocate, btgen's code never does; the generated code static_asserts that it is default
constructible and copyable), leaves get typed accessors
(``btgen::Input<T> goal()``, ``bool set_goal(const T&)``), and literals of such ports are
converted once, when the mission object is constructed, by the user's
``bool convertFromString(std::string_view, T&)`` (found by argument-dependent lookup) or a
specialisation of ``btgen::StringConverter<T>`` (btgen/user_type.hpp).
"""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Sequence
from dataclasses import dataclass

from btgen.diagnostics import Diagnostic, Loc, UserError, one_line
from btgen.lang import values
from btgen.lang.kind import UserKind
from btgen.lang.model import Mission

_IDENT = r"[A-Za-z_][A-Za-z0-9_]*"
_FUNDAMENTAL = (
    "int",
    "long",
    "short",
    "char",
    "double",
    "float",
    "bool",
    "signed",
    "unsigned",
    "wchar_t",
    "char16_t",
    "char32_t",
)
_TOKEN = re.compile(rf"\s*(::|{_IDENT}|[0-9]+|[<>,*&])", re.ASCII)


@dataclass(frozen=True)
class UserType:
    name: str  # the type as TreeNodesModel writes it (values.normalize_type form)
    cpp_type: str  # the C++ type, blanks normalised
    header: str  # as given; `<x.hpp>` keeps its brackets

    @property
    def include(self) -> str:
        return self.header if self.header.startswith("<") else f'"{self.header}"'

    @property
    def cpp(self) -> str:
        """The type as generated code names it: from the global namespace (`::nav::Pose2D`), so that no
        name of the generated namespaces (`detail`, `leaf`, `Blackboard`, ...) can capture it."""
        m = re.match(rf"\s*({_IDENT})", self.cpp_type)
        first = m.group(1) if m else ""
        if self.cpp_type.startswith("::") or first in _FUNDAMENTAL:
            return self.cpp_type
        return "::" + self.cpp_type

    @property
    def kind(self) -> UserKind:
        return kind_of(self.name)


def kind_of(name: str) -> UserKind:
    """The data-side kind of the entries of a user type (blanks around `<>,:*&` do not matter)."""
    return UserKind(values._compact(name))


# The words of C++17's fundamental value types; a run of them is one type when it is one of
# the standard's combinations (_fundamental_problem).
_FUNDAMENTAL_WORDS = frozenset(
    "bool char wchar_t char16_t char32_t short int long signed unsigned float double".split()
)


def _fundamental_problem(words: list[str]) -> str:
    """Why this run of fundamental type words is not one C++ type ("" when it is): the
    combinations of [dcl.type.simple], in any order (`long unsigned int` is `unsigned long`)."""
    count = {w: words.count(w) for w in set(words)}
    shown = " ".join(words)
    bad = f"`{shown}` is not a C++ type"
    if any(n > 1 for w, n in count.items() if w != "long") or count.get("long", 0) > 2:
        return bad
    sign = count.get("signed", 0) + count.get("unsigned", 0)
    size = count.get("short", 0) + count.get("long", 0)
    alone = {"bool", "wchar_t", "char16_t", "char32_t", "float"}
    if len(words) == 1:
        return ""
    if set(words) & alone:
        return bad
    if "char" in count:
        return "" if sign == 1 and len(words) == 2 else bad
    if "double" in count:
        return "" if set(words) == {"double", "long"} and count["long"] == 1 else bad
    if sign > 1 or ("short" in count and "long" in count):
        return bad
    return "" if sign + size + count.get("int", 0) == len(words) else bad


def _cpp_type_problem(text: str) -> str:
    """Why `text` is not a C++ type spelling btgen accepts ("" when it is): one fundamental
    type (`unsigned long`, `char32_t`), or a qualified name (`::nav::Pose2D`), each part of
    which may have template arguments (types or integers; `std::less<>`). Pointers and
    references are excluded, and so are keywords, macros (`NULL`, `std::EOF`, `NDEBUG`) and
    reserved names (`__x`, `_X`), which would not build."""
    tokens: list[str] = []
    pos = 0
    text = text.strip()
    while pos < len(text):
        m = _TOKEN.match(text, pos)
        if not m:
            return f"`{one_line(text[pos:].strip()[:1])}` cannot appear in a C++ type name here"
        tokens.append(m.group(1))
        pos = m.end()
    if any(t in ("*", "&") for t in tokens):
        return "pointers and references cannot live in the blackboard by value"
    from btgen.backend_cpp.naming import CPP_KEYWORDS, is_macro

    i = 0

    def peek() -> str:
        return tokens[i] if i < len(tokens) else ""

    def a_type() -> str:
        nonlocal i
        if peek() in _FUNDAMENTAL_WORDS:
            words = []
            while peek() in _FUNDAMENTAL_WORDS:
                words.append(peek())
                i += 1
            return _fundamental_problem(words)
        if peek() == "::":
            i += 1
        while True:
            t = peek()
            if not t or not re.fullmatch(_IDENT, t):
                return "it is incomplete" if not t else f"`{t}` is not a type"
            if t in CPP_KEYWORDS:
                return f"`{t}` is a C++ keyword"
            if is_macro(t):
                return f"`{t}` is a macro (the preprocessor replaces it)"
            if "__" in t or (t[0] == "_" and (len(t) == 1 or t[1].isupper())):
                return f"`{t}` is reserved in C++ (a double underscore, or `_` and a capital)"
            i += 1
            if peek() == "<":
                i += 1
                if peek() == ">":
                    i += 1
                else:
                    while True:
                        if peek()[:1].isdigit():
                            i += 1
                        else:
                            problem = a_type()
                            if problem:
                                return problem
                        if peek() == ",":
                            i += 1
                        elif peek() == ">":
                            i += 1
                            break
                        else:
                            return "it is incomplete" if not peek() else "unbalanced `<` and `>`"
            if peek() != "::":
                return ""
            i += 1

    problem = a_type()
    if problem:
        return problem
    if i < len(tokens):
        t = tokens[i]
        if t in (">", ","):
            return "unbalanced `<` and `>`" if t == ">" else "`,` outside template arguments"
        return f"`{t}` follows a complete type"
    return ""


# A header name that builds alike everywhere: letters, digits and `_ . + - /`, no `//` (a
# comment start inside a header name is undefined) and so no trigraph (`??/`) either.
_HEADER_PATH = re.compile(r"(?!.*//)[A-Za-z0-9_.+\-/]+", re.ASCII)


def parse(text: str) -> UserType:
    """``NAME=CPP_TYPE@HEADER`` -> UserType; ValueError with the reason."""
    name, eq, rest = text.partition("=")
    cpp, at, header = rest.rpartition("@")
    example = "for example Pose2D=nav::Pose2D@nav/pose2d.hpp"
    if not eq or not at or not name.strip() or not cpp.strip() or not header.strip():
        raise ValueError(f"`{text}` is not a type declaration: write NAME=CPP_TYPE@HEADER ({example})")
    name, cpp, header = name.strip(), cpp.strip(), header.strip()
    canonical = values.normalize_type(name)
    if not values.is_opaque_type(canonical):
        raise ValueError(
            f"`{name}` is a type btgen already knows ({canonical}); --type declares only types that are not built in"
        )
    problem = _cpp_type_problem(cpp)
    if problem:
        raise ValueError(f"`{cpp}` is not a C++ type btgen can use for `{name}`: {problem}")
    path = header[1:-1] if header.startswith("<") and header.endswith(">") else header
    if not _HEADER_PATH.fullmatch(path):
        raise ValueError(
            f"`{one_line(header)}` is not a header name: write path/to/header.hpp or <path/to/header.hpp> "
            "(letters, digits and `_ . + - /`)"
        )
    cpp = re.sub(r"\s+", " ", cpp)  # (a line break would end the // comment that names the type)
    cpp = re.sub(r"\s*(::|<|>|,)\s*", lambda m: m.group(1) + (" " if m.group(1) == "," else ""), cpp)
    return UserType(canonical, cpp, header)


def load(declarations: Sequence[str] = ()) -> tuple[UserType, ...]:
    """The `--type` declarations; UserError (one line per bad declaration, at `--type`)."""
    out: dict[str, UserType] = {}
    problems: list[Diagnostic] = []
    for text in declarations:
        try:
            t = parse(text)
        except ValueError as e:
            problems.append(Diagnostic(Loc("--type", 1, 1), str(e)))
            continue
        if t.name in out and out[t.name] != t:
            other = out[t.name]
            problems.append(
                Diagnostic(
                    Loc("--type", 1, 1),
                    f"type `{t.name}` is declared twice, as "
                    f"{other.cpp_type}@{other.header} and as "
                    f"{t.cpp_type}@{t.header}",
                )
            )
            continue
        out[t.name] = t
    if problems:
        raise UserError(problems)
    return tuple(out.values())


def apply(mission: Mission, types: Sequence[UserType]) -> Mission:
    """The mission with `types` declared (mission.user_types)."""
    if not types:
        return mission
    return dataclasses.replace(mission, user_types=tuple(types))


def unknown_type_warnings(mission: Mission) -> tuple[Diagnostic, ...]:
    """One warning per port type of the mission's leaves that is neither built in nor declared
    with `--type`, at the first port declaring it (models in declaration order): every command
    loads such ports, as BehaviorTree.CPP does, and holds their values as text (what the
    interpreter's scripted leaves need); in compiled code robot code then reads and writes
    text where BehaviorTree.CPP would hold the C++ type, so `validate` and `compile` say so and
    what to do (docs/types.md)."""
    declared = {t.name for t in mission.user_types}
    out: dict[str, Diagnostic] = {}
    for model in mission.used_user_models():
        for port in model.ports:
            name = port.type
            if not values.is_opaque_type(name) or name in declared or name in out:
                continue
            loc = port.loc or model.loc or Loc(mission.path, 1, 1)
            out[name] = Diagnostic(
                loc,
                f"port type `{name}` (port `{port.name}` of `{model.id}`) is not built in and no --type declares "
                f"it: its values are text here (robot code reads and writes std::string_view), a {name} in "
                f"BehaviorTree.CPP; to compile it as that C++ type, declare it: --type {name}=CPP_TYPE@HEADER",
                "warning",
            )
    return tuple(out.values())
