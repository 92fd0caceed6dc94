"""``gather-verify synthesize``: does any algorithm solve the task? (SEMANTICS.md §12)

Answers ``exists`` (exit 0) with an algorithm file the ordinary checker then verifies,
``none`` (exit 1) with a certificate that ``--verify`` checks again without searching, or
``unknown`` (exit 3) naming the limit that stopped the search. ``--verify CERT`` exits 0
when the certificate holds and 1 when it does not (one line saying where).
"""

from __future__ import annotations

import argparse
import json
import os
import re
import sys
import time
from pathlib import Path
from typing import Any

from gather_verify.cli.common import (
    ANSWER_EXIT,
    EXIT_BUG,
    EXIT_INCOMPLETE,
    EXIT_INTERRUPTED,
    EXIT_OK,
    EXIT_VIOLATED,
    UsageError,
    Words,
    add_json_arguments,
    bounded_float,
    bounded_int,
    print_json,
    writable_outputs,
)
from gather_verify.errors import InvalidInput
from gather_verify.words import counted
from schedulers import SCHEDULERS

HELP = ("does any algorithm solve the task, on a finite world or the paper's (grid)? exists "
        "(with an algorithm file, verified), none (with a certificate) or unknown (with the "
        "limit that stopped it)")
RULES_SHOWN = 12
"""Gap rules of a ring witness printed (the file and --json have them all)."""


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The question, the outputs and limits, and the many-answer forms, in that order."""
    _question_arguments(p)
    _output_and_limit_arguments(p)
    _many_answer_arguments(p)


def _question_arguments(p: argparse.ArgumentParser) -> None:
    """What is asked: the world, the robots and their starts, the task, the adversary, what
    the robots see and carry."""
    p.add_argument("--world", help="a finite world (ring:N, grid:WxH, torus:WxH, graph:FILE) "
                   "or the paper's world Z² with meeting nodes (grid)")
    p.add_argument("--robots", help='one initial configuration ("0 2"), or a count of robots '
                   "(2: every initial configuration of that many, up to the world's "
                   "symmetries)")
    p.add_argument("--start", default=None, metavar="SET",
                   choices=("all", "aperiodic", "asymmetric", "rigid", "periodic", "symmetric"),
                   help="with a count of robots: the initial configurations of that set "
                        "(all, aperiodic, asymmetric or rigid, periodic, symmetric: "
                        "docs/synthesis.md), each on its own; with --together, one algorithm "
                        "for all of them; with --minimum, the least count with one algorithm "
                        "for all of them")
    p.add_argument("--meeting", default="", help="meeting nodes, for the task that has them")
    p.add_argument("--task", default=None,
                   help="gathering, gathering-on-meeting-nodes (default with meeting nodes), "
                        "exclusive-perpetual-exploration or exploration-with-stop")
    p.add_argument("--scheduler", default="async", metavar="NAME",
                   help=f"the adversary: {', '.join(SCHEDULERS)} (default async)")
    p.add_argument("--multiplicity", default="local-weak", help="detection model "
                   "(none, local-weak, local-strong, global-weak, global-strong)")
    p.add_argument("--frames", default="all", choices=("all", "chirality", "compass"))
    p.add_argument("--visibility", type=bounded_int(-10**6, 10**6), default=None,
                   metavar="HOPS", help="robots see only the nodes within this many hops")
    p.add_argument("--lights", default=None, metavar="K[:internal]",
                   help="luminous robots with K colours, all starting at 0; with --minimum, "
                        "a range A-B asks the least number of colours")
    p.add_argument("--colours", default=None, metavar="C", nargs="+", action=Words,
                   help="with lights and one configuration: each robot's initial colour "
                        "(default 0); with --minimum --lights A-B, also 'some': from any "
                        "initial colouring")
    p.add_argument("--movement", choices=("rigid", "non-rigid"), help="rendezvous world")
    p.add_argument("--initial-colours", choices=("all", "same"), help="rendezvous world")


def _output_and_limit_arguments(p: argparse.ArgumentParser) -> None:
    """Where the answer goes, the re-check of a certificate, and the limits."""
    p.add_argument("--witness", default="synthesized.py", metavar="FILE.py",
                   help="where exists writes the algorithm (default synthesized.py)")
    p.add_argument("--certificate", default="synthesized.cert.json", metavar="FILE",
                   help="where none writes its certificate (default synthesized.cert.json)")
    p.add_argument("--verify", metavar="CERT",
                   help="re-check a certificate of none without searching, and exit")
    p.add_argument("--max-seconds", type=bounded_float(0.001, 10**7), default=600.0,
                   help="the whole command: the views, the search, the checker's run on a "
                        "witness, the re-check of a certificate (default %(default)g)")
    p.add_argument("--max-memory-mb", type=bounded_float(1, 10**7), default=None, metavar="MB",
                   help="on a finite world: resident memory limit of the whole command "
                        "(default: a share of this machine's memory, as check's)")
    p.add_argument("--max-candidates", type=bounded_int(1, 10**9), default=1_000_000,
                   help="tables the solver may propose (default %(default)s)")
    p.add_argument("--max-states", type=bounded_int(1, 10**9), default=2_000_000,
                   help="states of one exploration of one candidate (default %(default)s)")
    p.add_argument("--max-tree", type=bounded_int(1, 10**9), default=100_000,
                   help="nodes of the certificate's decision tree; past it, the certificate "
                        "is a resolution proof (default %(default)s)")
    p.add_argument("--one-mover", action=argparse.BooleanOptionalAction, default=None,
                   help="on a finite world: try first the tables in which one robot moves "
                        "per configuration, then those in which one class of robots (one "
                        "view) does, then every table; only the last answers none (default: "
                        "on; docs/synthesis.md)")


def _many_answer_arguments(p: argparse.ArgumentParser) -> None:
    """The least count (--minimum), the paper's box, one algorithm for many starts, seeds,
    explanations and the output's form."""
    p.add_argument("--minimum", action="store_true",
                   help="the least number of robots with an algorithm: --robots A-B (counts), "
                        "or of colours: --lights A-B; --world a size or a range of rings "
                        "(ring:4-8), --scheduler a comma list; one row per answer in the "
                        "results store (--db), resumed")
    p.add_argument("--db", default="gather-verify-results.sqlite",
                   help="with --minimum: the results database (as sweep's)")
    p.add_argument("--out", default=None, metavar="DIR",
                   help="with --minimum: where the witnesses and certificates go (default: "
                        "a folder synthesis/ beside the database)")
    p.add_argument("--box", default=None, metavar="WxH",
                   help="the paper's world (--world grid): every initial configuration inside "
                        "a W x H box of nodes, --robots and --meeting as counts or ranges A-B")
    p.add_argument("--select", default="all", choices=("u", "outside-u", "all"),
                   help="with --box: the configurations in U, outside U, or all (default)")
    p.add_argument("--classes", default=None, metavar="NAME,...",
                   help="with --box: only the configurations of these classes (I11 ... I42, "
                        "UNCLASSIFIED)")
    p.add_argument("--together", action="store_true",
                   help="one algorithm for every configuration at once: with --start, every "
                        "start of the set; with --world ring:A-B, every start of every size, "
                        "written as gap rules; with --box --select outside-u, every selected "
                        "configuration")
    p.add_argument("--seed", action="append", default=None, metavar="ALGORITHM",
                   help="an algorithm (name or FILE.py:NAME, a witness of an earlier run) "
                        "whose answers the search tries first (on the paper's world, before "
                        "the paper's and the nearest-meeting-node rule); may be repeated")
    p.add_argument("--gap-cap", type=bounded_int(2, 64), default=3, metavar="T",
                   help="with --world ring:A-B --together: gap rules read a gap below T "
                        "exactly, and compare the gaps of T or more with each other (default 3)")
    p.add_argument("--explain", action="store_true",
                   help="with --verify: the certificate in words (the starts it rests on, the "
                        "adversary's strategy along each branch)")
    p.add_argument("--rounds", type=bounded_int(0, 1000), default=12,
                   help="the paper's world: rounds of Theorem 1's adversary that a certificate "
                        "of none re-checks with the view code (default 12)")
    add_json_arguments(p, "print one JSON object", "the seconds")


