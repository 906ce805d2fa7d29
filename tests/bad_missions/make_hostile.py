"""Large hostile missions, written at test time instead of being committed.

Both files are well-formed BehaviorTree.CPP v4 missions whose only fault is
their size, so a front end that refuses them must do so for the right reason:

- ``deep_nesting``: a main tree that nests ``depth`` Inverters around one
  AlwaysSuccess. Expected: an error at the first element nested deeper than
  the front end's limit (BehaviorTree.CPP itself recurses once per level and
  can exhaust the stack), never a RecursionError or a crash.
- ``huge_file``: a main Sequence with as many AlwaysSuccess leaves as it takes
  to make the file exactly ``megabytes`` MiB. Expected: an error at 1:1 that
  the file is over the size limit, before the XML is parsed.

Usage from a test::

    from make_hostile import deep_nesting, huge_file
    deep_nesting(tmp_path / "deep.xml")

or from the shell: ``python tests/bad_missions/make_hostile.py OUT_DIR``.
"""

from __future__ import annotations

import os
import sys
from typing import Union

PathLike = Union[str, "os.PathLike[str]"]

_HEAD = (
    '<?xml version="1.0" encoding="UTF-8"?>\n'
    '<root BTCPP_format="4" main_tree_to_execute="Hostile">\n'
    '  <BehaviorTree ID="Hostile">\n'
)
_TAIL = "  </BehaviorTree>\n</root>\n"
_CHUNK = 1 << 20  # write in pieces of about 1 MiB


def deep_nesting(path: PathLike, depth: int = 10000) -> str:
    """Write a mission nesting ``depth`` Inverters (element depth ``depth + 3``); return the path."""
    if depth < 1:
        raise ValueError("depth must be at least 1")
    path = os.fspath(path)
    with open(path, "w", encoding="utf-8", newline="\n") as f:
        f.write(_HEAD)
        f.write("<Inverter>" * depth)  # one line: indentation would make the file quadratic in depth
        f.write("\n<AlwaysSuccess/>\n")
        f.write("</Inverter>" * depth)
        f.write("\n")
        f.write(_TAIL)
    return path


def huge_file(path: PathLike, megabytes: int = 50) -> str:
    """Write a valid mission of exactly ``megabytes`` MiB (at least 1); return the path.

    The leaves are numbered (``name="n0000001"``, ...) so that the content is
    not one repeated line a compressor or a cache could shortcut; a comment at
    the end pads the file to the exact size.
    """
    if megabytes < 1:
        raise ValueError("megabytes must be at least 1")
    path = os.fspath(path)
    target = megabytes * 1024 * 1024
    head = _HEAD + "    <Sequence>\n"
    tail = "    </Sequence>\n" + _TAIL
    pad_open, pad_close = "<!--", "-->\n"
    leaf_len = len('      <AlwaysSuccess name="n0000000"/>\n')
    room = target - len(head) - len(tail) - len(pad_open) - len(pad_close)
    count = room // leaf_len
    if count > 9_999_999:
        raise ValueError("megabytes too large for 7-digit leaf names")
    pad = room - count * leaf_len
    with open(path, "w", encoding="ascii", newline="\n") as f:
        f.write(head)
        lines: list[str] = []
        size = 0
        for i in range(1, count + 1):
            lines.append(f'      <AlwaysSuccess name="n{i:07d}"/>\n')
            size += leaf_len
            if size >= _CHUNK:
                f.write("".join(lines))
                lines, size = [], 0
        f.write("".join(lines))
        f.write(tail)
        f.write(pad_open + "x" * pad + pad_close)
    written = os.path.getsize(path)
    if written != target:  # a logic error here would make the test meaningless
        raise AssertionError(f"huge_file wrote {written} bytes, wanted {target}")
    return path


def main(argv: list[str]) -> int:
    if len(argv) != 2:
        print("usage: make_hostile.py OUT_DIR", file=sys.stderr)
        return 2
    out = argv[1]
    os.makedirs(out, exist_ok=True)
    print(deep_nesting(os.path.join(out, "deep_nesting.xml")))
    print(huge_file(os.path.join(out, "huge_file.xml")))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
