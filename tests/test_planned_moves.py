"""The paper's planned move sets (one plan for every robot and frame) equal the union of
``decide`` over the frames, view by view: on random configurations with multiplicities,
every reading, detection model and frame set, and on whole small boxes."""

from __future__ import annotations

import itertools

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gather_verify.algorithms import Unhandled
from gather_verify.algorithms.moves import frames_for, move_set, move_sets
from gather_verify.model.configuration import Configuration
from gather_verify.model.view import DETECTION_MODELS
from gather_verify.paper.algorithm import READINGS, PaperAlgorithm
from gather_verify.sweeps.census import enumerate_configurations


def _view_by_view(algo, c, detection, frames):
    """The move sets as the explorer defines them: ``decide`` per robot and frame."""
    try:
        return {v: move_set(algo, c, v, detection, frames) for v in c.counts}
    except Unhandled as error:
        return ("Unhandled", str(error))


def _planned(algo, c, detection, frames):
    try:
        out = algo.move_sets(c, detection, frames)
    except Unhandled as error:
        return ("Unhandled", str(error))
    return out


nodes = st.tuples(st.integers(0, 4), st.integers(0, 4))
readings = st.fixed_dictionaries({k: st.sampled_from(v) for k, v in READINGS.items()})


@settings(max_examples=400, deadline=None)
@given(st.lists(nodes, min_size=1, max_size=5), st.lists(nodes, min_size=1, max_size=4, unique=True),
       readings, st.sampled_from([d for d in DETECTION_MODELS if d != "none"]),
       st.sampled_from(["all", "chirality", "compass"]))
def test_planned_move_sets_are_the_union_of_decide_over_the_frames(robots, meeting, options,
                                                                   detection, frames):
    algo = PaperAlgorithm(**options)
    c = Configuration(robots, meeting)  # multiplicities allowed: Algorithm 4 reads them
    f = frames_for(frames)
    assert _planned(algo, c, detection, f) == _view_by_view(algo, c, detection, f)


def test_detection_none_is_left_to_decide():
    algo = PaperAlgorithm()
    c = Configuration([(0, 0), (1, 0), (1, 0)], [(0, 0), (3, 1)])  # Algorithm 4
    assert algo.move_sets(c, "none", frames_for("all")) is None
    with pytest.raises(Unhandled):  # the plan reads a multiplicity 'none' hides
        move_sets(algo, c, "none")


@pytest.mark.parametrize("box,n,m", [((3, 3), 2, 2), ((3, 3), 3, 2), ((4, 4), 2, 3)])
def test_planned_move_sets_on_whole_boxes(box, n, m):
    """Every configuration of the box, and each with two robots merged (a multiplicity)."""
    algo, f = PaperAlgorithm(), frames_for("all")
    checked = 0
    for c in enumerate_configurations(n, m, *box):
        merged = Configuration((c.robots[0],) + c.robots[:-1], c.meeting_nodes)
        for one in (c, merged):
            assert _planned(algo, one, "local-weak", f) == _view_by_view(algo, one, "local-weak", f)
            checked += 1
    assert checked > 100


def test_a_wrong_planned_move_set_is_caught():
    """The comparison can fail: planning for one frame only differs somewhere."""
    algo, f = PaperAlgorithm(), frames_for("all")
    differs = 0
    for c in itertools.islice(enumerate_configurations(3, 2, 3, 3), 200):
        if _planned(algo, c, "local-weak", f[:1]) != _view_by_view(algo, c, "local-weak", f):
            differs += 1
    assert differs


@given(nodes, nodes)
def test_closer_steps_are_the_neighbours_nearer_the_target(v, target):
    from gather_verify.model import geometry
    from gather_verify.paper.algorithm import closer_steps

    d = geometry.manhattan(v, target)
    expected = {u for u in geometry.neighbours(v) if geometry.manhattan(u, target) < d} or {v}
    assert closer_steps(v, target) == expected
