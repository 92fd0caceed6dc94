"""Worlds: the graphs the robots live on, by name (SEMANTICS.md §9).

``grid`` is the paper's infinite grid Z², handled by the Z² engines; every other
world is a finite :class:`~gather_verify.worlds.base.World`. A new world is one
module and one line in :data:`WORLDS` (``kind -> factory of the text after the
colon``).

>>> get_world("ring:9").name, get_world("torus:3x4").size, get_world("grid:2x3").size
('ring:9', 12, 6)
>>> get_world("ring:2")  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
gather_verify.errors.InvalidInput: ring:2: a ring has at least 3 nodes
"""

from __future__ import annotations

from collections.abc import Callable

from gather_verify.errors import InvalidInput
from gather_verify.worlds.base import World
from gather_verify.worlds.graph import FileGraph
from gather_verify.worlds.grid import FiniteGrid
from gather_verify.worlds.ring import Ring
from gather_verify.worlds.torus import Torus

WORLDS: dict[str, Callable[[str], World]] = {
    "grid": FiniteGrid.from_spec,
    "ring": Ring.from_spec,
    "torus": Torus.from_spec,
    "graph": FileGraph.from_spec,
}

PLANE = "grid"
"""The paper's world, Z² (no size): the Z² engines run it."""


def is_plane(spec: str | None) -> bool:
    return spec is None or spec.strip() == PLANE


def get_world(spec: str) -> World:
    """The finite world ``spec`` names (``ring:9``, ``grid:4x4``, ``torus:3x4``,
    ``graph:FILE``)."""
    kind, sep, arg = spec.strip().partition(":")
    if kind not in WORLDS:
        raise InvalidInput(f"unknown world {spec!r}: use grid, {', '.join(k + ':...' for k in WORLDS)}")
    if not sep or not arg:
        raise InvalidInput(f"world {kind} needs a size or file: {kind}:...")
    return WORLDS[kind](arg)


def world_specs(spec: str) -> list[str]:
    """A range of sizes, ``ring:5-9`` -> ``ring:5 .. ring:9``; anything else as it is."""
    kind, _, arg = spec.strip().partition(":")
    low, dash, high = arg.partition("-")
    if kind == "ring" and dash and low.isdigit() and high.isdigit():
        if int(low) > int(high):
            raise InvalidInput(f"world range {spec!r} is empty")
        return [f"ring:{k}" for k in range(int(low), int(high) + 1)]
    return [spec.strip()]
