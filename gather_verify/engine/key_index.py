"""The visited set of the bulk engines: state keys in id order and a hash index over them.

A bulk search numbers its states in BFS order and must find, for a whole array of
successor keys at once, the id of each one already met and the next ids for the new
ones, in order of first occurrence (the order the reference explorer gives them).
:class:`KeyIndex` does that with ``uint64`` keys in a column and an open-addressing
table of ``int32`` ids, probed a whole array at a time (numpy, with a tag byte per slot) or
in compiled code (:func:`gather_verify.kernels.find_or_add`, same ids in the same order: the
tag in the slot's high bits while the ids fit :data:`TAGGED_IDS` bits, and repeats within a
call found first in a small table of that call's keys). It is shared
by the bulk explorer (:mod:`~gather_verify.engine.fast_explore`), its facts table (one
row per configuration key), the union engine and the finite worlds' bulk search.
"""

from __future__ import annotations

import numpy as np

from gather_verify import kernels

LOAD = 0.7
"""Largest load factor of the hash table before it grows."""
FOURFOLD_BELOW = 20
"""A table of fewer than ``2**FOURFOLD_BELOW`` slots (4 MB) grows fourfold, a larger one
twofold: each growth places every stored key again, and a small table's extra room costs
little."""
TAGGED_IDS = 24
"""The compiled table's slots keep 7 bits of their key's hash above the id while the ids
fit this many bits (:func:`gather_verify.kernels.find_or_add`)."""
_MUL = np.uint64(0x9E3779B97F4A7C15)
_TAG_BITS = np.uint64(8)
_BYTES = np.uint64(0x0101010101010101)
_HIGH = np.uint64(0x8080808080808080)
_ZERO, _ONE, _3 = np.uint64(0), np.uint64(1), np.uint64(3)
_U8_3, _U8_8 = np.uint8(3), np.uint8(8)


