"""Property-based fuzzing (Hypothesis) of everything a user hands MultiBots: scenario TOML,
layout files, replay files and command-line flags (issue 16).

The property is the same everywhere: the input is used, or refused with a
:class:`~multibots.MultibotsError` whose message is one short line of printable text; never
another exception, a hang or an abort. ``make test`` runs a bounded number of examples
(profile ``ci``); ``make fuzz`` runs the ``fuzz`` profile with fresh seeds for ten minutes.
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import os
import struct
from pathlib import Path

import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import multibots
from multibots import MultibotsError, Scenario

settings.register_profile("ci", max_examples=60, deadline=None, derandomize=True,
                          suppress_health_check=[HealthCheck.too_slow])
settings.register_profile("fuzz", max_examples=2000, deadline=None,
                          suppress_health_check=[HealthCheck.too_slow])
# MULTIBOTS_FUZZ=fuzz (make fuzz) runs the long profile, with a fresh random seed each time.
settings.load_profile(os.environ.get("MULTIBOTS_FUZZ", "ci"))


def assert_clean(e: BaseException) -> None:
    """A refusal: a MultibotsError with one short printable line."""
    msg = str(e)
    assert isinstance(e, MultibotsError), f"{type(e).__name__}: {msg[:300]}"
    assert msg and "\n" not in msg and len(msg) < 1000, msg[:300]
    assert "\x1b" not in msg, msg[:300]


# ---------------------------------------------------------------- values

NUMBERS = st.one_of(
    st.integers(min_value=-(2**70), max_value=2**70),
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([0, 1, -1, 0.5, 1e-300, 1e300, 2**32, 2**64, 1e7, 12.5, 6]),
)
TEXT = st.one_of(st.text(max_size=20), st.sampled_from(["paper", "M", "A", "\x1b[31m", "x" * 300, "", "nearest",
                                                        "in-turn", "reserve", "original", "spread", "a:b"]))
SCALARS = st.one_of(NUMBERS, TEXT, st.booleans())
VALUES = st.recursive(SCALARS, lambda inner: st.lists(inner, max_size=5) | st.dictionaries(TEXT, inner, max_size=4),
                      max_leaves=12)

TABLES = {
    "charging": ["chargers", "level", "policy"],
    "collision": ["angle", "margin"],
    "cost": ["collision", "distance", "time"],
    "dwell": ["loading", "unloading"],
    "layout_generate": ["aisle", "aisles", "cell", "chargers", "group_cols", "group_height", "group_rows",
                        "group_width", "spur", "unloading_rows"],
    "metrics": ["gridlock", "warmup", "window"],
    "humans": ["count", "decel", "pick", "protective", "px_per_m", "radius", "rest", "seed", "slow", "speed",
               "step_seconds", "tour", "warning"],
    "orders": ["horizon", "rate", "restock", "seed"],
    "robot": ["charge_rate", "consumption", "energy_full", "radius", "speed", "threshold"],
}
TOP = ["allocator", "layout", "placement", "robots", "rules", "starts", "step_limit", "tasks", "traffic", "unload"]


def toml_value(v) -> str:
    """TOML text for a value; NaN and inf as TOML spells them, big ints as they are (TOML
    itself refuses those, which is one of the refusals under test)."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, int):
        return str(v)
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, list):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    return "{" + ", ".join(f"{json.dumps(k)} = {toml_value(x)}" for k, x in v.items()) + "}"


@st.composite
def scenario_text(draw) -> str:
    """A scenario file: the paper's warehouse with a few fields set to anything."""
    fields = {"layout": "paper", "robots": 2, "tasks": [11, 8], "step_limit": 400}
    for key in draw(st.lists(st.sampled_from(TOP), max_size=3, unique=True)):
        fields[key] = draw(st.one_of(VALUES, st.lists(st.integers(-5, 90), max_size=6)))
    lines = [f"{k} = {toml_value(v)}" for k, v in fields.items()]
    for table in draw(st.lists(st.sampled_from(sorted(TABLES)), max_size=2, unique=True)):
        lines.append(f"[{table}]")
        for key in draw(st.lists(st.sampled_from(TABLES[table]), min_size=1, max_size=3, unique=True)):
            lines.append(f"{key} = {toml_value(draw(VALUES))}")
    if draw(st.booleans()):
        lines.append(draw(st.text(max_size=30)))  # and sometimes plain garbage
    return "\n".join(lines) + "\n"


