"""Scripts compiled to C++ (backend_cpp/script_cpp/) and the runtime conversions they use.

Three layers: the static kinds of script expressions; the text of generated
code; and differential runs: the C++ conversions (runtime/include/btgen/value.hpp)
against values.py on a corpus of inputs, and compiled scripts against the
interpreter on missions whose conditions check every value a script computes.
"""

import math
import os
import random
import shutil
import struct
import subprocess

import pytest

import cppbuild
from btgen.backend_cpp import literals
from btgen.backend_cpp import script_cpp as scpp
from btgen.frontend.loader import load_mission
from btgen.interp.controls import switch_equal
from btgen.interp.engine import trace_text
from btgen.interp.scenario import load_scenario
from btgen.ir import kinds
from btgen.ir.script_types import SlotType, type_script
from btgen.lang import script as sc
from btgen.lang import values
from btgen.tools.cppengine import build_cpp


def _typing_views(views):
    """The slots as the typing pass sees them (no user port types here)."""
    return [SlotType(v.key, v.kind, v.declared, v.capacity, v.origin, kinds.kind_of_type(v.declared)) for v in views]


KINDS = {"i": "int", "d": "double", "s": "string", "b": "bool", "q": kinds.queue_kind("int"), "n": "none"}


def kind(code, **names):
    expr = sc.parse_script(code).statements[-1]
    return kinds.expr_kind(expr, lambda name: KINDS[names[name]] if name in names else None)


# ------------------------------------------------------------------ kinds
@pytest.mark.parametrize(
    "code,names,expected",
    [
        ("1", {}, "int"),
        ("1.5", {}, "double"),
        ("'a'", {}, "string"),
        ("true", {}, "int"),
        ("a + b", {"a": "i", "b": "i"}, "double"),  # 4.6.2 arithmetic is in doubles
        ("a + b", {"a": "s", "b": "s"}, "string"),
        ("a .. b", {"a": "s", "b": "i"}, "string"),
        ("a .. b", {"a": "i", "b": "d"}, "none"),  # 4.6.2: `..` of two numbers gives no value
        ("a == b", {"a": "s", "b": "i"}, "double"),
        ("!a", {"a": "b"}, "double"),
        ("a & 3", {"a": "d"}, "double"),
        ("c ? a : b", {"c": "s", "a": "s", "b": "s"}, "string"),
        ("x := a", {"x": "d", "a": "i"}, "double"),  # an assignment gives the entry's value
        ("a + b", {"a": "i"}, None),  # b unknown yet
    ],
)
def test_expression_kinds(code, names, expected):
    assert kind(code, **names) == expected


@pytest.mark.parametrize(
    "code,names,message",
    [
        ("a + 1", {"a": "q"}, "`+` cannot be applied to a queue<int> and an integer"),
        ("a < b", {"a": "q", "b": "i"}, "cannot compare a queue<int> with an integer using `<`"),
    ],
)
def test_expressions_that_always_fail(code, names, message):
    with pytest.raises(kinds.ScriptTypeError) as e:
        kind(code, **names)
    assert e.value.message == message


@pytest.mark.parametrize(
    "code,names,expected",
    [
        # 4.6.2 fails whenever these run; they compile to code that reports the interpreter's error then
        ("-a", {"a": "s"}, "double"),
        ("a - b", {"a": "s", "b": "s"}, "double"),
        ("a && 1", {"a": "s"}, "double"),
        ("a + 1", {"a": "n"}, "dyn"),
        ("x := 1 .. 2", {"x": "s"}, "string"),
        # `?:` branches of two kinds give a value whose type is known at run time only
        ("c ? 1 : 'x'", {"c": "i"}, "dyn"),
        ("c ? 1 : 2.5", {"c": "i"}, "dyn"),
    ],
)
def test_expressions_that_fail_or_change_type_at_run_time(code, names, expected):
    assert kind(code, **names) == expected


def test_cpp_literals_are_exact():
    for v in (0.1, 1e-300, 5e-324, 1.7976931348623157e308, -2.5, 3.0, 1e22, 123456789.123456789):
        text = literals.cpp_double(v)
        assert float(text.strip("()")) == v and ("." in text or "e" in text)
        assert not text.startswith("-")
    assert literals.cpp_double(math.inf) == "std::numeric_limits<double>::infinity()"
    assert literals.cpp_int64(-(2**63)) == "std::int64_t{-9223372036854775807 - 1}"
    assert literals.cpp_view('a"é') == 'std::string_view("a\\"\\303\\251", 4)'


