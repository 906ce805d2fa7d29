"""The interpreter's node base: statuses, the run context, ports and 4.6.2's ``TreeNode``
(pre/post conditions, status changes and the trace they write)."""

from __future__ import annotations

from typing import Callable, Optional

from btgen.diagnostics import Diagnostic, Loc, UserError
from btgen.interp.scenario import Scenario
from btgen.lang import blackboard as bbmod
from btgen.lang import script as scriptmod
from btgen.lang import values
from btgen.lang.catalogue import PortSpec
from btgen.lang.model import Attr, Mission, Node
from btgen.lang.status import NodeStatus

# ---------------------------------------------------------------- statuses
IDLE = NodeStatus.IDLE.value
RUNNING = NodeStatus.RUNNING.value
SUCCESS = NodeStatus.SUCCESS.value
FAILURE = NodeStatus.FAILURE.value
SKIPPED = NodeStatus.SKIPPED.value
_BY_VALUE = {s.value: s for s in NodeStatus}
_NAMES = {s.value: s.name for s in NodeStatus}
# "FROM -> TO\n" for every pair, indexed [from][to]; a trace line is a node's prefix and one of these
_TRANS = tuple(tuple(f"{_NAMES.get(a, '?')} -> {_NAMES.get(b, '?')}\n" for b in range(5)) for a in range(5))
_STATUS_OF_TEXT = {"SUCCESS": SUCCESS, "FAILURE": FAILURE, "RUNNING": RUNNING}


def status_enum(value: int) -> NodeStatus:
    return _BY_VALUE[value]


def quote_name(name: str) -> str:
    """A node name as the trace writes it, quotes included (FORMAT.md)."""
    out = ['"']
    for ch in name:
        o = ord(ch)
        if ch == '"':
            out.append('\\"')
        elif ch == "\\":
            out.append("\\\\")
        elif ch == "\n":
            out.append("\\n")
        elif ch == "\r":
            out.append("\\r")
        elif ch == "\t":
            out.append("\\t")
        elif o < 0x20 or o == 0x7F:
            out.append(f"\\x{o:02X}")  # upper case, as the library's recordings (\x7F)
        else:
            out.append(ch)
    out.append('"')
    return "".join(out)


MISSING = object()  # a port read that failed the way 4.6.2's getInput fails (no throw)


class RunError(UserError):
    """A problem found while running (a script error, a bad value in a port...)."""


def _run_error(loc: Loc, message: str) -> RunError:
    return RunError(Diagnostic(loc, message))


# ---------------------------------------------------------------- the run context
class _Cursor:
    """The scripted results of one leaf name, shared by all its instances."""

    __slots__ = ("statuses", "i")

    def __init__(self, statuses: tuple[int, ...]) -> None:
        self.statuses = statuses
        self.i = 0

    def next(self) -> int:
        i = self.i
        if i < len(self.statuses):
            self.i = i + 1
            return self.statuses[i]
        return self.statuses[-1]


class Runtime:
    """What all nodes of one run share: the trace output, the clock, the scenario."""

    def __init__(self, mission: Mission, scenario: Optional[Scenario]) -> None:
        self.mission = mission
        self.enums = dict(mission.enums)  # registerScriptingEnum (enums.py)
        # The trace so far, as pieces: whole lines ("tick 3\n") or a node's prefix followed by its
        # "FROM -> TO\n". Pieces are cheaper to collect than joined lines, and a run of 10,000
        # nodes makes some 26,000 of them per tick.
        self.buf: list[str] = []
        self.emit: Callable[[tuple[str, str]], None] = self.buf.extend
        self.now_ms = 0
        self.default = _STATUS_OF_TEXT[scenario.default] if scenario else SUCCESS
        self.cursors: dict[str, _Cursor] = {}
        if scenario is not None:
            for s in scenario.leaves:
                self.cursors[s.name] = _Cursor(tuple(_STATUS_OF_TEXT[t] for t in s.statuses))
        # `queue` lines: what each run of a leaf's code sets its queue ports to, by leaf name.
        self.fills: dict[str, list[tuple[str, tuple[str, ...]]]] = {}
        for q in scenario.queues if scenario is not None else ():
            self.fills.setdefault(q.name, []).append((q.port, q.items))
        self.uid = 0
        # The one place the interpreter learns the version: every node reads its switches here.
        self.sem = mission.semantics

    def write_line(self, line: str) -> None:
        self.buf.append(line + "\n")

    def take_text(self) -> str:
        text = "".join(self.buf)
        self.buf.clear()
        return text

    def cursor(self, name: str) -> Optional[_Cursor]:
        return self.cursors.get(name)

    def next_uid(self) -> int:
        self.uid += 1
        return self.uid