def run(args: argparse.Namespace) -> int:
    if args.world == "rendezvous" or (args.verify and _rendezvous_certificate(args.verify)):
        _no_one_mover(args, "the rendezvous world")
        return _rendezvous(args)
    if args.movement or args.initial_colours:
        raise UsageError("--movement and --initial-colours are options of the rendezvous world")
    if args.verify:
        return _verify(args)
    if not args.world:
        raise UsageError("give --world (a finite world), or --verify CERT")
    if args.robots is None:
        raise UsageError("give --robots: nodes (\"0 2\") or a count (2)")
    if args.minimum:
        return _minimum(args)
    from gather_verify.worlds import PLANE, entry_of

    if entry_of(args.world) == PLANE:
        _no_memory_limit(args)
        _no_one_mover(args, "the infinite grid")
        return _plane(args)
    from gather_verify.cli import synthesize_sets as sets

    box_only = [o for o, given in (("--select", args.select != "all"),
                                   ("--classes", args.classes is not None)) if given]
    if box_only:
        raise UsageError(f"{box_only[0]} goes with --box on the paper's world (--world grid "
                         "--box WxH)")
    if args.box is not None:
        raise UsageError("--box goes with the paper's world (--world grid)")
    if args.together and args.start is None and not sets.is_range(args.world):
        raise UsageError("--together goes with --box on the paper's world (--world grid "
                         "--box WxH), with --start SET (one algorithm for every start of "
                         "the set), or with a range of rings (--world ring:A-B)")

    if sets.is_range(args.world):
        from gather_verify.cli.synthesize_rules import run_range

        return run_range(args)
    if sets.wants_sets(args):
        return sets.per_start(args)
    if not args.witness.endswith(".py"):
        raise UsageError(f"--witness {args.witness}: the algorithm file must end in .py")
    writable_outputs(witness=args.witness, certificate=args.certificate)
    try:
        report, problem = _finite(args)
    except KeyboardInterrupt:
        print("interrupted: synthesize keeps no partial results; run the same command again "
              "(it starts over)", file=sys.stderr)
        return EXIT_INTERRUPTED
    if args.json:
        print_json(report if args.timings else {k: v for k, v in report.items()
                                                 if k != "seconds"})
    else:
        _print(report, args)
    if problem is not None:
        print(f"internal error: {problem}", file=sys.stderr)
        return EXIT_BUG
    return ANSWER_EXIT[report["answer"]]


def _finite(args: argparse.Namespace) -> tuple[dict[str, Any], str | None]:
    """``synthesize --world W`` on a finite world: the report and, if any, the bug it found.
    ``--max-seconds`` and ``--max-memory-mb`` bound the whole command: building the instance
    and its views, the search, the checker's run on a witness, the re-check of a
    certificate; a limit met on the way answers ``unknown`` naming the step."""
    from gather_verify.cli import synthesize_sets
    from gather_verify.engine.bounds import SetupStopped, setup
    from gather_verify.synthesis.search import synthesize
    from gather_verify.synthesis.views import Views, make_instance

    started = time.perf_counter()
    memory = _memory(args)

    def left() -> float:
        return max(0.001, args.max_seconds - (time.perf_counter() - started))

    report: dict[str, Any] = {
        "answer": "unknown", "world": args.world, "scheduler": args.scheduler,
        "task": args.task or ("gathering-on-meeting-nodes" if args.meeting.strip() else
                              "gathering"),
        "detection": args.multiplicity, "frames": args.frames, "visibility": args.visibility,
        "lights": args.lights or "1", "configurations": 0, "views": 0, "candidates": 0,
        "counterexamples": 0, "states": 0, "limit": None, "witness": None, "certificate": None}
    try:
        with setup(f"building the views of {args.world}", args.max_seconds, memory):
            inst = make_instance(args.world, args.robots, args.meeting, args.scheduler,
                                 args.task, args.multiplicity, args.frames, args.visibility,
                                 args.lights, args.colours, args.start)
            views = Views(inst)
            seeds = synthesize_sets.seeds(args)
        report.update(world=inst.world.name, task=inst.task.name, lights=str(inst.lights),
                      configurations=len(inst.configurations))
        with setup("the search over algorithms", None, memory):  # its own clock, and memory
            result = synthesize(inst, max_seconds=left(), max_candidates=args.max_candidates,
                                max_states=args.max_states, max_tree=args.max_tree,
                                views=views, max_memory_mb=memory, seeds=seeds,
                                one_mover=args.one_mover)
        report.update(answer=result.answer, views=result.views, candidates=result.candidates,
                      counterexamples=len(result.counterexamples), states=result.states,
                      limit=result.limit, one_mover=result.one_mover,
                      one_robot=result.one_robot)
        problem = None
        if result.answer == "exists":
            problem = _witnessed(args, inst, views, result, report, left())
        elif result.answer == "none":
            problem = _certified(args, inst, views, result, report, left(), memory)
    except SetupStopped as stop:
        report.update(answer="unknown", limit=stop.reason)
        problem = None
    report["seconds"] = time.perf_counter() - started
    return report, problem


def _no_memory_limit(args: argparse.Namespace) -> None:
    """The paper's world's synthesis (and its certificates' re-check) reads no memory limit:
    ``--max-memory-mb`` is refused there, not ignored."""
    if args.max_memory_mb is not None:
        raise UsageError("--max-memory-mb bounds synthesis on a finite world; on the paper's "
                         "world (--world grid, its certificates) no memory limit is read: "
                         "drop it")


def _memory(args: argparse.Namespace) -> float:
    """``--max-memory-mb``, or this machine's share (as check's)."""
    from gather_verify.engine.resources import memory_budget_mb

    return args.max_memory_mb if args.max_memory_mb is not None else memory_budget_mb()


