"""Step 3 of the data analysis: the kind of every slot."""

from __future__ import annotations

import re
from typing import Optional

from btgen.ir.data.resolve import Analysis
from btgen.ir.data.state import Slot, Write
from btgen.ir.kinds import DOUBLE, DYN, INT, NONE, STATUS, STRING, describe_kind, is_queue, is_user
from btgen.lang import values
from btgen.lang.blackboard import RAW_COPY_TYPES

# A script's update of an entry, as a Write names it ("`x += 1` in `code` of ...").
_COMPOUND = re.compile(r"^`[^`]*? (\+=|-=|\*=|/=) ")


# ------------------------------------------------------------ 3. kinds
def type_slots(a: Analysis) -> None:
    for s in a.slots:
        # A `string` entry is no constraint in 4.6.2: a script may store a number in it, and
        # string ports read numbers as text. Its type comes from its writes, as for `any`.
        declared = s.entry.type_name
        s.kind = a.kind_of_type(declared) if declared != values.STRING else None
        if s.kind is not None and not s.origin:
            s.origin = f"declared {declared}"
    # Entries nothing writes: reading them gives no value. Decided first, so an entry written
    # from one (`x := @missing + 1`) gets a kind and only the real error is reported.
    for s in a.slots:
        if s.kind is None and not s.writes:
            s.kind = STRING if s.entry.type_name == values.STRING else NONE
            s.origin = s.origin or "never written"
    undecided = [i for i, s in enumerate(a.slots) if s.kind is None]
    _propagate(a, undecided)
    # Entries robot code writes through untyped ports only (as TreeNodesModel files exported by
    # Groot2 often have them) hold text; decided before the copies of them are given up on
    # (`full_path := dir_path + tag_name`, tag_name an untyped port's entry), then propagated.
    for i in undecided:
        s = a.slots[i]
        if s.kind is None and all(x.source == "port" for x in s.writes):
            s.kind = STRING
            s.origin = "no declared type, written by untyped ports only: it holds text"
            s.origin_loc = None
            s.untyped_text = True
    _propagate(a, undecided)
    for s in a.slots:
        if s.kind is not None:
            continue
        w = min(s.writes, key=lambda x: x.order)
        if any(x.determining and x.kind() in (NONE, "error") for x in s.writes):
            s.kind = NONE  # a script that fails whatever runs: compiling it says why
            continue
        if not s.at_load and all(x.source == "script" and _COMPOUND.match(x.what) for x in s.writes):
            # Only updated (`x += 1`) and never created: the library loads it, and the script
            # throws where it runs ("does not exist yet"), as both engines do: said, not refused.
            a.run_time(
                w.loc,
                f"blackboard entry `{s.key}` is only updated ({w.what}), never given a first "
                f"value, so it never has one; initialize it first (e.g. `{s.key} := 0`)",
            )
            s.kind = NONE
            s.origin = "only updated, never created"
            continue
        s.failed = True
        if any(x.determining for x in s.writes):
            a.error(
                w.loc,
                f"cannot tell the type of blackboard entry `{s.key}`: every write copies "
                f"another entry of unknown type; write it with a literal first",
            )
        elif all(x.source == "script" for x in s.writes):
            a.error(
                w.loc,
                f"blackboard entry `{s.key}` is only updated ({w.what}), never given a first "
                f"value, so it never has one; initialize it first (e.g. `{s.key} := 0`)",
            )
        else:
            a.error(
                w.loc,
                f"cannot tell the type of blackboard entry `{s.key}`: {w.what} writes it, but "
                f"the port has no type; give the port a type in TreeNodesModel (e.g. "
                f'type="std::string")',
            )
        s.kind = STRING
    mark_dynamic(a)


def _propagate(a: Analysis, undecided: list[int]) -> None:
    """Each undecided slot's kind from its first determining write whose kind is known."""
    changed = True
    while changed:
        changed = False
        for i in undecided:
            s = a.slots[i]
            if s.kind is not None:
                continue
            det = sorted((w for w in s.writes if w.determining), key=lambda w: w.order)
            if not det:
                continue
            k = det[0].kind()
            if k is not None and k not in (NONE, "error"):
                s.kind = k
                s.origin = f"first written by {det[0].what}"
                s.origin_loc = det[0].loc
                changed = True
    # Cycles (`a := b; b := a` and no other first write): the first write whose kind is known.
    changed = True
    while changed:
        changed = False
        for i in undecided:
            s = a.slots[i]
            if s.kind is not None:
                continue
            for w in sorted((w for w in s.writes if w.determining), key=lambda w: w.order):
                k = w.kind()
                if k is not None and k not in (NONE, "error"):
                    s.kind = k
                    s.origin = f"first written by {w.what}"
                    s.origin_loc = w.loc
                    changed = True
                    break


