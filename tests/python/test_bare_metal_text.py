"""The bare-metal build's number <-> text conversions are the host's, without the C library's.

Under BTGEN_BARE_METAL (the Cortex-M build, mcu/) btgen/value.hpp formats doubles
itself, because newlib-nano's printf has no `%f` (and newlib's allocates for it), and
reads them itself, because newlib's strtod allocates for long inputs.
tests/cpp/mcu/fixed_text_check.cpp compares the formatter with the host's printf on
special values, ties, subnormals, extremes and random bit patterns,
tests/cpp/mcu/strtod_check.cpp the reader with the host's strtod on halfway cases,
subnormals, overflow, long mantissas, hexadecimal and random literals; here each is
built with the host compiler (warnings as errors) and run.
"""

import shutil
import subprocess

import pytest

import cppbuild
from conftest import ROOT


@pytest.mark.skipif(shutil.which("c++") is None, reason="no host C++ compiler")
@pytest.mark.parametrize("check,rounds", [("fixed_text_check", "100000"), ("strtod_check", "30000")])
def test_bare_metal_conversion_is_the_c_librarys(check, rounds, tmp_path):
    exe = tmp_path / check
    cppbuild.build([f"{ROOT}/tests/cpp/mcu/{check}.cpp"], exe, cxx="c++", opt="-O2", defines=["BTGEN_BARE_METAL=1"])
    proc = subprocess.run([str(exe), rounds], capture_output=True, text=True, check=False)
    assert proc.returncode == 0, proc.stdout
    assert proc.stdout.startswith("checked ") and proc.stdout.endswith(" bad 0\n")