def _witnessed(args: argparse.Namespace, inst: Any, views: Any, result: Any,
               report: dict[str, Any], seconds: float) -> str | None:
    """Write the witness and run the ordinary checker on it (within ``seconds``): into
    ``report``; the bug it shows, if the checker finds the witness wrong."""
    from gather_verify.synthesis.gapviews import exact_rules
    from gather_verify.synthesis.witness import check_witness, write_witness

    spec = write_witness(args.witness, inst, views, result.table)
    rules = exact_rules(views, result.table)
    if rules is not None:
        report["rules"] = [str(r) for r in rules]
    reports = check_witness(spec, inst, seconds)
    verdicts = sorted({r["verdict"] for r in reports})
    report["witness"] = spec
    report["table"] = len(result.table)
    report["checker"] = {"verdicts": verdicts, "reductions": "off",
                         "states": sum(r["states"] for r in reports)}
    if verdicts == ["VERIFIED"]:
        return None
    bad = next(r for r in reports if r["verdict"] != "VERIFIED")
    if bad["verdict"] == "INCOMPLETE":  # a limit, not a wrong witness: no answer yet
        report.update(answer="unknown", limit=f"{bad['reason']} (while the checker verified "
                      f"the witness {spec})")
        return None
    return (f"the ordinary checker says {bad['verdict']} of the witness from robots "
            f"{bad['robots']} ({bad['property']}: {bad['reason']}): this is a bug of "
            "gather-verify's synthesis, please report it")


def _certified(args: argparse.Namespace, inst: Any, views: Any, result: Any,
               report: dict[str, Any], seconds: float, memory: float) -> str | None:
    """Write the certificate and re-check it (within ``seconds`` and ``memory``): into
    ``report``; the bug it shows, if the certificate just written does not hold."""
    from gather_verify.engine.bounds import SetupStopped
    from gather_verify.synthesis.certificate import (
        CertificateError,
        verify_certificate,
        write_certificate,
    )
    from gather_verify.synthesis.explain import explain_certificate
    from gather_verify.synthesis.search import certificate_stats

    stats = certificate_stats(result)
    write_certificate(args.certificate, inst, views, result.counterexamples,
                      result.literals, result.tree, stats)
    report["certificate"] = args.certificate
    report["tree"] = {"nodes": stats["tree_nodes"], "leaves": stats["tree_leaves"],
                      "views": stats["tree_views"]}
    if "proof_lemmas" in stats:
        report["proof"] = {"lemmas": stats["proof_lemmas"], "steps": stats["proof_steps"]}
    try:
        got = verify_certificate(args.certificate, seconds, memory)
        report.update({k: got[k] for k in ("holds_under", "found_under")})
        report["rests_on"] = [[inst.world.node_to_json(v) for v in inst.configurations[j][0]]
                              for j in got["rests_on"]]
        report["explanation"] = explain_certificate(args.certificate)
    except CertificateError as error:
        return (f"the certificate just written does not re-check ({error}): this is a "
                "bug of gather-verify's synthesis, please report it")
    except SetupStopped as stop:
        report.update(answer="unknown", limit=f"{stop.reason} (while the certificate "
                      f"{args.certificate} was re-checked; --verify it with more time)")
    return None


def _print(report: dict[str, Any], args: argparse.Namespace) -> None:
    what = (f"{report['world']}  task {report['task']} / {report['scheduler']}  "
            f"detection {report['detection']}  frames {report['frames']}"
            + ("" if report["visibility"] is None else f"  visibility {report['visibility']}")
            + ("" if report["lights"] == "1" else f"  lights {report['lights']}"))
    print(f"{report['answer']}  {what}")
    print(f"configurations {report['configurations']}  views met {report['views']}  candidates "
          f"{report['candidates']}  counterexamples {report['counterexamples']}  states "
          f"{report['states']}  {report['seconds']:.2f}s")
    if report["answer"] == "exists":
        checker = report["checker"]
        print(f"witness: --algorithm {report['witness']} ({counted(report['table'], 'view')} "
              f"in its table)")
        print(f"checker, every reduction off: {', '.join(checker['verdicts'])} from "
              f"{counted(report['configurations'], 'configuration')}, "
              f"{counted(checker['states'], 'state')}")
        rules = report.get("rules")
        if rules is not None:
            print(f"as gap rules ({counted(len(rules), 'rule')} for the views that move; any "
                  "other view stays):")
            for rule in rules[:RULES_SHOWN]:
                print(f"  {rule}")
            if len(rules) > RULES_SHOWN:
                print(f"  ... and {len(rules) - RULES_SHOWN} more (the witness file lists them)")
    elif report["answer"] == "none":
        tree = report["tree"]
        print(f"certificate: {report['certificate']} "
              f"({counted(report['counterexamples'], 'counterexample')} over "
              f"{counted(tree['views'], 'view')}, "
              f"{tree_text(tree['nodes'], tree['leaves'], report.get('proof', {}).get('lemmas'))}"
              "); "
              "re-check it with")
        print(f"  gather-verify synthesize --verify {report['certificate']}")
        if "holds_under" in report:
            from gather_verify.cli.synthesize_sets import holds_line

            print(holds_line(report, report["scheduler"]))
        for line in report.get("explanation", []):
            print(line)
    else:
        print(f"the search stopped at a limit: {report['limit']} (no answer; raise it and run "
              "again)")


def tree_text(questions: int, leaves: int, lemmas: int | None = None) -> str:
    """A certificate's refutation in words: its decision tree's size (a tree of one leaf
    asks nothing), or its resolution proof's lemmas."""
    if lemmas is not None:
        return f"a resolution proof of {counted(lemmas, 'lemma')}"
    if questions == 0:
        return "a decision tree of one leaf (no question)"
    return (f"a decision tree of {counted(questions, 'question')} and "
            f"{counted(leaves, 'leaf', 'leaves')}")


def _no_one_mover(args: argparse.Namespace, world: str) -> None:
    """``--one-mover`` steers the finite worlds' search only: refused elsewhere, not ignored."""
    if args.one_mover is not None:
        raise UsageError(f"--one-mover is an option of the finite worlds' search, not of {world}")


def _rendezvous_certificate(path: str) -> bool:
    """Whether the certificate file is one of the rendezvous world (its bytes read once,
    :mod:`gather_verify.inputs`; a file that is none is left to the finite world's check,
    which says why in one line)."""
    from gather_verify.inputs import read_text

    try:
        data = json.loads(read_text(path, "certificate"))
    except (InvalidInput, ValueError, RecursionError):
        return False
    return isinstance(data, dict) and data.get("world") == "rendezvous"


