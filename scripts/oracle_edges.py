#!/usr/bin/env python3
"""Written edge cases around what fuzzgen does not reach, compared with the real library.

    python scripts/oracle_edges.py OUT_DIR [--keep DIR] [--only FAMILY,...]

Writes one mission and scenario per case into OUT_DIR (halting every Control and Decorator
while it runs, SKIPPED through every Control, every pre/post-condition on every node kind,
script operators and conversions, Parallel thresholds, Repeat/Retry with -1 and 0, RunOnce
then_skip, Switch2..6 on numbers, strings and enums, Loop nodes with empty and odd queues,
SubTree remapping, `_autoremap` and port defaults, TryCatch, entries never written, ports
reading entries of another type, script values seen through comparisons), runs each on both releases of the
real library and in btgen's interpreter (scripts/oracle_random.py), and prints the counts per
family and every divergence (kept in --keep, default build/oracle-edges-divergences).
Missions with Delay, Timeout or Sleep are not written (the library times them on the wall clock).
"""

from __future__ import annotations

import sys
from collections import Counter
from pathlib import Path
from xml.sax.saxutils import quoteattr

sys.path.insert(0, str(Path(__file__).resolve().parent))

import oracle_random as orc

CONTROLS = {
    "Sequence": 2,
    "SequenceWithMemory": 2,
    "AsyncSequence": 2,
    "ReactiveSequence": 2,
    "Fallback": 2,
    "AsyncFallback": 2,
    "ReactiveFallback": 2,
    "Parallel": 2,
    "ParallelAll": 2,
    "IfThenElse": 3,
    "WhileDoElse": 3,
}
DECORATORS = {
    "Inverter": "",
    "ForceSuccess": "",
    "ForceFailure": "",
    "KeepRunningUntilFailure": "",
    "Repeat": ' num_cycles="3"',
    "RetryUntilSuccessful": ' num_attempts="3"',
    "RunOnce": "",
    "Precondition": ' if="true" else="FAILURE"',
    "LoopInt": ' queue="1;2;3" value="{li}"',
    "SkipUnlessUpdated": ' entry="{upd}"',
    "WaitValueUpdate": ' entry="{upd}"',
}
MODELS = """  <TreeNodesModel>
    <Action ID="Act"/>
    <Condition ID="Check"/>
  </TreeNodesModel>"""
PRE_POST = ("_skipIf", "_failureIf", "_successIf", "_while")
POST = ("_onSuccess", "_onFailure", "_onHalted", "_post")


def mission(body: str, extra_trees: str = "", init: str = "n := 0; upd := 0") -> str:
    return (
        '<root BTCPP_format="4" main_tree_to_execute="Main">\n'
        '  <BehaviorTree ID="Main">\n'
        f'    <Sequence><Script code="{init}"/>{body}</Sequence>\n'
        "  </BehaviorTree>\n" + extra_trees + MODELS + "\n</root>\n"
    )


def control(kind: str, kids: list[str], attrs: str = "") -> str:
    return f"<{kind}{attrs}>{''.join(kids)}</{kind}>"


