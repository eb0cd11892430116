"""multibots.replay.Replay against the engine's own recordings and live Simulation."""

from __future__ import annotations

import math
import struct
import zlib

import numpy as np
import pytest

import multibots
from multibots import _core
from multibots.replay import Replay, ReplayError


def documented_layout(frames, robots, events):
    """Offsets and lengths of a decompressed chunk's sections, as docs/replay-format.md gives
    them (written out here, apart from the engine's codec, to check it)."""
    out, pos = {}, 16
    for name, size, count in (("counters", 4, 3 * frames), ("x", 4, frames * robots),
                              ("y", 4, frames * robots), ("events", 4, 4 * events), ("energy", 2, frames * robots),
                              ("heading", 1, frames * robots), ("state", 1, frames * robots)):
        out[name] = (pos, size * count)
        pos += size * count
    return out, pos


def sections(raw):
    first, k, n, e = struct.unpack_from("<4I", raw)
    lay, total = documented_layout(k, n, e)
    assert len(raw) == total

    def sec(name, dtype, shape):
        off, ln = lay[name]
        return np.frombuffer(raw[off:off + ln], dtype=dtype).reshape(shape)

    return first, {"counters": sec("counters", "<u4", (k, 3)), "x": sec("x", "<f4", (k, n)),
                   "y": sec("y", "<f4", (k, n)), "events": sec("events", "<u4", (e, 4)),
                   "energy_u16": sec("energy", "<u2", (k, n)), "heading_u8": sec("heading", "u1", (k, n)),
                   "state_raw": sec("state", "u1", (k, n))}


def paper(robots=3):
    return multibots.Scenario.paper(robots=robots)


def test_header_and_summary_match_the_run(paper_run):
    path, result = paper_run
    with Replay(path) as rp:
        assert rp.robots == 3
        assert rp.frames == result.steps + 1
        assert rp.summary["T"] == result.T
        assert rp.summary["S"] == result.S
        assert rp.summary["C"] == result.C
        assert rp.summary["delivered"] == result.delivered == 10
        assert rp.summary["outcome"] == "complete"
        assert rp.layout["name"] == "paper"
        assert len(rp.layout["cells"]) == 80
        assert rp.goods_total == 10
        last = rp.frame(rp.frames - 1)
        assert (last["S"], last["C"], last["delivered"]) == (result.S, result.C, 10)
        assert sum(rp.chunk_info(i)["frames"] for i in range(rp.chunk_count)) == rp.frames


