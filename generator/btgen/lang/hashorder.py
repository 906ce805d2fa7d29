"""The iteration order of a BehaviorTree.CPP blackboard's ``storage_``.

``Blackboard::debugMessage`` (4.10.0 prints it on stdout before ``Blackboard::set`` throws
"once declared, the type of a port shall not change") walks ``storage_``, a
``std::unordered_map<std::string, std::shared_ptr<Entry>>``, in the order libstdc++ keeps its
nodes. That order depends on the keys' hashes and on the whole history of insertions and
erasures, which :class:`HashOrder` replays:

- ``std::hash<std::string>`` is ``std::_Hash_bytes(data, size, 0xc70f6907)`` (64 bits);
- the first insertion allocates 13 buckets; an insertion that would make the size exceed the
  bucket count rehashes to the next count of :data:`BUCKET_COUNTS` (measured on this machine's
  libstdc++, the one the oracle builds use);
- a node inserted into an empty bucket goes to the front of the list, one inserted into a
  bucket that holds nodes goes before that bucket's first node; a rehash re-inserts the nodes
  in list order by the same rule; an erasure unlinks the node.

Checked against libstdc++ itself by tests/python/test_hashorder.py.
"""

from __future__ import annotations

from typing import Optional

_MASK = (1 << 64) - 1
_MUL = (0xC6A4A793 << 32) + 0x5BD1E995
_SEED = 0xC70F6907

# The bucket counts libstdc++'s prime rehash policy goes through (max_load_factor 1).
BUCKET_COUNTS = (13, 29, 59, 127, 257, 541, 1109, 2357, 5087, 10273, 20753, 42043, 85229, 172933, 351061)


def _shift_mix(v: int) -> int:
    return v ^ (v >> 47)


def std_hash(key: str) -> int:
    """``std::hash<std::string>`` of libstdc++ on a 64-bit machine (``_Hash_bytes``)."""
    buf = key.encode("utf-8", "surrogateescape")
    n = len(buf)
    h = (_SEED ^ (n * _MUL)) & _MASK
    aligned = n & ~7
    for i in range(0, aligned, 8):
        data = (_shift_mix((int.from_bytes(buf[i : i + 8], "little") * _MUL) & _MASK) * _MUL) & _MASK
        h ^= data
        h = (h * _MUL) & _MASK
    if n & 7:
        h ^= int.from_bytes(buf[aligned:], "little")
        h = (h * _MUL) & _MASK
    h = (_shift_mix(h) * _MUL) & _MASK
    return _shift_mix(h)


class HashOrder:
    """The node list of one ``std::unordered_map<std::string, ...>`` (keys only)."""

    __slots__ = ("buckets", "keys")

    def __init__(self) -> None:
        self.buckets = 0  # no bucket array allocated yet
        self.keys: list[str] = []

    def _place(self, keys: list[str], key: str, buckets: int) -> None:
        b = std_hash(key) % buckets
        for i, k in enumerate(keys):
            if std_hash(k) % buckets == b:
                keys.insert(i, key)  # before the first node of its bucket
                return
        keys.insert(0, key)

    def insert(self, key: str) -> None:
        if key in self.keys:
            return
        if self.buckets == 0:
            self.buckets = BUCKET_COUNTS[0]
        elif len(self.keys) + 1 > self.buckets:
            nxt: Optional[int] = next((c for c in BUCKET_COUNTS if c >= 2 * self.buckets), None)
            if nxt is None:
                raise ValueError("a blackboard larger than this table of bucket counts")
            self.buckets = nxt
            old, self.keys = self.keys, []
            for k in old:
                self._place(self.keys, k, self.buckets)
        self._place(self.keys, key, self.buckets)

    def erase(self, key: str) -> None:
        if key in self.keys:
            self.keys.remove(key)

    def order(self) -> list[str]:
        return list(self.keys)


def order_of(history: list[tuple[str, bool]]) -> list[str]:
    """The order after a history of (key, inserted: True / erased: False)."""
    h = HashOrder()
    for key, inserted in history:
        if inserted:
            h.insert(key)
        else:
            h.erase(key)
    return h.order()
