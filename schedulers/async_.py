"""ASYNC: Look and Move are separate events per robot.

``Look(i)`` on an idle robot fixes ``pending[i]`` to any move of its move set
(a Look that ends in staying changes nothing, so it is no transition);
``Move(i)`` takes robot i to its pending destination and makes it idle. Moves
are instantaneous: the asynchrony is the stale snapshot between Look and Move.
"""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np

from gather_verify.kernels.codes import OUTSIDE
from gather_verify.model.geometry import DEGREE, SLOTS, STEPS
from schedulers.base import (
    ActionOrder,
    Actions,
    Event,
    Frontier,
    LRobot,
    MoveSets,
    State,
    Successors,
    allowed_actions,
    configuration_of,
    luminous_order,
)

LOOK_ORDER = tuple(sorted(range(len(STEPS)), key=STEPS.__getitem__))
"""Step indices in the order :meth:`Async.successors` yields Looks (sorted destinations)."""
_LOOK_ORDER = np.array(LOOK_ORDER, dtype=np.int64)
_LOOK_STEP = np.array([k + 1 for k in LOOK_ORDER], dtype=np.int64)
_EVENTS = np.array([sum(1 << 8 * slot for slot, k in enumerate(LOOK_ORDER) if m >> k & 1)
                    for m in range(1 << SLOTS)] + [1], dtype="<u4")
"""A robot's events as four little-endian bytes (one per Look: Z²'s ``DEGREE`` is 4): by move
mask when idle, at ``1 << SLOTS`` when moving."""


class Async:
    name = "async"
    kinds = ("look", "move")
    union = True

    def activations(self, n: int) -> None:
        """None: one robot's Look or Move per event, not rounds."""
        return None

    def successors(self, state: State, move_sets: MoveSets) -> Iterator[tuple[Event, State]]:
        options = None
        for i, (node, pending) in enumerate(state):
            if pending is None:
                if options is None:
                    options = move_sets(configuration_of(state))
                for d in sorted(options[node]):
                    if d != node:
                        yield (Event("look", (i,), ((i, node, d),)),
                               state[:i] + ((node, d),) + state[i + 1:])
            else:
                yield (Event("move", (i,), ((i, node, pending),)),
                       state[:i] + ((pending, None),) + state[i + 1:])

    def luminous(self, robots: tuple[LRobot, ...], extra: object, actions: Actions, *,
                 order: ActionOrder = repr, null: bool = False
                 ) -> Iterator[tuple[Event, tuple[LRobot, ...], object]]:
        """A Look sets the pending destination and the new colour at once (§10: others see
        the colour before the robot moves); a Look that stays and keeps its colour is no
        event, one that changes only the colour is."""
        for i, (node, pending, colour) in enumerate(robots):
            if pending is None:
                for d, c in sorted(actions(i), key=order):
                    if d == node and c == colour:
                        continue
                    lights = ((i, colour, c),) if c != colour else ()
                    moves = ((i, node, d),) if d != node else ()
                    succ = robots[:i] + ((node, None if d == node else d, c),) + robots[i + 1:]
                    yield Event("look", (i,), moves, lights), succ, extra
            else:
                yield (Event("move", (i,), ((i, node, pending),)),
                       robots[:i] + ((pending, None, colour),) + robots[i + 1:], extra)

    def bulk_luminous(self, frontier: Frontier, budget: int, colours: int) -> Successors:
        """:meth:`luminous` on Z² in bulk (codes and masks with ``colours`` colours, as
        :class:`~schedulers.base.Frontier` says): per robot, an idle one's Looks (every action
        but staying with its own colour, in order; pending step and colour set at once), a
        busy one's Move (its colour kept; ``OUTSIDE`` when it leaves the region). One change per
        event."""
        codes, masks, neighbour = frontier
        s, n = codes.shape
        order = luminous_order(colours)
        w = len(order)
        if s * w * n > budget:
            s = max(1, budget // (w * n))
            codes, masks = codes[:s], masks[:s]
        robot_code = codes // colours  # cell * SLOTS + d
        colour = codes - robot_code * colours
        idle = robot_code % SLOTS == 0
        present = allowed_actions(masks, order)
        present &= order[None, None, :] != DEGREE * colours + colour[:, :, None]  # stay, same light
        present &= idle[:, :, None]
        present[:, :, 0] |= ~idle  # a busy robot's one event: its Move
        flat = np.flatnonzero(present)
        at, j = np.divmod(flat, w)
        src, robot = np.divmod(at, n)
        rc = robot_code.reshape(-1)[at]
        cell = rc // SLOTS
        step, c = np.divmod(order[j], colours)
        new = (cell * SLOTS + np.where(step < DEGREE, step + 1, 0)) * colours + c
        move = np.flatnonzero(~idle.reshape(-1)[at])
        if len(move):
            dest = neighbour[cell[move], rc[move] - cell[move] * SLOTS - 1]
            new[move] = np.where(dest >= 0,
                                 dest * SLOTS * colours + colour.reshape(-1)[at[move]], OUTSIDE)
        weight = np.zeros(len(flat), dtype=np.int8)
        weight[move] = 1
        return Successors(s, src, weight, robot, new, None)

    def bulk_successors(self, frontier: Frontier, budget: int) -> Successors:
        """:meth:`successors` for many states at once, in the same order: one change per
        event (a Look sets the robot's pending step, a Move takes it to its destination,
        ``OUTSIDE`` when that leaves the region); sources, robots and codes ``int32``."""
        codes, masks, neighbour = frontier
        s, n = codes.shape
        if s * DEGREE * n > budget:  # at most DEGREE Looks (or one Move) per robot
            s = max(1, budget // (DEGREE * n))
            codes, masks = codes[:s], masks[:s]
        from gather_verify import kernels  # here: importing numba costs every command 0.25 s

        if kernels.enabled():  # the same events, in compiled code
            src, weight, robot, new = kernels.async_successors(
                np.ascontiguousarray(codes, dtype=np.int64),
                np.ascontiguousarray(masks, dtype=np.uint8), neighbour, _LOOK_ORDER)
            return Successors(len(codes), src, weight, robot, new, None)
        idle = codes == codes // SLOTS * SLOTS  # (floor division by a constant: the fast one)
        # per robot, its events in order as four bytes (the Looks in LOOK_ORDER, or its one
        # Move in the first), then the events of the chunk in order where a byte is set
        events = _EVENTS[np.where(idle, masks, 1 << SLOTS)].view(np.bool_)
        flat = np.flatnonzero(events)
        at = flat >> 2  # the robot's position in codes.reshape(-1)
        src = at // n
        robot = at - src * n
        code = codes.reshape(-1)[at]
        new = code + _LOOK_STEP[flat & 3]  # a Look: cell * SLOTS + 1 + k (idle: cell * SLOTS)
        move = np.flatnonzero(~idle.reshape(-1)[at])
        if len(move):
            c = code[move]
            cell = c // SLOTS
            dest = neighbour[cell, c - cell * SLOTS - 1]
            new[move] = np.where(dest >= 0, dest * SLOTS, OUTSIDE)
        weight = np.zeros(len(flat), dtype=np.int8)
        weight[move] = 1
        return Successors(len(codes), src.astype(np.int32), weight, robot.astype(np.int32),
                          new.astype(np.int32), None)  # the compiled kernel's types
