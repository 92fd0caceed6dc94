"""Round-robin: robots are activated one at a time, each activation a whole atomic
Look-Compute-Move, in a cyclic order the adversary fixes at the start (the field's
round-robin schedulers on rings and grids).

The scheduler keeps its own state, ``(order, turn)``: every order is a start of the
search (``starts``), or only the one given as ``round-robin:order=2 0 1``. An activation
moves the turn on even when the robot stays, so it is always a transition. Every engine
runs it, on every world: they keep its state as an integer (``state_index``), ask it how
identical robots are relabelled (``relabel``), and take its events from ``luminous`` (one
state) or its bulk faces (many, each state's own as ``extra=``).
"""

from __future__ import annotations

from collections.abc import Iterator
from functools import cache
from itertools import permutations

import numpy as np

from gather_verify.errors import InvalidInput
from gather_verify.kernels.codes import OUTSIDE
from gather_verify.model.geometry import DEGREE, SLOTS
from schedulers.base import (
    _COUNT,
    _NTH,
    ActionOrder,
    Actions,
    Event,
    Frontier,
    LRobot,
    Successors,
    allowed_actions,
    luminous_order,
    round_event,
    subsets_matrix,
)


class RoundRobin:
    name = "round-robin"
    kinds = ("round",)
    stateful = True
    """It keeps state of its own (the order and whose turn it is)."""
    union = True
    """A sweep may share one state graph per meeting-node class (its state in the keys,
    :func:`gather_verify.engine.union.explore_union`)."""

    def __init__(self, order: str | None = None):
        self.order = None if order is None else _parse_order(order)

    def starts(self, n: int) -> list[object]:
        """Every cyclic order the adversary may fix (or the one given), turn 0."""
        return [(order, 0) for order in self._orders(n)]

    def _orders(self, n: int) -> tuple[tuple[int, ...], ...]:
        if self.order is not None:
            if sorted(self.order) != list(range(n)):
                raise InvalidInput(f"round-robin order {' '.join(map(str, self.order))} must "
                                   f"name each of the robots 0..{n - 1} once")
            return (self.order,)
        return _every_order(n)

    def activations(self, n: int) -> np.ndarray:
        """One robot per round: the one whose turn it is (its own state says which)."""
        return subsets_matrix([(i,) for i in range(n)], n)

    def state_count(self, n: int) -> int:
        """How many states of its own it may be in with ``n`` robots (orders times turns)."""
        return len(self._orders(n)) * n

    def state_index(self, extra: object, n: int) -> int:
        """Its state ``(order, turn)`` as an integer below :meth:`state_count`: the order's
        place among :meth:`starts` times ``n``, plus the turn."""
        order, turn = extra  # type: ignore[misc]
        return _places(self.order, n)[order] * n + turn

    def state_of(self, index: int, n: int) -> object:
        """The state :meth:`state_index` gave ``index``."""
        place, turn = divmod(index, n)
        return self._orders(n)[place], turn

    def pinned(self, extra: object) -> str:
        """Its name with the order of ``extra`` fixed (what a trace from that start names)."""
        order, _ = extra  # type: ignore[misc]
        return f"{self.name}:order={' '.join(map(str, order))}"

    def relabel(self, extra: object, n: int) -> tuple[tuple[int, ...], object]:
        """Identical robots (anonymity, SEMANTICS.md §4) relabelled so that the order is the
        first of :meth:`starts`: ``(perm, state)``, new robot k being old robot ``perm[k]``.
        The same robot acts at each turn, so the state's future is the same; the turn stays
        (it is whose turn it is, not who)."""
        order, turn = extra  # type: ignore[misc]
        first = self._orders(n)[0]
        where = {robot: j for j, robot in enumerate(first)}
        return tuple(order[where[k]] for k in range(n)), (first, turn)

    def luminous(self, robots: tuple[LRobot, ...], extra: object, actions: Actions, *,
                 order: ActionOrder = repr, null: bool = False
                 ) -> Iterator[tuple[Event, tuple[LRobot, ...], object]]:
        cycle, turn = extra  # type: ignore[misc]
        i = cycle[turn]
        after = (cycle, (turn + 1) % len(cycle))
        for action in sorted(actions(i), key=order):
            event, succ = round_event((i,), robots, (action,))
            yield event, succ, after

    def bulk_successors(self, frontier: Frontier, budget: int, *,
                        extra: np.ndarray | None = None) -> Successors:
        """:func:`~schedulers.base.oblivious_events` in bulk: per state, the robot whose turn
        it is (``extra``: each state's :meth:`state_index`), each of its choices in sorted
        order; :attr:`Successors.extra` the state after each event."""
        return self._bulk(frontier, budget, None, extra)

    def bulk_luminous(self, frontier: Frontier, budget: int, colours: int, *,
                      extra: np.ndarray | None = None) -> Successors:
        """:meth:`luminous` on Z² in bulk (``order`` the actions themselves)."""
        return self._bulk(frontier, budget, colours, extra)

    def _bulk(self, frontier: Frontier, budget: int, colours: int | None,
              extra: np.ndarray | None) -> Successors:
        codes, masks, neighbour = frontier
        assert extra is not None, "round-robin's bulk faces read each state's turn"
        total, n = codes.shape
        place, turn = np.divmod(extra[:total], n)
        active = _table(self.order, n)[place, turn]
        mask = masks[np.arange(total), active].astype(np.int64)
        if colours is None:
            count = _COUNT[mask]
        else:
            bits = luminous_order(colours)
            allowed = allowed_actions(mask[:, None], bits)[:, 0, :]
            count = allowed.sum(axis=1)
        ends = np.cumsum(count)
        s = min(total, max(1, int(np.searchsorted(ends, budget, side="right")))) if total else 0
        count, ends = count[:s], ends[:s]
        source = np.repeat(np.arange(s), count)
        rank = np.arange(len(source)) - (ends - count)[source]
        robot = active[source]
        if colours is None:
            step, colour, unit = _NTH[mask[source], rank], 0, SLOTS
        else:
            nth = bits[np.argsort(~allowed[:s], axis=1, kind="stable")]
            step, colour = np.divmod(nth[source, rank], colours)
            unit = SLOTS * colours
        cell = codes[source, robot] // unit
        go = step < DEGREE
        dest = neighbour[cell, np.where(go, step, 0)]
        code = np.where(go, np.where(dest >= 0, dest * unit + colour, OUTSIDE),
                        cell * unit + colour)
        weight = go.astype(np.int8 if n <= 127 else np.int16)
        after = (place * n + (turn + 1) % n)[source]
        return Successors(s, source, weight, robot, code, None, after)

    def successors(self, state, move_sets):  # noqa: ANN001, ANN201
        raise InvalidInput("round-robin keeps a scheduler state: its events need it "
                           "(schedulers.base.oblivious_events)")


@cache
def _every_order(n: int) -> tuple[tuple[int, ...], ...]:
    return tuple(permutations(range(n)))


@cache
def _table(given: tuple[int, ...] | None, n: int) -> np.ndarray:
    """The orders (the one ``given``, else every one) as rows: row k is start k's."""
    orders = (given,) if given is not None else _every_order(n)
    return np.array(orders, dtype=np.int64).reshape(len(orders), n)


@cache
def _places(given: tuple[int, ...] | None, n: int) -> dict[tuple[int, ...], int]:
    """Each order's place among the starts (the one ``given``, else every order)."""
    orders = (given,) if given is not None else _every_order(n)
    return {order: k for k, order in enumerate(orders)}


def _parse_order(text: str) -> tuple[int, ...]:
    try:
        return tuple(int(part, 10) for part in text.replace(",", " ").split())
    except ValueError:
        raise InvalidInput(f"round-robin order {text!r}: write robot indices, e.g. "
                           "order=2 0 1") from None
