"""Schedulers: the adversary that activates robots and resolves their choices.

SEMANTICS.md §4. A state holds, per robot (identities kept), its node and its
pending destination (``None`` when idle). A scheduler maps a state to its
successors, each with the event that led there; it asks the algorithm only
through ``move_sets(configuration)``, so it never knows which algorithm runs,
and the explorer never knows which scheduler it drives.

>>> from gather_verify.algorithms import get_algorithm
>>> from gather_verify.model.configuration import Configuration
>>> from gather_verify.algorithms.moves import move_sets
>>> algo, m = get_algorithm("go-to-target"), frozenset({(2, 2)})
>>> ms = lambda robots: move_sets(algo, Configuration.trusted(tuple(sorted(robots)), m))
>>> s0 = initial_state([(0, 0), (3, 1), (1, 4)])
>>> len(list(get_scheduler("fsync").successors(s0, ms)))
8
"""

from __future__ import annotations

from gather_verify.errors import InvalidInput
from schedulers.async_ import Async
from schedulers.base import Event, MoveSets, Scheduler, State, configuration_of, initial_state
from schedulers.fsync import FSync
from schedulers.ssync import SSync

SCHEDULERS: dict[str, type] = {"fsync": FSync, "ssync": SSync, "async": Async}


def get_scheduler(name: str) -> Scheduler:
    """The scheduler called ``name`` (``fsync``, ``ssync`` or ``async``)."""
    if name not in SCHEDULERS:
        raise InvalidInput(f"unknown scheduler {name!r}: use one of {', '.join(SCHEDULERS)}")
    return SCHEDULERS[name]()


__all__ = ["Async", "Event", "FSync", "MoveSets", "SCHEDULERS", "SSync", "Scheduler", "State",
           "configuration_of", "get_scheduler", "initial_state"]
