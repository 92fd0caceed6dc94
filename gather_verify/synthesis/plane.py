"""Synthesis on the paper's world: Z² with meeting nodes (SEMANTICS.md §1-6, §12).

Two answers are built here, each backed by something the ordinary code re-checks:

- **none**, for an initial configuration that meets Theorem 1's hypothesis (paper §3.2):
  an automorphism ``phi`` of the labelled configuration whose fixed nodes ``V'`` hold no
  robot and no meeting node, and whose linear part is one of the robots' frames. The
  certificate names ``phi``; :func:`verify_certificate` re-checks it without any search
  over algorithms: the hypothesis (finite checks), and the *over-approximation* of
  Theorem 1's FSYNC adversary (:func:`adversary_closure`) for a stated number of rounds,
  in which every view may answer anything at all and the only restriction is the one the
  view's symmetry forces (robots whose views are ``phi``-images of each other answer
  ``phi``-images of each other). On each configuration it reaches, the project's own view
  code must give the ``phi``-image of a robot's view the same key and the ``phi``-image of
  each option's move set; no configuration it reaches has every robot on one meeting node.
- **exists**: a lookup table from views up to isomorphism to answers, found by a SAT solver
  proposing tables and the ordinary Z² checker judging them
  (:func:`search_algorithm`), written as an algorithm file that the checker then verifies
  with every reduction off. Its clauses are heuristics (a table that leaves the region is
  excluded too), so an empty solver gives ``unknown``, never ``none``.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import time
from collections import Counter, deque
from collections.abc import Callable
from dataclasses import dataclass, field
from itertools import combinations
from pathlib import Path
from typing import Any

from gather_verify.algorithms.base import Unhandled
from gather_verify.errors import InvalidInput
from gather_verify.model import geometry
from gather_verify.model.canonical import canonical_form
from gather_verify.model.configuration import Configuration
from gather_verify.model.geometry import Node
from gather_verify.model.symmetry import (
    Automorphism,
    configuration_automorphisms,
    symmetry_defect,
)
from gather_verify.model.view import FRAME_SETS, View, check_detection
from gather_verify.synthesis import viewkey
from gather_verify.synthesis.certificate import CertificateError
from gather_verify.theory import get_fact

FORMAT = "gather-verify-plane-certificate/1"
TASK = "gathering-on-meeting-nodes"
COVERED_SCHEDULERS = ("fsync", "ssync", "async")
"""Theorem 1's adversary plays FSYNC rounds; an FSYNC round is also an SSYNC step (every
robot active) and an ASYNC sequence (every Look, then every Move), fair in each."""
DEFAULT_ROUNDS = 8
SELECTIONS = ("u", "outside-u", "all")
SEED_ROUND = 32
"""Candidates proposed with one seed's answers as the solver's phases before the next seed
takes over (the rounds double once every seed has had its turn)."""
CANDIDATE_SECONDS = 10.0
"""The least time one candidate's check gets before the search moves on (it gets a quarter
of what is left when that is more)."""

# -- views of Z² up to isomorphism --------------------------------------------------------


def group_description(frames: str) -> list[object]:
    """The robots' frames as a group of label maps (D4, the rotations, or the identity)."""
    return ["d4", [list(geometry.MATRICES[g]) for g in FRAME_SETS[frames]]]


class PlaneViews:
    """The views robots meet on Z², by key (index = key id), their options (answers up to
    the view's own symmetries, in the key's labels), and per occurrence each option's move
    set in global nodes: the union over the robot's frames, as
    :func:`~gather_verify.algorithms.moves.move_set` computes it for the witness."""

    def __init__(self, detection: str, frames: str):
        check_detection(detection)
        if frames not in FRAME_SETS:
            raise InvalidInput(f"unknown frames {frames!r}: use one of {', '.join(FRAME_SETS)}")
        self.detection, self.frames = detection, frames
        self.frame_ids = FRAME_SETS[frames]
        self.group = viewkey.build(group_description(frames))
        self.texts: list[str] = []
        self.index: dict[str, int] = {}
        self.options: list[list[Node]] = []
        self.first: list[tuple[Configuration, Node]] = []
        """Per key, the first occurrence met (a configuration and the robot's node)."""
        self._memo: dict[tuple[tuple[Node, ...], frozenset[Node], Node],
                         tuple[int, tuple[frozenset[Node], ...]]] = {}

    def occurrence(self, c: Configuration, node: Node) -> tuple[int, tuple[frozenset[Node], ...]]:
        """The key of the robots on ``node`` in ``c``, and per option its move set."""
        memo = (c.robots, c.meeting_nodes, node)
        got = self._memo.get(memo)
        if got is None:
            if len(self._memo) > 200_000:
                self._memo.clear()
            got = self._memo[memo] = self._compute(c, node)
        return got

    def key_of(self, c: Configuration, node: Node) -> tuple[str, int]:
        """The key text of the view at ``node`` in frame 0, and the map that gives it."""
        view = View.trusted(c, node, geometry.IDENTITY, self.detection)
        key, t = viewkey.canonical(self.group, viewkey.observe_plane(view, self.detection))
        return viewkey.key_text(key), t

    def _compute(self, c: Configuration, node: Node) -> tuple[int, tuple[frozenset[Node], ...]]:
        group = self.group
        per_frame = []
        text = None
        for g in self.frame_ids:
            view = View.trusted(c, node, g, self.detection)
            key, t = viewkey.canonical(group, viewkey.observe_plane(view, self.detection))
            got = viewkey.key_text(key)
            if text is None:
                text = got
            elif got != text:
                raise AssertionError(f"two frames of one view have two keys at {node}")
            per_frame.append((g, t))
        assert text is not None
        k = self.index.get(text)
        if k is None:
            k = self._register(text, node, per_frame)
            self.first.append((c, node))
        return k, tuple(self._dests(node, per_frame, label) for label in self.options[k])

    def _dests(self, node: Node, per_frame: list[tuple[int, int]], label: Node) -> frozenset[Node]:
        out = set()
        for g, t in per_frame:
            step = geometry.apply(geometry.inverse(g), viewkey.inverse(self.group, t, label))
            out.add(geometry.add(node, step))
        return frozenset(out)

    def _register(self, text: str, node: Node, per_frame: list[tuple[int, int]]) -> int:
        orbits: dict[frozenset[Node], list[Node]] = {}
        for label in (geometry.ORIGIN, *sorted(geometry.STEPS)):
            orbits.setdefault(self._dests(node, per_frame, label), []).append(label)
        k = len(self.texts)
        self.texts.append(text)
        self.index[text] = k
        self.options.append([labels[0] for labels in orbits.values()])
        return k


