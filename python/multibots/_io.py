"""Atomic file writes: a result file on disk is always whole, and never half-written.

Every file MultiBots writes (CSV, summaries, figures, layouts, videos) goes through
:func:`atomic_target`: the content goes to a temporary file beside the target, which is
renamed over the target once complete. A path that exists and is not a regular file (a
directory, ``/dev/null``, a FIFO, a socket) is refused with an :class:`OutputError`, because
renaming over it would replace a device or folder with a file.
"""

from __future__ import annotations

import contextlib
import fnmatch
import os
import re
import shutil
import stat
import sys
import tempfile
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any, BinaryIO, Optional

from multibots._text import inert, shown
from multibots.exceptions import OutputError

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - the same parser, from PyPI
    import tomli as tomllib

__all__ = [
    "MAX_INPUT_BYTES",
    "OutputSet",
    "atomic_open",
    "atomic_target",
    "atomic_write_bytes",
    "atomic_write_text",
    "check_folder",
    "check_outputs",
    "check_target",
    "load_toml",
    "read_input",
    "regular_file",
    "staged_folder",
]

#: The largest input file (scenario, layout, orders, strategy source) read whole: the
#: engine's limit (``limits::MAX_INPUT_BYTES``, docs/limits.md).
MAX_INPUT_BYTES = 64 << 20

# Read once, at import: os.umask can only be read by setting it, and setting it while other
# threads create files would race with them.
_UMASK = os.umask(0o022)
os.umask(_UMASK)
#: The mode a new output file gets: what open() would give it (0o666 minus the umask).
FILE_MODE = 0o666 & ~_UMASK


def regular_file(path: str | os.PathLike[str], error: type[Exception], what: str = "file") -> os.stat_result:
    """Checks that ``path`` is a regular file, before anything opens it.

    Opening a FIFO with no writer blocks forever and ``/dev/zero`` never ends, so input files
    are checked with ``stat`` first (symlinks followed) and anything else is refused.

    Raises:
        error: with one line naming the path: missing, a directory, not a regular file.
    """
    try:
        st = os.stat(path)
    except FileNotFoundError:
        raise error(f"{os.fspath(path)}: no such {what}") from None
    except OSError as e:
        raise error(f"{os.fspath(path)}: cannot read ({e.strerror})") from None
    if stat.S_ISDIR(st.st_mode):
        raise error(f"{os.fspath(path)}: is a directory, not a {what}")
    if not stat.S_ISREG(st.st_mode):
        raise error(f"{os.fspath(path)}: is not a regular file (a device, FIFO or socket), not a {what}")
    return st


def read_input(path: str | os.PathLike[str], error: type[Exception], what: str = "file",
               limit: int = MAX_INPUT_BYTES) -> str:
    """The UTF-8 text of the regular file ``path``, of at most ``limit`` bytes.

    Raises:
        error: one line naming the path: not a regular file, too large, unreadable, not UTF-8.
    """
    st = regular_file(path, error, what)
    name = os.fspath(path)
    if st.st_size > limit:
        raise error(f"{name}: is {st.st_size:,} bytes; a {what} may have at most {limit:,}")
    try:
        # O_NONBLOCK: if the path was swapped for a FIFO since the check, open does not hang.
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
        with os.fdopen(fd, "rb") as f:
            if not stat.S_ISREG(os.fstat(f.fileno()).st_mode):
                raise error(f"{name}: is not a regular file, not a {what}")
            data = f.read(limit + 1)
    except OSError as e:
        raise error(f"{name}: cannot read ({e.strerror})") from None
    if len(data) > limit:
        raise error(f"{name}: grew past {limit:,} bytes while being read")
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as e:
        raise error(f"{name}: is not UTF-8 text (byte {e.start})") from None


def load_toml(text: str, source: str, error: type[Exception]) -> dict[str, Any]:
    """TOML text read by Python's parser, once the engine has checked its shape: a value
    nested thousands deep, or a dotted key of 100,000 parts (100,000 nested tables), is
    refused before the parser recurses or allocates (docs/limits.md).

    Raises:
        error: one line naming ``source`` and the line: too deep, a key too long, or not TOML
            (the parser's reason, in its place).
    """
    from multibots import _core

    name = shown(source)
    shape = _core.toml_shape_error(text)
    if shape is not None:
        raise error(f"{name}: {shape}")
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise error(f"{name}: {_toml_reason(e)}") from None
    except RecursionError:  # past the shape check only if it missed a form of nesting
        raise error(f"{name}: nested too deep to read (docs/limits.md)") from None


def _toml_reason(e: Exception) -> str:
    """Python's TOML message as the engine words its own: ``line 3, column 5: invalid value``."""
    text = str(e)
    m = re.fullmatch(r"(?s)(.*) \(at line (\d+), column (\d+)\)", text)
    if m:
        reason, where = m.group(1), f"line {m.group(2)}, column {m.group(3)}"
    else:
        reason, where = text.replace(" (at end of document)", ""), "at the end of the file"
    reason = reason[:1].lower() + reason[1:]
    return inert(f"{where}: not TOML: {reason}", 240)


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


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OverflowError):
        return True  # someone else's process, or not a pid: leave it
    return True