def small_enough(s: Scenario) -> bool:
    """Runs of fuzzed scenarios stay short: a few thousand robot-steps of work at most."""
    d = s.to_dict()
    crowd = (d.get("humans") or {}).get("count", 0)
    return d.get("robots", 0) <= 50 and d.get("orders") is None and d.get("layout_generate") is None and crowd <= 20


@given(scenario_text())
def test_scenario_text_is_used_or_refused_in_one_line(text: str) -> None:
    try:
        s = Scenario.from_toml_str(text, "fuzz.toml")
    except BaseException as e:
        assert_clean(e)
        return
    assert Scenario.from_toml_str(s.to_toml(), "again.toml") == s  # what loads, round-trips
    if small_enough(s):
        try:
            r = multibots.simulate(s.replace(step_limit=min(s.to_dict().get("step_limit", 400), 400)))
        except BaseException as e:
            assert_clean(e)
            return
        assert r.outcome in {"complete", "incomplete", "gridlock", "stranded", "stalled", "livelock",
                             "collapse", "horizon", "deadlock", "fault"}


# ---------------------------------------------------------------- nesting (issue 28)

@st.composite
def nested_toml(draw) -> str:
    """TOML nested anything from 1 to 20,000 deep: arrays, inline tables, dotted keys, table
    headers of many parts, long keys, and brackets hidden in strings and comments."""
    depth = draw(st.one_of(st.integers(1, 40), st.integers(1, 300), st.sampled_from([1000, 20_000])))
    how = draw(st.sampled_from(["array", "table", "mixed", "dotted", "header", "long key", "in strings"]))
    if how == "array":
        body = "x = " + "[" * depth + "1" + "]" * depth
    elif how == "table":
        body = "x = " + "{a = " * depth + "1" + "}" * depth
    elif how == "mixed":
        opens = [draw(st.sampled_from(["[", "{a = ", "[{b = "])) for _ in range(min(depth, 60))]
        closes = ["]" if o == "[" else "}" if o.startswith("{") else "}]" for o in reversed(opens)]
        body = "x = " + "".join(opens) + "1" + "".join(closes)
    elif how == "dotted":
        body = ".".join(draw(st.sampled_from(["a", '"b.c"', "'d'", " e "])) for _ in range(depth)) + " = 1"
    elif how == "header":
        body = "[" + ".".join(["t"] * depth) + "]\nk = [[1]]"
    elif how == "long key":
        body = "k" * (depth * 7) + " = 1"
    else:
        quote3 = "'" * 3
        body = 'x = "' + "[" * depth + '" # ' + "{" * depth + "\ny = " + quote3 + "[{" * depth + quote3
    if draw(st.booleans()):  # unbalanced, or cut short
        body = body[: draw(st.integers(0, len(body)))]
    return body + "\n"


@given(nested_toml(), st.sampled_from(["scenario", "layout", "spec"]))
def test_nesting_is_refused_before_parsing_in_one_line(text: str, where: str) -> None:
    from multibots._io import load_toml
    from multibots.cli._common import named_allocator
    from multibots.exceptions import InputError
    from multibots.layouts import check_layout_text
    from multibots.sweeps.spec import parse_spec

    head = {"scenario": 'layout = "paper"\ntasks = [1]\n', "layout": 'name = "x"\n', "spec": "[axes]\n"}[where]
    try:
        if where == "scenario":
            Scenario.from_toml_str(head + text, "fuzz.toml")
        elif where == "layout":
            check_layout_text(head + text, "fuzz.toml")
        else:
            parse_spec(load_toml(head + text, "fuzz.toml", InputError), "fuzz.toml")
    except BaseException as e:
        assert_clean(e)
    path = Path(os.environ.get("TMPDIR", "/tmp")) / f"mb-fuzz-{os.getpid()}.toml"
    path.write_text(head + text)
    try:
        named_allocator(path)  # reads the file before anything checks it: never raises
    finally:
        path.unlink()