# ---------------------------------------------------------------- data access
class _Port:
    """A port of one node instance: the text written for it (or its default) and its spec."""

    __slots__ = ("name", "raw", "attr", "spec")

    def __init__(self, name: str, raw: str, attr: Optional[Attr], spec: Optional[PortSpec]) -> None:
        self.name = name
        self.raw = raw
        self.attr = attr
        self.spec = spec


class TreeNode:
    """4.6.2 ``TreeNode``: executeTick with pre/post conditions, setStatus, resetStatus, haltNode."""

    __slots__ = (
        "uid",
        "reg_id",
        "name",
        "status",
        "prefix",
        "emit",
        "rt",
        "model",
        "bb",
        "ports",
        "conds",
        "pre",
        "on_halted",
        "on_success",
        "on_failure",
        "post_always",
    )

    def __init__(self, rt: Runtime, model: Node, bb, reg_id: str, ports: Optional[dict] = None) -> None:
        self.uid = rt.next_uid()
        self.reg_id = reg_id
        self.name = model.display_name
        self.status = IDLE
        self.prefix = f"{self.uid} {reg_id} {quote_name(self.name)} "
        self.emit = rt.emit
        self.rt = rt
        self.model = model
        self.bb = bb
        self.ports: dict[str, _Port] = ports if ports is not None else {}
        # Pre-conditions in 4.6.2's PreCond order: _failureIf, _successIf, _skipIf, _while.
        pre = []
        for kind in ("_failureIf", "_successIf", "_skipIf", "_while"):
            a = model.pre_condition(kind)
            if a is not None:
                pre.append((kind, a))
        self.pre = tuple(pre)
        self.on_halted = model.post_condition("_onHalted")
        self.on_success = model.post_condition("_onSuccess")
        self.on_failure = model.post_condition("_onFailure")
        self.post_always = model.post_condition("_post")
        self.conds = (
            bool(self.pre) or self.on_success is not None or self.on_failure is not None or self.post_always is not None
        )

    # -- status
    def set_status(self, new: int) -> None:
        prev = self.status
        if prev != new:
            self.status = new
            self.emit((self.prefix, _TRANS[prev][new]))

    def reset_status(self) -> None:
        prev = self.status
        if prev != IDLE:
            self.status = IDLE
            self.emit((self.prefix, _TRANS[prev][IDLE]))

    # -- ticking
    def execute_tick(self) -> int:
        """TreeNode::executeTick: pre-conditions may replace tick(); post-conditions on completion;
        a SKIPPED result is returned to the parent but never stored."""
        if self.conds:
            return self._execute_tick_with_conditions()
        new = self.tick()
        if new != SKIPPED:
            if new == IDLE:  # setStatus(IDLE) throws even when the node is IDLE already (edges L1)
                raise self._idle_error()
            prev = self.status
            if prev != new:
                self.status = new
                self.emit((self.prefix, _TRANS[prev][new]))
        return new

    def _execute_tick_with_conditions(self) -> int:
        new = self._check_pre_conditions()
        if new is None:
            new = self.tick()
        if new in (SUCCESS, FAILURE):
            self._check_post_conditions(new)
        if new != SKIPPED:
            if new == IDLE:
                raise self._idle_error()
            self.set_status(new)
        return new

    def _idle_error(self) -> RunError:
        return _run_error(
            self.model.loc, f'`{self.reg_id}` "{self.name}" returned IDLE, which BehaviorTree.CPP forbids'
        )

    def _check_pre_conditions(self) -> Optional[int]:
        """TreeNode::checkPreConditions (4.6.2): all of them when IDLE, only _while when RUNNING."""
        st = self.status
        if st in (IDLE, SKIPPED):
            for kind, attr in self.pre:
                if self.truth(attr):
                    if kind == "_failureIf":
                        return FAILURE
                    if kind == "_successIf":
                        return SUCCESS
                    if kind == "_skipIf":
                        return SKIPPED
                elif kind == "_while":
                    return SKIPPED
        elif st == RUNNING:
            for kind, attr in self.pre:
                if kind == "_while" and not self.truth(attr):
                    self.halt_node()
                    return SKIPPED
        return None

    def _check_post_conditions(self, status: int) -> None:
        """TreeNode::checkPostConditions: _onSuccess or _onFailure, then _post."""
        if status == SUCCESS:
            if self.on_success is not None:
                self.run_script(self.on_success)
        elif status == FAILURE and self.on_failure is not None:
            self.run_script(self.on_failure)
        if self.post_always is not None:
            self.run_script(self.post_always)

    def tick(self) -> int:  # pragma: no cover - every class overrides it
        raise NotImplementedError

    def halt(self) -> None:
        """Leaves that cannot be RUNNING (SyncActionNode, ConditionNode): just reset."""
        self.reset_status()

    def halt_node(self) -> None:
        """TreeNode::haltNode: halt(), then the _onHalted script."""
        self.halt()
        if self.on_halted is not None:
            self.run_script(self.on_halted)

    # -- scripts and ports (the data layer lives in blackboard.py, script.py, values.py)
    def run_script(self, attr: Attr, parsed=None, from_blackboard: bool = False):
        """Run the script of `attr` (or `parsed`, a script read at run time) on the node's blackboard."""
        code = parsed if parsed is not None else attr.script
        if code is None:
            code = self._parse_at_run_time(attr, attr.value)
            from_blackboard = True
        try:
            return scriptmod.evaluate(code, self.bb, self.rt.enums, self.rt.sem.int_to_double_53_bits)
        except scriptmod.ScriptRuntimeError as e:
            raise self._script_error(attr, e.message, e.offset, from_blackboard) from None
        except (values.ConversionError, bbmod.BlackboardError) as e:
            raise self._script_error(attr, str(e), 0, True) from None

    def truth(self, attr: Attr, parsed=None, from_blackboard: bool = False) -> bool:
        """The script's result as a condition (4.6.2: ``cast<bool>()`` of it)."""
        value = self.run_script(attr, parsed, from_blackboard)
        try:
            return scriptmod.script_truth(value)
        except scriptmod.ScriptRuntimeError as e:
            raise self._script_error(attr, e.message, 0, True) from None

    def _script_error(self, attr: Attr, message: str, offset: int, at_start: bool) -> RunError:
        loc = attr.value_loc
        if not at_start and offset > 0:
            loc = scriptmod.script_error_loc(
                attr.value_loc, attr.value, offset, scriptmod.raw_attr_value(attr.value_loc)
            )
        return _run_error(loc, f'script error in `{attr.name}` of `{self.reg_id}` "{self.name}": {message}')

    def _parse_at_run_time(self, attr: Attr, text: str):
        try:
            return scriptmod.parse_script(text, self.rt.sem.script_grammar_49)
        except scriptmod.ScriptSyntaxError as e:
            raise _run_error(
                attr.value_loc,
                f'`{attr.name}` of `{self.reg_id}` "{self.name}" reads the script '
                f"`{text}`, which is invalid: {e.message}",
            ) from None

    def port_loc(self, name: str) -> Loc:
        p = self.ports.get(name)
        if p is not None and p.attr is not None:
            return p.attr.value_loc
        return self.model.loc

    def get_input(self, name: str, type_name: Optional[str] = None):
        """TreeNode::getInput<T>: the literal converted to the port's type, or the entry's value.

        Returns ``MISSING`` when 4.6.2's getInput would fail without
        throwing (no such port, entry missing or empty)."""
        p = self.ports.get(name)
        if p is None:
            return MISSING
        t = type_name or (p.spec.type if p.spec is not None else "any")
        try:
            return bbmod.get_input(self.bb, p.raw, t, port_name=name)
        except (values.ConversionError, bbmod.BlackboardError):
            return MISSING  # 4.6.2's getInput returns an error, it does not throw

    def require_input(self, name: str, type_name: Optional[str] = None):
        """getInput of a port the node cannot work without: 4.6.2 throws when it fails."""
        p = self.ports.get(name)
        if p is None:
            raise _run_error(self.model.loc, f'`{self.reg_id}` "{self.name}" needs port `{name}`')
        t = type_name or (p.spec.type if p.spec is not None else "any")
        try:
            return bbmod.get_input(self.bb, p.raw, t, port_name=name)
        except (values.ConversionError, bbmod.BlackboardError) as e:
            raise _run_error(self.port_loc(name), f'`{self.reg_id}` "{self.name}": {e}') from None

    def set_output(self, name: str, value, type_name: Optional[str] = None) -> bool:
        """TreeNode::setOutput: a port not written, or written as a literal, is not set
        (4.6.2 returns an error that the built-in nodes ignore)."""
        p = self.ports.get(name)
        if p is None or bbmod.remapped_key(name, p.raw) is None:
            return False
        t = type_name or (p.spec.type if p.spec is not None else "any")
        try:
            bbmod.set_output(self.bb, p.raw, value, t, port_name=name)
            return True
        except (values.ConversionError, bbmod.BlackboardError) as e:
            raise _run_error(self.port_loc(name), f'`{self.reg_id}` "{self.name}": {e}') from None

    def status_input(self, name: str) -> int:
        value = self.require_input(name, "NodeStatus")
        if isinstance(value, NodeStatus):
            return value.value
        raise _run_error(
            self.port_loc(name), f'port `{name}` of `{self.reg_id}` "{self.name}": `{value}` is not a NodeStatus'
        )


