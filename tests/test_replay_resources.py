"""A replay's resources (docs/replay-format.md, footer): the run's report and bottleneck, and
each reported resource's queue frame by frame, against the same run stepped live."""

from __future__ import annotations

import json
import struct

import pytest

import multibots
from multibots.replay import Replay, ReplayError

#: Every goods to one unloading zone of a small warehouse, more orders than it takes.
ONE_ZONE = {
    "robots": 40, "tasks": [], "unload": "first", "allocator": "nearest", "placement": "spread",
    "layout_generate": {"group_rows": 3, "group_cols": 4, "chargers": 9, "unloading_rows": 1, "aisles": "alternate"},
    "charging": {"chargers": "shared"},
    "orders": {"rate": 1.0, "horizon": 600, "restock": 50, "seed": 5},
}


@pytest.fixture(scope="module")
def one_zone(tmp_path_factory):
    path = tmp_path_factory.mktemp("resources") / "one-zone.mbr"
    scenario = multibots.Scenario.from_dict(ONE_ZONE)
    return scenario, path, multibots.simulate(scenario, record=path)


def test_the_footer_holds_the_runs_report_and_each_queue_step_by_step(one_zone):
    scenario, path, result = one_zone
    sim = multibots.Simulation(scenario)
    names = [n["name"] for n in sim.layout["nodes"]]
    with Replay(path) as rp:
        assert rp.resources == result.resources and rp.bottleneck == result.bottleneck
        assert rp.bottleneck is not None and rp.bottleneck["kind"] == "unloading"
        assert rp.queues_at(0) == [0] * len(rp.resources)
        queued = 0
        for f in range(1, rp.frames):
            sim.step()
            nodes, chargers = sim.queues()
            by_name = {names[k]: c for k, c in nodes.items()}
            by_name.update({f"{names[u]}->{names[v]}": c for (u, v), c in sim.lane_queues().items()})
            live = [chargers if u["kind"] == "charger-queue" else by_name.get(u["node"], 0) for u in rp.resources]
            assert rp.queues_at(f) == live, f
            queued += sum(live)
        assert queued > 0
        assert any(u["kind"] == "lane" for u in rp.resources), rp.resources
        # The longest queue the report names is the longest the frames hold.
        for j, u in enumerate(rp.resources):
            assert max(rp.queue_changes()[j][1::2], default=0) == u["longest_queue"], u


def _with_footer(src, dst, change):
    data = src.read_bytes()
    off, length = struct.unpack("<QQ", data[-16:])
    footer = json.loads(data[off:off + length])
    change(footer)
    fb = json.dumps(footer).encode()
    dst.write_bytes(data[:off] + fb + struct.pack("<QQ", off, len(fb)))
    return dst


def test_a_replay_without_them_has_no_resources(one_zone, tmp_path):
    def drop(f):
        for key in ("resources", "bottleneck", "queues"):
            del f[key]

    with Replay(_with_footer(one_zone[1], tmp_path / "old.mbr", drop)) as rp:
        assert (rp.resources, rp.bottleneck, rp.queues_at(5), rp.queue_changes()) == ([], None, [], [])


@pytest.mark.parametrize("name, change, message", [
    ("short", lambda f: f["queues"].pop(), "one list per resource"),
    ("odd", lambda f: f["queues"][0].append(3), "pairs"),
    ("order", lambda f: f["queues"].__setitem__(0, [5, 1, 3, 2]), "out of order"),
    ("count", lambda f: f["queues"].__setitem__(0, [3, -1]), "negative"),
    ("kind", lambda f: f["bottleneck"].update(kind="moon"), "'kind'"),
    ("busy", lambda f: f["resources"][0].update(busy=1e400), "'busy'"),
    ("relieve", lambda f: f["bottleneck"].update(relieve=[1]), "'relieve'"),
])
def test_a_wrong_footer_is_one_line(one_zone, tmp_path, name, change, message):
    bad = _with_footer(one_zone[1], tmp_path / f"{name}.mbr", change)
    with pytest.raises(ReplayError) as err:
        Replay(bad)
    text = str(err.value)
    assert message in text and "\n" not in text, text
