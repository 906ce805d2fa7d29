"""XSD schemas of missions, validated with xmlschema.

Two schemas:
- `schema/btcpp_v4.xsd`, fixed: the structure of every BTCPP_format="4" file
  (root, BehaviorTree, include, TreeNodesModel and its port declarations);
- the mission schema written by :func:`mission_xsd`: one element per node ID
  the mission may use (built-in catalogue plus its TreeNodesModel), with the
  node's ports as typed attributes, the special attributes, and the number
  of children its kind takes. Like BehaviorTree.CPP's writeTreeXSD, but it
  also covers inout ports and the pre/post-condition attributes. Editors
  validate against it as the user types (`btgen xsd MISSION.xml`).
"""

from __future__ import annotations

import collections
import functools
import hashlib
import os
import re
from collections.abc import Iterable
from xml.sax.saxutils import quoteattr

import xmlschema
from lxml import etree

from btgen import resources
from btgen.diagnostics import Diagnostic, Loc
from btgen.frontend.xmlsource import Source, lxml_name
from btgen.lang.catalogue import (
    METADATA_ATTRIBUTES,
    POST_CONDITIONS,
    PRE_CONDITIONS,
    STATUS_READ_WHEN_TICKED,
    NodeSpec,
    PortSpec,
)
from btgen.lang.model import Mission

_XML_NAME = re.compile(r"^[A-Za-z_][-A-Za-z0-9_.]*$")
SCHEMA_DIR = str(resources.SCHEMA_DIR)


def _schema_path(name: str) -> str:
    return os.path.join(SCHEMA_DIR, name)


@functools.cache
def structure_schema() -> xmlschema.XMLSchema:
    return xmlschema.XMLSchema(_schema_path("btcpp_v4.xsd"))


def _reason(err: xmlschema.XMLSchemaValidationError) -> str:
    reason = (err.reason or str(err)).strip()
    reason = re.sub(r"\s+", " ", reason)
    m = re.match(r"Unexpected child with tag '([^']+)' at position \d+\.?(.*)", reason)
    if m:
        tail = m.group(2).strip()
        expected = re.search(r"Tag (\([^)]*\)|'[^']+') expected", tail)
        exp = ""
        if expected:
            names = re.findall(r"'([^']+)'", expected.group(1))
            exp = " (expected " + " or ".join(f"<{n}>" for n in names) + ")"
        return f"unexpected element <{m.group(1)}>{exp}"
    m = re.match(r"attribute (\S+)='([^']*)':", reason)
    if m:
        if m.group(2) == "" and m.group(1) == "ID":
            # <BehaviorTree ID="">: BehaviorTree.CPP "must have the attribute [ID]"
            return "attribute `ID` is empty: it must name the tree or node"
        return f"attribute `{m.group(1)}`: `{m.group(2)}` is not a valid value here"
    m = re.match(r"missing required attribute '([^']+)'", reason)
    if m:
        return f"missing required attribute `{m.group(1)}`"
    m = re.match(r"'([^']+)' attribute not allowed for element\.?", reason)
    if m:
        return f"attribute `{m.group(1)}` is not allowed here"
    m = re.match(r"The content of element '([^']+)' is not complete\.(.*)", reason)
    if m:
        return f"<{m.group(1)}> is incomplete:{m.group(2)}"
    return reason[0].lower() + reason[1:] if reason else "does not match the schema"


def _iter_diags(schema: xmlschema.XMLSchema, src: Source, root: etree._Element) -> list[Diagnostic]:
    out = []
    for err in schema.iter_errors(etree.ElementTree(root)):
        elem = getattr(err, "elem", None)
        loc = Loc(src.path, 1, 1)
        if elem is not None:
            try:
                loc = src.loc(elem)
            except KeyError:
                loc = Loc(src.path, getattr(elem, "sourceline", 1) or 1, 1)
            m = re.search(r"attribute '([^']+)'|'([^']+)' attribute|attribute (\S+)=", err.reason or "")
            name = (m.group(1) or m.group(2) or m.group(3)) if m else None
            if name and name in elem.attrib:
                loc = src.attr_loc(elem, name)
            elif "character data" in (err.reason or ""):  # at the text (or CDATA), not its parent
                loc = src.text_loc(elem)
        out.append(Diagnostic(loc, _reason(err)))
    return out


