"""The explicit-state explorer: breadth-first search over the reachable states.

SEMANTICS.md §4-5. A state is, per robot, its node and its pending
destination. States are stored as integers: each robot is a *code*
``cell * SLOTS + direction`` (``geometry.SLOTS`` = degree + 1; ``cell`` indexes a node
of the search region, ``direction`` is 0 when idle, else 1 + the index of the pending
unit step in ``geometry.STEPS``), and a state packs its codes in base ``SLOTS * cells``. The
visited set maps these integers to dense ids; the graph is kept in CSR arrays
(successor ids and edge weights per state, in id order), so the same layout
can be moved to numpy for a bulk frontier.

Reductions (both on by default, both sound):

- anonymity: the robot codes are sorted (the state is the multiset of
  ``(node, pending)`` pairs);
- symmetry: states that differ by an element ``g`` of ``Aut(M)`` are one state,
  using only the ``g`` under which the frame set is closed (all 8 frames: every
  ``g``; common chirality: rotations; common compass: none). The search region
  is then the smallest ``Aut(M)``-invariant box containing the MER of the
  initial configuration grown by the margin.

The explorer expands the *representative* of each class: every successor,
event and per-configuration fact (move sets, class, target) is computed on a
concrete state, and only the successor's key is canonicalised.

>>> from gather_verify.model.configuration import Configuration
>>> c = Configuration([(0, 0), (3, 1), (1, 4)], [(2, 2)], initial=True)
>>> e = explore_reference(c, "go-to-target", "async", reduction=False)
>>> e.states, e.transitions, e.stopped
(2184, 7032, None)
"""

from __future__ import annotations

from array import array
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from functools import partial
from typing import Any

from gather_verify.algorithms import Algorithm, Unhandled, get_algorithm
from gather_verify.algorithms.moves import frames_for
from gather_verify.engine.bfs import breadth_first
from gather_verify.engine.checks import Checks, Violation, symmetric
from gather_verify.engine.encoding import (
    DEFAULT_MARGIN,
    DEFAULT_MAX_MEMORY_MB,
    DEFAULT_MAX_SECONDS,
    DEFAULT_MAX_STATES,
    NO_LIMITS,
    STEP_INDEX,
    Encoding,
    Limits,
    LuminousEncoding,
    Stop,
    Turns,
    rss_mb,
    symmetry_group,
)
from gather_verify.engine.region import region_box
from gather_verify.model.configuration import Configuration
from gather_verify.model.geometry import Node
from gather_verify.model.symmetry import Automorphism
from gather_verify.model.view import Lights, check_detection
from gather_verify.properties.facts import (
    ConfigurationFacts,
    StateFacts,
    configuration_facts,
    luminous_facts,
)
from schedulers import (
    Event,
    Scheduler,
    State,
    as_scheduler,
    configuration_of,
    get_scheduler,
    initial_state,
)
from schedulers.base import oblivious_events

__all__ = ["DEFAULT_MARGIN", "DEFAULT_MAX_MEMORY_MB", "DEFAULT_MAX_SECONDS", "DEFAULT_MAX_STATES",
           "STEP_INDEX", "ConfigurationFacts", "Encoding", "Exploration",
           "Limits", "Violation", "explore_reference", "facts_cache", "region_box",
           "rss_mb", "symmetry_group"]
"""(``Encoding``, ``Limits``, the defaults, ``region_box`` and ``symmetry_group`` live in
:mod:`gather_verify.engine.encoding`; they are re-exported here for existing callers.)"""


