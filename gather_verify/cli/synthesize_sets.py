"""``synthesize`` on start sets and ranges of rings: per-start answers (``--start S``), the
words a none rests on, and one gap-rule algorithm for a range of ring sizes (``--world
ring:A-B --together``). The single search itself is :mod:`gather_verify.cli.synthesize`'s.
"""

from __future__ import annotations

import argparse
import sys
import time
from typing import Any

from gather_verify.cli.common import (
    ANSWER_EXIT,
    EXIT_BUG,
    EXIT_INTERRUPTED,
    UsageError,
    print_json,
    writable_outputs,
)

WORDS = ("all", "aperiodic", "asymmetric", "rigid", "periodic", "symmetric")


def seeds(args: argparse.Namespace) -> list[Any]:
    """The algorithms of ``--seed`` (loaded now, so that a bad one is one line)."""
    from gather_verify.algorithms import get_algorithm

    return [get_algorithm(spec) for spec in args.seed or ()]


def is_range(world: str | None) -> bool:
    """A range of ring sizes, ``ring:A-B``."""
    from gather_verify.worlds import world_specs

    return world is not None and len(world_specs(world)) > 1


def wants_sets(args: argparse.Namespace) -> bool:
    """Whether this command answers per start (``--start`` without ``--together``) rather
    than with one search."""
    return args.start is not None and not args.together


def none_report(path: str) -> tuple[dict[str, Any], list[str]]:
    """What the re-check of a certificate of none says (where it holds, the starts it rests
    on) and the certificate in words."""
    from gather_verify.synthesis.certificate import verify_certificate
    from gather_verify.synthesis.explain import explain_certificate

    got = verify_certificate(path)
    return ({k: got[k] for k in ("holds_under", "found_under", "rests_on")},
            explain_certificate(path))


def holds_line(got: dict[str, Any], scheduler: str) -> str:
    """Where a none holds, in words (``got``: what the certificate's re-check says)."""
    holds = got.get("holds_under", [scheduler])
    found = got.get("found_under", [scheduler])
    if holds == [scheduler]:
        return f"holds under {scheduler}"
    return (f"holds under {', '.join(holds)}: every counterexample was found under "
            f"{' or '.join(found)}, and is a run of each of these adversaries")


def per_start(args: argparse.Namespace) -> int:
    """``--start S``: each start of the set on its own: exists with its witness (verified),
    none with its certificate (re-checked), or unknown; ``--max-seconds`` per start."""
    from gather_verify.synthesis.starts import describe
    from gather_verify.synthesis.views import make_instance

    if not args.witness.endswith(".py"):
        raise UsageError(f"--witness {args.witness}: the algorithm file must end in .py")
    writable_outputs(witness=args.witness, certificate=args.certificate)
    whole = make_instance(args.world, args.robots, args.meeting, args.scheduler, args.task,
                          args.multiplicity, args.frames, args.visibility, args.lights,
                          args.colours, args.start)
    w = whole.world
    started = time.perf_counter()
    rows: list[dict[str, Any]] = []
    stem, cstem = args.witness[:-3], args.certificate.removesuffix(".json").removesuffix(
        ".cert")
    problem = None
    try:
        for i, (robots, _) in enumerate(whole.configurations):
            text = " ".join(w.format_node(v) for v in robots)
            inst = make_instance(args.world, text, args.meeting, args.scheduler, args.task,
                                 args.multiplicity, args.frames, args.visibility, args.lights)
            row, trouble = one_start(args, inst, f"{stem}-{i}.py", f"{cstem}-{i}.cert.json")
            row.update(robots=text, kind=describe(w, robots, whole.meeting))
            rows.append(row)
            problem = problem or trouble
    except KeyboardInterrupt:
        print("interrupted: synthesize keeps no partial results; run the same command again "
              "(it starts over)", file=sys.stderr)
        return EXIT_INTERRUPTED
    answer = overall(rows)
    report = {"answer": answer, "world": w.name, "task": whole.task.name,
              "scheduler": whole.scheduler, "detection": whole.detection,
              "frames": whole.frames, "start": args.start, "robots": len(
                  whole.configurations[0][0]), "starts": len(rows),
              "answers": {a: sum(r["answer"] == a for r in rows)
                          for a in ("exists", "none", "unknown")},
              "seconds": time.perf_counter() - started, "rows": rows}
    return finish(args, report, rows, _print_rows, problem)


