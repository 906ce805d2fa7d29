#!/usr/bin/env python3
"""Written missions on issue 44's themes, run on the real library, the interpreter AND the C++.

    python scripts/oracle_themes.py OUT_DIR [--keep DIR] [--only FAMILY,...] [--no-cpp]
                                    [--cpp-every N] [--cpp-offset K] [--batch N]

The families scripts/oracle_edges.py leaves thin: one entry written by typed and changing-type
writers in turn (scripts, SetBlackboard literals and copies, the Loop nodes' typed `value`) and
read by scripts, typed ports and Switch; SubTree ports of changing type (remapped, `_autoremap`,
literal, model defaults); every script operator over entries of every writer; Loop nodes over
blackboard queues written by scripts, SetBlackboard and other Loops; Precondition,
ScriptCondition and `_skipIf`/`_successIf`/`_failureIf`/`_while` over changing entries; every
text form of a number or boolean into every typed port, literal, through SetBlackboard and
through a script; SKIPPED conditions of IfThenElse and WhileDoElse and TryCatch's
`catch_on_halt` while the entries change between ticks.

Every case is run on both releases of the real library (scripts/oracle_random.py's harnesses)
and by btgen's interpreter (the verdicts of oracle_random.compare), then compiled and run by the
C++ back end (batched as scripts/difftest.py does; `--cpp-every N` builds every Nth case only,
`--no-cpp` none), whose trace and failure must match the library's too, with the interpreter's
message. A mission the C++ back end refuses ("not supported by the C++ back end yet") or rejects
for another reason while the interpreter runs it is counted and listed by message (backticked
names masked). Prints a table per
family and release; divergences are kept in --keep (default build/oracle-themes-divergences).
Exit 1 on a divergence.
"""

from __future__ import annotations

import argparse
import os
import re
import sys
import time
from collections import Counter, defaultdict
from pathlib import Path
from xml.sax.saxutils import quoteattr

sys.path.insert(0, str(Path(__file__).resolve().parent))

import difftest
import oracle_random as orc

Case = tuple[str, str, str]  # stem, mission, scenario

MODELS = """  <TreeNodesModel>
    <Action ID="Act"/>
    <Condition ID="Check"/>
    <Action ID="Show"><input_port name="what"/></Action>
  </TreeNodesModel>"""


def mission(body: str, extra: str = "", models: str = MODELS) -> str:
    return (
        '<root BTCPP_format="4" main_tree_to_execute="Main">\n'
        '  <BehaviorTree ID="Main">\n'
        f"    <Sequence>{body}</Sequence>\n"
        "  </BehaviorTree>\n" + extra + models + "\n</root>\n"
    )


def script(code: str, name: str = "") -> str:
    return f"<Script{' name=' + quoteattr(name) if name else ''} code={quoteattr(code)}/>"


def probes(key: str, values: tuple[str, ...]) -> str:
    """One ForceSuccess'd ScriptCondition per value: the trace shows which comparisons held."""
    return "".join(
        f"<ForceSuccess><ScriptCondition name={quoteattr(f'{key}=={v}')} code={quoteattr(f'{key} == {v}')}/>"
        "</ForceSuccess>"
        for v in values
    )


# Writers of entry `v` (each a fragment), typed (the Loop nodes' `value`, a typed port) or not.
def writers(key: str) -> dict[str, str]:
    return {
        "int": script(f"{key} := 3"),
        "dbl": script(f"{key} := 2.5"),
        "str": script(f"{key} := 'abc'"),
        "numstr": script(f"{key} := '7'"),
        "bool": script(f"{key} := true"),
        "sbnum": f'<SetBlackboard value="7" output_key="{key}"/>',
        "sbtext": f'<SetBlackboard value="xy" output_key="{key}"/>',
        "sbcopy": script("w := 5") + f'<SetBlackboard value="{{w}}" output_key="{key}"/>',
        "loopint": f'<LoopInt queue="1;2" value="{{{key}}}"><AlwaysSuccess/></LoopInt>',
        "loopdbl": f'<LoopDouble queue="1.5" value="{{{key}}}"><AlwaysSuccess/></LoopDouble>',
        "loopstr": f'<LoopString queue="x;4" value="{{{key}}}"><AlwaysSuccess/></LoopString>',
        "loopbool": f'<LoopBool queue="true;false" value="{{{key}}}"><AlwaysSuccess/></LoopBool>',
        "port": f'<Show what="{{{key}}}"/>',
    }


