"""Start sets as the papers name them (SEMANTICS.md §9, §12): every initial configuration of
k robots that is periodic, aperiodic, symmetric, asymmetric (rigid), or all of them, one per
class under the world's symmetries.

A configuration's *stabiliser* is the set of automorphisms of the world that map its robots
(and its meeting nodes) onto themselves. On a ring, Aut(G) is the dihedral group: the
rotations and the reflections.

- **periodic**: invariant under a rotation other than the identity (rings only);
- **aperiodic**: not periodic;
- **symmetric**: invariant under some automorphism other than the identity (a reflection
  or a rotation);
- **asymmetric**, or **rigid**: no automorphism but the identity maps it onto itself.

>>> from gather_verify.worlds import get_world
>>> ring = get_world("ring:9")
>>> describe(ring, (0, 3, 6)), describe(ring, (0, 1, 3)), describe(ring, (0, 1, 2))
('periodic', 'rigid', 'symmetric')
>>> [c for c in starts(ring, 3, "periodic")]
[(0, 3, 6)]
"""

from __future__ import annotations

from collections.abc import Collection, Sequence
from itertools import combinations

from gather_verify.errors import InvalidInput
from gather_verify.worlds.base import World

START_SETS = ("all", "aperiodic", "asymmetric", "rigid", "periodic", "symmetric")
"""The words ``--start`` takes (docs/synthesis.md defines each once)."""
RING_ONLY = ("aperiodic", "periodic")
"""The words defined by rotations: a ring's."""


def stabiliser(world: World, robots: Collection[int],
               meeting: Collection[int] = ()) -> list[tuple[int, ...]]:
    """The automorphisms of ``world`` that map the robots' nodes, and the meeting nodes,
    onto themselves (the identity among them)."""
    nodes, marks = frozenset(robots), frozenset(meeting)
    return [p for p in world.automorphisms
            if frozenset(p[v] for v in nodes) == nodes
            and frozenset(p[v] for v in marks) == marks]


def rotations(world: World) -> frozenset[tuple[int, ...]]:
    """The rotations of a ring other than the identity (``v -> v + r``, r = 1 .. N-1)."""
    n = world.size
    return frozenset(tuple((v + r) % n for v in range(n)) for r in range(1, n))


def periodic(world: World, robots: Collection[int], meeting: Collection[int] = ()) -> bool:
    """Invariant under a rotation other than the identity (rings only)."""
    turns = rotations(world)
    return any(p in turns for p in stabiliser(world, robots, meeting))


def rigid(world: World, robots: Collection[int], meeting: Collection[int] = ()) -> bool:
    """No automorphism but the identity maps the configuration onto itself."""
    return len(stabiliser(world, robots, meeting)) == 1


def describe(world: World, robots: Collection[int], meeting: Collection[int] = ()) -> str:
    """One word for a configuration: ``periodic`` (rings), else ``symmetric``, else
    ``rigid``."""
    if world.kind == "ring" and periodic(world, robots, meeting):
        return "periodic"
    return "rigid" if rigid(world, robots, meeting) else "symmetric"


def in_set(world: World, word: str, robots: Collection[int],
           meeting: Collection[int] = ()) -> bool:
    """Whether the configuration belongs to the start set ``word``."""
    if word == "all":
        return True
    if word in ("periodic", "aperiodic"):
        return periodic(world, robots, meeting) == (word == "periodic")
    if word in ("rigid", "asymmetric"):
        return rigid(world, robots, meeting)
    return not rigid(world, robots, meeting)  # symmetric


def check_word(world: World, word: str) -> None:
    """One line (:class:`InvalidInput`) for a start set the world does not define."""
    if word not in START_SETS:
        raise InvalidInput(f"--start {word!r}: use one of {', '.join(START_SETS)}")
    if word in RING_ONLY and world.kind != "ring":
        raise InvalidInput(f"--start {word}: periodic is defined by rotations, on rings only "
                           f"({world.name} is not a ring); use all, rigid or symmetric")


def starts(world: World, k: int, word: str = "all", meeting: Collection[int] = (),
           frames: str = "all") -> list[tuple[int, ...]]:
    """Every initial configuration of ``k`` robots on distinct nodes in the start set
    ``word``, one per class under the world's symmetries that the robots' frames move along
    and that fix the meeting nodes (its least member), in lexicographic order."""
    check_word(world, word)
    marks = frozenset(meeting)
    group = [p for p in world.symmetries(frames)
             if frozenset(p[v] for v in marks) == marks]
    out = []
    for robots in combinations(range(world.size), k):
        if min(tuple(sorted(p[v] for v in robots)) for p in group) == robots \
                and in_set(world, word, robots, marks):
            out.append(robots)
    return out


def counts(world: World, configurations: Sequence[Sequence[int]],
           meeting: Collection[int] = ()) -> dict[str, int]:
    """How many configurations are periodic, symmetric (not periodic) and rigid."""
    out = {"periodic": 0, "symmetric": 0, "rigid": 0}
    for c in configurations:
        out[describe(world, c, meeting)] += 1
    return out
