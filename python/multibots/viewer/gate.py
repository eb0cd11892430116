"""Connections wait here, without a thread, until their request's headers have arrived.

A thread per connection from the start lets a client that sends its headers slowly hold a
thread, and 64 such clients hold every one the server has: a slow-header flood (issue 28)
kept a page from loading. So one thread watches every waiting connection with a selector
and hands a connection to a handler thread only once the request line and headers are in:
a client has :data:`HEADER_TIMEOUT` seconds to send them, :data:`KEEP_ALIVE` idle seconds
between requests, and at most :data:`MAX_PENDING` connections wait at once (past that the
one waiting longest is closed). A handler serves one request and hands the connection
back, so an idle keep-alive connection holds no thread either.
"""

from __future__ import annotations

import io
import selectors
import socket
import threading
import time
from collections import OrderedDict
from typing import Any, Callable, List, Tuple

__all__ = ["HEADER_TIMEOUT", "KEEP_ALIVE", "MAX_HEADER_BYTES", "MAX_PENDING", "HeaderGate", "Reader", "Writer"]

#: Seconds a client has to send a request's line and headers once it started it.
HEADER_TIMEOUT = 5.0
#: Seconds a connection may stay idle between requests.
KEEP_ALIVE = 15.0
#: Connections waiting for their headers at once: each holds a socket and its bytes so far.
MAX_PENDING = 512
#: Bytes of request line and headers a connection may send: past them the handler answers
#: (414 or 431) with what it has.
MAX_HEADER_BYTES = 96 * 1024


def headers_complete(buf: bytes) -> bool:
    """Whether ``buf`` holds a whole request head: the blank line after the headers, or a
    first line that is not HTTP/1.x (which the handler refuses at once), or too many bytes."""
    if b"\r\n\r\n" in buf or b"\n\n" in buf or len(buf) > MAX_HEADER_BYTES:
        return True
    end = buf.find(b"\n")
    return end >= 0 and not buf[:end].rstrip(b"\r").split(b" ")[-1].startswith(b"HTTP/")


class _Waiting:
    __slots__ = ("addr", "buf", "deadline", "idle")

    def __init__(self, addr: Any, buf: bytes, deadline: float, idle: bool) -> None:
        self.addr = addr
        self.buf = buf
        self.deadline = deadline
        self.idle = idle


