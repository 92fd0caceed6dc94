"""The bulk explorer: the same breadth-first search as :mod:`explore`, on numpy arrays.

SEMANTICS.md §4-5. It explores exactly the states of the reference
explorer (:func:`gather_verify.engine.explore.explore_reference`), gives them the same
ids in the same order (so the same BFS parents, the same first witnesses and the
same traces), and returns the same :class:`~gather_verify.engine.explore.Exploration`.
What changes is how:

- a state is one ``uint64``: the reference key (robot codes ``cell * 5 + d``
  packed in base ``5 * cells``, sorted and minimised over ``Aut(M)`` when the
  reductions are on);
- visited states live in an open-addressing hash table of ``int32`` ids over a
  ``uint64`` key column in id order; parents are an ``int32`` column;
- the frontier is expanded a chunk of states at a time: states are grouped by
  configuration, the facts of each configuration (move sets, deadlock, class,
  target) are computed once through the generic algorithm interface and kept
  as a row of small integers, and the scheduler's ``bulk_successors`` (part of
  the ``Scheduler`` protocol) applies them to the whole chunk at once, handed
  the states in the engine's encoding (``encoding.Encoding.frontier``); an
  event may change several robots (FSYNC/SSYNC rounds);
- the graph (successor ids, edge weights) is kept only when asked for
  (``graph=True``, what ``move-bound`` and ``termination`` need).

The explorer knows neither the algorithm nor the scheduler (witness events are
asked of the scheduler's ``successors``, by their rank among the state's events):
only a key that does not fit 64 bits, or more states than an ``int32`` id holds,
make :func:`supports` say no and the caller uses the reference path.

>>> from gather_verify.model.configuration import Configuration
>>> c = Configuration([(0, 0), (3, 1), (1, 4)], [(2, 2)], initial=True)
>>> e = explore_fast(c, "go-to-target", "async", reduction=False)
>>> e.states, e.transitions, e.stopped
(2184, 7032, None)
"""

from __future__ import annotations

import gc
import time
from collections.abc import Iterable, Iterator, Sequence
from functools import partial
from itertools import islice
from typing import Any

import numpy as np

from gather_verify import kernels
from gather_verify.algorithms import Algorithm, AlgorithmCrash, Unhandled, get_algorithm, target_of
from gather_verify.algorithms.moves import frames_for, move_sets
from gather_verify.engine.checks import Checks, ColumnChecks, selected, symmetric
from gather_verify.engine.encoding import (
    NO_LIMITS,
    Encoding,
    Limits,
    region_box,
    symmetry_group,
)
from gather_verify.engine.explore import (
    Exploration,
    facts_cache,
    rss_mb,
)
from gather_verify.model import geometry
from gather_verify.model.canonical import CanonicalForm, canonical_form, moved_form
from gather_verify.model.classes import classify_configuration
from gather_verify.model.configuration import Configuration
from gather_verify.model.geometry import STEPS, Node
from gather_verify.model.symmetry import Automorphism, meeting_automorphisms
from gather_verify.model.view import check_detection
from gather_verify.progress import PROGRESS
from gather_verify.recent import most_recent
from schedulers import State, get_scheduler, initial_state

CHUNK = 1 << 14
"""States expanded per bulk step: bounds the transient arrays (a few MB)."""
EVENTS = 1 << 19
"""About how many events a bulk step may generate: the scheduler takes fewer states than
``CHUNK`` when they have more events than this (FSYNC/SSYNC rounds: up to ``6**n`` per state)."""
MAX_IDS = 2**31 - 2
LOAD = 0.7
"""Largest load factor of the hash table before it doubles."""
_MUL = np.uint64(0x9E3779B97F4A7C15)
_TAG_BITS = np.uint64(8)
_BYTES = np.uint64(0x0101010101010101)
_HIGH = np.uint64(0x8080808080808080)
_ZERO, _ONE, _3 = np.uint64(0), np.uint64(1), np.uint64(3)
_U8_3, _U8_8 = np.uint8(3), np.uint8(8)


class IntColumn(Sequence[int]):
    """A read-only view of a numpy column that hands out Python ints (for the
    per-element code in :mod:`properties` and :mod:`check`)."""

    __slots__ = ("array",)

    def __init__(self, array: np.ndarray):
        self.array = array

    def __len__(self) -> int:
        return len(self.array)

    def __getitem__(self, i: Any) -> Any:
        if isinstance(i, slice):
            return self.array[i].tolist()
        return int(self.array[i])

    def __iter__(self) -> Iterator[int]:
        for start in range(0, len(self.array), 1 << 16):
            yield from self.array[start:start + (1 << 16)].tolist()


class KeyIndex:
    """Visited states: ``uint64`` keys in id order and a linear-probing table of ids.

    Beside each slot, a one-byte tag (0: empty; else 8 more bits of the key's hash)
    rejects most occupied slots without reading the key column; the tags are read
    eight slots at a time (one aligned ``uint64`` word, a group of slots).

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
        # the compiled index (kernels.find_or_add) keeps no tags: the same ids, in the same order
        self.compiled = kernels.enabled() if compiled is None else compiled
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
            kernels.place(self.table, self.keys, 0, self.count, self.shift)
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
        if need > load * len(self.table) or self.stale:
            bits = self.bits
            while need > LOAD * (1 << bits):
                bits += 1
            self._rebuild(bits)

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
        occurrence in ``q``; and the positions in ``q`` of those first occurrences.

        One probing pass: a key meeting an empty slot claims it with a tag naming
        its position in ``q`` (negative, to tell it from a stored id); the other
        occurrences of that key find the tag (they probe the same slots in step).
        No boolean-mask selections on the probing keys (slow on random masks):
        index lists and arithmetic."""
        m = len(q)
        self._fit(self.count + m, 0.9)  # never full during the pass
        if self.compiled:
            ids = np.empty(m, dtype=np.int64)
            first = np.empty(m, dtype=np.int64)
            q = np.ascontiguousarray(q, dtype=np.uint64)
            self.count, added = kernels.find_or_add(self.table, self.keys, self.count,
                                                    self.shift, q, ids, first)
            if self.count > LOAD * len(self.table):
                self._fit(self.count, LOAD)
            return ids, first[:added]
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
            del table, tags  # the old table goes before the new one is filled
            self._fit(self.count, LOAD)
        return ids, first

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


