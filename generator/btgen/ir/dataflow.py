"""The data side of a mission, resolved at compile time.

BehaviorTree.CPP 4.6.2 keeps one blackboard per tree instance, a map from
key to a type-erased entry, and finds entries by string at run time
through SubTree remappings, `_autoremap` and `@` root keys. btgen does all
of that here, once, in the steps below; `analyze` runs them, each in its module of
ir/data/ (records.py holds the output, DataIR; state.py the records the steps share):

1. **Load** (data/resolve.py). The main tree is instantiated the way 4.6.2's XML loader does
   it, with the reference blackboard (blackboard.py): a blackboard per
   SubTree instance (remappings, constants, model defaults), and every
   `{key}` port creating its entry with the port's type, in creation order.
   Type clashes 4.6.2 throws for at load time are errors here.
2. **Resolve** (data/resolve.py). Every key any node reads or writes (ports, scripts,
   SetBlackboard, UnsetBlackboard, WasEntryUpdated, ...) is looked up from
   the node's blackboard as 4.6.2 would look it up at run time; an entry
   4.6.2 would create at run time is created where it would land. Each
   distinct entry is one *slot* of the generated Blackboard struct.
3. **Type** (data/types.py). A slot whose entry has a declared type (a typed port created
   it) holds that type. Any other slot takes the type of what writes it:
   the first write in creation order that does not need a value already
   (so not `x += 1` nor `x := x + 1`). Writes of another type that 4.6.2
   would convert are compiled as conversions; writes that would fail, or
   change the entry's type, whenever they run are errors naming both sides.
4. **Size** (data/size.py). Strings and queues get fixed capacities: the longest value the
   writes can produce (literals, concatenations of bounded parts), at most
   the mission's string capacity (`--string-capacity`, default 128); a
   slot written by robot code or growing without bound gets that capacity.
5. **Decide** (data/operations.py). Scripts are typed (script_types.py); ports, SetBlackboard,
   UnsetBlackboard, Switch cases, Loop queues and the entry-update nodes
   become ir/dataops.py records over the slots (DataIR), which the back end
   writes as C++.
"""

from __future__ import annotations

from typing import Optional

from btgen.diagnostics import DiagnosticSink
from btgen.ir.data.operations import Compiler
from btgen.ir.data.records import DataIR, DataOptions
from btgen.ir.data.resolve import Analysis
from btgen.ir.data.size import size_slots
from btgen.ir.data.types import type_slots
from btgen.ir.numbering import Numbering
from btgen.lang.model import Mission


def analyze(
    mission: Mission, options: Optional[DataOptions] = None, numbering: Optional[Numbering] = None
) -> tuple[DataIR, DiagnosticSink]:
    """The data side of `mission`'s main tree, with the diagnostics found (errors make it unusable).
    `numbering`: the mission's node numbering (ir/numbering.py), when the caller has it."""
    a = Analysis(mission, options or DataOptions(), numbering)
    a.load()
    a.collect()
    a.find_owners()
    type_slots(a)
    size_slots(a)
    ir = Compiler(a).run()
    return ir, a.sink
