"""Diagnostics shared by every stage of btgen.

Every user-facing problem is a :class:`Diagnostic` printed as
``path:line:col: severity: message`` with the path as the user gave it.
User mistakes raise :class:`UserError` (one or more diagnostics, exit 1);
bugs in btgen itself raise :class:`InternalError`, which the command line
reports as an internal error and asks to be reported.
"""

from __future__ import annotations

import difflib
import os
import stat
import sys
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Optional


@dataclass(frozen=True)
class Loc:
    """A position in a source file: 1-based line and column."""

    path: str
    line: int = 1
    col: int = 1

    def __str__(self) -> str:
        return f"{self.path}:{self.line}:{self.col}"

    def shifted(self, columns: int) -> Loc:
        return Loc(self.path, self.line, self.col + columns)


@dataclass(frozen=True)
class Diagnostic:
    loc: Loc
    message: str
    severity: str = "error"  # "error" | "warning" | "note"

    def __str__(self) -> str:
        return f"{self.loc}: {self.severity}: {one_line(self.message)}"


MAX_DIAGNOSTIC_BYTES = 4096


def one_line(text: str) -> str:
    """`text` with line breaks and other control characters escaped (`\\n`, `\\x07`), so a
    diagnostic that quotes the user's input stays one `path:line:col:` line. A text longer
    than MAX_DIAGNOSTIC_BYTES in UTF-8 keeps its first bytes up to a character boundary and
    ends in `... (cut: N bytes in all)` (runtime/include/btgen/one_line.hpp does the same)."""
    if len(text) > MAX_DIAGNOSTIC_BYTES // 4:
        data = text.encode("utf-8", "surrogatepass")
        if len(data) > MAX_DIAGNOSTIC_BYTES:
            cut = MAX_DIAGNOSTIC_BYTES
            while cut > 0 and (data[cut] & 0xC0) == 0x80:
                cut -= 1
            return one_line(data[:cut].decode("utf-8", "surrogatepass")) + f"... (cut: {len(data)} bytes in all)"
    if text.isprintable():
        return text
    out = []
    for ch in text:
        if ch == "\n":
            out.append("\\n")
        elif ch == "\r":
            out.append("\\r")
        elif ch in "\u2028\u2029":  # line and paragraph separators
            out.append(f"\\u{ord(ch):04x}")
        elif ch == "\t" or ch.isprintable() or ord(ch) > 0x9F:
            out.append(ch)
        else:
            out.append(f"\\x{ord(ch):02x}")
    return "".join(out)


class UserError(Exception):
    """One or more problems in the user's input. Never shown as a traceback."""

    def __init__(self, diagnostics: Sequence[Diagnostic] | Diagnostic):
        if isinstance(diagnostics, Diagnostic):
            diagnostics = [diagnostics]
        self.diagnostics = tuple(diagnostics)
        super().__init__("\n".join(str(d) for d in self.diagnostics))

    @classmethod
    def at(cls, loc: Loc, message: str) -> UserError:
        return cls(Diagnostic(loc, message))


def read_bounded(
    path: str,
    limit: int,
    kind: str,
    plural: Optional[str] = None,
    shown: Optional[str] = None,
    cannot: str = "cannot read file",
) -> bytes:
    """The bytes of the file at `path`, never more than `limit` of them: the one reader of
    every file btgen reads (missions, models, scenarios, enums, traces, logs, knowledge
    bases), so /dev/zero or a FIFO that never ends costs `limit` bytes, not the machine.

    `kind` names the file in messages ("mission", "scenario", "knowledge base"), `plural` the
    limited things (default "<kind> files"); UserError at `shown:1:1` (default `path`) when it
    is a directory, a socket, too large or unreadable (`cannot`: the words before the reason)."""
    top = Loc(shown or path, 1, 1)
    plural = plural or f"{kind} files"
    a = "an" if kind[:1] in "aeiou" else "a"
    try:
        st = os.stat(path)
        if stat.S_ISDIR(st.st_mode):
            raise UserError.at(top, f"is a directory, not {a} {kind} file")
        if stat.S_ISSOCK(st.st_mode):
            raise UserError.at(top, f"is a socket, not {a} {kind} file")
        if stat.S_ISREG(st.st_mode) and st.st_size > limit:
            raise UserError.at(top, f"file is {st.st_size} bytes; {plural} are limited to {limit} bytes")
        with open(path, "rb") as f:
            data = f.read(limit + 1)
    except IsADirectoryError:
        raise UserError.at(top, f"is a directory, not {a} {kind} file") from None
    except OSError as e:
        raise UserError.at(top, f"{cannot}: {e.strerror or e}") from None
    if len(data) > limit:  # a pipe or device (its size shows only while reading), or it grew
        raise UserError.at(top, f"file is larger than {limit} bytes; {plural} are limited to {limit} bytes")
    return data


class InternalError(Exception):
    """A bug in btgen: reported with a request to file an issue."""


class DiagnosticSink:
    """Collects all diagnostics of a file so they can be reported together."""

    def __init__(self) -> None:
        self.items: list[Diagnostic] = []

    def error(self, loc: Loc, message: str) -> None:
        self.items.append(Diagnostic(loc, message, "error"))

    def warning(self, loc: Loc, message: str) -> None:
        self.items.append(Diagnostic(loc, message, "warning"))

    @property
    def errors(self) -> list[Diagnostic]:
        return [d for d in self.items if d.severity == "error"]

    def raise_if_errors(self) -> None:
        if self.errors:
            raise UserError(self.items)


def did_you_mean(word: str, candidates: Iterable[str]) -> Optional[str]:
    """The closest candidate to ``word``, or None when nothing is close."""
    cands = sorted(set(candidates))
    lower = {c.lower(): c for c in cands}
    if word.lower() in lower and lower[word.lower()] != word:
        return lower[word.lower()]
    match = difflib.get_close_matches(word, cands, n=1, cutoff=0.6)
    if match:
        return match[0]
    # A prefix/suffix relation ("SayGoodBye" vs "SayGoodByeSpeech").
    pref = [c for c in cands if c.startswith(word) or word.startswith(c)]
    if len(pref) == 1:
        return pref[0]

    # A long shared beginning ("IV. VisitLandmark" vs "IV. VisitExhibit").
    def shared(c: str) -> int:
        n = 0
        while n < min(len(c), len(word)) and c[n] == word[n]:
            n += 1
        return n

    best = max(cands, key=shared, default=None)
    if best is not None and shared(best) >= max(4, len(word) // 2):
        if sum(1 for c in cands if shared(c) == shared(best)) == 1:
            return best
    return None


def suggestion(word: str, candidates: Iterable[str]) -> str:
    """`` (did you mean `X`?)`` or the empty string."""
    m = did_you_mean(word, candidates)
    return f" (did you mean `{m}`?)" if m else ""


_printed_warnings: set[str] = set()  # the warnings this run has printed (new_run() forgets them)


def new_run() -> None:
    """A command starts: no warning has been printed yet (an entry point calls it first)."""
    _printed_warnings.clear()


def print_diagnostics(diags: Sequence[Diagnostic]) -> None:
    """Write each diagnostic on its own line of stderr (the `path:line:col: error: ...` form).
    A warning is printed once a run: a models file shared by two missions, or a file both
    loaded and analysed, warns once."""
    for diag in diags:
        text = str(diag)
        if diag.severity == "warning":
            if text in _printed_warnings:
                continue
            _printed_warnings.add(text)
        print(text, file=sys.stderr)
