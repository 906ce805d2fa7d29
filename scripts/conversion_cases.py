#!/usr/bin/env python3
"""The text-to-number conversion table: missions that reveal what each release reads.

    python scripts/conversion_cases.py                       # (re)writes the missions
    python scripts/conversion_cases.py --record 4.6.2 PREFIX462/bin/harness
    python scripts/conversion_cases.py --record 4.10.0 PREFIX410/bin/harness
    python scripts/conversion_cases.py --table               # the Markdown table, from the recordings
    python scripts/conversion_cases.py --index               # INDEX.md of the folder, with the table

One mission per (site, input) in tests/conformance/conversions/: a text is converted to a
number at one site of the data side (a LoopDouble literal queue, a SetBlackboard literal
into a double entry, a SetBlackboard copy of a string entry into a double entry, a
LoopDouble queue read from a string entry, a script storing a string into a double entry,
a LoopInt literal queue), and ScriptConditions under ForceSuccess compare the converted
value with the candidates (what std::stod and std::from_chars give), with itself (false
for NaN) and with ±10^6 (infinities); the trace shows which held. `--record` runs the real
library's harness and writes `<release>/<stem>.trace` (its stdout, cut short where it
threw) and `<release>/<stem>.error` (its message, when it threw or refused the file).
tests/python/test_conversions.py holds both engines to these recordings.
"""

from __future__ import annotations

import argparse
import contextlib
import math
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "tests", "conformance", "conversions")
sys.path.insert(0, os.path.join(ROOT, "generator"))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from btgen.lang import values

# Texts converted as a double: decimal, hex (std::stod reads it, std::from_chars stops at `x`),
# a blank or `+` first (stod only), text after the number, the special values, overflow,
# a subnormal (std::stod throws out_of_range for it), no digit before or after the point.
DOUBLE_INPUTS = ("8.5", "0x1p3", "0X10", " 8.5", "+8.5", "8.5abc", "inf", "nan", "1e400", "4e-320", ".5", "-0", "abc")
INT_INPUTS = ("0x10", "+8", " 8", "8.9", "-0", "2147483648")

SITES = {
    # site: (what, the mission's body with INPUT and the checks of x)
    "loop_literal": "a LoopDouble literal queue",
    "set_literal": "SetBlackboard of a literal into a double entry",
    "set_copy": "SetBlackboard copy of a string entry into a double entry",
    "loop_entry": "a LoopDouble queue read from a string entry",
    "script_store": "a script storing a string into a double entry",
    "loopint_literal": "a LoopInt literal queue",
}


def _candidate(text: str, from_chars: bool) -> float | None:
    try:
        return float(values.convert_from_string(values.DOUBLE, text, double_from_chars=from_chars))  # type: ignore[arg-type]
    except values.ConversionError:
        return None


def _literal(x: float) -> str | None:
    """A script literal for x (plain decimal), or None."""
    if math.isnan(x) or math.isinf(x):
        return None
    text = repr(float(x))
    return None if "e" in text or "E" in text else text.lstrip("-") if x == 0 else text


def checks(text: str, integer: bool) -> list[str]:
    cands: list[float] = []
    if integer:
        with contextlib.suppress(values.ConversionError):
            cands.append(float(values.convert_from_string(values.INT, text)))  # type: ignore[arg-type]
    else:
        for fc in (False, True):
            c = _candidate(text, fc)
            if c is not None and not any(c == d for d in cands):
                cands.append(c)
    codes = ["x == x", "x &gt; 1000000.0", "(0.0 - x) &gt; 1000000.0"]
    for c in cands:
        lit = _literal(c)
        if lit is not None:
            codes.append(f"x == {lit}")
    return codes


