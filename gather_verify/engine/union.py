"""One state graph per shape of meeting-node set: every initial configuration whose M
has that shape at once.

The configurations of a sweep that share their meeting nodes ``M``
(up to an isometry) explore largely the same states: on the 4 x 4 box the
union of their reachable states is 80-120 times smaller than the sum of
their searches. This module explores that union once (the bulk explorer's
machinery: the same chunk step, :mod:`~gather_verify.engine.bulk_step`, over a
:class:`~gather_verify.engine.key_index.KeyIndex` and a
:class:`~gather_verify.engine.facts_table.FactsTable`) and decides every
configuration's row from it:

- each configuration is moved by an isometry of the robots' frame group
  (:func:`shape_isometry`: with all 8 frames a rotation or reflection too, with
  chirality a rotation, with a compass a translation only) so that its ``M``
  is its shape's canonical ``M0`` (results are invariant under those
  isometries and no others, SEMANTICS.md §3), and the search is seeded with all
  of them: one graph for the up to 8 images of ``M`` and their translations,
  where there was one per translation class (on the 4 x 4 box, the largest
  class's union holds 522,534 states where its 8 unions held 2.83 million);
  states are merged by the elements of ``Aut(M0)`` the frames allow, as in one
  search (:func:`~gather_verify.engine.encoding.symmetry_group`);
- per state, the facts the per-configuration search checks: a deadlock
  (``final``), a configuration in U (``no-ungatherable``), an edge that changes
  the target (``target-invariance``), no rule (``defined``), a cycle (a changed
  self-loop of the quotient, or a component), and the bounding box, closed
  under ``Aut(M0)``, of its robots;
- one peeling of sinks (Kahn's algorithm on the reverse graph) orders the
  states that reach no cycle, and one pass in that order gives, per state,
  every violation reachable from it, the largest total moves (the longest
  path) and the box of every node reachable from it;
- per configuration, the number of states and transitions its own search
  would count (the orbits it reaches and their events) come from one pass of
  64-bit sets of seeds.

The region rule (:data:`~gather_verify.engine.region.PLANE`: ``plane_check.run_check`` searches
the MER grown by a margin of 2, doubled while the region stops the search, up to 32): the union is explored
in the union of the configurations' regions with margin ``UNION_MARGIN``; a
configuration's own search ends at the least margin of 2, 4, 8, 16, 32 whose
region holds every node it reaches, and its counts, verdict and moves are
those of that last search (a search that has met a violation is the last: one
that needs a margin past 2 and reaches a violation goes back to its own check,
which alone knows whether its margin-2 prefix meets it). A configuration is
handed to the per-configuration check instead (:func:`gather_verify.sweeps.mclass.decide_class` returns it in ``fallback``) when that is
not settled here exactly: a reachable state left the union's region or has
no rule, a cycle is reachable, its space passes ``max_states``, the target is
not equivariant on a reachable configuration, or move-bound is its first
failing property (its trace is the longest path of its own graph). A safety
violation's trace is the per-configuration search's own: its first witness
and BFS path, found by a BFS of the union from its seed, along the successors
in the order its own search makes them. For a seed moved by a translation that
is the union's own order (a translation keeps the order of nodes); for one
moved by a rotation or reflection, :class:`Oriented` computes it (each state
moved back, its representative there, that representative's events in the
scheduler's order). The target must commute with those isometries on every
reachable configuration, as with ``Aut(M0)``, or the seed falls back.

The scheduler is any that says ``union = True`` (ASYNC, FSYNC, SSYNC, centralized,
round-robin: :func:`unsupported`);
its ``bulk_successors`` makes the events, one change each (ASYNC's Looks and Moves) or a
round that changes several robots at once (FSYNC, SSYNC), fewer states at a time when their
events pass ``EVENTS``. A ``stateful`` scheduler (round-robin) keeps its state in the keys
as the bulk engine does (:class:`~gather_verify.engine.encoding.Turns`); a seed is then
every start its configuration's own search keeps (:func:`seed_starts`), counted together,
and a stuck state's turn going round the robots (``RING``: ``n`` states that make no move
and hold the same facts) is one state for the peeling and the counts (:func:`_rings`).

Time and memory limits are not deterministic: a class whose union search takes
longer than one configuration's time limit, or leaves the process over its memory
limit, is handed to the per-configuration checks whole.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any, cast

import numpy as np

from gather_verify import kernels
from gather_verify.algorithms import Algorithm, AlgorithmCrash, get_algorithm
from gather_verify.algorithms.moves import frames_for
from gather_verify.engine import union_kernels
from gather_verify.engine.bulk_loop import with_turns
from gather_verify.engine.bulk_step import (
    cell_ranks,
    decode_chunk,
    move_masks,
    successor_codes,
    successor_keys,
)
from gather_verify.engine.canonical_keys import Canon, decode_keys
from gather_verify.engine.columns import Growing
from gather_verify.engine.encoding import STEP_INDEX, Turns
from gather_verify.engine.explore import Encoding, symmetry_group
from gather_verify.engine.facts_table import STEP_PERM, FactsTable, facts_memo
from gather_verify.engine.key_index import KeyIndex
from gather_verify.engine.region import PLANE
from gather_verify.kernels.codes import OUTSIDE
from gather_verify.model import geometry
from gather_verify.model.canonical import canonical_form
from gather_verify.model.configuration import Configuration
from gather_verify.model.geometry import SLOTS, STEPS, Node
from gather_verify.model.symmetry import Automorphism
from gather_verify.properties import get_property
from schedulers import get_scheduler, initial_state

UNION_MARGIN = 2
"""The margin of the configurations' regions whose union the class is explored in."""
MARGINS = PLANE.margins
"""The margins ``run_check`` tries in turn (:class:`~gather_verify.engine.region.RegionPolicy`)."""
CHUNK = 1 << 14
"""States expanded at a time (fewer when their events pass ``EVENTS``)."""
EVENTS = 1 << 19
"""About how many events a step may make (FSYNC and SSYNC rounds: up to ``6**n`` per state)."""
UNION_MAX_STATES = 6_000_000
"""Largest union graph explored; a larger class is checked configuration by configuration."""

