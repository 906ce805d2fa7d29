"""What the Promela model does not translate: a located error (every module of the model raises it)."""

from __future__ import annotations

from btgen.diagnostics import Diagnostic, Loc, UserError


class Refusal(UserError):
    """The mission uses something the model does not translate (a located error)."""


def refuse(loc: Loc, message: str) -> Refusal:
    return Refusal(Diagnostic(loc, message))
