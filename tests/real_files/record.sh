#!/usr/bin/env bash
# Record, on the real BehaviorTree.CPP (../shared/oracle), DIR/<file>.trace for every file of
# runnable.txt and DIR/<file>.refused (the library's message) for every file of refused.txt.
#   bash tests/real_files/record.sh /path/to/oracle462/bin/harness            # -> expected/
#   bash tests/real_files/record.sh /path/to/oracle410/bin/harness expected-4.10.0
set -euo pipefail
HARNESS=${1:?usage: record.sh HARNESS [DIR]}
DIR=${2:-expected}
cd "$(dirname "$0")"
mkdir -p "$DIR"
grep -v '^#' runnable.txt | while read -r file scenario; do
  [ -n "$file" ] || continue
  flat=${file//\//__}
  "$HARNESS" trace "$file" "scenarios/$scenario.scenario" > "$DIR/${flat%.xml}.trace"
done
grep -v '^#' refused.txt | while read -r file; do
  [ -n "$file" ] || continue
  flat=${file//\//__}
  # The harness exits 2 with the library's exception on stderr when it refuses to load.
  if "$HARNESS" trace "$PWD/$file" scenarios/default.scenario > /dev/null 2> "$DIR/${flat%.xml}.refused"; then
    echo "$file: loaded, but refused.txt lists it" >&2
    exit 1
  fi
done
