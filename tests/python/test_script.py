"""The script language: parsing, errors and evaluation with BehaviorTree.CPP 4.6.2 semantics.

Sources: scripting/operators.hpp (grammar and Expr* evaluate), scripting/any_types.hpp
(literals), utils/safe_any.hpp and utils/convert_impl.hpp (value conversions).
"""

import math

import pytest

from btgen.diagnostics import Loc
from btgen.lang.blackboard import Blackboard
from btgen.lang.script import (
    Assign,
    Binary,
    Compare,
    Literal,
    Name,
    Script,
    ScriptRuntimeError,
    ScriptSyntaxError,
    Ternary,
    Unary,
    evaluate,
    format_expr,
    parse_script,
    script_error_loc,
    script_truth,
    variables_read,
    variables_written,
)
from btgen.lang.status import NodeStatus
from btgen.lang.values import Queue


def shape(code):
    return "; ".join(format_expr(s) for s in parse_script(code).statements)


def run(code, bb=None, enums=None):
    return evaluate(parse_script(code), bb if bb is not None else Blackboard(), enums)


def typed(value):
    return (type(value).__name__, value)


# ================================================================== parsing


@pytest.mark.parametrize(
    "code, expected",
    [
        ("a + b * c", "(a + (b * c))"),
        ("a * b + c", "((a * b) + c)"),
        ("a - b - c", "((a - b) - c)"),
        ("a / b * c", "((a / b) * c)"),
        ("-a * b", "(-a * b)"),
        ("- -a", "--a"),
        ("a .. b + c", "(a .. (b + c))"),
        ("a + b .. c * d", "((a + b) .. (c * d))"),
        ("a .. b .. c", "((a .. b) .. c)"),
        ("a | b & c", "(a | (b & c))"),
        ("a & b | c ^ d", "(((a & b) | c) ^ d)"),
        ("~a & !b", "(~a & !b)"),
        ("!!a", "!!a"),
        ("a == b", "(a == b)"),
        ("a < b < c", "(a < b < c)"),
        ("a == b != c >= d", "(a == b != c >= d)"),
        ("a + 1 < b * 2", "((a + 1) < (b * 2))"),
        ("!a == b", "(!a == b)"),
        ("a && b || c", "((a && b) || c)"),
        ("a || b && c", "((a || b) && c)"),  # && and || share one level, left to right
        ("a < b && c > d", "((a < b) && (c > d))"),
        ("c ? a : b", "(c ? a : b)"),
        ("x > 1 ? 'big' : 'small'", "((x > 1) ? 'big' : 'small')"),
        ("c ? x := 1 : 2", "(c ? (x := 1) : 2)"),  # the middle is a full expression
        ("c ? a : (d ? e : f)", "(c ? a : (d ? e : f))"),
        ("x := c ? 1 : 2", "(x := (c ? 1 : 2))"),
        ("x := a || b", "(x := (a || b))"),
        ("x += 1; y -= 2; z *= 3; w /= 4; v = 5", "(x += 1); (y -= 2); (z *= 3); (w /= 4); (v = 5)"),
        ("(a) := 1", "(a := 1)"),
        ("(a := 1) + 2", "((a := 1) + 2)"),
        ("@visits += 1", "(@visits += 1)"),
        ("x := @log .. '+' .. room", "(x := ((@log .. '+') .. room))"),
        ("a\t:=\n1 ;\r\nb := 2", "(a := 1); (b := 2)"),
        ("a := \\\n1", "(a := 1)"),  # a backslash-newline is a blank
        ("déjà_vu := 1", "(déjà_vu := 1)"),  # names are Unicode identifiers
        ("_x := 1", "(_x := 1)"),
    ],
)
def test_precedence_and_associativity(code, expected):
    assert shape(code) == expected


