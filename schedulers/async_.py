"""ASYNC: Look and Move are separate events per robot.

``Look(i)`` on an idle robot fixes ``pending[i]`` to any move of its move set
(a Look that ends in staying changes nothing, so it is no transition);
``Move(i)`` takes robot i to its pending destination and makes it idle. Moves
are instantaneous: the asynchrony is the stale snapshot between Look and Move.
"""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np

from gather_verify.geometry import STEPS
from schedulers.base import Event, MoveSets, State, configuration_of

LOOK_ORDER = tuple(sorted(range(len(STEPS)), key=STEPS.__getitem__))
"""Step indices in the order :meth:`Async.successors` yields Looks (sorted destinations)."""


class Async:
    name = "async"

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

    def bulk_successors(self, codes: np.ndarray, masks: np.ndarray, neighbour: np.ndarray
                        ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """:meth:`successors` for many states at once, in the same order.

        ``codes[s, i]`` is robot i of state s as ``cell * 5 + d`` (d = 0 idle, else 1 +
        the index in ``STEPS`` of its pending step), ``masks[s, i]`` its move set as
        bits (bit k: ``STEPS[k]`` allowed), ``neighbour[cell, k]`` the cell one
        ``STEPS[k]`` away (-1 outside the region). Returns, one entry per event
        (each changes exactly one robot): the state index, the robot, its new code
        (-1 when the robot moves out of the region) and the edges traversed.
        """
        s, n = codes.shape
        cell, d = codes // 5, codes % 5
        idle = d == 0
        valid = np.zeros((s, n, 4), dtype=bool)
        new = np.empty((s, n, 4), dtype=np.int64)
        for slot, k in enumerate(LOOK_ORDER):
            valid[:, :, slot] = idle & ((masks >> k) & 1).astype(bool)
            new[:, :, slot] = cell * 5 + (k + 1)
        moving = ~idle
        dest = neighbour[cell, np.maximum(d - 1, 0)]
        valid[:, :, 0] |= moving
        new[:, :, 0] = np.where(moving, np.where(dest >= 0, dest * 5, -1), new[:, :, 0])
        flat = np.flatnonzero(valid.reshape(-1))
        src, robot = flat // (4 * n), (flat // 4) % n
        return src, robot, new.reshape(-1)[flat], moving[src, robot].astype(np.int8)
