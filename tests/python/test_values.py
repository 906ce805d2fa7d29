"""Value types and conversions, checked against BehaviorTree.CPP 4.6.2's rules."""

import math

import pytest

from btgen.lang.status import NodeStatus
from btgen.lang.values import (
    ConversionError,
    Queue,
    cast,
    convert_from_string,
    copy_into,
    format_double,
    is_casting_safe,
    is_number,
    is_opaque_type,
    normalize_type,
    queue_element_type,
    to_text,
    type_of,
)

# ------------------------------------------------------------------ status


def test_node_status_prints_its_name_and_keeps_the_4_6_2_numbers():
    assert [str(s) for s in NodeStatus] == ["IDLE", "RUNNING", "SUCCESS", "FAILURE", "SKIPPED"]
    assert [s.value for s in NodeStatus] == [0, 1, 2, 3, 4]
    assert f"{NodeStatus.SUCCESS}" == "SUCCESS"
    assert [s.is_completed for s in NodeStatus] == [False, False, True, True, False]
    assert [s.is_active for s in NodeStatus] == [False, True, True, True, False]


# ------------------------------------------------------------------- types


@pytest.mark.parametrize(
    "text, expected",
    [
        (None, "any"),
        ("", "any"),
        ("BT::AnyTypeAllowed", "any"),
        ("std::string", "string"),
        ("std::__cxx11::basic_string<char, std::char_traits<char>, std::allocator<char> >", "string"),
        ("int", "int"),
        ("int32_t", "int"),
        ("int64_t", "int"),
        ("long", "int"),
        ("unsigned int", "unsigned"),
        ("  unsigned   int ", "unsigned"),
        ("uint32_t", "unsigned"),
        ("unsigned long", "unsigned"),
        ("double", "double"),
        ("float", "double"),
        ("bool", "bool"),
        ("BT::NodeStatus", "NodeStatus"),
        ("std::shared_ptr<std::deque<int, std::allocator<int> > >", "queue<int>"),
        ("std::shared_ptr<std::deque<double, std::allocator<double> > >", "queue<double>"),
        ("std::shared_ptr<std::deque<bool, std::allocator<bool> > >", "queue<bool>"),
        (
            "std::shared_ptr<std::deque<std::__cxx11::basic_string<char, std::char_traits<char>, "
            "std::allocator<char> >, "
            "std::allocator<std::__cxx11::basic_string<char, std::char_traits<char>, std::allocator<char> > > > >",
            "queue<string>",
        ),
        ("BT::SharedQueue<int>", "queue<int>"),
        ("SharedQueue<std::string>", "queue<string>"),
        ("queue<double>", "queue<double>"),
        ("Pose2D", "Pose2D"),
        ("  geometry_msgs::msg::Pose_<std::allocator<void> > ", "geometry_msgs::msg::Pose_<std::allocator<void> >"),
        ("std::shared_ptr<std::deque<Pose2D> >", "std::shared_ptr<std::deque<Pose2D> >"),
    ],
)
def test_normalize_type(text, expected):
    assert normalize_type(text) == expected


def test_type_helpers():
    assert queue_element_type("queue<string>") == "string"
    assert queue_element_type("int") is None
    assert is_opaque_type("Pose2D") and not is_opaque_type("queue<int>") and not is_opaque_type("any")
    assert [type_of(v) for v in (True, 3, 2.5, "x", NodeStatus.FAILURE, Queue("bool"))] == [
        "bool",
        "int",
        "double",
        "string",
        "NodeStatus",
        "queue<bool>",
    ]
    assert [is_number(v) for v in (True, 3, 2.5, "3", NodeStatus.IDLE, Queue("int"), None)] == [
        True,
        True,
        True,
        False,
        True,
        False,
        False,
    ]


# ------------------------------------------------------- convertFromString


