"""FSYNC: every step activates every robot; all look at one snapshot and move at once."""

from __future__ import annotations

from collections.abc import Iterator
from itertools import product

from schedulers.base import Event, MoveSets, State, configuration_of


class FSync:
    name = "fsync"

    def successors(self, state: State, move_sets: MoveSets) -> Iterator[tuple[Event, State]]:
        options = move_sets(configuration_of(state))
        robots = tuple(range(len(state)))
        for choice in product(*(sorted(options[node]) for node, _ in state)):
            moves = tuple((i, state[i][0], d) for i, d in enumerate(choice) if d != state[i][0])
            yield Event("round", robots, moves), tuple((d, None) for d in choice)