def _rendezvous(args: argparse.Namespace) -> int:
    """``synthesize --world rendezvous``: the least colours (``--minimum --lights A-B[:kind]``)
    or one number of colours; ``--verify`` of its certificates
    (:mod:`gather_verify.synthesis.rendezvous`)."""
    from gather_verify.synthesis import rendezvous as rv

    if args.verify:
        from gather_verify.inputs import read_text

        holds = rv.verify(json.loads(read_text(args.verify, "certificate")))
        if args.json:
            print_json({"certificate": args.verify, "holds": holds})
        else:
            print(f"certificate {'holds: none' if holds else 'REJECTED'}  rendezvous")
        return EXIT_OK if holds else EXIT_VIOLATED
    if args.robots is not None or args.meeting or args.task:
        raise UsageError("the rendezvous world takes no --robots, --meeting or --task")
    count, _, kind = (args.lights or "").partition(":")
    low, dash, high = count.partition("-")
    if not (low.isdigit() and (not dash or high.isdigit())) or (dash and not args.minimum):
        raise UsageError("--lights K[:full|external|internal] (A-B with --minimum) on the "
                         "rendezvous world")
    rows = []
    for k in range(int(low), int(high if dash else low) + 1):
        row = rv.synthesize(k, kind or "full", args.scheduler, args.movement or "non-rigid",
                            args.initial_colours or "all", max_seconds=args.max_seconds)
        rows.append(row)
        if row["answer"] == "none":
            Path(args.certificate).write_text(json.dumps(row["certificate"]) + "\n",
                                              encoding="utf-8")
        if row["answer"] != "none":
            break
    out = rows[-1] if not args.minimum else {"minimum": rows[-1]["colours"] if rows[-1][
        "answer"] == "exists" else None, "rows": [{k: v for k, v in r.items()
                                                  if k != "certificate"} for r in rows]}
    if args.json:
        print_json(out if args.minimum else {k: v for k, v in out.items() if k != "certificate"})
    else:
        for r in rows:
            print(f"{r['answer']:8} rendezvous  {r['colours']} {r['lights']} colour(s) / "
                  f"{r['scheduler']}  {r['movement']}, initial colours {r['initial_colours']}  "
                  f"({r['tables']} partial tables)")
    return EXIT_OK


def _verify(args: argparse.Namespace) -> int:
    """``--verify CERT``: re-check a certificate of none (a finite world's, or Theorem 1's on
    Z²) without searching; exit 0 when it holds, 1 with the line where it does not."""
    from gather_verify.engine.bounds import SetupStopped
    from gather_verify.synthesis import certificate, plane
    from gather_verify.synthesis.certificate import CertificateError

    started = time.perf_counter()
    on_plane = _plane_certificate(args.verify)
    if on_plane:
        _no_memory_limit(args)
    try:
        if on_plane:
            got = plane.verify_certificate(args.verify)
        else:
            got = certificate.verify_certificate(args.verify, args.max_seconds, _memory(args))
    except CertificateError as error:
        print(f"certificate REJECTED: {os.path.basename(args.verify)}: {error}",
              file=sys.stderr)
        return EXIT_VIOLATED
    except SetupStopped as stop:
        print(f"certificate NOT RE-CHECKED: {os.path.basename(args.verify)}: {stop.reason} "
              "(raise --max-seconds or --max-memory-mb)", file=sys.stderr)
        return EXIT_INCOMPLETE
    got["seconds"] = time.perf_counter() - started
    if args.explain and not on_plane:
        from gather_verify.synthesis.explain import explain_certificate

        got["explanation"] = list(explain_certificate(args.verify))
    if args.json:
        print_json(got if args.timings else {k: v for k, v in got.items() if k != "seconds"})
        return EXIT_OK
    inst = got["instance"]
    if on_plane:
        what = (f"grid (Z²)  task {inst['task']} / {inst['scheduler']}  "
                f"({counted(got['configurations'], 'configuration')}: Theorem 1's automorphism "
                f"and its adversary re-checked, {counted(got['states'], 'configuration')}, "
                f"{counted(got['views'], 'view')}; no search over algorithms)")
    else:
        what = (f"{inst['world']}  task {inst['task']} / {inst['scheduler']}  "
                f"({counted(got['counterexamples'], 'counterexample')} replayed over "
                f"{counted(got['views'], 'view')}, "
                f"{tree_text(got['tree_nodes'], got['leaves'], got.get('proof_lemmas'))}; "
                "no search)")
    print(f"certificate holds: none  {what}  {got['seconds']:.2f}s")
    if not on_plane:
        from gather_verify.cli.synthesize_sets import holds_line

        print(holds_line(got, inst["scheduler"]))
        for line in got.get("explanation", ()):
            print(line)
    return EXIT_OK


def _counts(text: str) -> range:
    low, dash, high = text.strip().partition("-")
    try:
        a = int(low, 10)
        b = int(high, 10) if dash else a
    except ValueError:
        raise UsageError(f"--robots {text!r}: with --minimum, a count or a range A-B") from None
    if not 1 <= a <= b <= 16:
        raise UsageError(f"--robots {text!r}: counts from 1 to 16, A <= B")
    return range(a, b + 1)


def _colour_range(text: str | None) -> tuple[range, str] | None:
    """``--lights A-B`` (or ``A-B:internal``) with ``--minimum``: the numbers of colours to
    ask, and the variant's suffix; None when ``--lights`` is not a range (the least number
    of robots is asked)."""
    if text is None:
        return None
    count, colon, variant = text.strip().partition(":")
    low, dash, high = count.partition("-")
    if not dash:
        return None
    try:
        a, b = int(low, 10), int(high, 10)
    except ValueError:
        raise UsageError(f"--lights {text!r}: with --minimum, a number of colours or a range "
                         "A-B (A-B:internal)") from None
    if a < 1:
        raise UsageError(f"--lights {text!r}: at least 1 colour (1 is no lights)")
    if a > b:
        raise UsageError(f"--lights {text!r}: the range of colours is empty (A <= B)")
    if b > 64:
        raise UsageError(f"--lights {text!r}: at most 64 colours")
    return range(a, b + 1), colon + variant


class _Least:
    """The question of ``--minimum``: the resource counted (robots or colours) and its
    values, the worlds and schedulers, the solver of one value and the settings that key the
    stored rows."""

    def __init__(self, args: argparse.Namespace) -> None:
        from gather_verify.worlds import PLANE, entry_of
        from schedulers import get_scheduler

        self.colours = _colour_range(args.lights)
        self.values = _counts(args.robots) if self.colours is None else self.colours[0]
        self.what = "robots" if self.colours is None else "colours"
        self.schedulers = [x.strip() for x in args.scheduler.split(",") if x.strip()]
        for name in self.schedulers:
            get_scheduler(name)
        self.robot_count: int | None = None
        self.solve: Any
        if args.start is not None and (self.colours is not None
                                       or entry_of(args.world) == PLANE):
            raise UsageError("--start with --minimum goes with a count of robots on a finite "
                             "world (--robots A-B: the least k with one algorithm for every "
                             "start of the set)")
        if entry_of(args.world) == PLANE:
            _no_one_mover(args, "the infinite grid")
            if self.colours is not None:
                raise UsageError("--minimum --lights A-B: the least number of colours is asked "
                                 "on the finite worlds only (synthesis on Z² has no lights)")
            self.worlds, self.solve, self.more = _plane_least(args, self.schedulers)
        elif self.colours is not None:
            self.worlds, self.solve, self.more = _colours_least(args, self.colours,
                                                                self.schedulers)
            self.robot_count = self.more.pop("n")
        else:
            self.worlds = _finite_least(args, self.values, self.schedulers)
            self.solve, self.more = _finite_one, {}

    def key(self, k: int) -> str:
        """The stored row's key of the value ``k``."""
        return f"k={k}" if self.colours is None else f"K={k}"


