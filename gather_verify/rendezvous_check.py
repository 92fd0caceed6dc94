"""Check and replay on the rendezvous world: two robots with lights in the plane under
one of §13's synchrony models (SEMANTICS.md §13).

The world (:class:`~gather_verify.worlds.rendezvous.Rendezvous`) and the phase scheduler
(:mod:`schedulers.phases`) make the state space; the one reference search
(:func:`~gather_verify.engine.bfs.breadth_first`) walks it from every initial state at
once; the one check (:func:`gather_verify.pipeline.run`) runs it under the watchdog; the
task ``rendezvous`` is decided by the fairness test every finite world's liveness part
uses (:func:`~gather_verify.tasks.base.livelock`): VIOLATED exactly when a fair strongly
connected component (both robots step inside it) lies outside the goal (one point,
nothing pending). The goal is absorbing, so that is §13's "reach it and stay".

>>> r = run_rendezvous_check("vig-2cols", "ssync")
>>> r["verdict"], r["states"], r["initial_states"]
('VERIFIED', 12, 12)
>>> r = run_rendezvous_check("to-half", "centralized", movement="rigid")
>>> r["verdict"], r["trace"]["cycle_start"]
('VIOLATED', 0)
>>> replay_rendezvous(r["trace"]).confirmed
True
"""

from __future__ import annotations

import time
from typing import Any, cast

from gather_verify import pipeline
from gather_verify.engine.bfs import breadth_first
from gather_verify.engine.encoding import (
    DEFAULT_MAX_MEMORY_MB,
    DEFAULT_MAX_SECONDS,
    DEFAULT_MAX_STATES,
    Limits,
)
from gather_verify.engine.world_search import WorldSearch
from gather_verify.errors import InvalidInput
from gather_verify.progress import PROGRESS
from gather_verify.replay import NoLongerReproduces, Replayed
from gather_verify.tasks.base import Context, Finding, fair_walk, livelock
from gather_verify.verdict import combine
from gather_verify.worlds.rendezvous import (
    RENDEZVOUS,
    Rendezvous,
    State,
    show_state,
    state_from_json,
    state_to_json,
)
from gather_verify.worlds.rendezvous_rules import (
    INITIAL_COLOURS,
    MOVEMENTS,
    RendezvousAlgorithm,
    get_algorithm,
)
from schedulers import Event
from schedulers.phases import MODELS, PhaseModel, phase_events

TASK = "rendezvous"
WHAT = ("a fair run never gathers: both robots complete cycles for ever and never stand at "
        "one point with nothing pending")


def phase_model(name: str) -> PhaseModel:
    """The synchrony model ``name`` (§13's meaning; one line naming them for any other)."""
    if name not in MODELS:
        raise InvalidInput(f"unknown synchrony model {name!r} on the rendezvous world: use "
                           f"one of {', '.join(MODELS)}")
    return MODELS[name]


class RendezvousModel:
    """The rendezvous world as the one reference search reads it
    (:class:`~gather_verify.engine.bfs.Model`): the states themselves are the keys (no
    reduction: fairness needs both identities), per expanded state its out-edges
    ``(target, robots mask, event)`` and whether it is the goal."""

    def __init__(self, world: Rendezvous, model: PhaseModel, starts: list[State]):
        self.world, self.model, self.starts = world, model, starts
        self.edges: list[list[tuple[int, int, Event]]] = []
        self.goal: list[bool] = []
        self.out: list[tuple[int, int, Event]] = []

    def seeds(self) -> list[State]:
        return self.starts

    def key(self, state: State) -> State:
        return state

    def stored(self, state: State, key: State) -> State:
        return state

    def state(self, sid: int, stored: State) -> State:
        return stored

    def expand(self, sid: int, state: State) -> list[tuple[Event, State]]:
        self.out = []
        self.goal.append(self.world.goal(state))
        return list(phase_events(self.model, self.world, state))

    def inside(self, succ: State) -> bool:
        return True

    def transition(self, sid: int, event: Event, succ: State) -> None:
        pass

    def discovered(self, did: int, succ: State) -> None:
        pass

    def edge(self, sid: int, did: int, event: Event, succ: State, state: State) -> None:
        self.out.append((did, sum(1 << i for i in event.robots), event))

    def expanded(self, sid: int) -> str | None:
        self.edges.append(self.out)
        return None