def cases() -> dict[str, list[tuple[str, str, str]]]:
    """family -> [(stem, mission, scenario)]"""
    fam: dict[str, list[tuple[str, str, str]]] = {}

    # 1. halting: a ReactiveSequence whose condition fails at tick 3 halts its second child
    # (each Control/Decorator with a RUNNING action inside) at whatever status it holds.
    halt = []
    for kind, n in CONTROLS.items():
        for status in ("RUNNING", "SUCCESS", "FAILURE"):
            kids = ['<Check name="c0"/>'] + [f'<Act name="a{i}"/>' for i in range(1, n)]
            if kind in ("IfThenElse", "WhileDoElse"):
                kids = ['<Check name="c0"/>', '<Act name="a1"/>', '<Act name="a2"/>']
            else:
                kids = [f'<Act name="a{i}"/>' for i in range(n)]
            body = (
                '<ReactiveSequence><Check name="guard"/>'
                + control(kind, kids, ' _onHalted="n := n + 1" _post="n := n + 10"')
                + '</ReactiveSequence><ScriptCondition code="n == 1"/>'
            )
            sc = (
                "ticks 5\nleaf guard SUCCESS SUCCESS FAILURE\n"
                f"leaf a0 RUNNING {status} RUNNING\nleaf a1 RUNNING {status} RUNNING\nleaf a2 {status} RUNNING\n"
                "leaf c0 SUCCESS FAILURE\n"
            )
            halt.append((f"halt_{kind}_{status.lower()}", mission(body), sc))
    for kind, attrs in DECORATORS.items():
        for status in ("RUNNING", "SUCCESS", "FAILURE"):
            body = (
                f'<ReactiveSequence><Check name="guard"/><{kind}{attrs} _onHalted="n := n + 1">'
                f'<Act name="a0"/></{kind}></ReactiveSequence><ScriptCondition code="n == 1"/>'
            )
            sc = f"ticks 5\nleaf guard SUCCESS SUCCESS FAILURE\nleaf a0 RUNNING {status} RUNNING RUNNING\n"
            halt.append((f"halt_{kind}_{status.lower()}", mission(body), sc))
    fam["halt"] = halt

    # 2. SKIPPED through every Control: all children skipped, the first only, the last only.
    skipped = []
    for kind, n in CONTROLS.items():
        for which, mask in (
            ("all", [True] * n),
            ("first", [True] + [False] * (n - 1)),
            ("last", [False] * (n - 1) + [True]),
        ):
            kids = [f'<Act name="a{i}"' + (' _skipIf="true"' if m else "") + "/>" for i, m in enumerate(mask)]
            if kind in ("IfThenElse", "WhileDoElse"):
                kids[0] = '<Check name="c0"' + (' _skipIf="true"' if mask[0] else "") + "/>"
            body = f'<Fallback>{control(kind, kids)}<AlwaysSuccess name="after"/></Fallback>'
            skipped.append(
                (f"skip_{kind}_{which}", mission(body), "ticks 3\ndefault SUCCESS\nleaf a1 FAILURE SUCCESS\n")
            )
    for kind, attrs in DECORATORS.items():
        body = (
            f'<Fallback><{kind}{attrs}><Act name="a0" _skipIf="true"/></{kind}><AlwaysSuccess name="after"/></Fallback>'
        )
        skipped.append((f"skip_{kind}", mission(body), "ticks 3\ndefault SUCCESS\n"))
    fam["skipped"] = skipped

    # 3. every pre/post-condition on every node kind
    kinds = {
        "action": '<Act name="x"{a}/>',
        "condition": '<Check name="x"{a}/>',
        "script": '<Script code="k := 1"{a}/>',
        "sequence": '<Sequence{a}><Act name="x"/></Sequence>',
        "reactive": '<ReactiveFallback{a}><Check name="y"/><Act name="x"/></ReactiveFallback>',
        "parallel": '<Parallel success_count="1"{a}><Act name="x"/></Parallel>',
        "inverter": '<Inverter{a}><Act name="x"/></Inverter>',
        "repeat": '<Repeat num_cycles="2"{a}><Act name="x"/></Repeat>',
        "subtree": '<SubTree ID="Sub"{a}/>',
        "always": "<AlwaysSuccess{a}/>",
        "setbb": '<SetBlackboard value="5" output_key="k"{a}/>',
        "ifthenelse": '<IfThenElse{a}><Check name="y"/><Act name="x"/><Act name="x"/></IfThenElse>',
        "whiledoelse": '<WhileDoElse{a}><Check name="y"/><Act name="x"/><Act name="x"/></WhileDoElse>',
        "switch": '<Switch2 variable="{{n}}" case_1="0" case_2="1"{a}>' + '<Act name="x"/>' * 3 + "</Switch2>",
        "loop": '<LoopInt queue="1;2" value="{{li}}"{a}><Act name="x"/></LoopInt>',
        "runonce": '<RunOnce{a}><Act name="x"/></RunOnce>',
        "keeprunning": '<KeepRunningUntilFailure{a}><Act name="x"/></KeepRunningUntilFailure>',
        "asyncseq": '<AsyncSequence{a}><Act name="x"/><Act name="x"/></AsyncSequence>',
        "parallelall": '<ParallelAll{a}><Act name="x"/></ParallelAll>',
        "precondition": '<Precondition if="true" else="FAILURE"{a}><Act name="x"/></Precondition>',
        "skipunless": '<SkipUnlessUpdated entry="{{upd}}"{a}><Act name="x"/></SkipUnlessUpdated>',
        "retry": '<RetryUntilSuccessful num_attempts="2"{a}><Act name="x"/></RetryUntilSuccessful>',
        "scriptcond": '<ScriptCondition code="n &lt; 3"{a}/>',
    }
    sub = '  <BehaviorTree ID="Sub">\n    <Act name="x"/>\n  </BehaviorTree>\n'
    conds = []
    for kname, tmpl in kinds.items():
        for attr in PRE_POST:
            for val in ("n == 0", "n != 0"):
                a = f" {attr}={quoteattr(val)} _post=" + quoteattr("n := n + 1")
                body = tmpl.format(a=a) + '<ScriptCondition code="n &lt; 5"/>'
                for sc_name, sc in (("run", "leaf x RUNNING RUNNING SUCCESS\n"), ("fail", "leaf x FAILURE\n")):
                    stem = f"cond_{kname}_{attr[1:]}_{'t' if '==' in val else 'f'}_{sc_name}"
                    conds.append((stem, mission(f"<Fallback>{body}</Fallback>", sub), "ticks 5\nleaf y FAILURE\n" + sc))
        for attr in POST:
            a = f" {attr}=" + quoteattr("n := n + 7")
            body = (
                '<ReactiveSequence><Check name="guard"/>'
                + tmpl.format(a=a)
                + '</ReactiveSequence><ScriptCondition code="n == 0"/>'
            )
            for sc_name, sc in (
                ("ok", "leaf x SUCCESS\n"),
                ("fail", "leaf x FAILURE\n"),
                ("halt", "leaf x RUNNING\nleaf guard SUCCESS FAILURE\n"),
            ):
                conds.append(
                    (
                        f"post_{kname}_{attr[1:]}_{sc_name}",
                        mission(f"<Fallback>{body}<Act name='z'/></Fallback>", sub),
                        "ticks 4\nleaf y FAILURE\n" + sc,
                    )
                )
    fam["conditions"] = conds

    # 4. scripts: operators, precedence (parenthesised where 4.6.2 needs it), types, conversions
    exprs = [
        "x := 7 / 2",
        "x := 7.0 / 2",
        "x := -7 / 2",
        "x := 7 % 2",
        "x := 1 / 0",
        "x := 1.0 / 0",
        "x := 0 / 0.0",
        "x := 2147483647 + 1",
        "x := 9223372036854775807",
        "x := 0x10 + 1",
        "x := 0xFF & 0x0F",
        "x := 5 | 2",
        "x := 5 ^ 1",
        "x := ~5",
        "x := !true",
        "x := !0",
        "x := !1.5",
        "x := 'a' .. 'b'",
        "x := 'a' .. 1",
        "x := 1 .. 2",
        "x := 'a' .. 1.5",
        "x := 'a' .. true",
        "x := '1' + 1",
        "x := '1.5' * 2",
        "x := 'abc' + 1",
        "x := true + 1",
        "x := true && 'x'",
        "x := 'x' == 'x'",
        "x := '1' == 1",
        "x := 1 == 1.0",
        "x := 'b' < 'a'",
        "x := 1 < 'a'",
        "x := (1 < 2) == true",
        "x := true ? 1 : 'a'",
        "x := 0 ? 1 : 2",
        "x := '' ? 1 : 2",
        "x := 'false' ? 1 : 2",
        "x := 1; x += 2.5",
        "x := 'a'; x += 'b'",
        "x := 'a'; x += 1",
        "x := 1; x -= 'a'",
        "x := 3; x *= 2; x /= 4",
        "x := 1; x = 'str'",
        "x := 'str'; x = 1",
        "x := 1.5; x = 2",
        "x := 2; x = 1.5",
        "x := true; x = 2",
        "x := -(-3)",
        "x := - 3",
        "x := 1e3",
        "x := .5",
        "x := 5.",
        "x := 1 - 2 - 3",
        "x := 2 * 3 + 1",
        "x := 1 + 2 * 3",
        "x := (1 + 2) * 3",
        "x := 10 / 3 * 3",
        "x := true || false && false",
        "x := false && true || true",
        "x := 1 < 2 < 3",
        "x := 3 > 2 > 1",
        "x := 1 == 1 == 1",
        "x := 'a' .. 'b' .. 'c'",
        "x := y",
        "y = 1",
        "x := @y",
    ]
    scripts = []
    for i, e in enumerate(exprs):
        body = (
            f'<Script code={quoteattr(e)}/><Switch3 variable="{{x}}" case_1="1" case_2="true" case_3="ab">'
            '<Act name="one"/><Act name="t"/><Act name="ab"/><Act name="other"/></Switch3>'
            f"<ScriptCondition code={quoteattr('x == x')}/>"
        )
        scripts.append((f"script_{i:02d}", mission(body, init="n := 0"), "ticks 1\ndefault SUCCESS\n"))
    fam["scripts"] = scripts

    # 5. Parallel thresholds, Repeat/Retry -1 and 0, RunOnce then_skip
    par = []
    for s in ("-1", "0", "1", "2", "3", "4", "-4"):
        for f in ("-1", "0", "1", "3", "4"):
            kids = '<Act name="a"/><Act name="b"/><Act name="c"/>'
            body = f'<Parallel success_count="{s}" failure_count="{f}">{kids}</Parallel>'
            par.append(
                (f"par_{s}_{f}", mission(body), "ticks 4\nleaf a SUCCESS\nleaf b FAILURE\nleaf c RUNNING SUCCESS\n")
            )
    for node, port in (("Repeat", "num_cycles"), ("RetryUntilSuccessful", "num_attempts")):
        for v in ("-1", "0", "1"):
            for st in ("SUCCESS", "FAILURE"):
                body = f'<{node} {port}="{v}"><Act name="a"/></{node}>'
                par.append(
                    (
                        f"loop_{node}_{v}_{st.lower()}",
                        mission(body),
                        f"ticks 6\nleaf a {st} {st} {st} {st} SUCCESS FAILURE\n",
                    )
                )
    for ts in ("true", "false"):
        body = (
            f'<ReactiveSequence><RunOnce then_skip="{ts}"><Act name="a"/></RunOnce><Act name="b"/></ReactiveSequence>'
        )
        par.append(
            (
                f"runonce_{ts}",
                mission(body),
                "ticks 4\nleaf a RUNNING SUCCESS FAILURE\nleaf b RUNNING RUNNING SUCCESS\n",
            )
        )
    fam["thresholds"] = par

    # 6. Switch2..6 with numbers, strings, enums-like texts
    sw = []
    for n in range(2, 7):
        for value in ("3", "3.0", "'3'", "' 3'", "'x'", "-1", "'-1'", "2.5", "true"):
            cases_ = " ".join(f'case_{i}="{c}"' for i, c in enumerate(("1", "2", "3", "x", "-1", "2.5")[:n], 1))
            kids = "".join(f'<Act name="k{i}"/>' for i in range(n + 1))
            body = f'<Script code={quoteattr("v := " + value)}/><Switch{n} variable="{{v}}" {cases_}>{kids}</Switch{n}>'
            sw.append((f"switch{n}_{len(sw)}", mission(body), "ticks 1\ndefault SUCCESS\n"))
    fam["switch"] = sw

    # 7. Loop nodes with empty and odd queues, literal and from the blackboard
    loops = []
    for node, queues in (
        ("LoopInt", ("", ";", "1;;2", "1; 2", "1;2;", " 1", "1.5;2", "0x10")),
        ("LoopDouble", ("", "1;;2", "1e1", "inf;-inf", "nan", "1.5;", "0x1p3")),
        ("LoopString", ("", ";", "a;;b", " a ; b", "a;")),
        ("LoopBool", ("", "true;0;1;false", "yes", "TRUE")),
    ):
        for i, q in enumerate(queues):
            for empty in ("SUCCESS", "FAILURE", "SKIPPED"):
                body = f'<{node} queue={quoteattr(q)} value="{{item}}" if_empty="{empty}"><Act name="a"/></{node}>'
                loops.append((f"loop_{node}_{i}_{empty.lower()}", mission(body), "ticks 5\ndefault SUCCESS\n"))
            body = (
                f"<Script code={quoteattr('q := ' + repr(q))}/>"
                f'<{node} queue="{{q}}" value="{{item}}"><Act name="a"/></{node}>'
            )
            loops.append((f"loopbb_{node}_{i}", mission(body), "ticks 5\ndefault SUCCESS\n"))
    fam["loops"] = loops

    # 8. SubTree remapping, _autoremap, port defaults
    subs = []
    models = (
        '  <TreeNodesModel>\n    <Action ID="Act"/>\n    <Condition ID="Check"/>\n'
        '    <SubTree ID="S">\n      <input_port name="a" default="5"/>\n      <output_port name="b"/>\n'
        "    </SubTree>\n  </TreeNodesModel>"
    )
    inner = (
        '  <BehaviorTree ID="S">\n    <Sequence><ScriptCondition code="a == 5"/><Script code="b := 9; c := 1"/>'
        "</Sequence>\n  </BehaviorTree>\n"
    )
    for i, call in enumerate(
        (
            '<SubTree ID="S"/>',
            '<SubTree ID="S" a="5"/>',
            '<SubTree ID="S" a="6"/>',
            '<SubTree ID="S" a="{x}" b="{y}"/>',
            '<SubTree ID="S" _autoremap="true"/>',
            '<SubTree ID="S" _autoremap="true" a="{x}"/>',
            '<SubTree ID="S" _autoremap="false" b="{b}"/>',
            '<SubTree ID="S" a="{a}"/>',
            '<SubTree ID="S" a="{=}" b="{=}"/>',
            '<SubTree ID="S" a="5" b="{y}" _autoremap="true"/>',
            '<SubTree ID="S" a="{@x}"/>',
            '<SubTree ID="S" a="" b="{y}"/>',
            '<SubTree ID="S" a=" 5" b="{y}"/>',
            '<SubTree ID="S" a="5.0" b="{y}"/>',
            '<SubTree ID="S" a="{x}" b="{x}"/>',
            '<SubTree ID="S" b="{a}"/>',
            '<SubTree ID="S" a="{missing}" b="{y}"/>',
            '<SubTree ID="S" _autoremap="1"/>',
        )
    ):
        body = (
            f"{call}<ScriptCondition code={quoteattr('y == 9')} name='y9'/>"
            if "{y}" in call
            else f"{call}<ScriptCondition code={quoteattr('b == 9')} name='b9'/>"
        )
        text = mission(
            f"<Fallback><Sequence>{body}</Sequence><Act name='fb'/></Fallback>", init="x := 5; a := 4"
        ).replace(MODELS, inner + models)
        subs.append((f"subtree_{i}", text, "ticks 1\ndefault SUCCESS\n"))
    fam["subtrees"] = subs

    # 9. TryCatch (4.10.0; 4.6.2 refuses it)
    tc = []
    for coh in ("true", "false"):
        for sts in ("SUCCESS FAILURE", "FAILURE SUCCESS", "RUNNING SUCCESS", "SUCCESS SUCCESS", "SKIP"):
            kids = '<Act name="t1"/><Act name="t2"' + (' _skipIf="true"' if sts == "SKIP" else "") + "/>"
            body = (
                f'<ReactiveSequence><Check name="guard"/><TryCatch catch_on_halt="{coh}">'
                f'<Sequence>{kids}</Sequence><Act name="catch"/></TryCatch></ReactiveSequence>'
            )
            t1, _, t2 = sts.partition(" ")
            first = t1 if t1 != "SKIP" else "SUCCESS"
            sc = (
                f"ticks 4\nleaf guard SUCCESS SUCCESS FAILURE\nleaf t1 {first} RUNNING\nleaf t2 {t2 or 'SUCCESS'}\n"
                "leaf catch RUNNING SUCCESS\n"
            )
            tc.append((f"trycatch_{coh}_{len(tc)}", mission(body), sc))
    fam["trycatch"] = tc

    # 10. entries that were never written, and ports reading entries of another type
    missing = []
    for i, body in enumerate(
        (
            '<Switch2 variable="{nope}" case_1="1" case_2="2"><Act name="a"/><Act name="b"/><Act name="c"/></Switch2>',
            '<LoopInt queue="{nope}" value="{v}"><Act name="a"/></LoopInt>',
            '<Precondition if="nope == 1" else="FAILURE"><Act name="a"/></Precondition>',
            '<SkipUnlessUpdated entry="{nope}"><Act name="a"/></SkipUnlessUpdated>',
            '<WaitValueUpdate entry="{nope}"><Act name="a"/></WaitValueUpdate>',
            '<WasEntryUpdated entry="{nope}"/>',
            '<Repeat num_cycles="{nope}"><Act name="a"/></Repeat>',
            '<RetryUntilSuccessful num_attempts="{nope}"><Act name="a"/></RetryUntilSuccessful>',
            '<Parallel success_count="{nope}"><Act name="a"/></Parallel>',
            '<RunOnce then_skip="{nope}"><Act name="a"/></RunOnce>',
            '<ScriptCondition code="nope == 1"/>',
            '<SetBlackboard value="{nope}" output_key="k"/>',
            '<UnsetBlackboard key="nope"/>',
            '<Precondition if="true" else="{nope}"><Act name="a"/></Precondition>',
        )
    ):
        text = mission(f"<Fallback>{body}<Act name='fb'/></Fallback>")
        missing.append((f"missing_{i:02d}", text, "ticks 3\ndefault SUCCESS\n"))
    fam["missing"] = missing

    reads = []
    values = ("'abc'", "'2.5'", "2.5", "true", "-1", "'-1'", "' 3'", "'3 '", "'0x3'", "1e10", "'1e400'", "3.0")
    values += ("'true'",)
    for node in (
        '<Repeat num_cycles="{k}"><Act name="a"/></Repeat>',
        '<RetryUntilSuccessful num_attempts="{k}"><Act name="a"/></RetryUntilSuccessful>',
        '<Parallel success_count="{k}" failure_count="1"><Act name="a"/><Act name="b"/></Parallel>',
        '<RunOnce then_skip="{k}"><Act name="a"/></RunOnce>',
        '<Switch2 variable="{k}" case_1="3" case_2="abc"><Act name="a"/><Act name="b"/><Act name="c"/></Switch2>',
        '<LoopInt queue="{k}" value="{v}"><Act name="a"/></LoopInt>',
        '<LoopDouble queue="{k}" value="{v}"><Act name="a"/></LoopDouble>',
        '<LoopBool queue="{k}" value="{v}"><Act name="a"/></LoopBool>',
        '<Precondition if="k" else="FAILURE"><Act name="a"/></Precondition>',
    ):
        for v in values:
            body = f"<Script code={quoteattr('k := ' + v)}/><Fallback>{node}<Act name='fb'/></Fallback>"
            sc = "ticks 4\ndefault SUCCESS\nleaf a FAILURE SUCCESS\n"
            reads.append((f"read_{len(reads):03d}", mission(body), sc))
    fam["port reads"] = reads

    # 11. script values seen through comparisons (each probe in a ForceSuccess, so the trace
    # shows which held; a probe that throws ends the run on both sides)
    probes = ("x == 1", "x == 1.5", "x == 3", "x == (0 - 1)", "x < 2", "x == 'ab'", "x == '1'", "x == true")
    vals = []
    for i, e in enumerate(
        (
            "1",
            "1.0",
            "1.5",
            "3 / 2",
            "3.0 / 2",
            "7 / 2 * 2",
            "-1",
            "0 - 1",
            "'1'",
            "'1.0'",
            "'ab'",
            "'a' .. 'b'",
            "true",
            "false",
            "1 == 1",
            "0x1",
            "1e0",
            "'1' .. ''",
            "1 .. ''",
            "2 - 1",
            "(1 + 2) / 2",
            "'3' == 3",
            "!0",
            "~0 + 2",
            "5 % 2",
            "1 & 3",
            "'true'",
            "'0x1'",
            "' 1'",
            "'1 '",
        )
    ):
        checks = "".join(
            f"<ForceSuccess><ScriptCondition name={quoteattr(pr)} code={quoteattr(pr)}/></ForceSuccess>"
            for pr in probes
        )
        vals.append((f"value_{i:02d}", mission(f"<Script code={quoteattr('x := ' + e)}/>{checks}"), "ticks 1\n"))
    fam["values"] = vals
    return fam


