"""The viewer's server: what it serves, what it refuses, and that it survives rude clients."""

from __future__ import annotations

import http.client
import json
import os
import re
import socket
import struct
import time
import zlib
from pathlib import Path

import pytest

import multibots.viewer
from multibots import _core
from multibots.replay import Replay

#: The codec's numbers as the page gets them (docs/replay-format.md), from the engine.
CODEC = {"marked": _core.MARKED, "state_mask": _core.STATE_MASK, "heading_steps": _core.HEADING_STEPS,
         "energy_scale": _core.ENERGY_SCALE}


def request(viewer, method, path, body=None, headers=None):
    conn = http.client.HTTPConnection("127.0.0.1", viewer.port, timeout=30)
    try:
        conn.request(method, path, body=body, headers=headers or {})
        resp = conn.getresponse()
        return resp.status, dict(resp.getheaders()), resp.read()
    finally:
        conn.close()


def raw(viewer, data: bytes) -> bytes:
    """Send raw bytes; return the whole reply (the server closes or we read the status)."""
    with socket.create_connection(("127.0.0.1", viewer.port), timeout=30) as s:
        s.sendall(data)
        out = b""
        while b"\r\n\r\n" not in out:
            part = s.recv(65536)
            if not part:
                break
            out += part
        return out


def status_of(reply: bytes) -> int:
    return int(reply.split(b" ", 2)[1])


def test_binds_loopback_by_default(replay_viewer, live_viewer):
    assert replay_viewer.httpd.server_address[0] == "127.0.0.1"
    assert live_viewer.httpd.server_address[0] == "127.0.0.1"
    assert replay_viewer.url.startswith("http://127.0.0.1:")


def test_serves_the_page_assets_and_meta(replay_viewer, paper_run):
    path, result = paper_run
    code, headers, body = request(replay_viewer, "GET", "/")
    assert code == 200 and b"<canvas" in body and headers["Content-Type"].startswith("text/html")
    for name in ("app.js", "draw.js", "data.js", "viewer.css"):
        code, _, body = request(replay_viewer, "GET", f"/static/{name}")
        assert code == 200 and len(body) > 100
    code, _, body = request(replay_viewer, "GET", "/api/meta")
    meta = json.loads(body)
    assert code == 200 and meta["mode"] == "replay" and meta["robots"] == 3
    assert meta["summary"]["T"] == result.T and meta["summary"]["S"] == result.S
    assert meta["frames"] == result.steps + 1 and meta["layout"]["name"] == "paper"
    assert meta["codec"] == CODEC


def test_the_page_takes_the_codec_s_numbers_from_the_server():
    # The engine defines them and the meta carries them: the page's scripts hold no copy.
    static = Path(multibots.viewer.__file__).parent / "static"
    for name in ("app.js", "draw.js", "data.js"):
        text = (static / name).read_text(encoding="utf-8")
        found = re.findall(r"\b(0x80|0x7f|65535|256|128|127)\b", text, flags=re.IGNORECASE)
        assert not found, f"{name} writes the codec's numbers out: {found}"


def test_chunks_plain_and_deflated(replay_viewer, paper_run):
    with Replay(paper_run[0]) as rp:
        expect = rp.chunk_bytes(0)
        base = rp.base_cells(rp.chunk_count - 1).tolist()
        last = rp.chunk_count - 1
    code, headers, body = request(replay_viewer, "GET", "/api/chunk/0", headers={"Accept-Encoding": "identity"})
    assert code == 200 and body == expect and "Content-Encoding" not in headers
    code, headers, body = request(replay_viewer, "GET", "/api/chunk/0", headers={"Accept-Encoding": "gzip, deflate"})
    assert code == 200 and headers["Content-Encoding"] == "deflate" and zlib.decompress(body) == expect
    code, _, body = request(replay_viewer, "GET", f"/api/base/{last}")
    assert code == 200 and json.loads(body)["cells"] == base


def test_serves_the_named_replay(replay_viewer, paper_run):
    path = paper_run[0]
    code, _, body = request(replay_viewer, "GET", f"/replay/{path.name}")
    assert code == 200 and body == path.read_bytes()


