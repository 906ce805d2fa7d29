#!/usr/bin/env bash
# Configure, build and run examples/mcu in QEMU (one command):
#   bash examples/mcu/run.sh [BUILD_DIR]
# Needs gcc-arm-none-eabi, libstdc++-arm-none-eabi-newlib, qemu-system-arm and
# btgen's Python environment (.venv, from scripts/setup.sh). QEMU's exit status
# is the firmware's: 0 when the tour succeeds.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
build="${1:-$root/build/mcu}"
python="${Python3_EXECUTABLE:-$root/.venv/bin/python}"
cmake -S "$here" -B "$build" -DCMAKE_TOOLCHAIN_FILE="$root/cmake/toolchain/arm-none-eabi-cortex-m4.cmake" \
  -DPython3_EXECUTABLE="$python" >/dev/null
cmake --build "$build" --target lab_tour_mcu -j 2 >/dev/null
exec qemu-system-arm -M mps2-an386 -display none -monitor none -serial stdio \
  -semihosting-config enable=on,target=native -kernel "$build/lab_tour_mcu.elf"