# What validating a file found, by (schema, shown path, text): `btgen check` loads a file once per
# mission that includes it (Nav2's models file, a tree library) and validates it against the same
# schema each time. Keyed by digests; bounded by the count of entries and of diagnostics in one; a
# Diagnostic is immutable.
_VALIDATED: collections.OrderedDict[tuple[str, str, bytes], tuple[Diagnostic, ...]] = collections.OrderedDict()
_VALIDATED_MAX = 1024
_VALIDATED_MAX_DIAGS = 64


def _digest(text: str) -> bytes:
    return hashlib.sha256(text.encode("utf-8", "surrogatepass")).digest()


def _validated(schema: xmlschema.XMLSchema, schema_key: str, src: Source) -> list[Diagnostic]:
    key = (schema_key, src.path, _digest(src.text))
    found = _VALIDATED.get(key)
    if found is None:
        found = tuple(_iter_diags(schema, src, src.root))
        if len(found) <= _VALIDATED_MAX_DIAGS:  # (a file with thousands of errors is not kept)
            _VALIDATED[key] = found
            if len(_VALIDATED) > _VALIDATED_MAX:
                _VALIDATED.popitem(last=False)
    else:
        _VALIDATED.move_to_end(key)
    return list(found)


def validate_structure(src: Source) -> list[Diagnostic]:
    """Check a file against schema/btcpp_v4.xsd."""
    return _validated(structure_schema(), "btcpp_v4.xsd", src)


# ---------------------------------------------------------------- mission XSD
_SIMPLE = {
    "int": ("union", "xs:int"),
    "unsigned": ("union", "xs:unsignedInt"),
    "double": ("union", "xs:double"),
}


def _type_ref(port: PortSpec, node_id: str = "", literal_writes: bool = False) -> str:
    t = port.type
    if node_id.startswith("Loop") and port.name == "queue":
        return "xs:string"  # untyped from 4.9.1, a literal queue or a {key} all the same
    if (node_id, port.name) in STATUS_READ_WHEN_TICKED:
        return "xs:string"  # converted when the node reads it: any text loads (the loader warns)
    if literal_writes and port.direction == "output":
        return "xs:string"  # a literal on the output port of a node the program registers loads (warned)
    if port.direction == "output" or (port.direction == "inout" and not t.startswith("queue<")):
        return "bt_key"
    return {
        "int": "bt_int",
        "unsigned": "bt_unsigned",
        "double": "bt_double",
        "bool": "bt_bool",
        "NodeStatus": "bt_status",
    }.get(t, "xs:string")


_PRELUDE = """  <xs:simpleType name="bt_ref">
    <xs:restriction base="xs:string"><xs:pattern value=" *\\{[\\s\\S]+\\} *"/></xs:restriction>
  </xs:simpleType>
  <xs:simpleType name="bt_key">
    <xs:restriction base="xs:string"><xs:pattern value=" *\\{[\\s\\S]+\\} *|\\{?@?[A-Za-z_][A-Za-z0-9_.:\\-]*\\}?"/></xs:restriction>
  </xs:simpleType>
  <xs:simpleType name="bt_int_prefix">
    <xs:restriction base="xs:string"><xs:pattern value="-?[0-9]+[\\s\\S]*"/></xs:restriction>
  </xs:simpleType>
  <xs:simpleType name="bt_double_prefix">
    <xs:restriction base="xs:string">
      <xs:pattern value="\\s*[+\\-]?([0-9]|\\.[0-9]|[iI][nN][fF]|[nN][aA][nN])[\\s\\S]*"/>
    </xs:restriction>
  </xs:simpleType>
  <xs:simpleType name="bt_int"><xs:union memberTypes="xs:int bt_int_prefix bt_ref"/></xs:simpleType>
  <xs:simpleType name="bt_unsigned"><xs:union memberTypes="xs:unsignedInt bt_int_prefix bt_ref"/></xs:simpleType>
  <xs:simpleType name="bt_double"><xs:union memberTypes="xs:double bt_double_prefix bt_ref"/></xs:simpleType>
  <xs:simpleType name="bt_bool_literal">
    <xs:restriction base="xs:string">
      <xs:enumeration value="true"/><xs:enumeration value="false"/><xs:enumeration value="True"/>
      <xs:enumeration value="False"/><xs:enumeration value="TRUE"/><xs:enumeration value="FALSE"/>
      <xs:enumeration value="1"/><xs:enumeration value="0"/>
    </xs:restriction>
  </xs:simpleType>
  <xs:simpleType name="bt_bool"><xs:union memberTypes="bt_bool_literal bt_ref"/></xs:simpleType>
  <xs:simpleType name="bt_status_literal">
    <xs:restriction base="xs:string">
      <xs:enumeration value="SUCCESS"/><xs:enumeration value="FAILURE"/><xs:enumeration value="SKIPPED"/>
      <xs:enumeration value="RUNNING"/><xs:enumeration value="IDLE"/>
    </xs:restriction>
  </xs:simpleType>
  <xs:simpleType name="bt_status"><xs:union memberTypes="bt_status_literal bt_ref"/></xs:simpleType>
  <xs:attributeGroup name="bt_common">
    <xs:attribute name="name" type="xs:string"/>
{specials}  </xs:attributeGroup>
"""


