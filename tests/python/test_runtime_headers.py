"""The runtime's headers. The Groot2 runtime: the protocol, the MessagePack of the replies and
the JSON of the hook requests (btgen/groot2/) each compile on their own, and need no operating
system; the publisher (btgen/groot2.hpp), with ZeroMQ and threads, includes them. No header is
over 1,000 lines: btgen/engine.hpp's parts are in btgen/engine/."""

from __future__ import annotations

from pathlib import Path

import pytest

import cppbuild

PROTOCOL_HEADERS = ("btgen/groot2/protocol.hpp", "btgen/groot2/msgpack.hpp", "btgen/groot2/json.hpp")


@pytest.mark.parametrize("header", PROTOCOL_HEADERS)
def test_each_protocol_header_compiles_alone_even_bare_metal(header, tmp_path):
    src = tmp_path / "one.cpp"
    src.write_text(f'#include "{header}"\n')
    cppbuild.syntax_check([src])
    cppbuild.syntax_check([src], defines=["BTGEN_BARE_METAL=1"])


def test_the_publisher_header_includes_the_protocol_headers():
    text = (cppbuild.RUNTIME_INCLUDE / "btgen" / "groot2.hpp").read_text(encoding="utf-8")
    for header in PROTOCOL_HEADERS:
        assert f'#include "{header}"' in text
    folder = cppbuild.RUNTIME_INCLUDE / "btgen" / "groot2"
    assert sorted(p.name for p in folder.glob("*.hpp")) == sorted(Path(h).name for h in PROTOCOL_HEADERS)


# ------------------------------------------------ headers split at their seams (issue 45)
ENGINE_PARTS = ("straight_line.hpp", "nav2_rules.hpp", "rules.hpp")


def test_no_runtime_header_is_over_1000_lines():
    """Issue 45: the runtime's headers stay readable, split at their seams (engine.hpp's
    parts are in btgen/engine/)."""
    sizes = {
        str(p.relative_to(cppbuild.RUNTIME_INCLUDE)): len(p.read_text(encoding="utf-8").splitlines())
        for p in sorted(cppbuild.RUNTIME_INCLUDE.rglob("*.hpp"))
    }
    assert "btgen/engine.hpp" in sizes and "btgen/engine/rules.hpp" in sizes
    assert {name: n for name, n in sizes.items() if n > 1000} == {}


def test_the_engine_parts_are_members_of_its_class():
    """btgen/engine.hpp includes its three parts inside the body of class Engine, each once, and
    btgen/engine/spec.hpp (what a Spec provides) before it; the parts keep clang-format off."""
    engine = (cppbuild.RUNTIME_INCLUDE / "btgen" / "engine.hpp").read_text(encoding="utf-8")
    start = engine.index("class Engine {")
    end = engine.rindex("};")
    assert engine.index('#include "btgen/engine/spec.hpp"') < start
    for part in ENGINE_PARTS:
        line = f'#include "btgen/engine/{part}"  // members of this class'
        assert engine.count(line) == 1 and start < engine.index(line) < end, part
        text = (cppbuild.RUNTIME_INCLUDE / "btgen" / "engine" / part).read_text(encoding="utf-8")
        assert "// clang-format off\n" in text and text.endswith("// clang-format on\n"), part


def test_the_spec_header_compiles_alone(tmp_path):
    src = tmp_path / "one.cpp"
    src.write_text('#include "btgen/engine/spec.hpp"\n')
    cppbuild.syntax_check([src])
