"""The environment knowledge base (CSSR4Africa D5.4.2, sections 4-5).

The knowledge base is a line-based `.dat` file (format: data/README.md):
one entry per line, ``key id values...``, for ten per-location keys plus one
``tourSpecification``. Stages:

1. read: size limit, UTF-8, no control characters (all bad lines reported,
   then stop: nothing after a broken byte can be trusted);
2. tokenize: key, location id, values, each with its line and column;
   unknown keys are reported here, with did-you-mean;
3. validate: each entry becomes one element of an XML tree (every token a
   child element) checked with xmlschema against
   schema/environment_knowledge_base.xsd -- types, value counts, required
   and duplicate keys, tour references -- and every xmlschema error is
   mapped back to the `.dat` position of the element that failed;
4. lint: what XSD 1.0 cannot say (tour count, byte lengths, placeholder
   messages, unvisited locations);
5. model: frozen dataclasses (:class:`KnowledgeBase`).

The limits below are shared with the C++ reader
(runtime/include/btgen/kb_limits.hpp) and the schema; a test checks that
all three agree.
"""

from __future__ import annotations

import functools
import os
import re
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from typing import Any, Optional
from xml.etree import ElementTree as ET

import xmlschema

from btgen import resources
from btgen.diagnostics import Diagnostic, DiagnosticSink, Loc, UserError, did_you_mean, read_bounded, suggestion

# ----- Limits: keep equal to runtime/include/btgen/kb_limits.hpp ----------------

KB_MAX_FILE_BYTES = 131072  # .dat and .ini files; the Lab Tour base is 4 kB (lint time grows with size: docs/limits.md)
KB_MAX_TEXT_BYTES = 255  # description or message, UTF-8 bytes, without terminator
KB_MAX_CULTURAL_KEYS = 10  # per location (D5.4.2 MAX_CULTURAL_KEYS)
KB_MAX_CULTURAL_KEY_BYTES = 63  # one cultural knowledge key
KB_MAX_TOUR_LOCATIONS = 20  # D5.4.2 MAX_NUMBER_OF_TOUR_LOCATIONS
KB_MAX_LOCATION_ID = 2147483647  # int32
KB_MAX_ABS_COORDINATE = 1000000  # metres (degrees for theta)

# ----- Keys ------------------------------------------------------------------

LANGUAGES = ("English", "IsiZulu", "Kinyarwanda")
TEXT_KEYS = (
    "robotLocationDescription",
    *(f"{phase}GestureMessage{lang}" for phase in ("pre", "post") for lang in LANGUAGES),
)
POINT_KEYS = {"robotLocationPose": "x y theta", "gestureTarget": "x y z"}
CULTURAL_KEY = "culturalKnowledge"
TOUR_KEY = "tourSpecification"
LOCATION_KEYS = (*TEXT_KEYS[:1], *POINT_KEYS, *TEXT_KEYS[1:], CULTURAL_KEY)

# Names used by earlier versions of D5.4.2 and its example file.
_RENAMED = {"robotLocation": ("robotLocationPose", "renamed in version 1.2 of D5.4.2")}

CONFIG_KEYS = ("knowledgeBase", "verboseMode")

# A message that stands in for a missing one ("No message in isiZulu").
_PLACEHOLDER_RE = re.compile(
    r"(?i)(no (message|translation|text)\b.*|(todo|tbd|fixme)\b.*|placeholder\b.*"
    r"|to be translated\b.*|x{3,}|\.\.\.|lorem ipsum\b.*)"
)

SCHEMA_PATH = str(resources.SCHEMA_DIR / "environment_knowledge_base.xsd")


@functools.cache
def kb_schema() -> xmlschema.XMLSchema10:
    """The compiled schema (built once per process)."""
    return xmlschema.XMLSchema10(SCHEMA_PATH)


def schema_keys() -> tuple[str, ...]:
    """Every key the schema allows, in schema order."""
    root: Any = kb_schema().elements["environmentKnowledgeBase"]
    return tuple(str(e.local_name) for e in root.type.content.iter_elements())


# ----- Model -----------------------------------------------------------------


@dataclass(frozen=True)
class Pose:
    """Where the robot stands: metres, metres, degrees."""

    x: float
    y: float
    theta: float


@dataclass(frozen=True)
class Point3:
    """A gesture target in metres."""

    x: float
    y: float
    z: float


