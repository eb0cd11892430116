"""The viewer's HTTP server and request handler: standard library only.

It serves the page's own files, a replay's metadata and chunks, and in live mode a stream
of frames (server-sent events) plus a small JSON control endpoint. Nothing else: any
other path, including ``/../`` tricks, gets 404. What it serves comes from a *source*
(:class:`multibots.viewer.server.ReplaySource` or ``LiveSource``).

Routes
------
``GET /``                     the page (``index.html``)
``GET /static/<name>``        one of the page's files (fixed list, read at start)
``GET /api/meta``             JSON: layout, robots, frames, summary, chunk table, mode, the
                              names of the codes and the codec's numbers (``codec``)
``GET /api/chunk/<i>``        replay: chunk i, decompressed (sent deflate-encoded when the
                              client accepts it: the stored zlib stream, untouched)
``GET /api/base/<i>``         replay: which cells hold goods before chunk i's events (a
                              grid replay: also ``goals``, each robot's goal cell or -1)
``GET /api/robot?id=I&frame=F``  one robot's panel: state, energy, task cell, S, C, route
``GET /replay/<file name>``   replay: the named replay file itself
``GET /api/stream``           live: server-sent events, one JSON frame message at a time
``POST /api/control``         live: ``{"action": "pause"|"resume"|"step"|"speed", "speed": x}``
"""

from __future__ import annotations

import ipaddress
import json
import os
import re
import socket
import threading
import urllib.parse
from http.server import BaseHTTPRequestHandler, HTTPServer
from typing import Any, Dict, Optional, Tuple

from multibots.exceptions import ReplayError
from multibots.viewer.gate import HeaderGate, Reader, Writer

__all__ = ["STATIC_DIR", "ViewerHTTPServer", "ViewerHandler", "load_assets"]

STATIC_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "static")
MAX_BODY = 4096  # bytes: a control message is a few dozen
MAX_STREAMS = 16  # concurrent live streams
DRAIN_LIMIT = 1 << 20  # an oversized body up to this size is read and dropped
_CTYPES = {
    ".html": "text/html; charset=utf-8",
    ".js": "text/javascript; charset=utf-8",
    ".css": "text/css; charset=utf-8",
    ".svg": "image/svg+xml",
    ".png": "image/png",
    ".ico": "image/x-icon",
}
_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]{0,100}$")
_LOCAL_HOSTS = {"127.0.0.1", "localhost", "::1"}
#: Requests served at once (each holds a thread; a live stream holds one for as long as it
#: lasts); past that a request gets 503. Connections waiting for their headers, or idle
#: between requests, hold none (gate.py). A page uses a few at once (the stream, frames,
#: control); 64 leaves room for many tabs.
MAX_CONNECTIONS = 64


def _is_loopback(name: str) -> bool:
    """localhost, or an IP address of the loopback network (not a name that looks like one)."""
    if name.lower() == "localhost":
        return True
    try:
        return ipaddress.ip_address(name).is_loopback
    except ValueError:
        return False


def load_assets(directory: str = STATIC_DIR) -> Dict[str, Tuple[bytes, str]]:
    """The page's files, read once: {name: (content, content type)}; no subdirectories."""
    out: Dict[str, Tuple[bytes, str]] = {}
    for name in sorted(os.listdir(directory)):
        path = os.path.join(directory, name)
        ext = os.path.splitext(name)[1].lower()
        if _NAME.match(name) and os.path.isfile(path) and ext in _CTYPES:
            with open(path, "rb") as fh:
                out[name] = (fh.read(), _CTYPES[ext])
    return out


class _Connection:
    """What a handler is given: the socket and the request head the gate read."""

    __slots__ = ("head", "sock")

    def __init__(self, sock: socket.socket, head: bytes) -> None:
        self.sock = sock
        self.head = head


