"""What `btgen diff` and `btgen diff --git` share: --observe, and a counterexample as scenario files."""

from __future__ import annotations

import difflib

from btgen import cmdline
from btgen.tools.diff.product import DEFAULT_OBSERVE, OBSERVABLES, Outcome
from btgen.tools.explore import Path, scenario_text


def parse_observe(args) -> frozenset:
    """--observe A,B,...: the observables named (product.OBSERVABLES), `default` for the default set."""
    text = getattr(args, "observe", None)
    if text is None:
        return DEFAULT_OBSERVE
    out: set[str] = set()
    for word in (w.strip() for w in text.split(",")):
        if word == "default":
            out |= DEFAULT_OBSERVE
        elif word in OBSERVABLES:
            out.add(word)
        else:
            close = difflib.get_close_matches(word, OBSERVABLES, 1)
            hint = f" (did you mean `{close[0]}`?)" if close else ""
            raise cmdline.error(
                args, text, f"--observe `{word}`{hint}: choose from {', '.join(OBSERVABLES)} or default"
            )
    if not out:
        raise cmdline.error(args, "--observe", "--observe names nothing to observe")
    return frozenset(out)


def scenario_texts(outcome: Outcome, rename: dict[str, str], clock_ms: int) -> tuple[str, str]:
    """The counterexample as a scenario file for OLD (its own leaf names) and for NEW."""
    back = {b: a for a, b in rename.items()}
    picks_new = tuple((name, st) for name, sts in outcome.plan.items() for st in sts)
    picks_old = tuple((back.get(name, name), st) for name, st in picks_new)
    comment = "btgen diff: a shortest scenario on which the two missions differ"
    texts = []
    for picks in (picks_old, picks_new):
        texts.append(scenario_text(Path((), picks, outcome.ticks, frozenset(), "differ"), clock_ms, comment))
    return texts[0], texts[1]
