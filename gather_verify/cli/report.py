"""``gather-verify report``: render a stored sweep as tables, HTML and a plot."""

from __future__ import annotations

import argparse
import sys
from typing import Any

from gather_verify.cli.common import add_json_arguments, print_json, without_timings
from gather_verify.errors import InvalidInput

HELP = "render the sweeps stored in a results database"


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--db", required=True, help="results database written by 'sweep' or 'synthesize --minimum'")
    p.add_argument("--html", metavar="FILE", help="write an HTML report (with SVG traces)")
    p.add_argument("--plot", metavar="FILE", help="write a plot of max moves against D·n")
    p.add_argument("--regressions", metavar="DIR",
                   help="write one scenario file per distinct counterexample into DIR "
                        "(e.g. scenarios/regressions)")
    p.add_argument("--workers-curve", metavar="N,N,...",
                   help="predict the wall time of these sweeps on N workers (a pool or a Dask "
                        "cluster), from the stored seconds of their tasks")
    p.add_argument("--algorithm", metavar="NAME",
                   help="only the sweeps of this algorithm: its spec, or its name with any "
                        "options (paper names paper:alpha=mer_f), or the NAME of FILE.py:NAME")
    add_json_arguments(p, None, "the slowest configurations and their seconds",
                       reproducible=False)


def run(args: argparse.Namespace) -> int:
    from gather_verify.sweeps.minimum import COMMAND
    from gather_verify.sweeps.report import (
        code_text,
        load_sweeps,
        settings_line,
        summaries,
        when,
        write_html,
        write_plot,
    )
    from gather_verify.sweeps.sweep import format_summary

    only = args.algorithm
    if only is not None and not only.strip():
        raise InvalidInput("--algorithm is empty: name the algorithm whose sweeps to report")
    # the answers of synthesize --minimum are tables of their own (they name no algorithm)
    found = [s for s in summaries(args.db, only) if s["settings"].get("command") != COMMAND]
    least = [] if only is not None else stored_minimum(load_sweeps(args.db))
    if args.html:
        write_html(args.db, args.html, algorithm=only)
    if args.plot:
        write_plot(args.db, args.plot, algorithm=only)
    if args.regressions:
        from gather_verify.sweeps.regressions import write_regressions

        for path in write_regressions(args.db, args.regressions, algorithm=only):
            print(f"wrote {path}", file=sys.stderr)
    from gather_verify.paper.readings import format_robustness, stored_robustness

    robust = stored_robustness(args.db, only)  # sweeps run with --readings: class x robustness
    curve, seconds = (None, []) if args.workers_curve is None else \
        _workers_curve(args.db, args.workers_curve)  # an empty list is refused, not ignored
    if args.json:
        print_json({"sweeps": found if args.timings else without_timings(found),
                    **({"robustness": robust} if robust else {}),
                    **({"minimum": [{k: v for k, v in t.items() if k != "cells"}
                                    for t in least]} if least else {}),
                    **({"workers_curve": curve} if curve else {})})
        return 0
    for i, summary in enumerate(found):
        if (summary["settings"].get("extra") or {}).get("readings"):
            continue  # one of the readings below
        settings = summary["settings"] or {}
        print(f"== sweep {i + 1}: " + settings_line(settings))
        written = when(summary["written"]["last"])
        print(f"{code_text(summary['current'])}; "
              + (f"rows written {written}" if written else "written before dates were kept"))
        format_summary(summary)
        print()
    for i, t in enumerate(least):
        print(f"== synthesize --minimum {i + 1}: " + settings_line(t["settings"]))
        print(f"{code_text(t['current'])}; least {t['resource']} with an algorithm "
              f"({t['resource']} {t['low']}-{t['high']} stored; ?: some value below is unknown "
              "or was not asked)")
        from gather_verify.sweeps.minimum import format_table

        for line in format_table(t["worlds"], t["schedulers"], t["cells"]):
            print(line)
        print()
    if not found and not least:
        print(f"no sweep in {args.db}" + (f" of algorithm {only}" if only else ""))
    for group, tables in robust.items():
        print(f"== readings {group}: class x robustness")
        format_robustness(tables["table"], switches=tables["switches"])
        print()
    if curve is not None:
        from gather_verify.sweeps.schedule import format_prediction

        print("== predicted wall time on N workers (tasks in hand-out order, from stored seconds)")
        format_prediction(seconds, curve["wall"])
    return 0


def _workers_curve(db: str, text: str) -> tuple[dict[str, Any], list[float]]:
    """The predicted wall time of the stored sweeps' tasks on the worker counts ``text``, and
    the tasks' seconds."""
    from gather_verify.sweeps.minimum import COMMAND
    from gather_verify.sweeps.schedule import predict, task_seconds
    from gather_verify.sweeps.store import Store

    workers = parse_workers(text)
    store = Store(db, read_only=True)
    try:
        # the sweeps' tasks: synthesize --minimum's answers are no sweep's
        skip = {i for i, settings in store.sweeps() if settings.get("command") == COMMAND}
        seconds = task_seconds(r for r in store.seconds() if r["sweep"] not in skip)
    finally:
        store.close()
    return {"tasks": len(seconds), "seconds": round(sum(seconds), 3),
            "largest": round(max(seconds), 3) if seconds else 0.0,
            "wall": predict(seconds, workers)}, seconds


def parse_workers(text: str) -> list[int]:
    """``1,2,8`` as worker counts (each 1 to 100,000)."""
    try:
        out = [int(w) for w in text.split(",")]
    except ValueError:
        out = []
    if not out or any(not 1 <= w <= 100_000 for w in out):
        raise InvalidInput(f"bad --workers-curve {text!r}: use worker counts like 1,2,4,8")
    return out


def stored_minimum(sweeps: list[tuple[dict[str, Any], list[dict[str, Any]]]]
                   ) -> list[dict[str, Any]]:
    """The tables of the ``synthesize --minimum`` sweeps
    (:func:`~gather_verify.sweeps.minimum.stored_tables`), each with ``least`` (the cells as
    JSON rows) and ``current``: whether gather-verify's source now is the one behind its rows
    (its ``gather_verify`` fingerprint)."""
    from gather_verify.fingerprint import own_digest
    from gather_verify.sweeps.minimum import stored_tables

    out = []
    for t in stored_tables(sweeps):
        t["current"] = t["settings"].get("gather_verify") == own_digest()
        t["least"] = [{"world": w, "scheduler": sc, "least": t["cells"][w, sc]}
                      for w in t["worlds"] for sc in t["schedulers"] if (w, sc) in t["cells"]]
        out.append(t)
    return out
