"""States, events and the scheduler protocol shared by FSYNC, SSYNC and ASYNC."""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator, Mapping
from dataclasses import dataclass
from typing import Protocol

from gather_verify.model.geometry import Node

Robot = tuple[Node, Node | None]
"""One robot: its node and its pending destination (None when idle)."""
State = tuple[Robot, ...]
"""Per robot index: (node, pending). Identities are kept; sort for anonymity."""
MoveSets = Callable[[tuple[Node, ...]], Mapping[Node, frozenset[Node]]]
"""Robot nodes (sorted) -> move set per occupied node (global destinations)."""


@dataclass(frozen=True)
class Event:
    """What one transition did.

    ``kind`` is ``round`` (FSYNC/SSYNC: ``robots`` looked and moved at once),
    ``look`` (ASYNC: one robot looked and fixed a pending destination) or
    ``move`` (ASYNC: one robot moved to its pending destination). ``moves``
    lists ``(robot, source, destination)`` for every robot that changed node
    or, for ``look``, the destination it fixed.
    """

    kind: str
    robots: tuple[int, ...]
    moves: tuple[tuple[int, Node, Node], ...]

    @property
    def distance(self) -> int:
        """Edges traversed in this transition (0 for a look)."""
        if self.kind == "look":
            return 0
        return sum(1 for _, a, b in self.moves if a != b)

    def to_json(self) -> dict[str, object]:
        return {"kind": self.kind, "robots": list(self.robots),
                "moves": [[i, list(a), list(b)] for i, a, b in self.moves]}


class Scheduler(Protocol):
    name: str

    def successors(self, state: State, move_sets: MoveSets) -> Iterator[tuple[Event, State]]:
        """Every (event, successor) the adversary can choose from ``state``."""
        ...


def initial_state(robots: Iterable[Node]) -> State:
    """All robots idle on their nodes, in the given order (robot i = i-th node)."""
    return tuple((r, None) for r in robots)


def configuration_of(state: State) -> tuple[Node, ...]:
    """The robot nodes of a state, sorted (what every robot sees)."""
    return tuple(sorted(node for node, _ in state))
