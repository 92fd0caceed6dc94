"""Counterexamples and the certificate of ``none`` (SEMANTICS.md §12), and their re-check.

A *counterexample* is one execution from one initial configuration that violates the task:
the events of a path (a safety part: two robots on one node or crossing one edge, or a final
state that is not a success), or of a path and a cycle a fair run can repeat for ever (a
liveness part). Replaying it from scratch gives the *literals* it relies on: per view met on
the way, the option the acting robots took (and, where the run needs it, that a robot may
stay, or that a state is not final). Every algorithm that takes those options has that
execution, so fails: the counterexample refutes all of them at once.

The certificate of ``none`` is a list of counterexamples and a decision tree: each inner node
names a view and has one child per option of it, each leaf names a counterexample whose
literals all hold on the path to it. Following the tree with any algorithm's answers ends
at a leaf, so every algorithm fails. :func:`verify_certificate` checks that with no search:
it replays each counterexample through the schedulers and the views (the same code the
checker runs), recomputes its literals and walks the tree. Where the tree would be too
large, the certificate holds a resolution proof instead (``proof``, :mod:`.refute`), over
the same clauses; the re-check runs it step by step (:mod:`.rup`).
"""

from __future__ import annotations

import json
import sys
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from typing import Any

from gather_verify.errors import GatherVerifyError, InvalidInput
from gather_verify.synthesis.lift import LADDER, lift, liftable
from gather_verify.synthesis.views import Instance, Views, make_instance
from schedulers import Event, get_scheduler

FORMAT = "gather-verify synthesis certificate 1"
PROOF_FORMAT = ("drup: per view of 'views', in order, one variable per option (numbered on "
                "from 1); the clauses are, per view, at least one option and at most one, then "
                "per counterexample 'not all of its literals'; each step adds a clause that "
                "follows by unit propagation, or (led by 0) deletes one; the empty clause ends "
                "it")
SAFETY_FINAL = ("gathered-when-final", "final", "explored-when-final")
LIVENESS = ("termination", "perpetual-exploration")
State = tuple[Any, int, object]
"""A replayed state: the robots (node, pending, colour), the visited nodes, the scheduler's."""


class CertificateError(GatherVerifyError):
    """A counterexample or a certificate of ``none`` does not hold.

    Cause: an event the scheduler cannot take with the move sets its literals give, a view
    that would need two answers, a run that violates nothing, or a decision tree that misses
    an option or uses a counterexample where its literals do not hold (a file edited or
    damaged, or one written for another instance). Fix: the message says where; run
    ``synthesize`` again to get a certificate that holds (``--verify`` exits 1 with that
    line)."""


@dataclass
class Replayed:
    """What a replay found: the literals (view id -> option) the run relies on, and the
    states it went through."""

    literals: dict[int, int]
    states: list[State]


def event_to_json(world: Any, event: Event) -> dict[str, Any]:
    name = world.node_to_json
    return {"kind": event.kind, "robots": list(event.robots),
            "moves": [[i, name(a), name(b)] for i, a, b in event.moves],
            "lights": [list(x) for x in event.lights]}


def event_from_json(world: Any, raw: Any) -> Event:
    try:
        node = world.node_from_json
        return Event(str(raw["kind"]), tuple(int(i) for i in raw["robots"]),
                     tuple((int(i), node(a), node(b)) for i, a, b in raw["moves"]),
                     tuple((int(i), int(a), int(b)) for i, a, b in raw.get("lights", [])))
    except (KeyError, TypeError, ValueError) as error:
        raise CertificateError(f"a malformed event {raw!r}: {error}") from None


def apply_event(robots: tuple[tuple[int, int | None, int], ...], event: Event
           ) -> tuple[tuple[int, int | None, int], ...]:
    out: list[Any] = list(robots)
    for i, _, new in event.lights:
        out[i] = (out[i][0], out[i][1], new)
    for i, src, dst in event.moves:
        out[i] = (src, dst, out[i][2]) if event.kind == "look" else (dst, None, out[i][2])
    return tuple(out)


