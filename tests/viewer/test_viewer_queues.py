"""Queues and the bottleneck in the viewer (docs/viewer.md): on a warehouse whose goods all
go to one unloading zone, the page shows the robots queued at each resource, frame by frame,
and names the bottleneck in the line `multibots run` prints, in a replay and live."""

from __future__ import annotations

import io
import json

import pytest
from PIL import Image

import multibots
from multibots.replay import Replay

from viewer_helpers import open_viewer

QUEUE_RGB = (0xE6, 0x51, 0x00)

#: 60 robots, a small generated warehouse, every goods to its first unloading zone and more
#: orders than that zone takes: the zone is the bottleneck (docs/metrics.md).
ONE_ZONE = {
    "robots": 60, "tasks": [], "unload": "first", "allocator": "nearest", "placement": "spread",
    "layout_generate": {"group_rows": 3, "group_cols": 4, "chargers": 9, "unloading_rows": 1, "aisles": "alternate"},
    "charging": {"chargers": "shared"},
    "orders": {"rate": 1.0, "horizon": 1500, "restock": 50, "seed": 3},
}


@pytest.fixture(scope="module")
def one_zone(cli, tmp_path_factory):
    """The case run and recorded by `multibots run`: (scenario, replay path, the bottleneck
    line it printed without its label, the unloading zone's name)."""
    root = tmp_path_factory.mktemp("queues")
    scenario = multibots.Scenario.from_dict(ONE_ZONE)
    toml, path = root / "one-zone.toml", root / "one-zone.mbr"
    toml.write_text(scenario.to_toml(), encoding="utf-8")
    p = cli("run", str(toml), "--record", str(path))
    assert p.returncode == 0, p.stderr
    lines = [ln for ln in p.stdout.splitlines() if ln.startswith("bottleneck ")]
    assert len(lines) == 1, p.stdout
    line = lines[0][len("bottleneck"):].strip()
    zone = multibots.Simulation(scenario).layout
    name = zone["nodes"][zone["unloading"][0]]["name"]
    assert line.startswith(f"unloading {name}: busy "), line
    return scenario, path, line, name


