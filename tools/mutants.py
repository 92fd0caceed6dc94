"""Mutation testing of the verifier: deliberate bugs in the paper's algorithm and in go-to-target.

Test tooling, not part of the installed package: it patches the *source* of
``gather_verify/paper/algorithm.py`` and ``go_to_target.py`` and reads the
scenario set ``scenarios/mutants/`` of a source checkout. Run it from the
repository's root::

    python -m tools.mutants            # the table and the score (exit 0: goal reached)
    python -m tools.mutants --json     # one JSON object
    python -m tools.mutants --list     # the mutants
    python -m tools.mutants --mutant mutant-gtt-stops-one-short
    python -m tools.mutants cli check --robots "0,0 1,1" --meeting "2,2" \
        --algorithm mutant-gtt-stops-one-short   # any gather-verify command, mutants known

A *mutant* is a real code mutation: the source of ``paper/algorithm.py`` or
``algorithms/go_to_target.py`` with one decision changed (a snippet replaced
by another, each snippet found exactly once, so a mutation cannot silently
miss its site when the algorithm is edited), loaded as a private copy of the
module. The original modules are never touched.

:func:`run_mutants` runs the explorer on a fixed scenario set
(``scenarios/mutants/``) against each mutant. Every scenario names the
*baseline* algorithm it belongs to (``paper:alpha=mer_f``, the variant of the
paper's algorithm that passes most, or ``go-to-target``) and the scheduler,
and records that the baseline is VERIFIED there. A mutant is *caught* when the
explorer finds a property VIOLATED on some scenario of its baseline (with a
counterexample trace); a mutant that only runs into a limit (INCOMPLETE) is
not counted as caught. The mutation score is caught / all mutants.

>>> names = [m.name for m in MUTANTS]
>>> len(names) >= 12 and all(n.startswith("mutant-") for n in names)
True
>>> m = get_mutant("mutant-paper-guard-stops-early").build()
>>> m.name
'mutant-paper-guard-stops-early'
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from types import ModuleType
from typing import Any

from gather_verify.algorithms import Algorithm, register
from gather_verify.algorithms import go_to_target as _go_to_target
from gather_verify.cli.common import (
    EXIT_OK,
    EXIT_USAGE,
    EXIT_VIOLATED,
    print_json,
    without_timings,
)
from gather_verify.errors import InvalidInput
from gather_verify.paper import algorithm as _paper
from gather_verify.plane_check import run_check
from gather_verify.properties import ORDER
from gather_verify.scenario import load_scenario

PAPER_BASELINE = "paper:alpha=mer_f"
GTT_BASELINE = "go-to-target"
SCENARIO_DIR = Path(__file__).resolve().parent.parent / "scenarios" / "mutants"
GOAL = 0.95
"""The mutation score ``python -m tools.mutants`` requires for exit code 0."""
MAX_STATES = 3000
MAX_SECONDS = 600.0
"""Limits of each check: every baseline space of the set has under 1200 states, so a mutant
whose space is larger is reported INCOMPLETE (not counted as caught) rather than searched.
The state limit, not the time limit, is the one meant to stop a search, so the result does
not depend on the machine's speed."""


class MutationSiteError(InvalidInput):
    """A mutant's snippet is not found exactly once in its module (the module changed)."""


@dataclass(frozen=True)
class Mutant:
    """One deliberate bug: ``edits`` (old snippet, new snippet) applied to ``module``'s source."""

    name: str
    baseline: str
    description: str
    edits: tuple[tuple[str, str], ...]
    expected: tuple[str, ...]
    """Properties the scenario set is expected to find violated (the test checks them)."""
    equivalent: str | None = None
    """Why the mutant cannot be caught, when it is an equivalent mutant."""

    @property
    def module(self) -> ModuleType:
        return _paper if self.baseline == PAPER_BASELINE else _go_to_target

    def build(self, **options: str) -> Algorithm:
        """A fresh instance of the mutated algorithm."""
        module = _mutated_module(self)
        if self.baseline == PAPER_BASELINE:
            algorithm = module.PaperAlgorithm(**{"alpha": "mer_f", **options})
        else:
            algorithm = module.GoToTarget(**options)
        algorithm.name = self.name
        return algorithm


_MODULES: dict[str, ModuleType] = {}