class HeaderGate:
    """Watches connections until their headers are in, then calls ``dispatch(sock, addr,
    head)`` (in the gate's thread; it must not block)."""

    def __init__(self, dispatch: Callable[[socket.socket, Any, bytes], None], header_timeout: float = HEADER_TIMEOUT,
                 keep_alive: float = KEEP_ALIVE, most: int = MAX_PENDING) -> None:
        self._dispatch = dispatch
        self._header_timeout = header_timeout
        self._keep_alive = keep_alive
        self._most = most
        self._sel = selectors.DefaultSelector()
        self._wake_r, self._wake_w = socket.socketpair()
        self._wake_r.setblocking(False)
        self._wake_w.setblocking(False)
        self._sel.register(self._wake_r, selectors.EVENT_READ)
        self._incoming: List[Tuple[socket.socket, Any, bytes, bool]] = []
        self._lock = threading.Lock()
        self._waiting: "OrderedDict[socket.socket, _Waiting]" = OrderedDict()
        self._closed = False
        self._thread = threading.Thread(target=self._run, name="multibots-viewer-gate", daemon=True)
        self._thread.start()

    def add(self, sock: socket.socket, addr: Any, buf: bytes = b"", idle: bool = False) -> None:
        """A new connection (``idle``: one handed back between requests, with the bytes of
        the next request already read)."""
        with self._lock:
            if self._closed:
                _close(sock)
                return
            self._incoming.append((sock, addr, buf, idle))
        try:
            self._wake_w.send(b"x")
        except OSError:  # the wake-up pipe is full: the gate wakes up anyway
            pass

    @property
    def waiting(self) -> int:
        return len(self._waiting)

    def close(self) -> None:
        with self._lock:
            self._closed = True
        try:
            self._wake_w.send(b"x")
        except OSError:
            pass
        self._thread.join(timeout=5)

    # ------------------------------------------------------------------ the gate's thread
    def _run(self) -> None:
        try:
            while not self._closed:
                now = time.monotonic()
                soonest = min((w.deadline for w in self._waiting.values()), default=now + 0.5)
                for key, _ in self._sel.select(timeout=min(max(soonest - now, 0.0), 0.5)):
                    if key.fileobj is self._wake_r:
                        try:
                            while self._wake_r.recv(4096):
                                pass
                        except OSError:
                            pass
                    else:
                        self._read(key.fileobj)  # type: ignore[arg-type]
                self._take_incoming()
                self._expire()
        finally:
            for sock in list(self._waiting):
                self._drop(sock)
            with self._lock:
                for sock, *_ in self._incoming:
                    _close(sock)
                self._incoming.clear()
            self._sel.close()
            self._wake_r.close()
            self._wake_w.close()

    def _take_incoming(self) -> None:
        with self._lock:
            new, self._incoming = self._incoming, []
        now = time.monotonic()
        for sock, addr, buf, idle in new:
            if buf and headers_complete(buf):  # a pipelined request, already whole
                self._dispatch(sock, addr, buf)
                continue
            while len(self._waiting) >= self._most:  # the one waiting longest goes
                self._drop(next(iter(self._waiting)))
            try:
                sock.setblocking(False)
                self._sel.register(sock, selectors.EVENT_READ)
            except (OSError, ValueError):
                _close(sock)
                continue
            wait = self._keep_alive if idle and not buf else self._header_timeout
            self._waiting[sock] = _Waiting(addr, buf, now + wait, idle and not buf)

    def _read(self, sock: socket.socket) -> None:
        w = self._waiting.get(sock)
        if w is None:
            return
        try:
            data = sock.recv(65536)
        except (BlockingIOError, InterruptedError):
            return
        except OSError:
            self._drop(sock)
            return
        if not data:  # the client is gone, or sent all it will
            if w.buf:
                self._hand_over(sock, w)
            else:
                self._drop(sock)
            return
        if w.idle:  # the next request begins: its headers have the usual time
            w.idle = False
            w.deadline = min(w.deadline, time.monotonic() + self._header_timeout)
        w.buf += data
        if headers_complete(w.buf):
            self._hand_over(sock, w)

    def _hand_over(self, sock: socket.socket, w: _Waiting) -> None:
        self._forget(sock)
        try:
            sock.setblocking(True)
        except OSError:
            _close(sock)
            return
        self._dispatch(sock, w.addr, w.buf)

    def _expire(self) -> None:
        now = time.monotonic()
        for sock in [s for s, w in self._waiting.items() if w.deadline <= now]:
            self._drop(sock)

    def _forget(self, sock: socket.socket) -> None:
        self._waiting.pop(sock, None)
        try:
            self._sel.unregister(sock)
        except (KeyError, ValueError, OSError):
            pass

    def _drop(self, sock: socket.socket) -> None:
        self._forget(sock)
        _close(sock)


def _close(sock: socket.socket) -> None:
    try:
        sock.shutdown(socket.SHUT_RDWR)
    except OSError:
        pass
    sock.close()


class Reader:
    """A request's input: the bytes the gate read, then the socket. Reading past them (a
    request body) must finish within :data:`HEADER_TIMEOUT` seconds."""

    def __init__(self, sock: socket.socket, head: bytes, timeout: float) -> None:
        self._sock = sock
        self._buf = bytearray(head)
        self._timeout = timeout
        self._deadline = time.monotonic() + HEADER_TIMEOUT
        self.closed = False

    def _fill(self) -> bool:
        left = self._deadline - time.monotonic()
        if left <= 0:
            raise socket.timeout("the request's body came too slowly")
        self._sock.settimeout(left)
        try:
            chunk = self._sock.recv(65536)
        finally:
            self._sock.settimeout(self._timeout)
        self._buf += chunk
        return bool(chunk)

    def readline(self, limit: int = -1) -> bytes:
        while True:
            end = self._buf.find(b"\n")
            if end >= 0 and (limit < 0 or end < limit):
                n = end + 1
                break
            if 0 <= limit <= len(self._buf) or not self._fill():
                n = len(self._buf) if limit < 0 else min(limit, len(self._buf))
                break
        out = bytes(self._buf[:n])
        del self._buf[:n]
        return out

    def read(self, n: int = -1) -> bytes:
        while (n < 0 or len(self._buf) < n) and self._fill():
            pass
        n = len(self._buf) if n < 0 else min(n, len(self._buf))
        out = bytes(self._buf[:n])
        del self._buf[:n]
        return out

    def leftover(self) -> bytes:
        """What was read past the request: the start of the next one."""
        return bytes(self._buf)

    def close(self) -> None:
        self.closed = True


class Writer(io.BufferedIOBase):
    """A response's output: every write is sent whole."""

    def __init__(self, sock: socket.socket) -> None:
        super().__init__()
        self._sock = sock

    def writable(self) -> bool:
        return True

    def write(self, data: Any) -> int:  # type: ignore[override]
        self._sock.sendall(data)
        return len(data)