@pytest.mark.parametrize(
    "code, expected",
    [
        # 4.6.2 rejects arithmetic as a direct comparison operand; the fixed meaning is used.
        ("a - b == 2", "((a - b) == 2)"),
        ("(a - b) == 2", "((a - b) == 2)"),
        # 4.6.2 rejects `A==-1` (fixed in 4.7.0).
        ("A==-1", "(A == -1)"),
        ("A != -1.5", "(A != -1.5)"),
        # 4.6.2 may read `A - B + C` as `A - (B + C)` (fixed in 4.9.0).
        ("A - B + C", "((A - B) + C)"),
        ("A - B - C + D", "(((A - B) - C) + D)"),
    ],
)
def test_fixed_4_6_2_parser_bugs(code, expected):
    assert shape(code) == expected


def test_ast_nodes_and_offsets():
    s = parse_script("x := a + 2; ok := y < 3 <= z ? -1 : 'no'")
    assert isinstance(s, Script) and s.code.startswith("x := a")
    assign = s.statements[0]
    assert assign == Assign(":=", "x", Binary("+", Name("a", 5), Literal(2, "2", 9), 5, 7), 0, 2)
    t = s.statements[1].value
    assert isinstance(t, Ternary) and t.offset == 18 and t.op_offset == 29
    assert t.cond == Compare(("<", "<="), (Name("y", 18), Literal(3, "3", 22), Name("z", 27)), 18, (20, 24))
    assert t.then == Unary("-", Literal(1, "1", 32), 31)
    assert t.orelse == Literal("no", "'no'", 36)
    with pytest.raises(AttributeError):
        t.op_offset = 1  # frozen


@pytest.mark.parametrize(
    "code, value",
    [
        ("42", 42),
        ("0x1F", 31),
        ("0XfF", 255),
        ("007", 7),
        ("9223372036854775807", 9223372036854775807),
        ("2.5", 2.5),
        ("1e3", 1000.0),
        ("1.5E-2", 0.015),
        ("2.0e+1", 20.0),
        ("true", 1),  # BooleanLiteral is lexy::constant(1): an integer
        ("false", 0),
        ("'it''", None),
        ("'single'", "single"),
        ('"double"', "double"),
        ("'say \"hi\"'", 'say "hi"'),
        ("''", ""),
        ("'a;b:=c'", "a;b:=c"),
        ("+5", 5),  # Integer takes a sign: a literal, not an operator
        ("+2.5", 2.5),
    ],
)
def test_literals(code, value):
    if value is None:
        with pytest.raises(ScriptSyntaxError):
            parse_script(code)
        return
    lit = parse_script(code).statements[0]
    assert isinstance(lit, Literal) and lit.value == value and type(lit.value) is type(value)


def test_signed_literal_only_where_4_6_2_reads_one():
    # `-` before an atom is the negation operator (a double result); after `!`/`~`
    # (whose operand is an atom) `-1` is the integer literal -1.
    neg = parse_script("-1").statements[0]
    assert neg == Unary("-", Literal(1, "1", 1), 0)
    assert parse_script("!-1").statements[0] == Unary("!", Literal(-1, "-1", 1), 0)
    assert parse_script("~ -1").statements[0] == Unary("~", Literal(-1, "-1", 2), 0)
    assert parse_script("a + +1").statements[0].right == Literal(1, "+1", 4)


# ============================================================ syntax errors