def fam_mixed() -> list[Case]:
    """Two writers of one entry in turn, then comparisons and a typed reader."""
    out = []
    w = writers("v")
    readers = {
        "num": probes("v", ("3", "2.5", "7", "5", "2", "1.5", "4", "true", "false")),
        "text": probes("v", ("'abc'", "'7'", "'xy'", "'4'", "'x'", "'3'", "'true'")),
        "repeat": '<Repeat num_cycles="{v}"><Act name="r"/></Repeat>',
        "switch": '<Switch3 variable="{v}" case_1="3" case_2="abc" case_3="2">'
        + "".join(f'<Act name="k{i}"/>' for i in range(4))
        + "</Switch3>",
        "script": script("z := v + 1") + probes("z", ("4", "3.5", "8", "'abc1'", "'71'", "3", "6", "2.5")),
    }
    for a, wa in w.items():
        for b, wb in w.items():
            for rname, reader in readers.items():
                if rname not in ("num", "text") and (a, b) not in _SAMPLE and a != b:
                    continue
                body = wa + wb + reader
                out.append((f"mixed_{a}_{b}_{rname}", mission(body), "ticks 2\ndefault SUCCESS\n"))
    return out


_SAMPLE = {
    (a, b)
    for a in ("int", "str", "sbnum", "loopint", "port", "loopstr", "sbcopy")
    for b in ("int", "dbl", "str", "numstr", "sbnum", "sbtext", "loopint", "loopstr", "sbcopy", "port")
}


def fam_subtree() -> list[Case]:
    """SubTree ports of changing type: the outer entry written one way, the inner another."""
    out = []
    models = MODELS.replace(
        "  </TreeNodesModel>",
        '    <SubTree ID="S">\n      <inout_port name="p" default="5"/>\n    </SubTree>\n  </TreeNodesModel>',
    )
    outer = {
        "none": "",
        "int": script("x := 3"),
        "str": script("x := 'abc'"),
        "sbnum": '<SetBlackboard value="7" output_key="x"/>',
        "loopint": '<LoopInt queue="4" value="{x}"><AlwaysSuccess/></LoopInt>',
    }
    calls = {
        "remap": '<SubTree ID="S" p="{x}"/>',
        "auto": '<SubTree ID="S" _autoremap="true"/>',
        "literal": '<SubTree ID="S" p="9"/>',
        "default": '<SubTree ID="S"/>',
    }
    inner = {
        "read": probes("p", ("3", "'abc'", "7", "4", "9", "5", "'5'")),
        "int": script("p := 11") + probes("p", ("11",)),
        "str": script("p := 'zz'"),
        "add": script("p := p + 1") + probes("p", ("4", "8", "5", "10", "6", "'abc1'")),
        "loopint": '<LoopInt queue="6" value="{p}"><AlwaysSuccess/></LoopInt>',
        "sbtext": '<SetBlackboard value="qq" output_key="p"/>',
        "loopstr": '<LoopString queue="s" value="{p}"><AlwaysSuccess/></LoopString>',
    }
    for o, wo in outer.items():
        for c, call in calls.items():
            if c == "auto":
                call_x = call.replace("_autoremap", "_autoremap")  # the inner `p` is the outer `p`
                wo_ = wo.replace("x :=", "p :=").replace('"x"', '"p"').replace("{x}", "{p}")
            else:
                call_x, wo_ = call, wo
            for i, wi in inner.items():
                sub = f'  <BehaviorTree ID="S">\n    <Sequence>{wi}</Sequence>\n  </BehaviorTree>\n'
                key = "p" if c == "auto" else "x"
                body = wo_ + call_x + probes(key, ("3", "'abc'", "7", "4", "11", "'zz'", "6", "'qq'", "'s'", "5"))
                out.append((f"subtree_{o}_{c}_{i}", mission(body, sub, models), "ticks 1\ndefault SUCCESS\n"))
    return out


