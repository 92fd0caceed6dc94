"""FSYNC: every step activates every robot; all look at one snapshot and move at once."""

from __future__ import annotations

from schedulers.base import Rounds


class FSync(Rounds):
    name = "fsync"

    def active_sets(self, n: int) -> list[tuple[int, ...]]:
        return [tuple(range(n))]
