"""Algorithms and their registry: names used by the CLI and scenario files.

A new algorithm is one module and one line in ``REGISTRY``. A name may carry
options after a colon, ``name:key=value,key=value``; the factory receives them
as keyword arguments (strings).

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

from collections.abc import Callable

from gather_verify.algorithms.base import Algorithm, AlgorithmError, Unhandled, target_of
from gather_verify.algorithms.go_to_target import GoToTarget
from gather_verify.algorithms.nearest_centre import NearestCentre
from gather_verify.algorithms.paper import PaperAlgorithm
from gather_verify.algorithms.random_equivariant import RandomEquivariant
from gather_verify.errors import InvalidInput

REGISTRY: dict[str, Callable[..., Algorithm]] = {
    "go-to-target": GoToTarget,
    "nearest-centre": NearestCentre,
    "paper": PaperAlgorithm,
    "random": RandomEquivariant,
}


def register(name: str, factory: Callable[..., Algorithm]) -> None:
    """Make ``factory`` available under ``name`` (for user algorithms)."""
    REGISTRY[name] = factory


def parse_name(spec: str) -> tuple[str, dict[str, str]]:
    """Split ``name:key=value,...`` into the name and its options."""
    name, _, rest = spec.partition(":")
    options: dict[str, str] = {}
    for item in filter(None, rest.split(",")):
        key, eq, value = item.partition("=")
        if not eq or not key:
            raise InvalidInput(f"bad algorithm option {item!r} in {spec!r}: expected key=value")
        options[key.strip()] = value.strip()
    return name.strip(), options


_INSTANCES: dict[tuple[str, Callable[..., Algorithm]], Algorithm] = {}
"""One instance per name and factory in a process: algorithms are pure functions of the view,
so every check of a sweep shares the caches an algorithm keeps (the paper's plans)."""


def get_algorithm(spec: str) -> Algorithm:
    """The algorithm registered under ``spec`` (with its options)."""
    name, options = parse_name(spec)
    if name not in REGISTRY:
        _register_optional(name)
    if name not in REGISTRY:
        raise InvalidInput(f"unknown algorithm {name!r}: use one of {', '.join(sorted(REGISTRY))}")
    factory = REGISTRY[name]
    algorithm = _INSTANCES.get((spec, factory))
    if algorithm is None:
        try:
            algorithm = factory(**options)
        except TypeError as error:
            raise InvalidInput(f"bad options for algorithm {name!r}: {error}") from None
        if options:
            algorithm.name = spec
        _INSTANCES[spec, factory] = algorithm
    return algorithm


def _register_optional(name: str) -> None:
    """The deliberately broken algorithms (``broken-*``, for tests and demos) are registered
    on first use of one of their names."""
    if name.startswith("broken-"):
        from gather_verify.algorithms.broken import BROKEN

        REGISTRY.update(BROKEN)


__all__ = ["Algorithm", "AlgorithmError", "REGISTRY", "Unhandled", "get_algorithm", "register",
           "target_of"]