OPS = ("+", "-", "*", "/", "%", "&", "|", "^", "..", "==", "!=", "<", "<=", ">", ">=", "&&", "||")


def fam_operators() -> list[Case]:
    """Every binary operator over two entries of every writer, the unary ones and the compound
    assignments: the result seen through comparisons."""
    out = []
    wa = writers("a")
    wb = {k: v for k, v in writers("b").items() if k in ("int", "dbl", "numstr", "sbnum", "loopstr", "str")}
    look = probes("x", ("3", "10", "0", "1", "true", "false", "'37'", "'abc7'", "6", "9", "4", "1.5"))
    for a, xa in wa.items():
        for b, xb in wb.items():
            for k, op in enumerate(OPS):
                body = xa + xb + script(f"x := a {op} b") + look
                out.append((f"op_{a}_{b}_{k:02d}", mission(body), "ticks 1\ndefault SUCCESS\n"))
        for k, op in enumerate(("-a", "!a", "~a", "a ? 1 : 2")):
            out.append((f"unary_{a}_{k}", mission(xa + script(f"x := {op}") + look), "ticks 1\ndefault SUCCESS\n"))
        for k, op in enumerate(("+=", "-=", "*=", "/=", "=")):
            for b in ("int", "str", "dbl"):
                lit = {"int": "2", "str": "'s'", "dbl": "0.5"}[b]
                body = xa + script(f"a {op} {lit}") + probes("a", ("5", "1", "6", "'abcs'", "3.5", "'s'", "2", "0.5"))
                out.append((f"compound_{a}_{k}_{b}", mission(body), "ticks 1\ndefault SUCCESS\n"))
    return out


def fam_queues() -> list[Case]:
    """Loop nodes over a blackboard queue written by a script, SetBlackboard or another Loop, run
    twice (a queue from the blackboard is consumed, a text is converted anew)."""
    out = []
    sources = {
        "script": script("q := '1;2;3'"),
        "scriptnum": script("q := 5"),
        "scriptdbl": script("q := 2.5"),
        "scriptbool": script("q := true"),
        "scriptempty": script("q := ''"),
        "sb": '<SetBlackboard value="1;2;3" output_key="q"/>',
        "sbone": '<SetBlackboard value="4" output_key="q"/>',
        "sbcopy": script("w := '6;7'") + '<SetBlackboard value="{w}" output_key="q"/>',
        "loopstr": '<LoopString queue="8;9" value="{q}"><AlwaysSuccess/></LoopString>',
        "loopint": '<LoopInt queue="1" value="{q}"><AlwaysSuccess/></LoopInt>',
        "port": '<Show what="{q}"/>' + script("q := '1;0'"),
    }
    for s, src in sources.items():
        for node in ("LoopInt", "LoopDouble", "LoopString", "LoopBool"):
            for again in ("once", "twice", "rewrite"):
                loop = f'<{node} queue="{{q}}" value="{{item}}" if_empty="FAILURE"><Act name="a"/></{node}>'
                body = src + f"<ForceSuccess>{loop}</ForceSuccess>"
                if again == "twice":
                    body += f"<ForceSuccess>{loop}</ForceSuccess>"
                if again == "rewrite":
                    body += src + f"<ForceSuccess>{loop}</ForceSuccess>"
                body += probes("item", ("1", "3", "'3'", "5", "2.5", "true", "4", "7", "9", "'9'", "0"))
                out.append((f"queue_{s}_{node}_{again}", mission(body), "ticks 3\ndefault SUCCESS\n"))
    return out