def _children(spec: NodeSpec) -> str:
    lo, hi = spec.min_children, spec.max_children
    if hi == 0:
        return ""
    hi_text = "unbounded" if hi is None else str(hi)
    return f'      <xs:element ref="bt_node" minOccurs="{lo}" maxOccurs="{hi_text}"/>\n'


def _node_type(spec: NodeSpec, lenient: bool, user: bool = False) -> str:
    mixed = ' mixed="true"' if lenient else ""
    lines = [f"  <xs:complexType name={quoteattr('node.' + lxml_name(spec.id))}{mixed}>\n"]
    kids = _children(spec)
    if kids:
        lines.append("    <xs:sequence>\n" + kids.replace("      ", "      ", 1) + "    </xs:sequence>\n")
    for p in spec.ports:
        use = ' use="required"' if p.required else ""
        ref = _type_ref(p, spec.id, literal_writes=lenient and user)
        if lenient and user and p.direction == "inout" and ref == "bt_key":
            ref = "xs:string"  # (read as a literal, as an input port: the loader checks and warns)
        lines.append(f'    <xs:attribute name={quoteattr(p.name)} type="{ref}"{use}/>\n')
    lines.append('    <xs:attributeGroup ref="bt_common"/>\n')
    if lenient:
        lines.append('    <xs:anyAttribute processContents="skip"/>\n')
    lines.append("  </xs:complexType>\n")
    return "".join(lines)