@dataclass(frozen=True)
class Messages:
    """One message in each language of the base."""

    english: str
    isizulu: str
    kinyarwanda: str

    def in_language(self, language: str) -> str:
        """``language`` is one of :data:`LANGUAGES` (any case)."""
        return {"english": self.english, "isizulu": self.isizulu, "kinyarwanda": self.kinyarwanda}[language.lower()]


@dataclass(frozen=True)
class Location:
    id: int
    loc: Loc  # first entry of the location in the .dat file
    description: str
    pose: Pose
    gesture_target: Point3
    pre_gesture: Messages
    post_gesture: Messages
    cultural_knowledge: tuple[str, ...]


@dataclass(frozen=True)
class KnowledgeBase:
    path: str
    locations: tuple[Location, ...]  # sorted by id
    tour: tuple[int, ...]  # location ids in visiting order
    warnings: tuple[Diagnostic, ...] = ()

    def location(self, location_id: int) -> Optional[Location]:
        """The location with this id, or None."""
        for loc in self.locations:
            if loc.id == location_id:
                return loc
        return None

    def tour_locations(self) -> tuple[Location, ...]:
        """The locations of the tour in visiting order (every id exists: checked on load)."""
        by_id = {loc.id: loc for loc in self.locations}
        return tuple(by_id[i] for i in self.tour)


@dataclass(frozen=True)
class KbConfiguration:
    path: str
    knowledge_base: str  # as written in the .ini
    knowledge_base_path: str  # resolved against the .ini's directory
    verbose_mode: bool


# ----- Reading lines ---------------------------------------------------------


@dataclass(frozen=True)
class _Line:
    number: int
    text: str


def _read_lines(path: str, sink: DiagnosticSink, what: str) -> Optional[list[_Line]]:
    """The decoded lines of a file, or None after reporting why it cannot be read.

    Lines end with LF or CRLF; a UTF-8 byte order mark is skipped. Every line
    with invalid UTF-8 or a control character (other than tab) is reported.
    """
    try:
        data = read_bounded(path, KB_MAX_FILE_BYTES, what)
    except UserError as e:
        sink.items.extend(e.diagnostics)
        return None
    if data.startswith(b"\xef\xbb\xbf"):
        data = data[3:]
    lines: list[_Line] = []
    ok = True
    for number, raw in enumerate(data.split(b"\n"), start=1):
        if raw.endswith(b"\r"):
            raw = raw[:-1]
        try:
            text = raw.decode("utf-8")
        except UnicodeDecodeError as e:
            col = len(raw[: e.start].decode("utf-8")) + 1
            sink.error(Loc(path, number, col), f"invalid UTF-8 byte 0x{raw[e.start]:02X}; save the file as UTF-8")
            ok = False
            continue
        bad = re.search(r"[\x00-\x08\x0a-\x1f\x7f]", text)
        if bad:
            sink.error(Loc(path, number, bad.start() + 1), f"control character U+{ord(bad.group()):04X} is not allowed")
            ok = False
            continue
        lines.append(_Line(number, text))
    return lines if ok else None


def _content(line: _Line) -> bool:
    stripped = line.text.lstrip(" \t")
    return bool(stripped) and not stripped.startswith("#")


# ----- Tokenizing ------------------------------------------------------------


@dataclass(frozen=True)
class _Token:
    text: str
    loc: Loc


@dataclass
class _Entry:
    key: _Token
    values: list[_Token]  # for text keys: [id, text]
    end: Loc  # just after the last character of the line
    broken: bool = False  # a separator error was reported: its value count means nothing


class _Scanner:
    """Items of one line: separated by blanks, or by a comma with optional blanks."""

    def __init__(self, path: str, line: _Line) -> None:
        self.path, self.line, self.text = path, line, line.text
        self.i = 0
        self.failed = False

    def loc(self, i: int) -> Loc:
        return Loc(self.path, self.line.number, i + 1)

    def _skip_blanks(self) -> None:
        while self.i < len(self.text) and self.text[self.i] in " \t":
            self.i += 1

    def item(self, sink: DiagnosticSink) -> Optional[_Token]:
        """The next item and its separator, None at the end of the line or on error (reported)."""
        self._skip_blanks()
        if self.i >= len(self.text):
            return None
        if self.text[self.i] == ",":
            sink.error(self.loc(self.i), "unexpected `,`: a value is missing before it")
            self.i, self.failed = len(self.text), True
            return None
        start = self.i
        while self.i < len(self.text) and self.text[self.i] not in " \t,":
            self.i += 1
        token = _Token(self.text[start : self.i], self.loc(start))
        self._skip_blanks()
        if self.i < len(self.text) and self.text[self.i] == ",":
            comma = self.i
            self.i += 1
            self._skip_blanks()
            if self.i >= len(self.text):
                sink.error(self.loc(comma), "unexpected `,` at the end of the line")
                self.failed = True
        return token

    def rest(self) -> Optional[_Token]:
        """The rest of the line without trailing blanks (text values), None if empty."""
        self._skip_blanks()
        text = self.text[self.i :].rstrip(" \t")
        start, self.i = self.i, len(self.text)
        return _Token(text, self.loc(start)) if text else None

    def end(self) -> Loc:
        return self.loc(len(self.text.rstrip(" \t")))


