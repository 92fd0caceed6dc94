"""The properties of SEMANTICS.md §5, each written once, in verdict order.

>>> [p.name for p in BUILTIN]
['crash', 'defined', 'final', 'no-ungatherable', 'target-invariance', 'move-bound', 'termination']
"""

from __future__ import annotations

from typing import Any

from gather_verify import theory
from gather_verify.errors import InvalidInput
from gather_verify.properties.base import Outcome, Property, Run, Witness, fails_at_end
from gather_verify.properties.facts import StateFacts
from gather_verify.properties.graph import GraphFacts, livelock, moving_cycle

# -- safety: state and transition properties, checked during the search ------------------


def _confirm_crash(prop: Property, run: Run) -> tuple[bool, str]:
    s = run.state_facts()
    if s.crash is not None:
        return True, str(s.crash)
    return False, "the algorithm no longer crashes in the last state"


CRASH = Property(
    "crash", "state",
    holds=lambda s: s.crash is None,
    message=lambda s: s.crash.reason,
    detail=lambda s: s.crash.detail(),
    confirm=_confirm_crash, pseudo=True, halts=True,
    symmetric=True,
    doc="the algorithm's decide and target raise no exception (nor decide answers something "
        "that is not a move) in any reached configuration (the search cannot go on where one "
        "does)")


def _confirm_defined(prop: Property, run: Run) -> tuple[bool, str]:
    ok, (s,) = fails_at_end(prop, run)
    if ok:
        return True, f"the algorithm has no rule in the last state: {s.unhandled}"
    return False, "the algorithm decides every robot in the last state"


DEFINED = Property(
    "defined", "state",
    holds=lambda s: s.unhandled is None,
    message=lambda s: f"the algorithm has no rule here: {s.unhandled}",
    confirm=_confirm_defined, pseudo=True, halts=True,
    symmetric=True,
    doc="the algorithm has a rule for every robot of every reached configuration (the search "
        "cannot go on where it has none)")


def _confirm_final(prop: Property, run: Run) -> tuple[bool, str]:
    ok, _ = fails_at_end(prop, run)
    return ok, ("deadlock confirmed: nothing can move and the robots are not gathered" if ok
                else "the last state is not a deadlock")


FINAL = Property(
    "final", "state",
    holds=lambda s: s.gathered or not s.stuck or not s.idle,
    message="deadlock: no robot can move, nothing is pending, and the robots are not all on "
            "one meeting node",
    confirm=_confirm_final,
    symmetric=True, union="deadlock",
    doc="a state where no robot can do anything but stay, with nothing pending, has every "
        "robot on one meeting node")


def _confirm_no_ungatherable(prop: Property, run: Run) -> tuple[bool, str]:
    ok, _ = fails_at_end(prop, run)
    first, end = (theory.get_fact("class").of(run.state_facts(k).configuration)
                  for k in (0, -1))
    return ok, f"{first} -> {end}"


def _initially_in_u(s: StateFacts) -> str | None:
    return theory.words_of("no-ungatherable").vacuous if s.in_U else None


NO_UNGATHERABLE = Property(
    "no-ungatherable", "state",
    holds=lambda s: not s.in_U,
    message=lambda s: theory.words_of("no-ungatherable").message,
    vacuous=_initially_in_u, confirm=_confirm_no_ungatherable, when="discovery",
    symmetric=True, union="in-u",
    doc="from an initial configuration outside the registered fact in_U, no reachable one is "
        "in it (the paper's words: gather_verify.theory.words_of)")
"""The fact ``in_U`` and the words (:func:`gather_verify.theory.words_of`) are the paper's,
registered by its package: this layer names neither U's classes nor its reasons."""


def _confirm_target(prop: Property, run: Run) -> tuple[bool, str]:
    if len(run.states) < 2:
        return False, "no transition"
    ok, (before, after) = fails_at_end(prop, run)
    return ok, f"target {before} -> {after}"


TARGET_INVARIANCE = Property(
    "target-invariance", "transition",
    value=lambda f: f.target,
    holds=lambda before, after: before is None or after is None or before == after,
    message=lambda before, after: f"the target meeting node changes from {list(before)} to "
                                  f"{list(after)}",
    detail=lambda before, after: {"target_before": list(before), "target_after": list(after)},
    confirm=_confirm_target,
    symmetric=True, union="target-change",
    doc="where the algorithm exposes its target meeting node, once defined it never changes "
        "along a transition")


# -- graph properties, decided on the whole reachable graph --------------------------------


