"""The bare-metal build's number text is the host's: `%f` without printf.

Under BTGEN_BARE_METAL (the Cortex-M build, mcu/) btgen/value.hpp formats doubles
itself, because newlib-nano's printf has no `%f` (and newlib's allocates for it).
tests/cpp/mcu/fixed_text_check.cpp compares that formatter with the host's printf on
special values, ties, subnormals, extremes and random bit patterns; here it is built
with the host compiler (warnings as errors) and run.
"""

import shutil
import subprocess

import pytest

from conftest import ROOT


@pytest.mark.skipif(shutil.which("c++") is None, reason="no host C++ compiler")
def test_bare_metal_fixed_text_is_printfs(tmp_path):
    exe = tmp_path / "fixed_text_check"
    subprocess.run(
        [
            "c++",
            "-std=c++17",
            "-O2",
            "-DBTGEN_BARE_METAL=1",
            "-Wall",
            "-Wextra",
            "-Wpedantic",
            "-Werror",
            "-I",
            f"{ROOT}/runtime/include",
            f"{ROOT}/tests/cpp/mcu/fixed_text_check.cpp",
            "-o",
            str(exe),
        ],
        check=True,
    )
    proc = subprocess.run([str(exe), "100000"], capture_output=True, text=True, check=False)
    assert proc.returncode == 0, proc.stdout
    assert proc.stdout.startswith("checked ") and proc.stdout.endswith(" bad 0\n")
