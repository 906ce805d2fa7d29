"""The Groot2 runtime in its headers: the protocol, the MessagePack of the replies and the JSON
of the hook requests (btgen/groot2/) each compile on their own, and need no operating system;
the publisher (btgen/groot2.hpp), with ZeroMQ and threads, includes them."""

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
