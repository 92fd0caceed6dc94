"""Input files, read once: the bytes of every file a command's results depend on.

Within :func:`kept` (every command of the command line runs inside it, and a sweep ships
what it kept to its workers) the first read of a file is kept, and every later read of that
path returns the same bytes, whatever the disk holds by then: a graph file, a scenario, a
trace or a ``--fingerprint-extra`` file edited while a command runs changes nothing until
the next run, and the digest a sweep keys its rows by is the digest of the bytes its
workers computed from. Outside :func:`kept` (a library caller) every read goes to the disk.

A read is bounded (:data:`MAX_INPUT_BYTES`) and takes regular files only: a FIFO with no
writer, a device (``/dev/zero``) or a socket is refused in one line before anything waits
on it or reads without end.

>>> with kept():
...     read_text("/nonexistent.json", "scenario")
Traceback (most recent call last):
...
gather_verify.errors.InvalidInput: scenario /nonexistent.json: no such file
"""

from __future__ import annotations

import hashlib
import os
import stat
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

from gather_verify.errors import InvalidInput

MAX_INPUT_BYTES = 64 << 20
"""The largest scenario, trace, graph, certificate or extra file read (64 MiB)."""

Stamp = tuple[int, int, int, int, int]
"""What tells a file apart from an edited one without reading it: device, inode, size,
modification and change times (ns). Any write changes the change time."""


@dataclass(frozen=True)
class Kept:
    """One input file as it was first read: its bytes, their digest and the file's stamp."""

    data: bytes
    digest: str
    stamp: Stamp | None


_KEPT: dict[str, Kept] | None = None
"""The files kept by the :func:`kept` block in force, by absolute path (None: no block)."""


@contextmanager
def kept() -> Iterator[dict[str, Kept]]:
    """Within the block, each input file is read once (the first read is kept). Blocks nest:
    an inner block keeps the outer block's files, and only the outermost forgets them."""
    global _KEPT
    if _KEPT is not None:
        yield _KEPT
        return
    _KEPT = {}
    try:
        yield _KEPT
    finally:
        _KEPT = None


def _key(path: str | Path) -> str:
    return os.path.abspath(os.path.expanduser(str(path)))


def stamp_of(st: os.stat_result) -> Stamp:
    return (st.st_dev, st.st_ino, st.st_size, st.st_mtime_ns, st.st_ctime_ns)