def mission_xsd(mission: Mission, lenient: bool = False, comment: bool = True) -> str:
    """The XSD for this mission's node elements (deterministic text).

    `lenient`: also accept what BehaviorTree.CPP ignores and the loader has already
    warned about (text between elements, attributes starting with `_`); the loader's
    backstop uses it, editors get the strict schema of `btgen xsd`. `comment`: the line that
    names the mission's file (without it, missions using the same nodes have the same text)."""
    specs: list[NodeSpec] = [s for s in mission.builtins.values() if s.id != "SubTree"]
    # An ID that is not an XML name (`IV. Act`) can only be written in the explicit
    # form <Action ID="IV. Act"/>, which the explicit.* types cover; one with a colon
    # (`arm:Grasp`) is declared, in the loader's backstop, under the name lxml was given
    # (xmlsource.undeclared_prefixes); editors read it as a namespace prefix.
    specs += [
        m
        for m in mission.models
        if m.kind != "SubTree" and _XML_NAME.match(m.id.replace(":", "_") if lenient else m.id)
    ]
    specials = "".join(
        f'    <xs:attribute name="{a}" type="xs:string"/>\n'
        for a in PRE_CONDITIONS + POST_CONDITIONS + METADATA_ATTRIBUTES
    )
    out = [
        '<?xml version="1.0" encoding="UTF-8"?>\n',
        f"<!-- Generated by btgen for {os.path.basename(mission.path)}: nodes and ports this mission may use. -->\n"
        if comment
        else "",
        '<xs:schema xmlns:xs="http://www.w3.org/2001/XMLSchema" elementFormDefault="qualified">\n',
        _PRELUDE.replace("{specials}", specials),
    ]
    # The root and file structure, as in schema/btcpp_v4.xsd, but with typed node content.
    out.append(
        """  <xs:element name="root">
    <xs:complexType{mixed}>
      <xs:choice minOccurs="0" maxOccurs="unbounded">
        <xs:element name="BehaviorTree">
          <xs:complexType{mixed}>
            <xs:sequence><xs:element ref="bt_node"/></xs:sequence>
            <xs:attribute name="ID" type="xs:string"/>
            <xs:anyAttribute processContents="skip"/>
          </xs:complexType>
        </xs:element>
        <xs:element name="include">
          <xs:complexType><xs:anyAttribute processContents="skip"/></xs:complexType>
        </xs:element>
        <xs:element name="TreeNodesModel">
          <xs:complexType>
            <xs:sequence><xs:any processContents="skip" minOccurs="0" maxOccurs="unbounded"/></xs:sequence>
          </xs:complexType>
        </xs:element>
      </xs:choice>
      <xs:anyAttribute processContents="skip"/>
    </xs:complexType>
  </xs:element>
""".replace("{mixed}", ' mixed="true"' if lenient else "")
    )
    # Every node element stands for the abstract `bt_node` (a substitution group
    # matches in one step, where a 50-way choice would be tried in turn).
    # Its name is one no node of this mission has (a model may be called `bt_node`).
    ids = {s.id for s in specs}
    group = next(n for n in ("bt_node", *(f"bt_node_{i}" for i in range(1, len(ids) + 2))) if n not in ids)
    out.append(f'  <xs:element name="{group}" abstract="true"/>\n')
    for s in specs:
        out.append(
            f"  <xs:element name={quoteattr(lxml_name(s.id))} type={quoteattr('node.' + lxml_name(s.id))} "
            f'substitutionGroup="{group}"/>\n'
        )
    for kind in ("Action", "Condition", "Control", "Decorator", "SubTree"):
        out.append(f'  <xs:element name="{kind}" type="explicit.{kind}" substitutionGroup="{group}"/>\n')
    for s in specs:
        out.append(_node_type(s, lenient, user=s.id not in mission.builtins))
    for kind, kids in (
        ("Action", ""),
        ("Condition", ""),
        ("Control", '      <xs:element ref="bt_node" minOccurs="1" maxOccurs="unbounded"/>\n'),
        ("Decorator", '      <xs:element ref="bt_node" minOccurs="1" maxOccurs="1"/>\n'),
        ("SubTree", ""),
    ):
        seq = f"    <xs:sequence>\n{kids}    </xs:sequence>\n" if kids else ""
        mixed = ' mixed="true"' if lenient else ""
        out.append(
            f'  <xs:complexType name="explicit.{kind}"{mixed}>\n{seq}'
            '    <xs:attribute name="ID" type="xs:string" use="required"/>\n'
            '    <xs:anyAttribute processContents="skip"/>\n  </xs:complexType>\n'
        )
    out.append("</xs:schema>\n")
    return "".join(out).replace('ref="bt_node"', f'ref="{group}"')


@functools.lru_cache(maxsize=32)
def _compiled(xsd_text: str) -> xmlschema.XMLSchema:
    # The text is btgen's own (mission_xsd): xmlschema's check of a schema against the XSD
    # meta-schema, 80% of compiling one, is left out (`validation="skip"`); the tests compile
    # the schemas of every shipped and recorded mission with it (test_check_speed.py), and the
    # files validate the same against either.
    return xmlschema.XMLSchema(xsd_text, validation="skip")


def mission_schema(mission: Mission) -> xmlschema.XMLSchema:
    """The compiled per-mission XSD (the same for every file of the mission: build it once, and
    once for the missions that use the same nodes: the text without its comment naming the file)."""
    return _compiled(mission_xsd(mission, lenient=True, comment=False))


def validate_against_mission_xsd(mission: Mission, src: Source) -> Iterable[Diagnostic]:
    text = mission_xsd(mission, lenient=True, comment=False)
    return _validated(_compiled(text), _digest(text).hex(), src)
