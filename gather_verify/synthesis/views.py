"""The instance a synthesis answers for, and the views its robots meet (SEMANTICS.md §12).

A view is known by its key (:mod:`gather_verify.synthesis.viewkey`). Its *options* are
the answers an algorithm may give there: stay or step to a visible neighbour, each with a
colour under lights, up to the view's own symmetries (two answers one symmetry of the view
swaps give the robot the same move set, so they are one option). An *occurrence* is a robot
on a node, with a colour, in a configuration: there each option is a set of actions
``(destination, colour)`` in node indices, the union over the robot's frames, exactly as
:class:`~gather_verify.worlds.moves.WorldMoves` computes it for an algorithm file.

>>> inst = make_instance("ring:6", "0 2", "", "ssync", "gathering")
>>> views = Views(inst)
>>> k, acts = views.occurrence(((0, 0), (2, 0)), 0, 0)
>>> views.texts[k], [sorted(a) for a in acts]
('[0,-1,[[0,[0,1,0,[]]],[1,[0,0,-1,[]]],[2,[0,0,-1,[]]],[3,[0,0,-1,[]]],[4,[0,1,-1,[]]],[5,[0,0,-1,[]]]]]', [[(0, 0)], [(5, 0)], [(1, 0)]])
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass
from typing import Any

from gather_verify.errors import InvalidInput
from gather_verify.model.view import check_detection
from gather_verify.synthesis import viewkey
from gather_verify.synthesis.starts import starts
from gather_verify.tasks import Task, get_task
from gather_verify.world_check import default_task
from gather_verify.worlds import FINITE, get_world
from gather_verify.worlds.base import FrameMap, World, decimal
from gather_verify.worlds.moves import parse_lights
from gather_verify.worlds.view import Lights, WorldView
from schedulers import get_scheduler, not_phased

Answer = tuple[object, int | None]
"""An answer in the key's labels: the destination label and the new colour (None: keep)."""
Seen = tuple[tuple[int, int], ...]
"""A configuration as the robots see it: the sorted (node, colour) of every robot."""


@dataclass(frozen=True)
class Instance:
    """Everything a synthesis is asked for: the world, the capabilities, the adversary, the
    task and the initial configurations (robots in order, their colours)."""

    world: World
    world_spec: str
    detection: str
    frames: str
    visibility: int | None
    lights: Lights
    scheduler: str
    task: Task
    meeting: frozenset[int]
    configurations: tuple[tuple[tuple[int, ...], tuple[int, ...]], ...]
    robots_text: str
    """The ``--robots`` text: one configuration, or a count (every class of them)."""
    start: str | None = None
    """With a count: the start set (:mod:`~gather_verify.synthesis.starts`) the
    configurations were taken from (None: every one, as ``all``)."""

    def describe(self) -> dict[str, object]:
        """The instance as JSON (what a certificate names)."""
        w = self.world
        return {
            "world": self.world_spec,
            "detection": self.detection, "frames": self.frames,
            "visibility": self.visibility, "lights": str(self.lights),
            "scheduler": self.scheduler, "task": self.task.name,
            "meeting_nodes": [w.node_to_json(v) for v in sorted(self.meeting)],
            "robots": self.robots_text,
            "colours": " ".join(str(c) for c in self.configurations[0][1])
            if not self.robots_text.isdigit() else None,
            "configurations": [{"robots": [w.node_to_json(v) for v in r], "colours": list(c)}
                               for r, c in self.configurations],
            **({"graph_sha256": digest} if isinstance(digest := getattr(w, "digest", None), str)
               else {}),
            **({"start": self.start} if self.start is not None else {}),
        }


