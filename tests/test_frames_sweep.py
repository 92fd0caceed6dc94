"""Every symmetry a sweep uses is one the robots' frames allow: under a common compass or
chirality a rotated or reflected copy is another problem, and a sweep's verdict of a class
must hold for every member of it (SEMANTICS.md §3)."""

from __future__ import annotations

import itertools
import os
import textwrap
from pathlib import Path

import pytest

from gather_verify.check import run_check
from gather_verify.model import geometry
from gather_verify.model.configuration import Configuration
from gather_verify.model.view import FRAME_SETS
from gather_verify.sweeps.census import enumerate_configurations
from gather_verify.sweeps.store import Store
from gather_verify.sweeps.sweep import SweepSettings, configuration_key, run_sweep

EAST_ONLY = textwrap.dedent("""\
    class EastOnly:
        '''Walks to the meeting node east first, and never west: correct in some
        orientations only (with a compass, a rotated copy is another problem).'''

        name = "east-only"

        def decide(self, view):
            (x, y) = min(view.meeting_nodes)
            if x > 0:
                return (1, 0)
            if x == 0 and y:
                return (0, 1 if y > 0 else -1)
            return (0, 0)
    """)
MIN_SUM = os.path.join(os.path.dirname(__file__), "fixtures", "min_sum_compass.py") + \
    ":MinSumCompass"
"""A user's algorithm for a common compass whose answer depends on the orientation."""
COUNTERCLOCKWISE = MIN_SUM.replace("min_sum_compass.py:MinSumCompass",
                                   "counterclockwise.py:Counterclockwise")
"""A user's algorithm for a common chirality whose answer depends on the handedness."""


def members(n: int, m: int, w: int, h: int) -> list[Configuration]:
    """Every configuration of the box, one per translation class (brute force)."""
    nodes = [(x, y) for x in range(w) for y in range(h)]
    seen, out = set(), []
    for robots in itertools.combinations(nodes, n):
        for meeting in itertools.combinations(nodes, m):
            x0 = min(v[0] for v in robots + meeting)
            y0 = min(v[1] for v in robots + meeting)
            c = Configuration([(x - x0, y - y0) for x, y in robots],
                              [(x - x0, y - y0) for x, y in meeting], initial=True)
            if configuration_key(c) not in seen:
                seen.add(configuration_key(c))
                out.append(c)
    return out


def images(c: Configuration, frames: str) -> set[str]:
    """The keys of ``c``'s images under the frame group, moved to the origin."""
    out = set()
    for g in FRAME_SETS[frames]:
        robots = [geometry.apply(g, v) for v in c.robots]
        meeting = [geometry.apply(g, v) for v in c.meeting_nodes]
        x0 = min(v[0] for v in robots + meeting)
        y0 = min(v[1] for v in robots + meeting)
        out.add(configuration_key(Configuration([(x - x0, y - y0) for x, y in robots],
                                                [(x - x0, y - y0) for x, y in meeting])))
    return out


@pytest.mark.parametrize("frames", ["all", "chirality", "compass"])
def test_the_census_counts_classes_up_to_the_frame_group_only(frames):
    """Against brute force: the classes of the box's configurations under the frame group
    (a shape that fits the box only when turned is another problem under a compass)."""
    for n, m, w, h in ((2, 1, 3, 2), (2, 2, 2, 3), (3, 1, 3, 3)):
        classes = {frozenset(images(c, frames)) for c in members(n, m, w, h)}
        assert sum(1 for _ in enumerate_configurations(n, m, w, h, frames)) == len(classes), \
            (n, m, w, h)


def test_three_robots_two_meeting_nodes_on_3x3_are_more_problems_with_a_compass():
    """The census of a sweep under each frame group, against brute force: a compass tells
    apart what chirality identifies, chirality what the 8 frames identify."""
    counts = {f: sum(1 for _ in enumerate_configurations(3, 2, 3, 3, f))
              for f in ("all", "chirality", "compass")}
    assert counts == {"all": 334, "chirality": 616, "compass": 2448}
    everything = members(3, 2, 3, 3)
    assert len(everything) == counts["compass"]
    assert len({frozenset(images(c, "chirality")) for c in everything}) == counts["chirality"]