@dataclass
class Exploration:
    """The reachable graph (CSR over dense ids) and what the search found."""

    initial: Configuration
    algorithm: Algorithm
    scheduler_name: str
    detection: str
    frames: str
    anonymity: bool
    symmetry: bool
    encoding: Encoding
    keys: list[int]
    parents: array
    offsets: array
    targets: array
    weights: array
    changed_loops: int
    states: int
    transitions: int
    stopped: Stop | str | None  # None: the whole space was expanded; else why, or the
    # halting property it stopped at
    violations: dict[str, Violation]
    seconds: float
    peak_rss_mb: float
    facts: Callable[[Any], ConfigurationFacts]  # sorted robot nodes (with lights: (node, colour))
    vacuous: dict[str, str]  # properties not checked: they hold from this initial state, why
    lights: Lights | None = None
    """The robots' lights (§10); None: oblivious robots. With lights a state's robots are
    ``(node, pending, colour)`` and :attr:`facts` takes sorted ``(node, colour)`` pairs."""
    colours: tuple[int, ...] | None = None  # the initial colours (with lights)
    engine: str = "reference"
    """Which engine ran the search: ``reference`` or ``bulk``."""
    engine_fallback: str | None = None
    """Why the bulk engine did not run it, when it was asked to if it could (``auto``)."""
    turns: Turns | None = None
    """A ``stateful`` scheduler's own state in the keys (round-robin's order and turn); None
    for the others. Its states are then :class:`TurnState` s."""
    starts: list[State] | None = None
    """With :attr:`turns`: the concrete initial state of each seed id (one per start of the
    scheduler that the reductions did not merge), in id order."""

    @property
    def n(self) -> int:
        return self.initial.n

    def state(self, sid: int) -> State:
        state = self.encoding.decode(self.keys[sid], self.n)
        if self.turns is not None:
            return TurnState(state, self.turns.extra(int(self.keys[sid])))
        return state

    def key_of(self, state: State) -> int:
        """The stored key of a concrete state (a :class:`TurnState` with :attr:`turns`)."""
        return state_key(self.encoding, self.turns)(state)

    def start_of(self, sid: int) -> State:
        """The concrete initial state a path from seed ``sid`` starts in."""
        return self.initial_state if self.starts is None else self.starts[sid]

    def scheduler_from(self, start: State) -> str:
        """The scheduler's name as a trace from ``start`` gives it: with :attr:`turns`, its
        start fixed (``round-robin:order=2 0 1``), so the trace shows it and replays it."""
        if self.turns is None:
            return self.scheduler_name
        return self.turns.sched.pinned(start.extra)  # type: ignore[attr-defined]

    def successors(self, sid: int) -> range:
        return range(self.offsets[sid], self.offsets[sid + 1])

    def facts_of(self, state: State) -> ConfigurationFacts:
        """The facts of a concrete state's configuration (with its lights, if any)."""
        if self.lights is not None:
            return self.facts(lit_configuration(state))
        return self.facts(configuration_of(state))

    def may_stay(self, state: State, i: int) -> bool:
        """Whether robot ``i`` is idle in ``state`` and may stay (keeping its colour): a null
        activation (§5's fairness)."""
        robot = state[i]
        if robot[1] is not None:
            return False
        facts = self.facts_of(state)
        if self.lights is not None:
            v, _, c = robot  # type: ignore[misc]
            return facts.actions is not None and (v, c) in facts.actions[v, c]
        return facts.move_sets is not None and robot[0] in facts.move_sets[robot[0]]

    def concrete_successors(self, state: State) -> list[tuple[Event, State]]:
        """Every (event, successor) of a concrete state, from the scheduler."""
        sched = get_scheduler(self.scheduler_name)
        extra = getattr(state, "extra", None)
        if self.lights is not None:
            facts = self.facts_of(state)
            if facts.actions is None:
                raise Unhandled(facts.unhandled or "unhandled")
            if self.turns is None:
                return list(luminous_events(sched, state, facts))
            return [(e, TurnState(s, a)) for e, s, a in luminous_steps(sched, state, facts, extra)]

        def ms(robots: tuple[Node, ...]) -> dict[Node, frozenset[Node]]:
            facts = self.facts(robots)
            if facts.move_sets is None:
                raise Unhandled(facts.unhandled or "unhandled")
            return facts.move_sets
        if self.turns is None:
            return list(sched.successors(state, ms))
        return [(e, TurnState(s, a)) for e, s, a in oblivious_events(sched, state, extra, ms)]

    def path_to(self, sid: int) -> list[int]:
        """Ids from the initial state to ``sid`` along BFS parents (a shortest path)."""
        path = [sid]
        while self.parents[path[-1]] >= 0:
            path.append(self.parents[path[-1]])
        return path[::-1]

    def concretise(self, ids: Sequence[int], start: State | None = None,
                   weights: Sequence[int] | None = None) -> list[tuple[Event, State]]:
        """Concrete events and states following a path of stored ids (``ids[0]`` is the start);
        with ``weights``, each event also makes that many moves (two events of a reduced
        graph may reach one class with different moves)."""
        state = self.start_of(ids[0]) if start is None else start
        steps = []
        for k, nxt in enumerate(ids[1:]):
            want = self.keys[nxt]
            for event, succ in self.concrete_successors(state):
                if self.key_of(succ) == want and (
                        weights is None or event.distance == weights[k]):
                    steps.append((event, succ))
                    state = succ
                    break
            else:  # pragma: no cover - the graph came from the same successors
                raise AssertionError(f"no concrete successor for stored state {nxt}")
        return steps

    @property
    def initial_state(self) -> State:
        if self.starts is not None:  # a stateful scheduler's first start
            return self.starts[0]
        if self.lights is not None:
            return lit_initial_state(self.initial.robots, self.colours)
        return initial_state(self.initial.robots)


