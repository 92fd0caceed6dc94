"""Worlds: the graphs the robots live on, by name (SEMANTICS.md §9).

Every world offers the edge the same face (:class:`~gather_verify.worlds.base.AnyWorld`):
how a node is written, the frames of a view, the canonical form of a configuration, its
drawing, and which entry of check, sweep and synthesize runs it (``entry``). ``grid``
is the paper's infinite grid Z² (:class:`~gather_verify.worlds.plane.Plane`, run by the
Z² engines); every world ``kind:ARG`` is a finite
:class:`~gather_verify.worlds.base.World`. A new world is one module and one line in
:data:`NAMED_WORLDS` (a world with no argument) or :data:`WORLDS` (``kind -> factory of
the text after the colon``).

>>> get_world("ring:9").name, get_world("torus:3x4").size, get_world("grid:2x3").size
('ring:9', 12, 6)
>>> get_world("grid").entry, get_world("grid:2x3").entry
('plane', 'finite')
>>> get_world("ring:2")  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
gather_verify.errors.InvalidInput: world size 2 is out of range [3, 10000] (ring:N: a ring has at least 3 nodes)
"""

from __future__ import annotations

from collections.abc import Callable

from gather_verify.errors import InvalidInput
from gather_verify.worlds.base import FINITE, PLANE, AnyWorld, World
from gather_verify.worlds.graph import FileGraph
from gather_verify.worlds.grid import FiniteGrid
from gather_verify.worlds.plane import Plane
from gather_verify.worlds.ring import Ring, parse_size
from gather_verify.worlds.torus import Torus

__all__ = ["DEFAULT_WORLD", "FINITE", "NAMED_WORLDS", "PLANE", "WORLDS", "AnyWorld", "World",
           "entry_of", "finite_world", "get_world", "world_specs"]

NAMED_WORLDS: dict[str, Callable[[], AnyWorld]] = {
    "grid": Plane,
}
"""The worlds named without an argument."""

WORLDS: dict[str, Callable[[str], World]] = {
    "grid": FiniteGrid.from_spec,
    "ring": Ring.from_spec,
    "torus": Torus.from_spec,
    "graph": FileGraph.from_spec,
}
"""The finite worlds, ``kind:ARG``: kind -> factory of the text after the colon."""

DEFAULT_WORLD = "grid"
"""The world a command runs when none is named: the paper's."""


def get_world(spec: str) -> AnyWorld:
    """The world ``spec`` names: ``grid`` (Z²), or a finite world (``ring:9``,
    ``grid:4x4``, ``torus:3x4``, ``graph:FILE``)."""
    name = spec.strip()
    if name in NAMED_WORLDS:
        return NAMED_WORLDS[name]()
    return finite_world(name)


def finite_world(spec: str) -> World:
    """The finite world ``spec`` names, for what runs only on one (one line for any other
    spec)."""
    kind, sep, arg = spec.strip().partition(":")
    if kind not in WORLDS and kind not in NAMED_WORLDS:
        raise InvalidInput(f"unknown world {spec!r}: use "
                           f"{', '.join([*NAMED_WORLDS, *(k + ':...' for k in WORLDS)])}")
    if kind not in WORLDS or not sep or not arg:
        raise InvalidInput(f"world {kind} needs a size or file: {kind}:...")
    return WORLDS[kind](arg)


def entry_of(spec: str | None) -> str:
    """Which entry of check, sweep and synthesize runs the world ``spec`` names (None: the
    :data:`DEFAULT_WORLD`): that world's ``entry``, asked without building a finite world
    (every world of :data:`WORLDS` is a :class:`World`, so a graph file need not be at hand
    to know it), and without checking the argument (the entry does).

    >>> entry_of(None), entry_of(" grid "), entry_of("ring:5-9"), entry_of("graph:lost.gml")
    ('plane', 'plane', 'finite', 'finite')
    """
    name = (DEFAULT_WORLD if spec is None else spec).strip()
    if name in NAMED_WORLDS:
        return NAMED_WORLDS[name]().entry
    return World.entry


def world_specs(spec: str) -> list[str]:
    """A range of sizes, ``ring:5-9`` -> ``ring:5 .. ring:9``; anything else as it is."""
    kind, _, arg = spec.strip().partition(":")
    low, dash, high = arg.partition("-")
    if kind == "ring" and dash:
        first, last = (parse_size(x, "ring:A-B: a ring has at least 3 nodes", 3) for x in (low, high))
        if first > last:
            raise InvalidInput(f"world range {spec!r} is empty")
        return [f"ring:{k}" for k in range(first, last + 1)]
    return [spec.strip()]
