"""The largest total moves / (D·n) per class of stored sweeps: the O(Dn) claim as sweeps test it.

The paper claims O(Dn) moves (§6): an asymptotic bound with no constant, so no single run
refutes it by its length, but the ratio moves / (D·n) over whole boxes shows whether it
grows as the boxes grow. Run it from the repository's root on the databases of ordinary
sweeps (one column per database; the sweeps ``--readings`` adds are left out)::

    python -m tools.move_ratios out/b3.sqlite out/b4.sqlite out/b5.sqlite
    python -m tools.move_ratios out/b3.sqlite out/b4.sqlite --meeting 2-3   # those sweeps only
    python -m tools.move_ratios out/b3.sqlite --json

Per class and database: ``verified``, the largest ratio over the configurations every
execution of which gathers (VERIFIED: where the claim is tested cleanly); ``all``, the
largest over every configuration whose longest run the sweep measured (the failing ones
too: a deadlock has a longest run); ``unmeasured``, the configurations with a run of
infinitely many moves (a cycle with moves) or none measured (a search stopped first).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

from gather_verify.sweeps.store import Store
from gather_verify.theory import get_fact


def ratios(db: str, algorithm: str | None = None, robots: range | None = None,
           meeting: range | None = None) -> dict[str, Any]:
    """The column of one database: what its ordinary sweeps cover (boxes, robots, meeting
    nodes; only the sweeps of ``algorithm`` and of the counts in ``robots`` and ``meeting``,
    when given) and, per class, ``configurations``, ``verified``, ``all`` and
    ``unmeasured``."""
    from gather_verify.sweeps.store import algorithm_matches

    store = Store(db, read_only=True)
    try:
        sweeps = [(i, s) for i, s in store.sweeps() if "covering" not in (s.get("extra") or {})
                  and algorithm_matches(s.get("algorithm"), algorithm)
                  and (robots is None or s["robots"] in robots)
                  and (meeting is None or s["meeting"] in meeting)]
        by: dict[str, dict[str, Any]] = {}
        for i, _ in sweeps:
            for name, verdict, ratio in store.db.execute(
                    "SELECT class, verdict, ratio FROM results WHERE sweep = ?", (i,)):
                if verdict == "NOT-APPLICABLE":
                    continue
                one = by.setdefault(name, {"configurations": 0, "verified": None, "all": None,
                                           "unmeasured": 0})
                one["configurations"] += 1
                if ratio is None:
                    one["unmeasured"] += 1
                    continue
                one["all"] = max(one["all"] or 0.0, float(ratio))
                if verdict == "VERIFIED":
                    one["verified"] = max(one["verified"] or 0.0, float(ratio))
    finally:
        store.close()
    covers = sorted({(tuple(s["box"]), s["robots"], s["meeting"]) for _, s in sweeps})
    order = get_fact("class").values
    return {"database": db, "covers": [[list(box), n, m] for box, n, m in covers],
            "classes": {name: by[name] for name in order if name in by}}


def _cover(column: dict[str, Any]) -> str:
    boxes = sorted({f"{w}x{h}" for (w, h), _, _ in column["covers"]})
    robots = sorted({n for _, n, _ in column["covers"]})
    meeting = sorted({m for _, _, m in column["covers"]})

    def span(values: list[int]) -> str:
        return str(values[0]) if len(values) == 1 else f"{values[0]}-{values[-1]}"

    return f"{','.join(boxes)} n {span(robots)} m {span(meeting)}" if boxes else "(no sweep)"


def format_table(columns: list[dict[str, Any]], write: Any = print) -> None:
    """One row per class, per database ``verified / all (unmeasured)``."""
    names = [n for n in get_fact("class").values if any(n in c["classes"] for c in columns)]
    heads = [_cover(c) for c in columns]
    width = max(24, *(len(h) for h in heads))
    write(f"{'class':<13}" + "".join(f"{h:>{width + 2}}" for h in heads))
    for name in names:
        cells = []
        for c in columns:
            one = c["classes"].get(name)
            if one is None:
                cells.append("-")
                continue
            v, a = one["verified"], one["all"]
            text = f"{'-' if v is None else f'{v:.2f}'} / {'-' if a is None else f'{a:.2f}'}"
            cells.append(text + (f" ({one['unmeasured']})" if one["unmeasured"] else ""))
        write(f"{name:<13}" + "".join(f"{cell:>{width + 2}}" for cell in cells))
    write("each cell: the largest moves / (D·n) over the VERIFIED configurations / over every "
          "configuration with a measured longest run (how many have none: a cycle with moves, "
          "or a search stopped first)")


def _counts(text: str) -> range:
    low, _, high = text.partition("-")
    try:
        return range(int(low), int(high or low) + 1)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r}: give N or A-B") from None


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m tools.move_ratios",
                                     description=__doc__.splitlines()[0])
    parser.add_argument("db", nargs="+", help="results databases of ordinary sweeps")
    parser.add_argument("--algorithm", default=None, help="only the sweeps of this algorithm")
    parser.add_argument("--robots", type=_counts, default=None, help="only these robots: N or A-B")
    parser.add_argument("--meeting", type=_counts, default=None,
                        help="only these meeting nodes: N or A-B")
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args(argv)
    missing = [d for d in args.db if not Path(d).is_file()]
    if missing:
        print(f"{missing[0]}: no such results database", file=sys.stderr)
        return 2
    columns = [ratios(d, args.algorithm, args.robots, args.meeting) for d in args.db]
    if args.json:
        print(json.dumps(columns, indent=1))
    else:
        format_table(columns)
    return 0


if __name__ == "__main__":
    sys.exit(main())