class TurnState(tuple[Any, ...]):
    """A concrete state of the robots with a ``stateful`` scheduler's own state, ``extra``
    (round-robin's order and turn): a :data:`~schedulers.base.State` to every reader of
    robots, and two are equal only when their schedulers' states are too (a cycle must
    return to the same turn)."""

    extra: object

    def __new__(cls, robots: Iterable[Any], extra: object) -> TurnState:
        self = super().__new__(cls, robots)
        self.extra = extra
        return self

    def __getnewargs__(self) -> tuple[Any, ...]:
        return tuple(self), self.extra

    def __eq__(self, other: object) -> bool:
        return isinstance(other, tuple) and tuple(self) == tuple(other) and \
            getattr(other, "extra", None) == self.extra

    def __ne__(self, other: object) -> bool:
        return not self == other

    def __hash__(self) -> int:
        return hash((tuple(self), self.extra))


def lit_configuration(state: State) -> tuple[tuple[Node, int], ...]:
    """What the robots of a luminous state see: every robot's (node, colour), sorted."""
    return tuple(sorted((r[0], r[2]) for r in state))  # type: ignore[misc]


def lit_initial_state(robots: Sequence[Node], colours: Sequence[int] | None) -> State:
    """All robots idle on their nodes with their initial colours (default 0)."""
    lights = colours if colours is not None else (0,) * len(robots)
    return tuple((v, None, c) for v, c in zip(robots, lights, strict=True))  # type: ignore[misc]


def _natural(action: object) -> object:
    return action


def luminous_events(sched: object, state: State,
                    facts: ConfigurationFacts) -> Iterable[tuple[Event, State]]:
    """The scheduler's events from a luminous Z² state, in the order of the oblivious
    ``successors`` (actions by destination, then colour; a round where every activated robot
    stays is a self-loop transition, as on Z² without lights, §4)."""
    for event, succ, _ in luminous_steps(sched, state, facts, None):
        yield event, succ


def luminous_steps(sched: object, state: State, facts: ConfigurationFacts, extra: object
                   ) -> Iterable[tuple[Event, State, object]]:
    """:func:`luminous_events` with the scheduler's own state (``extra``) before and after."""
    acts = facts.actions
    assert acts is not None

    def actions(i: int) -> frozenset[tuple[Node, int]]:
        v, _, c = state[i]  # type: ignore[misc]
        return acts[v, c]

    return sched.luminous(state, extra, actions,  # type: ignore[attr-defined]
                          order=_natural, null=True)


def weight_code(n: int) -> str:
    """The array type of a transition's weight (edges traversed, at most ``n``): a byte up to
    127 robots, two bytes beyond."""
    return "b" if n <= 127 else "h"


