"""`multibots view` and `multibots render` on the command line."""

from __future__ import annotations

import http.client
import json
import signal
import subprocess
import sys

import pytest
from PIL import Image

from viewer_helpers import cli_command, run_cli


def assert_one_line_error(proc, *words):
    assert proc.returncode == 2, (proc.returncode, proc.stdout, proc.stderr)
    err = proc.stderr.strip()
    assert err and "\n" not in err, err
    assert "Traceback" not in proc.stderr
    for w in words:
        assert w in err, (w, err)


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
    (["render", "REPLAY", "--out", "x.avi"], [".mp4 or .gif"]),
    (["render", "REPLAY", "--out", "x.gif", "--fps", "0"], ["--fps"]),
    (["render", "REPLAY", "--out", "x.gif", "--from", "999999"], ["--from", "999999"]),
    (["render", "REPLAY", "--out", "x.gif", "--from", "5", "--to", "2"], ["--to"]),
    (["render", "REPLAY", "--out", "x.gif", "--scale", "100"], ["--scale"]),
    (["render", "REPLAY", "--out", "nofolder/x.gif"], ["nofolder"]),
    (["render", "missing.mbr", "--out", "x.gif"], ["missing.mbr"]),
])
def test_bad_input_is_one_line_and_exit_2(args, words, small_run, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    args = [str(small_run[0]) if a == "REPLAY" else a for a in args]
    proc = run_cli(*args)
    assert_one_line_error(proc, *words)
    assert not (tmp_path / "x.gif").exists()


def test_bad_scenarios_are_reported_by_field(tmp_path):
    proc = run_cli("view", "--live", "--robots", "9", "--goods", "11,8", "--no-browser")
    assert_one_line_error(proc)
    bad = tmp_path / "bad.toml"
    bad.write_text("robots = 3\ntasks = [11, 11]\n")
    proc = run_cli("view", "--live", str(bad), "--no-browser")
    assert_one_line_error(proc)
    (tmp_path / "broken.mbr").write_bytes(b"MBREPLAY" + b"\0" * 30)
    proc = run_cli("view", str(tmp_path / "broken.mbr"), "--no-browser")
    assert_one_line_error(proc, "broken.mbr")


def test_view_serves_on_loopback_and_stops_on_ctrl_c(small_run):
    proc = subprocess.Popen(cli_command() + ["view", str(small_run[0]), "--no-browser", "--port", "0"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
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


def test_render_gif_from_the_command_line(small_run, tmp_path):
    out = tmp_path / "run.gif"
    proc = run_cli("render", small_run[0], "--out", out, "--from", "5", "--to", "34", "--fps", "10", "--quiet")
    assert proc.returncode == 0, proc.stderr
    assert "30 frames" in proc.stdout
    with Image.open(out) as im:
        assert im.n_frames == 30
        assert im.info["duration"] == 100
    assert not [p for p in tmp_path.iterdir() if p.name != "run.gif"]  # no temporary left behind


def test_export_frame_plan():
    from multibots.render import plan_frames

    assert plan_frames(100) == list(range(100))
    assert plan_frames(100, 10, 69) == list(range(10, 70))
    assert plan_frames(100, 0, 40, 2) == list(range(0, 41, 2))
    assert len(plan_frames(1720, 0, None, 4)) == (1719 - 0) // 4 + 1
    for bad in [dict(start=100), dict(start=5, end=2), dict(end=100), dict(every=0)]:
        with pytest.raises(ValueError):
            plan_frames(100, **bad)
