"""Which files of a repository are BehaviorTree.CPP files, what each one is, and how each is loaded.

A file is found by its content, not its name: its first element is a `<root ... BTCPP_format=...>`
(or a `<root>` whose first element is a tree, models or an include), after an XML declaration and
comments; so `nav.tree` or a file without extension counts, a `.xml` of ROS launch or a Python
file that holds such XML in a string does not.
Each is then one of:

- a Groot2 project (`.btproj`, or a `<root project_name=...>`): its `<include>`s name the project's
  tree files and its `<TreeNodesModel>` declares their nodes;
- a models file: a `<root>` holding only `<TreeNodesModel>` (Nav2's `nav2_tree_nodes.xml`);
- a file of trees: a mission, a tree library (some other file uses its trees as SubTrees without
  including it), or a file only included by others.

Every file of trees that is not only included is loaded as its own mission (`Unit`), the way the
project's program does: the models files of its folder (and of the Groot2 projects that list it, and
of the configuration) count as declared; the files of trees of its folder (or project) that define the
SubTrees it uses and does not include are tree libraries (`--trees`); a file with several trees and
no main_tree_to_execute is loaded once per tree (the program picks one in C++). The plan depends only
on the set of files found, never on the order of the walk.
"""

from __future__ import annotations

import fnmatch
import functools
import os
import re
import stat
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Optional

from lxml import etree

SNIFF_BYTES = 64 * 1024
MAX_BYTES = 4 * 1024 * 1024
SKIP_DIRS = {".git", ".hg", ".svn", "__pycache__", "node_modules", ".venv", "venv", ".tox", ".mypy_cache"}
# the first element of the file, after an XML declaration, comments and blank space
# (and a DOCTYPE, which the loader then refuses: E103)
_LEAD = (
    rb"\A(?:\xef\xbb\xbf)?\s*(?:<\?xml[^>]*\?>\s*)?(?:<!--.*?-->\s*)*"
    rb"(?:<!DOCTYPE[^\[>]*(?:\[.*?\])?\s*>\s*)?(?:<!--.*?-->\s*)*"
)
_ROOT = re.compile(_LEAD + rb"<root\b[^>]*\bBTCPP_format\s*=", re.S)
_ROOT_V3 = re.compile(_LEAD + rb"<root\b[^>]*>\s*(?:<!--.*?-->\s*)*<(?:BehaviorTree|TreeNodesModel|include)\b", re.S)
_XML_VERSION = re.compile(rb"(?:\xef\xbb\xbf)?\s*(<\?xml\s[^>]*?\bversion\s*=\s*[\"']([^\"']*)[\"'][^>]*\?>)")
_PROJECT = re.compile(rb"<root\b[^>]*\bproject_name\s*=", re.S)


@dataclass
class BTFile:
    path: str  # as shown: the checked PATH joined with the walk
    role: str = "trees"  # "project" | "models" | "trees" | "broken"
    trees: tuple[str, ...] = ()
    main: Optional[str] = None  # main_tree_to_execute
    subtrees: frozenset[str] = frozenset()  # SubTree IDs its trees use
    includes: tuple[str, ...] = ()  # real paths of the files its <include path=...> name
    ros_includes: bool = False
    models: frozenset[str] = frozenset()  # IDs its <TreeNodesModel> declares
    uses: frozenset[str] = frozenset()  # node IDs its trees use (element names, ID of the generic forms)
    included_by: list[str] = field(default_factory=list)  # shown paths of includers
    library_of: list[str] = field(default_factory=list)  # shown paths of files using its trees as SubTrees
    projects: list[str] = field(default_factory=list)  # shown paths of .btproj files listing it
    context: bool = False  # beside a file given by name: read for its models and trees, not checked

    @functools.cached_property
    def real(self) -> str:  # (asked for every pair of files of a folder: computed once)
        return os.path.realpath(self.path)

    @property
    def kind(self) -> str:
        """What the file is to the project, in words (for `--show-settings` and the docs)."""
        if self.role != "trees":
            return {"project": "Groot2 project", "models": "models file", "broken": "unreadable file"}[self.role]
        if self.included_by and self.main is None:
            return "included file"
        if self.library_of and self.main is None:
            return "tree library"
        return "mission"


@dataclass(frozen=True)
class Unit:
    """One load of the front end and IR: a file, the tree to run, its models and libraries."""

    path: str
    main_tree: Optional[str]
    models: tuple[str, ...]
    trees: tuple[str, ...]
    library: bool  # the file is a tree library checked on its own
    projects: tuple[str, ...] = ()  # those of `models` that are Groot2 projects (their TreeNodesModel counts)


