"""The synchrony models of the luminous-robot literature as one scheduler: a robot's cycle
cut into five steps, the model saying which steps are one atomic event, which robots may
step together and what a Look reads of a light being changed (SEMANTICS.md §13).

A robot's *phase* is the next step it takes: Look (it is idle), Begin-Compute,
End-Compute, Begin-Move, End-Move. Between Begin-Compute and End-Compute it is
*computing*: a Look of another robot then reads its light as the model says (``atomic``:
the old colour; ``regular``: the old or the new; ``safe``: any colour of the lights).
The algorithm is evaluated at the Look, which fixes the robot's command (its move and
its next colour); the light changes at End-Compute, the robot's position at End-Move.

The scheduler never sees the algorithm, the geometry or the world: it asks a
:class:`Phased` world each robot's phase and lights, and to carry a step out. The same
models run on the rendezvous world (two robots in the plane) and on every graph world
with lights (:class:`PhaseScheduler`'s ``luminous``, where a move is instantaneous, so
Begin-Move shows nothing to the others).

>>> MODELS["async-lc-atomic"].groups
((0, 1, 2), (3,), (4,))
>>> [name for name, m in MODELS.items() if m.reads == "safe"]
['async-safe', 'async-move-safe']
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from itertools import product
from typing import Any, Protocol

from schedulers.base import ActionOrder, Actions, Event, LRobot

LOOK, BEGIN_COMPUTE, END_COMPUTE, BEGIN_MOVE, END_MOVE = range(5)
PHASES = ("look", "begin-compute", "end-compute", "begin-move", "end-move")
"""The five steps of a cycle; a robot's phase is the next one it takes (``look``: idle)."""
READS = ("atomic", "regular", "safe")
CYCLE = ((LOOK, BEGIN_COMPUTE, END_COMPUTE, BEGIN_MOVE, END_MOVE),)
STEPS = ((LOOK,), (BEGIN_COMPUTE,), (END_COMPUTE,), (BEGIN_MOVE,), (END_MOVE,))
MOVE_ATOMIC = ((LOOK,), (BEGIN_COMPUTE,), (END_COMPUTE,), (BEGIN_MOVE, END_MOVE))
LC_ATOMIC = ((LOOK, BEGIN_COMPUTE, END_COMPUTE), (BEGIN_MOVE,), (END_MOVE,))

Change = tuple[tuple[tuple[int, Any, Any], ...], tuple[tuple[int, int, int], ...],
               tuple[tuple[int, Any, int, tuple[int, ...]], ...]]
"""What one step did, as :class:`~schedulers.base.Event` writes it: its ``moves``, its
``lights`` and its ``chosen`` (a Look's command and the colours it read)."""


@dataclass(frozen=True)
class PhaseModel:
    """A synchrony model: the cycle cut into atomic ``groups`` (in order), whether one robot
    steps at a time (``single``), whether every robot may do its first group at once when all
    are idle (``joint``: they all Look on one state, then each does the rest of its group in
    index order), how a Look reads a light being changed, and the steps per cycle of the SPIN
    model (its bounded fairness counts them)."""

    groups: tuple[tuple[int, ...], ...]
    single: bool = True
    joint: bool = False
    reads: str = "atomic"
    spin_steps: int = 5

    def group_of(self, phase: int) -> tuple[int, ...]:
        """The atomic group that starts with ``phase``."""
        return next(g for g in self.groups if g[0] == phase)


MODELS: dict[str, PhaseModel] = {
    "centralized": PhaseModel(CYCLE, spin_steps=1),
    "fsync": PhaseModel(CYCLE, single=False, joint=True, spin_steps=1),
    "ssync": PhaseModel(CYCLE, joint=True, spin_steps=1),
    "async": PhaseModel(STEPS),
    "async-regular": PhaseModel(STEPS, reads="regular"),
    "async-safe": PhaseModel(STEPS, reads="safe"),
    "async-lc-atomic": PhaseModel(LC_ATOMIC, joint=True, spin_steps=3),
    "async-lc-strict": PhaseModel(LC_ATOMIC, spin_steps=3),
    "async-cm-atomic": PhaseModel(((LOOK,), (BEGIN_COMPUTE, END_COMPUTE, BEGIN_MOVE, END_MOVE)),
                                  spin_steps=3),
    "async-move-atomic": PhaseModel(MOVE_ATOMIC, spin_steps=4),
    "async-move-regular": PhaseModel(MOVE_ATOMIC, reads="regular", spin_steps=4),
    "async-move-safe": PhaseModel(MOVE_ATOMIC, reads="safe", spin_steps=4),
}
"""§13's synchrony models by the SPIN model's names in lower case with hyphens
(``ASYNC_LC_ATOMIC`` is ``async-lc-atomic``). On the rendezvous world every name means
this; on a graph world ``centralized``, ``fsync``, ``ssync`` and ``async`` keep their §4/§10
meaning (their own modules) and the others run by :class:`PhaseScheduler`."""