def facts_cache(algorithm: Algorithm, initial: Configuration, detection: str,
                frames: Sequence[int]) -> Callable[[tuple[Node, ...]], ConfigurationFacts]:
    """A memoised ``robots -> ConfigurationFacts`` (decisions depend on the configuration only)."""
    cache: dict[tuple[Node, ...], ConfigurationFacts] = {}
    meeting = initial.meeting_nodes

    def facts(robots: tuple[Node, ...]) -> ConfigurationFacts:
        got = cache.get(robots)
        if got is None:
            got = configuration_facts(algorithm, Configuration.trusted(robots, meeting), initial,
                                      detection, frames)
            cache[robots] = got
        return got

    return facts


def luminous_facts_cache(algorithm: Algorithm, initial: Configuration, detection: str,
                         frames: Sequence[int], lights: Lights
                         ) -> Callable[[tuple[tuple[Node, int], ...]], ConfigurationFacts]:
    """:func:`facts_cache` of luminous configurations (sorted (node, colour) pairs)."""
    cache: dict[tuple[tuple[Node, int], ...], ConfigurationFacts] = {}

    def facts(robots: tuple[tuple[Node, int], ...]) -> ConfigurationFacts:
        got = cache.get(robots)
        if got is None:
            got = cache[robots] = luminous_facts(algorithm, robots, initial, detection, frames,
                                                 lights)
        return got

    return facts


def _turn_key(turns: Turns, enc: Encoding, state: Any) -> int:
    return turns.key(enc, state, state.extra)


def state_key(enc: Encoding, turns: Turns | None) -> Callable[[Any], int]:
    """The stored key of a concrete state: ``enc.key``, or with a ``stateful`` scheduler
    that of a :class:`TurnState` (its state above the robots' digits)."""
    return enc.key if turns is None else partial(_turn_key, turns, enc)


def turns_of(sched: object, n: int, anonymity: bool, base: int) -> Turns | None:
    """The scheduler's own state in the keys (:class:`Turns`), or None when it keeps none."""
    return Turns(sched, n, anonymity, base) if getattr(sched, "stateful", False) else None


def seed_states(start: State, turns: Turns | None) -> list[State]:
    """The concrete initial states of a search: ``start``, with each start of a ``stateful``
    scheduler."""
    return [start] if turns is None else [TurnState(start, x) for x in turns.starts()]


@dataclass(frozen=True)
class Request:
    """A search's request as every engine resolves it (:func:`resolve`, the engines' common
    prologue): the algorithm and scheduler objects, the frames' elements, the reductions
    asked for (``symmetry`` only when every requested property is symmetric), the usable
    elements of ``Aut(M)``, the region's box, and whether the scheduler keeps a state of
    its own (round-robin's order and turn)."""

    algorithm: Algorithm
    scheduler: Scheduler
    frame_elements: tuple[int, ...]
    anonymity: bool
    symmetry: bool
    group: list[Automorphism]
    box: tuple[int, int, int, int]
    stateful: bool

    @property
    def relabel(self) -> bool:
        """Whether the encoding sorts identical robots (not under a stateful scheduler: there
        its own state relabels them, :class:`~gather_verify.engine.encoding.Turns`)."""
        return self.anonymity and not self.stateful

    @property
    def reduced(self) -> bool:
        """Whether successor keys go through the canonical form."""
        return bool(self.group or self.anonymity)


def resolve(initial: Configuration, algorithm: str | Algorithm, scheduler: str | Scheduler,
            asked: Asked) -> Request:
    """The :class:`Request` of a search (an unknown algorithm, scheduler or detection model
    is an error here, before anything is searched)."""
    algo = get_algorithm(algorithm) if isinstance(algorithm, str) else algorithm
    sched = as_scheduler(scheduler)
    detection, frames, reduction = asked.detection, asked.frames, asked.reduction
    anonymity, symmetry, properties = asked.anonymity, asked.symmetry, asked.properties
    check_detection(detection)
    anonymity = reduction if anonymity is None else anonymity
    symmetry = (reduction if symmetry is None else symmetry) and symmetric(properties)
    group = symmetry_group(initial, frames) if symmetry else []
    return Request(algo, sched, frames_for(frames), anonymity, symmetry, group,
                   region_box(initial, asked.limits.margin, group),
                   getattr(sched, "stateful", False))