def matches(path: str, globs: tuple[str, ...]) -> bool:
    """Whether a path (relative, `/`-separated) or one of its folders matches one of the globs (a
    glob without `/` matches a name at any depth, as in ruff's `exclude`)."""
    p = path.replace(os.sep, "/")
    while p.startswith("./"):
        p = p[2:]
    parts = p.split("/")
    for g in globs:
        if fnmatch.fnmatch(p, g) or fnmatch.fnmatch(parts[-1], g):
            return True
        if any(fnmatch.fnmatch("/".join(parts[: i + 1]), g.rstrip("/")) for i in range(len(parts) - 1)):
            return True
    return False


def sniff(path: str) -> bool:
    """Whether the file starts like a BehaviorTree.CPP file (a regular, readable, not too large one)."""
    try:
        st = os.stat(path)
        if not stat.S_ISREG(st.st_mode) or st.st_size > MAX_BYTES or st.st_size == 0:
            return False
        with open(path, "rb") as f:
            head = f.read(SNIFF_BYTES)
    except OSError:
        return False
    # (a <root> without BTCPP_format whose first element is a tree, models or include: read as format 4)
    return b"\x00" not in head[:512] and (_ROOT.match(head) is not None or _ROOT_V3.match(head) is not None)


def walk(
    paths: list[str], skip: Callable[[str, bool], bool] = lambda p, is_dir: False, recurse: bool = True
) -> list[str]:
    """The BehaviorTree.CPP files under `paths` (a file given by name is taken when it sniffs as one),
    sorted, each once; `skip(path, is_dir)` leaves out what the configuration excludes."""
    found: dict[str, str] = {}
    for top in paths:
        if os.path.isfile(top):
            if sniff(top):
                found.setdefault(os.path.realpath(top), top)
            continue
        for folder, dirs, files in os.walk(top):
            dirs[:] = sorted(
                d
                for d in dirs
                if recurse and d not in SKIP_DIRS and not d.startswith(".") and not skip(os.path.join(folder, d), True)
            )
            for name in sorted(files):
                full = os.path.normpath(os.path.join(folder, name))
                if skip(full, False):
                    continue
                if sniff(full):
                    found.setdefault(os.path.realpath(full), full)
    return sorted(found.values())


_PARSER = etree.XMLParser(
    resolve_entities=False, no_network=True, load_dtd=False, huge_tree=False, remove_comments=True, remove_pis=True
)


def read(path: str) -> BTFile:
    """What one file declares; a file lxml cannot read is "broken" (the loader then says why)."""
    f = BTFile(path)
    try:
        with open(path, "rb") as fh:
            data = fh.read(MAX_BYTES + 1)
        if b"<!DOCTYPE" in data or b"<!ENTITY" in data:
            f.role = "broken"
            return f
        version = _XML_VERSION.match(data)
        if version is not None and not re.fullmatch(rb"1\.[0-9]+", version.group(2)):
            # a version libxml2 does not know (`2.0`), which tinyxml2 does not read: the loader warns
            data = data[: version.start(1)] + b" " * len(version.group(1)) + data[version.end(1) :]
        root = etree.fromstring(data, _PARSER)
    except (OSError, etree.XMLSyntaxError, ValueError):
        f.role = "broken"
        return f
    if root.tag != "root":
        f.role = "broken"
        return f
    kids = [c for c in root if isinstance(c.tag, str)]
    base = os.path.dirname(os.path.realpath(path))
    f.includes = tuple(
        os.path.realpath(os.path.join(base, c.get("path") or ""))
        for c in kids
        if c.tag in ("include", "Include") and c.get("path") and c.get("ros_pkg") is None
    )
    f.ros_includes = any(c.tag == "include" and c.get("ros_pkg") is not None for c in kids)
    f.models = frozenset(
        m.get("ID") or "" for c in kids if c.tag == "TreeNodesModel" for m in c if isinstance(m.tag, str)
    )
    if root.get("project_name") is not None or path.endswith(".btproj"):
        f.role = "project"
        return f
    trees = [c for c in kids if c.tag == "BehaviorTree"]
    if not trees and kids and all(c.tag == "TreeNodesModel" for c in kids):
        f.role = "models"
        return f
    f.trees = tuple(t.get("ID") or "" for t in trees)
    f.main = root.get("main_tree_to_execute")
    f.subtrees = frozenset(e.get("ID") or "" for t in trees for e in t.iter("SubTree"))
    f.uses = frozenset(
        (e.get("ID") or "") if e.tag in _GENERIC else e.tag
        for t in trees
        for e in t.iter()
        if isinstance(e.tag, str) and e is not t and e.tag != "SubTree"
    )
    return f