def _minimum(args: argparse.Namespace) -> int:
    """``--minimum``: per world and scheduler, synthesize for k = A, A+1, ... robots (every
    initial configuration of k), or with ``--lights A-B`` for K = A, A+1, ... colours (the
    robots of ``--robots``), up to the first ``exists``; each answer is a row of the results
    store keyed by the settings and gather-verify's own fingerprint, so a rerun resumes and
    an edited verifier computes again. On the paper's world (``--world grid``) the
    configurations of k robots are those of ``--box`` (:func:`_plane_least`)."""
    from gather_verify.sweeps.minimum import least_cell
    from gather_verify.sweeps.store import Store, check_db_path

    check_db_path(args.db)
    least = _Least(args)
    out = Path(args.out) if args.out else Path(args.db).resolve().parent / "synthesis"
    out.mkdir(parents=True, exist_ok=True)
    store = Store(args.db)
    table: dict[tuple[str, str], str] = {}
    rows_out: list[dict[str, Any]] = []
    try:
        for world in least.worlds:
            for sched in least.schedulers:
                answers = _least_answers(args, least, store, out, world, sched, rows_out)
                if isinstance(answers, str):
                    print(f"internal error: {answers}", file=sys.stderr)
                    return EXIT_BUG
                table[world, sched] = least_cell(answers)
    except KeyboardInterrupt:
        print("interrupted; run the same command again (every answer stored is kept, and it "
              "resumes)", file=sys.stderr)
        return EXIT_INTERRUPTED
    finally:
        store.close()
    _print_least(args, least, table, rows_out)
    return EXIT_INCOMPLETE if any("?" in cell for cell in table.values()) else EXIT_OK


def _least_answers(args: argparse.Namespace, least: _Least, store: Any, out: Path,
                   world: str, sched: str, rows_out: list[dict[str, Any]]
                   ) -> list[tuple[int, str]] | str:
    """The answers for k = A, A+1, ... on one world under one scheduler, up to the first
    ``exists`` (stored rows reused, new ones stored), each added to ``rows_out``; an
    internal problem's text instead."""
    from gather_verify.fingerprint import own_digest, world_inputs

    settings = {
        "command": "synthesize --minimum", "world": world, **world_inputs(world),
        "scheduler": sched,
        "task": args.task, "detection": args.multiplicity, "frames": args.frames,
        "visibility": args.visibility, "lights": args.lights,
        "meeting": args.meeting, "max_seconds": args.max_seconds,
        "max_candidates": args.max_candidates, "max_states": args.max_states,
        "gather_verify": own_digest(), **least.more,
        **({"start": args.start} if args.start is not None else {}),
    }
    sweep = store.sweep_id(settings)
    stored = {r["key"]: r for r in store.results(sweep)}
    answers: list[tuple[int, str]] = []
    for k in least.values:
        row = stored.get(least.key(k))
        if row is None:
            started = time.perf_counter()
            # the sweep's id: another question's files never take these names
            stem = out / (world.replace(':', '-').replace('/', '_').replace(' ', '-')
                          + f"-{sched}-" + (f"k{k}" if least.colours is None else f"K{k}")
                          + f"-s{sweep}")
            got = least.solve(args, world, sched, k, str(stem))
            if got is None:  # more robots than nodes
                break
            if isinstance(got, str):
                return got
            answer, limit, states, candidates, files = got
            # the world is the sweep's (its settings), not a class of the row
            row = {"key": least.key(k), "index": k, "class": None,
                   "verdict": answer, "reason": limit,
                   "n": k if least.colours is None else least.robot_count,
                   "states": states, "transitions": candidates,
                   "trace": files, "seconds": time.perf_counter() - started}
            store.add(sweep, [dict(row)])  # (the store encodes its copy)
        rows_out.append({"world": world, "scheduler": sched, least.what: k,
                         "answer": row["verdict"], "limit": row["reason"],
                         "files": row["trace"]})
        answers.append((k, row["verdict"]))
        if row["verdict"] == "exists":
            break
    return answers


def _print_least(args: argparse.Namespace, least: _Least, table: dict[tuple[str, str], str],
                 rows_out: list[dict[str, Any]]) -> None:
    """``--minimum``'s report: one JSON object, or the heading and the least-count table."""
    from gather_verify.sweeps.minimum import format_table

    what, colours, values = least.what, least.colours, least.values
    if args.json:
        print_json({"resource": what,
                    "minimum": [{"world": w, "scheduler": sc, "least": table[w, sc]}
                                for w in least.worlds for sc in least.schedulers],
                    "rows": rows_out})
        return
    print(f"least {what} with an algorithm  task {args.task or 'default'}  detection "
          f"{args.multiplicity}  frames {args.frames}"
          + ("" if args.start is None else f"  start {args.start}")
          + ("" if args.visibility is None else f"  visibility {args.visibility}")
          + ("" if args.lights is None or colours is not None else f"  lights {args.lights}")
          + ("" if colours is None else f"  robots {args.robots.strip()}  initial colours "
             f"{least.more['colours'] or '0'}" + (f"  lights K{colours[1]}" if colours[1] else ""))
          + ("" if args.box is None else f"  meeting {args.meeting}  select {args.select}"
             + (f"  classes {args.classes}" if args.classes else ""))
          + f"  ({what} {values[0]}-{values[-1]}; ?: some "
          + ("count" if colours is None else "number of colours") + " below is unknown)")
    for line in format_table(least.worlds, least.schedulers, table):
        print(line)


def _finite_least(args: argparse.Namespace, counts: range, schedulers: list[str]) -> list[str]:
    """The finite worlds of ``--minimum`` (a size, or a range of rings), each checked now so
    that bad input fails before any work."""
    from gather_verify.synthesis.views import make_instance
    from gather_verify.worlds import world_specs

    if args.colours is not None:
        raise UsageError("--colours with --minimum over robots: every initial configuration of "
                         "k robots starts at colour 0 (--colours goes with --lights A-B)")
    worlds = world_specs(args.world)
    for world in worlds:
        make_instance(world, str(min(counts[0], 3)), args.meeting, schedulers[0], args.task,
                      args.multiplicity, args.frames, args.visibility, args.lights)
    return worlds


def _start_set(world: str, k: int, args: argparse.Namespace) -> bool:
    """Whether ``--start`` (with ``--minimum``) leaves any start of ``k`` robots on ``world``
    (always, without it)."""
    from gather_verify.synthesis.starts import starts
    from gather_verify.worlds import get_world
    from gather_verify.worlds.base import World

    w = get_world(world)
    if args.start is None or not isinstance(w, World) or not 1 <= k <= w.size:
        return True  # make_instance says why, if anything is wrong
        return True
    meeting = frozenset(w.parse_nodes(args.meeting)) if args.meeting.strip() else frozenset()
    return bool(starts(w, k, args.start, meeting, args.frames))


Answer = tuple[str, str | None, int, int, dict[str, Any]]
"""One count's answer for ``--minimum``: answer, limit, states, candidates, files."""