class Phased(Protocol):
    """What a world gives the phase scheduler: each robot's phase and lights, and the steps
    carried out (the world alone knows the algorithm and the geometry)."""

    colours: int
    """K: the colours a safe read ranges over."""

    def count(self, state: Any) -> int:
        """The number of robots."""
        ...

    def phase(self, state: Any, i: int) -> int:
        """Robot ``i``'s next step."""
        ...

    def light(self, state: Any, i: int) -> tuple[int, int]:
        """Robot ``i``'s colour and the colour its Compute chose (equal when not computing)."""
        ...

    def look(self, state: Any, i: int, reads: Sequence[tuple[int, ...]]
             ) -> Iterator[tuple[Change, Any]]:
        """Robot ``i``'s Look: one successor per combination of colours it may read of each
        robot (``reads[j]``; its own entry is its own colour) and per choice the adversary has
        among the algorithm's answers; its phase becomes Begin-Compute."""
        ...

    def advance(self, state: Any, i: int, phase: int) -> tuple[Change, Any]:
        """Robot ``i`` takes its step ``phase`` (Begin-Compute .. End-Move)."""
        ...


NO_CHANGE: Change = ((), (), ())


def reads(model: PhaseModel, world: Phased, state: Any, i: int) -> list[tuple[int, ...]]:
    """The colours robot ``i``'s Look may read of each robot, by the model's read semantics
    (only a robot between Begin-Compute and End-Compute is read otherwise than atomically)."""
    out: list[tuple[int, ...]] = []
    for j in range(world.count(state)):
        colour, after = world.light(state, j)
        if j == i or world.phase(state, j) != END_COMPUTE or model.reads == "atomic":
            out.append((colour,))
        elif model.reads == "regular":
            out.append(tuple(sorted({colour, after})))
        else:
            out.append(tuple(range(world.colours)))
    return out


def _join(a: Change, b: Change) -> Change:
    return a[0] + b[0], a[1] + b[1], a[2] + b[2]


def _rest(world: Phased, state: Any, i: int, phases: Sequence[int], done: Change
          ) -> tuple[Change, Any]:
    for p in phases:
        change, state = world.advance(state, i, p)
        done = _join(done, change)
    return done, state


def _group(model: PhaseModel, world: Phased, state: Any, i: int, group: tuple[int, ...]
           ) -> Iterator[tuple[Change, Any]]:
    """Robot ``i``'s atomic ``group`` of steps: one outcome per outcome of its Look."""
    if group[0] != LOOK:
        yield _rest(world, state, i, group, NO_CHANGE)
        return
    for change, succ in world.look(state, i, reads(model, world, state, i)):
        yield _rest(world, succ, i, group[1:], change)


def phase_events(model: PhaseModel, world: Phased, state: Any
                 ) -> Iterator[tuple[Event, Any]]:
    """Every event of ``model`` from ``state``: each robot's next atomic group (``single``),
    then, when ``joint`` and every robot is idle, every robot's first group at once (all
    Look on one state, then each does the rest in index order). An event that changes
    nothing but phases is an event: a robot's cycle always is (§13)."""
    n = world.count(state)
    if model.single:
        for i in range(n):
            group = model.group_of(world.phase(state, i))
            for change, succ in _group(model, world, state, i, group):
                yield _event(group, (i,), change), succ
    if model.joint and n > 1 and all(world.phase(state, i) == LOOK for i in range(n)):
        group = model.groups[0]
        looked: list[tuple[Change, Any]] = [(NO_CHANGE, state)]
        for i in range(n):  # each Look reads the others' lights as they were
            looked = [(_join(done, change), succ) for done, s in looked
                      for change, succ in world.look(s, i, reads(model, world, state, i))]
        for done, succ in looked:
            for i in range(n):
                done, succ = _rest(world, succ, i, group[1:], done)
            yield _event(group, tuple(range(n)), done), succ


def _event(group: tuple[int, ...], robots: tuple[int, ...], change: Change) -> Event:
    moves, lights, chosen = change
    return Event("+".join(PHASES[p] for p in group), robots, moves, lights, chosen)


Record = tuple[int, int]
"""A robot's place in its cycle on a graph world: its phase and the colour its Compute chose."""


