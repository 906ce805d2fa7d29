#!/usr/bin/env python3
"""Record a conformance folder on the real BehaviorTree.CPP (the oracle harness).

    python scripts/record_conformance.py HARNESS DIR [STEM ...]

For every DIR/<stem>.xml with a <stem>.scenario: <stem>.trace when the library
runs it, else <stem>.refused holding the library's message (it refuses the
file, or throws while ticking). HARNESS is the `harness` program of an oracle
build of BehaviorTree.CPP (`<prefix>/bin/harness`): the project's shared oracle
folder beside the checkout (`../shared/oracle/README.md`) says how it is built.
"""

from __future__ import annotations

import os
import subprocess
import sys


def record(harness: str, folder: str, stems: list[str]) -> int:
    if not stems:
        stems = sorted(f[:-4] for f in os.listdir(folder) if f.endswith(".xml"))
    for stem in stems:
        base = os.path.join(folder, stem)
        proc = subprocess.run(
            [harness, "trace", base + ".xml", base + ".scenario"], capture_output=True, timeout=60, check=False
        )
        for ext in (".trace", ".refused"):
            if os.path.exists(base + ext):
                os.remove(base + ext)
        if proc.returncode == 0:
            with open(base + ".trace", "wb") as f:
                f.write(proc.stdout)
            print(f"trace   {stem}")
        else:
            message = proc.stderr.decode("utf-8", "replace").strip().splitlines()
            # the library may print a warning before the error (convertFromString<BT::Any>)
            message = [m for m in message if m.startswith("error:")] or message
            with open(base + ".refused", "w", encoding="utf-8") as f:
                f.write((message[0] if message else f"exit {proc.returncode}") + "\n")
            print(f"refused {stem}: {message[0] if message else proc.returncode}")
    return 0


if __name__ == "__main__":
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    sys.exit(record(sys.argv[1], sys.argv[2], sys.argv[3:]))