class Growing:
    """An append-only numpy column (amortised doubling)."""

    def __init__(self, dtype: Any, capacity: int = 1 << 16):
        self.data = np.empty(capacity, dtype=dtype)
        self.size = 0

    def extend(self, values: np.ndarray) -> None:
        need = self.size + len(values)
        if need > len(self.data):
            grown = np.empty(max(need, 2 * len(self.data)), dtype=self.data.dtype)
            grown[:self.size] = self.data[:self.size]
            self.data = grown
        self.data[self.size:need] = values
        self.size = need

    def array(self) -> np.ndarray:
        return self.data[:self.size]

    def widen(self, dtype: Any) -> None:
        """Hold larger values from now on (the values so far kept)."""
        if self.data.dtype != dtype:
            self.data = self.data.astype(dtype)


FactsMemo = dict
"""Facts of configurations up to translation and the frames, shared by the checks of a
sweep (one per algorithm, detection and frames: :func:`facts_memo`)."""
MEMO_SIZE = 1 << 20
"""Configurations a memo holds before it starts over (a few hundred bytes each). The runs of
a sweep that walk away from ``M`` meet some 300,000 configurations each, mostly the same
ones: a memo that holds them all serves the next such run of the class."""
MEMO_ALGORITHMS = 2
"""Algorithms whose memos a process keeps at once (the most recently used). A sweep under
every reading runs 16 or 64 algorithms in one pool: memos for all of them would fill the
worker's memory limit, and every check after that would stop INCOMPLETE (memory)."""
_MEMOS: dict[tuple[Algorithm, str, str], FactsMemo] = {}
_TARGETS: dict[Algorithm, dict[tuple, Node | None]] = {}


def make_room(limit_mb: float) -> None:
    """Drop every memo when this process holds more than half its memory limit: the memos
    are a cache (a few hundred bytes to kilobytes per configuration), and a check must not
    stop INCOMPLETE (memory) because of what earlier checks left in them."""
    if (_MEMOS or _TARGETS) and rss_mb() > limit_mb / 2:
        _MEMOS.clear()
        _TARGETS.clear()
        gc.collect()


def facts_memo(algorithm: Algorithm, detection: str, frames: str) -> FactsMemo:
    """The memo this process shares among the checks of one algorithm object."""
    return most_recent(_MEMOS, (algorithm, detection, frames), dict, MEMO_ALGORITHMS)


def target_memo(algorithm: Algorithm) -> dict[tuple, Node | None]:
    """Targets of configurations (robots and meeting nodes as they are: no symmetry assumed
    of ``target``), shared like :func:`facts_memo` by the checks of a sweep."""
    return most_recent(_TARGETS, algorithm, dict, MEMO_ALGORITHMS)


def _step_perm(g: int) -> tuple[int, ...]:
    """Move masks (bit k: ``STEPS[k]``, bit 4: stay) mapped by the D4 element ``g``."""
    image = [STEPS.index(geometry.apply(g, step)) for step in STEPS]
    return tuple((m & 16) | sum(1 << image[k] for k in range(4) if m >> k & 1)
                 for m in range(32))


STEP_PERM = tuple(_step_perm(g) for g in geometry.ALL)
BIT = {(0, 0): 16} | {step: 1 << k for k, step in enumerate(STEPS)}
"""The mask bit of each destination, relative to the robot."""


def never_in_u(aut_m: Sequence[Automorphism], meeting: Iterable[Node]) -> bool:
    """Whether no configuration over these meeting nodes is in U: U needs a symmetry of C
    (an element of Aut(M)) whose axis or centre holds no meeting node
    (:func:`~gather_verify.model.classes.in_U_of`), and here every element of Aut(M) but the
    identity fixes a meeting node (its axis or centre holds one)."""
    meeting = list(meeting)
    return all(any(a.fixes(m) for m in meeting) for a in aut_m[1:])