@pytest.mark.parametrize(
    "code, message, offset",
    [
        ("", "empty script", 0),
        ("   ", "empty script", 3),
        ("a := 5;", "unexpected `;` after the last statement (BehaviorTree.CPP 4.6.2 rejects a trailing `;`)", 6),
        ("a := 1;; b := 2", "empty statement between two `;`", 7),
        ("x := 1 +", "expected a value, a name or `(`, found the end of the script", 8),
        ("x := (1 + 2", "expected `)` to close the `(` at offset 5, found the end of the script", 11),
        ("x := 1 + 2)", "unexpected `)`; expected an operator, `;` or the end", 10),
        ("a b", "unexpected `b`; expected an operator, `;` or the end", 2),
        ("f(x)", "unexpected `(`; expected an operator, `;` or the end", 1),
        ("a = = b", "expected a value, a name or `(`, found `=`", 4),
        ("a := b := 1", "assignments cannot be chained; separate them with `;`", 7),
        ("a + 1 := 3", "the left side of `:=` must be a blackboard entry name", 0),
        ("1 += 2", "the left side of `+=` must be a blackboard entry name", 0),
        ("a ? b : c ? d : e", "`?:` cannot be chained without parentheses: write `a ? b : (c ? d : e)`", 10),
        ("a ? b", "expected `:` of `?:` here, found the end of the script", 5),
        (
            "a + b & c",
            "`&` cannot be mixed with `+` without parentheses (BehaviorTree.CPP keeps arithmetic "
            "and bitwise operators apart)",
            6,
        ),
        (
            "~a + 1",
            "`+` cannot be mixed with `~` without parentheses (BehaviorTree.CPP keeps arithmetic "
            "and bitwise operators apart)",
            3,
        ),
        (
            "!a .. 'x'",
            "`..` cannot be mixed with `!` without parentheses (BehaviorTree.CPP keeps arithmetic "
            "and bitwise operators apart)",
            3,
        ),
        (
            "-!a",
            "`!` cannot be mixed with `-` without parentheses (BehaviorTree.CPP keeps arithmetic "
            "and bitwise operators apart)",
            1,
        ),
        ("1..2", "invalid number `1..2` (write `..` with a space after a number, e.g. `1 .. x`)", 0),
        ("5abc", "invalid number `5abc`", 0),
        ("1_000", "invalid number `1_000`", 0),
        ("1.5.2", "invalid number `1.5.2`", 0),
        ("1e", "invalid number `1e`", 0),
        ("0x", "invalid number `0x`", 0),
        ("0x1g", "invalid number `0x1g`", 0),
        (".5", "unexpected character '.'", 0),
        ("9223372036854775808", "integer `9223372036854775808` is out of range (at most 9223372036854775807)", 0),
        ("1e999", "number `1e999` is out of range for a double", 0),
        ("x := 'abc", "unterminated string: missing closing '", 5),
        ("x := 'café'", "only ASCII characters are allowed in a script string (BehaviorTree.CPP 4.6.2)", 9),
        ("x := 1 # note", "unexpected character '#'", 7),
        ("x := a$", "unexpected character '$'", 6),
        ("x := 1 % 2", "unexpected character '%'", 7),
        ("x\u00a0:= 1", "unexpected character U+00A0", 1),
        ("@ := 1", "`@` must be followed by a name (`@key` is `key` on the root blackboard)", 0),
        ("a@b := 1", "unexpected `@b`; expected an operator, `;` or the end", 1),
        (
            "true_flag := 1",
            "`true_flag`: BehaviorTree.CPP 4.6.2 reads a name starting with `true` as the literal "
            "true followed by `_flag`; rename it",
            0,
        ),
        (
            "x := falsey",
            "`falsey`: BehaviorTree.CPP 4.6.2 reads a name starting with `false` as the literal "
            "false followed by `y`; rename it",
            5,
        ),
        ("x := !=1", "expected a value, a name or `(`, found `!=`", 5),
        ("x := - 'a' + + 1", "expected a value, a name or `(`, found `+`", 13),
    ],
)
def test_syntax_errors(code, message, offset):
    with pytest.raises(ScriptSyntaxError) as e:
        parse_script(code)
    assert (e.value.message, e.value.offset) == (message, offset)
    assert str(e.value) == message


