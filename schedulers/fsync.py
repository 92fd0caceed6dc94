"""FSYNC: every step activates every robot; all look at one snapshot and move at once."""

from __future__ import annotations

from collections.abc import Iterator
from functools import cache
from itertools import product

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
def _everyone(n: int) -> np.ndarray:
    return subsets_matrix([range(n)], n)


class FSync:
    name = "fsync"
    kinds = ("round",)
    union = True
    rounds = True

    def successors(self, state: State, move_sets: MoveSets) -> Iterator[tuple[Event, State]]:
        options = move_sets(configuration_of(state))
        robots = tuple(range(len(state)))
        for choice in product(*(sorted(options[node]) for node, _ in state)):
            moves = tuple((i, state[i][0], d) for i, d in enumerate(choice) if d != state[i][0])
            yield Event("round", robots, moves), tuple((d, None) for d in choice)

    def activations(self, n: int) -> np.ndarray:
        return _everyone(n)

    def bulk_successors(self, frontier: Frontier, budget: int) -> Successors:
        return bulk_rounds(frontier, budget, _everyone(frontier.codes.shape[1]))

    def bulk_luminous(self, frontier: Frontier, budget: int, colours: int) -> Successors:
        return bulk_luminous_rounds(frontier, budget, _everyone(frontier.codes.shape[1]), colours)

    def luminous(self, robots: tuple[LRobot, ...], extra: object, actions: Actions, *,
                 order: ActionOrder = repr, null: bool = False
                 ) -> Iterator[tuple[Event, tuple[LRobot, ...], object]]:
        everyone = tuple(range(len(robots)))
        for choice in product(*(sorted(actions(i), key=order) for i in everyone)):
            event, succ = round_event(everyone, robots, choice)
            if null or succ != robots:
                yield event, succ, extra