class FactsTable:
    """Per configuration (sorted robot cells, packed), the facts as small integers.

    ``masks[row, j]``: bit ``k`` set when the robots on the ``j``-th sorted cell may
    take ``STEPS[k]``; bit 4 when they may stay. ``in_u`` and ``target`` are
    computed only when asked for (-2 = not computed yet).

    Move sets are computed once per orbit of configurations under ``group`` (the
    elements ``a`` of ``Aut(M)`` whose linear part is one of the robots' frames):
    for such an ``a`` the views of the robots of ``a(C)`` are those of ``C``, so
    the move set of ``a(v)`` in ``a(C)`` is ``a`` of the move set of ``v`` in ``C``
    (SEMANTICS.md §3: the union over the frames), whatever the algorithm. Class
    and target are computed on the configuration itself."""

    def __init__(self, enc: Encoding, n: int, algorithm: Algorithm, meeting: frozenset,
                 detection: str, frames: Sequence[int], group: Sequence[Any],
                 memo: FactsMemo | None = None, targets: bool = False):
        self.enc, self.n, self.algorithm, self.meeting = enc, n, algorithm, meeting
        self.memo = memo
        # targets by configuration: the sweep's shared memo (one search keeps none: each row
        # keeps its own in ``target``, and a dict entry per configuration cost 6 bytes a state)
        self.targets: dict[tuple, Node | None] = {} if memo is None else target_memo(algorithm)
        self.keep_targets = targets  # also those met while checking for crashes
        self.detection, self.frames = detection, tuple(frames)
        self.meeting_form = canonical_form((), meeting, self.frames)
        self.aut_m = list(group)  # Aut(M), identity first
        self.never_in_u = never_in_u(self.aut_m, meeting)
        assert not self.aut_m or self.aut_m[0].g == geometry.IDENTITY and self.aut_m[0].t == (0, 0)
        self.index = KeyIndex(bits=10, capacity=1024)  # configuration key -> row
        self.nodes = [enc.node(c) for c in range(enc.cells)]  # the node of each cell
        self.compiled = self.index.compiled  # the bulk paths of the compiled engine
        self.cells = np.zeros((1024, n), dtype=np.int32)
        self.masks = np.zeros((1024, n), dtype=np.uint8)
        self.flags = np.zeros((1024, 3), dtype=np.int8)  # undefined (1, 2: crash), stuck, gathered
        self.in_u = np.full(1024, -2, dtype=np.int8)
        self.target = np.full(1024, -2, dtype=np.int32)
        self.size = 0
        self.target_nodes: list = []
        self.target_ids: dict = {}
        self.weights = np.array([enc.cells ** j for j in range(n)], dtype=np.int64)
        # the orbit cache: images of region cells in the group-closed box
        group = sorted(a for a in group if a.g in self.frames)
        corners = [(enc.x0, enc.y0), (enc.x0 + enc.width - 1, enc.y0 + enc.height - 1)]
        x0, y0, x1, y1 = geometry.bounding_box([a(v) for a in group for v in corners] + corners)
        w, h = x1 - x0 + 1, y1 - y0 + 1
        if not group or (w * h) ** n >= 2**63:
            group = [Automorphism(geometry.IDENTITY, (0, 0))]
            x0, y0, w, h = enc.x0, enc.y0, enc.width, enc.height
        self.group = group
        self.box = (x0, y0, h)
        self.images = np.array([[(a(enc.node(c))[0] - x0) * h + a(enc.node(c))[1] - y0
                                 for c in range(enc.cells)] for a in group], dtype=np.int64)
        self.cpowers = np.array([(w * h) ** j for j in range(n)], dtype=np.int64)
        # masks of a representative, seen from the configuration that ``a`` maps onto it
        self.perm = np.array([STEP_PERM[geometry.inverse(a.g)] for a in group], dtype=np.uint8)
        self.orbit: dict[int, int] = {}
        self.omasks = np.zeros((1024, n), dtype=np.uint8)
        self.oflags = np.zeros((1024, 3), dtype=np.int8)
        # per orbit, the canonical form of its representative when one was computed (what
        # the algorithm's own work left, or the memo's); per row, its orbit and the element
        # of ``group`` that maps it onto the representative: a row's form then comes from
        # the representative's with no search (canonical.moved_form), which is most of
        # what its target costs
        self.oforms: list[CanonicalForm | None] = []
        self.row_orbit = np.zeros(1024, dtype=np.int32)
        self.row_image = np.zeros(1024, dtype=np.int8)

    def config_keys(self, cells: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Sorted cells per row and their packed key."""
        srt = np.sort(cells, axis=1)
        return srt, srt @ self.weights

    def configuration(self, row: int, form: bool = False) -> Configuration:
        """The configuration of ``row``; with ``form``, carrying its canonical form when its
        orbit's is known (moved from the representative's, no search)."""
        node = self.nodes
        c = Configuration.trusted(tuple([node[c] for c in self.cells[row].tolist()]),
                                  self.meeting)
        known = self.oforms[self.row_orbit[row]] if form else None
        if known is not None:  # the representative is a(C): C is a^-1 of it
            back = self.group[self.row_image[row]].inverse()
            c.__dict__["canonical_form"] = moved_form(known, back.g, back.t)
        return c

    def rows(self, keys: np.ndarray, sorted_cells: np.ndarray) -> np.ndarray:
        """Row of every configuration key (computing the facts of new ones): rows are
        numbered as the index numbers keys, in order of first occurrence."""
        ids, first = self.index.find_or_add(keys.astype(np.uint64))
        if len(first):
            self._add(sorted_cells[first])
        return ids

    def _add(self, cells: np.ndarray) -> np.ndarray:
        m, n = cells.shape
        while self.size + m > len(self.masks):
            self.cells, self.masks, self.flags = (
                np.concatenate([a, np.zeros_like(a)]) for a in (self.cells, self.masks, self.flags))
            self.in_u = np.concatenate([self.in_u, np.full(len(self.in_u), -2, dtype=np.int8)])
            self.target = np.concatenate([self.target,
                                          np.full(len(self.target), -2, dtype=np.int32)])
            self.row_orbit, self.row_image = (np.concatenate([a, np.zeros_like(a)])
                                              for a in (self.row_orbit, self.row_image))
        rows = np.arange(self.size, self.size + m)
        self.size += m
        self.cells[rows] = cells
        # the orbit representative: least packed sorted image over the group
        image = self.images[:, cells]  # (G, m, n), unsorted
        srt = np.sort(image, axis=2)
        packed = srt @ self.cpowers
        best = np.argmin(packed, axis=0)
        pick = np.arange(m)
        okeys, ocells = packed[best, pick], srt[best, pick]
        orows = np.empty(m, dtype=np.int64)
        get = self.orbit.get
        for i, k in enumerate(okeys.tolist()):
            r = get(k)
            if r is None:
                r = self._orbit_facts(k, ocells[i])
            orows[i] = r
        # robot j of the configuration sits on the rank[j]-th cell of the representative
        rank = np.argmax(image[best, pick][:, :, None] == ocells[:, None, :], axis=2)
        self.masks[rows] = self.perm[best[:, None], self.omasks[orows[:, None], rank]]
        self.flags[rows] = self.oflags[orows]
        self.row_orbit[rows] = orows
        self.row_image[rows] = best
        return rows

    def _orbit_facts(self, key: int, cells: np.ndarray) -> int:
        r = len(self.orbit)
        if r == len(self.omasks):
            self.omasks = np.concatenate([self.omasks, np.zeros_like(self.omasks)])
            self.oflags = np.concatenate([self.oflags, np.zeros_like(self.oflags)])
        self.orbit[key] = r
        x0, y0, h = self.box
        robots = tuple((x0 + c // h, y0 + c % h) for c in cells.tolist())
        if self.memo is None:
            masks, flags, form = self._facts(robots)
        else:
            masks, flags, form = self._remembered_facts(robots)
        self.omasks[r] = masks
        self.oflags[r] = flags
        self.oforms.append(form)
        return r

    def _facts(self, robots: tuple[Node, ...]
               ) -> tuple[list[int], tuple[int, int, int], CanonicalForm | None]:
        """Move masks of ``robots`` (in order) and the flags (no move sets: 0, or 1 when the
        algorithm has no rule, 2 when it crashed in ``decide`` or ``target``; stuck; gathered),
        as :func:`~gather_verify.properties.facts.configuration_facts` defines them; and the
        configuration's canonical form if the algorithm computed it (none is searched for)."""
        c = Configuration.trusted(robots, self.meeting)
        undefined = 0
        try:
            ms = move_sets(self.algorithm, c, self.detection, self.frames)
        except Unhandled:
            undefined = 1
        except AlgorithmCrash:
            undefined = 2
        if undefined != 2:
            try:  # whether it crashes; the value is kept for target_id_of (c's canonical form
                # is already computed here, which is most of what a target costs)
                t = target_of(self.algorithm, c)
            except Unhandled:
                t = None
            except AlgorithmCrash:
                undefined = 2
            if undefined != 2 and self.keep_targets:
                self._remember_target((robots, self.meeting), t)
        form = c.__dict__.get("canonical_form")
        if undefined:
            return [0] * len(robots), (undefined, 0, 0), form
        masks = [sum(BIT[x - vx, y - vy] for x, y in ms[vx, vy]) for vx, vy in robots]
        return masks, (0, all(s == {v} for v, s in ms.items()),
                       len(c.counts) == 1 and robots[0] in self.meeting), form

    def _remembered_facts(self, robots: tuple[Node, ...]
                          ) -> tuple[list[int], tuple[int, int, int], CanonicalForm | None]:
        """:meth:`_facts` through the shared memo, keyed by a canonical form of the
        configuration over translations and the frames (multiplicities kept): ``M`` moved
        to its canonical place by one of the isometries that do so, the one that gives
        the least sorted robot nodes (``M`` is fixed during a search, so those isometries
        are found once). Exact for any algorithm: with ``g`` in the frame group, the views
        of ``g(C) + t`` are those of ``C`` in the frames composed with ``g``, which run over
        the same frames, so its move sets are the images of those of ``C`` (SEMANTICS.md
        §3: the union over the frames); the flags are invariant. The canonical form is kept
        as the placed configuration's, and moved back to each configuration that finds it."""
        best = None
        for g, (tx, ty) in self.meeting_form.minimisers:
            a, b, c, d = geometry.MATRICES[g]
            image = [(a * x + b * y + tx, c * x + d * y + ty) for x, y in robots]
            placed = sorted(image)
            if best is None or placed < best[0]:
                best = (placed, g, (tx, ty), image)
        placed, g, best_t, image = best
        key = (self.meeting_form.key, tuple(placed))
        known = self.memo.get(key)
        if known is None:
            masks, flags, form = self._facts(robots)
            forward = STEP_PERM[g]
            if len(self.memo) >= MEMO_SIZE:
                self.memo.clear()
            self.memo[key] = (dict(zip(image, (forward[m] for m in masks), strict=True)), flags,
                              None if form is None else moved_form(form, g, best_t))
            return masks, flags, form
        back = Automorphism(g, best_t).inverse()
        form = None if known[2] is None else moved_form(known[2], back.g, back.t)
        return [STEP_PERM[back.g][known[0][w]] for w in image], known[1], form

    def reason(self, row: int) -> str | None:
        """Why the algorithm has no rule in this configuration (computed on it; None: it has
        one, or it crashed in ``decide``)."""
        try:
            move_sets(self.algorithm, self.configuration(row), self.detection, self.frames)
        except Unhandled as error:
            return str(error) or "no rule for this view"
        except AlgorithmCrash:
            return None
        return None

    def crash_of(self, row: int) -> AlgorithmCrash:
        """The exception of the algorithm in this configuration (computed on it: ``decide``'s
        first, else ``target``'s, as :func:`~gather_verify.properties.facts.configuration_facts`)."""
        c = self.configuration(row)
        try:
            move_sets(self.algorithm, c, self.detection, self.frames)
        except Unhandled:
            pass
        except AlgorithmCrash as crash:
            return crash
        try:
            target_of(self.algorithm, c)
        except Unhandled:
            pass
        except AlgorithmCrash as crash:
            return crash
        raise AssertionError("the orbit crashes, so does every member")  # pragma: no cover

    def need_in_u(self, rows: np.ndarray) -> np.ndarray:
        for r in np.unique(rows[self.in_u[rows] < 0]).tolist():
            self.in_u_of(r)
        return self.in_u[rows] == 1

    def _settle_asymmetric(self) -> None:
        """The first test of :meth:`in_u_of`, in bulk on every row not settled yet: rows
        whose occupied nodes no element of Aut(M) but the identity maps onto themselves are
        not in U (they get ``in_u`` 0); the others are left to :meth:`in_u_of`."""
        rows = np.flatnonzero(self.in_u[:self.size] == -2)
        cells = self.cells[rows].astype(np.int64)
        x = self.enc.x0 + cells // self.enc.height
        y = self.enc.y0 + cells % self.enc.height
        some = np.zeros(len(rows), dtype=bool)
        for a in self.aut_m[1:]:
            m = geometry.MATRICES[a.g]
            ax = m[0] * x + m[1] * y + a.t[0]
            ay = m[2] * x + m[3] * y + a.t[1]
            inside = ((ax[:, :, None] == x[:, None, :]) & (ay[:, :, None] == y[:, None, :]))
            some |= inside.any(axis=2).all(axis=1)
        self.in_u[rows] = np.where(some, -3, 0)  # -3: left to in_u_of's classification

    def in_u_of(self, row: int) -> bool:
        """Whether the configuration of ``row`` is in U (computed once)."""
        known = int(self.in_u[row])
        if known < 0 and self.never_in_u:
            self.in_u[row] = known = 0
        if known == -2 and self.compiled:
            self._settle_asymmetric()
            known = int(self.in_u[row])
        if known >= 0:
            return known == 1
        # In U needs Aut(C) non-trivial, and Aut(C) is inside Aut(M): when no element of
        # Aut(M) but the identity maps the occupied nodes onto themselves, C is not in U.
        aut = self.aut_m
        c = self.configuration(row)
        occupied = set(c.robots)
        if any(all(a(v) in occupied for v in occupied) for a in aut[1:]):
            self.in_u[row] = classify_configuration(c, aut_m_all=aut).in_U
        else:
            self.in_u[row] = 0
        return bool(self.in_u[row] == 1)

    def need_target(self, rows: np.ndarray) -> np.ndarray:
        """Target id per row (-1: none)."""
        for r in np.unique(rows[self.target[rows] == -2]).tolist():
            self.target_id_of(r)
        return self.target[rows]

    def _remember_target(self, key: tuple, t: Node | None) -> None:
        if self.memo is None:  # one search: each row keeps its target in ``target``
            return
        if len(self.targets) >= MEMO_SIZE:
            self.targets.clear()
        self.targets[key] = t

    def target_of(self, c: Configuration, remember: bool = True) -> Node | None:
        """The algorithm's target in ``c`` (robots sorted; None: none, or no rule),
        remembered unless ``remember`` is false (a configuration not met again); a crash is
        raised, and not remembered."""
        key = (c.robots, c.meeting_nodes)
        if key in self.targets:
            return self.targets[key]
        try:
            t = target_of(self.algorithm, c)
        except Unhandled:
            t = None
        if remember:
            self._remember_target(key, t)
        return t

    def target_id_of(self, row: int) -> int:
        """The id of the target of ``row`` in ``target_nodes`` (-1: none; computed once)."""
        known = int(self.target[row])
        if known != -2:
            return known
        try:
            t = self.target_of(self.configuration(row, form=True))
        except AlgorithmCrash:  # a crash stops the search at the orbit
            t = None
        if t is None:
            self.target[row] = -1
        else:
            if t not in self.target_ids:
                self.target_ids[t] = len(self.target_nodes)
                self.target_nodes.append(t)
            self.target[row] = self.target_ids[t]
        return int(self.target[row])