def _compile(code, slots, condition=False):
    views = [scpp.SlotView(f"bb.{k}", k, kd, "any", 16, missing) for k, (kd, missing) in slots.items()]
    names = {k: i for i, k in enumerate(slots)}
    ctx = scpp.ScriptContext(views, names, lambda off: f"W[{off}]", "P: ")
    return scpp.compile_script(type_script(sc.parse_script(code), _typing_views(views), names, condition), ctx)


def test_generated_code_for_an_assignment():
    body = _compile("x := y + 1", {"x": ("double", True), "y": ("int", False)})
    assert body == [
        "  bb.x.exists = true;",
        "  [[maybe_unused]] const bool t1h = bb.y.has_value;",
        "  [[maybe_unused]] const std::int64_t t2 = bb.y.value;",
        '  if (!t1h) return err.fail(n, W[7], "P: the left operand of `+` has no value");',
        "  double t4 = 0.0;",
        "  if (btgen::script::num_v<Semantics::int_to_double_53_bits>(t2, t4) != btgen::Errc::kOk) "
        'return err.fail(n, W[7], "P: left operand of `+`: '
        'cannot convert the integer to double: precision would be lost");',
        "  const double t3 = t4 + 1.0;",
        "  bb.x.value = t3;",
        "  bb.x.mark_written();",
        "  return 1;",
    ]


def test_comparison_chains_stop_at_the_first_false_pair():
    body = _compile("a < b < c", {"a": ("int", False), "b": ("int", False), "c": ("int", True)}, condition=True)
    text = "\n".join(body)
    assert text.count("do {") == 1 and text.count("break;") == 2
    # `c` is read only after `a < b` held
    assert text.index("if (!btgen::script::lt(") < text.index("if (!bb.c.exists)")


def test_a_string_read_again_after_it_is_assigned_is_copied():
    body = _compile("s := s .. 'x' .. s", {"s": ("string", False)})
    assert "btgen::FixedString<16> t2;" in body[1] and "(void)t2.assign(bb.s.value.view());" in body[2]


# ------------------------------------------------------------------ C++ conversions vs values.py
CONVERSIONS_CPP = r"""
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <string>
#include "btgen/script.hpp"
#include "btgen/value.hpp"

static void put(btgen::Errc e, const double& d) {
  if (e != btgen::Errc::kOk) { std::printf("err\n"); return; }
  std::uint64_t bits; std::memcpy(&bits, &d, 8);
  std::printf("%016" PRIx64 "\n", bits);
}

int main() {
  char line[4096];
  while (std::fgets(line, sizeof line, stdin)) {
    std::string s(line);
    if (!s.empty() && s.back() == '\n') s.pop_back();
    const std::string op = s.substr(0, s.find('\t'));
    const std::string arg = s.substr(s.find('\t') + 1);
    double d = 0.0;
    std::int64_t i = 0;
    if (op == "text_int") {
      std::printf("%s\n", std::string(btgen::NumberText(static_cast<std::int64_t>(std::stoll(arg))).view()).c_str());
    } else if (op == "text_double") {
      std::uint64_t bits = std::stoull(arg, nullptr, 16);
      std::memcpy(&d, &bits, 8);
      std::printf("%s\n", std::string(btgen::NumberText(d).view()).c_str());
    } else if (op == "from_chars") {
      put(btgen::parse_double_from_chars(arg, d), d);
    } else if (op == "stod") {
      put(btgen::parse_double_stod(arg, d), d);
    } else if (op == "int" || op == "unsigned") {
      const bool u = op == "unsigned";
      const btgen::Errc e = btgen::parse_integer(arg, u ? 0 : INT32_MIN, u ? UINT32_MAX : INT32_MAX, i);
      if (e != btgen::Errc::kOk) std::printf("err\n"); else std::printf("%" PRId64 "\n", i);
    } else if (op == "switch") {
      const std::string a = arg.substr(0, arg.find('\t')), b = arg.substr(arg.find('\t') + 1);
      std::printf("%d\n", btgen::switch_equal(a, b) ? 1 : 0);
    } else if (op == "cmp_text") {
      put(btgen::script::text_to_double(arg, d), d);
    }
  }
  return 0;
}
"""


