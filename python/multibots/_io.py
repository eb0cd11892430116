"""Atomic file writes: a result file on disk is always whole, and never half-written.

Every file MultiBots writes (CSV, summaries, figures, layouts, videos) goes through
:func:`atomic_target`: the content goes to a temporary file beside the target, which is
renamed over the target once complete. A path that exists and is not a regular file (a
directory, ``/dev/null``, a FIFO, a socket) is refused with an :class:`OutputError`, because
renaming over it would replace a device or folder with a file.
"""

from __future__ import annotations

import contextlib
import os
import stat
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import BinaryIO

from multibots.exceptions import OutputError

__all__ = ["atomic_open", "atomic_target", "atomic_write_bytes", "atomic_write_text", "check_target"]

# Read once, at import: os.umask can only be read by setting it, and setting it while other
# threads create files would race with them.
_UMASK = os.umask(0o022)
os.umask(_UMASK)
#: The mode a new output file gets: what open() would give it (0o666 minus the umask).
FILE_MODE = 0o666 & ~_UMASK


def check_target(path: str | os.PathLike[str]) -> Path:
    """Checks that ``path`` is a new path or a regular file, which a rename may replace.

    Raises:
        OutputError: ``path`` is a directory, a device, a FIFO or a socket (one line).
    """
    path = Path(path)
    try:
        st = os.stat(path)
    except FileNotFoundError:
        return path
    except OSError as e:
        raise OutputError(f"{path}: cannot write ({e.strerror})") from None
    if not stat.S_ISREG(st.st_mode):
        kind = "a directory" if stat.S_ISDIR(st.st_mode) else "not a regular file"
        raise OutputError(f"{path}: is {kind}; refusing to replace it with an output file")
    return path


@contextlib.contextmanager
def atomic_target(path: str | os.PathLike[str], suffix: str = ".tmp") -> Iterator[Path]:
    """A temporary path beside ``path`` to write to; renamed over ``path`` if the block succeeds.

    For writers that want a file name (an encoder subprocess); :func:`atomic_open` gives a
    file object. The temporary file exists (empty) when the block starts and is removed if
    the block raises. The parent folder is created if missing.

    Raises:
        OutputError: ``path`` is not a regular file or a new path, or its folder cannot be
            written.
    """
    path = check_target(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, name = tempfile.mkstemp(prefix=f".{path.name}.", suffix=suffix, dir=path.parent)
    except OSError as e:
        raise OutputError(f"{path}: cannot write in {path.parent} ({e.strerror})") from None
    tmp = Path(name)
    try:
        # mkstemp makes the file private; an output file gets the usual permissions.
        os.fchmod(fd, FILE_MODE)
        os.close(fd)
        yield tmp
        with open(tmp, "rb+") as f:
            os.fsync(f.fileno())
        check_target(path)  # it may have changed while we wrote
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


@contextlib.contextmanager
def atomic_open(path: str | os.PathLike[str]) -> Iterator[BinaryIO]:
    """A binary file object whose content replaces ``path`` when the block succeeds."""
    with atomic_target(path) as tmp, open(tmp, "wb") as f:
        yield f


def atomic_write_bytes(path: str | os.PathLike[str], data: bytes) -> Path:
    """Writes ``data`` to ``path`` atomically; returns the path."""
    with atomic_open(path) as f:
        f.write(data)
    return Path(path)


def atomic_write_text(path: str | os.PathLike[str], text: str) -> Path:
    """Text version of :func:`atomic_write_bytes` (UTF-8)."""
    return atomic_write_bytes(path, text.encode("utf-8"))
