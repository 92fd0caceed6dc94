"""The explicit-state explorer: breadth-first search over the reachable states.

SEMANTICS.md §4-5. A state is, per robot, its node and its pending
destination. States are stored as integers: each robot is a *code*
``cell * 5 + direction`` (``cell`` indexes a node of the search region,
``direction`` is 0 when idle, else 1 + the index of the pending unit step in
``geometry.STEPS``), and a state packs its codes in base ``5 * cells``. The
visited set maps these integers to dense ids; the graph is kept in CSR arrays
(successor ids and edge weights per state, in id order), so the same layout
can be moved to numpy for a bulk frontier (issue 8).

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

import os
import resource
import time
from array import array
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field

from gather_verify.algorithms import Algorithm, Unhandled, get_algorithm, target_of
from gather_verify.algorithms.moves import frames_for, move_sets
from gather_verify.model import geometry
from gather_verify.model.classes import classify_configuration
from gather_verify.model.configuration import Configuration
from gather_verify.model.geometry import STEPS, Node
from gather_verify.model.symmetry import Automorphism, meeting_automorphisms
from gather_verify.model.view import check_detection
from schedulers import Event, State, configuration_of, get_scheduler, initial_state

STEP_INDEX = {step: i + 1 for i, step in enumerate(STEPS)}

DEFAULT_MAX_STATES = 30_000_000
DEFAULT_MAX_SECONDS = 3600.0
DEFAULT_MAX_MEMORY_MB = 16_000
"""Defaults sized for a 24 GiB machine (the reference path needs ~300 bytes/state)."""
DEFAULT_MARGIN = 2


@dataclass(frozen=True)
class Limits:
    """When to stop: any limit hit makes the search INCOMPLETE (never VERIFIED)."""

    max_states: int = DEFAULT_MAX_STATES
    max_seconds: float = DEFAULT_MAX_SECONDS
    max_memory_mb: float = DEFAULT_MAX_MEMORY_MB
    margin: int = DEFAULT_MARGIN


def rss_mb() -> float:
    """Resident set size of this process now, in MiB (``/proc``, else the peak)."""
    try:
        with open("/proc/self/statm", encoding="ascii") as f:
            return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2**20
    except (OSError, ValueError, IndexError):
        return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def symmetry_group(initial: Configuration, frames: str) -> list[Automorphism]:
    """The elements of ``Aut(M)`` the symmetry reduction may use with ``frames``."""
    allowed = set(frames_for(frames))
    group = [a for a in meeting_automorphisms(initial)]
    if allowed == set(geometry.ALL):
        return group
    return [a for a in group if a.g in allowed and all(
        geometry.compose(geometry.compose(a.g, f), geometry.inverse(a.g)) in allowed
        for f in allowed)]


def region_box(initial: Configuration, margin: int,
               group: Sequence[Automorphism] = ()) -> tuple[int, int, int, int]:
    """The MER of ``initial`` grown by ``margin``, closed under ``group``."""
    x0, y0, x1, y1 = initial.mer()
    corners = [(x0 - margin, y0 - margin), (x1 + margin, y1 + margin)]
    images = [a(v) for a in group for v in corners] + corners
    return geometry.bounding_box(images)


class Encoding:
    """Robots and states as integers over a box of the grid.

    >>> enc = Encoding((0, 0, 2, 2))
    >>> s = (((0, 0), (1, 0)), ((2, 2), None))
    >>> enc.decode(enc.key(s), 2) == s
    True
    """

    def __init__(self, box: tuple[int, int, int, int], group: Sequence[Automorphism] = (),
                 anonymity: bool = True):
        self.x0, self.y0, x1, y1 = box
        self.width, self.height = x1 - self.x0 + 1, y1 - self.y0 + 1
        self.cells = self.width * self.height
        self.base = self.cells * 5
        self.anonymity = anonymity
        self.tables = [self._table(a) for a in group if a.g != geometry.IDENTITY or a.t != (0, 0)]

    def inside(self, v: Node) -> bool:
        return 0 <= v[0] - self.x0 < self.width and 0 <= v[1] - self.y0 < self.height

    def node(self, cell: int) -> Node:
        return (self.x0 + cell // self.height, self.y0 + cell % self.height)

    def code(self, v: Node, pending: Node | None) -> int:
        cell = (v[0] - self.x0) * self.height + (v[1] - self.y0)
        return cell * 5 + (0 if pending is None else STEP_INDEX[(pending[0] - v[0], pending[1] - v[1])])

    def robot(self, code: int) -> tuple[Node, Node | None]:
        cell, d = divmod(code, 5)
        v = self.node(cell)
        return v, (None if d == 0 else geometry.add(v, STEPS[d - 1]))

    def _table(self, a: Automorphism) -> list[int]:
        out = []
        for code in range(self.base):
            v, p = self.robot(code)
            out.append(self.code(a(v), None if p is None else a(p)))
        return out

    def pack(self, codes: Iterable[int]) -> int:
        key, scale = 0, 1
        for c in codes:
            key += c * scale
            scale *= self.base
        return key

    def key(self, state: State) -> int:
        """The stored key of ``state`` (its class under the enabled reductions)."""
        codes = [self.code(v, p) for v, p in state]
        if self.anonymity:
            codes.sort()
        best = self.pack(codes)
        for table in self.tables:
            image = [table[c] for c in codes]
            if self.anonymity:
                image.sort()
            best = min(best, self.pack(image))
        return best

    def decode(self, key: int, n: int) -> State:
        out = []
        for _ in range(n):
            key, c = divmod(key, self.base)
            out.append(self.robot(c))
        return tuple(out)


@dataclass
class ConfigurationFacts:
    """What the properties need about one configuration (cached per configuration)."""

    move_sets: dict[Node, frozenset[Node]] | None  # None: the algorithm raised Unhandled
    unhandled: str | None
    stuck: bool  # every robot's move set is {its node}
    gathered: bool  # every robot on one meeting node
    in_U: bool
    target: Node | None


@dataclass
class Violation:
    """The first (shortest) witness of a safety property: the state it ends in, and for a
    transition property the event leaving it and the target values."""

    property: str
    state: int
    reason: str
    event: Event | None = None
    successor: State | None = None
    detail: dict[str, object] = field(default_factory=dict)


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
    stopped: str | None  # None: the whole space was expanded
    violations: dict[str, Violation]
    seconds: float
    peak_rss_mb: float
    facts: Callable[[tuple[Node, ...]], ConfigurationFacts]
    initial_in_U: bool

    @property
    def n(self) -> int:
        return self.initial.n

    def state(self, sid: int) -> State:
        return self.encoding.decode(self.keys[sid], self.n)

    def successors(self, sid: int) -> range:
        return range(self.offsets[sid], self.offsets[sid + 1])

    def concrete_successors(self, state: State) -> list[tuple[Event, State]]:
        """Every (event, successor) of a concrete state, from the scheduler."""
        def ms(robots: tuple[Node, ...]) -> dict[Node, frozenset[Node]]:
            facts = self.facts(robots)
            if facts.move_sets is None:
                raise Unhandled(facts.unhandled or "unhandled")
            return facts.move_sets
        return list(get_scheduler(self.scheduler_name).successors(state, ms))

    def path_to(self, sid: int) -> list[int]:
        """Ids from the initial state to ``sid`` along BFS parents (a shortest path)."""
        path = [sid]
        while self.parents[path[-1]] >= 0:
            path.append(self.parents[path[-1]])
        return path[::-1]

    def concretise(self, ids: Sequence[int], start: State | None = None) -> list[tuple[Event, State]]:
        """Concrete events and states following a path of stored ids (``ids[0]`` is the start)."""
        state = self.initial_state if start is None else start
        steps = []
        for nxt in ids[1:]:
            want = self.keys[nxt]
            for event, succ in self.concrete_successors(state):
                if self.encoding.key(succ) == want:
                    steps.append((event, succ))
                    state = succ
                    break
            else:  # pragma: no cover - the graph came from the same successors
                raise AssertionError(f"no concrete successor for stored state {nxt}")
        return steps

    @property
    def initial_state(self) -> State:
        return initial_state(self.initial.robots)


def facts_cache(algorithm: Algorithm, meeting: frozenset[Node], detection: str,
                frames: Sequence[int]) -> Callable[[tuple[Node, ...]], ConfigurationFacts]:
    """A memoised ``robots -> ConfigurationFacts`` (decisions depend on the configuration only)."""
    cache: dict[tuple[Node, ...], ConfigurationFacts] = {}

    def facts(robots: tuple[Node, ...]) -> ConfigurationFacts:
        got = cache.get(robots)
        if got is None:
            c = Configuration.trusted(robots, meeting)
            try:
                ms: dict[Node, frozenset[Node]] | None = move_sets(algorithm, c, detection, frames)
                unhandled = None
            except Unhandled as error:
                ms, unhandled = None, str(error) or "no rule for this view"
            stuck = ms is not None and all(s == {v} for v, s in ms.items())
            gathered = len(c.counts) == 1 and robots[0] in meeting
            try:
                target = target_of(algorithm, c)
            except Unhandled:
                target = None
            got = ConfigurationFacts(ms, unhandled, stuck, gathered,
                                     classify_configuration(c).in_U, target)
            cache[robots] = got
        return got

    return facts


SAFETY = ("defined", "final", "no-ungatherable", "target-invariance")


def explore_reference(
    initial: Configuration,
    algorithm: str | Algorithm,
    scheduler: str,
    *,
    detection: str = "local-weak",
    frames: str = "all",
    reduction: bool = True,
    anonymity: bool | None = None,
    symmetry: bool | None = None,
    properties: Iterable[str] = SAFETY,
    limits: Limits = Limits(),
) -> Exploration:
    """Breadth-first search of every state reachable from ``initial`` (reference path).

    Safety properties in ``properties`` (``final``, ``no-ungatherable``,
    ``target-invariance``; ``defined`` always) are checked on the way and their
    first witness kept; the search stops at a ``defined`` violation (the state
    cannot be expanded) or when a limit is hit (``stopped`` names it).
    """
    started = time.perf_counter()
    algo = get_algorithm(algorithm) if isinstance(algorithm, str) else algorithm
    sched = get_scheduler(scheduler)
    check_detection(detection)
    frame_elements = frames_for(frames)
    anonymity = reduction if anonymity is None else anonymity
    symmetry = reduction if symmetry is None else symmetry
    group = symmetry_group(initial, frames) if symmetry else []
    enc = Encoding(region_box(initial, limits.margin, group), group, anonymity)
    wanted = set(properties)
    facts = facts_cache(algo, initial.meeting_nodes, detection, frame_elements)
    initial_in_U = facts(initial.robots).in_U
    check_u = "no-ungatherable" in wanted and not initial_in_U
    check_target = "target-invariance" in wanted
    check_final = "final" in wanted

    def ms(robots: tuple[Node, ...]) -> dict[Node, frozenset[Node]]:
        got = facts(robots).move_sets
        assert got is not None  # checked before the scheduler runs
        return got

    start = initial_state(initial.robots)
    keys = [enc.key(start)]
    visited = {keys[0]: 0}
    parents, offsets, targets, weights = array("q", [-1]), array("q"), array("l"), array("b")
    violations: dict[str, Violation] = {}
    transitions = changed_loops = 0
    stopped: str | None = None
    peak = rss_mb()
    n = initial.n
    sid = 0
    while sid < len(keys):
        if sid & 1023 == 0:
            if time.perf_counter() - started > limits.max_seconds:
                stopped = "time"
                break
            if sid & 4095 == 0:
                peak = max(peak, rss_mb())
                if peak > limits.max_memory_mb:
                    stopped = "memory"
                    break
        state = enc.decode(keys[sid], n)
        robots = configuration_of(state)
        here = facts(robots)
        if here.move_sets is None:
            violations["defined"] = Violation(
                "defined", sid, f"the algorithm has no rule here: {here.unhandled}")
            stopped = "defined"
            break
        if (check_final and "final" not in violations and here.stuck and not here.gathered
                and all(p is None for _, p in state)):
            violations["final"] = Violation(
                "final", sid, "deadlock: no robot can move, nothing is pending, and the "
                "robots are not all on one meeting node")
        offsets.append(len(targets))
        for event, succ in sched.successors(state, ms):
            transitions += 1
            if not all(enc.inside(v) for v, _ in succ):
                stopped = "region"
                break
            if check_target and here.target is not None and "target-invariance" not in violations:
                after = facts(configuration_of(succ)).target
                if after is not None and after != here.target:
                    violations["target-invariance"] = Violation(
                        "target-invariance", sid,
                        f"the target meeting node changes from {list(here.target)} to {list(after)}",
                        event, succ, {"target_before": list(here.target), "target_after": list(after)})
            key = enc.key(succ)
            did = visited.get(key)
            if did is None:
                did = len(keys)
                visited[key] = did
                keys.append(key)
                parents.append(sid)
                if check_u and "no-ungatherable" not in violations and \
                        facts(configuration_of(succ)).in_U:
                    violations["no-ungatherable"] = Violation(
                        "no-ungatherable", did, "a configuration in U (I41/I42) is reached from "
                        "one outside U")
            elif did == sid and succ != state:
                changed_loops += 1
            targets.append(did)
            weights.append(event.distance)
        if stopped:
            break
        sid += 1
        if len(keys) > limits.max_states:
            stopped = "states"
            break
    offsets.append(len(targets))
    peak = max(peak, rss_mb())
    return Exploration(
        initial, algo, scheduler, detection, frames, anonymity, symmetry, enc, keys, parents,
        offsets, targets, weights, changed_loops, len(keys), transitions, stopped, violations,
        time.perf_counter() - started, peak, facts, initial_in_U)
