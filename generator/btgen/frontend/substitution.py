"""Reading substitution rules: BehaviorTree.CPP 4.x's JSON `TestNodeConfigs` and `SubstitutionRules`
(`BehaviorTreeFactory::loadSubstitutionRuleFromJSON`), for `--substitute FILE.json`
(`btgen run`, `btgen compile`): the file into `lang.substitution.Rules`, every problem located.

    {
      "TestNodeConfigs": {
        "SlowOk": {"return_status": "SUCCESS", "async_delay": 2000,
                   "success_script": "done := true", "post_script": "calls += 1"}
      },
      "SubstitutionRules": {
        "Navigate": "SlowOk",           // by node name or registration ID
        "IV_VisitExhibit/*": "AlwaysFailure",  // by path, with * and ? wildcards
        "talk": "MyOtherAction"
      }
    }

A rule's filter matches a node when it equals the node's name or its registration ID, or when
it matches, as a wildcard pattern, the node's path (`SubTreePath/name`, a node without a name
attribute being `ID::UID`, as 4.6.2's `config.path`). The first rule that matches, in the
file's order, applies (BehaviorTree.CPP keeps the rules in an unordered map, so which of two
matching rules wins is not defined there). A rule naming a TestNodeConfig makes the node a
`TestNode`: a StatefulActionNode that returns `return_status` at once, or after `async_delay`
milliseconds of the run's virtual clock (RUNNING until then), and on completion runs
`success_script` or `failure_script`, then `post_script`, on the node's blackboard. A rule naming
another node ID builds that node instead: a built-in leaf, or a scripted leaf of the mission
(which takes its results from the scenario under the node's own name). The node keeps its
registration ID, name and UID in the trace, as `setRegistrationID` keeps them.

Only leaves are substituted: a rule that matches a Control, a Decorator or a SubTree is an
error (a TestNode cannot hold their children).
"""

from __future__ import annotations

import bisect
import functools
import json
import re
from typing import Optional

from btgen.diagnostics import Diagnostic, Loc, UserError
from btgen.fileio import read_json
from btgen.lang import script as sc
from btgen.lang.model import Attr
from btgen.lang.status import NodeStatus
from btgen.lang.substitution import Rule, Rules, TestConfig

MAX_RULES_BYTES = 1 << 20
_STATUS = {s.name: s.value for s in (NodeStatus.SUCCESS, NodeStatus.FAILURE, NodeStatus.RUNNING)}


class _Obj(list):
    """A JSON object as its (key, value) pairs in file order (arrays stay plain lists)."""


@functools.lru_cache(maxsize=2)
def _line_starts(text: str) -> list[int]:
    return [0] + [m.end() for m in re.finditer("\n", text)]


def _loc_of(text: str, path: str, needle: str, start: int = 0) -> tuple[Loc, int]:
    """Where `needle` first is in `text` from `start` (a table of line starts: 20,000 rules
    cost 20,000 lookups, not 20,000 counts of the lines before each)."""
    at = text.find(needle, start)
    if at < 0:
        return Loc(path, 1, 1), start
    starts = _line_starts(text)
    line = bisect.bisect_right(starts, at)
    return Loc(path, line, at - starts[line - 1] + 1), at


def _plain(value):
    """A JSON value as Python's reader gives it without the pairs hook (objects as dicts)."""
    if isinstance(value, _Obj):
        return {k: _plain(v) for k, v in value}
    if isinstance(value, list):
        return [_plain(v) for v in value]
    return value


def _dumps(value) -> str:
    return json.dumps(_plain(value), ensure_ascii=False)


