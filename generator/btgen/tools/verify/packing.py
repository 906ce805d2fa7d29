"""The model's state vector in the fewest bits: statuses and counters as Promela `unsigned` bit fields.

pan stores a state as the bytes of its global variables; SPIN packs `bit` and `unsigned x : k`
variables into bit fields. A node's status temporaries (0..4) take 3 bits instead of a byte, a
Sequence's child index the bits of its number of children, a RUNNING counter the bits of
--running-bound, a Repeat's count the bits of num_cycles. Only variables whose range is known
here are packed: a value past its width would be cut silently by pan, so every width is the
largest value the emitter writes.
"""

from __future__ import annotations

import re
from collections.abc import Collection, Sequence

from btgen.ir.lower import IRNode

STATUS_BITS = 3  # IDLE, RUNNING, SUCCESS, FAILURE, SKIPPED
# per-node variables that hold a status (a child's result, a child's status before its tick),
# in the node kinds whose emitters write nothing else into them
_STATUS_VARS = ("cs", "prv", "ret")
# the kinds whose child counters (idx, skp, k, j) run from 0 to their number of children
_COUNTING = frozenset(
    {
        "Sequence",
        "AsyncSequence",
        "Fallback",
        "AsyncFallback",
        "SequenceWithMemory",
        "ReactiveSequence",
        "ReactiveFallback",
        "TryCatch",
    }
)
STATUS_KINDS = _COUNTING | {
    "Parallel",
    "ParallelAll",
    "IfThenElse",
    "WhileDoElse",
    "Inverter",
    "ForceSuccess",
    "ForceFailure",
    "Repeat",
    "RetryUntilSuccessful",
    "KeepRunningUntilFailure",
    "RunOnce",
    "Timeout",
    "Delay",
    "SubTree",
    "PipelineSequence",
    "RecoveryNode",
    "RoundRobin",
}


def bits(most: int) -> int:
    """The bits of an unsigned variable whose values are 0..most."""
    return max(1, most.bit_length())


def widths(
    nodes: Sequence[IRNode], rc: dict[int, int], fb: dict[int, int], counts_read: Collection[int] = ()
) -> dict[str, int]:
    """name -> bits of every variable packed: the status temporaries of STATUS_KINDS, the
    child counters of the Sequences, Fallbacks, reactive ones and TryCatch, and the RUNNING and
    FAILURE counters of the bounded leaves (node -> bound). A Repeat's or Retry's count read
    from the blackboard (`counts_read`) has no literal bound here: its counter stays an int."""
    out: dict[str, int] = {}
    for n in nodes:
        i = n.index
        if n.kind in STATUS_KINDS:
            for v in _STATUS_VARS:
                out[f"{v}{i}"] = STATUS_BITS
        if n.kind in _COUNTING:
            for v in ("idx", "skp", "k", "j"):
                out[f"{v}{i}"] = bits(len(n.children))
        if n.kind in ("Repeat", "RetryUntilSuccessful") and n.params[0] >= 0 and i not in counts_read:
            out[f"cnt{i}"] = bits(n.params[0])  # counts up to num_cycles / num_attempts
    for i, most in rc.items():
        out[f"rc{i}"] = bits(most)
    for i, most in fb.items():
        out[f"fb{i}"] = bits(most)
    return out


def pack(text: str, packed: dict[str, int], ticks: int | None) -> str:
    """The model with the `byte NAME;` / `int NAME;` declarations of `packed` as bit fields, and
    the tick counter in the bits of --ticks.

    The status array `st` stays an array of bytes: as scalars SPIN's dead variable elimination
    (on unless `spin -o2`) treats them as the one process's own and resets them where it thinks
    them dead, and the `@S` tick-end statuses (printf) then differ from explore's (measured on
    a random `control` mission: 61 tick-end states against explore's 77)."""
    out = []
    for line in text.split("\n"):
        m = re.fullmatch(r"(?:byte|int) ([a-z]+[0-9]+);", line)
        if m and m.group(1) in packed:
            out.append(f"unsigned {m.group(1)} : {packed[m.group(1)]};")
        elif line == "int ticks;" and ticks is not None:
            out.append(f"unsigned ticks : {bits(ticks)};")
        else:
            out.append(line)
    return "\n".join(out)
