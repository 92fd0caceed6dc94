"""The one region policy (:mod:`gather_verify.engine.region`): the margins ``run_check`` tries,
the margin the union engine says a search needs, and the regions, each as the rules written
out before the policy held them."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gather_verify.engine import union
from gather_verify.engine.encoding import DEFAULT_MARGIN, Limits
from gather_verify.engine.region import PLANE, RegionPolicy, region_box
from gather_verify.model import geometry
from gather_verify.model.configuration import Configuration
from gather_verify.model.symmetry import meeting_automorphisms
from gather_verify.plane_check import AUTO_MARGIN_MAX


def doubling_loop(initial: int, maximum: int) -> list[int]:
    """The margins of ``run_check``'s growth loop as it was written before the policy."""
    margin, out = initial, [initial]
    while margin < maximum:
        margin = min(2 * margin, maximum)
        out.append(margin)
    return out


def test_the_paper_world_schedule() -> None:
    assert PLANE.margins == tuple(2 << k for k in range(5)) == union.MARGINS
    assert (PLANE.initial, PLANE.maximum) == (DEFAULT_MARGIN, AUTO_MARGIN_MAX) == (2, 32)
    assert Limits().margin == PLANE.initial
    assert list(PLANE.margins) == doubling_loop(2, 32)
    assert PLANE.grow(32) is None and PLANE.grow(16) == 32


@given(initial=st.integers(1, 50), extra=st.integers(0, 200))
def test_grow_is_the_doubling_loop(initial: int, extra: int) -> None:
    policy = RegionPolicy(initial, initial + extra)
    assert list(policy.margins) == doubling_loop(initial, initial + extra)


@pytest.mark.parametrize(("initial", "maximum"), [(0, 32), (-1, 4), (8, 4)])
def test_a_policy_that_cannot_grow_is_refused(initial: int, maximum: int) -> None:
    with pytest.raises(ValueError, match="region policy"):
        RegionPolicy(initial, maximum)


def needed_before(c: Configuration, group: list, box: list[int]) -> int | None:
    """``union.margin_needed`` as it was written before the policy."""
    x0, y0, x1, y1 = box
    a0, b0, a1, b1 = region_box(c, 0, group)
    need = max(a0 - x0, b0 - y0, x1 - a1, y1 - b1)
    return next((m for m in tuple(2 << k for k in range(5)) if m >= need), None)


nodes = st.lists(st.tuples(st.integers(-3, 3), st.integers(-3, 3)), min_size=1, max_size=4,
                 unique=True)


@settings(max_examples=200, deadline=None)
@given(robots=nodes, meeting=nodes, box=st.lists(st.integers(-40, 40), min_size=4, max_size=4),
       margin=st.integers(0, 40))
def test_needed_and_region_are_the_old_rules(robots: list, meeting: list, box: list,
                                             margin: int) -> None:
    c = Configuration(robots, meeting)
    group = meeting_automorphisms(c)
    x0, x1 = sorted(box[::2])
    y0, y1 = sorted(box[1::2])
    b = [x0, y0, x1, y1]
    assert PLANE.needed(c, group, b) == needed_before(c, group, b) == \
        union.margin_needed(c, group, b)
    assert PLANE.region(c, margin, group) == region_box(c, margin, group)
    x0_, y0_, x1_, y1_ = c.mer()
    assert PLANE.region(c, margin) == geometry.bounding_box(
        [(x0_ - margin, y0_ - margin), (x1_ + margin, y1_ + margin)])