@pytest.fixture(scope="module")
def conversions_exe(tmp_path_factory):
    if shutil.which(os.environ.get("CXX", "c++")) is None:
        pytest.skip("no C++ compiler")
    d = tmp_path_factory.mktemp("conv")
    src = d / "conv.cpp"
    src.write_text(CONVERSIONS_CPP)
    exe = d / "conv"
    return cppbuild.build([src], exe, opt="-O1", warnings=False, flags=["-Wall", "-Wextra", "-Werror"])


def _bits(x):
    return struct.pack("<d", x)[::-1].hex()


def _py(op, arg):
    try:
        if op == "text_int":
            return values.to_text(int(arg))
        if op == "text_double":
            return values.format_double(struct.unpack(">d", bytes.fromhex(arg))[0])
        if op == "from_chars":
            return _bits(values._from_chars_double(arg))
        if op == "stod":
            return _bits(values._stod(arg))
        if op in ("int", "unsigned"):
            return str(values.convert_from_string(op, arg))
        if op == "switch":
            a, b = arg.split("\t")
            return "1" if switch_equal(a, b) else "0"
        if op == "cmp_text":
            if arg in ("true", "false"):
                return _bits(1.0 if arg == "true" else 0.0)
            return _bits(values.to_double(arg))
    except values.ConversionError:
        return "err"
    raise AssertionError(op)


def _number_texts(rng):
    yield from [
        "0",
        "-0",
        "1",
        "-1",
        "2147483647",
        "2147483648",
        "-2147483648",
        "-2147483649",
        "4294967295",
        "4294967296",
        "9223372036854775807",
        "9223372036854775808",
        "12abc",
        "-",
        "+5",
        " 5",
        "",
        "007",
        "1.5",
        "1e3",
        ".5",
        "5.",
        "-.5",
        "1e",
        "1e+",
        "1e-999",
        "1e999",
        "-1e999",
        "inf",
        "-INF",
        "Infinity",
        "infinit",
        "nan",
        "-nan",
        "NaN(123)",
        "nan(",
        "0x1p3",
        "0X1.8P1",
        "0x",
        "0x.8",
        "  \t3.25xyz",
        "1.7976931348623157e308",
        "1.7976931348623159e308",
        "4.9e-324",
        "2.2250738585072014e-308",
        "2.2e-308",
        "1_000",
        "١",
        "1e5x",
        "--1",
        "0.000000000000000000000000000000000000001",
    ]
    for _ in range(300):
        kind = rng.randrange(4)
        if kind == 0:
            yield str(rng.randint(-(2**40), 2**40))
        elif kind == 1:
            yield repr(rng.uniform(-1e6, 1e6))
        elif kind == 2:
            yield f"{rng.uniform(-10, 10):.{rng.randint(0, 20)}e}"
        else:
            yield "".join(rng.choice("0123456789.-+eExXabfinINFpP ") for _ in range(rng.randint(1, 8)))


def _doubles(rng):
    yield from [
        0.0,
        -0.0,
        1.0,
        -1.0,
        0.5,
        2.5,
        1e-7,
        0.0078125,
        1.0000005,
        123456.7891235,
        1e300,
        -1e300,
        1.7976931348623157e308,
        5e-324,
        math.inf,
        -math.inf,
        math.nan,
        -math.nan,
        0.1,
        2**53,
        1e22,
    ]
    for _ in range(300):
        yield (
            struct.unpack("<d", struct.pack("<Q", rng.getrandbits(64)))[0]
            if rng.random() < 0.3
            else rng.uniform(-1e9, 1e9) * 10 ** rng.randint(-12, 12)
        )


