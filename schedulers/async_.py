"""ASYNC: Look and Move are separate events per robot.

``Look(i)`` on an idle robot fixes ``pending[i]`` to any move of its move set
(a Look that ends in staying changes nothing, so it is no transition);
``Move(i)`` takes robot i to its pending destination and makes it idle. Moves
are instantaneous: the asynchrony is the stale snapshot between Look and Move.
"""

from __future__ import annotations

from collections.abc import Iterator

from schedulers.base import Event, MoveSets, State, configuration_of


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
