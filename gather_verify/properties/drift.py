"""Drift: a run that walks away, repeating itself shifted by a translation.

A search stopped by its region often has a run that leaves every region. The pattern
looked for along such a run: a stretch of ``period`` events after which the state is the
stretch's first state with some robots (at least one) moved, node and pending move, by one
non-zero ``vector`` and the others unchanged (as multisets: robots are anonymous); the same
holding state by state for ``periods_checked`` consecutive periods, and the stretch fair
(every robot has an event in it, or is idle in one of its states with staying in its move
set). The robots left behind are those that stay put (on a meeting node, say) while the
others walk away.

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

from collections import Counter
from collections.abc import Callable, Mapping, Sequence
from typing import Any

from gather_verify.model.geometry import Node

MIN_PERIODS = 3
"""A shift seen once or twice may be chance (a robot walking straight to its target); a
pattern is reported when it repeats at least this often."""

Robot = tuple[Node, Node | None]


def _order(robot: Robot) -> tuple[Node, bool, Node]:
    """A sort key for robots (two on one node may differ in having a pending move)."""
    node, pending = robot
    return node, pending is not None, pending or node


def _moved(robots: Sequence[Robot], v: Node) -> list[Robot]:
    """``robots`` (node and pending move) moved by ``v``, sorted."""
    dx, dy = v
    return sorted((((x + dx, y + dy), None if p is None else (p[0] + dx, p[1] + dy))
                   for (x, y), p in robots), key=_order)


def _difference(a: Sequence[Robot], b: Sequence[Robot]) -> tuple[list[Robot], list[Robot]]:
    """The robots of ``a`` not in ``b`` and those of ``b`` not in ``a`` (multisets, sorted)."""
    left, right = Counter(a), Counter(b)
    return (sorted((left - right).elements(), key=_order),
            sorted((right - left).elements(), key=_order))


def _shift(a: Sequence[Robot], b: Sequence[Robot]) -> Node | None:
    """The vector ``v`` such that ``b`` is ``a`` with some robots (at least one) moved by
    ``v`` and the others unchanged, or None."""
    gone, new = _difference(a, b)
    if not gone:
        return None
    v = (new[0][0][0] - gone[0][0][0], new[0][0][1] - gone[0][0][1])
    return v if _moved(gone, v) == new else None


def _repeats(a: Sequence[Robot], b: Sequence[Robot], v: Node) -> bool:
    """Whether ``b`` is ``a`` with some robots (at least one) moved by ``v``."""
    gone, new = _difference(a, b)
    return bool(gone) and _moved(gone, v) == new


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
    ``events[k]``): a ``period`` and a ``vector`` such that, from a ``start`` state on, each
    state ``period`` events later is the same with some robots (at least one) moved by
    ``vector`` and the others unchanged, over a fair first period, for at least
    ``min_periods`` whole periods. The one covering the most events wins, then the shortest
    period, then the earliest start. Its evidence as JSON (``vector``, ``period`` in
    events, ``periods_checked``, ``start`` step), or None."""
    last = len(states) - 1
    found: tuple[int, int, int, Node] | None = None  # (-covered, period, start, v)
    for period in range(1, last // min_periods + 1):
        for start in range(0, last - min_periods * period + 1):
            v = _shift(states[start], states[start + period])
            if v is None or v == (0, 0):
                continue
            t = start + 1  # states[u + period] repeats states[u] moved, for start <= u < t
            while t + period <= last and _repeats(states[t], states[t + period], v):
                t += 1
            periods = (t - 1 + period - start) // period  # whole periods from start
            if periods < min_periods:
                continue
            key = (-periods * period, period, start, v)
            if found is not None and key >= found:
                continue
            if _fair(states[start:start + period + 1], events[start:start + period], move_sets):
                found = key
    if found is None:
        return None
    covered, period, start, v = found
    return {"vector": list(v), "period": period, "periods_checked": -covered // period,
            "start": start}
