"""`btgen check`'s settings: `[tool.btgen]` of a `pyproject.toml`, or a `btgen.toml`.

The file is found as ruff finds its own: from the checked path (its folder for a file) upwards, the
first folder that holds a `btgen.toml`, or a `pyproject.toml` with a `[tool.btgen]` table (a
`pyproject.toml` without one is passed over); `--config FILE` names it instead. Paths and globs in it
are relative to its folder. An unknown key or a bad value is a `path:line:col: error:` at the key or
value in the file (code C001), like any bad input.
"""

from __future__ import annotations

import os
import re
import sys
from dataclasses import dataclass, field, replace
from typing import Any, Optional

from btgen.diagnostics import Diagnostic, Loc, UserError, read_bounded, suggestion
from btgen.lang.versions import SUPPORTED_VERSIONS
from btgen.tools.check.codes import valid_selector

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - the dependency of Python 3.9 and 3.10 (setup.py)
    import tomli as tomllib

CONFIG_NAMES = ("btgen.toml", "pyproject.toml")
MAX_CONFIG_BYTES = 1024 * 1024


@dataclass(frozen=True)
class Settings:
    """What applies to the files checked (defaults when no configuration is found)."""

    config: Optional[str] = None  # the file read, as shown
    root: str = "."  # its folder: paths and globs are relative to it
    models: tuple[str, ...] = ()
    trees: tuple[str, ...] = ()
    btcpp: str = "4.6.2"
    enum: tuple[str, ...] = ()
    enums: tuple[str, ...] = ()
    entry: tuple[str, ...] = ()
    type: tuple[str, ...] = ()
    main_tree: dict[str, str] = field(default_factory=dict)  # glob -> tree ID
    include: tuple[str, ...] = ()
    exclude: tuple[str, ...] = ()
    select: tuple[str, ...] = ()
    ignore: tuple[str, ...] = ()
    per_file_ignores: dict[str, tuple[str, ...]] = field(default_factory=dict)
    ros_packages: dict[str, str] = field(default_factory=dict)  # package -> folder
    string_capacity: Optional[int] = None
    queue_capacity: Optional[int] = None
    upgrade_to: Optional[str] = None
    analysis: bool = True

    def path(self, rel: str) -> str:
        """A path of the configuration as the user would write it from the current folder."""
        return os.path.normpath(os.path.join(self.root, rel)) if self.root != "." else os.path.normpath(rel)

    def rel(self, path: str) -> str:
        """A checked file's path relative to the configuration's folder, with `/` (for globs)."""
        return os.path.relpath(path, self.root).replace(os.sep, "/")


def _strs(v: Any) -> bool:
    return isinstance(v, list) and all(isinstance(x, str) for x in v)


# key: (check of the value, what it must be, Settings field)
_KEYS: dict[str, tuple[Any, str]] = {
    "models": (_strs, "a list of paths of models files"),
    "trees": (_strs, "a list of paths of tree library files or folders"),
    "btcpp": (lambda v: v in SUPPORTED_VERSIONS, "one of " + ", ".join(f'"{v}"' for v in SUPPORTED_VERSIONS)),
    "enum": (_strs, 'a list of enum declarations such as "Color=RED,GREEN"'),
    "enums": (_strs, "a list of paths of enum files"),
    "entry": (_strs, 'a list of entries such as "timeout=int" or "Tree:timeout=int"'),
    "type": (_strs, 'a list of port types such as "Pose2D=nav::Pose2D@nav/pose2d.hpp"'),
    "main-tree": (
        lambda v: isinstance(v, dict) and all(isinstance(x, str) for x in v.values()),
        'a table of glob = "TreeID"',
    ),
    "include": (_strs, "a list of globs"),
    "exclude": (_strs, "a list of globs"),
    "select": (_strs, "a list of codes or prefixes of codes"),
    "ignore": (_strs, "a list of codes or prefixes of codes"),
    "per-file-ignores": (
        lambda v: isinstance(v, dict) and all(_strs(x) for x in v.values()),
        "a table of glob = [codes]",
    ),
    "ros-packages": (
        lambda v: isinstance(v, dict) and all(isinstance(x, str) for x in v.values()),
        'a table of package = "folder"',
    ),
    "string-capacity": (
        lambda v: isinstance(v, int) and not isinstance(v, bool) and 1 <= v <= 1 << 20,
        "a whole number from 1 to 1048576",
    ),
    "queue-capacity": (
        lambda v: isinstance(v, int) and not isinstance(v, bool) and 1 <= v <= 1 << 20,
        "a whole number from 1 to 1048576",
    ),
    "upgrade-to": (lambda v: v in SUPPORTED_VERSIONS, "one of " + ", ".join(f'"{v}"' for v in SUPPORTED_VERSIONS)),
    "analysis": (lambda v: isinstance(v, bool), "true or false"),
}


