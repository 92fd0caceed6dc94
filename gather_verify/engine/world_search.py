"""The reference search on a finite world: every reachable state, its edges, and the facts
the tasks read (SEMANTICS.md §4, §9, §11).

A state is, per robot, its node and its pending destination (node indices of the
world), and, when the task explores, the set of nodes visited so far (bookkeeping the
robots never see). The search is breadth-first, so the parent of a state is on a
shortest path to it. It runs any world and any scheduler: it knows the world only
through the move sets and the automorphisms it is handed.

Reductions, when asked for and sound (§4): anonymity (the state is the multiset of
robots) and the world's symmetries under the robots' frames that fix the meeting
nodes (:meth:`~gather_verify.worlds.base.World.symmetries`). Under a scheduler that
keeps its own state (round-robin's order and turn) anonymity relabels the robots as the
scheduler says rather than sorting them, and the symmetries leave that state alone
(:func:`canonicaliser`). A liveness part needs robot identities (§5, §11), so a task with
one is searched unreduced; the report says so.

>>> from gather_verify.algorithms import get_algorithm
>>> from gather_verify.worlds import get_world
>>> from gather_verify.worlds.moves import WorldMoves
>>> ring = get_world("ring:9")
>>> moves = WorldMoves(ring, get_algorithm("go-to-target"), frozenset({7}))
>>> s = search(ring, (0, 3, 5), moves.actions, "async")
>>> s.states, s.transitions, s.stopped
(225, 560, None)
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from gather_verify.algorithms.base import AlgorithmCrash, Unhandled
from gather_verify.engine.encoding import NO_LIMITS, Limits, Stop, rss_mb
from gather_verify.progress import PROGRESS
from schedulers import Event, Scheduler, as_scheduler

WorldState = tuple[tuple[tuple[int, int | None, int], ...], int, object]
"""``(robots, visited, extra)``: per robot (node, pending or None, colour); the visited nodes
as a bit set (0 when the task does not explore); the scheduler's own state (None but for a
scheduler that keeps one, such as round-robin's order and turn)."""
Actions = Callable[[tuple[tuple[int, int | None, int], ...]], list[frozenset[tuple[int, int]]]]
"""The robots of a state -> per robot, its actions ``(destination, colour)``."""
Watch = Callable[[int, WorldState, bool, list[tuple[int, int, Event]]], "Halt | None"]
"""A safety test run on each expanded state (:func:`search`'s ``watch``)."""


@dataclass
class Halt:
    """A state the search could not expand: the algorithm crashed or has no rule there."""

    property: str  # crash | defined
    state: int
    reason: str
    detail: dict[str, object] = field(default_factory=dict)


@dataclass
class SearchArrays:
    """A search as arrays, for the tasks' compiled tests (:mod:`gather_verify.tasks.base`):
    the edges of the expanded states (CSR, in the order of :attr:`WorldSearch.edges`),
    per edge its robots' mask and whether it is a round that moves two robots across one
    edge in opposite directions; per state (expanded or not) its robots' nodes."""

    offsets: np.ndarray  # (expanded + 1,) int64
    targets: np.ndarray  # (E,) int32 or int64
    robots: np.ndarray  # (E,) unsigned, or int64 past 32 robots
    crossing: np.ndarray | None  # (E,) bool; None: no round among the events
    final: np.ndarray  # (expanded,) bool
    stay: np.ndarray  # (expanded,) int64
    nodes_of: Callable[[], np.ndarray]  # -> (states, n) robot nodes, computed when asked

    @cached_property
    def nodes(self) -> np.ndarray:
        return self.nodes_of()


@dataclass
class WorldSearch:
    """What :func:`search` found: the states (ids in BFS order), their edges, and per state
    the facts the tasks read."""

    keys: list[WorldState]
    parents: list[int]
    edges: list[list[tuple[int, int, Event]]]  # per expanded state: (target, robots mask, event)
    final: list[bool]  # no pending move and every move set is {stay}
    stay: list[int]  # per state: mask of idle robots whose move set holds staying
    states: int
    transitions: int
    stopped: Stop | str | None  # None: the whole space; else the limit or "crash"/"defined"
    halt: Halt | None
    reduced: bool
    seconds: float
    canonical: Callable[[WorldState], WorldState]
    engine: str = "reference"
    """Which engine searched: ``reference`` (this module) or ``bulk``
    (:mod:`gather_verify.engine.world_bulk`); both find the same fields."""
    arrays: SearchArrays | None = None
    """The same search as arrays (the bulk engine's; None for the reference, whose tasks
    read the fields above)."""
    seed_ids: np.ndarray | None = None
    """For a search of several initial states at once (the bulk engine's ``seeds``): per
    seed, the ids of its initial states (one per start of the scheduler)."""

    @property
    def complete(self) -> bool:
        return self.stopped is None

    def path_to(self, sid: int) -> list[int]:
        path = [sid]
        while self.parents[path[-1]] >= 0:
            path.append(self.parents[path[-1]])
        return path[::-1]


