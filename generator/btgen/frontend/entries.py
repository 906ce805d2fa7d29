"""Blackboard entries the application provides: set from C++ before the first tick.

A program often writes entries into the blackboard before it ticks the tree (Nav2 writes
`node`, `server_timeout`, `bt_loop_duration` and `wait_for_service_timeout` into every
tree's blackboard); scripts and ports then read them. btgen cannot see that C++, so it is
declared: ``--entry NAME=TYPE`` on the root blackboard (the main tree's), ``--entry
TREE:NAME=TYPE`` on the blackboard of every instance of BehaviorTree TREE. Both engines
create the entry, with that type and no value, when they create that blackboard; the
generated mission has a setter for each (``provide_<member>()``), and the application sets
it before the first tick. TYPE is a TreeNodesModel type (``int``, ``double``, ``bool``,
``std::string``, a ``--type`` user type, ...); a type that is neither built in nor declared with
``--type`` (``rclcpp::Node::SharedPtr``) is an error: btgen would have to hold it as text.
"""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Collection, Sequence

from btgen.diagnostics import Diagnostic, Loc, UserError, suggestion
from btgen.lang import blackboard, values
from btgen.lang.model import Mission, ProvidedEntry

_KEY = re.compile(r"[A-Za-z_][A-Za-z0-9_.\-]*\Z")


def load(declarations: Sequence[str], user_types: Collection[str] = ()) -> tuple[ProvidedEntry, ...]:
    """The `--entry` declarations; UserError (at `--entry:1:column`) when one does not parse,
    one entry is declared twice with different types, or one has a type btgen cannot hold:
    not built in, and not among `user_types` (the names `--type` declares, as
    values.normalize_type gives them)."""
    out: dict[tuple[str, str], ProvidedEntry] = {}
    problems: list[Diagnostic] = []
    for text in declarations:
        head, eq, type_text = text.partition("=")
        tree, colon, key = head.rpartition(":") if ":" in head else ("", "", head)
        if not eq or not type_text.strip():
            problems.append(
                Diagnostic(
                    Loc("--entry", 1, 1),
                    f"`{text}` is not an entry declaration: write NAME=TYPE or TREE:NAME=TYPE "
                    f"(for example server_timeout=int)",
                )
            )
            continue
        if not _KEY.match(key):
            problems.append(
                Diagnostic(
                    Loc("--entry", 1, len(tree) + len(colon) + 1),
                    f"`{key}` is not a blackboard key (letters, digits, `_`, `.`, `-`, not starting with a digit)",
                )
            )
            continue
        if colon and not tree.strip():
            problems.append(Diagnostic(Loc("--entry", 1, 1), f"`{text}`: the tree before `:` is empty"))
            continue
        entry = ProvidedEntry(tree or None, key, values.normalize_type(type_text.strip()))
        if values.is_opaque_type(entry.type) and entry.type not in user_types:
            problems.append(Diagnostic(Loc("--entry", 1, len(head) + 2), unheld_message(key, type_text.strip())))
            continue
        before = out.get((tree, key))
        if before is not None and before.type != entry.type:
            problems.append(
                Diagnostic(
                    Loc("--entry", 1, len(head) + 2),
                    f"entry `{key}` is declared as {before.type} and as {entry.type}",
                )
            )
            continue
        out[(tree, key)] = entry
    if problems:
        raise UserError(problems)
    return tuple(out.values())


def unheld_message(key: str, type_text: str) -> str:
    """Why an entry of a type that is neither built in nor declared cannot be provided, and what to do."""
    name = values.normalize_type(type_text)
    return (
        f"btgen cannot hold entry `{key}` of type `{type_text}`: it is not built in (int, unsigned, double, "
        f"bool, std::string, BT::NodeStatus, a queue) and no --type declares it; declare the C++ type with "
        f"--type {name}=CPP_TYPE@HEADER (any default-constructible, copyable type: a struct, a ROS message, "
        f"a std::shared_ptr), or give the entry a built-in type"
    )


def apply(mission: Mission, provided: tuple[ProvidedEntry, ...]) -> Mission:
    """The mission with the entries the application provides; UserError for a tree that the
    mission does not have."""
    if not provided:
        return mission
    ids = [t.id for t in mission.trees]
    problems = [
        Diagnostic(
            Loc("--entry", 1, 1),
            f"--entry {p.tree}:{p.key}: the mission has no BehaviorTree `{p.tree}`{suggestion(p.tree, ids)}",
        )
        for p in provided
        if p.tree is not None and p.tree not in ids
    ]
    if problems:
        raise UserError(problems)
    mission = dataclasses.replace(mission, provided=provided)
    # The root blackboard gets the main tree's entries and the root ones (`--entry
    # Patrol:timeout=int --entry timeout=string` with Patrol the main tree): two types of one
    # entry there are refused here, where every command loads the mission, with the words and
    # place of the data analysis (ir/data/resolve.py), which only some commands run.
    root = blackboard.Blackboard()
    for p in provided:
        if p.applies_to(mission.main_tree, True):
            try:
                root.create_entry(p.key, p.type)
            except blackboard.BlackboardError as e:
                problems.append(Diagnostic(mission.main.loc, f"{p.option}: {e}"))
    if problems:
        raise UserError(problems)
    return mission
