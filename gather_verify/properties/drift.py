"""Drift: a run that walks away, repeating itself shifted by a translation.

A search stopped by its region often has a run that leaves every region. The pattern
looked for along such a run: a stretch of ``period`` events after which every robot's node
and pending move are those of the stretch's first state moved by one non-zero ``vector``
(as a multiset: robots are anonymous), the same shift holding state by state for
``periods_checked`` consecutive periods, and the stretch fair (every robot has an event in
it, or is idle in one of its states with staying in its move set).

On the paper's world this is evidence, not a proof: the meeting nodes do not move with the
robots, so the shifted configuration is a different one and nothing forces the next period
to repeat the last. A run that drifts is reported INCOMPLETE (reason ``drift``) unless a
finite prefix already violates a property.

>>> from schedulers import Event
>>> one = lambda x: (((x, 0), None),)
>>> states = [one(x) for x in range(4)]
>>> events = [Event("round", (0,), (((1, 0)),)) for _ in range(3)]
>>> find_drift(states, events, lambda robots: {v: frozenset([(v[0] + 1, 0)]) for v in robots})
{'vector': [1, 0], 'period': 1, 'periods_checked': 3, 'start': 0}
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from typing import Any

from gather_verify.model.geometry import Node

MIN_PERIODS = 2
"""A shift seen once may be chance; a pattern is reported when it repeats at least this often."""

Robot = tuple[Node, Node | None]


def _shifted(state: Sequence[Robot], v: Node) -> list[tuple[Node, Node | None]]:
    """The robots of ``state`` moved by ``v``, sorted (a multiset)."""
    dx, dy = v
    return sorted(((x + dx, y + dy), None if p is None else (p[0] + dx, p[1] + dy))
                  for (x, y), p in state)


def _shift(a: Sequence[Robot], b: Sequence[Robot]) -> Node | None:
    """The non-zero vector moving ``a`` onto ``b`` (robots and pending moves), or None."""
    low_a, low_b = min(v for v, _ in a), min(v for v, _ in b)
    v = (low_b[0] - low_a[0], low_b[1] - low_a[1])
    if v == (0, 0) or _shifted(a, v) != sorted(b):
        return None
    return v


def _fair(states: Sequence[Sequence[Robot]], events: Sequence[Any],
          move_sets: Callable[[tuple[Node, ...]], Mapping[Node, frozenset[Node]]]) -> bool:
    """Every robot has an event in ``events`` or is idle in one of ``states`` with staying in
    its move set."""
    n = len(states[0])
    active = {i for ev in events for i in ev.robots}
    for state in states:
        if len(active) == n:
            break
        sets = move_sets(tuple(sorted(v for v, _ in state)))
        active |= {i for i, (v, p) in enumerate(state) if p is None and v in sets.get(v, ())}
    return len(active) == n


def find_drift(states: Sequence[Sequence[Robot]], events: Sequence[Any],
               move_sets: Callable[[tuple[Node, ...]], Mapping[Node, frozenset[Node]]],
               min_periods: int = MIN_PERIODS) -> dict[str, Any] | None:
    """The drift pattern along a run (``states[k + 1]`` follows ``states[k]`` by
    ``events[k]``): the shortest period, then the earliest start, whose shift holds state by
    state for at least ``min_periods`` periods over a fair stretch; its evidence as JSON
    (``vector``, ``period`` in events, ``periods_checked``, ``start`` step), or None."""
    last = len(states) - 1
    for period in range(1, last // min_periods + 1):
        for start in range(0, last - min_periods * period + 1):
            v = _shift(states[start], states[start + period])
            if v is None:
                continue
            t = start + 1  # states[u + period] is states[u] moved by v for start <= u < t
            while t + period <= last and _shifted(states[t], v) == sorted(states[t + period]):
                t += 1
            periods = (t - 1 + period - start) // period  # whole periods from start
            if periods < min_periods:
                continue
            if not _fair(states[start:start + period + 1], events[start:start + period],
                         move_sets):
                continue
            return {"vector": list(v), "period": period, "periods_checked": periods,
                    "start": start}
    return None
