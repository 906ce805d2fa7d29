#!/usr/bin/env python3
"""Record a folder of missions on one release of the real BehaviorTree.CPP, keeping partial traces.

    python scripts/record_releases.py DIR VERSION HARNESS

For every DIR/<stem>.xml with its <stem>.scenario, writes DIR/VERSION/<stem>.trace (what the
harness printed on stdout, cut short where the library threw) and DIR/VERSION/<stem>.error
(the library's message, when it refused the file or threw). Unlike record_conformance.py,
a throw keeps the trace before it, which both btgen engines must print too
(tests/python/release_cases.py). The harness is the project's oracle
(../shared/oracle/README.md).
"""

from __future__ import annotations

import os
import subprocess
import sys


def record(folder: str, version: str, harness: str) -> None:
    out = os.path.join(folder, version)
    os.makedirs(out, exist_ok=True)
    for name in sorted(os.listdir(folder)):
        if not name.endswith(".xml"):
            continue
        stem = name[: -len(".xml")]
        base = os.path.join(folder, stem)
        if not os.path.exists(base + ".scenario"):
            continue
        proc = subprocess.run(
            [harness, "trace", base + ".xml", base + ".scenario"], capture_output=True, timeout=60, check=False
        )
        with open(os.path.join(out, stem + ".trace"), "wb") as f:
            f.write(proc.stdout)
        err = os.path.join(out, stem + ".error")
        if os.path.exists(err):
            os.remove(err)
        if proc.returncode != 0:
            lines = [ln for ln in proc.stderr.decode("utf-8", "replace").splitlines() if ln.startswith("error:")]
            with open(err, "w", encoding="utf-8") as f:
                f.write((lines[0] if lines else f"exit {proc.returncode}") + "\n")


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    record(*sys.argv[1:])