def _mutated_module(mutant: Mutant) -> ModuleType:
    """The mutant's copy of its module (built once per process)."""
    got = _MODULES.get(mutant.name)
    if got is not None:
        return got
    original = mutant.module
    source = Path(original.__file__).read_text(encoding="utf-8")  # type: ignore[arg-type]
    for old, new in mutant.edits:
        count = source.count(old)
        if count != 1:
            raise MutationSiteError(f"{mutant.name}: mutation site {old.strip()!r} occurs {count} "
                                    f"times in {original.__name__} (expected once)")
        source = source.replace(old, new)
    name = f"{original.__name__}__{mutant.name.replace('-', '_')}"
    module = ModuleType(name)
    module.__file__ = original.__file__
    sys.modules[name] = module  # dataclasses resolve annotations through sys.modules
    exec(compile(source, f"<{mutant.name} of {original.__file__}>", "exec"),  # noqa: S102
         module.__dict__)
    _MODULES[mutant.name] = module
    return module


# -- the mutants ------------------------------------------------------------------------

_P, _G = PAPER_BASELINE, GTT_BASELINE
_OWN_FRAME = (
    "        key, g, t = view.canonical()\n",
    "        # the view as the robot holds it: no canonical form\n"
    "        key, g, t = ((tuple(sorted(view.robots)), tuple(sorted(view.meeting_nodes))),\n"
    "                     geometry.IDENTITY, (0, 0))\n")
"""Part of a compass mutant: each robot analyses its snapshot in its own frame, so a tie
broken by coordinates is broken by the robot's private compass."""
_GTT_STEP = "        x, y = target\n"
"""go-to-target's decision point: the robot's target in its own frame is known."""