def _action(robots: tuple[tuple[int, int | None, int], ...], event: Event, i: int
            ) -> tuple[int, int]:
    """What robot ``i`` chose in ``event`` (it acted in it): its destination and colour."""
    after = apply_event(robots, event)[i]
    if event.kind == "look":
        return (after[1] if after[1] is not None else after[0]), after[2]
    return after[0], after[2]


def replay(views: Views, cex: dict[str, Any], scheduler: str | None = None) -> Replayed:
    """Replay ``cex`` from scratch under its scheduler (the instance's, unless it names the
    cheaper one it was found under, :mod:`~gather_verify.synthesis.lift`; ``scheduler``
    overrides both): its literals, or :class:`CertificateError` naming what fails (an event
    the scheduler cannot take, two options for one view, no violation)."""
    inst = views.inst
    sched = get_scheduler(_scheduler_name(inst, cex, scheduler))
    got = _Fields.of(inst, cex)
    robots0, colours0 = got.config
    n = len(robots0)
    extra = _start(sched, n, cex)
    robots = tuple((v, None, c) for v, c in zip(robots0, colours0, strict=True))
    visited = _bits(robots0) if inst.task.visits else 0
    states: list[State] = [(robots, visited, extra)]
    events = [event_from_json(inst.world, e) for e in got.raw_events]
    literals: dict[int, int] = {}
    # pass 1: the states and the literals the events, stays, busy robots and the end rely on
    _walk_events(views, states, events, literals, n)
    _pin_stays(views, states, literals, got, n)
    # pass 2: each event is one the scheduler takes, with the move sets of those literals
    _schedule(sched, views, states, events, literals)
    _violation(views, inst, got.prop, cex, states, events, got.loop, got.stays, got.busy,
               got.final)
    return Replayed(literals, states)


def _scheduler_name(inst: Instance, cex: dict[str, Any], scheduler: str | None) -> str:
    """The scheduler a counterexample is replayed under: ``scheduler`` if given, else the
    one it names if the instance's lifts it, else :class:`CertificateError`."""
    if scheduler is not None:
        return scheduler
    name = cex.get("scheduler", inst.scheduler) if isinstance(cex, dict) else None
    if not isinstance(name, str) or not liftable(name, inst.scheduler, inst.lights.colours):
        raise CertificateError(f"a counterexample under {name!r} is none under "
                               f"{inst.scheduler}")
    return name


@dataclass(frozen=True)
class _Fields:
    """A counterexample's fields, read: its configuration, events (as written), loop,
    stays, busy robots, whether it ends final, and the property it violates."""

    config: Any
    raw_events: list[Any]
    loop: Any
    stays: list[tuple[int, int]]
    busy: list[tuple[int, int, Any, int]]
    final: bool
    prop: str

    @staticmethod
    def of(inst: Instance, cex: dict[str, Any]) -> _Fields:
        """Read ``cex``'s fields, or :class:`CertificateError` naming a malformed one."""
        try:
            return _Fields(
                config=inst.configurations[int(cex["configuration"])],
                raw_events=list(cex["events"]), loop=cex.get("loop"),
                stays=[(int(s), int(i)) for s, i in cex.get("stays", [])],
                busy=[(int(s), int(i), inst.world.node_from_json(d), int(c))
                      for s, i, d, c in cex.get("busy", [])],
                final=bool(cex.get("final", False)), prop=str(cex["property"]))
        except (KeyError, TypeError, ValueError, IndexError) as error:
            raise CertificateError(f"a malformed counterexample: {error!r}") from None
        except InvalidInput as error:
            raise CertificateError(f"a malformed counterexample: {error}") from None