def test_a_compass_algorithm_can_fail_on_a_rotated_copy_only():
    """Why a class under a compass is a translation class: the min-sum fixture gathers from
    one configuration and not from its quarter turn (``--frames compass``)."""
    c = Configuration([(0, 0), (0, 1), (1, 2)], [(0, 0), (1, 2)], initial=True)
    turned = Configuration([(0, 0), (-1, 0), (-2, 1)], [(0, 0), (-2, 1)], initial=True)
    assert images(turned, "chirality") == images(c, "chirality")
    assert run_check(c, algorithm=MIN_SUM, scheduler="async", frames="compass",
                     max_seconds=60.0)["verdict"] == "VERIFIED"
    assert run_check(turned, algorithm=MIN_SUM, scheduler="async", frames="compass",
                     max_seconds=60.0)["verdict"] == "VIOLATED"


SWEEPS = [  # (algorithm, robots, meeting nodes, box)
    ("go-to-target", 2, 1, (3, 2)),
    ("east-only", 2, 1, (3, 2)),
    ("paper", 2, 1, (3, 2)),
    ("paper", 2, 2, (2, 2)),
    ("min-sum", 2, 2, (3, 2)),
    ("min-sum", 3, 2, (2, 2)),
]


@pytest.mark.parametrize("frames", ["all", "chirality", "compass"])
@pytest.mark.parametrize(("algorithm", "n", "m", "box"), SWEEPS)
def test_a_sweep_s_verdict_holds_for_every_member_of_each_class(tmp_path, frames, algorithm,
                                                                n, m, box):
    """The rows of a sweep against the checks of every configuration of the box (each
    class expanded to its images under D4 and translations), each mapped to its row
    through the frame group; an orientation-dependent algorithm under a compass is the
    case that tells."""
    if algorithm == "east-only":
        (tmp_path / "east.py").write_text(EAST_ONLY)
        algorithm = f"{tmp_path / 'east.py'}:EastOnly"
    elif algorithm == "min-sum":  # a copy outside the project: its rows are found by key
        (tmp_path / "min_sum.py").write_text(Path(MIN_SUM.rpartition(":")[0]).read_text())
        algorithm = f"{tmp_path / 'min_sum.py'}:MinSumCompass"
    settings = SweepSettings(robots=n, meeting=m, box=box, algorithm=algorithm,
                             scheduler="async", frames=frames, max_seconds=60.0)
    db = str(tmp_path / "s.sqlite")
    run_sweep(settings, db, workers=1, progress=False)
    store = Store(db)
    try:
        rows = {r["key"]: r for r in store.results(store.sweep_id(settings.key()))}
    finally:
        store.close()
    checked = 0
    for c in members(n, m, *box):
        (key,) = images(c, frames) & rows.keys()
        got = run_check(c, algorithm=algorithm, scheduler="async", frames=frames,
                        max_seconds=60.0)
        assert (got["verdict"], got["property"], got["class"]) == (
            rows[key]["verdict"], rows[key]["property"], rows[key]["class"]), (c, frames)
        checked += 1
    assert checked == len(members(n, m, *box))


def test_under_a_compass_the_paper_s_U_is_checked_not_skipped():
    """An I42 configuration (in U for disoriented robots) is NOT-APPLICABLE under all 8
    frames, and checked like any other under a compass; ``no-ungatherable`` does not apply
    there (one line, exit 2 when asked for)."""
    from gather_verify.errors import InvalidInput

    i42 = Configuration([(0, 0), (2, 1)], [(0, 1), (2, 0)], initial=True)
    assert run_check(i42, algorithm="go-to-target", scheduler="async")["verdict"] == \
        "NOT-APPLICABLE"
    compass = run_check(i42, algorithm="go-to-target", scheduler="async", frames="compass")
    assert compass["verdict"] in ("VERIFIED", "VIOLATED")
    assert "no-ungatherable" not in compass["properties"]
    with pytest.raises(InvalidInput, match="does not apply under --frames compass"):
        run_check(i42, algorithm="go-to-target", scheduler="async", frames="compass",
                  properties=["no-ungatherable"])


