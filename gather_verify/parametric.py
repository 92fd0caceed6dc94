"""A safety property of a gap-rule algorithm for every ring size at once (docs/howto/rings.md).

The ring's size n is a parameter: Sangnier, Sznajder, Potop-Butucaru and Tixeuil
("Parameterized verification of algorithms for oblivious robots on a ring", FMCAD 2017 /
Formal Methods in System Design 2020) encode the configurations of k robots on a ring of any
size as k integers, the gaps between consecutive robots, and a robot's rules as formulas of
Presburger arithmetic (linear integer arithmetic) on them, and check them with an SMT solver.
Safety is decidable under the synchronous schedulers and undecidable under ASYNC in general.

Here, with k robots, a gap-rule algorithm (:mod:`gather_verify.algorithms.gap_rules`) and a
scheduler S among FSYNC, SSYNC and the centralized one, :func:`prove` decides
**exclusivity** (no two robots on one node, no two crossing an edge) from every initial
configuration, on every ring of n >= n0 nodes:

- a state of S is a configuration (no pending moves), so the reachable configurations from
  every start are exactly the configurations reached from robots on distinct nodes;
- every configuration with robots on distinct nodes is a start. So exclusivity holds on
  every run if and only if one round from any such configuration keeps the robots on
  distinct nodes and crosses no edge (an induction on the rounds; conversely a round that
  breaks it from a start is a counterexample);
- that one-round statement is a formula of linear integer arithmetic over the gaps
  g_0 .. g_{k-1} >= 1 with n = g_0 + ... + g_{k-1} >= n0: each robot's two readings (its
  frames), each rule's pattern, the first rule that matches, the adversary's choices (which
  robots, which direction where the move set holds both), and the gaps after the round,
  g_i' = g_i - d_i + d_{i+1}. It is unsatisfiable exactly when exclusivity holds. z3
  decides it (``pip install 'gather-verify[smt]'``).

A counterexample comes back as a size, a configuration and a round, the smallest size z3
finds; the ordinary checker then replays it at that size (the report says what it found).

Not decided here: liveness (perpetual exploration: every node visited infinitely often;
termination), which is no one-round statement; and ASYNC, where a state holds the pending
moves of stale snapshots, so the reachable states are not the starts and one round says
nothing (Sangnier et al. prove safety undecidable there in general). Check those at each
size with ``check --world ring:N``.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from typing import Any

from gather_verify.algorithms.gap_rules import GapRules, Rule
from gather_verify.errors import InvalidInput

SCHEDULERS = ("fsync", "ssync", "centralized")
PROPERTIES = ("exclusivity",)


def solver_module() -> Any:
    try:
        import z3
    except ImportError:
        raise InvalidInput("a proof for every ring size needs z3: pip install "
                           "'gather-verify[smt]'") from None
    return z3


def check_inputs(algorithm: Any, k: int, scheduler: str, detection: str, frames: str) -> None:
    """One line (:class:`InvalidInput`) for what :func:`prove` cannot decide."""
    if not isinstance(algorithm, GapRules):
        raise InvalidInput("a proof for every ring size reads the algorithm's rules: give a "
                           "gap-rule algorithm (docs/howto/rings.md), such as a witness of "
                           "synthesize --world ring:A-B --together")
    if scheduler not in SCHEDULERS:
        raise InvalidInput(f"scheduler {scheduler}: safety for every ring size is decided under "
                           f"{', '.join(SCHEDULERS)}; under async a state holds stale "
                           "snapshots and safety is undecidable in general (Sangnier et al.): "
                           "check each size with --world ring:N")
    if not 1 <= k <= 32:
        raise InvalidInput(f"--robots {k}: give a count of robots from 1 to 32")
    if frames not in ("all", "chirality", "compass"):
        raise InvalidInput(f"frames {frames!r}: use all, chirality or compass")
    for rule in algorithm.rules:
        for j, c in enumerate(rule.marks):
            shown = detection.startswith("global") or (detection.startswith("local") and j == 0)
            if c != "*" and not shown:
                raise InvalidInput(f"the rule {rule} reads a mark that detection {detection} "
                                   "does not show")


class Encoding:
    """The one-round formula for k robots: the gaps, each robot's move, the gaps after."""

    def __init__(self, z3: Any, algorithm: GapRules, k: int, scheduler: str, frames: str,
                 low: int):
        self.z3, self.k = z3, k
        self.gaps = [z3.Int(f"g{i}") for i in range(k)]
        self.n = z3.Sum(self.gaps) if k > 1 else self.gaps[0]
        self.facts = [g >= 1 for g in self.gaps] + [self.n >= max(low, 3)]
        self.moves = []
        active = [z3.Bool(f"active{i}") for i in range(k)]
        pick = [z3.Bool(f"back{i}") for i in range(k)]  # which frame's answer the robot takes
        for i in range(k):
            ahead = [self.gaps[(i + j) % k] for j in range(k)]
            cw = self.answer(algorithm, ahead)  # in the clockwise frame: +1 is forward
            ccw = -self.answer(algorithm, ahead[::-1])  # the anticlockwise frame
            move = cw if frames != "all" else z3.If(pick[i], ccw, cw)
            self.moves.append(z3.If(active[i], move, 0))
        if scheduler == "fsync":
            self.facts += active
        elif scheduler == "centralized":
            self.facts.append(z3.PbEq([(a, 1) for a in active], 1))
        else:
            self.facts.append(z3.Or(active))
        self.after = [self.gaps[i] - self.moves[i] + self.moves[(i + 1) % k] for i in range(k)]

    def answer(self, algorithm: GapRules, reading: Sequence[Any]) -> Any:
        """The displacement (+1 forward, -1 back, 0 stay) the rules answer on ``reading``:
        the first rule matching it as it is, or the other way round (then mirrored)."""
        z3 = self.z3
        out = _step(algorithm.otherwise)
        back = list(reading)[::-1]
        for rule in reversed(algorithm.rules):
            if not rule.one_way:
                out = z3.If(self.matches(rule, back), -_step(rule.then), out)
            out = z3.If(self.matches(rule, reading), _step(rule.then), out)
        return out

    def matches(self, rule: Rule, reading: Sequence[Any]) -> Any:
        """Whether ``rule`` matches a reading of robots on distinct nodes (every mark is one
        robot)."""
        z3 = self.z3
        if len(rule.tokens) != len(reading) or "T" in rule.marks:
            return z3.BoolVal(False)
        terms = [g == t.low if t.exact else g >= t.low
                 for g, t in zip(reading, rule.tokens, strict=True)]
        ops = {"<": lambda x, y: x < y, "<=": lambda x, y: x <= y, "=": lambda x, y: x == y,
               ">=": lambda x, y: x >= y, ">": lambda x, y: x > y}
        terms += [ops[op](reading[x], reading[y]) for x, op, y in rule.relations]
        return z3.And(terms) if terms else z3.BoolVal(True)


