"""Replay: re-execute a trace from scratch and confirm its violation independently.

One walk for every world (:func:`walk`): it uses only the algorithm and the schedulers
(never the explorer). At each step the robots that computed do what the event says (a
node one edge away, a colour of the lights: else the trace does not match itself, exit
2); the scheduler must offer that event from the state before and reach the recorded
state (under a scheduler that keeps its own state, from a start the trace allows: the
order it names, else any); and the algorithm must still choose that action (else the
trace no longer reproduces, exit 5). A world's trace format reads its states and events
and says how its failure is confirmed: on the paper's world (here, :func:`replay`) by the
property object itself (:meth:`~gather_verify.properties.Property.confirmed`: a state or
transition property re-evaluates its predicate on facts computed here from the
algorithm; a graph property checks its cycle or its move count); on a finite world by
its task's part (:mod:`gather_verify.world_replay`).

>>> from gather_verify.plane_check import run_check
>>> from gather_verify.model.configuration import Configuration
>>> r = run_check(Configuration([(0, 0), (2, 1)], [(1, 1)], initial=True), algorithm="go-to-target",
...               scheduler="fsync", max_states=1000, max_seconds=10, move_bound_c=0.1)
>>> replay(r["trace"]).confirmed
True
"""

from __future__ import annotations

import json
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any

from gather_verify.algorithms import AlgorithmCrash, Unhandled, get_algorithm
from gather_verify.algorithms.moves import frames_for, move_sets
from gather_verify.errors import InvalidInput
from gather_verify.model.configuration import Configuration
from gather_verify.model.geometry import STEPS, add
from gather_verify.model.view import Lights
from gather_verify.properties.base import Run
from gather_verify.properties.facts import configuration_facts, luminous_facts
from gather_verify.properties.registry import get_property
from gather_verify.trace import initial_of, load_trace, steps_of
from gather_verify.worlds.moves import parse_lights
from schedulers import Event, configuration_of, get_scheduler, initial_state
from schedulers.base import Action, LRobot


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


LRobots = tuple[LRobot, ...]
"""A state as the walk reads it, on every world: per robot its node, its pending
destination (None when idle) and its colour (0 without lights)."""


@dataclass
class Walk:
    """A trace's run, replayed: per state before a step, each robot's actions the algorithm
    gives there; and the scheduler's own state along every run the trace is consistent with
    (one start each; ``[None, ...]`` for a scheduler that keeps none)."""

    actions: list[Sequence[frozenset[Any]]] = field(default_factory=list)
    runs: list[list[object]] = field(default_factory=list)


@dataclass(frozen=True)
class Steps:
    """How a world's trace reads for the walk: where a robot may go in one edge, how many
    colours its lights have, how its nodes, actions and events are written, whether a round
    that changes nothing is an event (Z², §4), and what an unmatched event should add (the
    order a round-robin trace names)."""

    neighbours: Callable[[Any], Iterable[Any]]
    colours: int
    node_text: Callable[[Any], str]
    event_text: Callable[[Event], str]
    null: bool = False
    note: str = ""


def walk(scheduler: Any, states: Sequence[LRobots], events: Sequence[Event],
         actions: Callable[[Any], Sequence[frozenset[Any]]], steps: Steps) -> Walk:
    """Replay ``events`` from ``states[0]`` (see the module): InvalidInput (one line) when the
    trace does not match itself, :class:`NoLongerReproduces` when the algorithm no longer
    takes a step."""
    # the scheduler's own state (round-robin's order and turn): a trace names the start its
    # run began in (round-robin:order=1 0 2), then that start alone is followed; an older
    # trace without it is followed from every start, keeping those it is consistent with
    try:
        starts = getattr(scheduler, "starts", lambda _n: [None])(len(states[0]))
    except InvalidInput as error:
        raise InvalidInput(f"bad trace: its scheduler: {error}") from None
    done = Walk(runs=[[extra] for extra in starts])
    for k, (event, after) in enumerate(zip(events, states[1:], strict=True), 1):
        before = states[k - 1]
        unknown = [i for i in event.robots if not 0 <= i < len(before)]
        if unknown:
            raise InvalidInput(f"bad trace: step {k}: robot {unknown[0]!r} is not one of the "
                               f"trace's robots 0..{len(before) - 1}")
        chosen = chosen_by(event, before)
        for i, action in chosen.items():
            _legal(k, i, before[i][0], action, steps)
        done.runs = _follow(k, scheduler, before, done.runs, event, after, steps)
        try:
            offered = actions(before)
        except (AlgorithmCrash, Unhandled) as error:
            raise NoLongerReproduces(f"step {k}: the algorithm does not decide the state before "
                                     f"any more ({error})") from None
        done.actions.append(offered)
        for i, action in chosen.items():
            if action not in _as_read(event, i, before, offered, actions):
                raise NoLongerReproduces(f"step {k}: the algorithm no longer lets robot {i} "
                                         f"do {_action_text(action, steps)} "
                                         f"({steps.event_text(event)})")
    return done


