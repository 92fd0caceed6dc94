"""Move sets on a finite world: the union over a robot's frames of its algorithm's answer
(SEMANTICS.md §3, §9), with the robot's light (§10).

An answer is a node of the view (keep the colour) or, for a luminous algorithm, a pair
``(node, colour)``. A robot's *actions* are the pairs ``(destination, colour)`` in
global node indices.

>>> from gather_verify.algorithms import get_algorithm
>>> from gather_verify.worlds import get_world
>>> moves = WorldMoves(get_world("ring:9"), get_algorithm("go-to-target"), frozenset({7}))
>>> [sorted(a) for a in moves.actions(((0, None, 0), (3, None, 0), (5, None, 0)))]
[[(8, 0)], [(4, 0)], [(6, 0)]]
"""

from __future__ import annotations

from collections import Counter

from gather_verify.algorithms.base import Algorithm, AlgorithmCrash, AlgorithmError, Unhandled
from gather_verify.algorithms.moves import HiddenRead
from gather_verify.errors import InvalidInput
from gather_verify.model.view import MultiplicityHidden, check_detection
from gather_verify.watchdog import Overtime, real_interrupt, watched
from gather_verify.worlds.base import World
from gather_verify.worlds.view import LightHidden, Lights, WorldView

MEMO_SIZE = 1 << 18
"""Configurations whose actions a search keeps (then the memo starts over)."""
LightedRobots = tuple[tuple[int, int | None, int], ...]