def test_conversions_agree_with_values_py(conversions_exe):
    rng = random.Random(5)
    cases = []
    for text in _number_texts(rng):
        for op in ("from_chars", "stod", "int", "unsigned", "cmp_text"):
            cases.append((op, text))
    for x in _doubles(rng):
        cases.append(("text_double", struct.pack(">d", x).hex()))
    for v in [0, -1, 2**63 - 1, -(2**63), 42, -7] + [rng.randint(-(2**63), 2**63 - 1) for _ in range(50)]:
        cases.append(("text_int", str(v)))
    words = ["1", "01", "1.0", "1.00000001", "abc", "-0", "0", "2147483648", "1e2", "100", "inf", "x1", "", "1 "]
    for a in words:
        for b in words:
            cases.append(("switch", f"{a}\t{b}"))
    stdin = "".join(f"{op}\t{arg}\n" for op, arg in cases)
    out = (
        subprocess.run([str(conversions_exe)], input=stdin.encode("utf-8"), stdout=subprocess.PIPE, check=True)
        .stdout.decode("utf-8")
        .splitlines()
    )
    assert len(out) == len(cases)
    wrong = [(op, arg, got, _py(op, arg)) for (op, arg), got in zip(cases, out) if got != _py(op, arg)]
    assert wrong == []


# ------------------------------------------------------------------ compiled scripts vs the interpreter
# Each expression is evaluated after INIT; its value's text (std::to_string for numbers) is checked by a
# ScriptCondition against what the reference evaluator (script.py) computes, so a C++ value that differs
# fails the condition and the trace differs from the interpreter's.
INIT = "i := 7; j := -3; big := 9007199254740993; d := 2.5; z := 0.0; s := 'robot'; n := '42'; t := true"
EXPRESSIONS = [
    "i + j",
    "i - j * 2",
    "i / j",
    "i / 0",
    "-i / 0",
    "z / z",
    "d * d",
    "-d",
    "!i",
    "!z",
    "~j",
    "i & 3",
    "i | 8",
    "i ^ 5",
    "i > j",
    "i == 7.00000001",
    "d != 2.5000001",
    "i >= 7 && j < 0",
    "z || t",
    "i < j || d > 1",
    "1 < 2 < 3",
    "3 > 2 > 1",
    "s == 'robot'",
    "s < 'rocket'",
    "n == 42",
    "n > 41.5",
    "'true' == 1",
    "i > 5 ? 'big' : 'small'",
    "n ? 1 : 2",
    "s .. i",
    "i .. s",
    "d .. '/' .. z",
    "s .. (i / 3)",
    "s + '!'",
    "(i + 1) .. ''",
    "1e300 * 1e300 .. ''",
    "-(1e300 * 1e300) .. ''",
    "0.1 + 0.2",
    "(0.1 + 0.2) == 0.3",
    "i == 7 ? (d .. '') : s",
    "i += 1",
    "i -= 0.5 * 2",
    "d *= 4",
    "d /= 0",
    "s += '-x'",
    "t := !t",
]


def _expected_text(code):
    from btgen.lang.blackboard import Blackboard

    bb = Blackboard()
    sc.evaluate(sc.parse_script(INIT), bb)
    value = sc.evaluate(sc.parse_script(code), bb)
    return values.to_text(value)


def test_compiled_scripts_compute_what_the_interpreter_computes(tmp_path):
    rows = []
    for k, code in enumerate(EXPRESSIONS):
        expected = _expected_text(code)
        assert "'" not in expected
        esc = code.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;").replace('"', "&quot;")
        rows.append(
            f'<Script name="init{k}" code="{INIT}"/>'
            f'<Script name="eval{k}" code="r{k} := \'\' .. ({esc})"/>'
            f'<ScriptCondition name="check{k}" code="r{k} == \'{expected}\'"/>'
        )
    mission = tmp_path / "scripts.xml"
    mission.write_text(
        '<root BTCPP_format="4"><BehaviorTree ID="M"><Sequence>' + "".join(rows) + "</Sequence></BehaviorTree></root>\n"
    )
    scenario = tmp_path / "s.scenario"
    scenario.write_text("ticks 1\n")
    m = load_mission(str(mission))
    sc_, _ = load_scenario(str(scenario), m)
    expected = trace_text(m, sc_)
    assert expected.endswith("result SUCCESS\n")  # every check holds in the interpreter
    proc = subprocess.run([str(build_cpp(str(mission))), str(scenario)], capture_output=True, text=True, check=False)
    assert (proc.returncode, proc.stderr) == (0, "")
    assert proc.stdout == expected


# ------------------------------------------------------------------ the typing pass agrees with the writer
_DECLARED = {
    "int": ("any", "int", "unsigned", "bool"),
    "double": ("any", "double"),
    "string": ("any", "std::string", "Pose2D"),
    "status": ("NodeStatus",),
    kinds.queue_kind("int"): ("std::deque<int>",),
    "dyn": ("any",),
    "none": ("any",),
}
_LITERALS = ("0", "1", "7", "-2", "2.5", "1e300", "'a'", "'12'", "'x y'", "'true'", "'RUNNING'", "true", "''")
_OPS = ("+", "-", "*", "/", "..", "&", "|", "^", "&&", "||")