# -- Theorem 1's certificate -----------------------------------------------------------

def theorem1_phi(c: Configuration, frames: str) -> Automorphism | None:
    """An automorphism of the labelled configuration meeting Theorem 1's hypothesis (no
    robot and no meeting node on its fixed nodes) whose linear part is a frame of the
    robots; largest order first. None when there is none (the configuration is then
    outside U, or its symmetry is one the robots' frames do not share)."""
    marked = c.occupied | c.meeting_nodes
    allowed = FRAME_SETS[frames]
    found = [a for a in configuration_automorphisms(c)[1:]
             if a.g in allowed and not any(a.fixes(v) for v in marked)]
    return min(found, key=lambda a: (-a.order, a.g, a.t)) if found else None


def _state(c: Configuration) -> tuple[tuple[int, int, int], ...]:
    return tuple((x, y, k) for (x, y), k in sorted(Counter(c.robots).items()))


def _power(phi: Automorphism, j: int, v: Node) -> Node:
    for _ in range(j):
        v = phi(v)
    return v


@dataclass
class Closure:
    """The configurations Theorem 1's adversary may reach within ``rounds`` FSYNC rounds
    against any algorithm (the over-approximation), and their digest."""

    rounds: int
    states: int
    digest: str
    radius: int
    """How far from the initial MER any robot got (at most ``rounds``)."""


def adversary_closure(c0: Configuration, phi: Automorphism, views: PlaneViews,
                      rounds: int) -> Closure:
    """Every configuration Theorem 1's FSYNC adversary may reach within ``rounds`` rounds,
    whatever the algorithm: each group of robots (an orbit of ``<phi>`` outside ``V'``, or
    the robots on one node of ``V'``) may take *any* destination that *some* answer of its
    view gives (the union of its options' move sets), and the adversary moves the group's
    other robots to the ``phi``-images, as the proof's cases 1 to 4 do.

    At each configuration it checks what makes that choice available to the adversary for
    every algorithm, with the project's view code: the ``phi``-image of a robot's node has
    the same key, and each option's move set there is the ``phi``-image of the option's move
    set (so whatever the algorithm answers, the images are in the other robots' move sets);
    on ``V'``, each option's move set is closed under ``phi`` and the count is a multiple
    of k. And it checks the theorem's invariant: ``phi`` still maps the configuration onto
    itself, and not every robot is on one meeting node. Any failure: CertificateError."""
    meeting = c0.meeting_nodes
    x0, y0, x1, y1 = geometry.bounding_box(c0.robots)
    seen: dict[tuple[tuple[int, int, int], ...], int] = {_state(c0): 0}
    queue: deque[tuple[Configuration, int]] = deque([(c0, 0)])
    radius = 0
    while queue:
        c, depth = queue.popleft()
        defect = symmetry_defect(phi, c)
        if defect is not None:
            raise CertificateError(f"the adversary's invariant breaks after {depth} rounds: "
                                   f"{defect}")
        if c.is_gathered:
            raise CertificateError(f"every robot is on meeting node {list(c.robots[0])} after "
                                   f"{depth} rounds")
        for x, y in c.robots:
            radius = max(radius, x0 - x, x - x1, y0 - y, y - y1)
        if depth >= rounds:
            continue
        choices = _adversary_choices(c, phi, views)
        for pick in itertools.product(*choices):
            robots = tuple(sorted(d for group in pick for d in group))
            d = Configuration.trusted(robots, meeting)
            s = _state(d)
            if s not in seen:
                seen[s] = depth + 1
                queue.append((d, depth + 1))
    digest = hashlib.sha256(json.dumps(sorted(seen.items())).encode()).hexdigest()
    return Closure(rounds, len(seen), digest, radius)


