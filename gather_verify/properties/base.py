"""A property as one object: what it says, over which facts, how it fails, how replay
confirms it (SEMANTICS.md §5; the Stateright model: properties are data that one
generic checker loop evaluates).

Three kinds:

- ``state``: ``holds(s)`` over the :class:`~gather_verify.properties.facts.StateFacts` of
  every reached state (``final``: a deadlock is gathered);
- ``transition``: ``holds(before, after)`` over a per-configuration ``value`` on each side
  of every transition (``target-invariance``: the target never changes);
- ``graph``: ``decide(graph)`` on the whole reachable graph once the search is complete
  (``move-bound``, ``termination``; :mod:`gather_verify.properties.graph`).

The predicate is written once, over facts; the reference engine evaluates it on
each state, the bulk engine once per distinct configuration (and idle flag, or
pair of values) of its facts table, ``replay`` on the facts of the replayed states.

>>> from gather_verify.properties.facts import StateFacts
>>> p = Property("near", "state", holds=lambda s: s.idle, message="something is pending")
>>> p.message_for(StateFacts(None, idle=False))
'something is pending'
>>> Property("x", "liveness")
Traceback (most recent call last):
...
gather_verify.errors.InvalidInput: property 'x': kind must be one of state, transition, graph, not 'liveness'
"""

from __future__ import annotations

from collections.abc import Callable, Hashable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from gather_verify.errors import InvalidInput
from gather_verify.properties.facts import Facts, StateFacts

if TYPE_CHECKING:
    from gather_verify.properties.graph import GraphFacts

KINDS = ("state", "transition", "graph")
WHEN = ("expansion", "discovery")
"""When a state property is evaluated: as each state is expanded (the default, as in
Stateright's BFS), or as soon as it is first reached (its witness may then be a state
the search found but never expanded before a limit stopped it)."""

UNION_FACTS = ("deadlock", "in-u", "target-change", "longest-path", "acyclic")
"""What the union engine reads per configuration off its shared state graph, the facts a
property may name as its ``union``: a reachable deadlock (no robot can move, nothing
pending, not gathered), a reachable configuration in U, a reachable transition that changes
the target, the largest total moves (compared with ``c * D * n``), and no reachable cycle."""


@dataclass
class Witness:
    """A counterexample of a graph property: ``path`` (state ids from the initial state) and,
    for an infinite execution, a ``cycle`` of ids from the path's last state back to it, in
    ``exploration`` (the reduced graph, or the one lifted to concrete states)."""

    exploration: Any
    path: list[int]
    reason: str
    cycle: list[int] | None = None
    detail: dict[str, Any] = field(default_factory=dict)


@dataclass
class Outcome:
    """What a graph property decided: its entry in the report's ``properties`` and, when it
    fails, the witness the trace is built from."""

    result: dict[str, Any]
    witness: Witness | None = None


@dataclass
class Run:
    """A replayed trace, as ``replay`` hands it to a property's confirmation: the states it
    reached (``states[0]`` is the initial state) and the facts of a state computed from the
    algorithm alone (never from the explorer)."""

    trace: dict[str, Any]
    states: list[Any]
    steps: list[Any]
    facts: Callable[[Any], Facts]
    move_sets: Callable[[tuple], dict]
    stays: Callable[[Any, int], bool] | None = None
    """With lights: whether robot i of a state is idle and may stay, keeping its colour."""

    def state_facts(self, k: int = -1) -> StateFacts:
        """The facts of the ``k``-th replayed state (the last by default)."""
        state = self.states[k]
        return StateFacts(self.facts(state), all(r[1] is None for r in state))

    def may_stay(self, state: Any, i: int) -> bool:
        """Whether robot ``i`` of ``state`` is idle and may stay (a null activation, §5)."""
        if self.stays is not None:
            return self.stays(state, i)
        v, p = state[i]
        return p is None and v in self.move_sets(tuple(sorted(r[0] for r in state)))[v]


