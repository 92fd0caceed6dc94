"""Algorithms and their registry: names used by the CLI and scenario files.

A new algorithm of the project is one module and one line in ``REGISTRY``. A
name may carry options after a colon, ``name:key=value,key=value``; the factory
receives them as keyword arguments (strings). An algorithm of your own needs no
edit here: ``my_alg.py:MyAlgorithm``, ``package.module:MyAlgorithm`` or an
entry point (:mod:`gather_verify.algorithms.loading`, docs/algorithms.md).

>>> get_algorithm("go-to-target").name
'go-to-target'
>>> get_algorithm("paper:alpha=mer_f").name
'paper:alpha=mer_f'
>>> get_algorithm("random:seed=7").name  # an equivariant algorithm answering at random
'random:seed=7'
>>> get_algorithm("nope")  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
gather_verify.errors.InvalidInput: unknown algorithm 'nope': use one of ...
"""

from __future__ import annotations

import importlib
from collections.abc import Callable

from gather_verify.algorithms.base import (
    Algorithm,
    AlgorithmCrash,
    AlgorithmError,
    Unhandled,
    target_of,
)
from gather_verify.algorithms.beacon import Beacon
from gather_verify.algorithms.bounce import Bounce
from gather_verify.algorithms.go_to_target import GoToTarget
from gather_verify.algorithms.inchworm import RingInchworm
from gather_verify.algorithms.loading import (
    absolute_spec,
    entry_point_factory,
    entry_point_names,
    instantiate,
    load_external,
    parse_options,
    split_external,
)
from gather_verify.algorithms.nearest_centre import NearestCentre
from gather_verify.algorithms.random_equivariant import RandomEquivariant
from gather_verify.algorithms.ring_exploration import RingExplore
from gather_verify.algorithms.ring_gathering import RingGather
from gather_verify.errors import InvalidInput
from gather_verify.recent import most_recent


def paper_algorithm(**options: str) -> Algorithm:
    """The paper's ``Gathering()`` (:class:`gather_verify.paper.algorithm.PaperAlgorithm`),
    imported on first use: the paper's theory is a package of its own, above this layer."""
    return importlib.import_module("gather_verify.paper.algorithm").PaperAlgorithm(**options)


REGISTRY: dict[str, Callable[..., Algorithm]] = {
    "beacon": Beacon,
    "bounce": Bounce,
    "go-to-target": GoToTarget,
    "nearest-centre": NearestCentre,
    "paper": paper_algorithm,
    "random": RandomEquivariant,
    "ring-inchworm": RingInchworm,
    "ring-explore": RingExplore,
    "ring-gather": RingGather,
}


def register(name: str, factory: Callable[..., Algorithm]) -> None:
    """Make ``factory`` available under ``name`` (for user algorithms)."""
    REGISTRY[name] = factory


def parse_name(spec: str) -> tuple[str, dict[str, str]]:
    """Split ``name:key=value,...`` into the name and its options."""
    name, _, rest = spec.partition(":")
    return name.strip(), parse_options(rest, spec)


_INSTANCES: dict[tuple[str, object], Algorithm] = {}
"""One instance per name and factory in a process: algorithms are pure functions of the view,
so every check of a sweep shares the caches an algorithm keeps (the paper's plans)."""
INSTANCES_KEPT = 4
"""Instances kept at once, the most recently used: a sweep under every reading runs 16 or 64
algorithms in one worker, and the plans of all of them would fill its memory limit (every
check after that would stop INCOMPLETE (memory))."""


def get_algorithm(spec: str) -> Algorithm:
    """The algorithm ``spec`` names (with its options): registered, in a file or module, or
    an entry point of an installed package (:mod:`gather_verify.algorithms.loading`)."""
    external = split_external(spec)
    if external is not None:
        spec = absolute_spec(spec)
        factory, _ = load_external(spec)
        options, named = external[2], True
    else:
        name, options = parse_name(spec)
        if name not in REGISTRY:
            _register_optional(name)
        factory, named = REGISTRY.get(name), bool(options)
        if factory is None:
            factory, named = entry_point_factory(name), True
        if factory is None:
            known = sorted({*REGISTRY, *entry_point_names()})
            raise InvalidInput(f"unknown algorithm {name!r}: use one of {', '.join(known)}, "
                             "or FILE.py:NAME or package.module:NAME")

    def make() -> Algorithm:
        algorithm = instantiate(factory, options, spec)
        if named and getattr(algorithm, "name", None) != spec:
            try:  # the spec, so a trace or a stored row names what loads it again
                algorithm.name = spec
            except AttributeError:
                raise InvalidInput(f"algorithm {spec!r}: cannot set its name attribute") from None
        return algorithm

    return most_recent(_INSTANCES, (spec, factory), make, INSTANCES_KEPT)


def _register_optional(name: str) -> None:
    """The deliberately broken algorithms (``broken-*``, for tests and demos) are registered
    on first use of one of their names."""
    if name.startswith("broken-"):
        from gather_verify.algorithms.broken import BROKEN

        REGISTRY.update(BROKEN)


__all__ = ["Algorithm", "AlgorithmCrash", "AlgorithmError", "REGISTRY", "Unhandled", "get_algorithm", "register",
           "target_of"]