def _adversary_choices(c: Configuration, phi: Automorphism, views: PlaneViews
                       ) -> list[list[list[Node]]]:
    """Per group of robots of ``c`` (the robots on one node of ``V'``, or an orbit of
    ``<phi>``), per destination some answer of its view gives: the group's destinations, as
    :func:`adversary_closure` moves them; CertificateError where the views let the algorithm
    break the symmetry."""
    k = phi.order
    counts = Counter(c.robots)
    choices: list[list[list[Node]]] = []
    done: set[Node] = set()
    for v in sorted(counts):
        if v in done:
            continue
        key, opts = views.occurrence(c, v)
        anything = sorted(set().union(*opts))
        if phi(v) == v:  # a node of V': reached by a multiplicity only
            done.add(v)
            choices.append(_fixed_group(phi, v, counts[v], opts, anything))
            continue
        orbit = phi.orbit(v)
        if len(orbit) != k:
            raise CertificateError(f"the orbit of {list(v)} has {len(orbit)} nodes, not {k}")
        done.update(orbit)
        for j, w in enumerate(orbit[1:], start=1):
            key_w, opts_w = views.occurrence(c, w)
            if key_w != key:
                raise CertificateError(f"the views on {list(v)} and on its image {list(w)} "
                                       "have different keys: phi is not a symmetry the "
                                       "robots cannot tell apart")
            for o, dests in enumerate(opts):
                if opts_w[o] != {_power(phi, j, d) for d in dests}:
                    raise CertificateError(f"option {o} moves the robots on {list(v)} and "
                                           f"{list(w)} asymmetrically")
        choices.append([[_power(phi, j, u) for j, w in enumerate(orbit)
                         for _ in range(counts[w])] for u in anything])
    return choices