class RowFacts:
    """The :class:`~gather_verify.properties.facts.Facts` of one row of a :class:`FactsTable`,
    read from the table (class and target computed on first use); with ``idle`` given, also
    a state's facts (:class:`~gather_verify.properties.facts.StateFacts`), and ``read_idle``
    tells whether a predicate read it (if not, its answer holds for both values)."""

    __slots__ = ("table", "row", "initial", "_flags", "_idle", "read_idle")

    def __init__(self, table: FactsTable, row: int, initial: Configuration,
                 idle: bool | None = None, flags: Sequence[int] | None = None):
        self.table, self.row, self.initial = table, row, initial
        self._flags = flags  # read from the table on first use
        self._idle = idle
        self.read_idle = False

    @property
    def flags(self) -> Sequence[int]:
        if self._flags is None:
            self._flags = self.table.flags[self.row].tolist()
        return self._flags

    @staticmethod
    def many(table: FactsTable, initial: Configuration, rows: np.ndarray,
             idle: np.ndarray) -> list[RowFacts]:
        """The state facts of many (row, idle) pairs, their flags read in one go."""
        return [RowFacts(table, r, initial, i, f) for r, i, f in
                zip(rows.tolist(), idle.tolist(), table.flags[rows].tolist(), strict=True)]

    @property
    def idle(self) -> bool:
        if self._idle is None:
            raise AttributeError("idle: the facts of a configuration, not of a state")
        self.read_idle = True
        return self._idle

    @property
    def configuration(self) -> Configuration:
        return self.table.configuration(self.row)

    @property
    def move_sets(self) -> dict[Node, frozenset[Node]] | None:
        if self.flags[0]:
            return None
        out = {}
        for cell, mask in zip(self.table.cells[self.row].tolist(),
                              self.table.masks[self.row].tolist(), strict=True):
            v = self.table.enc.node(cell)
            out[v] = frozenset(geometry.add(v, d) for d, bit in BIT.items() if mask & bit)
        return out

    @property
    def unhandled(self) -> str | None:
        if not self.flags[0]:
            return None
        got = self.table.reason(self.row)
        assert got is not None or self.flags[0] == 2, "the orbit is unhandled, so is every member"
        return got

    @property
    def crash(self) -> AlgorithmCrash | None:
        return self.table.crash_of(self.row) if self.flags[0] == 2 else None

    @property
    def stuck(self) -> bool:
        return bool(self.flags[1])

    @property
    def gathered(self) -> bool:
        return bool(self.flags[2])

    @property
    def in_U(self) -> bool:
        return self.table.in_u_of(self.row)

    @property
    def target(self) -> Node | None:
        t = self.table.target_id_of(self.row)
        return None if t < 0 else self.table.target_nodes[t]


