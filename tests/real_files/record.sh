#!/usr/bin/env bash
# Record, on the real BehaviorTree.CPP (../shared/oracle), DIR/<file>.trace for every file of
# runnable.txt (or DIR/<file>.refused, the library's message, when this version refuses it) and
# DIR/<file>.refused for every file of refused.txt.
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
  rm -f "$DIR/${flat%.xml}.trace" "$DIR/${flat%.xml}.refused"
  # A file this version refuses (4.10.0's test trees on 4.6.2, and the reverse) gets its
  # message as .refused; the harness exits 2 then.
  if ! "$HARNESS" trace "$file" "scenarios/$scenario.scenario" > "$DIR/${flat%.xml}.trace" \
    2> "$DIR/${flat%.xml}.err"; then
    grep -v '^note: ' "$DIR/${flat%.xml}.err" > "$DIR/${flat%.xml}.refused"
    rm "$DIR/${flat%.xml}.trace"
  fi
  rm "$DIR/${flat%.xml}.err"
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
