"""``gather-verify impossibility``: play Theorem 1's adversary on a configuration in U.

Exit codes: 0 the theorem held on every run, 1 some run gathered or lost the
symmetry (the run is printed), 4 the configuration is not in U (its class is
printed), 2 bad input.
"""

from __future__ import annotations

import argparse
import json
import sys

from gather_verify.cli.common import (
    EXIT_NOT_APPLICABLE,
    EXIT_OK,
    EXIT_VIOLATED,
    UsageError,
    add_configuration_arguments,
    bounded_int,
    load_configuration,
    print_json,
)

HELP = "check Theorem 1 (impossibility on U = I41 ∪ I42) against the paper's and random algorithms"


def add_arguments(p: argparse.ArgumentParser) -> None:
    add_configuration_arguments(p)
    p.add_argument("--algorithms", type=bounded_int(0, 10_000), default=20, metavar="K",
                   help="number of random equivariant algorithms (default 20)")
    p.add_argument("--steps", type=bounded_int(1, 100_000), default=20, metavar="T",
                   help="rounds to play (default 20)")
    p.add_argument("--seed", type=bounded_int(0, 2**31 - 1), default=0, metavar="S",
                   help="seed of the first random algorithm and of the adversary's RNG")
    p.add_argument("--explore", choices=("all", "random"), default="all",
                   help="all: every equivariant choice breadth-first (default); "
                        "random: one seeded run per algorithm")
    p.add_argument("--max-states", type=bounded_int(1, 10_000_000), default=2000, metavar="N",
                   help="configurations explored per algorithm with --explore all (default 2000)")
    p.add_argument("--no-paper", action="store_true", help="leave out the paper's algorithm")
    p.add_argument("--algorithm", action="append", dest="user_algorithms", metavar="SPEC",
                   default=[], help="also play against this algorithm (a name, FILE.py:NAME or "
                                    "package.module:NAME; repeatable)")
    p.add_argument("--split-orbit", action="store_true",
                   help="deliberately break the adversary (one orbit chooses independently)")
    p.add_argument("--beyond-u", action="store_true",
                   help="deprecated, no effect: U follows the end of §3.2, so no configuration "
                        "outside U meets Theorem 1's hypothesis (a warning says so)")
    p.add_argument("--json", action="store_true", help="print the result as JSON")


def algorithms_for(k: int, seed: int, paper: bool = True) -> tuple[list, str]:
    """The paper's algorithm (when registered) and ``k`` random equivariant ones,
    with a note on the paper's algorithm."""
    from gather_verify.algorithms import get_algorithm
    from gather_verify.algorithms.random_equivariant import RandomEquivariant

    out: list = []
    note = "paper algorithm left out"
    if paper:
        try:
            out.append(get_algorithm("paper"))
            note = "paper algorithm included"
        except ValueError:
            note = "paper algorithm not registered: left out"
    out.extend(RandomEquivariant(seed + i) for i in range(k))
    return out, note


def run(args: argparse.Namespace) -> int:
    from gather_verify.paper.impossibility import check_impossibility

    configuration, scenario = load_configuration(args)
    from gather_verify.algorithms import get_algorithm

    algorithms, note = algorithms_for(args.algorithms, args.seed, not args.no_paper)
    algorithms += [get_algorithm(spec) for spec in args.user_algorithms]
    if not algorithms:
        raise UsageError("no algorithm to play against: give --algorithms K >= 1")
    if args.beyond_u:  # (after the input is taken: a mistake is still one line)
        print("warning: --beyond-u is deprecated and changes nothing (U follows §3.2, so no "
              "configuration outside U meets Theorem 1's hypothesis); drop it", file=sys.stderr)
    detection = scenario.multiplicity if scenario else "local-weak"
    result = check_impossibility(
        configuration, algorithms, steps=args.steps, explore=args.explore,
        max_states=args.max_states, seed=args.seed, detection=detection,
        split_orbit=args.split_orbit, beyond_u=args.beyond_u,
    )
    if args.json:
        out = result.to_json()
        out["paper"] = note
        print_json(out)
    else:
        _print(result, note)
    if not result.partitive:
        return EXIT_NOT_APPLICABLE
    return EXIT_OK if result.holds else EXIT_VIOLATED


def _print(result, note: str) -> None:  # noqa: ANN001
    print(f"class: {result.class_name}")
    if not result.partitive:
        print("partitive: no (not in U as §3.2 describes it): Theorem 1 does not apply")
        return
    phi = result.automorphism
    print(f"partitive automorphism: {phi.describe()}, k = {phi.order}; V' = {result.v_prime()}")
    print(f"{note}; {len(result.runs)} algorithms, up to {result.steps} rounds")
    for r in result.runs:
        status = "holds" if r.holds else f"BROKEN: {r.defect}"
        extra = f", {r.unhandled} unhandled views (robots stayed)" if r.unhandled else ""
        print(f"  {r.algorithm}: {r.explore}, {r.rounds} rounds, {r.states} configurations, "
              f"{'closed' if r.repeated else 'open'}{'' if r.complete else ' (cut)'}{extra}: "
              f"{status}")
    if result.holds:
        print("Theorem 1 holds on every run")
        return
    first = result.failures[0]
    print(f"Theorem 1 broken against {first.algorithm}; the run:")
    print(json.dumps(first.trace, indent=1))
