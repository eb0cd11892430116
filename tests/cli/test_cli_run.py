"""``multibots run``: quick runs, files, the JSON shape, exit codes, and every bad input of issue 2."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from multibots import Scenario, simulate
from multibots.result import LIFELONG_KEYS

from oracle.geometry import formula_t

ROOT = Path(__file__).resolve().parents[2]


def test_quick_run_json(cli):
    p = cli("run", "--robots", "3", "--goods", "11,8,39,28,53,1,69,42,79,6", "--json")
    assert p.returncode == 0, p.stderr
    lines = p.stdout.strip().splitlines()
    assert len(lines) == 1
    out = json.loads(lines[0])
    expected = simulate(Scenario.paper(robots=3, goods=[11, 8, 39, 28, 53, 1, 69, 42, 79, 6]))
    assert {k: out[k] for k in ("T", "S", "C", "outcome", "steps", "delivered")} == {
        "T": expected.T, "S": expected.S, "C": expected.C, "outcome": "complete", "steps": expected.T, "delivered": 10,
    }


def test_quick_run_flags(cli, tmp_path):
    p = cli(
        "run",
        "--robots",
        "1",
        "--goods",
        "42",
        "--starts",
        "C",
        "--unload",
        "O",
        "--margin",
        "8",
        "--step-limit",
        "5000",
        "--json",
        "--record",
        str(tmp_path / "r.mbr"),
    )
    assert p.returncode == 0, p.stderr
    assert json.loads(p.stdout)["T"] == formula_t(42, "C", "O")
    assert (tmp_path / "r.mbr").stat().st_size > 0


def test_run_scenario_file_and_table(cli, tmp_path):
    f = tmp_path / "s.toml"
    f.write_text(Scenario.paper(robots=1, goods=[42]).to_toml())
    p = cli("run", str(f))
    assert p.returncode == 0, p.stderr
    assert "T (steps)  726" in p.stdout
    # Flags override the file.
    p = cli("run", str(f), "--goods", "11", "--json")
    assert json.loads(p.stdout)["T"] == formula_t(11)


# Every bad input of issue 2, point 4: (TOML text or None for a CLI-only case, expected fragments).
BAD_FILES = {
    "unknown key": ("tasks = [1]\nrobts = 3\n", ["unknown field `robts`"]),
    "unknown nested key": ("tasks = [1]\n[robot]\nsped = 4.0\n", ["robot", "unknown field `sped`"]),
    "wrong type": ('tasks = [1]\nrobots = "three"\n', ["robots", '"three"']),
    "wrong type nested": ('tasks = [1]\n[robot]\nspeed = "fast"\n', ["robot.speed", '"fast"']),
    "zero speed": ("tasks = [1]\n[robot]\nspeed = 0.0\n", ["robot.speed = 0"]),
    "negative speed": ("tasks = [1]\n[robot]\nspeed = -4.0\n", ["robot.speed = -4"]),
    "zero radius": ("tasks = [1]\n[robot]\nradius = 0.0\n", ["robot.radius = 0"]),
    "negative radius": ("tasks = [1]\n[robot]\nradius = -1.0\n", ["robot.radius = -1"]),
    "zero consumption": ("tasks = [1]\n[robot]\nconsumption = 0.0\n", ["robot.consumption = 0"]),
    "negative charge rate": ("tasks = [1]\n[robot]\ncharge_rate = -0.05\n", ["robot.charge_rate = -0.05"]),
    "zero loading": ("tasks = [1]\n[dwell]\nloading = 0\n", ["dwell.loading = 0"]),
    "negative unloading": ("tasks = [1]\n[dwell]\nunloading = -20\n", ["dwell.unloading", "-20"]),
    "zero step limit": ("tasks = [1]\nstep_limit = 0\n", ["step_limit = 0"]),
    "negative step limit": ("tasks = [1]\nstep_limit = -5\n", ["step_limit", "-5"]),
    "threshold at full": ("tasks = [1]\n[robot]\nthreshold = 10.0\n", ["robot.threshold = 10"]),
    "threshold above full": ("tasks = [1]\n[robot]\nthreshold = 12.0\nenergy_full = 10.0\n", ["robot.threshold = 12"]),
    "cell out of range": ("tasks = [1, 80]\n", ["tasks[1] = 80", "out of range"]),
    "negative cell": ("tasks = [-1]\n", ["tasks[0] = -1"]),
    "repeated cell": ("tasks = [5, 7, 5]\n", ["tasks[2] = 5", "twice"]),
    "empty task list": ("tasks = []\n", ["tasks", "empty"]),
    "missing tasks": ("robots = 2\n", ["missing field `tasks`"]),
    "unknown start": ('tasks = [1]\nrobots = 2\nstarts = ["A", "Z"]\n',
                      ['starts[1] = "Z"', "unknown node (the departure nodes are A, B, C, D, E, F)"]),
    "misspelt start": ('tasks = [1]\nrobots = 2\nstarts = ["A", "b"]\n', ['starts[1] = "b"', 'did you mean "B"?']),
    "unknown unload": ('tasks = [1]\nunload = "Q2"\n',
                       ['unload = "Q2"', 'unknown node: the unloading zones are M, N, O, P, Q, R; or "nearest"']),
    "misspelt strategy": ('tasks = [1]\nallocator = "hungarain"\n',
                          ['allocator = "hungarain"', 'did you mean "hungarian"?']),
    "too many robots": ("tasks = [1]\nrobots = 7\nplacement = \"departure\"\n",
                        ["robots = 7", "more robots than start nodes"]),
    "start not departure": ('tasks = [1]\nrobots = 2\nstarts = ["A", "M"]\n', ['starts[1] = "M"', "departure zone"]),
    "repeated start": ('tasks = [1]\nrobots = 2\nstarts = ["B", "B"]\n', ['starts[1] = "B"', "distinct"]),
    "unload not unloading": ('tasks = [1]\nunload = "A"\n',
                             ['unload = "A"', "is not an unloading zone: the unloading zones are M, N"]),
    "malformed toml": ("tasks = [1, 2\n", ["s.toml", "line"]),
    "unknown layout": ('tasks = [1]\nlayout = "moon"\n', ['layout = "moon"']),
}


@pytest.mark.parametrize("case", sorted(BAD_FILES))
def test_bad_scenario_files(cli, tmp_path, case):
    text, fragments = BAD_FILES[case]
    f = tmp_path / "s.toml"
    f.write_text(text)
    cli.assert_one_line_error(cli("run", f), *fragments)


def test_missing_unreadable_and_directory_files(cli, tmp_path):
    cli.assert_one_line_error(cli("run", tmp_path / "nope.toml"), "nope.toml", "no such scenario file")
    binary = tmp_path / "b.toml"
    binary.write_bytes(b"\xff\xfe\x00tasks")
    cli.assert_one_line_error(cli("run", binary), "b.toml", "UTF-8")
    cli.assert_one_line_error(cli("run", tmp_path), "is a directory")


BAD_FLAGS = {
    "goods not numbers": (["--goods", "11,x"], ["--goods", "11,x"]),
    "goods empty": (["--goods", ","], ["--goods"]),
    "robots zero": (["--robots", "0", "--goods", "1"], ["robots = 0"]),
    "robots not int": (["--robots", "two", "--goods", "1"], ["two"]),
    "negative margin": (["--goods", "1", "--margin", "-1"], ["collision.margin = -1"]),
    "bad start": (["--robots", "1", "--goods", "1", "--starts", "M"], ["starts[0] = \"M\""]),
    "bad unload": (["--goods", "1", "--unload", "B"], ["unload = \"B\""]),
    "cell out of range": (["--goods", "1,99"], ["tasks[1] = 99"]),
    "zero step limit": (["--goods", "1", "--step-limit", "0"], ["step_limit = 0"]),
    "nothing to run": ([], ["--goods"]),
    "unknown option": (["--bogus"], ["--bogus"]),
    "allocator that is no allocator": (["--goods", "1", "--allocator", "os:getcwd"], ["allocator = \"os:getcwd\""]),
    "unknown allocator": (["--goods", "1", "--allocator", "fastest"], ["allocator = \"fastest\""]),
    "margin not finite": (["--goods", "1", "--margin", "nan"], ["--margin", "nan"]),
}


@pytest.mark.parametrize("case", sorted(BAD_FLAGS))
def test_bad_flags(cli, case):
    args, fragments = BAD_FLAGS[case]
    cli.assert_one_line_error(cli("run", *args), *fragments)


# --- exit codes and the JSON shape -------------------------------------------------------


def test_an_incomplete_run_exits_with_code_3_and_says_so(cli):
    p = cli("run", "--goods", "11,8", "--step-limit", "100", "--json")
    assert p.returncode == 3, (p.stdout, p.stderr)
    out = json.loads(p.stdout)
    assert out["outcome"] == "incomplete" and out["T"] is None and out["steps"] == 100
    assert p.stderr.strip() == "multibots: the run ended incomplete: 0 of 2 goods delivered in 100 steps (exit code 3)"
    table = cli("run", "--goods", "11,8", "--step-limit", "100")
    assert table.returncode == 3 and "outcome    incomplete" in table.stdout
    # A complete run and a lifelong run that reaches its horizon exit 0.
    assert cli("run", "--goods", "42", "--json").returncode == 0
    assert cli("run", ROOT / "scenarios" / "warehouse-1000.toml", "--horizon", "50", "--json").returncode == 0


def _keys(d, prefix=""):
    """Every key path of a nested dict, except the per-robot lists' contents."""
    out = set()
    for k, v in d.items():
        out.add(prefix + k)
        if isinstance(v, dict):
            out |= _keys(v, prefix + k + ".")
    return out