_GENERIC = ("Action", "Condition", "Control", "Decorator")


@dataclass
class Project:
    files: dict[str, BTFile]  # by real path

    def by_folder(self, real: str) -> list[BTFile]:
        folder = os.path.dirname(real)
        return [f for r, f in sorted(self.files.items()) if os.path.dirname(r) == folder]

    @functools.cached_property
    def definers(self) -> dict[str, list[BTFile]]:
        """The files of trees defining each tree ID (a file found anywhere under the checked paths)."""
        out: dict[str, list[BTFile]] = {}
        for _r, f in sorted(self.files.items()):
            if f.role == "trees":
                for t in f.trees:
                    out.setdefault(t, []).append(f)
        return out

    @functools.cached_property
    def models_files(self) -> list[BTFile]:
        return [f for _r, f in sorted(self.files.items()) if f.role == "models"]


def distance(a: str, b: str) -> int:
    """How far apart two files' folders are: the folders to go up from one and down to the other."""
    pa = os.path.dirname(a).split(os.sep)
    pb = os.path.dirname(b).split(os.sep)
    common = 0
    for x, y in zip(pa, pb):
        if x != y:
            break
        common += 1
    return len(pa) + len(pb) - 2 * common


def _ancestor(folder: str, real: str) -> bool:
    """Whether `folder` is the folder of the file `real` or one above it."""
    d = os.path.dirname(real)
    return d == folder or d.startswith(folder.rstrip(os.sep) + os.sep)


def _folders_above(path: str) -> list[str]:
    """The folders above the file's own, up to the current folder (shown relative to it); none when the
    file is not under the current folder."""
    here = os.path.realpath(os.getcwd())
    folder = os.path.dirname(os.path.realpath(path))
    if folder != here and not folder.startswith(here.rstrip(os.sep) + os.sep):
        return []
    out = []
    while folder != here:
        folder = os.path.dirname(folder)
        out.append(os.path.relpath(folder, here))
    return out


def survey(paths: list[str], skip: Callable[[str, bool], bool] = lambda p, is_dir: False) -> Project:
    """Every file found, read, with who includes it, whose library it is and which projects list it."""
    project = Project({})
    for p in walk(paths, skip):
        project.files[os.path.realpath(p)] = read(p)
    # A file given by name (pre-commit passes the changed files) is loaded as in its folder: the
    # models files, tree libraries and Groot2 projects beside it count, without being checked.
    for top in paths:
        if os.path.isfile(top):
            for p in walk([os.path.dirname(top) or "."], skip, recurse=False):
                if os.path.realpath(p) not in project.files:
                    f = read(p)
                    f.context = True
                    project.files[os.path.realpath(p)] = f
        # the models files of the folders above a file or folder given, up to the current folder
        # (where `btgen models .` writes one for the whole repository)
        if os.path.exists(top):
            for folder in _folders_above(top if os.path.isfile(top) else os.path.join(top, "x")):
                for p in walk([folder], skip, recurse=False):
                    if os.path.realpath(p) not in project.files:
                        f = read(p)
                        if f.role == "models":
                            f.context = True
                            project.files[os.path.realpath(p)] = f
    for _real, f in sorted(project.files.items()):
        for target in f.includes:
            t = project.files.get(target)
            if t is None:
                continue
            if f.role == "project":
                t.projects.append(f.path)
            else:
                t.included_by.append(f.path)
    for _real, f in sorted(project.files.items()):
        if f.role != "trees":
            continue
        own = _closure_trees(project, f)
        marked = set()
        for other in _candidates(project, f):
            if other is not f and (f.subtrees - own) & set(other.trees):
                other.library_of.append(f.path)
                marked.add(other.real)
        for other in _libraries(project, f, _closure(project, f)):
            if other.real not in marked:
                other.library_of.append(f.path)
    return project


def _closure(project: Project, f: BTFile) -> list[BTFile]:
    """The file and the files it includes, transitively (those found)."""
    seen: dict[str, BTFile] = {}
    stack = [f]
    while stack:
        g = stack.pop()
        if g.real in seen:
            continue
        seen[g.real] = g
        stack.extend(project.files[t] for t in g.includes if t in project.files)
    return list(seen.values())


def _closure_trees(project: Project, f: BTFile) -> set[str]:
    return {t for g in _closure(project, f) for t in g.trees}


def _candidates(project: Project, f: BTFile) -> list[BTFile]:
    """The files whose trees and models `f` may use: its folder, and the files of the projects listing it."""
    out = {g.real: g for g in project.by_folder(f.real)}
    for p in f.projects:
        proj = project.files[os.path.realpath(p)]
        for t in proj.includes:
            if t in project.files:
                out.setdefault(t, project.files[t])
    return [out[k] for k in sorted(out)]