# per-state flags
DEFINED, FINAL, UNGATHERABLE, TARGET, TAINT, CYCLE, ASYMMETRIC, RING = (1 << k for k in range(8))
"""``RING``: a stuck state (no robot can move, none has a pending move) of a stateful
scheduler: its turn goes round the robots, each staying, a cycle of ``n`` states that make
no move and hold the same facts (:func:`_rings`)."""
FACT_BITS = {"deadlock": FINAL, "in-u": UNGATHERABLE, "target-change": TARGET}
"""The state flag of each fact of :data:`~gather_verify.properties.base.UNION_FACTS` that a
state or a transition has (the others, ``longest-path`` and ``acyclic``, are the graph's)."""


def property_fact(name: str) -> str | None:
    """The union fact the registered property ``name`` names (None: the union cannot decide it)."""
    return get_property(name).union


def unsupported(scheduler: str, reduction: bool, frames: str) -> str | None:
    """Why a sweep with these settings cannot be decided a meeting-node class at a time, or
    None when it can: the scheduler says so (its ``union`` attribute) and both reductions are
    on (any frames: the isometries used are the frame group's, :func:`shape_isometry`)."""
    if not getattr(get_scheduler(scheduler), "union", False):
        return f"the union engine does not run the {scheduler} scheduler"
    if not reduction:
        return "the union engine runs with the reductions only"
    return None


def meeting_form(c: Configuration) -> tuple[tuple[Node, ...], tuple[int, Node]]:
    """``M`` translated so that its MER starts at the origin, and that translation (as
    ``(identity, t)``): the key of a meeting-node class (``M`` up to translation)."""
    x0, y0, _, _ = geometry.bounding_box(c.meeting_nodes)
    return (tuple(sorted((x - x0, y - y0) for x, y in c.meeting_nodes)),
            (geometry.IDENTITY, (-x0, -y0)))


def shape_isometry(c: Configuration, frames: str = "all") -> tuple[int, Node]:
    """The isometry ``v -> g(v) + t`` (the first, in D4's order) that takes ``M`` onto the
    canonical place of its shape, ``g`` in the robots' frame group: every configuration
    whose ``M`` has that shape (up to translations and that group) is moved by its own onto
    one ``M0``, and all are seeds of one union. Verdicts, counts, moves and margins are
    invariant under such isometries (the views of ``g(C) + t`` are those of ``C`` in the
    frames composed with ``g``, which run over the same frames), not under the others: a
    rotated copy is another problem for robots with a compass (SEMANTICS.md §3). The BFS
    order is not invariant, so a seed moved by a rotation or reflection has its witness
    paths found along :meth:`UnionGraph.oriented`."""
    return canonical_form((), c.meeting_nodes, frames_for(frames)).minimisers[0]


def shape_key(c: Configuration, frames: str = "all") -> tuple:
    """The key of ``M``'s shape up to translations and the frame group (one union each)."""
    return canonical_form((), c.meeting_nodes, frames_for(frames)).key


def normalise(c: Configuration, iso: tuple[int, Node]) -> Configuration:
    """``c`` moved by ``v -> g(v) + t``."""
    g, t = iso
    robots = tuple(sorted(geometry.add(geometry.apply(g, v), t) for v in c.robots))
    return Configuration.trusted(robots, frozenset(geometry.add(geometry.apply(g, v), t)
                                                   for v in c.meeting_nodes))


def labels(c: Configuration, iso: tuple[int, Node]) -> tuple[int, ...]:
    """Robot ``k`` of :func:`normalise` ``(c, iso)`` is robot ``labels[k]`` of ``c`` (the
    moved robots are sorted: a stateful scheduler's starts name ``c``'s robots)."""
    g, t = iso
    return tuple(sorted(range(c.n), key=lambda i: geometry.add(geometry.apply(g, c.robots[i]),
                                                               t)))


def meeting_classes(items: Sequence[tuple[int, Configuration]]
                    ) -> list[list[tuple[int, Configuration]]]:
    """``items`` grouped by meeting-node set up to translation, in order of first occurrence."""
    groups: dict[tuple[Node, ...], list[tuple[int, Configuration]]] = {}
    for item in items:
        groups.setdefault(meeting_form(item[1])[0], []).append(item)
    return list(groups.values())


