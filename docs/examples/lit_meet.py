"""Two robots on a ring with a light of two colours, written as a user would
(docs/worlds.md, "A luminous algorithm of your own"): the lit robot waits; an unlit robot
walks the shorter way to the other and lights up when its step reaches it.

    gather-verify check --world ring:7 --robots "0 3" --algorithm docs/examples/lit_meet.py:Meet \\
        --task gathering --lights 2 --colours "1 0" --scheduler async      # VERIFIED
    gather-verify check --world ring:7 --robots "0 3" --algorithm docs/examples/lit_meet.py:Meet \\
        --task gathering --lights 2 --scheduler fsync                      # VIOLATED

Started with one robot lit, it gathers under every scheduler. Started both unlit, both walk,
and the adversary activates them together: they swap nodes over the last edge, both light
up, and wait for each other for ever on two nodes.
"""

from typing import Any


class Meet:
    name = "meet"
    plane = False  # it reads a finite world's view (view.me, view.neighbours(), view.distance)

    def decide(self, view: Any) -> tuple[Any, int]:
        others = [v for v in view.robots if v != view.me]
        if not others or view.light == 1:  # together, or lit: stay lit
            return view.me, 1
        other = others[0]
        step = min(view.neighbours(), key=lambda v: view.distance(v, other))
        return step, 1 if step == other else 0