def _fixed_group(phi: Automorphism, v: Node, count: int, opts: Any, anything: list[Node]
                 ) -> list[list[Node]]:
    """The choices of the ``count`` robots on ``v``, a node of ``V'``: each option's move
    set closed under ``phi``, the robots split evenly over each destination's orbit."""
    k = phi.order
    if count % k:
        raise CertificateError(f"{count} robots on {list(v)} in V' do not split "
                               f"over orbits of {k} nodes")
    for o, dests in enumerate(opts):
        if {phi(d) for d in dests} != dests:
            raise CertificateError(f"option {o} of the view on {list(v)} in V' is "
                                   "not closed under phi")
    group = []
    for u in anything:
        if phi(u) == u:
            group.append([u] * count)
        else:
            group.append([w for w in phi.orbit(u) for _ in range(count // k)])
    return group


def theorem1_entry(c: Configuration, phi: Automorphism, views: PlaneViews,
                   rounds: int) -> dict[str, Any]:
    """One configuration's part of a certificate of none."""
    closure = adversary_closure(c, phi, views, rounds)
    return {
        "robots": [list(v) for v in c.robots],
        "meeting_nodes": [list(v) for v in sorted(c.meeting_nodes)],
        "class": get_fact("class").of(c), "in_U": get_fact("in_U").of(c),
        "phi": {"g": phi.g, "t": list(phi.t), "describe": phi.describe(), "k": phi.order},
        "rounds": rounds, "states": closure.states, "radius": closure.radius,
        "digest": closure.digest,
    }


# -- the instance --------------------------------------------------------------------------

def parse_box(text: str) -> tuple[int, int]:
    """``WxH`` nodes."""
    w, sep, h = text.lower().partition("x")
    try:
        width, height = int(w, 10), int(h, 10)
    except ValueError:
        width = height = 0
    if not sep or not (1 <= width <= 8 and 1 <= height <= 8):
        raise InvalidInput(f"--box {text!r}: write WxH, each from 1 to 8 nodes (3x3)")
    return width, height


def parse_range(text: str, what: str, high: int) -> range:
    low, dash, top = text.strip().partition("-")
    try:
        a = int(low, 10)
        b = int(top, 10) if dash else a
    except ValueError:
        raise InvalidInput(f"{what} {text!r}: with --box, a count or a range A-B") from None
    if not 1 <= a <= b <= high:
        raise InvalidInput(f"{what} {text!r}: counts from 1 to {high}, A <= B")
    return range(a, b + 1)


def box_configurations(width: int, height: int, robots: range, meeting: range,
                       select: str, classes: tuple[str, ...] = ()) -> list[Configuration]:
    """Every initial configuration whose robots and meeting nodes lie in the ``width`` x
    ``height`` box of nodes (robots on distinct nodes, a robot may stand on a meeting node),
    one per class under translations and D4 (its first member in enumeration order), with
    ``select``: those in U (§2), those outside, or all; only the paper's ``classes`` when
    some are named."""
    if select not in SELECTIONS:
        raise InvalidInput(f"--select {select!r}: use one of {', '.join(SELECTIONS)}")
    nodes = [(x, y) for x in range(width) for y in range(height)]
    out = []
    keys: set[object] = set()
    for n in robots:
        for m in meeting:
            if n > len(nodes) or m > len(nodes):
                continue
            for ms in combinations(nodes, m):
                for rs in combinations(nodes, n):
                    key = (n, canonical_form(rs, ms)[0])
                    if key in keys:
                        continue
                    keys.add(key)
                    c = Configuration(list(rs), list(ms), initial=True)
                    if (select == "all" or (select == "u") == get_fact("in_U").of(c)) and (
                            not classes or get_fact("class").of(c) in classes):
                        out.append(c)
    return out


@dataclass
class PlaneInstance:
    """What a synthesis on Z² is asked: configurations, adversary, capabilities."""

    configurations: list[Configuration]
    scheduler: str
    detection: str
    frames: str
    box: dict[str, Any] | None = None

    def describe(self) -> dict[str, Any]:
        return {"world": "grid", "task": TASK, "scheduler": self.scheduler,
                "detection": self.detection, "frames": self.frames, "box": self.box}


def make_instance(robots: str, meeting: str, scheduler: str, task: str | None,
                  detection: str, frames: str, box: str | None = None,
                  select: str = "all", classes: str | None = None) -> PlaneInstance:
    """The instance from command-line text (one line of InvalidInput for anything else)."""
    from schedulers import get_scheduler

    get_scheduler(scheduler)
    check_detection(detection)
    if frames not in FRAME_SETS:
        raise InvalidInput(f"unknown frames {frames!r}: use one of {', '.join(FRAME_SETS)}")
    if task not in (None, TASK, "gathering"):
        raise InvalidInput(f"task {task!r} on the paper's world: synthesize takes "
                           f"{TASK} (the paper's task)")
    if scheduler not in COVERED_SCHEDULERS:
        raise InvalidInput(f"scheduler {scheduler!r} on the paper's world: synthesize takes "
                           f"{', '.join(COVERED_SCHEDULERS)}")
    if box is not None:
        width, height = parse_box(box)
        rs = parse_range(robots, "--robots", width * height)
        ms = parse_range(meeting, "--meeting", width * height)
        names = tuple(x.strip() for x in (classes or "").split(",") if x.strip())
        class_names = get_fact("class").values
        unknown = [x for x in names if x not in class_names]
        if unknown:
            raise InvalidInput(f"--classes {unknown[0]!r}: use the paper's classes "
                               f"({', '.join(class_names)})")
        configs = box_configurations(width, height, rs, ms, select, names)
        return PlaneInstance(configs, scheduler, detection, frames,
                             {"width": width, "height": height, "robots": [rs[0], rs[-1]],
                              "meeting": [ms[0], ms[-1]], "select": select,
                              "classes": list(names)})
    if not meeting.strip():
        raise InvalidInput("the paper's world needs meeting nodes: give --meeting")
    c = Configuration(geometry.parse_nodes(robots), geometry.parse_nodes(meeting),
                      initial=True)
    return PlaneInstance([c], scheduler, detection, frames)


# -- certificates ----------------------------------------------------------------------------

CLAIM = ("for each configuration and every algorithm (a deterministic function of the view up "
         "to isomorphism, under these frames and this detection), Theorem 1's FSYNC adversary "
         "has a run that keeps every configuration symmetric under phi, so it never gathers on "
         "one meeting node (an FSYNC run is an SSYNC and an ASYNC run too). The adversary's "
         "step is re-checked with the view code on every configuration it reaches within "
         "'rounds' rounds (within the initial MER grown by 'rounds' nodes); beyond them it "
         "carries on by the theorem's induction, as phi's linear part is one of the robots' "
         "frames.")
"""What a certificate of none claims; ``--verify`` refuses one that claims anything else."""


def write_certificate(path: str, inst: PlaneInstance, entries: list[dict[str, Any]]) -> None:
    data = {"format": FORMAT, "instance": inst.describe(), "claim": CLAIM,
            "configurations": entries}
    Path(path).write_text(json.dumps(data, indent=1) + "\n", encoding="utf-8")


def verify_certificate(path: str) -> dict[str, Any]:
    """Re-check a certificate of none on Z² without any search over algorithms (see the
    module docstring). Returns what it checked; CertificateError says where it fails."""
    from gather_verify.inputs import read_text

    try:
        data = json.loads(read_text(path, "certificate"))
    except ValueError as error:
        raise InvalidInput(f"{path}: not JSON ({error})") from None
    if not isinstance(data, dict) or data.get("format") != FORMAT:
        raise InvalidInput(f"{path}: not a certificate of the paper's world ({FORMAT})")
    try:
        return _verify(data)
    except InvalidInput as error:  # a certificate that could check nothing: not one at all
        raise InvalidInput(f"{path}: {error}") from None
    except (KeyError, TypeError, ValueError, IndexError) as error:
        raise CertificateError(f"malformed: {type(error).__name__}: {error}") from None


def _verify(data: dict[str, Any]) -> dict[str, Any]:
    inst = data["instance"]
    if data["claim"] != CLAIM:
        raise CertificateError("the claim is not the one this verifier checks")
    if inst["task"] != TASK:
        raise CertificateError(f"task {inst['task']!r}: the certificate covers {TASK} only")
    if inst["scheduler"] not in COVERED_SCHEDULERS:
        raise CertificateError(f"scheduler {inst['scheduler']!r} is not covered")
    detection, frames = inst["detection"], inst["frames"]
    if frames not in FRAME_SETS:
        raise CertificateError(f"unknown frames {frames!r}")
    try:
        check_detection(detection)
    except InvalidInput as error:
        raise CertificateError(str(error)) from None
    views = PlaneViews(detection, frames)
    entries = data["configurations"]
    if not entries:
        raise CertificateError("no configuration")
    states = 0
    for i, e in enumerate(entries):
        where = f"configuration {i}"
        try:
            c = Configuration([tuple(v) for v in e["robots"]],
                              [tuple(v) for v in e["meeting_nodes"]], initial=True)
        except InvalidInput as error:
            raise CertificateError(f"{where}: {error}") from None
        phi = Automorphism(int(e["phi"]["g"]), (int(e["phi"]["t"][0]), int(e["phi"]["t"][1])))
        if phi.g == geometry.IDENTITY or phi.g not in FRAME_SETS[frames]:
            raise CertificateError(f"{where}: phi's linear part {geometry.NAMES[phi.g]} is not "
                                   f"a non-trivial frame of the robots (frames {frames})")
        defect = symmetry_defect(phi, c)
        if defect is not None:
            raise CertificateError(f"{where}: phi is no automorphism of the configuration: "
                                   f"{defect}")
        fixed = sorted(v for v in c.occupied | c.meeting_nodes if phi.fixes(v))
        if fixed:
            raise CertificateError(f"{where}: phi fixes {[list(v) for v in fixed]}, a robot or "
                                   "a meeting node (Theorem 1 needs V' empty of both)")
        rounds = int(e["rounds"])
        if not 1 <= rounds <= 1000:  # 0: the adversary's step would be checked nowhere
            raise InvalidInput(f"{where}: rounds {rounds}: give 1 to 1000 (with 0 the "
                               "adversary's step is checked on no configuration)")
        _check_stated(where, e, c, phi)
        closure = adversary_closure(c, phi, views, rounds)
        if (closure.states, closure.digest) != (e["states"], e["digest"]):
            raise CertificateError(f"{where}: the adversary's configurations within {rounds} "
                                   f"rounds are {closure.states} (digest "
                                   f"{closure.digest[:12]}), the certificate says "
                                   f"{e['states']} ({str(e['digest'])[:12]})")
        states += closure.states
    box = inst.get("box")
    if box is not None:
        want = box_configurations(int(box["width"]), int(box["height"]),
                                  range(box["robots"][0], box["robots"][1] + 1),
                                  range(box["meeting"][0], box["meeting"][1] + 1),
                                  box["select"], tuple(box.get("classes", ())))
        got = sorted(_text(e["robots"], e["meeting_nodes"]) for e in entries)
        if box["select"] != "u" or got != sorted(_text(c.robots, c.meeting_nodes)
                                                 for c in want):
            raise CertificateError("the configurations are not those in U of the box it names")
    return {"instance": inst, "configurations": len(entries), "states": states,
            "views": len(views.texts)}


def _check_stated(where: str, entry: dict[str, Any], c: Configuration,
                  phi: Automorphism) -> None:
    """What an entry states besides what the check re-derives (its class, ``in_U``, and
    phi's description and order) must be true of the configuration and of ``phi``."""
    stated = {"class": entry["class"], "in_U": entry["in_U"],
              "phi describe": entry["phi"]["describe"], "phi k": entry["phi"]["k"]}
    true = {"class": get_fact("class").of(c), "in_U": get_fact("in_U").of(c),
            "phi describe": phi.describe(), "phi k": phi.order}
    wrong = [name for name in stated if stated[name] != true[name]]
    if wrong:
        raise CertificateError(f"{where}: it states {wrong[0]} {stated[wrong[0]]!r}, which is "
                               f"{true[wrong[0]]!r}")


def _text(robots: Any, meeting: Any) -> str:
    """A configuration as text, for comparing lists of them."""
    return json.dumps([sorted(list(v) for v in robots), sorted(list(v) for v in meeting)])


# -- exists: a table, proposed by a solver and judged by the ordinary checker --------------

class TableAlgorithm:
    """A candidate: per key, an option (its first answer label). A view the table does not
    hold has no rule, unless ``extend`` is given: the view is then registered and takes the
    option ``extend`` gives it, written into ``choice`` (one exploration then follows the
    seed as far as it goes). A view whose robots and meeting nodes span more than ``span``
    edges is out of the region: no rule (the search excludes the table; a heuristic, never a
    none)."""

    name = "synthesized-candidate"

    def __init__(self, views: PlaneViews, choice: dict[int, int], span: int,
                 extend: Callable[[int], int] | None = None):
        self.views, self.choice, self.span, self.extend = views, choice, span, extend

    def decide(self, view: View) -> Node:
        views = self.views
        nodes = view.robots | view.meeting_nodes
        xs = [x for x, _ in nodes]
        ys = [y for _, y in nodes]
        if max(max(xs) - min(xs), max(ys) - min(ys)) > self.span:
            raise Unhandled("region: the robots went too far from the meeting nodes")
        key, t = viewkey.canonical(views.group, viewkey.observe_plane(view, views.detection))
        k = views.index.get(viewkey.key_text(key))
        if (k is None or k not in self.choice) and self.extend is not None:
            k = views.occurrence(view._snapshot, view._node)[0]
            self.choice[k] = self.extend(k)
        if k is None or k not in self.choice:
            raise Unhandled("a view the search has not met")
        label = views.options[k][self.choice[k]]
        out = viewkey.inverse(views.group, t, label)
        return (int(out[0]), int(out[1]))


@dataclass
class SearchResult:
    """The search's answer (exists or unknown) and the table of exists."""

    answer: str  # exists | unknown
    candidates: int
    views: int
    seconds: float
    limit: str | None = None
    table: dict[int, int] = field(default_factory=dict)


def search_algorithm(configurations: list[Configuration], inst: PlaneInstance,
                     views: PlaneViews, *, max_seconds: float, max_candidates: int,
                     max_states: int, margin: int = 2,
                     seeds: list[Any] | None = None) -> SearchResult:
    """Counterexample-guided: the solver proposes a table over the views met so far, the
    ordinary checker (every reduction off, properties final and termination) judges it from
    each configuration in turn (the last one that failed first); a violation's trace gives
    the clause "not these options on the views it relies on". A view that the exploration
    meets for the first time joins the table with the seed's answer, and the exploration
    goes on. One table must gather from every configuration.

    ``seeds`` (algorithms; None stands for the nearest-meeting-node rule) give the answer
    the solver tries first on each view (:func:`preferred`), one seed at a time: the first
    for :data:`SEED_ROUND` candidates, the next for as many, and round again with twice as
    many. A seed is a phase, never a constraint: every clause holds whichever seed is on,
    and the answer is judged by the checker alone. Default: :func:`default_seeds`."""
    from gather_verify.synthesis.search import TIME_LIMIT, budget
    from gather_verify.watchdog import Overtime

    started = time.perf_counter()
    cegis = _Cegis(views, default_seeds() if seeds is None else seeds)
    spans = []
    for c in configurations:
        x0, y0, x1, y1 = geometry.bounding_box([*c.robots, *c.meeting_nodes])
        # a robot d nodes out of the initial MER is d from every meeting node, so every view
        # with a rule lies within span of the MER: the checker's region (span + 1) holds it
        spans.append(max(x1 - x0, y1 - y0) + margin)
    order = list(range(len(configurations)))

    def result(answer: str, limit: str | None = None, **more: Any) -> SearchResult:
        cegis.solver.delete()
        return SearchResult(answer, cegis.candidates, len(views.texts),
                            time.perf_counter() - started, limit, **more)

    try:
        with budget(max_seconds):
            for c in configurations:
                for v in sorted(c.occupied):
                    views.occurrence(c, v)
            while True:
                choice = cegis.propose(started + max_seconds, max_candidates)
                if isinstance(choice, str):
                    return result("unknown", choice)
                failed, report, cap, left = _judge(configurations, order, inst, cegis, choice,
                                                   spans, max_states, started + max_seconds)
                if failed is None:
                    return result("exists", table=choice)
                order.remove(failed)
                order.insert(0, failed)
                stop = cegis.learn(report, configurations[failed], choice, cap < left)
                if stop is not None:
                    return result("unknown", stop)
    except Overtime:  # the views may be half filled: the caller drops them with the answer
        return result("unknown", f"{TIME_LIMIT} (cut by the watchdog)")


def _judge(configurations: list[Configuration], order: list[int], inst: PlaneInstance,
           cegis: _Cegis, choice: dict[int, int], spans: list[int], max_states: int,
           end: float) -> tuple[int | None, dict[str, Any], float, float]:
    """The candidate table ``choice`` checked from each configuration in ``order`` (every
    reduction off, properties final and termination), until one is not VERIFIED: that one
    (None if every one is), its report, the seconds it was given and those that were left."""
    from gather_verify.plane_check import run_check

    report: dict[str, Any] = {}
    cap = left = 0.0
    for idx in order:
        c = configurations[idx]
        left = end - time.perf_counter()
        cap = min(left, max(CANDIDATE_SECONDS, left / 4))
        # a view met for the first time takes the seed's answer and the exploration goes
        # on: one exploration settles a configuration the seed gathers from
        table = TableAlgorithm(cegis.views, choice, spans[idx], cegis.fresh)
        report = run_check(c, algorithm=table,
                           scheduler=inst.scheduler, detection=inst.detection,
                           frames=inst.frames, properties=["final", "termination"],
                           reduction=False, max_states=max_states,
                           max_seconds=max(cap, 0.001), margin=spans[idx] + 1, force=True)
        if report["verdict"] != "VERIFIED":
            return idx, report, cap, left
    return None, report, cap, left


class _Cegis:
    """The solver of :func:`search_algorithm`: one variable per option of each view met,
    exactly one option a view; the seeds' answers as its phases; the candidates proposed
    and the clauses learnt from their counterexamples."""

    def __init__(self, views: PlaneViews, seeds: list[Any]):
        from gather_verify.synthesis.search import solver_class

        self.views, self.seeds = views, seeds
        self.solver = solver_class()(name="cadical153")
        self.base: list[int] = []  # per view: its first variable, less one
        self.total = 0
        self.best: list[list[int]] = [[] for _ in seeds]  # per seed, per view: tried first
        # the seed in use, the candidate at which the next takes over, the turns begun
        self.on = [0, SEED_ROUND, 1]
        self.candidates = 0
        self.heuristic = False

    def register(self) -> None:
        """The views met since, as variables; the next seed's phases when its turn came."""
        views, solver, base = self.views, self.solver, self.base
        while len(base) < len(views.texts):
            j = len(base)
            xs = [self.total + o + 1 for o in range(len(views.options[j]))]
            base.append(self.total)
            self.total += len(xs)
            solver.add_clause(xs)
            for a, b in combinations(xs, 2):
                solver.add_clause([-a, -b])
        on = self.on
        if self.candidates >= on[1]:
            on[0] = (on[0] + 1) % len(self.seeds)
            on[1] = self.candidates + SEED_ROUND * 2 ** (on[2] // len(self.seeds))
            on[2] += 1
        mine = self.best[on[0]]
        while len(mine) < len(base):
            mine.append(preferred(views, len(mine), self.seeds[on[0]]))
        solver.set_phases([base[k] + o + 1 if o == mine[k] else -(base[k] + o + 1)
                           for k in range(len(base)) for o in range(len(views.options[k]))])

    def fresh(self, k: int) -> int:
        """The option of a view met during an exploration that follows the seed."""
        mine = self.best[self.on[0]]
        while len(mine) <= k:
            mine.append(preferred(self.views, len(mine), self.seeds[self.on[0]]))
        return mine[k]

    def propose(self, end: float, max_candidates: int) -> dict[int, int] | str:
        """The next candidate table (view to option), or the limit that ends the search."""
        from gather_verify.synthesis.search import TIME_LIMIT, solve_within

        if end - time.perf_counter() <= 0:
            return TIME_LIMIT
        if self.candidates >= max_candidates:
            return "max-candidates"
        self.register()
        sat = solve_within(self.solver, end)
        if sat is None:
            return f"{TIME_LIMIT} (during the SAT solver's call)"
        if not sat:
            return ("region (every table left is excluded; the clauses that exclude tables "
                    "leaving the region or taking too long are heuristics, so this is no none)"
                    if self.heuristic else "search exhausted without a certificate")
        model = self.solver.get_model() or []
        self.candidates += 1
        return {k: o for k, first in enumerate(self.base)
                for o in range(len(self.views.options[k])) if model[first + o] > 0}

    def learn(self, report: dict[str, Any], c: Configuration, choice: dict[int, int],
              cut: bool) -> str | None:
        """The clause a failed candidate's report gives (None: the search goes on), or why
        the search ends there; ``cut``: its check was given less than the time left."""
        views = self.views
        trace = report.get("trace")
        if report["verdict"] == "INCOMPLETE" and not trace and cut:
            # one candidate took its share of the time: exclude this very table (a
            # heuristic, as for the region) and go on
            self.heuristic = True
            self.register()
            self.solver.add_clause([-(self.base[k] + o + 1) for k, o in sorted(choice.items())])
            return None
        if report["verdict"] == "INCOMPLETE" and report.get("reason") == "time":
            return "max-seconds (during a candidate's check)"
        if report["verdict"] != "VIOLATED" or not trace:
            return f"the checker says {report['verdict']} ({report.get('reason')}) of a candidate"
        before = len(views.texts)
        configs, exact = literals(views, trace, c.meeting_nodes, choice)
        used: set[int] = set()
        for d in configs:
            for v in d.occupied:
                used.add(views.occurrence(d, v)[0])
        reason = str(report.get("reason", ""))
        if report.get("property") == "defined" and "region" not in reason:
            if len(views.texts) == before:
                return f"the checker found no rule for a view it cannot name ({reason})"
            return None  # a new view: the table grows
        self.heuristic = self.heuristic or report.get("property") == "defined"
        self.register()
        clause = [-(self.base[k] + choice[k] + 1)
                  for k in sorted(exact if exact is not None else used) if k in choice]
        if not clause:
            return "a violation that no view of the table causes"
        self.solver.add_clause(clause)
        return None


def default_seeds() -> list[Any]:
    """The seeds of :func:`search_algorithm`: the paper's ``Gathering()`` (default reading),
    which gathers from most configurations outside U, then the nearest-meeting-node rule."""
    from gather_verify.algorithms import get_algorithm

    return [get_algorithm("paper"), None]


def preferred(views: PlaneViews, k: int, seed: Any = None) -> int:
    """The option the solver tries first for view ``k`` (a phase, not a constraint): the
    option whose move set is the ``seed`` algorithm's there, when a seed is given and has
    one; else stay on a meeting node, else the option whose every move ends nearest a
    meeting node."""
    c, node = views.first[k]
    _, opts = views.occurrence(c, node)
    if seed is not None:
        from gather_verify.algorithms.moves import move_set

        try:
            wanted = move_set(seed, c, node, views.detection, views.frame_ids)
        except Exception:  # no rule there (or a crash): the seed has no say on this view
            wanted = None
        if wanted in opts:
            return opts.index(wanted)
    if node in c.meeting_nodes:
        return next((o for o, d in enumerate(opts) if d == {node}), 0)

    def far(dests: frozenset[Node]) -> int:
        return max(min(geometry.manhattan(d, m) for m in c.meeting_nodes) for d in dests)

    return min(range(len(opts)), key=lambda o: (far(opts[o]), o))


def literals(views: PlaneViews, trace: dict[str, Any], meeting: frozenset[Node],
             choice: dict[int, int] | None = None
             ) -> tuple[list[Configuration], set[int] | None]:
    """The configurations of a checker's trace, and the views whose chosen option the
    trace relies on: each activated robot's view (the option that holds what it did); at a
    deadlock, every robot's; on a fair cycle, for each robot that does not act on the
    cycle, its view at one state of the cycle where it is idle and its option is to stay
    (what makes the cycle fair for it, SEMANTICS.md §5). Any table with these options has
    the same execution, so the clause "not all of these" excludes no table that gathers.
    None when the trace is of another kind (the clause then names every view of its
    configurations)."""
    configs = [Configuration([tuple(v) for v in trace["initial"]["robots"]], meeting)]
    configs += [Configuration([tuple(r["node"]) for r in step["state"]], meeting)
                for step in trace["steps"]]
    cs = trace.get("cycle_start")
    kind = trace.get("property")
    if not (kind in ("final", "defined") and cs is None
            or kind == "termination" and cs is not None and choice is not None):
        return configs, None
    used: set[int] = set()
    acted: set[int] = set()
    for j, step in enumerate(trace["steps"]):
        if step["event"]["kind"] in ("look", "round"):
            for i in step["event"]["robots"]:
                used.add(views.occurrence(configs[j], _robot_node(trace, j, i))[0])
        if cs is not None and j >= cs:
            acted.update(step["event"]["robots"])
    if kind == "final":
        last = configs[-1]
        used.update(views.occurrence(last, v)[0] for v in last.occupied)
    if cs is not None:
        assert choice is not None
        n = len(trace["initial"]["robots"])
        for i in sorted(set(range(n)) - acted):
            for j in range(cs, len(configs)):
                state = trace["steps"][j - 1]["state"] if j else None
                if state is not None and state[i]["pending"] is not None:
                    continue
                k = views.occurrence(configs[j], _robot_node(trace, j, i))[0]
                if k in choice and views.options[k][choice[k]] == geometry.ORIGIN:
                    used.add(k)
                    break
            else:  # no state says why the cycle is fair for robot i: fall back
                return configs, None
    return configs, used


def _robot_node(trace: dict[str, Any], j: int, i: int) -> Node:
    """Robot ``i``'s node before step ``j`` of a trace."""
    if j == 0:
        return tuple(trace["initial"]["robots"][i])
    return tuple(trace["steps"][j - 1]["state"][i]["node"])


# -- the witness ----------------------------------------------------------------------------

WITNESS_NAME = "Synthesized"
WITNESS = '''"""An algorithm synthesised by gather-verify synthesize on the paper's world (Z²).

Instance: {instance}

A lookup table from views up to isomorphism to answers: {count} views. Load it with
--algorithm {filename}:{name}. It answers only the views the synthesis met from this
initial configuration; any other view has no rule (the checker's ``defined``).
"""

{imports}
from gather_verify.algorithms.base import Unhandled

# -- how a view is keyed (a copy of gather_verify/synthesis/viewkey.py) --------------------
{viewkey}
# -- the instance -------------------------------------------------------------------------
GROUP = build({group!r})
DETECTION = {detection!r}

# view key -> the answer, in the key's frame
TABLE = {{
{table}}}


class {name}:
    name = "synthesized"

    def decide(self, view):
        key, t = canonical(GROUP, observe_plane(view, DETECTION))
        answer = TABLE.get(key_text(key))
        if answer is None:
            raise Unhandled("a view the synthesis never met")
        x, y = inverse(GROUP, t, answer)
        return (x, y)
'''


def write_witness(path: str, inst: PlaneInstance, c: Configuration, views: PlaneViews,
                  table: dict[int, int]) -> str:
    """Write the witness for configuration ``c``; returns its ``--algorithm`` spec."""
    from gather_verify.synthesis.witness import viewkey_source

    rows = "".join(f"    {views.texts[k]!r}: {tuple(views.options[k][o])!r},\n"
                   for k, o in sorted(table.items(), key=lambda kv: views.texts[kv[0]]))
    instance = {**inst.describe(), "robots": [list(v) for v in c.robots],
                "meeting_nodes": [list(v) for v in sorted(c.meeting_nodes)]}
    imports, viewkey = viewkey_source()
    Path(path).write_text(WITNESS.format(
        instance=json.dumps(instance, sort_keys=True), count=len(table),
        filename=Path(path).name, name=WITNESS_NAME, imports=imports, viewkey=viewkey,
        group=group_description(inst.frames), detection=inst.detection, table=rows),
        encoding="utf-8")
    return f"{path}:{WITNESS_NAME}"


def check_witness(spec: str, inst: PlaneInstance, c: Configuration,
                  max_seconds: float) -> dict[str, Any]:
    """The ordinary checker on the witness file, every reduction off (final, termination),
    within ``max_seconds`` (:func:`~gather_verify.synthesis.search.budget`: past it, the
    verdict is INCOMPLETE with reason ``time``)."""
    from gather_verify.plane_check import run_check
    from gather_verify.synthesis.search import budget
    from gather_verify.watchdog import Overtime

    if max_seconds <= 0:
        return {"verdict": "INCOMPLETE", "reason": "time", "states": 0}
    try:
        with budget(max_seconds):
            return run_check(c, algorithm=spec, scheduler=inst.scheduler,
                             detection=inst.detection, frames=inst.frames,
                             properties=["final", "termination"], reduction=False,
                             max_seconds=max_seconds, force=True)
    except Overtime:
        return {"verdict": "INCOMPLETE", "reason": "time", "states": 0}


def out_of_time(checked: dict[str, Any]) -> bool:
    """Whether the checker's verdict on a witness is INCOMPLETE for lack of time (the
    answer is then unknown, not a fault of the witness)."""
    return checked["verdict"] == "INCOMPLETE" and str(checked.get("reason")).startswith("time")
