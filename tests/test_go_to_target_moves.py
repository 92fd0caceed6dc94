"""go-to-target's move sets computed at once (the ``move_sets`` hook) equal the union of
``decide`` over the frames, view by view; subclasses that answer otherwise are asked view by
view."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from gather_verify.algorithms.broken import Away
from gather_verify.algorithms.go_to_target import GoToTarget
from gather_verify.algorithms.moves import frames_for, move_set, move_sets
from gather_verify.model.configuration import Configuration
from gather_verify.sweeps.census import enumerate_configurations

nodes = st.tuples(st.integers(-3, 4), st.integers(-3, 4))


def _view_by_view(algo, c, frames):
    return {v: move_set(algo, c, v, "local-weak", frames) for v in c.counts}


@settings(max_examples=300, deadline=None)
@given(st.lists(nodes, min_size=1, max_size=5), st.lists(nodes, min_size=1, max_size=4, unique=True),
       st.sampled_from(["all", "chirality", "compass"]))
def test_move_sets_are_the_union_of_decide_over_the_frames(robots, meeting, frames):
    c = Configuration(robots, meeting)
    f = frames_for(frames)
    assert GoToTarget().move_sets(c, "local-weak", f) == _view_by_view(GoToTarget(), c, f)


def test_move_sets_on_a_whole_box():
    algo, f = GoToTarget(), frames_for("all")
    for c in enumerate_configurations(3, 2, 3, 3):
        assert algo.move_sets(c, "none", f) == _view_by_view(algo, c, f)


def test_a_subclass_with_its_own_decide_is_asked_view_by_view():
    c = Configuration([(0, 0), (1, 2)], [(2, 2)])  # (1, 2) at odd distance: Away steps away
    assert Away().move_sets(c, "local-weak", frames_for("all")) is None
    assert move_sets(Away(), c) == _view_by_view(Away(), c, frames_for("all"))
    assert move_sets(Away(), c) != move_sets(GoToTarget(), c)  # the comparison can fail