@pytest.mark.parametrize(
    "type_name, text, expected",
    [
        ("int", "42", 42),
        ("int", "-7", -7),
        ("int", "007", 7),
        ("int", "-0", 0),
        ("int", "2147483647", 2147483647),
        ("int", "-2147483648", -2147483648),
        # std::from_chars stops at the first non-digit and 4.6.2 ignores the rest
        # (basic_types.cpp, convertFromString<int64_t>): "12abc" is 12, "0x10" is 0.
        ("int", "12abc", 12),
        ("int", "3.7", 3),
        ("int", "0x10", 0),
        ("unsigned", "4294967295", 4294967295),
        ("unsigned", "-0", 0),
        ("unsigned", "0", 0),
        # std::stod: leading blanks, a sign, hex floats, inf and nan; rest ignored.
        ("double", "3.5", 3.5),
        ("double", " 2.5", 2.5),
        ("double", "+1e3", 1000.0),
        ("double", "-.5", -0.5),
        ("double", "7.", 7.0),
        ("double", "1.5abc", 1.5),
        ("double", "0x1p3", 8.0),
        ("double", "0x1.8", 1.5),
        ("double", "inf", math.inf),
        ("double", "-Infinity", -math.inf),
        ("bool", "true", True),
        ("bool", "TRUE", True),
        ("bool", "True", True),
        ("bool", "1", True),
        ("bool", "false", False),
        ("bool", "FALSE", False),
        ("bool", "False", False),
        ("bool", "0", False),
        ("NodeStatus", "IDLE", NodeStatus.IDLE),
        ("NodeStatus", "RUNNING", NodeStatus.RUNNING),
        ("NodeStatus", "SUCCESS", NodeStatus.SUCCESS),
        ("NodeStatus", "FAILURE", NodeStatus.FAILURE),
        ("NodeStatus", "SKIPPED", NodeStatus.SKIPPED),
        ("string", " any text; with {braces} ", " any text; with {braces} "),
        ("string", "", ""),
        ("any", "42", "42"),
        ("Pose2D", "1;2;3", "1;2;3"),
    ],
)
def test_convert_from_string_accepts(type_name, text, expected):
    got = convert_from_string(type_name, text)
    assert got == expected and type(got) is type(expected)


def test_convert_from_string_nan():
    assert math.isnan(convert_from_string("double", "nan"))
    assert math.isnan(convert_from_string("double", "NAN(123)"))


@pytest.mark.parametrize(
    "type_name, text, message",
    [
        ("int", "three", "`three` is not a valid int"),
        ("int", "", "`` is not a valid int"),
        ("int", " 5", "` 5` is not a valid int"),  # from_chars takes no blanks
        ("int", "+5", "`+5` is not a valid int"),  # ... and no plus sign
        ("int", "2147483648", "`2147483648` is out of range for int (-2147483648 to 2147483647)"),
        ("int", "-2147483649", "`-2147483649` is out of range for int (-2147483648 to 2147483647)"),
        ("int", "99999999999999999999", "`99999999999999999999` is out of range for int (-2147483648 to 2147483647)"),
        ("unsigned", "-1", "`-1` is out of range for unsigned (0 to 4294967295)"),
        ("unsigned", "4294967296", "`4294967296` is out of range for unsigned (0 to 4294967295)"),
        ("unsigned", "many", "`many` is not a valid unsigned"),
        ("double", "abc", "`abc` is not a valid double"),
        ("double", "", "`` is not a valid double"),
        ("double", ".", "`.` is not a valid double"),
        ("double", "1e999", "`1e999` is out of range for double"),
        ("double", "1e-400", "`1e-400` is out of range for double"),  # std::stod throws on underflow
        ("double", "1e-310", "`1e-310` is out of range for double"),  # glibc strtod: ERANGE for subnormals
        ("bool", "yes", "`yes` is not a valid bool (use true or false, 1 or 0)"),
        ("bool", "tRUE", "`tRUE` is not a valid bool (use true or false, 1 or 0)"),
        ("bool", "2", "`2` is not a valid bool (use true or false, 1 or 0)"),
        ("bool", "", "`` is not a valid bool (use true or false, 1 or 0)"),
        (
            "NodeStatus",
            "success",
            "`success` is not a valid NodeStatus (use IDLE, RUNNING, SUCCESS, FAILURE or SKIPPED)",
        ),
        ("queue<int>", "1;x;3", "`1;x;3` is not a valid queue<int>: element 2: `x` is not a valid int"),
        ("queue<int>", ";1", "`;1` is not a valid queue<int>: element 1: `` is not a valid int"),
        ("queue<double>", "1;;2", "`1;;2` is not a valid queue<double>: element 2: `` is not a valid double"),
        (
            "queue<bool>",
            "true;yes",
            "`true;yes` is not a valid queue<bool>: element 2: `yes` is not a valid bool (use true or false, 1 or 0)",
        ),
    ],
)
def test_convert_from_string_rejects(type_name, text, message):
    with pytest.raises(ConversionError) as e:
        convert_from_string(type_name, text)
    assert str(e.value) == message