def fam_conditions() -> list[Case]:
    """Precondition, ScriptCondition and the pre-conditions over an entry of every writer."""
    out = []
    w = writers("v")
    tests = ("v == 3", "v == '7'", "v", "v > 2", "v == 'abc'", "v != 1.5")
    for name, wv in w.items():
        for k, t in enumerate(tests):
            forms = {
                "pre": f'<Precondition if={quoteattr(t)} else="FAILURE"><Act name="a"/></Precondition>',
                "cond": f"<ScriptCondition code={quoteattr(t)}/>",
                "skip": f'<Act name="a" _skipIf={quoteattr(t)}/>',
                "succ": f'<Act name="a" _successIf={quoteattr(t)}/>',
                "while": f'<Act name="a" _while={quoteattr(t)}/>',
            }
            for f, node in forms.items():
                body = wv + f"<Fallback>{node}<Act name='fb'/></Fallback>"
                out.append((f"cond_{name}_{k}_{f}", mission(body), "ticks 2\ndefault SUCCESS\nleaf a RUNNING\n"))
    return out


TEXTS = (
    "3",
    " 3",
    "3 ",
    "+3",
    "-3",
    "03",
    "0x10",
    "0X1f",
    "1e2",
    "2.5",
    "2.",
    ".5",
    "-0",
    "inf",
    "-inf",
    "nan",
    "NaN",
    "infinity",
    "0x1p3",
    "1e400",
    "99999999999",
    "true",
    "TRUE",
    "false",
    "1",
    "0",
    "",
    "abc",
    "3abc",
    "1;2",
)


def fam_conversions() -> list[Case]:
    """Every text form into every typed port: a literal, a SetBlackboard literal, a script string."""
    out = []
    ports = {
        "repeat": ('<Repeat num_cycles="{}"><Act name="a"/></Repeat>', "ticks 4\ndefault SUCCESS\n"),
        "retry": (
            '<RetryUntilSuccessful num_attempts="{}"><Act name="a"/></RetryUntilSuccessful>',
            "ticks 4\ndefault FAILURE\n",
        ),
        "parallel": (
            '<Parallel success_count="{}" failure_count="1"><Act name="a"/><Act name="b"/></Parallel>',
            "ticks 4\ndefault SUCCESS\n",
        ),
        "runonce": ('<RunOnce then_skip="{}"><Act name="a"/></RunOnce>', "ticks 4\ndefault SUCCESS\n"),
        "loopint": ('<LoopInt queue="{}" value="{{i}}"><Act name="a"/></LoopInt>', "ticks 4\ndefault SUCCESS\n"),
        "loopdbl": ('<LoopDouble queue="{}" value="{{i}}"><Act name="a"/></LoopDouble>', "ticks 4\ndefault SUCCESS\n"),
        "loopbool": ('<LoopBool queue="{}" value="{{i}}"><Act name="a"/></LoopBool>', "ticks 4\ndefault SUCCESS\n"),
        "switch": (
            '<Switch2 variable="{}" case_1="3" case_2="2.5"><Act name="a"/><Act name="b"/><Act name="c"/></Switch2>',
            "ticks 4\ndefault SUCCESS\n",
        ),
        "precond": (
            '<Precondition if="false" else="{}"><Act name="a"/></Precondition>',
            "ticks 4\ndefault SUCCESS\n",
        ),
        "intentry": (
            '<ForceSuccess><LoopInt queue="1" value="{{i}}"><AlwaysSuccess/></LoopInt></ForceSuccess>'
            '<SetBlackboard value="{}" output_key="i"/>',
            "ticks 4\ndefault SUCCESS\n",
        ),
        "dblentry": (
            '<ForceSuccess><LoopDouble queue="1" value="{{i}}"><AlwaysSuccess/></LoopDouble></ForceSuccess>'
            '<SetBlackboard value="{}" output_key="i"/>',
            "ticks 4\ndefault SUCCESS\n",
        ),
    }
    look = probes("i", ("3", "1", "2.5", "0", "16", "true", "'3'"))
    for pname, (tmpl, sc) in ports.items():
        for k, text in enumerate(TEXTS):
            vias = {
                "lit": ("", text),
                "sb": (f"<SetBlackboard value={quoteattr(text)} output_key='k'/>", "{k}"),
                "scr": (script(f"k := {text!r}"), "{k}"),
            }
            for via, (pre, arg) in vias.items():
                node = tmpl.replace("{}", quoteattr(arg)[1:-1]).replace("{{", "{").replace("}}", "}")
                body = pre + f"<Fallback>{node}<Act name='fb'/></Fallback>" + look
                out.append((f"conv_{pname}_{k:02d}_{via}", mission(body), sc))
    return out


