#!/usr/bin/env python3
"""`btgen diff F F --btcpp-old 4.6.2 --btcpp-new 4.10.0` on every real file (tests/real_files):
does the upgrade change what each mission does? Prints one line per file and a summary; then
the Nav2 default trees from jazzy to lyrical.

    PYTHONPATH=generator python scripts/diff_real_files.py [--max-ticks K] [--max-states N] [--only PREFIX]

Models as tests/python/test_real_files.py gives them: Nav2's models file for nav2/, none for
btcpp/trees and btcpp/fuzzing, else the models `btgen models` infers (under 4.10.0 for 4.10.0's
own test trees). jazzy's default trees (tests/nav2_models/jazzy/behavior_trees/) are also run
4.6.2 against 4.10.0 with jazzy's models file.

Jazzy to lyrical: each jazzy default tree (OLD, jazzy's models file, so jazzy's built-in
Controls) against the tree of the same file name on main (= lyrical, tests/real_files/nav2/, NEW,
lyrical's models file), both under 4.10.0, with `--rename` for the Conditions Nav2 renamed
(lang/nav2.py RENAMES: IsPathValid -> ValidatePath, ...) that the tree uses. The two files name
their main tree differently (`MainTree` / `NavigateToPose...`): NEW is compared from a
temporary copy whose main tree takes OLD's ID (tree IDs are not observed).
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import os
import re
import sys
import tempfile
import time

from btgen.cli import main

HERE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "real_files")
JAZZY = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "nav2_models", "jazzy")


def _models(rel: str, tmp: str) -> list[str]:
    if rel.startswith("nav2/"):
        return ["--models", os.path.join(HERE, "nav2", "nav2_tree_nodes.xml")]
    if rel.startswith(("btcpp/trees/", "btcpp/fuzzing/")):
        return []
    out = os.path.join(tmp, rel.replace("/", "__") + ".models.xml")
    version = ["--btcpp", "4.10.0"] if rel.startswith("btcpp/tests-4.10.0/") else []
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        if main(["models", os.path.join(HERE, rel), "-o", out, *version]) != 0:
            return []
    return ["--models", out]


def _run(argv: list[str], a) -> tuple[int, dict, str, float]:
    argv = [*argv, "--format", "json", "--max-ticks", a.max_ticks, "--max-states", a.max_states]
    if a.observe:
        argv += ["--observe", a.observe]
    out, err = io.StringIO(), io.StringIO()
    t0 = time.perf_counter()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            rc = main(argv)
        except SystemExit as e:
            rc = int(e.code or 0)
    report = json.loads(out.getvalue()) if out.getvalue().strip() else {}
    return rc, report, err.getvalue(), time.perf_counter() - t0


def _main_tree(path: str) -> str:
    with open(path, encoding="utf-8") as f:
        m = re.search(r'main_tree_to_execute\s*=\s*"([^"]*)"', f.read())
    return m.group(1) if m else ""


def _jazzy_to_lyrical(a, tmp: str) -> tuple[dict[str, int], float]:
    from btgen import pipeline
    from btgen.lang import nav2
    from btgen.lang.leaves import mission_leaves

    counts: dict[str, int] = {}
    total = 0.0
    jazzy_models = os.path.join(JAZZY, "nav2_tree_nodes.xml")
    lyrical_models = os.path.join(HERE, "nav2", "nav2_tree_nodes.xml")
    print("jazzy -> lyrical (both under 4.10.0):")
    for name in sorted(os.listdir(os.path.join(JAZZY, "behavior_trees"))):
        old = os.path.join(JAZZY, "behavior_trees", name)
        new = os.path.join(HERE, "nav2", name)
        if not os.path.exists(new):
            print(f"  {name}: no tree of that name on lyrical")
            continue
        with open(new, encoding="utf-8") as f:
            text = f.read()
        main_old, main_new = _main_tree(old), _main_tree(new)
        if main_old and main_new and main_old != main_new:
            text = re.sub(rf'(ID|main_tree_to_execute)="{re.escape(main_new)}"', rf'\1="{main_old}"', text)
        copy = os.path.join(tmp, "lyrical__" + name)
        with open(copy, "w", encoding="utf-8") as f:
            f.write(text)
        renames = []
        try:
            with contextlib.redirect_stderr(io.StringIO()):
                m = pipeline.load(old, pipeline.CompileOptions(models=(jazzy_models,), btcpp="4.10.0"))
            leaf_names = {u.name for u in mission_leaves(m)}
        except Exception:  # the diff below reports why it does not load
            leaf_names = set()
        for r in nav2.renames("jazzy", "lyrical"):
            if r.node != r.to and r.node in leaf_names:
                renames += ["--rename", f"{r.node}={r.to}"]
        argv = ["diff", old, copy, "--btcpp", "4.10.0", "--models-old", jazzy_models, "--models-new", lyrical_models]
        rc, report, err, dt = _run(argv + renames, a)
        total += dt
        kind, detail = _kind(report, err, a)
        counts[kind] = counts.get(kind, 0) + 1
        shown = " ".join(renames[1::2])
        print(f"  {name}: rc={rc} {kind} {dt:.2f} s {detail}" + (f" (rename {shown})" if shown else ""), flush=True)
    return counts, total


def _kind(report: dict, err: str, a) -> tuple[str, str]:
    if not report:
        errs = [line for line in err.splitlines() if ": error: " in line]
        sides = [s for s in ("OLD", "NEW") if f"note: while loading {s} under" in err]
        kind = {
            ("OLD",): "refused by OLD only",
            ("NEW",): "refused by NEW only",
            ("OLD", "NEW"): "refused by both",
        }.get(tuple(sides), "refused")
        return kind, errs[0].split(": error: ", 1)[1][:110] if errs else ""
    if report.get("equivalent") is False:
        first = report["first_difference"]
        return "different", f"tick {first['tick']}: {first['old']} / {first['new']}"
    if report.get("equivalent") is None:
        return "partial", f"{report['states']} states"
    kind = "equivalent (exhaustively)" if report["exhaustive"] else f"equivalent (<= {a.max_ticks} ticks)"
    return kind, f"{report['states']} states"


def main_() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--max-ticks", default="8")
    p.add_argument("--max-states", default="20000")
    p.add_argument("--only", default="", help="only the files whose path (under tests/real_files) starts so")
    p.add_argument("--observe", default="", help="btgen diff's --observe (default: its default)")
    p.add_argument("--distros-only", action="store_true", help="only jazzy -> lyrical")
    a = p.parse_args()
    files = []
    for root, _, names in os.walk(HERE):
        files += [os.path.relpath(os.path.join(root, n), HERE) for n in names if n.endswith(".xml")]
    for name in sorted(os.listdir(os.path.join(JAZZY, "behavior_trees"))):
        files.append("jazzy/" + name)
    counts: dict[str, int] = {}
    total = 0.0
    with tempfile.TemporaryDirectory() as tmp:
        for rel in sorted(files):
            if rel.endswith("nav2_tree_nodes.xml") or not rel.startswith(a.only) or a.distros_only:
                continue
            if rel.startswith("jazzy/"):
                path = os.path.join(JAZZY, "behavior_trees", rel[len("jazzy/") :])
                models = ["--models", os.path.join(JAZZY, "nav2_tree_nodes.xml")]
            else:
                path = os.path.join(HERE, rel)
                models = _models(rel, tmp)
            argv = ["diff", path, path, "--btcpp-old", "4.6.2", "--btcpp-new", "4.10.0", *models]
            rc, report, err, dt = _run(argv, a)
            total += dt
            kind, detail = _kind(report, err, a)
            kind = kind.replace("by OLD only", "by 4.6.2 only").replace("by NEW only", "by 4.10.0 only")
            counts[kind] = counts.get(kind, 0) + 1
            print(f"{rel}: rc={rc} {kind} {dt:.2f} s {detail}", flush=True)
        summary = ", ".join(f"{v} {k}" for k, v in sorted(counts.items()))
        if not a.distros_only:
            print(f"{sum(counts.values())} files, {total:.1f} s: {summary}")
        if "nav2".startswith(a.only) or a.only.startswith(("nav2", "jazzy")) or not a.only:
            counts, total = _jazzy_to_lyrical(a, tmp)
            print(f"jazzy -> lyrical: {sum(counts.values())} trees, {total:.1f} s: ", end="")
            print(", ".join(f"{v} {k}" for k, v in sorted(counts.items())))
    return 0


if __name__ == "__main__":
    sys.exit(main_())
