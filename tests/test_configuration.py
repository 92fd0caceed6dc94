"""Configurations (configuration.py): labels, MER/MER_F, D, validation messages."""

import pytest

from gather_verify.model.configuration import Configuration


def test_labels_follow_the_paper():
    c = Configuration([(0, 0), (1, 1), (1, 1), (2, 2), (3, 3), (3, 3)], [(0, 0), (4, 4), (3, 3)])
    assert c.label((0, 0)) == 2  # one robot on a meeting node
    assert c.label((3, 3)) == 3  # several robots on a meeting node
    assert c.label((4, 4)) == 1
    assert c.label((1, 1)) == 5
    assert c.label((2, 2)) == 4
    assert c.label((9, 9)) == 0
    assert c.weak_label((3, 3)) == 2 and c.weak_label((1, 1)) == 4
    assert c.lam((4, 4)) == 1 and c.lam((1, 1)) == 0


def test_mer_mer_f_and_D_count_edges():
    c = Configuration([(0, 0), (5, 1)], [(1, 1), (2, 3)])
    assert c.mer() == (0, 0, 5, 3)
    assert c.mer_f() == (1, 1, 2, 3)
    assert c.D == 5
    assert Configuration([(0, 0)], [(0, 0)]).D == 0


def test_equality_ignores_input_order():
    assert Configuration([(1, 0), (0, 0)], [(2, 2)]) == Configuration([(0, 0), (1, 0)], [(2, 2)])
    assert len({Configuration([(1, 0), (0, 0)], [(2, 2)]), Configuration([(0, 0), (1, 0)], [(2, 2)])}) == 1


@pytest.mark.parametrize(
    ("robots", "meeting", "message"),
    [
        ([], [(0, 0)], "no robots"),
        ([(0, 0)], [], "no meeting nodes"),
        ([(0, 0), (0, 0)], [(1, 1)], r"duplicate robot \[0, 0\]"),
        ([(0, 0)], [(1, 1), (1, 1)], r"duplicate meeting node \[1, 1\]"),
        ([(0.5, 0)], [(1, 1)], "coordinates must be integers"),
        ([(True, 0)], [(1, 1)], "coordinates must be integers"),
        ([(10**7, 0)], [(1, 1)], r"\|coordinate\|"),
        ([(1, 2, 3)], [(1, 1)], "exactly two coordinates"),
        (["0,0"], [(1, 1)], "pair of integers"),
    ],
)
def test_validation_names_the_bad_value(robots, meeting, message):
    with pytest.raises(ValueError, match=message):
        Configuration(robots, meeting, initial=True)


def test_multiplicities_allowed_when_not_initial():
    c = Configuration([(0, 0), (0, 0)], [(0, 0)])
    assert c.is_gathered and c.has_multiplicity and c.n == 2