def fam_branches() -> list[Case]:
    """IfThenElse / WhileDoElse whose condition or branch is skipped on some ticks (an entry a
    script changes between ticks), and TryCatch with catch_on_halt while entries change."""
    out = []
    skips = ("n == 1", "n == 2", "n >= 1", "n == 0", "false")
    statuses = ("RUNNING RUNNING SUCCESS", "FAILURE SUCCESS", "RUNNING FAILURE", "SUCCESS")
    for kind in ("IfThenElse", "WhileDoElse"):
        for si, s in enumerate(skips):
            for where in ("cond", "then", "else", "both"):
                for ti, st in enumerate(statuses):
                    attrs = {p: (f" _skipIf={quoteattr(s)}" if where in (p, "both") else "") for p in ("c", "t", "e")}
                    if where == "both":
                        attrs["e"] = ""
                    node = (
                        f'<{kind}><Check name="c"{attrs["c"]}/><Act name="t"{attrs["t"]}/>'
                        f'<Act name="e"{attrs["e"]}/></{kind}>'
                    )
                    body = (
                        script("n := 0")
                        + "<ReactiveSequence>"
                        + script("n := n + 1", "inc")
                        + node
                        + "</ReactiveSequence>"
                    )
                    sc = f"ticks 5\nleaf c SUCCESS FAILURE SUCCESS\nleaf t {st}\nleaf e {st}\n"
                    out.append((f"branch_{kind}_{si}_{where}_{ti}", mission(body), sc))
    for coh in ("true", "false"):
        for si, s in enumerate(skips):
            for ti, st in enumerate(statuses):
                body = (
                    script("n := 0")
                    + '<ReactiveSequence><Check name="guard"/>'
                    + script("n := n + 1", "inc")
                    + f'<TryCatch catch_on_halt="{coh}"><Sequence><Act name="t" _skipIf={quoteattr(s)}/>'
                    + '<Act name="u"/></Sequence>'
                    + f"<Sequence>{script('n := n + 10', 'caught')}<Act name='e'/></Sequence></TryCatch>"
                    + "</ReactiveSequence>"
                    + probes("n", ("3", "4", "13", "14", "23", "24"))
                )
                sc = f"ticks 5\nleaf guard SUCCESS SUCCESS SUCCESS FAILURE\nleaf t {st}\nleaf u {st}\nleaf e RUNNING\n"
                out.append((f"trycatch_{coh}_{si}_{ti}", mission(body), sc))
    return out


