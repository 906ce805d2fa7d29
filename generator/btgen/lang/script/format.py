"""A script expression as text, fully parenthesized (for tests and messages)."""

from __future__ import annotations

from btgen.lang.script.nodes import Binary, Compare, Expr, Literal, Name, Ternary, Unary


def format_expr(node: Expr) -> str:
    """The expression fully parenthesized, e.g. ``((a - b) + c)``; for tests and messages."""
    if isinstance(node, Literal):
        return node.text
    if isinstance(node, Name):
        return node.name
    if isinstance(node, Unary):
        return f"{node.op}{format_expr(node.operand)}"
    if isinstance(node, Binary):
        return f"({format_expr(node.left)} {node.op} {format_expr(node.right)})"
    if isinstance(node, Compare):
        parts = [format_expr(node.operands[0])]
        for op, o in zip(node.ops, node.operands[1:]):
            parts += [op, format_expr(o)]
        return "(" + " ".join(parts) + ")"
    if isinstance(node, Ternary):
        return f"({format_expr(node.cond)} ? {format_expr(node.then)} : {format_expr(node.orelse)})"
    return f"({node.target} {node.op} {format_expr(node.value)})"
