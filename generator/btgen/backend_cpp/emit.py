"""Emission: the lowered Program -> C++ text, through the Jinja2 templates.

One Environment (StrictUndefined, keep_trailing_newline, autoescape off);
every name, literal and reference spelling is a Python filter from here or
naming.py. Templates only loop and substitute; a choice a template does not know
(an operation kind it has no C++ for) calls `unknown()`, and any error while
rendering is an InternalError located at the template's line, never C++ that
quietly does something else. Output depends on nothing but the Program, the
file stem and the banner's input paths: same input, same bytes.
"""

from __future__ import annotations

import os
import sys
import textwrap
from dataclasses import dataclass
from typing import Any, Callable, NoReturn, Optional

import jinja2

from btgen import resources
from btgen.backend_cpp import data_cpp, naming
from btgen.backend_cpp.literals import cpp_bool, cpp_int, cpp_string, cpp_string_view
from btgen.backend_cpp.script_cpp import compile_scripts
from btgen.backend_cpp.shapes import shapes
from btgen.diagnostics import InternalError
from btgen.ir.lower import SUPPORTED, IRNode, Program
from btgen.lang.versions import semantics, switch_names, version_number
from btgen.version import RUNTIME_ABI, __version__

TEMPLATE_DIR = resources.TEMPLATE_DIR
TEMPLATES = ("mission.hpp.j2", "mission.cpp.j2")

_NODE_KINDS = frozenset(k for k, _, _ in SUPPORTED.values()) | {"Action", "Condition", "UserControl", "UserDecorator"}


@dataclass(frozen=True)
class Output:
    name: str  # file name (no directory)
    text: str


# The node table's spellings: the mission's namespace `detail` has using-declarations of
# btgen::NodeKind, kNoNode, kNoSlot and kNoModel (btgen/node.hpp), so that a row fits a line.
def node_ref(index: int) -> str:
    return "kNoNode" if index < 0 else str(index)


def slot_ref(slot: int) -> str:
    return "kNoSlot" if slot < 0 else f"{slot}u"


def model_ref(model: int) -> str:
    return "kNoModel" if model < 0 else str(model)


def node_kind(kind: str) -> str:
    if kind not in _NODE_KINDS:
        raise InternalError(f"no btgen::NodeKind for `{kind}`")
    return f"NodeKind::{kind}"


def node_label(n: IRNode, depth: int) -> str:
    """A node table row's comment: its kind, model ID and name (each once), indented by depth."""
    label = n.kind if n.kind == n.id else f"{n.kind} {n.id}"
    if n.name != n.id:
        label += f' "{n.name}"'
    return "  " * depth + label


def groot2_context(program: Program) -> dict:
    """What the template's Groot2 section needs: the tree XML as lines, BehaviorTree.CPP's
    status order, its blackboard names and, per blackboard, its entries sorted by key."""
    tree = program.groot2
    if tree is None:
        raise InternalError("the program has no Groot2 tree (lower() makes one)")
    data = program.data
    assert data is not None
    names = [inst.blackboard_name for inst in tree.instances]
    index_of_uid = {0: 0}
    for i, inst in enumerate(tree.instances[1:], start=1):
        index_of_uid[inst.nodes[0]] = i  # the SubTree node's UID is its tree root's index
    entries: list[dict[str, Any]] = []
    for sl, member in zip(data.slots, naming.slot_members(data.slots)):
        bb = index_of_uid.get(sl.owner_uid)
        if bb is None:
            raise InternalError(f"blackboard of SubTree UID {sl.owner_uid} not among the tree instances")
        entries.append(dict(bb=bb, key=sl.key, member=member, pool=sl.pool))
    entries.sort(key=lambda e: (e["bb"], e["key"].encode("utf-8")))
    return dict(
        xml_lines=tree.xml.splitlines(keepends=True),
        xml_size=len(tree.xml.encode("utf-8")),
        order=tree.status_order,
        blackboards=names,
        entries=entries,
    )


class TemplateFailure(Exception):
    """A template met a value it has no C++ for (raised by `unknown()` in a template)."""


def unknown(what: str, value: object) -> NoReturn:
    """Called by a template for a choice it does not know: fail, rather than print code that
    does something else."""
    raise TemplateFailure(f"the templates have no C++ for the {what} `{value}`")