@pytest.mark.parametrize("path", [
    "/../", "/..", "/../../etc/passwd", "/static/../server.py", "/static/..%2fserver.py",
    "/static/%2e%2e/server.py", "/%2e%2e/%2e%2e/etc/passwd", "/static/", "/static", "/etc/passwd",
    "//etc/passwd", "/static//app.js", "/static/app.js/", "/static/APP.JS", "/static/.hidden",
    "/server.py", "/viewer/server.py", "/api/chunk/999999", "/api/chunk/-1", "/api/chunk/x",
    "/api/base/999999", "/replay/other.mbr", "/replay/../group1-3.mbr", "/api/stream", "/api/control",
    "/index.html/..", "/static/app.js%00.png", "/%5c..%5cserver.py",
])
def test_everything_else_is_404(replay_viewer, path):
    reply = raw(replay_viewer, f"GET {path} HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n".encode())
    assert status_of(reply) == 404, (path, reply[:80])


def test_absolute_and_odd_request_targets(replay_viewer):
    for target in ("http://127.0.0.1/../etc/passwd", "*", "../etc/passwd"):
        reply = raw(replay_viewer, f"GET {target} HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n".encode())
        assert status_of(reply) in (400, 404), target


def test_foreign_host_header_is_refused(replay_viewer, paper_run):
    for host in ("evil.example:80", "127.evil.example", "localhost.evil.example:8765", ""):
        code, _, _ = request(replay_viewer, "GET", "/api/meta", headers={"Host": host})
        assert code == 403, host
    for host in ("localhost:9999", "127.0.0.1", "127.0.0.2:1", "[::1]:8765"):
        code, _, _ = request(replay_viewer, "GET", "/api/meta", headers={"Host": host})
        assert code == 200, host
    from multibots.viewer import Viewer

    with Viewer.for_replay(str(paper_run[0]), allow_hosts=("ide.example",)) as v:
        assert request(v, "GET", "/api/meta", headers={"Host": "ide.example:443"})[0] == 200
        assert request(v, "GET", "/api/meta", headers={"Host": "evil.example"})[0] == 403


def test_oversized_and_malformed_requests(replay_viewer):
    long_line = b"GET /" + b"a" * 70000 + b" HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n"
    assert status_of(raw(replay_viewer, long_line)) == 414
    many = b"GET / HTTP/1.1\r\nHost: 127.0.0.1\r\n" + b"".join(b"X-%d: 1\r\n" % i for i in range(150)) + b"\r\n"
    assert status_of(raw(replay_viewer, many)) == 431
    assert status_of(raw(replay_viewer, b"HELLO\r\n\r\n")) == 400
    assert status_of(raw(replay_viewer, b"GET / HTTP/9.9\r\n\r\n")) in (400, 505)
    code, _, _ = request(replay_viewer, "GET", "/api/robot?id=abc&frame=0")
    assert code == 400
    code, _, _ = request(replay_viewer, "GET", "/api/robot?id=7&frame=0")
    assert code == 400
    code, _, _ = request(replay_viewer, "GET", "/api/robot?id=0&frame=99999999")
    assert code == 400
    code, _, _ = request(
        replay_viewer, "POST", "/api/control", body=b"{}", headers={"Content-Type": "application/json"}
    )
    assert code == 404  # no controls for a replay
    code, _, _ = request(replay_viewer, "DELETE", "/")
    assert code == 405


def test_robot_panel_data(replay_viewer, paper_run):
    with Replay(paper_run[0]) as rp:
        f = rp.frames // 2
        st = rp.state_at(f)
        fr = rp.frame(f)
    code, _, body = request(replay_viewer, "GET", f"/api/robot?id=1&frame={f}")
    info = json.loads(body)
    assert code == 200
    assert info["id"] == 1 and info["frame"] == f
    assert info["state"] == int(fr["state"][1]) and info["S"] == int(st["robot_S"][1])
    assert info["C"] == int(st["robot_C"][1])
    assert info["route"][0] == pytest.approx([float(fr["x"][1]), float(fr["y"][1])], abs=0.01)


def post(viewer, body: bytes, ctype="application/json", extra=b""):
    head = (f"POST /api/control HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: {ctype}\r\n"
            f"Content-Length: {len(body)}\r\nConnection: close\r\n").encode() + extra + b"\r\n"
    return status_of(raw(viewer, head + body))