@dataclass(frozen=True)
class Asked:
    """What a search of the paper's world is asked, whichever engine runs it (the keyword
    arguments of :func:`explore_reference` and of the bulk engine's ``explore_fast``):
    the detection model and the frames, the reductions (``anonymity`` and ``symmetry``
    default to ``reduction``), the properties checked on the way (default: every registered
    one), the limits, whether to stop once every requested property has its counterexample
    (``settle``), and luminous robots (``lights``, with their initial ``colours``)."""

    detection: str = "local-weak"
    frames: str = "all"
    reduction: bool = True
    anonymity: bool | None = None
    symmetry: bool | None = None
    properties: Iterable[str] | None = None
    limits: Limits = NO_LIMITS
    settle: bool = False
    lights: Lights | None = None
    colours: Sequence[int] | None = None

    def initial_colours(self, n: int) -> tuple[int, ...] | None:
        """The robots' initial colours with lights (default 0), None without."""
        return None if self.lights is None else tuple(self.colours or (0,) * n)


def explore_reference(initial: Configuration, algorithm: str | Algorithm,
                      scheduler: str | Scheduler, **options: Any) -> Exploration:
    """Breadth-first search of every state reachable from ``initial`` (reference path): the
    one reference search (:func:`~gather_verify.engine.bfs.breadth_first`) over the paper's
    world (:class:`PlaneModel`).

    ``lights``: luminous robots (§10; ``colours``: their initial colours, default 0): a
    state's robots carry their colours, an algorithm answers a move or (move, colour).

    ``settle``: stop (``stopped == "settled"``) once every requested property has a
    counterexample (``properties`` named, none of them a graph property).

    The state and transition properties named in ``properties`` (default: every registered
    one; the pseudo-properties ``crash`` and ``defined`` always) are checked on the way and their
    first witness kept (:mod:`gather_verify.engine.checks`); the search stops at a violation
    of a halting property (``crash``, ``defined``: the state cannot be expanded; ``stopped`` names the
    property) or when a limit is hit (``stopped`` names it).
    """
    asked = Asked(**options)
    req = resolve(initial, algorithm, scheduler, asked)
    model = PlaneModel(initial, req, asked.detection, asked.properties, asked.settle,
                       asked.lights, asked.colours)
    walked = breadth_first(model, asked.limits)
    model.offsets.append(len(model.targets))
    return Exploration(
        initial=initial, algorithm=req.algorithm,
        scheduler_name=scheduler if isinstance(scheduler, str) else req.scheduler.name,
        detection=asked.detection, frames=asked.frames, anonymity=req.anonymity,
        symmetry=req.symmetry, encoding=model.enc, keys=walked.stored, parents=walked.parents, offsets=model.offsets,
        targets=model.targets, weights=model.weights, changed_loops=model.changed_loops,
        states=len(walked.stored), transitions=walked.transitions, stopped=walked.stopped,
        violations=model.checks.violations, seconds=walked.seconds,
        peak_rss_mb=walked.peak_rss_mb, facts=model.facts, vacuous=model.checks.vacuous,
        lights=asked.lights, colours=asked.initial_colours(initial.n), turns=model.turns,
        starts=None if model.turns is None else walked.seeds)