def _finite_one(args: argparse.Namespace, world: str, sched: str, k: int,
                stem: str) -> Answer | str | None:
    """``synthesize`` for every initial configuration of ``k`` robots on a finite world (with
    ``--start``, every one of that set: ``empty`` when it has none), one algorithm for all of
    them (None: more robots than nodes; a string: a fault of ours, to report)."""
    from gather_verify.synthesis.views import make_instance

    try:
        if not _start_set(world, k, args):
            return "empty", f"no start of {counted(k, 'robot')} is {args.start}", 0, 0, {}
        inst = make_instance(world, str(k), args.meeting, sched, args.task, args.multiplicity,
                             args.frames, args.visibility, args.lights, start=args.start)
    except InvalidInput:  # more robots than nodes
        return None
    got = _finite_search(args, inst, stem)
    if isinstance(got, str):
        return got
    answer, limit, states, candidates, files = got
    if answer == "none":  # one certificate, as it has always been named
        files = {"certificate": files["certificates"][0]}
    return answer, limit, states, candidates, files


def _finite_search(args: argparse.Namespace, inst: Any, stem: str) -> Answer | str:
    """One search of ``--minimum`` on a finite world: exists with the witness ``stem.py``
    that the checker verifies, none with the certificate ``stem.cert.json`` that ``--verify``
    accepts (both re-checked here), or unknown; a string: a fault of ours, to report."""
    from gather_verify.synthesis.certificate import (
        CertificateError,
        verify_certificate,
        write_certificate,
    )
    from gather_verify.synthesis.search import certificate_stats, synthesize
    from gather_verify.synthesis.views import Views
    from gather_verify.synthesis.witness import check_witness, write_witness

    views = Views(inst)
    res = synthesize(inst, max_seconds=args.max_seconds, max_candidates=args.max_candidates,
                     max_states=args.max_states, max_tree=args.max_tree, views=views,
                     max_memory_mb=_memory(args), one_mover=args.one_mover)
    files: dict[str, Any] = {}
    if res.answer == "exists":
        spec = write_witness(f"{stem}.py", inst, views, res.table)
        verdicts = {r["verdict"] for r in check_witness(spec, inst, args.max_seconds)}
        if verdicts != {"VERIFIED"}:
            return (f"the checker says {sorted(verdicts)} of the witness {spec}: this is a bug "
                    "of gather-verify's synthesis, please report it")
        files["witness"] = spec
    elif res.answer == "none":
        path = f"{stem}.cert.json"
        write_certificate(path, inst, views, res.counterexamples, res.literals, res.tree,
                          certificate_stats(res))
        try:
            verify_certificate(path)
        except CertificateError as error:
            return (f"the certificate {path} just written does not re-check ({error}): this "
                    "is a bug of gather-verify's synthesis, please report it")
        files["certificates"] = [path]
    return res.answer, res.limit, res.states, res.candidates, files


def _colours_least(args: argparse.Namespace, colours: tuple[range, str],
                   schedulers: list[str]) -> tuple[list[str], Any, dict[str, Any]]:
    """``--minimum --lights A-B`` on the finite worlds: the robots of ``--robots`` (one
    configuration, or a count: every class of that many), their initial colours from
    ``--colours`` (one colouring, all 0 by default, or ``some``: any colouring). Every
    world and number of colours is checked now, so that bad input fails before any work.
    Returns the worlds, the solver of one number of colours and the settings that key the
    stored rows."""
    from gather_verify.synthesis.views import make_instance
    from gather_verify.worlds import world_specs

    values, variant = colours
    robots = args.robots.strip()
    if re.fullmatch(r"\d+-\d+", robots):
        raise UsageError(f"--robots {robots!r} with --lights {args.lights}: --minimum asks the "
                         "least of one resource, robots (--robots A-B) or colours (--lights "
                         "A-B), not both")
    some = args.colours is not None and args.colours.strip() == "some"
    if some and (robots.isdigit() and " " not in robots):
        raise UsageError("--colours some goes with one configuration (--robots \"0 1\"), not "
                         "a count")
    if args.colours is not None and not some:
        try:
            most = max((int(c, 10) for c in args.colours.split()), default=-1)
        except ValueError:
            most = -1  # make_instance says what is wrong
        if most >= values[0]:
            raise UsageError(f"--colours {args.colours.strip()!r} needs more colours than "
                             f"{values[0]}: start --lights at {most + 1} or more, or ask "
                             "--colours some")
    worlds = world_specs(args.world)
    for world in worlds:
        for k in values:
            inst = make_instance(world, robots, args.meeting, schedulers[0], args.task,
                                 args.multiplicity, args.frames, args.visibility,
                                 f"{k}{variant}", None if some else args.colours)
    more = {"minimum": "colours", "robots": robots, "lights": f"K{variant}",
            "colours": args.colours.strip() if args.colours is not None else None,
            "n": len(inst.configurations[0][0])}
    return worlds, _colours_one, more


def _colours_one(args: argparse.Namespace, world: str, sched: str, k: int,
                 stem: str) -> Answer | str:
    """Is there an algorithm with ``k`` colours for the robots of ``--robots``? With one
    colouring (``--colours``, or all 0), the search's answer. With ``--colours some``, each
    initial colouring in turn (all of them, none left out by a symmetry): exists as soon as
    one has an algorithm (the witness is for that colouring), none when every one is none
    (a certificate each), else unknown. A string: a fault of ours, to report."""
    from itertools import product

    from gather_verify.synthesis.views import make_instance

    robots = args.robots.strip()
    variant = args.lights.partition(":")[1] + args.lights.partition(":")[2]
    lights = f"{k}{variant}"
    some = args.colours is not None and args.colours.strip() == "some"
    if some:
        n = len(robots.split())
        colourings: list[str | None] = [" ".join(map(str, c))
                                        for c in product(range(k), repeat=n)]
    else:
        colourings = [args.colours]
    certificates: list[str] = []
    unknown: str | None = None
    states = candidates = 0
    for colouring in colourings:
        inst = make_instance(world, robots, args.meeting, sched, args.task, args.multiplicity,
                             args.frames, args.visibility, lights, colouring)
        here = stem + ("" if not some or colouring is None else
                       "-c" + "-".join(colouring.split()))
        got = _finite_search(args, inst, here)
        if isinstance(got, str):
            return got
        answer, limit, s, c, files = got
        states, candidates = states + s, candidates + c
        if answer == "exists":
            if some:  # and the colourings before it, each none
                files.update(initial_colours=colouring, certificates=certificates)
            return "exists", None, states, candidates, files
        if answer == "none":
            certificates += files["certificates"]
        elif unknown is None:
            unknown = limit if not some else f"{limit} (initial colours {colouring})"
    if unknown is not None:
        return "unknown", unknown, states, candidates, {"certificates": certificates}
    return "none", None, states, candidates, {"certificates": certificates}


