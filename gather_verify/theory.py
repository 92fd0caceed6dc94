"""The registry of a paper's theory: what the generic layers ask of it, without importing it.

A paper's package (the one built in: :mod:`gather_verify.paper`) registers, when it is
imported:

- its *facts* of a configuration (:func:`fact`): the paper's are ``class`` (I11 ... I42,
  UNCLASSIFIED) and ``in_U``, which the facts table, the properties, the ``class`` column
  of check and of the sweeps, the census and the viewer read;
- its *precondition* (:func:`precondition`): why ``check`` answers NOT-APPLICABLE for an
  initial configuration (the paper's: in U or UNCLASSIFIED, for disoriented robots), and
  what the sweep table's legend says of those configurations;
- the *scope* of a property whose meaning it defines (:func:`scope`): the frames and the
  robots it applies to, and why not elsewhere (the paper's: ``no-ungatherable``, for
  oblivious robots with no common orientation, as U is Theorem 1's); outside it check
  leaves the property out with that reason;
- the *words* of such a property (:func:`words`): why it fails, why it holds without
  checking, what it checks, in the paper's terms (the paper's: ``no-ungatherable``'s U and
  its classes I41/I42), which the property, written once in the generic layer, says.

The generic layers look them up here (:func:`get_fact`, :func:`not_applicable`,
:func:`scope_of`, :func:`words_of`); the first lookup imports the packages named in :data:`THEORIES`, so
nothing depends on import order.
``lint-imports`` forbids the generic layers to import ``gather_verify.paper``
(``pyproject.toml``).

>>> from gather_verify.model.configuration import Configuration
>>> c = Configuration([(0, 1), (2, 1)], [(0, 0), (2, 0)], initial=True)
>>> get_fact("class").of(c), get_fact("in_U").of(c)
('UNCLASSIFIED', True)
>>> not_applicable(c, "all")
'initial configuration is UNCLASSIFIED: use the impossibility checks (or --force)'
>>> not_applicable(c, "compass") is None  # U is about robots with no common orientation
True
>>> scope_of("no-ungatherable").under_frames("compass")
'U (Theorem 1) is for robots with no common orientation'
>>> scope_of("final") is None  # applies everywhere
True
>>> words_of("no-ungatherable").vacuous
'initial configuration is in U'
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from gather_verify.model.configuration import Configuration

THEORIES = ("gather_verify.paper",)
"""The packages whose import registers the built-in theory (a new paper: one more name)."""


@dataclass(frozen=True)
class Fact:
    """A fact of a configuration that a paper defines."""

    name: str
    of: Callable[..., Any]
    """``of(configuration, aut_m_all=None)``: the value (``aut_m_all``: ``Aut(M)``, identity
    first, when the caller has it already)."""
    values: tuple[Any, ...] = ()
    """The values it takes, in report order (empty: not listed)."""
    never: Callable[[Sequence[Any], Iterable[Any]], bool] | None = None
    """``never(aut_m_all, meeting_nodes)``: True when the fact is false on every configuration
    over these meeting nodes (a bulk engine then asks ``of`` nothing)."""
    symmetric_only: bool = False
    """True only on configurations with a symmetry (an element of ``Aut(M)`` but the identity
    maps the robots onto themselves): a bulk engine settles the others to False in bulk."""


@dataclass(frozen=True)
class Precondition:
    """What an initial configuration must satisfy for a paper's properties to apply."""

    summary: str
    """What a sweep counts the configurations that fail it under."""
    why_not: Callable[[Configuration, str], str | None]
    """``why_not(configuration, frames)``: why it does not apply (None: it applies)."""
    legend: str = ""
    """What the sweep table's legend says of the configurations that fail it (empty: nothing)."""


@dataclass(frozen=True)
class Scope:
    """Where a property applies, as the paper that defines its meaning says: outside it,
    check leaves the property out (``not_applicable``, with why) or refuses it when it is
    asked for by name. A property with no registered scope applies everywhere."""

    property: str
    frames: tuple[str, ...] | None = None
    """The frames it applies under (None: every one)."""
    frames_why: str = ""
    """Why it does not apply under the other frames."""
    oblivious: bool = False
    """True when it applies to oblivious robots only (no lights, or one colour)."""
    lights_why: str = ""
    """Why it does not apply to luminous robots with more than one colour."""

    def under_frames(self, frames: str) -> str | None:
        """Why it does not apply under ``frames`` (None: it does)."""
        return None if self.frames is None or frames in self.frames else self.frames_why

    def with_colours(self, colours: int) -> str | None:
        """Why it does not apply to robots with lights of ``colours`` colours (None: it does;
        one colour, seen by all, is the oblivious robot)."""
        return self.lights_why if self.oblivious and colours > 1 else None