def _random_expr(rng, names, depth):
    if depth <= 0 or rng.random() < 0.3:
        return rng.choice(_LITERALS) if rng.random() < 0.5 else rng.choice(names)
    pick = rng.randrange(6)
    if pick == 0:
        return f"{rng.choice('-!~')}{_random_expr(rng, names, depth - 1)}"
    if pick == 1:
        return f"({_random_expr(rng, names, depth - 1)} {rng.choice(_OPS)} {_random_expr(rng, names, depth - 1)})"
    if pick == 2:
        op = rng.choice(("==", "!=", "<", ">=", "<="))
        return f"({_random_expr(rng, names, depth - 1)} {op} {_random_expr(rng, names, depth - 1)})"
    if pick == 3:
        parts = [_random_expr(rng, names, depth - 1) for _ in range(3)]
        return f"({parts[0]} ? {parts[1]} : {parts[2]})"
    op = rng.choice((":=", "=", "+=", "-=", "*=", "/="))
    return f"({rng.choice(names)} {op} {_random_expr(rng, names, depth - 1)})"


def test_the_cpp_writer_prints_every_typed_script():
    """Scripts are typed once (ir/script_types.py), which reports every type error; the writer
    (backend_cpp/script_cpp/) only prints from the typed tree. Over random scripts on entries of every
    kind and declared type, whatever the typing pass accepts is written without an error, and
    an expression of each kind of decision is written both ways (static and dynamic)."""
    rng = random.Random(20261124)
    checked = rejected = 0
    routes, dynamic = set(), set()
    for _ in range(3000):
        names = ["a", "b", "c"]
        views = []
        for k in names:
            kd = rng.choice(list(_DECLARED))
            views.append(
                scpp.SlotView(
                    f"bb.{k}", k, kd, rng.choice(_DECLARED[kd]), rng.choice((1, 4, 16)), rng.random() < 0.3, ""
                )
            )
        index = {k: i for i, k in enumerate(names)}
        code = "; ".join(_random_expr(rng, names, 3) for _ in range(rng.randint(1, 2)))
        try:
            script = sc.parse_script(code)
        except sc.ScriptSyntaxError:
            continue
        condition = rng.random() < 0.5
        checked += 1
        try:
            typed = type_script(script, _typing_views(views), index, condition)
        except kinds.ScriptTypeError:
            rejected += 1
            continue
        for stmt in script.statements:
            for node in sc.walk(stmt):
                t = typed.of(node)
                routes.add(t.route)
                dynamic.add((type(node).__name__, t.dynamic or any(t.links)))
        ctx = scpp.ScriptContext(views, index, lambda off: f"W[{off}]", "P: ")
        body = scpp.compile_script(typed, ctx)
        assert body and body[-1].lstrip().startswith("return"), code
    assert {"none", "dynamic", "compound", "same", "converted", "number_text", "number"} <= routes
    for kind_name in ("Unary", "Binary", "Compare", "Ternary"):
        assert {(kind_name, False), (kind_name, True)} <= dynamic, kind_name
    assert checked > 2000 and 100 < rejected < checked - 100, (checked, rejected)


def test_the_writer_applies_no_typing_rule():
    """backend_cpp/script_cpp/ takes of ir/kinds.py only its vocabulary (the kind names,
    bounds, descriptions), none of the rules: the typing pass applied them once."""
    import ast
    import inspect

    from btgen.backend_cpp.script_cpp import compiler, stores, writer

    for module in (scpp, compiler, stores, writer):
        source = inspect.getsource(module)
        taken = {
            a.name
            for n in ast.walk(ast.parse(source))
            if isinstance(n, ast.ImportFrom) and n.module == "btgen.ir.kinds"
            for a in n.names
        }
        allowed = {"DYN", "INT32_MAX", "INT32_MIN", "TEXT_BOUND", "UINT32_MAX", "describe_kind", "is_queue"}
        assert taken <= allowed, (module.__name__, taken)
        assert "ScriptTypeError" not in source, module.__name__
