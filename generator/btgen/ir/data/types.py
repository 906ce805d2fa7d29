"""Step 3 of the data analysis: the kind of every slot."""

from __future__ import annotations

from btgen.ir.data.resolve import Analysis
from btgen.ir.data.state import Slot
from btgen.ir.kinds import DYN, describe_kind, is_queue, is_user
from btgen.lang import values


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
            s.kind = "string" if s.entry.type_name == values.STRING else "none"
            s.origin = s.origin or "never written"
    undecided = [i for i, s in enumerate(a.slots) if s.kind is None]
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
            if k is not None and k not in ("none", "error"):
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
                if k is not None and k not in ("none", "error"):
                    s.kind = k
                    s.origin = f"first written by {w.what}"
                    s.origin_loc = w.loc
                    changed = True
                    break
    for s in a.slots:
        if s.kind is not None:
            continue
        w = min(s.writes, key=lambda x: x.order)
        if any(x.determining and x.kind() in ("none", "error") for x in s.writes):
            s.kind = "none"  # a script that fails whatever runs: compiling it says why
            continue
        if all(x.source == "port" for x in s.writes):
            # Robot code writes it through untyped ports only (as TreeNodesModel files
            # exported by Groot2 often have them): it holds text.
            s.kind = "string"
            s.origin = "no declared type, written by untyped ports only: it holds text"
            s.origin_loc = None
            s.untyped_text = True
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
        s.kind = "string"
    mark_dynamic(a)


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
            if (
                s.kind == DYN
                or s.failed
                or s.entry.type_name != values.ANY
                or s.initial is not None
                or s.untyped_text
                or s.kind is None
                or is_queue(s.kind)
                or (s.kind == "none" and not s.writes)
                or is_user(s.kind)
            ):  # (a user type's entry: other writes are errors, reported as such)
                continue
            for w in s.writes:
                if w.source in ("port", "loop"):
                    continue
                k = w.kind()
                if k is None or k in ("none", "error") or is_queue(k):
                    continue
                if s.kind == "none" and k != DYN:
                    continue  # (a script that fails whatever runs: compiling it says why)
                if (
                    k == DYN
                    or (k == "string") != (s.kind == "string")
                    or (k == "status") != (s.kind == "status")
                    or (w.source == "copy" and k != s.kind)
                ):
                    # (a SetBlackboard copy is set<Any>: it replaces an untyped entry's value with the
                    # source's, an integer stays an integer in a double entry)
                    s.kind = DYN
                    s.origin = f"its type changes at run time ({w.what} writes {describe_kind(k)})"
                    s.origin_loc = w.loc
                    changed = True
                    break


def _mark_typed_number_dynamic(a: Analysis, s: Slot) -> None:
    """A typed number entry (a port declared it `int` or `double`) that a script may give
    its first value with the other kind of number (`speed := 1` for a double port): 4.6.2's
    Any::copyInto into the empty entry stores the value as it is, so the entry then holds
    an integer (and converts later writes to integers). Its slot is dynamic so the C++
    engine follows (it stopped with "would store an integer in the empty entry")."""
    if (
        s.kind not in ("int", "double")
        or s.failed
        or s.initial is not None
        or a.kind_of_type(s.entry.type_name) != s.kind
    ):
        return
    kinds = [w.kind() for w in s.writes]
    if any(k not in ("int", "double", None) for k in kinds):
        return  # (strings go through the declared type's converter: a static slot does that)
    for w, k in zip(s.writes, kinds):
        if w.source == "script" and w.determining and k in ("int", "double") and k != s.kind:
            s.kind = DYN
            s.origin = (
                f"4.6.2 stores the other kind of number as it is in the empty entry ({w.what} writes "
                f"{describe_kind(k)})"
            )
            s.origin_loc = w.loc
            return