def test_control_messages_are_checked(live_viewer):
    assert post(live_viewer, b'{"action": "pause"}') == 200
    assert post(live_viewer, b'{"action": "speed", "speed": 4}') == 200
    assert post(live_viewer, b'{"action": "fly"}') == 400
    assert post(live_viewer, b'{"action": "speed", "speed": 1000}') == 400
    assert post(live_viewer, b'{"action": "speed", "speed": "fast"}') == 400
    assert post(live_viewer, b'{"action": "pause", "extra": 1}') == 400
    assert post(live_viewer, b'[1, 2]') == 400
    assert post(live_viewer, b'{"action": ') == 400
    assert post(live_viewer, b'\xff\xfe\x00') == 400
    assert post(live_viewer, b'{"action": "pause"}', ctype="text/plain") == 415
    # oversized: refused from the Content-Length alone, before reading a byte of it
    head = (b"POST /api/control HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n"
            b"Content-Length: 10000000\r\n\r\n")
    assert status_of(raw(live_viewer, head)) == 413
    assert post(live_viewer, b'{"action": "pause", "speed": 1' + b" " * 5000 + b"}") == 413
    no_length = b"POST /api/control HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n\r\n"
    assert status_of(raw(live_viewer, no_length)) == 411
    chunked = (b"POST /api/control HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n"
               b"Transfer-Encoding: chunked\r\n\r\n5\r\nhello\r\n0\r\n\r\n")
    assert status_of(raw(live_viewer, chunked)) == 411
    runner = live_viewer.source.runner
    assert runner.paused is True and runner.speed == 4.0  # the bad ones changed nothing


def read_event(sock_file):
    """One server-sent event's data, as JSON."""
    data = []
    while True:
        line = sock_file.readline()
        if not line:
            raise EOFError
        line = line.rstrip(b"\r\n")
        if line.startswith(b"data: "):
            data.append(line[6:])
        elif line == b"" and data:
            return json.loads(b"".join(data))


def open_stream(viewer):
    s = socket.create_connection(("127.0.0.1", viewer.port), timeout=30)
    s.sendall(b"GET /api/stream HTTP/1.1\r\nHost: 127.0.0.1\r\nAccept: text/event-stream\r\n\r\n")
    f = s.makefile("rb")
    status = f.readline()
    assert b" 200 " in status
    while f.readline() not in (b"\r\n", b""):
        pass
    return s, f


def test_stream_survives_clients_that_vanish(live_viewer):
    # several clients connect and drop abruptly (RST), mid-stream
    for _ in range(5):
        s, f = open_stream(live_viewer)
        msg = read_event(f)
        assert msg["frame"] and "t" in msg
        s.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
        s.close()
    # a client that sends half a request and leaves
    with socket.create_connection(("127.0.0.1", live_viewer.port), timeout=30) as s:
        s.sendall(b"GET /api/me")
    # the server still serves, and still streams
    code, _, body = request(live_viewer, "GET", "/api/meta")
    assert code == 200 and json.loads(body)["mode"] == "live" and json.loads(body)["codec"] == CODEC
    s, f = open_stream(live_viewer)
    try:
        first = read_event(f)
        later = read_event(f)
        while later["t"] <= first["t"]:
            later = read_event(f)
        assert later["t"] > first["t"]
    finally:
        s.close()


def test_replay_download_interrupted_does_not_stop_it(replay_viewer, paper_run):
    with socket.create_connection(("127.0.0.1", replay_viewer.port), timeout=30) as s:
        s.sendall(f"GET /replay/{paper_run[0].name} HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n".encode())
        s.recv(100)
        s.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
    code, _, _ = request(replay_viewer, "GET", "/api/chunk/0")
    assert code == 200


def test_live_robot_panel(live_viewer):
    code, _, body = request(live_viewer, "GET", "/api/robot?id=2")
    info = json.loads(body)
    assert code == 200 and info["id"] == 2 and info["task_cell"] in (None, 39)
    assert len(info["route"]) >= 1
    code, _, _ = request(live_viewer, "GET", "/api/robot?id=3")
    assert code == 400


def test_shared_server_still_refuses_foreign_names(paper_run):
    """Bound to every address (--host 0.0.0.0), the server answers addresses and this machine's
    names, but not a name that resolves to it through someone else's DNS (rebinding)."""
    from multibots.viewer import Viewer

    with Viewer.for_replay(str(paper_run[0]), host="0.0.0.0") as v:
        for host in ("evil.example", "evil.example:8765", "127.0.0.1.evil.example", ""):
            assert request(v, "GET", "/api/meta", headers={"Host": host})[0] == 403, host
        for host in ("127.0.0.1", "10.1.2.3:8765", "[::1]:1", socket.gethostname()):
            assert request(v, "GET", "/api/meta", headers={"Host": host})[0] == 200, host


def test_deeply_nested_control_message_is_a_400(live_viewer):
    body = b"[" * 1500 + b"]" * 1500
    code, _, reply = request(live_viewer, "POST", "/api/control", body=body,
                             headers={"Content-Type": "application/json", "Host": "127.0.0.1"})
    assert code == 400 and b"malformed" in reply
    assert request(live_viewer, "GET", "/api/meta")[0] == 200  # the server lives on


