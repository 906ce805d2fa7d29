"""Secure reading of mission XML with exact source positions.

lxml parses with every dangerous feature off: no DTD loading, no entity
expansion, no network, no huge-tree mode. Any document type declaration is
rejected before lxml sees the file, so billion-laughs and external-entity
files fail at once with bounded memory.

lxml only records the line where a start tag *ends*, so a small scanner
of our own records where every start tag and every attribute begins (line
and column, 1-based, in characters). Elements come out of lxml in document
order, which is the order of the start tags, so the i-th element gets the
i-th start tag's positions.
"""

from __future__ import annotations

import collections
import contextlib
import hashlib
import re
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Optional

from lxml import etree

from btgen.diagnostics import Diagnostic, Loc, UserError, read_bounded

MAX_FILE_BYTES = 16 * 1024 * 1024  # a 10,000-node mission is about 1 MB
MAX_DEPTH = 256  # BehaviorTree.CPP refuses deeper trees too


@dataclass
class AttrPos:
    name: str
    loc: Loc
    value_offset: int  # offset of the first character of the raw value in the text
    raw_value: str


@dataclass
class StartTag:
    name: str
    loc: Loc
    attrs: dict[str, AttrPos]


class _LineIndex:
    def __init__(self, text: str) -> None:
        # XML ends lines with LF, CR LF or a lone CR (all read as LF).
        self.starts = [0] + [m.end() for m in re.finditer("\r\n|\r|\n", text)]

    def pos(self, offset: int) -> tuple[int, int]:
        import bisect

        i = bisect.bisect_right(self.starts, offset) - 1
        return i + 1, offset - self.starts[i] + 1


_NAME = r"[A-Za-z_:][-A-Za-z0-9_:.]*"
_TAG_RE = re.compile(r"<(" + _NAME + ")")
_ATTR_RE = re.compile(r"\s*(" + _NAME + r")\s*=\s*(\"([^\"]*)\"|'([^']*)')")
_ENTITY_RE = re.compile(r"&(#x[0-9A-Fa-f]+|#[0-9]+|[A-Za-z]+);")


class Source:
    """A decoded, well-formed XML file with positions for every element."""

    def __init__(self, path: str, text: str, root: etree._Element, tags: list[StartTag]) -> None:
        self.path = path
        self.text = text
        # what tinyxml2 reads and XML does not, read as tinyxml2 does (`tolerated`): one warning each
        self.warnings: list[Diagnostic] = []
        self.root = root
        self._lines = _LineIndex(text)
        self._tags: dict[etree._Element, StartTag] = {}
        elems = [e for e in root.iter() if isinstance(e.tag, str)]
        if len(elems) == len(tags):
            self._tags = dict(zip(elems, tags))
        else:  # should not happen for well-formed input; degrade to lxml's lines
            for e in elems:
                self._tags[e] = StartTag(e.tag, Loc(path, e.sourceline or 1, 1), {})

    def loc(self, elem: etree._Element) -> Loc:
        return self._tags[elem].loc

    def attr_loc(self, elem: etree._Element, name: str) -> Loc:
        a = self._tags[elem].attrs.get(name)
        return a.loc if a else self.loc(elem)

    def value_loc(self, elem: etree._Element, name: str, offset: int = 0) -> Loc:
        """Position of character `offset` of the decoded value of attribute `name`."""
        a = self._tags[elem].attrs.get(name)
        if a is None:
            return self.loc(elem)
        raw = a.raw_value
        # Walk the raw text: an entity reference is one decoded character.
        i = decoded = 0
        while i < len(raw) and decoded < offset:
            m = _ENTITY_RE.match(raw, i) if raw[i] == "&" else None
            # (CR LF is one line end, so one character of the value)
            i = m.end() if m else i + 2 if raw.startswith("\r\n", i) else i + 1
            decoded += 1
        line, col = self._lines.pos(a.value_offset + i)
        return Loc(self.path, line, col)

    def text_loc(self, elem: etree._Element) -> Loc:
        """Where the first character data directly inside `elem` (not in a child) that is not
        white space starts: its first character, or its `<![CDATA[`; the element when none."""
        start = self.loc(elem)
        if start.line > len(self._lines.starts):
            return start
        text = self.text
        i = self._lines.starts[start.line - 1] + start.col - 1
        tag = re.compile(r"<(/?)(" + _NAME + r")(?:\s+(?:" + _NAME + r")\s*=\s*(?:\"[^\"]*\"|'[^']*'))*\s*(/?)>")
        m = tag.match(text, i)
        if m is None or m.group(3):
            return start
        i, depth = m.end(), 0
        while i < len(text):
            c = text[i]
            if c == "<":
                for opener, closer in (("<!--", "-->"), ("<?", "?>")):
                    if text.startswith(opener, i):
                        end = text.find(closer, i)
                        i = len(text) if end < 0 else end + len(closer)
                        break
                else:
                    if text.startswith("<![CDATA[", i):
                        end = text.find("]]>", i)
                        if depth == 0 and text[i + 9 : end if end >= 0 else len(text)].strip():
                            return Loc(self.path, *self._lines.pos(i))
                        i = len(text) if end < 0 else end + 3
                        continue
                    m = tag.match(text, i)
                    if m is None:
                        return start
                    if m.group(1):
                        if depth == 0:
                            return start
                        depth -= 1
                    elif not m.group(3):
                        depth += 1
                    i = m.end()
                continue
            if depth == 0 and not c.isspace():
                return Loc(self.path, *self._lines.pos(i))
            i += 1
        return start

    def attr_names_in_order(self, elem: etree._Element) -> list[str]:
        return list(self._tags[elem].attrs)

    def tag(self, elem: etree._Element) -> str:
        """The element's name as written: `arm:Grasp` where lxml was given `arm\u00b7Grasp`
        (undeclared_prefixes)."""
        return self._tags[elem].name if isinstance(elem.tag, str) and PREFIX_MARK in elem.tag else elem.tag


