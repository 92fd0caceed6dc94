"""The bulk explorer's search loop: the same breadth-first search as :mod:`explore`, on
numpy arrays.

SEMANTICS.md §4-5. It explores exactly the states of the reference
explorer (:func:`gather_verify.engine.explore.explore_reference`), gives them the same
ids in the same order (so the same BFS parents, the same first witnesses and the
same traces), and returns the same :class:`~gather_verify.engine.explore.Exploration`.
What changes is how:

- a state is one ``uint64``: the reference key (robot codes ``cell * 5 + d``
  packed in base ``5 * cells``, sorted and minimised over ``Aut(M)`` when the
  reductions are on; :mod:`~gather_verify.engine.canonical_keys`);
- visited states live in an open-addressing hash table of ``int32`` ids over a
  ``uint64`` key column in id order (:mod:`~gather_verify.engine.key_index`);
  parents are an ``int32`` column (:mod:`~gather_verify.engine.columns`);
- the frontier is expanded a chunk of states at a time
  (:mod:`~gather_verify.engine.bulk_step`, the step the union engine takes too):
  states are grouped by configuration, the facts of each configuration (move sets,
  deadlock, class, target) are computed once through the generic algorithm
  interface and kept as a row of small integers
  (:mod:`~gather_verify.engine.facts_table`), and the scheduler's
  ``bulk_successors`` (part of the ``Scheduler`` protocol) applies them to the whole
  chunk at once, handed the states in the engine's encoding
  (``encoding.Encoding.frontier``); an event may change several robots (FSYNC/SSYNC
  rounds);
- the graph (successor ids, edge weights) is kept only when asked for
  (``graph=True``, what ``move-bound`` and ``termination`` need).

This module is the loop (:func:`bulk_search`): the limits, the properties evaluated on each
chunk, the graph's columns and the stop, for oblivious robots (:class:`Oblivious`) and
luminous ones (:mod:`~gather_verify.engine.lit_bulk`) alike, each through its
:class:`Face`. The explorer knows neither the algorithm nor the scheduler (witness events are
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

import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from functools import partial
from itertools import islice
from typing import Any, cast

import numpy as np

from gather_verify import kernels
from gather_verify.algorithms import Algorithm, get_algorithm
from gather_verify.algorithms.moves import frames_for
from gather_verify.engine.bulk_step import (
    PairRows,
    decode_chunk,
    move_masks,
    successor_codes,
    successor_keys,
)
from gather_verify.engine.canonical_keys import Canon, decode_keys
from gather_verify.engine.checks import Checks, ColumnChecks, selected, symmetric
from gather_verify.engine.columns import Growing, IntColumn
from gather_verify.engine.encoding import (
    NO_LIMITS,
    Encoding,
    Limits,
    Stop,
    region_box,
    symmetry_group,
)
from gather_verify.engine.explore import (
    Exploration,
    TurnState,
    facts_cache,
    rss_mb,
    seed_states,
    state_key,
    turns_of,
)
from gather_verify.engine.facts_table import FactsTable, RowFacts, facts_memo, make_room
from gather_verify.engine.key_index import KeyIndex
from gather_verify.model.configuration import Configuration
from gather_verify.model.geometry import Node
from gather_verify.model.symmetry import meeting_automorphisms
from gather_verify.model.view import check_detection
from gather_verify.progress import PROGRESS
from schedulers import Scheduler, State, as_scheduler, initial_state
from schedulers.base import oblivious_events

CHUNK = 1 << 14
"""States expanded per bulk step: bounds the transient arrays (a few MB)."""
EVENTS = 1 << 19
"""About how many events a bulk step may generate: the scheduler takes fewer states than
``CHUNK`` when they have more events than this (FSYNC/SSYNC rounds: up to ``6**n`` per state)."""
MAX_IDS = 2**31 - 2


def supports(initial: Configuration, scheduler: str | Scheduler, reduction: bool = True,
             anonymity: bool | None = None, symmetry: bool | None = None, frames: str = "all",
             limits: Limits = NO_LIMITS) -> bool:
    """Whether the bulk path can run this request (else use the reference path): every
    registered scheduler has the bulk interface; the key must fit 63 bits and the ids 31."""
    sched = as_scheduler(scheduler)  # an unknown name is an error, not a fallback
    symmetry = reduction if symmetry is None else symmetry
    group = symmetry_group(initial, frames) if symmetry else []
    x0, y0, x1, y1 = region_box(initial, limits.margin, group)
    base = (x1 - x0 + 1) * (y1 - y0 + 1) * 5
    turns = turns_of(sched, initial.n, False, base)
    fits = base ** initial.n < 2**63 if turns is None else turns.fits()
    return fits and min(limits.max_states, MAX_IDS) >= 1


def explore_fast(
    initial: Configuration,
    algorithm: str | Algorithm,
    scheduler: str | Scheduler,
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
    sched = as_scheduler(scheduler)
    check_detection(detection)
    frame_elements = frames_for(frames)
    anonymity = reduction if anonymity is None else anonymity
    symmetry = (reduction if symmetry is None else symmetry) and symmetric(properties)
    group = symmetry_group(initial, frames) if symmetry else []
    stateful = getattr(sched, "stateful", False)  # its state above the robots' digits
    enc = Encoding(region_box(initial, limits.margin, group), group, anonymity and not stateful)
    n = initial.n
    turns = turns_of(sched, n, anonymity, enc.base)
    facts = facts_cache(algo, initial, detection, frame_elements)
    if memo:
        make_room(limits.max_memory_mb)
    table = FactsTable(enc, n, algo, initial.meeting_nodes, detection, frame_elements,
                       meeting_automorphisms(initial),
                       facts_memo(algo, detection, frames) if memo else None,
                       targets=any(p.kind == "transition" for p in selected(properties)))

    seeds = seed_states(initial_state(initial.robots), turns)
    start_keys = np.array(list(map(state_key(enc, turns), seeds)), dtype=np.uint64)
    init_cells = np.array([[enc.code(v, None) // 5 for v in initial.robots]], dtype=np.int64)
    srt, ck = table.config_keys(init_cells)
    init_row = table.rows(ck, srt)
    checks = Checks(properties, RowFacts(table, int(init_row[0]), initial, True))
    columns = ColumnChecks(checks, lambda row, idle=None: RowFacts(table, row, initial, idle),
                           lambda rows, idle: RowFacts.many(table, initial, rows, idle),
                           table.flag_codes)
    columns.states(0, init_row, np.ones(1, dtype=bool), checks.on_discovery)

    max_states = min(limits.max_states, MAX_IDS)
    # columns reserved up front: untouched pages cost no memory, and nothing is copied
    reserve = min(max_states + max(CHUNK * 8 * n, EVENTS) + 1, 1 << 27)
    index = KeyIndex(capacity=reserve)
    _, first_seeds = index.find_or_add(start_keys)
    seeds = [seeds[i] for i in first_seeds.tolist()]
    face = Oblivious(enc, n, sched, turns, facts, bool(group or anonymity), table)
    # the graph's columns reserved too (untouched pages cost nothing): no copy as they grow,
    # so no transient second copy of the graph
    searched = bulk_search(face, checks, columns, index, len(seeds), limits=limits,
                           started=started, graph=graph, settle=settle, reserve=reserve,
                           edges=min(8 * reserve, 1 << 28))
    return Exploration(
        initial=initial, algorithm=algo, scheduler_name=scheduler if isinstance(
            scheduler, str) else sched.name, detection=detection,
        frames=frames, anonymity=anonymity, symmetry=symmetry, encoding=enc,
        **searched.fields(), violations=checks.violations,
        seconds=time.perf_counter() - started, facts=facts,
        vacuous=checks.vacuous, engine="bulk", turns=turns,
        starts=None if turns is None else seeds)


class Face:
    """What the oblivious and the luminous bulk searches do differently around the one loop,
    :func:`bulk_search`: how a chunk of keys is decoded and its configurations looked up,
    how the scheduler's bulk face is asked for their events, and how the configurations the
    transitions and the new states reach are found. A robot's code is ``cell * 5 + d``
    without lights, ``(cell * 5 + d) * K + colour`` with them (the colour one more digit)."""

    chunk = CHUNK
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


class Oblivious(Face):
    """:class:`Face` of oblivious robots: a :class:`FactsTable` of move masks."""

    def __init__(self, enc: Encoding, n: int, sched: Scheduler, turns: Any, facts: Any,
                 reduced: bool, table: FactsTable):
        super().__init__(enc, n, sched, turns, facts, reduced)
        self.table = table
        self.pairs = PairRows(table) if self.compiled else None

    def decode(self, keys: np.ndarray) -> tuple[np.ndarray, ...]:
        step = decode_chunk(keys, self.table, self.compiled)
        return step.keys, step.codes, step.cells, step.rows, step.idle, step.rank

    def no_actions(self, rows: np.ndarray) -> np.ndarray:
        return self.table.flags[rows, 0]

    def events(self, codes: np.ndarray, rows: np.ndarray, rank: np.ndarray,
               extra: np.ndarray | None) -> Any:
        # robot i's move mask: the mask of its cell's position in the sorted row
        frontier = self.enc.frontier(codes, move_masks(self.table, rows, rank,
                                                       flat=self.compiled))
        if extra is None:
            return self.sched.bulk_successors(frontier, EVENTS)
        return cast(Any, self.sched).bulk_successors(frontier, EVENTS, extra=extra)

    def pair_after(self, rows: np.ndarray, cells: np.ndarray | None, rank: np.ndarray,
                   src: np.ndarray, robot: np.ndarray, old: np.ndarray,
                   new: np.ndarray) -> np.ndarray | None:
        if self.pairs is None:
            return None
        return self.pairs.after(rows, cells, rank, src, robot, old, new)

    def after_rows(self, codes: np.ndarray, cells: np.ndarray | None, src: np.ndarray,
                   robot: np.ndarray, new: np.ndarray, event: np.ndarray | None,
                   succ_codes: np.ndarray | None) -> tuple[np.ndarray, np.ndarray | None]:
        if succ_codes is None and event is not None:  # the compiled keys left the codes out
            succ_codes = successor_codes(codes, src, robot, new, event)
        if succ_codes is None:  # one change per event, no reduction: event c is change c
            assert cells is not None
            succ_cells = cells[src].copy()
            succ_cells[np.arange(len(src)), robot] = new // 5
        else:
            succ_cells = succ_codes // 5
        return self.rows_of_cells(succ_cells), succ_codes

    def rows_of_cells(self, cells: np.ndarray) -> np.ndarray:
        srt, keys = self.table.config_keys(cells)
        return self.table.rows(keys, srt)

    def rows_of(self, codes: np.ndarray) -> np.ndarray:
        return self.rows_of_cells(codes // 5)

    def idle(self, codes: np.ndarray) -> np.ndarray:
        return np.all(codes % 5 == 0, axis=1)

    def witness(self, keys: np.ndarray, src: np.ndarray,
                succ_codes: np.ndarray | None) -> Callable[[int], tuple[Any, State]]:
        return partial(_step, self.enc, self.sched, self.facts, self.n, keys, src, succ_codes,
                       turns=self.turns)


@dataclass
class Searched:
    """What :func:`bulk_search` found: the stored states' columns and graph, and why it
    stopped (the fields of an :class:`~gather_verify.engine.explore.Exploration`)."""

    index: KeyIndex
    parents: Growing
    offsets: Growing
    targets: Growing
    weights: Growing
    transitions: int
    changed_loops: int
    stopped: Stop | str | None
    peak: float

    def fields(self) -> dict[str, Any]:
        return {"keys": IntColumn(self.index.keys[:self.index.count]),
                "parents": IntColumn(self.parents.array()),
                "offsets": IntColumn(self.offsets.array()),
                "targets": IntColumn(self.targets.array()),
                "weights": IntColumn(self.weights.array()), "changed_loops": self.changed_loops,
                "states": self.index.count, "transitions": self.transitions,
                "stopped": self.stopped, "peak_rss_mb": self.peak}


def bulk_search(face: Face, checks: Checks, columns: ColumnChecks, index: KeyIndex, seeds: int,
                *, limits: Limits, started: float, graph: bool, settle: bool,
                reserve: int = 1 << 16, edges: int = 1 << 16) -> Searched:
    """The breadth-first search of both bulk engines, a chunk of states at a time, from the
    ``seeds`` first keys of ``index``: the limits, the properties evaluated on each chunk,
    the graph's columns (``reserve`` states and ``edges`` transitions reserved up front) and
    the stop; ``face`` does what oblivious and luminous robots do differently."""
    enc, n, turns = face.enc, face.n, face.turns
    max_states = min(limits.max_states, MAX_IDS)
    parents = Growing(np.int32, reserve)
    parents.extend(np.full(seeds, -1, dtype=np.int32))
    offsets = Growing(np.int32, reserve if graph else 1 << 16)  # int64 past 2**31 edges (widen)
    targets = Growing(np.int32, edges if graph else 1 << 16)
    weight_type = np.int8 if n <= 127 else np.int16  # a weight is at most n edges
    weights = Growing(weight_type, edges if graph else 1 << 16)
    on_chunk = checks.halting + checks.on_expansion
    transitions = changed_loops = 0
    stopped: Stop | str | None = None
    peak = rss_mb()
    sid = 0
    chunk = face.chunk
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
        bulk = face.events(codes[:limit_src], rows[:limit_src], rank[:limit_src],
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
        robot, new, event = bulk.robot, bulk.code, bulk.event  # the changes
        single = event is None  # one change per event (event c is change c)
        outside = np.flatnonzero(new < 0)
        cut = len(src)
        if len(outside):
            cut = int(outside[0]) if single else int(event[outside[0]])
            stop_src = int(src[cut])
            stop = Stop.REGION
            transitions += cut + 1
        else:
            stop_src = limit_src
            stop = halt[1].name if halt is not None and halt[0] == limit_src else None
            transitions += cut
        src, weight = src[:cut], weight[:cut]
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
        expanded = stop_src + (stop in (Stop.REGION, Stop.STATES))
        columns.record(sid, checks.on_expansion, failing[:expanded, len(checks.halting):],
                       rows, idle)
        open_transition = checks.open(checks.on_transition) and cut
        open_discovery = checks.open(checks.on_discovery) and len(fresh_keys)
        paired = None
        if single and (open_transition or open_discovery):
            # the configuration each transition reaches, once per (row, cell, destination)
            paired = face.pair_after(rows, cells, rank, src, robot, old, new)
        if open_transition:
            after, succ_codes = (paired, succ_codes) if paired is not None else \
                face.after_rows(codes, cells, src, robot, new, event, succ_codes)
            columns.transitions(sid, src, rows[src], after, face.witness(K, src, succ_codes))
        if open_discovery:
            fresh = decode_keys(fresh_keys, enc.base, n)
            fresh_rows = face.rows_of(fresh) if paired is None else \
                paired[first[:len(fresh_keys)]]
            columns.states(known, fresh_rows, face.idle(fresh), checks.on_discovery)
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
            stopped = Stop.SETTLED
            break
    if graph:
        offsets.extend(np.array([targets.size], dtype=np.int64))
    peak = max(peak, rss_mb())
    return Searched(index, parents, offsets, targets, weights, transitions, changed_loops,
                    stopped, peak)


def with_turns(succ: np.ndarray, extra: np.ndarray | None, turns: Any) -> np.ndarray:
    """Successor keys with the scheduler's state after each event (``extra``, from its bulk
    face) above the robots' digits (:class:`~gather_verify.engine.encoding.Turns`)."""
    assert extra is not None, "a stateful scheduler's bulk face gives its state after each event"
    scale = np.uint64(turns.scale)
    return succ % scale + scale * extra[:len(succ)].astype(np.uint64)


def _step(enc: Encoding, sched: Any, facts: Any, n: int, K: np.ndarray, src: np.ndarray,
          succ_codes: np.ndarray | None, i: int, turns: Any = None) -> tuple[Any, State]:
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

    if turns is not None:
        extra = turns.extra(int(K[src[i]]))
        event, succ, after = next(islice(oblivious_events(sched, state, extra, ms), k, None))
        succ = TurnState(succ, after)
    else:
        event, succ = next(islice(sched.successors(state, ms), k, None))
    if codes is not None:  # pragma: no branch - the two faces of the scheduler agree
        assert [enc.code(v, p) for v, p in succ] == codes.tolist()
    return event, succ
