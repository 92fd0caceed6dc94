"""The bulk explorer's search loop: the same breadth-first search as :mod:`explore`, on
numpy arrays.

SEMANTICS.md §4-5. It explores exactly the states of the reference
explorer (:func:`gather_verify.engine.explore.explore_reference`), gives them the same
ids in the same order (so the same BFS parents, the same first witnesses and the
same traces), and returns the same :class:`~gather_verify.engine.explore.Exploration`.
What changes is how:

- a state is one ``uint64``: the reference key (robot codes ``cell * SLOTS + d``
  packed in base ``SLOTS * cells``, sorted and minimised over ``Aut(M)`` when the
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

This module sets the search up and runs the loop
(:func:`~gather_verify.engine.bulk_loop.bulk_search`: the limits, the properties evaluated
on each chunk, the graph's columns and the stop) for oblivious robots (:class:`Oblivious`)
and luminous ones (``lights``, :mod:`~gather_verify.engine.lit_bulk`) alike, each through
its :class:`~gather_verify.engine.bulk_loop.Face`. The explorer knows neither the algorithm nor the scheduler (witness events are
asked of the scheduler's ``successors``, by their rank among the state's events):
only a key that does not fit 64 bits, or more states than an ``int32`` id holds,
make :func:`supports` say no and the caller uses the reference path.

>>> from gather_verify.model.configuration import Configuration
>>> c = Configuration([(0, 0), (3, 1), (1, 4)], [(2, 2)], initial=True)
>>> e = explore_fast(c, "go-to-target", "ssync", reduction=False)
>>> e.states, e.transitions, e.engine
(216, 2556, 'bulk')
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable
from functools import partial
from itertools import islice
from typing import Any, cast

import numpy as np

from gather_verify.algorithms import Algorithm
from gather_verify.engine.bulk_loop import MAX_IDS, Face, bulk_search
from gather_verify.engine.bulk_step import (
    PairRows,
    decode_chunk,
    move_masks,
    successor_codes,
)
from gather_verify.engine.checks import Checks, ColumnChecks, selected
from gather_verify.engine.encoding import (
    NO_LIMITS,
    Encoding,
    Limits,
    region_box,
    symmetry_group,
)
from gather_verify.engine.explore import (
    Asked,
    Exploration,
    Request,
    TurnState,
    facts_cache,
    resolve,
    seed_states,
    state_key,
    turns_of,
)
from gather_verify.engine.facts_table import FactsTable, RowFacts, facts_memo, make_room
from gather_verify.engine.key_index import KeyIndex
from gather_verify.engine.lit_bulk import luminous
from gather_verify.model.configuration import Configuration
from gather_verify.model.geometry import SLOTS, Node
from gather_verify.model.symmetry import meeting_automorphisms
from schedulers import Scheduler, State, as_scheduler, initial_state
from schedulers.base import RoundKeys, bulk_round_keys, oblivious_events

CHUNK = 1 << 14
"""States expanded per bulk step: bounds the transient arrays (a few MB)."""
EVENTS = 1 << 19
"""About how many events a bulk step may generate: the scheduler takes fewer states than
``CHUNK`` when they have more events than this (FSYNC/SSYNC rounds: up to ``6**n`` per state)."""


def supports(initial: Configuration, scheduler: str | Scheduler, reduction: bool = True,
             anonymity: bool | None = None, symmetry: bool | None = None, frames: str = "all",
             limits: Limits = NO_LIMITS) -> bool:
    """Whether the bulk path can run this request (else use the reference path): every
    registered scheduler has the bulk interface; the key must fit 63 bits and the ids 31."""
    sched = as_scheduler(scheduler)  # an unknown name is an error, not a fallback
    symmetry = reduction if symmetry is None else symmetry
    group = symmetry_group(initial, frames) if symmetry else []
    x0, y0, x1, y1 = region_box(initial, limits.margin, group)
    base = (x1 - x0 + 1) * (y1 - y0 + 1) * SLOTS
    turns = turns_of(sched, initial.n, False, base)
    fits = base ** initial.n < 2**63 if turns is None else turns.fits()
    return fits and min(limits.max_states, MAX_IDS) >= 1


def explore_fast(initial: Configuration, algorithm: str | Algorithm, scheduler: str | Scheduler,
                 *, graph: bool = True, memo: bool = False, **options: Any) -> Exploration:
    """Breadth-first search in bulk; same result as the reference explorer.

    ``settle``: stop after the chunk in which every requested property got its
    counterexample (as :func:`~gather_verify.engine.explore.explore_reference`).

    ``graph=False`` keeps no edges (the result's ``offsets``, ``targets`` and
    ``weights`` are empty): enough for the safety properties and the state count.
    ``memo=True`` shares the facts of configurations with the other searches of this
    process for the same algorithm object (:func:`facts_memo`): what a sweep wants,
    where many searches meet the same configurations; a single large search gains
    nothing from it (with lights it is unused: the facts are kept per search, as the
    reference keeps them).

    ``lights``: luminous robots (§10; ``colours``: their initial colours, default 0), through
    :mod:`~gather_verify.engine.lit_bulk` (ask its ``unsupported`` first).
    """
    started = time.perf_counter()
    asked = Asked(**options)
    req = resolve(initial, algorithm, scheduler, asked)
    detection, limits, lights = asked.detection, asked.limits, asked.lights
    if lights is None:
        face, checks, columns, start = _oblivious(initial, req, detection, asked.frames,
                                                  asked.properties, memo, limits)
    else:
        face, checks, columns, start = luminous(initial, req, detection, lights, asked.colours,
                                                asked.properties)
    n, turns = initial.n, face.turns
    seeds = seed_states(start, turns)
    max_states = min(limits.max_states, MAX_IDS)
    # columns reserved up front: untouched pages cost no memory, and nothing is copied
    reserve = min(max_states + max(CHUNK * 8 * n, EVENTS) + 1, 1 << 27)
    index = KeyIndex(capacity=reserve)
    _, first_seeds = index.find_or_add(np.array(list(map(state_key(face.enc, turns), seeds)),
                                                dtype=np.uint64))
    seeds = [seeds[i] for i in first_seeds.tolist()]
    # the graph's columns reserved too (untouched pages cost nothing): no copy as they grow,
    # so no transient second copy of the graph
    searched = bulk_search(face, checks, columns, index, len(seeds), limits=limits,
                           started=started, graph=graph, settle=asked.settle, reserve=reserve,
                           edges=min(8 * reserve, 1 << 28))
    return Exploration(
        initial=initial, algorithm=req.algorithm, scheduler_name=scheduler if isinstance(
            scheduler, str) else req.scheduler.name, detection=detection,
        frames=asked.frames, anonymity=req.anonymity, symmetry=req.symmetry, encoding=face.enc,
        **searched.fields(), violations=checks.violations,
        seconds=time.perf_counter() - started, facts=face.facts,
        vacuous=checks.vacuous, engine="bulk", turns=turns,
        starts=None if turns is None else seeds, lights=lights,
        colours=asked.initial_colours(n))


def _oblivious(initial: Configuration, req: Request, detection: str, frames: str,
               properties: Iterable[str] | None, memo: bool, limits: Limits
               ) -> tuple[Oblivious, Checks, ColumnChecks, State]:
    """The oblivious side of :func:`explore_fast`'s setup: its :class:`Oblivious` face (the
    encoding, the configurations' :class:`FactsTable`), the property checks on that table
    (the initial configuration's discovery checked), and the initial state."""
    algo, n = req.algorithm, initial.n
    enc = Encoding(req.box, req.group, req.relabel)
    turns = turns_of(req.scheduler, n, req.anonymity, enc.base)
    facts = facts_cache(algo, initial, detection, req.frame_elements)
    if memo:
        make_room(limits.max_memory_mb)
    table = FactsTable(enc, n, algo, initial.meeting_nodes, detection, req.frame_elements,
                       meeting_automorphisms(initial),
                       facts_memo(algo, detection, frames) if memo else None,
                       targets=any(p.kind == "transition" for p in selected(properties)))
    init_cells = np.array([[enc.code(v, None) // SLOTS for v in initial.robots]], dtype=np.int64)
    srt, ck = table.config_keys(init_cells)
    init_row = table.rows(ck, srt)
    checks = Checks(properties, RowFacts(table, int(init_row[0]), initial, True))
    columns = ColumnChecks(checks, lambda row, idle=None: RowFacts(table, row, initial, idle),
                           lambda rows, idle: RowFacts.many(table, initial, rows, idle),
                           table.flag_codes)
    columns.states(0, init_row, np.ones(1, dtype=bool), checks.on_discovery)
    return (Oblivious(enc, n, req.scheduler, turns, facts, req.reduced, table), checks, columns,
            initial_state(initial.robots))


class Oblivious(Face):
    """:class:`~gather_verify.engine.bulk_loop.Face` of oblivious robots: a
    :class:`FactsTable` of move masks."""

    chunk = CHUNK

    def __init__(self, enc: Encoding, n: int, sched: Scheduler, turns: Any, facts: Any,
                 reduced: bool, table: FactsTable):
        super().__init__(enc, n, sched, turns, facts, reduced)
        self.table = table
        self.pairs = PairRows(table) if self.compiled else None
        # a round scheduler's events and their keys in one compiled pass (no reduction: the
        # keys are the codes' plain sum; a stateful scheduler's keys carry its state too)
        self.rounds = self.compiled and not reduced and turns is None and \
            getattr(sched, "rounds", False)
        self.subsets = sched.activations(n) if self.rounds else None

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

    def round_keys(self, keys: np.ndarray, codes: np.ndarray, rows: np.ndarray,
                   rank: np.ndarray) -> RoundKeys | None:
        if not self.rounds:
            return None
        frontier = self.enc.frontier(codes, move_masks(self.table, rows, rank, flat=True))
        return bulk_round_keys(frontier, EVENTS, self.subsets, keys, self.canon.powers)

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
            succ_cells[np.arange(len(src)), robot] = new // SLOTS
        else:
            succ_cells = succ_codes // SLOTS
        return self.rows_of_cells(succ_cells), succ_codes

    def rows_of_cells(self, cells: np.ndarray) -> np.ndarray:
        srt, keys = self.table.config_keys(cells)
        return self.table.rows(keys, srt)

    def rows_of(self, codes: np.ndarray) -> np.ndarray:
        return self.rows_of_cells(codes // SLOTS)

    def idle(self, codes: np.ndarray) -> np.ndarray:
        pending = codes % SLOTS
        out = pending[:, 0] == 0
        for j in range(1, self.n):  # column by column: twice as fast as all(axis=1) on n columns
            out &= pending[:, j] == 0
        return out

    def witness(self, keys: np.ndarray, src: np.ndarray,
                succ_codes: np.ndarray | None) -> Callable[[int], tuple[Any, State]]:
        return partial(_step, self.enc, self.sched, self.facts, self.n, keys, src, succ_codes,
                       turns=self.turns)


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