def main(argv: list[str]) -> int:
    if not argv:
        sys.exit(__doc__)
    out = Path(argv[0])
    keep = Path(argv[argv.index("--keep") + 1]) if "--keep" in argv else orc.ROOT / "build" / "oracle-edges-divergences"
    out.mkdir(parents=True, exist_ok=True)
    only = argv[argv.index("--only") + 1].split(",") if "--only" in argv else None
    counts: Counter = Counter()
    for family, items in cases().items():
        if only is not None and family not in only:
            continue
        for stem, text, scenario in items:
            m, s = out / f"{stem}.xml", out / f"{stem}.scenario"
            m.write_text(text, encoding="utf-8")
            s.write_text(scenario, encoding="utf-8")
            for version in orc.BTCPP_VERSIONS:
                lib = orc.observe(orc.default_harness(version), text, str(m), str(s), str(out))
                got = orc.interpreter(str(m), str(s), version)
                verdict = orc.compare(lib, got, version, text)
                counts[(family, version, verdict)] += 1
                if verdict == "divergence":
                    orc.keep_case(keep, f"{stem}_on{version.replace('.', '')}", text, scenario, lib, got)
                    print(f"DIVERGENCE {family} {stem} on {version}", flush=True)
    print("| family | release | cases | agree | documented | divergences |")
    print("|---|---|---|---|---|---|")
    for family in cases():
        if only is not None and family not in only:
            continue
        for v in orc.BTCPP_VERSIONS:
            row = [counts[(family, v, w)] for w in ("agree", "documented", "divergence")]
            print(f"| {family} | {v} | {sum(row)} | {row[0]} | {row[1]} | {row[2]} |")
    return 1 if any(k[2] == "divergence" for k in counts) else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