def _start(sched: Any, n: int, cex: dict[str, Any]) -> Any:
    """The scheduler's start the counterexample names (None for a stateless scheduler), or
    :class:`CertificateError` when the scheduler has no such start."""
    starts = getattr(sched, "starts", lambda _n: [None])(n)
    start = cex.get("start")
    try:
        extra = None if start is None else (tuple(start[0]), int(start[1]))
    except (TypeError, ValueError, IndexError, KeyError):
        raise CertificateError(f"a malformed start {str(start)[:40]}") from None
    if extra not in starts:
        raise CertificateError(f"the scheduler has no start {start!r}")
    return extra


def _need(views: Views, literals: dict[int, int], state: State, i: int,
          action: tuple[int, int], why: str) -> None:
    """Fix the literal of robot ``i``'s view in ``state`` to the option holding ``action``,
    or :class:`CertificateError` when no option or two answers for one view."""
    k, acts = views.robots(state[0])[i]
    hits = [o for o, a in enumerate(acts) if action in a]
    if len(hits) != 1:
        raise CertificateError(f"{why}: robot {i} cannot do {action} there")
    if literals.setdefault(k, hits[0]) != hits[0]:
        raise CertificateError(f"{why}: view {k} would need two answers")


def _walk_events(views: Views, states: list[State], events: list[Event],
                 literals: dict[int, int], n: int) -> None:
    """Apply the events in turn, appending each state (its scheduler's part filled in by
    :func:`_schedule`) and fixing the literals of the robots that act."""
    visits = views.inst.task.visits
    for step, event in enumerate(events):
        rs = states[-1][0]
        if any(not 0 <= i < n for i in event.robots):
            raise CertificateError(f"step {step}: no such robot")
        if event.kind in ("round", "look"):
            for i in event.robots:
                _need(views, literals, states[-1], i, _action(rs, event, i), f"step {step}")
        nxt = apply_event(rs, event)
        seen = states[-1][1]
        if visits:
            seen |= _bits(v for v, _, _ in nxt)
        states.append((nxt, seen, None))


def _pin_stays(views: Views, states: list[State], literals: dict[int, int], got: _Fields,
               n: int) -> None:
    """Fix the literals the stays, the busy robots and a final last state rely on."""
    for s, i in got.stays:
        if not 0 <= s < len(states) or not 0 <= i < n or states[s][0][i][1] is not None:
            raise CertificateError(f"stay ({s}, {i}): no idle robot {i} in state {s}")
        v, _, c = states[s][0][i]
        _need(views, literals, states[s], i, (v, c), f"stay ({s}, {i})")
    for s, i, d, c in got.busy:
        if not 0 <= s < len(states) or not 0 <= i < n or states[s][0][i][1] is not None:
            raise CertificateError(f"busy ({s}, {i}): no idle robot {i} in state {s}")
        if (d, c) == (states[s][0][i][0], states[s][0][i][2]):
            raise CertificateError(f"busy ({s}, {i}): staying does not make a state busy")
        _need(views, literals, states[s], i, (d, c), f"busy ({s}, {i})")
    if got.final:
        last = states[-1]
        for i, (v, p, c) in enumerate(last[0]):
            if p is not None:
                raise CertificateError("the last state has a pending move: it is not final")
            k, acts = views.robots(last[0])[i]
            stay = views.stay_option(k, acts, v, c)
            if stay < 0 or literals.setdefault(k, stay) != stay:
                raise CertificateError(f"the last state: robot {i} cannot be made to stay")


def _schedule(sched: Any, views: Views, states: list[State], events: list[Event],
              literals: dict[int, int]) -> None:
    """Check that each event is one the scheduler takes with the move sets of ``literals``,
    filling in each state's scheduler part."""
    for step, event in enumerate(events):
        rs, _, now = states[step]
        per = views.robots(rs)

        def actions(i: int, per: Any = per) -> frozenset[tuple[int, int]]:
            k, acts = per[i]
            return acts[literals[k]] if k in literals else frozenset()

        for got, succ, after in sched.luminous(rs, now, actions):
            if got == event and succ == states[step + 1][0]:
                states[step + 1] = (succ, states[step + 1][1], after)
                break
        else:
            raise CertificateError(f"step {step}: the scheduler has no such event")