def _frame_with_a_queue(rp, name):
    """A frame where the zone has at least two robots queued, and its index among resources."""
    j = next(k for k, u in enumerate(rp.resources) if u["kind"] == "unloading" and u["node"] == name)
    for f in range(rp.frames // 2, rp.frames):
        if rp.queues_at(f)[j] >= 2:
            return f, j
    raise AssertionError("the zone never had a queue of two")


def test_the_replay_meta_carries_the_runs_report_and_the_clis_line(one_zone):
    from multibots.viewer import Viewer

    scenario, path, line, _ = one_zone
    result = multibots.simulate(scenario)
    with Viewer.for_replay(str(path)) as v:
        meta = v.source.meta
        assert meta["resources"] == result.resources
        assert meta["bottleneck"] == result.bottleneck
        assert meta["bottleneck_line"] == line
        assert len(meta["queues"]) == len(result.resources)


def test_a_live_run_sends_the_queues_as_they_are_and_the_clis_line_at_the_end(one_zone):
    # The live path (Simulation.queues, each frame) and the recorded one (the footer's
    # changes) must agree on every queue both report, frame after frame.
    from multibots.viewer import Viewer

    scenario, path, line, _ = one_zone
    v = Viewer.for_simulation(multibots.Simulation(scenario), paused=True)
    runner = v.source.runner
    try:
        with Replay(path) as rp:
            index = {(u["kind"], u["node"]): k for k, u in enumerate(rp.resources)}
            compared = queued = 0
            while True:
                with runner.lock:
                    runner.sim.step(97)
                    runner._publish_locked()
                msg = json.loads(runner.message)
                recorded = rp.queues_at(msg["t"])
                for u, q in zip(msg["resources"], msg["queue"]):
                    k = index.get((u["kind"], u["node"]))
                    if k is not None:
                        assert q == recorded[k], (msg["t"], u)
                        compared += 1
                        queued += q > 0
                if msg["done"]:
                    break
        assert compared > 50 and queued > 10, (compared, queued)
        assert msg["bottleneck_line"] == line
    finally:
        v.close()


def test_a_replay_shows_each_queue_on_the_map_and_names_the_bottleneck(page, one_zone):
    from multibots.viewer import Viewer

    _, path, line, name = one_zone
    with Replay(path) as rp:
        f, j = _frame_with_a_queue(rp, name)
        counts = rp.queues_at(f)
        resources = rp.resources
    with Viewer.for_replay(str(path)) as v:
        open_viewer(page, v)
        assert page.locator("#bottleneck-line").inner_text().strip() == line
        assert page.locator("#bottleneck-head").inner_text().strip() == "bottleneck"
        page.evaluate(f"() => window.mbViewer.seek({f})")
        # Beside the map: every resource with robots queued, with how many.
        shown = page.evaluate("""() => [...document.querySelectorAll('#queue-list dd')]
            .map(dd => [dd.dataset.kind, dd.dataset.node, Number(dd.textContent)])""")
        want = [[u["kind"], u["node"], c] for u, c in zip(resources, counts) if c > 0]
        assert sorted(shown) == sorted(want)
        # On the map: a badge at each of those with a node (the chargers' queue has none).
        badges = page.evaluate("() => window.mbViewer.badges()")
        assert sorted([b["kind"], b["node"], b["count"]] for b in badges) == sorted(
            w for w in want if w[0] != "charger-queue")
        # Queues reach back along the lanes into the zone: their badges sit by the lanes.
        assert any(b["kind"] == "lane" for b in badges), badges
        zone = next(b for b in badges if b["node"] == name)
        assert zone["count"] == counts[j] >= 2
        shot = Image.open(io.BytesIO(page.screenshot())).convert("RGB")
        px = shot.getpixel((int(zone["x"] + 2), int(zone["y"] + zone["h"] / 2)))
        assert all(abs(a - b) <= 3 for a, b in zip(px, QUEUE_RGB)), px
        # Before the first step nobody queues.
        page.evaluate("() => window.mbViewer.seek(0)")
        assert page.evaluate("() => window.mbViewer.badges()") == []
        assert page.locator("#queue-none").inner_text().strip() == "no robot queued now"


def test_a_live_run_shows_the_queues_now_and_at_its_end_the_clis_bottleneck(page, one_zone):
    from multibots.viewer import Viewer

    scenario, _, line, _ = one_zone
    v = Viewer.for_simulation(multibots.Simulation(scenario), speed=64.0, paused=True)
    runner = v.source.runner
    v.start()
    try:
        open_viewer(page, v)
        with runner.lock:
            runner.sim.step(700)
            names = [n["name"] for n in runner.sim.layout["nodes"]]
            nodes, chargers = runner.sim.queues()
            lanes = runner.sim.lane_queues()
            result = runner.sim.result()
            runner._publish_locked()
        page.wait_for_function("() => window.mbViewer.state().frame === 700")
        now = {names[k]: c for k, c in nodes.items()}
        now.update({f"{names[u]}->{names[v]}": c for (u, v), c in lanes.items()})
        want = sorted([u["kind"], u["node"], chargers if u["kind"] == "charger-queue" else now.get(u["node"], 0)]
                      for u in result.resources)
        want = [w for w in want if w[2] > 0]
        assert want, "robots queue at step 700"
        shown = page.evaluate("""() => [...document.querySelectorAll('#queue-list dd')]
            .map(dd => [dd.dataset.kind, dd.dataset.node, Number(dd.textContent)])""")
        assert sorted(shown) == want
        assert page.locator("#bottleneck-head").inner_text().strip() == "bottleneck so far"
        page.click("#btn-play")
        page.wait_for_function("() => window.mbViewer.state().done", timeout=120_000)
        page.wait_for_function("() => document.getElementById('bottleneck-head').textContent === 'bottleneck'")
        assert page.locator("#bottleneck-line").inner_text().strip() == line
    finally:
        v.close()