def _scan(path: str, text: str, lines: _LineIndex) -> list[StartTag]:
    """Start tags and attribute positions, in document order; checks nesting depth."""
    tags: list[StartTag] = []
    depth = 0
    i, n = 0, len(text)
    while True:
        j = text.find("<", i)
        if j < 0 or j + 1 >= n:
            break
        c = text[j + 1]
        if text.startswith("<!--", j):
            k = text.find("-->", j + 4)
            i = n if k < 0 else k + 3
            continue
        if text.startswith("<![CDATA[", j):
            k = text.find("]]>", j + 9)
            i = n if k < 0 else k + 3
            continue
        if c == "?":
            k = text.find("?>", j + 2)
            i = n if k < 0 else k + 2
            continue
        if c == "!":
            line, col = lines.pos(j)
            raise UserError.at(
                Loc(path, line, col),
                "document type declarations are not allowed in a mission "
                "(entities could expand without bound or read other files)",
            )
        if c == "/":
            depth -= 1
            k = text.find(">", j)
            i = n if k < 0 else k + 1
            continue
        m = _TAG_RE.match(text, j)
        if not m:
            i = j + 1
            continue
        line, col = lines.pos(j)
        tag = StartTag(m.group(1), Loc(path, line, col), {})
        k = m.end()
        while True:
            am = _ATTR_RE.match(text, k)
            if not am:
                break
            aline, acol = lines.pos(am.start(1))
            vstart = am.start(3) if am.group(3) is not None else am.start(4)
            raw = am.group(3) if am.group(3) is not None else am.group(4)
            tag.attrs.setdefault(am.group(1), AttrPos(am.group(1), Loc(path, aline, acol), vstart, raw))
            k = am.end()
        rest = re.compile(r"\s*(/?)>").match(text, k)
        self_closing = bool(rest and rest.group(1))
        tags.append(tag)
        if depth + 1 > MAX_DEPTH:  # a self-closing element is a level too (libxml2 counts it)
            raise UserError.at(
                tag.loc, f"elements nested deeper than {MAX_DEPTH} levels (BehaviorTree.CPP refuses such trees too)"
            )
        if not self_closing:
            depth += 1
        i = rest.end() if rest else k
    return tags