class WorldMoves:
    """Per configuration (nodes and colours), each robot's actions, memoised (decisions
    depend on nothing else)."""

    def __init__(self, world: World, algorithm: Algorithm, meeting: frozenset[int],
                 detection: str = "local-weak", frames: str = "all",
                 visibility: int | None = None, lights: Lights | None = None):
        check_detection(detection)
        self.world, self.algorithm, self.meeting = world, algorithm, meeting
        self.detection, self.frames, self.visibility = detection, frames, visibility
        self.lights = lights or Lights(1)
        self._memo: dict[tuple[tuple[int, int], ...], dict[tuple[int, int],
                                                            frozenset[tuple[int, int]]]] = {}
        hook = getattr(algorithm, "answers_by_node", None)
        self._by_node: dict[tuple[int, int], frozenset[tuple[int, int]]] | None = (
            {} if hook is not None and hook() else None)
        world.frames(0, visibility, frames)  # bad frames (chirality on a graph) fail here

    @property
    def by_node(self) -> bool:
        """Whether the algorithm's answers depend on the robot's node (and colour) only
        (its ``answers_by_node`` hook, go-to-target's)."""
        return self._by_node is not None

    def actions(self, robots: LightedRobots) -> list[frozenset[tuple[int, int]]]:
        """Each robot's actions ``(destination, colour)`` in the configuration of ``robots``
        (a robot with a pending move is listed too: its view is that of the snapshot)."""
        seen = tuple(sorted((v, c) for v, _, c in robots))
        table = self._memo.get(seen)
        if table is None:
            table = self.table(seen)
            if len(self._memo) >= MEMO_SIZE:
                self._memo.clear()
            self._memo[seen] = table
        return [table[v, c] for v, _, c in robots]

    def table(self, seen: tuple[tuple[int, int], ...]
              ) -> dict[tuple[int, int], frozenset[tuple[int, int]]]:
        """The actions of every robot of the configuration ``seen`` (its robots' (node,
        colour) pairs, sorted), by (node, colour); not memoised. Raises what the algorithm
        raises (:class:`AlgorithmCrash`, :class:`Unhandled`) for the first pair that fails,
        in the same order whoever asks."""
        by_node = self._by_node
        if by_node is not None:
            # an algorithm that reads only its node, the graph and the meeting nodes
            # (``answers_by_node``): each node's actions once, whatever the configuration
            out = {}
            for v, c in set(seen):
                got = by_node.get((v, c))
                if got is None:
                    got = by_node[v, c] = self.table_of(seen, v, c)
                out[v, c] = got
            return out
        counts, colours = _counted(seen)
        return {(v, c): self.action_set(counts, colours, v, c) for v, c in set(seen)}

    def table_of(self, seen: tuple[tuple[int, int], ...], node: int,
                 colour: int) -> frozenset[tuple[int, int]]:
        """The actions of the robots on ``node`` with light ``colour`` in ``seen``."""
        counts, colours = _counted(seen)
        return self.action_set(counts, colours, node, colour)

    def action_set(self, counts: Counter[int], colours: dict[int, Counter[int]], node: int,
                   colour: int) -> frozenset[tuple[int, int]]:
        """What the robots on ``node`` with light ``colour`` may do."""
        algorithm, out = self.algorithm, set()
        for frame in self.world.frames(node, self.visibility, self.frames):
            view = WorldView(self.world, counts, self.meeting, node, frame, self.detection,
                             self.lights, colours, colour)
            try:
                with watched():  # an endless decide ends with the time limit (watchdog)
                    answer = algorithm.decide(view)
            except (MultiplicityHidden, LightHidden) as error:
                raise HiddenRead(f"algorithm {algorithm.name!r} reads what its robots cannot "
                                 f"see: {error}") from None
            except (Unhandled, Overtime):  # no rule; the watchdog's stop at the time limit
                raise
            except BaseException as error:  # SystemExit, KeyboardInterrupt, os._exit too
                if real_interrupt(error):  # only a real Ctrl-C stops the verifier
                    raise
                raise AlgorithmCrash(algorithm.name, "decide", error,
                                     self.world.label(node), view) from None
            out.add(self._action(answer, frame, node, colour, view))
        return frozenset(out)

    def _action(self, answer: object, frame: object, node: int, colour: int,
                view: WorldView) -> tuple[int, int]:
        """An answer as ``(destination index, colour)``, or a crash naming what is wrong."""
        target, new = answer, colour
        back = frame.inverse.get(answer) if _hashable(answer) else None  # type: ignore[attr-defined]
        if back is None and isinstance(answer, tuple) and len(answer) == 2:
            target, new = answer
            back = frame.inverse.get(target) if _hashable(target) else None  # type: ignore[attr-defined]
        problem = None
        if back is None or (back != node and back not in self.world.adjacency[node]):
            problem = (f"answered {answer!r}: a move must be view.me ({view.me!r}) or one of "
                       f"its neighbours {list(view.neighbours())}, or such a node with a "
                       "colour, (node, colour)")
        elif isinstance(new, bool) or not isinstance(new, int) or \
                not 0 <= new < self.lights.colours:
            problem = (f"answered colour {new!r}: the lights have colours 0.."
                       f"{self.lights.colours - 1}")
        if problem is not None:
            raise AlgorithmCrash(self.algorithm.name, "decide",
                                 AlgorithmError(f"algorithm {self.algorithm.name!r} {problem}"),
                                 self.world.label(node), view) from None
        return back, new


def _counted(seen: tuple[tuple[int, int], ...]) -> tuple[Counter[int], dict[int, Counter[int]]]:
    """The robots per node, and the colours per node, of a configuration."""
    counts = Counter(v for v, _ in seen)
    colours: dict[int, Counter[int]] = {}
    for v, c in seen:
        colours.setdefault(v, Counter())[c] += 1
    return counts, colours


def parse_lights(text: str | None) -> Lights:
    """``--lights K`` or ``K:external`` / ``K:internal`` (K >= 1 colours)."""
    if text is None:
        return Lights(1)
    count, colon, variant = text.partition(":")
    if not (count.isascii() and count.isdigit()):  # int() takes ' 2', '+2', '٢', '2_0'
        raise InvalidInput(f"--lights {text!r}: write K, K:external or K:internal (K in "
                           "the digits 0-9)")
    k = int(count, 10)
    if not 1 <= k <= 64:
        raise InvalidInput(f"--lights {k}: the number of colours must be in [1, 64]")
    if colon and variant not in ("external", "internal"):
        raise InvalidInput(f"--lights {text!r}: the variant is external or internal")
    return Lights(k, variant or "full")


def _hashable(value: object) -> bool:
    try:
        hash(value)
    except TypeError:
        return False
    return True
