"""The BehaviorTree.CPP script language, in the modules of this package:

- ``nodes``: the syntax tree (Literal, Name, Unary, Binary, Compare, Ternary, Assign; Script),
  the operator groups, the nesting and depth limits, and the queries over a tree;
- ``grammar462``: 4.6.2's lexer and parser; ``grammar49``: the tokenizer and Pratt parser of
  4.9.0 and later; ``parse``: ``parse_script`` with either, and a script's places in its file;
- ``format``: an expression as text;
- ``evaluate``: running a script on a blackboard with 4.6.2's value rules (the interpreter's
  evaluator; ``analyze`` uses it too).

Scripts appear in ``Script``/``ScriptCondition`` ``code``, ``Precondition`` ``if`` and the
``_skipIf``/``_successIf``/``_failureIf``/``_while``/``_onSuccess``/``_onFailure``/``_onHalted``/
``_post`` attributes. Every stage imports the names below from ``btgen.lang.script``.
"""

from btgen.lang.script.evaluate import (
    FLT_EPSILON,
    MAX_STRING_BYTES,
    ScriptRuntimeError,
    evaluate,
    script_truth,
)
from btgen.lang.script.format import format_expr
from btgen.lang.script.nodes import (
    ASSIGN_OPS,
    BIT_OPS,
    COMPARE_OPS,
    LOGIC_OPS,
    MATH_OPS,
    MAX_DEPTH,
    MAX_NESTING,
    Assign,
    Binary,
    Compare,
    Expr,
    Literal,
    Name,
    Script,
    ScriptSyntaxError,
    Ternary,
    Unary,
    variables_read,
    variables_written,
    walk,
)
from btgen.lang.script.parse import parse_script, raw_attr_value, script_error_loc

__all__ = [
    "ASSIGN_OPS",
    "BIT_OPS",
    "COMPARE_OPS",
    "FLT_EPSILON",
    "LOGIC_OPS",
    "MATH_OPS",
    "MAX_DEPTH",
    "MAX_NESTING",
    "MAX_STRING_BYTES",
    "Assign",
    "Binary",
    "Compare",
    "Expr",
    "Literal",
    "Name",
    "Script",
    "ScriptRuntimeError",
    "ScriptSyntaxError",
    "Ternary",
    "Unary",
    "evaluate",
    "format_expr",
    "parse_script",
    "raw_attr_value",
    "script_error_loc",
    "script_truth",
    "variables_read",
    "variables_written",
    "walk",
]