def test_error_locations_inside_the_attribute():
    start = Loc("m.xml", 7, 20)
    assert script_error_loc(start, "x := 1 +", 8) == Loc("m.xml", 7, 28)
    assert script_error_loc(start, "a := 1;\nb := a +", 15) == Loc("m.xml", 8, 8)
    assert script_error_loc(start, "a\n\nb", 3) == Loc("m.xml", 9, 1)
    assert script_error_loc(start, "abc", 99) == Loc("m.xml", 7, 23)  # clamped to the end
    # The value as written: `&amp;&amp;` and `&#10;` are one decoded character each.
    code = "a && b;\nc := +"
    raw = "a &amp;&amp; b;&#10;c := +"
    assert script_error_loc(start, code, 5, raw) == Loc("m.xml", 7, 33)  # `b`
    assert script_error_loc(start, code, 13, raw) == Loc("m.xml", 7, 45)  # after `+`
    raw_nl = "a &amp;&amp; b;\n  c := +"
    assert script_error_loc(start, "a && b;\n  c := +", 10, raw_nl) == Loc("m.xml", 8, 3)


# =============================================================== evaluation


@pytest.mark.parametrize(
    "code, expected",
    [
        # numbers: every arithmetic result is a double (ExprBinaryArithmetic casts to double)
        ("7", ("int", 7)),
        ("2 + 3", ("float", 5.0)),
        ("7 - 10", ("float", -3.0)),
        ("6 * 7", ("float", 42.0)),
        ("7 / 2", ("float", 3.5)),
        ("1 / 3", ("float", 1 / 3)),
        ("-4", ("float", -4.0)),
        ("2.5 * 2", ("float", 5.0)),
        ("true + true", ("float", 2.0)),
        ("0x10 | 1", ("float", 17.0)),
        ("12 & 10", ("float", 8.0)),
        ("12 ^ 10", ("float", 6.0)),
        ("~5", ("float", -6.0)),
        ("~0", ("float", -1.0)),
        ("~2.9", ("float", -3.0)),  # static_cast<int64_t> truncates
        ("!0", ("float", 1.0)),
        ("!3", ("float", 0.0)),
        ("!0.5", ("float", 0.0)),
        ("!-1", ("float", 0.0)),
        ("1 && 0", ("float", 0.0)),
        ("1 || 0", ("float", 1.0)),
        ("0.5 && 2.5", ("float", 1.0)),  # a double converts to bool when non-zero
        ("true && false || true", ("float", 1.0)),
        # strings
        ("'ab' + 'cd'", ("str", "abcd")),
        ("'ab' .. 'cd'", ("str", "abcd")),
        ("'n=' .. 5", ("str", "n=5")),
        ("5 .. '!'", ("str", "5!")),
        ("'x=' .. 2.5", ("str", "x=2.500000")),  # Any::cast<std::string> is std::to_string
        ("'x=' .. -1", ("str", "x=-1.000000")),  # -1 is a negation: a double
        ("'x=' .. (2 + 2)", ("str", "x=4.000000")),
        ("'t=' .. true", ("str", "t=1")),
        ("'a' .. 1 + 2", ("str", "a3.000000")),
        ("1 .. 2", ("NoneType", None)),  # two numbers: 4.6.2 returns an empty value
        # comparisons give 1.0 / 0.0
        ("3 == 3", ("float", 1.0)),
        ("3 == 3.0", ("float", 1.0)),
        ("0.1 + 0.2 == 0.3", ("float", 1.0)),
        ("1 == 1.0000001", ("float", 1.0)),  # within FLT_EPSILON
        ("1 == 1.000001", ("float", 0.0)),
        ("1 != 1.0000001", ("float", 0.0)),
        ("2 < 3", ("float", 1.0)),
        ("3 < 3", ("float", 0.0)),
        ("3 <= 3", ("float", 1.0)),
        ("4 > 3", ("float", 1.0)),
        ("3 >= 4", ("float", 0.0)),
        ("'abc' == 'abc'", ("float", 1.0)),
        ("'abc' < 'abd'", ("float", 1.0)),
        ("'ab' < 'abc'", ("float", 1.0)),
        ("'B' < 'a'", ("float", 1.0)),  # byte order
        ("'b' >= 'a'", ("float", 1.0)),
        ("'42' == 42", ("float", 1.0)),  # a string against a number is read as a number
        ("42 == '42.0'", ("float", 1.0)),
        ("'7abc' == 7", ("float", 1.0)),  # from_chars ignores the rest
        ("'true' == 1", ("float", 1.0)),
        ("'false' < 1", ("float", 1.0)),
        # chained comparisons: every adjacent pair, not C's (a < b) < c
        ("1 < 2 < 3", ("float", 1.0)),
        ("3 > 2 > 1", ("float", 1.0)),
        ("1 < 3 < 2", ("float", 0.0)),
        ("5 > 1 < 3", ("float", 1.0)),
        ("1 == 1 == 1", ("float", 1.0)),
        ("2 == 2 == 1", ("float", 0.0)),
        # ternary
        ("1 ? 'yes' : 'no'", ("str", "yes")),
        ("0 ? 'yes' : 'no'", ("str", "no")),
        ("0.0 ? 1 : 2", ("int", 2)),
        ("'1' ? 1 : 2", ("int", 1)),  # a string condition must hold a number
        ("'0' ? 1 : 2", ("int", 2)),
        ("2 > 1 ? 3 > 2 ? 'a' : 'b' : 'c'", ("str", "a")),
        # IEEE arithmetic as in C++
        ("1 / 0", ("float", math.inf)),
        ("-1 / 0", ("float", -math.inf)),
        ("1 / -0.0", ("float", -math.inf)),
    ],
)
def test_operators(code, expected):
    assert typed(run(code)) == expected


