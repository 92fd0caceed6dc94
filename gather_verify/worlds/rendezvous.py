"""The rendezvous world: two robots with lights in the plane, as a world of the one
pipeline (SEMANTICS.md §13).

A state is the robots' relative position and, per robot, its phase, its colour, the colour
its Compute chose and its pending move: ``(position, (phase, colour, next, pending) x 2)``
(:mod:`gather_verify.worlds.rendezvous_rules` holds the rules; this module steps them for
the phase scheduler, :mod:`schedulers.phases`, and hands the search its
:class:`~gather_verify.engine.bfs.Model`). The search starts from every initial state at
once (every allowed position and colour pair, all robots idle).

>>> from gather_verify.worlds.rendezvous_rules import WHITE, get_algorithm
>>> w = Rendezvous(get_algorithm("vig-2cols"))
>>> s = (NEAR, (LOOK, WHITE, WHITE, STAY), (LOOK, WHITE, WHITE, STAY))
>>> [show_state(t) for _, t in w.look(s, 0, [(WHITE,), (WHITE,)])]
['near | A begin-compute white->black to-half | B look white stay']
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from typing import Any

from gather_verify.errors import InvalidInput
from gather_verify.worlds.rendezvous_rules import (
    FAR,
    MOVES,
    NEAR,
    POSITIONS,
    SAME,
    STAY,
    RendezvousAlgorithm,
    colour_name,
    decide,
    end_move,
    gathered,
    initial_colour_pairs,
    initial_positions,
)
from schedulers.phases import (
    BEGIN_COMPUTE,
    BEGIN_MOVE,
    END_COMPUTE,
    END_MOVE,
    LOOK,
    PHASES,
    Change,
)

__all__ = ["FAR", "NEAR", "RENDEZVOUS", "SAME", "Rendezvous", "RendezvousWorld", "show_state",
           "state_from_json", "state_to_json"]

RENDEZVOUS = "rendezvous"
"""The entry of check and replay that runs the rendezvous world."""

Robot = tuple[int, int, int, int]
"""A robot: ``(phase, colour, next colour, pending move)``."""
State = tuple[int, Robot, Robot]
"""``(position, robot A, robot B)``."""


class Rendezvous:
    """One algorithm's rendezvous world, as the phase scheduler steps it
    (:class:`~schedulers.phases.Phased`): a Look evaluates the algorithm on the colour it
    read and §13's two rules (:func:`~gather_verify.worlds.rendezvous_rules.decide`),
    End-Compute shows the new colour, End-Move applies §13's table
    (:func:`~gather_verify.worlds.rendezvous_rules.end_move`) to the position and to the
    other robot's pending move."""

    def __init__(self, algorithm: RendezvousAlgorithm):
        self.algorithm = algorithm
        self.colours = algorithm.colours

    def count(self, state: State) -> int:
        return 2

    def phase(self, state: State, i: int) -> int:
        return _robot(state, i)[0]

    def light(self, state: State, i: int) -> tuple[int, int]:
        return _robot(state, i)[1], _robot(state, i)[2]

    def starts(self, movement: str, colours: str) -> list[State]:
        """Every initial state: each allowed position, each colour pair, both robots idle."""
        return [(p, (LOOK, a, a, STAY), (LOOK, b, b, STAY))
                for p in initial_positions(movement)
                for a, b in initial_colour_pairs(self.colours, colours)]

    def look(self, state: State, i: int, reads: Sequence[tuple[int, ...]]
             ) -> Iterator[tuple[Change, State]]:
        position = state[0]
        _, colour, _, _ = _robot(state, i)
        other = _robot(state, 1 - i)
        moving = other[0] == END_MOVE and other[3] != STAY
        for seen in reads[1 - i]:
            move, new = decide(self.algorithm, colour, seen, position, moving)
            yield ((), (), ((i, MOVES[move], new, (seen,)),)), \
                _put(state, i, (BEGIN_COMPUTE, colour, new, move))

    def advance(self, state: State, i: int, phase: int) -> tuple[Change, State]:
        _, colour, after, pending = _robot(state, i)
        if phase == BEGIN_COMPUTE:
            return ((), (), ()), _put(state, i, (END_COMPUTE, colour, after, pending))
        if phase == END_COMPUTE:
            lights = ((i, colour, after),) if after != colour else ()
            return ((), lights, ()), _put(state, i, (BEGIN_MOVE, after, after, pending))
        if phase == BEGIN_MOVE:
            return ((), (), ()), _put(state, i, (END_MOVE, colour, after, pending))
        position = state[0]
        if pending == STAY:
            return ((), (), ()), _put(state, i, (LOOK, colour, colour, STAY))
        where, theirs = end_move(position, pending, _robot(state, 1 - i)[3])
        p, c, n, _ = _robot(state, 1 - i)
        other = (p, c, n, theirs)
        mine = (LOOK, colour, colour, STAY)
        robots = (mine, other) if i == 0 else (other, mine)
        return (((i, POSITIONS[position], POSITIONS[where]),), (), ()), (where, *robots)

    @staticmethod
    def goal(state: State) -> bool:
        """§13's goal: one point, nothing pending (absorbing)."""
        return gathered(state[0], (state[1][3], state[2][3]))