def load_rules(path: str, grammar_49: bool = False) -> Rules:
    """Read a substitution file; UserError with `path:line:col` for every problem found.
    Its scripts are parsed with the grammar of the selected release (`grammar_49`: the
    mission's `semantics.script_grammar_49`), as the same text in the mission would be."""
    doc, text = read_json(path, MAX_RULES_BYTES, "substitution", object_pairs_hook=_Obj)
    errors: list[Diagnostic] = []

    def err(loc: Loc, message: str) -> None:
        errors.append(Diagnostic(loc, message))

    top = dict(doc) if isinstance(doc, _Obj) else {}
    if not isinstance(doc, _Obj):
        raise UserError(Diagnostic(Loc(path, 1, 1), "the file must hold a JSON object"))
    configs: dict[str, TestConfig] = {}
    pos = 0
    raw_configs = top.get("TestNodeConfigs", [])
    if key_missing := "TestNodeConfigs" not in top:
        err(Loc(path, 1, 1), "the file has no `TestNodeConfigs` (BehaviorTree.CPP requires it: `{}` when empty)")
    if not isinstance(raw_configs, _Obj):
        if not key_missing:
            err(_loc_of(text, path, '"TestNodeConfigs"')[0], "`TestNodeConfigs` must be an object")
        raw_configs = []
    for name, body in raw_configs:
        loc, pos = _loc_of(text, path, _dumps(name), pos)
        if not isinstance(body, _Obj):
            err(loc, f"test node config `{name}` must be an object")
            continue
        fields = dict(body)
        for key in fields:
            if key not in ("return_status", "async_delay", "success_script", "failure_script", "post_script"):
                err(
                    _loc_of(text, path, _dumps(key), pos)[0],
                    f"unknown field `{key}` of `{name}`: use return_status, async_delay, success_script, "
                    "failure_script or post_script",
                )
        status = fields.get("return_status")
        if status is None:
            err(loc, f"test node config `{name}` has no `return_status` (BehaviorTree.CPP requires it)")
            continue
        if not isinstance(status, str) or status not in _STATUS:
            err(
                _loc_of(text, path, _dumps(status), pos)[0],
                f"`return_status` of `{name}` is {_dumps(status)}: use SUCCESS, FAILURE or RUNNING",
            )
            continue
        delay = fields.get("async_delay", 0)
        if not isinstance(delay, int) or isinstance(delay, bool) or not -(2**31) <= delay < 2**31:
            err(_loc_of(text, path, '"async_delay"', pos)[0], f"`async_delay` of `{name}` must be a whole number")
            continue
        scripts: dict[str, Optional[Attr]] = {}
        for key in ("success_script", "failure_script", "post_script"):
            code = fields.get(key)
            if code is None or code == "":
                scripts[key] = None
                continue
            kloc = _loc_of(text, path, _dumps(key), pos)[0]
            if not isinstance(code, str):
                err(kloc, f"`{key}` of `{name}` must be a string")
                continue
            vloc = _loc_of(text, path, _dumps(code), pos)[0]
            try:
                parsed = sc.parse_script(code, grammar_49)
            except sc.ScriptSyntaxError as e:
                err(vloc, f"`{key}` of `{name}`: {e.message}")
                continue
            scripts[key] = Attr(key, code, kloc, vloc, parsed)
        configs[name] = TestConfig(
            name,
            _STATUS[status],
            delay,
            scripts.get("success_script"),
            scripts.get("failure_script"),
            scripts.get("post_script"),
            grammar_49,
        )
    rules: list[Rule] = []
    raw_rules = top.get("SubstitutionRules", [])
    if key_missing := "SubstitutionRules" not in top:
        err(Loc(path, 1, 1), "the file has no `SubstitutionRules` (BehaviorTree.CPP requires it: `{}` when empty)")
    if not isinstance(raw_rules, _Obj):
        if not key_missing:
            err(_loc_of(text, path, '"SubstitutionRules"')[0], "`SubstitutionRules` must be an object")
        raw_rules = []
    rules_at = _loc_of(text, path, '"SubstitutionRules"')[1]
    pos = rules_at
    for filt, target in raw_rules:
        loc, pos = _loc_of(text, path, _dumps(filt), pos)
        if not isinstance(target, str):
            err(loc, f"the rule `{filt}` must name a test node config or a node ID")
            continue
        rules.append(Rule(filt, target, loc, configs.get(target)))
    if errors:
        raise UserError(errors)
    return Rules(rules)