def fam_text_numbers() -> list[Case]:
    """Every text form of a number written into an entry (script, SetBlackboard, LoopString) and
    used by scripts as a number, compared, and read by a typed port (from_chars against stod)."""
    out = []
    uses = {
        "add": script("x := v + 0") + probes("x", ("3", "16", "100", "2.5", "0", "1", "31")),
        "mul": script("x := v * 1.0") + probes("x", ("3", "16", "100", "2.5", "0", "1")),
        "cmp": probes("v", ("3", "16", "100", "2.5", "0", "1")),
        "neg": script("x := -v") + probes("x", ("-3", "-2.5", "0")),
        "repeat": '<Repeat num_cycles="{v}"><Act name="r"/></Repeat>',
        "cond": "<ScriptCondition code='v'/>",
    }
    for k, text in enumerate(TEXTS):
        writers_ = {
            "scr": script(f"v := {text!r}"),
            "sb": f"<SetBlackboard value={quoteattr(text)} output_key='v'/>",
            "loop": f"<LoopString queue={quoteattr(text + ';')} value='{{v}}' if_empty='SUCCESS'>"
            "<AlwaysSuccess/></LoopString>",
        }
        for w, wr in writers_.items():
            if w == "loop" and ";" in text:
                continue
            for u, use in uses.items():
                out.append((f"text_{k:02d}_{w}_{u}", mission(wr + use), "ticks 3\ndefault SUCCESS\n"))
    return out


def fam_dynamic_keys() -> list[Case]:
    """Keys read from entries: SetBlackboard output_key / UnsetBlackboard key / SkipUnlessUpdated
    entry named by an entry a script, a SetBlackboard or a Loop wrote, into typed and changing
    entries."""
    out = []
    key_writers = {
        "scr": script("k := 'n'"),
        "sb": '<SetBlackboard value="n" output_key="k"/>',
        "loop": '<LoopString queue="n" value="{k}"><AlwaysSuccess/></LoopString>',
        "num": script("k := 5"),
    }
    targets = {
        "none": "",
        "int": '<ForceSuccess><LoopInt queue="1" value="{n}"><AlwaysSuccess/></LoopInt></ForceSuccess>',
        "str": script("n := 'abc'"),
        "dbl": script("n := 2.5"),
        "port": '<Show what="{n}"/>',
    }
    actions = {
        "set": '<SetBlackboard value="41" output_key="{k}"/>',
        "settext": '<SetBlackboard value="zz" output_key="{k}"/>',
        "setcopy": script("m := 8") + '<SetBlackboard value="{m}" output_key="{k}"/>',
        "unset": '<UnsetBlackboard key="{k}"/>',
    }
    look = probes("n", ("41", "'41'", "8", "1", "2.5", "'zz'", "'abc'"))
    for kw, kwx in key_writers.items():
        for t, tx in targets.items():
            for a, ax in actions.items():
                body = tx + kwx + ax + look + script("p := n + 1") + probes("p", ("42", "9", "2", "3.5"))
                out.append((f"dkey_{kw}_{t}_{a}", mission(body), "ticks 1\ndefault SUCCESS\n"))
    return out


def fam_switch() -> list[Case]:
    """Switch over an entry of every writer against case labels of every text form."""
    out = []
    w = writers("v")
    labels = ("3", "3.0", "03", " 3", "abc", "7", "2.5", "2.50", "true", "1", "x", "4")
    for name, wv in w.items():
        for i in range(0, len(labels), 3):
            cases = labels[i : i + 3]
            attrs = " ".join(f"case_{j}={quoteattr(c)}" for j, c in enumerate(cases, 1))
            kids = "".join(f'<Act name="k{j}"/>' for j in range(len(cases) + 1))
            body = wv + f'<Switch3 variable="{{v}}" {attrs}>{kids}</Switch3>'
            out.append((f"switch_{name}_{i}", mission(body), "ticks 3\ndefault SUCCESS\n"))
    return out


FAMILIES = {
    "mixed writers": fam_mixed,
    "subtree ports": fam_subtree,
    "operators": fam_operators,
    "queues": fam_queues,
    "conditions": fam_conditions,
    "conversions": fam_conversions,
    "branches": fam_branches,
    "text numbers": fam_text_numbers,
    "dynamic keys": fam_dynamic_keys,
    "switch": fam_switch,
}