def test_json_has_one_shape_for_every_run(cli):
    plain = json.loads(cli("run", "--goods", "11,8,39", "--json").stdout)
    lifelong = json.loads(cli("run", ROOT / "scenarios" / "warehouse-1000.toml", "--horizon", "60", "--json").stdout)
    assert _keys(plain) == _keys(lifelong)
    assert set(plain["lifelong"]) == set(LIFELONG_KEYS) == set(lifelong["lifelong"])
    assert all(v is None for v in plain["lifelong"].values())
    assert lifelong["lifelong"]["ordered"] >= lifelong["delivered"]
    assert len(lifelong["robots"]["distance"]) == 1000


def test_json_floats_are_rounded(cli):
    p = cli("run", "--robots", "3", "--goods", "11,8,39,28,53,1,69,42,79,6", "--json")
    out = json.loads(p.stdout)
    exact = simulate(Scenario.paper(robots=3))
    # The engine's sums carry float noise (8.080000000000169); the JSON does not.
    assert any(len(repr(float(e))) > 12 for e in exact.energy_used), "the test needs a noisy value"
    assert out["robots"]["energy_used"] == [round(float(e), 6) for e in exact.energy_used]
    for value in out["robots"]["energy_used"] + out["robots"]["distance"]:
        assert len(repr(value).split(".")[1]) <= 6, value
    # Not a step of precision lost that a reader could need.
    assert out["robots"]["energy_used"] == pytest.approx(exact.energy_used.tolist(), abs=1e-6)