def render_template(env: jinja2.Environment, name: str, ctx: dict) -> str:
    """The template `name` rendered; an error inside it (unknown(), an undefined name, a
    filter's InternalError, a bug of the template) is an InternalError that names the
    template file and line where it happened."""
    try:
        return env.get_template(name).render(ctx)
    except (TemplateFailure, jinja2.TemplateError, InternalError, LookupError, TypeError, ValueError) as e:
        where = name
        tb = sys.exc_info()[2]
        while tb is not None:  # Jinja2 gives template frames the template's file and line
            filename = tb.tb_frame.f_code.co_filename
            if filename.endswith(".j2"):
                where = f"{display_path(filename, str(TEMPLATE_DIR.parent))}:{tb.tb_lineno}"
            tb = tb.tb_next
        raise InternalError(f"{where}: {e}") from e


def _cpp_name(model: Any) -> str:
    """A leaf model's class name (naming.name_program made it a CppLeafModel)."""
    if not isinstance(model, naming.CppLeafModel):
        raise InternalError(f"leaf model `{model.id}` has no C++ name (naming.name_program gives it one)")
    return model.cpp_name


def contract_models(program: Program) -> list[str]:
    """The lines of the header's contract that name this mission's models by kind."""
    parts = []
    for kind, models, ns in (
        ("Action", program.actions, "leaf"),
        ("Condition", program.conditions, "leaf"),
        ("Control or Decorator", program.user_nodes, "control"),
    ):
        if models:
            names = ", ".join(_cpp_name(m) for m in models)
            parts.append(f"{len(models)} {kind} model{'s' if len(models) > 1 else ''} in {ns}:: ({names})")
    if not parts:
        return ["This mission has no models: Leaves needs no hook."]
    return textwrap.wrap("Here: " + "; ".join(parts) + ".", width=96, break_on_hyphens=False)


def _environment() -> jinja2.Environment:
    env = jinja2.Environment(
        loader=jinja2.FileSystemLoader(str(TEMPLATE_DIR)),
        undefined=jinja2.StrictUndefined,
        keep_trailing_newline=True,
        autoescape=False,
        trim_blocks=True,
        lstrip_blocks=True,
    )
    env.filters.update(
        cpp_string=cpp_string,
        cpp_comment=naming.cpp_comment,
        node_ref=node_ref,
        slot_ref=slot_ref,
        model_ref=model_ref,
        node_kind=node_kind,
        cpp_int=cpp_int,
        cpp_bool=cpp_bool,
        cpp_string_view=cpp_string_view,
    )
    env.filters.update(data_cpp.FILTERS)
    env.tests.update(data_cpp.TESTS)
    env.globals["unknown"] = unknown
    return env


_ENV: Optional[jinja2.Environment] = None


def environment() -> jinja2.Environment:
    global _ENV
    if _ENV is None:
        _ENV = _environment()
    return _ENV


def display_path(path: str, relative_to: Optional[str]) -> str:
    """`path` relative to `relative_to`, with `/` separators (the banner's form); as given
    (the diagnostics' form) when `relative_to` is None."""
    if relative_to is None:
        return path
    rel = os.path.relpath(os.path.abspath(path), os.path.abspath(relative_to))
    return rel.replace(os.sep, "/")


def output_names(stem: str) -> tuple[str, str]:
    return naming.header_name(stem), naming.source_name(stem)


