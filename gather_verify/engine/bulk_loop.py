"""The breadth-first search loop of the bulk engines on the paper's world, written once for
oblivious robots (:mod:`~gather_verify.engine.fast_explore`) and luminous ones
(:mod:`~gather_verify.engine.lit_bulk`).

:func:`bulk_search` expands the stored states a chunk at a time: the limits (time, memory,
states, region), the halting, expansion, transition and discovery properties on each
chunk, the successor keys and their ids (the BFS order), the graph's columns and the stop.
What differs between the two kinds of robots is a :class:`Face`: how a chunk's keys are
decoded and their configurations looked up, how the scheduler's bulk face is asked for
their events, and how the configurations that transitions and new states reach are found.
A luminous robot's code is an oblivious one's with its colour as one more digit,
``(cell * SLOTS + d) * K + colour``, so everything else is the same code on both.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from gather_verify import kernels
from gather_verify.engine.bulk_step import successor_keys
from gather_verify.engine.canonical_keys import Canon, decode_keys
from gather_verify.engine.checks import Checks, ColumnChecks
from gather_verify.engine.chunks import drive
from gather_verify.engine.columns import (
    Growing,
    GrowingBits,
    GrowingIds,
    IntColumn,
    LazyColumn,
    first_sources,
    small_pages,
)
from gather_verify.engine.encoding import Encoding, Limits, Stop
from gather_verify.engine.explore import rss_mb
from gather_verify.engine.key_index import KeyIndex
from gather_verify.kernels.codes import OUTSIDE
from gather_verify.progress import PROGRESS
from schedulers import Scheduler, State
from schedulers.base import RoundKeys

MAX_IDS = 2**31 - 2
"""States and edges an ``int32`` id holds."""


class Face:
    """What the oblivious and the luminous bulk searches do differently around the one loop,
    :func:`bulk_search`: how a chunk of keys is decoded and its configurations looked up,
    how the scheduler's bulk face is asked for their events, and how the configurations the
    transitions and the new states reach are found. A robot's code is ``cell * SLOTS + d``
    without lights, ``(cell * SLOTS + d) * K + colour`` with them (the colour one more digit)."""

    chunk: int
    """States expanded per bulk step (fewer when their events are many)."""

    def __init__(self, enc: Encoding, n: int, sched: Scheduler, turns: Any, facts: Any,
                 reduced: bool):
        self.enc, self.n, self.sched, self.turns, self.facts = enc, n, sched, turns, facts
        self.canon = Canon(enc, n)
        self.reduced = reduced  # successor keys through Canon
        self.compiled = kernels.enabled()

    def decode(self, keys: np.ndarray) -> tuple[np.ndarray, ...]:
        """The chunk's keys, robot codes, cells (or None), configuration rows, whether every
        robot is idle, and each robot's rank among its configuration's sorted robots."""
        raise NotImplementedError

    def no_actions(self, rows: np.ndarray) -> np.ndarray:
        """Per state, whether the algorithm gives its configuration no actions."""
        raise NotImplementedError

    def events(self, codes: np.ndarray, rows: np.ndarray, rank: np.ndarray,
               extra: np.ndarray | None) -> Any:
        """The scheduler's bulk events of the states (``extra``: its own state of each)."""
        raise NotImplementedError

    def round_keys(self, keys: np.ndarray, codes: np.ndarray, rows: np.ndarray,
                   rank: np.ndarray) -> RoundKeys | None:
        """The events of the states with their successors' keys and no changes
        (:func:`~schedulers.base.bulk_round_keys`), when the face can give them that way (a
        round scheduler, no reduction, compiled kernels); else None (ask :meth:`events`)."""
        return None

    def pair_after(self, rows: np.ndarray, cells: np.ndarray | None, rank: np.ndarray,
                   src: np.ndarray, robot: np.ndarray, old: np.ndarray,
                   new: np.ndarray) -> np.ndarray | None:
        """The configuration row each one-robot transition reaches, when kept per pair
        (:class:`~gather_verify.engine.bulk_step.PairRows`); None when not."""
        return None

    def after_rows(self, codes: np.ndarray, cells: np.ndarray | None, src: np.ndarray,
                   robot: np.ndarray, new: np.ndarray, event: np.ndarray | None,
                   succ_codes: np.ndarray | None) -> tuple[np.ndarray, np.ndarray | None]:
        """The configuration row each transition reaches, and the successors' codes (when
        computed)."""
        raise NotImplementedError

    def rows_of(self, codes: np.ndarray) -> np.ndarray:
        """The configuration rows of states given by their robot codes."""
        raise NotImplementedError

    def idle(self, codes: np.ndarray) -> np.ndarray:
        """Per state, whether every robot is idle (no pending step)."""
        raise NotImplementedError

    def witness(self, keys: np.ndarray, src: np.ndarray,
                succ_codes: np.ndarray | None) -> Callable[[int], tuple[Any, State]]:
        """The event and successor of the ``i``-th transition of a bulk step, concretely."""
        raise NotImplementedError


