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

import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from gather_verify import kernels
from gather_verify.engine.bulk_step import successor_keys
from gather_verify.engine.canonical_keys import Canon, decode_keys
from gather_verify.engine.checks import Checks, ColumnChecks
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
    the stop; ``face`` does what oblivious and luminous robots do differently.

    With the graph kept, what a state costs is mostly its edges: each is its target's id,
    three bytes while the ids fit (below ``2**24``), else four, and its weight, one bit while
    every weight is 0 or 1 (ASYNC: a Look or a one-edge Move), else a byte; each expanded
    state's out-degree is a byte (wider when one is larger), the offsets are summed from
    them once the search is over and the hash table freed; no parents are stored (the
    edges give them, :func:`first_sources`)."""
    enc, n, turns = face.enc, face.n, face.turns
    max_states = min(limits.max_states, MAX_IDS)
    parents = None if graph else Growing(np.int32, reserve)
    if parents is not None:
        parents.extend(np.full(seeds, -1, dtype=np.int32))
    degrees = Growing(np.uint8, reserve if graph else 1 << 16)
    targets = GrowingIds(edges if graph else 1 << 16)
    weight_type = np.int8 if n <= 127 else np.int16  # a weight is at most n edges
    bits = GrowingBits(edges if graph else 1 << 16)
    weights: Growing | GrowingBits = bits
    # the reserved columns are written from their start: small pages, only that is resident
    for column in (degrees, targets.data, bits.data) + (() if parents is None else (parents,)):
        small_pages(column.data)
    on_chunk = checks.halting + checks.on_expansion
    transitions = changed_loops = 0
    stopped: Stop | str | None = None
    peak = rss_mb()
    sid = 0
    chunk = face.chunk
    # a chunk's changes (a view of its events'), released at the chunk's end with the rest
    robot: Any
    new: Any
    event: Any
    old: Any
    after: Any
    counts: Any
    PROGRESS.states = 1
    while sid < index.count and stopped is None:
        if time.perf_counter() - started > limits.max_seconds:
            stopped = Stop.TIME
            break
        peak = max(peak, rss_mb())
        if peak > limits.max_memory_mb:
            stopped = Stop.MEMORY
            break
        hi = min(index.count, sid + chunk)
        K, codes, cells, rows, idle, rank = face.decode(index.keys[sid:hi].copy())
        # the last source state to expand: a halting property stops before the state it fails in
        limit_src = len(K)
        # the halting and the expansion properties, evaluated together on the whole chunk
        failing = columns.failures(on_chunk, rows, idle, gate=len(checks.halting))
        halt = columns.first_failure(checks.halting, failing[:, :len(checks.halting)])
        if halt is not None:
            limit_src = halt[0]
        assert not face.no_actions(rows[:limit_src]).any(), \
            "a state without actions needs a halting property"
        # no transition property to feed: a round scheduler's events come with their keys
        keyed = None if checks.open(checks.on_transition) else \
            face.round_keys(K[:limit_src], codes[:limit_src], rows[:limit_src], rank[:limit_src])
        bulk: Any = keyed if keyed is not None else \
            face.events(codes[:limit_src], rows[:limit_src], rank[:limit_src],
                        None if turns is None else turns.of_keys(K[:limit_src]))
        if bulk.states < limit_src:  # the scheduler took fewer states: the rest waits
            hi = sid + bulk.states
            K, codes, rows = K[:bulk.states], codes[:bulk.states], rows[:bulk.states]
            if cells is not None:
                cells = cells[:bulk.states]
            limit_src = bulk.states
            chunk = max(1, bulk.states)
        elif chunk < face.chunk:
            chunk = min(face.chunk, 2 * chunk)
        src, weight = bulk.source, bulk.weight
        stop: Stop | str | None
        if keyed is not None:  # no changes listed; the last event may leave the region
            single, leaving = False, keyed.leaves
            cut = len(src) - leaving
        else:
            robot, new, event = bulk.robot, bulk.code, bulk.event  # the changes
            single = event is None  # one change per event (event c is change c)
            outside = np.flatnonzero(new == OUTSIDE)  # a move out of the region: a limit
            leaving = len(outside) > 0
            cut = len(src) if not leaving else int(outside[0]) if single else \
                int(event[outside[0]])
        if leaving:
            stop_src = int(src[cut])
            stop = Stop.REGION
            transitions += cut + 1
        else:
            stop_src = limit_src
            stop = halt[1].name if halt is not None and halt[0] == limit_src else None
            transitions += cut
        src, weight = src[:cut], weight[:cut]
        if keyed is not None:
            succ, succ_codes = keyed.keys[:cut], None
        else:
            changes = cut if single else int(np.searchsorted(event, cut))
            robot, new = robot[:changes], new[:changes]
            if not single:
                event = event[:changes]
            succ, old, succ_codes = successor_keys(K, codes, src, robot, new, event, face.canon,
                                                   face.reduced, face.compiled)
        if turns is not None:
            succ = with_turns(succ, bulk.extra, turns)
        # new states get the next ids in order of first occurrence: the BFS order
        known = index.count
        ids, first = index.find_or_add(succ)
        fresh_src = src[first]
        # the states limit: after the first source whose expansion passes it
        if index.count > max_states:
            after = known + np.searchsorted(fresh_src, np.arange(stop_src), side="right")
            over = np.flatnonzero(after > max_states)
            if len(over):
                stop_src, stop = int(over[0]), Stop.STATES
                keep = int(np.searchsorted(src, stop_src, side="right"))
                transitions -= cut - keep
                cut = keep
                src, weight, succ, ids = src[:cut], weight[:cut], succ[:cut], ids[:cut]
                if keyed is None and single:
                    robot, new, old = robot[:cut], new[:cut], old[:cut]
                elif keyed is None:
                    changes = int(np.searchsorted(event, cut))
                    robot, new, old, event = (a[:changes] for a in (robot, new, old, event))
                if succ_codes is not None:
                    succ_codes = succ_codes[:cut]
                m = int(np.searchsorted(fresh_src, stop_src, side="right"))
                fresh_src = fresh_src[:m]
                index.truncate(known + m)
        del succ  # its ids are what the rest reads
        fresh_keys = index.keys[known:index.count]
        expanded = stop_src + (stop in (Stop.REGION, Stop.STATES))
        columns.record(sid, checks.on_expansion, failing[:expanded, len(checks.halting):],
                       rows, idle)
        if keyed is not None:  # a round's step always changes its robot's code
            changed = weight > 0
        elif single:
            changed = new != old
        else:
            changed = np.zeros(cut, dtype=bool)
            changed[event[new != old]] = True
        changed_loops += int(np.count_nonzero((ids == sid + src) & changed))
        if graph:
            # (src is sorted: no widened copy of it, as bincount makes of int32 sources)
            counts = np.diff(np.searchsorted(src, np.arange(expanded + 1, dtype=src.dtype)))
            if len(counts) and counts.max() > np.iinfo(degrees.data.dtype).max:
                degrees.widen(np.int64)
            degrees.extend(counts)
            targets.extend(ids, index.count)
            if isinstance(weights, GrowingBits) and len(weight) and weight.max() > 1:
                wide = Growing(weight_type, len(weights.data.data) * 8)  # a weight over 1
                wide.extend(weights.array().astype(weight_type))
                weights = wide
            weights.extend(weight.astype(weight_type) if isinstance(weights, Growing) else weight)
        else:
            assert parents is not None
            parents.extend((sid + fresh_src).astype(np.int32))
        del ids, changed  # the graph has them: gone before the properties' arrays come
        open_transition = checks.open(checks.on_transition) and cut
        open_discovery = checks.open(checks.on_discovery) and len(fresh_keys)
        paired = None
        if single and (open_transition or open_discovery):
            # the configuration each transition reaches, once per (row, cell, destination)
            paired = face.pair_after(rows, cells, rank, src, robot, old, new)
        if open_transition:
            after, succ_codes = (paired, succ_codes) if paired is not None else \
                face.after_rows(codes, cells, src, robot, new, event, succ_codes)
            columns.transitions(sid, src, rows, after, face.witness(K, src, succ_codes))
        if open_discovery:
            fresh = decode_keys(fresh_keys, enc.base, n)
            fresh_rows = face.rows_of(fresh) if paired is None else \
                paired[first[:len(fresh_keys)]]
            columns.states(known, fresh_rows, face.idle(fresh), checks.on_discovery)
        if halt is not None and stop == halt[1].name and halt[0] == stop_src:
            columns.record_halt(sid + stop_src, int(rows[stop_src]), bool(idle[stop_src]), halt[1])
        if stop is not None:
            stopped = stop
            break
        sid = hi
        # the chunk's arrays go before the next chunk makes its own, so the heap reuses their
        # room: two chunks' arrays alive at once grow it, fragmented, by as much again
        del K, codes, cells, rows, idle, rank, failing, bulk, keyed, src, weight, \
            succ_codes, first, fresh_src, fresh_keys, paired
        robot = new = event = old = after = counts = None
        PROGRESS.states = index.count  # read by a progress line (check --progress)
        if settle and checks.settled():
            stopped = Stop.SETTLED
            break
    peak = max(peak, rss_mb())
    index.drop_table()  # the search is over: its hash table goes before the offsets come
    offsets = np.empty(0, dtype=np.int32)
    if graph:
        offsets = np.zeros(degrees.size + 1, dtype=np.int32 if targets.size <= MAX_IDS
                           else np.int64)
        degree, step = degrees.array(), 1 << 16
        for lo in range(0, len(degree), step):  # in slices: numpy widens each to a copy
            hi = min(len(degree), lo + step)
            np.cumsum(degree[lo:hi], dtype=offsets.dtype, out=offsets[lo + 1:hi + 1])
            offsets[lo + 1:hi + 1] += offsets[lo]
    del degrees
    return Searched(index, parents, offsets, targets, weights, seeds, transitions,
                    changed_loops, stopped, peak)


def with_turns(succ: np.ndarray, extra: np.ndarray | None, turns: Any) -> np.ndarray:
    """Successor keys with the scheduler's state after each event (``extra``, from its bulk
    face) above the robots' digits (:class:`~gather_verify.engine.encoding.Turns`)."""
    assert extra is not None, "a stateful scheduler's bulk face gives its state after each event"
    scale = np.uint64(turns.scale)
    return succ % scale + scale * extra[:len(succ)].astype(np.uint64)