_LIBXML_MSG = [
    (
        re.compile(r"Opening and ending tag mismatch: (\S+) line (\d+) and (\S+)"),
        lambda m: (
            f"closing tag </{m.group(3)}> does not match <{m.group(1)}> opened on line {m.group(2)} "
            f"(is a closing tag missing?)"
        ),
    ),
    (
        re.compile(r"Specification mandates value for attribute (\S+)"),
        lambda m: f"attribute `{m.group(1)}` has no value (attribute names cannot contain spaces)",
    ),
    (re.compile(r"Attribute (\S+) redefined"), lambda m: f"attribute `{m.group(1)}` appears twice"),
    (
        re.compile(r"Premature end of data in tag (\S+) line (\d+)"),
        lambda m: f"file ends before <{m.group(1)}> opened on line {m.group(2)} is closed",
    ),
    # tinyxml2 (BehaviorTree.CPP's parser) reads these two, but they are not XML
    (
        re.compile(r"Unescaped '<' not allowed in attributes? values"),
        lambda m: "a raw `<` in an attribute value is not XML: write `&lt;` (tinyxml2 reads it, other tools do not)",
    ),
    (
        re.compile(r"xmlParseEntityRef: no name|EntityRef: expecting ';'"),
        lambda m: "a raw `&` is not XML: write `&amp;` (`&&` is `&amp;&amp;`; tinyxml2 reads it, other tools do not)",
    ),
    (re.compile(r"Document is empty"), lambda m: 'file is empty: expected <root BTCPP_format="4">'),
    (re.compile(r"Extra content at the end of the document"), lambda m: "content after the end of the root element"),
]


def _syntax_error(path: str, text: str, err: etree.XMLSyntaxError) -> UserError:
    line, col = err.position if err.position else (1, 1)
    msg = (err.msg or "malformed XML").split(", line ")[0].rstrip("\n")
    # A malformed closing tag such as `</ Sequence>`: point at it and say what is wrong.
    lines = re.split("\r\n|\r|\n", text)
    if 1 <= line <= len(lines):
        bad = re.search(r"</\s+(" + _NAME + r")\s*>", lines[line - 1])
        if bad:
            return UserError.at(
                Loc(path, line, bad.start() + 1),
                f"malformed closing tag `{bad.group(0)}`: no space is allowed after `</` (write `</{bad.group(1)}>`)",
            )
    if 1 <= line <= len(lines):
        m = re.search(r"Specification mandates value for attribute (\S+)", msg)
        spaced = m is not None and re.search(
            r"\b" + re.escape(m.group(1)) + r"\s+([A-Za-z_][\w]*)\s*=", lines[line - 1]
        )
        if m is not None and spaced:
            joined = f"{m.group(1)}_{spaced.group(1)}"
            return UserError.at(
                Loc(path, line, spaced.start() + 1),
                f"attribute name `{m.group(1)} {spaced.group(1)}` contains a space (did you mean `{joined}`?)",
            )
    if 1 <= line <= len(lines) and re.search(r"xmlParseEntityRef|EntityRef: expecting", msg):
        amp = lines[line - 1].rfind("&", 0, max(col - 1, 1))  # libxml2 points past the `&` (and its name)
        if amp >= 0:
            col = amp + 1
    for pattern, render in _LIBXML_MSG:
        m = pattern.search(msg)
        if m:
            msg = render(m)
            break
    else:
        msg = f"malformed XML: {msg}"
    return UserError.at(Loc(path, line, max(col, 1)), msg)


# `btgen check` loads a file once per mission that includes it or looks beside it for a hint: within
# shared_sources(), a file read again with the same bytes under the same shown path is the Source
# parsed before (nothing changes a Source or its tree after parse_bytes). Bounded, least recently
# used first out.
_SHARED: Optional[collections.OrderedDict[tuple[str, bytes], Source]] = None
_SHARED_MAX = 256  # files
_SHARED_MAX_BYTES = 64 * 1024 * 1024  # of their texts


@contextlib.contextmanager
def shared_sources() -> Iterator[None]:
    """Share parsed files between the loads run inside (`btgen check`)."""
    global _SHARED
    outer = _SHARED
    if outer is None:
        _SHARED = collections.OrderedDict()
    try:
        yield
    finally:
        _SHARED = outer