Relabel = Callable[[object], tuple[Sequence[int], object]]
"""A ``stateful`` scheduler's state -> ``(perm, state)``: identical robots relabelled, new robot
k being old robot ``perm[k]`` (its ``relabel`` with the number of robots given)."""


def relabeller(sched: object, n: int) -> Relabel | None:
    """How anonymity acts on a state of ``sched``: None for a scheduler that keeps no state of
    its own (the robots are then sorted); else its ``relabel`` for ``n`` robots, which names
    the robots so that its own state is the one it picks (round-robin: the order is the first
    it may fix). Sorting them instead would forget whose turn comes when (SEMANTICS.md §4)."""
    if not getattr(sched, "stateful", False):
        return None
    relabel = sched.relabel  # type: ignore[attr-defined]
    return lambda extra: relabel(extra, n)


def canonicaliser(automorphisms: Sequence[Sequence[int]], meeting: frozenset[int],
                  anonymity: bool, visits: bool, relabel: Relabel | None = None
                  ) -> Callable[[WorldState], WorldState]:
    """The key of a state under the reductions: its least image under the automorphisms
    that fix the meeting nodes, robots sorted when anonymous.

    With a scheduler that keeps its own state (``relabel``, :func:`relabeller`), anonymity
    relabels the robots as the scheduler says instead of sorting them, and the
    automorphisms move the robots' nodes and leave the scheduler's state alone (it names
    robots, not nodes). The two commute, so the key is the least image over the whole group
    and two states have one key exactly when they are in one orbit."""
    group = [p for p in automorphisms if frozenset(p[m] for m in meeting) == meeting]
    if len(group) <= 1 and not anonymity:
        return lambda state: state
    sort = anonymity and relabel is None

    def named(state: WorldState) -> WorldState:
        """The state with its robots relabelled as the scheduler says (when it keeps one)."""
        if not anonymity or relabel is None:
            return state
        robots, visited, extra = state
        perm, extra = relabel(extra)
        return tuple(robots[i] for i in perm), visited, extra

    def image(p: Sequence[int], state: WorldState) -> WorldState:
        robots, visited, extra = state
        moved = tuple((p[v], None if d is None else p[d], c) for v, d, c in robots)
        if sort:
            moved = tuple(sorted(moved, key=_order))
        if visits:
            visited = sum(1 << p[v] for v in range(len(p)) if visited >> v & 1)
        return moved, visited, extra

    if len(group) <= 1:
        if not sort:
            return named
        return lambda state: (tuple(sorted(state[0], key=_order)), state[1], state[2])
    return lambda state: min((image(p, s) for s in (named(state),) for p in group),
                             key=_state_order)


def _order(robot: tuple[int, int | None, int]) -> tuple[int, int, int]:
    return robot[0], -1 if robot[1] is None else robot[1], robot[2]


def _state_order(state: WorldState) -> tuple[object, ...]:
    return tuple(_order(r) for r in state[0]), state[1]


