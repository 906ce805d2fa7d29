"""Names of generated files and C++ entities, and C++ literal spelling.

Pure functions, registered as Jinja2 filters by emit.py and unit-tested in
tests/python/test_compiler.py. Templates never build a name themselves.
"""

from __future__ import annotations

import re
import textwrap
from collections.abc import Iterable
from dataclasses import dataclass, fields, replace
from types import MappingProxyType
from typing import Callable, Optional, Union

from btgen.backend_cpp.cpp_reserved import GLOBALS, MACROS
from btgen.diagnostics import one_line
from btgen.ir.data.records import DataIR, PortIR, ScriptSlot, SlotIR
from btgen.ir.lower import LeafModel, Program

# C++17 keywords and alternative tokens, plus names the generated code uses.
CPP_KEYWORDS = frozenset(
    """
alignas alignof and and_eq asm auto bitand bitor bool break case catch char char8_t char16_t char32_t
class compl concept const consteval constexpr constinit const_cast continue co_await co_return co_yield
decltype default delete do double dynamic_cast else enum explicit export extern false float for friend
goto if inline int long mutable namespace new noexcept not not_eq nullptr operator or or_eq private
protected public register reinterpret_cast requires return short signed sizeof static static_assert
static_cast struct switch template this thread_local throw true try typedef typeid typename union
unsigned using virtual void volatile wchar_t while xor xor_eq
""".split()
)

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
    return cpp_identifier(name or "Mission", kind="class")


# Macros beyond the standard headers' (cpp_reserved.MACROS) that a translation unit holding
# generated code may see: those a build defines (`NDEBUG` in every CMake Release build, the
# drivers' `BTGEN_MISSION_HEADER`), the runtime's own (`BTGEN_STRAIGHT_LINE_BUDGET`, include
# guards), and ZeroMQ's, which the Groot2 monitor includes beside the mission header. A
# mission name equal to one would be replaced by the preprocessor wherever it is spelled.
BUILD_MACROS = frozenset({"NDEBUG", "EFSM", "EMTHREAD", "ENOCOMPATPROTO", "ETERM"})
MACRO_PREFIXES = ("BTGEN_", "ZMQ_", "CPPZMQ_")


def is_macro(ident: str) -> bool:
    """True when a translation unit of generated code may see a macro named `ident`."""
    return ident in MACROS or ident in BUILD_MACROS or ident.startswith(MACRO_PREFIXES)


# What a mission name may not become, by the scope the generated code declares it in. Every
# scope also excludes CPP_KEYWORDS and the standard headers' MACROS (cpp_reserved.py, read from
# the compilers by scripts/update_cpp_reserved.py).
#
# Namespaces the generated code names unqualified where mission names are declared (a leaf
# class `std` in namespace `leaf`, a port `detail`, an entry `btgen` would hide them).
QUALIFIERS = frozenset({"std", "btgen", "detail", "leaf"})
# Members of every generated leaf class and the names its accessors use unqualified.
LEAF_MEMBERS = frozenset(
    {
        "kId",
        "kKind",
        "kModel",
        "node",
        "blackboard",
        "bb_",
        "err_",
        "node_",
        "bb",
        "n",
        "err",
        "e",
        "value",
        "T",
        # the members custom Control and Decorator classes add
        "fail",
        "sync_result",
        "children_count",
        "tick_child",
        "halt_child",
        "halt_children",
        "reset_child_status",
        "child_status",
        "status",
        "set_status",
        "now_ms",
        "name",
        "uid",
        "children",
        # the scenario runners' setter of a queue port by name (btgen/user_node.hpp), and the
        # name the setters of queue ports (set_queue_port) and their getters' views leave visible
        "set_queue_port",
        "queue_port",
        # the base classes (btgen/user_node.hpp), named unqualified in each leaf class
        "ModelBase",
        "ControlModelBase",
        "ops_",
    }
)
# Members of btgen::Slot, which the generated code reads beside the entries' members.
SLOT_MEMBERS = frozenset({"value", "seq", "exists", "has_value"})
# The names the mission class template and its scope use: its base and template parameters.
CLASS_NAMES = frozenset({"Engine", "Leaves", "Clock", "Observer", "Spec", "Blackboard"})
# Members the generator adds beside mission names: a leaf class's `scratch<k>_` number texts,
# the blackboard's `loop_<node>` literal queues, `loopq_<node>` queues converted from a string
# entry (4.9.1) and `ulit<k>_` literals of user port types.
_GENERATED = {
    "port": re.compile(r"scratch[0-9]+_"),
    "entry": re.compile(r"loopq?_[0-9]+|ulit[0-9]+_"),
}
# `kind` -> (prefix for names that cannot start an identifier, names that scope reserves).
KINDS: dict[str, tuple[str, frozenset]] = {
    "model": ("Leaf", QUALIFIERS | LEAF_MEMBERS),
    "port": ("port", QUALIFIERS | LEAF_MEMBERS),
    "entry": ("e", QUALIFIERS | SLOT_MEMBERS),
    "class": ("Mission", QUALIFIERS | CLASS_NAMES),
    # Global scope: the C library's functions, objects and types, and `main`.
    "namespace": ("mission", QUALIFIERS | GLOBALS | {"main"}),
    "plain": ("n", frozenset()),
}