def read_source(path: str, display_path: Optional[str] = None) -> Source:
    """Read, decode and securely parse an XML file; UserError on any problem."""
    shown = display_path or path
    data = read_bounded(path, MAX_FILE_BYTES, "mission", "missions", shown)
    shared = _SHARED
    if shared is None:
        return parse_bytes(data, shown)
    key = (shown, hashlib.sha256(data).digest())
    src = shared.get(key)
    if src is None:
        src = shared[key] = parse_bytes(data, shown)
        while len(shared) > 1 and (
            len(shared) > _SHARED_MAX or sum(len(s.text) for s in shared.values()) > _SHARED_MAX_BYTES
        ):
            shared.popitem(last=False)
    else:
        shared.move_to_end(key)
    return src


def parse_bytes(data: bytes, path: str) -> Source:
    if len(data) > MAX_FILE_BYTES:
        raise UserError.at(Loc(path, 1, 1), f"file is larger than {MAX_FILE_BYTES} bytes")
    if data.startswith(b"\xef\xbb\xbf"):
        data = data[3:]
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as e:
        good = data[: e.start].decode("utf-8")
        line = good.count("\n") + 1
        col = len(good) - (good.rfind("\n") + 1) + 1
        raise UserError.at(
            Loc(path, line, col), f"invalid UTF-8 (byte 0x{data[e.start]:02x}); missions must be UTF-8"
        ) from None
    if not text.strip():
        raise UserError.at(Loc(path, 1, 1), 'file is empty: expected <root BTCPP_format="4">')
    nul = text.find("\x00")
    if nul >= 0:  # (XML allows no NUL; UTF-16 text read as UTF-8 is full of them)
        line, col = _LineIndex(text).pos(nul)
        utf16 = len(text) >= 4 and (text[1] == text[3] == "\x00" or text[0] == text[2] == "\x00")
        raise UserError.at(
            Loc(path, line, col),
            "NUL bytes: the file looks like UTF-16 without a byte-order mark; missions must be UTF-8"
            if utf16
            else "a NUL byte (0x00), which XML does not allow; missions must be UTF-8 text",
        )
    lines = _LineIndex(text)
    decl = re.match(r"\s*<\?xml[^>]*encoding\s*=\s*[\"']([^\"']+)", text)
    if decl and decl.group(1).replace("-", "").lower() != "utf8":
        raise UserError.at(
            Loc(path, *lines.pos(decl.start(1))),
            f"encoding `{decl.group(1)}` is not supported; missions must be UTF-8",
        )
    tags = _scan(path, text, lines)
    fixed, warnings = tolerated(path, text, lines)
    fixed, prefixed = undeclared_prefixes(fixed)
    for tag in tags:  # one warning per name, at its first element
        if tag.name in prefixed:
            prefixed.discard(tag.name)
            warnings.append(Diagnostic(tag.loc, _colon_message(tag.name), "warning"))
    # tinyxml2 (both BehaviorTree.CPP versions) reads an XML declaration after blank lines or
    # spaces (a C++ raw string `R"(\n<?xml ...` of the library's own tests); XML wants it first,
    # so lxml is given spaces in its place, which keeps every line and column.
    late = re.match(r"\s+(<\?xml\s[^>]*\?>)", fixed)
    parsed = fixed if late is None else fixed[: late.start(1)] + " " * len(late.group(1)) + fixed[late.end(1) :]
    # tinyxml2 reads the declaration's version without looking at it; libxml2 knows only 1.x:
    # another one (`version="2.0"`) is given to lxml as spaces, with a warning.
    decl_version = XML_VERSION_RE.match(parsed)
    if decl_version is not None and not re.fullmatch(r"1\.[0-9]+", decl_version.group(2)):
        warnings.append(
            Diagnostic(Loc(path, *lines.pos(decl_version.start(2))), version_message(decl_version.group(2)), "warning")
        )
        parsed = parsed[: decl_version.start(1)] + " " * len(decl_version.group(1)) + parsed[decl_version.end(1) :]
    parser = etree.XMLParser(
        resolve_entities=False,
        no_network=True,
        load_dtd=False,
        dtd_validation=False,
        huge_tree=False,
        remove_comments=False,
        remove_pis=True,
    )
    try:
        root = etree.fromstring(parsed.encode("utf-8"), parser)
    except etree.XMLSyntaxError as e:
        raise _syntax_error(path, text, e) from None
    src = Source(path, text, root, tags)
    warnings += _unread_model_elements(src)
    src.warnings = warnings
    return src