def mark_dynamic(a: Analysis) -> None:
    """Entries whose type 4.6.2 changes at run time get a dynamic slot (btgen::Dyn).

    Only entries no typed port declared (`any`) can change their type: a write of
    another kind than the entry's (a SetBlackboard literal into an integer entry, a
    string assigned to an entry a script made a number, a copy of such an entry) makes
    it dynamic, and so does a write of a dynamic value; expressions over it are then
    dynamic too, so this runs until nothing changes. Numbers of two kinds (integer and
    double) written by scripts are conversions, not type changes: those entries stay
    static; a SetBlackboard copy of another kind of number replaces the value's type."""
    for s in a.slots:
        _mark_typed_number_dynamic(a, s)
    changed = True
    while changed:
        changed = False
        for s in a.slots:
            if _mark_typed_copy_dynamic(a, s):
                changed = True
                continue
            if (
                s.kind == DYN
                or s.failed
                or s.entry.type_name != values.ANY
                or s.initial is not None
                or s.untyped_text
                or s.kind is None
                or is_queue(s.kind)
                or (s.kind == NONE and not s.writes)
                or is_user(s.kind)
            ):  # (a user type's entry: other writes are errors, reported as such)
                continue
            typed = _typed_write_change(s)
            if typed is not None:
                s.kind = DYN
                s.origin = f"its type changes at run time ({typed.what} writes {typed.type_name})"
                s.origin_loc = typed.loc
                changed = True
                continue
            for w in s.writes:
                if w.source in ("port", "loop"):
                    continue
                k = w.kind()
                if k is None or k in (NONE, "error") or is_queue(k):
                    continue
                if s.kind == NONE and k != DYN:
                    continue  # (a script that fails whatever runs: compiling it says why)
                if (
                    k == DYN
                    or (k == STRING) != (s.kind == STRING)
                    or (k == STATUS) != (s.kind == STATUS)
                    or (w.source == "copy" and k != s.kind)
                ):
                    # (a SetBlackboard copy is set<Any>: it replaces an untyped entry's value with the
                    # source's, an integer stays an integer in a double entry)
                    s.kind = DYN
                    s.origin = f"its type changes at run time ({w.what} writes {describe_kind(k)})"
                    s.origin_loc = w.loc
                    changed = True
                    break


# The types of a Blackboard::set<T> (a Loop's `value`, a node's output port) that the C++
# back end follows into an entry whose type changes at run time (btgen::port::write of a Dyn
# slot, btgen::Dyn::typed; ir/data/operations.py refuses the others).
TYPED_WRITE_TYPES = (values.INT, values.DOUBLE, values.BOOL, values.STRING)


def _typed_write_change(s: Slot) -> Optional[Write]:
    """A typed write into an entry no port declared that changes its type: Blackboard::set<T>
    gives the entry the type T, and a write of another kind (a LoopDouble into an entry
    scripts give integers), or a typed write of another T (a LoopBool and a LoopInt), then
    converts or throws by that type. The write, or None."""
    typed = [w for w in s.writes if w.source in ("port", "loop") and w.type_name in TYPED_WRITE_TYPES]
    if not typed:
        return None
    for w in typed:
        if w.type_name != typed[0].type_name:
            return w
    for w in s.writes:
        k = w.kind()
        if k is None or k in (NONE, "error") or is_queue(k):
            continue
        if k != s.kind or k == DYN:
            return w if w in typed else typed[0]
    return None


def _mark_typed_number_dynamic(a: Analysis, s: Slot) -> None:
    """A typed number entry (a port declared it `int` or `double`) that a script may give
    its first value with the other kind of number (`speed := 1` for a double port): 4.6.2's
    Any::copyInto into the empty entry stores the value as it is, so the entry then holds
    an integer (and converts later writes to integers). Its slot is dynamic so the C++
    engine follows (it stopped with "would store an integer in the empty entry")."""
    if s.kind not in (INT, DOUBLE) or s.failed or s.initial is not None or a.kind_of_type(s.entry.type_name) != s.kind:
        return
    kinds = [w.kind() for w in s.writes]
    # (from 4.7.0 a SetBlackboard copy of a string or of a value of changing type converts it or
    # must have the entry's type: btgen::port::set_dyn_typed_410 follows that into a Dyn slot)
    converted = a.m.semantics.setblackboard_converts_to_entry_type
    if any(
        k not in (INT, DOUBLE, None) and not (converted and w.source == "copy" and k in (STRING, DYN))
        for w, k in zip(s.writes, kinds)
    ):
        return  # (strings go through the declared type's converter: a static slot does that)
    for w, k in zip(s.writes, kinds):
        if w.source == "script" and w.determining and k in (INT, DOUBLE) and k != s.kind:
            s.kind = DYN
            s.origin = (
                f"4.6.2 stores the other kind of number as it is in the empty entry ({w.what} writes "
                f"{describe_kind(k)})"
            )
            s.origin_loc = w.loc
            return


def _mark_typed_copy_dynamic(a: Analysis, s: Slot) -> bool:
    """A typed int, unsigned, double or bool entry that a 4.6.2 SetBlackboard copies a string
    (or a value of changing type) into: 4.6.2 copies the value as it is (`dst_entry->value =
    src_entry->value`), so the entry keeps its declared type and holds the string. Its slot
    is dynamic; its other writes must be copies, writes of its own type by ports (a typed
    write into it is then Blackboard::set<T>'s copyInto, btgen::port::write of a Dyn slot)
    or scripts (whose strings still go through the declared type's converter:
    btgen::port::store_declared).
    True when the slot became dynamic."""
    declared = s.entry.type_name
    if (
        a.m.semantics.setblackboard_converts_to_entry_type
        or s.kind == DYN
        or s.failed
        or s.initial is not None
        or declared not in RAW_COPY_TYPES
        or s.kind != a.kind_of_type(declared)
    ):
        return False
    # (a number of another kind is copied as it is too: an integer into a `double` entry, any
    # integer into an `unsigned` or `bool` one)
    copied = [
        w
        for w in s.writes
        if w.source == "copy"
        and (
            w.kind() in (STRING, DYN)
            or (w.kind() in (INT, DOUBLE) and w.kind() != s.kind)
            or (w.kind() == INT and declared in (values.UNSIGNED, values.BOOL))
        )
    ]
    if not copied or any(w.source not in ("copy", "loop", "port", "script") for w in s.writes):
        return False
    s.kind = DYN
    s.origin = (
        f"4.6.2's SetBlackboard copies a string into it as it is ({copied[0].what} writes "
        f"{describe_kind(copied[0].kind() or DYN)})"
    )
    s.origin_loc = copied[0].loc
    return True
