"""The BehaviorTree.CPP versions btgen implements, and every difference between them.

btgen follows one release of the library exactly: 4.6.2 (the default) or 4.10.0
(``--btcpp 4.10.0``). Every way in which the two behave differently is one named
switch of :class:`Semantics`, listed here with the release that made it; the
interpreter (``interp/``), the loader (``frontend/``), the script parser
(``lang/script/``) and the generated C++ (one ``constexpr bool`` per switch in
the header, read by ``runtime/include/btgen/engine.hpp``) read these switches and
nothing else. A reader can list every difference from this file; the prose, with
the library quirks btgen follows, is ``docs/btcpp-versions.md``.

The switches are facts recorded on the real library (the conformance cases of
``tests/conformance/btcpp-4.10.0/`` show each one, with a case where the rule
holds on both versions).
"""

from __future__ import annotations

from dataclasses import dataclass, fields

DEFAULT_VERSION = "4.6.2"
SUPPORTED_VERSIONS = ("4.6.2", "4.10.0")


@dataclass(frozen=True)
class Semantics:
    """The behaviour of one BehaviorTree.CPP release, as named switches.

    Each field is False in 4.6.2 and True in 4.10.0; its comment names the
    release (and upstream commit) that changed it."""

    version: str

    # ---------------------------------------------------------------- node semantics
    # Sequence, SequenceWithMemory, Fallback, AsyncSequence/AsyncFallback return SKIPPED
    # when every child was skipped in this run (a counter), not by 4.6.2's sticky flag that
    # any non-skipped result clears (4.7.0 957a7f88, 4.7.2 689fb9f1).
    skipped_by_count: bool = False
    # Repeat and RetryUntilSuccessful end their loop with SUCCESS / FAILURE, never SKIPPED
    # (4.6.2: SKIPPED when the loop never ran a child, e.g. num_cycles="0") (4.7.0 957a7f88).
    loop_end_never_skipped: bool = False
    # RetryUntilSuccessful reads num_attempts again after every child FAILURE (4.7.0 17a9c35c).
    retry_rereads_attempts: bool = False
    # Precondition evaluates `if` only until its child has started, then ticks the child
    # until it completes (4.6.2: every tick, returning `else` without halting the child)
    # (4.7.0 5f3f6756).
    precondition_if_until_started: bool = False
    # SetBlackboard converts a string (literal or copied) with the destination entry's own
    # converter; an entry without one (created untyped) is left empty and typed BT::Any (then
    # a string stored there by SetBlackboard or a Script throws), and copying an empty entry
    # returns FAILURE (4.7.0 3651a242).
    setblackboard_converts_to_entry_type: bool = False
    # Loop nodes: `queue` is an untyped port; a blackboard string is converted into a
    # private queue at each start, a vector is accepted (4.9.0 c36bd4d6, 4.9.1 f42cd38b).
    loop_queue_untyped: bool = False
    # Switch matches a case only when the whole text parses as a number (4.10.0 a49a047f).
    switch_whole_parse: bool = False
    # SubTree literal ports are stored as int / double when the whole text is one
    # (4.9.1 5e5f65b9).
    subtree_literals_typed: bool = False
    # An integer converted to double fails beyond 2^53-1, exact or not (4.7.0 7704d94e).
    int_to_double_53_bits: bool = False
    # convertFromString<double> is std::from_chars: no leading blank, no `+`, no hex
    # (4.9.0 d1983321; 4.6.2: std::stod).
    double_from_chars: bool = False
    # TryCatch is a built-in control node (4.9.0 b8f27152).
    trycatch: bool = False
    # Blackboard::set<bool>(false) into an entry typed int throws (isCastingSafe refuses it;
    # `true`, and either into a double entry, are accepted) (recorded on 4.10.0:
    # tests/conformance/typed-writes/loop_int_then_bool_*; the commit is not identified).
    false_into_int_unsafe: bool = False

    # ---------------------------------------------------------------- monitoring
    # A Groot2 BLACKBOARD reply that dumps a SubTree's blackboard also holds the root
    # blackboard (the main tree's) under the key `ROOT` (4.10.0 ce95461e).
    groot2_root_blackboard: bool = False

    # ---------------------------------------------------------------- scripts
    # The 4.9.0 script parser (d1983321): `&&` above `||`, `..` with `+`/`-`, true/false
    # doubles, optional `;`, no double quotes, no unary `+`, every operator group mixed by
    # precedence, ternaries nested in the else branch, names starting with true/false.
    script_grammar_49: bool = False

    # ---------------------------------------------------------------- loading
    # Tree, SubTree and model IDs: no blanks, < > & " ' / \ : * ? | . or control
    # characters, not `Root` (4.8.4 8f86eb99).
    name_validation_484: bool = False
    # Attributes that are not valid port names (e.g. containing `.`) are ignored rather
    # than refused as unknown ports (4.7.0 48f6c5bd, 4.8.4 8f86eb99).
    attribute_names_484: bool = False
    # Two SubTree nodes with the same path (same `name` in one tree instance) are refused
    # (4.8.4 3e8c2928).
    unique_subtree_paths: bool = False
    # A ReactiveSequence refuses children written <Action ID=..>/<Condition ID=..> and more
    # than one AsyncSequence child (4.7.0 b2fc82c8, d4d8ae13).
    reactive_sequence_child_checks: bool = False

    # ---------------------------------------------------------------- Groot2 monitor
    # Groot2 hooks with position 1 (POST) are kept apart from PRE ones and run after the
    # node's tick (its post-conditions included), even when a pre-condition decided: a
    # SUCCESS or FAILURE they give replaces the node's result. HOOK_REMOVE,
    # BREAKPOINT_UNLOCK, HOOKS_DUMP (PRE hooks, then POST) and DISABLE_ALL_HOOKS see them.
    # (4.6.2 files every hook as PRE.) (4.10.0 6fe6dcdf; runtime/include/btgen/groot2.hpp)
    groot2_post_hooks: bool = False
    # A HOOK_INSERT array with a bad hook in it keeps the hooks before it (4.10.0 answers
    # the exception's message; 4.6.2's server thread terminates the process) (4.10.0
    # 6fe6dcdf).
    groot2_insert_until_error: bool = False