def _remove_stale(path: Path) -> None:
    """Removes temporary files for ``path`` left by writers that were killed.

    Temporary files are named ``.NAME.PID.*`` (the engine's ``.NAME.PID.K.tmp`` too), so one
    whose process is gone belongs to nobody: a ``kill -9`` costs disk space only until the
    next write of the same file.
    """
    prefix = f".{path.name}."
    try:
        entries = list(os.scandir(path.parent))
    except OSError:
        return
    for entry in entries:
        if not entry.name.startswith(prefix):
            continue
        pid = entry.name[len(prefix):].split(".", 1)[0]
        if pid.isdigit() and int(pid) != os.getpid() and not _alive(int(pid)):
            with contextlib.suppress(OSError):
                if entry.is_dir(follow_symlinks=False):
                    shutil.rmtree(entry.path)
                else:
                    os.unlink(entry.path)


def check_folder(path: str | os.PathLike[str], option: str = "--out") -> Path:
    """Checks that ``path`` is a folder or a new path, for an option naming an output folder.

    Raises:
        OutputError: ``path`` exists and is not a folder (one line naming the option).
    """
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise OutputError(f"{option} = {os.fspath(path)!r}: exists and is not a folder; name a folder for the outputs")
    return path


@contextlib.contextmanager
def staged_folder(out: str | os.PathLike[str], option: str = "--out") -> Iterator[Path]:
    """A staging folder whose files move into ``out`` only when the whole block succeeds.

    A set of outputs (a table and its figures) is either written whole or not at all: on a
    full disk or an error half-way, ``out`` keeps what it had. The staging folder sits beside
    ``out`` (same file system, so each move is a rename) and is removed on failure; one left
    by a killed process is removed by the next write of the same folder.
    """
    out = check_folder(out, option)
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
        _remove_stale(out)
        stage = Path(tempfile.mkdtemp(prefix=f".{out.name}.{os.getpid()}.", suffix=".staging", dir=out.parent))
    except OSError as e:
        raise OutputError(f"{option} = {os.fspath(out)!r}: cannot write ({e.strerror})") from None
    try:
        os.chmod(stage, 0o777 & ~_UMASK)
        yield stage
        for src in sorted(p for p in stage.rglob("*") if not p.is_dir()):
            dest = out / src.relative_to(stage)
            dest.parent.mkdir(parents=True, exist_ok=True)
            check_target(dest)
            os.replace(src, dest)
    except OSError as e:
        if isinstance(e, OutputError):
            raise
        raise OutputError(f"{option} = {os.fspath(out)!r}: cannot write ({e.strerror})") from None
    finally:
        shutil.rmtree(stage, ignore_errors=True)


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
        _remove_stale(path)
        fd, name = tempfile.mkstemp(prefix=f".{path.name}.{os.getpid()}.", suffix=suffix, dir=path.parent)
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


def _identity(path: Path) -> tuple[Any, ...]:
    """What a path names: the file itself (device and inode, whatever the spelling, symlinks or
    hard links) where it exists, else its resolved path."""
    try:
        st = os.stat(path)
    except OSError:
        return ("path", os.path.realpath(path))
    return ("file", st.st_dev, st.st_ino)


def _writable(label: str, path: Path) -> None:
    """Checks, before any run, that ``path`` can be written: a regular file or a new path, not
    read-only, in a folder that exists and takes a new file (a file is made there and removed)."""
    name = f"{label} = {os.fspath(path)!r}"
    try:
        st = os.stat(path)
    except FileNotFoundError:
        st = None
    except OSError as e:
        raise OutputError(f"{name}: cannot write ({e.strerror})") from None
    if st is not None:
        if not stat.S_ISREG(st.st_mode):
            kind = "a directory" if stat.S_ISDIR(st.st_mode) else "not a regular file"
            raise OutputError(f"{name}: is {kind}; refusing to replace it with an output file")
        if not st.st_mode & (stat.S_IWUSR | stat.S_IWGRP | stat.S_IWOTH):
            raise OutputError(f"{name}: is read-only; refusing to replace it")
    folder = path.parent if os.fspath(path.parent) else Path(".")
    if not folder.is_dir():
        raise OutputError(f"{name}: the folder {os.fspath(folder)!r} does not exist")
    try:
        fd, probe = tempfile.mkstemp(prefix=f".{path.name}.{os.getpid()}.", suffix=".probe", dir=folder)
        os.close(fd)
        os.unlink(probe)
    except OSError as e:
        raise OutputError(f"{name}: cannot write in {os.fspath(folder)!r} ({e.strerror})") from None


