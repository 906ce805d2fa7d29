"""The files btgen reads as JSON and the files it writes: one reader, one guard.

`read_json` is the one reader of a JSON file a user gives (substitution rules): bounded in
bytes and in nesting depth before Python's reader sees it, so whatever the file holds the
answer is `path:line:col: error: ...` (never a RecursionError or a ValueError of a
4,300-digit number). `NaN` and `Infinity`, which Python accepts and JSON does not, are
refused.

`write_output` is the one writer of a file a command was asked to write (`-o`): it refuses
to write over any of the command's inputs (by identity of the file, so `./m.xml`, a
symbolic link or a hard link to it are the same) or onto a folder, and writes through a
temporary file in the same folder renamed over the target, so the file is whole or absent,
never partial. `Manifest` lists what one command wrote into an output folder, so a later
run removes exactly the files an earlier run wrote and no longer writes (never by name
pattern, never a file it did not write, never a folder).
"""

from __future__ import annotations

import contextlib
import json
import os
import re
import stat
import tempfile
from collections.abc import Iterable, Sequence
from typing import Any, Optional

from btgen.diagnostics import Loc, UserError, read_bounded

MAX_JSON_DEPTH = 64
_JSON_TOKEN = re.compile(r'"(?:[^"\\]|\\.)*"?|[\[\]{}]', re.DOTALL)


def _line_col(text: str, at: int) -> tuple[int, int]:
    line = text.count("\n", 0, at) + 1
    return line, at - (text.rfind("\n", 0, at) + 1) + 1


def json_depth_error(text: str, limit: int = MAX_JSON_DEPTH) -> Optional[tuple[int, int]]:
    """Where the nesting of arrays and objects first goes deeper than `limit`, or None."""
    depth = 0
    for m in _JSON_TOKEN.finditer(text):
        c = m.group(0)[0]
        if c in "[{":
            depth += 1
            if depth > limit:
                return _line_col(text, m.start())
        elif c in "]}":
            depth -= 1
    return None


class _Constant(ValueError):
    pass


def _no_constant(name: str) -> Any:
    raise _Constant(name)


def read_json(path: str, limit: int, kind: str, object_pairs_hook=None) -> tuple[Any, str]:
    """The JSON document of the file at `path` and its text; UserError at `path:line:col` for
    every way the file can be bad (too large, not UTF-8, not JSON, too deep, NaN)."""
    data = read_bounded(path, limit, kind, cannot=f"cannot read the {kind} file")
    if data.startswith(b"\xef\xbb\xbf"):
        data = data[3:]
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as e:
        good = data[: e.start].decode("utf-8")
        line, col = _line_col(good, len(good))
        raise UserError.at(Loc(path, line, col), f"invalid UTF-8 (byte 0x{data[e.start]:02x})") from None
    deep = json_depth_error(text)
    if deep is not None:
        raise UserError.at(
            Loc(path, *deep), f"arrays and objects nested deeper than {MAX_JSON_DEPTH} levels: a {kind} file is flat"
        )
    try:
        doc = json.loads(text, object_pairs_hook=object_pairs_hook, parse_constant=_no_constant)
    except json.JSONDecodeError as e:
        raise UserError.at(Loc(path, e.lineno, e.colno), f"invalid JSON: {e.msg}") from None
    except _Constant as e:
        m = re.search(r"-?\b" + re.escape(str(e)), text)
        line, col = _line_col(text, m.start()) if m else (1, 1)
        raise UserError.at(Loc(path, line, col), f"invalid JSON: `{e}` is not a JSON number") from None
    except (ValueError, RecursionError, MemoryError) as e:  # a number of thousands of digits, ...
        m = re.search(r"[0-9]{4000,}", text)
        line, col = _line_col(text, m.start()) if m else (1, 1)
        raise UserError.at(Loc(path, line, col), f"invalid JSON: {e}") from None
    return doc, text


