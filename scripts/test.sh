#!/usr/bin/env bash
# Run every test of btgen: Python (pytest) and C++ (GoogleTest via ctest),
# the latter also under AddressSanitizer + UBSan, and the libFuzzer targets
# for a bounded time (clang: BTGEN_WITH_CLANG=1, on by default here; set it
# to 0 to skip them on a machine without clang). Installs what it needs.
# This is what CI runs.
#
#   bash scripts/test.sh --quick
#
# is a contributor's check in minutes: code style, the shipped missions, and pytest without
# the tests marked slow (random differential runs, whole corpora built as C++, the package),
# sanitize (ASan/UBSan builds) and qemu (the Cortex-M images); no ctest, no ROS 1, no
# libFuzzer, and nothing installed but the Python environment (markers: tests/python/conftest.py).
set -euo pipefail
cd "$(dirname "$0")/.."
quick=0
if [ "${1:-}" = "--quick" ]; then
  quick=1
  shift
fi
if [ $# -gt 0 ]; then
  echo "usage: bash scripts/test.sh [--quick]" >&2
  exit 2
fi
if [ "$quick" = 1 ]; then
  export BTGEN_WITH_CLANG=${BTGEN_WITH_CLANG:-0}
else
  export BTGEN_WITH_CLANG=${BTGEN_WITH_CLANG:-1}
fi
# the pre-commit hook in a fresh repository (tests/python/test_check_precommit.py: about a minute)
export BTGEN_TEST_PRECOMMIT=${BTGEN_TEST_PRECOMMIT:-$((1 - quick))}
bash scripts/setup.sh
export PATH="$PWD/.venv/bin:$PATH"
jobs=$(nproc 2>/dev/null || echo 2)

if [ "$quick" = 1 ]; then
  start=$(date +%s)
  echo "== code style: ruff, mypy, clang-format"
  ruff check .
  ruff format --check .
  mypy
  bash scripts/format_cpp.sh --check
  echo "== validate shipped missions"
  btgen validate -q missions/*.xml
  echo "== Python tests, quick: -m \"not slow and not sanitize and not qemu\""
  pytest -q -p no:cacheprovider -n "$jobs" --dist loadfile --durations=15 -m "not slow and not sanitize and not qemu"
  echo "== quick path done in $(($(date +%s) - start)) s (CI runs bash scripts/test.sh: everything)"
  exit 0
fi

echo "== code style: ruff, mypy, clang-format (configuration: pyproject.toml, .clang-format)"
ruff check .
ruff format --check .
mypy
bash scripts/format_cpp.sh --check

echo "== validate shipped missions"
btgen validate -q missions/*.xml

if [ -f data/environmentKnowledgeBaseInput.dat ] && [ -f generator/btgen/kb/lint.py ]; then
  echo "== lint the shipped knowledge base"
  btgen lint-kb data/environmentKnowledgeBaseInput.dat --config data/environmentKnowledgeBaseConfiguration.ini
fi

echo "== the Cortex-M toolchain and QEMU (scripts/test_mcu.sh; tests/python/test_mcu.py runs with pytest)"
bash scripts/test_mcu.sh --install-only

echo "== Python tests (pytest-xdist: $jobs processes, one test file per process at a time)"
pytest -q -p no:cacheprovider -n "$jobs" --dist loadfile --durations=25

echo "== C++ tests"
cmake -S . -B build/test -G Ninja -DCMAKE_BUILD_TYPE=Debug -DPython3_EXECUTABLE="$PWD/.venv/bin/python" >/dev/null
cmake --build build/test -j "$jobs"
ctest --test-dir build/test --output-on-failure -j "$jobs"

echo "== C++ tests under AddressSanitizer + UBSan"
cmake -S . -B build/asan -G Ninja -DCMAKE_BUILD_TYPE=Debug -DBTGEN_SANITIZE=ON \
  -DPython3_EXECUTABLE="$PWD/.venv/bin/python" >/dev/null
cmake --build build/asan -j "$jobs"
ctest --test-dir build/asan --output-on-failure -j "$jobs"

echo "== ROS 1: the Lab Tour node under roscore (scripts/test_ros1.sh)"
bash scripts/test_ros1.sh

if [ "$BTGEN_WITH_CLANG" = 1 ]; then
  echo "== libFuzzer targets of the runtime's readers under ASan + UBSan (${BTGEN_FUZZ_SECONDS:-20} s each)"
  bash scripts/fuzz_cpp.sh "${BTGEN_FUZZ_SECONDS:-20}"
fi
