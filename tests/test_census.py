"""Census (census.py): totals against a plain-Python brute force, canonical forms,
a deterministic order, validation."""

import itertools
import os
import subprocess
import sys

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gather_verify.model import geometry
from gather_verify.model.configuration import Configuration
from gather_verify.paper.classes import CLASS_NAMES, classify_configuration
from gather_verify.sweeps.census import (
    canonical,
    canonical_key,
    census,
    enumerate_configurations,
    validate_census_arguments,
)


def _orbit(robots, meeting):
    """All 8 images, each translated to the origin: the same set for every placement."""
    out = set()
    for g in geometry.ALL:
        r = [geometry.apply(g, p) for p in robots]
        m = [geometry.apply(g, p) for p in meeting]
        x0 = min(x for x, _ in r + m)
        y0 = min(y for _, y in r + m)
        out.add((frozenset((x - x0, y - y0) for x, y in r), frozenset((x - x0, y - y0) for x, y in m)))
    return frozenset(out)


def brute_force(n, m, w, h):
    cells = [(x, y) for x in range(w) for y in range(h)]
    return {_orbit(r, mm) for r in itertools.combinations(cells, n)
            for mm in itertools.combinations(cells, m)}


BOXES = [(1, 1, 1, 1), (1, 1, 2, 1), (1, 2, 1, 3), (2, 1, 3, 2), (2, 2, 3, 3), (3, 2, 2, 4),
         (2, 3, 4, 2), (3, 3, 3, 3), (1, 4, 3, 3)]


@pytest.mark.parametrize("args", BOXES, ids=lambda a: "n{}-m{}-{}x{}".format(*a))
def test_census_total_equals_brute_force(args):
    expected = brute_force(*args)
    reps = list(enumerate_configurations(*args))
    assert len(reps) == len(expected)
    assert {_orbit(c.robots, c.meeting_nodes) for c in reps} == expected
    result = census(*args)
    assert result.total == len(expected) == sum(result.counts.values())
    assert list(result.counts) == list(CLASS_NAMES)


def test_representatives_are_canonical_sorted_and_classified():
    result = census(2, 2, 3, 3)
    keys = [canonical_key(c) for c in result.representatives]
    assert keys == sorted(keys) and len(set(keys)) == len(keys)
    for c, name in zip(result.representatives, result.classes, strict=True):
        assert canonical(c) == c
        assert classify_configuration(c).name == name
        x0, y0, x1, y1 = c.mer()
        assert (x0, y0) == (0, 0) and sorted((x1 + 1, y1 + 1)) <= [3, 3]


def test_non_square_box_counts_rotated_placements_once():
    # a 3x1 box and a 1x3 box hold the same configurations
    assert list(enumerate_configurations(2, 1, 3, 1)) == list(enumerate_configurations(2, 1, 1, 3))


nodes = st.tuples(st.integers(-4, 4), st.integers(-4, 4))


@settings(max_examples=100, deadline=None)
@given(st.lists(nodes, min_size=1, max_size=4, unique=True),
       st.lists(nodes, min_size=1, max_size=4, unique=True),
       st.sampled_from(geometry.ALL), st.tuples(st.integers(-9, 9), st.integers(-9, 9)))
def test_canonical_is_invariant(robots, meeting, g, t):
    c = Configuration(robots, meeting, initial=True)
    assert canonical(c) == canonical(c.transformed(g, t))
    assert canonical(canonical(c)) == canonical(c)
    assert classify_configuration(canonical(c)).name == classify_configuration(c).name


def test_enumeration_order_is_deterministic_across_hash_seeds():
    code = ("from gather_verify.sweeps.census import enumerate_configurations as e;"
            "print([(c.robots, sorted(c.meeting_nodes)) for c in e(2, 2, 3, 3)])")
    outs = {subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                           env={**os.environ, "PYTHONHASHSEED": seed}).stdout for seed in ("1", "2")}
    assert len(outs) == 1
    assert outs.pop().strip() == str([(c.robots, sorted(c.meeting_nodes))
                                      for c in enumerate_configurations(2, 2, 3, 3)])