# ====================================================================== writing
def xml_files_of(folder: str) -> list[str]:
    """The `*.xml` files of a folder (not below it), in name order: what `--trees DIR` registers,
    as registerBehaviorTreeFromFile is called on each."""
    return sorted(
        os.path.join(folder, f)
        for f in os.listdir(folder)
        if f.endswith(".xml") and os.path.isfile(os.path.join(folder, f))
    )


def _identity(path: str) -> Optional[tuple[int, int]]:
    try:
        st = os.stat(path)
    except (OSError, ValueError):
        return None
    return (st.st_dev, st.st_ino)


def check_output(
    output: str, inputs: Iterable[str], option: str = "-o", message: Optional[str] = None, folders: bool = True
) -> None:
    """UserError (at the input: `message`, or the standard words) when writing `output` would
    replace one of `inputs`, and at the output when it is a folder (unless `folders` is
    False: the caller reports that itself)."""
    target = _identity(output)
    if target is not None:
        if folders and stat.S_ISDIR(os.stat(output).st_mode):
            raise UserError.at(Loc(output, 1, 1), f"{option} {output}: is a folder, not a file")
        for f in inputs:
            if f and _identity(f) == target:
                raise UserError.at(
                    Loc(f, 1, 1),
                    message or f"`{option} {output}` would overwrite this input file: choose another output file",
                )


def write_output(
    path: str, data: bytes, inputs: Iterable[str] = (), option: str = "-o", message: Optional[str] = None
) -> None:
    """Write `path` whole or not at all, never over one of `inputs` (UserError)."""
    check_output(path, inputs, option, message)
    folder = os.path.dirname(os.path.abspath(path))
    try:
        fd, tmp = tempfile.mkstemp(dir=folder, prefix=".btgen-", suffix=".tmp")
    except OSError as e:
        raise UserError.at(Loc(path, 1, 1), f"cannot write: {e.strerror or e}") from None
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)  # what a new file gets (mkstemp's are 0600)
        os.replace(tmp, path)
    except OSError as e:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise UserError.at(Loc(path, 1, 1), f"cannot write: {e.strerror or e}") from None


class Manifest:
    """What a command wrote into an output folder for one mission, in a file beside them
    (`.<stem>.btgen-<command>`, JSON): the next run of the command for that
    mission removes what the last one wrote and this one did not, and nothing else."""

    def __init__(self, folder: str, stem: str, command: str) -> None:
        self.folder = folder
        self.path = os.path.join(folder, f".{stem}.btgen-{command}")
        self.command = command

    def previous(self) -> list[str]:
        """The file names the earlier run wrote (none when the manifest is absent or not one)."""
        try:
            doc = json.loads(read_bounded(self.path, 1 << 20, "manifest").decode("utf-8"))
        except (UserError, ValueError, RecursionError):
            return []
        if not isinstance(doc, dict) or doc.get("written by") != f"btgen {self.command}":
            return []
        files = doc.get("files")
        if not isinstance(files, list):
            return []
        return [n for n in files if isinstance(n, str) and n and n == os.path.basename(n) and n not in (".", "..")]

    def check(self, inputs: Iterable[str] = ()) -> None:
        """UserError when the manifest itself cannot be written (call before writing the files)."""
        check_output(self.path, inputs)

    def replace(self, written: Sequence[str], inputs: Iterable[str] = ()) -> list[str]:
        """Record `written` (paths in the folder) as this run's files; remove the files of
        the earlier run that this one did not write again (regular files only, never one of
        `inputs`, whatever the manifest says). Returns the removed paths."""
        names = [os.path.basename(p) for p in written]
        keep = {i for i in (_identity(f) for f in inputs) if i is not None}
        removed = []
        for old in self.previous():
            if old in names:
                continue
            full = os.path.join(self.folder, old)
            with contextlib.suppress(OSError):
                if stat.S_ISREG(os.lstat(full).st_mode) and _identity(full) not in keep:
                    os.unlink(full)
                    removed.append(full)
        doc = {"written by": f"btgen {self.command}", "files": names}
        write_output(self.path, (json.dumps(doc, indent=1) + "\n").encode("utf-8"), inputs)
        return removed