def _decide_move_bound(g: GraphFacts) -> Outcome:
    bound = g.c * g.D * g.n
    detail: dict[str, Any] = {"max_moves": g.longest.max_moves, "c": g.c, "D": g.D, "n": g.n}
    m = g.longest.max_moves
    if m is not None:
        ok = m <= bound
        reason = f"largest total moves {m} {'<=' if ok else '>'} {g.c:g}*D*n = {bound:g}"
        result = {"holds": ok, "max_moves": m, "bound": bound, "reason": reason}
        return Outcome(result, None if ok else Witness(g.exploration, g.longest.path, reason,
                                                       None, detail))
    lifted = g.lifted
    assert lifted is not None
    cycle = moving_cycle(lifted)
    assert cycle is not None
    return Outcome({"holds": False, "max_moves": None, "reason": "a cycle with moves: no bound"},
                   Witness(lifted, lifted.path_to(cycle[0]),
                           "a reachable cycle makes moves forever: no bound", cycle, detail))


def _confirm_move_bound(prop: Property, run: Run) -> tuple[bool, str]:
    states, steps = run.states, run.steps
    cs = run.trace.get("cycle_start")
    if cs is not None:  # a cycle that changes only colours (or a turn) leaves the moves bounded
        moves = sum(ev.distance for ev, _ in steps[cs:])
        if states[cs] != states[-1] or cs == len(states) - 1:
            return False, "the cycle does not return to its first state"
        ok = moves > 0
        return ok, (f"the cycle returns and makes {moves} moves per turn" if ok else
                    "the cycle returns but makes no move: the moves stay bounded")
    detail = run.trace.get("detail", {})
    c, D, n = detail.get("c"), detail.get("D"), detail.get("n")
    if not all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in (c, D, n)):
        raise InvalidInput("bad trace: a move-bound trace needs numbers c, D and n in 'detail'")
    first = run.state_facts(0).configuration  # D and n from the trace's own start
    if (D, n) != (first.D, first.n):
        raise InvalidInput(f"bad trace: its detail says D = {D}, n = {n}; its initial "
                           f"configuration has D = {first.D}, n = {first.n}")
    total = sum(ev.distance for ev, _ in steps)
    return total > c * D * n, f"{total} moves vs bound {c}*{D}*{n} = {c * D * n:g}"


MOVE_BOUND = Property(
    "move-bound", "graph", decide=_decide_move_bound, confirm=_confirm_move_bound,
    symmetric=True, union="longest-path",
    doc="the largest total moves over all executions is at most c * D * n")


def _decide_termination(g: GraphFacts) -> Outcome:
    if g.longest.max_moves is not None and not g.longest.cyclic:
        return Outcome({"holds": True, "reason": "the reachable graph is acyclic"})
    lifted = g.lifted
    assert lifted is not None
    live = livelock(lifted)
    if live is None:
        return Outcome({"holds": True, "reason": "every cycle is unfair" + (
            " or goes round a final state" if g.longest.cyclic else "")})
    reason = ("livelock: a fair execution stays forever in a component of "
              f"{len(live.component)} states without reaching a final state")
    return Outcome({"holds": False, "reason": reason},
                   Witness(lifted, lifted.path_to(live.cycle[0]), reason, live.cycle))


def _confirm_termination(prop: Property, run: Run) -> tuple[bool, str]:
    cs = run.trace.get("cycle_start")
    if cs is None:
        raise InvalidInput("bad trace: a termination trace needs 'cycle_start' (its cycle)")
    return fair_cycle(run, cs)


TERMINATION = Property(
    "termination", "graph", decide=_decide_termination, confirm=_confirm_termination,
    symmetric=True, union="acyclic",
    doc="no fair infinite execution that never reaches a final state")


def fair_cycle(run: Run, cs: int) -> tuple[bool, str]:
    """The cycle from state ``cs`` returns to it, changes something, and is fair: every robot
    has an event in it or is idle somewhere in it with staying in its move set."""
    states, steps = run.states, run.steps
    if states[cs] != states[-1] or cs == len(states) - 1:
        return False, "the cycle does not return to its first state"
    n = len(states[0])
    active = set()
    for ev, _ in steps[cs:]:
        active |= set(ev.robots)
    for state in states[cs:]:
        active |= {i for i in range(n) if i not in active and run.may_stay(state, i)}
    if active != set(range(n)):
        return False, f"unfair: robots {sorted(set(range(n)) - active)} never act in the cycle"
    return True, f"fair cycle of {len(states) - 1 - cs} steps confirmed"


BUILTIN = (CRASH, DEFINED, FINAL, NO_UNGATHERABLE, TARGET_INVARIANCE, MOVE_BOUND, TERMINATION)
"""The built-in properties in verdict order: when several fail, the first is named (a
livelock is named termination: :func:`gather_verify.verdict.named_first`)."""
