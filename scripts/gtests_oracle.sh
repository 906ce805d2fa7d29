#!/usr/bin/env bash
# Builds and runs `btgen tests` suites on a built BehaviorTree.CPP, then on edited copies of
# the mission (the suite must fail). The numbers of docs/tests.md come from this script.
#
#   bash scripts/gtests_oracle.sh PREFIX VERSION MISSION.xml OUT_DIR [SED_EDIT]
#
# PREFIX: a BehaviorTree.CPP install (lib/cmake/behaviortree_cpp); VERSION: 4.6.2 or 4.10.0;
# SED_EDIT: a sed expression giving the edited mission (default: ReactiveSequence -> Sequence).
# BTGEN_TESTS_ARGS: more arguments for `btgen tests` (e.g. `--scenarios DIR/*.scenario`);
# BTGEN_CMAKE_ARGS: more arguments for the suite's cmake configure (e.g. `-DBTGEN_PLUGINS=...`).
# A Nav2 tree with Nav2's own Controls and Decorators (plugins built from a navigation2 mirror):
#   P=$(python scripts/nav2_oracle/record.py PREFIX VERSION --mirror GIT_DIR --distros lyrical --plugins-only)
#   BTGEN_TESTS_ARGS="--models tests/real_files/nav2/nav2_tree_nodes.xml \
#     --register scripts/nav2_oracle/gtests_register.cpp" \
#   BTGEN_CMAKE_ARGS="-DBTGEN_PLUGINS=$P -DBTGEN_INCLUDE_DIRS=$PWD/scripts/nav2_oracle" \
#   bash scripts/gtests_oracle.sh PREFIX VERSION tests/real_files/nav2/TREE.xml OUT 's/PipelineSequence/Sequence/g'
set -euo pipefail
prefix=$1 version=$2 mission=$3 out=$4
edit=${5:-'s/ReactiveSequence/Sequence/g'}
# shellcheck disable=SC2086 # BTGEN_TESTS_ARGS is a list of words
python -m btgen tests "$mission" --btcpp "$version" -o "$out" ${BTGEN_TESTS_ARGS:-}
# shellcheck disable=SC2086 # BTGEN_CMAKE_ARGS is a list of words
cmake -S "$out" -B "$out/build" -DCMAKE_PREFIX_PATH="$prefix" ${BTGEN_CMAKE_ARGS:-} >/dev/null
cmake --build "$out/build" -j1 >/dev/null
echo "== $mission on $prefix (btgen --btcpp $version)"
ctest --test-dir "$out/build" | grep "tests passed"
edited="$out/build/edited-$(basename "$mission")"
sed -E "$edit" "$mission" >"$edited"
if cmp -s "$mission" "$edited"; then
  echo "the edit '$edit' changes nothing in $mission" >&2
  exit 1
fi
edited=$(cd "$(dirname "$edited")" && pwd)/$(basename "$edited")
cmake -S "$out" -B "$out/build" -DBTGEN_MISSION="$edited" >/dev/null
cmake --build "$out/build" -j1 >/dev/null
echo "== edited ($edit)"
ctest --test-dir "$out/build" | grep "tests passed" || true