@dataclass
class Searched:
    """What :func:`bulk_search` found: the stored states' columns and graph, and why it
    stopped (the fields of an :class:`~gather_verify.engine.explore.Exploration`). With the
    graph kept, ``parents`` is None: they are read off the edges when first asked for
    (:func:`~gather_verify.engine.columns.first_sources`)."""

    index: KeyIndex
    parents: Growing | None
    offsets: np.ndarray
    targets: GrowingIds
    weights: Growing | GrowingBits
    seeds: int
    transitions: int
    changed_loops: int
    stopped: Stop | str | None
    peak: float

    def fields(self) -> dict[str, Any]:
        count, offsets, targets = self.index.count, self.offsets, self.targets.column()
        parents = IntColumn(self.parents.array()) if self.parents is not None else \
            LazyColumn(lambda: first_sources(offsets, targets, self.seeds, count))
        weights = self.weights.column() if isinstance(self.weights, GrowingBits) else \
            IntColumn(self.weights.array())
        return {"keys": IntColumn(self.index.keys[:count]), "parents": parents,
                "offsets": IntColumn(offsets), "targets": targets,
                "weights": weights, "changed_loops": self.changed_loops,
                "states": count, "transitions": self.transitions,
                "stopped": self.stopped, "peak_rss_mb": self.peak}


def bulk_search(face: Face, checks: Checks, columns: ColumnChecks, index: KeyIndex, seeds: int,
                *, limits: Limits, started: float, graph: bool, settle: bool,
                reserve: int = 1 << 16, edges: int = 1 << 16) -> Searched:
    """The breadth-first search of both bulk engines, a chunk of states at a time, from the
    ``seeds`` first keys of ``index``: the limits, the properties evaluated on each chunk,
    the graph's columns (``reserve`` states and ``edges`` transitions reserved up front) and
    the stop; ``face`` does what oblivious and luminous robots do differently. Each chunk is
    one :meth:`_Run.step`, driven by :func:`~gather_verify.engine.chunks.drive`.

    With the graph kept, what a state costs is mostly its edges: each is its target's id,
    three bytes while the ids fit (below ``2**24``), else four, and its weight, one bit while
    every weight is 0 or 1 (ASYNC: a Look or a one-edge Move), else a byte; each expanded
    state's out-degree is a byte (wider when one is larger), the offsets are summed from
    them once the search is over and the hash table freed; no parents are stored (the
    edges give them, :func:`first_sources`)."""
    run = _Run(face, checks, columns, index, seeds, graph, reserve, edges,
               min(limits.max_states, MAX_IDS), settle)
    PROGRESS.states = 1
    drive(run, limits, started)
    return run.searched()


class _Chunk:
    """One chunk's arrays as :meth:`_Run.step`'s phases hand them on, let go together when
    the step returns (so the next chunk's arrays reuse their room in the heap): its keys,
    codes, cells, configuration rows, idle flags and ranks; the properties' failures and the
    first halting one; the scheduler's events (``keyed`` when they come with their keys) and
    their changes; where the events are cut (region, halt, states limit) and why."""

    hi: int
    K: Any
    codes: Any
    cells: Any
    rows: Any
    idle: Any
    rank: Any
    failing: Any
    halt: Any
    limit_src: int
    keyed: Any
    bulk: Any
    src: Any
    weight: Any
    robot: Any = None
    new: Any = None
    event: Any = None
    old: Any = None
    single: bool
    cut: int
    stop_src: int
    stop: Stop | str | None
    succ_codes: Any
    known: int
    fresh_src: Any
    fresh_keys: Any
    expanded: int