class PairRows:
    """The configuration row a one-robot change reaches, kept per (configuration row, sorted
    position of the robot's cell, step): a configuration and its few moves are met by many
    states (the robots' pending steps differ), so the successor's configuration is sorted
    and looked up once per such triple, not once per transition. A direct table (16 bytes
    per row and robot) while the rows are few; beyond, a hash index of the triples."""

    DIRECT_ROWS = 1 << 20
    """Rows the direct table may cover (80 MB with five robots); beyond: the hash index."""

    def __init__(self, table: FactsTable):
        self.table = table
        self.succ = np.full((1024, table.n, 4), -1, dtype=np.int32)
        self.neighbour = table.enc.neighbour
        self.index = KeyIndex(bits=12, capacity=1 << 12)
        self.rows = Growing(np.int64, 1 << 12)
        self.stride = table.n * table.enc.cells

    def after(self, rows: np.ndarray, cells: np.ndarray, rank: np.ndarray, src: np.ndarray,
              robot: np.ndarray, old: np.ndarray, new: np.ndarray) -> np.ndarray:
        """The row of each transition's successor configuration (``src``: source states of
        the chunk; robot ``robot`` goes from code ``old`` to code ``new``)."""
        if self.table.size > self.DIRECT_ROWS:
            return self._hashed(rows, cells, rank, src, robot, old, new)
        if len(self.succ) < self.table.size:
            grown = np.full((max(self.table.size, 2 * len(self.succ)),) + self.succ.shape[1:],
                            -1, dtype=np.int32)
            grown[:len(self.succ)] = self.succ
            self.succ = grown
        out, miss, slot = kernels.successor_rows(rows, rank, src, robot, old, new,
                                                 self.neighbour, self.succ)
        if len(miss):
            succ = cells[src[miss]].copy()
            succ[np.arange(len(miss)), robot[miss]] = new[miss] // 5
            srt, k = self.table.config_keys(succ)
            got = self.table.rows(k, srt)
            out[miss] = got
            known = slot >= 0
            self.succ.reshape(-1)[slot[known]] = got[known]
        return out

    def _hashed(self, rows: np.ndarray, cells: np.ndarray, rank: np.ndarray, src: np.ndarray,
                robot: np.ndarray, old: np.ndarray, new: np.ndarray) -> np.ndarray:
        out = rows[src]
        moved, key = kernels.pair_keys(rows, rank, src, robot, old, new, self.stride,
                                       self.table.enc.cells)
        if not len(moved):
            return out
        ids, first = self.index.find_or_add(key)
        if len(first):
            f = moved[first]
            succ = cells[src[f]].copy()
            succ[np.arange(len(f)), robot[f]] = new[f] // 5
            srt, k = self.table.config_keys(succ)
            self.rows.extend(self.table.rows(k, srt))
        out[moved] = self.rows.array()[ids]
        return out


