"""D4 and grid helpers (geometry.py): group laws, parsing errors."""

import itertools

import pytest

from gather_verify.model import geometry

PROBES = [(1, 0), (0, 1), (2, -3), (-5, 7)]


def test_d4_has_eight_distinct_elements():
    images = {tuple(geometry.apply(g, p) for p in PROBES) for g in geometry.ALL}
    assert len(images) == 8


def test_compose_and_inverse_agree_with_apply():
    for g, h in itertools.product(geometry.ALL, repeat=2):
        for p in PROBES:
            assert geometry.apply(geometry.compose(g, h), p) == geometry.apply(g, geometry.apply(h, p))
    for g in geometry.ALL:
        assert geometry.compose(g, geometry.inverse(g)) == geometry.IDENTITY
        for p in PROBES:
            assert geometry.apply(geometry.inverse(g), geometry.apply(g, p)) == p


def test_isometries_preserve_distance_and_rotations_are_the_determinant_one_half():
    for g in geometry.ALL:
        for p, q in itertools.combinations(PROBES, 2):
            assert geometry.manhattan(geometry.apply(g, p), geometry.apply(g, q)) == geometry.manhattan(p, q)
    assert [g for g in geometry.ALL if geometry.is_rotation(g)] == list(geometry.ROTATIONS)


def test_neighbours_and_bounding_box():
    assert sorted(geometry.neighbours((0, 0))) == [(-1, 0), (0, -1), (0, 1), (1, 0)]
    assert geometry.bounding_box([(3, -1), (0, 2)]) == (0, -1, 3, 2)


@pytest.mark.parametrize("text", ["a,b", "1,2,3", "1.5,2", "1e400,0", "1", "", ",", "0x1,2"])
def test_parse_node_rejects_with_the_text_named(text):
    with pytest.raises(ValueError, match="bad point"):
        geometry.parse_node(text)


def test_parse_nodes():
    assert geometry.parse_nodes("0,0 3,-1  2,2") == [(0, 0), (3, -1), (2, 2)]
    with pytest.raises(ValueError, match="separate points with spaces"):
        geometry.parse_nodes("0,0 3,-1;2,2")  # one separator: spaces