def test_requests_past_the_thread_cap_get_503(live_viewer):
    """Requests whose headers are in hold a thread each, at most MAX_CONNECTIONS; past that
    the answer is 503 at once. (Here the cap is 2, held by two live streams.)"""
    import threading

    live_viewer.httpd.slots = threading.BoundedSemaphore(2)
    streams = [open_stream(live_viewer) for _ in range(2)]
    try:
        reply = raw(live_viewer, b"GET /api/meta HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n")
        assert status_of(reply) == 503
    finally:
        for sock, f in streams:
            f.close()
            sock.close()
    # Slots come back when the stream threads notice their clients left: a keep-alive every
    # 5 s, and the write after the peer closed may still succeed, so up to 10 s, more on a
    # loaded machine (a clean-clone run missed a 10 s wait).
    for _ in range(600):
        if request(live_viewer, "GET", "/api/meta")[0] == 200:
            break
        time.sleep(0.1)
    assert request(live_viewer, "GET", "/api/meta")[0] == 200


def test_idle_and_slow_connections_hold_no_thread(replay_viewer):
    """A slow-header flood (issue 28): 300 connections that send their headers a byte at a
    time held all 64 threads, and a page request failed. Now they wait in the gate, without
    a thread: normal requests are served meanwhile, and each slow one is closed once it has
    taken HEADER_TIMEOUT seconds."""
    from multibots.viewer.gate import HEADER_TIMEOUT

    port = replay_viewer.port
    slow = [socket.create_connection(("127.0.0.1", port), timeout=30) for _ in range(300)]
    idle = [socket.create_connection(("127.0.0.1", port), timeout=30) for _ in range(100)]
    served = []
    t0 = time.monotonic()
    try:
        prefix = b"GET /api/meta HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: "
        for k in range(len(prefix)):
            if time.monotonic() - t0 > HEADER_TIMEOUT + 3:
                break
            for sock in slow:
                try:
                    sock.send(prefix[k:k + 1])
                except OSError:
                    pass
            if k % 4 == 0 and len(served) < 8:
                start = time.monotonic()
                code = request(replay_viewer, "GET", "/")[0]
                served.append((code, time.monotonic() - start))
            time.sleep(0.25)
        assert [c for c, _ in served] == [200] * 8, served
        assert max(d for _, d in served) < 2.0, served
        # Past the header timeout the slow connections are closed, unanswered.
        time.sleep(max(0.0, t0 + HEADER_TIMEOUT + 1.5 - time.monotonic()))
        slow[0].settimeout(5)
        try:
            got = slow[0].recv(100)
        except ConnectionResetError:
            got = b""
        assert got == b"", got[:40]
    finally:
        for sock in slow + idle:
            sock.close()
    assert request(replay_viewer, "GET", "/api/meta")[0] == 200


def test_keep_alive_and_pipelined_requests(replay_viewer):
    """A connection serves request after request (it goes back to the gate between them),
    pipelined ones too."""
    conn = http.client.HTTPConnection("127.0.0.1", replay_viewer.port, timeout=30)
    try:
        for path in ("/", "/api/meta", "/api/chunk/0", "/api/meta"):
            conn.request("GET", path)
            resp = conn.getresponse()
            assert resp.status == 200 and resp.read()
    finally:
        conn.close()
    two = (b"GET /api/meta HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n" * 2
           + b"GET /nothing HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n")
    with socket.create_connection(("127.0.0.1", replay_viewer.port), timeout=30) as s:
        s.sendall(two)
        out = b""
        while True:
            part = s.recv(65536)
            if not part:
                break
            out += part
    assert out.count(b"HTTP/1.1 200 OK") == 2 and out.count(b"HTTP/1.1 404") == 1


def test_serves_the_replay_it_opened_not_what_the_path_names_later(tmp_path, paper_run, small_run):
    """A replay replaced by a symlink to another file after the viewer started: the viewer
    still serves the file it opened (issue 28)."""
    import shutil

    from multibots.viewer import Viewer

    path = tmp_path / "r.mbr"
    shutil.copy(paper_run[0], path)
    original = path.read_bytes()
    with Viewer.for_replay(str(path)) as v:
        other = tmp_path / "other.mbr"
        shutil.copy(small_run[0], other)
        link = tmp_path / "link"
        link.symlink_to(other)
        os.replace(link, path)
        assert path.read_bytes() != original
        code, headers, body = request(v, "GET", "/replay/r.mbr")
        assert code == 200 and body == original and int(headers["Content-Length"]) == len(original)
        code, _, chunk = request(v, "GET", "/api/chunk/0")
        assert code == 200 and chunk == Replay(paper_run[0]).chunk_bytes(0)
