"""The impossibility theorem as a check: Theorem 1's FSYNC adversary, played.

Paper §3.2 (Theorem 1, its four-case proof, Corollary 1), SEMANTICS.md §6.
For an initial configuration in U = I41 ∪ I42 the check finds the partitive
automorphism ``phi`` and the set ``V'`` of Theorem 1:

- I41: ``phi`` is the reflection of ``C`` in its axis L; ``V' = L``, which
  holds no node when L runs through edges, and the axis nodes otherwise.
- I42: ``phi`` is the rotation of ``C`` of largest order (90 degrees when
  ``C`` has it, k = 4, else 180 degrees, k = 2); ``V' = {c}``, no node when the
  centre c is an edge midpoint or a square centre.

In both cases ``V'`` is exactly the set of nodes ``phi`` fixes, and ``phi`` is
partitive on ``V \\ V'`` (every other orbit of ``H = <phi>`` has ``k`` nodes).

The adversary then plays FSYNC rounds. Robots' move sets come from
:func:`gather_verify.algorithms.moves.move_sets` (all frames, the detection model given).
Every round it groups the occupied nodes into *groups*:

- each orbit ``H(v)`` of occupied nodes outside ``V'``: one destination ``u``
  is chosen for the representative ``v`` (its smallest node) and the robots
  on ``phi^j(v)`` go to ``phi^j(u)`` (proof cases 1 and 3);
- each occupied node ``w`` of ``V'`` (reached only through multiplicities,
  since ``R(0) ∩ V' = ∅``): one destination ``u`` is chosen; if ``u`` is in
  ``V'`` all robots on ``w`` go to ``u`` (case 4, and staying), otherwise
  they split evenly, ``count(w) / k`` robots to each node of ``H(u)`` (case 2).

Every chosen move is checked against the robot's move set: by equivariance
(see :mod:`gather_verify.algorithms.random_equivariant`) it is always there;
if not, :class:`AdversaryError` is raised (a bug in the model, reported
loudly, never silently skipped).

After every round the check verifies the theorem's invariant, precisely:

1. ``symmetry``: ``phi`` maps the robot multiset onto itself with exact
   counts (so ``phi`` stays an automorphism of ``(C, l)``; ``M`` is fixed), and
   every occupied node of ``V'`` holds a multiple of ``k`` robots (what case 2
   needs to split them). ``phi`` being partitive on ``V \\ V'`` is then a
   property of ``phi`` alone.
2. ``not gathered``: no round ends with every robot on one meeting node.

Exploration (``explore``): ``"all"`` enumerates every equivariant choice
breadth-first, up to ``steps`` rounds and ``max_states`` configurations (the
default: the strongest check while small); ``"random"`` plays one run whose
choices come from a seeded RNG, for ``steps`` rounds or until a configuration
repeats (the adversary can then repeat the cycle forever). ``split_orbit=True``
deliberately breaks the adversary: the nodes of the first orbit outside
``V'`` choose independently, so a test can show the check does fail.

>>> from gather_verify.model.configuration import Configuration
>>> from gather_verify.algorithms.random_equivariant import RandomEquivariant
>>> c = Configuration([(0, 1), (1, -1)], [(0, 0), (1, 0)], initial=True)
>>> r = check_impossibility(c, [RandomEquivariant(1)], steps=6)
>>> r.partitive, r.class_name, r.holds, r.automorphism.describe()
(True, 'I42', True, 'rotation 180 about (0.5, 0) [edge]')
"""

from __future__ import annotations

import itertools
import random
from collections import deque
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass, field
from typing import Any

from gather_verify.algorithms.base import Algorithm, Unhandled
from gather_verify.algorithms.moves import move_set
from gather_verify.errors import GatherVerifyError, InvalidInput
from gather_verify.model import geometry
from gather_verify.model.configuration import Configuration
from gather_verify.model.geometry import Node
from gather_verify.model.symmetry import (
    Automorphism,
    configuration_automorphisms,
    symmetry_defect,
)
from gather_verify.paper.classes import Classification, classify_configuration

