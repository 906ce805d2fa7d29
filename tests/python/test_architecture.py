"""The package's imports go one way, as ARCHITECTURE.md draws them."""

import ast
from pathlib import Path

from conftest import ROOT

PACKAGE = Path(ROOT) / "generator" / "btgen"

# layer -> the layers it may import (itself always allowed)
BASE = {"btgen.diagnostics", "btgen.version", "btgen.resources", "btgen.fileio"}
ALLOWED = {
    "base": set(),
    "lang": {"base"},
    "frontend": {"base", "lang"},
    "ir": {"base", "lang", "frontend"},
    "backend_cpp": {"base", "lang", "ir"},
    "interp": {"base", "lang"},
    "kb": {"base", "frontend"},
    "top": {"base", "lang", "frontend", "ir", "backend_cpp", "interp", "kb", "tools", "top"},
    "tools": {"base", "lang", "frontend", "ir", "backend_cpp", "interp", "kb", "tools", "top"},
}
# Edges ARCHITECTURE.md names as debt: (importing module, imported module).
KNOWN_DEBT = {
    # --type names a C++ type: checking its spelling needs C++'s keywords
    ("btgen.frontend.usertypes", "btgen.backend_cpp.naming"),
}


def _layer(module: str) -> str:
    if module in BASE:
        return "base"
    parts = module.split(".")
    if len(parts) >= 3 and parts[1] in ALLOWED:
        return parts[1]
    return "top"  # btgen.cli, btgen.compiler, btgen.__main__


def _module_name(path: Path) -> str:
    rel = path.relative_to(PACKAGE.parent).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _imports(path: Path):
    tree = ast.parse(path.read_text(encoding="utf-8"))
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            if node.module.startswith("btgen"):
                for alias in node.names:
                    full = f"{node.module}.{alias.name}"
                    # `from btgen.lang import values` imports the module btgen.lang.values
                    path = PACKAGE.parent / full.replace(".", "/")
                    is_module = path.with_suffix(".py").exists() or (path / "__init__.py").exists()
                    yield full if is_module else node.module
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.startswith("btgen"):
                    yield alias.name
        elif isinstance(node, ast.ImportFrom) and node.level > 0:
            yield f"relative import in {path.name}"


def test_imports_follow_the_layers():
    wrong = []
    for path in sorted(PACKAGE.rglob("*.py")):
        me = _module_name(path)
        mine = _layer(me)
        for target in _imports(path):
            if target.startswith("relative import"):
                wrong.append(f"{me}: {target} (use absolute btgen.* imports)")
                continue
            theirs = _layer(target)
            if theirs == mine or theirs in ALLOWED[mine] or (me, target) in KNOWN_DEBT:
                continue
            wrong.append(f"{me} ({mine}) imports {target} ({theirs})")
    assert wrong == []


def test_the_known_debt_is_still_real():
    """An edge in KNOWN_DEBT that no longer exists must leave the list (and ARCHITECTURE.md)."""
    present = {(_module_name(p), t) for p in PACKAGE.rglob("*.py") for t in _imports(p)}
    assert present >= KNOWN_DEBT


def test_every_subpackage_is_in_the_table():
    subpackages = {p.parent.name for p in PACKAGE.glob("*/__init__.py")}
    assert subpackages <= set(ALLOWED), subpackages - set(ALLOWED)


def _module_level_names(path: Path) -> set[str]:
    names = set()
    for node in ast.parse(path.read_text(encoding="utf-8")).body:
        targets = (
            node.targets if isinstance(node, ast.Assign) else [node.target] if isinstance(node, ast.AnnAssign) else []
        )
        names |= {t.id for t in targets if isinstance(t, ast.Name)}
    return names


