"""tests/conformance/typed-writes/: typed writes (Blackboard::set<T>: a LoopInt, LoopDouble,
LoopBool or LoopString `value`) into an entry whose type changes at run time, after it held a
number, a string or nothing, and what scripts, SetBlackboard literals and later typed writes do
to the entry once a typed write gave it a type; and (`copy_int_into_missing_*`) a SetBlackboard
copy of an int entry a port declared into such an entry an UnsetBlackboard removed. Recorded on
the real 4.6.2 and 4.10.0 (traces cut short where the library threw), through both engines
(issue 44).

Where the library throws "once declared, the type of a port shall not change" it first prints
its blackboard on stdout (Blackboard::debugMessage: one `key (type)` line per entry, in the
order of an unordered_map), which neither engine prints: those lines are left out of the
comparison, everything before them is compared byte for byte.

KNOWN: recordings neither engine follows yet, each a strict expected failure with its reason."""

import os
import re
import subprocess

import pytest

import release_cases as rc
from btgen import pipeline
from btgen.ir.lower import lower
from conftest import ROOT

HERE = os.path.join(ROOT, "tests", "conformance", "typed-writes")
_ONCE_DECLARED = "once declared, the type of a port shall not change"
_DUMP_LINE = re.compile(r'[^\s"]+ \([^()\n]*\)\n')
# 4.10.0: a script's `n := 5` leaves an int64 in the entry a port declared int, and a copy
# into a missing entry creates it typed int and throws on that value; the interpreter keeps
# no C++ type of a value (`n := '5'`, through the converter, copies; tests/python probes)
_SCRIPT_HELD_410 = (
    "4.10.0 throws: the copy creates the missing entry with the source's type, int, and the "
    "source holds the int64 a script stored; both engines copy"
)
KNOWN = {(f"copy_int_into_missing_after_{held}", "4.10.0"): _SCRIPT_HELD_410 for held in ("none", "num", "text")}


def _expected(stem: str, version: str) -> tuple[str, bool]:
    """The library's trace without the blackboard it prints before an "once declared" throw."""
    trace, failed = rc.expected(HERE, stem, version)
    error = os.path.join(HERE, version, stem + ".error")
    if failed:
        with open(error, encoding="utf-8") as f:
            if _ONCE_DECLARED in f.read():
                lines = trace.splitlines(keepends=True)
                while lines and _DUMP_LINE.fullmatch(lines[-1]):
                    lines.pop()
                trace = "".join(lines)
    return trace, failed


def _cases():
    out = []
    for stem, version in rc.recorded(HERE):
        why = KNOWN.get((stem, version))
        marks = [pytest.mark.xfail(strict=True, reason=why)] if why is not None else []
        out.append(pytest.param(stem, version, marks=marks, id=f"{stem}-{version}"))
    return out


def test_every_case_is_recorded_on_both_releases():
    assert len(rc.stems(HERE)) >= 30
    assert len(rc.recorded(HERE)) == 2 * len(rc.stems(HERE))
    for stem in rc.stems(HERE):
        with open(os.path.join(HERE, stem + ".xml"), encoding="utf-8") as f:
            assert f.read().startswith("<!--"), f"{stem}: say what it shows"


def test_the_dump_is_only_left_out_where_the_library_printed_it():
    """The lines left out are the library's blackboard, after the last node line: six of the
    families' recordings throw so, and nothing else is cut."""
    cut = 0
    for stem, version in rc.recorded(HERE):
        trace, _ = rc.expected(HERE, stem, version)
        kept, _ = _expected(stem, version)
        assert trace.startswith(kept)
        if kept != trace:
            cut += 1
            assert all(_DUMP_LINE.fullmatch(line) for line in trace[len(kept) :].splitlines(keepends=True))
    # loop_bool, loop_int_then_double, loop_string_then_int; 4.10.0: loop_int_then_bool, copy_int_into_missing
    assert cut == 6 + 6 + 6 + 3 + 3


@pytest.mark.parametrize("stem,version", _cases())
def test_interpreter(stem, version):
    trace, failed, _ = rc.interp(HERE, stem, version)
    assert (trace, failed) == _expected(stem, version)


@pytest.fixture(scope="module")
def batches(tmp_path_factory):
    return rc.Batches(HERE, tmp_path_factory.mktemp("typed_writes")).build()


@pytest.mark.parametrize("stem,version", _cases())
def test_compiled_executor(stem, version, batches):
    """Every mission compiles (none is refused) and prints the library's trace, failing where
    it failed with the interpreter's message."""
    lower(pipeline.load(os.path.join(HERE, stem + ".xml"), pipeline.CompileOptions(btcpp=version)))
    got = batches.run(stem, version)
    assert got is not None
    assert got.rc in (0, 1), got.stderr
    assert (got.stdout, got.rc == 1) == _expected(stem, version)
    if got.rc == 1:
        _, _, message = rc.interp(HERE, stem, version)
        assert message and message in got.stderr, (message, got.stderr)


