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

from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from gather_verify.algorithms.base import AlgorithmCrash, Unhandled
from gather_verify.engine.bfs import breadth_first
from gather_verify.engine.encoding import NO_LIMITS, Limits, Stop
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
           watch: Watch | None = None, palette: int = 1) -> WorldSearch:
    """Breadth-first search of every state reachable from ``robots`` (all idle, with the
    initial ``colours``, default 0), from each start the scheduler has (one, or one per
    round-robin order): the one reference search
    (:func:`~gather_verify.engine.bfs.breadth_first`) over a finite world
    (:class:`WorldModel`).

    ``actions`` gives each robot's actions (:class:`~gather_verify.worlds.moves.WorldMoves`);
    ``symmetries``: the automorphisms that commute with the robots' frames
    (:meth:`~gather_verify.worlds.base.World.symmetries`), to merge states by (those that
    fix the meeting nodes). A crash or a missing rule stops the search at that state
    (``halt``); a limit stops it with ``stopped`` naming the limit. ``watch``, called on each
    expanded state with its id, key, finality and out-edges, stops the search (``stopped`` =
    ``"watch"``, ``halt`` = what it returned) when it returns a :class:`Halt`: a caller that
    needs only the first violation of a safety part need not search on. ``palette``: K, the
    colours a safe read of a phase scheduler ranges over (:mod:`schedulers.phases`).
    """
    sched = as_scheduler(scheduler)
    canon = canonicaliser(symmetries, meeting, anonymity, visits,
                          relabeller(sched, len(robots)))
    lights = tuple(colours) if colours is not None else (0,) * len(robots)
    start = tuple((v, None, c) for v, c in zip(robots, lights, strict=True))
    model = WorldModel(sched, start, canon, actions, visits, watch, palette)
    walked = breadth_first(model, limits)
    return WorldSearch(keys=walked.stored, parents=walked.parents.tolist(), edges=model.edges,
                       final=model.final, stay=model.stay, states=len(walked.stored),
                       transitions=walked.transitions, stopped=walked.stopped, halt=model.halt,
                       reduced=anonymity or len(symmetries) > 1, seconds=walked.seconds,
                       canonical=canon)


class WorldModel:
    """A finite world as the one reference search reads it (:class:`~gather_verify.engine.bfs.Model`):
    a state is ``(robots, visited, extra)`` (:data:`WorldState`), stored as the first
    member of its class met; per expanded state the facts the tasks read (final, the
    robots that may stay) and its out-edges ``(target, robots mask, event)``."""

    def __init__(self, sched: Scheduler, start: tuple[tuple[int, int | None, int], ...],
                 canon: Callable[[WorldState], WorldState], actions: Actions, visits: bool,
                 watch: Watch | None, palette: int = 1):
        self.sched, self.start, self.key, self.actions = sched, start, canon, actions
        self.phased = getattr(sched, "phased", False)
        """A phase scheduler (:mod:`schedulers.phases`): a Look may read colours being
        changed (it re-evaluates the actions under them), and a robot's null cycle is
        events of its own, so no robot is counted as staying by a null activation."""
        self.palette = palette
        self.visits, self.watch = visits, watch
        self.edges: list[list[tuple[int, int, Event]]] = []
        self.final: list[bool] = []
        self.stay: list[int] = []
        self.out: list[tuple[int, int, Event]] = []
        self.halt: Halt | None = None
        self.current: WorldState = (start, 0, None)  # the state being expanded

    def seeds(self) -> list[WorldState]:
        seen = _visit_bits(v for v, _, _ in self.start) if self.visits else 0
        starts = getattr(self.sched, "starts", lambda _n: [None])(len(self.start))
        return [(self.start, seen, extra) for extra in starts]

    def stored(self, state: WorldState, key: WorldState) -> WorldState:
        return state

    def state(self, sid: int, stored: WorldState) -> WorldState:
        return stored

    def expand(self, sid: int, state: WorldState) -> Iterable[tuple[Event, WorldState]] | str:
        robots, visited, extra = state
        try:
            options = self.actions(robots)
            events = self.sched.luminous(robots, extra, options.__getitem__, **(
                {"view": self.actions, "colours": self.palette} if self.phased else {}))
            if self.phased:  # a read Look evaluates the algorithm again: crashes here
                events = list(events)
        except AlgorithmCrash as error:
            self.halt = Halt("crash", sid, error.reason, error.detail())
            return self.halt.property
        except Unhandled as error:
            self.halt = Halt("defined", sid, f"the algorithm has no rule here: {error}")
            return self.halt.property
        self.final.append(all(p is None and options[i] == {(v, c)}
                              for i, (v, p, c) in enumerate(robots)))
        self.stay.append(0 if self.phased else sum(
            1 << i for i, (v, p, c) in enumerate(robots) if p is None and (v, c) in options[i]))
        self.current, self.out = state, []
        return ((event, (succ, self.visited(visited, succ), after))
                for event, succ, after in events)

    def visited(self, before: int, succ: tuple[tuple[int, int | None, int], ...]) -> int:
        """The nodes visited once ``succ`` is reached (when the task explores)."""
        return before | _visit_bits(v for v, _, _ in succ) if self.visits else before

    def inside(self, succ: WorldState) -> bool:
        return True

    def transition(self, sid: int, event: Event, succ: WorldState) -> None:
        pass

    def discovered(self, did: int, succ: WorldState) -> None:
        pass

    def edge(self, sid: int, did: int, event: Event, succ: WorldState,
             state: WorldState) -> None:
        self.out.append((did, _mask(event.robots), event))

    def expanded(self, sid: int) -> str | None:
        self.edges.append(self.out)
        if self.watch is not None:
            self.halt = self.watch(sid, self.current, self.final[-1], self.out)
            if self.halt is not None:
                return Stop.WATCH
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