def test_nan_results():
    assert math.isnan(run("0 / 0"))
    assert run("0/0 == 0/0") == 0.0
    assert run("0/0 < 1") == 1.0  # `<` fails only when `>=` holds (SwitchImpl)
    assert run("!(0/0)") == 0.0


def test_statements_run_in_order_and_the_last_value_is_the_result():
    bb = Blackboard()
    assert run("a := 1; b := a + 1; c := b * 10", bb) == 20.0
    assert typed(bb.get("a")) == ("int", 1)
    assert typed(bb.get("b")) == ("float", 2.0)
    assert run("a; 'last'", bb) == "last"


def test_script_expressions_case():
    # conformance case script_expressions, statement by statement
    bb = Blackboard()
    run("a := 5; b := 3; who := 'robot'; ok := true", bb)
    assert run("(a * 2 - b) == 7 && ((a + b) / 2) == 4", bb) == 1.0
    run("msg := 'hello ' .. who; label := a > b ? 'big' : 'small'; total := a + b * 2", bb)
    assert (bb.get("msg"), bb.get("label"), bb.get("total")) == ("hello robot", "big", 11.0)
    assert run("(a > b) && ok || false", bb) == 1.0
    assert run("total >= 11 && b != a && b <= 3", bb) == 1.0
    assert run("!(a < b)", bb) == 1.0
    assert run("a < b || who == 'human'", bb) == 0.0
    run("a += 1; b *= 2; who := who .. '_' .. a", bb)
    assert typed(bb.get("a")) == ("int", 6)  # the integer entry stays an integer: "robot_6"
    assert run("a == 6 && b == 6 && who == 'robot_6'", bb) == 1.0


def test_both_sides_of_logic_operators_always_run():
    bb = Blackboard()
    assert run("false && (x := 1)", bb) == 0.0
    assert run("true || (y := 0)", bb) == 1.0
    assert (bb.get("x"), bb.get("y")) == (1, 0)


def test_chained_comparison_stops_at_the_first_false_pair():
    assert run("1 > 2 > nowhere") == 0.0
    with pytest.raises(ScriptRuntimeError, match="unknown variable `nowhere`"):
        run("1 < 2 < nowhere")


def test_ternary_runs_one_branch():
    bb = Blackboard()
    assert run("1 ? (t := 1) : (e := 2)", bb) == 1
    assert bb.get_entry("e") is None and bb.get("t") == 1