_BY_VERSION = {
    "4.6.2": Semantics("4.6.2"),
    "4.10.0": Semantics("4.10.0", **{f.name: True for f in fields(Semantics) if f.name != "version"}),
}

# The release that made each switch, for messages (upgrade-check, validate warnings).
SINCE = {
    "skipped_by_count": "4.7.0",
    "loop_end_never_skipped": "4.7.0",
    "retry_rereads_attempts": "4.7.0",
    "precondition_if_until_started": "4.7.0",
    "setblackboard_converts_to_entry_type": "4.7.0",
    "loop_queue_untyped": "4.9.1",
    "switch_whole_parse": "4.10.0",
    "subtree_literals_typed": "4.9.1",
    "int_to_double_53_bits": "4.7.0",
    "double_from_chars": "4.9.0",
    "trycatch": "4.9.0",
    "false_into_int_unsafe": "4.10.0",
    "groot2_root_blackboard": "4.10.0",
    "script_grammar_49": "4.9.0",
    "name_validation_484": "4.8.4",
    "attribute_names_484": "4.8.4",
    "unique_subtree_paths": "4.8.4",
    "reactive_sequence_child_checks": "4.7.0",
    "groot2_post_hooks": "4.10.0",
    "groot2_insert_until_error": "4.10.0",
}
assert set(SINCE) == {f.name for f in fields(Semantics)} - {"version"}


def semantics(version: str = DEFAULT_VERSION) -> Semantics:
    """The switches of a supported version; ValueError for any other."""
    try:
        return _BY_VERSION[version]
    except KeyError:
        raise ValueError(
            f"unsupported BehaviorTree.CPP version `{version}` (supported: {', '.join(SUPPORTED_VERSIONS)})"
        ) from None


def switch_names() -> tuple[str, ...]:
    """Every switch, in declaration order (the C++ header gets one constexpr each)."""
    return tuple(f.name for f in fields(Semantics) if f.name != "version")


def version_number(version: str) -> int:
    """4.10.0 -> 41000: the constant of the generated header and the runtime."""
    major, minor, patch = (int(x) for x in version.split("."))
    return major * 10000 + minor * 100 + patch


def at_release(version: str) -> Semantics:
    """The switches of a release between 4.6.2 and 4.10.0 that btgen does not implement as
    such (4.8.2, whose Python bindings `behaviortreepy` runs in CI): every switch made by
    that release or an earlier one (SINCE) is on. Only as exact as SINCE: a change of that
    release that is no switch (none is known) is not in it. For comparisons, never for
    `--btcpp`."""
    key = version_number(version)
    if not version_number(DEFAULT_VERSION) <= key <= version_number(SUPPORTED_VERSIONS[-1]):
        raise ValueError(f"`{version}` is not between {DEFAULT_VERSION} and {SUPPORTED_VERSIONS[-1]}")
    on = {name: version_number(since) <= key for name, since in SINCE.items()}
    return Semantics(version, **on)