def body(site: str, text: str) -> str:
    attr = text.replace("&", "&amp;").replace('"', "&quot;").replace("<", "&lt;")
    typing = ""  # a node never ticked whose port declares x a double (or int) at load
    if site == "loop_literal":
        conv = f'<LoopDouble queue="{attr};1.0" value="{{x}}">\n        <AlwaysSuccess/>\n      </LoopDouble>'
    elif site == "loopint_literal":
        conv = f'<LoopInt queue="{attr};1" value="{{x}}">\n        <AlwaysSuccess/>\n      </LoopInt>'
    elif site == "set_literal":
        conv = f'<SetBlackboard value="{attr}" output_key="x"/>'
        typing = "double"
    elif site == "set_copy":
        conv = f'<SetBlackboard value="{attr}" output_key="s"/>\n      <SetBlackboard value="{{s}}" output_key="x"/>'
        typing = "double"
    elif site == "loop_entry":
        conv = (
            f'<SetBlackboard value="{attr};1.0" output_key="s"/>\n'
            '      <LoopDouble queue="{s}" value="{x}">\n        <AlwaysSuccess/>\n      </LoopDouble>'
        )
    elif site == "script_store":
        quoted = attr.replace("'", "")
        conv = f"<Script code=\"x := '{quoted}'\"/>"
        typing = "double"
    else:
        raise ValueError(site)
    # The loops hand x the first element, then 1.0: the checks run inside the loop, on the first.
    integer = site == "loopint_literal"
    tests = "".join(
        f'\n        <ForceSuccess>\n          <ScriptCondition code="{c}"/>\n        </ForceSuccess>'
        for c in checks(text, integer)
    )
    if site.startswith("loop"):
        nested = tests.replace("\n", "\n    ")
        inner = (
            '<Sequence>\n        <Script code="n := n + 1"/>\n'
            '        <Precondition if="n == 1" else="SUCCESS">\n'
            f"          <Sequence>{nested}\n          </Sequence>\n"
            "        </Precondition>\n      </Sequence>"
        )
        conv = conv.replace("<AlwaysSuccess/>", inner)
        tests = ""
        start = '<Script code="n := 0"/>\n      '
    else:
        start = ""
    typed = ""
    if typing:
        typed = (
            '\n      <Fallback>\n        <AlwaysSuccess/>\n        <LoopDouble queue="1.0" value="{x}">\n'
            "          <AlwaysSuccess/>\n        </LoopDouble>\n      </Fallback>"
        )
    return f"<Sequence>{typed}\n      {start}{conv}{tests}\n    </Sequence>"


def mission(site: str, text: str) -> str:
    return (
        f"<!-- {SITES[site]}: the text `{text.replace('--', '- -')}` -->\n"
        '<root BTCPP_format="4" main_tree_to_execute="Main">\n'
        f'  <BehaviorTree ID="Main">\n    {body(site, text)}\n  </BehaviorTree>\n</root>\n'
    )


def stem_of(site: str, i: int) -> str:
    return f"{site}_{i:02d}"


def cases() -> list[tuple[str, str, str]]:
    out = []
    for site in SITES:
        inputs = INT_INPUTS if site == "loopint_literal" else DOUBLE_INPUTS
        for i, text in enumerate(inputs):
            out.append((stem_of(site, i), site, text))
    return out


def write() -> None:
    os.makedirs(OUT, exist_ok=True)
    for stem, site, text in cases():
        with open(os.path.join(OUT, stem + ".xml"), "w", encoding="utf-8") as f:
            f.write(mission(site, text))
        with open(os.path.join(OUT, stem + ".scenario"), "w", encoding="utf-8") as f:
            f.write("ticks 6\n")


def record(version: str, harness: str) -> None:
    from record_releases import record as record_folder

    record_folder(OUT, version, harness)


