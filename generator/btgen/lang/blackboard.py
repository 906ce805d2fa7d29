"""Blackboards with BehaviorTree.CPP 4.6.2 semantics (``blackboard.h/.cpp``).

A :class:`Blackboard` holds :class:`Entry` objects by key. An entry has a
declared type (a canonical name from :mod:`btgen.lang.values`; ``any`` for 4.6.2's
``AnyTypeAllowed``), a value (``None`` until first written) and an update
counter, ``sequence_id``, that every write bumps. Entries are shared objects:
a SubTree blackboard that remaps ``goal`` to its parent's ``target`` hands out
the parent's very entry, as 4.6.2 shares ``shared_ptr<Entry>``.

Key lookup (:meth:`Blackboard.get_entry`), in 4.6.2's order:

1. ``@key`` always means ``key`` on the root blackboard;
2. an entry stored on this blackboard;
3. an explicit SubTree remapping (``port="{parent_key}"``) to the parent;
4. with ``_autoremap``, the same key on the parent, except private keys
   (starting with ``_``);
5. otherwise there is no entry.

The module also has what nodes need to read and write ports the way
``TreeNode::getInput``/``setOutput`` do, and what the XML loader does when
it builds a tree (:func:`create_port_entry`, :meth:`Blackboard.for_subtree`).
Errors raise :class:`BlackboardError`.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Optional

from btgen.lang import values
from btgen.lang.catalogue import ENTRY_PORTS
from btgen.lang.hashorder import HashOrder
from btgen.lang.values import ANY, STRING, ConversionError, Value

# An entry typed BT::Any: what 4.7.0's SetBlackboard leaves when it writes a string into an
# entry created untyped (versions.py setblackboard_converts_to_entry_type). Not strongly
# typed; its "converter" always fails.
ANY_TYPED = "BT::Any"


class BlackboardError(Exception):
    """A blackboard or port operation that 4.6.2 rejects (it throws there). `stdout`: what the
    library prints before it throws (Blackboard::debugMessage), part of the trace."""

    def __init__(self, message: str, stdout: str = "") -> None:
        super().__init__(message)
        self.message = message
        self.stdout = stdout


# The type names Blackboard::debugMessage prints (BT::demangle with libstdc++), by declared type.
CPP_TYPE_NAMES = {
    values.ANY: "BT::AnyTypeAllowed",
    ANY_TYPED: "BT::Any",
    values.INT: "int",
    values.UNSIGNED: "unsigned int",
    values.DOUBLE: "double",
    values.BOOL: "bool",
    values.STRING: "std::string",  # (BT::demangle names it so)
    values.NODE_STATUS: "BT::NodeStatus",
}
# The type an integer a script stored has (int64_t), where values.type_of says `int`; only
# 4.7.0's SetBlackboard (Blackboard::set<BT::Any> into a typed entry) tells them apart.
INT64 = "int64"


class Entry:
    """One blackboard entry: declared type, value (None: not written yet), update counter."""

    __slots__ = ("type_name", "value", "sequence_id", "double_from_chars", "held_int32")

    def __init__(
        self, type_name: str, value: Optional[Value] = None, sequence_id: int = 0, double_from_chars: bool = False
    ) -> None:
        self.type_name = type_name
        self.value = value
        self.sequence_id = sequence_id
        # the release's convertFromString<double> (versions.Semantics.double_from_chars)
        self.double_from_chars = double_from_chars
        # An integer this untyped entry holds is an `int` (copied from an int entry by 4.7.0's
        # SetBlackboard), not a script's int64_t (set_blackboard_410)
        self.held_int32 = False

    @property
    def strongly_typed(self) -> bool:
        return values.is_strongly_typed(self.type_name) and self.type_name != ANY_TYPED

    @property
    def has_converter(self) -> bool:
        """Whether 4.6.2 gives the entry a string converter (its type's convertFromString).

        ``any`` has none, and neither has ``NodeStatus``: 4.6.2 gives enums no
        converter (``GetAnyFromStringFunctor``).
        """
        return self.type_name not in (ANY, values.NODE_STATUS)

    def convert(self, text: str) -> Value:
        """The entry's string converter applied to ``text``; raises ConversionError."""
        if self.type_name == ANY_TYPED:
            raise ConversionError(
                f"cannot convert {values.describe(text)} to BT::Any: the library has no convertFromString for BT::Any"
            )
        return values.convert_from_string(self.type_name, text, double_from_chars=self.double_from_chars)

    def bump(self) -> None:
        self.sequence_id += 1

    def __repr__(self) -> str:
        return f"Entry({self.type_name!r}, {self.value!r}, sequence_id={self.sequence_id})"


def _is_private(key: str) -> bool:
    return key.startswith("_")


class Blackboard:
    """A blackboard, optionally the child of a SubTree's parent blackboard."""

    def __init__(
        self,
        parent: Optional[Blackboard] = None,
        *,
        autoremap: bool = False,
        double_from_chars: Optional[bool] = None,
        false_into_int_unsafe: Optional[bool] = None,
    ) -> None:
        self.parent = parent
        self.autoremap = autoremap
        # The release's convertFromString<double>, which every entry's converter and every port
        # read use (versions.Semantics.double_from_chars); a SubTree's blackboard inherits it.
        if double_from_chars is None:
            double_from_chars = parent.double_from_chars if parent is not None else False
        self.double_from_chars: bool = double_from_chars
        # versions.Semantics.false_into_int_unsafe (set<bool>(false) into an int entry throws)
        if false_into_int_unsafe is None:
            false_into_int_unsafe = parent.false_into_int_unsafe if parent is not None else False
        self.false_into_int_unsafe: bool = false_into_int_unsafe
        self._storage: dict[str, Entry] = {}
        self._remapping: dict[str, str] = {}
        # the order std::unordered_map keeps storage_ and internal_to_external_ in (debug_message)
        self._order = HashOrder()
        self._remap_order = HashOrder()

    # ----------------------------------------------------------- structure
    @property
    def root(self) -> Blackboard:
        bb = self
        while bb.parent is not None:
            bb = bb.parent
        return bb

    def add_remapping(self, internal: str, external: str) -> None:
        """``internal`` on this blackboard means ``external`` on the parent."""
        self._remapping[internal] = external
        self._remap_order.insert(internal)

    @property
    def remapping(self) -> dict[str, str]:
        return dict(self._remapping)

    def local_keys(self) -> tuple[str, ...]:
        """Keys stored on this blackboard itself (not reached through remapping)."""
        return tuple(self._storage)

    def local_entry(self, key: str) -> Optional[Entry]:
        """The entry stored on this blackboard itself under `key` (no remapping, no `@`)."""
        return self._storage.get(key)

    @classmethod
    def for_subtree(
        cls, parent: Blackboard, ports: Iterable[tuple[str, str]], autoremap: bool = False, typed_literals: bool = False
    ) -> Blackboard:
        """The blackboard 4.6.2's XML loader makes for a SubTree instance.

        ``ports`` are the SubTree element's port attributes (name, value),
        with any TreeNodesModel defaults already added. ``{=}`` means
        ``{name}``; ``{key}`` remaps ``name`` to the parent's ``key``; any
        other value is a constant: a local ``name`` entry holding that string
        (never autoremapped), as ``Blackboard::set<std::string>`` creates it;
        with ``typed_literals`` (4.9.1, versions.py subtree_literals_typed) a
        text that is wholly an integer is stored as an int, one that is wholly
        a real (std::from_chars) as a double.
        """
        bb = cls(parent, autoremap=autoremap)
        for name, value in ports:
            if value == "{=}":
                value = "{" + name + "}"
            key = strip_blackboard_pointer(value)
            if key is not None:
                bb.add_remapping(name, key)
            else:
                bb.autoremap = False
                typed = typed_literal(value) if typed_literals else None
                if typed is None:
                    bb.set(name, value, STRING)
                else:
                    bb.set(name, typed, values.type_of(typed))
                bb.autoremap = autoremap
        return bb

    # ---------------------------------------------------------------- look-up
    def get_entry(self, key: str) -> Optional[Entry]:
        """The entry ``key`` names from here, or None (4.6.2 ``getEntry``)."""
        if key.startswith("@"):
            return self.root.get_entry(key[1:])
        entry = self._storage.get(key)
        if entry is not None:
            return entry
        if self.parent is not None:
            if key in self._remapping:
                return self.parent.get_entry(self._remapping[key])
            if self.autoremap and not _is_private(key):
                return self.parent.get_entry(key)
        return None

    def get(self, key: str) -> Value:
        """The value of ``key``; raises when there is no entry or it has no value yet."""
        entry = self.get_entry(key)
        if entry is None:
            raise BlackboardError(f"no blackboard entry `{key}`")
        if entry.value is None:
            raise BlackboardError(f"blackboard entry `{key}` has no value yet")
        return entry.value

    # --------------------------------------------------------------- creation
    def create_entry(self, key: str, type_name: str) -> Entry:
        """Create ``key`` with a declared type, or return the entry it already names.

        As 4.6.2 ``createEntry``: ``@key`` creates on the root; a remapped or
        autoremapped key creates on the parent. An existing entry keeps its
        type, but two different strong types are an error.
        """
        if key.startswith("@"):
            if "@" in key[1:]:
                raise BlackboardError(f"`{key}`: the character `@` may appear only once, at the start of a key")
            return self.root._create_entry_impl(key[1:], type_name)
        return self._create_entry_impl(key, type_name)

    def _create_entry_impl(self, key: str, type_name: str) -> Entry:
        entry = self._storage.get(key)
        if entry is not None:
            if entry.type_name != type_name and entry.strongly_typed and values.is_strongly_typed(type_name):
                raise BlackboardError(
                    f"blackboard entry `{key}` is declared as {entry.type_name}; it cannot be used as {type_name}"
                )
            return entry
        if key in self._remapping:
            if self.parent is None:
                raise BlackboardError(f"`{key}` is remapped but the blackboard has no parent")
            # An `@key` target goes to the root (4.6.2 misplaces it; fixed later, #1192).
            return self.parent.create_entry(self._remapping[key], type_name)
        if self.autoremap and not _is_private(key):
            if self.parent is None:
                raise BlackboardError(f"`{key}` is autoremapped but the blackboard has no parent")
            return self.parent._create_entry_impl(key, type_name)
        entry = Entry(type_name, double_from_chars=self.double_from_chars)
        self._storage[key] = entry
        self._order.insert(key)
        return entry

    # ------------------------------------------------------------------ writes
    def set(self, key: str, value: Value, type_name: Optional[str] = None) -> Entry:
        """Write ``value`` as 4.6.2 ``Blackboard::set<T>`` does; returns the entry.

        ``type_name`` is T, the C++ type the writer uses (default: the value's
        own type); ``any`` stands for ``set<BT::Any>`` (what SetBlackboard
        uses). Every write bumps ``sequence_id``.

        - No entry stored on this blackboard: the entry is created (through
          remapping if the key is remapped) with type T, except that a string
          creates an ``any`` entry and ``set<Any>`` uses the value's type, and
          the value is stored as is.
        - An ``any`` entry stored here takes type T (stays ``any`` for
          ``set<Any>``) and the value.
        - A typed entry stored here accepts a value of its type; a string
          converted by the entry's converter; a number that fits
          (``isCastingSafe``); anything else is an error. The value is then
          copied into the entry (``Any::copyInto``).
        """
        if key.startswith("@"):
            return self.root.set(key[1:], value, type_name)
        t = type_name if type_name is not None else values.type_of(value)
        if t in (values.INT, values.UNSIGNED) and isinstance(value, int) and not isinstance(value, bool):
            try:
                values.cast(value, t)  # a C++ `int`/`unsigned` cannot hold more
            except ConversionError as e:
                raise BlackboardError(f"cannot write {value} to `{key}`: {e}") from None
        entry = self._storage.get(key)
        if entry is None:
            if t == STRING:
                new_type = ANY
            elif t == ANY:
                new_type = values.type_of(value)
            else:
                new_type = t
            entry = self._create_entry_impl(key, new_type)
            entry.value = value
            entry.bump()
            return entry
        if not entry.strongly_typed:
            entry.type_name = t  # set<BT::Any> leaves it generic (BT::Any is not a strong type)
            entry.value = value
            entry.bump()
            return entry
        new_value = value
        value_type = values.type_of(value) if t == ANY else t
        if entry.type_name != value_type:
            mismatching = True
            if t == STRING and entry.has_converter:
                try:
                    new_value = entry.convert(value)  # type: ignore[arg-type]
                    mismatching = False
                except ConversionError as e:
                    raise BlackboardError(
                        f"cannot write {values.describe(value)} to `{key}` ({entry.type_name}): {e}"
                    ) from None
            if (
                mismatching
                and t in (values.INT, values.UNSIGNED, values.DOUBLE, values.BOOL)
                and values.is_casting_safe(entry.type_name, value)
                and not (self.false_into_int_unsafe and value is False and entry.type_name == values.INT)
            ):
                mismatching = False
            if mismatching:
                raise BlackboardError(
                    f"blackboard entry `{key}` is declared as {entry.type_name}; it cannot be written with a {t}"
                )
        if t == ANY:
            entry.value = new_value
        else:
            try:
                entry.value = values.copy_into(new_value, entry.value)
            except ConversionError as e:
                raise BlackboardError(f"cannot write {values.describe(value)} to `{key}`: {e}") from None
        entry.bump()
        return entry

    def unset(self, key: str) -> None:
        """Remove ``key`` from this blackboard's own storage (4.6.2 ``unset``).

        As in 4.6.2, a key reached only through remapping (or written with
        `@`) is not removed, and a missing key is no error.
        """
        if self._storage.pop(key, None) is not None:
            self._order.erase(key)

    def storage_order(self) -> list[str]:
        """The keys of this blackboard's own storage in the order the library keeps them."""
        return self._order.order()

    def debug_message(self) -> str:
        """What ``Blackboard::debugMessage`` prints: every entry with its type, in the order of
        libstdc++'s unordered_map (hashorder.py), then the SubTree remappings."""
        lines = []
        for key in self._order.order():
            entry = self._storage[key]
            lines.append(f"{key} ({CPP_TYPE_NAMES.get(entry.type_name, entry.type_name)})\n")
        for internal in self._remap_order.order():
            external = self._remapping[internal]
            line = f"[{internal}] remapped to port of parent tree [{external}]"
            target = self.parent.get_entry(external) if self.parent is not None else None
            if target is not None:
                line += f" ({CPP_TYPE_NAMES.get(target.type_name, target.type_name)})"
            lines.append(line + "\n")
        return "".join(lines)


# ------------------------------------------------------------ port helpers


def typed_literal(text: str) -> Optional[Value]:
    """4.9.1's reading of a SubTree literal port: an int when the whole text is an integer
    (no `.`, `e`, `E`), a double when it is wholly a real for std::from_chars, else None."""
    if not text:
        return None
    if not any(c in text for c in ".eE") and values.FROM_CHARS_INT_RE.fullmatch(text):
        n = int(text)
        if values.INT64_MIN <= n <= values.INT64_MAX:
            return n
    try:
        return values.convert_from_string(values.DOUBLE, text, strict=True, double_from_chars=True)
    except ConversionError:
        return None


def is_blackboard_pointer(text: str) -> bool:
    """4.6.2 ``isBlackboardPointer``: ``{key}`` with optional blanks around it."""
    return strip_blackboard_pointer(text) is not None


def strip_blackboard_pointer(text: str) -> Optional[str]:
    """``key`` for ``{key}`` (spaces around the braces ignored, not inside), else None."""
    stripped = text.strip(" ")
    if len(stripped) >= 3 and stripped[0] == "{" and stripped[-1] == "}":
        return stripped[1:-1]
    return None


def remapped_key(port_name: str, text: str) -> Optional[str]:
    """4.6.2 ``getRemappedKey``: the entry a port value names, or None for a literal.

    ``{=}`` and ``=`` name the entry called like the port.
    """
    if text in ("{=}", "="):
        if not port_name:
            raise BlackboardError(f"`{text}` needs the port name")
        return port_name
    return strip_blackboard_pointer(text)


def get_input(bb: Blackboard, port_value_text: str, port_type: str, port_name: str = "") -> Value:
    """Read a port as 4.6.2 ``TreeNode::getInput<T>`` with T = ``port_type``.

    A literal is converted with ``convertFromString``. A ``{key}`` reads the
    entry: a string value is converted with ``convertFromString`` unless T
    is ``string``, any other value with ``Any::cast``; an ``any`` port gets
    the value as stored. A missing entry, or one without a value yet, is an
    error, as is a failed conversion.
    """
    key = remapped_key(port_name, port_value_text)
    what = f"port `{port_name}`" if port_name else "port"
    if key is None:
        try:
            return values.convert_from_string(port_type, port_value_text, double_from_chars=bb.double_from_chars)
        except ConversionError as e:
            raise BlackboardError(f"{what}: {e}") from None
    entry = bb.get_entry(key)
    if entry is None or entry.value is None:
        state = "does not exist" if entry is None else "has no value yet"
        raise BlackboardError(f"{what} reads blackboard entry `{key}`, which {state}")
    value = entry.value
    try:
        if port_type == ANY:
            return value
        if port_type != STRING and isinstance(value, str):
            return values.convert_from_string(port_type, value, double_from_chars=bb.double_from_chars)
        return values.cast(value, port_type)
    except ConversionError as e:
        raise BlackboardError(f"{what} reads blackboard entry `{key}`: {e}") from None


def set_output(bb: Blackboard, port_value_text: str, value: Value, port_type: str, port_name: str = "") -> Entry:
    """Write a port as 4.6.2 ``TreeNode::setOutput<T>`` with T = ``port_type``.

    The port must name an entry (``{key}``, ``{=}``); a literal is an error.
    """
    key = remapped_key(port_name, port_value_text)
    if key is None:
        what = f"output port `{port_name}`" if port_name else "an output port"
        raise BlackboardError(f"{what} must name a blackboard entry, as `{{key}}`, not `{port_value_text}`")
    t = port_type if port_type != ANY else values.type_of(value)
    return bb.set(key, value, t)


def create_port_entry(
    bb: Blackboard, port_value_text: str, port_type: str, port_name: str = "", node_id: str = ""
) -> Optional[Entry]:
    """What 4.6.2's XML loader does for one port of a node it creates.

    A port naming an entry (``{key}``, ``{=}``) creates that entry with the
    port's type when it does not exist yet (no value, ``sequence_id`` 0). If
    it exists, two different strong types are an error unless the existing
    entry is a ``string`` (4.6.2 converts strings on reading). Literal ports
    create nothing (None). The `entry` port of WasEntryUpdated, SkipUnlessUpdated and
    WaitValueUpdate (node `node_id`) is declared ``InputPort<BT::Any>``: its entry is typed
    BT::Any (:data:`ANY_TYPED`: not strongly typed, and its string converter throws, so a
    script storing a string there throws).
    """
    key = remapped_key(port_name, port_value_text)
    if key is None:
        return None
    if (node_id, port_name) in ENTRY_PORTS:
        port_type = ANY_TYPED
    entry = bb.get_entry(key)
    if entry is not None:
        if (
            entry.strongly_typed
            and port_type != ANY_TYPED
            and values.is_strongly_typed(port_type)
            and entry.type_name != port_type
            and entry.type_name != STRING
        ):
            raise BlackboardError(
                f"blackboard entry `{key}` was created as {entry.type_name}, "
                f"but port `{port_name}` uses it as {port_type}"
            )
        return entry
    return bb.create_entry(key, port_type)


# SetBlackboard value="{src}" when `src` exists but holds no value yet (a remapped port
# created it): BehaviorTree.CPP 4.6.2 copies the empty value (the destination loses its
# value, its update counter stays) and succeeds; 4.7.0 and later fail the node. The one
# place this rule lives for 4.6.2: both engines read it (dataflow.py passes it to the C++
# template); 4.10.0 is versions.py setblackboard_converts_to_entry_type.
EMPTY_COPY_SUCCEEDS = True  # BehaviorTree.CPP 4.6.2


# The declared types of the entries a 4.6.2 SetBlackboard copy leaves holding a string as it
# is (the C++ back end gives them a dynamic slot: ir/data/types.py).
RAW_COPY_TYPES = (values.INT, values.UNSIGNED, values.DOUBLE, values.BOOL)


def set_blackboard(bb: Blackboard, output_key: str, value_text: str) -> bool:
    """The SetBlackboard action: write ``value_text`` (or the entry it names) to ``output_key``.

    A literal is written as 4.6.2 does, with ``set<std::string>`` (a typed
    entry converts it; an ``any`` one stores the string). ``{key}`` copies
    that entry's value; the destination is created with the source's type
    if missing, a string is copied as it is into a typed one, and the copy
    bumps the destination's update counter (4.7.0 behaviour, see FORMAT.md;
    4.6.2 copied the counter along). A source with no value yet empties the
    destination and succeeds, or returns False (the node fails), as
    EMPTY_COPY_SUCCEEDS says; a missing source is an error.
    """
    src_key = strip_blackboard_pointer(value_text)
    if src_key is None:
        bb.set(output_key, value_text, STRING)
        return True
    src = bb.get_entry(src_key)
    if src is None:
        raise BlackboardError(f"SetBlackboard: `value` reads blackboard entry `{src_key}`, which does not exist")
    dst = bb.get_entry(output_key)
    if dst is None:
        dst = bb.create_entry(output_key, src.type_name)
    if src.value is None:
        if not EMPTY_COPY_SUCCEEDS:
            return False
        dst.value = None
        return True
    out = src.value
    # set<BT::Any>; this module's values do not tell unsigned from int, the entry that holds one
    # does: a value converted for the destination, or copied from an unsigned entry, has that type
    written = values.UNSIGNED if src.type_name == values.UNSIGNED else ANY
    if dst.type_name in RAW_COPY_TYPES and isinstance(out, str):
        # 4.6.2 copies the value as it is (`dst_entry->value = src_entry->value`): the entry
        # keeps its type and holds the string (recorded: tests/conformance/conversions set_copy_*).
        # (Queue, NodeStatus and user-typed destinations still convert: not followed yet.)
        dst.value = out
        dst.bump()
        return True
    if dst.strongly_typed and (dst.type_name == STRING or not isinstance(out, str)):
        # Any other value is copied as it is too: the entry keeps its declared type and holds the
        # source's value (recorded: tests/conformance/changing-types/, a number into an entry a
        # port declared string or double); reading it then casts (Any::cast), as the library does.
        dst.value = out
        dst.bump()
        return True
    if dst.strongly_typed and dst.type_name != STRING and isinstance(out, str):
        if not dst.has_converter:
            raise BlackboardError(f"SetBlackboard: cannot convert {values.describe(out)} to {dst.type_name}")
        try:
            out = dst.convert(out)
        except ConversionError as e:
            raise BlackboardError(f"SetBlackboard: {e}") from None
        written = dst.type_name
    bt_any = dst.type_name == ANY_TYPED
    entry = bb.set(output_key, out, written)
    if bt_any and entry is dst:
        entry.type_name = ANY_TYPED  # a raw copy (dst->value = src->value) keeps the entry's type
    return True


def set_blackboard_410(bb: Blackboard, output_key: str, value_text: str) -> bool:
    """The SetBlackboard action of 4.7.0 and later (versions.py
    setblackboard_converts_to_entry_type); returns False when the node fails.

    The value (the literal, or a copy of the ``{key}`` entry's value) is
    empty: FAILURE. A string written into an existing entry whose type is not
    a string is converted by that entry's converter; an entry created untyped
    has none, so it receives an empty value and becomes typed BT::Any, whose
    converter then fails on the next string (the library throws). The write
    is ``Blackboard::set<BT::Any>``: a new local entry takes the value's type;
    an untyped local entry becomes BT::Any; a typed one must get its own type.
    """
    dst = bb.get_entry(output_key)
    src_key = strip_blackboard_pointer(value_text)
    out: Optional[Value]
    # The type BT::Any keeps with the value (its original type), where the value alone does not
    # tell it: this module's values do not tell unsigned from int, the entry that holds one does.
    out_type: Optional[str] = None
    # An integer copied from an untyped entry is a script's int64_t (Entry.held_int32)
    int64 = False
    if src_key is not None:
        src = bb.get_entry(src_key)
        if src is None:
            raise BlackboardError(f"SetBlackboard: `value` reads blackboard entry `{src_key}`, which does not exist")
        if dst is None:
            dst = bb.create_entry(output_key, src.type_name)
        out = src.value
        if src.type_name == values.UNSIGNED:
            out_type = values.UNSIGNED
        int64 = out is not None and values.type_of(out) == values.INT and not src.strongly_typed and not src.held_int32
    else:
        out = value_text
    if out is None:
        return False
    if dst is not None and dst.type_name != STRING and isinstance(out, str):
        if not dst.has_converter:
            out = None  # TypeInfo::parseString without a converter: an empty value
        else:
            try:
                out = dst.convert(out)
            except ConversionError as e:
                raise BlackboardError(f"SetBlackboard: cannot convert {values.describe(value_text)}: {e}") from None
            out_type = dst.type_name  # TypeInfo::parseString gives an Any of the entry's type
    key = output_key
    target = bb
    if key.startswith("@"):
        target, key = bb.root, key[1:]
    written = out_type if out_type is not None else values.type_of(out) if out is not None else ANY
    local = target._storage.get(key)
    held_int32 = out is not None and values.type_of(out) == values.INT and not int64
    if local is None:
        entry = target._create_entry_impl(key, written)
        entry.value = out
        entry.held_int32 = held_int32
        entry.bump()
        return True
    if not local.strongly_typed:
        local.type_name = ANY_TYPED
        local.value = out
        local.held_int32 = held_int32
        local.bump()
        return True
    if int64 and out_type is None and local.type_name in RAW_COPY_TYPES:
        written = INT64  # (an `int` entry refuses it too; another entry refuses any integer)
    if out is not None and local.type_name != written and not values.is_opaque_type(local.type_name):
        # Blackboard::set prints the blackboard (debugMessage) before it throws. (Followed for the
        # entries RAW_COPY_TYPES names; into a std::string entry too in the library, which neither
        # engine prints yet: recorded by hand, `SetBlackboard value="{n}"` into an entry a literal
        # typed std::string.)
        raise BlackboardError(
            f"SetBlackboard: blackboard entry `{output_key}` is declared as {local.type_name}; "
            f"it cannot be written with a {written}",
            target.debug_message() if local.type_name in RAW_COPY_TYPES else "",
        )
    if out is None and local.type_name == values.NODE_STATUS and isinstance(value_text, str):
        # A string into an entry a port typed NodeStatus: no converter, so an empty value
        # (BT::Any), which the typed entry refuses (recorded: oracle-diff/set_text_into_status_entry)
        raise BlackboardError(
            f"SetBlackboard: blackboard entry `{output_key}` is declared as NodeStatus; a string converts "
            f"to no value there (no converter), and the entry cannot be written with an empty value"
        )
    local.value = out
    local.bump()
    return True