MUTANTS: tuple[Mutant, ...] = (
    # Guard selection and placement (Algorithm 2).
    Mutant(
        "mutant-paper-guard-stops-early", _P,
        "guard placement stops one step early: a guard one step from its MER corner stays",
        (("    if guard not in corners:\n",
          "    if guard not in corners and min(manhattan(guard, k) for k in corners) == 1:\n"
          "        return Plan('I2 guard placement', None, moves, guard=guard)\n"
          "    if guard not in corners:\n"),),
        ("final",)),
    Mutant(
        "mutant-paper-guard-selection-stops-early", _P,
        "guard selection stops one step early: a robot level with the farthest meeting node "
        "already counts as outside (dist >= d1 instead of dist > d1)",
        (("            return dist(v) > d1\n", "            return dist(v) >= d1\n"),),
        ("final",)),
    Mutant(
        "mutant-paper-guard-selection-inward", _P,
        "the robot chosen in guard selection steps towards L ∪ {c} instead of away from it",
        (("if dist(u) > dist(v))", "if dist(u) < dist(v))"),),
        ("defined", "final")),
    Mutant(
        "mutant-paper-guard-tie-fixed-compass", _P,
        "a tie between farthest robots in guard selection is broken by a fixed compass (the "
        "lowest in the robot's own frame) instead of the maximum configuration view",
        (("guard = farthest[0] if len(farthest) == 1 else strings.max_view(c, farthest, weak=True)",
          "guard = farthest[0]"),
         _OWN_FRAME),
        ("defined",)),
    Mutant(
        "mutant-paper-placement-towards-axis", _P,
        "guard placement may take steps that bring the guard nearer L ∪ {c}",
        (("closer_steps(guard, k) if dist(u) >= dist(guard))",
          "closer_steps(guard, k) if dist(u) >= dist(guard) - 2)"),),
        ("termination",)),
    Mutant(
        "mutant-paper-non-guards-before-placement", _P,
        "non-guard robots start MakeMultiplicity before the guard is placed on its MER corner",
        (("        moves[guard] = steps\n",
          "        moves[guard] = steps\n"
          "        early = min(c.meeting_nodes, key=lambda m: (manhattan(guard, m), m))\n"
          "        rest = [r for r in c.occupied if r != guard and r != early]\n"
          "        for r in rest:\n"
          "            if manhattan(r, early) == min(manhattan(s, early) for s in rest):\n"
          "                moves[r] = closer_steps(r, early)\n"),),
        ("target-invariance",)),
    # Target and MakeMultiplicity (Algorithm 3).
    Mutant(
        "mutant-paper-target-farthest", _P,
        "the target meeting node is the one farthest from the guard instead of the closest",
        (("    best = min(manhattan(guard, m) for m in c.meeting_nodes)",
          "    best = max(manhattan(guard, m) for m in c.meeting_nodes)"),),
        ("final",)),
    Mutant(
        "mutant-paper-target-tie-fixed-compass", _P,
        "a tie between meeting nodes closest to the guard is broken by a fixed compass (the "
        "lowest in the robot's own frame) instead of the order O''",
        (("    return min(closest, key=ordering_O_second(c, guard, oscan).index)",
          "    return min(closest)"),
         _OWN_FRAME),
        ("target-invariance", "termination")),
    Mutant(
        "mutant-paper-make-multiplicity-away", _P,
        "in MakeMultiplicity a robot next to the target steps away from it instead of onto it",
        (("                moves[r] = closer_steps(r, target)\n",
          "                moves[r] = closer_steps(r, target) if manhattan(r, target) > 1 else \\\n"
          "                    frozenset(u for u in geometry.neighbours(r)\n"
          "                              if manhattan(u, target) > 1)\n"),),
        ("termination",)),
    Mutant(
        "mutant-paper-make-multiplicity-all", _P,
        "in MakeMultiplicity every non-guard robot moves, not only the closest to the target",
        (("            if manhattan(r, target) == nearest:\n",
          "            if manhattan(r, target) >= nearest:\n"),),
        ("target-invariance",)),
    Mutant(
        "mutant-paper-guard-joins-early", _P,
        "the guard takes part in MakeMultiplicity (it leaves its corner before the others "
        "have gathered)",
        (("    others = [r for r in c.occupied if r != guard and r != target]",
          "    others = [r for r in c.occupied if r != target]"),),
        ("final",)),
    # Finalization (Algorithm 4).
    Mutant(
        "mutant-paper-finalize-both-move", _P,
        "in Finalization the robots on the meeting node also walk towards the guard",
        (("        elif survivor == \"not-both\" or not on_meeting:",
          "        elif True:"),),
        ("final",)),
    Mutant(
        "mutant-paper-reads-hidden-multiplicity", _P,
        "in Finalization the guard asks whether the other position is a multiplicity, which "
        "local-weak detection does not show",
        (("        return _answer(self.allowed(plan, me, view.multiplicity()), me, g)",
          "        return _answer(self.allowed(plan, me, view.multiplicity() or any(\n"
          "            view.multiplicity(v) for v in view.robots)), me, g)"),),
        ("defined",)),
    # The symmetric classes (Algorithm 1, I12/I13, and SymmetryBreaking, Algorithm 5).
    Mutant(
        "mutant-paper-i13-nearest-meeting-node", _P,
        "I13: every robot walks to its own nearest meeting node instead of the one on c",
        (('        return _everyone_to(c, "I13", on_symmetry[0])',
          '        return Plan("I13", on_symmetry[0], {v: closer_steps(v, min(\n'
          '            c.meeting_nodes, key=lambda m: (manhattan(v, m), m))) for v in c.occupied})'),),
        ("final",)),
    Mutant(
        "mutant-paper-i11-first-of-O", _P,
        "I11: the robots head for the first meeting node of O instead of the last",
        (('        return _everyone_to(c, "I11", order[-1])',
          '        return _everyone_to(c, "I11", order[0])'),),
        (),
        equivalent="with alpha over MER_F, O depends on the meeting nodes only, so its first "
                   "element is as fixed a target as its last: every robot still walks a shortest "
                   "path to one node that never changes, and gathers there"),
    Mutant(
        "mutant-paper-symmetry-breaking-along-axis", _P,
        "SymmetryBreaking: the robot on the axis L of C steps along L instead of off it",
        (("    moves[r] = frozenset(u for u in geometry.neighbours(r) if not mirror.fixes(u))",
          "    moves[r] = frozenset(u for u in geometry.neighbours(r) if mirror.fixes(u))"),),
        ("defined",)),
    Mutant(
        "mutant-paper-symmetry-breaking-centre-stays", _P,
        "SymmetryBreaking: the robot on the centre c of a rotation of C stays",
        (("        moves[centre[0]] = frozenset(geometry.neighbours(centre[0]))",
          "        moves[centre[0]] = frozenset({centre[0]})"),),
        ("final",)),
    # go-to-target (SEMANTICS.md §4's yardstick).
    Mutant(
        "mutant-gtt-stops-one-short", _G,
        "a robot one step from the target stays",
        ((_GTT_STEP, _GTT_STEP + "        if abs(x) + abs(y) == 1:\n"
                                 "            return ORIGIN\n"),),
        ("final",)),
    Mutant(
        "mutant-gtt-steps-away", _G,
        "a robot two steps from the target may step away from it",
        ((_GTT_STEP, _GTT_STEP + "        if abs(x) + abs(y) == 2:\n"
                                 "            return (1, 0)  # in its own frame: any direction\n"),),
        ("termination",)),
    Mutant(
        "mutant-gtt-target-farthest", _G,
        "with several meeting nodes the target is the one farthest from the robot instead of "
        "the nearest",
        (("    best = min(manhattan(m, v) for m in nodes)",
          "    best = max(manhattan(m, v) for m in nodes)"),),
        ("termination",)),
    Mutant(
        "mutant-gtt-leaves-target-alone", _G,
        "a robot alone on the target steps off it (it waits for company elsewhere)",
        ((_GTT_STEP, _GTT_STEP + "        if (x, y) == ORIGIN and not view.multiplicity():\n"
                                 "            return (1, 0)\n"),),
        ("termination",)),
    Mutant(
        "mutant-gtt-reads-hidden-multiplicity", _G,
        "a robot next to an occupied target waits until the target holds a multiplicity, which "
        "local-weak detection does not show",
        ((_GTT_STEP, _GTT_STEP + "        if abs(x) + abs(y) == 1 and target in view.robots and \\\n"
                                 "                not view.multiplicity(target):\n"
                                 "            return ORIGIN\n"),),
        ("defined",)),
)