def _violation(views: Views, inst: Instance, prop: str, cex: dict[str, Any],
               states: list[State], events: list[Event], loop: Any,
               stays: list[tuple[int, int]], busy: list[tuple[int, int, int, int]],
               final: bool) -> None:
    """The replayed run violates ``prop`` of the task (else :class:`CertificateError`)."""
    task = inst.task
    if prop not in task.parts:
        raise CertificateError(f"task {task.name} has no part {prop!r}")
    last = states[-1][0]
    nodes = [v for v, _, _ in last]
    if prop == "exclusivity":
        if len(set(nodes)) < len(nodes):
            return
        if events and events[-1].kind == "round":
            crossing = {(a, b) for _, a, b in events[-1].moves}
            if any((b, a) in crossing for a, b in crossing):
                return
        raise CertificateError("exclusivity: no two robots share a node or cross an edge")
    if prop in SAFETY_FINAL:
        if not final:
            raise CertificateError(f"{prop}: the counterexample does not end in a final state")
        if prop == "explored-when-final":
            if states[-1][1] != (1 << inst.world.size) - 1:
                return
        elif len(set(nodes)) > 1 or (prop == "final" and not set(nodes) <= inst.meeting):
            return
        raise CertificateError(f"{prop}: the final state is a success")
    if prop not in LIVENESS:  # pragma: no cover - every task part is one of the above
        raise CertificateError(f"no re-check for {prop!r}")
    if not isinstance(loop, int) or not 0 <= loop < len(states):
        raise CertificateError(f"{prop}: no cycle")
    if states[loop] != states[-1]:
        raise CertificateError(f"{prop}: the cycle does not come back to state {loop}")
    n = len(last)
    covered = set()
    for event in events[loop:]:
        covered |= set(event.robots)
    covered |= {i for s, i in stays if s >= loop}
    if covered != set(range(n)):
        raise CertificateError(f"{prop}: the cycle is not fair (robots "
                               f"{sorted(set(range(n)) - covered)} never act nor stay)")
    if prop == "termination":
        if len(states) - 1 == loop:
            raise CertificateError("termination: the cycle has no event")
        shown = {s for s, _, _, _ in busy}
        for s in range(loop, len(states) - 1):
            e = events[s]
            pending = any(p is not None for _, p, _ in states[s][0])
            if not (e.moves or e.lights or pending or s in shown):
                raise CertificateError(f"termination: state {s} of the cycle may be final")
        return
    node = cex.get("node")
    try:
        v = inst.world.node_from_json(node)
    except InvalidInput:
        raise CertificateError(f"perpetual-exploration: {node!r} is not a node") from None
    if any(v in {u for u, _, _ in st[0]} for st in states[loop:]):
        raise CertificateError(f"perpetual-exploration: node {node} is visited on the cycle")


def _bits(nodes: Iterable[int]) -> int:
    bits = 0
    for v in nodes:
        bits |= 1 << v
    return bits


# -- the decision tree ------------------------------------------------------------------

class TreeTooLarge(GatherVerifyError):
    """The certificate's decision tree outgrew its limit of nodes.

    Cause: the counterexamples refute every algorithm, but only through a tree larger than
    ``--max-tree``. Fix: none needed: ``synthesize`` certifies the ``none`` with a resolution
    proof instead (:mod:`.refute`), and answers ``unknown`` naming ``max-tree`` only when
    that proof does not come within the time left (raise ``--max-seconds``)."""


