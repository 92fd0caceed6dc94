"""Replay: re-execute a trace from scratch and confirm its violation independently.

Uses only the algorithm, :mod:`~gather_verify.algorithms.moves` and the schedulers (never the
explorer): every event must be one the scheduler offers from the previous
state, every recorded state must be the one reached, and the property's
failure is re-established on the replayed states by the property object itself
(:meth:`~gather_verify.properties.Property.confirmed`: a state or transition property
re-evaluates its predicate on facts computed here from the algorithm; a graph property
checks its cycle or its move count).

>>> from gather_verify.check import run_check
>>> from gather_verify.model.configuration import Configuration
>>> r = run_check(Configuration([(0, 0), (2, 1)], [(1, 1)], initial=True), algorithm="go-to-target",
...               scheduler="fsync", max_states=1000, max_seconds=10, move_bound_c=0.1)
>>> replay(r["trace"]).confirmed
True
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from gather_verify.algorithms import AlgorithmCrash, Unhandled, get_algorithm
from gather_verify.algorithms.moves import frames_for, move_sets
from gather_verify.errors import InvalidInput
from gather_verify.model.configuration import Configuration
from gather_verify.model.geometry import STEPS, add
from gather_verify.properties.base import Run
from gather_verify.properties.facts import configuration_facts
from gather_verify.properties.registry import get_property
from gather_verify.trace import initial_of, load_trace, steps_of
from schedulers import State, configuration_of, get_scheduler, initial_state


class NoLongerReproduces(InvalidInput):
    """The trace no longer reproduces: ``replay`` exits 5.

    Cause: the algorithm, scheduler or property changed since the trace was written. Either
    every step is a legal execution of the robots but the algorithm no longer takes one of
    them, or the trace is still taken but its property no longer fails at its end (the
    message says which). Fix: run ``check`` again for a fresh trace; if the change was not
    meant, the trace points at what it altered."""


@dataclass
class Replayed:
    confirmed: bool
    message: str
    steps: int


def replay(trace: dict[str, Any]) -> Replayed:
    """Re-execute ``trace``; ValueError (one line) when it does not match its configuration."""
    trace = load_trace(trace)
    if trace.get("lights") is not None:
        raise InvalidInput(f"a trace with lights ({trace['lights']}) is not replayed: run "
                           "check again to see it")
    algorithm = get_algorithm(trace["algorithm"])
    scheduler = get_scheduler(trace["scheduler"])
    frames = frames_for(trace["frames"])
    detection = trace["detection"]
    initial = initial_of(trace)
    meeting = initial.meeting_nodes

    def conf(state: State) -> Configuration:
        return Configuration.trusted(configuration_of(state), meeting)

    def ms(robots: tuple) -> dict:
        return move_sets(algorithm, Configuration.trusted(robots, meeting), detection, frames)

    def anything(robots: tuple) -> dict:  # every robot may stay or take any unit step
        return {v: frozenset([v, *(add(v, step) for step in STEPS)]) for v in robots}

    states = [initial_state(initial.robots)]
    steps = steps_of(trace)
    for k, (event, state) in enumerate(steps, 1):
        possible = dict(scheduler.successors(states[-1], anything))
        if event not in possible:
            raise InvalidInput(f"trace step {k}: event {event.to_json()} is not allowed from the "
                             "previous state")
        if possible[event] != state:
            raise InvalidInput(f"trace step {k}: the recorded state is not the one the event reaches")
        try:
            offered = dict(scheduler.successors(states[-1], ms))
        except (Unhandled, AlgorithmCrash) as error:
            raise NoLongerReproduces(f"trace step {k}: the algorithm does not decide the previous "
                                     f"state any more ({error})") from None
        if event not in offered:  # a legal execution, but not this algorithm's (any more)
            raise NoLongerReproduces(f"trace step {k}: the algorithm no longer allows event "
                                     f"{event.to_json()}")
        states.append(state)
    try:
        prop = get_property(trace["property"])
    except InvalidInput as error:
        raise InvalidInput(f"bad trace: {error}") from None
    run = Run(trace, states, steps,
              lambda state: configuration_facts(algorithm, conf(state), initial, detection, frames),
              ms)
    confirmed, message = prop.confirmed(run)
    return Replayed(confirmed, message, len(steps))