@dataclass
class UnionGraph:
    """The union of the reachable states of a class's seeds, as the decisions need it."""

    seeds: np.ndarray  # the state ids of the seeds' initial states, seed by seed (seed_off)
    states: int
    reach: np.ndarray  # per state: the flags reachable from it (CYCLE: not peeled)
    best: np.ndarray  # per state: the largest total moves from it (acyclic part)
    box: np.ndarray  # per state: (x0, y0, x1, y1) of every node reachable from it, Aut-closed
    counts: np.ndarray  # per seed: states reachable (-1: not counted)
    transitions: np.ndarray  # per seed: events of those states
    seconds: float
    encoding: Encoding
    keys: np.ndarray  # per state: its key
    flags: np.ndarray  # per state: its own flags
    offsets: np.ndarray  # successors of state s: targets[offsets[s]:offsets[s + 1]], in
    targets: np.ndarray  # the search's order (self-loops left out)
    table: FactsTable  # the facts of the union's configurations
    index: KeyIndex  # state key -> id
    scheduler: str
    frames: str = "all"
    seed_off: np.ndarray | None = None  # seed j: seeds[seed_off[j]:seed_off[j + 1]] (None: one)
    starts: list[list[object]] | None = None  # per seed: the scheduler's start of each state
    turns: Turns | None = None  # a stateful scheduler's state in the keys
    orders: dict = field(default_factory=dict)  # linear part -> its Oriented successors
    _offsets: list[int] | None = None  # offsets as a list (read state by state)

    def initial(self, seed: int) -> np.ndarray:
        """The union ids of seed ``seed``'s initial states (one; with a stateful scheduler,
        one per start its own search keeps, in that search's order)."""
        if self.seed_off is None:
            return self.seeds[seed:seed + 1]
        return self.seeds[self.seed_off[seed]:self.seed_off[seed + 1]]

    def reach_of(self, seed: int) -> int:
        """The flags reachable from seed ``seed``."""
        return int(np.bitwise_or.reduce(self.reach[self.initial(seed)]))

    def best_of(self, seed: int) -> int:
        """The largest total moves from seed ``seed`` (acyclic part)."""
        return int(self.best[self.initial(seed)].max())

    def box_of(self, seed: int) -> np.ndarray:
        """The box of every node reachable from seed ``seed``."""
        b = self.box[self.initial(seed)]
        return np.array([b[:, 0].min(), b[:, 1].min(), b[:, 2].max(), b[:, 3].max()])

    def witness_path(self, seed: int, bit: int, fresh: bool,
                     order: Oriented | None = None) -> list[int] | None:
        """The union ids from seed ``seed``'s initial states to the first state with
        flag ``bit`` in its own search's BFS order (``fresh``: the initial states excluded),
        along BFS parents: the witness and the path that search reports (it starts at one
        of :meth:`initial`). ``order``: the
        successors as :meth:`oriented` gives them, for a seed moved here by a rotation or
        reflection (default: the union's own order, that of a seed moved by a translation)."""
        starts = self.initial(seed).tolist()
        parent = dict.fromkeys(starts, -1)
        found = next((s for s in starts if not fresh and self.flags[s] & bit), -1)
        queue, head = list(starts), 0
        if self._offsets is None:
            self._offsets = self.offsets.tolist()
        off, tgt, flags = self._offsets, self.targets, self.flags
        while found < 0 and head < len(queue):
            s = queue[head]
            head += 1
            # in the oriented order: computed for the states queued so far, in one batch
            succ = (tgt[off[s]:off[s + 1]].tolist() if order is None
                    else order.successors(s, queue, head - 1))
            for t in succ:
                if t not in parent:
                    parent[t] = s
                    if flags[t] & bit:
                        found = t
                        break
                    queue.append(t)
        if found < 0:
            return None
        path = [found]
        while parent[path[-1]] >= 0:
            path.append(parent[path[-1]])
        return path[::-1]

    def oriented(self, h: Automorphism) -> Oriented:
        """The states' successors in the order of the own search of a configuration
        ``h(C)``, ``C`` a seed here (``h`` maps ``M0`` onto its ``M``); see
        :class:`Oriented`. The order depends on ``h``'s linear part only (a translation
        keeps the order of nodes); remembered per linear part."""
        if h.g not in self.orders:
            self.orders[h.g] = Oriented(self, h)
        return self.orders[h.g]


def _closed_boxes(box: np.ndarray, group: Sequence[Automorphism]) -> np.ndarray:
    """Each row ``(x0, y0, x1, y1)`` grown to the bounding box of its images under ``group``."""
    out = box.copy()
    for a in group:
        ma, mb, mc, md = geometry.MATRICES[a.g]
        for xs, ys in ((box[:, 0], box[:, 1]), (box[:, 2], box[:, 3])):
            x, y = ma * xs + mb * ys + a.t[0], mc * xs + md * ys + a.t[1]
            np.minimum(out[:, 0], x, out=out[:, 0])
            np.minimum(out[:, 1], y, out=out[:, 1])
            np.maximum(out[:, 2], x, out=out[:, 2])
            np.maximum(out[:, 3], y, out=out[:, 3])
    return out


