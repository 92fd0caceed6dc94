"""Z² as a world (SEMANTICS.md §9): the registry's ``grid`` is the Plane, behind the face
every world offers; its nodes round-trip, its frames are the 8 of D4 and present the view
the Z² engine presents, and its canonical form is model/canonical's, invariant under the
frames and the translations. A Plane with one frame missing, or a canonical form blind to
D4, is caught."""

from __future__ import annotations

import json
from collections.abc import Sequence

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gather_verify.errors import InvalidInput
from gather_verify.model import geometry
from gather_verify.model.canonical import canonical, canonical_form
from gather_verify.model.configuration import Configuration
from gather_verify.model.geometry import Node
from gather_verify.model.view import View
from gather_verify.worlds import (
    FINITE,
    NAMED_WORLDS,
    PLANE,
    AnyWorld,
    World,
    entry_of,
    finite_world,
    get_world,
)
from gather_verify.worlds.base import AnyFrame
from gather_verify.worlds.grid import FiniteGrid
from gather_verify.worlds.plane import Plane, PlaneFrame

coordinate = st.integers(-50, 50)
node = st.tuples(coordinate, coordinate)
configurations = st.tuples(st.lists(node, min_size=1, max_size=6),
                           st.lists(node, min_size=1, max_size=3, unique=True))


# -- the registry --------------------------------------------------------------------------

def test_the_registry_names_the_plane_grid_and_a_finite_grid_grid_wxh() -> None:
    z2 = get_world("grid")
    assert isinstance(z2, Plane) and isinstance(z2, AnyWorld)
    assert (z2.name, z2.kind, z2.entry) == ("grid", "grid", PLANE)
    assert get_world(" grid ").entry == PLANE
    assert NAMED_WORLDS["grid"] is Plane
    box = get_world("grid:3x2")
    assert isinstance(box, FiniteGrid) and box.entry == FINITE and box.name == "grid:3x2"


def test_every_finite_world_offers_the_same_face(tmp_path) -> None:
    path = tmp_path / "path3.edgelist"
    path.write_text("0 1\n1 2\n")
    for spec in ("ring:5", "grid:3x3", "torus:3x4", f"graph:{path}"):
        world = get_world(spec)
        assert isinstance(world, World) and isinstance(world, AnyWorld), spec
        assert world.entry == FINITE == entry_of(spec)
        assert all(isinstance(f, AnyFrame) for f in world.frames(0, None, "all"))
    assert all(isinstance(f, AnyFrame) for f in Plane().frames((0, 0), None, "all"))


def test_entry_of_asks_the_registry_without_building_a_finite_world() -> None:
    assert entry_of(None) == entry_of("grid") == PLANE
    assert entry_of("graph:/no/such/file.gml") == FINITE  # never read
    assert entry_of("ring:5-9") == FINITE  # a range of sizes is a sweep's


def test_what_needs_a_finite_world_refuses_the_plane_in_one_line() -> None:
    with pytest.raises(InvalidInput, match="world grid needs a size or file: grid:..."):
        finite_world("grid")
    with pytest.raises(InvalidInput, match="unknown world 'hex': use grid, rendezvous, grid:..., ring:..."):
        get_world("hex")


# -- nodes ---------------------------------------------------------------------------------

@given(node)
def test_a_node_round_trips_through_text_and_json(v: Node) -> None:
    z2 = Plane()
    assert z2.parse_node(z2.format_node(v)) == v
    assert z2.node_from_json(json.loads(json.dumps(z2.node_to_json(v)))) == v


@given(st.lists(node, max_size=5))
def test_nodes_round_trip_as_the_command_line_writes_them(vs: list[Node]) -> None:
    z2 = Plane()
    assert z2.parse_nodes(" ".join(z2.format_node(v) for v in vs)) == vs


@pytest.mark.parametrize("text", ["1", "1,2,3", "a,b", "1.5,2", ""])
def test_a_bad_node_is_one_line(text: str) -> None:
    with pytest.raises(InvalidInput):
        Plane().parse_node(text)
    with pytest.raises(InvalidInput):
        Plane().node_from_json(text.split(","))


# -- frames --------------------------------------------------------------------------------

def d4_problems(world: AnyWorld, v: Node, frames: str = "all") -> list[str]:
    """What keeps the frames of a robot on ``v`` from being the robot at the origin turned by
    the elements of D4 the frame set allows, each once (SEMANTICS.md §9)."""
    problems = []
    seen = []
    for f in world.frames(v, None, frames):
        if f.label(v) != (0, 0):
            problems.append(f"{f}: the robot's node reads {f.label(v)}, not (0, 0)")
        ex, ey = f.label(geometry.add(v, (1, 0))), f.label(geometry.add(v, (0, 1)))
        matrix = (ex[0], ey[0], ex[1], ey[1])
        if matrix not in geometry.MATRICES:
            problems.append(f"{f}: {matrix} is no element of D4")
            continue
        g = geometry.MATRICES.index(matrix)
        far = geometry.add(v, (7, -3))
        if f.label(far) != geometry.apply(g, (7, -3)):
            problems.append(f"{f}: not a translation followed by {geometry.NAMES[g]}")
        seen.append(g)
    wanted = {"all": geometry.ALL, "chirality": geometry.ROTATIONS,
              "compass": (geometry.IDENTITY,)}[frames]
    if sorted(seen) != sorted(wanted):
        problems.append(f"frames {sorted(geometry.NAMES[g] for g in seen)}, not "
                        f"{sorted(geometry.NAMES[g] for g in wanted)}")
    return problems


