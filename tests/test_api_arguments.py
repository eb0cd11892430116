"""The Python API inside its exception tree: every public function, given a hostile value for
any one argument, either runs or raises a MultibotsError whose one line names that argument
(never the binding's conversion words, a plain ValueError or TypeError, or a traceback)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Callable

import pytest

import multibots
import multibots.lorr
from multibots import ArgumentError, MultibotsError, Scenario

REF = Path(__file__).resolve().parents[2] / "shared" / "reference" / "lorr"
HOSTILE: list[Any] = [None, -1, 1.5, math.nan, math.inf, "x", b"x", [], {}, object(), True, 2**70, -(2**70), ""]
#: Words of the binding's conversions and of Python's built-in errors, which a user must never read.
FOREIGN = ("argument '", "PyString", "cannot be interpreted", "object is not", "can't convert", "int too big",
           "expected str, bytes or os.PathLike")


def tiny_problem(folder: Path) -> Path:
    (folder / "m.map").write_text("type octile\nheight 3\nwidth 4\nmap\n....\n.@@.\n....\n")
    (folder / "a.agents").write_text("2\n0\n11\n")
    (folder / "t.tasks").write_text("# version for LoRR 2024\n3\n3,8\n11\n0,3\n")
    (folder / "p.json").write_text('{"mapFile": "m.map", "agentFile": "a.agents", "taskFile": "t.tasks", '
                                   '"teamSize": 2, "numTasksReveal": 1.5, "version": "2024 LoRR"}')
    return folder / "p.json"


def calls(tmp: Path) -> dict[str, tuple[Callable[..., Any], dict[str, Any]]]:
    """Each function with arguments that make a quick, valid call."""
    s = Scenario.paper(robots=1, goods=[42])
    return {
        "simulate": (multibots.simulate, {"scenario": s, "record": None, "allocator": None}),
        "simulate_many": (multibots.simulate_many, {"scenarios": [s], "workers": 1, "allocator": None}),
        "Simulation": (multibots.Simulation, {"scenario": s, "allocator": None}),
        "Simulation.step": (lambda n: multibots.Simulation(s).step(n), {"n": 5}),
        "Simulation.route": (lambda robot: multibots.Simulation(s).route(robot), {"robot": 0}),
        "Scenario.paper": (Scenario.paper, {"robots": 1, "goods": [42], "starts": None, "unload": "M", "margin": 0.0,
                                            "step_limit": 1000}),
        "Scenario.from_toml": (Scenario.from_toml, {"path": str(tmp / "s.toml")}),
        "Scenario.from_toml_str": (Scenario.from_toml_str, {"text": "tasks = [42]", "source": "s"}),
        "Scenario.from_dict": (Scenario.from_dict, {"data": {"tasks": [42]}}),
        "lorr.run": (multibots.lorr.run, {"problem": tiny_problem(tmp), "steps": 3, "out": None, "planner": "auto",
                                          "scheduler": "spread", "seed": 0, "plan_time_limit_ms": None,
                                          "progress": None, "record": None, "robots": None}),
        "Replay": (multibots.Replay, {"path": str(tmp / "r.mbr")}),
        "layout_json": (multibots.layout_json, {"name": "paper"}),
    }


@pytest.fixture(scope="module")
def table(tmp_path_factory: pytest.TempPathFactory) -> dict[str, tuple[Callable[..., Any], dict[str, Any]]]:
    tmp = tmp_path_factory.mktemp("api")
    (tmp / "s.toml").write_text("robots = 1\ntasks = [42]\n")
    multibots.simulate(Scenario.paper(robots=1, goods=[42]), record=tmp / "r.mbr")
    return calls(tmp)


@pytest.mark.parametrize("name", ["simulate", "simulate_many", "Simulation", "Simulation.step", "Simulation.route",
                                  "Scenario.paper", "Scenario.from_toml", "Scenario.from_toml_str",
                                  "Scenario.from_dict", "lorr.run", "Replay", "layout_json"])
def test_every_hostile_argument_is_a_multibots_error_naming_it(
        table: dict[str, Any], name: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    # A hostile value may be a valid relative path ("x"): what it writes lands here, not in
    # the working folder.
    monkeypatch.chdir(tmp_path)
    fn, good = table[name]
    fn(**good)  # the valid call runs
    for param in good:
        for value in HOSTILE:
            args = {**good, param: value}
            try:
                fn(**args)
            except MultibotsError as e:
                text = str(e)
                assert "\n" not in text and text, (name, param, value, text)
                assert not any(w in text for w in FOREIGN), (name, param, value, text)
                if isinstance(e, ArgumentError):
                    assert param in text, (name, param, value, text)
            except Exception as e:
                pytest.fail(f"{name}({param}={value!r}) raised {type(e).__name__}: {e}")


def test_argument_errors_are_value_and_type_errors_and_name_the_bound() -> None:
    with pytest.raises(ValueError, match=r"steps = 1\.5: expected a number of steps from 0 to 4,294,967,295"):
        multibots.lorr.run("p.json", steps=1.5)
    with pytest.raises(TypeError, match=r"robots = 1\.5: expected a number of robots from 1 to 1,000,000"):
        multibots.lorr.run("p.json", steps=1, robots=1.5)
    with pytest.raises(ArgumentError, match=r"steps = 1000000000000: expected a number of steps from 0"):
        multibots.lorr.run("p.json", steps=10**12)
    with pytest.raises(ArgumentError, match=r"workers = -1: expected a whole number from 0 to 1,024"):
        multibots.simulate_many([Scenario.paper(robots=1, goods=[42])], workers=-1)
