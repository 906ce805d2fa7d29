"""User port types: what BehaviorTree.CPP's ``convertFromString<T>`` specialisations give a team.

A port or entry type that TreeNodesModel names and that is not built in (``Pose2D``,
``geometry_msgs::msg::PoseStamped``, ...) is text by default. ``btgen compile --type
NAME=CPP_TYPE@HEADER`` maps it to a C++ type instead:

- NAME is the type exactly as the port's ``type=`` attribute writes it (blanks around
  ``<>,:*&`` do not matter, as for built-in type names);
- CPP_TYPE is the C++ type (``nav::Pose2D``, ``std::array<double, 3>``);
- HEADER declares it and its conversion; the generated header has ``#include "HEADER"``
  (``@<HEADER>`` gives ``#include <HEADER>``).

Entries of that type hold the value itself in the static blackboard (the generated code
static_asserts that the type is trivially copyable), leaves get typed accessors
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

from btgen.diagnostics import Diagnostic, Loc, UserError
from btgen.lang import values
from btgen.lang.model import Mission

_IDENT = r"[A-Za-z_][A-Za-z0-9_]*"
_FUNDAMENTAL = ("int", "long", "short", "char", "double", "float", "bool", "signed", "unsigned")
_TOKEN = re.compile(rf"\s*(::|{_IDENT}|[0-9]+|[<>,*&])")


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
    def kind(self) -> str:
        return kind_of(self.name)


def kind_of(name: str) -> str:
    """The data-side kind of the entries of a user type (blanks around `<>,:*&` do not matter)."""
    return f"user:{values._compact(name)}"


def _cpp_type_problem(text: str) -> str:
    """Why `text` is not a C++ type spelling btgen accepts ("" when it is): a qualified name,
    optionally with template arguments (types or integers), `*` and `&` excluded."""
    tokens: list[str] = []
    pos = 0
    text = text.strip()
    while pos < len(text):
        m = _TOKEN.match(text, pos)
        if not m:
            return f"`{text[pos:].strip()[:1]}` cannot appear in a C++ type name here"
        tokens.append(m.group(1))
        pos = m.end()
    if any(t in ("*", "&") for t in tokens):
        return "pointers and references cannot live in the blackboard by value"
    from btgen.backend_cpp.naming import CPP_KEYWORDS

    depth = 0
    expect_name = True  # after `::`, `<`, `,` or at the start
    prev = ""
    for _i, t in enumerate(tokens):
        if t == "::":
            if prev == "::" or prev[:1].isdigit():
                return "`::` must separate names"
            expect_name = True
        elif t == "<":
            if not re.fullmatch(_IDENT, prev):
                return "`<` must follow a template name"
            depth += 1
            expect_name = True
        elif t == ">":
            if depth == 0 or expect_name:
                return "unbalanced `<` and `>`"
            depth -= 1
            expect_name = False
        elif t == ",":
            if depth == 0 or expect_name:
                return "`,` outside template arguments"
            expect_name = True
        elif t[0].isdigit():
            if depth == 0 or not expect_name or prev == "::":
                return f"`{t}` is not a type"
            expect_name = False
        else:
            if not expect_name and t not in ("int", "long", "short", "char", "double", "signed", "unsigned"):
                return f"`{t}` follows another name without `::`"
            if t in CPP_KEYWORDS and t not in (
                "int",
                "long",
                "short",
                "char",
                "double",
                "float",
                "bool",
                "signed",
                "unsigned",
            ):
                return f"`{t}` is a C++ keyword"
            expect_name = False
        prev = t
    if not tokens or depth != 0 or expect_name:
        return "it is incomplete"
    return ""


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
    if (
        header.startswith("<") != header.endswith(">")
        or any(c in '"\\' or ord(c) < 32 for c in header)
        or (header.startswith("<") and len(header) < 3)
    ):
        raise ValueError(f"`{header}` is not a header name: write path/to/header.hpp or <path/to/header.hpp>")
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
