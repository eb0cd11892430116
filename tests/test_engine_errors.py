"""Errors cross the binding as exceptions of one tree (tests/test_exceptions.py); a panic never
kills the interpreter."""

import pytest

import multibots
from multibots import _core


def test_a_panic_becomes_an_engine_error_and_python_goes_on():
    with pytest.raises(multibots.EngineError, match="deliberate panic"):
        _core._panic_for_tests()
    # The interpreter and the engine still work.
    assert multibots.simulate(multibots.Scenario.paper(robots=1, goods=[42])).T == 726


def test_stepping_after_the_end_is_harmless():
    sim = multibots.Simulation(multibots.Scenario.paper(robots=1, goods=[42]))
    sim.run()
    assert sim.step(10) == 0 and sim.t == 726
    with pytest.raises(multibots.ArgumentError, match=r"n = -1: expected a whole number from 0"):
        sim.step(-1)
    with pytest.raises(multibots.ArgumentError, match=r"robot = 5: expected a whole number from 0 to 0"):
        sim.route(5)


def test_an_allocator_error_ends_the_run_for_good():
    calls = []

    def flaky(view):
        calls.append(view.step)
        if len(calls) == 1:
            raise RuntimeError("first call fails")
        return {int(r): int(g) for r, g in zip(view.idle, view.goods)}

    sim = multibots.Simulation(multibots.Scenario.paper(robots=1, goods=[42]), allocator=flaky)
    with pytest.raises(multibots.AllocatorError, match="first call fails"):
        sim.step()
    # Phases 2-8 of that step never ran: the run must not go on as if they had.
    with pytest.raises(multibots.AllocatorError, match="the run stopped at step 1"):
        sim.step()
    assert len(calls) == 1


def test_ctrl_c_stops_a_long_run_with_one_line_and_no_half_written_replay(cli, tmp_path):
    import signal
    import time

    scenario = tmp_path / "long.toml"
    # Lifelong orders with a horizon far away: the robot works on and on.
    scenario.write_text('robots = 1\ntasks = []\n[orders]\nrate = 0.01\nhorizon = 2000000000\n')
    replay = tmp_path / "long.mbr"
    p = cli.popen("run", scenario, "--record", replay)
    time.sleep(3)
    p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=120)
    assert p.returncode == 130, (out, err)
    assert err.strip() == "multibots: interrupted"
    assert list(tmp_path.iterdir()) == [scenario]


_CHECK_MANY_INTERRUPTED = """
import os, signal, sys, threading
from multibots import Scenario, _core
one = Scenario._parsed_only({"layout": "paper", "robots": 6, "tasks": {"random": 40, "seed": 1}})._core
threading.Timer(0.2, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
try:
    _core.check_many([one] * 200_000, 1)  # about 5 s of checks, stopped after 0.2 s
except KeyboardInterrupt:
    print("interrupted")
    sys.exit(0)
print("ran to the end")
"""


def test_ctrl_c_stops_checking_many_scenarios():
    # A sweep checks every planned run in one engine call: Ctrl-C must stop it as it stops runs.
    # In a fresh process: inside the full suite this test failed most runs on a 2-core machine
    # (the checks ran to the end; never when run alone), from state an earlier test leaves
    # behind that was not found. Alone in its process it measures only the engine's watch.
    import subprocess
    import sys

    p = subprocess.run([sys.executable, "-c", _CHECK_MANY_INTERRUPTED], capture_output=True, text=True, timeout=120)
    assert (p.returncode, p.stdout.strip()) == (0, "interrupted"), (p.stdout, p.stderr)
