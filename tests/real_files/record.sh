#!/usr/bin/env bash
# Record expected/*.trace of runnable.txt on the real BehaviorTree.CPP (../shared/oracle).
#   bash tests/real_files/record.sh /path/to/oracle462/bin/harness
set -euo pipefail
HARNESS=${1:?usage: record.sh HARNESS}
cd "$(dirname "$0")"
grep -v '^#' runnable.txt | while read -r file scenario; do
  [ -n "$file" ] || continue
  flat=${file//\//__}
  "$HARNESS" trace "$file" "scenarios/$scenario.scenario" > "expected/${flat%.xml}.trace"
done