def render(
    program: Program, stem: str, relative_to: Optional[str] = ".", namespace: Optional[str] = None
) -> tuple[Output, ...]:
    """The generated header and source for `program`; paths in it are relative to
    `relative_to`, or as the diagnostics give them when it is None. `namespace`:
    the C++ namespace (`--namespace`, checked by the command line), else derived
    from `stem`."""
    show: Callable[[str], str] = lambda p: display_path(p, relative_to)  # noqa: E731
    program = naming.name_program(program)  # the C++ names of slots, ports and models
    data = program.data
    if data is None:
        raise InternalError("the program has no data side (lower() makes one)")
    header, source = output_names(stem)
    cls = naming.pascal_case(stem)
    compiled, where = compile_scripts(data)
    depth: dict[int, int] = {}
    for n in program.nodes:  # a parent comes before its children
        depth[n.index] = 0 if n.parent < 0 else depth[n.parent] + 1
    tables = script_tables(compiled, len(program.nodes))

    def source_of(n: IRNode) -> str:
        return f"{show(n.loc.path)}:{n.loc.line}:{n.loc.col}"

    def show_loc(loc) -> str:
        return f"{show(loc.path)}:{loc.line}:{loc.col}"

    ctx: dict[str, Any] = dict(
        version=__version__,
        abi=RUNTIME_ABI,
        input=show(program.mission_path),
        includes=[show(f) for f in program.files[1:]],
        header=header,
        source=source,
        guard=naming.include_guard(stem),
        ns=naming.mission_namespace(stem, namespace),
        cls=cls,
        program=program,
        nodes=[dict(n=n, source=source_of(n), label=node_label(n, depth[n.index])) for n in program.nodes],
        contract_models=contract_models(program),
        data=data,
        slots=[
            dict(s=sl, origin=sl.origin + (f" at {show_loc(sl.origin_loc)}" if sl.origin_loc else ""))
            for sl in data.slots
        ],
        where=[show_loc(loc) for loc in where],
        leaves=[dict(m=m, ports=data.ports.get(m.id, ())) for m in program.leaf_models],
        # the models Spec's visitors dispatch to: every Action and Condition, the Controls and
        # Decorators a node uses (the others' hooks need not exist)
        dispatched=[
            ("visit_action", program.actions),
            ("visit_condition", program.conditions),
            ("visit_user_node", program.used_user_nodes),
        ],
        scripts=tables,
        groot2=groot2_context(program),
        shapes=shapes(program, tables["node_fns"]),
        btcpp=program.btcpp,
        btcpp_number=version_number(program.btcpp),
        switches=[(name, getattr(semantics(program.btcpp), name)) for name in switch_names()],
    )
    env = environment()
    return _stamped(
        Output(header, render_template(env, "mission.hpp.j2", ctx)),
        Output(source, render_template(env, "mission.cpp.j2", ctx)),
        ctx["ns"],
        ctx["guard"],
    )


def script_tables(scripts, node_count: int) -> dict:
    """The compiled scripts as the header holds them: one function per distinct body (identical
    scripts share it), and a site per node and ScriptSlot (the function, the places and
    messages its errors name, the message prefix), sites ordered by node, `first[i]` the first
    site of node i (node_count + 1 entries)."""
    functions: list[dict] = []
    by_body: dict[tuple[str, ...], dict] = {}
    sites: list[dict] = []
    errors: list[tuple[str, str]] = []
    for c in sorted(scripts, key=lambda c: (c.node, c.which)):
        fn = by_body.get(c.body)
        if fn is None:
            fn = by_body[c.body] = dict(name=f"script{len(functions)}", comment=c.comment, body=c.body, uses=0)
            functions.append(fn)
        fn["uses"] += 1
        sites.append(
            dict(
                node=c.node,
                which=naming.SCRIPT_SLOT_ENUMERATORS[c.which],
                fn=fn["name"],
                at=len(errors) if c.errors else None,
                prefix=c.prefix,
                comment=c.comment,
            )
        )
        errors.extend(c.errors)
    first = [0] * (node_count + 1)
    node_fns: list[tuple[str, ...]] = [()] * node_count
    for site in sites:
        first[site["node"] + 1] += 1
        node_fns[site["node"]] += (site["fn"],)
    for i in range(node_count):
        first[i + 1] += first[i]
    return dict(functions=functions, sites=sites, errors=errors, first=first, node_fns=node_fns)


def _stamped(header: Output, source: Output, ns: str, guard: str) -> tuple[Output, Output]:
    """Both files with the generation they belong to: a hash of the pair, a constant in the
    header that the source checks. A header from one run and a source from another (two
    compiles of same-stem missions into one folder at once, or a kill between the two
    renames) fail to build with a message that says so, instead of mixing two missions."""
    import hashlib

    digest = hashlib.sha256((header.text + "\0" + source.text).encode("utf-8")).hexdigest()[:16]
    end = f"#endif  // {guard}\n"
    if not header.text.endswith(end):
        raise InternalError("the generated header does not end with its include guard")
    stamp = (
        f"// The generation of {header.name} and {source.name} (both carry it; {source.name} checks it).\n"
        f"namespace {ns}::detail {{\ninline constexpr unsigned long long kGeneration = 0x{digest}ULL;\n}}\n\n"
    )
    check = (
        f"\nstatic_assert({ns}::detail::kGeneration == 0x{digest}ULL,\n"
        f'              "{header.name} and {source.name} come from different btgen runs: run btgen compile '
        f'again");\n'
    )
    return (Output(header.name, header.text[: -len(end)] + stamp + end), Output(source.name, source.text + check))