DUMP = re.compile(r"^[^ \n]+ \((?:BT::|std::)?[\w:<>, ]+\)\n", re.M)


def verdict_of(lib: tuple[str, bool, str], got: tuple[str, bool, str], version: str, text: str) -> str:
    """oracle_random.compare, and `blackboard dump` where the only difference is the lines the
    library prints on stdout (Blackboard::debugMessage, `key (type)`) before it throws on a write
    that changes an entry's type: a known difference (tests/python/test_changing_types.py KNOWN)."""
    verdict = orc.compare(lib, got, version, text)
    if verdict == "divergence" and lib[1] and got[1] and "shall not change" in lib[2]:
        if DUMP.sub("", lib[0]) == got[0] and DUMP.search(lib[0]):
            return "blackboard dump"
    return verdict


def cpp_runs(cases: list[tuple[str, str, str, str]], work: Path, batch: int, log) -> dict:
    """(family, stem, version) -> ("refused", message) | ("rejected", message) | ("ran", Outcome)."""
    results: dict = {}
    old = os.getcwd()
    os.chdir(work)
    try:
        for version in orc.BTCPP_VERSIONS:
            difftest.BTCPP[0] = version
            compiled = []
            for family, stem, _, _ in cases:
                rel = f"{stem}.xml"
                kind, msg = difftest.classify(rel)
                if kind == "unsupported":
                    results[(family, stem, version)] = ("refused", msg)
                elif kind == "rejected":
                    results[(family, stem, version)] = ("rejected", msg)
                elif kind == "compiled":
                    compiled.append((family, stem))
            for i in range(0, len(compiled), batch):
                chunk = compiled[i : i + batch]
                t = time.monotonic()
                binary = difftest.build_batch([f"{s}.xml" for _, s in chunk])
                log(f"  C++ {version}: built {len(chunk)} missions in {time.monotonic() - t:.0f} s")
                for index, (family, stem) in enumerate(chunk):
                    results[(family, stem, version)] = (
                        "ran",
                        difftest.run_cpp(binary, index, f"{stem}.xml", f"{stem}.scenario"),
                    )
            difftest._MISSIONS.clear()
    finally:
        difftest.BTCPP[0] = "4.6.2"
        os.chdir(old)
    return results


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("out", type=Path)
    p.add_argument("--keep", type=Path, default=orc.ROOT / "build" / "oracle-themes-divergences")
    p.add_argument("--only", default="", help="families, comma-separated (names as in the table)")
    p.add_argument("--no-cpp", action="store_true")
    p.add_argument("--cpp-every", type=int, default=1, help="compile every Nth case only")
    p.add_argument("--cpp-offset", type=int, default=0, help="starting with case K (0-based)")
    p.add_argument("--batch", type=int, default=80, help="missions per C++ executable")
    p.add_argument("--list", action="store_true", help="print the families and their case counts")
    args = p.parse_args(argv)
    only = [f for f in args.only.split(",") if f]
    for f in only:
        if f not in FAMILIES:
            p.error(f"unknown family `{f}`; known: {', '.join(FAMILIES)}")
    fams = {k: fn() for k, fn in FAMILIES.items() if not only or k in only}
    if args.list:
        for k, items in fams.items():
            print(f"{k}: {len(items)}")
        return 0
    out = args.out.resolve()
    out.mkdir(parents=True, exist_ok=True)
    log = lambda s: print(s, file=sys.stderr, flush=True)  # noqa: E731
    counts: Counter = Counter()
    lib_of: dict = {}
    interp_of: dict = {}
    start = time.monotonic()
    every: list[tuple[str, str, str, str]] = []
    for family, items in fams.items():
        for stem, text, scenario in items:
            m, s = out / f"{stem}.xml", out / f"{stem}.scenario"
            m.write_text(text, encoding="utf-8")
            s.write_text(scenario, encoding="utf-8")
            every.append((family, stem, text, scenario))
            for version in orc.BTCPP_VERSIONS:
                lib = orc.observe(orc.default_harness(version), text, str(m), str(s), str(out))
                got = orc.interpreter(str(m), str(s), version)
                lib_of[(stem, version)], interp_of[(stem, version)] = lib, got
                verdict = verdict_of(lib, got, version, text)
                counts[(family, version, "runs")] += 1
                counts[(family, version, "library threw" if lib[1] else "library ran")] += 1
                counts[(family, version, f"interp {verdict}")] += 1
                if verdict == "divergence":
                    orc.keep_case(args.keep, f"{stem}_on{version.replace('.', '')}", text, scenario, lib, got)
                    log(f"DIVERGENCE interpreter {family} {stem} on {version}")
        log(f"{family}: {len(items)} cases on the library and the interpreter, {time.monotonic() - start:.0f} s")
    refusals: dict[str, list[str]] = defaultdict(list)
    if not args.no_cpp:
        chosen = every[args.cpp_offset :: max(1, args.cpp_every)]
        results = cpp_runs(chosen, out, args.batch, log)
        for (family, stem, version), (kind, res) in sorted(results.items()):
            text = next(t for f, s, t, _ in chosen if s == stem)
            if kind != "ran":
                counts[(family, version, f"C++ {kind}")] += 1
                first = res.splitlines()[0].split(": error: ", 1)[-1]
                refusals[f"{kind}: {re.sub(r'`[^`]*`', '`_`', first)[:160]}"].append(f"{stem} ({version})")
                continue
            lib, got = lib_of[(stem, version)], interp_of[(stem, version)]
            mine = (res.stdout, res.rc == 1, res.stderr)
            verdict = verdict_of(lib, mine, version, text) if res.rc in (0, 1) else "divergence"
            if verdict != "divergence" and got[1] and got[2] not in res.stderr:
                verdict = "divergence"  # the interpreter's message, byte for byte
            if verdict == "divergence" and got[:2] == mine[:2]:
                verdict = verdict_of(lib, got, version, text)  # a documented or known difference
            counts[(family, version, f"C++ {verdict}")] += 1
            if verdict == "divergence":
                orc.keep_case(args.keep, f"{stem}_on{version.replace('.', '')}_cpp", text, "", lib, mine)
                log(f"DIVERGENCE C++ {family} {stem} on {version}: rc {res.rc} {res.stderr[-200:]!r}")
    print(
        "| family | release | runs | library threw | interpreter agrees | documented | blackboard dump "
        "| divergences | C++ runs | C++ agrees | C++ documented or dump | C++ not supported yet | C++ rejected "
        "| C++ divergences |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for family in fams:
        for v in orc.BTCPP_VERSIONS:
            c = lambda w, f=family, r=v: counts[(f, r, w)]  # noqa: E731
            doc = c("interp documented") + c("interp library abort")
            cdoc = c("C++ documented") + c("C++ library abort") + c("C++ blackboard dump")
            cpp = c("C++ agree") + cdoc + c("C++ divergence")
            print(
                f"| {family} | {v} | {c('runs')} | {c('library threw')} | {c('interp agree')} | {doc} "
                f"| {c('interp blackboard dump')} | {c('interp divergence')} | {cpp} | {c('C++ agree')} | {cdoc} "
                f"| {c('C++ refused')} | {c('C++ rejected')} | {c('C++ divergence')} |"
            )
    for message, where in sorted(refusals.items(), key=lambda kv: -len(kv[1])):
        print(f"C++ {len(where)}x {message}\n    e.g. {', '.join(where[:4])}")
    div = sum(n for k, n in counts.items() if k[2].endswith("divergence"))
    print(f"{len(every)} cases, {div} divergences, {time.monotonic() - start:.0f} s")
    return 1 if div else 0


if __name__ == "__main__":
    sys.exit(main())