@dataclass
class _Parsed:
    entries: list[_Entry]
    # (location id as written, key) of lines whose key is unknown but close to a
    # real one: the missing-entry error for that pair would only repeat it.
    explained: set[tuple[str, str]]


def _tokenize(path: str, lines: Sequence[_Line], sink: DiagnosticSink) -> _Parsed:
    known = schema_keys()
    explained: set[tuple[str, str]] = set()
    entries: list[_Entry] = []
    previous: Optional[_Line] = None  # the last content line, for wrapped text
    for line in lines:
        if not _content(line):
            continue
        sc = _Scanner(path, line)
        key = sc.item(sink)
        wrapped_from, previous = previous, line
        if key is None:
            continue
        if key.text not in known:
            sink.error(key.loc, _unknown_key_message(key.text, known, wrapped_from))
            meant = _RENAMED[key.text][0] if key.text in _RENAMED else did_you_mean(key.text, known)
            ident = sc.item(DiagnosticSink())
            if meant is not None and ident is not None:
                explained.add((ident.text, meant))
            continue
        values: list[_Token] = []
        if key.text in TEXT_KEYS:
            ident = sc.item(sink)
            if ident is not None:
                values.append(ident)
                text = sc.rest()
                if text is not None:
                    values.append(text)
        else:
            while (tok := sc.item(sink)) is not None:
                values.append(tok)
        entries.append(_Entry(key, values, sc.end(), sc.failed))
    return _Parsed(entries, explained)


def _unknown_key_message(word: str, known: Sequence[str], previous: Optional[_Line]) -> str:
    if word in _RENAMED:
        new, why = _RENAMED[word]
        return f"unknown key `{word}`: it was {why}; write `{new}`"
    m = did_you_mean(word, known)
    if m and m.lower() == word.lower():
        return f"unknown key `{word}` (did you mean `{m}`? keys are case-sensitive)"
    if m:
        return f"unknown key `{word}` (did you mean `{m}`?)"
    previous_key = re.match(r"[ \t]*([^ \t,]*)", previous.text) if previous is not None else None
    if previous is not None and previous_key is not None and previous_key.group(1) in TEXT_KEYS:
        return (
            f"unknown key `{word}`; if this line continues the text on line {previous.number}, "
            f"join them: an entry is one line"
        )
    return f"unknown key `{word}`: a line starts with a key such as `{known[0]}`"


# ----- Schema validation -----------------------------------------------------


@dataclass
class _Tree:
    """The XML image of the entries, with the source position of every element.

    Elements are keyed by id(): the root keeps them all alive, so ids stay unique.
    """

    root: ET.Element
    locs: dict[int, Loc] = field(default_factory=dict)  # id(element) -> position
    entries: dict[int, _Entry] = field(default_factory=dict)  # id(entry element) -> entry

    def add(self, parent: ET.Element, tag: str, loc: Loc, text: Optional[str] = None) -> ET.Element:
        elem = ET.SubElement(parent, tag)
        elem.text = text
        self.locs[id(elem)] = loc
        return elem


def _child_tags(key: str) -> tuple[str, str]:
    """Tag of the first value and of the others, as in the schema."""
    if key == TOUR_KEY:
        return "count", "id"
    if key == CULTURAL_KEY:
        return "id", "key"
    if key in POINT_KEYS:
        return "id", "value"
    return "id", "text"


def _build_tree(entries: Sequence[_Entry], path: str) -> _Tree:
    tree = _Tree(ET.Element("environmentKnowledgeBase"))
    tree.locs[id(tree.root)] = Loc(path, 1, 1)
    # The content model wants every tour after the location entries.
    ordered = [e for e in entries if e.key.text != TOUR_KEY] + [e for e in entries if e.key.text == TOUR_KEY]
    for entry in ordered:
        elem = tree.add(tree.root, entry.key.text, entry.key.loc)
        tree.entries[id(elem)] = entry
        first, other = _child_tags(entry.key.text)
        for i, tok in enumerate(entry.values):
            tree.add(elem, first if i == 0 else other, tok.loc, tok.text)
    return tree


