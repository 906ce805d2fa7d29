#!/usr/bin/env bash
# Record mission.trace on the oracle (../shared/oracle): its harness reads one file, so the
# trees and models of lib/*.xml are pasted into a copy of the mission first.
set -euo pipefail
HARNESS=${1:?usage: record.sh HARNESS}
cd "$(dirname "$0")"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
python3 - "$tmp/combined.xml" <<'PY'
import glob, sys
import xml.etree.ElementTree as ET
root = ET.parse("mission.xml").getroot()
root.set("main_tree_to_execute", "Main")
models = ET.SubElement(root, "TreeNodesModel")
for f in sorted(glob.glob("lib/*.xml")):
    for child in ET.parse(f).getroot():
        if child.tag == "BehaviorTree":
            root.append(child)
        elif child.tag == "TreeNodesModel":
            models.extend(list(child))
ET.ElementTree(root).write(sys.argv[1], encoding="unicode")
PY
"$HARNESS" trace "$tmp/combined.xml" mission.scenario > mission.trace