def get_mutant(name: str) -> Mutant:
    for m in MUTANTS:
        if m.name == name:
            return m
    raise InvalidInput(f"unknown mutant {name!r}: use one of {', '.join(m.name for m in MUTANTS)}")


def register_mutants() -> None:
    """Add every mutant to the algorithm registry under its ``mutant-*`` name (the tests,
    :func:`run_mutants` and ``replay`` of a mutant's trace in this process need it)."""
    for m in MUTANTS:
        register(m.name, m.build)


# -- running them ------------------------------------------------------------------------


@dataclass
class MutantResult:
    """What the scenario set found against one mutant."""

    mutant: Mutant
    runs: list[dict[str, Any]] = field(default_factory=list)

    @property
    def caught_by(self) -> list[str]:
        """Every property found violated on some scenario (in the explorer's order)."""
        found = {p for r in self.runs for p in r["violated"]}
        return [p for p in (*ORDER, *sorted(found - set(ORDER))) if p in found]

    @property
    def caught(self) -> bool:
        return bool(self.caught_by)

    @property
    def witness(self) -> str | None:
        """The first scenario (in file order) on which a property failed, and that property."""
        for r in self.runs:
            if r["verdict"] == "VIOLATED":
                return f"{r['scenario']} ({r['scheduler']}): {r['property']}"
        return None

    def to_json(self) -> dict[str, Any]:
        return {"mutant": self.mutant.name, "baseline": self.mutant.baseline,
                "description": self.mutant.description, "caught": self.caught,
                "caught_by": self.caught_by, "witness": self.witness,
                "expected": list(self.mutant.expected),
                "equivalent": self.mutant.equivalent, "runs": self.runs}


def load_mutant_scenarios(directory: Path = SCENARIO_DIR) -> list[Any]:
    """The fixed scenario set, in file-name order."""
    files = sorted(directory.glob("*.json"))
    if not files:
        raise InvalidInput(f"{directory}: no scenario files (run from a source checkout)")
    return [load_scenario(f) for f in files]


def _check(scenario: Any, algorithm: str, scheduler: str) -> dict[str, Any]:
    started = time.perf_counter()
    report = run_check(scenario.configuration, algorithm=algorithm, scheduler=scheduler,
                       detection=scenario.multiplicity, frames=scenario.frames,
                       max_states=MAX_STATES, max_seconds=MAX_SECONDS)
    violated = sorted(p for p, r in report["properties"].items() if r.get("holds") is False)
    return {"scenario": scenario.name, "scheduler": scheduler, "verdict": report["verdict"],
            "property": report["property"], "violated": violated,
            "reason": report["reason"], "states": report["states"],
            "seconds": round(time.perf_counter() - started, 2)}


def scenario_runs(scenario: Any) -> list[tuple[str, str]]:
    """(baseline, scheduler) pairs a scenario records as VERIFIED."""
    return [(e.algorithm, e.scheduler) for e in scenario.expectations
            if e.verdict == "VERIFIED" and e.algorithm in (PAPER_BASELINE, GTT_BASELINE)]