def build_tree(clauses: list[dict[int, int]], options: list[int], limit: int) -> Any:
    """A decision tree over views that ends, on every path, at a clause (a counterexample's
    literals) that holds there: an int (the clause) or ``[view, [child per option]]``.
    ``clauses`` must be unsatisfiable together with "one option per view"."""
    count = [0]
    sys.setrecursionlimit(max(sys.getrecursionlimit(), 4 * len(options) + 1000))

    def grow(assign: dict[int, int], active: list[int]) -> Any:
        count[0] += 1
        if count[0] > limit:
            raise TreeTooLarge
        score: dict[int, float] = {}
        for j in active:
            open_ = [k for k in clauses[j] if k not in assign]
            if not open_:
                return j
            weight = 2.0 ** -len(open_)
            for k in open_:
                score[k] = score.get(k, 0.0) + weight
        if not score:  # pragma: no cover - the clauses were not unsatisfiable
            raise AssertionError("the counterexamples leave an algorithm unrefuted")
        k = max(score, key=lambda key: (score[key], -key))
        children = []
        for o in range(options[k]):
            assign[k] = o
            children.append(grow(assign, [j for j in active if clauses[j].get(k, o) == o]))
            del assign[k]
        return [k, children]

    return grow({}, list(range(len(clauses))))


def prune(tree: Any, clauses: list[dict[int, int]]) -> tuple[Any, list[int]]:
    """The tree of :func:`build_tree` without the questions that no clause at a leaf below
    reads (any child answers for the others there), its leaves renumbered over the clauses
    they use: the tree, and the kept clauses' indices in ``clauses``, in order. A certificate
    then holds only the counterexamples its tree needs."""

    def walk(node: Any) -> tuple[Any, set[int]]:
        if isinstance(node, int):
            return node, set(clauses[node])
        got = [walk(child) for child in node[1]]
        if not any(node[0] in read for _, read in got):
            return got[0]
        return [node[0], [child for child, _ in got]], set().union(*(read for _, read in got))

    def leaves(node: Any) -> Iterator[int]:
        if isinstance(node, int):
            yield node
        else:
            for child in node[1]:
                yield from leaves(child)

    def renumber(node: Any, number: dict[int, int]) -> Any:
        if isinstance(node, int):
            return number[node]
        return [node[0], [renumber(child, number) for child in node[1]]]

    pruned = walk(tree)[0]
    kept = sorted(set(leaves(pruned)))
    return renumber(pruned, {j: i for i, j in enumerate(kept)}), kept


def tree_size(tree: Any) -> tuple[int, int]:
    """(inner nodes, leaves)."""
    if isinstance(tree, int):
        return 0, 1
    inner, leaves = 1, 0
    for child in tree[1]:
        a, b = tree_size(child)
        inner, leaves = inner + a, leaves + b
    return inner, leaves


def check_tree(tree: Any, clauses: list[dict[int, int]], options: dict[int, int]) -> int:
    """Walk the tree: every inner node branches on a view with one child per option, no view
    twice on a path, every leaf's clause holds on its path. Returns the number of leaves."""
    leaves = 0
    stack: list[tuple[Any, dict[int, int]]] = [(tree, {})]
    while stack:
        node, assign = stack.pop()
        if isinstance(node, int) and not isinstance(node, bool):
            if not 0 <= node < len(clauses):
                raise CertificateError(f"a leaf names counterexample {node}, which is not there")
            if any(assign.get(k) != o for k, o in clauses[node].items()):
                raise CertificateError(f"counterexample {node} does not hold where the tree "
                                       "uses it")
            leaves += 1
            continue
        if not (isinstance(node, list) and len(node) == 2 and isinstance(node[0], int)
                and isinstance(node[1], list)):
            raise CertificateError(f"a malformed tree node {str(node)[:60]}")
        k, children = node
        if k in assign:
            raise CertificateError(f"the tree branches on view {k} twice on one path")
        if k not in options:
            raise CertificateError(f"the tree branches on view {k}, which no counterexample "
                                   "meets")
        if len(children) != options[k]:
            raise CertificateError(f"view {k} has {options[k]} options, the tree "
                                   f"{len(children)} branches")
        for o, child in enumerate(children):
            stack.append((child, {**assign, k: o}))
    return leaves