@given(st.integers(1, 3000), st.sampled_from(["dict", "list", "mixed"]), st.sampled_from(["robot", "tasks", "x"]))
def test_nested_dictionaries_are_refused_in_one_line(depth: int, how: str, key: str) -> None:
    value: object = 1.0
    for k in range(depth):
        value = {"a": value} if how == "dict" or (how == "mixed" and k % 2) else [value]
    try:
        Scenario.from_dict({"layout": "paper", "tasks": [1], key: value})
    except BaseException as e:
        assert_clean(e)


# ---------------------------------------------------------------- layout files

@st.composite
def layout_text(draw) -> str:
    from multibots.layouts import generate_layout

    lines = generate_layout(1, 2, "2x2").splitlines()
    for _ in range(draw(st.integers(1, 4))):
        k = draw(st.integers(0, len(lines) - 1))
        how = draw(st.sampled_from(["value", "drop", "dup", "garbage"]))
        if how == "value" and "=" in lines[k]:
            key = lines[k].split("=", 1)[0]
            lines[k] = f"{key}= {toml_value(draw(VALUES))}"
        elif how == "drop":
            del lines[k]
        elif how == "dup":
            lines.insert(k, lines[k])
        else:
            lines[k] = draw(st.text(max_size=40))
        if not lines:
            break
    return "\n".join(lines) + "\n"


@given(layout_text())
def test_layout_text_is_used_or_refused_in_one_line(text: str) -> None:
    from multibots.layouts import check_layout_text

    try:
        data = check_layout_text(text, "fuzz-layout.toml")
    except BaseException as e:
        assert_clean(e)
        return
    assert data["nodes"] and data["cells"]


# ---------------------------------------------------------------- replay files

_REPLAY: dict[str, bytes] = {}


def small_replay(tmp: Path) -> bytes:
    if "r" not in _REPLAY:
        s = Scenario.from_dict({"layout": "paper", "robots": 2, "tasks": [11, 8, 39]})
        path = tmp / "base.mbr"
        multibots.simulate(s, record=path)
        _REPLAY["r"] = path.read_bytes()
    return _REPLAY["r"]