MIRRORED = [  # M with reflections: under chirality the mirror image of a run is no run
    Configuration([(0, 0), (0, 1), (0, 2)], [(1, 0), (1, 1)], initial=True),
    Configuration([(0, 0), (0, 1), (1, 2)], [(2, 0), (2, 1)], initial=True),
]


def test_the_symmetries_a_search_merges_by_are_in_the_frame_group():
    """``symmetry_group``: every element of ``Aut(M)`` under all 8 frames, its rotations
    under chirality, nothing but the identity under a compass."""
    from gather_verify.engine.encoding import symmetry_group
    from gather_verify.model.symmetry import meeting_automorphisms

    square = Configuration([(0, 0)], [(0, 0), (1, 0), (0, 1), (1, 1)], initial=True)
    assert len(symmetry_group(square, "all")) == len(meeting_automorphisms(square)) == 8
    assert sorted(a.g for a in symmetry_group(square, "chirality")) == \
        sorted(geometry.ROTATIONS)
    assert [a.g for a in symmetry_group(square, "compass")] == [geometry.IDENTITY]
    for c in MIRRORED:
        assert len(meeting_automorphisms(c)) == 4
        assert {a.g for a in symmetry_group(c, "chirality")} == {geometry.IDENTITY,
                                                                 geometry.ROTATIONS[2]}


@pytest.mark.parametrize("frames", [pytest.param("chirality", marks=pytest.mark.slow),
                                    "compass"])
def test_a_search_merges_states_only_by_the_symmetries_of_M_its_frames_allow(frames):
    """The Aut(M) reduction inside one search: with chirality a reflection of ``M`` is no
    symmetry of the problem, with a compass nor is a rotation; every verdict with the
    reduction equals the verdict without it, for algorithms that read the orientation
    (merging a state with its mirror image under chirality breaks the search on
    ``MIRRORED``)."""
    from gather_verify.model.symmetry import meeting_automorphisms

    small = [c for n, m, box in ((2, 2, (3, 2)), (3, 2, (2, 2)), (2, 3, (3, 2)))
             for c in members(n, m, *box) if len(meeting_automorphisms(c)) > 1]
    compared = 0
    for c in MIRRORED + small:
        for algorithm in (MIN_SUM, COUNTERCLOCKWISE):
            got = [run_check(c, algorithm=algorithm, scheduler="async", frames=frames,
                             reduction=reduction, max_seconds=60.0)
                   for reduction in (True, False)]
            (on, off) = [(r["verdict"], r["property"], r["max_moves"]) for r in got]
            assert on == off, (c, frames, algorithm)
            compared += 1
    assert compared > 50


def test_theorem_1_needs_disorientation_a_compass_gathers_an_I42_configuration():
    """The I42 configuration of the test above is gathered by robots with a common compass
    (the min-sum fixture): Theorem 1's impossibility is for disoriented robots, which is
    why the verifier checks U there instead of answering NOT-APPLICABLE."""
    i42 = Configuration([(0, 0), (2, 1)], [(0, 1), (2, 0)], initial=True)
    got = run_check(i42, algorithm=MIN_SUM, scheduler="async", frames="compass",
                    max_seconds=60.0)
    assert (got["class"], got["verdict"]) == ("I42", "VERIFIED")
    assert run_check(i42, algorithm=MIN_SUM, scheduler="async",
                     max_seconds=60.0)["verdict"] == "NOT-APPLICABLE"