def _locate(text: str, table: str, key: str, want_value: bool) -> tuple[int, int]:
    """Line and column of `key` (or of its value) in table `[table]` of a TOML text (1, 1 if not found).
    tomllib gives no positions; keys are found by a scan of the lines, which covers how a
    configuration is written (one `key = value` a line under its table header)."""
    current = ""
    header = re.compile(r"^\s*\[\s*([^\]]+?)\s*\]\s*(#.*)?$")
    for n, line in enumerate(text.splitlines(), 1):
        h = header.match(line)
        if h and not line.lstrip().startswith("[["):
            current = h.group(1).replace('"', "").replace(" ", "")
            continue
        if current != table:
            continue
        m = re.match(r'^(\s*)("?)([A-Za-z0-9_.*/\-\[\]{}?]+)\2\s*=\s*', line)
        if m and m.group(3) == key:
            return (n, (m.end() if want_value else len(m.group(1))) + 1)
    return (1, 1)


def find_config(start: str) -> Optional[str]:
    """The configuration file that applies to `start` (a file or folder), found upwards."""
    folder = os.path.abspath(start if os.path.isdir(start) else os.path.dirname(start) or ".")
    while True:
        for name in CONFIG_NAMES:
            candidate = os.path.join(folder, name)
            if os.path.isfile(candidate):
                if name == "btgen.toml":
                    return candidate
                try:
                    with open(candidate, "rb") as f:
                        data = f.read(MAX_CONFIG_BYTES)
                except OSError:
                    continue
                if re.search(rb"^\s*\[\s*tool\s*\.\s*btgen\s*[\].]", data, re.M):
                    return candidate
        parent = os.path.dirname(folder)
        if parent == folder:
            return None
        folder = parent


