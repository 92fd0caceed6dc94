"""Corner strings, key and leading corners (strings.py): the paper's figures and
invariance under the 8 isometries and translations."""

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gather_verify.model import geometry
from gather_verify.model.configuration import Configuration
from gather_verify.paper import strings
from gather_verify.paper.classes import classify_configuration
from gather_verify.scenario import load_scenario

STRING2 = "001001400004000000000000404000400401000000100"
ALPHA_ORDER1 = "01000001000000010100000000001001000"

nodes = st.tuples(st.integers(-3, 3), st.integers(-3, 3))
configurations = st.builds(
    lambda r, m: Configuration(r, m, initial=True),
    st.lists(nodes, min_size=1, max_size=5, unique=True),
    st.lists(nodes, min_size=1, max_size=4, unique=True),
)
isometries = st.tuples(st.sampled_from(geometry.ALL), st.tuples(st.integers(-9, 9), st.integers(-9, 9)))


def test_string2_is_I21_with_exactly_that_key_string():
    c = strings.from_string(STRING2, 5)
    assert classify_configuration(c).name == "I21"
    keys = strings.key_scans(c)
    assert {s.text for s in keys} == {STRING2}
    assert strings.key_corners(c) == [(0, 0)]  # A, unique: C is asymmetric
    assert load_scenario("scenarios/paper/string2.json").configuration == c


def test_order1_alpha_over_the_5x7_mer_and_not_over_mer_f():
    c = load_scenario("scenarios/paper/order1.json").configuration
    x0, y0, x1, y1 = c.mer()
    assert sorted((x1 - x0 + 1, y1 - y0 + 1)) == [5, 7]  # nodes
    leads = strings.leading_scans(c, "mer")
    assert [s.text for s in leads] == [ALPHA_ORDER1]
    assert strings.leading_corners(c, "mer") == [(0, 0)]  # D, unique: M is asymmetric
    over_f = strings.leading_scans(c, "mer_f")
    assert all(len(s.text) < len(ALPHA_ORDER1) for s in over_f)
    assert ALPHA_ORDER1 not in {s.text for s in over_f}
    assert len(over_f[0].text) == 28  # MER_F is 7 x 4 nodes: one row smaller


def test_representation_rules():
    # non-square: the string runs along the shorter side
    c = Configuration([(0, 0)], [(3, 1)])
    assert all(len(set(x for x, _ in s.nodes[:2])) == 1 for s in strings.representations(c.mer(), c.label))
    # square: the larger of the two strings of each corner, both when equal
    sq = Configuration([(0, 0), (1, 1)], [(0, 1)])
    reps = strings.representations(sq.mer(), sq.label)
    assert all(s.text == max(t.text for t in strings.all_scans(sq.mer(), sq.label) if t.corner == s.corner)
               for s in reps)


def _texts(c, value):
    return sorted(s.text for s in strings.all_scans(c.mer(), value(c)))


@settings(max_examples=150, deadline=None)
@given(configurations, isometries)
def test_corner_strings_key_and_alpha_invariant_under_isometries(c, iso):
    g, t = iso
    image = c.transformed(g, t)
    assert _texts(image, lambda x: x.label) == _texts(c, lambda x: x.label)
    assert strings.key_scans(image)[0].text == strings.key_scans(c)[0].text
    # the key corners move with the configuration
    assert {geometry.add(geometry.apply(g, v), t) for v in strings.key_corners(c)} == set(
        strings.key_corners(image))
    for region in ("mer", "mer_f"):
        assert strings.leading_scans(image, region)[0].text == strings.leading_scans(c, region)[0].text
        assert {geometry.add(geometry.apply(g, v), t) for v in strings.leading_corners(c, region)} == set(
            strings.leading_corners(image, region))


@settings(max_examples=150, deadline=None)
@given(configurations)
def test_one_key_scan_exactly_when_configuration_asymmetric(c):
    """Paper §2: an asymmetric configuration has a unique largest string; a
    symmetry maps the key scan onto another scan with the same text."""
    from gather_verify.model.symmetry import configuration_automorphisms

    asymmetric = len(configuration_automorphisms(c)) == 1
    assert (len(strings.key_scans(c)) == 1) == asymmetric
    if asymmetric:
        assert len(strings.key_corners(c)) == 1


@pytest.mark.parametrize("bad", [("0123", 2), ("0124", 3), ("0125", 2), ("", 0)])
def test_from_string_rejects(bad):
    with pytest.raises(ValueError):
        strings.from_string(*bad)


def _dense_text(scan, value):
    return "".join(str(value(u)) for u in scan.nodes)


@settings(max_examples=300, deadline=None)
@given(configurations, st.sampled_from(["label", "weak_label", "lam"]))
def test_sparse_scans_read_and_order_as_the_dense_strings(c, name):
    """Scans are held sparsely (labelled nodes only): their text, positions and order are
    those of the dense string read node by node over the whole rectangle."""
    value = getattr(c, name)
    rect = c.mer() if name != "lam" else c.mer_f()
    sparse = strings.all_scans(rect, value, c.labelled)
    dense = strings.all_scans(rect, value)  # every node of the rectangle is looked at
    assert [s.labels for s in sparse] == [s.labels for s in dense]
    for s in sparse:
        assert s.text == _dense_text(s, value)
        assert [s.index(v) for v in s.nodes] == list(range(len(s.nodes)))
    for a in sparse:
        for b in sparse:
            if a.line == b.line:
                assert (a.order < b.order) == (a.text < b.text)
    reps = strings.representations(rect, value, c.labelled)
    top = max(s.text for s in reps)
    assert [s.text for s in strings.largest(reps)] == [s.text for s in reps if s.text == top]