_KEYREF_RE = re.compile(r"value \((.*),\) not found for XsdKey\(name='(\w+)'\)")
_DUPLICATE_RE = re.compile(r"duplicated value \((.*),\) for XsdKey\(name='(\w+)'\)")
_INT_RE = re.compile(r"Decimal\('([0-9]+)'\)")


def _describe_values(key: str) -> str:
    if key in POINT_KEYS:
        return f"a location id and 3 numbers ({POINT_KEYS[key]})"
    if key == CULTURAL_KEY:
        return f"a location id and 1 to {KB_MAX_CULTURAL_KEYS} cultural knowledge keys"
    if key == TOUR_KEY:
        return "the number of locations, then their ids in visiting order"
    return "a location id and a text"


def _type_message(elem: ET.Element, parent: ET.Element, validator: object) -> str:
    value = elem.text or ""
    key = parent.tag
    facet = type(validator).__name__
    if elem.tag == "id":
        return f"expected a location id (a whole number from 1 to {KB_MAX_LOCATION_ID}), found `{value}`"
    if elem.tag == "value":
        if "Inclusive" in facet:
            return f"`{value}` is out of range: coordinates are at most {KB_MAX_ABS_COORDINATE} in magnitude"
        try:
            float(value)
            why = " (write a plain decimal such as 0.82: no exponent, INF or NaN)"
        except ValueError:
            why = ""
        return f"expected a number in `{key}` ({POINT_KEYS.get(key, 'x y z')}), found `{value}`{why}"
    if elem.tag == "key":
        if "Length" in facet:
            return (
                f"cultural knowledge key `{value[:20]}...` is {len(value.encode())} bytes long; "
                f"at most {KB_MAX_CULTURAL_KEY_BYTES} are allowed"
            )
        return f"`{value}` is not a cultural knowledge key (an ASCII letter, then letters, digits or `_`)"
    if elem.tag == "count":
        if "Inclusive" in facet:
            return f"the tour has {value} locations; at most {KB_MAX_TOUR_LOCATIONS} are allowed"
        return f"expected the number of tour locations (a whole number), found `{value}`"
    return f"`{key}` needs a text after the location id"


def _validate(tree: _Tree, explained: set[tuple[str, str]], path: str, sink: DiagnosticSink) -> set[int]:
    """Report schema errors at .dat positions; returns the ids of elements with a bad value."""
    parents = {id(c): p for p in tree.root.iter() for c in p}
    errors = list(kb_schema().iter_errors(tree.root))
    bad: set[int] = set()
    reported: set[int] = set()
    identity: list[xmlschema.XMLSchemaValidationError] = []

    for err in errors:
        elem = err.elem
        if elem is None or id(elem) not in tree.locs:
            identity.append(err)  # should not happen; reported below with a fallback
            continue
        loc = tree.locs[id(elem)]
        reason = err.reason or ""
        if isinstance(err, xmlschema.XMLSchemaChildrenValidationError):
            _content_error(tree, err, elem, path, sink)
            reported.add(id(elem))
        elif elem is tree.root or reason.startswith(("duplicated value", "missing key field")):
            identity.append(err)
        elif id(elem) not in reported:  # one message per bad value
            reported.add(id(elem))
            bad.add(id(elem))
            sink.error(loc, _type_message(elem, parents[id(elem)], err.validator))

    _identity_errors(tree, identity, bad, reported, explained, path, sink)
    return bad