@pytest.mark.parametrize(
    "type_name, text, expected",
    [
        ("queue<int>", "1;2;3", [1, 2, 3]),
        ("queue<int>", "", []),  # splitString gives no part for an empty text
        ("queue<int>", "1;2;", [1, 2]),  # ... nor after a final `;`
        ("queue<int>", "-4", [-4]),
        ("queue<double>", "0.5;1.25;2", [0.5, 1.25, 2.0]),
        ("queue<bool>", "true;0;False", [True, False, False]),
        ("queue<string>", "kitchen;lab;dock", ["kitchen", "lab", "dock"]),
        ("queue<string>", ";a; b", ["", "a", " b"]),
        ("queue<string>", "closing", ["closing"]),
    ],
)
def test_convert_queue(type_name, text, expected):
    q = convert_from_string(type_name, text)
    assert isinstance(q, Queue) and q.type_name == type_name and list(q) == expected
    assert [type(x) for x in q] == [type(x) for x in expected]


@pytest.mark.parametrize(
    "type_name, text, message",
    [
        ("int", "12abc", "`12abc` is not a valid int: unexpected `abc` after the number"),
        ("int", "3.7", "`3.7` is not a valid int: unexpected `.7` after the number"),
        ("double", "1.5abc", "`1.5abc` is not a valid double: unexpected `abc` after the number"),
        ("double", " 2", "` 2` is not a valid double: unexpected blanks before the number"),
        (
            "queue<int>",
            "1;2x",
            "`1;2x` is not a valid queue<int>: element 2: `2x` is not a valid int: unexpected `x` after the number",
        ),
    ],
)
def test_strict_conversion_rejects_what_4_6_2_silently_drops(type_name, text, message):
    with pytest.raises(ConversionError) as e:
        convert_from_string(type_name, text, strict=True)
    assert str(e.value) == message
    convert_from_string(type_name, text)  # 4.6.2 itself accepts it


def test_strict_conversion_accepts_complete_numbers():
    assert convert_from_string("int", "-12", strict=True) == -12
    assert convert_from_string("double", "+1.5e2", strict=True) == 150.0


# ----------------------------------------------------------------- to_text


@pytest.mark.parametrize(
    "value, text",
    [
        (6, "6"),
        (-12, "-12"),
        (6.0, "6.000000"),  # std::to_string(double) is printf("%f")
        (2.5, "2.500000"),
        (-0.0, "-0.000000"),
        (1.0 / 3.0, "0.333333"),
        (1e20, "100000000000000000000.000000"),
        (1e-7, "0.000000"),
        (math.inf, "inf"),
        (-math.inf, "-inf"),
        (math.nan, "nan"),
        (-math.nan, "-nan"),
        (True, "1"),  # a bool is the integer 1 inside 4.6.2's Any
        (False, "0"),
        (NodeStatus.FAILURE, "3"),
        ("text", "text"),
    ],
)
def test_to_text(value, text):
    assert to_text(value) == text


def test_to_text_has_no_form_for_a_queue_or_nothing():
    with pytest.raises(ConversionError, match="a queue<int> has no text form"):
        to_text(Queue("int", [1]))
    with pytest.raises(ConversionError, match="the value is empty"):
        to_text(None)  # type: ignore[arg-type]
    assert format_double(0.1) == "0.100000"


# -------------------------------------------------------------------- cast
# safe_any.hpp Any::tryCast / convert_impl.hpp convertNumber


@pytest.mark.parametrize(
    "value, type_name, expected",
    [
        (6.0, "int", 6),
        (-3.0, "int", -3),
        (7, "int", 7),
        (True, "int", 1),
        (NodeStatus.SUCCESS, "int", 2),
        (5, "unsigned", 5),
        (5.0, "unsigned", 5),
        (3, "double", 3.0),
        (2**53, "double", 9007199254740992.0),
        (True, "double", 1.0),
        (2.5, "double", 2.5),
        (1, "bool", True),
        (0, "bool", False),
        (0.5, "bool", True),  # a double converts to bool by truncation-free static_cast
        (0.0, "bool", False),
        (False, "bool", False),
        ("42", "int", 42),
        ("42abc", "int", 42),  # from_chars ignores what follows
        ("-2.5", "double", -2.5),
        ("7", "unsigned", 7),
        ("2", "NodeStatus", NodeStatus.SUCCESS),
        (3, "NodeStatus", NodeStatus.FAILURE),
        (NodeStatus.RUNNING, "NodeStatus", NodeStatus.RUNNING),
        (5, "string", "5"),
        (2.5, "string", "2.500000"),
        (True, "string", "1"),
        ("x", "string", "x"),
        ("x", "Pose2D", "x"),
        (2.5, "any", 2.5),
    ],
)
def test_cast(value, type_name, expected):
    got = cast(value, type_name)
    assert got == expected and type(got) is type(expected)


