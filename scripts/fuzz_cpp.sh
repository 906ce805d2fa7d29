#!/usr/bin/env bash
# libFuzzer targets of the runtime's readers (tests/fuzz) under ASan + UBSan.
#
#   scripts/fuzz_cpp.sh [SECONDS_PER_TARGET]     (default 20; CI runs the default)
#
# Builds tests/fuzz with clang into build/fuzz and runs every target for the
# given time over a fresh working corpus seeded from tests/fuzz/corpus/<target>.
# A crash, a sanitizer report, a leak, a timeout (10 s per input) or more than
# 2 GiB of memory fails the run and leaves the input as build/fuzz/<target>-crash-*.
# Needs clang and libFuzzer's runtime (Debian: clang, libclang-rt-14-dev;
# scripts/setup.sh installs them when BTGEN_WITH_CLANG=1).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-20}
cxx=${BTGEN_FUZZ_CXX:-clang++}
if ! command -v "$cxx" >/dev/null; then
  echo "fuzz_cpp: $cxx not found (install clang and libclang-rt-14-dev, or run BTGEN_WITH_CLANG=1 scripts/setup.sh)" >&2
  exit 1
fi
python=${PYTHON:-$PWD/.venv/bin/python}
cmake -S tests/fuzz -B build/fuzz -G Ninja -DCMAKE_CXX_COMPILER="$cxx" -DPython3_EXECUTABLE="$python" \
  -DBTGEN_FUZZ_SECONDS="$seconds" >/dev/null
cmake --build build/fuzz
rm -rf build/fuzz/corpus
ctest --test-dir build/fuzz --output-on-failure
for log in build/fuzz/Testing/Temporary/LastTest.log; do
  grep -E "^(stat::number_of_executed_units|Running: |#[0-9]+ +DONE)" "$log" | sed 's/^/fuzz_cpp: /' || true
done