def overall(rows: list[dict[str, Any]]) -> str:
    """The answer of many rows: theirs when they agree, else ``unknown`` if one is, else
    ``mixed``."""
    answers = {r["answer"] for r in rows}
    return answers.pop() if len(answers) == 1 else "unknown" if "unknown" in answers else "mixed"


def finish(args: argparse.Namespace, report: dict[str, Any], rows: list[dict[str, Any]],
           show: Any, problem: str | None) -> int:
    """Print a synthesis report of many rows (JSON without timings unless asked, else
    ``show``), an internal problem last, and return the exit code of its answer."""
    if args.json:
        if not args.timings:
            report.pop("seconds")
            for r in rows:
                r.pop("seconds")
        print_json(report)
    else:
        show(report)
    if problem is not None:
        print(f"internal error: {problem}", file=sys.stderr)
        return EXIT_BUG
    return ANSWER_EXIT[report["answer"]]


def one_start(args: argparse.Namespace, inst: Any, witness: str, certificate: str
              ) -> tuple[dict[str, Any], str | None]:
    """The search from one start, its file re-checked: the row, and a fault of ours (a
    witness the checker rejects, a certificate that does not re-check) or None."""
    from gather_verify.synthesis.certificate import CertificateError, write_certificate
    from gather_verify.synthesis.search import certificate_stats, synthesize
    from gather_verify.synthesis.views import Views
    from gather_verify.synthesis.witness import check_witness, write_witness

    t0 = time.perf_counter()
    views = Views(inst)
    res = synthesize(inst, max_seconds=args.max_seconds, max_candidates=args.max_candidates,
                     max_states=args.max_states, max_tree=args.max_tree, views=views,
                     seeds=seeds(args), one_mover=args.one_mover)
    row: dict[str, Any] = {"answer": res.answer, "limit": res.limit,
                           "candidates": res.candidates, "views": res.views,
                           "one_mover": res.one_mover, "one_robot": res.one_robot}
    trouble = None
    if res.answer == "exists":
        spec = write_witness(witness, inst, views, res.table)
        verdicts = sorted({r["verdict"] for r in check_witness(spec, inst, args.max_seconds)})
        row.update(witness=spec, checker=verdicts)
        if verdicts != ["VERIFIED"]:
            trouble = (f"the checker says {verdicts} of the witness {spec}: this is a bug of "
                       "gather-verify's synthesis, please report it")
    elif res.answer == "none":
        write_certificate(certificate, inst, views, res.counterexamples, res.literals,
                          res.tree, certificate_stats(res))
        row["certificate"] = certificate
        try:
            row.update(none_report(certificate)[0])
        except CertificateError as error:
            trouble = (f"the certificate {certificate} just written does not re-check "
                       f"({error}): this is a bug of gather-verify's synthesis, please report it")
    row["seconds"] = time.perf_counter() - t0
    return row, trouble


def _print_rows(report: dict[str, Any]) -> None:
    counts = report["answers"]
    print(f"{report['answer']}  {report['world']}  task {report['task']} / "
          f"{report['scheduler']}  detection {report['detection']}  frames {report['frames']}"
          f"  start {report['start']} ({report['robots']} robots), each on its own")
    print(f"starts {report['starts']} (none {counts['none']}, exists {counts['exists']}, "
          f"unknown {counts['unknown']})  {report['seconds']:.2f}s")
    for r in report["rows"]:
        line = f"  {r['answer']:<8} {r['robots']:<16} {r['kind']:<10} "
        if r["answer"] == "exists":
            line += (f"--algorithm {r['witness']}: checker {', '.join(r['checker'])} "
                     f"({r['candidates']} candidates)")
        elif r["answer"] == "none":
            line += f"certificate {r['certificate']}, " + holds_line(r, report["scheduler"])
        else:
            line += f"limit: {r['limit']}"
        print(line)
