"""``gather-verify mutants``: the mutation score of the verifier (docs/reliability.md).

Runs the explorer on the fixed scenario set ``scenarios/mutants/`` against every
deliberate bug of :mod:`gather_verify.mutants` and prints which property caught
each. Exit 0 when the score reaches the goal (95%), 1 when it does not, 2 on
bad input (an unknown mutant name, a scenario whose baseline is not VERIFIED)."""

from __future__ import annotations

import argparse
import sys

from gather_verify.cli.common import EXIT_OK, EXIT_VIOLATED, print_json, without_timings

HELP = "run the explorer against deliberately broken algorithms and report the mutation score"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--mutant", action="append", dest="names", metavar="NAME",
                        help="only this mutant (repeatable; default: all)")
    parser.add_argument("--list", action="store_true", help="list the mutants and exit")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.add_argument("--timings", action="store_true", help="with --json, add the seconds")


def run(args: argparse.Namespace) -> int:
    from gather_verify.mutants import GOAL, MUTANTS, get_mutant, run_mutants

    chosen = [get_mutant(n) for n in args.names] if args.names else list(MUTANTS)
    if args.list:
        for m in chosen:
            print(f"{m.name:48} {m.baseline:18} {m.description}")
        return EXIT_OK
    progress = None if args.json else (lambda line: print(line, file=sys.stderr, flush=True))
    summary = run_mutants(chosen, progress=progress if sys.stderr.isatty() else None)
    if args.json:
        print_json(summary if args.timings else without_timings(summary))
    else:
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
    return EXIT_OK if summary["score"] >= GOAL else EXIT_VIOLATED