class _Equivariance:
    """Per configuration row: whether the target commutes with ``Aut(M0)`` there
    (``target(a C) == a(target C)``), and with the isometries that take ``M0`` back to the
    seeds' own ``M``; what lets one quotient graph decide target-invariance for every seed."""

    def __init__(self, table: FactsTable, group: Sequence[Automorphism],
                 turns: Sequence[Automorphism]):
        self.table, self.group = table, list(group)[1:]
        # the seeds' own M are not M0: their configurations are no rows, nor met again
        self.turns = [(a, frozenset(map(a, table.meeting))) for a in turns]
        self.known: dict[int, bool] = {}

    def broken(self, rows: np.ndarray) -> np.ndarray:
        if not self.group and not self.turns:
            return np.zeros(len(rows), dtype=bool)
        unique, back = np.unique(rows, return_inverse=True)
        out = np.zeros(len(unique), dtype=bool)
        for i, r in enumerate(unique.tolist()):
            ok = self.known.get(r)
            if ok is None:
                c = self.table.configuration(r, form=True)
                try:  # through the table's targets: the images are rows of the class too
                    t = self.table.target_of(c)
                    ok = True
                    for a in self.group:
                        image = c.transformed(a.g, a.t)
                        if self.table.target_of(image) != (None if t is None else a(t)):
                            ok = False
                            break
                    for a, meeting in self.turns if ok else ():
                        image = c.transformed(a.g, a.t, meeting)
                        if (self.table.target_of(image, remember=False)
                                != (None if t is None else a(t))):
                            ok = False
                            break
                except AlgorithmCrash:  # a crash is the per-configuration check's to report
                    ok = False
                self.known[r] = ok
            out[i] = not ok
        return out[back]


def explore_union(
    meeting: frozenset[Node],
    seeds: Sequence[tuple[Node, ...]],
    algorithm: str | Algorithm,
    scheduler: str,
    *,
    detection: str = "local-weak",
    frames: str = "all",
    properties: Sequence[str],
    box: tuple[int, int, int, int],
    count_seeds: np.ndarray | None = None,
    max_states: int = UNION_MAX_STATES,
    orientations: Sequence[Automorphism] = (),
    labels: Sequence[tuple[int, ...]] | None = None,
) -> UnionGraph | None:
    """Explore the union of the states reachable from every seed (robots, all with
    ``meeting``) in ``box`` (closed under ``Aut(meeting)``), with both reductions; the
    graph facts above. ``count_seeds`` (a bool per seed, default all): the seeds whose
    states and transitions are counted. ``orientations``: the maps from ``meeting`` back
    to the seeds' own meeting nodes, for those moved here by a rotation or reflection (the
    target must commute with them too). ``properties``: the names of the properties checked,
    whose facts (their ``union``) the graph records. None when the union passes ``max_states``.

    A ``stateful`` scheduler (round-robin) keeps its state in the keys as the bulk engine
    does (:class:`~gather_verify.engine.encoding.Turns`: the robots keep their places, its
    ``relabel`` is the anonymity); a seed is then the set of its starts (:func:`seed_starts`;
    ``labels``: per seed, the index each robot has in the configuration it stands for, default
    its own, so that the starts come in that configuration's order)."""
    started = time.perf_counter()
    algo = get_algorithm(algorithm) if isinstance(algorithm, str) else algorithm
    sched = get_scheduler(scheduler)
    n = len(seeds[0])
    group = symmetry_group(Configuration.trusted(seeds[0], meeting), frames)
    stateful = getattr(sched, "stateful", False)
    enc = Encoding(box, group, not stateful)
    turns = Turns(sched, n, True, enc.base) if stateful else None
    if (enc.base ** n >= 2**63) if turns is None else not turns.fits():
        return None
    wanted = {property_fact(p) for p in properties}
    table = FactsTable(enc, n, algo, meeting, detection, frames_for(frames), group,
                       facts_memo(algo, detection, frames), targets="target-change" in wanted)
    run = _UnionRun(table, sched, turns, wanted, _Equivariance(table, group, orientations))
    starts = [seed_starts(enc, turns, r, None if labels is None else labels[j])
              for j, r in enumerate(seeds)]
    seed_off = np.zeros(len(seeds) + 1, dtype=np.int64)
    np.cumsum([len(k) for k, _ in starts], out=seed_off[1:])
    seed_ids, _ = run.index.find_or_add(np.array([key for k, _ in starts for key in k],
                                                 dtype=np.uint64))
    sid: int | None = 0
    while sid is not None and sid < run.index.count:
        sid = run.step(sid, max_states)
    if sid is None:  # past max_states
        return None
    S = run.index.count
    graph, ring_of, sizes, events_all, tgt_all, src_all = run.analysed(group)
    reach, best, reach_box, rounds, pred_off, pred_src, out_off, out_tgt = graph
    count_ids = seed_ids
    if ring_of is not None:
        count_ids = ring_of[seed_ids]
        for column in (reach, best, reach_box):  # a ring's members: its facts
            column[:] = column[ring_of]
        out_off = np.zeros(S + 1, dtype=np.int64)  # the whole graph, for the witness paths
        np.cumsum(np.bincount(src_all, minlength=S), out=out_off[1:])
        out_tgt = tgt_all
    wanted_seeds = np.ones(len(seeds), dtype=bool) if count_seeds is None else count_seeds
    seed_reach = np.bitwise_or.reduceat(reach[seed_ids], seed_off[:-1])
    which = np.flatnonzero(wanted_seeds & ((seed_reach & CYCLE) == 0))
    counts, transitions = _seed_counts(graph, count_ids, which, seed_off, events_all, sizes, S)
    return UnionGraph(seed_ids, S, reach, best, reach_box, counts, transitions,
                      time.perf_counter() - started, enc, run.index.keys[:S].copy(),
                      run.flags.array(), out_off, out_tgt, table, run.index, scheduler, frames,
                      seed_off, [st for _, st in starts], turns)