def test_the_help_documents_the_exit_codes(cli):
    for args in (["--help"], ["run", "--help"]):
        text = " ".join(cli(*args).stdout.split())
        assert "3 the run did not complete" in text and "2 bad input" in text and "130 interrupted" in text


OVERLOADED = """\
robots = 30
tasks = []
placement = "spread"
unload = "nearest"
[layout_generate]
group_rows = 3
group_cols = 5
group_width = 2
group_height = 6
chargers = 4
unloading_rows = 2
[charging]
chargers = "shared"
[robot]
consumption = 0.00002
[orders]
rate = 0.5
horizon = 4000
restock = 100
seed = 1
"""


def test_a_lifelong_run_past_its_fleet_says_how_to_find_the_rate_it_carries(cli, tmp_path):
    f = tmp_path / "w.toml"
    f.write_text(OVERLOADED)
    out = cli("run", f)
    assert out.returncode == 0, out.stderr
    line = next(s for s in out.stdout.splitlines() if s.startswith("backlog"))
    assert "more demand than this fleet carries" in line and f"multibots capacity {f}" in line
    # Within what the fleet carries: no such line.
    f.write_text(OVERLOADED.replace("rate = 0.5", "rate = 0.01"))
    out = cli("run", f)
    assert out.returncode == 0 and "backlog" not in out.stdout, out.stdout


def test_robots_stranding_while_the_rest_deliver_exit_3_with_when_and_where(cli, tmp_path):
    # A layout nobody tuned whose threshold charging strands robots one by one from step
    # ~6,700 while the rest keep delivering (crates/multibots-core/tests/engine/outcomes.rs has the
    # engine's side): the run is not a normal `horizon`.
    scenario = tmp_path / "untuned.toml"
    scenario.write_text(
        'robots = 900\ntasks = []\nplacement = "spread"\nunload = "nearest"\nallocator = "nearest"\n'
        'traffic = "reserve"\n[layout_generate]\ngroup_rows = 14\ngroup_cols = 18\ngroup_width = 1\n'
        'group_height = 5\nchargers = 60\ncharger_walls = "top-bottom"\n[charging]\nchargers = "shared"\n'
        "[robot]\nconsumption = 0.0015\n[orders]\nrate = 1.2\nhorizon = 12000\nrestock = 150\nseed = 13\n"
    )
    p = cli("run", scenario, "--json")
    assert p.returncode == 3, p.stderr
    out = json.loads(p.stdout)
    c = out["collapse"]
    assert out["outcome"] == "stranded" and c["stranded"] == len(out["stranded"]) > 0
    assert "the run ended stranded" in p.stderr
    table = cli("run", scenario)
    assert table.returncode == 3
    line = next(x for x in table.stdout.splitlines() if x.startswith("stranded "))
    assert f"from step {c['step']:,}: {c['stranded']} robots out of energy" in line
    assert f"windows best {c['best']}, last {c['last']}" in line
    assert f"{c['crossings'][0][0]} ({c['crossings'][0][1]})" in line
    assert not c["collapsed"] and c["first_stranded"] == c["step"]


def test_a_task_list_run_whose_robot_strands_says_when_and_where(cli, tmp_path):
    # One robot, the far unloading zone R and a threshold too low to get back: it runs flat
    # at step 2,000 (10 energy at 0.005 a step) and the run ends there.
    s = Scenario.paper(robots=1, goods=[11, 8, 39, 28, 53, 1, 69, 42, 79, 6])
    s = s.replace(unload="R", step_limit=20000, robot={"threshold": 0.3})
    path = tmp_path / "flat.toml"
    path.write_text(s.to_toml())
    p = cli("run", path)
    assert p.returncode == 3, p.stderr
    line = next(x for x in p.stdout.splitlines() if x.startswith("stranded     from"))
    want = "stranded     from step 2,000: 1 robots out of energy, windows best 2, last 2; they stand at "
    assert line.startswith(want), line
    assert line.endswith(" (1)"), line