_MODEL_KINDS = ("Action", "Condition", "Control", "Decorator", "SubTree")
_MODEL_CHILDREN = ("input_port", "output_port", "inout_port", "bidirectional_port", "MetadataFields")


def _unread_model_elements(src: Source) -> list[Diagnostic]:
    """Other elements in a node model than its ports and Groot2's MetadataFields (MoveIt Pro writes
    a `<description>` there for its editor): BehaviorTree.CPP 4.6.2 and 4.10.0 load the file and never
    read them. They are taken out of the parsed tree, with a warning each."""
    out: list[Diagnostic] = []
    for models in src.root:
        if models.tag != "TreeNodesModel":
            continue
        for model in models:
            if model.tag not in _MODEL_KINDS:
                continue
            for child in list(model):
                if isinstance(child.tag, str) and child.tag not in _MODEL_CHILDREN:
                    out.append(
                        Diagnostic(
                            src.loc(child),
                            f"<{src.tag(child)}> in the model of `{model.get('ID') or ''}` is not read by "
                            "BehaviorTree.CPP (a model holds its ports and MetadataFields): ignored",
                            "warning",
                        )
                    )
                    tail = child.tail
                    model.remove(child)  # (lxml takes the tail text with it: kept)
                    if tail and tail.strip():
                        model.text = (model.text or "") + tail
    return out


XML_VERSION_RE = re.compile(r"\ufeff?\s*(<\?xml\s[^>]*?\bversion\s*=\s*[\"']([^\"']*)[\"'][^>]*\?>)")


def version_message(version: str) -> str:
    return (
        f'XML version `{version}` does not exist (XML is version 1.0 or 1.1): write `version="1.0"`; '
        "tinyxml2 (BehaviorTree.CPP) reads it, other tools do not"
    )


_TOLERATED_ATTR = (
    "a raw `&` in an attribute value is not XML: write `&amp;` (`&&` is `&amp;&amp;`); tinyxml2 "
    "(BehaviorTree.CPP) reads it as `&`, other tools do not"
)
_TOLERATED_LT = (
    "a raw `<` in an attribute value is not XML: write `&lt;`; tinyxml2 (BehaviorTree.CPP) reads it "
    "as `<`, other tools do not"
)


def tolerated(path: str, text: str, lines: _LineIndex) -> tuple[str, list[Diagnostic]]:
    """The text lxml is given for what tinyxml2 reads and XML does not, and a warning for each:
    a raw `&` or `<` in an attribute value (given to lxml as `&amp;`, `&lt;`), `--` inside a
    comment (as `- `), two attributes without a space between them (a space is added). Lines are
    never added or removed, and every position btgen reports comes from the scan of the text as
    written, so positions are unchanged; the parser's settings (no DTD, no entities, no network)
    are untouched. Anything else that is not XML stays an error."""
    edits: list[tuple[int, int, str]] = []
    warnings: list[Diagnostic] = []

    def warn(offset: int, message: str) -> None:
        warnings.append(Diagnostic(Loc(path, *lines.pos(offset)), message, "warning"))

    i, n = 0, len(text)
    while True:
        j = text.find("<", i)
        if j < 0 or j + 1 >= n:
            break
        if text.startswith("<!--", j):
            k = text.find("-->", j + 4)
            end = n if k < 0 else k
            inner = text[j + 4 : end]
            if k >= 0 and ("--" in inner or inner.endswith("-")):
                bad = inner.find("--") if "--" in inner else len(inner) - 1
                warn(
                    j + 4 + bad,
                    "`--` inside a comment is not XML (a comment ends at `-->` only); tinyxml2 "
                    "(BehaviorTree.CPP) reads it, other tools do not: write it another way",
                )
                fixed = inner.replace("--", "- ").replace("--", "- ")
                if fixed.endswith("-"):
                    fixed = fixed[:-1] + " "
                edits.append((j + 4, end, fixed))
            i = n if k < 0 else k + 3
            continue
        if text.startswith("<![CDATA[", j) or text[j + 1] in "?!/":
            k = text.find(">", j)
            i = n if k < 0 else k + 1
            continue
        m = _TAG_RE.match(text, j)
        if not m:
            i = j + 1
            continue
        k = m.end()
        previous_quoted = False
        while True:
            am = _ATTR_RE.match(text, k)
            if not am:
                break
            if previous_quoted and am.start(1) == am.start():
                warn(
                    am.start(1),
                    f"no space before attribute `{am.group(1)}`: XML needs one between two attributes; "
                    f"tinyxml2 (BehaviorTree.CPP) reads it, other tools do not",
                )
                edits.append((am.start(1), am.start(1), " "))
            vstart = am.start(3) if am.group(3) is not None else am.start(4)
            raw = am.group(3) if am.group(3) is not None else am.group(4)
            said = False
            for x, ch in enumerate(raw):
                if ch == "<":
                    edits.append((vstart + x, vstart + x + 1, "&lt;"))
                elif ch == "&" and not _ENTITY_RE.match(raw, x):
                    edits.append((vstart + x, vstart + x + 1, "&amp;"))
                else:
                    continue
                if not said:
                    warn(vstart + x, _TOLERATED_LT if ch == "<" else _TOLERATED_ATTR)
                    said = True
            previous_quoted = True
            k = am.end()
        i = k
    if not edits:
        return text, warnings
    out, at = [], 0
    for start, end, repl in sorted(edits):
        out.append(text[at:start])
        out.append(repl)
        at = end
    out.append(text[at:])
    return "".join(out), warnings


