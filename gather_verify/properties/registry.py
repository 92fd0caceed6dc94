"""The registry of properties, in verdict order (when several fail, the first is named; a
livelock is named termination, :func:`gather_verify.verdict.named_first`).

The built-in properties come first; a property written elsewhere is one
:class:`~gather_verify.properties.base.Property` and one :func:`register` call (it goes
last), or a file loaded with ``--property FILE.py:NAME`` (:func:`load_property`).

>>> check_property_names(["final", "termination"])
['final', 'termination']
>>> check_property_names(["nope"])
Traceback (most recent call last):
...
gather_verify.errors.InvalidInput: unknown property 'nope' (choose from final, no-ungatherable, target-invariance, move-bound, termination)
"""

from __future__ import annotations

import hashlib
import importlib.util
import sys
from collections.abc import Iterable
from dataclasses import replace
from pathlib import Path

from gather_verify.errors import InvalidInput
from gather_verify.inputs import not_a_file
from gather_verify.properties.base import Property
from gather_verify.properties.builtin import BUILTIN
from gather_verify.watchdog import OverMemory, Overtime, guards, watched

RESERVED = ("states", "time", "memory", "region")
"""Names a search's ``stopped`` uses for its limits: no property may take them."""

_REGISTRY: dict[str, Property] = {p.name: p for p in BUILTIN}
_LOADED: dict[tuple[str, str], Property] = {}
_FROM: dict[str, str] = {}
"""The file each loaded property came from, as named (a snapshot of it replaces it)."""

ORDER = tuple(p.name for p in BUILTIN)
"""The built-in properties' names in verdict order (:func:`names` adds registered ones)."""
PROPERTIES = tuple(p.name for p in BUILTIN if not p.pseudo)
"""The built-in properties a check may request (the pseudo-properties ``crash`` and ``defined`` are always on)."""


def register(prop: Property) -> Property:
    """Add ``prop`` to the registry, after the others; registering the same object again is
    a no-op. InvalidInput when another property already has its name."""
    if not isinstance(prop, Property):
        raise InvalidInput(f"cannot register {prop!r}: not a gather_verify Property")
    if prop.name in RESERVED:
        raise InvalidInput(f"cannot register property {prop.name!r}: the name of a search limit "
                         f"({', '.join(RESERVED)})")
    known = _REGISTRY.get(prop.name)
    if known is not None and known is not prop:
        raise InvalidInput(f"cannot register property {prop.name!r}: another property has that name")
    _REGISTRY[prop.name] = prop
    return prop


def unregister(name: str) -> None:
    """Remove a registered property (built-in ones stay)."""
    if name in ORDER:
        raise InvalidInput(f"cannot unregister the built-in property {name!r}")
    _REGISTRY.pop(name, None)
    for key in [k for k, p in _LOADED.items() if p.name == name]:
        del _LOADED[key]


def registered() -> list[Property]:
    """Every registered property, in verdict order."""
    return list(_REGISTRY.values())


def names() -> tuple[str, ...]:
    """Every registered property's name, in verdict order."""
    return tuple(_REGISTRY)


def get_property(name: str) -> Property:
    """The registered property ``name``; InvalidInput (one line) if there is none."""
    prop = _REGISTRY.get(name)
    if prop is None:
        raise InvalidInput(f"unknown property {name!r} (registered: {', '.join(_REGISTRY)}; load "
                         "one with --property FILE.py:NAME)")
    return prop


def is_spec(text: str) -> bool:
    """Whether ``text`` names a property in a file, ``FILE.py:NAME``."""
    path, sep, name = text.rpartition(":")
    return bool(sep and name and path.endswith(".py"))


def absolute_spec(text: str) -> str:
    """``FILE.py:NAME`` with the file's absolute path (what a sweep stores, so its workers
    load the same file from anywhere); a plain name unchanged."""
    if not is_spec(text):
        return text
    path, _, name = text.rpartition(":")
    return f"{Path(path).expanduser().resolve()}:{name}"