def run_mutants(mutants: Sequence[Mutant] = MUTANTS, scenarios: Sequence[Any] | None = None,
                progress: Callable[[str], Any] | None = None) -> dict[str, Any]:
    """Run every mutant against every scenario of its baseline; the JSON-able summary.

    The baselines are checked first: a scenario whose baseline is not VERIFIED is an
    error (the set would not measure anything), reported as InvalidInput."""
    register_mutants()
    scenarios = load_mutant_scenarios() if scenarios is None else list(scenarios)
    started = time.perf_counter()
    for s in scenarios:
        for baseline, scheduler in scenario_runs(s):
            got = _check(s, baseline, scheduler)
            if got["verdict"] != "VERIFIED":
                raise InvalidInput(f"scenario {s.name}: the baseline {baseline} / {scheduler} is "
                                 f"{got['verdict']} ({got['reason']}), not VERIFIED")
    results = []
    for m in mutants:
        result = MutantResult(m)
        for s in scenarios:
            for baseline, scheduler in scenario_runs(s):
                if baseline == m.baseline:
                    result.runs.append(_check(s, m.name, scheduler))
        if progress is not None:
            progress(f"{m.name}: {'caught by ' + ', '.join(result.caught_by) if result.caught else 'SURVIVED'}")
        results.append(result)
    caught = sum(r.caught for r in results)
    equivalent = [r for r in results if not r.caught and r.mutant.equivalent]
    score = caught / len(results) if results else 0.0
    return {
        "mutants": [r.to_json() for r in results],
        "scenarios": [s.name for s in scenarios],
        "caught": caught, "total": len(results), "score": round(score, 4), "goal": GOAL,
        "survivors": [r.mutant.name for r in results if not r.caught],
        "equivalent_survivors": [r.mutant.name for r in equivalent],
        "score_without_equivalent": round(caught / (len(results) - len(equivalent)), 4)
        if len(results) > len(equivalent) else 1.0,
        "seconds": round(time.perf_counter() - started, 1),
    }


# -- the command line ----------------------------------------------------------------------


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m tools.mutants``: the mutation score of the verifier (docs/reliability.md).

    Exit 0 when the score reaches the goal (95%), 1 when it does not, 2 on bad input
    (an unknown mutant name, a scenario whose baseline is not VERIFIED). ``cli ARGS...``
    runs ``gather-verify ARGS...`` with the mutants registered (check or replay one)."""
    argv = sys.argv[1:] if argv is None else list(argv)
    if argv[:1] == ["cli"]:
        from gather_verify.cli import main as gather_verify_main

        register_mutants()
        return gather_verify_main(argv[1:])
    parser = argparse.ArgumentParser(
        prog="python -m tools.mutants",
        description="run the explorer against deliberately broken algorithms and report the "
                    "mutation score")
    parser.add_argument("--mutant", action="append", dest="names", metavar="NAME",
                        help="only this mutant (repeatable; default: all)")
    parser.add_argument("--list", action="store_true", help="list the mutants and exit")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.add_argument("--timings", action="store_true", help="with --json, add the seconds")
    args = parser.parse_args(argv)
    try:
        chosen = [get_mutant(n) for n in args.names] if args.names else list(MUTANTS)
        if args.list:
            for m in chosen:
                print(f"{m.name:48} {m.baseline:18} {m.description}")
            return EXIT_OK
        progress = None if args.json else (lambda line: print(line, file=sys.stderr, flush=True))
        summary = run_mutants(chosen, progress=progress if sys.stderr.isatty() else None)
    except InvalidInput as error:
        print(f"error: {error}", file=sys.stderr)
        return EXIT_USAGE
    if args.json:
        print_json(summary if args.timings else without_timings(summary))
    else:
        _print_table(summary)
    return EXIT_OK if summary["score"] >= GOAL else EXIT_VIOLATED


def _print_table(summary: dict[str, Any]) -> None:
    rows = [(m["mutant"], ", ".join(m["caught_by"]) or
             ("SURVIVED (equivalent)" if m["equivalent"] else "SURVIVED"),
             m["witness"] or "-") for m in summary["mutants"]]
    widths = [max(len(r[i]) for r in rows) for i in range(2)]
    print(f"{'mutant':{widths[0]}}  {'caught by':{widths[1]}}  first witness")
    print("-" * (sum(widths) + 40))
    for name, got, witness in rows:
        print(f"{name:{widths[0]}}  {got:{widths[1]}}  {witness}")
    print()
    print(f"score {summary['caught']}/{summary['total']} = {100 * summary['score']:.1f}% "
          f"(goal {100 * GOAL:.0f}%) on {len(summary['scenarios'])} scenarios; "
          f"without the argued-equivalent survivors "
          f"{100 * summary['score_without_equivalent']:.1f}%")
    for m in summary["mutants"]:
        if not m["caught"]:
            why = m["equivalent"] or "not explained: add a scenario that catches it"
            print(f"survivor {m['mutant']}: {why}")


if __name__ == "__main__":
    sys.exit(main())
