"""`multibots view` on the command line (``render``'s is in test_cli_render.py)."""

from __future__ import annotations

import http.client
import json
import signal

import pytest


@pytest.mark.parametrize("args, words", [
    (["view", "missing.mbr", "--no-browser"], ["missing.mbr", "no such replay file"]),
    (["view", "--no-browser"], ["REPLAY"]),
    (["view", "REPLAY", "--port", "70000", "--no-browser"], ["--port", "70000"]),
    (["view", "REPLAY", "--host", "not-an-ip", "--no-browser"], ["--host"]),
    (["view", "--live", "--goods", "11,x", "--no-browser"], ["--goods", "11,x"]),
    (["view", "--live", "--goods", "11,8", "--robots", "0", "--no-browser"], ["--robots"]),
    (["view", "--live", "--goods", "11,8", "--speed", "100", "--no-browser"], ["--speed"]),
    (["view", "--live", "missing.toml", "--no-browser"], ["missing.toml"]),
    (["view", "--robots", "3", "--no-browser"], ["--live"]),
])
def test_bad_input_is_one_line_and_exit_2(cli, args, words, small_run, tmp_path):
    args = [str(small_run[0]) if a == "REPLAY" else a for a in args]
    cli.assert_one_line_error(cli(*args, cwd=tmp_path), *words)


def test_bad_scenarios_are_reported_by_field(cli, tmp_path):
    proc = cli("view", "--live", "--robots", "9", "--goods", "11,8", "--rules", "original", "--no-browser")
    cli.assert_one_line_error(proc, "robots = 9")
    bad = tmp_path / "bad.toml"
    bad.write_text("robots = 3\ntasks = [11, 11]\n")
    proc = cli("view", "--live", str(bad), "--no-browser")
    cli.assert_one_line_error(proc, "tasks[1] = 11")
    (tmp_path / "broken.mbr").write_bytes(b"MBREPLAY" + b"\0" * 30)
    proc = cli("view", str(tmp_path / "broken.mbr"), "--no-browser")
    cli.assert_one_line_error(proc, "broken.mbr")


def test_view_serves_on_loopback_and_stops_on_ctrl_c(cli, small_run):
    proc = cli.popen("view", small_run[0], "--no-browser", "--port", "0")
    try:
        url = None
        for _ in range(10):
            line = proc.stdout.readline()
            if "http://" in line:
                url = line.split()[0]
                break
        assert url and url.startswith("http://127.0.0.1:"), url
        port = int(url.rstrip("/").rsplit(":", 1)[1])
        conn = http.client.HTTPConnection("127.0.0.1", port, timeout=30)
        conn.request("GET", "/api/meta")
        meta = json.loads(conn.getresponse().read())
        conn.close()
        assert meta["mode"] == "replay" and meta["name"] == small_run[0].name
    finally:
        proc.send_signal(signal.SIGINT)
        try:
            proc.wait(timeout=30)
        finally:
            if proc.poll() is None:
                proc.kill()
    assert proc.returncode == 0
    assert "Traceback" not in proc.stderr.read()
