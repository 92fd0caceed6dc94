"""``bounce``: the luminous yardstick of SEMANTICS.md §10, on every world (K = 2).

A robot with colour 0 turns to 1 and stays; a robot with colour 1 turns to 0 and steps to
a neighbour (the first in its frame's order: the frames, hence the adversary, give every
neighbour on a ring, a grid, a torus or Z², whose views have ``me`` and ``neighbours()``
too).

>>> from gather_verify.world_check import run_world_check
>>> r = run_world_check("ring:6", "0 2", "", "bounce", "async", task="gathering",
...                     lights="2", reduction=False)
>>> r["states"], r["transitions"]
(576, 1440)
"""

from __future__ import annotations

from typing import Any


class Bounce:
    name = "bounce"
    luminous = True  # it answers colours: check it with --lights 2

    def decide(self, view: Any) -> Any:
        if view.light == 0:
            return view.me, 1
        return view.neighbours()[0], 0