# -- the certificate file ------------------------------------------------------------------

def write_certificate(path: str, inst: Instance, views: Views, cexs: list[dict[str, Any]],
                      literals: list[dict[int, int]], tree: Any, stats: dict[str, Any]
                      ) -> None:
    """The certificate as JSON: the instance, the views the counterexamples meet (by key
    text, with their number of options), the counterexamples and the tree."""
    from gather_verify.synthesis.refute import Refutation

    used = sorted({k for lits in literals for k in lits})
    number = {k: j for j, k in enumerate(used)}
    proof = tree if isinstance(tree, Refutation) else None
    if proof is not None and proof.views != used:  # pragma: no cover - refute numbers so
        raise AssertionError("a proof numbered over other views than its counterexamples'")

    def renumber(node: Any) -> Any:
        return node if isinstance(node, int) else [number[node[0]],
                                                   [renumber(c) for c in node[1]]]

    doc = {
        "format": FORMAT,
        "answer": "none",
        "instance": inst.describe(),
        "covers": ("every algorithm that is a deterministic function of the view up to "
                   "isomorphism (these capabilities, these frames) fails the task from at "
                   "least one of these initial configurations under this scheduler, and under "
                   "each scheduler of holds_under: each leaf's counterexample is an execution "
                   "every algorithm on its path has (found under the adversary it names, a "
                   "run of every stronger one too)"),
        "holds_under": holds_under(views, cexs, literals),
        "views": [{"key": views.texts[k], "options": len(views.options[k])} for k in used],
        "counterexamples": cexs,
        "tree": None if proof is not None else renumber(tree),
        **({"proof": {"format": PROOF_FORMAT, "steps": proof.steps}} if proof else {}),
        "stats": stats,
    }
    with open(path, "w", encoding="utf-8") as f:
        json.dump(doc, f, separators=(",", ":"))
        f.write("\n")


def load_certificate(path: str) -> tuple[dict[str, Any], Instance]:
    """A certificate file (its fields of the types they must have) and the instance its text
    gives today, or :class:`InvalidInput` (not a certificate) / :class:`CertificateError`
    (a malformed one, or its instance does not match)."""
    doc = _read(path)
    raw = _fields(doc)[0]
    return doc, _instance(raw)


def _read(path: str) -> dict[str, Any]:
    """The certificate's JSON, read bounded (its size is checked before it is parsed)."""
    from gather_verify.inputs import read_text

    try:
        doc = json.loads(read_text(path, "certificate"))
    except json.JSONDecodeError as error:
        raise InvalidInput(f"{path}: not JSON ({error})") from None
    except RecursionError:
        raise InvalidInput(f"{path}: not JSON (nested too deeply)") from None
    if not isinstance(doc, dict) or doc.get("format") != FORMAT:
        raise InvalidInput(f"{path}: not a synthesis certificate ({FORMAT!r})")
    return doc


def _instance(raw: dict[str, Any]) -> Instance:
    """The instance a certificate's text gives today; it must be the one it names."""
    inst = make_instance(raw["world"], raw["robots"],
                         " ".join(str(_text(v)) for v in raw["meeting_nodes"]),
                         raw["scheduler"], raw["task"], raw["detection"], raw["frames"],
                         raw["visibility"], raw["lights"], raw.get("colours"),
                         raw.get("start"))
    if inst.describe() != raw:
        raise CertificateError("the instance does not match what its text gives today "
                               "(the configurations or the graph file changed)")
    return inst


