"""The least number of colours per synchrony model and light kind, by synthesis on the
rendezvous world (SEMANTICS.md §13): one table per movement and initial colours.

Each cell is ``synthesize --world rendezvous --minimum --lights 1-B:KIND --scheduler MODEL``
with the same budget per number of colours; every ``none`` certificate is re-checked by
``verify`` and every witness by the ordinary check (inside ``synthesize``). Run it from the
repository's root::

    python -m tools.rendezvous_minimum --movement non-rigid --initial-colours all \\
        --max-seconds 60 --out out/minimum.json --markdown out/minimum.md

A cell reads ``K`` (a verified witness with K colours and a re-checked ``none`` for every
smaller number), ``≥ K`` (re-checked ``none`` below K, K unknown within the budget) or
``> B`` (``none`` up to the bound B).

``--combine FILE...`` reads the JSON of such runs (any number, for any movements and
initial colours; a longer run of one cell adds its answers) and prints the table of four
answers per cell: non-rigid moves from every colour pair, rigid from every pair, non-rigid
from one colour for both, rigid from one colour. The answers bound one another: a rigid
run is a non-rigid run and one colour for both is one of the pairs, so a ``none`` under
rigid moves or from one colour holds under non-rigid moves or from every pair, and a
witness goes the other way. An answer that such a consequence sharpens is marked ``*``::

    python -m tools.rendezvous_minimum --combine out/minimum-*.json
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path
from typing import Any

from gather_verify.synthesis.rendezvous import synthesize, verify
from gather_verify.worlds.rendezvous_rules import LIGHTS
from schedulers.phases import MODELS


def least(model: str, lights: str, movement: str, initial: str, bound: int,
          seconds: float) -> dict[str, Any]:
    """One cell: the answers for 1, 2, ... colours up to the first that is not ``none``."""
    rows = []
    for k in range(1, bound + 1):
        started = time.perf_counter()
        r = synthesize(k, lights, model, movement, initial, max_seconds=seconds)
        row = {"colours": k, "answer": r["answer"], "tables": r["tables"],
               "seconds": round(time.perf_counter() - started, 2)}
        if r["answer"] == "none":
            row["certificate_holds"] = verify(r["certificate"])
            if not row["certificate_holds"]:  # pragma: no cover - search and verify agree
                raise AssertionError(f"{model} {lights} {k}: the certificate does not hold")
        if r["answer"] == "exists":
            row["witness"] = r["witness"]
        rows.append(row)
        if r["answer"] != "none":
            break
    return {"model": model, "lights": lights, "movement": movement,
            "initial_colours": initial, "rows": rows, "cell": cell_text(rows, bound)}


def cell_text(rows: list[dict[str, Any]], bound: int) -> str:
    last = rows[-1]
    if last["answer"] == "exists":
        return f"**{last['colours']}**"
    if last["answer"] == "unknown":
        return f"≥ {last['colours']}"
    return f"> {bound}"


def markdown(cells: list[dict[str, Any]]) -> str:
    by = {(c["model"], c["lights"]): c["cell"] for c in cells}
    lines = ["| model | " + " | ".join(LIGHTS) + " |", "|---|" + "---|" * len(LIGHTS)]
    for model in MODELS:
        if any((model, kind) in by for kind in LIGHTS):
            lines.append(f"| `{model}` | " + " | ".join(by.get((model, kind), "")
                                                        for kind in LIGHTS) + " |")
    return "\n".join(lines) + "\n"


VARIANTS = (("non-rigid", "all"), ("rigid", "all"), ("non-rigid", "same"), ("rigid", "same"))
"""The four answers of a cell, in the order the combined table gives them."""


def _implies(weak: tuple[str, str], strong: tuple[str, str]) -> bool:
    """Whether a witness under ``weak`` (movement, initial colours) is one under ``strong``
    (every run of ``strong`` is a run of ``weak``), and so a ``none`` goes the other way."""
    return all(w in (s, wide) for w, s, wide in zip(weak, strong, ("non-rigid", "all"),
                                                        strict=True))


def _text(none: set[int], exists: set[int], bound: int) -> str:
    low = next(k for k in range(1, bound + 2) if k not in none)
    least = min(exists, default=None)
    if least is not None and least <= low:
        return f"**{least}**"
    if low > bound:
        return f"> {bound}"
    return f"≥ {low}" if least is None else f"{low}–{least}"


def combined(cells: list[dict[str, Any]], bound: int) -> str:
    """The table of four answers per cell (see the module's text), with ``*`` where another
    variant's answers sharpen a cell's own; one entry where the four agree."""
    facts: dict[tuple[str, str], dict[tuple[str, str], tuple[set[int], set[int]]]] = {}
    for c in cells:
        own = facts.setdefault((c["model"], c["lights"]), {}).setdefault(
            (c["movement"], c["initial_colours"]), (set(), set()))
        for r in c["rows"]:
            if r["answer"] == "none" and r.get("certificate_holds"):
                own[0].add(r["colours"])
            if r["answer"] == "exists":
                own[1].add(r["colours"])
    lines = ["| model | " + " | ".join(LIGHTS) + " |", "|---|" + "---|" * len(LIGHTS)]
    for model in MODELS:
        row = []
        for kind in LIGHTS:
            known = facts.get((model, kind), {})
            texts = []
            for v in VARIANTS:
                none, exists = known.get(v, (set(), set()))
                every_none = set().union(*(n for u, (n, _) in known.items() if _implies(v, u)))
                every_exists = set().union(*(e for u, (_, e) in known.items()
                                             if _implies(u, v)))
                text = _text(every_none, every_exists, bound)
                texts.append(text + ("\\*" if text != _text(none, exists, bound) else ""))
            row.append(texts[0].replace("\\*", "") if len(set(texts)) == 1 and known
                       else " / ".join(texts) if known else "")
        if any(row):
            lines.append(f"| `{model}` | " + " | ".join(row) + " |")
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m tools.rendezvous_minimum",
                                description=__doc__.split("\n\n")[0])
    p.add_argument("--movement", choices=("rigid", "non-rigid"), default="non-rigid")
    p.add_argument("--initial-colours", choices=("all", "same"), default="all")
    p.add_argument("--max-seconds", type=float, default=60.0, help="per number of colours")
    p.add_argument("--bound", type=int, default=4, help="the most colours tried")
    p.add_argument("--models", default=",".join(MODELS))
    p.add_argument("--lights", default=",".join(LIGHTS))
    p.add_argument("--out", help="JSON of every cell's rows")
    p.add_argument("--markdown", help="the table")
    p.add_argument("--combine", nargs="+", metavar="FILE",
                   help="print the table of four answers per cell from these runs' JSON")
    args = p.parse_args(argv)
    if args.combine:
        cells = [c for f in args.combine for c in json.loads(Path(f).read_text("utf-8"))]
        sys.stdout.write(combined(cells, args.bound))
        return 0
    cells = []
    for model in args.models.split(","):
        for kind in args.lights.split(","):
            cell = least(model, kind, args.movement, args.initial_colours, args.bound,
                         args.max_seconds)
            cells.append(cell)
            print(f"{model:20} {kind:9} {cell['cell']:6} "
                  f"{[(r['colours'], r['answer'], r['seconds']) for r in cell['rows']]}",
                  flush=True)
            if args.out:
                Path(args.out).write_text(json.dumps(cells, indent=1) + "\n", encoding="utf-8")
    if args.markdown:
        Path(args.markdown).write_text(markdown(cells), encoding="utf-8")
    else:
        sys.stdout.write(markdown(cells))
    return 0


if __name__ == "__main__":
    sys.exit(main())