def make_instance(world: str, robots: str, meeting: str, scheduler: str, task: str | None,
                  detection: str = "local-weak", frames: str = "all",
                  visibility: int | None = None, lights: str | None = None,
                  colours: str | None = None, start: str | None = None) -> Instance:
    """The instance from command-line text; one line (:class:`InvalidInput`) for anything
    the synthesis cannot take. ``start``: with a count of robots, the start set
    (:data:`~gather_verify.synthesis.starts.START_SETS`) the configurations come from."""
    w = get_world(world)
    if not isinstance(w, World) or w.entry != FINITE:
        raise InvalidInput("these views are a finite world's (--world ring:N, grid:WxH, "
                           "torus:WxH or graph:FILE); the paper's world Z² has its own "
                           "synthesis: synthesize --world grid")
    check_detection(detection)
    not_phased(scheduler, "in synthesis (not built yet)")
    sched = get_scheduler(scheduler)
    light = parse_lights(lights)
    if light.variant == "external" and light.colours > 1:
        raise InvalidInput("synthesize takes full or internal lights: under external lights "
                           "a robot may keep a colour it cannot see, which the search does not "
                           "encode yet")
    if visibility is not None and visibility < 0:
        raise InvalidInput(f"visibility {visibility} is negative: give a number of hops >= 0")
    m = w.parse_nodes(meeting) if meeting.strip() else []
    if len(set(m)) != len(m):
        raise InvalidInput("--meeting names a node twice")
    t = get_task(task or default_task(m))
    if t.needs_meeting and not m:
        raise InvalidInput(f"task {t.name} needs meeting nodes: give --meeting")
    if t.visits and w.size > 62:
        raise InvalidInput(f"task {t.name} tracks visited nodes in the state: {w.name} has "
                           f"{w.size} nodes, at most 62 are supported")
    text = robots.strip()
    if not text:
        raise InvalidInput("--robots is empty: give nodes (\"0 2\") or a count (2)")
    if text.isascii() and text.isdigit():  # a count; int() also takes '٢'
        k = int(text)
        if not 1 <= k <= w.size:
            raise InvalidInput(f"--robots {k}: between 1 and {w.size} robots on {w.name}")
        if colours is not None and colours.strip():
            raise InvalidInput("--colours goes with one configuration (--robots \"0 1\"), not "
                               "a count")
        configurations = tuple((r, (0,) * k)
                               for r in starts(w, k, start or "all", frozenset(m), frames))
        if not configurations:
            raise InvalidInput(f"--start {start}: no initial configuration of {k} robots on "
                               f"{w.name} is {start}")
    else:
        if start is not None:
            raise InvalidInput("--start goes with a count of robots (--robots 3), not one "
                               "configuration")
        r = tuple(w.parse_nodes(text))
        if len(set(r)) != len(r):
            raise InvalidInput("--robots: an initial configuration has robots on distinct nodes")
        lit = (0,) * len(r)
        if colours is not None and colours.strip():
            try:
                lit = tuple(decimal(c) for c in colours.split())
            except ValueError:
                raise InvalidInput(f"--colours {colours!r}: one integer colour per robot"
                                   ) from None
            if len(lit) != len(r) or not all(0 <= c < light.colours for c in lit):
                raise InvalidInput(f"--colours {colours!r}: one colour per robot, each in "
                                   f"0..{light.colours - 1}")
        configurations = ((r, lit),)
    if getattr(sched, "stateful", False) and len(configurations[0][0]) > 6:
        raise InvalidInput("round-robin starts from every order of the robots: at most 6")
    return Instance(w, world, detection, frames, visibility, light, scheduler, t, frozenset(m),
                    configurations, text, start)


def classes(world: World, k: int, meeting: frozenset[int], frames: str) -> list[tuple[int, ...]]:
    """Every initial configuration of ``k`` robots on distinct nodes, one per class under the
    world's symmetries (those the robots' frames move along, §9) that fix the meeting nodes,
    its least member, in lexicographic order (as ``sweep --world`` counts them)."""
    return starts(world, k, "all", meeting, frames)