def run_rendezvous_check(algorithm: str | RendezvousAlgorithm, scheduler: str, *,
                         movement: str = "non-rigid", initial_colours: str = "all",
                         max_states: int = DEFAULT_MAX_STATES,
                         max_seconds: float = DEFAULT_MAX_SECONDS,
                         max_memory_mb: float = DEFAULT_MAX_MEMORY_MB) -> dict[str, Any]:
    """Check ``rendezvous`` for ``algorithm`` under the synchrony model ``scheduler``, from
    every initial state of ``movement`` and ``initial_colours``: a JSON-ready report
    (``verdict``, ``reason``, ``states``, ``transitions``, ``initial_states``, ``trace``)."""
    checker = RendezvousCheck(algorithm, scheduler, movement, initial_colours,
                              Limits(max_states=max_states, max_seconds=max_seconds,
                                     max_memory_mb=max_memory_mb))
    return pipeline.run(checker, max_seconds)


class RendezvousCheck:
    """The rendezvous world's part of the one check (:class:`~gather_verify.pipeline.Checker`)."""

    def __init__(self, algorithm: str | RendezvousAlgorithm, scheduler: str, movement: str,
                 initial_colours: str, limits: Limits):
        self.started = time.perf_counter()
        self.algo = get_algorithm(algorithm) if isinstance(algorithm, str) else algorithm
        self.model = phase_model(scheduler)
        if movement not in MOVEMENTS or initial_colours not in INITIAL_COLOURS:
            raise InvalidInput(f"movement {movement!r}, initial colours {initial_colours!r}: "
                               f"use {' or '.join(MOVEMENTS)}, and {' or '.join(INITIAL_COLOURS)}")
        self.world = Rendezvous(self.algo)
        self.starts = self.world.starts(movement, initial_colours)
        self.request = {"world": RENDEZVOUS, "task": TASK, "algorithm": self.algo.name,
                        "scheduler": scheduler, "movement": movement,
                        "initial_colours": initial_colours, "lights": self.algo.lights,
                        "colours": self.algo.colours}
        self.limits = limits

    def search(self, watch: pipeline.Watch) -> WorldSearch:
        PROGRESS.doing = "exploring"
        model = RendezvousModel(self.world, self.model, self.starts)
        walked = breadth_first(model, self.limits)
        n = len(model.edges)
        s = WorldSearch(keys=walked.stored, parents=walked.parents.tolist(), edges=model.edges,
                        final=model.goal[:n], stay=[0] * len(walked.stored),
                        states=len(walked.stored), transitions=walked.transitions,
                        stopped=walked.stopped, halt=None, reduced=False,
                        seconds=walked.seconds, canonical=lambda state: state)
        watch.searched.append(s)
        return s

    def decide(self, s: WorldSearch) -> dict[str, Any]:
        ctx = Context(2, 0, frozenset(), str(self.request["scheduler"]), ())
        found = livelock(s, ctx, TASK, WHAT, inside=lambda v: not s.final[v],
                         single_states=True)
        verdict = combine([TASK] if found else [], None if s.complete else str(s.stopped))
        return {**self.request, "verdict": verdict, "property": TASK if found else None,
                "reason": WHAT if found else None if s.complete else str(s.stopped),
                "stopped": s.stopped, "states": s.states, "transitions": s.transitions,
                "initial_states": len(self.starts), "engine": "reference",
                "trace": None if found is None else self.trace(s, found),
                "seconds": time.perf_counter() - self.started, "search_seconds": s.seconds}

    def trace(self, s: WorldSearch, found: Finding) -> dict[str, Any]:
        """The counterexample: a shortest prefix from an initial state to the fair component,
        then a closed walk in it in which both robots step (:func:`fair_walk`)."""
        ids = s.path_to(found.state)
        hops = [(a, next(k for k, (t, _, _) in enumerate(s.edges[a]) if t == b))
                for a, b in zip(ids, ids[1:], strict=False)]
        assert found.component is not None
        hops += fair_walk(s, found.component, 2, found.state)
        keys = cast(list[State], s.keys)  # the rendezvous world's states, not robots on nodes
        steps = [{"event": None, "state": state_to_json(keys[ids[0]])}]
        for a, k in hops:
            target, _, event = s.edges[a][k]
            steps.append({"event": event.to_json(), "state": state_to_json(keys[target])})
        return {**self.request, "property": TASK, "reason": WHAT, "steps": steps,
                "cycle_start": len(ids) - 1}

    def overtime(self, seconds: float, watch: pipeline.Watch) -> dict[str, Any]:
        return {**self.request, "verdict": "INCOMPLETE", "property": None,
                "reason": pipeline.overtime_reason(seconds), "stopped": "time",
                "states": PROGRESS.states, "transitions": 0,
                "initial_states": len(self.starts), "engine": "reference", "trace": None,
                "seconds": time.perf_counter() - self.started}


