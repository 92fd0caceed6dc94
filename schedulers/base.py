"""States, events and the scheduler protocol shared by FSYNC, SSYNC and ASYNC.

A scheduler has two faces that must agree event for event: ``successors``
(one concrete state, what the reference engine, replay and traces use) and
``bulk_successors`` (many encoded states at once, what the bulk engine uses).
The engine owns the encoding (``gather_verify.engine.encoding``) and hands the
states over as a :class:`Frontier`; the scheduler answers with
:class:`Successors`, a format in which one event may change several robots.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from functools import cache
from itertools import product
from typing import Any, NamedTuple, Protocol

import numpy as np

from gather_verify.kernels.codes import OUTSIDE
from gather_verify.model.geometry import DEGREE, SLOTS, STEPS, Node

Robot = tuple[Node, Node | None]
"""One robot: its node and its pending destination (None when idle)."""
State = tuple[Robot, ...]
"""Per robot index: (node, pending). Identities are kept; sort for anonymity."""
MoveSets = Callable[[tuple[Node, ...]], Mapping[Node, frozenset[Node]]]
"""Robot nodes (sorted) -> move set per occupied node (global destinations)."""


@dataclass(frozen=True)
class Event:
    """What one transition did.

    ``kind`` is ``round`` (FSYNC/SSYNC: ``robots`` looked and moved at once),
    ``look`` (ASYNC: one robot looked and fixed a pending destination) or
    ``move`` (ASYNC: one robot moved to its pending destination). ``moves``
    lists ``(robot, source, destination)`` for every robot that changed node
    or, for ``look``, the destination it fixed.
    """

    kind: str
    robots: tuple[int, ...]
    moves: tuple[tuple[int, Node, Node], ...]
    lights: tuple[tuple[int, int, int], ...] = ()
    """``(robot, old colour, new colour)`` for every robot whose light changed (§10)."""
    chosen: tuple[tuple[int, Any, int, tuple[int, ...]], ...] = ()
    """Under a phase scheduler (:mod:`schedulers.phases`), per robot that looked: ``(robot,
    destination, next colour, the colours it read of the others)``; its light and position
    change at later steps."""

    @property
    def distance(self) -> int:
        """Edges traversed in this transition (0 for a look)."""
        if self.kind == "look":
            return 0
        return sum(1 for _, a, b in self.moves if a != b)

    def to_json(self) -> dict[str, object]:
        out: dict[str, object] = {"kind": self.kind, "robots": list(self.robots),
                                  "moves": [[i, _json(a), _json(b)] for i, a, b in self.moves]}
        if self.lights:
            out["lights"] = [list(change) for change in self.lights]
        if self.chosen:
            out["chosen"] = [[i, d, c, list(read)] for i, d, c, read in self.chosen]
        return out


def _json(place: Any) -> object:
    """A place as a trace writes it: a node of Z² as a list, any other (a position of the
    rendezvous world, ``near``) as it is."""
    return list(place) if isinstance(place, tuple) else place


class Frontier(NamedTuple):
    """Encoded states handed to :meth:`Scheduler.bulk_successors` by the engine.

    ``codes[s, i]`` is robot i of state s as ``cell * SLOTS + d`` (``SLOTS`` = degree + 1):
    ``cell`` a node of the engine's region, ``d`` 0 when idle, else 1 + the index in
    ``STEPS`` of its pending step. ``masks[s, i]`` is robot i's move set in the
    configuration of state s as bits: bit k for ``STEPS[k]``, bit ``DEGREE`` for staying.
    ``neighbour[cell, k]`` is the cell one ``STEPS[k]`` away (``OUTSIDE``: outside the
    region, a limit; Z² has no ``NO_EDGE``). A move there gets the new code ``OUTSIDE``.
    A scheduler reads these and nothing else of the engine.

    With K colours (luminous robots, §10; ``bulk_luminous``) a robot's code is
    ``(cell * SLOTS + d) * K + colour`` and its mask has a bit per action, bit
    ``k * K + c`` for ``STEPS[k]`` (k = ``DEGREE``: stay) with the new colour c
    (:func:`luminous_order`).
    """

    codes: np.ndarray  # (S, n) int64
    masks: np.ndarray  # (S, n) uint8
    neighbour: np.ndarray  # (cells, DEGREE) int64


class Successors(NamedTuple):
    """Every event of the first ``states`` states of a :class:`Frontier`, in the order
    ``successors`` yields them, state after state.

    Per event e: ``source[e]`` (its state's row, non-decreasing) and ``weight[e]``
    (edges traversed, :attr:`Event.distance`). Its successor is its source with
    some robots changed: per change c, robot ``robot[c]`` of event ``event[c]``
    gets code ``code[c]`` (``OUTSIDE`` when it leaves the region); changes are listed by
    event, non-decreasing. ``event`` is None when there is exactly one change per
    event (change c belongs to event c: ASYNC's Looks and Moves), which saves the
    engine work; an event with no change is a self-loop.
    """

    states: int
    source: np.ndarray  # (E,) int64 (int32 from ASYNC's bulk_successors)
    weight: np.ndarray  # (E,) int8 (int16 past 127 robots)
    robot: np.ndarray  # (C,) int64 (int32 from ASYNC's bulk_successors)
    code: np.ndarray  # (C,) int64 (int32 from ASYNC's bulk_successors)
    event: np.ndarray | None  # (C,) int64, or None: C == E and event[c] == c
    extra: np.ndarray | None = None
    """(E,) int64: a ``stateful`` scheduler's own state after each event (``state_index``)."""


class Scheduler(Protocol):
    """An adversary: the events it may choose in a state, one state at a time and in bulk.

    Two optional class attributes say what else may run it (absent: False): ``stateful``, it
    keeps a state of its own (``starts``, ``state_index``, ``state_of``, ``state_count``,
    ``relabel``; its ``luminous`` takes and gives that state, its bulk faces take it per
    state as ``extra=`` and fill :attr:`Successors.extra`), and ``union``, a sweep of the
    paper's world may explore all the configurations of one meeting-node set in one shared
    state graph under it (:mod:`gather_verify.engine.union`): its events from a state depend
    on that state alone and its ``bulk_successors`` gives them all, in ``successors``' order.
    A scheduler without ``union`` has each configuration of a sweep checked on its own.
    A third, ``rounds``: its ``bulk_successors`` is :func:`bulk_rounds` over its
    ``activations``, so the engine may take its events' successor keys straight from
    :func:`bulk_round_keys`."""

    name: str
    kinds: tuple[str, ...]
    """The :attr:`Event.kind` values its events carry."""

    def successors(self, state: State, move_sets: MoveSets) -> Iterator[tuple[Event, State]]:
        """Every (event, successor) the adversary can choose from ``state``."""
        ...

    def bulk_successors(self, frontier: Frontier, budget: int) -> Successors:
        """:meth:`successors` of the leading states of ``frontier``, as many as fit in about
        ``budget`` events (at least one state when there is one; all of them is fine when
        they fit): the same events, in the same order."""
        ...

    def activations(self, n: int) -> np.ndarray | None:
        """The robots a round activates, a boolean ``(k, n)`` matrix of the rounds' subsets in
        event order; None when its events are ASYNC's one Look or Move of one robot. The
        finite worlds' bulk engine reads it (a stateful scheduler's row is its turn's robot,
        one per row)."""
        ...

    def bulk_luminous(self, frontier: Frontier, budget: int, colours: int) -> Successors:
        """:meth:`luminous` on Z² in bulk (``order`` the actions themselves, ``null``), for
        the leading states of ``frontier`` as :meth:`bulk_successors` takes them; robots and
        masks are luminous (:func:`luminous_order` gives the layout)."""
        ...

    def luminous(self, robots: tuple[LRobot, ...], extra: object, actions: Actions, *,
                 order: ActionOrder = repr, null: bool = False
                 ) -> Iterator[tuple[Event, tuple[LRobot, ...], object]]:
        """Every event on a state of robots with their lights (and the scheduler's own
        ``extra``, None for the stateless ones), with the successor; a robot's actions are
        tried in the ``order`` of that key. An event that changes nothing is not yielded (it
        is no transition, §9-10) unless ``null``: on Z² a round in which every activated
        robot stays is a transition (§4), as the oblivious ``successors`` yield it."""
        ...


LRobot = tuple[object, object | None, int]
"""A robot on a finite world (§9-10): its node, its pending destination (None when idle) and
its light's colour (0 without lights)."""
Action = tuple[object, int]
"""What a robot may do when activated: go to (or stay on) a node, and set its colour."""
Actions = Callable[[int], frozenset[Action]]
"""Robot index -> its actions in the current configuration (the union over its frames)."""
ActionOrder = Callable[[Action], Any]
"""The sort key of a robot's actions in :meth:`Scheduler.luminous` (``repr`` on finite worlds;
the actions themselves on Z², the order of the oblivious ``successors``)."""


def round_event(active: Sequence[int], robots: tuple[LRobot, ...],
                choice: Sequence[Action]) -> tuple[Event, tuple[LRobot, ...]]:
    """The atomic Look-Compute-Move of the ``active`` robots, each doing its ``choice``:
    they move and set their colours at once (FSYNC, SSYNC, centralized, round-robin)."""
    new = list(robots)
    moves, lights = [], []
    for i, (d, c) in zip(active, choice, strict=True):
        v, _, old = robots[i]
        new[i] = (d, None, c)
        if d != v:
            moves.append((i, v, d))
        if c != old:
            lights.append((i, old, c))
    return Event("round", tuple(active), tuple(moves), tuple(lights)), tuple(new)


def oblivious_events(sched: Any, state: State, extra: object, move_sets: MoveSets
                     ) -> Iterator[tuple[Event, State, object]]:
    """The events of a ``stateful`` scheduler on Z² without lights, from its own ``luminous``
    (one colour, the actions in the order of ``successors``), with its state after each."""
    options = move_sets(configuration_of(state))

    def actions(i: int) -> frozenset[Action]:
        return frozenset((d, 0) for d in options[state[i][0]])

    robots = tuple((v, p, 0) for v, p in state)
    for event, succ, after in sched.luminous(robots, extra, actions, order=_natural, null=True):
        yield event, tuple((v, p) for v, p, _ in succ), after


def _natural(action: object) -> object:
    return action


def initial_state(robots: Iterable[Node]) -> State:
    """All robots idle on their nodes, in the given order (robot i = i-th node)."""
    return tuple((r, None) for r in robots)


def configuration_of(state: State) -> tuple[Node, ...]:
    """The robot nodes of a state, sorted (what every robot sees)."""
    return tuple(sorted(node for node, _ in state))


def _sorted_choices() -> tuple[tuple[int, ...], tuple[int, ...]]:
    """Per move mask, the allowed choices in the order of their sorted destinations
    (as ``successors`` tries them), each as its step index (``DEGREE``: stay); and how many."""
    order = sorted(range(SLOTS), key=lambda k: STEPS[k] if k < DEGREE else (0, 0))
    table, count = [], []
    for mask in range(1 << SLOTS):
        allowed = [k for k in order if mask >> k & 1]
        count.append(len(allowed))
        table.extend(allowed + [DEGREE] * (SLOTS - len(allowed)))
    return tuple(table), tuple(count)


_NTH, _COUNT = (np.array(t, dtype=np.int64) for t in _sorted_choices())
_NTH = _NTH.reshape(1 << SLOTS, SLOTS)


def bulk_rounds(frontier: Frontier, budget: int, subsets: np.ndarray) -> Successors:
    """The events of round schedulers in bulk: per state, for each activated subset in
    the order of the rows of ``subsets`` (a boolean ``(k, n)`` matrix), every choice of
    destinations of the activated robots in the order of ``itertools.product`` over
    their sorted move sets; the activated robots move at once, the others stay.
    Pending destinations play no part (round schedulers keep every robot idle).

    In compiled code when the kernels run (:mod:`gather_verify.kernels`), else in numpy
    (:func:`numpy_rounds`, the reference): the same events, field by field."""
    from gather_verify import kernels  # here: importing numba costs every command 0.25 s

    if not kernels.enabled():
        return numpy_rounds(frontier, budget, subsets)
    codes, masks, neighbour = frontier
    codes = np.ascontiguousarray(codes, dtype=np.int64)
    masks = np.ascontiguousarray(masks, dtype=np.uint8)
    subsets = np.ascontiguousarray(subsets, dtype=np.bool_)
    s, e, c = kernels.round_counts(masks, subsets, _COUNT, budget)
    n = codes.shape[1]
    source = np.empty(e, dtype=np.int64)
    weight = np.empty(e, dtype=np.int8 if n <= 127 else np.int16)
    robot, code, event = (np.empty(c, dtype=np.int64) for _ in range(3))
    kernels.round_events(codes, masks, np.ascontiguousarray(neighbour, dtype=np.int64), subsets,
                         _NTH, _COUNT, s, source, weight, robot, code, event)
    return Successors(s, source, weight, robot, code, event)


class RoundKeys(NamedTuple):
    """What :func:`bulk_round_keys` gives: the events of the first ``states`` states of a
    :class:`Frontier` as :func:`bulk_rounds` lists them (``source``, ``weight``), each with
    its successor's key in place of its changes; when ``leaves``, the last event listed is
    the first in which a robot leaves the region (its key is none) and the list stops there."""

    states: int
    source: np.ndarray  # (E,) int64
    weight: np.ndarray  # (E,) int8 (int16 past 127 robots)
    keys: np.ndarray  # (E,) uint64
    leaves: bool


def bulk_round_keys(frontier: Frontier, budget: int, subsets: np.ndarray, keys: np.ndarray,
                    powers: np.ndarray) -> RoundKeys:
    """:func:`bulk_rounds` with each event's successor key computed in the same compiled pass
    instead of its changes: the key of state s is ``keys[s]``, the sum of its robots' codes
    times ``powers`` (the engine's key without reductions), and a successor's is that sum
    with the stepping robots recoded. For the engine's searches that read no change (no
    transition property): writing and reading the changes cost more than the events.
    Compiled kernels only (:func:`gather_verify.kernels.enabled`)."""
    from gather_verify import kernels

    codes, masks, neighbour = frontier
    codes = np.ascontiguousarray(codes, dtype=np.int64)
    masks = np.ascontiguousarray(masks, dtype=np.uint8)
    subsets = np.ascontiguousarray(subsets, dtype=np.bool_)
    s, e, _ = kernels.round_counts(masks, subsets, _COUNT, budget)
    source = np.empty(e, dtype=np.int64)
    weight = np.empty(e, dtype=np.int8 if codes.shape[1] <= 127 else np.int16)
    succ = np.empty(e, dtype=np.uint64)
    e, leaves = kernels.round_keys(np.ascontiguousarray(keys, dtype=np.uint64), codes, masks,
                                   np.ascontiguousarray(neighbour, dtype=np.int64), subsets,
                                   _NTH, _COUNT, s, np.ascontiguousarray(powers, dtype=np.uint64),
                                   source, weight, succ)
    return RoundKeys(s, source[:e], weight[:e], succ[:e], bool(leaves))


def _widths(count: np.ndarray, subsets: np.ndarray, budget: int
            ) -> tuple[int, np.ndarray, np.ndarray]:
    """How many states of a chunk one step of rounds expands (at least one; as many as keep
    the events within ``budget``), and per (state, subset) row: each robot's number of
    choices (1 when not activated) and their product. ``count``: (S, n) choices per robot."""
    s, n = count.shape
    k = len(subsets)
    width = np.where(subsets[None, :, :], count[:, None, :], 1)  # (S, k, n)
    per = width.prod(axis=2)  # events per (state, subset)
    if s:
        total = np.cumsum(per.sum(axis=1))
        s = min(len(total), max(1, int(np.searchsorted(total, budget, side="right"))))
    return s, width[:s].reshape(s * k, n), per[:s].reshape(-1)


def _products(slot: np.ndarray, per: np.ndarray, width: np.ndarray, choice: np.ndarray,
              moves: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The events of rounds, one per product of the activated robots' choices (the last
    robot varies fastest): per event its (state, subset) row, the robots' new codes and
    which robots move. ``slot[row, i]``: where robot i's choices start in the flat
    ``choice``/``moves`` tables; ``width[row, i]``: how many it has; ``per[row]``: their
    product."""
    group = np.repeat(np.arange(len(per)), per)  # the (state, subset) of each event
    n = slot.shape[1]
    rank = np.arange(len(group)) - (np.cumsum(per) - per)[group]  # rank in its group
    new = np.empty((len(group), n), dtype=np.int64)
    moved = np.empty((len(group), n), dtype=bool)
    for i in range(n - 1, -1, -1):
        rank, digit = np.divmod(rank, width[group, i])
        at = slot[group, i] + digit
        new[:, i] = choice[at]
        moved[:, i] = moves[at]
    return group, new, moved


def _chosen(codes: np.ndarray, choice: np.ndarray, go: np.ndarray, subsets: np.ndarray,
            per: np.ndarray, width: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`_products` of rounds: ``choice[s, i, j]`` robot i's new code for its j-th choice
    in state s (``go``: whether it moves), a robot that is not activated keeping its code."""
    s, n, w = choice.shape
    table = np.empty((s, n, w + 1), dtype=np.int64)
    table[:, :, :w] = choice
    table[:, :, w] = codes
    moves = np.zeros((s, n, w + 1), dtype=bool)
    moves[:, :, :w] = go
    # per (state, subset) and robot: where its choices start in those flat tables
    slot = ((np.arange(s)[:, None] * n + np.arange(n)) * (w + 1))[:, None, :] + \
        np.where(subsets, 0, w)[None, :, :]
    return _products(slot.reshape(s * len(subsets), n), per, width, table.reshape(-1),
                     moves.reshape(-1))


def numpy_rounds(frontier: Frontier, budget: int, subsets: np.ndarray) -> Successors:
    """:func:`bulk_rounds` in numpy: the reference the compiled kernel is tested against."""
    codes, masks, neighbour = frontier
    s, n = codes.shape
    k = len(subsets)
    count = _COUNT[masks]  # (S, n) choices per robot
    s, width, per = _widths(count, subsets, budget)
    # per (state, robot): its new code for its j-th choice (j < SLOTS), or when not
    # activated (j = SLOTS); and whether that choice moves it
    nth = _NTH[masks[:s]]  # (S, n, SLOTS): step index of the j-th choice (DEGREE: stay)
    cell = codes[:s] // SLOTS
    go = nth < DEGREE
    dest = neighbour[cell[:, :, None], np.where(go, nth, 0)]
    choice = np.where(go, np.where(dest >= 0, dest * SLOTS, OUTSIDE), cell[:, :, None] * SLOTS)
    group, new, moved = _chosen(codes[:s], choice, go, subsets, per, width)
    flat = np.flatnonzero(moved.reshape(-1))
    event, robot = np.divmod(flat, n)
    return Successors(s, group // k, moved.sum(axis=1, dtype=np.int8 if n <= 127 else np.int16),
                      robot,
                      new.reshape(-1)[flat], event)


def luminous_order(colours: int) -> np.ndarray:
    """The action bits of a luminous robot on Z² in the order ``luminous`` tries its actions
    (sorted (destination, colour) pairs: the order of the oblivious ``successors``, then
    the colour): bit ``k * colours + c`` is ``STEPS[k]`` (k = ``DEGREE``: stay) with colour
    c."""
    order = sorted(range(SLOTS), key=lambda k: STEPS[k] if k < DEGREE else (0, 0))
    return np.array([k * colours + c for k in order for c in range(colours)], dtype=np.int64)


def allowed_actions(masks: np.ndarray, order: np.ndarray) -> np.ndarray:
    """Per robot, which actions of ``order`` its mask holds: an ``(S, n, len(order))`` bool."""
    return (masks.astype(np.int64)[:, :, None] >> order & 1).astype(bool)


def bulk_luminous_rounds(frontier: Frontier, budget: int, subsets: np.ndarray,
                         colours: int) -> Successors:
    """:func:`numpy_rounds` for luminous robots (codes and masks as :class:`Frontier` says
    with K colours): per state, per activated subset (rows of ``subsets``), every choice of
    actions of the activated robots in the order of ``itertools.product`` over their sorted
    actions; they move and set their colours at once (the rounds of ``luminous``, ``null``:
    a round that changes nothing is a self-loop). A change is listed per robot whose code
    changed (a move or a new colour); the weight counts the moves."""
    codes, masks, neighbour = frontier
    s, n = codes.shape
    k = len(subsets)
    order = luminous_order(colours)
    allowed = allowed_actions(masks, order)  # (S, n, W)
    count = allowed.sum(axis=2)
    s, width, per = _widths(count, subsets, budget)
    # per (state, robot): the bit of its j-th action (allowed ones first, in order)
    nth = order[np.argsort(~allowed[:s], axis=2, kind="stable")]  # (S, n, W)
    step, colour = np.divmod(nth, colours)
    cell = codes[:s] // (SLOTS * colours)
    go = step < DEGREE
    dest = neighbour[cell[:, :, None], np.where(go, step, 0)]
    choice = np.where(go, np.where(dest >= 0, dest * SLOTS * colours + colour, OUTSIDE),
                      cell[:, :, None] * SLOTS * colours + colour)
    group, new, moved = _chosen(codes[:s], choice, go, subsets, per, width)
    source = group // k
    flat = np.flatnonzero((new != codes[source]).reshape(-1))
    event, robot = np.divmod(flat, n)
    return Successors(s, source, moved.sum(axis=1, dtype=np.int8 if n <= 127 else np.int16),
                      robot, new.reshape(-1)[flat], event)


def subsets_matrix(subsets: Iterable[Iterable[int]], n: int) -> np.ndarray:
    """Activated subsets as a boolean matrix, one row per subset, in order."""
    rows = [[i in set(a) for i in range(n)] for a in subsets]
    return np.array(rows, dtype=bool).reshape(len(rows), n)


class Rounds:
    """A scheduler of atomic rounds: each event activates a set of robots that look at one
    snapshot and move (and set their colours) at once; the adversary picks the set, among
    :meth:`active_sets`, and each robot's choice. FSYNC, SSYNC and centralized are this
    with their sets (every robot; every non-empty subset; one robot); the events, one state
    at a time or in bulk, are written once here."""

    name: str
    kinds = ("round",)
    union = True
    rounds = True

    def active_sets(self, n: int) -> Iterable[tuple[int, ...]]:
        """The sets of robots a round may activate, in event order."""
        raise NotImplementedError

    def successors(self, state: State, move_sets: MoveSets) -> Iterator[tuple[Event, State]]:
        options = move_sets(configuration_of(state))
        for active in self.active_sets(len(state)):
            for choice in product(*(sorted(options[state[i][0]]) for i in active)):
                nodes = [node for node, _ in state]
                for i, d in zip(active, choice, strict=True):
                    nodes[i] = d
                moves = tuple((i, state[i][0], d)
                              for i, d in zip(active, choice, strict=True) if d != state[i][0])
                yield Event("round", active, moves), tuple((v, None) for v in nodes)

    def activations(self, n: int) -> np.ndarray:
        return _activations(type(self), n)

    def bulk_successors(self, frontier: Frontier, budget: int) -> Successors:
        return bulk_rounds(frontier, budget, self.activations(frontier.codes.shape[1]))

    def bulk_luminous(self, frontier: Frontier, budget: int, colours: int) -> Successors:
        return bulk_luminous_rounds(frontier, budget, self.activations(frontier.codes.shape[1]),
                                    colours)

    def luminous(self, robots: tuple[LRobot, ...], extra: object, actions: Actions, *,
                 order: ActionOrder = repr, null: bool = False
                 ) -> Iterator[tuple[Event, tuple[LRobot, ...], object]]:
        for active in self.active_sets(len(robots)):
            for choice in product(*(sorted(actions(i), key=order) for i in active)):
                event, succ = round_event(active, robots, choice)
                if null or succ != robots:
                    yield event, succ, extra


@cache
def _activations(kind: type[Rounds], n: int) -> np.ndarray:
    """The rounds' sets of a :class:`Rounds` scheduler for ``n`` robots, as a boolean
    matrix (:func:`subsets_matrix`), once per kind and ``n``."""
    return subsets_matrix(kind().active_sets(n), n)
