"""Scenario files: what every scripted leaf of a mission returns, call by call.

The format is the contract of ``tests/conformance/FORMAT.md``::

    ticks 20                       # most root ticks to send (default 100, at least 1)
    default SUCCESS                # what unlisted leaves return (default SUCCESS)
    leaf FindBall FAILURE SUCCESS  # successive results of the leaf named FindBall
    clock_ms 100                   # virtual time per tick (default 0)
    queue ParseWaypoints waypoint_queue a b c   # what the leaf's queue port gets (setOutput)

:func:`parse_scenario` reads a file into a frozen :class:`Scenario` and reports
every syntax problem as ``path:line:col: error: ...``. :func:`check_scenario`
does the checks that need the mission: no Condition may return RUNNING, and a
``leaf`` line that names no leaf of the mission is a warning.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Optional

from btgen.diagnostics import (
    Diagnostic,
    DiagnosticSink,
    Loc,
    UserError,
    did_you_mean,
    one_line,
    read_bounded,
    suggestion,
)
from btgen.lang import values
from btgen.lang.leaves import LeafUse, _tree_with_leaf, mission_leaves
from btgen.lang.model import Mission
from btgen.lang.nav2 import ENV_INPUTS

MAX_SCENARIO_BYTES = 16 * 1024 * 1024
DEFAULT_TICKS = 100
STATUSES = ("SUCCESS", "FAILURE", "RUNNING")
KEYWORDS = ("ticks", "default", "leaf", "clock_ms", "queue")

_TOKEN_RE = re.compile(r"[^ \t\f\v]+")
_INT_RE = re.compile(r"[+-]?[0-9]+")


@dataclass(frozen=True)
class Token:
    text: str
    loc: Loc


@dataclass(frozen=True)
class LeafScript:
    """The statuses listed for one leaf name, with where each was written."""

    name: str
    statuses: tuple[str, ...]
    loc: Loc  # the name
    status_locs: tuple[Loc, ...]


@dataclass(frozen=True)
class QueueScript:
    """A `queue` line: every run of the leaf's code first sets its queue port `port` to a new
    queue of `items` (setOutput of a SharedQueue<T>, each item converted as convertFromString<T>)."""

    name: str
    port: str
    items: tuple[str, ...]
    loc: Loc  # the name
    port_loc: Loc
    item_locs: tuple[Loc, ...]


@dataclass(frozen=True)
class Scenario:
    path: str
    ticks: int = DEFAULT_TICKS
    default: str = "SUCCESS"
    leaves: tuple[LeafScript, ...] = ()
    clock_ms: int = 0
    default_loc: Optional[Loc] = None  # the status of the `default` line, when there is one
    queues: tuple[QueueScript, ...] = ()

    def leaf(self, name: str) -> Optional[LeafScript]:
        for s in self.leaves:
            if s.name == name:
                return s
        return None

    @property
    def by_name(self) -> dict[str, LeafScript]:
        return {s.name: s for s in self.leaves}


def _tokens(path: str, lineno: int, line: str) -> list[Token]:
    hash_at = line.find("#")
    if hash_at >= 0:
        line = line[:hash_at]
    return [Token(m.group(0), Loc(path, lineno, m.start() + 1)) for m in _TOKEN_RE.finditer(line)]


def _status_error(tok: Token) -> str:
    hint = (
        did_you_mean(tok.text.upper(), STATUSES) if tok.text.upper() != tok.text else did_you_mean(tok.text, STATUSES)
    )
    extra = f" (did you mean `{hint}`?)" if hint else ""
    if tok.text == "SKIPPED":
        return "`SKIPPED` cannot be scripted: a leaf returns SUCCESS, FAILURE or RUNNING"
    if tok.text == "IDLE":
        return "`IDLE` cannot be scripted: a leaf returns SUCCESS, FAILURE or RUNNING"
    return f"unknown status `{tok.text}`: use SUCCESS, FAILURE or RUNNING{extra}"


def _read_text(path: str) -> str:
    data = read_bounded(path, MAX_SCENARIO_BYTES, "scenario", "scenarios", cannot="cannot read scenario")
    if data.startswith(b"\xef\xbb\xbf"):
        data = data[3:]
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as e:
        good = data[: e.start].decode("utf-8")
        line = good.count("\n") + 1
        col = len(good) - (good.rfind("\n") + 1) + 1
        raise UserError.at(
            Loc(path, line, col), f"invalid UTF-8 (byte 0x{data[e.start]:02x}); scenarios must be UTF-8"
        ) from None


def parse_scenario(path: str) -> Scenario:
    """Read a scenario file; UserError with every problem found."""
    return parse_scenario_text(_read_text(path), path)


def parse_scenario_text(text: str, path: str = "<scenario>") -> Scenario:
    sink = DiagnosticSink()
    ticks: Optional[int] = None
    ticks_loc: Optional[Loc] = None
    default: Optional[str] = None
    default_loc: Optional[Loc] = None
    default_line: Optional[Loc] = None
    clock: Optional[int] = None
    clock_loc: Optional[Loc] = None
    leaves: dict[str, LeafScript] = {}
    queues: dict[tuple[str, str], QueueScript] = {}

    for lineno, line in enumerate(text.split("\n"), start=1):
        if line.endswith("\r"):
            line = line[:-1]
        toks = _tokens(path, lineno, line)
        if not toks:
            continue
        kw, args = toks[0], toks[1:]
        if kw.text == "ticks":
            if ticks_loc is not None:
                sink.error(kw.loc, f"`ticks` is given twice (first at line {ticks_loc.line})")
                continue
            ticks_loc = kw.loc
            value = _one_int(sink, kw, args, "ticks", "the most root ticks to send")
            if value is not None:
                if value < 1:
                    sink.error(args[0].loc, f"ticks must be at least 1, got {value}")
                else:
                    ticks = value
        elif kw.text == "default":
            if default_line is not None:
                sink.error(kw.loc, f"`default` is given twice (first at line {default_line.line})")
                continue
            default_line = kw.loc
            if not args:
                sink.error(kw.loc, "`default` needs a status: SUCCESS, FAILURE or RUNNING")
                continue
            if len(args) > 1:
                sink.error(args[1].loc, f"`default` takes one status, found also `{args[1].text}`")
            if args[0].text in STATUSES:
                default, default_loc = args[0].text, args[0].loc
            else:
                sink.error(args[0].loc, _status_error(args[0]))
        elif kw.text == "clock_ms":
            if clock_loc is not None:
                sink.error(kw.loc, f"`clock_ms` is given twice (first at line {clock_loc.line})")
                continue
            clock_loc = kw.loc
            value = _one_int(sink, kw, args, "clock_ms", "the milliseconds the clock advances before each tick")
            if value is not None:
                if value < 0:
                    sink.error(args[0].loc, f"clock_ms cannot be negative, got {value}")
                else:
                    clock = value
        elif kw.text == "leaf":
            if not args:
                sink.error(kw.loc, "`leaf` needs a leaf name and at least one status")
                continue
            name, sts = args[0], args[1:]
            if name.text in leaves:
                sink.error(name.loc, f"leaf `{name.text}` is listed twice (first at line {leaves[name.text].loc.line})")
                continue
            if not sts:
                sink.error(name.loc, f"leaf `{name.text}` has no status: list one or more of SUCCESS, FAILURE, RUNNING")
                continue
            bad = [t for t in sts if t.text not in STATUSES]
            for t in bad:
                sink.error(t.loc, _status_error(t))
            leaves[name.text] = LeafScript(name.text, tuple(t.text for t in sts), name.loc, tuple(t.loc for t in sts))
        elif kw.text == "queue":
            if len(args) < 2:
                sink.error(kw.loc, "`queue` needs a leaf name, its queue port and the queue's items (none: empty)")
                continue
            name, port = args[0], args[1]
            prev = queues.get((name.text, port.text))
            if prev is not None:
                sink.error(
                    port.loc,
                    f"queue port `{port.text}` of leaf `{name.text}` is listed twice (first at line {prev.loc.line})",
                )
                continue
            items = args[2:]
            queues[(name.text, port.text)] = QueueScript(
                name.text, port.text, tuple(t.text for t in items), name.loc, port.loc, tuple(t.loc for t in items)
            )
        else:
            sink.error(
                kw.loc,
                f"unknown keyword `{kw.text}`: a line starts with ticks, default, leaf, clock_ms or queue"
                f"{suggestion(kw.text, KEYWORDS)}",
            )
    sink.raise_if_errors()
    return Scenario(
        path,
        ticks if ticks is not None else DEFAULT_TICKS,
        default or "SUCCESS",
        tuple(leaves.values()),
        clock if clock is not None else 0,
        default_loc,
        tuple(queues.values()),
    )


# ====================================================================== writing
MAX_VALUE = 2**31 - 1  # the largest `ticks` and `clock_ms` either reader takes
_WORD_RE = re.compile(r"[^ \t\f\v\r\n#]+")


def name_problem(name: str) -> Optional[str]:
    """Why a leaf name cannot be written in a scenario file (None when it can): the readers
    (this module and harness/scenario.hpp) split a line at blanks and cut it at `#`."""
    if _WORD_RE.fullmatch(name):
        return None
    return (
        f"the leaf name `{name}` cannot be written in a scenario file, whose names are one word "
        "(no blank and no `#`): rename the node (e.g. `"
        + (re.sub(r"[ \t\f\v\r\n#]+", "_", name).strip("_") or "leaf")
        + "`) to script it"
    )


def leaf_locs(mission: Mission) -> dict[str, Loc]:
    """Where each leaf name of the mission is first used (the place a writer's refusal names)."""
    out: dict[str, Loc] = {}
    for use in mission_leaves(mission, set()):
        out.setdefault(use.name, use.node.loc)
    return out


def format_scenario(
    ticks: int,
    leaves: Sequence[tuple[str, Sequence[str]]],
    clock_ms: int = 0,
    comment: str = "",
    where: Optional[Mapping[str, Loc]] = None,
) -> str:
    """The one writer of scenario files (`btgen explore`, `btgen scenario-from-log`): what it
    writes, parse_scenario reads back to the same ticks, clock and leaf lines, or it refuses
    (UserError at the leaf's node, `where[name]`, for a name the format cannot hold; at
    `<scenario>` for a value no reader takes)."""
    problems = []
    for what, value, low in (("ticks", ticks, 1), ("clock_ms", clock_ms, 0)):
        if not low <= value <= MAX_VALUE:
            problems.append(
                Diagnostic(
                    Loc("<scenario>", 1, 1), f"{what} {value} cannot be written: it is from {low} to {MAX_VALUE}"
                )
            )
    seen: set[str] = set()
    for name, statuses in leaves:
        problem = name_problem(name)
        if problem is None and name in seen:
            problem = f"the leaf name `{name}` is given twice"
        if problem is not None:
            problems.append(Diagnostic((where or {}).get(name, Loc("<scenario>", 1, 1)), problem))
        seen.add(name)
        if not statuses or any(st not in STATUSES for st in statuses):
            raise ValueError(f"statuses of {name!r}: {statuses!r}")  # (a bug of the caller)
    if problems:
        raise UserError(problems)
    lines = [f"# {one_line(line)}" for line in comment.split("\n")] if comment else []
    lines.append(f"ticks {ticks}")
    if clock_ms:
        lines.append(f"clock_ms {clock_ms}")
    lines += [f"leaf {name} {' '.join(sts)}" for name, sts in leaves]
    return "\n".join(lines) + "\n"


def _one_int(sink: DiagnosticSink, kw: Token, args: list[Token], what: str, meaning: str) -> Optional[int]:
    if not args:
        sink.error(kw.loc, f"`{what}` needs a whole number ({meaning})")
        return None
    if len(args) > 1:
        sink.error(args[1].loc, f"`{what}` takes one number, found also `{args[1].text}`")
        return None
    if not _INT_RE.fullmatch(args[0].text):
        sink.error(args[0].loc, f"`{what}` needs a whole number, got `{args[0].text}`")
        return None
    text = args[0].text
    digits = text.lstrip("+-").lstrip("0") or "0"
    negative = text.startswith("-") and digits != "0"
    if not negative and (len(digits) > 10 or int(digits) > 2**31 - 1):  # (no int() of a million digits)
        sink.error(args[0].loc, f"{what} {digits} is too large (at most {2**31 - 1})")
        return None
    if not negative:
        return int(digits)
    return -min(int(digits) if len(digits) <= 20 else 2**62, 2**62)  # saturated, as the C++ runner


def _distance(a: bytes, b: bytes) -> int:
    row = list(range(len(b) + 1))
    for i in range(1, len(a) + 1):
        diag, row[0] = row[0], i
        for j in range(1, len(b) + 1):
            up = row[j]
            row[j] = min(diag + (a[i - 1] != b[j - 1]), up + 1, row[j - 1] + 1)
            diag = up
    return row[len(b)]


def closest_leaf(word: str, names: list[str]) -> Optional[str]:
    """The scripted-leaf hint, as the C++ scenario runner gives it (scenario.hpp did_you_mean):
    a name equal but for ASCII case, else the first of the closest names (in mission order) at
    most a third of whose bytes differ. (The generic did_you_mean gave `b` for `bb` where the
    runner gave none: hostile names in the random missions found it.)"""

    def upper(b: bytes) -> bytes:
        return bytes(c - 32 if 97 <= c <= 122 else c for c in b)

    w = word.encode("utf-8", "surrogatepass")
    encoded = [(n, n.encode("utf-8", "surrogatepass")) for n in names]
    for n, b in encoded:
        if b != w and upper(b) == upper(w):
            return n
    best, best_d = None, 0
    for n, b in encoded:
        if abs(len(b) - len(w)) > max(len(b), len(w)) // 3:
            continue
        d = _distance(w, b)
        if 0 < d <= max(len(w), len(b)) // 3 and (best is None or d < best_d):
            best, best_d = n, d
    return best


def check_scenario(scenario: Scenario, mission: Mission) -> list[Diagnostic]:
    """Check a scenario against its mission.

    Raises UserError when a Condition could return RUNNING; returns the
    warnings (leaf lines naming no leaf of the mission).
    """
    uses: dict[str, list[LeafUse]] = {}
    builtin_names: set[str] = set()
    for use in mission_leaves(mission, builtin_names):
        uses.setdefault(use.name, []).append(use)
    sink = DiagnosticSink()
    for script in scenario.leaves:
        found = uses.get(script.name)
        if not found and script.name in builtin_names:
            sink.warning(
                script.loc,
                f"`{script.name}` is a built-in node of BehaviorTree.CPP and keeps its "
                f"built-in behaviour; its line is ignored",
            )
            continue
        unused_tree = _tree_with_leaf(mission, script.name) if not found else None
        if unused_tree is not None:
            sink.warning(
                script.loc,
                f"leaf `{script.name}` is only in BehaviorTree `{unused_tree}`, which the "
                f"main tree `{mission.main_tree}` does not run; its line is ignored",
            )
            continue
        if not found:
            hint = closest_leaf(script.name, list(uses))
            extra = f" (did you mean `{hint}`?)" if hint else ""
            sink.warning(
                script.loc,
                f"leaf `{script.name}` matches no Action or Condition of the mission; its line is ignored{extra}",
            )
            continue
        cond = next((u for u in found if u.kind == "Condition"), None)
        if cond is not None:
            for status, loc in zip(script.statuses, script.status_locs):
                if status == "RUNNING" and cond.node.children:
                    sink.error(
                        loc,
                        f"`{script.name}` scripts the input of Nav2's `{cond.node.id}` at {cond.node.loc} "
                        f"({ENV_INPUTS[cond.node.id]}): SUCCESS for yes or FAILURE for no, not RUNNING",
                    )
                    break
                if status == "RUNNING":
                    sink.error(
                        loc,
                        f"`{script.name}` is a Condition and cannot return RUNNING "
                        f"(a Condition answers in one tick; its Condition node is at {cond.node.loc})",
                    )
                    break
    for q in scenario.queues:
        _check_queue(sink, q, uses.get(q.name), mission, uses)
    if scenario.default == "RUNNING":
        reached = [
            (name, next(u for u in found if u.kind == "Condition"))
            for name, found in uses.items()
            if scenario.leaf(name) is None and any(u.kind == "Condition" for u in found)
        ]
        if reached:
            listed = ", ".join(f"`{name}` ({use.node.loc})" for name, use in reached)
            what = "the Condition" if len(reached) == 1 else "the Conditions"
            each = "it its" if len(reached) == 1 else "each its"
            sink.error(
                scenario.default_loc or Loc(scenario.path, 1, 1),
                f"`default RUNNING` reaches {what} {listed}, which cannot return RUNNING; give {each} own `leaf` line",
            )
    sink.raise_if_errors()
    return list(sink.items)


def _check_queue(
    sink: DiagnosticSink, q: QueueScript, found: Optional[list[LeafUse]], mission: Mission, uses: Mapping[str, object]
) -> None:
    """A `queue` line: its leaf runs, and every model it stands for declares `port` an output
    queue whose element type every item converts to (an error, else a warning naming the line)."""
    if not found:
        hint = closest_leaf(q.name, list(uses))
        extra = f" (did you mean `{hint}`?)" if hint else ""
        sink.warning(
            q.loc,
            f"leaf `{q.name}` of a `queue` line matches no Action or Condition of the mission; it is ignored{extra}",
        )
        return
    for use in found:
        spec = mission.spec(use.node.id)
        ps = next((p for p in spec.ports if p.name == q.port), None)
        elem = values.queue_element_type(ps.type) if ps is not None else None
        if ps is None or elem is None or not ps.writes:
            declared = (
                f"declares it {ps.direction} port of type {ps.type}" if ps is not None else "declares no such port"
            )
            sink.error(
                q.port_loc,
                f"`{q.port}` of leaf `{q.name}` is no output queue port: model `{use.node.id}` {declared} "
                f"(a `queue` line sets a port declared BT::SharedQueue<T> as output or inout)",
            )
            return
        for item, loc in zip(q.items, q.item_locs):
            try:
                values.convert_from_string(elem, item, double_from_chars=mission.semantics.double_from_chars)
            except values.ConversionError as e:
                sink.error(loc, f"item `{item}` of queue port `{q.port}` ({ps.type}) of leaf `{q.name}`: {e}")
                return


def load_scenario(path: str, mission: Mission) -> tuple[Scenario, list[Diagnostic]]:
    """Parse and check a scenario; returns it with its warnings."""
    scenario = parse_scenario(path)
    return scenario, check_scenario(scenario, mission)
