"""A luminous sweep of the paper's world: every configuration of the census with its initial
colourings, and the row the store keeps for each (SEMANTICS.md §10).

Without ``--initial-colours all`` every robot starts at colour 0: one item per configuration.
With it, every colouring of the robots up to the configuration's own symmetries: a colouring
and its image under an automorphism of the configuration (translation and an element of the
robots' frame group that maps its robots and meeting nodes onto themselves) are one class,
represented by its least member (colours listed as the sorted robots, compared as tuples).
Such a pair has the same verdict: the automorphism maps every execution of one onto an
execution of the other. The union engine encodes no colours: each item is checked on its own
(:func:`gather_verify.plane_check.run_check`), by the bulk engine where it can run it.

>>> from gather_verify.model.configuration import Configuration
>>> line = Configuration([(0, 0), (2, 0)], [(1, 0)])  # a mirror swaps its two robots
>>> [lit.colours for lit in lit_configurations(line, "k", 2, "all", every=True)]
[(0, 0), (0, 1), (1, 1)]
>>> [lit.colours for lit in lit_configurations(line, "k", 2, "compass", every=True)]
[(0, 0), (0, 1), (1, 0), (1, 1)]
"""

from __future__ import annotations

import time
from collections.abc import Iterator
from itertools import product
from typing import Any, NamedTuple

from gather_verify.errors import InvalidInput
from gather_verify.model.configuration import Configuration

MAX_COLOURINGS = 100_000
"""The most colourings of one configuration ``--initial-colours all`` enumerates (K^n)."""


class LitConfiguration(NamedTuple):
    """A configuration of Z² with its robots' initial colours (in the order of its sorted
    robots) and its stored key."""

    configuration: Configuration
    colours: tuple[int, ...]
    key: str
    every: bool
    """Whether the sweep enumerates every colouring (its rows then store each robot with its
    colour, as a finite world's do)."""


def check_colourings(colours: int, robots: int) -> None:
    """Refuse, in one line, a sweep of more initial colourings than :data:`MAX_COLOURINGS`."""
    if colours ** robots > MAX_COLOURINGS:
        raise InvalidInput(f"--initial-colours all: {colours}^{robots} colourings per "
                           f"configuration, more than {MAX_COLOURINGS:,}: fewer colours or "
                           "robots")


def colour_symmetries(c: Configuration, frames: str) -> list[tuple[int, ...]]:
    """The automorphisms of ``c`` in the frame group of ``frames``, each as the permutation
    of robot indices (sorted robots) it makes."""
    from gather_verify.model.symmetry import configuration_automorphisms
    from gather_verify.model.view import FRAME_SETS

    index = {v: i for i, v in enumerate(c.robots)}
    return [tuple(index[a(v)] for v in c.robots) for a in configuration_automorphisms(c)
            if a.g in FRAME_SETS[frames]]


def lit_configurations(c: Configuration, key: str, colours: int, frames: str, every: bool
                       ) -> Iterator[LitConfiguration]:
    """``c`` (stored under ``key``) with all robots at colour 0, or with ``every`` each class
    of its colourings in ``colours`` colours, least member first, in lexicographic order."""
    if not every:
        yield LitConfiguration(c, (0,) * c.n, key, False)
        return
    moves = colour_symmetries(c, frames)
    for lit in product(range(colours), repeat=c.n):
        images = []
        for perm in moves:
            image = [0] * c.n
            for i, j in enumerate(perm):
                image[j] = lit[i]
            images.append(tuple(image))
        if all(lit <= image for image in images):
            yield LitConfiguration(c, lit, f"{key}|{' '.join(map(str, lit))}", True)


def verify_lit_one(settings: Any, index: int, lit: LitConfiguration,
                   engine: str = "auto") -> dict[str, Any]:
    """Classify and check one configuration with its initial colours (``engine`` as
    ``run_check`` takes it: the bulk engine where it can); the row the store keeps (robots
    as ``[node, colour]`` with ``every``)."""
    from gather_verify.plane_check import run_check
    from gather_verify.sweeps.store import check_row

    started = time.perf_counter()
    c = lit.configuration
    report = run_check(c, **settings.check_options(), lights=settings.lights,
                       colours=list(lit.colours), engine=engine)
    robots = [[list(r), colour] if lit.every else list(r)
              for r, colour in zip(c.robots, lit.colours, strict=True)]
    return check_row(report, lit.key, index, robots, c, time.perf_counter() - started)
