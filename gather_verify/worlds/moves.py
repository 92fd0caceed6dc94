"""Move sets on a finite world: the union over a robot's frames of its algorithm's answer
(SEMANTICS.md §3, §9).

>>> from gather_verify.algorithms import get_algorithm
>>> from gather_verify.worlds import get_world
>>> moves = WorldMoves(get_world("ring:9"), get_algorithm("go-to-target"), frozenset({7}))
>>> {v: sorted(s) for v, s in moves((0, 3, 5)).items()}
{0: [8], 3: [4], 5: [6]}
"""

from __future__ import annotations

from collections import Counter

from gather_verify.algorithms.base import Algorithm, AlgorithmCrash, AlgorithmError, Unhandled
from gather_verify.algorithms.moves import HiddenRead
from gather_verify.model.view import MultiplicityHidden, check_detection
from gather_verify.worlds.base import World
from gather_verify.worlds.view import WorldView

MEMO_SIZE = 1 << 18
"""Configurations whose move sets a search keeps (then the memo starts over)."""


class WorldMoves:
    """``robots (sorted node indices) -> {occupied node: its move set}`` for one algorithm
    on one world, memoised per configuration (decisions depend on nothing else)."""

    def __init__(self, world: World, algorithm: Algorithm, meeting: frozenset[int],
                 detection: str = "local-weak", frames: str = "all",
                 visibility: int | None = None):
        check_detection(detection)
        self.world, self.algorithm, self.meeting = world, algorithm, meeting
        self.detection, self.frames, self.visibility = detection, frames, visibility
        self._memo: dict[tuple[int, ...], dict[int, frozenset[int]]] = {}
        world.frames(0, visibility, frames)  # bad frames (chirality on a graph) fail here

    def __call__(self, robots: tuple[int, ...]) -> dict[int, frozenset[int]]:
        got = self._memo.get(robots)
        if got is None:
            counts = Counter(robots)
            got = {v: self.move_set(counts, v) for v in counts}
            if len(self._memo) >= MEMO_SIZE:
                self._memo.clear()
            self._memo[robots] = got
        return got

    def move_set(self, counts: Counter[int], node: int) -> frozenset[int]:
        """The nodes the robots on ``node`` may go to (``node`` itself: stay)."""
        algorithm, out = self.algorithm, set()
        for frame in self.world.frames(node, self.visibility, self.frames):
            view = WorldView(self.world, counts, self.meeting, node, frame, self.detection)
            try:
                answer = algorithm.decide(view)  # type: ignore[arg-type]
            except MultiplicityHidden as error:
                raise HiddenRead(f"algorithm {algorithm.name!r} reads multiplicity its robots "
                                 f"cannot see: {error}") from None
            except (Unhandled, KeyboardInterrupt):
                raise
            except BaseException as error:  # SystemExit too: user code never ends the verifier
                raise AlgorithmCrash(algorithm.name, "decide", error,
                                     self.world.label(node), view) from None
            back = frame.inverse.get(answer) if _hashable(answer) else None
            if back is None or (back != node and back not in self.world.adjacency[node]):
                error = AlgorithmError(
                    f"algorithm {algorithm.name!r} answered {answer!r}: a move must be view.me "
                    f"({view.me!r}) or one of its neighbours {list(view.neighbours())}")
                raise AlgorithmCrash(algorithm.name, "decide", error,
                                     self.world.label(node), view) from None
            out.add(back)
        return frozenset(out)


def _hashable(value: object) -> bool:
    try:
        hash(value)
    except TypeError:
        return False
    return True