def verify_certificate(path: str, max_seconds: float | None = None,
                       max_memory_mb: float | None = None) -> dict[str, Any]:
    """Re-check a certificate without searching; a summary, or :class:`CertificateError`
    (the certificate does not hold) / :class:`InvalidInput` (not a certificate). The file is
    read bounded, and the re-check runs within ``max_seconds`` and ``max_memory_mb``
    (:class:`~gather_verify.engine.bounds.SetupStopped` past them: a certificate may name a
    world too large to rebuild in time)."""
    from gather_verify.engine.bounds import setup

    doc = _read(path)
    raw, cexs, tree, listed = _fields(doc)
    with setup(f"re-checking the certificate of {raw['world']}", max_seconds, max_memory_mb):
        inst = _instance(raw)
        views = Views(inst)
        clauses = []
        for j, cex in enumerate(cexs):
            try:
                got = replay(views, cex)
            except CertificateError as error:
                raise CertificateError(f"counterexample {j}: {error}") from None
            clauses.append(got.literals)
        # the certificate names views by its own numbering (its list of key texts)
        number = {views.index[text]: j for j, text in enumerate(listed) if text in views.index}
        renamed = []
        for lits in clauses:
            try:
                renamed.append({number[k]: o for k, o in lits.items()})
            except KeyError as error:
                raise CertificateError(f"a counterexample meets a view the list leaves out "
                                       f"({views.texts[error.args[0]][:60]})") from None
        options = {number[k]: len(views.options[k]) for lits in clauses for k in lits}
        if "proof" in doc:
            lemmas = check_proof(doc["proof"], renamed, options, len(listed))
            leaves, inner, more = 0, 0, {"proof_lemmas": lemmas}
        else:
            leaves, inner, more = check_tree(tree, renamed, options), _inner_nodes(tree), {}
        holds = holds_under(views, cexs, clauses)
    if "holds_under" in doc and doc["holds_under"] != holds:
        raise CertificateError(f"the certificate says it holds under {doc['holds_under']}; "
                               f"its counterexamples show {holds}")
    return {"answer": "none", "holds": True, "counterexamples": len(cexs),
            "views": len(options), "leaves": leaves, "tree_nodes": inner, **more,
            "holds_under": holds,
            "found_under": sorted({str(c.get("scheduler", inst.scheduler)) for c in cexs}),
            "rests_on": rests_on(None if "proof" in doc else tree, cexs), "instance": raw}


def check_proof(proof: Any, clauses: list[dict[int, int]], options: dict[int, int],
                listed: int) -> int:
    """Run a certificate's resolution proof (:mod:`.refute`'s clauses over the ``listed``
    views, :func:`~gather_verify.synthesis.rup.check`): its number of lemmas, or
    :class:`CertificateError` naming the step that does not follow."""
    from gather_verify.synthesis import refute, rup

    steps = proof.get("steps") if isinstance(proof, dict) else None
    if not isinstance(steps, list) or not all(
            isinstance(s, list) and all(type(x) is int for x in s) for s in steps):
        raise CertificateError("a malformed proof: 'steps' is not a list of lists of integers")
    if set(options) != set(range(listed)):
        raise CertificateError("the list of views names one that no counterexample meets")
    nvars, cnf = refute.clauses([options[j] for j in range(listed)], clauses)
    try:
        got = rup.check(nvars, cnf, steps)
    except ValueError as error:
        raise CertificateError(f"the proof: {error}") from None
    if not got.holds:
        where = "" if got.step < 0 else f" (step {got.step})"
        raise CertificateError(f"the proof does not hold{where}: {got.why}")
    return sum(1 for s in steps[:got.last + 1] if not s or s[0] != 0)


