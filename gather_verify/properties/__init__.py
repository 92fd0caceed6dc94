"""Properties as data (SEMANTICS.md §5): one :class:`Property` object per property, a
registry in verdict order, and the graph analyses the graph properties use.

A new property is one object and one :func:`register` call (or ``--property FILE.py:NAME``
on the command line); both engines, ``run_check`` and ``replay`` take it from the
registry. See docs/properties.md.

>>> from gather_verify.properties import always, register, unregister, names
>>> p = register(always("idle", lambda s: s.idle, "a move is pending"))
>>> names()[-1]
'idle'
>>> unregister("idle")
"""

from gather_verify.properties.base import (
    KINDS,
    Outcome,
    Property,
    Run,
    Witness,
    always,
)
from gather_verify.properties.builtin import BUILTIN
from gather_verify.properties.facts import (
    ConfigurationFacts,
    Facts,
    StateFacts,
    configuration_facts,
)
from gather_verify.properties.graph import (
    GraphFacts,
    Livelock,
    LongestPath,
    any_cycle,
    has_cycle,
    livelock,
    longest_path,
    strongly_connected,
)
from gather_verify.properties.registry import (
    ORDER,
    PROPERTIES,
    check_property_names,
    get_property,
    load_property,
    names,
    register,
    registered,
    unregister,
)

__all__ = [
    "BUILTIN", "KINDS", "ORDER", "PROPERTIES", "ConfigurationFacts", "Facts", "GraphFacts",
    "Livelock", "LongestPath", "Outcome", "Property", "Run", "StateFacts", "Witness", "always",
    "any_cycle", "check_property_names", "configuration_facts", "get_property", "has_cycle",
    "livelock", "load_property", "longest_path", "names", "register", "registered",
    "strongly_connected", "unregister",
]
