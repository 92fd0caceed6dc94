"""SSYNC: each step activates a non-empty subset chosen by the adversary; those
robots look at one snapshot and move at once."""

from __future__ import annotations

from collections.abc import Iterator
from functools import cache
from itertools import combinations, product

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


def _active_sets(n: int) -> Iterator[tuple[int, ...]]:
    """The non-empty subsets of robots, by size, then in lexicographic order."""
    for k in range(1, n + 1):
        yield from combinations(range(n), k)


@cache
def _subsets(n: int) -> np.ndarray:
    return subsets_matrix(_active_sets(n), n)


class SSync:
    name = "ssync"
    kinds = ("round",)
    union = True
    rounds = True

    def successors(self, state: State, move_sets: MoveSets) -> Iterator[tuple[Event, State]]:
        options = move_sets(configuration_of(state))
        for active in _active_sets(len(state)):
            choices = [sorted(options[state[i][0]]) for i in active]
            for choice in product(*choices):
                nodes = [node for node, _ in state]
                for i, d in zip(active, choice, strict=True):
                    nodes[i] = d
                moves = tuple((i, state[i][0], d)
                              for i, d in zip(active, choice, strict=True) if d != state[i][0])
                yield Event("round", active, moves), tuple((v, None) for v in nodes)

    def activations(self, n: int) -> np.ndarray:
        return _subsets(n)

    def bulk_successors(self, frontier: Frontier, budget: int) -> Successors:
        return bulk_rounds(frontier, budget, _subsets(frontier.codes.shape[1]))

    def bulk_luminous(self, frontier: Frontier, budget: int, colours: int) -> Successors:
        return bulk_luminous_rounds(frontier, budget, _subsets(frontier.codes.shape[1]), colours)

    def luminous(self, robots: tuple[LRobot, ...], extra: object, actions: Actions, *,
                 order: ActionOrder = repr, null: bool = False
                 ) -> Iterator[tuple[Event, tuple[LRobot, ...], object]]:
        for active in _active_sets(len(robots)):
            for choice in product(*(sorted(actions(i), key=order) for i in active)):
                event, succ = round_event(active, robots, choice)
                if null or succ != robots:
                    yield event, succ, extra