class Views:
    """The views the robots meet, found as the search goes: their keys (``texts``, index =
    key id), their options, and per occurrence each option's actions."""

    def __init__(self, inst: Instance):
        self.inst = inst
        self.world = inst.world
        self.group = viewkey.build(inst.world.frame_group(inst.frames, inst.visibility))
        self.texts: list[str] = []
        self.index: dict[str, int] = {}
        self.options: list[list[Answer]] = []
        self._labels: list[list[list[object]]] = []  # per key, per option: its labels' orbit
        self.first: list[tuple[int, Seen, int, int]] = []
        """Per key: where it was met first (this views' part, the configuration, the node,
        the colour), for the seeds (:func:`~gather_verify.synthesis.search.synthesize`)."""
        self.still: list[list[int]] = []
        """Per key: its options that leave the robot on its node (a colour change at most)."""
        self.movers: list[tuple[int, ...]] = []
        """The distinct keys of the robots of each configuration met that has more than one
        (in the order met, once each): what a search that lets one class move restricts
        (:mod:`~gather_verify.synthesis.search`)."""
        self._movers_met: set[tuple[int, ...]] = set()
        self.crowded: list[int] = []
        """The keys held by more than one robot of their configuration (the twins of a
        symmetric configuration, or the robots of a tower), in the order met: what a search
        that lets one robot move restricts (:mod:`~gather_verify.synthesis.search`)."""
        self._crowded_met: set[int] = set()
        self.part = 0
        self._memo: dict[Seen, dict[tuple[int, int], tuple[int, tuple[frozenset, ...]]]] = {}
        self._checked: set[int] = set()

    def share(self, other: Views, part: int) -> None:
        """Key this part's views in ``other``'s table (one variable per key and option for
        every part of a search); ``part`` names this one in the table's ``first``."""
        self.texts, self.index, self.options = other.texts, other.index, other.options
        self._labels, self.first, self.part = other._labels, other.first, part
        self.still, self.movers, self._movers_met = other.still, other.movers, other._movers_met
        self.crowded, self._crowded_met = other.crowded, other._crowded_met

    # -- one occurrence -----------------------------------------------------------------
    def occurrence(self, seen: Seen, node: int, colour: int
                   ) -> tuple[int, tuple[frozenset[tuple[int, int]], ...]]:
        """The key of the robot on ``node`` with ``colour`` in ``seen``, and per option of
        that key its actions there."""
        table = self._memo.get(seen)
        if table is None:
            if len(self._memo) > 200_000:
                self._memo.clear()
            table = self._memo[seen] = {}
        got = table.get((node, colour))
        if got is None:
            got = table[node, colour] = self._compute(seen, node, colour)
        return got

    def robots(self, robots: tuple[tuple[int, int | None, int], ...]
               ) -> list[tuple[int, tuple[frozenset[tuple[int, int]], ...]]]:
        """Per robot of a state, its key and its options' actions."""
        seen = tuple(sorted((v, c) for v, _, c in robots))
        new = seen not in self._memo
        got = [self.occurrence(seen, v, c) for v, _, c in robots]
        if new:
            held = Counter(k for k, _ in got)
            keys = tuple(sorted(held))
            if len(keys) > 1 and keys not in self._movers_met:
                self._movers_met.add(keys)
                self.movers.append(keys)
            for k in keys:
                if held[k] > 1 and k not in self._crowded_met:
                    self._crowded_met.add(k)
                    self.crowded.append(k)
        return got

    def _compute(self, seen: Seen, node: int, colour: int
                 ) -> tuple[int, tuple[frozenset[tuple[int, int]], ...]]:
        inst, world, group = self.inst, self.world, self.group
        self._check_frames(node)
        counts = Counter(v for v, _ in seen)
        colours: dict[int, Counter[int]] = {}
        for v, c in seen:
            colours.setdefault(v, Counter())[c] += 1
        per_frame = []
        key = None
        for frame in world.frames(node, inst.visibility, inst.frames):
            view = WorldView(world, counts, inst.meeting, node, frame, inst.detection,
                             inst.lights, colours, colour)
            got, t = viewkey.canonical(group, viewkey.observe(
                view, inst.detection, inst.lights.colours, inst.lights.variant))
            if key is None:
                key, first_view, first_t = got, view, t
            elif got != key:  # pragma: no cover - the orbit check above rules it out
                raise AssertionError(f"two frames of one view have two keys at node {node}")
            per_frame.append((frame, t))
        text = viewkey.key_text(key)
        k = self.index.get(text)
        if k is None:
            k = self._new_key(text, key, first_view, first_t, per_frame)
            self.first.append((self.part, seen, node, colour))
        acts = []
        for labels, (answer, new) in zip(self._labels[k], self.options[k], strict=True):
            # the move set of the answer the witness gives (the option's first label), over
            # the robot's frames, exactly as the checker will compute it
            dests = {frame.inverse[viewkey.inverse(group, t, answer)] for frame, t in per_frame}
            if len(labels) > 1 and dests != {frame.inverse[viewkey.inverse(group, t, label)]
                                             for label in labels for frame, t in per_frame}:
                raise AssertionError(f"the answers of one option of view {k} move the robot "
                                     "differently: the options are not up to the view's "
                                     "symmetries")
            acts.append(frozenset((d, colour if new is None else new) for d in dests))
        return k, tuple(acts)

    def _new_key(self, text: str, key: Any, view: WorldView, t: int,
                 per_frame: list[tuple[FrameMap, int]]) -> int:
        """Register a key: its options, the answers up to the view's symmetries (labels whose
        destinations coincide at one occurrence are one orbit, hence one option)."""
        group = self.group
        me = key[0]
        labels = [me] + sorted((viewkey.image(group, t, n) for n in view.neighbours()),
                               key=_order)
        orbits: dict[frozenset[int], list[object]] = {}
        for label in labels:
            dests = frozenset(frame.inverse[viewkey.inverse(group, tf, label)]
                              for frame, tf in per_frame)
            orbits.setdefault(dests, []).append(label)
        groups = sorted(orbits.values(), key=lambda ls: _order(ls[0]))
        k_colours = self.inst.lights.colours
        colours: list[int | None] = [None] if k_colours == 1 else list(range(k_colours))
        k = len(self.texts)
        self.texts.append(text)
        self.index[text] = k
        self.options.append([(ls[0], c) for ls in groups for c in colours])
        self._labels.append([ls for ls in groups for _ in colours])
        self.still.append([o for o, ls in enumerate(self._labels[k]) if me in ls])
        return k

    def _check_frames(self, node: int) -> None:
        """The group moves one frame of ``node`` onto every other (§9's frames are its
        orbit): else keys would not be up to isomorphism. Once per node."""
        if node in self._checked:
            return
        frames = self.world.frames(node, self.inst.visibility, self.inst.frames)
        want = {frozenset(f.labels.items()) for f in frames}
        first = frames[0].labels
        got = {frozenset((u, viewkey.image(self.group, t, label)) for u, label in first.items())
               for t in range(viewkey.size(self.group))}
        if got != want:
            raise InvalidInput(f"{self.world.name}: the frames at node "
                               f"{self.world.format_node(node)} are not one orbit of a group of "
                               "label maps; synthesize cannot key its views")
        self._checked.add(node)

    # -- options ------------------------------------------------------------------------
    def stay_option(self, k: int, acts: tuple[frozenset, ...], node: int, colour: int) -> int:
        """The option whose only action is to stay as it is (-1 if none)."""
        for o, a in enumerate(acts):
            if a == {(node, colour)}:
                return o
        return -1

    def option_of(self, acts: tuple[frozenset, ...], action: tuple[int, int]) -> int:
        """The one option that holds ``action`` at this occurrence."""
        found = [o for o, a in enumerate(acts) if action in a]
        if len(found) != 1:
            raise AssertionError(f"action {action} is in {len(found)} options")
        return found[0]


def _order(label: object) -> tuple[int, object]:
    return (0, label) if not isinstance(label, str) else (1, label)