def _kind(mode: int) -> str:
    for test, name in ((stat.S_ISDIR, "a folder"), (stat.S_ISFIFO, "a FIFO (named pipe)"),
                       (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
                       (stat.S_ISSOCK, "a socket")):
        if test(mode):
            return name
    return "not a regular file"


def not_a_file(path: str | Path) -> str:
    """Why ``path`` is no file to read, for a message once ``os.path.isfile`` said no: "no
    such file", or what it is instead (a folder, a FIFO, a device)."""
    try:
        mode = os.stat(path).st_mode
    except (OSError, ValueError):
        return "no such file"
    return f"{_kind(mode)}, not a file (give a regular file)"


def _read(path: str, what: str, limit: int) -> Kept:
    """The bytes of a regular file, at most ``limit``; one line for anything else."""
    try:  # O_NONBLOCK: opening a FIFO with no writer returns at once (then it is refused)
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    except FileNotFoundError:
        raise InvalidInput(f"{what} {path}: no such file") from None
    except IsADirectoryError:
        raise InvalidInput(f"{what} {path}: a folder, not a file") from None
    except ValueError:  # a NUL byte in the name
        raise InvalidInput(f"{what} {path!r}: not a file name") from None
    except OSError as error:
        raise InvalidInput(f"{what} {path}: cannot read it ({error.strerror or error})") from None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise InvalidInput(f"{what} {path}: {_kind(st.st_mode)}, not a file (give a "
                               f"regular file)")
        if st.st_size > limit:
            raise InvalidInput(f"{what} {path}: larger than {_size(limit)}, not a {what}")
        chunks, left = [], limit + 1
        while left > 0:
            chunk = os.read(fd, min(left, 1 << 20))
            if not chunk:
                break
            chunks.append(chunk)
            left -= len(chunk)
        data = b"".join(chunks)
    except OSError as error:
        raise InvalidInput(f"{what} {path}: cannot read it ({error.strerror or error})") from None
    finally:
        os.close(fd)
    if len(data) > limit:  # grown while it was read
        raise InvalidInput(f"{what} {path}: larger than {_size(limit)}, not a {what}")
    return Kept(data, hashlib.sha256(data).hexdigest(), stamp_of(st))


def _size(limit: int) -> str:
    return f"{limit >> 20} MiB" if limit >= 1 << 20 else f"{limit:,} bytes"


def read_bytes(path: str | Path, what: str, limit: int = MAX_INPUT_BYTES) -> bytes:
    """The bytes of the input file ``path`` (``what`` names it in a message): the kept ones
    within :func:`kept`."""
    return _get(path, what, limit).data


def _get(path: str | Path, what: str, limit: int = MAX_INPUT_BYTES) -> Kept:
    key = _key(path)
    if _KEPT is not None and key in _KEPT:
        got = _KEPT[key]
        if len(got.data) > limit:
            raise InvalidInput(f"{what} {path}: larger than {_size(limit)}, not a {what}")
        return got
    got = _read(str(path), what, limit)
    if _KEPT is not None:
        _KEPT[key] = got
    return got


def read_text(path: str | Path, what: str, limit: int = MAX_INPUT_BYTES) -> str:
    """:func:`read_bytes` as UTF-8 text; one line for bytes that are not."""
    data = read_bytes(path, what, limit)
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as error:
        raise InvalidInput(f"{what} {path}: not UTF-8 text (byte {error.start})") from None


def digest(path: str | Path, what: str) -> str:
    """The SHA-256 (hex) of the input file's bytes, as :func:`read_bytes` gives them."""
    return _get(path, what).digest


def disk_digest(path: str | Path, what: str) -> str:
    """The digest of what the disk holds at ``path`` now: the kept digest while the file is
    the one kept (same stamp), else a digest of its bytes read again (a file that is gone
    or unreadable: a digest of the message)."""
    key = _key(path)
    known = None if _KEPT is None else _KEPT.get(key)
    try:
        now = stamp_of(os.stat(key))
    except OSError as error:
        return hashlib.sha256(f"unreadable: {error}".encode()).hexdigest()
    if known is not None and known.stamp == now:
        return known.digest  # (a file shipped from another process has no stamp: read below)
    try:
        got = _read(key, what, MAX_INPUT_BYTES)
    except InvalidInput as error:
        return hashlib.sha256(f"unreadable: {error}".encode()).hexdigest()
    if known is not None and got.digest == known.digest and known.stamp is not None:
        # the same bytes, written again: it may have held others in between (an edit and
        # its undo), which a reader of the disk may have read meanwhile
        return hashlib.sha256(f"rewritten: {known.digest}".encode()).hexdigest()
    return got.digest


def export(paths: Iterable[str | Path] | None = None) -> dict[str, bytes]:
    """The kept files (those of ``paths``, or all), for a worker on another machine."""
    if _KEPT is None:
        return {}
    wanted = None if paths is None else {_key(p) for p in paths}
    return {k: v.data for k, v in _KEPT.items() if wanted is None or k in wanted}


def adopt(files: dict[str, bytes]) -> None:
    """Keep ``files`` (:func:`export`'s) as if read here: a worker builds its world from the
    bytes its parent read, never from the disk. Within :func:`kept` only."""
    if _KEPT is None or not files:
        return
    for key, data in files.items():
        if key not in _KEPT:
            _KEPT[key] = Kept(data, hashlib.sha256(data).hexdigest(), None)


__all__ = ["MAX_INPUT_BYTES", "Kept", "adopt", "digest", "disk_digest", "export", "kept",
           "not_a_file", "read_bytes", "read_text"]
