#!/usr/bin/env bash
# clang-format over the hand-written C++ (runtime, tests, examples, the ROS node,
# bench): `--check` reports files that differ and fails; without it, rewrites them.
# Generated code (generated/, build trees) follows the templates and is not formatted.
set -euo pipefail
cd "$(dirname "$0")/.."
mapfile -t files < <(git ls-files 'runtime/*.hpp' 'runtime/*.cpp' 'tests/cpp/*.cpp' 'tests/cpp/*.hpp' \
  'tests/fuzz/*.cpp' 'examples/*.cpp' 'examples/*.hpp' 'ros/*.cpp' 'ros/*.hpp' 'ros/*.h' 'bench/*.cpp' \
  'mcu/*.c' 'mcu/*.cpp' 'mcu/*.hpp')
if [ "${1:-}" = "--check" ]; then
  clang-format --dry-run -Werror "${files[@]}"
else
  clang-format -i "${files[@]}"
fi