@pytest.mark.parametrize("frames", ["all", "chirality", "compass"])
@pytest.mark.parametrize("v", [(0, 0), (3, -4)])
def test_the_frames_are_the_elements_of_d4_the_frame_set_allows(frames: str, v: Node) -> None:
    assert len(Plane().frames(v, None, frames)) == {"all": 8, "chirality": 4, "compass": 1}[frames]
    assert d4_problems(Plane(), v, frames) == []


class OneFrameShort(Plane):
    """A broken Z²: the last element of D4 (the anti-diagonal reflection) is never tried."""

    def frames(self, v: Node, visibility: int | None, frames: str) -> list[PlaneFrame]:
        return super().frames(v, visibility, frames)[:-1]


class FramesNotAtTheRobot(Plane):
    """A broken Z²: the frames turn the grid about the origin, not about the robot."""

    def frames(self, v: Node, visibility: int | None, frames: str) -> list[PlaneFrame]:
        return [PlaneFrame(f.element, (0, 0)) for f in super().frames(v, visibility, frames)]


def test_a_plane_with_one_frame_missing_is_caught() -> None:
    problems = d4_problems(OneFrameShort(), (2, 5))
    assert len(problems) == 1 and "flip-anti" in problems[0]


def test_frames_that_do_not_centre_the_robot_are_caught() -> None:
    assert any("not (0, 0)" in p for p in d4_problems(FramesNotAtTheRobot(), (2, 5)))
    assert d4_problems(FramesNotAtTheRobot(), (0, 0)) == []  # only off the origin


@settings(max_examples=60, deadline=None)
@given(configurations, st.sampled_from(["none", "local-weak", "global-strong"]))
def test_a_frame_presents_the_view_the_z2_engine_presents(conf: tuple[list[Node], list[Node]],
                                                          detection: str) -> None:
    robots, meeting = conf
    c = Configuration(robots, meeting)
    for v in set(robots):
        for f in Plane().frames(v, None, "all"):
            view = View(c, v, f.element, detection)
            assert view.robots == {f.label(u) for u in robots}
            assert view.meeting_nodes == {f.label(u) for u in meeting}


def test_limited_visibility_is_refused_in_one_line() -> None:
    with pytest.raises(InvalidInput, match="visibility needs a finite world"):
        Plane().frames((0, 0), 2, "all")
    with pytest.raises(InvalidInput, match="unknown frames"):
        Plane().frames((0, 0), None, "some")


# -- canonical forms -----------------------------------------------------------------------

def invariance_problems(world: AnyWorld, robots: Sequence[Node], meeting: Sequence[Node],
                        shift: Node) -> list[str]:
    """The frames and translations under which the world's canonical form of a configuration
    changes (it must not: they are symmetries of Z², SEMANTICS.md §2)."""
    key = world.canonical(robots, meeting)
    out = []
    for f in world.frames(robots[0], None, "all"):
        def move(u: Node, f: AnyFrame = f) -> Node:
            return geometry.add(f.label(u), shift)

        if world.canonical([move(u) for u in robots], [move(u) for u in meeting]) != key:
            out.append(f"{f} then + {shift}")
    return out


@settings(max_examples=200, deadline=None)
@given(configurations)
def test_the_canonical_form_is_model_canonicals(conf: tuple[list[Node], list[Node]]) -> None:
    robots, meeting = conf
    z2 = Plane()
    assert z2.canonical(robots, meeting) == canonical(robots, meeting)[0]
    # a configuration's own form leaves multiplicity out: it is that of the occupied nodes
    assert z2.canonical(set(robots), meeting) == Configuration(robots,
                                                               meeting).canonical_form.key
    for frames, group in (("chirality", geometry.ROTATIONS), ("compass", (geometry.IDENTITY,))):
        assert z2.canonical(robots, meeting, frames) == canonical_form(robots, meeting,
                                                                       group).key


@settings(max_examples=200, deadline=None)
@given(configurations, node)
def test_the_canonical_form_is_invariant_under_the_frames_and_translations(
        conf: tuple[list[Node], list[Node]], shift: Node) -> None:
    robots, meeting = conf
    assert invariance_problems(Plane(), robots, meeting, shift) == []


class TranslationsOnly(Plane):
    """A broken Z²: its canonical form forgets D4 (it merges translates only)."""

    def canonical(self, robots, meeting, frames="all"):  # noqa: ANN001, ANN201
        return canonical_form(robots, meeting, (geometry.IDENTITY,)).key


def test_a_canonical_form_blind_to_d4_is_caught() -> None:
    robots, meeting = [(0, 0), (2, 1)], [(1, 0)]
    problems = invariance_problems(TranslationsOnly(), robots, meeting, (4, -1))
    assert problems and len(problems) < 8  # the identity (and a symmetry, if any) keep it
    assert invariance_problems(TranslationsOnly(), robots, meeting, (0, 0))


def test_the_canonical_form_under_compass_keeps_orientation() -> None:
    z2 = Plane()
    a, b = [(0, 0), (2, 1)], [(0, 0), (1, 2)]  # one is the other reflected in x = y
    assert z2.canonical(a, [(5, 5)]) == z2.canonical(b, [(5, 5)])
    assert z2.canonical(a, [(5, 5)], "compass") != z2.canonical(b, [(5, 5)], "compass")


def test_a_finite_worlds_canonical_form_is_the_least_image_under_its_symmetries() -> None:
    ring = get_world("ring:8")
    assert isinstance(ring, World)
    key = ring.canonical([1, 4], [6])
    for p in ring.automorphisms:
        assert ring.canonical([p[1], p[4]], [p[6]]) == key
    assert ring.canonical([1, 4], [6], "chirality") != ring.canonical([6, 3], [1],
                                                                        "chirality")


def test_z2_has_no_drawing_of_its_own() -> None:
    assert Plane().drawing() is None
    assert get_world("ring:4").drawing()["nodes"]