class ViewerHTTPServer(HTTPServer):
    allow_reuse_address = True
    request_queue_size = 64

    def __init__(self, addr: Tuple[str, int], source: Any, assets: Dict[str, Tuple[bytes, str]],
                 verbose: bool = False, allow_hosts: Tuple[str, ...] = ()) -> None:
        host = addr[0]
        try:
            self.address_family = socket.AF_INET6 if ipaddress.ip_address(host).version == 6 else socket.AF_INET
        except ValueError:
            self.address_family = socket.AF_INET
        super().__init__(addr, ViewerHandler)
        self.source = source
        self.assets = assets
        self.verbose = verbose
        self.stopping = threading.Event()
        self.streams = 0
        self.streams_lock = threading.Lock()
        self.check_host = _is_loopback(host)
        self.allow_hosts = {h.lower() for h in allow_hosts}
        # Names under which other machines reach this one, for a server shared on purpose.
        self.own_names = {n.lower() for n in (socket.gethostname(), socket.getfqdn()) if n}
        self.slots = threading.BoundedSemaphore(MAX_CONNECTIONS)
        # Connections wait for their headers in the gate, without a thread (gate.py).
        self.gate = HeaderGate(self._dispatch)

    def process_request(self, request: Any, client_address: Any) -> None:
        self.gate.add(request, client_address)

    def _dispatch(self, sock: socket.socket, client_address: Any, head: bytes) -> None:
        """A request whose headers are in: a handler thread serves it, at most
        MAX_CONNECTIONS at once; past that it gets 503 at once."""
        if not self.slots.acquire(blocking=False):
            try:
                sock.setblocking(False)
                sock.send(_BUSY)
            except OSError:
                pass
            self.shutdown_request(sock)
            return
        try:
            threading.Thread(target=self._serve, args=(sock, client_address, head), daemon=True,
                             name="multibots-viewer-request").start()
        except BaseException:
            self.slots.release()
            self.shutdown_request(sock)
            raise

    def _serve(self, sock: socket.socket, client_address: Any, head: bytes) -> None:
        handler: Optional[ViewerHandler] = None
        try:
            handler = ViewerHandler(_Connection(sock, head), client_address, self)
        except Exception:
            self.handle_error(sock, client_address)
        finally:
            self.slots.release()
            if handler is None or not handler.handed_back:
                self.shutdown_request(sock)

    def server_close(self) -> None:
        self.gate.close()
        super().server_close()

    def handle_error(self, request: Any, client_address: Any) -> None:
        # A client that vanishes mid-response is normal; never print tracebacks for it.
        if self.verbose:
            super().handle_error(request, client_address)


_BUSY = b"HTTP/1.1 503 Service Unavailable\r\nContent-Length: 0\r\nConnection: close\r\n\r\n"