@dataclass(frozen=True, eq=False)
class Property:
    """One property: its name, kind, predicate, message and confirmation.

    - ``holds``: state: ``holds(s) -> bool`` over :class:`StateFacts`; transition:
      ``holds(before, after) -> bool`` over ``value`` of each side.
    - ``value``: transition: ``value(facts) -> hashable``, a function of the configuration.
    - ``message``: why it fails, a string or a function of the same arguments as ``holds``.
    - ``detail``: ``detail(...) -> dict`` (the same arguments as ``holds``) for the witness's
      and the trace's ``detail`` (``crash``: the robot, its view, the exception).
    - ``vacuous``: ``vacuous(s) -> str | None`` on the initial state: a reason the property
      holds without checking (then it is not checked).
    - ``confirm``: ``confirm(prop, run) -> (confirmed, message)`` for ``replay``; by default
      state and transition properties re-evaluate ``holds`` on the replayed facts.
    - ``decide``: graph: ``decide(graph) -> Outcome`` (:class:`GraphFacts`).
    - ``pseudo``: always checked and never requested by name (``defined``: the algorithm has
      a rule wherever the search goes); ``halts``: a failing state cannot be expanded, so
      the search stops there; ``when``: see :data:`WHEN`.
    - ``symmetric``: the answer is the same on the images of a state under ``Aut(M)``, so the
      symmetry reduction (which stores one state per class) is sound for it. False (the
      default) switches that reduction off while the property is checked: a predicate that
      reads absolute nodes (the initial MER, a fixed node) is not symmetric. Anonymity needs
      nothing: facts are those of the robot multiset.
    - ``union``: the fact of the union engine's shared state graph
      (:mod:`gather_verify.engine.union`) that decides this property in a sweep, one of
      :data:`UNION_FACTS`: a promise that the property fails exactly where that fact says.
      None (the default): the union cannot decide it, and a sweep that checks it checks
      every configuration on its own.
    """

    name: str
    kind: str
    holds: Callable[..., bool] | None = None
    message: str | Callable[..., str] = ""
    value: Callable[[Facts], Hashable] | None = None
    detail: Callable[..., dict[str, Any]] | None = None
    vacuous: Callable[[StateFacts], str | None] | None = None
    confirm: Callable[[Property, Run], tuple[bool, str]] | None = None
    decide: Callable[[GraphFacts], Outcome] | None = None
    pseudo: bool = False
    halts: bool = False
    when: str = "expansion"
    symmetric: bool = False
    union: str | None = None
    doc: str = ""

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name or any(
                ch.isspace() or ch == ":" for ch in self.name):
            raise InvalidInput(f"bad property name {self.name!r}: a non-empty word without ':'")
        what = f"property {self.name!r}"
        if self.kind not in KINDS:
            raise InvalidInput(f"{what}: kind must be one of {', '.join(KINDS)}, not {self.kind!r}")
        if self.when not in WHEN:
            raise InvalidInput(f"{what}: when must be one of {', '.join(WHEN)}, not {self.when!r}")
        if self.kind == "graph":
            if not callable(self.decide) or not callable(self.confirm):
                raise InvalidInput(f"{what}: a graph property needs decide and confirm")
        elif not callable(self.holds):
            raise InvalidInput(f"{what}: a {self.kind} property needs a holds predicate")
        if self.kind == "transition" and not callable(self.value):
            raise InvalidInput(f"{what}: a transition property needs a value function")
        if self.union is not None and self.union not in UNION_FACTS:
            raise InvalidInput(f"{what}: union must be one of {', '.join(UNION_FACTS)} or None, "
                               f"not {self.union!r}")
        if self.halts and self.kind != "state":
            raise InvalidInput(f"{what}: only a state property can stop the search")

    def message_for(self, *args: Any) -> str:
        """The failure message for the arguments of a failing ``holds``."""
        return self.message(*args) if callable(self.message) else self.message

    def detail_for(self, *args: Any) -> dict[str, Any]:
        return {} if self.detail is None else self.detail(*args)

    def confirmed(self, run: Run) -> tuple[bool, str]:
        """Whether the replayed ``run`` really violates this property, and why (for ``replay``)."""
        if self.confirm is not None:
            return self.confirm(self, run)
        return default_confirm(self, run)


def fails_at_end(prop: Property, run: Run) -> tuple[bool, tuple[Any, ...]]:
    """Whether ``prop`` fails at the end of ``run`` (the last state; for a transition property,
    the last transition), and the arguments its predicate was evaluated on."""
    if prop.kind == "state":
        s = run.state_facts()
        first = run.state_facts(0)
        vacuous = prop.vacuous is not None and prop.vacuous(first) is not None
        return not vacuous and not prop.holds(s), (s,)  # type: ignore[misc]
    if prop.kind == "transition":
        if len(run.states) < 2:
            return False, ()
        value = prop.value
        assert value is not None and prop.holds is not None
        args = (value(run.facts(run.states[-2])), value(run.facts(run.states[-1])))
        return not prop.holds(*args), args
    raise AssertionError(f"property {prop.name!r}: a graph property confirms itself")


def default_confirm(prop: Property, run: Run) -> tuple[bool, str]:
    """``holds`` re-evaluated on the replayed facts: confirmed when it fails at the end."""
    ok, args = fails_at_end(prop, run)
    if ok:
        return True, prop.message_for(*args)
    where = "state" if prop.kind == "state" else "transition"
    return False, f"{prop.name} holds on the last {where}"


def always(name: str, holds: Callable[[StateFacts], bool], message: str | Callable[..., str],
           **options: Any) -> Property:
    """A state property that must hold in every reachable state (Stateright's ``always``).

    >>> p = always("idle", lambda s: s.idle, "a move is pending")
    >>> p.kind, p.name
    ('state', 'idle')
    """
    return Property(name, "state", holds=holds, message=message, **options)
