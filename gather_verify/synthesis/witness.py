"""The witness of ``exists``: an algorithm file that ``--algorithm FILE.py:Synthesized`` loads
(SEMANTICS.md §12).

The file is self-contained: a copy of :mod:`gather_verify.synthesis.viewkey` (how a view is
keyed up to isomorphism), the group of label maps of the world's frames, and the table from
keys to answers, in the key's labels. ``decide`` keys the view it is handed, looks the
answer up and carries it back into the view's own labels. A view the synthesis never met
has no rule (``Unhandled``): the ordinary checker would report it as ``defined``.
"""

from __future__ import annotations

import ast
import inspect
import json
from pathlib import Path
from typing import Any

from gather_verify.synthesis import viewkey
from gather_verify.synthesis.gapviews import exact_rules
from gather_verify.synthesis.views import Instance, Views

NAME = "Synthesized"

TEMPLATE = '''"""An algorithm synthesised by gather-verify synthesize (SEMANTICS.md §12).

Instance: {instance}

A lookup table from views up to isomorphism to answers: {count} views. Load it with
--algorithm {filename}:{name}. It answers only the views the synthesis met from these
initial configurations; any other view has no rule (the checker's ``defined``).
{rules}"""

{imports}
from gather_verify.algorithms.base import Unhandled

# -- how a view is keyed (a copy of gather_verify/synthesis/viewkey.py) --------------------
{viewkey}
# -- the instance -------------------------------------------------------------------------
GROUP = build({group!r})
DETECTION = {detection!r}
COLOURS = {colours!r}
VARIANT = {variant!r}

# view key -> (destination label in the key's frame, new colour or None to keep it)
TABLE = {{
{table}}}


class {name}:
    name = "synthesized"
    plane = False  # it reads a finite world's view

    def decide(self, view):
        key, t = canonical(GROUP, observe(view, DETECTION, COLOURS, VARIANT))
        answer = TABLE.get(key_text(key))
        if answer is None:
            raise Unhandled("a view the synthesis never met")
        label, colour = answer
        here = inverse(GROUP, t, label)
        return here if colour is None else (here, colour)
'''


def viewkey_source() -> tuple[str, str]:
    """viewkey's code without its module docstring, split as (its imports, the rest), so
    that a witness file lists every import at its top (ruff-clean)."""
    source = inspect.getsource(viewkey)
    lines = source.splitlines()
    tree = ast.parse(source)
    doc = tree.body[0] if isinstance(tree.body[0], ast.Expr) else None
    imports = [node for node in tree.body if isinstance(node, (ast.Import, ast.ImportFrom))]
    drop = {i for node in [*imports, *([doc] if doc else [])]
            for i in range(node.lineno - 1, node.end_lineno or node.lineno)}
    body = "\n".join(line for i, line in enumerate(lines) if i not in drop)
    return ("".join(f"{ast.get_source_segment(source, node)}\n" for node in imports),
            body.strip("\n") + "\n")


def write_witness(path: str, inst: Instance, views: Views, table: dict[int, int]) -> str:
    """Write the witness; returns the ``--algorithm`` spec that loads it."""
    rows = []
    for k in sorted(table, key=lambda k: views.texts[k]):
        label, colour = views.options[k][table[k]]
        rows.append(f"    {views.texts[k]!r}: ({label!r}, {colour!r}),\n")
    rules = exact_rules(views, table)
    said = "" if rules is None else (
        "\nThe same table as gap rules (docs/howto/rings.md): the gaps from the robot to the "
        "next robots,\nthe gap ahead first; the views the table stays on, and those it never "
        "met, are not listed.\n\n" + "".join(f"    {r}\n" for r in rules))
    imports, viewkey = viewkey_source()
    text = TEMPLATE.format(
        rules=said,
        instance=json.dumps(inst.describe(), sort_keys=True),
        count=len(table), filename=Path(path).name, name=NAME, imports=imports, viewkey=viewkey,
        group=inst.world.frame_group(inst.frames, inst.visibility),
        detection=inst.detection, colours=inst.lights.colours, variant=inst.lights.variant,
        table="".join(rows))
    Path(path).write_text(text, encoding="utf-8")
    return f"{path}:{NAME}"


def check_witness(spec: str, inst: Instance, max_seconds: float) -> list[dict[str, Any]]:
    """The ordinary checker on the witness, every reduction off, from every initial
    configuration: one report each."""
    from gather_verify.world_check import run_world_check

    out = []
    w = inst.world
    for robots, colours in inst.configurations:
        out.append(run_world_check(
            w, list(robots), sorted(inst.meeting), spec, inst.scheduler, task=inst.task.name,
            detection=inst.detection, frames=inst.frames, visibility=inst.visibility,
            lights=str(inst.lights), colours=list(colours), reduction=False,
            max_seconds=max_seconds))
    return out