def test_small_census_counts_by_hand():
    # two robots fill a 2x1 box and the meeting node is under one of them: one class
    assert census(2, 1, 2, 1).counts["I13"] == 1 and census(2, 1, 2, 1).total == 1
    # two meeting nodes: always a half-turn of M with no meeting node on its centre
    result = census(2, 2, 3, 3)
    assert {k for k, v in result.counts.items() if v} <= {"I22", "I32", "I42", "UNCLASSIFIED"}
    assert result.counts["UNCLASSIFIED"] > 0


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ((0, 1, 3, 3), "robot count 0"),
        ((-1, 1, 3, 3), "robot count -1"),
        ((1, 0, 3, 3), "meeting node count 0"),
        ((1, 1, 0, 3), "box width 0"),
        ((1, 1, 3, 0), "box height 0"),
        ((1, 1, 9, 3), "box width 9"),
        ((10, 1, 3, 3), "n=10"),
        ((1, 10, 3, 3), "m=10"),
        ((1.5, 1, 3, 3), "robot count 1.5"),
        ((True, 1, 3, 3), "robot count True"),
        ((8, 8, 8, 8), "placements"),
    ],
)
def test_validation(args, message):
    with pytest.raises(ValueError, match=message):
        validate_census_arguments(*args)
    with pytest.raises(ValueError, match=message):
        census(*args)
    with pytest.raises(ValueError, match=message):
        list(enumerate_configurations(*args))


@pytest.mark.slow
def test_census_3_3_4x4_against_brute_force():
    assert census(3, 3, 4, 4).total == len(brute_force(3, 3, 4, 4))


def test_box_orientation_does_not_matter():
    assert census(2, 2, 2, 4).counts == census(2, 2, 4, 2).counts


LAZY_BOXES = BOXES + [(3, 3, 4, 4), (2, 2, 8, 2), (1, 3, 2, 7), (2, 2, 5, 3)]


@pytest.mark.parametrize("args", LAZY_BOXES, ids=lambda a: "n{}-m{}-{}x{}".format(*a))
def test_lazy_enumeration_equals_the_sorted_unique_census(args):
    """The streamed census gives exactly the rows, in the same order, of the all-at-once one."""
    import numpy as np

    from gather_verify.sweeps.census import _canonical_masks, _canonical_masks_lazy

    lazy = list(_canonical_masks_lazy(*args))
    assert len(lazy) > 1 or args[2] * args[3] < 9  # streamed in several blocks
    assert np.array_equal(np.concatenate(lazy), _canonical_masks(*args))


def test_the_first_configurations_need_no_whole_census():
    """Taking a prefix stops the enumeration early (the generator has not run to its end)."""
    gen = enumerate_configurations(4, 4, 4, 4)
    first = list(itertools.islice(gen, 5))
    assert [canonical_key(c) for c in first] == sorted(canonical_key(c) for c in first)
    assert gen.gi_frame is not None  # suspended, not exhausted


def test_census_counts_classes_up_to_the_frames_as_sweeps_do() -> None:
    """``census --frames`` counts what a sweep under those frames checks, one per class."""
    import json
    import subprocess
    import sys

    from gather_verify.sweeps.census import enumerate_configurations

    totals = {}
    for frames in ("all", "chirality", "compass"):
        run = subprocess.run([sys.executable, "-m", "gather_verify", "census", "--robots", "3",
                              "--meeting", "2", "--box", "3x3", "--frames", frames, "--json"],
                             capture_output=True, text=True, timeout=120)
        totals[frames] = json.loads(run.stdout)["total"]
        assert totals[frames] == sum(1 for _ in enumerate_configurations(3, 2, 3, 3, frames))
    assert totals["all"] < totals["chirality"] < totals["compass"]
