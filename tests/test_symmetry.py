"""Automorphisms (symmetry.py): completeness against brute force, labels preserved,
Aut(C) ⊆ Aut(M), kinds, axes and centres in doubled coordinates."""

import itertools

from hypothesis import example, given, settings
from hypothesis import strategies as st

from gather_verify.model import geometry
from gather_verify.model.configuration import Configuration
from gather_verify.model.symmetry import (
    Automorphism,
    automorphisms,
    configuration_automorphisms,
    meeting_automorphisms,
)

BOX = 4
nodes = st.tuples(st.integers(0, BOX - 1), st.integers(0, BOX - 1))
configurations = st.builds(
    lambda r, m: Configuration(r, m, initial=True),
    st.lists(nodes, min_size=1, max_size=4, unique=True),
    st.lists(nodes, min_size=1, max_size=4, unique=True),
)


def brute_force(labelled):
    """Every (g, t) with t in a window wide enough to map the box onto itself."""
    out = set()
    for g in geometry.ALL:
        for t in itertools.product(range(-3 * BOX, 3 * BOX + 1), repeat=2):
            a = Automorphism(g, t)
            if all(labelled.get(a(v)) == label for v, label in labelled.items()):
                out.add(a)
    return out


@settings(max_examples=60, deadline=None)
@given(configurations)
def test_automorphisms_complete_and_label_preserving(c):
    for labelled in (c.labelled, dict.fromkeys(c.meeting_nodes, 1)):
        found = automorphisms(labelled)
        assert found[0] == Automorphism(geometry.IDENTITY, (0, 0))
        assert len(set(found)) == len(found)
        assert set(found) == brute_force(labelled)
        for a in found:
            assert {a(v): label for v, label in labelled.items()} == dict(labelled)


@settings(max_examples=150, deadline=None)
@given(configurations)
def test_aut_c_is_a_subgroup_of_aut_m(c):
    aut_c = set(configuration_automorphisms(c))
    aut_m = set(meeting_automorphisms(c))
    assert aut_c <= aut_m
    assert set(configuration_automorphisms(c, weak=True)) <= aut_m


@settings(max_examples=100, deadline=None)
@given(configurations)
def test_fixed_points_match_centre_and_axis(c):
    for a in meeting_automorphisms(c):
        fixed = [v for v in itertools.product(range(-2, BOX + 3), repeat=2) if a.fixes(v)]
        if a.kind == "rotation":
            cx, cy = a.centre2
            expect = [(cx // 2, cy // 2)] if a.centre_kind == "node" else []
            assert fixed == expect
        elif a.kind == "reflection":
            orientation, k = a.axis
            on_axis = {
                "vertical": lambda v, k=k: 2 * v[0] == k,
                "horizontal": lambda v, k=k: 2 * v[1] == k,
                "diagonal": lambda v, k=k: v[0] - v[1] == k,
                "anti-diagonal": lambda v, k=k: v[0] + v[1] == k,
            }[orientation]
            assert all(on_axis(v) for v in fixed)
            assert (a.axis_through == "nodes") == any(
                on_axis(v) for v in itertools.product(range(-20, 21), repeat=2))


def test_kinds_centres_axes_by_hand():
    two = {(0, 0): 1, (2, 0): 1}
    kinds = {a.describe() for a in automorphisms(two)}
    assert kinds == {"identity", "rotation 180 about (1, 0) [node]",
                     "reflection, vertical axis x = 1 through nodes",
                     "reflection, horizontal axis y = 0 through nodes"}
    square = dict.fromkeys([(0, 0), (1, 0), (0, 1), (1, 1)], 1)
    rotations = [a for a in automorphisms(square) if a.kind == "rotation"]
    assert sorted(a.angle for a in rotations) == [90, 180, 270]
    assert {a.centre_kind for a in rotations} == {"square"}
    pair = {(0, 0): 1, (1, 0): 1}
    rot = next(a for a in automorphisms(pair) if a.kind == "rotation")
    assert rot.centre_kind == "edge" and rot.centre2 == (1, 0)
    flip = next(a for a in automorphisms(pair) if a.axis and a.axis[0] == "vertical")
    assert flip.axis_through == "edges" and flip.is_partitive_on(pair)


def test_partitive_and_orbits():
    square = dict.fromkeys([(0, 0), (2, 0), (0, 2), (2, 2)], 1)
    r90 = next(a for a in automorphisms(square) if a.angle == 90)
    assert len(r90.orbit((0, 0))) == 4 and r90.is_partitive_on(square)
    assert not r90.is_partitive_on([(1, 1)])  # the centre is a node, fixed
    assert not Automorphism(geometry.IDENTITY, (0, 0)).is_partitive_on([(0, 0)])


@settings(max_examples=400, deadline=None)
@given(st.lists(st.tuples(st.integers(-3, 3), st.integers(-3, 3)), min_size=1, max_size=6),
       st.lists(st.tuples(st.integers(-3, 3), st.integers(-3, 3)), min_size=1, max_size=4,
                unique=True))
@example(robots=[(0, 1)] * 3 + [(1, 0)] * 2, meeting=[(0, 0)])  # 3 robots and 2: both label 5
def test_configuration_automorphisms_filtered_from_aut_m_are_those_of_the_labels(robots, meeting):
    """``Aut(C)`` is taken from ``Aut(M)``; it is exactly the automorphisms of the labels
    (strong and weak), in the same order."""
    c = Configuration(robots, meeting)  # multiplicities allowed
    assert configuration_automorphisms(c) == automorphisms(c.labelled)
    weak = {v: c.weak_label(v) for v in c.labelled}
    assert configuration_automorphisms(c, weak=True) == automorphisms(weak)