class ViewerHandler(BaseHTTPRequestHandler):
    server: ViewerHTTPServer
    server_version = "MultiBotsViewer/1"
    sys_version = ""
    protocol_version = "HTTP/1.1"
    timeout = 60  # a client that stops reading a response does not hold a thread forever
    default_request_version = "HTTP/1.0"  # errors always carry a status line
    handed_back = False

    def setup(self) -> None:
        conn: _Connection = self.request
        self.connection = conn.sock
        self.connection.settimeout(self.timeout)
        self.rfile = Reader(conn.sock, conn.head, self.timeout)  # type: ignore[assignment]
        self.wfile = Writer(conn.sock)

    def handle(self) -> None:
        # One request, then the connection goes back to the gate to wait for the next.
        self.close_connection = True
        self.handle_one_request()
        if not self.close_connection and not self.server.stopping.is_set():
            self.handed_back = True
            self.server.gate.add(self.connection, self.client_address, self.rfile.leftover(), idle=True)

    def parse_request(self) -> bool:
        if not super().parse_request():
            return False
        if len(self.requestline.split()) != 3:  # no HTTP/0.9
            self.send_error(400, "Bad request syntax")
            return False
        return True

    # ------------------------------------------------------------------ plumbing
    def log_message(self, format: str, *args: Any) -> None:
        if self.server.verbose:
            super().log_message(format, *args)

    def _send(self, code: int, body: bytes, ctype: str, extra: Optional[Dict[str, str]] = None,
              head_only: bool = False) -> None:
        self.send_response(code)
        self.send_header("Content-Type", ctype)
        self.send_header("Content-Length", str(len(body)))
        self.send_header("Cache-Control", "no-store")
        self.send_header("X-Content-Type-Options", "nosniff")
        self.send_header("Referrer-Policy", "no-referrer")
        for k, v in (extra or {}).items():
            self.send_header(k, v)
        self.end_headers()
        if not head_only:
            self.wfile.write(body)

    def _json(self, obj: Any, code: int = 200, head_only: bool = False) -> None:
        body = json.dumps(obj, separators=(",", ":")).encode("utf-8")
        self._send(code, body, "application/json", head_only=head_only)

    def _error(self, code: int, message: str, close: bool = False) -> None:
        if close:
            self.close_connection = True
        body = json.dumps({"error": message}).encode("utf-8")
        self.send_response(code)
        self.send_header("Content-Type", "application/json")
        self.send_header("Content-Length", str(len(body)))
        self.send_header("Cache-Control", "no-store")
        if close:
            self.send_header("Connection", "close")
        self.end_headers()
        if self.command != "HEAD":
            self.wfile.write(body)

    def _not_found(self) -> None:
        self._error(404, "not found")

    def _host_ok(self) -> bool:
        # Checked on every address, 0.0.0.0 included: DNS rebinding reaches the server under
        # the attacker's own name, so only addresses, this machine's names and the names
        # the user allowed are served. A server bound to loopback accepts only loopback.
        host = self.headers.get("Host", "")
        if host.startswith("["):
            name = host[1:].split("]", 1)[0]
        else:
            name = host.rsplit(":", 1)[0] if host.count(":") == 1 else host
        if _is_loopback(name) or name.lower() in self.server.allow_hosts:
            return True
        if self.server.check_host:  # bound to loopback
            return False
        try:
            ipaddress.ip_address(name)
            return True
        except ValueError:
            return name.lower() in self.server.own_names

    def _route(self) -> Optional[Tuple[str, Dict[str, list]]]:
        """The request's path, if it is a clean one; None means 404."""
        raw = self.path
        if not raw.startswith("/") or len(raw) > 2048:
            return None
        parts = urllib.parse.urlsplit(raw)
        path = parts.path
        decoded = urllib.parse.unquote(path)
        if decoded != path and not path.startswith("/replay/"):
            return None  # nothing we serve needs escapes, except a replay's own name
        if "\\" in decoded or "\x00" in decoded or "/." in decoded or "//" in decoded:
            return None
        try:
            query = urllib.parse.parse_qs(parts.query, keep_blank_values=True, strict_parsing=False,
                                          max_num_fields=8)
        except ValueError:
            return None
        return decoded, query

    @staticmethod
    def _int(query: Dict[str, list], key: str, default: Optional[int] = None) -> int:
        vals = query.get(key)
        if not vals:
            if default is None:
                raise ValueError(f"missing parameter {key!r}")
            return default
        v = vals[0]
        if not re.fullmatch(r"\d{1,9}", v):
            raise ValueError(f"parameter {key!r} must be a non-negative integer, not {v[:20]!r}")
        return int(v)

    # ------------------------------------------------------------------ methods
    def do_HEAD(self) -> None:
        self._get(head_only=True)

    def do_GET(self) -> None:
        self._get(head_only=False)

    def _get(self, head_only: bool) -> None:
        try:
            self._dispatch_get(head_only)
        except (BrokenPipeError, ConnectionResetError, ConnectionAbortedError, socket.timeout):
            self.close_connection = True

    def _dispatch_get(self, head_only: bool) -> None:
        if not self._host_ok():
            self._error(403, "forbidden host")
            return
        routed = self._route()
        if routed is None:
            self._not_found()
            return
        path, query = routed
        src = self.server.source
        assets = self.server.assets
        if path in ("/", "/index.html"):
            body, ctype = assets["index.html"]
            self._send(200, body, ctype, {"Content-Security-Policy": _CSP}, head_only)
            return
        if path.startswith("/static/"):
            name = path[len("/static/"):]
            if name in assets:
                body, ctype = assets[name]
                self._send(200, body, ctype, None, head_only)
            else:
                self._not_found()
            return
        if path == "/favicon.ico":
            self._send(204, b"", "image/x-icon", None, head_only)
            return
        if path == "/api/meta":
            self._json(src.meta, head_only=head_only)
            return
        if path == "/api/robot":
            self._robot(query, head_only)
            return
        if src.mode == "replay":
            m = re.fullmatch(r"/api/(chunk|base)/(\d{1,9})", path)
            if m:
                i = int(m.group(2))
                if i >= src.replay.chunk_count:
                    self._not_found()
                    return
                if m.group(1) == "chunk":
                    self._chunk(i, head_only)
                else:
                    try:
                        body = {"chunk": i, "cells": src.replay.base_cells(i).tolist()}
                        if src.replay.grid is not None:  # a LoRR replay: goals before the chunk
                            body["goals"] = src.replay.base_goals(i).tolist()
                    except ReplayError as exc:
                        self._error(500, str(exc))
                        return
                    self._json(body, head_only=head_only)
                return
            if path == "/replay/" + src.file_name:
                self._file(head_only)
                return
        else:
            if path == "/api/stream":
                self._stream(head_only)
                return
        self._not_found()

    def _robot(self, query: Dict[str, list], head_only: bool) -> None:
        src = self.server.source
        try:
            i = self._int(query, "id")
            if src.mode == "replay":
                f = self._int(query, "frame", 0)
                if f >= src.replay.frames:
                    raise ValueError(f"frame {f} out of range 0..{src.replay.frames - 1}")
                info = src.robot(i, f)
            else:
                info = src.robot(i)
        except (ValueError, IndexError) as exc:
            self._error(400, str(exc))
            return
        except ReplayError as exc:
            self._error(500, str(exc))
            return
        self._json(info, head_only=head_only)

    def _chunk(self, i: int, head_only: bool) -> None:
        replay = self.server.source.replay
        accept = self.headers.get("Accept-Encoding", "")
        codings = {c.split(";")[0].strip().lower() for c in accept.split(",")}
        try:
            if "deflate" in codings:
                body = replay.chunk_raw(i)
                extra = {"Content-Encoding": "deflate", "Vary": "Accept-Encoding"}
            else:
                body = replay.chunk_bytes(i)
                extra = {"Vary": "Accept-Encoding"}
        except ReplayError as exc:
            self._error(500, str(exc))
            return
        self._send(200, body, "application/octet-stream", extra, head_only)

    def _file(self, head_only: bool) -> None:
        # From the descriptor opened at start, never the path: a file put in its place since
        # (a symlink to another file) is not served.
        replay = self.server.source.replay
        self.send_response(200)
        self.send_header("Content-Type", "application/octet-stream")
        self.send_header("Content-Length", str(replay.file_size))
        self.send_header("Content-Disposition",
                         "attachment; filename*=UTF-8''" + urllib.parse.quote(self.server.source.file_name))
        self.end_headers()
        if head_only:
            return
        try:
            for block in replay.file_blocks():
                self.wfile.write(block)
        except ReplayError:  # the file shrank: the client sees a short body
            self.close_connection = True

    def _stream(self, head_only: bool) -> None:
        srv = self.server
        runner = srv.source.runner
        with srv.streams_lock:
            if srv.streams >= MAX_STREAMS:
                self._error(503, "too many viewers")
                return
            srv.streams += 1
        try:
            self.close_connection = True
            self.send_response(200)
            self.send_header("Content-Type", "text/event-stream")
            self.send_header("Cache-Control", "no-store")
            self.send_header("Connection", "close")
            self.send_header("X-Accel-Buffering", "no")
            self.end_headers()
            if head_only:
                return
            self.wfile.write(b"retry: 1000\n\n")
            self.wfile.flush()
            runner.begin()
            seen = -1
            idle = 0.0
            while not srv.stopping.is_set() and not runner.stopped:
                version, message = runner.wait_message(seen, 0.5)
                if version != seen:
                    seen = version
                    idle = 0.0
                    self.wfile.write(b"data: " + message.encode("utf-8") + b"\n\n")
                    self.wfile.flush()
                else:
                    idle += 0.5
                    if idle >= 5.0:  # a comment line: finds out whether the client is gone
                        idle = 0.0
                        self.wfile.write(b": keep-alive\n\n")
                        self.wfile.flush()
        except (BrokenPipeError, ConnectionResetError, ConnectionAbortedError, socket.timeout, OSError):
            pass
        finally:
            with srv.streams_lock:
                srv.streams -= 1

    def do_POST(self) -> None:
        try:
            self._post()
        except (BrokenPipeError, ConnectionResetError, ConnectionAbortedError, socket.timeout):
            self.close_connection = True

    def _post(self) -> None:
        if not self._host_ok():
            self._error(403, "forbidden host", close=True)
            return
        routed = self._route()
        src = self.server.source
        if routed is None or routed[0] != "/api/control" or src.mode != "live":
            self._error(404, "not found", close=True)
            return
        if self.headers.get("Transfer-Encoding"):
            self._error(411, "a Content-Length is required", close=True)
            return
        length_s = self.headers.get("Content-Length")
        if length_s is None or not re.fullmatch(r"\d{1,9}", length_s.strip()):
            self._error(411, "a Content-Length is required", close=True)
            return
        length = int(length_s)
        if length > MAX_BODY:
            if length <= DRAIN_LIMIT:  # read what was sent so the reply is not lost to a reset
                self.rfile.read(length)
            self._error(413, f"message too large ({length} bytes; at most {MAX_BODY})", close=True)
            return
        ctype = self.headers.get("Content-Type", "").split(";")[0].strip().lower()
        body = self.rfile.read(length)
        if ctype != "application/json":
            self._error(415, "control messages must be application/json")
            return
        try:
            msg = json.loads(body.decode("utf-8"))
        except (UnicodeDecodeError, ValueError, RecursionError):  # RecursionError: nested thousands deep
            self._error(400, "malformed message: not UTF-8 JSON")
            return
        if not isinstance(msg, dict) or not isinstance(msg.get("action"), str) \
                or set(msg) - {"action", "speed"}:
            self._error(400, "malformed message: expected {\"action\": ..., \"speed\": ...}")
            return
        try:
            state = src.runner.control(msg["action"], msg.get("speed"))
        except ValueError as exc:
            self._error(400, f"malformed message: {exc}")
            return
        self._json(state)

    def _unsupported(self) -> None:
        self._error(405, "method not allowed", close=True)

    do_PUT = do_DELETE = do_PATCH = do_OPTIONS = do_TRACE = do_CONNECT = _unsupported  # type: ignore


_CSP = ("default-src 'self'; script-src 'self'; style-src 'self'; img-src 'self' data: blob:; "
        "connect-src 'self'; object-src 'none'; base-uri 'none'; frame-ancestors 'none'")