def _seed_counts(graph: tuple[Any, ...], count_ids: np.ndarray, which: np.ndarray,
                 seed_off: np.ndarray, events_all: np.ndarray, sizes: Any, S: int
                 ) -> tuple[np.ndarray, np.ndarray]:
    """The states and transitions each seed of ``which`` reaches (-1 for the others): the
    compiled pass over the graph's rounds, else :func:`_count`."""
    rounds, pred_off, pred_src = graph[3], graph[4], graph[5]
    counts = np.full(len(seed_off) - 1, -1, dtype=np.int64)
    transitions = np.full(len(seed_off) - 1, -1, dtype=np.int64)
    if kernels.enabled() and len(which):
        topo = np.concatenate([r[::-1] for r in rounds[::-1]]) if rounds else np.zeros(0, np.int64)
        members = np.concatenate([np.arange(seed_off[j], seed_off[j + 1]) for j in which])
        counts[which], transitions[which] = union_kernels.seed_counts(
            topo, pred_off, pred_src, graph[6], graph[7], count_ids[members], events_all,
            np.concatenate([[0], np.cumsum(seed_off[which + 1] - seed_off[which])]), sizes)
    else:
        _count(count_ids, which, rounds, pred_off, pred_src, events_all, S, counts,
               transitions, seed_off, sizes)
    return counts, transitions