def _robot(state: State, i: int) -> Robot:
    return state[1] if i == 0 else state[2]


def _put(state: State, i: int, robot: Robot) -> State:
    return (state[0], robot, state[2]) if i == 0 else (state[0], state[1], robot)


def show_state(state: State) -> str:
    """A state as one line: ``near | A begin-compute white->black to-half | B look ...``."""
    parts = [POSITIONS[state[0]]]
    for name, (phase, colour, after, pending) in zip("AB", state[1:], strict=True):
        light = colour_name(colour) + (f"->{colour_name(after)}" if after != colour else "")
        parts.append(f"{name} {PHASES[phase]} {light} {MOVES[pending]}")
    return " | ".join(parts)


def state_to_json(state: State) -> dict[str, Any]:
    """A state as a trace stores it."""
    return {"position": POSITIONS[state[0]],
            "robots": [{"phase": PHASES[p], "colour": c, "next": n, "pending": MOVES[m]}
                       for p, c, n, m in state[1:]]}


def state_from_json(raw: object, colours: int, where: str) -> State:
    """A trace's state read back (InvalidInput, one line, if it is none)."""
    try:
        assert isinstance(raw, dict) and set(raw) == {"position", "robots"}
        robots = raw["robots"]
        assert isinstance(robots, list) and len(robots) == 2
        out = []
        for r in robots:
            assert isinstance(r, dict) and set(r) == {"phase", "colour", "next", "pending"}
            for c in (r["colour"], r["next"]):
                assert type(c) is int and 0 <= c < colours
            out.append((PHASES.index(r["phase"]), r["colour"], r["next"],
                        MOVES.index(r["pending"])))
        return POSITIONS.index(raw["position"]), out[0], out[1]
    except (AssertionError, ValueError, TypeError):
        raise InvalidInput(f"bad trace: {where}: a state is {{position, robots: two "
                           f"{{phase, colour, next, pending}}}} with colours in "
                           f"0..{colours - 1}") from None


class RendezvousWorld:
    """The world ``rendezvous`` as the commands see it: no nodes, no frames (its robots see
    colours and whether they are at one point or near); check and replay run it through
    their rendezvous entry (:mod:`gather_verify.rendezvous_check`)."""

    name = kind = RENDEZVOUS
    entry = RENDEZVOUS

    def _no_nodes(self, *_: object) -> Any:
        raise InvalidInput("the rendezvous world has no nodes: it takes --algorithm, "
                           "--scheduler, --movement and --initial-colours, not --robots or "
                           "--meeting")

    format_node = parse_node = parse_nodes = node_to_json = node_from_json = _no_nodes
    frames = canonical = _no_nodes

    def drawing(self) -> None:
        return None

