"""``synthesize --world ring:A-B --together``: one gap-rule algorithm for every start of every
ring size of the range, verified by the ordinary checker at each size (docs/howto/rings.md)."""

from __future__ import annotations

import argparse
import sys
import time
from typing import Any

from gather_verify.cli.common import (
    EXIT_BUG,
    EXIT_INCOMPLETE,
    EXIT_INTERRUPTED,
    EXIT_OK,
    UsageError,
    print_json,
    writable_outputs,
)
from gather_verify.words import counted


def _range_parts(args: argparse.Namespace) -> list[tuple[Any, Any]]:
    """The question of ``--world ring:A-B --together`` checked, and one part per ring size:
    its instance and its gap views, the views shared with the first size's (one algorithm
    written as gap rules for every size)."""
    from gather_verify.synthesis.gapviews import GapViews
    from gather_verify.synthesis.views import make_instance
    from gather_verify.worlds import world_specs

    if not args.together:
        raise UsageError(f"--world {args.world}: a range of rings asks one algorithm for "
                         "every size, add --together (or --minimum for the least number of "
                         "robots per size)")
    robots = (args.robots or "").strip()
    if not robots.isdigit():
        raise UsageError("--world ring:A-B --together: --robots is a count (every start of "
                         "that many robots at every size)")
    if not args.witness.endswith(".py"):
        raise UsageError(f"--witness {args.witness}: the algorithm file must end in .py")
    writable_outputs(witness=args.witness)
    worlds = world_specs(args.world)
    parts: list[tuple[Any, Any]] = []
    for j, world in enumerate(worlds):
        inst = make_instance(world, robots, args.meeting, args.scheduler, args.task,
                             args.multiplicity, args.frames, args.visibility, args.lights,
                             None, args.start)
        views = GapViews(inst, args.gap_cap)
        if parts:
            views.share(parts[0][1], j)
        parts.append((inst, views))
    return parts


def run_range(args: argparse.Namespace) -> int:
    from gather_verify.cli.synthesize_sets import seeds
    from gather_verify.synthesis.gapviews import rules_of, write_rules
    from gather_verify.synthesis.search import synthesize
    from gather_verify.synthesis.witness import check_witness

    parts = _range_parts(args)
    started = time.perf_counter()
    try:
        res = synthesize(parts[0][0], parts=parts, max_seconds=args.max_seconds,
                         max_candidates=args.max_candidates, max_states=args.max_states,
                         max_tree=args.max_tree, seeds=seeds(args), one_mover=args.one_mover)
    except KeyboardInterrupt:
        print("interrupted: synthesize keeps no partial results; run the same command again "
              "(it starts over)", file=sys.stderr)
        return EXIT_INTERRUPTED
    first = parts[0][0]
    report: dict[str, Any] = {
        "answer": res.answer, "world": args.world, "sizes": len(parts),
        "task": first.task.name, "scheduler": first.scheduler, "detection": first.detection,
        "frames": first.frames, "start": args.start or "all", "robots": int(args.robots),
        "gap_cap": args.gap_cap, "configurations": sum(len(i.configurations) for i, _ in parts),
        "views": res.views, "candidates": res.candidates,
        "counterexamples": len(res.counterexamples), "states": res.states,
        "limit": res.limit, "one_mover": res.one_mover, "one_robot": res.one_robot,
        "witness": None, "rules": None}
    problem = None
    if res.answer == "none":
        report["answer"] = "unknown"
        report["limit"] = (f"gap rules: no gap-rule algorithm reading gaps below "
                           f"{args.gap_cap} exactly solves every start of every size (no "
                           "certificate that no algorithm does: ask each size, or a larger "
                           "--gap-cap)")
    elif res.answer == "exists":
        rules = rules_of(parts[0][1], res.table)
        summary = (f"One algorithm for every ring of {args.world.partition(':')[2]} nodes: "
                   f"task {first.task.name}, scheduler {first.scheduler}, detection "
                   f"{first.detection}, frames {first.frames}, {int(args.robots)} robots from every "
                   f"{'' if (args.start or 'all') == 'all' else args.start + ' '}start. The "
                   "ordinary checker verified it at every size, every reduction off.")
        spec = write_rules(args.witness, rules, summary)
        report.update(witness=spec, rules=[str(r) for r in rules])
        verdicts: set[str] = set()
        states = 0
        for inst, _ in parts:
            left = args.max_seconds - (time.perf_counter() - started)
            got = check_witness(spec, inst, max(left, 1.0))
            verdicts |= {r["verdict"] for r in got}
            states += sum(r["states"] for r in got)
        report["checker"] = {"verdicts": sorted(verdicts), "reductions": "off",
                             "states": states}
        if verdicts != {"VERIFIED"}:
            problem = (f"the ordinary checker says {sorted(verdicts)} of the gap rules {spec}: "
                       "this is a bug of gather-verify's synthesis, please report it")
    report["seconds"] = time.perf_counter() - started
    if args.json:
        print_json(report if args.timings else {k: v for k, v in report.items()
                                                 if k != "seconds"})
    else:
        _print(report)
    if problem is not None:
        print(f"internal error: {problem}", file=sys.stderr)
        return EXIT_BUG
    return EXIT_OK if report["answer"] == "exists" else EXIT_INCOMPLETE


def _print(report: dict[str, Any]) -> None:
    print(f"{report['answer']}  {report['world']} ({counted(report['sizes'], 'size')}), one "
          "gap-rule "
          f"algorithm  task {report['task']} / {report['scheduler']}  detection "
          f"{report['detection']}  frames {report['frames']}  start {report['start']} "
          f"({report['robots']} robots)")
    print(f"configurations {report['configurations']}  views (gap keys, cap "
          f"{report['gap_cap']}) {report['views']}  candidates {report['candidates']}  "
          f"counterexamples {report['counterexamples']}  states {report['states']}  "
          f"{report['seconds']:.2f}s")
    if report["answer"] == "exists":
        print(f"witness: --algorithm {report['witness']} "
              f"({counted(len(report['rules']), 'rule')}); "
              f"checker at every size, every reduction off: "
              f"{', '.join(report['checker']['verdicts'])}, {report['checker']['states']} "
              "states")
        for rule in report["rules"]:
            print(f"  {rule}")
        print("  any other view  -> stay")
    else:
        print(f"the search stopped: {report['limit']}")