class _UnionRun:
    """One search of a union of seeds' spaces between its chunks: the facts table, the
    scheduler, the index of the stored states, the edges kept (self-loops left out), each
    state's flags and events counted, its box, and the chunk size."""

    def __init__(self, table: FactsTable, sched: Any, turns: Turns | None, wanted: set[str],
                 equivariance: _Equivariance):
        self.table, self.enc, self.sched, self.turns = table, table.enc, sched, turns
        self.wanted, self.equivariance = wanted, equivariance
        self.canon = Canon(table.enc, table.n)
        self.compiled = kernels.enabled()
        self.index = KeyIndex()
        self.e_src, self.e_tgt, self.e_w = Growing(np.int32), Growing(np.int32), Growing(np.int8)
        self.flags, self.events = Growing(np.uint8), Growing(np.int32)
        self.boxes_rows: list[np.ndarray] = []
        self.chunk = CHUNK

    def step(self, sid: int, max_states: int) -> int | None:
        """Expand the chunk of stored states from ``sid``: their definedness, events,
        successors' ids, facts and edges; returns where the next chunk starts (``sid``
        again with a smaller chunk when the events pass the budget), None past
        ``max_states``."""
        table, enc, index, turns = self.table, self.enc, self.index, self.turns
        hi = min(index.count, sid + self.chunk)
        step = decode_chunk(index.keys[sid:hi].copy(), table, self.compiled)
        K, codes, rows = step.keys, step.codes, step.rows
        f = np.zeros(len(K), dtype=np.uint8)
        f[table.flags[rows, 0] != 0] |= DEFINED  # no rule, or a crash: the per-config check's
        ok = np.flatnonzero(table.flags[rows, 0] == 0)
        masks = move_masks(table, rows, step.rank, flat=self.compiled)
        frontier = enc.frontier(codes[ok], masks[ok])
        got = (self.sched.bulk_successors(frontier, EVENTS) if turns is None else
               cast(Any, self.sched).bulk_successors(frontier, EVENTS,
                                                     extra=turns.of_keys(K[ok])))
        assert got.states or not len(ok), f"{self.sched.name}: bulk_successors took no state"
        if got.states < len(ok):  # more events than the budget (rounds): fewer states at a time
            self.chunk = int(ok[got.states])
            return sid
        self.chunk = min(CHUNK, 2 * self.chunk)
        src, robot, new, weight, event = got.source, got.robot, got.code, got.weight, got.event
        src = ok[src]
        self.events.extend(np.bincount(src, minlength=len(K)).astype(np.int32))
        gone, (src, weight, robot, new, event, after) = _inside(src, weight, robot, new, event,
                                                                got.extra)
        f[gone] |= TAINT
        succ, old, succ_codes = successor_keys(K, codes, src, robot, new, event, self.canon,
                                               True, self.compiled)
        if turns is not None:  # the scheduler's state after each event, above the robots
            succ = with_turns(succ, after, turns)
        ids, _ = index.find_or_add(succ)
        if index.count > max_states:
            return None
        self._facts(f, step, src, robot, new, event, succ_codes)
        loop = ids == sid + src
        changed = new != old
        if event is not None:  # several changes per event: one that changes a robot
            changed = np.zeros(len(src), dtype=bool)
            changed[event[new != old]] = True
        f[src[loop & changed]] |= CYCLE  # a changed self-loop lifts to a real cycle
        edge = ~loop
        self.e_src.extend((sid + src[edge]).astype(np.int32))
        self.e_tgt.extend(ids[edge].astype(np.int32))
        self.e_w.extend(weight[edge])
        self.flags.extend(f)
        cells = step.cells
        xs, ys = enc.x0 + cells // enc.height, enc.y0 + cells % enc.height
        self.boxes_rows.append(np.stack([xs.min(axis=1), ys.min(axis=1), xs.max(axis=1),
                                         ys.max(axis=1)], axis=1))
        return hi

    def _facts(self, f: np.ndarray, step: Any, src: np.ndarray, robot: np.ndarray,
               new: np.ndarray, event: np.ndarray | None, succ_codes: np.ndarray | None
               ) -> None:
        """The chunk's flags of the wanted facts: final (deadlock), a ring's turn, in U, an
        asymmetric target or one that changes along a transition."""
        table, rows, wanted = self.table, step.rows, self.wanted
        if "deadlock" in wanted:
            dead = (table.flags[rows, 1] == 1) & (table.flags[rows, 2] == 0) & step.idle
            f[dead] |= FINAL
        if self.turns is not None and table.n > 1:  # (one robot: its turn is a self-loop)
            f[(table.flags[rows, 1] == 1) & step.idle] |= RING
        if "in-u" in wanted:
            f[table.need_in_u(rows)] |= UNGATHERABLE
        if "target-change" in wanted and len(src):
            f[self.equivariance.broken(rows)] |= ASYMMETRIC
            before = table.need_target(rows[src])
            maybe = np.flatnonzero(before >= 0)
            if len(maybe):
                if succ_codes is None:  # the compiled keys left the codes out
                    succ_codes = successor_codes(step.codes, src, robot, new, event)
                s2, k2 = table.config_keys(succ_codes[maybe] // SLOTS)
                after = table.need_target(table.rows(k2, s2))
                bad = (after >= 0) & (after != before[maybe])
                f[src[maybe[bad]]] |= TARGET

    def analysed(self, group: Sequence[Automorphism]) -> tuple[Any, ...]:
        """The graph's pass (:func:`_analyse`) over the edges kept, each ring (a round
        robin's turns) one state; returns the pass's columns, the rings and their sizes, the
        events per state (per ring), and the edges' targets and sources."""
        S = self.index.count
        own_box = _closed_boxes(np.concatenate(self.boxes_rows).astype(np.int64), group)
        src_all = self.e_src.array().astype(np.int64)
        tgt_all = self.e_tgt.array().astype(np.int64)
        w_all, events_all = self.e_w.array().astype(np.int64), self.events.array().astype(np.int64)
        flags = self.flags.array()
        ring_of, sizes = _rings(S, src_all, tgt_all, flags)
        if ring_of is None:
            graph = _analyse(S, src_all, tgt_all, w_all, flags, own_box)
        else:  # each ring one state, for the pass and the counts; the witness paths walk them
            keep = (flags[src_all] & RING) == 0
            graph = _analyse(S, src_all[keep], ring_of[tgt_all[keep]], w_all[keep], flags,
                             own_box)
            events_all = np.bincount(ring_of, weights=events_all, minlength=S).astype(np.int64)
        return graph, ring_of, sizes, events_all, tgt_all, src_all


def seed_starts(enc: Encoding, turns: Turns | None, robots: tuple[Node, ...],
                labels: tuple[int, ...] | None = None) -> tuple[list[int], list[object]]:
    """The stored keys of a seed's initial states and the scheduler's start of each, as its
    own search keeps them (:func:`~gather_verify.engine.explore.seed_states`, the repeats
    the reductions merge left out): one state, or with a ``stateful`` scheduler one per
    start, in the order of the starts of the configuration the seed stands for. ``labels``:
    robot ``k`` here is robot ``labels[k]`` there (its starts name those robots)."""
    state = initial_state(robots)
    if turns is None:
        return [enc.key(state)], [None]
    here = {r: k for k, r in enumerate(range(len(robots)) if labels is None else labels)}
    keys: list[int] = []
    starts: list[object] = []
    for start in turns.starts():
        order, turn = cast(tuple[tuple[int, ...], int], start)
        key = turns.key(enc, state, (tuple(here[r] for r in order), turn))
        if key not in keys:
            keys.append(key)
            starts.append((order, turn))
    return keys, starts


class Oriented:
    """A union's states' successors (union ids, self-loops and repeats kept) in the order
    the own search of a configuration ``h(C)`` makes them, ``C`` a seed of the union:
    each state moved by ``h``, its representative there (the least key under that
    search's ``Aut(M)``), that representative's events in the scheduler's order (its
    facts: the union's, their steps mapped by ``h``), and the successors moved back.
    Computed on demand, for a batch of states at a time (a BFS asks for the states it
    has queued), and kept."""

    def __init__(self, u: UnionGraph, h: Automorphism):
        enc, table = u.encoding, u.table
        self.u, self.n = u, table.n
        # the box, its group and its encoding as the oriented search sees them
        corners = [(enc.x0, enc.y0), (enc.x0 + enc.width - 1, enc.y0 + enc.height - 1)]
        meeting_h = frozenset(map(h, table.meeting))
        enc_h = Encoding(geometry.bounding_box(list(map(h, corners))),
                         symmetry_group(Configuration.trusted((), meeting_h), u.frames),
                         u.turns is None)
        # codes (cell * SLOTS + pending step) mapped both ways
        dirs = [0] + [STEP_INDEX[geometry.apply(h.g, step)] for step in STEPS]
        self.forward = np.empty(enc.cells * SLOTS, dtype=np.int64)
        self.back = np.empty(enc_h.cells * SLOTS, dtype=np.int64)
        for cell in range(enc.cells):
            x, y = h(enc.node(cell))
            hcell = (x - enc_h.x0) * enc_h.height + y - enc_h.y0
            for d in range(SLOTS):
                self.forward[cell * SLOTS + d] = hcell * SLOTS + dirs[d]
                self.back[hcell * SLOTS + dirs[d]] = cell * SLOTS + d
        self.perm = np.array(STEP_PERM[h.g], dtype=np.uint8)
        self.enc_h = enc_h
        self.canon, self.canon_h = Canon(enc, self.n), Canon(enc_h, self.n)
        self.sched = get_scheduler(u.scheduler)
        self.known: dict[int, list[int]] = {}

    def successors(self, s: int, queue: list[int], head: int) -> list[int]:
        """State ``s``'s successors; if they are not computed yet, those of the queued
        states from ``head`` on (``s`` among them) are computed with them."""
        succ = self.known.get(s)
        if succ is None:
            known = self.known
            self._compute(np.array(sorted({t for t in queue[head:] if t not in known}),
                                   dtype=np.int64))
            succ = known[s]
        return succ

    def _compute(self, states: np.ndarray) -> None:
        u, table, n = self.u, self.u.table, self.n
        back = self.back
        keys = u.keys[states]
        rep_h = decode_keys(self.canon_h.keys(self.forward[decode_keys(
            keys, u.encoding.base, n)]), self.enc_h.base, n)
        turn = None if u.turns is None else u.turns.of_keys(keys)  # the isometries keep it
        cells = back[rep_h] // SLOTS  # the representative, in the union's coordinates
        srt, ck = table.config_keys(cells)
        rows = table.rows(ck, srt)
        ok = np.flatnonzero(table.flags[rows, 0] == 0)
        masks = self.perm[move_masks(table, rows, cell_ranks(cells, srt))]
        frontier = self.enc_h.frontier(rep_h[ok], masks[ok])
        parts, at = [], 0
        while at < len(ok):  # every event of these states, the budget's worth at a time
            part = frontier._replace(codes=frontier.codes[at:], masks=frontier.masks[at:])
            got = (self.sched.bulk_successors(part, EVENTS) if turn is None else
                   cast(Any, self.sched).bulk_successors(part, EVENTS, extra=turn[ok[at:]]))
            _, (src, _, robot, new, event, after) = _inside(
                ok[at + got.source], got.weight, got.robot, got.code, got.event, got.extra)
            parts.append((src, successor_codes(rep_h, src, robot, new, event), after))
            at += got.states
        src = np.concatenate([p[0] for p in parts]) if parts else np.zeros(0, dtype=np.int64)
        succ = (np.concatenate([p[1] for p in parts]) if parts
                else np.zeros((0, n), dtype=np.int64))
        succ_keys = self.canon.keys(back[succ])
        if u.turns is not None:
            succ_keys = with_turns(succ_keys, np.concatenate([p[2] for p in parts]) if parts
                                   else np.zeros(0, dtype=np.int64), u.turns)
        ids, first = u.index.find_or_add(succ_keys)
        assert not len(first), "a successor the union does not hold: a bug of gather-verify"
        ends = np.cumsum(np.bincount(src, minlength=len(states))).tolist()
        ids_list = ids.tolist()
        a = 0
        for state, b in zip(states.tolist(), ends, strict=True):
            self.known[state] = ids_list[a:b]
            a = b


def _inside(src: np.ndarray, weight: np.ndarray, robot: np.ndarray, new: np.ndarray,
            event: np.ndarray | None, extra: np.ndarray | None = None
            ) -> tuple[np.ndarray, tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray,
                                         np.ndarray | None, np.ndarray | None]]:
    """The source states of the events (``src``, ``weight``; their changes ``robot``,
    ``new``, ``event`` as in :class:`schedulers.Successors`; ``extra``: a stateful
    scheduler's state after each) that take a robot out of the region (the code
    ``OUTSIDE``), and the events without them, their changes renumbered."""
    outside = new == OUTSIDE
    if not outside.any():
        return src[:0], (src, weight, robot, new, event, extra)
    bad = np.zeros(len(src), dtype=bool)
    bad[outside if event is None else event[outside]] = True
    keep = ~bad
    after = None if extra is None else extra[:len(src)][keep]
    if event is None:
        return src[bad], (src[keep], weight[keep], robot[keep], new[keep], None, after)
    kept = keep[event]
    renumber = np.cumsum(keep) - 1
    return src[bad], (src[keep], weight[keep], robot[kept], new[kept], renumber[event[kept]],
                      after)