class PlaneModel:
    """The paper's world as the one reference search reads it (:class:`~gather_verify.engine.bfs.Model`):
    states stored as their integer keys (:class:`~gather_verify.engine.encoding.Encoding`,
    the canonical representative decoded back for expansion), the configuration facts of
    each state from the algorithm (:func:`facts_cache`), the registered properties checked
    on the way (:class:`~gather_verify.engine.checks.Checks`), the graph kept in CSR arrays
    with each edge's weight (moves), and the region as the search's bound."""

    def __init__(self, initial: Configuration, req: Request, detection: str,
                 properties: Iterable[str] | None, settle: bool, lights: Lights | None,
                 colours: Sequence[int] | None):
        algo, frame_elements = req.algorithm, req.frame_elements
        self.sched, self.settle, self.n = req.scheduler, settle, initial.n
        self.facts: Callable[[Any], ConfigurationFacts]
        self.conf: Callable[[Any], Any]  # a state -> what its robots see (with lights: colours)
        self.start: Any
        if lights is None:
            self.enc = Encoding(req.box, req.group, req.relabel)
            self.facts = facts_cache(algo, initial, detection, frame_elements)
            self.conf = configuration_of
            self.start = initial_state(initial.robots)
        else:
            self.enc = LuminousEncoding(req.box, req.group, req.relabel, lights.colours)
            self.facts = luminous_facts_cache(algo, initial, detection, frame_elements, lights)
            self.conf = lit_configuration
            self.start = lit_initial_state(initial.robots, colours)
        self.lights = lights
        self.turns = turns_of(self.sched, initial.n, req.anonymity, self.enc.base)
        self.key = state_key(self.enc, self.turns)
        first = StateFacts(self.facts_of(self.start), True)
        self.checks = Checks(properties, first)
        self.checks.state(0, first, self.checks.on_discovery)
        self.offsets, self.targets = array("q"), array("l")
        self.weights = array(weight_code(initial.n))
        self.changed_loops = 0
        self.here: ConfigurationFacts | None = None  # the facts of the state being expanded

    def facts_of(self, state: Any) -> ConfigurationFacts:
        """The facts of a concrete state's configuration (with its lights, if any)."""
        return self.facts(self.conf(state))

    def seeds(self) -> list[State]:
        return seed_states(self.start, self.turns)

    def stored(self, state: State, key: int) -> int:
        return key

    def state(self, sid: int, stored: int) -> State:
        state = self.enc.decode(stored, self.n)
        if self.turns is not None:
            return TurnState(state, self.turns.extra(stored))
        return state

    def expand(self, sid: int, state: State) -> Iterable[tuple[Event, State]] | str:
        here = self.here = self.facts_of(state)
        seen = StateFacts(here, all(r[1] is None for r in state))
        halted = self.checks.halt(sid, seen)
        if halted:
            return halted
        assert here.move_sets is not None, "a state without move sets needs a halting property"
        self.checks.state(sid, seen, self.checks.on_expansion)
        self.offsets.append(len(self.targets))
        return self.events(state, here)

    def events(self, state: State, here: ConfigurationFacts) -> Iterable[tuple[Event, State]]:
        """The scheduler's events of a concrete state (its own state carried along when it
        keeps one)."""
        sched, turns = self.sched, self.turns
        if self.lights is not None:
            if turns is not None:
                return ((e, TurnState(s, a)) for e, s, a in luminous_steps(
                    sched, state, here, state.extra))  # type: ignore[attr-defined]
            return luminous_events(sched, state, here)

        def ms(robots: tuple[Node, ...]) -> dict[Node, frozenset[Node]]:
            got = self.facts(robots).move_sets
            assert got is not None  # checked before the scheduler runs
            return got

        if turns is not None:
            return ((e, TurnState(s, a)) for e, s, a in oblivious_events(
                sched, state, state.extra, ms))  # type: ignore[attr-defined]
        return sched.successors(state, ms)

    def inside(self, succ: State) -> bool:
        return all(self.enc.inside(r[0]) for r in succ)

    def transition(self, sid: int, event: Event, succ: State) -> None:
        if self.checks.on_transition:
            assert self.here is not None
            self.checks.transition(sid, self.here, lambda: self.facts_of(succ), (event, succ))

    def discovered(self, did: int, succ: State) -> None:
        if self.checks.on_discovery:
            self.checks.state(did, StateFacts(self.facts_of(succ),
                                              all(r[1] is None for r in succ)),
                              self.checks.on_discovery)

    def edge(self, sid: int, did: int, event: Event, succ: State, state: State) -> None:
        if did == sid and succ != state:
            self.changed_loops += 1
        self.targets.append(did)
        self.weights.append(event.distance)

    def expanded(self, sid: int) -> str | None:
        return Stop.SETTLED if self.settle and self.checks.settled() else None
