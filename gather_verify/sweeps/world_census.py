"""The initial configurations of a finite world, one per class under its symmetries
(SEMANTICS.md §9), and the row a sweep stores for each.

A configuration is k robots on distinct nodes and m meeting nodes (a meeting node may
hold a robot). Two configurations are one class when a symmetry of the world under the
robots' frames (:meth:`~gather_verify.worlds.base.World.symmetries`) maps one onto the
other; the class is represented by its least image (sorted node indices), so the
enumeration order is fixed.

>>> from gather_verify.worlds import finite_world
>>> [c.robots for c in world_configurations(finite_world("ring:6"), 2, 0, "all")]
[(0, 1), (0, 2), (0, 3)]
"""

from __future__ import annotations

import time
from collections.abc import Iterator
from itertools import combinations, product
from typing import Any, NamedTuple

from gather_verify.sweeps.store import report_row
from gather_verify.worlds import finite_world
from gather_verify.worlds.base import World


class WorldConfiguration(NamedTuple):
    """An initial configuration of a finite world: node indices, sorted, and the robots'
    initial colours in the same order (all 0 without lights)."""

    world: str
    robots: tuple[int, ...]
    meeting: tuple[int, ...]
    colours: tuple[int, ...] = ()


def world_configurations(world: World, k: int, m: int, frames: str, colours: int = 1
                         ) -> Iterator[WorldConfiguration]:
    """Every class of initial configurations of ``k`` robots and ``m`` meeting nodes (and,
    with ``colours`` K > 1, every initial colouring of the robots), its least member, in
    lexicographic order."""
    if k > world.size:
        return
    for robots in combinations(range(world.size), k):
        for meeting in combinations(range(world.size), m):
            for lit in product(range(colours), repeat=k):
                me = (tuple(zip(robots, lit, strict=True)), meeting)
                if world.canonical(robots, meeting, frames, colours=lit) == me:
                    yield WorldConfiguration(world.name, robots, meeting,
                                             lit if colours > 1 else ())


def world_key(world: World, c: WorldConfiguration) -> str:
    """The stored key of a configuration: its robots and meeting nodes as the world writes
    them."""
    robots = " ".join(world.format_node(v) for v in c.robots)
    meeting = " ".join(world.format_node(v) for v in c.meeting)
    lit = "|" + " ".join(map(str, c.colours)) if c.colours else ""
    return f"{world.name}|{robots}|{meeting}{lit}"


def verify_world_one(settings: Any, index: int, c: WorldConfiguration) -> dict[str, Any]:
    """Check one configuration of a finite world; the row the store keeps (``class`` is the
    world's name, so a sweep over several sizes has a line per size)."""
    from gather_verify.world_check import run_world_check

    started = time.perf_counter()
    world = finite_world(c.world)
    report = run_world_check(
        world, list(c.robots), list(c.meeting), settings.algorithm, settings.scheduler,
        task=settings.task, properties=list(settings.properties) or None,
        detection=settings.detection, frames=settings.frames, visibility=settings.visibility,
        lights=settings.lights, colours=list(c.colours) if c.colours else None,
        reduction=settings.reduction, max_states=settings.max_states,
        max_seconds=settings.max_seconds,
        **({} if settings.max_memory_mb is None else {"max_memory_mb": settings.max_memory_mb}))
    robots = report["robots"] if not c.colours else [
        [v, colour] for v, colour in zip(report["robots"], c.colours, strict=True)]
    return report_row(report, key=world_key(world, c), index=index, robots=robots,
                      meeting_nodes=report["meeting_nodes"], class_=world.name,
                      n=len(c.robots), max_moves=None, D=None, ratio=None, cause=None,
                      seconds=time.perf_counter() - started)
