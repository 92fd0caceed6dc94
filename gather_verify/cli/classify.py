"""``gather-verify classify``: the class of an initial configuration and why (paper §2-3.1)."""

from __future__ import annotations

import argparse

from gather_verify.cli.common import add_configuration_arguments, load_configuration, print_json
from gather_verify.model.configuration import Configuration
from gather_verify.paper.classes import classify_configuration, describe_views

HELP = "classify an initial configuration (I11 ... I42 or UNCLASSIFIED) with its symmetry and corners"


def add_arguments(p: argparse.ArgumentParser) -> None:
    add_configuration_arguments(p)
    p.add_argument("--json", action="store_true", help="print one JSON object")


def report(c: Configuration) -> dict[str, object]:
    """Everything ``classify`` prints, as one JSON-ready object.

    ``leading_corner``/``alpha_string`` are read over the MER of R and M (the
    paper's Figure "order1"); the ``*_mer_f`` fields over MER_F.

    >>> r = report(Configuration([(0, 1), (2, 1)], [(0, 0), (2, 0)], initial=True))
    >>> r["class"], r["in_U"], r["key_string"]
    ('UNCLASSIFIED', True, '410041')
    """
    out = classify_configuration(c).to_json()
    out.update(describe_views(c, "mer"))
    mer_f = describe_views(c, "mer_f")
    out["leading_corner_mer_f"] = mer_f["leading_corner"]
    out["alpha_string_mer_f"] = mer_f["alpha_string"]
    out["mer"] = list(c.mer())
    out["mer_f"] = list(c.mer_f())
    out["D"] = c.D
    out["configuration"] = c.to_json()
    return out


def _corners(corners: object) -> str:
    return " ".join(f"({x},{y})" for x, y in corners)  # type: ignore[attr-defined]


def _rect(rect: list[int]) -> str:
    x0, y0, x1, y1 = rect
    return f"({x0},{y0})-({x1},{y1}), {x1 - x0} x {y1 - y0} edges"


def run(args: argparse.Namespace) -> int:
    c, _ = load_configuration(args)
    r = report(c)
    if args.json:
        print_json(r)
        return 0
    symmetry = r["symmetry"]
    lines = [
        f"class: {r['class']}{'  (in U: ungatherable by Theorem 1)' if r['in_U'] else ''}",
        f"reason: {r['reason']}",
        f"symmetry of M used: {symmetry['describe'] if symmetry else 'none'}",  # type: ignore[index]
        f"symmetries of C: {', '.join(r['configuration_symmetries']) or 'none'}",  # type: ignore[arg-type]
        f"meeting nodes on it: {_corners(r['meeting_nodes_on_symmetry']) or 'none'}",
        f"robots on it: {_corners(r['robots_on_symmetry']) or 'none'}",
        f"MER: {_rect(r['mer'])}; MER_F: {_rect(r['mer_f'])}; D = {r['D']}",  # type: ignore[arg-type]
        f"key corner(s): {_corners(r['key_corner'])}",
        f"key string: {r['key_string']}",
        f"leading corner(s) over MER: {_corners(r['leading_corner'])}  alpha = {r['alpha_string']}",
        f"leading corner(s) over MER_F: {_corners(r['leading_corner_mer_f'])}  "
        f"alpha = {r['alpha_string_mer_f']}",
    ]
    print("\n".join(lines))
    return 0