# ---------------------------------------------------------------- Blackboard::set<T>, one table
# What a typed write (a Loop's `value`, a user node's output port) does to an entry of changing
# type, whatever it held: the interpreter's Blackboard.set against btgen::port::write of a Dyn
# slot, case by case (the recordings above reach a part of it through Loops; user nodes' ports,
# which no scenario writes, go through the same function).
_STATES = {  # name: (declared type, value); None: no entry
    "missing": None,
    "untyped_empty": ("any", None),
    "untyped_3": ("any", 3),
    "untyped_2.5": ("any", 2.5),
    "untyped_abc": ("any", "abc"),
    "int_1": ("int", 1),
    "double_1.5": ("double", 1.5),
    "bool_true": ("bool", True),
    "string_x": ("string", "x"),
}
_WRITES = (("int", 7), ("double", 2.0), ("double", 2.5), ("bool", False), ("string", "8"), ("string", "x"))
_CXX_TYPE = {"int": "std::int32_t", "double": "double", "bool": "bool", "string": "std::string_view"}
_TAG = {"any": "kNone", "int": "kInt", "double": "kDouble", "bool": "kBool", "string": "kString"}


def _cxx_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return f'std::string_view("{v}")'
    if isinstance(v, float):
        return repr(v)
    return f"std::int32_t{{{v}}}"


def _interp_write(state, t: str, value, version: str = "4.6.2") -> str:
    from btgen.lang import values
    from btgen.lang.blackboard import Blackboard, BlackboardError
    from btgen.lang.versions import semantics

    bb = Blackboard(false_into_int_unsafe=semantics(version).false_into_int_unsafe)
    if state is not None:
        bb.create_entry("v", state[0]).value = state[1]
    try:
        entry = bb.set("v", value, t)
    except BlackboardError as e:
        return f"error {e.message}"
    return f"ok {entry.type_name} {values.describe(entry.value)}"


def test_typed_writes_agree_with_the_interpreter(tmp_path):
    """Both releases in one program (built with ASan and UBSan): each line the state, the write
    and what followed, `ok TYPE VALUE` or `error MESSAGE`."""
    lines, expected = [], []
    for version in rc.VERSIONS:
        unsafe = "true" if version != "4.6.2" else "false"
        for name, state in _STATES.items():
            for t, value in _WRITES:
                what = f"{version} {name} <- {t} {value!r}"
                expected.append(f"{what}: {_interp_write(state, t, value, version)}")
                setup = ""
                if state is not None:
                    decl, held = state
                    setup = "s.exists = true;\n"
                    if decl == "string":
                        setup += "s.value.typed_string = true; s.entry_type = btgen::EntryType::kTyped;\n"
                    elif decl != "any":
                        setup += (
                            f"s.value.typed = btgen::DynTag::{_TAG[decl]}; s.entry_type = btgen::EntryType::kTyped;\n"
                        )
                    if held is not None:
                        ref = {bool: "of_bool", int: "of_int", float: "of_double", str: "of_string"}[type(held)]
                        lit = _cxx_value(held).replace("std::int32_t", "std::int64_t")
                        setup += f"(void)s.value.set(btgen::dyn::{ref}({lit})); s.has_value = true;\n"
                lines.append(
                    "{\nSlot s;\n" + setup + f'std::printf("%s: ", "{what}");\n'
                    f"btgen::dyn::Msg m;\n"
                    f"if (btgen::port::write<false, {unsafe}>(s, btgen::Declared::kAny, "
                    f'{_cxx_value(value)}, "v", m)) report(s);\n'
                    'else std::printf("error %.*s\\n", static_cast<int>(m.view().size()), m.view().data());\n}'
                )
    source = (
        '#include <cstdio>\n#include <string_view>\n#include "btgen/port.hpp"\n'
        "using Slot = btgen::Slot<btgen::Dyn<16>>;\n"
        "static void report(const Slot& s) {\n"
        "  const btgen::DynTag t = btgen::dyn::declared(s);\n"
        '  const char* type = t == btgen::DynTag::kNone ? "any" : t == btgen::DynTag::kString ? "string"\n'
        '      : t == btgen::DynTag::kInt ? "int" : t == btgen::DynTag::kDouble ? "double" : "bool";\n'
        "  btgen::dyn::Msg m;\n  btgen::dyn::add_value(m, btgen::dyn::ref(s));\n"
        '  std::printf("ok %s %.*s\\n", type, static_cast<int>(m.view().size()), m.view().data());\n}\n'
        "int main() {\n" + "\n".join(lines) + "\nreturn 0;\n}\n"
    )
    src = tmp_path / "writes.cpp"
    src.write_text(source, encoding="utf-8")
    exe = tmp_path / "writes"
    include = os.path.join(ROOT, "runtime", "include")
    flags = ["-std=c++17", "-O1", "-Wall", "-Wextra", "-Wpedantic", "-Werror", f"-I{include}"]
    sanitize = ["-fsanitize=address,undefined", "-fno-sanitize-recover=all"]
    subprocess.run(["g++", *flags, *sanitize, str(src), "-o", str(exe)], check=True, capture_output=True)
    got = subprocess.run([str(exe)], check=True, capture_output=True, text=True).stdout.splitlines()
    assert got == expected
    # the table holds each outcome: a new type, a conversion, a number that fits, each refusal
    joined = "\n".join(expected)
    for outcome in (
        "ok int 7",
        "ok double 2.0",
        "is declared as int; it cannot be written with a double",
        "cannot write 'x' to `v` (int)",
        "is declared as string; it cannot be written with a int",
        "ok string '8'",
        "4.6.2 int_1 <- bool False: ok int 0",
        "4.10.0 int_1 <- bool False: error blackboard entry `v` is declared as int; it cannot be written with a bool",
    ):
        assert outcome in joined, outcome
