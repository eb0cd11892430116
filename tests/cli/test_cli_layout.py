"""``multibots layout``: draw, ``generate`` and ``check``, and their one-line errors."""

from __future__ import annotations

import json

import pytest

from multibots.layouts import check_layout_file


def test_layout_command(cli, tmp_path):
    for name in ("layout.png", "layout.svg"):
        p = cli("layout", "--out", tmp_path / name)
        assert p.returncode == 0, p.stderr
        assert (tmp_path / name).stat().st_size > 1000
    p = cli("layout", "--json")
    assert len(json.loads(p.stdout)["cells"]) == 80


def test_bad_layout_output(cli, tmp_path):
    cli.assert_one_line_error(cli("layout", "--out", tmp_path / "x.txt"), "--out", "x.txt")


def test_output_that_is_not_a_regular_file_is_refused(cli, tmp_path):
    folder = tmp_path / "fig.png"
    folder.mkdir()
    cli.assert_one_line_error(cli("layout", "--out", folder), "fig.png", "is a directory")
    assert folder.is_dir()
    cli.assert_one_line_error(cli("layout", "generate", "--out", "/dev/null"), "/dev/null", "not a regular file")


def test_cli_generate_writes_a_checked_file(cli, tmp_path):
    out = tmp_path / "wh.toml"
    p = cli(
        "layout",
        "generate",
        "--group-rows",
        "3",
        "--group-cols",
        "4",
        "--group-size",
        "1x6",
        "--chargers",
        "2",
        "--out",
        str(out),
    )
    assert p.returncode == 0, p.stderr
    assert "wrote" in p.stdout and "20 crossings" in p.stdout
    data = check_layout_file(out)
    assert len(data["cells"]) == 3 * 4 * 6
    assert len(data["chargers"]) == 2
    assert not list(tmp_path.glob(".*.tmp")), "no temporary file left behind"
    p = cli("layout", "check", str(out))
    assert p.returncode == 0 and "ok" in p.stdout
    # The drawing command takes a layout file too.
    p = cli("layout", "--layout", str(out), "--json")
    assert p.returncode == 0, p.stderr
    assert json.loads(p.stdout)["cells"] == data["cells"]


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--group-rows", "0"], "--group-rows = 0: must be at least 1"),
        (["--group-cols", "0"], "--group-cols = 0: must be at least 1"),
        (["--group-size", "3x4"], "--group-size = 3x4: must be 1 or 2"),
        (["--group-size", "2by4"], "--group-size = '2by4': expected WxH"),
        (["--chargers", "12"], "--chargers = 12: must be between 1 and 11"),
        (["--chargers", "23", "--charger-walls", "top-bottom"], "--chargers = 23: must be between 1 and 22"),
        (["--chargers", "29", "--charger-walls", "all"], "--chargers = 29: must be between 1 and 28"),
        (["--charger-walls", "sides"], '--charger-walls = "sides": expected one of top, top-bottom, all'),
        (["--aisle", "0"], "--aisle = 0: must be greater than 0"),
    ],
)
def test_cli_generate_errors_are_one_line_exit_2(cli, tmp_path, args, message):
    p = cli("layout", "generate", "--out", str(tmp_path / "x.toml"), *args)
    assert p.returncode == 2, (p.stdout, p.stderr)
    assert p.stderr.count("\n") == 1 and message in p.stderr, p.stderr
    assert not (tmp_path / "x.toml").exists()


def test_layout_generate_has_a_flag_for_every_layout_generate_field(cli, tmp_path) -> None:
    import re
    from pathlib import Path

    schema = json.loads((Path(__file__).resolve().parents[2] / "docs/schema/scenario.schema.json").read_text())
    fields = set(schema["$defs"]["LayoutParams"]["properties"])
    help_text = cli("layout", "generate", "--help").stdout
    flags = {f.replace("-", "_") for f in re.findall(r"--([a-z][a-z-]+)", help_text)}
    # The group's two sizes share --group-size (ACROSSxDOWN).
    assert not fields - flags - {"group_width", "group_height"}, fields - flags
    assert "group_size" in flags
    out = tmp_path / "g.toml"
    p = cli("layout", "generate", "--out", out, "--group-rows", "4", "--unloading-rows", "2", "--aisles", "alternate")
    assert p.returncode == 0, p.stderr
    text = out.read_text()
    assert "unloading_rows = 2" in text and 'aisles = "alternate"' in text


def test_cli_generate_puts_chargers_on_every_wall(cli, tmp_path):
    out = tmp_path / "walls.toml"
    p = cli("layout", "generate", "--out", out, "--chargers", "18", "--charger-walls", "all")
    assert p.returncode == 0, p.stderr
    assert "18 chargers" in p.stdout and 'charger_walls = "all"' in out.read_text()
    data = check_layout_file(out)
    x0, y0, x1, y1 = data["bounds"]
    charger_xy = [(n["x"], n["y"]) for n in data["nodes"] if n["kind"] == "charger"]
    # Outside the warehouse on each of its four sides, one charger to a place.
    assert len(set(charger_xy)) == 18
    sides = {(x < x0, x > x1, y < y0, y > y1) for x, y in charger_xy}
    assert sides == {tuple(k == j for k in range(4)) for j in range(4)}