def _rings(S: int, src: np.ndarray, tgt: np.ndarray, flags: np.ndarray
           ) -> tuple[np.ndarray | None, np.ndarray | None]:
    """The rings of stuck states (``RING``: each state's one event, a stay, moves the turn
    on, so the states of one configuration and every turn form a cycle that makes no move):
    per state, the least member of its ring (itself when in none), and the states each
    state counts for (a ring's least member: the ring's; its other members: none). (None,
    None) when there is no ring."""
    stuck = np.flatnonzero(flags & RING)
    if not len(stuck):
        return None, None
    out = np.bincount(src, minlength=S)
    assert (out[stuck] == 1).all(), "a stuck state with other than one event"
    nxt = np.arange(S)
    nxt[src[(flags[src] & RING) != 0]] = tgt[(flags[src] & RING) != 0]
    assert (flags[nxt[stuck]] & RING).all(), "a stuck state's turn leads out of its ring"
    ring_of = np.arange(S)
    here = stuck.copy()
    for _ in range(len(stuck)):  # round each ring (its length: the robots)
        here = nxt[here]
        if (here == stuck).all():
            break
        ring_of[stuck] = np.minimum(ring_of[stuck], here)
    sizes = np.bincount(ring_of, minlength=S)
    return ring_of, sizes


