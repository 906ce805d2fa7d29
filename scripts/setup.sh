#!/usr/bin/env bash
# Install what btgen needs on a Debian machine (run as root) and create .venv.
# Idempotent: a second run only checks.
set -euo pipefail
cd "$(dirname "$0")/.."

need_apt=()
for pkg in python3 python3-venv g++ cmake ninja-build libgtest-dev libeigen3-dev libzmq3-dev cppzmq-dev graphviz clang-format spin tcc; do
  dpkg -s "$pkg" >/dev/null 2>&1 || need_apt+=("$pkg")
done
if [ "${BTGEN_WITH_CLANG:-0}" = 1 ]; then
  for pkg in clang libclang-rt-14-dev; do
    dpkg -s "$pkg" >/dev/null 2>&1 || need_apt+=("$pkg")
  done
fi
if [ ${#need_apt[@]} -gt 0 ]; then
  echo "setup: installing ${need_apt[*]}" >&2
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${need_apt[@]}" >/dev/null
fi

PY=${PYTHON:-python3}
if [ ! -x .venv/bin/python ]; then
  "$PY" -m venv .venv
fi
stamp=.venv/.btgen-requirements
if ! cmp -s requirements.txt "$stamp" 2>/dev/null; then
  .venv/bin/pip install -q --disable-pip-version-check -r requirements.txt
  .venv/bin/pip install -q --disable-pip-version-check --no-deps -e .
  cp requirements.txt "$stamp"
fi
# Test-only packages (the Groot2 tests' third-party client and BehaviorTree.CPP bindings).
test_stamp=.venv/.btgen-test-requirements
if [ -f requirements-test.txt ] && ! cmp -s requirements-test.txt "$test_stamp" 2>/dev/null; then
  .venv/bin/pip install -q --disable-pip-version-check -r requirements-test.txt
  cp requirements-test.txt "$test_stamp"
fi