def _plane_least(args: argparse.Namespace, schedulers: list[str]
                 ) -> tuple[list[str], Any, dict[str, Any]]:
    """``--minimum`` on the paper's world: the initial configurations of k robots are those
    of ``--box`` (with ``--meeting``, ``--select`` and ``--classes``); without a box they
    are infinitely many, and synthesis on Z² has no lights. Returns the row's name, the
    solver of one count and the settings that key the stored rows."""
    from gather_verify.synthesis import plane

    _no_memory_limit(args)
    if args.box is None:
        raise UsageError("--minimum on the paper's world needs --box WxH: the initial "
                         "configurations of k robots on Z² are infinitely many")
    if args.lights is not None or args.visibility is not None or args.colours is not None:
        raise UsageError("--minimum on the paper's world counts robots: synthesis there has no "
                         "lights and no limited visibility (drop --lights, --colours, "
                         "--visibility)")
    width, height = plane.parse_box(args.box)
    for sched in schedulers:  # bad input fails before any work
        plane.make_instance("1", args.meeting, sched, args.task, args.multiplicity,
                            args.frames, args.box, args.select, args.classes)
    more = {"box": f"{width}x{height}", "select": args.select, "classes": args.classes,
            "rounds": args.rounds, "seeds": args.seed}
    return [f"grid {width}x{height}"], _plane_one, more


def _plane_one(args: argparse.Namespace, world: str, sched: str, k: int,
               stem: str) -> Answer | str | None:
    """Does one algorithm gather from every selected configuration of ``k`` robots of the
    box? none, with Theorem 1's certificate of one of them (no algorithm gathers from it);
    else the search for one table (as ``--together``), exists with the witness the checker
    verifies from each; else unknown. None: more robots than nodes; a string: a fault of
    ours, to report."""
    from gather_verify.synthesis import plane

    started = time.perf_counter()
    try:
        inst = plane.make_instance(str(k), args.meeting, sched, args.task, args.multiplicity,
                                   args.frames, args.box, args.select, args.classes)
    except InvalidInput:  # more robots than nodes
        return None
    if not inst.configurations:
        return "empty", "no configuration of the box is selected", 0, 0, {}
    views = plane.PlaneViews(inst.detection, inst.frames)
    for c in inst.configurations:
        phi = plane.theorem1_phi(c, inst.frames)
        if phi is not None:
            path = f"{stem}.cert.json"
            entry = plane.theorem1_entry(c, phi, views, args.rounds)
            plane.write_certificate(path, plane.PlaneInstance([], sched, inst.detection,
                                                              inst.frames), [entry])
            try:
                plane.verify_certificate(path)
            except plane.CertificateError as error:
                return (f"the certificate {path} just written does not re-check ({error}): "
                        "this is a bug of gather-verify's synthesis, please report it")
            return ("none", None, entry["states"], 0,
                    {"certificate": path, "configurations": len(inst.configurations)})
    found = plane.search_algorithm(inst.configurations, inst, views,
                                   max_seconds=args.max_seconds,
                                   max_candidates=args.max_candidates,
                                   max_states=args.max_states, seeds=_seeds(args))
    files: dict[str, Any] = {"configurations": len(inst.configurations)}
    if found.answer != "exists":
        return found.answer, found.limit, 0, found.candidates, files
    spec = plane.write_witness(f"{stem}.py", inst, inst.configurations[0], views, found.table)
    for c in inst.configurations:  # within the count's budget, as the search
        checked = plane.check_witness(spec, inst, c,
                                      args.max_seconds - (time.perf_counter() - started))
        if plane.out_of_time(checked):
            return ("unknown", "max-seconds (during the checker's run on the witness)", 0,
                    found.candidates, files)
        if checked["verdict"] != "VERIFIED":
            return (f"the checker says {checked['verdict']} of the witness {spec} from robots "
                    f"{[list(v) for v in c.robots]}: this is a bug of gather-verify's "
                    "synthesis, please report it")
    files["witness"] = spec
    return "exists", None, 0, found.candidates, files


# -- the paper's world ---------------------------------------------------------------------

def _plane_certificate(path: str) -> bool:
    """Whether ``path`` holds a certificate of the paper's world (a quick look at its
    format; anything else goes to the finite worlds' verifier, which says what is wrong)."""
    import json

    from gather_verify.inputs import read_text
    from gather_verify.synthesis.plane import FORMAT

    text = read_text(path, "certificate")  # bounded, a regular file, read once
    try:
        return json.loads(text).get("format") == FORMAT
    except (ValueError, AttributeError, RecursionError):
        return False


def _plane(args: argparse.Namespace) -> int:
    """``synthesize --world grid``: per initial configuration, none with Theorem 1's
    certificate, exists with a verified witness, or unknown."""
    from gather_verify.synthesis import plane

    if args.lights is not None or args.visibility is not None or args.colours is not None:
        raise UsageError("the paper's world has no lights and no limited visibility: drop "
                         "--lights, --colours and --visibility")
    if not args.witness.endswith(".py"):
        raise UsageError(f"--witness {args.witness}: the algorithm file must end in .py")
    if args.together and args.box is None:
        raise UsageError("--together asks one algorithm for every configuration of a box: "
                         "give --box WxH (with --select outside-u)")
    writable_outputs(witness=args.witness, certificate=args.certificate)
    inst = plane.make_instance(args.robots, args.meeting, args.scheduler, args.task,
                               args.multiplicity, args.frames, args.box, args.select,
                               args.classes)
    if not inst.configurations:
        raise UsageError("no configuration of the box is selected: widen --robots, --meeting "
                         "or --select")
    if args.together:
        return _plane_together(args, inst)
    seeds = _seeds(args)
    started = time.perf_counter()
    views = plane.PlaneViews(inst.detection, inst.frames)
    rows: list[dict[str, Any]] = []
    entries: list[dict[str, Any]] = []
    problem = None
    try:
        for i, c in enumerate(inst.configurations):
            t0 = time.perf_counter()
            row: dict[str, Any] = {"robots": [list(v) for v in c.robots],
                                   "meeting_nodes": [list(v) for v in sorted(c.meeting_nodes)]}
            phi = plane.theorem1_phi(c, inst.frames)
            if phi is not None:
                entry = plane.theorem1_entry(c, phi, views, args.rounds)
                entries.append(entry)
                row.update(answer="none", **{k: entry[k] for k in ("class", "in_U", "states",
                                                                   "rounds")},
                           phi=entry["phi"]["describe"])
            else:
                fields, bug = _plane_search(args, inst, c, i, seeds, t0)
                row.update(fields)
                problem = problem or bug
            row["seconds"] = time.perf_counter() - t0
            rows.append(row)
    except KeyboardInterrupt:
        print("interrupted: synthesize keeps no partial results; run the same command again "
              "(it starts over)", file=sys.stderr)
        return EXIT_INTERRUPTED
    from gather_verify.cli.synthesize_sets import finish, overall

    answer = overall(rows)
    report: dict[str, Any] = {"answer": answer, **inst.describe(),
                              "configurations": len(rows),
                              # the views of the certificates, and of each search
                              "views": len(views.texts) + sum(r.get("views", 0) for r in rows),
                              "answers": {a: sum(r["answer"] == a for r in rows)
                                          for a in ("exists", "none", "unknown")},
                              "certificate": None}
    if entries:
        whole = inst.box is not None and inst.box["select"] == "u" and answer == "none"
        plane.write_certificate(args.certificate, inst if whole or inst.box is None else
                                plane.PlaneInstance([], inst.scheduler, inst.detection,
                                                    inst.frames), entries)
        report["certificate"] = args.certificate
        try:
            plane.verify_certificate(args.certificate)
        except plane.CertificateError as error:
            problem = problem or (f"the certificate just written does not re-check ({error}): "
                                  "this is a bug of gather-verify's synthesis, please report it")
    report["seconds"] = time.perf_counter() - started
    report["rows"] = rows
    return finish(args, report, rows, _print_plane, problem)


