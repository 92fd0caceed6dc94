"""Round-robin: robots are activated one at a time, each activation a whole atomic
Look-Compute-Move, in a cyclic order the adversary fixes at the start (the field's
round-robin schedulers on rings and grids).

The scheduler keeps its own state, ``(order, turn)``: every order is a start of the
search (``starts``), or only the one given as ``round-robin:order=2 0 1``. An activation
moves the turn on even when the robot stays, so it is always a transition. Finite worlds
only: the Z² engines keep no scheduler state.
"""

from __future__ import annotations

from collections.abc import Iterator
from itertools import permutations

from gather_verify.errors import InvalidInput
from schedulers.base import ActionOrder, Actions, Event, LRobot, round_event


class RoundRobin:
    name = "round-robin"
    kinds = ("round",)
    stateful = True
    """It keeps state of its own (the order and whose turn it is)."""

    def __init__(self, order: str | None = None):
        self.order = None if order is None else _parse_order(order)

    def starts(self, n: int) -> list[object]:
        """Every cyclic order the adversary may fix (or the one given), turn 0."""
        if self.order is not None:
            if sorted(self.order) != list(range(n)):
                raise InvalidInput(f"round-robin order {' '.join(map(str, self.order))} must "
                                   f"name each of the robots 0..{n - 1} once")
            return [(self.order, 0)]
        return [(p, 0) for p in permutations(range(n))]

    def luminous(self, robots: tuple[LRobot, ...], extra: object, actions: Actions, *,
                 order: ActionOrder = repr, null: bool = False
                 ) -> Iterator[tuple[Event, tuple[LRobot, ...], object]]:
        cycle, turn = extra  # type: ignore[misc]
        i = cycle[turn]
        after = (cycle, (turn + 1) % len(cycle))
        for action in sorted(actions(i), key=order):
            event, succ = round_event((i,), robots, (action,))
            yield event, succ, after

    def successors(self, state, move_sets):  # noqa: ANN001, ANN201
        raise InvalidInput("round-robin keeps a scheduler state: it runs on finite worlds "
                           "(--world ring:N, grid:WxH, torus:WxH, graph:FILE)")

    bulk_successors = successors


def _parse_order(text: str) -> tuple[int, ...]:
    try:
        return tuple(int(part, 10) for part in text.replace(",", " ").split())
    except ValueError:
        raise InvalidInput(f"round-robin order {text!r}: write robot indices, e.g. "
                           "order=2 0 1") from None
