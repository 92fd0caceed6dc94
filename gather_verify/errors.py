"""The project's exceptions share one root, and two kinds of failure are kept apart (as
Hypothesis keeps ``InvalidArgument`` apart).

- :class:`GatherVerifyError`: the root. Every exception class that gather-verify defines
  derives from it, except :class:`gather_verify.watchdog.Overtime`, a ``BaseException``
  on purpose (the user's ``except Exception`` must not swallow it).
- :class:`InvalidInput`: the user's mistake (a bad node, an unknown algorithm, a
  malformed scenario or trace). The CLI prints its message as one line on stderr
  and exits 2. It subclasses ``ValueError`` so callers that caught ``ValueError``
  keep working.
- Anything else that escapes is a bug of gather-verify: the CLI says so, prints
  the traceback and exits 70 (``EX_SOFTWARE`` of ``sysexits.h``).

A bug in the user's *algorithm* is neither: it is a counterexample (the
``crash`` property, beside ``defined`` for Unhandled), never an exception here.

>>> raise InvalidInput("bad node 'x': expected x,y")
Traceback (most recent call last):
...
gather_verify.errors.InvalidInput: bad node 'x': expected x,y
>>> issubclass(InvalidInput, ValueError), issubclass(InvalidInput, GatherVerifyError)
(True, True)
"""

from __future__ import annotations


class GatherVerifyError(Exception):
    """The root of every exception gather-verify defines: ``except GatherVerifyError``
    catches what the project raises on purpose, and nothing else.

    Each subclass states its cause and its fix. Each also keeps the built-in base it had
    before (``ValueError``, ``LookupError``, ``AssertionError``), so that code catching
    those keeps working."""


class InvalidInput(GatherVerifyError, ValueError):
    """The user's mistake: a bad node, an unknown name, a malformed scenario, trace or file.

    Cause: a value given on the command line or in an input file is not one gather-verify
    accepts. Fix: the message names the bad value and what to give instead; the CLI prints
    it as one line and exits 2."""


__all__ = ["GatherVerifyError", "InvalidInput"]