def _step(answer: str) -> int:
    return {"stay": 0, "forward": 1, "back": -1}[answer]


def prove(algorithm: Any, k: int, scheduler: str, *, low: int = 3,
          detection: str = "global-weak", frames: str = "all",
          max_seconds: float = 600.0) -> dict[str, Any]:
    """Decide exclusivity of ``algorithm`` for ``k`` robots under ``scheduler`` on every ring
    of ``low`` nodes or more: ``holds`` True (a proof), False (with the smallest size z3
    finds, the configuration as node numbers and the round), or None (z3 gave up)."""
    check_inputs(algorithm, k, scheduler, detection, frames)
    z3 = solver_module()
    started = time.perf_counter()
    enc = Encoding(z3, algorithm, k, scheduler, frames, low)
    out: dict[str, Any] = {"property": "exclusivity", "robots": k, "scheduler": scheduler,
                           "frames": frames, "low": max(low, 3)}
    if k == 1:
        out.update(holds=True, seconds=time.perf_counter() - started)
        return out
    opt = z3.Optimize()
    opt.set("timeout", int(max_seconds * 1000))
    opt.add(*enc.facts)
    opt.add(z3.Or([g <= 0 for g in enc.after]))
    opt.minimize(enc.n)
    got = opt.check()
    out["seconds"] = time.perf_counter() - started
    if got == z3.unsat:
        out["holds"] = True
        return out
    if got != z3.sat:
        out.update(holds=None, reason=f"z3 answered {got} ({opt.reason_unknown()})")
        return out
    model = opt.model()
    gaps = [model.eval(g).as_long() for g in enc.gaps]
    moves = [model.eval(m, model_completion=True).as_long() for m in enc.moves]
    nodes = [sum(gaps[:i]) for i in range(k)]
    out.update(holds=False, n=sum(gaps), gaps=gaps, robots_at=nodes, moves=moves)
    return out


def breaks_at(algorithm: GapRules, gaps: Sequence[int], scheduler: str,
              frames: str = "all") -> bool:
    """Whether the formula of :func:`prove` has a round breaking exclusivity from the
    configuration with these gaps (the tests hold it against the ordinary successors)."""
    z3 = solver_module()
    enc = Encoding(z3, algorithm, len(gaps), scheduler, frames, 3)
    s = z3.Solver()
    s.add(*enc.facts, *(g == v for g, v in zip(enc.gaps, gaps, strict=True)))
    s.add(z3.Or([g <= 0 for g in enc.after]))
    return bool(s.check() == z3.sat)


def rounds_at(algorithm: GapRules, gaps: Sequence[int], scheduler: str,
              frames: str = "all") -> set[tuple[int, ...]]:
    """Every round the formula allows from the configuration with these gaps, as the robots'
    displacements (+1 clockwise), the round where nobody moves left out (the tests hold it
    against the scheduler's own successors)."""
    z3 = solver_module()
    enc = Encoding(z3, algorithm, len(gaps), scheduler, frames, 3)
    s = z3.Solver()
    s.add(*enc.facts, *(g == v for g, v in zip(enc.gaps, gaps, strict=True)))
    out = set()
    while s.check() == z3.sat:
        model = s.model()
        got = tuple(model.eval(m, model_completion=True).as_long() for m in enc.moves)
        out.add(got)
        s.add(z3.Or([m != v for m, v in zip(enc.moves, got, strict=True)]))
    out.discard((0,) * len(gaps))
    return out


def round_text(result: dict[str, Any]) -> str:
    """The counterexample's round in words."""
    n = result["n"]
    said = []
    for v, d in zip(result["robots_at"], result["moves"], strict=True):
        if d:
            said.append(f"robot on {v} steps {'clockwise' if d > 0 else 'anticlockwise'} to "
                        f"{(v + d) % n}")
    return "; ".join(said) or "no robot moves"