def holds_under(views: Views, cexs: list[dict[str, Any]], clauses: list[dict[int, int]]
                ) -> list[str]:
    """The schedulers under which the certificate holds: the instance's, and, when every
    counterexample was found under a cheaper adversary, every scheduler each of them lifts
    to (a none under FSYNC is one under SSYNC and ASYNC, :mod:`.lift`). Each claim is
    re-checked: every counterexample, lifted to that scheduler, replays through it and
    relies on no literal its own replay did not (so the tree holds there too)."""
    inst = views.inst
    target, colours = inst.scheduler, inst.lights.colours
    found = [str(c.get("scheduler", target)) for c in cexs]
    holds = [s for s in LADDER if all(liftable(f, s, colours) for f in found)] or [target]
    for s in holds:
        for j, (cex, own) in enumerate(zip(cexs, found, strict=True)):
            if own == s:
                continue
            start = [inst.world.node_to_json(v)
                     for v in inst.configurations[int(cex["configuration"])][0]]
            try:
                got = replay(views, lift(cex, own, s, colours, start), scheduler=s)
            except (CertificateError, KeyError, ValueError) as error:
                raise CertificateError(f"counterexample {j}, lifted to {s}: {error}") from None
            if any(clauses[j].get(k) != o for k, o in got.literals.items()):
                raise CertificateError(f"counterexample {j}, lifted to {s}, relies on an "
                                       "answer its own replay does not")
    return holds


def rests_on(tree: Any, cexs: list[dict[str, Any]]) -> list[int]:
    """The initial configurations (indices) of the counterexamples the tree's leaves use (a
    proof's: all of them, it keeps those it uses): no one algorithm solves the task from
    all of them."""
    if tree is None:
        return sorted({int(c["configuration"]) for c in cexs})
    out: set[int] = set()
    stack = [tree]
    while stack:
        node = stack.pop()
        if isinstance(node, int):
            out.add(int(cexs[node]["configuration"]))
        else:
            stack.extend(node[1])
    return sorted(out)


INSTANCE_FIELDS: dict[str, tuple[type, ...]] = {
    "world": (str,), "robots": (str,), "meeting_nodes": (list,), "scheduler": (str,),
    "task": (str, type(None)), "detection": (str,), "frames": (str,),
    "visibility": (int, type(None)), "lights": (str, type(None)),
    "colours": (str, type(None)), "configurations": (list,), "start": (str, type(None))}
"""The fields of a certificate's instance, with the JSON types each may hold."""


def _fields(doc: dict[str, Any]) -> tuple[dict[str, Any], list[Any], Any, list[str]]:
    """The instance, counterexamples, tree and view keys of a certificate, each of the type
    it must have (:class:`CertificateError` naming the first that is not)."""
    raw = doc.get("instance")
    if not isinstance(raw, dict):
        raise CertificateError("a malformed certificate: 'instance' is not an object")
    for name, types in INSTANCE_FIELDS.items():
        value = raw.get(name)
        if name not in raw and name not in ("colours", "start") or isinstance(value, bool) or \
                not isinstance(value, types):
            raise CertificateError(f"a malformed certificate: instance field {name!r} is "
                                   f"{json.dumps(value)[:40]}, not "
                                   f"{' or '.join(_json_type(t) for t in types)}")
    cexs, tree, views = doc.get("counterexamples"), doc.get("tree"), doc.get("views")
    if not isinstance(cexs, list) or not all(isinstance(c, dict) for c in cexs):
        raise CertificateError("a malformed certificate: 'counterexamples' is not a list of "
                               "objects")
    if not isinstance(views, list) or not all(
            isinstance(v, dict) and isinstance(v.get("key"), str) for v in views):
        raise CertificateError("a malformed certificate: 'views' is not a list of objects "
                               "with a text 'key'")
    return raw, cexs, tree, [v["key"] for v in views]


def _json_type(t: type) -> str:
    return {str: "text", list: "a list", int: "an integer", type(None): "null"}[t]


def _inner_nodes(tree: Any) -> int:
    """The questions (inner nodes) of a decision tree that :func:`check_tree` accepted."""
    count, stack = 0, [tree]
    while stack:
        node = stack.pop()
        if isinstance(node, list):
            count += 1
            stack.extend(node[1])
    return count


def _text(node: Any) -> str:
    return ",".join(map(str, node)) if isinstance(node, list) else str(node)