# ================================================================ controls


class _ScriptPort:
    """A port holding a script (`code`, `if`): parsed once when written literally; read and
    parsed again when it changes if it names a blackboard entry (4.6.2 loadExecutor)."""

    __slots__ = ("node", "name", "attr", "parsed", "text", "literal")

    def __init__(self, node: TreeNode, name: str) -> None:
        self.node = node
        self.name = name
        p = node.ports.get(name)
        attr = p.attr if p is not None else None
        self.attr: Optional[Attr] = attr
        self.literal = attr is not None and attr.script is not None and not bbmod.is_blackboard_pointer(attr.value)
        self.parsed = attr.script if attr is not None and self.literal else None
        self.text = attr.value if attr is not None and self.literal else None

    def load(self):
        if not self.literal:
            text = self.node.require_input(self.name, "string")
            if text != self.text:
                self.parsed = self.node._parse_at_run_time(self.attr, text)
                self.text = text
        return self.parsed

    def run(self):
        parsed = self.load()
        # load() fails for a missing port, and `code`/`if` have no model default
        assert self.attr is not None
        return self.node.run_script(self.attr, parsed, not self.literal)

    def truth(self) -> bool:
        parsed = self.load()
        assert self.attr is not None
        return self.node.truth(self.attr, parsed, not self.literal)


def _entry_of(node):
    """The entry `key` names from the node's blackboard (getEntry); a bad key is an error."""
    try:
        return node.bb.get_entry(node.key)
    except bbmod.BlackboardError as e:
        raise _run_error(node.port_loc("entry"), f'`{node.reg_id}` "{node.name}": {e}') from None