Reserved = Union[Iterable[str], Callable[[str], bool]]


def is_reserved(ident: str, kind: str = "plain", reserved: Optional[Reserved] = None) -> bool:
    """True when `ident` may not name a mission entity of `kind` (see KINDS)."""
    if ident in CPP_KEYWORDS or is_macro(ident) or ident in KINDS[kind][1]:
        return True
    pattern = _GENERATED.get(kind)
    if pattern is not None and pattern.fullmatch(ident):
        return True
    if reserved is None:
        return False
    return reserved(ident) if callable(reserved) else ident in reserved


def cpp_identifier(
    text: str, prefix: Optional[str] = None, kind: str = "plain", reserved: Optional[Reserved] = None
) -> str:
    """A valid C++ identifier close to `text` that cannot collide with a keyword, a standard
    macro, or what the generated code declares or uses in the scope of `kind` (KINDS).

    Invalid characters become `_`, runs of `_` collapse (a double underscore is reserved),
    a leading digit or underscore gets `prefix` (the kind's own by default), and a reserved
    result gets trailing `_` until it is free.
    """
    if prefix is None:
        prefix = KINDS[kind][0]
    ident = re.sub(r"[^A-Za-z0-9_]", "_", text)
    ident = re.sub(r"_+", "_", ident)
    if not ident or ident == "_":
        ident = prefix
    if ident[0].isdigit() or ident[0] == "_":
        ident = prefix + ("" if ident[0] == "_" else "_") + ident
    ident = re.sub(r"_+", "_", ident)
    if ident.startswith(MACRO_PREFIXES):  # (a trailing `_` cannot free a reserved prefix)
        ident = prefix + "_" + ident
    while is_reserved(ident, kind, reserved):
        # `NULL` -> `NULL_`; `x_` (reserved) -> `x_1`: never a double underscore.
        ident = ident + "1" if ident.endswith("_") else ident + "_"
    return ident


def unique_identifiers(
    names: Iterable[str], taken: Iterable[str] = (), prefix: Optional[str] = None, kind: str = "plain"
) -> tuple[str, ...]:
    """cpp_identifier of each name, with `_2`, `_3`, ... added where two would collide."""
    used = set(taken)
    out = []
    for name in names:
        ident = unique_identifier(name, used, prefix, kind)
        used.add(ident)
        out.append(ident)
    return tuple(out)


def unique_identifier(
    name: str,
    used: Union[set, Callable[[str], bool]],
    prefix: Optional[str] = None,
    kind: str = "plain",
    reserved: Optional[Reserved] = None,
) -> str:
    """cpp_identifier(name) not in `used` (a set or a predicate), with `_2`, `_3`, ... added."""
    taken = used if callable(used) else used.__contains__
    base = cpp_identifier(name, prefix, kind, reserved)
    ident, n = base, 1
    while taken(ident) or is_reserved(ident, kind, reserved):
        n += 1
        ident = f"{base}{n}" if base.endswith("_") else f"{base}_{n}"
    return ident


