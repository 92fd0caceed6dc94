"""The search region of the paper's world (Z²) and the one rule by which it grows.

Z² is infinite, so a search runs in a box: the MER of the initial configuration grown by a
*margin*, closed under the symmetries the search uses (:func:`region_box`). A search that
leaves the box stops (``Stop.REGION``, never VERIFIED), and ``run_check`` runs it again in a
larger box. :class:`RegionPolicy` is that rule, read by every part that needs it: the
default margin of :class:`~gather_verify.engine.encoding.Limits`, the growth loop of
``plane_check.run_check``, and the margin a configuration's own search would end with, which the
union engine (:mod:`gather_verify.engine.union`, :mod:`gather_verify.sweeps.mclass`)
computes without running it (:meth:`RegionPolicy.needed`).

A finite world (``ring:N``, ``grid:WxH``, ...) has no region: its search holds the whole
graph from the start, so it never stops for the region and reads no policy.

>>> PLANE.margins
(2, 4, 8, 16, 32)
>>> from gather_verify.model.configuration import Configuration
>>> c = Configuration([(0, 0), (1, 0)], [(1, 1)])
>>> PLANE.region(c, 2)
(-2, -2, 3, 3)
>>> PLANE.needed(c, (), (-3, 0, 1, 1)), PLANE.needed(c, (), (-40, 0, 1, 1))
(4, None)
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property
from typing import Any

from gather_verify.model import geometry
from gather_verify.model.configuration import Configuration
from gather_verify.model.symmetry import Automorphism

Box = tuple[int, int, int, int]


def region_box(initial: Configuration, margin: int,
               group: Sequence[Automorphism] = ()) -> Box:
    """The MER of ``initial`` grown by ``margin``, closed under ``group``."""
    x0, y0, x1, y1 = initial.mer()
    corners = [(x0 - margin, y0 - margin), (x1 + margin, y1 + margin)]
    images = [a(v) for a in group for v in corners] + corners
    return geometry.bounding_box(images)


@dataclass(frozen=True)
class RegionPolicy:
    """Where a search starts (margin ``initial``) and how its region grows: the margin
    doubles, up to ``maximum`` (the last margin tried)."""

    initial: int
    maximum: int

    def __post_init__(self) -> None:
        if not 0 < self.initial <= self.maximum:
            raise ValueError(f"a region policy needs 0 < initial <= maximum, not {self}")

    def grow(self, margin: int) -> int | None:
        """The margin tried after ``margin``: doubled, at most ``maximum``; None past it."""
        return None if margin >= self.maximum else min(2 * margin, self.maximum)

    @cached_property
    def margins(self) -> tuple[int, ...]:
        """Every margin a growing search tries, in turn."""
        out = [self.initial]
        while (bigger := self.grow(out[-1])) is not None:
            out.append(bigger)
        return tuple(out)

    @staticmethod
    def region(initial: Configuration, margin: int, group: Sequence[Automorphism] = ()) -> Box:
        """The region of a search from ``initial`` with ``margin`` (:func:`region_box`)."""
        return region_box(initial, margin, group)

    def needed(self, initial: Configuration, group: Sequence[Automorphism],
               box: Sequence[int] | Any) -> int | None:
        """The margin a growing search from ``initial`` ends with when every node it reaches
        lies in ``box`` (x0, y0, x1, y1): the least of :attr:`margins` whose region holds
        ``box``; None when none does. A region is the margin-0 region grown by the margin
        (an isometry maps a box grown by ``k`` onto its image grown by ``k``), so one region
        box answers for every margin."""
        x0, y0, x1, y1 = (int(v) for v in box)
        a0, b0, a1, b1 = region_box(initial, 0, group)
        need = max(a0 - x0, b0 - y0, x1 - a1, y1 - b1)
        return next((margin for margin in self.margins if margin >= need), None)


PLANE = RegionPolicy(initial=2, maximum=32)
"""The paper's world: margin 2, doubled while the region stops a search, up to 32."""
DEFAULT_MARGIN = PLANE.initial
"""The margin of a search given none (:class:`~gather_verify.engine.encoding.Limits`)."""
AUTO_MARGIN_MAX = PLANE.maximum
"""The largest margin tried when the margin is left to grow by itself."""