@pytest.mark.parametrize(
    "value, type_name, message",
    [
        (6.5, "int", "cannot convert 6.5 (double) to int: the value is not a whole number"),
        (math.nan, "int", "cannot convert nan (double) to int: the value is not a whole number"),
        (2**31, "int", "cannot convert 2147483648 (int) to int: the value is out of range"),
        (3e9, "int", "cannot convert 3000000000.0 (double) to int: the value is out of range"),
        (-1, "unsigned", "cannot convert -1 (int) to unsigned: the value is negative"),
        (-1.0, "unsigned", "cannot convert -1.0 (double) to unsigned: the value is negative"),
        (2**53 + 1, "double", "cannot convert 9007199254740993 (int) to double: precision would be lost"),
        (2, "bool", "cannot convert 2 (int) to bool: only the integers 0 and 1 convert to bool"),
        (-1, "bool", "cannot convert -1 (int) to bool: only the integers 0 and 1 convert to bool"),
        ("true", "bool", "cannot convert the string 'true' to bool"),
        (" 42", "int", "` 42` is not a valid int"),
        ("2147483648", "int", "`2147483648` is out of range for int (-2147483648 to 2147483647)"),
        ("-1", "unsigned", "`-1` is not a valid unsigned"),
        ("abc", "double", "`abc` is not a valid double"),
        ("SUCCESS", "NodeStatus", "`SUCCESS` is not a valid integer"),
        (7, "NodeStatus", "cannot convert 7 (int) to NodeStatus: 7 is not a status number (0 to 4)"),
        (5, "Pose2D", "cannot convert 5 (int) to Pose2D: no known conversion"),
        ("1;2", "queue<int>", "cannot convert '1;2' (string) to queue<int>: no known conversion"),
        (
            Queue("int", [1]),
            "queue<double>",
            "cannot convert queue<int> [1] (queue<int>) to queue<double>: no known conversion",
        ),
        (Queue("int", [1]), "string", "cannot convert queue<int> [1] (queue<int>) to string: no known conversion"),
        (Queue("int", [1]), "int", "cannot convert queue<int> [1] (queue<int>) to int: no known conversion"),
        (None, "int", "the value is empty"),
    ],
)
def test_cast_rejects(value, type_name, message):
    with pytest.raises(ConversionError) as e:
        cast(value, type_name)
    assert str(e.value) == message


def test_cast_to_a_queue_shares_the_queue():
    q = Queue("int", [1, 2])
    assert cast(q, "queue<int>") is q


def test_casting_safe_and_copy_into():
    # blackboard.h Blackboard::set: a number written to a typed entry must fit it.
    assert is_casting_safe("int", 100) and is_casting_safe("int", 4.0) and is_casting_safe("double", 3)
    assert not is_casting_safe("int", 4.5) and not is_casting_safe("unsigned", -1)
    assert not is_casting_safe("int", 2**40) and not is_casting_safe("bool", 1)
    assert not is_casting_safe("double", 2**53 + 1) and not is_casting_safe("int", "4")
    # safe_any.hpp Any::copyInto: the destination keeps its kind.
    assert copy_into(5, None) == 5
    got = copy_into(2.0, 7)
    assert got == 2 and type(got) is int
    got = copy_into(5, 1.5)
    assert got == 5.0 and type(got) is float
    assert copy_into("b", "a") == "b"
    got = copy_into(True, 3)
    assert got == 1 and type(got) is int  # the destination's original type is kept
    assert copy_into(1, False) is True and copy_into(5, False) == 5
    assert copy_into(2, NodeStatus.IDLE) is NodeStatus.SUCCESS
    with pytest.raises(ConversionError, match="the value is not a whole number"):
        copy_into(2.5, 7)
    with pytest.raises(ConversionError, match="a string cannot be stored where a int is"):
        copy_into("x", 7)
    with pytest.raises(ConversionError, match="a int cannot be stored where a string is"):
        copy_into(7, "x")