def model_identifiers(ids: Iterable[str]) -> tuple[str, ...]:
    """The classes of the leaf models in the generated `leaf` namespace."""
    return unique_identifiers(ids, kind="model")


def port_identifiers(ports: Iterable[str], model_class: str) -> tuple[str, ...]:
    """The accessors of a leaf class's ports: `p()` reads and `set_p()` writes, so no
    port may take another's getter or setter name, nor the class's own name."""
    used: set[str] = set()

    def taken(ident: str) -> bool:
        return (
            ident in used
            or "set_" + ident in used
            or ident == model_class
            or (ident.startswith("set_") and ident[4:] in used)
        )

    out = []
    for name in ports:
        ident = unique_identifier(name, taken, kind="port")
        used.add(ident)
        used.add("set_" + ident)
        out.append(ident)
    return tuple(out)


def entry_identifiers(names: Iterable[str]) -> tuple[str, ...]:
    """The members of the generated blackboard struct, one per entry."""
    return unique_identifiers(names, kind="entry")


# ---------------------------------------------------------------- the program's C++ names
# The IR names slots, ports and models by key and ID; these records add the C++ names the
# generated code gives them, and `name_program` gives them all at once.


@dataclass(frozen=True)
class CppSlot(SlotIR):
    member: str = ""  # its member of the generated Blackboard struct


@dataclass(frozen=True)
class CppPort(PortIR):
    name: str = ""  # the getter of the model class (the setter is set_<name>)
    scratch: str = ""  # the member its getter writes a number's text into ("" when it never does)


@dataclass(frozen=True)
class CppLeafModel(LeafModel):
    cpp_name: str = ""  # its class in the generated `leaf` namespace


# The `btgen::ScriptSlot` enumerators (runtime/include/btgen/blackboard.hpp).
SCRIPT_SLOT_ENUMERATORS = MappingProxyType(
    {
        ScriptSlot.FAILURE_IF: "kFailureIf",
        ScriptSlot.SUCCESS_IF: "kSuccessIf",
        ScriptSlot.SKIP_IF: "kSkipIf",
        ScriptSlot.WHILE: "kWhile",
        ScriptSlot.ON_SUCCESS: "kOnSuccess",
        ScriptSlot.ON_FAILURE: "kOnFailure",
        ScriptSlot.POST: "kPost",
        ScriptSlot.ON_HALTED: "kOnHalted",
        ScriptSlot.CODE: "kCode",
    }
)


def _with(record, cls, **names):
    return cls(**{f.name: getattr(record, f.name) for f in fields(record)}, **names)


def slot_members(slots: Iterable[SlotIR]) -> tuple[str, ...]:
    """The Blackboard struct's members, one per slot: the key, prefixed by the SubTree
    instance path outside the root blackboard."""
    return entry_identifiers(s.key if s.owner == "root" else f"{s.owner}_{s.key}" for s in slots)


def name_program(program: Program) -> Program:
    """`program` with every slot, port and leaf model carrying its C++ name (CppSlot,
    CppPort, CppLeafModel). Classes are named over every model the mission declares, so a
    model's class keeps its name whatever else is used."""
    classes = dict(zip(program.model_ids, model_identifiers(program.model_ids)))
    models = tuple(_with(m, CppLeafModel, cpp_name=classes[m.id]) for m in program.leaf_models)
    data = program.data
    if data is None:
        return replace(program, leaf_models=models)
    slots = tuple(_with(s, CppSlot, member=m) for s, m in zip(data.slots, slot_members(data.slots)))
    ports: dict[str, tuple[PortIR, ...]] = {}
    for model_id, model_ports in data.ports.items():
        getters = port_identifiers([p.port for p in model_ports], classes.get(model_id, ""))
        ports[model_id] = tuple(
            _with(p, CppPort, name=g, scratch=f"scratch{k}_" if p.needs_scratch else "")
            for k, (p, g) in enumerate(zip(model_ports, getters))
        )
    named: DataIR = replace(data, slots=slots, ports=ports)
    return replace(program, leaf_models=models, data=named)