def test_the_ir_keeps_no_module_level_mutable_state():
    """The IR passes what a compile needs as values: no table of a module changes during a
    run, and its constant tables cannot be changed (frozenset, MappingProxyType, tuples)."""
    import importlib

    mutable = []
    for path in sorted((PACKAGE / "ir").rglob("*.py")):
        module = importlib.import_module(_module_name(path))
        for name in sorted(_module_level_names(path)):
            value = getattr(module, name)
            if isinstance(value, (dict, list, set, bytearray)):
                mutable.append(f"{module.__name__}.{name}: {type(value).__name__}")
    assert mutable == []


def test_the_ir_carries_no_cpp_names():
    """The IR names slots, ports and models by key and ID; backend_cpp/naming.py gives the
    C++ names (CppSlot.member, CppPort.name and scratch, CppLeafModel.cpp_name)."""
    from dataclasses import fields

    from btgen.ir.data.records import PortIR, SlotIR
    from btgen.ir.lower import LeafModel

    names = {(cls.__name__, f.name) for cls in (SlotIR, PortIR, LeafModel) for f in fields(cls)}
    assert not names & {("SlotIR", "member"), ("PortIR", "name"), ("PortIR", "scratch"), ("LeafModel", "cpp_name")}


def test_script_slots_are_the_runtimes():
    """The IR's script places (ScriptSlot, their NodeInfo::scripts bits) and the back end's
    enumerators for them are runtime/include/btgen/blackboard.hpp's `enum class ScriptSlot`."""
    import re

    from btgen.backend_cpp.naming import SCRIPT_SLOT_ENUMERATORS
    from btgen.ir.data.records import ScriptSlot

    header = (Path(ROOT) / "runtime" / "include" / "btgen" / "blackboard.hpp").read_text(encoding="utf-8")
    body = re.search(r"enum class ScriptSlot : std::uint8_t \{(.*?)\};", header, re.S)
    assert body is not None
    runtime = {name: int(value) for name, value in re.findall(r"(k\w+) = (\d+)", body.group(1))}
    assert {SCRIPT_SLOT_ENUMERATORS[s]: int(s) for s in ScriptSlot} == runtime


def _import_graph() -> dict[str, set[str]]:
    """Module -> the btgen modules it imports, wherever the import statement stands (an import
    inside a function is still an arrow: it only hides a cycle until that function runs)."""
    graph: dict[str, set[str]] = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        graph[_module_name(path)] = {t for t in _imports(path) if not t.startswith("relative import")}
    return graph


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module, and modules importing
    themselves (Tarjan's algorithm, iterative), each sorted."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    on_stack: set[str] = set()
    stack: list[str] = []
    found: list[list[str]] = []
    for root in sorted(graph):
        if root in index:
            continue
        work = [(root, iter(sorted(graph.get(root, ()))))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            node, children = work[-1]
            child = next(children, None)
            if child is not None:
                if child not in index:
                    index[child] = low[child] = len(index)
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(graph.get(child, ())))))
                elif child in on_stack:
                    low[node] = min(low[node], index[child])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                component = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    component.append(member)
                    if member == node:
                        break
                if len(component) > 1 or node in graph.get(node, ()):
                    found.append(sorted(component))
    return found


def test_no_import_cycles():
    """No two modules of btgen import each other, directly or through others."""
    assert _cycles(_import_graph()) == []


def test_the_cycle_finder_finds_cycles():
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a", "d"}, "d": set(), "e": {"e"}, "f": {"d"}}
    assert sorted(_cycles(graph)) == [["a", "b", "c"], ["e"]]
    assert _cycles({"a": {"b"}, "b": set()}) == []


def test_only_the_pipeline_lowers():
    """`pipeline.program` is the one caller of the IR's `lower` outside the IR (so every command,
    the executor's builds and the Cortex-M builds lower alike, substitution rules included)."""
    callers = []
    for path in sorted(PACKAGE.rglob("*.py")):
        me = _module_name(path)
        if me == "btgen.pipeline" or me.startswith("btgen.ir."):
            continue
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and node.module == "btgen.ir.lower":
                if any(alias.name == "lower" for alias in node.names):
                    callers.append(me)
    assert callers == []
