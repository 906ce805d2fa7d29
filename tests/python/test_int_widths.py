"""Integer port types of every width (issue 37: Nav2's `uint16` error codes became text).

tests/int_widths/convert-4.6.2.txt is what BehaviorTree.CPP 4.6.2's convertFromString<T> gave for
each integer width (recorded with tests/int_widths/record_convert.cpp against the real library):
every width parses alike (std::from_chars: an optional `-`, digits, the rest ignored; no `+`, no
blank before) and differs only in its range, which 4.6.2 checks when it loads the tree. btgen reads
every spelling of an integer type as an integer (signed: `int`, unsigned: `unsigned`, whose
accessors are std::int32_t / std::uint32_t) and checks literals against the declared width's
range; docs/types.md says where the 32-bit accessors still differ."""

import os
import re
import shutil
import subprocess

import pytest

from btgen.cli import main
from btgen.lang import values
from conftest import ROOT

HERE = os.path.join(ROOT, "tests", "int_widths")
RECORDING = os.path.join(HERE, "convert-4.6.2.txt")

# Spellings of each width: <cstdint>'s, ROS's (Nav2's models file writes `uint16`), 4.6.2's
# demangled names on Linux x86-64 (what Groot2 and writeTreeNodesModelXML write), and C++'s words
# in another order.
SPELLINGS = {
    "int8_t": ["int8_t", "std::int8_t", "int8", "signed char", "char signed", "int_least8_t"],
    "int16_t": ["int16_t", "std::int16_t", "int16", "short", "short int", "signed short int", "int_fast16_t"],
    "int32_t": ["int32_t", "std::int32_t", "int32", "int", "signed", "signed int", "int signed"],
    "int64_t": ["int64_t", "std::int64_t", "int64", "long", "long int", "long long", "long long int", "intmax_t"],
    "uint8_t": ["uint8_t", "std::uint8_t", "uint8", "unsigned char", "char unsigned", "std::uint_least8_t"],
    "uint16_t": ["uint16_t", "std::uint16_t", "uint16", "unsigned short", "short unsigned int", "unsigned short int"],
    "uint32_t": ["uint32_t", "std::uint32_t", "uint32", "unsigned", "unsigned int", "int unsigned"],
    "uint64_t": [
        "uint64_t",
        "std::uint64_t",
        "uint64",
        "unsigned long",
        "long unsigned int",
        "unsigned long long",
        "long long unsigned int",
        "size_t",
        "std::size_t",
        "uintptr_t",
    ],
}
NOT_INTEGERS = ["long char", "short long", "unsigned signed", "int int", "long long long", "uint128", "char16"]


def _recording() -> dict[str, list[tuple[str, str]]]:
    out: dict[str, list[tuple[str, str]]] = {}
    with open(RECORDING, encoding="utf-8") as f:
        for line in f:
            t, quoted, result = line.rstrip("\n").split("\t")
            assert quoted.startswith('"') and quoted.endswith('"') and "\\" not in quoted
            out.setdefault(t, []).append((quoted[1:-1], result))
    return out


RECORDED = _recording()


def test_the_recording_covers_every_width():
    assert sorted(RECORDED) == sorted(SPELLINGS)
    assert all(len(rows) == 34 for rows in RECORDED.values())


@pytest.mark.parametrize("width", sorted(SPELLINGS))
def test_every_spelling_is_an_integer(width):
    kind = values.UNSIGNED if width.startswith("u") else values.INT
    for spelling in SPELLINGS[width]:
        assert values.normalize_type(spelling) == kind, spelling
        assert not values.is_opaque_type(values.normalize_type(spelling))


def test_what_is_not_an_integer_stays_a_name():
    for spelling in NOT_INTEGERS:
        assert values.is_opaque_type(values.normalize_type(spelling)), spelling


def _btgen(kind: str, text: str) -> str:
    try:
        return str(values.convert_from_string(kind, text))
    except values.ConversionError:
        return "error"


def _range(width: str) -> range:
    bits = int(re.sub(r"[^0-9]", "", width))
    return range(2**bits) if width.startswith("u") else range(-(2 ** (bits - 1)), 2 ** (bits - 1))


@pytest.mark.parametrize("width", sorted(SPELLINGS))
def test_literals_convert_as_the_library_converts_them(width):
    """values.convert_from_string of `int`/`unsigned` (the 32-bit conversion the IR and the
    accessors use): for int32_t and uint32_t it is the library's, input for input. The other
    widths parse alike and differ in range only: the result differs from the library's exactly
    for the numbers inside one of the two ranges (the width's, 32 bits) and outside the other
    (the loader checks the width's own range: test_literals_load_as_the_library_loads_them)."""
    unsigned = width.startswith("u")
    kind, ours_range = (values.UNSIGNED, _range("uint32_t")) if unsigned else (values.INT, _range("int32_t"))
    differ = []
    for text, recorded in RECORDED[width]:
        m = re.match(r"-?[0-9]+", text)  # std::from_chars' number (the library ignores the rest)
        number = int(m.group()) if m else None
        either = number is not None and ((number in _range(width)) != (number in ours_range))
        assert (_btgen(kind, text) != recorded) == either, (width, text, recorded)
        if either:
            differ.append(text)
    if width in ("int32_t", "uint32_t"):
        assert differ == []
    else:
        assert differ  # the recording reaches past both ranges