def _as_read(event: Event, i: int, before: LRobots, offered: Sequence[frozenset[Any]],
             actions: Callable[[Any], Sequence[frozenset[Any]]]) -> frozenset[Any]:
    """Robot ``i``'s actions as its Look saw the others: ``offered[i]``, or under a phase
    scheduler's regular or safe read, the actions under the colours it read."""
    read = next((r for j, _, _, r in event.chosen if j == i), None)
    if read is None:
        return offered[i]
    others = iter(read)
    seen = tuple(r if j == i else (r[0], r[1], next(others)) for j, r in enumerate(before))
    if seen == before:
        return offered[i]
    try:
        return actions(seen)[i]
    except (AlgorithmCrash, Unhandled) as error:
        raise NoLongerReproduces(f"the algorithm does not decide what robot {i} read any "
                                 f"more ({error})") from None


def chosen_by(event: Event, before: LRobots) -> dict[int, Action]:
    """What each robot that computed in ``event`` chose, as the event says: its destination
    (its new node after a round, its pending one after a Look; its own node when it stays)
    and its colour (the new one when its light changed)."""
    if event.chosen:  # a phase scheduler's Look: what it chose, carried out later
        return {i: (d, c) for i, d, c, _ in event.chosen}
    if event.kind not in ("round", "look"):
        return {}
    dest = {i: b for i, _, b in event.moves}
    colour = {i: new for i, _, new in event.lights}
    return {i: (dest.get(i, before[i][0]), colour.get(i, before[i][2])) for i in event.robots}


def _legal(k: int, i: int, v: Any, action: Action, steps: Steps) -> None:
    """InvalidInput when robot ``i`` on ``v`` cannot take ``action``: a node past one edge,
    or a colour its lights do not have."""
    d, c = action
    if d != v and d not in steps.neighbours(v):
        raise InvalidInput(f"bad trace: step {k}: robot {i} cannot reach {steps.node_text(d)} "
                           f"from {steps.node_text(v)} in one edge")
    if isinstance(c, bool) or not isinstance(c, int) or not 0 <= c < steps.colours:
        raise InvalidInput(f"bad trace: step {k}: robot {i} cannot take colour {c!r}: the "
                           f"lights have {steps.colours} colour(s)")


def _follow(k: int, scheduler: Any, before: LRobots, runs: list[list[object]], event: Event,
            after: LRobots, steps: Steps) -> list[list[object]]:
    """The runs that go on through step ``k``: those from whose scheduler state ``event``
    is offered (each computing robot doing what the event says) and reaches ``after``."""
    offered = [([*run, nxt], succ) for run in runs
               for nxt, succ in offers(scheduler, before, run[-1], event, steps.null,
                                       steps.colours)]
    kept = [run for run, succ in offered if succ == after]
    if not kept:
        what = "does not reach the recorded state" if offered else \
            "is not allowed from the state before"
        raise InvalidInput(f"bad trace: step {k}: the event {steps.event_text(event)} {what}"
                           + steps.note)
    return kept


def offers(scheduler: Any, before: LRobots, extra: object, event: Event, null: bool = False,
           colours: int = 1) -> list[tuple[object, LRobots]]:
    """Each way the scheduler (in its own state ``extra``) offers ``event`` from ``before``
    when every computing robot does what the event says: its state after, and the
    successor (``colours``: K, what a phase scheduler's safe read ranges over)."""
    chosen = chosen_by(event, before)
    legal = {i: frozenset({chosen[i]}) if i in chosen else frozenset({(v, c)})
             for i, (v, _, c) in enumerate(before)}
    more = {"colours": colours} if getattr(scheduler, "phased", False) else {}
    return [(nxt, succ) for got, succ, nxt in scheduler.luminous(before, extra, legal.__getitem__,
                                                                 null=null, **more)
            if same_event(got, event)]


def same_event(a: Event, b: Event) -> bool:
    """One event: the same kind, robots, moves, colour changes and commands chosen."""
    return (a.kind, a.robots, sorted(a.moves), sorted(a.lights), sorted(a.chosen)) == \
        (b.kind, b.robots, sorted(b.moves), sorted(b.lights), sorted(b.chosen))


def scheduler_after(scheduler: Any, before: LRobots, extra: object, event: Event,
                    after: LRobots, null: bool = False) -> list[object]:
    """The scheduler's own state after ``event`` (a list of one), when it offers ``event``
    from ``before`` (its own state ``extra``) and the event reaches ``after``; else an empty
    list."""
    return [nxt for nxt, succ in offers(scheduler, before, extra, event, null)
            if succ == after][:1]


def _action_text(action: Action, steps: Steps) -> str:
    d, c = action
    return steps.node_text(d) + (f" with colour {c}" if c else "")


