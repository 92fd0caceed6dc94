"""The two kinds of failure, kept apart (as Hypothesis keeps ``InvalidArgument`` apart).

- :class:`InvalidInput`: the user's mistake (a bad node, an unknown algorithm, a
  malformed scenario or trace). The CLI prints its message as one line on stderr
  and exits 2. It subclasses ``ValueError`` so callers that caught ``ValueError``
  keep working.
- Anything else that escapes is a bug of gather-verify: the CLI says so, prints
  the traceback and exits 70 (``EX_SOFTWARE`` of ``sysexits.h``).

A bug in the user's *algorithm* is neither: it is a counterexample (the
``defined`` property), never an exception here.

>>> raise InvalidInput("bad node 'x': expected x,y")
Traceback (most recent call last):
...
gather_verify.errors.InvalidInput: bad node 'x': expected x,y
>>> issubclass(InvalidInput, ValueError)
True
"""

from __future__ import annotations


class InvalidInput(ValueError):
    """The user's mistake: the message names the bad value and what to do instead."""


__all__ = ["InvalidInput"]
