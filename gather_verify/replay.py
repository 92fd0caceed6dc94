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
from gather_verify.properties.facts import configuration_facts, luminous_facts
from gather_verify.properties.registry import get_property
from gather_verify.trace import initial_of, load_trace, steps_of
from gather_verify.worlds.moves import parse_lights
from schedulers import State, configuration_of, get_scheduler, initial_state
from schedulers.base import oblivious_events


class _Turns:
    """A ``stateful`` scheduler's own state along a replay (round-robin's order and turn; a
    trace from a search names the order it started in, ``round-robin:order=2 0 1``): every
    start it may have had, kept while the trace is consistent with it, as on finite worlds
    (:mod:`gather_verify.world_replay`). The replayed states carry it
    (:class:`~gather_verify.engine.explore.TurnState`), so a cycle must return to its turn."""

    def __init__(self, scheduler: Any, n: int):
        self.runs: list[list[object]] = [[x] for x in scheduler.starts(n)]

    def follow(self, k: int, event: Any, state: Any, events: Any) -> None:
        """Keep the runs in which ``events(extra)`` (event, successor, extra after) offers
        ``event`` reaching ``state``; InvalidInput (one line) when none does."""
        kept = [[*run, after] for run in self.runs for ev, succ, after in events(run[-1])
                if ev == event and succ == state]
        if not kept:
            raise InvalidInput(f"trace step {k}: event {event.to_json()} is not allowed from the "
                               "previous state, or does not reach the recorded state")
        self.runs = kept

    def offered(self, k: int, events: Any) -> set[Any]:
        """The events the algorithm offers at step ``k`` in the runs kept so far."""
        return {ev for run in self.runs for ev, _, _ in events(run[k - 1])}

    def states(self, states: list[Any]) -> list[Any]:
        """The replayed states with the first kept run's scheduler state."""
        from gather_verify.engine.explore import TurnState

        return [TurnState(s, x) for s, x in zip(states, self.runs[0], strict=True)]


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
        return _replay_lights(trace)
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
    turns = _Turns(scheduler, initial.n) if getattr(scheduler, "stateful", False) else None
    for k, (event, state) in enumerate(steps, 1):
        if turns is not None:
            before = states[-1]
            turns.follow(k, event, state,
                         lambda x: oblivious_events(scheduler, before, x, anything))  # noqa: B023
            try:
                offers = turns.offered(k, lambda x: oblivious_events(scheduler, before, x, ms))  # noqa: B023
            except (Unhandled, AlgorithmCrash) as error:
                raise NoLongerReproduces(f"trace step {k}: the algorithm does not decide the "
                                         f"previous state any more ({error})") from None
            if event not in offers:
                raise NoLongerReproduces(f"trace step {k}: the algorithm no longer allows event "
                                         f"{event.to_json()}")
            states.append(state)
            continue
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
    if turns is not None:
        states = turns.states(states)
    run = Run(trace, states, steps,
              lambda state: configuration_facts(algorithm, conf(state), initial, detection, frames),
              ms)
    confirmed, message = prop.confirmed(run)
    return Replayed(confirmed, message, len(steps))


def _replay_lights(trace: dict[str, Any]) -> Replayed:
    """:func:`replay` of a trace with lights (SEMANTICS.md §10): the states carry colours, the
    events the lights they changed, and the algorithm answers (move, colour)."""
    if not isinstance(trace["lights"], str):
        raise InvalidInput("bad trace: 'lights' must be a string, K or K:variant")
    light = parse_lights(trace["lights"])
    algorithm = get_algorithm(trace["algorithm"])
    scheduler = get_scheduler(trace["scheduler"])
    frames = frames_for(trace["frames"])
    detection = trace["detection"]
    initial = initial_of(trace)
    colours = trace["initial"].get("colours", [0] * initial.n)
    if not isinstance(colours, list) or len(colours) != initial.n or any(
            isinstance(c, bool) or not isinstance(c, int) or not 0 <= c < light.colours
            for c in colours):
        raise InvalidInput(f"bad trace: 'initial.colours' must give each robot a colour in "
                           f"0..{light.colours - 1}")

    def lit(state: Any) -> Any:
        return tuple(sorted((r[0], r[2]) for r in state))

    def facts(state: Any) -> Any:
        return luminous_facts(algorithm, lit(state), initial, detection, frames, light)

    def anything(state: Any) -> Any:  # stay or take any unit step, with any colour
        return lambda i: frozenset((d, c) for d in (state[i][0], *(add(state[i][0], s)
                                                                    for s in STEPS))
                                   for c in range(light.colours))

    def offered(state: Any) -> Any:
        f = facts(state)
        if f.actions is None:
            return None, f.unhandled or str(f.crash)
        acts = f.actions
        return (lambda i: acts[state[i][0], state[i][2]]), None

    def natural(action: Any) -> Any:
        return action

    states: list[Any] = [tuple((v, None, c) for v, c in zip(initial.robots, colours,
                                                                strict=True))]
    steps = steps_of(trace)
    turns = _Turns(scheduler, initial.n) if getattr(scheduler, "stateful", False) else None
    for k, (event, state) in enumerate(steps, 1):
        if any(len(r) != 3 for r in state):
            raise InvalidInput(f"trace step {k}: a state of a trace with lights gives every "
                               "robot its 'colour'")
        if turns is not None:
            before = states[-1]
            turns.follow(k, event, state, lambda x: scheduler.luminous(  # noqa: B023
                before, x, anything(before), order=natural, null=True))  # noqa: B023
            actions, why = offered(before)
            if actions is None:
                raise NoLongerReproduces(f"trace step {k}: the algorithm does not decide the "
                                         f"previous state any more ({why})")
            if event not in turns.offered(k, lambda x: scheduler.luminous(  # noqa: B023
                    before, x, actions, order=natural, null=True)):  # noqa: B023
                raise NoLongerReproduces(f"trace step {k}: the algorithm no longer allows event "
                                         f"{event.to_json()}")
            states.append(state)
            continue
        possible = {ev: succ for ev, succ, _ in scheduler.luminous(
            states[-1], None, anything(states[-1]), order=natural, null=True)}
        if event not in possible:
            raise InvalidInput(f"trace step {k}: event {event.to_json()} is not allowed from the "
                               "previous state")
        if possible[event] != state:
            raise InvalidInput(f"trace step {k}: the recorded state is not the one the event reaches")
        actions, why = offered(states[-1])
        if actions is None:
            raise NoLongerReproduces(f"trace step {k}: the algorithm does not decide the previous "
                                     f"state any more ({why})")
        if event not in {ev for ev, _, _ in scheduler.luminous(states[-1], None, actions,
                                                               order=natural, null=True)}:
            raise NoLongerReproduces(f"trace step {k}: the algorithm no longer allows event "
                                     f"{event.to_json()}")
        states.append(state)
    try:
        prop = get_property(trace["property"])
    except InvalidInput as error:
        raise InvalidInput(f"bad trace: {error}") from None

    def stays(state: Any, i: int) -> bool:
        v, p, c = state[i]
        acts = facts(state).actions
        return p is None and acts is not None and (v, c) in acts[v, c]

    def no_move_sets(robots: tuple) -> dict:
        raise InvalidInput("with lights a robot's move set depends on its colour: read "
                           "run.facts(state).actions, per (node, colour)")

    if turns is not None:
        states = turns.states(states)
    run = Run(trace, states, steps, facts, no_move_sets, stays)
    confirmed, message = prop.confirmed(run)
    return Replayed(confirmed, message, len(steps))