TRACE_FORMAT = "impossibility-trace/1"
EXPLORE_MODES = ("all", "random")
Move = tuple[Node, Node]


class AdversaryError(GatherVerifyError, AssertionError):
    """A move the theorem's adversary needs is missing from a robot's move set.

    Cause: the adversary of the impossibility theorem, built for a configuration in U, needs
    a move (or a split of a multiplicity) that a robot's move set does not hold: the move sets
    are not equivariant, a bug in the model or the algorithm. Fix: check that the algorithm
    answers from its view alone (no state, no randomness outside the view); if it does,
    report the configuration and the algorithm (an ``AssertionError``: the proof's premise
    failed)."""


# -- the theorem's data ---------------------------------------------------------------


def partitive_automorphism(classification: Classification) -> Automorphism | None:
    """``phi`` of Theorem 1 for a configuration in U (None outside U): the reflection
    (I41, and UNCLASSIFIED with an empty axis) or the rotation (I42)."""
    symmetries = classification.configuration_symmetries
    if classification.name == "I41":
        mirrors = [a for a in symmetries if a.kind == "reflection"]
        if len(mirrors) != 1 or mirrors[0] != classification.symmetry:
            raise AssertionError(f"I41 without the reflection of M: {symmetries}")
        return mirrors[0]
    if classification.name == "I42":
        rotations = [a for a in symmetries if a.kind == "rotation"]
        # 90 before 180; among the two 90-degree ones the counter-clockwise one
        return min(rotations, key=lambda a: (-a.order, a.g))
    if classification.name == "UNCLASSIFIED" and classification.in_U:
        (mirror,) = symmetries  # §3.2's U: a unique line of symmetry, its axis empty
        return mirror
    return None


def theorem1_automorphism(c: Configuration) -> Automorphism | None:
    """Any ``phi`` in ``Aut(C, l)`` meeting Theorem 1's hypothesis, whatever the class:
    no robot and no meeting node on its fixed nodes ``V'`` (largest order first).

    Exactly the configurations in U have one (§3.2's description of U is Theorem 1's
    hypothesis: I12/I13/I31/I32 hold a meeting node or robot on L or c, I1x/I2x have
    ``Aut(C)`` trivial, an UNCLASSIFIED configuration is in U when its axis is empty).

    >>> theorem1_automorphism(Configuration([(0, 1), (2, 1)], [(0, 0), (2, 0)])).describe()
    'reflection, vertical axis x = 1 through nodes'
    """
    marked = c.occupied | c.meeting_nodes
    candidates = [a for a in configuration_automorphisms(c)[1:]
                  if not any(a.fixes(v) for v in marked)]
    return min(candidates, key=lambda a: (-a.order, a.g, a.t)) if candidates else None


def in_v_prime(phi: Automorphism, v: Node) -> bool:
    """``v`` in ``V'``: the axis nodes (I41) or the centre node (I42), i.e. ``phi(v) = v``."""
    return phi(v) == v


def power(phi: Automorphism, j: int, v: Node) -> Node:
    """``phi^j(v)``."""
    for _ in range(j):
        v = phi(v)
    return v


# -- the adversary ----------------------------------------------------------------------


@dataclass(frozen=True)
class Group:
    """Nodes whose robots the adversary moves together, and its options.

    Each option is a tuple of (source, destination) robot moves."""

    nodes: tuple[Node, ...]
    options: tuple[tuple[Move, ...], ...]


def robot_move_sets(
    algorithm: Algorithm, c: Configuration, detection: str, frames: Sequence[int]
) -> tuple[dict[Node, frozenset[Node]], list[Node]]:
    """Move set per occupied node; a node whose view the algorithm leaves
    :class:`Unhandled` stays (returned in the second list)."""
    out: dict[Node, frozenset[Node]] = {}
    unhandled: list[Node] = []
    for v in sorted(c.counts):
        try:
            out[v] = move_set(algorithm, c, v, detection, frames)
        except Unhandled:
            out[v] = frozenset({v})
            unhandled.append(v)
    return out, unhandled


