"""One execution under a random fair adversary: the simulator.

SEMANTICS.md §4. The adversary is a seeded ``random.Random``: at every step it
picks one successor among those the scheduler offers
(``successors(state, move_sets)``), so every run is an execution the explorer
also sees. Fairness is bounded waiting: a robot that has had no event for
``2 n`` steps is *overdue*, and the next step must serve it (SSYNC: activate it;
ASYNC: do its pending move, or its Look; a Look that can only end in staying
offers no transition, and counts as a null activation). FSYNC activates
everybody anyway.

The run stops when the state is final (no pending move and every robot's move
set is ``{stay}``): ``gathered`` if every robot is on one meeting node, else
``deadlock``; when the algorithm raises :class:`Unhandled` (``unhandled``);
or after ``max_steps`` steps (``max-steps``).

>>> from gather_verify.algorithms import get_algorithm
>>> from gather_verify.model.configuration import Configuration
>>> c = Configuration([(0, 0), (3, 1), (1, 4)], [(2, 2)], initial=True)
>>> run = simulate(c, get_algorithm("go-to-target"), "async", seed=1)
>>> run.outcome, run.meeting_node, run.moves
('gathered', (2, 2), 9)
"""

from __future__ import annotations

import random
from dataclasses import dataclass, field
from typing import Any

from gather_verify.algorithms.base import Algorithm, Unhandled
from gather_verify.algorithms.moves import frames_for, move_sets
from gather_verify.model.configuration import Configuration
from gather_verify.model.geometry import Node
from gather_verify.model.view import check_detection
from schedulers import Event, State, get_scheduler, initial_state
from schedulers.base import configuration_of, oblivious_events

OUTCOMES = ("gathered", "deadlock", "unhandled", "max-steps")


@dataclass
class Run:
    """The record of one execution."""

    outcome: str
    initial: Configuration
    states: list[State] = field(default_factory=list)
    events: list[Event] = field(default_factory=list)
    message: str = ""

    @property
    def final(self) -> Configuration:
        return Configuration.trusted(configuration_of(self.states[-1]), self.initial.meeting_nodes)

    @property
    def gathered(self) -> bool:
        return self.outcome == "gathered"

    @property
    def meeting_node(self) -> Node | None:
        return self.final.robots[0] if self.gathered else None

    @property
    def moves(self) -> int:
        """Edges traversed in total (the paper's number of moves)."""
        return sum(e.distance for e in self.events)

    @property
    def steps(self) -> int:
        return len(self.events)

    def to_json(self) -> dict[str, Any]:
        m = self.meeting_node
        return {
            "outcome": self.outcome,
            "gathered": self.gathered,
            "meeting_node": None if m is None else list(m),
            "moves": self.moves,
            "steps": self.steps,
            "message": self.message,
            "initial": self.initial.to_json(),
            "final": self.final.to_json(),
            "events": [e.to_json() for e in self.events],
        }


def simulate(
    configuration: Configuration,
    algorithm: Algorithm,
    scheduler: str = "async",
    *,
    detection: str = "local-weak",
    frames: str = "all",
    seed: int = 0,
    max_steps: int = 10_000,
) -> Run:
    """Run one execution from ``configuration`` under a seeded random fair adversary."""
    check_detection(detection)
    frame_set = frames_for(frames)
    sched = get_scheduler(scheduler)
    rng = random.Random(seed)
    meeting = configuration.meeting_nodes
    cache: dict[tuple[Node, ...], dict[Node, frozenset[Node]]] = {}

    def sets(robots: tuple[Node, ...]) -> dict[Node, frozenset[Node]]:
        if robots not in cache:
            cache[robots] = move_sets(algorithm, Configuration.trusted(robots, meeting),
                                      detection, frame_set)
        return cache[robots]

    state = initial_state(configuration.robots)
    run = Run("max-steps", configuration, [state])
    n = len(state)
    patience = 2 * n
    since = [0] * n
    # a scheduler with a state of its own (round-robin's order and turn) starts in one of its
    # starts, drawn as the adversary's other choices are
    extra = rng.choice(sched.starts(n)) if getattr(sched, "stateful", False) else None  # type: ignore[attr-defined]
    try:
        for _ in range(max_steps + 1):
            options = sets(configuration_of(state))
            if all(p is None for _, p in state) and all(
                    options[v] == frozenset({v}) for v, _ in state):
                final = Configuration.trusted(configuration_of(state), meeting)
                run.outcome = "gathered" if final.is_gathered else "deadlock"
                return run
            if run.steps == max_steps:
                return run
            successors: list[tuple[Event, State, object]]
            if extra is None:
                successors = [(e, s, None) for e, s in sched.successors(state, sets)]
            else:
                successors = list(oblivious_events(sched, state, extra, sets))
            overdue = sorted((i for i in range(n) if since[i] >= patience),
                             key=lambda i: -since[i])
            for i in overdue:
                serving = [s for s in successors if i in s[0].robots]
                if serving:
                    successors = serving
                    break
                since[i] = 0  # a null activation: the robot looks and stays
            event, state, extra = rng.choice(successors)
            for i in range(n):
                since[i] = 0 if i in event.robots else since[i] + 1
            run.events.append(event)
            run.states.append(state)
    except Unhandled as error:
        run.outcome, run.message = "unhandled", str(error)
    return run
