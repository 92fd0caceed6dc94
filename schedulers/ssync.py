"""SSYNC: each step activates a non-empty subset chosen by the adversary; those
robots look at one snapshot and move at once."""

from __future__ import annotations

from collections.abc import Iterator
from itertools import combinations, product

from schedulers.base import Event, MoveSets, State, configuration_of


class SSync:
    name = "ssync"

    def successors(self, state: State, move_sets: MoveSets) -> Iterator[tuple[Event, State]]:
        options = move_sets(configuration_of(state))
        n = len(state)
        for k in range(1, n + 1):
            for active in combinations(range(n), k):
                choices = [sorted(options[state[i][0]]) for i in active]
                for choice in product(*choices):
                    nodes = [node for node, _ in state]
                    for i, d in zip(active, choice, strict=True):
                        nodes[i] = d
                    moves = tuple((i, state[i][0], d)
                                  for i, d in zip(active, choice, strict=True) if d != state[i][0])
                    yield Event("round", active, moves), tuple((v, None) for v in nodes)