@given(data=st.data())
def test_replay_bytes_are_read_or_refused_in_one_line(tmp_path_factory: pytest.TempPathFactory, data) -> None:
    from multibots.replay import Replay

    tmp = tmp_path_factory.getbasetemp()
    raw = bytearray(small_replay(tmp))
    how = data.draw(st.sampled_from(["flip", "truncate", "splice", "header", "footer"]))
    if how == "flip":
        for _ in range(data.draw(st.integers(1, 8))):
            i = data.draw(st.integers(0, len(raw) - 1))
            raw[i] ^= 1 << data.draw(st.integers(0, 7))
    elif how == "truncate":
        raw = raw[: data.draw(st.integers(0, len(raw) - 1))]
    elif how == "splice":
        i = data.draw(st.integers(0, len(raw)))
        raw[i:i] = data.draw(st.binary(max_size=64))
    else:
        hlen = struct.unpack("<I", raw[12:16])[0]
        foot_off, foot_len = struct.unpack("<QQ", raw[-16:])
        header = json.loads(raw[16:16 + hlen])
        footer = json.loads(raw[foot_off:foot_off + foot_len])
        table = header if how == "header" else footer
        key = data.draw(st.sampled_from(sorted(table)))
        table[key] = data.draw(VALUES)
        hb, fb = json.dumps(header).encode(), json.dumps(footer).encode()
        assume(len(hb) == hlen or how == "footer")
        body = bytes(raw[16 + hlen:foot_off])
        head = bytes(raw[:12]) + struct.pack("<I", len(hb)) + hb + body
        raw = bytearray(head + fb + struct.pack("<QQ", len(head), len(fb)))
    path = tmp / f"fuzz-{how}.mbr"
    path.write_bytes(bytes(raw))
    try:
        with Replay(path) as r:
            for i in range(0, r.frames, max(1, r.frames // 7)):
                r.frame(i)
    except BaseException as e:
        assert_clean(e)


# ---------------------------------------------------------------- command-line flags

FLAG_VALUES = st.one_of(st.sampled_from(["nan", "inf", "-1", "0", "1e400", "99999999999999999999", "1..0", "", "a,b",
                                         "11,8", "\x1b[2J", "x" * 500, "3", "M", "1,1,1", "0.5"]),
                        st.text(max_size=12))


@given(st.lists(st.tuples(st.sampled_from(["--robots", "--goods", "--starts", "--unload", "--margin",
                                           "--step-limit", "--rules", "--traffic", "--allocator"]),
                          FLAG_VALUES), min_size=1, max_size=4, unique_by=lambda t: t[0]))
def test_run_flags_exit_0_2_or_3_with_one_line(flags: list[tuple[str, str]]) -> None:
    from multibots.cli import main

    argv = ["run"]
    for flag, value in flags:
        if flag == "--allocator" and ":" in value:
            value = "nearest"  # code is not what this test fuzzes
        argv += [flag, value]
    if not any(f == "--goods" for f, _ in flags):
        argv += ["--goods", "11,8"]
    argv += ["--step-limit", "300"] if not any(f == "--step-limit" for f, _ in flags) else []
    err, out = io.StringIO(), io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(out), pytest.raises(SystemExit) as done:
        main(argv)
        raise SystemExit(0)
    code = done.value.code or 0
    assert code in (0, 2, 3), (argv, code, err.getvalue()[-500:])
    if code == 2:
        line = err.getvalue().strip()
        assert len(line.splitlines()) == 1 and "Traceback" not in line and "\x1b" not in line, line[:300]
        assert len(line) < 1000


# ---------------------------------------------------------------- every numeric flag (issue 28)

#: Numbers a hostile user types.
HOSTILE_NUMBERS = ["nan", "NaN", "inf", "-inf", "+inf", "infinity", "1e400", "-1e400", "1e308", "99999999999999999999",
                   "18446744073709551616", "4294967296", "4294967295", "2147483648", "-2147483649", "-1", "0", "-0",
                   "0x10", "1_000", "١٢", "²", "9" * 5000, "1e-400", "", " 7 ", "3", "0.5"]
#: Every numeric flag: (command and arguments before, flag, kind, arguments after). The
#: arguments after keep the work short: a run of 300 steps, or a refusal once the flags are
#: read (a missing replay, an unknown rule set) where the command would do long work or
#: serve.
NUMERIC_FLAGS = [
    (["run", "--goods", "11,8"], "--robots", "int", ["--step-limit", "300"]),
    (["run", "--goods", "11,8"], "--margin", "float", ["--step-limit", "300"]),
    (["run", "--goods", "11,8"], "--step-limit", "int", ["--robots", "1"]),
    (["run", "--goods", "11,8"], "--horizon", "int", ["--step-limit", "300"]),
    (["view", "no-such.mbr", "--no-browser"], "--port", "int", []),
    (["view", "--live", "--goods", "11", "--no-browser"], "--speed", "float", ["--unload", "NOWHERE"]),
    (["view", "--live", "--goods", "11", "--no-browser"], "--margin", "float", ["--unload", "NOWHERE"]),
    (["view", "--live", "--goods", "11", "--no-browser"], "--robots", "int", ["--unload", "NOWHERE"]),
    (["view", "--live", "--goods", "11", "--no-browser"], "--step-limit", "int", ["--unload", "NOWHERE"]),
    (["paper", "--rules", "none"], "--margin", "float", []),
    (["paper", "--rules", "none"], "--workers", "int", []),
    (["compare", "--tasks", "none"], "--seeds", "int", []),
    (["compare", "--tasks", "none"], "--workers", "int", []),
    (["compare", "--tasks", "none"], "--robots", "int", []),
    (["compare", "--tasks", "none"], "--humans", "int", []),
    (["layout", "generate"], "--group-rows", "int", []),
    (["layout", "generate"], "--group-cols", "int", []),
    (["layout", "generate"], "--chargers", "int", []),
    (["layout", "generate"], "--aisle", "float", []),
    (["layout", "generate"], "--cell", "float", []),
    (["layout", "generate"], "--spur", "float", []),
    (["layout", "generate"], "--unloading-rows", "int", []),
    (["layout", "generate"], "--group-size", "int", []),
    (["render", "no-such.mbr", "--out", "x.gif"], "--fps", "int", []),
    (["render", "no-such.mbr", "--out", "x.gif"], "--from", "int", []),
    (["render", "no-such.mbr", "--out", "x.gif"], "--to", "int", []),
    (["render", "no-such.mbr", "--out", "x.gif"], "--every", "int", []),
    (["render", "no-such.mbr", "--out", "x.gif"], "--scale", "float", []),
    (["sweep", "no-such.toml"], "--workers", "int", []),
    (["lorr", "no-such.json", "--out", "r.json"], "--steps", "int", []),
    (["lorr", "no-such.json", "--out", "r.json"], "--plan-time-limit", "int", []),
    (["lorr", "no-such.json", "--out", "r.json"], "--seed", "int", []),
    (["capacity", "no-such.toml"], "--seeds", "int", []),
    (["capacity", "no-such.toml"], "--horizon", "int", []),
    (["capacity", "no-such.toml"], "--robots-for", "float", []),
    (["capacity", "no-such.toml"], "--start", "float", []),
    (["capacity", "no-such.toml"], "--served", "float", []),
    (["capacity", "no-such.toml"], "--workers", "int", []),
]


def run_cli(argv: list[str], cwd: Path) -> tuple[int, str]:
    """``multibots ARGV`` in this process, in ``cwd``: (exit code, stderr)."""
    from multibots.cli import main

    err, out = io.StringIO(), io.StringIO()
    old = os.getcwd()
    os.chdir(cwd)
    try:
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(out), pytest.raises(SystemExit) as done:
            main(argv)
            raise SystemExit(0)
    finally:
        os.chdir(old)
    return done.value.code or 0, err.getvalue()


def assert_clean_exit(argv: list[str], code: int, err: str) -> None:
    assert code in (0, 2, 3), (argv[:8], code, err[-500:])
    if code == 2:
        line = err.strip()
        assert len(line.splitlines()) == 1 and "Traceback" not in line and "\x1b" not in line, line[:300]
        assert len(line) < 1000 and "internal error" not in line, line[:300]


def flag_argv(entry: tuple, value: str, out: Path) -> list[str]:
    before, flag, _, after = entry
    if flag == "--group-size":
        value = f"2x{value}"
    argv = [*before, f"{flag}={value}", *after]
    if before[:2] == ["layout", "generate"]:
        argv += ["--out", str(out / "g.toml")]
    if before[0] in ("compare", "sweep", "paper", "capacity"):
        argv += ["--out", str(out / "o")]
    return argv


@pytest.mark.parametrize("entry", NUMERIC_FLAGS, ids=lambda e: f"{e[0][0]} {e[1]}")
def test_nan_inf_and_huge_numbers_are_refused_naming_the_flag(tmp_path: Path, entry: tuple) -> None:
    """NaN and infinity on every float flag, numbers past any limit on every integer flag:
    exit 2 with one line that names the flag, where the flag is read."""
    values = ["nan", "inf", "-inf"] if entry[2] == "float" else ["99999999999999999999", "1" + "0" * 400, "nan"]
    for value in values:
        code, err = run_cli(flag_argv(entry, value, tmp_path), tmp_path)
        assert code == 2 and entry[1] in err and len(err.strip().splitlines()) == 1, (value, code, err[-400:])
        assert "Traceback" not in err and "internal error" not in err and "Input should" not in err, err


@given(st.sampled_from(NUMERIC_FLAGS),
       st.one_of(st.sampled_from(HOSTILE_NUMBERS), st.integers(-(2**80), 2**80).map(str),
                 st.floats().map(repr), st.text(max_size=8)))
def test_numeric_flags_exit_0_2_or_3_with_one_line(tmp_path_factory: pytest.TempPathFactory, entry: tuple,
                                                   value: str) -> None:
    tmp = tmp_path_factory.mktemp("flags")
    argv = flag_argv(entry, value, tmp)
    code, err = run_cli(argv, tmp)
    assert_clean_exit(argv, code, err)


# ---------------------------------------------------------------- League of Robot Runners problems (issue 28)

@st.composite
def lorr_files(draw) -> dict[str, str]:
    """A LoRR problem (JSON), its map, agents and tasks files: shaped like the real ones, with
    hostile values, lines and nesting in any of them."""
    h, w = draw(st.integers(0, 6)), draw(st.integers(0, 6))
    cells = draw(st.lists(st.sampled_from(".@TES"), min_size=h * w, max_size=h * w))
    rows = ["".join(cells[r * w:(r + 1) * w]) for r in range(h)]
    header = draw(st.sampled_from([f"type octile\nheight {h}\nwidth {w}\nmap", f"height {h}\nwidth {w}",
                                   f"type octile\nheight {draw(NUMBERS)}\nwidth {w}\nmap"]))
    map_text = header + "\n" + "\n".join(rows) + draw(st.sampled_from(["", "\n", "\nextra\n"]))
    ints = st.one_of(st.integers(-3, h * w + 3), st.sampled_from([2**31, 2**64, -(2**40)]))
    agents = draw(st.lists(ints, max_size=8))
    agents_text = "\n".join(map(str, [draw(st.one_of(st.just(len(agents)), ints)), *agents]))
    if draw(st.booleans()):
        tasks = draw(st.lists(st.lists(ints, min_size=0, max_size=3), max_size=6))
        tasks_text = "#\n" + "\n".join([str(len(tasks)), *(",".join(map(str, t)) for t in tasks)])
        version = {"version": "2024 LoRR"}
    else:
        tasks = draw(st.lists(ints, max_size=6))
        tasks_text = "\n".join(map(str, [len(tasks), *tasks]))
        version = {"taskAssignmentStrategy": draw(st.sampled_from(["roundrobin", "greedy", "x"]))}
    problem: dict = {"mapFile": "m.map", "agentFile": "a.agents", "taskFile": "t.tasks",
                     "teamSize": draw(st.one_of(st.just(len(agents)), NUMBERS, TEXT)),
                     "numTasksReveal": draw(st.one_of(st.just(1), NUMBERS)), **version}
    if draw(st.booleans()):
        problem[draw(st.sampled_from(sorted(problem)))] = draw(VALUES)
    text = json.dumps(problem, default=str)
    depth = draw(st.sampled_from([0, 0, 40, 3000]))
    if depth:
        text = text[:-1] + ', "deep": ' + "[" * depth + "]" * depth + "}"
    return {"p.json": text, "m.map": map_text, "a.agents": agents_text, "t.tasks": tasks_text}


@given(lorr_files())
def test_lorr_problems_are_run_or_refused_in_one_line(tmp_path_factory: pytest.TempPathFactory, files) -> None:
    from multibots import lorr

    tmp = tmp_path_factory.mktemp("lorr")
    for name, text in files.items():
        (tmp / name).write_text(text)
    try:
        lorr.run(tmp / "p.json", steps=3)
    except Exception as e:  # the property: only a clean refusal
        assert_clean(e)


RUST_WORDS = ("i64", "u32", "u64", "f64", "invalid type:", "ProblemJson", "struct ", "serde")


@given(lorr_files())
def test_lorr_problem_refusals_name_the_field_not_serde(tmp_path_factory: pytest.TempPathFactory, files) -> None:
    from multibots import _core

    tmp = tmp_path_factory.mktemp("lorr-words")
    for name, text in files.items():
        (tmp / name).write_text(text)
    try:
        _core.LorrRun(str(tmp / "p.json"))
    except MultibotsError as e:
        assert not any(w in str(e) for w in RUST_WORDS), str(e)


# ---------------------------------------------------------------- the Python API (issue 43)

def api_calls(tmp: Path) -> list[tuple[str, object, dict]]:
    """(name, function, valid arguments) of the public API, each quick with valid arguments."""
    from multibots import lorr

    (tmp / "s.toml").write_text("robots = 1\ntasks = [42]\n")
    files = {"p.json": '{"mapFile": "m.map", "agentFile": "a.agents", "taskFile": "t.tasks", "teamSize": 2, '
                       '"numTasksReveal": 1.5, "version": "2024 LoRR"}',
             "m.map": "type octile\nheight 3\nwidth 4\nmap\n....\n.@@.\n....\n", "a.agents": "2\n0\n11\n",
             "t.tasks": "# version for LoRR 2024\n3\n3,8\n11\n0,3\n"}
    for name, text in files.items():
        (tmp / name).write_text(text)
    s = Scenario.paper(robots=1, goods=[42])
    return [
        ("simulate", multibots.simulate, {"scenario": s, "record": None, "allocator": None}),
        ("simulate_many", multibots.simulate_many, {"scenarios": [s], "workers": 1, "allocator": None}),
        ("step", lambda n: multibots.Simulation(s).step(n), {"n": 3}),
        ("paper", Scenario.paper, {"robots": 1, "goods": [42], "margin": 0.0, "step_limit": 900}),
        ("from_toml", Scenario.from_toml, {"path": tmp / "s.toml"}),
        ("lorr", lorr.run, {"problem": tmp / "p.json", "steps": 2, "out": None, "planner": "pibt", "seed": 0,
                            "plan_time_limit_ms": None, "robots": None, "record": None, "progress": None}),
    ]


@given(data=st.data())
def test_api_arguments_are_used_or_refused_in_one_line(tmp_path_factory: pytest.TempPathFactory, data) -> None:
    tmp = tmp_path_factory.mktemp("api")
    name, fn, good = data.draw(st.sampled_from(api_calls(tmp)))
    param = data.draw(st.sampled_from(sorted(good)))
    value = data.draw(st.one_of(VALUES, st.sampled_from([object(), b"x", -1, 2**70, math.nan])))
    if name == "lorr" and param == "steps" and isinstance(value, int) and not isinstance(value, bool):
        assume(value < 1000)  # a valid long run is not a refusal, only slow
    if name == "step" and isinstance(value, int) and not isinstance(value, bool):
        value = min(value, 10**6) if value > 0 else value
    # A drawn value may be a valid relative path (an `out` of "x"): what it writes lands in the
    # test's folder, never in the working folder (the repository).
    cwd = os.getcwd()
    os.chdir(tmp)
    try:
        fn(**{**good, param: value})
    except Exception as e:  # the property: only a clean refusal, naming the parameter when it is the argument
        assert_clean(e)
        if isinstance(e, multibots.ArgumentError):
            assert param in str(e) or name == "step", (name, param, str(e))
    finally:
        os.chdir(cwd)


# ---------------------------------------------------------------- outputs that name inputs (issue 43)

@given(st.sampled_from(["p.json", "./p.json", "m.map", "link.json", "hard.json", "a.agents", "t.tasks", "r.json",
                        "sub/../p.json", "r.json.multibots.json"]),
       st.sampled_from(["--out", "--record"]), st.sampled_from([None, "r.json", "p.json", "r.mbr"]))
def test_no_output_is_ever_an_input(tmp_path_factory: pytest.TempPathFactory, target: str, flag: str,
                                    other: str) -> None:
    tmp = tmp_path_factory.mktemp("outin")
    for name, text in {"p.json": '{"mapFile": "m.map", "agentFile": "a.agents", "taskFile": "t.tasks", '
                                 '"teamSize": 2, "numTasksReveal": 1, "taskAssignmentStrategy": "roundrobin"}',
                       "m.map": "type octile\nheight 3\nwidth 4\nmap\n....\n.@@.\n....\n", "a.agents": "2\n0\n11\n",
                       "t.tasks": "3\n3\n8\n0\n"}.items():
        (tmp / name).write_text(text)
    (tmp / "sub").mkdir()
    os.symlink("p.json", tmp / "link.json")
    os.link(tmp / "p.json", tmp / "hard.json")
    before = {n: (tmp / n).read_bytes() for n in ("p.json", "m.map", "a.agents", "t.tasks")}
    argv = ["lorr", "p.json", "--steps", "3", flag, target]
    other_flag = "--record" if flag == "--out" else "--out"
    if other is not None:
        argv += [other_flag, other]
    code, err = run_cli(argv, tmp)
    assert code in (0, 2), (argv, code, err)
    assert {n: (tmp / n).read_bytes() for n in before} == before, argv
    if code == 2:
        assert err.count("\n") <= 1 and "Traceback" not in err, err
