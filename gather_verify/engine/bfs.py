"""The one reference search: breadth-first over any world's state space (SEMANTICS.md §4).

Stateright's shape: a world hands the search a :class:`Model` of its state space (the
initial states, the key of a state under the reductions, the events of a state or why it
cannot be expanded) and this one loop searches it, whatever the world: the paper's Z²
(:mod:`gather_verify.engine.explore`), the finite worlds
(:mod:`gather_verify.engine.world_search`), and any world that brings its own model. The
loop owns the order (breadth-first, so a state's parent is on a shortest path to it), the
ids, the parents and the limits; the model keeps what its properties read of each state
and edge, through the hooks the loop calls.

The limits bound every step: the clock is read at every state, and every 1,024 events of
one state the clock and the states limit again (one state can have very many events: a
round of many robots is a product of their choices), so a search stops within one state's
worth of a limit; memory is read every 4,096 states.

>>> class Counter:  # the states 0..4, each with an edge to the next
...     def seeds(self): return [0]
...     def key(self, state): return state
...     def stored(self, state, key): return state
...     def state(self, sid, stored): return stored
...     def expand(self, sid, state): return [("step", state + 1)] if state < 4 else []
...     def inside(self, succ): return True
...     def transition(self, sid, event, succ): pass
...     def discovered(self, did, succ): pass
...     def edge(self, sid, did, event, succ, state): pass
...     def expanded(self, sid): return None
>>> walked = breadth_first(Counter())
>>> walked.stored, walked.parents.tolist(), walked.transitions, walked.stopped
([0, 1, 2, 3, 4], [-1, 0, 1, 2, 3], 4, None)
"""

from __future__ import annotations

import time
from array import array
from collections.abc import Hashable, Iterable, Sequence
from dataclasses import dataclass
from typing import Any, Protocol

from gather_verify.engine.encoding import NO_LIMITS, Limits, Stop, rss_mb
from gather_verify.progress import PROGRESS

EVENT_GRAIN = 1023
"""The limits are read again every 1,024 events of one state (``k & EVENT_GRAIN == 0``)."""
EVENT_CUT = EVENT_GRAIN + 1
"""So a state's expansion stops once the states stored pass ``max_states`` by at most this
many (a bulk engine weighs a round's events against the same bound)."""
MEMORY_GRAIN = 4095
"""The memory is read every 4,096 states."""


class Model(Protocol):
    """A world's state space as :func:`breadth_first` reads it. A *state* is whatever the
    world's scheduler steps (concrete: robots with identities); the search stores, per id,
    what :meth:`stored` keeps (the state itself, or its key when the key decodes back to a
    concrete member of the class) and expands what :meth:`state` gives back."""

    def seeds(self) -> Sequence[Any]:
        """The concrete initial states, in order (one per start of a scheduler that keeps
        a state of its own; several roots where the world has several)."""
        ...

    def key(self, state: Any) -> Hashable:
        """The state's key under the reductions: one key per orbit."""
        ...

    def stored(self, state: Any, key: Any) -> Any:
        """What the search keeps of a state met first (the state, or its key)."""
        ...

    def state(self, sid: int, stored: Any) -> Any:
        """The concrete state expanded for id ``sid``, from what was kept."""
        ...

    def expand(self, sid: int, state: Any) -> Iterable[tuple[Any, Any]] | str:
        """The events of ``state`` as ``(event, successor)``, in the scheduler's order; or
        why it cannot be expanded (a halting property's name: the search stops there)."""
        ...

    def inside(self, succ: Any) -> bool:
        """Whether every robot of ``succ`` is inside the search region (False: the search
        stops, ``region``; a finite world is all region)."""
        ...

    def transition(self, sid: int, event: Any, succ: Any) -> None:
        """A transition of the state being expanded, before its target's key is looked up."""
        ...

    def discovered(self, did: int, succ: Any) -> None:
        """A state met for the first time, given id ``did``."""
        ...

    def edge(self, sid: int, did: int, event: Any, succ: Any, state: Any) -> None:
        """The transition ``event`` from ``sid`` (the concrete ``state``) to id ``did``."""
        ...

    def expanded(self, sid: int) -> str | None:
        """The state ``sid`` is expanded: a reason to stop here (None: go on)."""
        ...


@dataclass
class Walked:
    """What :func:`breadth_first` found besides what the model kept: per id what was stored
    and its BFS parent (-1 for a seed), the concrete seeds kept (one per key), the
    transitions, why it stopped (None: every reachable state expanded) and the peak memory."""

    stored: list[Any]
    parents: array
    seeds: list[Any]
    transitions: int
    stopped: str | None
    peak_rss_mb: float
    seconds: float


def breadth_first(model: Model, limits: Limits = NO_LIMITS) -> Walked:
    """Breadth-first search of every state of ``model`` reachable from its seeds, within
    ``limits`` (see the module)."""
    started = time.perf_counter()
    stored: list[Any] = []
    visited: dict[Hashable, int] = {}
    seeds = []
    for seed in model.seeds():
        key = model.key(seed)
        if visited.setdefault(key, len(stored)) == len(stored):
            stored.append(model.stored(seed, key))
            seeds.append(seed)
    parents = array("q", [-1] * len(stored))
    transitions = 0
    stopped: str | None = None
    peak = rss_mb()
    sid = 0
    PROGRESS.states = len(stored)
    while sid < len(stored):
        if time.perf_counter() - started > limits.max_seconds:
            stopped = Stop.TIME
            break
        if sid & MEMORY_GRAIN == 0:
            peak = max(peak, rss_mb())
            if peak > limits.max_memory_mb:
                stopped = Stop.MEMORY
                break
        state = model.state(sid, stored[sid])
        events = model.expand(sid, state)
        if isinstance(events, str):
            stopped = events
            break
        for k, (event, succ) in enumerate(events, 1):
            transitions += 1
            if k & EVENT_GRAIN == 0:
                stopped = _inside_limit(limits, started, len(stored))
                if stopped:  # a round of very many events: its events cut here
                    break
            if not model.inside(succ):
                stopped = Stop.REGION
                break
            model.transition(sid, event, succ)
            key = model.key(succ)
            did = visited.get(key)
            if did is None:
                did = visited[key] = len(stored)
                stored.append(model.stored(succ, key))
                parents.append(sid)
                model.discovered(did, succ)
            model.edge(sid, did, event, succ, state)
        if stopped:
            model.expanded(sid)
            break
        stopped = model.expanded(sid)
        if stopped:
            break
        sid += 1
        PROGRESS.states = len(stored)  # read by a progress line and the watchdog's report
        if len(stored) > limits.max_states:
            stopped = Stop.STATES
            break
    return Walked(stored, parents, seeds, transitions, stopped, max(peak, rss_mb()),
                  time.perf_counter() - started)


def _inside_limit(limits: Limits, started: float, stored: int) -> str | None:
    """The limit a state of very many events has passed while it is expanded, if any: a
    round of 20 robots of two moves each makes 2**20 of them."""
    if stored > limits.max_states:
        return Stop.STATES
    if time.perf_counter() - started > limits.max_seconds:
        return Stop.TIME
    if rss_mb() > limits.max_memory_mb:
        return Stop.MEMORY
    return None