def test_enums_are_numbers_and_win_over_entries():
    bb = Blackboard()
    run("color := 'RED'; RED := 5", bb)
    enums = {"RED": 1, "GREEN": 2}
    assert typed(run("GREEN", bb, enums)) == ("float", 2.0)
    assert run("RED + 1", bb, enums) == 2.0
    assert run("color == 1", bb, enums) == 1.0  # StringToDouble looks the string up too
    assert run("RED", bb) == 5


# ============================================================ assignments
# operators.hpp ExprAssignment::evaluate


def test_create_assign_and_update_counters():
    bb = Blackboard()
    run("n := 1", bb)
    e = bb.get_entry("n")
    assert (e.type_name, e.value, e.sequence_id) == ("any", 1, 1)
    run("n = 2; n += 3; n -= 1; n *= 2; n /= 4", bb)
    assert typed(e.value) == ("int", 2) and e.sequence_id == 6
    run("n := 10", bb)
    assert e.value == 10 and e.sequence_id == 7
    assert run("s := 'a'; s += 'b'; s += 'c'", bb) == "abc"
    assert run("t := 2.5; t += 1", bb) == 3.5


def test_integer_entries_keep_integers():
    bb = Blackboard()
    run("n := 5", bb)
    assert typed(run("n := 7.0", bb)) == ("int", 7)
    with pytest.raises(ScriptRuntimeError) as e:
        run("n /= 2", bb)  # 3.5 cannot go back into an integer
    assert e.value.message == (
        "cannot store the result of `/=` in `n`: cannot convert 3.5 (double) to integer: "
        "the value is not a whole number"
    )
    assert bb.get("n") == 7 and bb.get_entry("n").sequence_id == 2
    run("d := 5.0; d /= 2", bb)
    assert bb.get("d") == 2.5


def test_strings_into_typed_and_numeric_entries():
    bb = Blackboard()
    run("n := 5", bb)
    assert typed(run("n := '7'", bb)) == ("float", 7.0)  # no converter: StringToDouble
    bb.create_entry("port_int", "int")
    assert typed(run("port_int := '12'", bb)) == ("int", 12)  # the entry's convertFromString
    bb.create_entry("port_q", "queue<int>")
    assert run("port_q := '1;2'", bb) == Queue("int", [1, 2])
    bb.create_entry("empty_int", "int")
    assert typed(run("empty_int := 2.5", bb)) == ("float", 2.5)  # copyInto an empty Any takes anything
    bb.create_entry("flag", "bool")
    assert run("flag := 'true'", bb) is True


@pytest.mark.parametrize(
    "setup, code, message, offset",
    [
        ("", "x = 1", "blackboard entry `x` does not exist yet; use `:=` to create it", 2),
        ("", "x += 1", "blackboard entry `x` does not exist yet; use `:=` to create it", 2),
        ("s := 'a'", "s := 5", "cannot assign 5 to `s`: a int cannot be stored where a string is", 2),
        ("n := 5", "n := 'abc'", "the string 'abc' is not a number", 2),
        (
            "n := 5",
            "n := 2.5",
            "cannot assign 2.5 to `n`: cannot convert 2.5 (double) to integer: the value is not a whole number",
            2,
        ),
        ("n := 5", "n -= 'a'", "`-=` cannot be used with a string", 2),
        ("n := 5", "n += 'a'", "cannot store the result of `+=` in `n`: a string cannot be stored where a int is", 2),
        ("s := 'a'", "s += 1", "`+=` with a number needs a numeric `s`, but it holds a string", 2),
        ("", "x := 1 .. 2", "the right operand of `:=` has no value", 2),
        ("", "x := y", "unknown variable `y` (no blackboard entry of that name; create it with `y := ...`)", 5),
    ],
)
def test_assignment_errors(setup, code, message, offset):
    bb = Blackboard()
    if setup:
        run(setup, bb)
    with pytest.raises(ScriptRuntimeError) as e:
        run(code, bb)
    assert (e.value.message, e.value.offset) == (message, offset)