def test_a_nav2_error_code_is_an_integer(tmp_path, capsys):
    mission = tmp_path / "m.xml"
    mission.write_text(
        """<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence><Plan error_code_id="{code}"/><Check code="{code}" limit="300"/></Sequence>
  </BehaviorTree>
  <TreeNodesModel>
    <Action ID="Plan"><output_port name="error_code_id" type="uint16"/></Action>
    <Condition ID="Check">
      <input_port name="code" type="std::uint16_t"/><input_port name="limit" type="unsigned short int"/>
    </Condition>
  </TreeNodesModel>
</root>
""",
        encoding="utf-8",
    )
    assert main(["validate", "-q", str(mission)]) == 0
    assert main(["compile", str(mission), "-o", str(tmp_path / "out")]) == 0
    assert capsys.readouterr().err == ""
    header = (tmp_path / "out" / "m.hpp").read_text(encoding="utf-8")
    assert "btgen::Slot<std::int64_t> code{" in header
    assert "bool set_error_code_id(std::uint32_t value) const noexcept" in header
    assert "btgen::Input<std::uint32_t> code() const noexcept" in header
    assert "btgen::Input<std::uint32_t> limit() const noexcept" in header


@pytest.mark.parametrize("width", sorted(SPELLINGS))
def test_literals_load_as_the_library_loads_them(width, tmp_path, capsys):
    """4.6.2 converts a typed port's literal when it loads the tree, with the width's own range
    (`uint16` and 70000: the load fails; `int64_t` and 5000000000: it loads). btgen refuses
    exactly the literals the library refused, for every width and spelling."""
    spelling = SPELLINGS[width][2]  # the ROS spelling: `uint16`, `int64`
    rows = RECORDED[width]
    nodes = "\n".join(f'      <Take v="{text}"/>' for text, _ in rows)
    mission = tmp_path / "m.xml"
    mission.write_text(
        f"""<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence>
{nodes}
    </Sequence>
  </BehaviorTree>
  <TreeNodesModel><Action ID="Take"><input_port name="v" type="{spelling}"/></Action></TreeNodesModel>
</root>
""",
        encoding="utf-8",
    )
    status = main(["validate", "-q", str(mission)])
    err = capsys.readouterr().err
    refused = [line.split(":")[1] for line in err.splitlines() if ": error: " in line]
    expected = [str(4 + i) for i, (_, recorded) in enumerate(rows) if recorded == "error"]
    assert refused == expected, err
    assert status == 1


def test_4_10_0_converts_and_reads_as_4_6_2():
    """The recordings of both releases are the same: one rule serves both."""
    for name in ("convert", "entry_reads"):
        with (
            open(os.path.join(HERE, f"{name}-4.6.2.txt"), encoding="utf-8") as a,
            open(os.path.join(HERE, f"{name}-4.10.0.txt"), encoding="utf-8") as b,
        ):
            assert a.read() == b.read(), name


ENTRY_READS_MAIN = r"""#include <cstdio>

#include "entry_reads.hpp"

struct Leaves {
  template <class M>
  btgen::Status report(M& m, const btgen::NodeInfo& node) {
    const auto v = m.v();
    if (v) {
      std::printf("%.*s value %lld\n", static_cast<int>(node.name.size()), node.name.data(),
                  static_cast<long long>(*v));
    } else {
      std::printf("%.*s error\n", static_cast<int>(node.name.size()), node.name.data());
    }
    return btgen::Status::SUCCESS;
  }
  btgen::Status tick(entry_reads::leaf::U16& m, const btgen::NodeInfo& n) { return report(m, n); }
  btgen::Status tick(entry_reads::leaf::I8& m, const btgen::NodeInfo& n) { return report(m, n); }
  btgen::Status tick(entry_reads::leaf::U32& m, const btgen::NodeInfo& n) { return report(m, n); }
};

int main() {
  Leaves leaves;
  entry_reads::EntryReads<Leaves> mission(leaves);
  return mission.tick() == btgen::Status::SUCCESS ? 0 : 1;
}
"""


def test_narrow_ports_read_entries_as_the_library_reads_them(tmp_path, capsys):
    """A `uint16` or `int8_t` port reading an entry that holds a number outside its width fails
    (btgen::PortError::kConversion), as 4.6.2's getInput<T> does (entry_reads-4.6.2.txt)."""
    if shutil.which("g++") is None:
        pytest.skip("no g++")
    mission = os.path.join(HERE, "entry_reads.xml")
    assert main(["compile", mission, "-o", str(tmp_path / "out")]) == 0
    assert capsys.readouterr().err == ""
    (tmp_path / "main.cpp").write_text(ENTRY_READS_MAIN, encoding="utf-8")
    subprocess.run(
        ["g++", "-std=c++17", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-O0"]
        + ["-I", os.path.join(ROOT, "runtime", "include"), "-I", str(tmp_path / "out")]
        + [str(tmp_path / "main.cpp"), str(tmp_path / "out" / "entry_reads.cpp"), "-o", str(tmp_path / "run")],
        check=True,
    )
    run = subprocess.run([str(tmp_path / "run")], capture_output=True, text=True, check=False)
    with open(os.path.join(HERE, "entry_reads-4.6.2.txt"), encoding="utf-8") as f:
        assert (run.returncode, run.stdout) == (0, f.read())
