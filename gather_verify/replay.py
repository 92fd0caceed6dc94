"""Replay: re-execute a trace from scratch and confirm its violation independently.

Uses only the algorithm, :mod:`moves` and the schedulers (never the
explorer): every event must be one the scheduler offers from the previous
state, every recorded state must be the one reached, and the property's
failure is re-established on the replayed states (a deadlock really has no
move; the target really changes; a cycle really returns and is fair; ...).

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

from gather_verify.algorithms import Unhandled, get_algorithm, target_of
from gather_verify.algorithms.moves import frames_for, move_sets
from gather_verify.errors import InvalidInput
from gather_verify.model.configuration import Configuration
from gather_verify.trace import initial_of, load_trace, steps_of
from schedulers import State, configuration_of, get_scheduler, initial_state


@dataclass
class Replayed:
    confirmed: bool
    message: str
    steps: int


def replay(trace: dict[str, Any]) -> Replayed:
    """Re-execute ``trace``; ValueError (one line) when it does not match its configuration."""
    trace = load_trace(trace)
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

    states = [initial_state(initial.robots)]
    steps = steps_of(trace)
    for k, (event, state) in enumerate(steps, 1):
        offered = dict(scheduler.successors(states[-1], ms))
        if event not in offered:
            raise InvalidInput(f"trace step {k}: event {event.to_json()} is not allowed from the "
                             "previous state")
        if offered[event] != state:
            raise InvalidInput(f"trace step {k}: the recorded state is not the one the event reaches")
        states.append(state)
    prop = trace["property"]
    last = states[-1]
    gathered = len(set(v for v, _ in last)) == 1 and last[0][0] in meeting
    if prop == "defined":
        try:
            ms(configuration_of(last))
        except Unhandled as error:
            return Replayed(True, f"the algorithm has no rule in the last state: {error}", len(steps))
        return Replayed(False, "the algorithm decides every robot in the last state", len(steps))
    if prop == "final":
        sets = ms(configuration_of(last))
        stuck = all(s == {v} for v, s in sets.items()) and all(p is None for _, p in last)
        ok = stuck and not gathered
        return Replayed(ok, "deadlock confirmed: nothing can move and the robots are not gathered"
                        if ok else "the last state is not a deadlock", len(steps))
    if prop == "no-ungatherable":
        from gather_verify.model.classes import classify_configuration
        first, end = classify_configuration(initial), classify_configuration(conf(last))
        ok = not first.in_U and end.in_U
        return Replayed(ok, f"{first.name} -> {end.name}", len(steps))
    if prop == "target-invariance":
        if len(states) < 2:
            return Replayed(False, "no transition", len(steps))
        before, after = target_of(algorithm, conf(states[-2])), target_of(algorithm, conf(last))
        ok = before is not None and after is not None and before != after
        return Replayed(ok, f"target {before} -> {after}", len(steps))
    total = sum(ev.distance for ev, _ in steps)
    cs = trace.get("cycle_start")
    if cs is not None:
        ok, why = _fair_cycle(states, steps, cs, ms)
        if prop == "move-bound":
            moves = sum(ev.distance for ev, _ in steps[cs:])
            ok = ok or (states[cs] == last and moves > 0)
            why = f"the cycle returns and makes {moves} moves per turn" if ok else why
        return Replayed(ok, why, len(steps))
    if prop == "move-bound":
        detail = trace.get("detail", {})
        c, D, n = detail.get("c"), detail.get("D"), detail.get("n")
        if not all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in (c, D, n)):
            raise InvalidInput("bad trace: a move-bound trace needs numbers c, D and n in 'detail'")
        ok = total > c * D * n
        return Replayed(ok, f"{total} moves vs bound {c}*{D}*{n} = {c * D * n:g}", len(steps))
    raise InvalidInput(f"bad trace: unknown property {prop!r}")


def _fair_cycle(states: list[State], steps: list, cs: int, ms: Any) -> tuple[bool, str]:
    """The cycle from state ``cs`` returns to it, changes something, and is fair: every robot
    has an event in it or is idle somewhere in it with staying in its move set; and it never
    passes a final gathered state."""
    if states[cs] != states[-1] or cs == len(states) - 1:
        return False, "the cycle does not return to its first state"
    n = len(states[0])
    active = set()
    for ev, _ in steps[cs:]:
        active |= set(ev.robots)
    for state in states[cs:]:
        sets = ms(configuration_of(state))
        active |= {i for i, (v, p) in enumerate(state) if p is None and v in sets[v]}
    if active != set(range(n)):
        return False, f"unfair: robots {sorted(set(range(n)) - active)} never act in the cycle"
    return True, f"fair cycle of {len(states) - 1 - cs} steps confirmed"