# tinyxml2 reads `<arm:Grasp/>` as the element `arm:Grasp`; XML reads `arm` as a namespace prefix,
# and one the file does not declare is an error. lxml is given `arm\u00b7Grasp` instead (a middle
# dot, an XML name character, one character for one), Source.tag gives the name as written, and
# the mission XSD declares the node under the name lxml sees (lxml_name, in xsd.mission_xsd).
PREFIX_MARK = "\u00b7"
_PREFIXED_TAG_RE = re.compile(r"<(/?)([A-Za-z_][-A-Za-z0-9_.]*(?::[-A-Za-z0-9_.]*)+)")
_DECLARED_PREFIX_RE = re.compile(r"\bxmlns:([A-Za-z_][-A-Za-z0-9_.]*)\s*=")


def lxml_name(name: str) -> str:
    """The name lxml is given for an element written `name` (undeclared_prefixes)."""
    return name.replace(":", PREFIX_MARK)


def _colon_message(name: str) -> str:
    return (
        f"element name `{name}` has a colon: XML reads `{name.split(':')[0]}` as a namespace prefix, which "
        f"this file does not declare; tinyxml2 (BehaviorTree.CPP) reads it as one name, other tools do not"
    )


def undeclared_prefixes(text: str) -> tuple[str, set[str]]:
    """The text lxml is given for element names with a colon whose prefix the file does not declare
    (`<arm:Grasp/>`, read whole by tinyxml2), and those names. Only when the file holds no middle
    dot already (the mark must stand for one thing); a declared prefix stays XML's (and btgen's
    "no namespace" error)."""
    if ":" not in text or PREFIX_MARK in text:
        return text, set()
    declared = set(_DECLARED_PREFIX_RE.findall(text)) | {"xml", "xmlns"}
    out: list[str] = []
    names: set[str] = set()
    at, i, n = 0, 0, len(text)
    while True:
        j = text.find("<", i)
        if j < 0 or j + 1 >= n:
            break
        for opener, closer in (("<!--", "-->"), ("<![CDATA[", "]]>"), ("<?", "?>"), ("<!", ">")):
            if text.startswith(opener, j):
                k = text.find(closer, j + len(opener))
                i = n if k < 0 else k + len(closer)
                break
        else:
            m = _PREFIXED_TAG_RE.match(text, j)
            i = j + 1
            if m is None or m.group(2).split(":")[0] in declared:
                continue
            out.append(text[at : m.start(2)])
            out.append(lxml_name(m.group(2)))
            at = i = m.end()
            if not m.group(1):
                names.add(m.group(2))
    if not out:
        return text, set()
    out.append(text[at:])
    return "".join(out), names
