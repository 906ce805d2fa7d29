#!/usr/bin/env python3
"""`btgen diff F F --btcpp-old 4.6.2 --btcpp-new 4.10.0` on every real file (tests/real_files):
does the upgrade change what each mission does? Prints one line per file and a summary.

    PYTHONPATH=generator python scripts/diff_real_files.py [--max-ticks K] [--max-states N]

Models as tests/python/test_real_files.py gives them: Nav2's models file for nav2/, none for
btcpp/trees and btcpp/fuzzing, else the models `btgen models` infers (under 4.10.0 for 4.10.0's
own test trees).
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import os
import sys
import tempfile
import time

from btgen.cli import main

HERE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "real_files")


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


def main_() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--max-ticks", default="8")
    p.add_argument("--max-states", default="20000")
    a = p.parse_args()
    files = []
    for root, _, names in os.walk(HERE):
        files += [os.path.relpath(os.path.join(root, n), HERE) for n in names if n.endswith(".xml")]
    counts: dict[str, int] = {}
    total = 0.0
    with tempfile.TemporaryDirectory() as tmp:
        for rel in sorted(files):
            if rel.endswith("nav2_tree_nodes.xml"):
                continue
            path = os.path.join(HERE, rel)
            argv = ["diff", path, path, "--btcpp-old", "4.6.2", "--btcpp-new", "4.10.0", "--format", "json"]
            argv += ["--max-ticks", a.max_ticks, "--max-states", a.max_states, *_models(rel, tmp)]
            out, err = io.StringIO(), io.StringIO()
            t0 = time.perf_counter()
            with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
                try:
                    rc = main(argv)
                except SystemExit as e:
                    rc = int(e.code or 0)
            dt = time.perf_counter() - t0
            total += dt
            report = json.loads(out.getvalue()) if out.getvalue().strip() else {}
            if not report:
                errs = [line for line in err.getvalue().splitlines() if ": error: " in line]
                sides = [s for s in ("OLD", "NEW") if f"note: while loading {s} under" in err.getvalue()]
                kind = {
                    ("OLD",): "refused by 4.6.2 only",
                    ("NEW",): "refused by 4.10.0 only",
                    ("OLD", "NEW"): "refused by both",
                }.get(tuple(sides), "refused")
                detail = errs[0].split(": error: ", 1)[1][:90] if errs else ""
            elif report.get("equivalent") is False:
                kind = "different"
                detail = f"tick {report['first_difference']['tick']}: {report['first_difference']['old']}"
                detail += f" / {report['first_difference']['new']}"
            elif report.get("equivalent") is None:
                kind = "partial"
                detail = ""
            else:
                kind = "equivalent (exhaustively)" if report["exhaustive"] else f"equivalent (<= {a.max_ticks} ticks)"
                detail = f"{report['states']} states"
            counts[kind] = counts.get(kind, 0) + 1
            print(f"{rel}: rc={rc} {kind} {dt:.2f} s {detail}", flush=True)
    print(f"{sum(counts.values())} files, {total:.1f} s: " + ", ".join(f"{v} {k}" for k, v in sorted(counts.items())))
    return 0


if __name__ == "__main__":
    sys.exit(main_())