def _plane_search(args: argparse.Namespace, inst: Any, c: Any, i: int, seeds: list[Any],
                  t0: float) -> tuple[dict[str, Any], str | None]:
    """One configuration of the paper's world that Theorem 1 does not settle: the search,
    then the ordinary checker's run on a witness within what is left of the configuration's
    budget. The row's fields, and the bug of the synthesis if the checker refutes its
    witness."""
    from gather_verify.paper.classes import classify_configuration
    from gather_verify.synthesis import plane

    # a fresh table per configuration: the views of the others do not matter
    own = plane.PlaneViews(inst.detection, inst.frames)
    found = plane.search_algorithm([c], inst, own, max_seconds=args.max_seconds,
                                   max_candidates=args.max_candidates,
                                   max_states=args.max_states, seeds=seeds)
    cl = classify_configuration(c)
    row: dict[str, Any] = dict(answer=found.answer, limit=found.limit,
                               candidates=found.candidates, views=found.views,
                               **{"class": cl.name, "in_U": cl.in_U})
    if found.answer != "exists":
        return row, None
    path = args.witness if len(inst.configurations) == 1 else f"{args.witness[:-3]}-{i}.py"
    spec = plane.write_witness(path, inst, c, own, found.table)
    # the witness's check is part of the configuration's budget
    checked = plane.check_witness(spec, inst, c, args.max_seconds - (time.perf_counter() - t0))
    row.update(witness=spec, table=len(found.table),
               checker={"verdict": checked["verdict"], "states": checked["states"],
                        "reductions": "off"})
    if plane.out_of_time(checked):
        row.update(answer="unknown", limit="max-seconds (during the checker's run on the "
                   "witness)")
    elif checked["verdict"] != "VERIFIED":
        return row, (f"the ordinary checker says {checked['verdict']} of the witness {spec} "
                     f"({checked.get('reason')}): this is a bug of gather-verify's synthesis, "
                     "please report it")
    return row, None


def _seeds(args: argparse.Namespace) -> list[Any]:
    """The search's seeds: those of ``--seed`` (loaded now, so a bad one is one line), then
    the defaults."""
    from gather_verify.algorithms import get_algorithm
    from gather_verify.synthesis import plane

    return [*(get_algorithm(spec) for spec in args.seed or ()), *plane.default_seeds()]


def _print_plane(report: dict[str, Any]) -> None:
    box = report["box"]
    where = "" if box is None else (f"  box {box['width']}x{box['height']}  robots "
                                    f"{box['robots'][0]}-{box['robots'][1]}  meeting "
                                    f"{box['meeting'][0]}-{box['meeting'][1]}  select "
                                    f"{box['select']}")
    counts = report["answers"]
    print(f"{report['answer']}  grid (Z²)  task {report['task']} / {report['scheduler']}  "
          f"detection {report['detection']}  frames {report['frames']}{where}")
    print(f"configurations {report['configurations']} (none {counts['none']}, exists "
          f"{counts['exists']}, unknown {counts['unknown']})  views {report['views']}  "
          f"{report['seconds']:.2f}s")
    for r in report["rows"]:
        nodes = " ".join(f"{x},{y}" for x, y in r["robots"])
        meeting = " ".join(f"{x},{y}" for x, y in r["meeting_nodes"])
        line = f"  {r['answer']:<8} {r['class']:<12} robots {nodes}  meeting {meeting}  "
        if r["answer"] == "none":
            line += f"Theorem 1: {r['phi']}, adversary re-checked {r['rounds']} rounds"
        elif r["answer"] == "exists":
            line += (f"--algorithm {r['witness']}: checker {r['checker']['verdict']} "
                     f"({r['candidates']} candidates)")
        else:
            line += f"limit: {r['limit']}"
        print(line)
    if report["certificate"]:
        print(f"certificate: {report['certificate']} (Theorem 1 for every algorithm, per "
              "configuration answered none); re-check it with")
        print(f"  gather-verify synthesize --verify {report['certificate']}")


def _plane_together(args: argparse.Namespace, inst: Any) -> int:
    """``--together``: one table that gathers from every selected configuration (a repaired
    algorithm for all of them), verified by the ordinary checker from each; else unknown."""
    from gather_verify.synthesis import plane

    if inst.box is None or inst.box["select"] != "outside-u" or inst.frames != "all":
        raise UsageError("--together goes with --box and --select outside-u (disoriented "
                         "robots: in U no algorithm gathers)")
    started = time.perf_counter()
    views = plane.PlaneViews(inst.detection, inst.frames)
    found = plane.search_algorithm(inst.configurations, inst, views,
                                   max_seconds=args.max_seconds,
                                   max_candidates=args.max_candidates,
                                   max_states=args.max_states, seeds=_seeds(args))
    report: dict[str, Any] = {"answer": found.answer, **inst.describe(), "together": True,
                              "configurations": len(inst.configurations),
                              "views": found.views, "candidates": found.candidates,
                              "limit": found.limit, "witness": None}
    problem = None
    if found.answer == "exists":
        spec = plane.write_witness(args.witness, inst, inst.configurations[0], views,
                                   found.table)
        checks = [plane.check_witness(spec, inst, c,
                                      args.max_seconds - (time.perf_counter() - started))
                  for c in inst.configurations]  # within the one budget
        verdicts = [r["verdict"] for r in checks]
        report.update(witness=spec, table=len(found.table),
                      checker={"verdicts": sorted(set(verdicts)), "reductions": "off"})
        if any(plane.out_of_time(r) for r in checks):
            report.update(answer="unknown", limit="max-seconds (during the checker's run on "
                          "the witness)")
        elif set(verdicts) != {"VERIFIED"}:
            problem = (f"the ordinary checker says {sorted(set(verdicts))} of the witness "
                       f"{spec}: this is a bug of gather-verify's synthesis, please report it")
    report["seconds"] = time.perf_counter() - started
    if args.json:
        print_json(report if args.timings else {k: v for k, v in report.items()
                                                 if k != "seconds"})
    else:
        box = report["box"]
        print(f"{report['answer']}  grid (Z²)  one algorithm for "
              f"{counted(len(inst.configurations), 'configuration')} of the "
              f"{box['width']}x{box['height']} box outside U  "
              f"task {report['task']} / {report['scheduler']}")
        print(f"views {found.views}  candidates {found.candidates}  "
              f"{report['seconds']:.2f}s")
        if report["answer"] == "exists":
            print(f"witness: --algorithm {report['witness']} "
                  f"({counted(report['table'], 'view')}); "
                  f"checker, every reduction off, from each configuration: "
                  f"{', '.join(report['checker']['verdicts'])}")
        else:
            print(f"the search stopped: {report['limit']}")
    if problem is not None:
        print(f"internal error: {problem}", file=sys.stderr)
        return EXIT_BUG
    return EXIT_OK if report["answer"] == "exists" else EXIT_INCOMPLETE