def test_frames_equal_the_simulation_step_by_step(paper_run):
    path, result = paper_run
    sim = multibots.Simulation(paper(3))
    with Replay(path) as rp:
        checks = sorted({0, 1, 2, 37, 250, 251, rp.frames // 2, rp.frames - 2, rp.frames - 1})
        for f in checks:
            sim.step(f - sim.t) if f > sim.t else None
            assert sim.t == f
            fr = rp.frame(f)
            pos = np.asarray(sim.positions)
            np.testing.assert_array_equal(fr["x"], pos[:, 0].astype(np.float32))
            np.testing.assert_array_equal(fr["y"], pos[:, 1].astype(np.float32))
            np.testing.assert_array_equal(fr["state"], np.asarray(sim.states))
            np.testing.assert_array_equal(fr["marked"], np.asarray(sim.marked))
            np.testing.assert_allclose(fr["energy"], np.asarray(sim.energy), atol=sim.energy_full / 65535)
            dh = np.angle(np.exp(1j * (fr["heading"] - np.asarray(sim.headings))))
            assert np.all(np.abs(dh) <= math.pi / 256 + 1e-9)
            assert (fr["S"], fr["C"], fr["delivered"]) == (sim.S, sim.C, sim.delivered)
            np.testing.assert_array_equal(rp.cells_at(f), np.asarray(sim.cells))
            st = rp.state_at(f)
            np.testing.assert_array_equal(st["robot_S"], np.asarray(sim.robot_S))
            np.testing.assert_array_equal(st["robot_C"], np.asarray(sim.robot_C))


def test_events_add_up_to_the_indicators(paper_run):
    path, result = paper_run
    with Replay(path) as rp:
        ev = rp.events(0, rp.frames)
        kinds = ev[:, 1]
        assert int((kinds == 5).sum()) == result.S  # WAIT
        assert int((kinds == 6).sum()) == result.C  # CHARGE
        assert int((kinds == 4).sum()) == 10  # DELIVER
        assert int((kinds == 3).sum()) == 10  # PICKUP
        assert np.all(np.diff(ev[:, 0].astype(np.int64)) >= 0)
        # a window of events is the matching slice
        mid = rp.frames // 2
        part = rp.events(mid, rp.frames)
        assert len(part) == int((ev[:, 0] >= mid).sum())
        assert rp.cells_at(0).sum() == 10 and rp.cells_at(rp.frames - 1).sum() == 0


def test_opening_reads_no_chunk_and_frames_read_one(paper_run, monkeypatch):
    path, _ = paper_run
    calls = []
    real = _core.decode_chunk
    monkeypatch.setattr(_core, "decode_chunk", lambda data, limit: calls.append(len(data)) or real(data, limit))
    with Replay(path) as rp:
        assert calls == []
        rp.frame(rp.frames - 1)
        assert len(calls) == 1
        rp.frame(rp.frames - 1)
        assert len(calls) == 1  # cached


def test_chunk_bytes_is_the_documented_layout(paper_run):
    path, _ = paper_run
    with Replay(path) as rp:
        raw = rp.chunk_bytes(0)
        first, secs = sections(raw)
        assert (first, secs["x"].shape[1]) == (0, 3)
        assert raw == zlib.decompress(rp.chunk_raw(0))
        assert len(raw) == rp.footer["chunks"][0]["raw_length"]
        ch = rp.chunk(0)
        for key, arr in secs.items():
            np.testing.assert_array_equal(ch[key] if key != "state_raw" else ch["state"] | (ch["marked"] << 7), arr)


def test_trajectory_follows_the_recorded_positions(paper_run):
    path, _ = paper_run
    with Replay(path) as rp:
        pts = rp.trajectory(0, 0)
        fr0 = rp.frame(0)
        assert tuple(pts[0]) == (float(fr0["x"][0]), float(fr0["y"][0]))
        assert len(pts) >= 3  # down the spur, along the highway, up to a service point
        # the route ends where the robot next stops (loading at its first cell's service point)
        cell = 11
        svc = rp.layout["cells"][cell]["service"]
        assert np.allclose(pts[-1], svc, atol=1e-3)


def test_live_frames_are_the_engines_codec():
    sim = multibots.Simulation(paper(3))
    sim.step(400)
    first, secs = sections(sim.frame_chunk())
    assert first == sim.t == 400
    pos = np.asarray(sim.positions)
    np.testing.assert_array_equal(secs["x"][0], pos[:, 0].astype(np.float32))
    np.testing.assert_array_equal(secs["y"][0], pos[:, 1].astype(np.float32))
    # The documented quantisation: energy as a fraction of full in 16 bits, heading in 256ths
    # of a turn, the state code with 128 added when marked to charge.
    np.testing.assert_array_equal(secs["energy_u16"][0], np.rint(np.clip(np.asarray(sim.energy) / 10.0, 0, 1) * 65535))
    turns = np.asarray(sim.headings) / (2 * math.pi)
    np.testing.assert_array_equal(secs["heading_u8"][0], np.mod(np.rint(turns * 256), 256))
    np.testing.assert_array_equal(secs["state_raw"][0], np.asarray(sim.states) | (np.asarray(sim.marked) << 7))
    assert secs["counters"][0].tolist() == [sim.S, sim.C, sim.delivered]
    assert len(secs["events"]) == 0
    header = sim.viewer_header()
    assert header["state_names"] == list(multibots.STATE_NAMES)
    assert header["event_names"]["5"] == "WAIT" and header["robots"] == 3


def test_the_engine_exports_the_documented_codec_numbers():
    # The numbers of docs/replay-format.md, written out here: the reader and the viewer take
    # them from the engine, so changing one there is a new format version, not a quiet edit.
    assert (_core.REPLAY_MAGIC, _core.REPLAY_VERSION, _core.BYTES_PER_ROBOT_STEP) == (b"MBREPLAY", 1, 12)
    assert (_core.MARKED, _core.STATE_MASK, _core.HEADING_STEPS, _core.ENERGY_SCALE) == (0x80, 0x7F, 256, 65535)


def test_a_chunk_that_inflates_past_its_size_is_refused(paper_run, tmp_path):
    # A decompression bomb: a chunk that inflates to far more than its frames can hold is
    # refused with one line, before it can fill the memory.
    path, _ = paper_run
    with Replay(path) as rp:
        info = rp.chunk_info(0)
        bomb = zlib.compress(bytes(64 << 20), 9)
        assert len(bomb) < 100_000
        data = bytearray(path.read_bytes())
        head = bytes(data[:info["offset"]])
        # The footer of a replay of the first chunk alone: without the whole run's queues.
        footer = {k: v for k, v in rp.footer.items() if k != "queues"}
        footer["queues"] = [[] for _ in rp.resources]
        footer["chunks"] = [{**rp.footer["chunks"][0], "length": len(bomb)}]
        footer["frames"] = info["frames"]
        fb = __import__("json").dumps(footer).encode()
        out = tmp_path / "bomb.mbr"
        out.write_bytes(head + bomb + fb + struct.pack("<QQ", len(head) + len(bomb), len(fb)))
    with Replay(out) as bad:
        with pytest.raises(ReplayError) as e:
            bad.frame(0)
    msg = str(e.value)
    assert "chunk 0 inflates to more than" in msg and "\n" not in msg


def _corrupt(src, dst, fn):
    data = bytearray(src.read_bytes())
    fn(data)
    dst.write_bytes(bytes(data))
    return dst


@pytest.mark.parametrize("name, change, message", [
    ("magic", lambda d: d.__setitem__(slice(0, 8), b"NOTAREPL"), "bad magic"),
    ("version", lambda d: d.__setitem__(slice(8, 12), struct.pack("<I", 7)), "version 7"),
    ("truncated", lambda d: d.__delitem__(slice(len(d) - 40, len(d))), "footer"),
    ("header", lambda d: d.__setitem__(slice(16, 18), b"\xff\xfe"), "header"),
])
def test_bad_files_give_one_line_errors(paper_run, tmp_path, name, change, message):
    bad = _corrupt(paper_run[0], tmp_path / f"{name}.mbr", change)
    with pytest.raises(ReplayError) as err:
        Replay(bad)
    text = str(err.value)
    assert str(bad) in text and message in text and "\n" not in text
    assert isinstance(err.value, ValueError) and isinstance(err.value, multibots.MultibotsError)


def test_a_corrupt_chunk_is_reported_when_read(paper_run, tmp_path):
    with Replay(paper_run[0]) as rp:
        off = rp.chunk_info(0)["offset"]
    bad = _corrupt(paper_run[0], tmp_path / "chunk.mbr", lambda d: d.__setitem__(slice(off + 2, off + 40), b"\0" * 38))
    with Replay(bad) as rp:
        with pytest.raises(ReplayError, match=r"chunk 0"):
            rp.frame(0)


def test_missing_and_empty_files(tmp_path):
    with pytest.raises(ReplayError, match="no such replay file"):
        Replay(tmp_path / "nope.mbr")
    (tmp_path / "empty.mbr").write_bytes(b"")
    with pytest.raises(ReplayError, match="not a MultiBots replay"):
        Replay(tmp_path / "empty.mbr")


def test_out_of_range_frames_and_chunks(paper_run):
    with Replay(paper_run[0]) as rp:
        with pytest.raises(IndexError):
            rp.frame(rp.frames)
        with pytest.raises(IndexError):
            rp.chunk(rp.chunk_count)
        with pytest.raises(IndexError):
            rp.frame(-1)
