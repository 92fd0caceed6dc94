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
from schedulers.base import (
    Event,
    Frontier,
    MoveSets,
    Scheduler,
    State,
    Successors,
    configuration_of,
    initial_state,
)
from schedulers.centralized import Centralized
from schedulers.fsync import FSync
from schedulers.phases import PhaseScheduler, phase_scheduler
from schedulers.round_robin import RoundRobin
from schedulers.ssync import SSync

SCHEDULERS: dict[str, type[Scheduler]] = {
    "fsync": FSync, "ssync": SSync, "async": Async, "centralized": Centralized,
    "round-robin": RoundRobin,
    "async-lc-atomic": phase_scheduler("async-lc-atomic"),
    "async-lc-strict": phase_scheduler("async-lc-strict"),
    "async-cm-atomic": phase_scheduler("async-cm-atomic"),
    "async-move-atomic": phase_scheduler("async-move-atomic"),
    "async-regular": phase_scheduler("async-regular"),
    "async-safe": phase_scheduler("async-safe"),
    "async-move-regular": phase_scheduler("async-move-regular"),
    "async-move-safe": phase_scheduler("async-move-safe"),
}
"""Every scheduler by name, in the order the CLI and the scenario loader list them: a new
scheduler is one module implementing :class:`Scheduler` and one line here."""


def plane_schedulers() -> tuple[str, ...]:
    """The schedulers that keep no state of their own (the Z² engines run them through
    ``successors``; a ``stateful`` one, round-robin, through its state; a ``phased`` one,
    :mod:`schedulers.phases`, runs on the finite worlds and the rendezvous world only)."""
    return tuple(name for name, cls in SCHEDULERS.items()
                 if not getattr(cls, "stateful", False) and not getattr(cls, "phased", False))


def get_scheduler(name: str) -> Scheduler:
    """The scheduler called ``name`` (a key of :data:`SCHEDULERS`), with its options:
    ``round-robin:order=2 0 1``."""
    base, _, rest = name.partition(":")
    if base not in SCHEDULERS:
        raise InvalidInput(f"unknown scheduler {name!r}: use one of {', '.join(SCHEDULERS)}")
    if not rest:
        return SCHEDULERS[base]()
    key, eq, value = rest.partition("=")
    if base != "round-robin" or key.strip() != "order" or not eq:
        raise InvalidInput(f"scheduler {name!r}: only round-robin takes an option, order=...")
    return SCHEDULERS[base](value)  # type: ignore[call-arg]


def not_phased(name: str, where: str) -> None:
    """InvalidInput (one line) when ``name`` is a phase scheduler (:mod:`schedulers.phases`),
    which ``where`` does not run."""
    base = name.partition(":")[0]
    if getattr(SCHEDULERS.get(base), "phased", False):
        raise InvalidInput(f"scheduler {base} is one of §13's phase schedulers: it runs on the "
                           f"finite worlds (check --world ring:N ...) and the rendezvous "
                           f"world, not {where}")


def as_scheduler(scheduler: str | Scheduler) -> Scheduler:
    """``scheduler`` itself, or the one its name names (:func:`get_scheduler`): a check
    resolves its scheduler once, at the edge, and the engines take the object (or a name,
    for their other callers).

    >>> s = get_scheduler("ssync")
    >>> as_scheduler(s) is s, as_scheduler("ssync").name
    (True, 'ssync')
    """
    return get_scheduler(scheduler) if isinstance(scheduler, str) else scheduler


__all__ = ["PhaseScheduler", "as_scheduler", "not_phased", "plane_schedulers", "Async", "Event", "FSync", "Frontier", "MoveSets", "SCHEDULERS", "SSync", "Scheduler",
           "State", "Successors", "configuration_of", "get_scheduler", "initial_state"]