def _content_error(
    tree: _Tree, err: xmlschema.XMLSchemaChildrenValidationError, elem: ET.Element, path: str, sink: DiagnosticSink
) -> None:
    key = elem.tag
    child = getattr(err, "invalid_child", None)
    if elem is tree.root:
        if child is not None and child.tag == TOUR_KEY:
            # The content model stops at the second tour: report every later one.
            tours = [e for e in tree.root if e.tag == TOUR_KEY]
            for later in tours[1:]:
                sink.error(
                    tree.locs[id(later)], f"duplicate `{TOUR_KEY}`; the first is on line {tree.locs[id(tours[0])].line}"
                )
        elif child is None:
            sink.error(
                Loc(path, 1, 1),
                f"the knowledge base has no `{TOUR_KEY}` (the number of locations, then their ids in visiting order)",
            )
        else:  # cannot happen: unknown keys never reach the tree
            sink.error(tree.locs[id(child)], f"unexpected `{child.tag}`")
        return
    entry = tree.entries[id(elem)]
    if entry.broken:
        return  # the separator error already explains the count
    if child is not None:  # too many values
        if key == TOUR_KEY:
            sink.error(tree.locs[id(child)], f"the tour lists more than {KB_MAX_TOUR_LOCATIONS} locations")
        elif key == CULTURAL_KEY:
            sink.error(
                tree.locs[id(child)], f"more than {KB_MAX_CULTURAL_KEYS} cultural knowledge keys for one location"
            )
        else:
            sink.error(tree.locs[id(child)], f"too many values: `{key}` takes {_describe_values(key)}")
        return
    # Too few values.
    # Report where the missing value belongs: one blank after the end of the line.
    if not entry.values:
        sink.error(entry.end.shifted(1), f"`{key}` needs {_describe_values(key)}")
    elif key in POINT_KEYS:
        sink.error(
            entry.end.shifted(1),
            f"`{key}` takes {_describe_values(key)}; "
            f"found {len(entry.values) - 1} number"
            f"{'' if len(entry.values) == 2 else 's'}",
        )
    elif key == TOUR_KEY:
        sink.error(entry.end.shifted(1), f"`{TOUR_KEY}` lists no location ids after the count")
    elif key == CULTURAL_KEY:
        sink.error(entry.end.shifted(1), f"`{CULTURAL_KEY}` of location {entry.values[0].text} lists no keys")
    else:
        sink.error(entry.end.shifted(1), f"`{key}` of location {entry.values[0].text} has no text")


def _entry_id(tree: _Tree, elem: ET.Element, bad: set[int]) -> Optional[int]:
    """The location id of an entry element if it is well formed."""
    first = elem.find("id")
    if elem.tag == TOUR_KEY or first is None or id(first) in bad or first is not elem[0]:
        return None
    return int(first.text or "0")


def _identity_errors(
    tree: _Tree,
    errs: Sequence[xmlschema.XMLSchemaValidationError],
    bad: set[int],
    reported: set[int],
    explained: set[tuple[str, str]],
    path: str,
    sink: DiagnosticSink,
) -> None:
    first_of: dict[int, ET.Element] = {}  # location id -> its first entry element
    unidentified: set[str] = set()  # keys with an entry whose id is missing or malformed
    for elem in tree.root:
        lid = _entry_id(tree, elem, bad)
        if lid is not None:
            first_of.setdefault(lid, elem)
        elif elem.tag != TOUR_KEY:
            unidentified.add(elem.tag)
    seen: set[tuple[str, str]] = set()
    for err in errs:
        reason = err.reason or ""
        if reason.startswith("missing key field"):
            continue  # the entry has no id: already reported as incomplete
        dup = _DUPLICATE_RE.match(reason)
        if dup:
            # xmlschema reports the second entry only: report every later one too.
            dup_elem = err.elem
            lid = _entry_id(tree, dup_elem, bad) if dup_elem is not None else None
            if dup_elem is None or lid is None:
                continue
            tag = dup_elem.tag
            same = [e for e in tree.root if e.tag == tag and _entry_id(tree, e, bad) == lid]
            for later in same[1:]:
                if id(later) not in reported:  # an entry with a count error is not also a duplicate
                    reported.add(id(later))
                    sink.error(
                        tree.locs[id(later)],
                        f"duplicate `{tag}` entry for location {lid}; "
                        f"the first is on line {tree.locs[id(same[0])].line}",
                    )
            continue
        ref = _KEYREF_RE.match(reason)
        if ref:
            num = _INT_RE.fullmatch(ref.group(1))
            key = ref.group(2)
            if num is None or (num.group(1), key) in seen:
                continue  # an id of the wrong type: already reported
            seen.add((num.group(1), key))
            lid = int(num.group(1))
            if key == "location":
                if lid in first_of:
                    continue  # the location exists but has no pose: reported as missing key
                known = ", ".join(str(i) for i in sorted(first_of)[:12]) or "none"
                for tid in tree.root.iter("id"):
                    parent_is_tour = any(tid is c for t in tree.root.iter(TOUR_KEY) for c in t)
                    if parent_is_tour and id(tid) not in bad and int(tid.text or "0") == lid:
                        sink.error(
                            tree.locs[id(tid)],
                            f"the tour visits location {lid}, which the knowledge "
                            f"base does not define (locations: {known})",
                        )
            elif lid in first_of and key not in unidentified and (str(lid), key) not in explained:
                # Location entries keep their file order in the tree: first_of is the first line.
                sink.error(tree.locs[id(first_of[lid])], f"location {lid} has no `{key}` entry")
            continue
        loc = tree.locs.get(id(err.elem), Loc(path, 1, 1)) if err.elem is not None else Loc(path, 1, 1)
        sink.error(loc, f"does not match the knowledge base schema: {reason}")