def load_settings(path: Optional[str]) -> Settings:
    """The settings of configuration file `path` (None: the defaults); UserError at the key or value."""
    if path is None:
        return Settings()
    shown = os.path.relpath(path) if os.path.isabs(path) else path
    data = read_bounded(path, MAX_CONFIG_BYTES, "configuration", shown=shown)
    try:
        text = data.decode("utf-8")
        doc = tomllib.loads(text)
    except UnicodeDecodeError:
        raise UserError.at(Loc(shown, 1, 1), "the configuration is not UTF-8 text") from None
    except tomllib.TOMLDecodeError as e:
        line, col = getattr(e, "lineno", 1) or 1, getattr(e, "colno", 1) or 1
        m = re.search(r"\(at line (\d+), column (\d+)\)", str(e))
        if m:
            line, col = int(m.group(1)), int(m.group(2))
        msg = re.sub(r"\s*\(at line \d+, column \d+\)", "", str(e)) or "invalid TOML"
        raise UserError.at(Loc(shown, line, col), f"invalid TOML: {msg}") from None
    is_pyproject = os.path.basename(path) == "pyproject.toml"
    table_name = "tool.btgen" if is_pyproject else ""
    table = doc.get("tool", {}).get("btgen", {}) if is_pyproject else doc
    if not isinstance(table, dict):
        raise UserError.at(Loc(shown, 1, 1), "[tool.btgen] must be a table")
    errors: list[Diagnostic] = []
    values: dict[str, Any] = {}
    for key, value in table.items():
        if key not in _KEYS:
            line, col = _locate(text, table_name, key, False)
            errors.append(
                Diagnostic(
                    Loc(shown, line, col), f"unknown key `{key}` in the btgen configuration{suggestion(key, _KEYS)}"
                )
            )
            continue
        check, what = _KEYS[key]
        if not check(value):
            line, col = _locate(text, table_name, key, True)
            errors.append(Diagnostic(Loc(shown, line, col), f"`{key}` must be {what}"))
            continue
        if key in ("select", "ignore"):
            bad = [p for p in (valid_selector(s) for s in value) if p]
            if bad:
                line, col = _locate(text, table_name, key, True)
                errors.append(Diagnostic(Loc(shown, line, col), f"`{key}`: {bad[0]}"))
                continue
        if key == "per-file-ignores":
            for glob, codes in value.items():
                bad = [p for p in (valid_selector(s) for s in codes) if p]
                if bad:
                    line, col = _locate(text, f"{table_name}.per-file-ignores".lstrip("."), glob, True)
                    errors.append(Diagnostic(Loc(shown, line, col), f"`per-file-ignores`: {bad[0]}"))
        values[key] = value
    if errors:
        raise UserError(errors)
    root = os.path.dirname(shown) or "."
    s = Settings(config=shown, root=root)
    rel = s.path
    return replace(
        s,
        models=tuple(rel(p) for p in values.get("models", ())),
        trees=tuple(rel(p) for p in values.get("trees", ())),
        btcpp=values.get("btcpp", "4.6.2"),
        enum=tuple(values.get("enum", ())),
        enums=tuple(rel(p) for p in values.get("enums", ())),
        entry=tuple(values.get("entry", ())),
        type=tuple(values.get("type", ())),
        main_tree=dict(values.get("main-tree", {})),
        include=tuple(values.get("include", ())),
        exclude=tuple(values.get("exclude", ())),
        select=tuple(values.get("select", ())),
        ignore=tuple(values.get("ignore", ())),
        per_file_ignores={k: tuple(v) for k, v in values.get("per-file-ignores", {}).items()},
        ros_packages={k: rel(v) for k, v in values.get("ros-packages", {}).items()},
        string_capacity=values.get("string-capacity"),
        queue_capacity=values.get("queue-capacity"),
        upgrade_to=values.get("upgrade-to"),
        analysis=values.get("analysis", True),
    )


def settings_text(s: Settings, path: str, kind: str, unit_lines: list[str]) -> str:
    """`--show-settings FILE`: what applies to one file, one `key = value` a line."""
    out = [
        f"file = {path!r}",
        f"kind = {kind!r}",
        f"config = {s.config!r}",
        f"btcpp = {s.btcpp!r}",
        f"select = {list(s.select) or ['ALL']!r}",
        f"ignore = {list(s.ignore) + [c for g, cs in s.per_file_ignores.items() if _glob(s, path, g) for c in cs]!r}",
        f"enum = {list(s.enum)!r}",
        f"enums = {list(s.enums)!r}",
        f"entry = {list(s.entry)!r}",
        f"type = {list(s.type)!r}",
        f"string-capacity = {s.string_capacity!r}",
        f"queue-capacity = {s.queue_capacity!r}",
        f"upgrade-to = {s.upgrade_to!r}",
        f"analysis = {s.analysis!r}",
    ]
    return "\n".join(out + unit_lines) + "\n"


def _glob(s: Settings, path: str, glob: str) -> bool:
    from btgen.tools.check.discovery import matches

    return matches(s.rel(path), (glob,))
