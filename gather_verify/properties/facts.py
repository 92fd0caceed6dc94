"""The facts a property reads: per configuration of a search, and per state.

A property is written once over these facts; the reference engine hands it a
:class:`ConfigurationFacts` (computed here), the bulk engine an object with the
same attributes read from its facts table, and ``replay`` the facts it computes
itself from the algorithm (never from the explorer). SEMANTICS.md §5.

>>> from gather_verify.algorithms import get_algorithm
>>> from gather_verify.model.configuration import Configuration
>>> c = Configuration([(0, 0), (3, 1)], [(2, 2)], initial=True)
>>> f = configuration_facts(get_algorithm("go-to-target"), c, c, "local-weak", (0,))
>>> f.stuck, f.gathered, f.in_U, f.target
(False, False, False, (2, 2))
>>> StateFacts(f, idle=True).target  # a state sees its configuration's facts
(2, 2)
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Protocol

from gather_verify.algorithms.base import Algorithm, AlgorithmCrash, Unhandled, target_of
from gather_verify.algorithms.moves import Action, LitRobots, luminous_table, move_sets
from gather_verify.model.configuration import Configuration
from gather_verify.model.geometry import Node
from gather_verify.model.view import Lights
from gather_verify.theory import get_fact


class Facts(Protocol):
    """What a property may read about one configuration reached by a search."""

    @property
    def configuration(self) -> Configuration: ...  # robots (sorted, with multiplicities), M
    @property
    def initial(self) -> Configuration: ...  # the search's initial configuration
    @property
    def move_sets(self) -> Mapping[Node, frozenset[Node]] | None: ...  # None: no rule
    @property
    def unhandled(self) -> str | None: ...  # why the algorithm has no rule (None: it has)
    @property
    def stuck(self) -> bool: ...  # every robot's move set is {its node}
    @property
    def gathered(self) -> bool: ...  # every robot on one meeting node
    @property
    def in_U(self) -> bool: ...  # SEMANTICS.md §2: the paper's fact (gather_verify.theory)
    @property
    def target(self) -> Node | None: ...  # the algorithm's target meeting node, if it has one
    @property
    def crash(self) -> AlgorithmCrash | None: ...  # decide or target raised (None: neither did)


@dataclass
class ConfigurationFacts:
    """:class:`Facts`, computed eagerly (the reference engine caches one per configuration)."""

    configuration: Configuration
    initial: Configuration
    move_sets: dict[Node, frozenset[Node]] | None
    unhandled: str | None
    stuck: bool
    gathered: bool
    in_U: bool
    target: Node | None
    crash: AlgorithmCrash | None = None
    actions: dict[tuple[Node, int], frozenset[Action]] | None = None
    """With lights (§10): per (node, colour), the actions (destination, colour) of the
    robots there; ``move_sets`` is then their destinations, per node."""


def configuration_facts(algorithm: Algorithm, configuration: Configuration,
                        initial: Configuration, detection: str,
                        frames: Sequence[int]) -> ConfigurationFacts:
    """The facts of ``configuration`` under ``algorithm`` (the definition every engine follows).

    An exception of the algorithm's own (:class:`AlgorithmCrash`, in ``decide`` or
    ``target``) is recorded in ``crash`` (the first one: ``decide``'s) and leaves no move
    sets: the search cannot go on from there."""
    crash = None
    try:
        ms: dict[Node, frozenset[Node]] | None = move_sets(algorithm, configuration, detection,
                                                           frames)
        unhandled = None
    except Unhandled as error:
        ms, unhandled = None, str(error) or "no rule for this view"
    except AlgorithmCrash as error:
        ms, unhandled, crash = None, None, error
    try:
        target = target_of(algorithm, configuration)
    except Unhandled:
        target = None
    except AlgorithmCrash as error:
        target, crash, ms = None, crash or error, None
    robots = configuration.robots
    stuck = ms is not None and all(s == {v} for v, s in ms.items())
    gathered = len(configuration.counts) == 1 and robots[0] in configuration.meeting_nodes
    return ConfigurationFacts(configuration, initial, ms, unhandled, stuck, gathered,
                              get_fact("in_U").of(configuration), target, crash)


def luminous_facts(algorithm: Algorithm, robots: LitRobots, initial: Configuration,
                   detection: str, frames: Sequence[int], lights: Lights) -> ConfigurationFacts:
    """:func:`configuration_facts` of a luminous configuration (its robots' sorted (node,
    colour) pairs): the same facts, read from the robots' actions. A robot is stuck when its
    one action is to stay and keep its colour (a colour change is an event, §10)."""
    configuration = Configuration.trusted(tuple(v for v, _ in robots), initial.meeting_nodes)
    crash = None
    actions: dict[tuple[Node, int], frozenset[Action]] | None = None
    unhandled = None
    try:
        actions = luminous_table(algorithm, robots, initial.meeting_nodes, detection, frames,
                                 lights)
    except Unhandled as error:
        unhandled = str(error) or "no rule for this view"
    except AlgorithmCrash as error:
        crash = error
    try:
        target = target_of(algorithm, configuration)
    except Unhandled:
        target = None
    except AlgorithmCrash as error:
        target, crash, actions = None, crash or error, None
    ms: dict[Node, frozenset[Node]] | None = None
    if actions is not None:
        ms = {}
        for (v, _), acts in actions.items():
            ms[v] = ms.get(v, frozenset()) | frozenset(d for d, _ in acts)
    stuck = actions is not None and all(a == {(v, c)} for (v, c), a in actions.items())
    gathered = len(configuration.counts) == 1 and \
        configuration.robots[0] in configuration.meeting_nodes
    return ConfigurationFacts(configuration, initial, ms, unhandled, stuck, gathered,
                              get_fact("in_U").of(configuration), target, crash,
                              actions)


class StateFacts:
    """The facts of a state: those of its configuration, and ``idle`` (no robot has a pending
    move). What a state property's predicate reads; attributes are looked up lazily, so an
    engine computes only the facts a predicate asks for."""

    __slots__ = ("facts", "idle")

    def __init__(self, facts: Facts, idle: bool):
        self.facts = facts
        self.idle = idle

    def __getattr__(self, name: str) -> Any:
        return getattr(self.facts, name)

    def __repr__(self) -> str:
        return f"StateFacts({self.facts!r}, idle={self.idle})"
