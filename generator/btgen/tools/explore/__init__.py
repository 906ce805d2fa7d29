"""`btgen explore`: every result the leaves can give, up to a bound, run on the interpreter.

`search.py` holds the search (plans played on one interpreter, the state hash, properties,
coverage goals; its docstring says how it works), which `diff`, `mutate`, `tests`, `cover`
and `verify` build on; `command.py` holds the command (scenario files, coverage lines, the
options' checks, the report, the progress line).
"""

from btgen.tools.explore.command import (
    Places,
    _possible,
    check_clock_ms,
    check_ticks,
    coverage_lines,
    criteria_lines,
    criteria_of,
    explore_command,
    obligation_counts,
    scenario_text,
    sync_actions,
)
from btgen.tools.explore.search import (
    BY_NAME,
    NAMES,
    Explorer,
    Path,
    Property,
    Result,
    _Branch,
    _Run,
    _Stop,
    parse_property,
)

__all__ = [
    "BY_NAME",
    "NAMES",
    "Explorer",
    "Path",
    "Places",
    "Property",
    "Result",
    "_Branch",
    "_Run",
    "_Stop",
    "_possible",
    "check_clock_ms",
    "check_ticks",
    "coverage_lines",
    "criteria_lines",
    "criteria_of",
    "explore_command",
    "obligation_counts",
    "parse_property",
    "scenario_text",
    "sync_actions",
]