def test_typed_entry_errors():
    bb = Blackboard()
    bb.create_entry("n", "int")
    with pytest.raises(ScriptRuntimeError) as e:
        run("n := 'many'", bb)
    assert e.value.message == "cannot assign 'many' to `n` (int): `many` is not a valid int"
    with pytest.raises(ScriptRuntimeError) as e:
        run("n += 1", bb)
    assert e.value.message == "`n` has no value yet, so `+=` cannot update it"
    bb.create_entry("st", "NodeStatus")
    bb.set("st", NodeStatus.RUNNING)
    with pytest.raises(ScriptRuntimeError) as e:
        run("st := 'SUCCESS'", bb)  # enums get no string converter in 4.6.2
    assert e.value.message == "the string 'SUCCESS' is not a number"
    assert run("st := 2", bb) is NodeStatus.SUCCESS
    assert run("st == 2", bb) == 1.0


def test_create_inside_subtrees():
    root = Blackboard()
    auto = Blackboard(root, autoremap=True)
    run("first := 1", auto)
    assert root.get("first") == 1
    iso = Blackboard(root)
    run("first := 2; @first += 10", iso)
    assert iso.get("first") == 2 and root.get("first") == 11


# =========================================================== runtime errors


@pytest.mark.parametrize(
    "setup, code, message, offset",
    [
        ("", "'a' - 1", "`-` cannot be applied to a string and a int", 4),
        ("", "'a' + 1", "`+` cannot be applied to a string and a int", 4),
        ("", "'a' * 'b'", "`*` cannot be applied to a string and a string", 4),
        ("", "'a' && 1", "`&&` cannot be applied to a string and a int", 4),
        (
            "",
            "2 && 1",
            "`&&` needs operands that convert to bool: cannot convert 2 (int) to bool: "
            "only the integers 0 and 1 convert to bool",
            2,
        ),
        (
            "",
            "1.5 | 1",
            "`|` needs whole-number operands: cannot convert 1.5 (double) to integer: the value is not a whole number",
            4,
        ),
        ("", "-'a'", "`-` cannot be applied to a string", 0),
        ("", "!'a'", "`!` cannot be applied to a string", 0),
        ("", "~1e30", "1e+30 is out of range for `~`", 0),
        ("", "'a' == 1", "the string 'a' is not a number", 4),
        ("", "1 < 'x'", "the string 'x' is not a number", 2),
        ("x := 1", "y + 1", "unknown variable `y` (no blackboard entry of that name; create it with `y := ...`)", 0),
        ("", "'abc' ? 1 : 2", "the condition of `?:` is the string 'abc', which is not a number", 6),
        (
            "",
            "9007199254740993 + 0",
            "left operand of `+`: cannot convert 9007199254740993 (int) to double: precision would be lost",
            17,
        ),
    ],
)
def test_runtime_errors(setup, code, message, offset):
    bb = Blackboard()
    if setup:
        run(setup, bb)
    with pytest.raises(ScriptRuntimeError) as e:
        run(code, bb)
    assert (e.value.message, e.value.offset) == (message, offset)


def test_runtime_errors_on_values_not_yet_set():
    bb = Blackboard()
    bb.create_entry("e", "int")
    assert run("e", bb) is None
    for code, message, offset in [
        ("e + 1", "the left operand of `+` has no value", 2),
        ("1 + e", "the right operand of `+` has no value", 2),
        ("e == 1", "the left operand of `==` has no value", 2),
        ("-e", "the operand of `-` has no value", 0),
        ("e ? 1 : 2", "the condition of `?:` has no value", 2),
        ("x := e", "the right operand of `:=` has no value", 2),
    ]:
        with pytest.raises(ScriptRuntimeError) as err:
            run(code, bb)
        assert (err.value.message, err.value.offset) == (message, offset), code