class KeyIndex:
    """Visited states: ``uint64`` keys in id order and a linear-probing table of ids.

    In the numpy path, beside each slot, a one-byte tag (0: empty; else 8 more bits of the
    key's hash) rejects most occupied slots without reading the key column; the tags are
    read eight slots at a time (one aligned ``uint64`` word, a group of slots). The
    compiled path keeps 7 such bits in the slot itself, above the id.

    >>> ix = KeyIndex()
    >>> ids, first = ix.find_or_add(np.array([7, 3, 9], dtype=np.uint64))
    >>> ids.tolist(), first.tolist()
    ([0, 1, 2], [0, 1, 2])
    >>> ids, first = ix.find_or_add(np.array([4, 3, 8, 4, 8, 5], dtype=np.uint64))
    >>> ids.tolist(), first.tolist(), ix.count
    ([3, 1, 4, 3, 4, 5], [0, 2, 5], 6)
    >>> ix.truncate(4)
    >>> ix.find_or_add(np.array([4, 8], dtype=np.uint64))[0].tolist()
    [3, 4]
    """

    def __init__(self, bits: int = 16, capacity: int = 1 << 16, compiled: bool | None = None):
        self.keys = np.empty(capacity, dtype=np.uint64)
        self.count = 0
        self.stale = False
        # the compiled index (kernels.find_or_add) keeps its tags in the slots: same ids, order
        self.compiled = kernels.enabled() if compiled is None else compiled
        self.local = np.empty(0, dtype=np.int32)  # the compiled pass's table of a call's keys
        self.idbits = TAGGED_IDS  # the compiled slots' id bits (31 once the ids outgrow 24)
        self._alloc(bits)

    def _alloc(self, bits: int) -> None:
        self.bits = bits
        self.mask = (1 << bits) - 1
        self.shift = np.uint64(64 - bits)
        self.table = np.zeros(1 << bits, dtype=np.int32)  # id + 1; 0 is empty
        if not self.compiled:
            self.tags = np.zeros(1 << bits, dtype=np.uint8)  # 0 is empty
            self.groups = self.tags.view("<u8")  # the tags of slots 8g .. 8g + 7

    def _hash(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Home slots (as ``int64``) and tags (``uint8``, never 0) of ``q``."""
        h = q * _MUL
        tag = (h >> (self.shift - _TAG_BITS)).astype(np.uint8)
        np.maximum(tag, 1, out=tag)
        # below 2**bits, so the same bits read as int64: no conversion pass
        return (h >> self.shift).view(np.int64), tag

    def _rebuild(self, bits: int) -> None:
        """A fresh table of ``2**bits`` slots holding every stored key."""
        self._alloc(bits)
        self.stale = False
        if self.compiled:
            kernels.place(self.table, self.keys, 0, self.count, self.shift, self.idbits)
            return
        for lo in range(0, self.count, 1 << 16):  # in slices: small temporaries
            hi = min(self.count, lo + (1 << 16))
            self._place(self.keys[lo:hi], lo)

    def _fit(self, need: int, load: float) -> None:
        """Room for ``need`` keys: in the key column, and the table at most ``load`` full."""
        if need > len(self.keys):
            grown = np.empty(max(need, 2 * len(self.keys)), dtype=np.uint64)
            grown[:self.count] = self.keys[:self.count]
            self.keys = grown
        if self.compiled and self.idbits < 31 and need >= 1 << self.idbits:
            self.idbits, self.stale = 31, True  # ids outgrow the tagged slots: none from now
        if need > load * len(self.table) or self.stale:
            bits = self.bits
            while need > LOAD * (1 << bits):
                bits += 2 if bits < FOURFOLD_BELOW else 1
            self._rebuild(bits)

    def drop_table(self) -> None:
        """Free the hash table (the keys stay): a finished search needs only its keys. The
        table is rebuilt when next used."""
        self._alloc(3)  # eight slots: a group of tags
        self.stale = True

    def truncate(self, count: int) -> None:
        """Forget the keys from id ``count`` on (the table is rebuilt when next used)."""
        if count < self.count:
            self.count = count
            self.stale = True

    def _probe(self, slot: np.ndarray, tags: np.ndarray | None
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Probes from ``slot`` to the end of its group of eight slots, branch-free:
        the first slot there that is empty or holds the key's tag (``tags``: each
        key's tag in all eight bytes; None: only empty slots), else the first slot
        of the next group (not wrapped); whether one was found; whether it is empty."""
        # the bytes before the start made nonzero: no zero byte there, nothing borrows
        below = (_ONE << ((slot & 7).view(np.uint64) << _3)) - _ONE
        w = self.groups[slot >> 3] | below
        z = (w - _BYTES) & ~w  # the lowest zero byte has its high bit set, exactly
        empty = z
        if tags is not None:
            x = (w ^ tags) | below
            z = z | ((x - _BYTES) & ~x)
        z &= _HIGH
        low = z & (_ZERO - z)  # the first marker (0: none)
        k = np.bitwise_count(low - _ONE) >> _U8_3  # slots before it (8: none)
        return (slot & ~7) + k, k < _U8_8, (empty & low) != _ZERO

    def find_or_add(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Ids of ``q``, the absent keys appended with the next ids in order of first
        occurrence in ``q``; and the positions in ``q`` of those first occurrences (both
        ``int32``: the table holds ``int32`` ids).

        One probing pass: a key meeting an empty slot claims it with a tag naming
        its position in ``q`` (negative, to tell it from a stored id); the other
        occurrences of that key find the tag (they probe the same slots in step).
        No boolean-mask selections on the probing keys (slow on random masks):
        index lists and arithmetic."""
        m = len(q)
        self._fit(self.count + m, 0.9)  # never full during the pass
        if self.compiled:
            return self._find_or_add_compiled(q)
        ids, rep, claimed = self._probe_all(q)
        return self._add_claimed(q, ids, rep, claimed)

    def _find_or_add_compiled(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`find_or_add` by the compiled kernel (int32: an id is below the table's
        int32 ids, a position below ``len(q)``)."""
        m = len(q)
        ids = np.empty(m, dtype=np.int32)
        first = np.empty(m, dtype=np.int32)
        q = np.ascontiguousarray(q, dtype=np.uint64)
        if len(self.local) < 2 * m:
            self.local = np.empty(1 << max(10, (2 * m - 1).bit_length()), dtype=np.int32)
        self.count, added = kernels.find_or_add(self.table, self.keys, self.count,
                                                self.shift, self.idbits, q, ids, first,
                                                self.local)
        if self.count > LOAD * len(self.table):
            self._fit(self.count, LOAD)
        return ids, first[:added]

    def _probe_all(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """:meth:`find_or_add`'s probing pass in numpy: per position of ``q``, the id of a
        stored key (``ids``), else the position that claimed its slot (``rep``, -1 for a
        stored key), and per claimer the slot it claimed (``claimed``)."""
        m = len(q)
        table, tags, keys, mask = self.table, self.tags, self.keys, self.mask
        ids = np.empty(m, dtype=np.int64)
        rep = np.full(m, -1, dtype=np.int64)  # absent key: the position that claimed its slot
        claimed = np.empty(m, dtype=np.int64)  # the claimer's slot
        slot, tag = self._hash(q)
        rtag = tag.astype(np.uint64) * _BYTES  # in all eight bytes
        a = None  # positions still probing (None: all of them, in order)
        qa, ta = q, rtag
        while len(slot):
            at, found, empty = self._probe(slot, ta)
            at &= mask  # where the next probe starts, unless settled below
            more = ~found
            i = np.flatnonzero(found & ~empty)  # the tag matches
            if len(i):
                s = at[i]
                t = table[s]
                own = t > 0  # a stored key (else one claimed in this pass)
                if own.all():
                    stored = t.astype(np.int64) - 1
                    hit = keys[stored] == qa[i]
                    ids[i[hit] if a is None else a[i[hit]]] = stored[hit]
                else:
                    hit = np.zeros(len(i), dtype=bool)
                    j = np.flatnonzero(own)
                    stored = t[j].astype(np.int64) - 1
                    h = keys[stored] == qa[i[j]]
                    hit[j[h]] = True
                    ids[i[j[h]] if a is None else a[i[j[h]]]] = stored[h]
                    j = np.flatnonzero(~own)
                    w = -1 - t[j].astype(np.int64)
                    h = q[w] == qa[i[j]]
                    hit[j[h]] = True
                    rep[i[j[h]] if a is None else a[i[j[h]]]] = w[h]
                if not hit.all():
                    j = i[~hit]
                    more[j] = True
                    at[j] = (at[j] + 1) & mask
            i = np.flatnonzero(empty)  # claim it
            if len(i):
                ai = i if a is None else a[i]
                s = at[i]
                # written last to first, so the first occurrence wins (usually: checked below)
                table[s[::-1]] = (-1 - ai[::-1]).astype(np.int32)
                w = -1 - table[s].astype(np.int64)
                won = w == ai
                tags[s[won]] = tag[ai[won]]
                claimed[ai[won]] = s[won]
                same = q[w] == qa[i]
                rep[ai[same]] = w[same]
                if not same.all():  # lost to another key: on to the next slot
                    j = i[~same]
                    more[j] = True
                    at[j] = (at[j] + 1) & mask
            i = np.flatnonzero(more)
            a = i if a is None else a[i]
            slot, qa, ta = at[i], q[a], rtag[a]
        return ids, rep, claimed

    def _add_claimed(self, q: np.ndarray, ids: np.ndarray, rep: np.ndarray,
                     claimed: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The keys the probing pass claimed slots for, added with the next ids in order of
        first occurrence; :meth:`find_or_add`'s answer."""
        m = len(q)
        table, keys = self.table, self.keys
        news = np.flatnonzero(rep >= 0)
        r = rep[news]
        winners = news[r == news]  # ascending
        first = winners
        if np.any(news < r):  # a claim was won by a later occurrence
            pos = np.arange(m)
            np.minimum.at(pos, r, news)
            first = pos[winners]
            order = np.argsort(first, kind="stable")
            winners, first = winners[order], first[order]
        k, base = len(winners), self.count
        fresh = np.arange(base, base + k)
        rank = rep  # reused: by claimer, the id
        rank[winners] = fresh
        ids[news] = rank[r]
        table[claimed[winners]] = (fresh + 1).astype(np.int32)
        keys[base:base + k] = q[first]
        self.count = base + k
        if self.count > LOAD * len(table):
            del table  # the old table goes before the new one is filled
            self._fit(self.count, LOAD)
        return ids.astype(np.int32), first.astype(np.int32)  # the compiled path's types

    def _place(self, q: np.ndarray, first_id: int) -> None:
        """Put distinct keys absent from the table, ids ``first_id`` on, in their slots."""
        slot, tag = self._hash(q)
        ids = np.arange(first_id + 1, first_id + 1 + len(q), dtype=np.int32)
        table, tags, mask = self.table, self.tags, self.mask
        while len(slot):
            at, _, empty = self._probe(slot, None)
            at &= mask
            i = np.flatnonzero(empty)
            s = at[i]
            table[s] = ids[i]  # of keys wanting one slot, one wins
            won = table[s] == ids[i]
            tags[s[won]] = tag[i[won]]
            more = ~empty
            more[i[~won]] = True  # on to the next slot (taken now)
            j = np.flatnonzero(more)
            slot, tag, ids = at[j], tag[j], ids[j]

