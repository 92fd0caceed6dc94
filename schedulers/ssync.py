"""SSYNC: each step activates a non-empty subset chosen by the adversary; those
robots look at one snapshot and move at once."""

from __future__ import annotations

from collections.abc import Iterator
from itertools import combinations

from schedulers.base import Rounds


class SSync(Rounds):
    name = "ssync"

    def active_sets(self, n: int) -> Iterator[tuple[int, ...]]:
        """The non-empty subsets of robots, by size, then in lexicographic order."""
        for k in range(1, n + 1):
            yield from combinations(range(n), k)