class GraphPhases:
    """A graph world's robots as the phase scheduler steps them: the state is the robots
    ``(node, pending destination or None, colour)`` and the scheduler's own state, per
    robot its :data:`Record` (None when every robot is idle). A Look fixes the destination
    and the next colour from the robot's actions under the colours it read
    (``view``: the robots with those colours -> each robot's actions); End-Compute shows
    the colour; End-Move takes the robot to its destination (instantaneous: Begin-Move
    shows nothing)."""

    def __init__(self, colours: int, actions: Actions, order: ActionOrder,
                 view: Callable[[tuple[LRobot, ...]], Sequence[frozenset[Any]]] | None):
        self.colours, self.actions, self.order, self.view = colours, actions, order, view

    def count(self, state: Any) -> int:
        return len(state[0])

    def record(self, state: Any, i: int) -> Record:
        robots, records = state
        return (LOOK, robots[i][2]) if records is None else records[i]

    def phase(self, state: Any, i: int) -> int:
        return self.record(state, i)[0]

    def light(self, state: Any, i: int) -> tuple[int, int]:
        return state[0][i][2], self.record(state, i)[1]

    def _with(self, state: Any, i: int, robot: LRobot, record: Record) -> Any:
        robots, _ = state
        records = [self.record(state, j) for j in range(len(robots))]
        records[i] = record
        robots = robots[:i] + (robot,) + robots[i + 1:]
        return robots, None if all(r[0] == LOOK for r in records) else tuple(records)

    def look(self, state: Any, i: int, reads: Sequence[tuple[int, ...]]
             ) -> Iterator[tuple[Change, Any]]:
        robots, _ = state
        node, _, colour = robots[i]
        seen = set()
        for read in product(*reads):
            if self.view is None or all(r == c for r, (_, _, c) in zip(read, robots, strict=True)):
                options = self.actions(i)
            else:
                options = self.view(tuple((v, p, r) for (v, p, _), r
                                          in zip(robots, read, strict=True)))[i]
            others = tuple(r for j, r in enumerate(read) if j != i)
            for d, c in sorted(options, key=self.order):
                if (d, c, others) in seen:
                    continue
                seen.add((d, c, others))
                succ = self._with(state, i, (node, None if d == node else d, colour),
                                  (BEGIN_COMPUTE, c))
                yield ((), (), ((i, d, c, others),)), succ

    def advance(self, state: Any, i: int, phase: int) -> tuple[Change, Any]:
        robots, _ = state
        node, pending, colour = robots[i]
        after = self.record(state, i)[1]
        if phase == END_COMPUTE:
            lights = ((i, colour, after),) if after != colour else ()
            return ((), lights, ()), self._with(state, i, (node, pending, after), (BEGIN_MOVE, after))
        if phase == END_MOVE:
            moves = ((i, node, pending),) if pending is not None else ()
            return (moves, (), ()), self._with(state, i, (node if pending is None else pending,
                                                          None, colour), (LOOK, colour))
        return NO_CHANGE, self._with(state, i, robots[i], (phase + 1, after))


class PhaseScheduler:
    """One of §13's synchrony models (:data:`MODELS`) as a scheduler of a graph world with
    lights: its own state is each robot's place in its cycle (:class:`GraphPhases`), its
    events are :func:`phase_events`. The reference engine runs it (no bulk face); the
    reductions are off under it (its records name robots)."""

    phased = True
    """It keeps each robot's phase as its own state: the reference engine only, unreduced."""
    kinds = PHASES

    def __init__(self, name: str):
        self.name, self.model = name, MODELS[name]

    def activations(self, n: int) -> None:
        return None

    def luminous(self, robots: tuple[LRobot, ...], extra: object, actions: Actions, *,
                 order: ActionOrder = repr, null: bool = False,
                 view: Callable[[tuple[LRobot, ...]], Sequence[frozenset[Any]]] | None = None,
                 colours: int = 1) -> Iterator[tuple[Event, tuple[LRobot, ...], object]]:
        """Every event from ``robots`` with the records ``extra``; ``view`` re-evaluates the
        robots' actions under colours a regular or safe read saw (without it, a Look sees the
        colours of ``robots``), ``colours`` is K (what a safe read ranges over)."""
        world = GraphPhases(colours, actions, order, view)
        for event, (succ, records) in phase_events(self.model, world, (robots, extra)):
            yield event, succ, records


def phase_scheduler(name: str) -> type[PhaseScheduler]:
    """A registry entry: the class of the model ``name`` (so that the registry holds one
    class per name, as for every scheduler)."""
    return type(name.title().replace("-", ""), (PhaseScheduler,),
                {"__init__": lambda self: PhaseScheduler.__init__(self, name),
                 "__doc__": f"§13's {name} (:data:`MODELS`)."})
