"""`multibots render` on the command line: export, bad input, and the missing 'render' extra."""

from __future__ import annotations

import subprocess
import sys

import pytest
from PIL import Image


@pytest.mark.parametrize("args, words", [
    (["render", "REPLAY", "--out", "x.avi"], [".mp4 or .gif"]),
    (["render", "REPLAY", "--out", "x.gif", "--fps", "0"], ["--fps"]),
    (["render", "REPLAY", "--out", "x.gif", "--from", "999999"], ["--from", "999999"]),
    (["render", "REPLAY", "--out", "x.gif", "--from", "5", "--to", "2"], ["--to"]),
    (["render", "REPLAY", "--out", "x.gif", "--scale", "100"], ["--scale"]),
    (["render", "REPLAY", "--out", "nofolder/x.gif"], ["nofolder"]),
    (["render", "missing.mbr", "--out", "x.gif"], ["missing.mbr"]),
])
def test_bad_input_is_one_line_and_exit_2(cli, args, words, small_run, tmp_path):
    args = [str(small_run[0]) if a == "REPLAY" else a for a in args]
    cli.assert_one_line_error(cli(*args, cwd=tmp_path), *words)
    assert not (tmp_path / "x.gif").exists()


def test_output_that_is_not_a_regular_file_is_refused(cli, small_run, tmp_path):
    (tmp_path / "x.gif").mkdir()
    cli.assert_one_line_error(cli("render", small_run[0], "--out", tmp_path / "x.gif"), "x.gif", "is a directory")


def test_render_gif_from_the_command_line(cli, small_run, tmp_path):
    out = tmp_path / "run.gif"
    proc = cli("render", small_run[0], "--out", out, "--from", "5", "--to", "34", "--fps", "10", "--quiet")
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


def test_without_the_render_extra_the_error_names_it(small_run, tmp_path):
    # Playwright made unimportable, as in a core install ("pip install multibots").
    code = (
        "import sys; sys.modules['playwright'] = None\n"
        "from multibots.cli import main\n"
        f"main(['render', {str(small_run[0])!r}, '--out', {str(tmp_path / 'x.gif')!r}])"
    )
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert p.returncode == 2, (p.stdout, p.stderr)
    assert p.stderr == "multibots render needs the 'render' extra: pip install 'multibots[render]'\n"
    assert not list(tmp_path.iterdir())


def _legend_has(gif, colour: str) -> bool:
    """Whether the legend (the strip below the floor) of the first frame draws with ``colour``:
    more than a few pixels of it (the edge of another icon may fall on it in the palette)."""
    want = tuple(int(colour[i:i + 2], 16) for i in (1, 3, 5))
    with Image.open(gif) as im:
        im.seek(0)
        rgb = im.convert("RGB")
        w, h = rgb.size
        strip = rgb.crop((0, h - 40, w, h))
        return sum(n for n, c in strip.getcolors(w * 40) if c == want) > 8


def test_people_are_in_the_legend_of_a_run_with_people_only(cli, small_run, tmp_path):
    import multibots

    replay = tmp_path / "people.mbr"
    multibots.simulate(multibots.Scenario.from_toml("scenarios/people.toml"), record=str(replay))
    for source, people in ((replay, True), (small_run[0], False)):
        out = tmp_path / f"{people}.gif"
        proc = cli("render", source, "--out", out, "--from", "5", "--to", "6", "--quiet")
        assert proc.returncode == 0, proc.stderr
        # The person's shoulders and the warning zone's amber (draw.js COLOURS).
        assert _legend_has(out, "#2b6cb0") is people and _legend_has(out, "#e6a000") is people
