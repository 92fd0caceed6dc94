"""The paper's partition (classes.py): hand-made examples, invariance, the rules themselves."""

import json
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gather_verify.model import geometry
from gather_verify.model.configuration import Configuration
from gather_verify.model.symmetry import configuration_automorphisms, meeting_automorphisms
from gather_verify.paper.classes import (
    CLASS_NAMES,
    classify,
    classify_configuration,
    describe_views,
)
from gather_verify.paper.impossibility import theorem1_automorphism
from gather_verify.scenario import load_scenario

ROOT = Path(__file__).resolve().parent.parent
CLASS_FILES = sorted((ROOT / "scenarios" / "classes").glob("*.json"))
PAPER_FILES = sorted((ROOT / "scenarios" / "paper").glob("*.json"))

nodes = st.tuples(st.integers(-3, 3), st.integers(-3, 3))
configurations = st.builds(
    lambda r, m: Configuration(r, m, initial=True),
    st.lists(nodes, min_size=1, max_size=5, unique=True),
    st.lists(nodes, min_size=1, max_size=4, unique=True),
)
isometries = st.tuples(st.sampled_from(geometry.ALL), st.tuples(st.integers(-9, 9), st.integers(-9, 9)))


def test_every_class_has_a_hand_made_example():
    reached = {load_scenario(p).expected_class for p in CLASS_FILES}
    assert reached == set(CLASS_NAMES)


@pytest.mark.parametrize("path", CLASS_FILES + PAPER_FILES, ids=lambda p: p.name)
def test_scenario_files_classify_as_expected(path):
    raw = json.loads(path.read_text())
    assert raw["name"] and raw["description"] and raw["expect"]["class"]
    s = load_scenario(path)
    result = classify_configuration(s.configuration)
    assert result.name == s.expected_class
    assert result.in_U == (s.expected_class in ("I41", "I42")
                           or s.expected_class == "UNCLASSIFIED"
                           and theorem1_automorphism(s.configuration) is not None)


def test_in_U_as_the_paper_describes_it():
    """§3.2's U: an UNCLASSIFIED configuration is in U exactly when its axis is empty."""
    empty_axis = classify_configuration(Configuration([(0, 1), (2, 1)], [(0, 0), (2, 0)]))
    assert (empty_axis.name, empty_axis.in_U) == ("UNCLASSIFIED", True)
    meeting_on_axis = classify_configuration(
        Configuration([(0, 1), (2, 1)], [(0, 0), (2, 0), (1, 1), (1, -1)]))
    assert (meeting_on_axis.name, meeting_on_axis.in_U) == ("UNCLASSIFIED", False)
    assert meeting_on_axis.to_json()["in_U"] is False


@settings(max_examples=200, deadline=None)
@given(configurations, isometries)
def test_classification_invariant_under_isometries(c, iso):
    g, t = iso
    a, b = classify_configuration(c), classify_configuration(c.transformed(g, t))
    assert (a.name, a.in_U, len(a.meeting_on), len(a.robots_on)) == (
        b.name, b.in_U, len(b.meeting_on), len(b.robots_on))
    assert len(a.configuration_symmetries) == len(b.configuration_symmetries)


@settings(max_examples=200, deadline=None)
@given(configurations)
def test_classes_follow_the_semantics_rules(c):
    """SEMANTICS.md §2, recomputed from the automorphism groups directly."""
    aut_m = meeting_automorphisms(c)[1:]
    aut_c = configuration_automorphisms(c)[1:]
    rotations = [a for a in aut_m if a.kind == "rotation"]
    name = classify_configuration(c).name
    if not aut_m:
        assert name == "I11"
    elif not rotations:
        (mirror,) = aut_m
        if any(mirror.fixes(m) for m in c.meeting_nodes):
            assert name == "I12"
        elif not aut_c:
            assert name == "I21"
        else:
            assert name == ("I31" if any(mirror.fixes(r) for r in c.robots) else "I41")
    else:
        centre = rotations[0]
        if any(centre.fixes(m) for m in c.meeting_nodes):
            assert name == "I13"
        elif not aut_c:
            assert name == "I22"
        elif any(a.kind == "rotation" for a in aut_c):
            assert name == ("I32" if any(centre.fixes(r) for r in c.robots) else "I42")
        else:
            assert name == "UNCLASSIFIED"
            assert len(aut_c) == 1 and aut_c[0].kind == "reflection"


def test_unclassified_example_of_the_semantics():
    result = classify([(0, 1), (2, 1)], [(0, 0), (2, 0)])
    assert result.name == "UNCLASSIFIED" and result.in_U  # its axis x = 1 is empty: §3.2
    assert result.symmetry is not None and result.symmetry.kind == "rotation"
    assert "misses" in result.reason


def test_json_report_fields():
    c = Configuration([(0, 1)], [(0, 0), (3, 0), (1, 1), (2, 1)], initial=True)
    data = {**classify_configuration(c).to_json(), **describe_views(c)}
    assert data["class"] == "I21" and data["in_U"] is False
    assert data["symmetry"]["axis"] == "vertical" and data["symmetry"]["axis_through"] == "edges"
    assert data["key_corner"] and data["leading_corner"] and data["key_string"]
    json.dumps(data)