def test_queues_in_scripts():
    bb = Blackboard()
    bb.set("q", Queue("int", [1]))
    with pytest.raises(ScriptRuntimeError, match=r"^cannot compare a queue<int> with a int using `==`$"):
        run("q == 1", bb)
    with pytest.raises(ScriptRuntimeError, match=r"^`\.\.` cannot be applied to a queue<int> and a string$"):
        run("q .. 'x'", bb)


# ============================================================ truth, queries


@pytest.mark.parametrize(
    "value, truth",
    [
        (1.0, True),
        (0.0, False),
        (-0.0, False),
        (math.nan, True),
        (1, True),
        (0, False),
        (True, True),
        (NodeStatus.RUNNING, True),
        (NodeStatus.IDLE, False),
    ],
)
def test_script_truth(value, truth):
    # ScriptCondition / Precondition / _skipIf...: result.cast<bool>()
    assert script_truth(value) is truth


@pytest.mark.parametrize(
    "value, message",
    [
        (None, "the script gives no value, so it cannot be used as a condition"),
        (
            2,
            "the script's result cannot be used as a condition: cannot convert 2 (int) to bool: "
            "only the integers 0 and 1 convert to bool",
        ),
        (
            -0.5,  # both releases: "Value is negative and can't be converted to unsigned" (oracle-diff)
            "the script's result cannot be used as a condition: cannot convert -0.5 (double) to bool: "
            "the value is negative",
        ),
        (
            -1,
            "the script's result cannot be used as a condition: cannot convert -1 (int) to bool: the value is negative",
        ),
        ("true", "the script gives 'true' (string), which is not a condition"),
        (Queue("int"), "the script gives queue<int> [] (queue<int>), which is not a condition"),
        (
            NodeStatus.SUCCESS,
            "the script's result cannot be used as a condition: cannot convert SUCCESS (NodeStatus) "
            "to bool: only the integers 0 and 1 convert to bool",
        ),
    ],
)
def test_script_truth_errors(value, message):
    with pytest.raises(ScriptRuntimeError) as e:
        script_truth(value)
    assert e.value.message == message


def test_conditions_of_the_conformance_cases():
    bb = Blackboard()
    run("arm_ready := false; door_locked := true; at_goal := true; n := 0", bb)
    assert [script_truth(run(c, bb)) for c in ("!arm_ready", "door_locked", "at_goal", "n != 4", "n < 4")] == [
        True,
        True,
        True,
        True,
        True,
    ]
    run("level := 2", bb)
    with pytest.raises(ScriptRuntimeError):
        script_truth(run("level", bb))  # an integer 2 is no bool in 4.6.2


def test_variables_read_and_written():
    s = parse_script("@visits += 1; log := @log .. room; x = y > 1 ? z : w; n := n + 1; log := 'a'")
    assert variables_read(s) == ("@visits", "@log", "room", "y", "z", "w", "n")
    assert variables_written(s) == ("@visits", "log", "x", "n")
    assert variables_read(parse_script("a := 1")) == ()


def test_absurd_nesting_is_an_error_not_a_crash():
    ok = "x := " + "(" * 32 + "1" + ")" * 32
    assert run(ok) == 1
    with pytest.raises(ScriptSyntaxError) as e:
        parse_script("x := " + "(" * 33 + "1" + ")" * 33)
    assert (e.value.message, e.value.offset) == ("the expression is nested too deeply (more than 32 levels)", 37)
    with pytest.raises(ScriptSyntaxError) as e:
        parse_script("!" * 40 + "a")
    assert e.value.message == "the expression is nested too deeply (more than 32 levels)"
    assert run("x := " + " + ".join(["1"] * 99)) == 99.0  # 100 levels: the limit
    with pytest.raises(ScriptSyntaxError) as e:
        parse_script("x := " + " + ".join(["1"] * 100))
    assert (e.value.message, e.value.offset) == (
        "the expression is too deep (101 levels, at most 100); split it into several statements",
        5,
    )