# ----- Checks beyond the schema ----------------------------------------------


def _lint_entries(entries: Sequence[_Entry], sink: DiagnosticSink) -> None:
    """Text lengths, placeholders, tour count; independent of schema errors."""
    for entry in entries:
        key = entry.key.text
        if key in TEXT_KEYS and len(entry.values) == 2:
            text = entry.values[1]
            size = len(text.text.encode("utf-8"))
            where = f"`{key}` of location {entry.values[0].text}"
            if size > KB_MAX_TEXT_BYTES:
                sink.error(
                    text.loc,
                    f"{where} is {size} bytes long; the runtime holds at most {KB_MAX_TEXT_BYTES} bytes (UTF-8)",
                )
            elif _PLACEHOLDER_RE.fullmatch(text.text) and key != "robotLocationDescription":
                sink.warning(
                    text.loc, f"{where} is a placeholder, not a message: `{text.text}` (the robot would say it)"
                )
        if key == TOUR_KEY and entry.values:
            count, ids = entry.values[0], entry.values[1:]
            if (
                re.fullmatch(r"0|[1-9][0-9]*", count.text)
                and int(count.text) <= KB_MAX_TOUR_LOCATIONS
                and ids
                and len(ids) <= KB_MAX_TOUR_LOCATIONS
                and int(count.text) != len(ids)
            ):
                sink.error(
                    count.loc,
                    f"the tour count is {count.text} but {len(ids)} location "
                    f"id{'' if len(ids) == 1 else 's'} follow "
                    f"({' '.join(t.text for t in ids)})",
                )


# ----- The model ---------------------------------------------------------------


def _build_model(path: str, entries: Sequence[_Entry], warnings: Sequence[Diagnostic]) -> KnowledgeBase:
    """Entries already validated: every location complete, numbers well formed."""
    by_id: dict[int, dict[str, _Entry]] = {}
    tour: tuple[int, ...] = ()
    for entry in entries:
        if entry.key.text == TOUR_KEY:
            tour = tuple(int(t.text) for t in entry.values[1:])
        else:
            by_id.setdefault(int(entry.values[0].text), {})[entry.key.text] = entry

    def text(e: dict[str, _Entry], key: str) -> str:
        return e[key].values[1].text

    def nums(e: dict[str, _Entry], key: str) -> tuple[float, float, float]:
        a, b, c = (float(t.text) for t in e[key].values[1:])
        return a, b, c

    def messages(e: dict[str, _Entry], phase: str) -> Messages:
        return Messages(*(text(e, f"{phase}GestureMessage{lang}") for lang in LANGUAGES))

    locations = []
    for lid in sorted(by_id):
        e = by_id[lid]
        first = min((x.key.loc for x in e.values()), key=lambda loc: (loc.line, loc.col))
        locations.append(
            Location(
                id=lid,
                loc=first,
                description=text(e, "robotLocationDescription"),
                pose=Pose(*nums(e, "robotLocationPose")),
                gesture_target=Point3(*nums(e, "gestureTarget")),
                pre_gesture=messages(e, "pre"),
                post_gesture=messages(e, "post"),
                cultural_knowledge=tuple(t.text for t in e[CULTURAL_KEY].values[1:]),
            )
        )
    return KnowledgeBase(path, tuple(locations), tour, tuple(warnings))


def _sorted(diags: Sequence[Diagnostic]) -> list[Diagnostic]:
    unique = list(dict.fromkeys(diags))
    return sorted(unique, key=lambda d: (d.loc.line, d.loc.col))


