#!/usr/bin/env bash
# btgen on a microcontroller: installs the bare-metal toolchain and QEMU when
# missing (Debian: gcc-arm-none-eabi, libstdc++-arm-none-eabi-newlib,
# qemu-system-arm), then runs tests/python/test_mcu.py: every conformance and
# regression case built for a Cortex-M4 (QEMU's mps2-an386) and run there,
# its trace the host's byte for byte, the no-heap check, and examples/mcu
# built with btgen_add_mission() and the toolchain file and run in QEMU.
#
#   bash scripts/test_mcu.sh                 # install what is missing, run the tests
#   bash scripts/test_mcu.sh --install-only  # only install (scripts/test.sh, before pytest)
set -euo pipefail
cd "$(dirname "$0")/.."

need=()
if ! command -v arm-none-eabi-g++ >/dev/null 2>&1; then
  need+=(gcc-arm-none-eabi libstdc++-arm-none-eabi-newlib)
elif [ "$(arm-none-eabi-g++ -mthumb -mcpu=cortex-m4 -print-file-name=libstdc++_nano.a)" = libstdc++_nano.a ]; then
  need+=(libstdc++-arm-none-eabi-newlib)
fi
command -v qemu-system-arm >/dev/null 2>&1 || need+=(qemu-system-arm)
if [ ${#need[@]} -gt 0 ]; then
  echo "== installing ${need[*]}"
  sudo=""
  [ "$(id -u)" = 0 ] || sudo=sudo
  $sudo apt-get update -qq
  $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${need[@]}" >/dev/null
fi
[ "${1:-}" = "--install-only" ] && exit 0

[ -x .venv/bin/python ] || bash scripts/setup.sh
export PATH="$PWD/.venv/bin:$PATH"
# CI=1: the tests must run here (they skip only when the tools are missing outside CI).
CI=1 pytest -q -p no:cacheprovider tests/python/test_mcu.py