def _analyse(S: int, src: np.ndarray, tgt: np.ndarray, w: np.ndarray, flags: np.ndarray,
             own_box: np.ndarray) -> tuple[np.ndarray, ...]:
    """Peel sinks round by round (the states that reach no cycle, successors first) and,
    in that order, the reachable flags, longest paths and node boxes; the unpeeled states
    get ``CYCLE`` in their reachable flags. Compiled (:func:`union_kernels.peel`), the
    rounds are one: every state after its successors."""
    order = np.argsort(src, kind="stable")  # already sorted: cheap
    src, tgt, w = src[order], tgt[order], w[order]
    out_off = np.zeros(S + 1, dtype=np.int64)
    np.cumsum(np.bincount(src, minlength=S), out=out_off[1:])
    by_tgt = np.argsort(tgt, kind="stable")
    pred_src = src[by_tgt]
    pred_off = np.zeros(S + 1, dtype=np.int64)
    np.cumsum(np.bincount(tgt, minlength=S), out=pred_off[1:])
    outdeg = np.diff(out_off) + ((flags & CYCLE) != 0)
    reach = flags.astype(np.uint8).copy()
    best = np.zeros(S, dtype=np.int64)
    box = own_box.copy()
    if kernels.enabled():
        order = union_kernels.peel(out_off, tgt, w, pred_off, pred_src, outdeg.astype(np.int64),
                                   reach, best, box)
        peeled = np.zeros(S, dtype=bool)
        peeled[order] = True
        reach[~peeled] |= CYCLE
        return reach, best, box, [order], pred_off, pred_src, out_off, tgt
    rounds: list[np.ndarray] = []
    frontier = np.flatnonzero(outdeg == 0)
    while len(frontier):
        if rounds:  # every state here has successors, all in earlier rounds
            idx, starts = _gather(out_off, frontier)
            t = tgt[idx]
            reach[frontier] |= np.bitwise_or.reduceat(reach[t], starts)
            best[frontier] = np.maximum.reduceat(w[idx] + best[t], starts)
            for k, op in enumerate((np.minimum, np.minimum, np.maximum, np.maximum)):
                box[frontier, k] = op(box[frontier, k], op.reduceat(box[t, k], starts))
        rounds.append(frontier)
        idx, _ = _gather(pred_off, frontier)
        p, k = np.unique(pred_src[idx], return_counts=True)
        outdeg[p] -= k
        frontier = p[outdeg[p] == 0]
    peeled = np.zeros(S, dtype=bool)
    for r in rounds:
        peeled[r] = True
    reach[~peeled] |= CYCLE
    return reach, best, box, rounds, pred_off, pred_src, out_off, tgt


def _gather(off: np.ndarray, states: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Edge positions of ``states`` in a CSR (state by state) and where each state's run starts."""
    counts = off[states + 1] - off[states]
    starts = np.cumsum(counts) - counts
    idx = np.repeat(off[states] - starts, counts) + np.arange(int(counts.sum()))
    return idx, starts


def _count(seed_ids: np.ndarray, which: np.ndarray, rounds: list[np.ndarray],
           pred_off: np.ndarray, pred_src: np.ndarray, events: np.ndarray, S: int,
           counts: np.ndarray, transitions: np.ndarray, seed_off: np.ndarray | None = None,
           sizes: np.ndarray | None = None) -> None:
    """States and events reachable from each seed in ``which`` (all in the peeled part):
    the set of seeds reaching each state, 64 seeds a word, pulled from the predecessors
    from the sources down. ``seed_off``: seed ``j`` is the states
    ``seed_ids[seed_off[j]:seed_off[j + 1]]`` together (default: one state each); ``sizes``:
    the states each state counts for (default one)."""
    if seed_off is None:
        seed_off = np.arange(len(seed_ids) + 1)
    for lo in range(0, len(which), 64):
        group = which[lo:lo + 64]
        mark = np.zeros(S, dtype=np.uint64)
        bits = np.left_shift(np.uint64(1), np.arange(len(group), dtype=np.uint64))
        starts_per_seed = seed_off[group + 1] - seed_off[group]
        members = np.concatenate([np.arange(seed_off[j], seed_off[j + 1]) for j in group])
        np.bitwise_or.at(mark, seed_ids[members], np.repeat(bits, starts_per_seed))
        for states in reversed(rounds):
            idx, starts = _gather(pred_off, states)
            if len(idx):
                has = np.diff(np.r_[starts, len(idx)]) > 0  # zero-length runs left out
                mark[states[has]] |= np.bitwise_or.reduceat(mark[pred_src[idx]], starts[has])
        c = np.zeros(64, dtype=np.float64)
        t = np.zeros(64, dtype=np.float64)
        weights = events.astype(np.float64)
        ones = np.ones(S) if sizes is None else sizes.astype(np.float64)
        for a in range(0, S, 1 << 14):
            block = np.unpackbits(mark[a:a + (1 << 14)].view(np.uint8).reshape(-1, 8), axis=1,
                                  bitorder="little").astype(np.float64)
            c += ones[a:a + (1 << 14)] @ block  # sums of integers below 2**53: exact (BLAS)
            t += weights[a:a + (1 << 14)] @ block
        counts[group] = c[:len(group)].astype(np.int64)
        transitions[group] = t[:len(group)].astype(np.int64)


def margin_needed(c: Configuration, group: Sequence[Automorphism], box: np.ndarray) -> int | None:
    """The margin ``run_check`` ends its search with: the least whose region holds ``box``
    (:meth:`~gather_verify.engine.region.RegionPolicy.needed`)."""
    return PLANE.needed(c, group, box)