def reading(version: str, stem: str, text: str, integer: bool) -> str:
    """What the recording says the release read: the value, or the error."""
    folder = os.path.join(OUT, version)
    if not os.path.exists(os.path.join(folder, stem + ".trace")):
        return "?"
    with open(os.path.join(folder, stem + ".trace"), encoding="utf-8") as f:
        trace = f.read()
    err = os.path.join(folder, stem + ".error")
    held = re.findall(r'ScriptCondition "ScriptCondition" IDLE -> (SUCCESS|FAILURE)', trace)
    codes = [c.replace("&gt;", ">").replace("&lt;", "<") for c in checks(text, integer)]
    if len(held) < len(codes):
        if os.path.exists(err):
            with open(err, encoding="utf-8") as f:
                return "error: " + f.read().strip().removeprefix("error: ")
        return "not reached (the mission ends before)"
    ok = dict(zip(codes, (h == "SUCCESS" for h in held)))
    if ok["x > 1000000.0"] and ok["(0.0 - x) > 1000000.0"]:
        return "nan"  # (4.6.2's `>` holds for NaN)
    if ok["x > 1000000.0"]:
        return "inf"
    if ok["(0.0 - x) > 1000000.0"]:
        return "-inf"
    if not ok["x == x"]:
        return "nan"
    for c, v in ok.items():
        if v and c.startswith("x == ") and c != "x == x":
            return c[len("x == ") :]
    return "a value none of the checks names"


def table() -> str:
    lines = [
        "| site | text | 4.6.2 | 4.10.0 |",
        "|---|---|---|---|",
    ]
    for stem, site, text in cases():
        integer = site == "loopint_literal"
        cells = [reading(v, stem, text, integer) for v in ("4.6.2", "4.10.0")]
        lines.append(f"| {SITES[site]} | `{text}` | {cells[0]} | {cells[1]} |")
    return "\n".join(lines)


INDEX_HEAD = """# The text-to-number conversion table of BehaviorTree.CPP 4.6.2 and 4.10.0

One mission per (site, text), written by `scripts/conversion_cases.py`: the text is converted
to a number at one site of the data side, and ScriptConditions under ForceSuccess compare the
value with the candidates (what `std::stod` and `std::from_chars` read), with itself and with
±10^6 (the library's scripts find an infinity unequal to itself, and NaN both above 10^6 and
below -10^6, which tells the two apart). `4.6.2/<stem>.trace` and
`4.10.0/<stem>.trace` are what the real library printed (cut short where it threw);
`<stem>.error` is its message when it threw or refused the file. Recorded with

    python scripts/conversion_cases.py --record 4.6.2 PREFIX462/bin/harness
    python scripts/conversion_cases.py --record 4.10.0 PREFIX410/bin/harness

`tests/python/test_conversions.py` runs every case through the interpreter and the compiled
executor of each release: same trace, and an error exactly where the library failed (btgen's
own message, the same in both engines). The value each release read, from the recordings
(`python scripts/conversion_cases.py --table`):

"""

INDEX_TAIL = """
Reading the table: `convertFromString<double>` is `std::stod` in 4.6.2 (blanks, `+`, hex floats;
a subnormal is out of range) and `std::from_chars` in 4.10.0 (`0x1p3` reads 0.0, stopping at
`x`; a blank or `+` first is an error; a subnormal is a value). Integers are `std::from_chars`
in both. In 4.6.2 a SetBlackboard copy of a string entry into a double entry copies the string
as it is, which a script then fails to use as a number; both btgen engines convert it instead
(the one known difference, `xfail` in the test). In 4.10.0 SetBlackboard leaves a new untyped
entry empty, so the copy and the LoopDouble reading such an entry never see the text.
"""


def index() -> str:
    """tests/conformance/conversions/INDEX.md: what the folder holds and the table."""
    return INDEX_HEAD + table() + "\n" + INDEX_TAIL


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--record", nargs=2, metavar=("VERSION", "HARNESS"))
    p.add_argument("--table", action="store_true", help="print the table")
    p.add_argument("--index", action="store_true", help="write INDEX.md (the table and what it means)")
    args = p.parse_args()
    if args.record:
        record(*args.record)
    elif args.table:
        print(table())
    elif args.index:
        with open(os.path.join(OUT, "INDEX.md"), "w", encoding="utf-8") as f:
            f.write(index())
    else:
        write()
    return 0


if __name__ == "__main__":
    sys.exit(main())