class _Run:
    """One bulk search on the paper's world between its chunks (:class:`~gather_verify.
    engine.chunks.Chunks`): the graph's columns (out-degrees, targets, weights) or, without
    the graph, the parents; the transitions and changed self-loops counted, where the next
    chunk starts and its size, the peak memory and why it stopped."""

    def __init__(self, face: Face, checks: Checks, columns: ColumnChecks, index: KeyIndex,
                 seeds: int, graph: bool, reserve: int, edges: int, max_states: int,
                 settle: bool):
        self.face, self.checks, self.columns, self.index = face, checks, columns, index
        self.seeds, self.graph, self.max_states, self.settle = seeds, graph, max_states, settle
        self.parents = None if graph else Growing(np.int32, reserve)
        if self.parents is not None:
            self.parents.extend(np.full(seeds, -1, dtype=np.int32))
        self.degrees = Growing(np.uint8, reserve if graph else 1 << 16)
        self.targets = GrowingIds(edges if graph else 1 << 16)
        self.weight_type = np.int8 if face.n <= 127 else np.int16  # a weight: at most n edges
        bits = GrowingBits(edges if graph else 1 << 16)
        self.weights: Growing | GrowingBits = bits
        # the reserved columns are written from their start: small pages, only that resident
        for column in (self.degrees, self.targets.data, bits.data) + (
                () if self.parents is None else (self.parents,)):
            small_pages(column.data)
        self.on_chunk = checks.halting + checks.on_expansion
        self.transitions = self.changed_loops = 0
        self.stopped: Stop | str | None = None
        self.peak = rss_mb()
        self.chunk = face.chunk
        self.sid = 0

    def pending(self) -> bool:
        """Whether stored states are left to expand."""
        return self.sid < self.index.count

    def rss(self) -> float:
        """The memory in use now (MB), the peak kept."""
        self.peak = max(self.peak, rss_mb())
        return self.peak

    def chunk_done(self) -> None:
        """The progress line's count; with ``settle``, stop once every property settled."""
        PROGRESS.states = self.index.count  # read by a progress line (check --progress)
        if self.settle and self.checks.settled():
            self.stopped = Stop.SETTLED

    def step(self, limits: Limits) -> None:
        """Expand the chunk of stored states from ``sid``: their events, the successors'
        ids, the graph's columns, the properties (``stopped`` set when the search stops in
        it); the chunk's arrays are gone when it returns."""
        sid = self.sid
        c = self._events(sid)
        self._cut(c)
        ids, first = self._identify(c)
        self._record(c, sid, ids)
        del ids  # the graph has them: gone before the properties' arrays come
        self._properties(c, sid, first)
        if c.stop is not None:
            self.stopped = c.stop
        else:
            self.sid = c.hi

    def _events(self, sid: int) -> _Chunk:
        """The chunk decoded, its halting and expansion properties evaluated, and the
        scheduler's events of its states up to the first that halts (fewer states when the
        scheduler takes fewer: the rest waits, and the chunk size follows)."""
        face, checks, c = self.face, self.checks, _Chunk()
        c.hi = min(self.index.count, sid + self.chunk)
        c.K, c.codes, c.cells, c.rows, c.idle, c.rank = face.decode(
            self.index.keys[sid:c.hi].copy())
        # the last source state to expand: a halting property stops before the state it fails in
        c.limit_src = len(c.K)
        # the halting and the expansion properties, evaluated together on the whole chunk
        c.failing = self.columns.failures(self.on_chunk, c.rows, c.idle,
                                          gate=len(checks.halting))
        c.halt = self.columns.first_failure(checks.halting,
                                            c.failing[:, :len(checks.halting)])
        if c.halt is not None:
            c.limit_src = c.halt[0]
        lim = c.limit_src
        assert not face.no_actions(c.rows[:lim]).any(), \
            "a state without actions needs a halting property"
        # no transition property to feed: a round scheduler's events come with their keys
        c.keyed = None if checks.open(checks.on_transition) else \
            face.round_keys(c.K[:lim], c.codes[:lim], c.rows[:lim], c.rank[:lim])
        turns = face.turns
        c.bulk = c.keyed if c.keyed is not None else \
            face.events(c.codes[:lim], c.rows[:lim], c.rank[:lim],
                        None if turns is None else turns.of_keys(c.K[:lim]))
        taken = c.bulk.states
        if taken < lim:  # the scheduler took fewer states: the rest waits
            c.hi = sid + taken
            c.K, c.codes, c.rows = c.K[:taken], c.codes[:taken], c.rows[:taken]
            if c.cells is not None:
                c.cells = c.cells[:taken]
            c.limit_src = taken
            self.chunk = max(1, taken)
        elif self.chunk < face.chunk:
            self.chunk = min(face.chunk, 2 * self.chunk)
        return c

    def _cut(self, c: _Chunk) -> None:
        """Where the chunk's events end: at the first that leaves the region (a limit), else
        all of them (a halt stops after its state's predecessors); the transitions counted."""
        c.src, c.weight = c.bulk.source, c.bulk.weight
        if c.keyed is not None:  # no changes listed; the last event may leave the region
            c.single, leaving = False, c.keyed.leaves
            c.cut = len(c.src) - leaving
        else:
            c.robot, c.new, c.event = c.bulk.robot, c.bulk.code, c.bulk.event  # the changes
            c.single = c.event is None  # one change per event (event c is change c)
            outside = np.flatnonzero(c.new == OUTSIDE)  # a move out of the region: a limit
            leaving = len(outside) > 0
            c.cut = len(c.src) if not leaving else int(outside[0]) if c.single else \
                int(c.event[outside[0]])
        if leaving:
            c.stop_src = int(c.src[c.cut])
            c.stop = Stop.REGION
            self.transitions += c.cut + 1
        else:
            c.stop_src = c.limit_src
            c.stop = c.halt[1].name if c.halt is not None and c.halt[0] == c.limit_src else None
            self.transitions += c.cut
        c.src, c.weight = c.src[:c.cut], c.weight[:c.cut]

    def _identify(self, c: _Chunk) -> tuple[np.ndarray, np.ndarray]:
        """The successors' keys and their ids (new states get the next ids in order of first
        occurrence: the BFS order), cut after the first source whose expansion passes the
        states limit; returns the ids and where each new state first occurs."""
        face, index = self.face, self.index
        if c.keyed is not None:
            succ, c.succ_codes = c.keyed.keys[:c.cut], None
        else:
            changes = c.cut if c.single else int(np.searchsorted(c.event, c.cut))
            c.robot, c.new = c.robot[:changes], c.new[:changes]
            if not c.single:
                c.event = c.event[:changes]
            succ, c.old, c.succ_codes = successor_keys(c.K, c.codes, c.src, c.robot, c.new,
                                                       c.event, face.canon, face.reduced,
                                                       face.compiled)
        if face.turns is not None:
            succ = with_turns(succ, c.bulk.extra, face.turns)
        c.known = index.count
        ids, first = index.find_or_add(succ)
        del succ  # its ids are what the rest reads
        c.fresh_src = c.src[first]
        if index.count > self.max_states:
            ids = self._states_limit(c, ids)
        c.fresh_keys = index.keys[c.known:index.count]
        c.expanded = c.stop_src + (c.stop in (Stop.REGION, Stop.STATES))
        return ids, first

    def _states_limit(self, c: _Chunk, ids: np.ndarray) -> np.ndarray:
        """The chunk cut after the first source whose expansion passes the states limit (if
        one does): its events, changes and new states; returns the ids kept."""
        after = c.known + np.searchsorted(c.fresh_src, np.arange(c.stop_src), side="right")
        over = np.flatnonzero(after > self.max_states)
        if not len(over):
            return ids
        c.stop_src, c.stop = int(over[0]), Stop.STATES
        keep = int(np.searchsorted(c.src, c.stop_src, side="right"))
        self.transitions -= c.cut - keep
        c.cut = keep
        c.src, c.weight, ids = c.src[:keep], c.weight[:keep], ids[:keep]
        if c.keyed is None and c.single:
            c.robot, c.new, c.old = c.robot[:keep], c.new[:keep], c.old[:keep]
        elif c.keyed is None:
            changes = int(np.searchsorted(c.event, keep))
            c.robot, c.new, c.old, c.event = (a[:changes] for a in (c.robot, c.new, c.old,
                                                                     c.event))
        if c.succ_codes is not None:
            c.succ_codes = c.succ_codes[:keep]
        m = int(np.searchsorted(c.fresh_src, c.stop_src, side="right"))
        c.fresh_src = c.fresh_src[:m]
        self.index.truncate(c.known + m)
        return ids

    def _record(self, c: _Chunk, sid: int, ids: np.ndarray) -> None:
        """The expansion properties' failures of the states expanded, the changed
        self-loops, and the graph's columns (or the new states' parents)."""
        checks = self.checks
        self.columns.record(sid, checks.on_expansion,
                            c.failing[:c.expanded, len(checks.halting):], c.rows, c.idle)
        if c.keyed is not None:  # a round's step always changes its robot's code
            changed = c.weight > 0
        elif c.single:
            changed = c.new != c.old
        else:
            changed = np.zeros(c.cut, dtype=bool)
            changed[c.event[c.new != c.old]] = True
        self.changed_loops += int(np.count_nonzero((ids == sid + c.src) & changed))
        del changed
        if not self.graph:
            assert self.parents is not None
            self.parents.extend((sid + c.fresh_src).astype(np.int32))
            return
        # (src is sorted: no widened copy of it, as bincount makes of int32 sources)
        counts = np.diff(np.searchsorted(c.src, np.arange(c.expanded + 1, dtype=c.src.dtype)))
        if len(counts) and counts.max() > np.iinfo(self.degrees.data.dtype).max:
            self.degrees.widen(np.int64)
        self.degrees.extend(counts)
        self.targets.extend(ids, self.index.count)
        weight, weights = c.weight, self.weights
        if isinstance(weights, GrowingBits) and len(weight) and weight.max() > 1:
            wide = Growing(self.weight_type, len(weights.data.data) * 8)  # a weight over 1
            wide.extend(weights.array().astype(self.weight_type))
            self.weights = weights = wide
        weights.extend(weight.astype(self.weight_type) if isinstance(weights, Growing)
                       else weight)

    def _properties(self, c: _Chunk, sid: int, first: np.ndarray) -> None:
        """The transition and discovery properties on the chunk's transitions and new
        states (the configurations they reach found once), and the halting property's
        failure where the search stops at it."""
        face, checks, columns = self.face, self.checks, self.columns
        open_transition = checks.open(checks.on_transition) and c.cut
        open_discovery = checks.open(checks.on_discovery) and len(c.fresh_keys)
        paired = None
        if c.single and (open_transition or open_discovery):
            # the configuration each transition reaches, once per (row, cell, destination)
            paired = face.pair_after(c.rows, c.cells, c.rank, c.src, c.robot, c.old, c.new)
        if open_transition:
            after, succ_codes = (paired, c.succ_codes) if paired is not None else \
                face.after_rows(c.codes, c.cells, c.src, c.robot, c.new, c.event, c.succ_codes)
            columns.transitions(sid, c.src, c.rows, after, face.witness(c.K, c.src, succ_codes))
        if open_discovery:
            fresh = decode_keys(c.fresh_keys, face.enc.base, face.n)
            fresh_rows = face.rows_of(fresh) if paired is None else \
                paired[first[:len(c.fresh_keys)]]
            columns.states(c.known, fresh_rows, face.idle(fresh), checks.on_discovery)
        halt = c.halt
        if halt is not None and c.stop == halt[1].name and halt[0] == c.stop_src:
            columns.record_halt(sid + c.stop_src, int(c.rows[c.stop_src]),
                                bool(c.idle[c.stop_src]), halt[1])

    def searched(self) -> Searched:
        """The search's result: the hash table freed first, then the offsets summed from
        the out-degrees (in slices: numpy widens each to a copy)."""
        self.peak = max(self.peak, rss_mb())
        self.index.drop_table()  # the search is over: its hash table goes before the offsets
        offsets = np.empty(0, dtype=np.int32)
        if self.graph:
            offsets = np.zeros(self.degrees.size + 1, dtype=np.int32
                               if self.targets.size <= MAX_IDS else np.int64)
            degree, step = self.degrees.array(), 1 << 16
            for lo in range(0, len(degree), step):
                hi = min(len(degree), lo + step)
                np.cumsum(degree[lo:hi], dtype=offsets.dtype, out=offsets[lo + 1:hi + 1])
                offsets[lo + 1:hi + 1] += offsets[lo]
        del self.degrees
        return Searched(self.index, self.parents, offsets, self.targets, self.weights,
                        self.seeds, self.transitions, self.changed_loops, self.stopped,
                        self.peak)


def with_turns(succ: np.ndarray, extra: np.ndarray | None, turns: Any) -> np.ndarray:
    """Successor keys with the scheduler's state after each event (``extra``, from its bulk
    face) above the robots' digits (:class:`~gather_verify.engine.encoding.Turns`)."""
    assert extra is not None, "a stateful scheduler's bulk face gives its state after each event"
    scale = np.uint64(turns.scale)
    return succ % scale + scale * extra[:len(succ)].astype(np.uint64)