def check_outputs(outputs: Sequence[tuple[str, Optional[Path]]], inputs: Sequence[tuple[str, Path]],
                  folders: Sequence[tuple[str, Path, Sequence[str]]] = ()) -> None:
    """Before any run: no output is a file the run reads, or another output of the same run
    (the same file by any spelling, through symlinks or hard links), and every output can be
    written. ``outputs`` are (option, file) pairs (None: not asked for); ``inputs`` (what,
    file) pairs; ``folders`` (option, folder, names): an output folder and the file names
    (shell patterns) the run writes in it.

    Raises:
        OutputError: one line naming the option, the path and the file it would replace.
    """
    read = {_identity(Path(p)): (what, p) for what, p in inputs if os.path.exists(p)}
    taken: dict[tuple[Any, ...], str] = {}
    for label, p in outputs:
        if p is None:
            continue
        ident = _identity(Path(p))
        if ident in read:
            what, q = read[ident]
            raise OutputError(f"{label} = {os.fspath(p)!r}: is the {what} {os.fspath(q)!r}, which the run reads; "
                              "choose another path")
        if ident in taken:
            raise OutputError(f"{label} = {os.fspath(p)!r}: the same file as {taken[ident]}; each output needs its own "
                              "path")
        taken[ident] = label
        _writable(label, Path(p))
    for label, folder, names in folders:
        folder = Path(folder)
        for what, q in inputs:
            try:
                rel = Path(os.path.realpath(q)).relative_to(os.path.realpath(folder))
            except ValueError:
                continue
            if any(fnmatch.fnmatch(rel.as_posix(), pattern) for pattern in names):
                raise OutputError(f"{label} = {os.fspath(folder)!r}: the run writes {rel.as_posix()} there, which is "
                                  f"the {what} {os.fspath(q)!r} it reads; choose another folder")
        if folder.exists() and not folder.is_dir():
            raise OutputError(f"{label} = {os.fspath(folder)!r}: exists and is not a folder; name a folder for the "
                              "outputs")
        # The folder is made when the outputs are written: its nearest existing ancestor must
        # take a new file.
        existing = next(p for p in [folder, *folder.absolute().parents] if p.exists())
        try:
            fd, probe = tempfile.mkstemp(prefix=f".{folder.name or 'out'}.{os.getpid()}.", suffix=".probe",
                                         dir=existing)
            os.close(fd)
            os.unlink(probe)
        except OSError as e:
            raise OutputError(f"{label} = {os.fspath(folder)!r}: cannot write in {os.fspath(existing)!r} "
                              f"({e.strerror})") from None


class OutputSet:
    """Outputs written as one set: each to a temporary file beside its target, then all moved
    into place together when every one is whole, or none (a failure half-way puts back what
    the moved ones replaced).

    Example::

        with OutputSet({"--out": out, "--record": record}) as tmp:
            write(tmp["--out"]); write(tmp["--record"])
    """

    def __init__(self, targets: dict[str, Optional[Path]]) -> None:
        self.targets = {k: Path(v) for k, v in targets.items() if v is not None}
        self.temps: dict[str, Path] = {}

    def __enter__(self) -> dict[str, Path]:
        for label, target in self.targets.items():
            _remove_stale(target)
            try:
                fd, name = tempfile.mkstemp(prefix=f".{target.name}.{os.getpid()}.", suffix=".tmp",
                                            dir=target.parent if os.fspath(target.parent) else ".")
            except OSError as e:
                self._discard()
                raise OutputError(f"{label} = {os.fspath(target)!r}: cannot write ({e.strerror})") from None
            os.fchmod(fd, FILE_MODE)
            os.close(fd)
            # Writers that make their own temporary file and rename it here want no file yet.
            os.unlink(name)
            self.temps[label] = Path(name)
        return dict(self.temps)

    def _discard(self) -> None:
        for tmp in self.temps.values():
            with contextlib.suppress(OSError):
                tmp.unlink()

    def __exit__(self, kind: Any, value: Any, tb: Any) -> None:
        if kind is not None:
            self._discard()
            return
        moved: list[tuple[Path, Optional[Path]]] = []
        try:
            for label, target in self.targets.items():
                tmp = self.temps[label]
                if not tmp.exists():
                    raise OutputError(f"{label} = {os.fspath(target)!r}: was not written")
                check_target(target)
                backup = None
                if target.exists():
                    backup = target.with_name(f".{target.name}.{os.getpid()}.backup")
                    os.replace(target, backup)
                try:
                    os.replace(tmp, target)
                except OSError:
                    if backup is not None:
                        os.replace(backup, target)
                    raise
                moved.append((target, backup))
        except BaseException as e:
            # None of the set: the moved ones go back to what they replaced.
            for target, backup in reversed(moved):
                with contextlib.suppress(OSError):
                    if backup is not None:
                        os.replace(backup, target)
                    else:
                        target.unlink()
            self._discard()
            if isinstance(e, OSError) and not isinstance(e, OutputError):
                raise OutputError(f"cannot write the outputs ({e.strerror})") from None
            raise
        for _, backup in moved:
            if backup is not None:
                with contextlib.suppress(OSError):
                    backup.unlink()