def supports(initial: Configuration, scheduler: str, reduction: bool = True,
             anonymity: bool | None = None, symmetry: bool | None = None, frames: str = "all",
             limits: Limits = NO_LIMITS) -> bool:
    """Whether the bulk path can run this request (else use the reference path): every
    registered scheduler has the bulk interface; the key must fit 63 bits and the ids 31."""
    get_scheduler(scheduler)  # an unknown name is an error, not a fallback
    symmetry = reduction if symmetry is None else symmetry
    group = symmetry_group(initial, frames) if symmetry else []
    x0, y0, x1, y1 = region_box(initial, limits.margin, group)
    base = (x1 - x0 + 1) * (y1 - y0 + 1) * 5
    return base ** initial.n < 2**63 and min(limits.max_states, MAX_IDS) >= 1


class Canon:
    """Canonical keys of code rows under the enabled reductions (as ``Encoding.key``)."""

    def __init__(self, enc: Encoding, n: int):
        self.anonymity = enc.anonymity
        self.tables = [np.asarray(t, dtype=np.int64) for t in enc.tables]
        self.powers = np.array([enc.base ** j for j in range(n)], dtype=np.uint64)

    def pack(self, columns: list[np.ndarray]) -> np.ndarray:
        out = columns[0].astype(np.uint64)
        for j in range(1, len(columns)):
            out += columns[j].astype(np.uint64) * self.powers[j]
        return out

    def sort(self, columns: list[np.ndarray]) -> list[np.ndarray]:
        """Sort each row, the columns given as separate arrays (a transposition network:
        a handful of elementwise min/max, much faster than a row-wise sort for small n)."""
        cols = list(columns)
        n = len(cols)
        for rnd in range(n):
            for i in range(rnd % 2, n - 1, 2):
                lo, hi = np.minimum(cols[i], cols[i + 1]), np.maximum(cols[i], cols[i + 1])
                cols[i], cols[i + 1] = lo, hi
        return cols

    def keys(self, codes: np.ndarray) -> np.ndarray:
        columns = [np.ascontiguousarray(codes[:, j]) for j in range(codes.shape[1])]
        best = self.pack(self.sort(columns) if self.anonymity else columns)
        for table in self.tables:
            image = [table[c] for c in columns]
            np.minimum(best, self.pack(self.sort(image) if self.anonymity else image), out=best)
        return best


