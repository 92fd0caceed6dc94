"""``explore``: one entry to both engines (the bulk engine when it can run the request,
else the reference BFS); both give the same :class:`Exploration`.

It sits above :mod:`explore` and :mod:`fast_explore` so that neither imports the other's
caller (no import cycle).

>>> from gather_verify.model.configuration import Configuration
>>> c = Configuration([(0, 0), (3, 1), (1, 4)], [(2, 2)], initial=True)
>>> e = explore(c, "go-to-target", "async", reduction=False)
>>> e.states, e.transitions, e.stopped
(2184, 7032, None)
"""

from __future__ import annotations

from dataclasses import replace

from gather_verify.algorithms import Algorithm
from gather_verify.engine import fast_explore, lit_bulk
from gather_verify.engine.explore import Exploration, explore_reference
from gather_verify.errors import InvalidInput
from gather_verify.model.configuration import Configuration
from schedulers import Scheduler

ENGINES = ("auto", "fast", "reference")


def explore(
    initial: Configuration,
    algorithm: str | Algorithm,
    scheduler: str | Scheduler,
    *,
    engine: str = "auto",
    graph: bool = True,
    memo: bool = False,
    **options: object,
) -> Exploration:
    """Every state reachable from ``initial``: the bulk engine when it supports the request
    (``engine="auto"``, the default), else the reference BFS; both give the same result.

    ``engine="fast"`` insists on the bulk engine (InvalidInput if it cannot run this
    request), ``engine="reference"`` runs :func:`explore_reference`. With ``lights`` the bulk
    engine is :func:`~gather_verify.engine.fast_explore.explore_fast` too (its face for lights
    in :mod:`~gather_verify.engine.lit_bulk`); when ``auto`` falls back to
    the reference, the result's ``engine_fallback`` says why. ``graph=False`` lets the bulk
    engine keep no edges (only states and safety witnesses; see :mod:`fast_explore`);
    ``memo=True`` lets it share configuration facts with the other searches of this
    process (sweeps). Other keyword arguments are those of :func:`explore_reference`.
    """
    if engine not in ENGINES:
        raise InvalidInput(f"unknown engine {engine!r}: use one of {', '.join(ENGINES)}")
    lights = options.get("lights")
    if lights is not None:  # luminous robots: the lit bulk engine, when it can
        if engine == "reference":
            return explore_reference(initial, algorithm, scheduler, **options)
        why = lit_bulk.unsupported(initial, scheduler, **options)
        if why is None:
            return fast_explore.explore_fast(initial, algorithm, scheduler, graph=graph,
                                             memo=memo, **options)
        if engine == "fast":
            raise InvalidInput(f"the bulk engine cannot run this request ({why}): use "
                               "--engine auto or reference")
        return replace(explore_reference(initial, algorithm, scheduler, **options),
                       engine_fallback=why)
    if engine != "reference":
        keys = ("reduction", "anonymity", "symmetry", "frames", "limits")
        if fast_explore.supports(initial, scheduler, **{k: options[k] for k in keys if k in options}):
            return fast_explore.explore_fast(initial, algorithm, scheduler, graph=graph,
                                             memo=memo, **options)
        if engine == "fast":
            raise InvalidInput("the fast engine cannot run this request (its keys do not fit 63 "
                               "bits): use engine='auto' or 'reference'")
    return explore_reference(initial, algorithm, scheduler, **options)
