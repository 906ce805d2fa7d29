"""Hostile names for generated C++: a mission that uses every C++ keyword, every
macro of <cerrno> <cstdio> <cstdlib> <cmath> <climits> <cstdint>, every runtime name and
every generated member name as model IDs, ports and blackboard keys, and as file stems.

The macros are read from the compiler here (not from btgen's own list), so a macro the
naming layer does not know fails the build instead of passing unseen."""

from __future__ import annotations

import re
import shutil
import subprocess

from btgen.backend_cpp import naming
from btgen.tools.fuzzgen import HOSTILE_NAMES

SIX_HEADERS = ("cerrno", "cstdio", "cstdlib", "cmath", "climits", "cstdint")


def compiler_macros(cxx: str = "g++") -> list[str]:
    """The macros (not starting with `_`) the six headers define with `cxx`."""
    if shutil.which(cxx) is None:
        return []
    src = "".join(f"#include <{h}>\n" for h in SIX_HEADERS)
    out = subprocess.run(
        [cxx, "-std=c++17", "-x", "c++", "-dM", "-E", "-"], input=src, text=True, stdout=subprocess.PIPE, check=True
    ).stdout
    return sorted({m.group(1) for m in re.finditer(r"^#define ([A-Za-z][A-Za-z0-9_]*)", out, re.M)})


def pool() -> list[str]:
    """Every hostile name: keywords, the six headers' macros (g++ and clang++), runtime and
    generated names (fuzzgen.HOSTILE_NAMES), without duplicates, in a fixed order."""
    names = list(HOSTILE_NAMES) + sorted(naming.CPP_KEYWORDS) + compiler_macros("g++") + compiler_macros("clang++")
    return list(dict.fromkeys(n for n in names if _xml_name(n)))


def _xml_name(n: str) -> bool:
    # Port and model names must be XML-attribute-safe and allowed by 4.6.2 (not `name`, `ID`, `_x`).
    return bool(re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*", n)) and n not in ("name", "ID")


def mission(names: list[str]) -> str:
    """Every name as a model ID (an Action whose one port is named like its model, read from
    the key of that name), and as a port and key of one model `Ports` (typed int, double, string
    and untyped in turn, all inout: getter and setter); each model's port has the same type.
    Comment text ends in `??/`."""
    types = ("int", "double", "std::string", None)
    models, nodes, ports, attrs = [], [], [], []
    for i, n in enumerate(names):
        t = types[i % 4]
        typed = f' type="{t}"' if t else ""
        models.append(f'    <Action ID="{n}"><input_port name="{n}"{typed}/></Action>')
        nodes.append(f'      <{n} {n}="{{{n}}}"/>')
        # A description ending in the trigraph `??/` (it would continue a // comment).
        ports.append(f'      <inout_port name="{n}"' + (f' type="{t}"' if t else "") + ">ends ??/</inout_port>")
        attrs.append(f'{n}="{{{n}}}"')
    return (
        '<root BTCPP_format="4" main_tree_to_execute="Main">\n  <BehaviorTree ID="Main">\n    <Sequence>\n'
        + "\n".join(
            [
                f"      <Ports {' '.join(attrs)}/>",
                '      <LoopString queue="a;b??/" value="{loop_value}"><AlwaysSuccess/></LoopString>',
            ]
            + nodes
        )
        + '\n    </Sequence>\n  </BehaviorTree>\n  <TreeNodesModel>\n    <Action ID="Ports">\n'
        + "\n".join(ports)
        + "\n    </Action>\n"
        + "\n".join(models)
        + "\n  </TreeNodesModel>\n</root>\n"
    )


STEM_MISSION = """<root BTCPP_format="4">
  <BehaviorTree ID="Main">
    <Sequence><AlwaysSuccess/><Act x="{x}"/></Sequence>
  </BehaviorTree>
  <TreeNodesModel><Action ID="Act"><inout_port name="x" type="int"/></Action></TreeNodesModel>
</root>
"""


def stems_translation_unit(tmp, names: list[str], instantiate: frozenset = frozenset()) -> str:
    """Generate a small mission under each name as its file stem into `tmp` and return one
    translation unit that includes every header, and the source (the explicit instantiation
    of the mission's engine, slow) of the stems in `instantiate`."""
    from btgen.compiler import generate

    seen: set[str] = set()
    lines = []
    for n in names:
        header = naming.header_name(n)
        if header in seen:
            continue
        seen.add(header)
        path = tmp / f"{n}.xml"
        path.write_text(STEM_MISSION, encoding="utf-8")
        for out in generate(str(path), relative_to=str(tmp)):
            (tmp / out.name).write_text(out.text, encoding="utf-8")
            if out.name.endswith(".hpp") or n in instantiate:
                lines.append(f'#include "{out.name}"')
    return "\n".join(lines) + "\n"
