"""Every registered algorithm: registry, equivariance of move sets, hidden multiplicity."""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from gather_verify.algorithms import REGISTRY, Unhandled, get_algorithm, register
from gather_verify.algorithms.moves import HiddenRead, move_set, move_sets
from gather_verify.algorithms.nearest_centre import NearestCentre
from gather_verify.model import geometry
from gather_verify.model.configuration import Configuration
from gather_verify.model.geometry import ORIGIN, Node
from gather_verify.model.view import MultiplicityHidden, View

ALGORITHMS = sorted(n for n in REGISTRY if getattr(REGISTRY[n], "plane", True)
                    and not getattr(REGISTRY[n], "luminous", False)) + ["paper:alpha=mer_f", "paper:outside=mer_f", "paper:metric=euclid",
                                  "paper:oscan=guard,finalize=target", "paper:finalize=literal"]

nodes = st.tuples(st.integers(0, 4), st.integers(0, 4))
configurations = st.builds(
    lambda robots, meeting: Configuration(robots, meeting),
    st.lists(nodes, min_size=1, max_size=5),  # duplicates allowed: multiplicities
    st.lists(nodes, min_size=1, max_size=4, unique=True),
)


def outcome(algorithm, c: Configuration) -> dict[Node, frozenset[Node]] | str:
    try:
        return move_sets(algorithm, c)
    except Unhandled:
        return "unhandled"


@pytest.mark.parametrize("name", ALGORITHMS)
@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(c=configurations, g=st.sampled_from(geometry.ALL),
       t=st.tuples(st.integers(-3, 3), st.integers(-3, 3)))
def test_move_sets_transform_with_the_configuration(name, c, g, t):
    """S_psi(C)(psi(v)) = psi(S_C(v)) for every grid isometry psi = (g, t)."""
    algorithm = get_algorithm(name)
    before, after = outcome(algorithm, c), outcome(algorithm, c.transformed(g, t))
    if before == "unhandled":
        assert after == "unhandled"
        return
    psi = lambda v: geometry.add(geometry.apply(g, v), t)  # noqa: E731
    assert after == {psi(v): frozenset(map(psi, s)) for v, s in before.items()}


@pytest.mark.parametrize("name", ALGORITHMS)
@settings(max_examples=25, deadline=None)
@given(c=configurations)
def test_answers_are_moves_and_targets_are_meeting_nodes(name, c):
    algorithm = get_algorithm(name)
    sets = outcome(algorithm, c)
    if sets != "unhandled":
        for v, s in sets.items():
            assert s and all(geometry.manhattan(v, u) <= 1 for u in s)
    target = getattr(algorithm, "target", lambda _: None)(c)
    assert target is None or target in c.meeting_nodes


class Peeking:
    """Reads the multiplicity of a neighbour: forbidden under local-weak."""

    name = "peeking"

    def decide(self, view: View) -> Node:
        return (1, 0) if view.multiplicity((1, 0)) else ORIGIN


def test_reading_hidden_multiplicity_fails_loudly():
    c = Configuration([(0, 0), (1, 0), (1, 0)], [(5, 5)])
    with pytest.raises(MultiplicityHidden, match="local-weak"):
        move_set(Peeking(), c, (0, 0), "local-weak")
    assert move_set(Peeking(), c, (0, 0), "global-weak", frames=[0]) == {(1, 0)}


LOCAL_WEAK_YARD = Configuration([(0, 0), (0, 0), (3, 1), (1, 4)], [(2, 2), (0, 4)])


def run_under_local_weak(algorithm, c: Configuration = LOCAL_WEAK_YARD) -> int:
    """Every robot's move set under local-weak; the number of nodes with no rule.

    A hidden read is a ``HiddenRead``, which is also an ``Unhandled``: it is re-raised
    before the paper's own no-rule cases (plain ``Unhandled``) are let through, so an
    algorithm that reads what it cannot see fails here instead of counting as "no rule"."""
    unhandled = 0
    for node in c.counts:
        try:
            move_set(algorithm, c, node, "local-weak")
        except HiddenRead:
            raise
        except Unhandled:
            unhandled += 1
    return unhandled


@pytest.mark.parametrize("name", ALGORITHMS)
def test_registered_algorithms_run_under_local_weak(name):
    """None of ours reads more than local-weak shows (a hidden read raises ``HiddenRead``)."""
    assert 0 <= run_under_local_weak(get_algorithm(name)) <= len(LOCAL_WEAK_YARD.counts)


class Leaking:
    """Reads the multiplicity of another robot's node (hidden under local-weak) where it sees
    one, and has no rule (``Unhandled``) elsewhere: a leak among no-rule cases."""

    name = "leaking"

    def decide(self, view: View) -> Node:
        others = sorted(v for v in view.robots if v != ORIGIN)
        if view.multiplicity() and others:
            return (1, 0) if view.multiplicity(others[0]) else ORIGIN
        raise Unhandled("no rule here")


def test_the_local_weak_test_fails_on_a_hidden_read():
    """The check above is not vacuous: the very helper it runs lets a plain ``Unhandled``
    through but fails on an algorithm that reads what local-weak hides."""
    class NoRule:
        name = "no-rule"

        def decide(self, view: View) -> Node:
            raise Unhandled("no rule anywhere")

    assert run_under_local_weak(NoRule()) == len(LOCAL_WEAK_YARD.counts)
    with pytest.raises(HiddenRead, match="local-weak"):
        run_under_local_weak(Leaking())
    with pytest.raises(HiddenRead):
        run_under_local_weak(Peeking(), Configuration([(0, 0), (1, 0), (1, 0)], [(5, 5)]))


def test_register_a_new_algorithm():
    class Stay:
        name = "stay"

        def decide(self, view: View) -> Node:
            return ORIGIN

    register("stay-test", Stay)
    try:
        assert move_set(get_algorithm("stay-test"), Configuration([(0, 0)], [(1, 1)]),
                        (0, 0)) == {(0, 0)}
    finally:
        del REGISTRY["stay-test"]


def test_nearest_centre_target_and_tie():
    c = Configuration([(0, 0), (4, 0)], [(2, 1), (9, 9)])
    assert NearestCentre().target(c) == (2, 1)
    tie = Configuration([(0, 0), (4, 0)], [(2, 1), (2, -1)])
    assert NearestCentre().target(tie) is None
    assert move_set(NearestCentre(), tie, (0, 0)) == {(0, 0)}