@dataclass(frozen=True)
class Words:
    """What a paper says of a property whose meaning it defines, in its own terms."""

    property: str
    message: str
    """Why the property fails (the violation's reason)."""
    vacuous: str = ""
    """Why it holds without checking, when the initial state says so."""
    doc: str = ""
    """What it checks, in one line."""


_FACTS: dict[str, Fact] = {}
_PRECONDITIONS: list[Precondition] = []
_SCOPES: dict[str, Scope] = {}
_WORDS: dict[str, Words] = {}
_loaded: list[str] = []


def fact(name: str, *, values: Iterable[Any] = (),
         never: Callable[[Sequence[Any], Iterable[Any]], bool] | None = None,
         symmetric_only: bool = False) -> Callable[[Callable[..., Any]], Callable[..., Any]]:
    """Decorator: register the function as the fact ``name`` (a name is registered once; the
    same function again, as a reload of its module registers it, replaces it)."""
    def register(of: Callable[..., Any]) -> Callable[..., Any]:
        known = _FACTS.get(name)
        if known is not None and _where(known.of) != _where(of):
            raise ValueError(f"the fact {name!r} is registered already")
        _FACTS[name] = Fact(name, of, tuple(values), never, symmetric_only)
        return of
    return register


def precondition(summary: str, *, legend: str = ""
                 ) -> Callable[[Callable[..., str | None]], Callable[..., str | None]]:
    """Decorator: register the function as a precondition (checked in registration order)."""
    def register(why_not: Callable[..., str | None]) -> Callable[..., str | None]:
        _PRECONDITIONS[:] = [p for p in _PRECONDITIONS if _where(p.why_not) != _where(why_not)]
        _PRECONDITIONS.append(Precondition(summary, why_not, legend))
        return why_not
    return register


def scope(prop: str, *, frames: Iterable[str] | None = None, frames_why: str = "",
          oblivious: bool = False, lights_why: str = "") -> Scope:
    """Register where the property ``prop`` applies (:class:`Scope`; each restriction with
    its reason). A property has one scope: the same again, as a reload of its module
    registers it, is a no-op; another is a ValueError."""
    if (frames is not None and not frames_why) or (oblivious and not lights_why):
        raise ValueError(f"the scope of {prop!r}: say why it does not apply elsewhere")
    new = Scope(prop, None if frames is None else tuple(frames), frames_why, oblivious,
                lights_why)
    known = _SCOPES.get(prop)
    if known is not None and known != new:
        raise ValueError(f"the scope of the property {prop!r} is registered already")
    _SCOPES[prop] = new
    return new


def words(prop: str, *, message: str, vacuous: str = "", doc: str = "") -> Words:
    """Register the paper's words for the property ``prop`` (:class:`Words`). A property has
    one set of words: the same again, as a reload of its module registers them, is a no-op;
    others are a ValueError."""
    new = Words(prop, message, vacuous, doc)
    known = _WORDS.get(prop)
    if known is not None and known != new:
        raise ValueError(f"the words of the property {prop!r} are registered already")
    _WORDS[prop] = new
    return new


def _where(function: Callable[..., Any]) -> tuple[str, str]:
    """Where a function is defined: the same after a reload of its module."""
    return getattr(function, "__module__", ""), getattr(function, "__qualname__", "")


def _load() -> None:
    """Import the built-in theories once (their imports register their facts)."""
    for module in THEORIES:
        if module not in _loaded:
            importlib.import_module(module)
            _loaded.append(module)


def get_fact(name: str) -> Fact:
    """The registered fact ``name`` (KeyError, naming the registered ones, when none is)."""
    _load()
    got = _FACTS.get(name)
    if got is None:
        raise KeyError(f"no theory registers the fact {name!r} (registered: {', '.join(_FACTS)})")
    return got


def scope_of(prop: str) -> Scope | None:
    """The registered scope of the property ``prop`` (None: it applies everywhere)."""
    _load()
    return _SCOPES.get(prop)


def words_of(prop: str) -> Words:
    """The registered words of the property ``prop`` (KeyError, naming the registered ones,
    when no theory registers them)."""
    _load()
    got = _WORDS.get(prop)
    if got is None:
        raise KeyError(f"no theory registers the words of the property {prop!r} (registered: "
                       f"{', '.join(_WORDS)})")
    return got


def preconditions() -> list[Precondition]:
    """Every registered precondition, in registration order."""
    _load()
    return list(_PRECONDITIONS)


def failing(configuration: Configuration, frames: str) -> tuple[Precondition, str] | None:
    """The first registered precondition that fails on ``configuration`` under ``frames``,
    with why; None when every one holds."""
    for p in preconditions():
        why = p.why_not(configuration, frames)
        if why is not None:
            return p, why
    return None


def not_applicable(configuration: Configuration, frames: str) -> str | None:
    """Why check answers NOT-APPLICABLE for ``configuration`` (:func:`failing`), or None."""
    got = failing(configuration, frames)
    return None if got is None else got[1]