def _check_kb(dat_path: str) -> tuple[list[Diagnostic], Optional[KnowledgeBase], list[_Entry]]:
    sink = DiagnosticSink()
    lines = _read_lines(dat_path, sink, "knowledge base")
    if lines is None:
        return _sorted(sink.items), None, []
    if not any(_content(line) for line in lines):
        sink.error(
            Loc(dat_path, 1, 1),
            "the knowledge base is empty: it has no locations and no "
            f"`{TOUR_KEY}` (format: key, location id, values; one entry a line)",
        )
        return _sorted(sink.items), None, []
    parsed = _tokenize(dat_path, lines, sink)
    entries = parsed.entries
    tree = _build_tree(entries, dat_path)
    _validate(tree, parsed.explained, dat_path, sink)
    _lint_entries(entries, sink)
    if not sink.errors:  # locations no tour visits
        visited = {int(t.text) for e in entries if e.key.text == TOUR_KEY for t in e.values[1:]}
        firsts: dict[int, Loc] = {}
        for e in entries:
            if e.key.text != TOUR_KEY:
                firsts.setdefault(int(e.values[0].text), e.key.loc)
        for lid, loc in firsts.items():
            if lid not in visited:
                sink.warning(loc, f"location {lid} is not visited by the tour")
    diags = _sorted(sink.items)
    if sink.errors:
        return diags, None, entries
    return diags, _build_model(dat_path, entries, [d for d in diags if d.severity == "warning"]), entries


# ----- Configuration (.ini) ----------------------------------------------------


def _check_config(ini_path: str) -> tuple[list[Diagnostic], Optional[KbConfiguration], Optional[Loc]]:
    """Diagnostics, the configuration if valid, and the position of the knowledgeBase value."""
    sink = DiagnosticSink()
    lines = _read_lines(ini_path, sink, "configuration")
    if lines is None:
        return _sorted(sink.items), None, None
    values: dict[str, _Token] = {}
    kb_written = False  # a knowledgeBase line exists, even a wrong one
    for line in lines:
        if not _content(line):
            continue
        m = re.match(r"[ \t]*([^ \t]+)[ \t]*(.*?)[ \t]*$", line.text)
        assert m is not None  # a content line has a first token
        key = _Token(m.group(1), Loc(ini_path, line.number, m.start(1) + 1))
        value = _Token(m.group(2), Loc(ini_path, line.number, m.start(2) + 1))
        name = key.text.split("=")[0]
        kb_written = kb_written or name == "knowledgeBase"
        if "=" in key.text or value.text.startswith("="):
            sink.error(key.loc, f"write `{name or 'key'} value` separated by blanks, without `=`")
            continue
        if key.text not in CONFIG_KEYS:
            sink.error(key.loc, f"unknown configuration key `{key.text}`{suggestion(key.text, CONFIG_KEYS)}")
            continue
        if key.text in values:
            sink.error(key.loc, f"duplicate `{key.text}`; the first is on line {values[key.text].loc.line}")
            continue
        if not value.text:
            sink.error(key.loc.shifted(len(key.text)), f"`{key.text}` needs a value")
            continue
        values[key.text] = value
    verbose = False
    if "verboseMode" in values:
        v = values["verboseMode"]
        if v.text not in ("true", "false"):
            sink.error(v.loc, f"`verboseMode` must be `true` or `false`, found `{v.text}`")
        verbose = v.text == "true"
    kb = values.get("knowledgeBase")
    if kb is None:
        if not kb_written:
            sink.error(
                Loc(ini_path, 1, 1), "the configuration has no `knowledgeBase` (the file name of the knowledge base)"
            )
        return _sorted(sink.items), None, None
    resolved = os.path.join(os.path.dirname(ini_path), kb.text)
    if not os.path.isfile(resolved):
        # (a directory or FIFO exists: "not found" sent the user looking for a typo)
        why = (
            "is a directory, not a knowledge base file"
            if os.path.isdir(resolved)
            else "is not a regular file"
            if os.path.exists(resolved)
            else "not found"
        )
        sink.error(
            kb.loc,
            f"knowledge base file `{kb.text}` {why} (looked for `{resolved}`; "
            f"the name is relative to the configuration file's folder)",
        )
    if sink.errors:
        return _sorted(sink.items), None, kb.loc
    return _sorted(sink.items), KbConfiguration(ini_path, kb.text, resolved, verbose), kb.loc


def load_config(ini_path: str) -> KbConfiguration:
    """Read a configuration file; UserError on any problem."""
    diags, config, _ = _check_config(ini_path)
    if config is None:
        raise UserError(diags)
    return config


# ----- Mission references ------------------------------------------------------

_MISSION_PORT_RE = re.compile(r"(?i)(location|exhibit)(_?id)?")


