"""Centralized: one robot at a time performs a whole atomic Look-Compute-Move; the
adversary picks which robot, and its choice (SEMANTICS.md §4; the field's ``centralized``
scheduler, as in the SPIN models of luminous robots). On Z² it is SSYNC restricted to
single robots."""

from __future__ import annotations

from schedulers.base import Rounds


class Centralized(Rounds):
    name = "centralized"

    def active_sets(self, n: int) -> list[tuple[int, ...]]:
        return [(i,) for i in range(n)]
