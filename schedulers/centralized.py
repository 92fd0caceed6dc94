"""Centralized: one robot at a time performs a whole atomic Look-Compute-Move; the
adversary picks which robot, and its choice (SEMANTICS.md §4; the field's ``centralized``
scheduler, as in the SPIN models of luminous robots). On Z² it is SSYNC restricted to
single robots."""

from __future__ import annotations

from collections.abc import Iterator
from functools import cache

import numpy as np

from schedulers.base import (
    ActionOrder,
    Actions,
    Event,
    Frontier,
    LRobot,
    MoveSets,
    State,
    Successors,
    bulk_luminous_rounds,
    bulk_rounds,
    configuration_of,
    round_event,
    subsets_matrix,
)


@cache
def _singletons(n: int) -> np.ndarray:
    return subsets_matrix([(i,) for i in range(n)], n)


class Centralized:
    name = "centralized"
    kinds = ("round",)
    union = True
    rounds = True

    def successors(self, state: State, move_sets: MoveSets) -> Iterator[tuple[Event, State]]:
        options = move_sets(configuration_of(state))
        for i, (node, _) in enumerate(state):
            for d in sorted(options[node]):
                moves = ((i, node, d),) if d != node else ()
                yield (Event("round", (i,), moves),
                       state[:i] + ((d, None),) + state[i + 1:])

    def activations(self, n: int) -> np.ndarray:
        return _singletons(n)

    def bulk_successors(self, frontier: Frontier, budget: int) -> Successors:
        return bulk_rounds(frontier, budget, _singletons(frontier.codes.shape[1]))

    def bulk_luminous(self, frontier: Frontier, budget: int, colours: int) -> Successors:
        return bulk_luminous_rounds(frontier, budget, _singletons(frontier.codes.shape[1]), colours)

    def luminous(self, robots: tuple[LRobot, ...], extra: object, actions: Actions, *,
                 order: ActionOrder = repr, null: bool = False
                 ) -> Iterator[tuple[Event, tuple[LRobot, ...], object]]:
        for i in range(len(robots)):
            for action in sorted(actions(i), key=order):
                event, succ = round_event((i,), robots, (action,))
                if null or succ != robots:
                    yield event, succ, extra
