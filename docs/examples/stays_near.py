"""A property written outside gather_verify: no robot ever leaves the initial MER grown by
one node on every side (docs/properties.md).

    gather-verify check --robots "0,0 3,1" --meeting "2,2" --algorithm broken-away \\
        --property docs/examples/stays_near.py:STAYS_NEAR
    gather-verify check --robots "0,0 3,1" --meeting "2,2" --algorithm go-to-target \\
        --property docs/examples/stays_near.py:STAYS_NEAR

The first is VIOLATED (``broken-away`` steps away from the meeting node at odd distances),
the second VERIFIED. The predicate reads absolute nodes (the initial MER), which the
symmetries of M do not preserve, so it is not ``symmetric``: the check runs without the
symmetry reduction (anonymity stays on).
"""

from gather_verify.model.geometry import Node
from gather_verify.properties import Property, StateFacts


def outside(s: StateFacts) -> list[Node]:
    """The robots of the state that are outside the initial MER grown by 1."""
    x0, y0, x1, y1 = s.initial.mer()
    return [v for v in s.configuration.robots
            if not (x0 - 1 <= v[0] <= x1 + 1 and y0 - 1 <= v[1] <= y1 + 1)]


STAYS_NEAR = Property(
    "stays-near", "state",
    holds=lambda s: not outside(s),
    message=lambda s: f"robots {[list(v) for v in outside(s)]} left the initial MER grown by 1",
    doc="no robot ever leaves the initial MER grown by one node on every side",
)
