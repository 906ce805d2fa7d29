"""Names of generated files and C++ entities, and C++ literal spelling.

Pure functions, registered as Jinja2 filters by emit.py and unit-tested in
tests/python/test_compiler.py. Templates never build a name themselves.
"""
from __future__ import annotations

import re
from typing import Iterable, Optional

# C++17 keywords and alternative tokens, plus names the generated code uses.
CPP_KEYWORDS = frozenset("""
alignas alignof and and_eq asm auto bitand bitor bool break case catch char char8_t char16_t char32_t
class compl concept const consteval constexpr constinit const_cast continue co_await co_return co_yield
decltype default delete do double dynamic_cast else enum explicit export extern false float for friend
goto if inline int long mutable namespace new noexcept not not_eq nullptr operator or or_eq private
protected public register reinterpret_cast requires return short signed sizeof static static_assert
static_cast struct switch template this thread_local throw true try typedef typeid typename union
unsigned using virtual void volatile wchar_t while xor xor_eq
""".split())

_WORD_RE = re.compile(r"[A-Z]+(?=[A-Z][a-z0-9])|[A-Z]?[a-z0-9]+|[A-Z]+")


def _words(text: str) -> list[str]:
    """Split a name into lower-case words at case changes and non-alphanumerics."""
    words: list[str] = []
    for chunk in re.split(r"[^A-Za-z0-9]+", text):
        words.extend(w.lower() for w in _WORD_RE.findall(chunk))
    return words


def snake_case(stem: str) -> str:
    """`LabTour` -> `lab_tour`, `HTTPServer2` -> `http_server2`, `lab-tour v2` -> `lab_tour_v2`.

    Used for generated file names; never empty.
    """
    words = _words(stem)
    return "_".join(words) if words else "mission"


def pascal_case(stem: str) -> str:
    """`lab_tour` / `LabTour` -> `LabTour`: the mission's class name."""
    name = "".join(w[:1].upper() + w[1:] for w in _words(stem))
    return cpp_identifier(name or "Mission", prefix="Mission")


def cpp_identifier(text: str, prefix: str = "n") -> str:
    """A valid, non-reserved C++ identifier close to `text`.

    Invalid characters become `_`, runs of `_` collapse (a double underscore
    is reserved), a leading digit or underscore gets `prefix`, keywords get a
    trailing `_`.
    """
    ident = re.sub(r"[^A-Za-z0-9_]", "_", text)
    ident = re.sub(r"_+", "_", ident)
    if not ident or ident == "_":
        ident = prefix
    if ident[0].isdigit() or ident[0] == "_":
        ident = prefix + ("" if ident[0] == "_" else "_") + ident
    ident = re.sub(r"_+", "_", ident)
    if ident in CPP_KEYWORDS:
        ident += "_"
    return ident


def unique_identifiers(names: Iterable[str], taken: Iterable[str] = (), prefix: str = "n") -> tuple[str, ...]:
    """cpp_identifier of each name, with `_2`, `_3`, ... added where two would collide."""
    used = set(taken)
    out = []
    for name in names:
        base = cpp_identifier(name, prefix)
        ident, n = base, 1
        while ident in used:
            n += 1
            ident = f"{base}_{n}"
        used.add(ident)
        out.append(ident)
    return tuple(out)


def header_name(stem: str) -> str:
    return snake_case(stem) + ".hpp"


def source_name(stem: str) -> str:
    return snake_case(stem) + ".cpp"


# Names a mission's namespace must not take at global scope: `main` is the
# program's function (`namespace main` and `int main()` cannot coexist), `btgen`
# the runtime's namespace, the others the standard library's.
CLASHING_NAMESPACES = frozenset({"main", "btgen", "std", "posix"})
_NAMESPACE_PART_RE = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")


def namespace_name(stem: str) -> str:
    """The mission's C++ namespace: its snake-case stem, made a valid identifier
    that clashes with nothing (`main.xml` -> `main_mission`)."""
    ns = cpp_identifier(snake_case(stem), prefix="mission")
    if ns.rstrip("_") in CLASHING_NAMESPACES or ns in CLASHING_NAMESPACES:
        ns = ns.rstrip("_") + "_mission"
    return ns


def namespace_problem(ns: str) -> str:
    """Why `ns` cannot be a mission's namespace (`--namespace`), "" when it can.

    `a::b` (nested) is allowed; each part must be a C++ identifier that is not a
    keyword nor reserved (`_X...`, `__`), and the outermost part must not be one
    of CLASHING_NAMESPACES."""
    if not ns:
        return "the namespace is empty"
    parts = ns.split("::")
    for part in parts:
        if not _NAMESPACE_PART_RE.match(part):
            return (f"`{part}` is not a C++ identifier (letters, digits and `_`, not starting with a digit)"
                    if part else f"`{ns}` has an empty part")
        if part in CPP_KEYWORDS:
            return f"`{part}` is a C++ keyword"
        if "__" in part or part[0] == "_":
            return f"`{part}` is reserved in C++ (a leading `_` or a double underscore)"
    if parts[0] in CLASHING_NAMESPACES:
        what = "the program's main()" if parts[0] == "main" else (
            "btgen's runtime" if parts[0] == "btgen" else "the standard library")
        return f"`{parts[0]}` clashes with {what}; choose another name"
    return ""


def mission_namespace(stem: str, requested: Optional[str] = None) -> str:
    """The namespace of the generated code: `requested` (`--namespace`) when given,
    else derived from the file name. ValueError when `requested` is unusable."""
    if requested is None:
        return namespace_name(stem)
    problem = namespace_problem(requested)
    if problem:
        raise ValueError(problem)
    return requested


def include_guard(stem: str) -> str:
    return "BTGEN_GENERATED_" + cpp_identifier(snake_case(stem), prefix="mission").upper() + "_HPP"


def cpp_string(text: str) -> str:
    """A C++ narrow string literal holding the UTF-8 bytes of `text`.

    Printable ASCII is kept; everything else is an octal escape, so the
    literal is pure ASCII, and no `?` sequences can form trigraphs.
    """
    out = ['"']
    for b in text.encode("utf-8"):
        c = chr(b)
        if c == '"' or c == "\\":
            out.append("\\" + c)
        elif c == "?":
            out.append("\\?")
        elif 0x20 <= b < 0x7F:
            out.append(c)
        else:
            out.append(f"\\{b:03o}")
    out.append('"')
    return "".join(out)


def cpp_comment(text: str) -> str:
    """`text` made safe inside a // comment: one line, no trailing backslash, ASCII."""
    safe = "".join(ch if 0x20 <= ord(ch) < 0x7F else "?" for ch in text)
    return safe.rstrip("\\ ")