def _libraries(project: Project, f: BTFile, closure: list[BTFile]) -> list[BTFile]:
    """The files of trees that define the SubTrees `f` (and its includes) uses and does not define:
    first those of its folder (and of the Groot2 projects listing it), then, for a tree none of those
    defines, the nearest file found anywhere under the checked paths that defines it (fewest folders
    apart, then by path: a repository whose program registers the trees of several folders, like
    MoveIt Pro's objectives). Libraries may use libraries."""
    own = {t for g in closure for t in g.trees}
    cands = _candidates(project, f)
    libs: list[BTFile] = []
    chosen: set[str] = set()
    need = {s for g in closure for s in g.subtrees} - own
    known = set(own)

    def take(g: BTFile) -> bool:
        nonlocal need, known
        if g.role != "trees" or g is f or g.real in chosen or not need & set(g.trees):
            return False
        lib_trees = _closure_trees(project, g)
        if lib_trees & known:
            return False  # it redefines a tree already loaded ("defined twice"): not a library of f
        libs.append(g)
        chosen.add(g.real)
        known |= lib_trees
        need = (need | {s for h in _closure(project, g) for s in h.subtrees}) - known
        return True

    changed = True
    while need and changed:
        changed = False
        for g in cands:
            changed = take(g) or changed
        if not changed:
            for tree in sorted(need):
                for g in sorted(project.definers.get(tree, ()), key=lambda g: (distance(f.real, g.real), g.path)):
                    if take(g):
                        changed = True
                        break
                if changed:
                    break
    return sorted(libs, key=lambda g: g.path)


def _models_for(project: Project, f: BTFile, closure: list[BTFile], libs: list[BTFile]) -> list[str]:
    """The models files that count for `f`: those of its folder and of the folders above it (the one
    `btgen models .` writes at the top of a repository), those beside its tree libraries, then any other
    models file found under the checked paths that declares a node the files use and those do not
    (Nav2's `nav2_behavior_tree/nav2_tree_nodes.xml` for the trees of `nav2_bt_navigator/`)."""
    near = [g for g in _candidates(project, f) if g.role == "models"]
    near += [
        m
        for m in project.models_files
        if m not in near and any(_ancestor(os.path.dirname(m.real), g.real) for g in [f, *libs])
    ]
    declared = {i for m in near for i in m.models} | {i for g in [*closure, *libs] for i in g.models}
    uses = {u for g in [*closure, *libs] for h in _closure(project, g) for u in h.uses} - declared
    far = [m for m in project.models_files if m not in near and m.models & uses]
    return sorted(m.path for m in near) + sorted(m.path for m in far)


def plan(
    project: Project,
    models: tuple[str, ...] = (),
    trees: tuple[str, ...] = (),
    main_for: Callable[[str], Optional[str]] = lambda path: None,
) -> list[Unit]:
    """The loads that check the project: one per mission, one per tree of a file that picks none."""
    units: list[Unit] = []
    # a file given by name that only others include is checked through them (their own findings are
    # left out by the runner: they were not given)
    through: set[str] = set()
    stack = [f for f in project.files.values() if not f.context and f.included_by and f.main is None]
    while stack:
        g = stack.pop()
        for p in g.included_by:
            includer = project.files[os.path.realpath(p)]
            if includer.context and includer.real not in through:
                through.add(includer.real)
                if includer.included_by and includer.main is None:
                    stack.append(includer)
    for _real, f in sorted(project.files.items()):
        if f.context and f.real not in through:
            continue
        if f.role == "broken":
            units.append(Unit(f.path, None, (), (), False))
            continue
        if f.role != "trees":
            continue
        if f.included_by and f.main is None:
            continue  # loaded with the files that include it
        closure = _closure(project, f)
        lib_files = _libraries(project, f, closure)
        libs = [g.path for g in lib_files]
        model_files = _models_for(project, f, closure, lib_files)
        model_files += sorted(f.projects)
        opts_models = tuple(models) + tuple(m for m in model_files if m not in models)
        opts_trees = tuple(trees) + tuple(sorted(libs))
        library = bool(f.library_of) and f.main is None
        chosen = main_for(f.path)
        own_trees = sorted({t for g in closure for t in g.trees})
        if chosen is not None or f.main is not None or len(own_trees) <= 1:
            units.append(Unit(f.path, chosen, opts_models, opts_trees, library, tuple(f.projects)))
        else:
            units.extend(Unit(f.path, t, opts_models, opts_trees, library, tuple(f.projects)) for t in own_trees)
    return units