def _check_mission(mission_path: str, kb: Sequence[_Entry], sink: DiagnosticSink) -> None:
    """Literal location ids in the mission's ports must exist in the base.

    Looks at every attribute named `location`, `location_id`, `locationId`,
    `exhibit`, `exhibit_id` or `exhibitId` (any case); values in braces
    (blackboard entries) and scripts are left alone.
    """
    from btgen.frontend.xmlsource import read_source  # secure lxml reading: no DTD, entities or network

    try:
        src = read_source(mission_path)
    except UserError as e:
        sink.items.extend(e.diagnostics)
        return
    ids = {
        int(e.values[0].text)
        for e in kb
        if e.key.text != TOUR_KEY and e.values and re.fullmatch(r"[1-9][0-9]{0,9}", e.values[0].text)
    }
    descriptions = {
        e.values[1].text.lower(): e.values[0].text
        for e in kb
        if e.key.text == "robotLocationDescription" and len(e.values) == 2
    }
    known = ", ".join(str(i) for i in sorted(ids)[:12]) or "none"
    for elem in src.root.iter():
        if not isinstance(elem.tag, str):
            continue
        for raw_name, raw_value in elem.attrib.items():
            name, value = str(raw_name), str(raw_value)
            if not _MISSION_PORT_RE.fullmatch(name):
                continue
            v = value.strip()
            if not v or v.startswith(("{", "=")) or "{" in v:
                continue  # blackboard entry or script: known at run time only
            loc = src.value_loc(elem, name, len(value) - len(value.lstrip()))
            if re.fullmatch(r"[1-9][0-9]*", v):
                if int(v) not in ids:
                    sink.error(
                        loc,
                        f"`{name}` names location {v}, which the knowledge base does not define (locations: {known})",
                    )
                continue
            hint = descriptions.get(v.lower())
            more = f" (location {hint} is described as `{v}`)" if hint else ""
            sink.error(
                loc,
                f"`{name}` must be a location id of the knowledge base or a blackboard "
                f"entry such as `{{{name}}}`, found `{v}`{more}",
            )


# ----- Entry points -----------------------------------------------------------


def lint_kb(dat_path: str, config_path: Optional[str] = None, mission_path: Optional[str] = None) -> list[Diagnostic]:
    """Every problem of a knowledge base (and its configuration and mission), never raising.

    Diagnostics come file by file (base, configuration, mission), each
    sorted by position.
    """
    diags, _, entries = _check_kb(dat_path)
    if config_path is not None:
        cdiags, config, kb_loc = _check_config(config_path)
        diags += cdiags
        if (
            config is not None
            and kb_loc is not None
            and os.path.exists(dat_path)
            and not os.path.samefile(config.knowledge_base_path, dat_path)
        ):
            diags.append(
                Diagnostic(
                    kb_loc,
                    f"the configuration names `{config.knowledge_base}`, not the file being checked (`{dat_path}`)",
                    "warning",
                )
            )
    if mission_path is not None:
        sink = DiagnosticSink()
        _check_mission(mission_path, entries, sink)
        diags += _sorted(sink.items)
    return diags


def load_kb(dat_path: str) -> KnowledgeBase:
    """Parse and check a knowledge base; UserError listing every problem if it has errors."""
    diags, kb, _ = _check_kb(dat_path)
    if kb is None:
        raise UserError(diags)
    return kb


def iter_placeholders(kb: KnowledgeBase) -> Iterator[tuple[int, str]]:
    """(location id, key) of every message that is a placeholder."""
    for loc in kb.locations:
        for phase, msgs in (("pre", loc.pre_gesture), ("post", loc.post_gesture)):
            for lang in LANGUAGES:
                if _PLACEHOLDER_RE.fullmatch(msgs.in_language(lang)):
                    yield loc.id, f"{phase}GestureMessage{lang}"


__all__ = [
    "KB_MAX_FILE_BYTES",
    "KB_MAX_TEXT_BYTES",
    "KB_MAX_CULTURAL_KEYS",
    "KB_MAX_CULTURAL_KEY_BYTES",
    "KB_MAX_TOUR_LOCATIONS",
    "KB_MAX_LOCATION_ID",
    "KB_MAX_ABS_COORDINATE",
    "LANGUAGES",
    "Pose",
    "Point3",
    "Messages",
    "Location",
    "KnowledgeBase",
    "KbConfiguration",
    "lint_kb",
    "load_kb",
    "load_config",
    "iter_placeholders",
    "schema_keys",
]