def _require(sets: dict[Node, frozenset[Node]], source: Node, destination: Node) -> None:
    if destination not in sets[source]:
        raise AdversaryError(
            f"the theorem's adversary needs the move {list(source)} -> {list(destination)}, "
            f"which is not in that robot's move set {sorted(sets[source])}: the move sets are "
            "not equivariant (a bug in the model or the algorithm)"
        )


def groups(
    phi: Automorphism,
    c: Configuration,
    sets: dict[Node, frozenset[Node]],
    split_orbit: bool = False,
) -> list[Group]:
    """The adversary's groups and their equivariant options for one round."""
    k = phi.order
    out: list[Group] = []
    seen: set[Node] = set()
    broken = False
    for v in sorted(c.counts):
        if v in seen:
            continue
        count = c.counts[v]
        if in_v_prime(phi, v):
            seen.add(v)
            if count % k:
                raise AdversaryError(f"{count} robots on {list(v)} in V' cannot split over "
                                     f"orbits of {k} nodes (case 2 of the proof)")
            options = []
            for u in sorted(sets[v]):
                if in_v_prime(phi, u):
                    moves = ((v, u),) * count
                else:
                    moves = tuple((v, w) for w in phi.orbit(u) for _ in range(count // k))
                for source, destination in moves:
                    _require(sets, source, destination)
                options.append(moves)
            out.append(Group((v,), tuple(options)))
            continue
        orbit = phi.orbit(v)
        seen.update(orbit)
        if split_orbit and not broken:  # the deliberate bug: each node on its own
            broken = True
            for w in orbit:
                out.append(Group((w,), tuple(((w, u),) * c.counts[w] for u in sorted(sets[w]))))
            continue
        options = []
        for u in sorted(sets[v]):
            moves = []
            for j, w in enumerate(orbit):
                destination = power(phi, j, u)
                _require(sets, w, destination)
                moves.extend([(w, destination)] * c.counts[w])
            options.append(tuple(moves))
        out.append(Group(orbit, tuple(options)))
    return out


def apply_moves(c: Configuration, moves: Iterable[Move]) -> Configuration:
    """The configuration after every robot moved (FSYNC: all at once)."""
    robots = tuple(sorted(destination for _, destination in moves))
    return Configuration.trusted(robots, c.meeting_nodes)


# -- one algorithm ----------------------------------------------------------------------


@dataclass
class Run:
    """What the adversary did against one algorithm."""

    algorithm: str
    explore: str
    rounds: int = 0
    states: int = 0
    repeated: bool = False
    complete: bool = True
    gathered: bool = False
    symmetry_kept: bool = True
    defect: str | None = None
    unhandled: int = 0
    trace: list[dict[str, Any]] | None = None

    @property
    def holds(self) -> bool:
        return not self.gathered and self.symmetry_kept

    def to_json(self) -> dict[str, Any]:
        out: dict[str, Any] = {
            "algorithm": self.algorithm, "explore": self.explore, "rounds": self.rounds,
            "states": self.states, "repeated": self.repeated, "complete": self.complete,
            "gathered": self.gathered, "symmetry_kept": self.symmetry_kept,
            "unhandled_views": self.unhandled, "holds": self.holds,
        }
        if self.defect:
            out["defect"] = self.defect
        if self.trace is not None:
            out["trace"] = self.trace
        return out


class _Game:
    """Successor function of the adversary against one algorithm (memoised per configuration)."""

    def __init__(self, phi: Automorphism, algorithm: Algorithm, detection: str,
                 frames: Sequence[int], split_orbit: bool) -> None:
        self.phi, self.algorithm, self.detection = phi, algorithm, detection
        self.frames, self.split_orbit = tuple(frames), split_orbit
        self.unhandled: set[tuple[Configuration, Node]] = set()

    def groups(self, c: Configuration) -> list[Group]:
        sets, unhandled = robot_move_sets(self.algorithm, c, self.detection, self.frames)
        self.unhandled.update((c, v) for v in unhandled)
        return groups(self.phi, c, sets, self.split_orbit)

    def successors(self, c: Configuration) -> Iterator[tuple[tuple[Move, ...], Configuration]]:
        for choice in itertools.product(*(g.options for g in self.groups(c))):
            moves = tuple(m for option in choice for m in option)
            yield moves, apply_moves(c, moves)

    def broken(self, c: Configuration) -> tuple[bool, str | None]:
        """(gathered, symmetry defect) after a round."""
        return c.is_gathered, symmetry_defect(self.phi, c)


def _trace(steps: list[tuple[Configuration, tuple[Move, ...] | None]]) -> list[dict[str, Any]]:
    out = []
    for t, (c, moves) in enumerate(steps):
        item: dict[str, Any] = {"round": t, "configuration": c.to_json()}
        if moves is not None:
            item["moves"] = [[list(s), list(d)] for s, d in sorted(moves)]
        out.append(item)
    return out


def _record_failure(run: Run, c: Configuration, gathered: bool, defect: str | None,
                    path: list[tuple[Configuration, tuple[Move, ...] | None]]) -> Run:
    run.gathered, run.symmetry_kept, run.defect = gathered, defect is None, defect
    run.complete = False  # stopped at the first run that broke the theorem
    if gathered and defect is None:
        run.defect = f"every robot gathered on {list(c.robots[0])}"
    run.trace = _trace(path)
    return run


def explore_all(game: _Game, start: Configuration, name: str, steps: int,
                max_states: int) -> Run:
    """Breadth-first over every equivariant choice, up to ``steps`` rounds."""
    run = Run(name, "all")
    parent: dict[Configuration, tuple[Configuration, tuple[Move, ...]] | None] = {start: None}
    frontier: deque[tuple[Configuration, int]] = deque([(start, 0)])

    def path_to(c: Configuration) -> list[tuple[Configuration, tuple[Move, ...] | None]]:
        out: list[tuple[Configuration, tuple[Move, ...] | None]] = []
        moves: tuple[Move, ...] | None = None
        node: Configuration | None = c
        while node is not None:
            out.append((node, moves))
            link = parent[node]
            node, moves = (None, None) if link is None else link
        out.reverse()  # each entry: a configuration and the moves leaving it
        return out

    while frontier:
        c, depth = frontier.popleft()
        if depth >= steps:
            run.complete = False
            continue
        run.rounds = max(run.rounds, depth + 1)  # a round is played from c
        for moves, d in game.successors(c):
            if d in parent:
                continue
            parent[d] = (c, moves)
            gathered, defect = game.broken(d)
            if gathered or defect:
                run.rounds = depth + 1
                run.states = len(parent)
                run.unhandled = len(game.unhandled)
                return _record_failure(run, d, gathered, defect, path_to(d))
            if len(parent) > max_states:
                run.complete = False
                frontier.clear()
                break
            frontier.append((d, depth + 1))
    run.states = len(parent)
    run.repeated = run.complete  # every run of the adversary loops in a finite set
    run.unhandled = len(game.unhandled)
    return run


def play_random(game: _Game, start: Configuration, name: str, steps: int,
                rng: random.Random) -> Run:
    """One run, choices from ``rng``, until ``steps`` rounds or a repeat."""
    run = Run(name, "random", complete=False)
    seen = {start}
    path: list[tuple[Configuration, tuple[Move, ...] | None]] = []
    c = start
    for t in range(1, steps + 1):
        options = [rng.choice(g.options) for g in game.groups(c)]
        moves = tuple(m for option in options for m in option)
        d = apply_moves(c, moves)
        path.append((c, moves))
        run.rounds = t
        gathered, defect = game.broken(d)
        if gathered or defect:
            run.states = len(seen) + 1
            run.unhandled = len(game.unhandled)
            return _record_failure(run, d, gathered, defect, [*path, (d, None)])
        if d in seen:
            run.repeated = True
            break
        seen.add(d)
        c = d
    run.states = len(seen)
    run.unhandled = len(game.unhandled)
    return run


# -- the check --------------------------------------------------------------------------


@dataclass
class ImpossibilityResult:
    """Outcome of the impossibility check on one initial configuration."""

    configuration: Configuration
    classification: Classification
    automorphism: Automorphism | None
    runs: list[Run] = field(default_factory=list)
    steps: int = 0

    @property
    def partitive(self) -> bool:
        return self.automorphism is not None

    @property
    def class_name(self) -> str:
        return self.classification.name

    @property
    def gathered(self) -> bool:
        return any(r.gathered for r in self.runs)

    @property
    def holds(self) -> bool:
        """Theorem 1 survived every run (vacuously false outside U)."""
        return self.partitive and all(r.holds for r in self.runs)

    @property
    def failures(self) -> list[Run]:
        return [r for r in self.runs if not r.holds]

    def v_prime(self) -> str:
        phi = self.automorphism
        if phi is None:
            return "-"
        if phi.kind == "reflection":
            return "L (axis nodes)" if phi.axis_through == "nodes" else "L (no node: axis through edges)"
        return "{c} (the centre node)" if phi.centre_kind == "node" else "{c} (no node: centre not a node)"

    def to_json(self) -> dict[str, Any]:
        phi = self.automorphism
        return {
            "configuration": self.configuration.to_json(),
            "class": self.class_name,
            "partitive": self.partitive,
            "automorphism": None if phi is None else {**phi.to_json(), "k": phi.order},
            "v_prime": self.v_prime(),
            "gathered": self.gathered,
            "holds": self.holds,
            "rounds": self.steps,
            "algorithms": [r.to_json() for r in self.runs],
        }


def check_impossibility(
    configuration: Configuration,
    algorithms: Sequence[Algorithm],
    *,
    steps: int = 20,
    explore: str = "all",
    max_states: int = 2000,
    seed: int = 0,
    detection: str = "local-weak",
    frames: Sequence[int] = geometry.ALL,
    split_orbit: bool = False,
    beyond_u: bool = False,
) -> ImpossibilityResult:
    """Play Theorem 1's adversary against each algorithm (see the module docstring).

    Outside U the result is not partitive, unless ``beyond_u`` asks for any
    automorphism of ``C`` that meets Theorem 1's hypothesis (:func:`theorem1_automorphism`).
    """
    if explore not in EXPLORE_MODES:
        raise InvalidInput(f"unknown exploration {explore!r}: use one of {', '.join(EXPLORE_MODES)}")
    if steps < 1:
        raise InvalidInput(f"steps must be at least 1, not {steps}")
    if configuration.has_multiplicity:
        raise InvalidInput("Theorem 1 is about initial configurations: robots on distinct nodes")
    classification = classify_configuration(configuration)
    phi = partitive_automorphism(classification)
    if phi is None and beyond_u:
        phi = theorem1_automorphism(configuration)
    result = ImpossibilityResult(configuration, classification, phi, steps=steps)
    if phi is None:
        return result
    defect = symmetry_defect(phi, configuration)
    if defect or any(in_v_prime(phi, r) for r in configuration.robots):
        raise AssertionError(f"{classification.name} configuration not partitive: {defect}")
    for i, algorithm in enumerate(algorithms):
        game = _Game(phi, algorithm, detection, frames, split_orbit)
        if explore == "all":
            run = explore_all(game, configuration, algorithm.name, steps, max_states)
        else:
            run = play_random(game, configuration, algorithm.name, steps,
                              random.Random(f"{seed}:{i}"))
        result.runs.append(run)
    return result