def load_property(spec: str) -> Property:
    """The property ``NAME`` defined in ``FILE.py`` (``spec = "FILE.py:NAME"``, the path relative
    to the working directory), registered; the same file and name load once per process.
    InvalidInput (one line) when the file cannot be read or run, or ``NAME`` is no Property."""
    from gather_verify.algorithms.loading import source_of

    text, _, attr = spec.rpartition(":")
    # the copy of a sweep's snapshot when one is in force, as for an algorithm file
    path = Path(source_of(str(Path(text).expanduser().resolve())))
    key = (str(path), attr)
    if key in _LOADED:
        return _LOADED[key]
    if not path.is_file():
        why = not_a_file(path)
        raise InvalidInput(f"cannot load property {spec!r}: "
                           + (f"no file {text}" if why == "no such file" else f"{text}: {why}"))
    module_name = "gather_verify_user_property_" + hashlib.sha1(str(path).encode()).hexdigest()[:12]
    module = sys.modules.get(module_name)
    if module is None:
        loader_spec = importlib.util.spec_from_file_location(module_name, path)
        if loader_spec is None or loader_spec.loader is None:
            raise InvalidInput(f"cannot load property {spec!r}: {text} is not a Python file")
        module = importlib.util.module_from_spec(loader_spec)
        sys.modules[module_name] = module
        try:
            with watched():  # an endless loop at import ends with the time limit (watchdog)
                loader_spec.loader.exec_module(module)
        except BaseException as error:  # the user's file: any failure is bad input
            del sys.modules[module_name]
            if isinstance(error, KeyboardInterrupt | OverMemory):  # Ctrl-C; the memory limit
                raise
            if isinstance(error, Overtime):
                raise InvalidInput(f"cannot load property {spec!r}: {text} did not finish "
                                   f"importing within {error.seconds:g} s (an endless loop "
                                   "at import?)") from None
            why = " ".join(str(error).split()) or "no message"
            raise InvalidInput(f"cannot load property {spec!r}: {text} raised "
                             f"{type(error).__name__}: {why}") from None
    prop = getattr(module, attr, None)
    if prop is None:
        raise InvalidInput(f"cannot load property {spec!r}: {text} defines no {attr!r}")
    if not isinstance(prop, Property):
        raise InvalidInput(f"cannot load property {spec!r}: {attr} is a {type(prop).__name__}, "
                         "not a gather_verify.properties.Property")
    prop = _guarded(prop)
    known = _REGISTRY.get(prop.name)
    if known is getattr(module, attr) or (known is not None and _FROM.get(prop.name) == text):
        _REGISTRY[prop.name] = prop  # the file registered it itself, or an earlier read of it
    else:
        register(prop)
    _FROM[prop.name] = text
    _LOADED[key] = prop
    return prop


CALLABLES = ("holds", "message", "value", "detail", "vacuous", "confirm", "decide")
"""The fields of a :class:`Property` that hold the user's code."""


def _guarded(prop: Property) -> Property:
    """``prop`` with each of its functions run as the user's code, which the watchdog stops
    at the time limit (:func:`gather_verify.watchdog.guards`)."""
    return replace(prop, **{name: guards(f) for name in CALLABLES
                            if callable(f := getattr(prop, name))})


def check_property_names(requested: Iterable[str] | None) -> list[str]:
    """The names of the requested properties, in the order given (every registered one that
    may be requested when ``requested`` is empty or None); a ``FILE.py:NAME`` entry is loaded
    and registered (:func:`load_property`). InvalidInput on an unknown name."""
    choices = [p.name for p in _REGISTRY.values() if not p.pseudo]
    if not requested:
        return choices
    out: list[str] = []
    for name in requested:
        if is_spec(name):
            name = load_property(name).name
            if _REGISTRY[name].pseudo:
                raise InvalidInput(f"property {name!r} is always checked: do not request it")
        elif name not in choices:
            raise InvalidInput(f"unknown property {name!r} (choose from {', '.join(choices)})")
        if name not in out:
            out.append(name)
    return out