def search(world: object, robots: Sequence[int], actions: Actions, scheduler: str | Scheduler, *,
           colours: Sequence[int] | None = None, visits: bool = False,
           anonymity: bool = False, symmetries: Sequence[Sequence[int]] = (),
           meeting: frozenset[int] = frozenset(), limits: Limits = NO_LIMITS,
           watch: Watch | None = None) -> WorldSearch:
    """Breadth-first search of every state reachable from ``robots`` (all idle, with the
    initial ``colours``, default 0), from each start the scheduler has (one, or one per
    round-robin order).

    ``actions`` gives each robot's actions (:class:`~gather_verify.worlds.moves.WorldMoves`);
    ``symmetries``: the automorphisms that commute with the robots' frames
    (:meth:`~gather_verify.worlds.base.World.symmetries`), to merge states by (those that
    fix the meeting nodes). A crash or a missing rule stops the search at that state
    (``halt``); a limit stops it with ``stopped`` naming the limit. ``watch``, called on each
    expanded state with its id, key, finality and out-edges, stops the search (``stopped`` =
    ``"watch"``, ``halt`` = what it returned) when it returns a :class:`Halt`: a caller that
    needs only the first violation of a safety part need not search on.
    """
    started = time.perf_counter()
    sched = as_scheduler(scheduler)
    canon = canonicaliser(symmetries, meeting, anonymity, visits,
                          relabeller(sched, len(robots)))
    lights = tuple(colours) if colours is not None else (0,) * len(robots)
    start_robots = tuple((v, None, c) for v, c in zip(robots, lights, strict=True))
    seen0 = _visit_bits(robots) if visits else 0
    starts = getattr(sched, "starts", lambda _n: [None])(len(robots))
    reps: list[WorldState] = []
    index: dict[WorldState, int] = {}
    for extra in starts:
        rep = (start_robots, seen0, extra)
        if index.setdefault(canon(rep), len(reps)) == len(reps):
            reps.append(rep)
    parents = [-1] * len(reps)
    edges: list[list[tuple[int, int, Event]]] = []
    final: list[bool] = []
    stay: list[int] = []
    transitions = 0
    stopped: Stop | str | None = None
    halt = None
    sid = 0
    PROGRESS.states = len(reps)
    while sid < len(reps):
        if sid & 63 == 0:
            PROGRESS.states = len(reps)  # read by a progress line and by the watchdog's report
            if time.perf_counter() - started > limits.max_seconds:
                stopped = Stop.TIME
                break
        if sid & 4095 == 0 and rss_mb() > limits.max_memory_mb:
            stopped = Stop.MEMORY
            break
        state, visited, extra = reps[sid]
        try:
            options = actions(state)
        except AlgorithmCrash as error:
            halt = Halt("crash", sid, error.reason, error.detail())
        except Unhandled as error:
            halt = Halt("defined", sid, f"the algorithm has no rule here: {error}")
        if halt is not None:
            stopped = halt.property
            break
        final.append(all(p is None and options[i] == {(v, c)}
                         for i, (v, p, c) in enumerate(state)))
        stay.append(sum(1 << i for i, (v, p, c) in enumerate(state)
                        if p is None and (v, c) in options[i]))
        out: list[tuple[int, int, Event]] = []
        for event, succ, after in sched.luminous(state, extra, options.__getitem__):
            if len(reps) > limits.max_states + EVENT_CUT or len(out) & 1023 == 1023:
                stopped = _inside_limit(limits, started, len(reps))  # a round of very many
                if stopped is not None:  # events: the limits inside it
                    break
            transitions += 1
            seen = visited
            if visits:
                seen |= _visit_bits(v for v, _, _ in succ)
            nxt: WorldState = (succ, seen, after)
            key = canon(nxt)
            did = index.get(key)
            if did is None:
                did = len(reps)
                index[key] = did
                reps.append(nxt)
                parents.append(sid)
            out.append((did, _mask(event.robots), event))
        edges.append(out)
        if stopped is not None:  # its events cut: the search is INCOMPLETE
            break
        if watch is not None:
            halt = watch(sid, reps[sid], final[-1], out)
            if halt is not None:
                stopped = Stop.WATCH
                break
        sid += 1
        if len(reps) > limits.max_states:
            stopped = Stop.STATES
            break
    return WorldSearch(keys=reps, parents=parents, edges=edges, final=final, stay=stay,
                       states=len(reps), transitions=transitions, stopped=stopped, halt=halt,
                       reduced=anonymity or len(symmetries) > 1,
                       seconds=time.perf_counter() - started, canonical=canon)


EVENT_CUT = 1024
"""A state's expansion stops once the states stored pass ``max_states`` by this many."""


def _inside_limit(limits: Limits, started: float, stored: int) -> Stop | None:
    """The limit a state of very many events has passed while it is expanded (its events are
    then cut there), if any: a round of 20 robots of two moves each makes 2**20 of them."""
    if stored > limits.max_states + EVENT_CUT:
        return Stop.STATES
    if time.perf_counter() - started > limits.max_seconds:
        return Stop.TIME
    if rss_mb() > limits.max_memory_mb:
        return Stop.MEMORY
    return None


def arrays_of(s: WorldSearch) -> SearchArrays:
    """A reference search's :class:`SearchArrays` (the tests run the tasks' compiled tests on
    it, to compare them with their Python reading of the same search)."""
    offsets = np.zeros(len(s.edges) + 1, dtype=np.int64)
    offsets[1:] = np.cumsum([len(out) for out in s.edges])
    flat = [edge for out in s.edges for edge in out]
    targets = np.array([t for t, _, _ in flat], dtype=np.int64)
    robots = np.array([m for _, m, _ in flat], dtype=np.int64)
    crossing = np.array([e.kind == "round" and any(
        (b, a) in {(a, b) for _, a, b in e.moves} for _, a, b in e.moves) for _, _, e in flat],
        dtype=bool)
    n = len(s.keys[0][0]) if s.keys else 0
    return SearchArrays(offsets, targets, robots, crossing,
                        np.array(s.final, dtype=bool), np.array(s.stay, dtype=np.int64),
                        lambda: np.array([[v for v, _, _ in k[0]] for k in s.keys],
                                         dtype=np.int64).reshape(len(s.keys), n))


def _visit_bits(nodes: object) -> int:
    bits = 0
    for v in nodes:  # type: ignore[attr-defined]
        bits |= 1 << v
    return bits


def _mask(robots: Sequence[int]) -> int:
    bits = 0
    for i in robots:
        bits |= 1 << i
    return bits
