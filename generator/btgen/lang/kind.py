"""Kinds as values: the static kind of a blackboard entry or of a script expression.

The typing rules over kinds are in ir/kinds.py; this module only defines the values, so that
the front end (usertypes.py) can name a user type's kind without importing the IR.

    Scalar     int, double, bool, status, string, dyn, none (a `str` Enum: each member is its text)
    QueueKind  the entries of Loop nodes: a queue of int, double, bool or string values
    UserKind   a user port type (`--type`), by its name with blanks around `<>,:*&` removed

`render` gives a kind's text (`int`, `queue<int>`, `user:Pose2D`) where a string is needed.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum
from typing import Union


class Scalar(str, Enum):
    """A kind without parts; each member equals (and hashes as) its text, and prints as it."""

    INT = "int"
    DOUBLE = "double"
    BOOL = "bool"  # only in conversions: bool entries hold integers, as 4.6.2's Any does
    STATUS = "status"
    STRING = "string"
    DYN = "dyn"  # a value whose type changes at run time
    NONE = "none"  # no value ever (`1 .. 2`, an entry nothing writes)

    def __str__(self) -> str:
        return self.value

    def __format__(self, spec: str) -> str:
        return format(self.value, spec)


@dataclass(frozen=True)
class QueueKind:
    """A queue of `element` values (Scalar.INT, DOUBLE, BOOL or STRING)."""

    element: Scalar

    def __str__(self) -> str:
        return f"queue<{self.element}>"


@dataclass(frozen=True)
class UserKind:
    """The kind of the entries of a user port type: `name` is the type's compact name."""

    name: str

    def __str__(self) -> str:
        return f"user:{self.name}"


Kind = Union[Scalar, QueueKind, UserKind]
# While some code still writes scalar kinds as their text ("int" == Scalar.INT): what the
# typing functions accept.
KindLike = Union[str, QueueKind, UserKind]


def render(kind: KindLike) -> str:
    """A kind's text: `int`, `queue<int>`, `user:Pose2D`."""
    return str(kind)