def replay_rendezvous(trace: dict[str, Any]) -> Replayed:
    """Re-execute a rendezvous trace: every step must be an event the synchrony model offers
    from the state before (the algorithm evaluated again at each Look) reaching the recorded
    state; then the run from ``cycle_start`` must come back to where it began, both robots
    stepping and no state gathered (a fair run that never gathers). InvalidInput (exit 2)
    when the trace does not match itself; :class:`NoLongerReproduces` (exit 5) when a
    Look's command is no longer the algorithm's."""
    try:
        algo = get_algorithm(trace["algorithm"])
        model = phase_model(trace["scheduler"])
        steps, cycle = trace["steps"], trace["cycle_start"]
        assert isinstance(steps, list) and steps and all(isinstance(x, dict) for x in steps)
        assert type(cycle) is int and 0 <= cycle < len(steps)
    except (KeyError, TypeError, AssertionError):
        raise InvalidInput("bad trace: a rendezvous trace has algorithm, scheduler, steps "
                           "and cycle_start") from None
    world = Rendezvous(algo)
    states = [state_from_json(step.get("state"), algo.colours, f"step {k}")
              for k, step in enumerate(steps)]
    if states[0] not in world.starts(trace.get("movement", "non-rigid"),
                                     trace.get("initial_colours", "all")):
        raise InvalidInput(f"bad trace: it starts in {show_state(states[0])}, no initial state "
                           "of its movement and initial colours")
    robots = 0
    for k in range(1, len(steps)):
        event = _follow(k, model, world, states[k - 1], steps[k].get("event"), states[k])
        if k > cycle:
            robots |= sum(1 << i for i in event.robots)
    loop = states[cycle:]
    if len(loop) < 2 or loop[0] != loop[-1]:
        return Replayed(False, "the run from cycle_start does not come back to its start",
                        len(steps) - 1)
    if robots != 3:
        return Replayed(False, "a robot never steps in the cycle: the run is not fair",
                        len(steps) - 1)
    if any(world.goal(state) for state in loop):
        return Replayed(False, "the cycle passes through a gathered state", len(steps) - 1)
    return Replayed(True, f"a fair cycle of {len(loop) - 1} events never gathers",
                    len(steps) - 1)


def _follow(k: int, model: PhaseModel, world: Rendezvous, before: State, raw: object,
            after: State) -> Event:
    """The event of step ``k`` as the model offers it from ``before`` to ``after``."""
    offered = list(phase_events(model, world, before))
    for event, succ in offered:
        if event.to_json() == raw and succ == after:
            return event
    if isinstance(raw, dict) and any(
            (e.kind, list(e.robots)) == (raw.get("kind"), raw.get("robots")) and
            [list(c[3]) for c in e.chosen] == [c[3] for c in raw.get("chosen", [])]
            for e, _ in offered if e.chosen):
        raise NoLongerReproduces(f"step {k}: the algorithm no longer answers what the Look "
                                 f"of the trace chose ({raw.get('chosen')})")
    raise InvalidInput(f"bad trace: step {k}: the event {raw} is not offered from "
                       f"{show_state(before)} or does not reach {show_state(after)}")


def render_rendezvous_trace(trace: dict[str, Any]) -> str:
    """The trace as text, one line per step (``*`` where the cycle starts)."""
    colours = get_algorithm(trace["algorithm"]).colours
    lines = [f"{trace['property']}: {trace['reason']}"]
    for k, step in enumerate(trace["steps"]):
        event = step["event"]
        what = "start" if event is None else (
            "+".join("AB"[i] for i in event["robots"]) + ": " + event["kind"])
        mark = "*" if trace.get("cycle_start") == k else " "
        state = state_from_json(step["state"], colours, f"step {k}")
        lines.append(f"{mark}{k:3d}  {what:44}  {show_state(state)}")
    lines.append(f"  (from * the run can repeat the cycle forever: steps "
                 f"{trace['cycle_start']}..{len(trace['steps']) - 1})")
    return "\n".join(lines)
