"""``gather-verify test PATH...``: run scenario files against their ``expect`` blocks."""

from __future__ import annotations

import argparse

from gather_verify.cli.common import EXIT_OK, EXIT_VIOLATED, UsageError, writable_outputs

HELP = "run scenario files (and folders of them) against their expect blocks, as tests"


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("paths", nargs="+", metavar="PATH",
                   help="scenario file, or folder: every *.json under it")
    p.add_argument("--slow", action="store_true",
                   help='also run the expectations marked "options": {"slow": true}')
    p.add_argument("--junit", metavar="FILE", help="also write JUnit XML, one test case per case")
    p.add_argument("--quiet", action="store_true", help="print only the mismatches and the total")


def run(args: argparse.Namespace) -> int:
    from gather_verify.scenario_tests import run_cases, scenario_files

    writable_outputs(junit=args.junit)
    if not scenario_files(args.paths):  # a missing path fails before any work
        raise UsageError(f"no scenario files under {' '.join(args.paths)}")
    outcomes = []
    for outcome in run_cases(args.paths, slow=args.slow):
        outcomes.append(outcome)
        if not outcome.passed:
            print(f"FAIL {outcome.message}\n")
        elif not args.quiet:
            print(f"ok   {outcome.name}")
    failed = [o for o in outcomes if not o.passed]
    print(f"{len(outcomes) - len(failed)} passed, {len(failed)} failed"
          + "".join(f"\n  failed: {o.name}" for o in failed))
    if args.junit:
        from gather_verify.junit import write_junit

        write_junit(args.junit, "scenarios", (o.junit_case() for o in outcomes))
    return EXIT_VIOLATED if failed else EXIT_OK