def explore_fast(
    initial: Configuration,
    algorithm: str | Algorithm,
    scheduler: str,
    *,
    detection: str = "local-weak",
    frames: str = "all",
    reduction: bool = True,
    anonymity: bool | None = None,
    symmetry: bool | None = None,
    properties: Iterable[str] | None = None,
    limits: Limits = NO_LIMITS,
    graph: bool = True,
    memo: bool = False,
    settle: bool = False,
) -> Exploration:
    """Breadth-first search in bulk; same result as the reference explorer.

    ``settle``: stop after the chunk in which every requested property got its
    counterexample (as :func:`~gather_verify.engine.explore.explore_reference`).

    ``graph=False`` keeps no edges (the result's ``offsets``, ``targets`` and
    ``weights`` are empty): enough for the safety properties and the state count.
    ``memo=True`` shares the facts of configurations with the other searches of this
    process for the same algorithm object (:func:`facts_memo`): what a sweep wants,
    where many searches meet the same configurations; a single large search gains
    nothing from it.
    """
    started = time.perf_counter()
    algo = get_algorithm(algorithm) if isinstance(algorithm, str) else algorithm
    sched = get_scheduler(scheduler)
    check_detection(detection)
    frame_elements = frames_for(frames)
    anonymity = reduction if anonymity is None else anonymity
    symmetry = (reduction if symmetry is None else symmetry) and symmetric(properties)
    group = symmetry_group(initial, frames) if symmetry else []
    enc = Encoding(region_box(initial, limits.margin, group), group, anonymity)
    n = initial.n
    facts = facts_cache(algo, initial, detection, frame_elements)
    if memo:
        make_room(limits.max_memory_mb)
    table = FactsTable(enc, n, algo, initial.meeting_nodes, detection, frame_elements,
                       meeting_automorphisms(initial),
                       facts_memo(algo, detection, frames) if memo else None,
                       targets=any(p.kind == "transition" for p in selected(properties)))
    canon = Canon(enc, n)
    base = enc.base
    powers = np.array([base ** j for j in range(n)], dtype=np.uint64)

    start_key = enc.key(initial_state(initial.robots))
    init_cells = np.array([[enc.code(v, None) // 5 for v in initial.robots]], dtype=np.int64)
    srt, ck = table.config_keys(init_cells)
    init_row = table.rows(ck, srt)
    checks = Checks(properties, RowFacts(table, int(init_row[0]), initial, True))
    columns = ColumnChecks(checks, lambda row, idle=None: RowFacts(table, row, initial, idle),
                           lambda rows, idle: RowFacts.many(table, initial, rows, idle))
    columns.states(0, init_row, np.ones(1, dtype=bool), checks.on_discovery)
    on_chunk = checks.halting + checks.on_expansion

    max_states = min(limits.max_states, MAX_IDS)
    # columns reserved up front: untouched pages cost no memory, and nothing is copied
    reserve = min(max_states + max(CHUNK * 8 * n, EVENTS) + 1, 1 << 27)
    index = KeyIndex(capacity=reserve)
    index.find_or_add(np.array([start_key], dtype=np.uint64))
    parents = Growing(np.int32, reserve)
    parents.extend(np.array([-1], dtype=np.int32))
    # the graph's columns reserved too (untouched pages cost nothing): no copy as they grow,
    # so no transient second copy of the graph
    edges = min(8 * reserve, 1 << 28) if graph else 1 << 16
    offsets = Growing(np.int32, reserve if graph else 1 << 16)  # int64 past 2**31 edges (widen)
    targets = Growing(np.int32, edges)
    weight_type = np.int8 if n <= 127 else np.int16  # a weight is at most n edges
    weights = Growing(weight_type, edges)
    transitions = changed_loops = 0
    stopped: str | None = None
    compiled = kernels.enabled()
    pair_rows = PairRows(table) if compiled else None
    peak = rss_mb()
    sid = 0
    chunk = CHUNK
    PROGRESS.states = 1
    while sid < index.count and stopped is None:
        if time.perf_counter() - started > limits.max_seconds:
            stopped = "time"
            break
        peak = max(peak, rss_mb())
        if peak > limits.max_memory_mb:
            stopped = "memory"
            break
        hi = min(index.count, sid + chunk)
        K = index.keys[sid:hi].copy()
        if compiled:
            codes, cells, srt, ck, idle, rank = kernels.decode_chunk(K, base, n, table.weights)
        else:
            codes = _decode(K, base, n)
            cells = codes // 5
            srt, ck = table.config_keys(cells)
            idle = np.all(codes % 5 == 0, axis=1)
        rows = table.rows(ck, srt)
        # the last source state to expand: a halting property stops before the state it fails in
        limit_src = len(K)
        # the halting and the expansion properties, evaluated together on the whole chunk
        failing = columns.failures(on_chunk, rows, idle, gate=len(checks.halting))
        halt = columns.first_failure(checks.halting, failing[:, :len(checks.halting)])
        if halt is not None:
            limit_src = halt[0]
        assert not table.flags[rows[:limit_src], 0].any(), \
            "a state without move sets needs a halting property"
        # robot i's move mask: the mask of its cell's position in the sorted row
        if not compiled:
            rank = np.argmax(cells[:, :, None] == srt[:, None, :], axis=2)
        if compiled:  # (one flat gather: much faster than the two-dimensional one)
            masks = np.take(table.masks.reshape(-1), rows[:, None] * n + rank)
        else:
            masks = table.masks[rows[:, None], rank]
        bulk = sched.bulk_successors(enc.frontier(codes[:limit_src], masks[:limit_src]), EVENTS)
        if bulk.states < limit_src:  # the scheduler took fewer states: the rest waits
            hi = sid + bulk.states
            K, codes, cells, rows = K[:bulk.states], codes[:bulk.states], cells[:bulk.states], \
                rows[:bulk.states]
            limit_src = bulk.states
            chunk = max(1, bulk.states)
        elif chunk < CHUNK:
            chunk = min(CHUNK, 2 * chunk)
        src, weight = bulk.source, bulk.weight
        robot, new, event = bulk.robot, bulk.code, bulk.event  # the changes
        single = event is None  # one change per event (event c is change c)
        outside = np.flatnonzero(new < 0)
        cut = len(src)
        if len(outside):
            cut = int(outside[0]) if single else int(event[outside[0]])
            stop_src = int(src[cut])
            stop = "region"
            transitions += cut + 1
        else:
            stop_src = limit_src
            stop = halt[1].name if halt is not None and halt[0] == limit_src else None
            transitions += cut
        src, weight = src[:cut], weight[:cut]
        changes = cut if single else int(np.searchsorted(event, cut))
        robot, new = robot[:changes], new[:changes]
        if single and compiled and not (group or anonymity):
            succ, old = kernels.successor_keys(K, codes, src, robot, new, powers)
        elif single:
            old = codes[src, robot]
        else:
            event = event[:changes]
            old = codes[src[event], robot]
        succ_codes = None
        if group or anonymity or not single:
            succ_codes = codes[src]
            succ_codes[np.arange(cut) if single else event, robot] = new
            succ = canon.keys(succ_codes)
        elif compiled:
            pass  # the keys came with the old codes
        else:
            delta = (new - old).astype(np.uint64) * powers[robot]
            succ = K[src] + delta  # wraps correctly for negative deltas
        # new states get the next ids in order of first occurrence: the BFS order
        known = index.count
        ids, first = index.find_or_add(succ)
        fresh_src = src[first]
        # the states limit: after the first source whose expansion passes it
        if index.count > max_states:
            after = known + np.searchsorted(fresh_src, np.arange(stop_src), side="right")
            over = np.flatnonzero(after > max_states)
            if len(over):
                stop_src, stop = int(over[0]), "states"
                keep = int(np.searchsorted(src, stop_src, side="right"))
                transitions -= cut - keep
                cut = keep
                src, weight, succ, ids = src[:cut], weight[:cut], succ[:cut], ids[:cut]
                if single:
                    robot, new, old = robot[:cut], new[:cut], old[:cut]
                else:
                    changes = int(np.searchsorted(event, cut))
                    robot, new, old, event = (a[:changes] for a in (robot, new, old, event))
                if succ_codes is not None:
                    succ_codes = succ_codes[:cut]
                m = int(np.searchsorted(fresh_src, stop_src, side="right"))
                fresh_src = fresh_src[:m]
                index.truncate(known + m)
        fresh_keys = index.keys[known:index.count]
        expanded = stop_src + (stop in ("region", "states"))
        columns.record(sid, checks.on_expansion, failing[:expanded, len(checks.halting):],
                       rows, idle)
        open_transition = checks.open(checks.on_transition) and cut
        open_discovery = checks.open(checks.on_discovery) and len(fresh_keys)
        after = None
        if single and pair_rows is not None and (open_transition or open_discovery):
            # the configuration each transition reaches, once per (row, cell, destination)
            after = pair_rows.after(rows, cells, rank, src, robot, old, new)
        if open_transition:
            if after is None:
                # the configuration each transition reaches, from the scheduler's changes
                if succ_codes is None:  # one change per event, no reduction: event c is change c
                    succ_cells = cells[src].copy()
                    succ_cells[np.arange(cut), robot] = new // 5
                else:
                    succ_cells = succ_codes // 5
                s2, k2 = table.config_keys(succ_cells)
                after = table.rows(k2, s2)
            columns.transitions(sid, src, rows[src], after,
                                partial(_step, enc, sched, facts, n, K, src, succ_codes))
        if open_discovery:
            fresh = _decode(fresh_keys, base, n)
            if after is not None and single and pair_rows is not None:
                fresh_rows = after[first[:len(fresh_keys)]]
            else:
                s3, k3 = table.config_keys(fresh // 5)
                fresh_rows = table.rows(k3, s3)
            columns.states(known, fresh_rows, np.all(fresh % 5 == 0, axis=1),
                           checks.on_discovery)
        if single:
            changed = new != old
        else:
            changed = np.zeros(cut, dtype=bool)
            changed[event[new != old]] = True
        changed_loops += int(np.count_nonzero((ids == sid + src) & changed))
        if graph:
            counts = np.bincount(src, minlength=expanded)[:expanded]
            starts = targets.size + np.cumsum(counts) - counts
            if targets.size + len(ids) > MAX_IDS:
                offsets.widen(np.int64)
            offsets.extend(starts)
            targets.extend(ids.astype(np.int32))
            weights.extend(weight.astype(weight_type))
        parents.extend((sid + fresh_src).astype(np.int32))
        if halt is not None and stop == halt[1].name and halt[0] == stop_src:
            columns.record_halt(sid + stop_src, int(rows[stop_src]), bool(idle[stop_src]), halt[1])
        if stop is not None:
            stopped = stop
            break
        sid = hi
        PROGRESS.states = index.count  # read by a progress line (check --progress)
        if settle and checks.settled():
            stopped = "settled"
            break
    if graph:
        offsets.extend(np.array([targets.size], dtype=np.int64))
    peak = max(peak, rss_mb())
    keys = index.keys[:index.count]
    return Exploration(
        initial, algo, scheduler, detection, frames, anonymity, symmetry, enc, IntColumn(keys),
        IntColumn(parents.array()), IntColumn(offsets.array()), IntColumn(targets.array()),
        IntColumn(weights.array()), changed_loops, index.count, transitions, stopped,
        checks.violations, time.perf_counter() - started, peak, facts, checks.vacuous)


def _decode(keys: np.ndarray, base: int, n: int) -> np.ndarray:
    codes = np.empty((len(keys), n), dtype=np.int64)
    rest, b = keys, np.uint64(base)
    for j in range(n):
        quot = rest // b  # (floor division by a constant is the fast one; % is not)
        codes[:, j] = (rest - quot * b).view(np.int64)
        rest = quot
    return codes



def _step(enc: Encoding, sched: Any, facts: Any, n: int, K: np.ndarray, src: np.ndarray,
          succ_codes: np.ndarray | None, i: int) -> tuple[Any, State]:
    """The event and successor of the ``i``-th transition of a bulk step (from state
    ``K[src[i]]``), asked of the scheduler's concrete ``successors``: its ``k``-th event, k
    its rank among its state's events (the bulk events come in the same order);
    ``succ_codes``: the successors' codes the bulk step computed, when it did."""
    state = enc.decode(int(K[src[i]]), n)
    k = i - int(np.searchsorted(src, src[i]))
    codes = None if succ_codes is None else succ_codes[i]

    def ms(robots: tuple[Node, ...]) -> dict[Node, frozenset[Node]]:
        got = facts(robots).move_sets
        assert got is not None  # the state was expanded
        return got

    event, succ = next(islice(sched.successors(state, ms), k, None))
    if codes is not None:  # pragma: no branch - the two faces of the scheduler agree
        assert [enc.code(v, p) for v, p in succ] == codes.tolist()
    return event, succ