def _event_text(event: Event) -> str:
    return json.dumps(event.to_json())


def plane_steps(trace: dict[str, Any], colours: int) -> Steps:
    """How a trace of the paper's world reads for :func:`walk`: unit steps, its lights'
    colours, nodes written ``x,y``; a round in which every robot stays is an event (§4)."""
    return Steps(neighbours=lambda v: [add(v, step) for step in STEPS], colours=colours,
                 node_text=lambda v: f"{v[0]},{v[1]}", event_text=_event_text, null=True,
                 note=(f" (under {trace['scheduler']}, the order the trace names)"
                       if ":order=" in trace["scheduler"] else ""))


def replay(trace: dict[str, Any]) -> Replayed:
    """Re-execute a trace of the paper's world and confirm its violation (see the module):
    InvalidInput (one line) when it does not match its configuration."""
    trace = load_trace(trace)
    light = None
    if trace.get("lights") is not None:
        if not isinstance(trace["lights"], str):
            raise InvalidInput("bad trace: 'lights' must be a string, K or K:variant")
        light = parse_lights(trace["lights"])
    algorithm = get_algorithm(trace["algorithm"])
    scheduler = get_scheduler(trace["scheduler"])
    frames = frames_for(trace["frames"])
    detection = trace["detection"]
    initial = initial_of(trace)
    meeting = initial.meeting_nodes
    steps = steps_of(trace)

    def ms(robots: tuple) -> dict:
        return move_sets(algorithm, Configuration.trusted(robots, meeting), detection, frames)

    if light is None:
        lit: list[LRobots] = [tuple((v, p, 0) for v, p in state) for state in
                              [initial_state(initial.robots), *(s for _, s in steps)]]

        def facts(state: Any) -> Any:
            return configuration_facts(algorithm, Configuration.trusted(
                configuration_of(state), meeting), initial, detection, frames)

        def actions(robots: LRobots) -> list[frozenset[Action]]:
            options = ms(tuple(sorted(r[0] for r in robots)))
            return [frozenset((d, 0) for d in options[v]) for v, _, _ in robots]
    else:
        lit = [_lit_start(trace, initial, light), *(_lit_state(k, s) for k, (_, s) in
                                                      enumerate(steps, 1))]

        def facts(state: Any) -> Any:
            return luminous_facts(algorithm, tuple(sorted((r[0], r[2]) for r in state)),
                                  initial, detection, frames, light)

        def actions(robots: LRobots) -> list[frozenset[Action]]:
            f = facts(robots)
            if f.actions is None:
                raise Unhandled(f.unhandled or str(f.crash))
            return [f.actions[v, c] for v, _, c in robots]
    done = walk(scheduler, lit, [e for e, _ in steps], actions,
                plane_steps(trace, 1 if light is None else light.colours))
    try:
        prop = get_property(trace["property"])
    except InvalidInput as error:
        raise InvalidInput(f"bad trace: {error}") from None
    states: list[Any] = [lit[0] if light is not None else initial_state(initial.robots),
                         *(s for _, s in steps)]
    if getattr(scheduler, "stateful", False):
        from gather_verify.engine.explore import TurnState

        states = [TurnState(s, x) for s, x in zip(states, done.runs[0], strict=True)]
    if light is None:
        run = Run(trace, states, steps, facts, ms)
    else:
        run = Run(trace, states, steps, facts, _no_move_sets, _stays(facts))
    confirmed, message = prop.confirmed(run)
    return Replayed(confirmed, message, len(steps))


def _lit_start(trace: dict[str, Any], initial: Configuration, light: Lights) -> LRobots:
    """The initial state of a trace with lights: every robot idle with its initial colour."""
    colours = trace["initial"].get("colours", [0] * initial.n)
    if not isinstance(colours, list) or len(colours) != initial.n or any(
            isinstance(c, bool) or not isinstance(c, int) or not 0 <= c < light.colours
            for c in colours):
        raise InvalidInput(f"bad trace: 'initial.colours' must give each robot a colour in "
                           f"0..{light.colours - 1}")
    return tuple((v, None, c) for v, c in zip(initial.robots, colours, strict=True))


def _lit_state(k: int, state: Any) -> LRobots:
    if any(len(r) != 3 for r in state):
        raise InvalidInput(f"trace step {k}: a state of a trace with lights gives every "
                           "robot its 'colour'")
    return tuple(state)


def _stays(facts: Callable[[Any], Any]) -> Callable[[Any, int], bool]:
    """Whether robot i of a luminous state is idle and may stay, keeping its colour."""

    def stays(state: Any, i: int) -> bool:
        v, p, c = state[i]
        acts = facts(state).actions
        return p is None and acts is not None and (v, c) in acts[v, c]

    return stays


def _no_move_sets(robots: tuple) -> dict:
    raise InvalidInput("with lights a robot's move set depends on its colour: read "
                       "run.facts(state).actions, per (node, colour)")