def header_name(stem: str) -> str:
    return snake_case(stem) + ".hpp"


def source_name(stem: str) -> str:
    return snake_case(stem) + ".cpp"


# Names a mission's namespace must not take at global scope: `main` is the
# program's function (`namespace main` and `int main()` cannot coexist), `btgen`
# the runtime's namespace, the others the standard library's.
CLASHING_NAMESPACES = frozenset({"main", "btgen", "std", "posix"})
_NAMESPACE_PART_RE = re.compile(r"[A-Za-z_][A-Za-z0-9_]*", re.ASCII)
# Types the C++ headers (not the C ones GLOBALS is read from) declare at global scope.
GLOBAL_TYPES = frozenset({"nullptr_t", "max_align_t", "byte"})


def namespace_name(stem: str) -> str:
    """The mission's C++ namespace: its snake-case stem, made a valid identifier that names
    nothing else at global scope (`exit` -> `exit_`, `main` -> `main_`)."""
    return cpp_identifier(snake_case(stem), kind="namespace")


namespace_for_stem = namespace_name


def namespace_problem(ns: str) -> str:
    """Why `ns` cannot be a mission's namespace (`--namespace`), "" when it can.

    `a::b` (nested) is allowed; each part must be a C++ identifier (ASCII, no line break)
    that is not a keyword, a macro (is_macro), reserved (`_X...`, `__`) nor a namespace the
    generated code names unqualified inside it (QUALIFIERS: `robot::std` would hide `std`);
    the outermost part must not be one of CLASHING_NAMESPACES nor name something at global
    scope."""
    if not ns:
        return "the namespace is empty"
    parts = ns.split("::")
    for part in parts:
        if not _NAMESPACE_PART_RE.fullmatch(part):
            return (
                f"`{one_line(part)}` is not a C++ identifier (letters, digits and `_`, not starting with a digit)"
                if part
                else f"`{one_line(ns)}` has an empty part"
            )
        if part in CPP_KEYWORDS:
            return f"`{part}` is a C++ keyword"
        if part in MACROS:
            return f"`{part}` is a macro of the C++ standard library"
        if is_macro(part):
            return f"`{part}` is a macro of btgen's runtime or of a build (`NDEBUG`, `BTGEN_...`, `ZMQ_...`)"
        if "__" in part or part[0] == "_":
            return f"`{part}` is reserved in C++ (a leading `_` or a double underscore)"
    if parts[0] in (GLOBALS | GLOBAL_TYPES) and parts[0] not in CLASHING_NAMESPACES:
        return f"`{parts[0]}` names something of the C++ standard library at global scope; choose another name"
    if parts[0] in CLASHING_NAMESPACES:
        what = (
            "the program's main()"
            if parts[0] == "main"
            else ("btgen's runtime" if parts[0] == "btgen" else "the standard library")
        )
        return f"`{parts[0]}` clashes with {what}; choose another name"
    for part in parts[1:]:
        if part in ("std", "btgen"):
            return (
                f"`{part}` inside the mission's namespace would hide `::{part}`, which the generated "
                "code names there; choose another name"
            )
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
    return "BTGEN_GENERATED_" + namespace_name(stem).rstrip("_").upper() + "_HPP"


def cpp_comment_lines(text: str, width: int = 100) -> list[str]:
    """cpp_comment(text) wrapped at spaces into lines of at most `width` characters (a word
    longer than that stays whole)."""
    lines = textwrap.wrap(cpp_comment(text), width, break_long_words=False, break_on_hyphens=False)
    return [line.rstrip("\\ ") for line in lines] or [""]


def cpp_comment(text: str) -> str:
    """`text` made safe inside a // comment: one line (line breaks and other control or
    non-ASCII characters become `?`), no trailing backslash, and no `??` (the trigraph
    `??/` ends a // comment's line like a backslash; g++ -Wall warns of any trigraph)."""
    safe = "".join(ch if 0x20 <= ord(ch) < 0x7F else "?" for ch in text)
    safe = re.sub(r"\?(?=\?)", "?_", safe)
    return safe.rstrip("\\ ")
